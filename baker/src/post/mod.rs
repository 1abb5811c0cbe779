//! # The post-processing layer: what happens to a finished bake before it is written
//!
//! The lightmap as images with dilation of empty texels ([`images`]), joint non-local
//! means denoising within charts ([`denoise`]) and UV seams — found from the geometry,
//! measured and stitched by least squares ([`seams`]); the non-negative bases' fits with
//! their irradiance pinned to the texel's E/π ([`refit`], `--solver nnls-irradiance`).
//!
//! Uses: [`crate::scene`], [`crate::layout`], [`crate::accumulate`].

pub mod denoise;
pub mod images;
pub mod refit;
pub mod seams;
