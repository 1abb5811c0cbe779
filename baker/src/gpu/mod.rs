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
pub mod filter;
pub mod multi;
pub mod prims;
pub mod wavefront;

pub use bake::*;
