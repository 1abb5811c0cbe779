//! The CPU twin of the fragment shading, in f64 through `sbf` (what the GPU image is
//! tested against). Per pixel, with the lobes' values `c` from the lightmap, the surface
//! material and unit world normal n and view v (towards the eye):
//!
//! - the tangent frame (t, b, n) of n (Duff et al. 2017: `tangent_frame`, the frame the
//!   bake encoded every texel in), v in it: v_t = (v·t, v·b, v·n), n_t = +Z — or, with a
//!   normal map ([`Shader::terms_at`]), n_t the perturbed normal in the texel's frame;
//! - diffuse = albedo · E/π(c, n_t): the plain E/π itself, SH's band factors
//!   (Ramamoorthi & Hanrahan 2001), SG by Hill's fit (the runtime's c₀), AD by the
//!   minimax quadratic per lobe ([Roughton19 §8.3]);
//! - specular (when v_t·z > 0 and the material has F0): the basis's runtime — SH by the
//!   zonal filter about the dominant direction with the split-sum DFG table, SG by the
//!   ASG warp (Xu et al. 2013) or the per-lobe tables, AD by Listing 8.1's fit with the
//!   Listing 8.2 table or the per-lobe tables. Schlick Fresnel with f90 = 1; a coloured
//!   F0 (metals) by linearity, F0·S(1, 0) + S(0, 1), a grey one by one call S(F0, 1).
//!
//! Emission is not part of the image: it is the light reflected by the visible surface.

use super::lighting::{lobe_axes, Encoding, Lighting, SurfaceMaterial};
use crate::accumulate::{BakedBasis, BasisId};
use sbf::glam::DVec3;
use sbf::profile::SpecularPath;
use sbf::recon::{ambient_dice, lobe_ggx, sg, sh};

/// The diffuse and specular reflected radiance of a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Terms {
    pub diffuse: DVec3,
    pub specular: DVec3,
}

impl Terms {
    pub fn total(&self) -> DVec3 {
        self.diffuse + self.specular
    }
}

/// Everything the shading of one configuration needs besides the pixel.
#[derive(Debug)]
pub struct Shader {
    pub lighting: Lighting,
    axes: Vec<DVec3>,
    sh: Option<sbf::ShBasis>,
}

impl Shader {
    pub fn new(lighting: Lighting) -> Shader {
        let sh = match lighting.encoding {
            Encoding::Basis(BasisId::Sh1 | BasisId::Zh3) => Some(sbf::ShBasis::new(1).expect("order 1")),
            Encoding::Basis(BasisId::Sh2) => Some(sbf::ShBasis::new(2).expect("order 2")),
            _ => None,
        };
        Shader { lighting, axes: lobe_axes(lighting.encoding), sh }
    }

    /// Diffuse and specular at unit world normal `n`, unit view `v`, lobe values `c`.
    pub fn terms(&self, c: &[DVec3], m: &SurfaceMaterial, n: DVec3, v: DVec3) -> Terms {
        self.terms_at(c, m, n, n, v)
    }

    /// [`Shader::terms`] at a shading normal `n` other than the texel's: the lobes are in
    /// the tangent frame of `frame` (the interpolated normal the bake encoded them in), and
    /// both diffuse and specular are evaluated at `n` in that frame (normal mapping).
    pub fn terms_at(&self, c: &[DVec3], m: &SurfaceMaterial, frame: DVec3, n: DVec3, v: DVec3) -> Terms {
        let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(frame);
        let local = |x: DVec3| DVec3::new(x.dot(t), x.dot(b), x.dot(frame));
        let (nt, vt) = (local(n), local(v));
        let diffuse = m.albedo * self.irradiance_at(c, nt);
        let specular = if m.glossy() && nt.dot(vt) > 0.0 && self.lighting.encoding != Encoding::Irradiance {
            if m.f0.x == m.f0.y && m.f0.y == m.f0.z {
                self.specular_at(c, nt, vt, m.alpha, m.f0.x, 1.0)
            } else {
                m.f0 * self.specular_at(c, nt, vt, m.alpha, 1.0, 0.0) + self.specular_at(c, nt, vt, m.alpha, 0.0, 1.0)
            }
        } else {
            DVec3::ZERO
        };
        Terms { diffuse, specular }
    }

    /// The most the GPU's per-lobe tables can add to [`Shader::terms`]' specular when the
    /// texture unit filters them (`lobe_ggx_filtered_*`) with weights within
    /// `weight_error` and a returned value within `result_error` (relative) of exact —
    /// [`lobe_ggx::specular_rgb_filter_error`] in the same frame and Fresnel split as the
    /// twin; zero for the fits and every path without tables.
    pub fn table_filter_error(&self, c: &[DVec3], m: &SurfaceMaterial, n: DVec3, v: DVec3, weight_error: f64, result_error: f64) -> DVec3 {
        let table = match self.lighting.encoding {
            _ if self.lighting.specular != SpecularPath::Tables => return DVec3::ZERO,
            Encoding::Basis(BasisId::Sg9 | BasisId::Sg12) => sbf::recon::tables::lobe_ggx_sg6(),
            Encoding::Basis(BasisId::Ad9 | BasisId::Ad12) => sbf::recon::tables::lobe_ggx_ad(),
            _ => return DVec3::ZERO,
        };
        let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(n);
        let vt = DVec3::new(v.dot(t), v.dot(b), v.dot(n));
        if !m.glossy() || vt.z <= 0.0 {
            return DVec3::ZERO;
        }
        let rgb: Vec<[f64; 3]> = c.iter().map(|x| x.to_array()).collect();
        let bound = |f0: f64, f90: f64| {
            DVec3::from(lobe_ggx::specular_rgb_filter_error(
                table,
                &self.axes,
                &rgb,
                DVec3::Z,
                vt,
                m.alpha,
                f0,
                f90,
                weight_error,
                result_error,
            ))
        };
        if m.f0.x == m.f0.y && m.f0.y == m.f0.z {
            bound(m.f0.x, 1.0)
        } else {
            m.f0.abs() * bound(1.0, 0.0) + bound(0.0, 1.0)
        }
    }

    /// E/π at tangent-frame direction `nt` (the plain E/π lightmap has no direction: its
    /// value whatever `nt`).
    pub fn irradiance_at(&self, c: &[DVec3], nt: DVec3) -> DVec3 {
        match self.lighting.encoding {
            Encoding::Irradiance => c[0],
            Encoding::Basis(b) => b.irradiance_at(c, nt, self.lighting.sg_sharpness),
        }
    }

    /// E/π at the tangent-frame normal +Z ([`BakedBasis::irradiance_at_normal`]).
    pub fn irradiance(&self, c: &[DVec3]) -> DVec3 {
        self.irradiance_at(c, DVec3::Z)
    }

    /// Specular radiance towards tangent-frame view `vt` (vt.z > 0) with Schlick (f0, f90).
    pub fn specular(&self, c: &[DVec3], vt: DVec3, alpha: f64, f0: f64, f90: f64) -> DVec3 {
        self.specular_at(c, DVec3::Z, vt, alpha, f0, f90)
    }

    /// [`Shader::specular`] at tangent-frame normal `z` (z·vt > 0).
    pub fn specular_at(&self, c: &[DVec3], z: DVec3, vt: DVec3, alpha: f64, f0: f64, f90: f64) -> DVec3 {
        let nv = z.dot(vt);
        let rgb: Vec<[f64; 3]> = c.iter().map(|x| x.to_array()).collect();
        let tables = self.lighting.specular == SpecularPath::Tables;
        let s = match self.lighting.encoding {
            Encoding::Irradiance => [0.0; 3],
            Encoding::Basis(b) if b.is_sh() => {
                let sh = self.sh.as_ref().expect("SH basis");
                let g = sh::specular_zonal_filter(sh.order(), nv, alpha);
                let dfg = sbf::recon::tables::dfg().sample2(nv.clamp(0.0, 1.0) as f32, alpha as f32);
                sh::specular_zonal_rgb(sh, &rgb, &g, z, vt, alpha, f0, f90, [dfg[0] as f64, dfg[1] as f64]).expect("SH coefficients")
            }
            Encoding::Basis(BasisId::Sg9 | BasisId::Sg12) if tables => {
                lobe_ggx::specular_rgb(sbf::recon::tables::lobe_ggx_sg6(), &self.axes, &rgb, z, vt, alpha, f0, f90)
            }
            Encoding::Basis(BasisId::Sg9 | BasisId::Sg12) => {
                let d = sbf::recon::tables::dfg().sample2(nv.clamp(0.0, 1.0) as f32, alpha as f32);
                let w = sg::SplitSumWarp::new(z, vt, alpha, f0, f90, [d[0] as f64, d[1] as f64]);
                let s = self.axes.iter().zip(c).fold(DVec3::ZERO, |acc, (a, ci)| {
                    acc + *ci * w.lobe(&sbf::Sg { axis: *a, sharpness: self.lighting.sg_sharpness, amplitude: 1.0 })
                });
                s.to_array()
            }
            Encoding::Basis(BasisId::Ad9 | BasisId::Ad12) if tables => {
                lobe_ggx::specular_rgb(sbf::recon::tables::lobe_ggx_ad(), &self.axes, &rgb, z, vt, alpha, f0, f90)
            }
            Encoding::Basis(BasisId::Ad9 | BasisId::Ad12) => {
                let l = sbf::recon::tables::ad_specular_2d().sample2(nv.clamp(0.0, 1.0) as f32, alpha as f32);
                ambient_dice::specular_rgb(&self.axes, &rgb, z, vt, alpha, f0, f90, [l[0] as f64, l[1] as f64])
            }
            Encoding::Basis(b) => unreachable!("{b}: not a lightmap basis (Lighting::check refuses it)"),
        };
        DVec3::from(s)
    }
}

/// A dynamic object's terms from interpolated SH L2 probe coefficients (world frame) at
/// unit world normal `n`, view `v`: E/π by SH's band factors, specular by the zonal filter
/// with the split-sum DFG (the runtime's `sh_l2_irradiance`, `sh_l2_specular`).
pub fn probe_terms(c: &[DVec3; 9], m: &SurfaceMaterial, n: DVec3, v: DVec3) -> Terms {
    let ch = |k: usize| sh::irradiance(&c.iter().map(|x| x[k]).collect::<Vec<_>>(), n).expect("9 SH coefficients");
    let diffuse = m.albedo * DVec3::new(ch(0), ch(1), ch(2));
    let nv = n.dot(v);
    if !m.glossy() || nv <= 0.0 {
        return Terms { diffuse, specular: DVec3::ZERO };
    }
    let sh = sbf::ShBasis::new(2).expect("order 2");
    let rgb: Vec<[f64; 3]> = c.iter().map(|x| x.to_array()).collect();
    let g = sh::specular_zonal_filter(2, nv, m.alpha);
    let d = sbf::recon::tables::dfg().sample2(nv.clamp(0.0, 1.0) as f32, m.alpha as f32);
    let s = |f0: f64, f90: f64| {
        DVec3::from(sh::specular_zonal_rgb(&sh, &rgb, &g, n, v, m.alpha, f0, f90, [d[0] as f64, d[1] as f64]).expect("SH L2"))
    };
    let specular = if m.f0.x == m.f0.y && m.f0.y == m.f0.z { s(m.f0.x, 1.0) } else { m.f0 * s(1.0, 0.0) + s(0.0, 1.0) };
    Terms { diffuse, specular }
}
