//! GGX (Trowbridge–Reitz) microfacet pieces in tangent space (normal +Z), isotropic α.
//!
//! - D(h) = α²/(π(α²cos²θ + sin²θ)²) — the math.md form α²/(π((n·h)²(α² − 1) + 1)²)
//!   rewritten with sin²θ = h_x² + h_y² so that α → 1e-4 does not cancel.
//! - Smith Λ(v) = (−1 + √(1 + α²tan²θ))/2 = a/(2(1 + √(1 + a))), a = α²tan²θ.
//! - G1 = 1/(1 + Λ); height-correlated G2 = 1/(1 + Λ(v) + Λ(l)) (Heitz 2014).
//! - Visible-normal sampling and its pdf D_v(h) = G1(v)·max(0, v·h)·D(h)/v_z (Heitz 2018,
//!   "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)).
//!
//! α is clamped by callers, not here; every function is finite for α ∈ [1e-4, 1]
//! and any direction with v_z > 0 (tested). Directions with v_z ≤ 0 give G1 = 0.

use glam::DVec3;
use std::f64::consts::PI;

/// NDF D(h) for a unit half vector h in tangent space; 0 below the surface.
pub fn d(h: DVec3, alpha: f64) -> f64 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let sin2 = h.x * h.x + h.y * h.y;
    let t = a2 * h.z * h.z + sin2;
    a2 / (PI * t * t)
}

/// a = α²·tan²θ for unit v with v_z > 0.
fn a_term(v: DVec3, alpha: f64) -> f64 {
    alpha * alpha * (v.x * v.x + v.y * v.y) / (v.z * v.z)
}

/// Smith Λ(v). Precondition v_z > 0 (debug-asserted); grows without bound as v_z → 0.
pub fn lambda(v: DVec3, alpha: f64) -> f64 {
    debug_assert!(v.z > 0.0, "Smith Λ needs v_z > 0, got {v:?}");
    let a = a_term(v, alpha);
    a / (2.0 * (1.0 + (1.0 + a).sqrt()))
}

/// Smith masking G1(v) = 2/(1 + √(1 + a)); 0 for v_z ≤ 0.
pub fn g1(v: DVec3, alpha: f64) -> f64 {
    if v.z <= 0.0 {
        return 0.0;
    }
    2.0 / (1.0 + (1.0 + a_term(v, alpha)).sqrt())
}

/// Height-correlated masking-shadowing G2(v, l) = 1/(1 + Λ(v) + Λ(l)); 0 if either is below.
pub fn g2(v: DVec3, l: DVec3, alpha: f64) -> f64 {
    if v.z <= 0.0 || l.z <= 0.0 {
        return 0.0;
    }
    1.0 / (1.0 + lambda(v, alpha) + lambda(l, alpha))
}

/// Which GGX specular integral a reference or table computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Convention {
    /// The single-scattering BRDF: per visible-normal sample the weight G2(v, l)/G1(v)
    /// (Heitz 2018, eq. 19), light only from above the surface, Fresnel from the caller.
    #[default]
    Physical,
    /// [Roughton19 Appendix C]'s pipeline, as its code reads: Listing 8.2's
    /// `SmithGGXMaskingShadowingG2OverG1Reflection` returns `numerator / (denominator *
    /// G1Inverse)` = G2(v, l)·G1(v) — every sample scaled by G1(v)² relative to the physical
    /// weight — with Λ of a light below the surface taken from its |cos| (the reference does
    /// not cut at the horizon; the Listing 8.2 table does), and Schlick's Fresnel with
    /// f0 = 0.9, f90 = 1 (the author's Probulator fork, `specularF0` in Common.h).
    AppendixC,
}

impl Convention {
    /// Schlick (f0, f90) the convention fixes (Appendix C), or None (the caller's).
    pub fn fresnel(self) -> Option<(f64, f64)> {
        match self {
            Convention::Physical => None,
            Convention::AppendixC => Some((0.9, 1.0)),
        }
    }

    /// Weight of a visible-normal sample of view v (v_z > 0) that reflects to l, Fresnel
    /// excluded: G2/G1(v), 0 below the surface (physical); G2·G1(v) with Λ(l) from |l_z|,
    /// 0 only at l_z = 0 (Appendix C).
    pub fn vndf_weight(self, v: DVec3, l: DVec3, alpha: f64) -> f64 {
        match self {
            Convention::Physical => {
                let g1 = g1(v, alpha);
                if g1 > 0.0 {
                    g2(v, l, alpha) / g1
                } else {
                    0.0
                }
            }
            Convention::AppendixC => {
                if v.z <= 0.0 || l.z == 0.0 {
                    return 0.0;
                }
                let mirrored = DVec3::new(l.x, l.y, l.z.abs());
                g1(v, alpha) / (1.0 + lambda(v, alpha) + lambda(mirrored, alpha))
            }
        }
    }

    /// Short name for reports: `physical` or `appendix-c`.
    pub fn name(self) -> &'static str {
        match self {
            Convention::Physical => "physical",
            Convention::AppendixC => "appendix-c",
        }
    }
}

/// Samples a visible normal for view v (v_z > 0) from u ∈ [0,1)² (Heitz 2018, Listing 1).
pub fn sample_vndf(v: DVec3, alpha: f64, u: [f64; 2]) -> DVec3 {
    // Stretch the view vector to the hemisphere configuration.
    let vh = DVec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 { DVec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt() } else { DVec3::X };
    let t2 = vh.cross(t1);
    // Uniform disk sample, warped towards the visible half.
    let r = u[0].sqrt();
    let phi = 2.0 * PI * u[1];
    let p1 = r * phi.cos();
    let mut p2 = r * phi.sin();
    let s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    // Unstretch.
    DVec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize()
}

/// Density of [`sample_vndf`] w.r.t. the solid angle of h.
pub fn vndf_pdf(v: DVec3, h: DVec3, alpha: f64) -> f64 {
    if v.z <= 0.0 {
        return 0.0;
    }
    g1(v, alpha) * v.dot(h).max(0.0) * d(h, alpha) / v.z
}

/// Reflects v about h: 2(v·h)h − v.
pub fn reflect(v: DVec3, h: DVec3) -> DVec3 {
    2.0 * v.dot(h) * h - v
}

/// Density of the reflected direction l = reflect(v, h) for h ~ VNDF:
/// D_v(h)/(4 v·h) (Heitz 2018 eq. 17).
pub fn vndf_reflected_pdf(v: DVec3, l: DVec3, alpha: f64) -> f64 {
    let h = v + l;
    if h.length_squared() == 0.0 {
        return 0.0;
    }
    let h = h.normalize();
    let vh = v.dot(h);
    if vh <= 0.0 {
        return 0.0;
    }
    vndf_pdf(v, h, alpha) / (4.0 * vh)
}

/// Schlick's Fresnel weight F_c = (1 − v·h)⁵, so that F = f0·(1 − F_c) + f90·F_c.
#[inline]
pub fn schlick_weight(v_dot_h: f64) -> f64 {
    let x = (1.0 - v_dot_h).clamp(0.0, 1.0);
    let x2 = x * x;
    x2 * x2 * x
}

/// One split-sum DFG entry (Karis 2013): for view cosine `n_dot_v` and α, the
/// directional albedo split as (∫(1 − F_c)·f·cos, ∫F_c·f·cos), so that
/// E = f0·x + f90·y. Estimated with `samples` visible-normal samples from the
/// Hammersley set (weight G2/G1 per sample; Heitz 2018). `n_dot_v` is clamped to
/// [1e-6, 1] and α to [1e-4, 1] (documented clamps: the integrand is undefined at
/// n·v = 0 and α = 0).
pub fn dfg_entry(n_dot_v: f64, alpha: f64, samples: u32) -> [f64; 2] {
    let nv = n_dot_v.clamp(1e-6, 1.0);
    let alpha = alpha.clamp(1e-4, 1.0);
    let v = DVec3::new((1.0 - nv * nv).max(0.0).sqrt(), 0.0, nv);
    let mut acc = [0.0; 2];
    let n = samples.max(1);
    for i in 0..n {
        let u = crate::sampling::hammersley2(i as u64, n as u64);
        let h = sample_vndf(v, alpha, u);
        let l = reflect(v, h);
        if l.z <= 0.0 {
            continue;
        }
        let w = g2(v, l, alpha) / g1(v, alpha);
        let fc = schlick_weight(v.dot(h));
        acc[0] += (1.0 - fc) * w;
        acc[1] += fc * w;
    }
    acc.map(|a| a / n as f64)
}

/// The DFG entry of [`dfg_entry`] by deterministic quadrature — an independent method for
/// checking the tables. In half-vector form
/// ∫ f·cos dl = ∫ D(h)·G2(v, l)·F·(v·h)/(n·v) dω_h (dl = 4(v·h) dω_h), and the GGX NDF's
/// own CDF ξ = tan²θ_h/(α² + tan²θ_h) turns D(h)(n·h) dω_h into dξ dφ/(2π), so the
/// integrand G2·F·(v·h)/((n·v)(n·h)) is bounded on [0, 1] × [0, π] (v in the xz-plane:
/// symmetric in φ). Per ξ the azimuths where l stays above the surface form one interval
/// [0, φ_max] (closed form below), integrated alone, so the rule never straddles the
/// cut-off. Gauss–Legendre: `n` nodes in φ, and in ξ n/8 nodes on each of 52 geometric
/// panels towards ξ = 1; callers state its error by comparing n and 2n. Same clamps as
/// [`dfg_entry`].
pub fn dfg_quadrature(n_dot_v: f64, alpha: f64, n: usize) -> [f64; 2] {
    let mut acc = [0.0; 2];
    reflection_quadrature(n_dot_v, alpha, n, (n / 8).max(4), |_, fc, wt, val| {
        acc[0] += wt * (1.0 - fc) * val;
        acc[1] += wt * fc * val;
    });
    acc
}

/// The nodes of [`dfg_quadrature`]'s rule for any integrand g(l) over the GGX lobe:
/// ∫ g(l)·f(v, l)·cos θ_l dl ≈ Σ wt·val·g(l) with F ≡ 1, Schlick's weight F_c = `fc`
/// passed along (F = f0(1 − F_c) + f90·F_c). Normal +Z, v = (√(1 − (n·v)²), 0, n·v).
/// Only the half φ_h ∈ [0, φ_max] is visited and `wt` counts both halves: an integrand
/// that is not symmetric under y → −y must average g at l and at (l.x, −l.y, l.z).
/// `n` Gauss–Legendre nodes in φ_h, `m` in ξ on each of the 52 panels. Calls
/// `visit(l, fc, wt, val)`.
pub fn reflection_quadrature(n_dot_v: f64, alpha: f64, n: usize, m: usize, mut visit: impl FnMut(DVec3, f64, f64, f64)) {
    let nv = n_dot_v.clamp(1e-6, 1.0);
    let alpha = alpha.clamp(1e-4, 1.0);
    let v = DVec3::new((1.0 - nv * nv).max(0.0).sqrt(), 0.0, nv);
    let (x, w) = crate::quadrature::gauss_legendre(n.max(1));
    // ξ on geometric panels [1 − 2^−i, 1 − 2^−(i+1)], i < 52, with m nodes each: at grazing
    // views only the NDF's tail (ξ → 1) reflects above the horizon.
    let (xp, wp_) = crate::quadrature::gauss_legendre(m.max(1));
    let xi_nodes: Vec<(f64, f64)> = (0..52)
        .flat_map(|i| {
            let (a, b) = (1.0 - 0.5f64.powi(i), 1.0 - 0.5f64.powi(i + 1));
            xp.iter().zip(&wp_).map(move |(t, wt)| (a + 0.5 * (b - a) * (t + 1.0), 0.5 * (b - a) * wt)).collect::<Vec<_>>()
        })
        .collect();
    for &(xi, dxi) in &xi_nodes {
        // tan²θ = α²ξ/(1 − ξ): cos²θ = (1 − ξ)/(1 − ξ + α²ξ).
        let c2 = (1.0 - xi) / (1.0 - xi + alpha * alpha * xi);
        let (ct, st) = (c2.sqrt(), (1.0 - c2).max(0.0).sqrt());
        // l_z = 2(v·h)h_z − v_z > 0 ⇔ cos φ > c* = (n·v/(2h_z) − n·v·h_z)/(v_x sin θ_h): the
        // valid azimuths are [0, φ_max], integrated alone so the rule never meets the cut.
        let den = v.x * st;
        let cstar = if den > 0.0 {
            (nv / (2.0 * ct) - nv * ct) / den
        } else if 2.0 * nv * ct * ct > nv {
            -1.0
        } else {
            1.0
        };
        let phi_max = cstar.clamp(-1.0, 1.0).acos();
        if phi_max <= 0.0 {
            continue;
        }
        for (phi_node, wp) in x.iter().zip(&w) {
            let phi = 0.5 * phi_max * (phi_node + 1.0);
            let h = DVec3::new(st * phi.cos(), st * phi.sin(), ct);
            let vh = v.dot(h);
            if vh <= 0.0 || ct <= 0.0 {
                continue;
            }
            let l = reflect(v, h);
            if l.z <= 0.0 {
                continue;
            }
            let val = g2(v, l, alpha) * vh / (nv * ct);
            // Weights: dξ, dφ = (φ_max/2) dy, both halves of [−π, π] (symmetry), / 2π.
            let wt = dxi * wp * 0.5 * phi_max * 2.0 / (2.0 * PI);
            visit(l, schlick_weight(vh), wt, val);
        }
    }
}

/// GGX dominant direction (Listing 8.2, after Lagarde & de Rousiers 2014):
/// normalize(mix(N, R, s·(√s + α))) with s = saturate(1 − α).
pub fn dominant_direction(n: DVec3, r: DVec3, alpha: f64) -> DVec3 {
    let s = (1.0 - alpha).clamp(0.0, 1.0);
    let f = s * (s.sqrt() + alpha);
    (n + (r - n) * f).normalize()
}
