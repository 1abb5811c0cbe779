//! # The estimator layer: the CPU reference path tracer
//!
//! The incident-radiance estimator every bake runs ([`trace::Tracer`]): next-event
//! estimation of every light kind at the baked point and along the path with multiple
//! importance sampling, Lambert + GGX BSDF sampling, Russian roulette. It is the oracle
//! of the GPU kernels (`gpu`), which implement the same estimator in WGSL and are tested
//! against it.
//!
//! Uses: [`crate::scene`], [`crate::sampling`].

pub mod trace;
