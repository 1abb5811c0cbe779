//! The three jobs an engine developer comes for, in a few lines each: project an HDR
//! environment onto a basis, evaluate irradiance and GGX specular from the coefficients
//! (a probe's, or a baked lightmap texel's), with the f32 runtime the shaders mirror.
//!
//! Radiance bases: the lightmap bases of the profiles and the baker (`sh1`, `sh2`, `sg9`,
//! `sg12`, `ad9`, `ad12`; `sbf::profile`, feature `profile`), laid out as the baker lays them out in a
//! texel's tangent frame (normal +Z): SH in the frame's own axes, SG lobes on a Vogel
//! spiral over the upper hemisphere with λ 6, AD 9 Roughton's upper-hemisphere set, AD 12
//! the icosahedron. A probe uses the same layouts in its own frame (the map's axes).
//! Irradiance bases (`ac`, `h4`, `h6`): the ambient cube (Valve) and the H-basis (Habel &
//! Wimmer 2010) hold E/π itself — the cube the exact E/π at the six axes, the H-basis a
//! least-squares fit of E/π over the upper hemisphere — so they shade diffuse only:
//! [`Probe::radiance`] and [`Probe::specular`] are errors for them.
//!
//! ```
//! use sbf::envmap::{LatLongImage, ProceduralSky};
//! use sbf::glam::Vec3;
//! use sbf::probe::{Probe, ProbeBasis};
//!
//! // Project a map (here the built-in sky, 64×32) onto SH L2 …
//! let sky = ProceduralSky::default();
//! let map = LatLongImage::from_fn(64, 32, |d| sky.radiance(d))?;
//! let probe = Probe::project(&map, ProbeBasis::Sh2)?;
//! // … and shade: irradiance E/π at a normal, GGX specular for a view, α and f0.
//! let e = probe.irradiance(Vec3::Y);
//! let s = probe.specular(Vec3::Y, Vec3::new(0.0, 0.6, 0.8), 0.3, 0.04)?;
//! assert!(e.min_element() > 0.0 && s.is_finite());
//! # Ok::<(), sbf::SbfError>(())
//! ```
//!
//! A baked lightmap texel is a probe in the texel's tangent frame: the baker writes one EXR
//! per coefficient (`ad9_00.exr` … `ad9_08.exr`, RGB); read texel (x, y) of each into a list
//! and evaluate with a tangent-space normal (a normal map's value) and view:
//!
//! ```
//! use sbf::glam::Vec3;
//! use sbf::probe::{Probe, ProbeBasis};
//!
//! // Nine RGB coefficients as read from ad9_00.exr … ad9_08.exr at one texel.
//! let texel = [[0.2, 0.2, 0.25]; 9].map(Vec3::from);
//! let probe = Probe::from_coefficients(ProbeBasis::Ad9, &texel)?;
//! let n = Vec3::Z; // the texel's normal, unperturbed
//! let diffuse = probe.irradiance(n) * Vec3::new(0.8, 0.7, 0.6); // × albedo: E/π·ρ
//! let v = Vec3::new(0.0, 0.6, 0.8);
//! let specular = probe.specular(n, v, 0.2, 0.04)?;
//! assert!(diffuse.min_element() > 0.0 && specular.min_element() > 0.0);
//! # Ok::<(), sbf::SbfError>(())
//! ```
//!
//! Irradiance: SH by the exact band factors, SG by Hill's fit, AD by the minimax quadratic
//! ([`crate::recon::runtime`], the twins of the WGSL functions). Specular: SH by zonal
//! convolution about the dominant direction with the DFG split sum
//! ([`crate::recon::sh::specular_zonal_rgb`], f64), SG by the split sum over the warped
//! NDF ([`crate::recon::runtime::sg_specular_split_sum`]), AD by Roughton's Listing 8.1 fit and Listing 8.2 table. Fresnel is Schlick with f0 given and f90 = 1.

use crate::basis::Basis;
use crate::envmap::LatLongImage;
use crate::gram::{gram_matrix, GramOptions};
use crate::recon::runtime;
use crate::solve::{map_samples, moments, solve_gram, LsOptions};
use crate::{Domain, SbfError, ShBasis};
use glam::{DVec3, Vec3};

/// SG lobes' sharpness in the hemisphere layouts (the baker's and Roughton's Appendix C).
pub use crate::registry::SG_SHARPNESS;

/// The bases a probe is in: the registry's ([`crate::registry`]).
pub type ProbeBasis = crate::registry::BasisId;

/// RGB coefficients in one basis, ready to shade with.
#[derive(Debug, Clone)]
pub struct Probe {
    basis: ProbeBasis,
    coefficients: Vec<Vec3>,
    axes: Vec<Vec3>,
}

impl Probe {
    /// Encodes a lat-long map in `basis`, in f64 with exact texel solid angles. Radiance
    /// bases: least-squares projection of the radiance over the basis's domain (the whole
    /// sphere, or the upper hemisphere z > 0 for the hemisphere layouts); for SH the
    /// orthonormal projection. Ambient cube: the exact E/π at the six axes (a direct sum over
    /// the texels, [`crate::recon::reference::irradiance_map`]). H-basis: least squares on
    /// the exact E/π at 256 normals spread over the upper hemisphere (spherical Fibonacci).
    pub fn project(map: &LatLongImage, basis: ProbeBasis) -> Result<Probe, SbfError> {
        let b = basis.basis();
        let domain = b.domain();
        let irradiance = |n: DVec3| crate::recon::reference::irradiance_map(map, n);
        let rgb: Vec<[f64; 3]> = match basis {
            ProbeBasis::AmbientCube => {
                [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z].into_iter().map(irradiance).collect()
            }
            ProbeBasis::H4 | ProbeBasis::H6 => {
                // Fibonacci points on z ∈ (0, 1], equal weights (the fit's samples).
                let k = 256;
                let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
                let samples: Vec<crate::solve::RadianceSample> = (0..k)
                    .map(|i| {
                        let z = 1.0 - (i as f64 + 0.5) / k as f64;
                        let r = (1.0 - z * z).sqrt();
                        let d = DVec3::new(r * (golden * i as f64).cos(), r * (golden * i as f64).sin(), z);
                        crate::solve::RadianceSample { direction: d, value: irradiance(d), weight: 1.0 }
                    })
                    .collect();
                let c = solve_gram(&crate::solve::sample_gram(b.as_ref(), &samples), &moments(b.as_ref(), &samples), LsOptions::default())?
                    .coeffs;
                (0..c.nrows()).map(|i| [c[(i, 0)], c[(i, 1)], c[(i, 2)]]).collect()
            }
            _ => {
                let mut samples = map_samples(map);
                if domain == Domain::UpperHemisphere {
                    samples.retain(|s| s.direction.z > 0.0);
                }
                let m = moments(b.as_ref(), &samples);
                let c = match basis {
                    ProbeBasis::Sh1 | ProbeBasis::Sh2 => m,
                    _ => solve_gram(&gram_matrix(b.as_ref(), domain, GramOptions::default())?.matrix, &m, LsOptions::default())?.coeffs,
                };
                (0..c.nrows()).map(|i| [c[(i, 0)], c[(i, 1)], c[(i, 2)]]).collect()
            }
        };
        let rgb: Vec<Vec3> = rgb.iter().map(|c| DVec3::from_array(*c).as_vec3()).collect();
        Probe::from_coefficients(basis, &rgb)
    }

    /// A probe from coefficients already encoded (a baked lightmap texel, a probe read from
    /// disk): `basis.coefficient_count()` RGB values in the basis's order.
    pub fn from_coefficients(basis: ProbeBasis, coefficients: &[Vec3]) -> Result<Probe, SbfError> {
        if coefficients.len() != basis.coefficient_count() {
            return Err(SbfError::LengthMismatch {
                what: "probe coefficients",
                expected: basis.coefficient_count(),
                got: coefficients.len(),
            });
        }
        if let Some(x) = coefficients.iter().find(|c| !c.is_finite()) {
            return Err(SbfError::InvalidParameter { name: "probe coefficient", value: x.max_element() as f64, reason: "must be finite" });
        }
        let axes = basis.axes().iter().map(|a| a.as_vec3()).collect();
        Ok(Probe { basis, coefficients: coefficients.to_vec(), axes })
    }

    /// The basis.
    pub fn basis(&self) -> ProbeBasis {
        self.basis
    }

    /// The RGB coefficients.
    pub fn coefficients(&self) -> &[Vec3] {
        &self.coefficients
    }

    /// Radiance the coefficients encode in direction `d` (unit; f64 basis evaluation); an
    /// error for the irradiance bases.
    pub fn radiance(&self, d: Vec3) -> Result<Vec3, SbfError> {
        if self.basis.holds_irradiance() {
            return Err(SbfError::NotEncoded { basis: self.basis.name(), what: "radiance" });
        }
        Ok(self.combine(d))
    }

    /// Σ c_i·B_i(d).
    fn combine(&self, d: Vec3) -> Vec3 {
        let b = self.basis.basis();
        let mut y = vec![0.0; b.len()];
        b.eval_into(d.as_dvec3(), &mut y);
        self.coefficients.iter().zip(&y).fold(Vec3::ZERO, |acc, (c, w)| acc + *c * *w as f32)
    }

    /// Irradiance E/π at unit normal `n` (multiply by the albedo for Lambert); for the
    /// H-basis meaningful on the upper hemisphere (n_z ≥ 0) only.
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        let c = &self.coefficients;
        match self.basis {
            ProbeBasis::AmbientCube | ProbeBasis::H4 | ProbeBasis::H6 => self.combine(n),
            ProbeBasis::Sh1 => runtime::sh_l1_irradiance(&[c[0], c[1], c[2], c[3]], n),
            ProbeBasis::Zh3 => {
                let ch = |k: usize| std::array::from_fn(|i| c[i][k] as f64);
                let e = crate::recon::sh::irradiance_l1_zh3(&[ch(0), ch(1), ch(2)], n.as_dvec3()).expect("finite coefficients (checked)");
                Vec3::new(e[0] as f32, e[1] as f32, e[2] as f32)
            }
            ProbeBasis::Sh2 => runtime::sh_l2_irradiance(&std::array::from_fn(|i| c[i]), n),
            ProbeBasis::Sg9 | ProbeBasis::Sg12 => runtime::sg_irradiance(&self.axes, SG_SHARPNESS as f32, c, n),
            ProbeBasis::Ad9 | ProbeBasis::Ad12 => runtime::ad_irradiance(&self.axes, c, n),
        }
    }

    /// GGX specular radiance towards unit view `v` (pointing away from the surface) at unit
    /// normal `n`, GGX α (`alpha`, clamped to [1e-4, 1]) and Schlick Fresnel with `f0`
    /// (f90 = 1). Single scattering, no multiple-scattering compensation. An error for the
    /// irradiance bases.
    pub fn specular(&self, n: Vec3, v: Vec3, alpha: f32, f0: f32) -> Result<Vec3, SbfError> {
        let c = &self.coefficients;
        let alpha = alpha.clamp(1e-4, 1.0);
        Ok(match self.basis {
            ProbeBasis::AmbientCube | ProbeBasis::H4 | ProbeBasis::H6 => {
                return Err(SbfError::NotEncoded { basis: self.basis.name(), what: "specular" })
            }
            ProbeBasis::Sh1 | ProbeBasis::Sh2 | ProbeBasis::Zh3 => {
                let order = if self.basis == ProbeBasis::Sh2 { 2 } else { 1 };
                let sh = ShBasis::new(order).expect("order 1 or 2");
                let nv = n.dot(v) as f64;
                let g = crate::recon::sh::specular_zonal_filter(order, nv, alpha as f64);
                let dfg = crate::recon::tables::dfg().sample2(nv.clamp(0.0, 1.0) as f32, alpha);
                let rgb: Vec<[f64; 3]> = c.iter().map(|x| x.as_dvec3().to_array()).collect();
                let s = crate::recon::sh::specular_zonal_rgb(
                    &sh,
                    &rgb,
                    &g,
                    n.as_dvec3(),
                    v.as_dvec3(),
                    alpha as f64,
                    f0 as f64,
                    1.0,
                    [dfg[0] as f64, dfg[1] as f64],
                )
                .expect("coefficients of the basis's order");
                Vec3::new(s[0] as f32, s[1] as f32, s[2] as f32)
            }
            ProbeBasis::Sg9 | ProbeBasis::Sg12 => {
                let dfg = crate::recon::tables::dfg().sample2(n.dot(v).clamp(0.0, 1.0), alpha);
                runtime::sg_specular_split_sum(&self.axes, SG_SHARPNESS as f32, c, n, v, alpha, f0, 1.0, dfg)
            }
            ProbeBasis::Ad9 | ProbeBasis::Ad12 => {
                runtime::ad_specular(&self.axes, c, n, v, alpha, f0, 1.0, crate::recon::tables::ad_specular_2d())
            }
        })
    }
}
