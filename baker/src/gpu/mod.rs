//! # The GPU layer: the same bake on wgpu
//!
//! The bake kernel and its host side ([`bake::GpuBake`]), run as one megakernel or as the
//! [`wavefront`] pass graph; adaptive and camera-based batches ([`adaptive`]), filtered
//! accumulation ([`filter`]), one bake split across GPUs ([`multi`]), and the reusable
//! primitives (scan, compaction, sort; [`prims`]).
//!
//! Uses: [`crate::scene`], [`crate::layout`], [`crate::sampling`], [`crate::estimator`],
//! [`crate::accumulate`].

pub mod adaptive;
pub mod bake;
pub mod buffers;
pub mod camera;
pub mod compose;
pub mod encoders;
pub mod filter;
pub mod guide;
pub mod kernel;
pub mod maps;
pub mod multi;
pub mod params;
pub mod prims;
pub mod slots;
pub mod timing;
pub mod wavefront;

pub use bake::{wave_capacity, GpuBake, BATCH_TARGET_SECONDS, MAX_PASSES_PER_DISPATCH};
pub use buffers::check_bindings;
pub use kernel::{guide_build_sources, kernel, GuideBuild, Kernel};
pub use params::TraceParams;
pub use timing::RayStats;

/// A compute pipeline of `module`'s `entry` with the layout its bindings imply.
pub(crate) fn compute_pipeline(d: &wgpu::Device, module: &wgpu::ShaderModule, entry: &str) -> wgpu::ComputePipeline {
    d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}
