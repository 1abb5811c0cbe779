//! # The sampling layer: where every random number and sampled direction comes from
//!
//! Per-item, per-vertex sample sequences (shuffled Owen-scrambled Sobol' or white noise,
//! [`sequence`]), the environment's importance sampler ([`environment`]) and the
//! first-bounce guiding distributions — texel clusters, learned directional bins, the
//! mixture sampler and its pdf ([`guiding`]).
//!
//! Uses: [`crate::scene`], [`crate::layout`].

pub mod environment;
pub mod guiding;
pub mod sequence;
