//! Sample generation with densities: sequences on [0,1)², warps to the sphere,
//! hemisphere and disk, and GGX visible-normal sampling.
//!
//! | what | function | pdf | inverse |
//! |---|---|---|---|
//! | Halton (2, 3) | [`halton2`] | 1 on [0,1)² | — |
//! | Hammersley | [`hammersley2`] | 1 on [0,1)² | — |
//! | R2 (Roberts 2018), Cranley–Patterson shifted | [`R2`] | 1 on [0,1)² | — |
//! | R3 (Roberts 2018), shifted | [`R3`] | 1 on [0,1)³ | — |
//! | Sobol', shuffled and Owen-scrambled (Burley 2020), 4D per seed | [`owen_sobol4`] | 1 on [0,1)⁴ | — |
//! | uniform sphere | [`uniform_sphere`] | 1/4π | [`uniform_sphere_inv`] |
//! | uniform hemisphere | [`uniform_hemisphere`] | 1/2π | [`uniform_hemisphere_inv`] |
//! | uniform hemisphere, equal-area via the concentric disk | [`uniform_hemisphere_concentric`] | 1/2π | [`uniform_hemisphere_concentric_inv`] |
//! | cosine hemisphere | [`cosine_hemisphere`] | cos θ/π | [`cosine_hemisphere_inv`] |
//! | concentric disk (Shirley & Chiu 1997) | [`concentric_disk`] | 1/π | [`concentric_disk_inv`] |
//! | spherical Fibonacci point set | [`spherical_fibonacci`] | 1/4π (per point 4π/N) | [`spherical_fibonacci_nearest`] |
//! | GGX visible normals (Heitz 2018) | [`crate::ggx::sample_vndf`] | [`crate::ggx::vndf_pdf`] | — |
//!
//! Sequence order matters for the progressive encoder ([Roughton19 §7.3.1]): use
//! Halton, R2 or the shuffled Sobol' points, not Hammersley in index order.

mod rng;
mod sequences;
pub mod sobol;
mod warp;

pub use rng::Pcg32;
pub use sequences::{halton2, hammersley2, radical_inverse, R2, R3};
pub use sobol::{owen_sobol4, owen_sobol4_u32};
pub use warp::*;
