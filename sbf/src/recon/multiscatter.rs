//! Multiple scattering on the GGX microsurface: the random-walk reference and the runtime's
//! energy compensation.
//!
//! - **Reference**: the stochastic microsurface walk of Heitz, Hanika, d'Eon and Dachsbacher
//!   2016 ("Multiple-Scattering Microfacet BSDFs with the Smith Model", SIGGRAPH; §4 and its
//!   supplemental conductor walk): uncorrelated heights with the uniform height distribution
//!   C1(h) = (h + 1)/2 on [−1, 1], GGX slopes, each scattering event a visible normal for the
//!   incoming direction and a mirror reflection weighted by Schlick's Fresnel, the next
//!   height from the Smith shadowing with height (their eqs. 15–17). Its first-order term is
//!   the single-scattering BRDF with height-correlated G2 (tested against
//!   [`crate::ggx::dfg_quadrature`]); with F ≡ 1 no energy is lost and the albedo is 1.
//!   Visible normals for any incoming direction, including from below the mean surface
//!   (directions after a first bounce), come from the spherical-cap construction of Dupuy
//!   and Benyoub 2023 ("Sampling Visible GGX Normals with Spherical Caps", HPG), exact for
//!   every direction.
//! - **Runtime**: the single-scattering response scaled by 1 + f0·(1/E − 1), E the
//!   single-scattering albedo at f0 = f90 = 1 (the DFG table's two channels summed): the
//!   energy lost to single scattering added back with the lobe's shape (Fdez-Agüera 2019,
//!   "A Multiple-Scattering Microfacet Model for Real-Time Image-based Lighting", JCGT 8(1);
//!   as Filament, §4.7.2 of its material documentation). With f0 = 1 the compensated albedo is
//!   the true single-scattering albedo over the table's — 1 up to the table's error.

use crate::ggx;
use crate::sampling::Pcg32;
use glam::DVec3;
use std::f64::consts::PI;

/// The compensation factor 1 + f0·(1/E − 1) for single-scattering albedo `e` (at f0 = f90 =
/// 1; `e` ≤ 0 or NaN gives 1: no compensation from an unusable table value).
pub fn energy_compensation(e: f64, f0: f64) -> f64 {
    if e > 0.0 {
        1.0 + f0 * (1.0 / e - 1.0)
    } else {
        1.0
    }
}

/// Smith Λ for a direction on either side of the mean surface: the usual Λ above, and
/// Λ(ω) = −1 − Λ(−ω) below (Heitz et al. 2016, §3: the shadowing of a downward ray).
fn lambda_any(w: DVec3, alpha: f64) -> f64 {
    if w.z >= 0.0 {
        if w.z >= 1.0 {
            return 0.0;
        }
        ggx::lambda(w, alpha)
    } else {
        -1.0 - lambda_any(-w, alpha)
    }
}

/// Uniform height distribution on [−1, 1]: its CDF and inverse.
fn c1(h: f64) -> f64 {
    (0.5 * (h + 1.0)).clamp(0.0, 1.0)
}
fn inv_c1(u: f64) -> f64 {
    (2.0 * u - 1.0).clamp(-1.0, 1.0)
}

/// The height of the next intersection of a ray leaving height `h` in direction `w`, or
/// None when it leaves the microsurface (Heitz et al. 2016, eqs. 16–17, uniform heights):
/// an upward ray escapes with probability G1(w, h) = C1(h)^Λ(w); otherwise, and always for
/// a downward ray (Λ ≤ −1), the height solves C1(h') = C1(h)/(1 − u)^(1/Λ(w)).
fn next_height(w: DVec3, h: f64, u: f64, alpha: f64) -> Option<f64> {
    if w.z >= 0.9999 {
        return None;
    }
    if w.z <= -0.9999 {
        return Some(inv_c1(u * c1(h)));
    }
    if w.z.abs() < 1e-4 {
        return Some(h);
    }
    let lam = lambda_any(w, alpha);
    if w.z > 0.0 && u > 1.0 - c1(h).powf(lam) {
        return None;
    }
    Some(inv_c1(c1(h) / (1.0 - u).powf(1.0 / lam)))
}

/// A visible normal of the GGX microsurface (isotropic α) for the direction `wi` pointing
/// away from it, above or below the mean surface (Dupuy and Benyoub 2023, Listing 3): a
/// point on the spherical cap {z ≥ −wi.z} of the stretched configuration plus wi, unstretched.
pub fn sample_visible_normal(wi: DVec3, alpha: f64, u: [f64; 2]) -> DVec3 {
    let s = DVec3::new(alpha * wi.x, alpha * wi.y, wi.z).normalize();
    let phi = 2.0 * PI * u[0];
    let z = (1.0 - u[1]) * (1.0 + s.z) - s.z;
    let st = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
    let h = DVec3::new(st * phi.cos(), st * phi.sin(), z) + s;
    DVec3::new(alpha * h.x, alpha * h.y, h.z.max(0.0)).normalize()
}

/// What a set of walks measured for one view: the directional albedo (energy leaving,
/// per unit entering), its single-scattering part, and their standard errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkAlbedo {
    /// Directional albedo: mean energy leaving per walk.
    pub total: f64,
    /// Its standard error.
    pub total_sigma: f64,
    /// The part that left after exactly one scattering event.
    pub single: f64,
    /// Its standard error.
    pub single_sigma: f64,
    /// Mean number of scattering events per walk.
    pub mean_order: f64,
    /// Walks stopped at [`MAX_ORDER`] events (their energy counted as lost).
    pub truncated: u64,
}

/// Scattering events after which a walk is stopped (the energy left then is < 1e-6 of the
/// total at every α; reported as `truncated`).
pub const MAX_ORDER: u32 = 256;

/// One walk for the view `v` (n = +Z, v.z > 0): the energy that leaves, its scattering
/// order and exit direction (None when truncated).
pub fn walk(v: DVec3, alpha: f64, f0: f64, rng: &mut Pcg32) -> (f64, u32, Option<DVec3>) {
    let alpha = alpha.clamp(1e-4, 1.0);
    let mut w = -v;
    let mut h = 1.0 + inv_c1(0.999);
    let mut energy = 1.0;
    for order in 0..=MAX_ORDER {
        let next = next_height(w, h, rng.next_f64(), alpha);
        let Some(hn) = next else { return (energy, order, Some(w)) };
        if order == MAX_ORDER {
            break;
        }
        h = hn;
        let wi = -w;
        let m = sample_visible_normal(wi, alpha, [rng.next_f64(), rng.next_f64()]);
        let c = wi.dot(m).max(0.0);
        energy *= f0 + (1.0 - f0) * ggx::schlick_weight(c);
        w = -wi + 2.0 * c * m;
    }
    (energy, MAX_ORDER, None)
}

/// Directional albedo of the multiple-scattering GGX conductor (Schlick f0, f90 = 1) for
/// view cosine `n_dot_v`, from `walks` random walks seeded by `seed`.
pub fn albedo(n_dot_v: f64, alpha: f64, f0: f64, walks: u64, seed: u64) -> WalkAlbedo {
    let nv = n_dot_v.clamp(1e-6, 1.0);
    let v = DVec3::new((1.0 - nv * nv).max(0.0).sqrt(), 0.0, nv);
    // PCG32's seed is added to its state: nearby seeds give related streams. SplitMix64's
    // finaliser (Steele, Lea and Flood 2014) first, so any two seeds are unrelated.
    let mut z = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    let mut rng = Pcg32::new(z ^ (z >> 31), 0x6d75_6c74_6973_6361);
    let (mut s1, mut s2, mut t1, mut t2, mut orders, mut truncated) = (0.0, 0.0, 0.0, 0.0, 0u64, 0u64);
    for _ in 0..walks {
        let (e, order, out) = walk(v, alpha, f0, &mut rng);
        if out.is_none() {
            truncated += 1;
            continue;
        }
        orders += order as u64;
        t1 += e;
        t2 += e * e;
        if order == 1 {
            s1 += e;
            s2 += e * e;
        }
    }
    let n = walks.max(1) as f64;
    let sd = |a: f64, b: f64| ((b / n - (a / n).powi(2)).max(0.0) / n).sqrt();
    WalkAlbedo {
        total: t1 / n,
        total_sigma: sd(t1, t2),
        single: s1 / n,
        single_sigma: sd(s1, s2),
        mean_order: orders as f64 / n,
        truncated,
    }
}
