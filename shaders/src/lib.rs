//! # shaders — WGSL runtime reconstruction library
//!
//! Not implemented yet (issue "shaders"). Planned: one WGSL module per concern
//! (SH, SG, Ambient Dice, GGX, LUT sampling, progressive update), composition of a
//! module from a configuration with pruning, naga validation and export, and a
//! wgpu parity harness against the `sbf` CPU twins.
