//! # The accumulate layer: from samples to coefficients, the interface CPU and GPU share
//!
//! What a bake is asked to do ([`config`]), what it samples ([`targets`]: texels or
//! probes), the state both paths fill ([`state`]: moments, progressive encoders, guiding
//! sums, the filtered state), and the CPU bake that fills it ([`bake`]: progressive passes
//! of the reference estimator) behind the interface every engine offers ([`progressive`]). The strategies that decide which items take samples and
//! where the samples go: adaptive sampling ([`adaptive`]), camera-based sampling
//! ([`camera`]) and filtered gather-based accumulation ([`filter`]); how items are dealt out
//! to devices and shards ([`partition`]). The GPU layer keeps
//! the same state with the same updates, so a GPU bake is tested against this one.
//!
//! Uses: [`crate::scene`], [`crate::layout`], [`crate::sampling`], [`crate::estimator`].

pub mod adaptive;
pub mod bake;
pub mod camera;
pub mod config;
pub mod filter;
pub mod partition;
pub mod progressive;
pub mod state;
pub mod targets;

pub use bake::Bake;
pub use config::{
    lightmap_basis, BakeConfig, BakedBasis, BasisId, Pipeline, Solver, BAKE_ACCELERATION, SG_HEMISPHERE_SHARPNESS, SG_SHARPNESS_RANGE,
};
pub use partition::Partition;
pub use progressive::Progressive;
pub use state::{BakeState, ItemSample, Moments, MAX_BACK_FACE_FRACTION};
pub use targets::{Targets, TILE};
