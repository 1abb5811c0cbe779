//! Real-time rendering of baked scenes ([Roughton19 §8.4.3, Figs. 8.6]–8.8, Table 8.1): the
//! scene rasterised from a camera and every visible lightmapped surface shaded from the
//! bake — diffuse and GGX specular reflection of the incident light the lightmap encodes
//! (direct light from the baked lights plus indirect) — with the runtime functions the
//! `shaders` crate exports, next to a path-traced reference of the same quantity.
//!
//! | module | holds |
//! |---|---|
//! | [`lighting`] | what a configuration shades with: the plain E/π lightmap or one basis, its specular path, f32/f16 storage |
//! | [`probes`] | dynamic objects' lighting: the bake's SH L2 probe grid, trilinear |
//! | [`atlas`] | a bake's coefficient images (one per lobe) read back from its EXRs; the bilinear lookup both shaders use |
//! | [`shade`] | the CPU twin of the fragment shading in f64 through `sbf` (the GPU image's oracle) |
//! | [`normal_map`] | normal-mapped shading: glTF normal maps on MikkTSpace tangents perturb the visible surface's shading normal |
//! | [`visible`] | the visible surface per pixel by ray casting (the rasteriser's CPU twin) and the CPU image |
//! | `bindings` | what every render pipeline binds (the layout) and the probes as shader rows |
//! | [`raster`] | the GPU pass on wgpu: depth pre-pass, forward shading (`wgsl/render.wgsl` after the composed runtime) |
//! | `deferred` | the deferred path: a G-buffer from the raster pass, shading in a compute pass over 8×8 tiles |
//! | `timing` | frame times on either path by timestamp queries: the frame and its shading pass |
//! | [`reference`](mod@reference) | the path-traced reference: the same reflected radiance, estimated with the bake's own incident-radiance estimator |
//! | [`reference_gpu`] | the same reference on the GPU: the bake's WGSL path tracer over the same visible surfaces (`wgsl/reference.wgsl`) |
//! | [`compare`] | errors against the reference (its noise subtracted) |
//! | [`session`] | one comparison as the `render` command runs it: visible surfaces and reference once, then per configuration image, errors and frame time |
//! | [`report`] | what a comparison writes: EXR and PNG images, the +3 EV differences, results.json, report.html |
//! | [`web`] | the bake viewer for the browser (`render --web`): the scene, lightmaps and reference for WebGL 2 and WebGPU, shaded by the exported library |
//!
//! Uses: [`crate::scene`], [`crate::layout`], [`crate::accumulate`], [`crate::estimator`],
//! [`crate::sampling`], [`crate::gpu`] (the reference's kernel and buffers),
//! [`crate::output`].

pub mod atlas;
mod bindings;
pub mod compare;
mod deferred;
pub mod lighting;
pub mod normal_map;
pub mod probes;
pub mod raster;
pub mod reference;
pub mod reference_gpu;
pub mod report;
pub mod session;
pub mod shade;
mod timing;
pub mod visible;
pub mod web;
