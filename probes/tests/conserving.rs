//! The conserving NNLS modes (`probes::conserving`) on a map that defeats plain NNLS: a dim
//! sky and an 8° cap 30–40× brighter, the shape docs/probes.md measured `sgnnls` ×1.10 on.
//!
//! Oracles, independent of the solver:
//! - **The equalities**: the fit's SH L0 + L1 projections, integrated here over the fitted
//!   radiance Σ c_i B_i(ω) on a spherical Fibonacci set (not the solver's Gauss rule), must equal
//!   the map's, summed here over its texels (L·Y_lm·Ω; band 1 is K₁·(y, z, x), written out).
//!   Error model: the Fibonacci rule's error, estimated as twice the difference between N and
//!   N/4 points, plus the solver's equality residual (1e-10 relative).
//! - **The mean of E/π over all normals** equals the mean radiance, (1/4π)∫L (∫max(0, n·ω)dn =
//!   π for every ω), so a fit that keeps L0 has the reference's mean irradiance. The Ambient Dice
//!   lobes' E/π is exact (a quartic), so the ratio of the mode's mean E/π to the exact
//!   reference's, both on the output grid, is 1 within the grid's midpoint rule on two smooth
//!   functions (relative ≲ 2·(π/H)²/24 × a second-derivative ratio ≤ 4 for each) — plain NNLS
//!   of the same moments misses that bar (the test asserts it does). SG uses Hill's fitted curve,
//!   whose recorded error (`HILL_C0_MAX_ERROR`, of a lobe's peak, ≤ 4× its mean over normals)
//!   adds to the bar.
//! - **Progressive**: 4096 Halton samples in f32; the moments' error is bounded by 5 standard
//!   errors of the i.i.d. estimator (Halton does at least as well on these integrands) plus f32
//!   running-mean rounding (4096·2⁻²⁴ relative). Roughton's progressive encoder misses its
//!   limit by ×0.63–0.78 on the built-in sky (docs/probes.md); the bar here is ≈ 3 %.

use probes::conserving::Problem;
use probes::modes::{prepare, Context};
use sbf::envmap::LatLongImage;
use sbf::glam::DVec3;
use sbf::solve::{moments, nnls_gram, NnlsOptions};
use sbf::{AmbientDiceSrbf, Basis, Domain, SgBasis};
use std::f64::consts::PI;
use std::sync::Arc;

const K0: f64 = 0.282_094_791_773_878_14;
const K1: f64 = 0.488_602_511_902_919_9;

fn sun_dir() -> DVec3 {
    DVec3::new(0.3, 0.8, -0.5).normalize()
}

/// The sharp source: an 8° sun in [`sun_dir`], 4 000× the sky's brightness.
fn sun() -> LatLongImage {
    let (w, cos0) = (sun_dir(), 8f64.to_radians().cos());
    LatLongImage::from_fn(256, 128, |d| if d.dot(w) >= cos0 { [40.0, 30.0, 20.0] } else { [0.01, 0.008, 0.005] }).unwrap()
}

fn sh4(d: DVec3) -> [f64; 4] {
    [K0, K1 * d.y, K1 * d.z, K1 * d.x]
}

/// The map's SH L0 + L1 by its texels (4 × RGB).
fn map_sh(ctx: &Context) -> [[f64; 3]; 4] {
    let mut out = [[0.0; 3]; 4];
    for s in &ctx.samples {
        for (o, y) in out.iter_mut().zip(sh4(s.direction)) {
            for c in 0..3 {
                o[c] += s.weight * s.value[c] * y;
            }
        }
    }
    out
}

/// The fitted radiance's SH L0 + L1 on a spherical Fibonacci set of `n` points.
fn fit_sh(basis: &dyn Basis, c: &[[f64; 3]], n: u64) -> [[f64; 3]; 4] {
    let mut out = [[0.0; 3]; 4];
    let mut b = vec![0.0; basis.len()];
    for k in 0..n {
        let d = sbf::sampling::spherical_fibonacci(k, n);
        basis.eval_into(d, &mut b);
        let y = sh4(d);
        for ch in 0..3 {
            let l: f64 = b.iter().zip(c).map(|(bi, ci)| bi * ci[ch]).sum();
            for m in 0..4 {
                out[m][ch] += 4.0 * PI / n as f64 * l * y[m];
            }
        }
    }
    out
}

/// The standard error of the i.i.d. estimate of ∫Y_m·L (channel c) from 4096 uniform
/// directions: √((4π∫Y_m²L² − (∫Y_m L)²)/4096), the integrals over the map's texels. Halton
/// points do at least as well on these integrands (bounded variation), so 5σ bounds the
/// progressive modes' moments.
fn sigma(ctx: &Context, m: usize, c: usize) -> f64 {
    let (mut s1, mut s2) = (0.0, 0.0);
    for s in &ctx.samples {
        let yl = sh4(s.direction)[m] * s.value[c];
        s1 += s.weight * yl;
        s2 += s.weight * yl * yl;
    }
    ((4.0 * PI * s2 - s1 * s1).max(0.0) / 4096.0).sqrt()
}

/// Solid-angle-weighted mean of an image over the output grid, per channel.
fn grid_mean(ctx: &Context, img: &[[f64; 3]]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (k, v) in img.iter().enumerate() {
        let w = ctx.grid.texel_solid_angle(k / ctx.grid.width);
        for c in 0..3 {
            s[c] += w * v[c];
        }
    }
    s.map(|x| x / (4.0 * PI))
}

fn basis_of(id: &str) -> Arc<dyn Basis + Send + Sync> {
    if id.starts_with("sg") {
        Arc::new(SgBasis::new(&sbf::layout::vogel_sphere(12).unwrap(), 6.0, false).unwrap())
    } else {
        Arc::new(AmbientDiceSrbf::twelve())
    }
}

/// The midpoint rule's relative error bar on the output grid (module docs).
fn grid_bar(ctx: &Context) -> f64 {
    2.0 * 2.0 * (PI / ctx.grid.height as f64).powi(2) / 24.0 * 4.0
}

/// The largest |L1|/L0 of any one basis function (its SH projections on the Fibonacci set).
/// A non-negative combination cannot exceed it (|Σc_i v_i| ≤ Σc_i|v_i| ≤ r·Σc_i u_i), so a
/// channel whose |L1|/L0 is larger has no non-negative fit that keeps both.
fn max_lobe_l1_ratio(basis: &dyn Basis) -> f64 {
    (0..basis.len())
        .map(|i| {
            let mut c = vec![[0.0; 3]; basis.len()];
            c[i] = [1.0; 3];
            let y = fit_sh(basis, &c, 1 << 16);
            (y[1][0].powi(2) + y[2][0].powi(2) + y[3][0].powi(2)).sqrt() / y[0][0]
        })
        .fold(0.0, f64::max)
}

#[test]
fn conserving_fits_keep_the_maps_sh_l0_l1_and_its_mean_irradiance() {
    // The sun: |L1|/L0 above every lobe's, so each channel keeps L0 alone (proved per channel
    // below, independently of the solver); batch modes only: the i.i.d. error bound of 4096
    // point samples of a 4 000:1 sun is wider than the quantity (Halton does far better, but
    // has no simple bound). A smooth map L = a(1 + b·ω), |L1|/L0 = (K₁/K₀)|b|/3 = 0.35: all four
    // equalities, all four modes.
    let ctx = Context::new(sun());
    check_map("sun 8°", &ctx, &["adnnlsc", "sgnnlsc"]);
    let (a, b) = ([1.0, 0.7, 0.4], DVec3::new(-0.2, 0.5, 0.3));
    let ctx = Context::new(LatLongImage::from_fn(256, 128, |d| a.map(|ak| ak * (1.0 + b.dot(d)))).unwrap());
    check_map("linear", &ctx, &["adnnlsc", "sgnnlsc", "adpnnlsc", "sgpnnlsc"]);
}

fn check_map(name: &str, ctx: &Context, ids: &[&str]) {
    let want = map_sh(ctx);
    let refmean = grid_mean(ctx, &ctx.irradiance);
    for id in ids {
        let id = *id;
        let r = prepare(id, ctx, 1).unwrap().result;
        let basis = basis_of(id);
        let rmax = max_lobe_l1_ratio(basis.as_ref());
        let (fine, coarse) = (fit_sh(basis.as_ref(), &r.coefficients, 1 << 18), fit_sh(basis.as_ref(), &r.coefficients, 1 << 16));
        // Progressive: the moments' standard error (i.i.d. bound) per SH function and channel.
        let progressive = id.contains("pnnls");
        let mut l0_only = 0;
        for c in 0..3 {
            let ratio = (want[1][c].powi(2) + want[2][c].powi(2) + want[3][c].powi(2)).sqrt() / want[0][c];
            let infeasible = ratio > rmax;
            println!("{name} {id} ch {c}: map |L1|/L0 {ratio:.4}, lobes' max {rmax:.4}");
            l0_only += infeasible as usize;
            for m in 0..if infeasible { 1 } else { 4 } {
                let quad = 2.0 * (fine[m][c] - coarse[m][c]).abs();
                let scale = want[0][c].abs();
                let mc = if progressive { 5.0 * sigma(ctx, m, c) + 4096.0 * 2f64.powi(-24) * scale } else { 0.0 };
                let tol = quad + 1e-10 * scale + mc;
                let e = (fine[m][c] - want[m][c]).abs();
                println!("{name} {id} SH {m} ch {c}: fit {:.6} map {:.6} |e| {e:.2e} tol {tol:.2e}", fine[m][c], want[m][c]);
                assert!(e <= tol, "{name} {id}: SH function {m} channel {c}: fit {} vs map {} (tol {tol:.2e})", fine[m][c], want[m][c]);
            }
        }
        assert_eq!(r.solver.contains("L0 alone"), l0_only > 0, "{name} {id}: solver '{}' vs {l0_only} infeasible channels", r.solver);
        // Mean E/π over all normals (the progressive modes' L0 carries its Monte Carlo error).
        let got = grid_mean(ctx, &r.irradiance);
        let hill = if id.starts_with("sg") { 4.0 * sbf::luts::committed::constants::HILL_C0_MAX_ERROR } else { 0.0 };
        for c in 0..3 {
            let ratio = got[c] / refmean[c];
            // The L0 estimate's relative standard error ×5.
            let mc = if progressive { 5.0 * sigma(ctx, 0, c) / want[0][c] } else { 0.0 };
            let bar = grid_bar(ctx) + hill + mc;
            println!("{name} {id} channel {c}: mean E/π ratio {ratio:.5} (bar ±{bar:.2e})");
            assert!((ratio - 1.0).abs() <= bar, "{name} {id} channel {c}: mean E/π {ratio:.5} of the reference's (bar {bar:.2e})");
        }
    }
}

/// The same moments without the equalities (plain NNLS) miss the mean-irradiance bar: the
/// test above can fail, and the map is one where the constraint matters.
#[test]
fn plain_nnls_of_the_same_moments_misses_the_bar() {
    let ctx = Context::new(sun());
    let refmean = grid_mean(&ctx, &ctx.irradiance);
    let p = Problem::new(Arc::new(AmbientDiceSrbf::twelve())).unwrap();
    let m = moments(p.basis(), &ctx.samples);
    let g = sbf::gram::gram_matrix(p.basis(), Domain::Sphere, Default::default()).unwrap().matrix;
    let ad = AmbientDiceSrbf::twelve();
    let mut worst = 0.0f64;
    for c in 0..3 {
        let col: Vec<f64> = m.column(c).iter().copied().collect();
        let x = nnls_gram(&g, &col, NnlsOptions::default()).unwrap().coeffs;
        let img: Vec<[f64; 3]> = ctx
            .dirs
            .iter()
            .map(|d| {
                let e: f64 = ad.lobes().iter().zip(&x).map(|(a, xi)| xi * sbf::recon::ambient_dice::lobe_irradiance_cos(a.dot(*d))).sum();
                [e; 3]
            })
            .collect();
        let ratio = grid_mean(&ctx, &img)[0] / refmean[c];
        println!("plain AD 12 NNLS channel {c}: mean E/π ratio {ratio:.4}");
        worst = worst.max((ratio - 1.0).abs());
    }
    assert!(worst > 10.0 * grid_bar(&ctx), "plain NNLS keeps the mean irradiance here ({worst:.2e}): the map does not test the constraint");
}
