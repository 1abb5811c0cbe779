//! # baker — bakes lightmaps and light probes into any `sbf` basis, progressively
//!
//! - [`scene`]: meshes, materials (Lambert + GGX layers), lights, environment (analytic
//!   sky or a lat-long map), and the built-in scenes ([`scene::cornell`], the default;
//!   [`scene::furnace`] for tests; [`scene::slit`] lit through a slit (guiding); [`scene::sunbeam`] a sun through the slit (adaptive sampling); [`scene::room_1m`]
//!   with 1 M lightmapped triangles (the fair benchmark); [`scene::dense`] with a 1 M-triangle sphere for timing).
//! - [`import`]: glTF 2.0 (TEXCOORD_1 lightmap UVs, metallic/roughness, emission,
//!   KHR_lights_punctual) with a report of what was skipped.
//! - [`camera`]: camera-based lightmap sampling — a view camera, per-batch jitter, the
//!   texels its pixels see (CPU ray cast twin of the GPU raster in [`adapt_gpu`]).
//! - [`bvh`]: binned-SAH BVH flattened into GPU-shaped nodes, CPU traversal.
//! - [`lightmap`]: planar charts (or the mesh's own UVs), shelf packing, 16 sub-texel
//!   sample positions per texel with a coverage mask.
//! - [`lights`]: delta lights at a point (directional, point, spot with cone and range),
//!   the self-intersection-safe ray offset, the environment's importance sampler.
//! - [`sampler`]: every random number of a pass from (seed, item, pass, path vertex, use):
//!   shuffled Owen-scrambled Sobol' points per vertex (seed 004 §6.2) or white noise.
//! - [`trace`]: the path-traced L_in estimator with next-event estimation of every light
//!   kind at the baked point and along the path (MIS), Russian roulette, CPU.
//! - [`adapt`]: adaptive sampling — pilot passes, then batches whose texels join with
//!   probability from their 8×8 tile's mean σ (Neyman allocation, a defensive floor);
//!   [`adapt_gpu`]: the same selection on the GPU (compaction, indirect dispatch).
//! - [`bake`]: targets (texels or probes), progressive passes feeding plain irradiance
//!   and the per-sample encoders on the CPU (the reference path), the shared state.
//! - [`gpu`]: the same estimator in WGSL (`wgsl/trace.wgsl`) with the `shaders`
//!   progressive update, composed per bake; ray-throughput measurement; the passes run
//!   by the megakernel (`bake_pass`) or by the [`wavefront`] pipeline.
//! - [`wavefront`]: breadth-first passes (seed 004 §3.1, §5.1) — generate, then per bounce
//!   intersect, shade and compact the active paths (indirect dispatch), then accumulate;
//!   the pass graph in its root, one WGSL file per pass.
//! - [`multi_gpu`]: one bake split across several GPUs (contiguous item ranges, a thread
//!   per device, the merged state equal to the single-device one).
//! - [`guiding`]: first-bounce ray guiding (seed 003): texel clusters, learned directional
//!   bins on the concentric square, quadtree relaxation, CDFs, the mixture sampler and pdf.
//! - [`gpu_prims`]: reusable GPU primitives with CPU twins — exclusive prefix sum (any
//!   length, multi-level), stream compaction, radix sort, the offset buffer, tile indices,
//!   the filtered gather (box, Gaussian, Mitchell, within a chart) — for the wavefront pipeline.
//! - [`filter`]: filtered gather-based accumulation (seed 004 §3.2): every texel a chart
//!   overlaps gathers the samples within a box, Gaussian or Mitchell radius into its own
//!   encoders and weighted Welford moments, so uncovered edge texels get values;
//!   [`filter_gpu`]: the same on the GPU (records per item and pass, a gather pass).
//! - [`checkpoint`]: atomic checkpoints of the progressive state, resume.
//! - [`denoise`]: joint non-local means over valid texels within a chart (position, normal
//!   guides, variance-normalised patches), the same weights for every coefficient.
//! - [`seams`]: UV seams found from the geometry (welded edges, not creases), the seam
//!   metric, least-squares stitching of the bilinear lookups across them.
//! - [`output`]: EXR images with a validity alpha, dilation, metadata, runtime WGSL,
//!   preview PNG.
//! - [`placement`]: the probe grid; probes inside geometry found (back-face fraction)
//!   and moved out.
//! - [`run`]: a whole bake as the `baker` command runs it.
//! - [`slc`], [`slc_gpu`]: stochastic light culling of VPLs on a G-buffer (seeds 000–002):
//!   tiled culling by random-range bounds and shading, CPU reference and wgpu twin,
//!   the cross-bilateral filter for interleaved sampling.
//! - [`slc_media`]: the same for single scattering in a homogeneous slab (seed 001): point
//!   lights and diffuse VPLs, equiangular sampling inside the inner sphere, uniform outside.

pub mod adapt;
pub mod adapt_gpu;
pub mod bake;
pub mod bvh;
pub mod camera;
pub mod checkpoint;
pub mod denoise;
pub mod filter;
pub mod filter_gpu;
pub mod gpu;
pub mod gpu_prims;
pub mod guiding;
pub mod import;
pub mod lightmap;
pub mod lights;
pub mod multi_gpu;
pub mod output;
pub mod placement;
pub mod run;
pub mod sampler;
pub mod scene;
pub mod seams;
pub mod slc;
pub mod slc_gpu;
pub mod slc_media;
pub mod trace;
pub mod wavefront;
