//! probes against independent computations: the exact reference vs brute force, SH L2
//! irradiance RMS, coefficients in results.json vs a dense design-matrix solve, and the
//! irradiance RMS of every peer-equivalent mode vs the peer's figures (peers.md).

use probes::{metrics, modes, reference, report};
use sbf::glam::DVec3;
use sbf::nalgebra::DMatrix;
use std::f64::consts::PI;
use std::path::PathBuf;

fn probe(name: &str) -> Option<sbf::envmap::LatLongImage> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../shared/probes/{name}.hdr"));
    if !p.exists() {
        assert!(
            std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"),
            "SBF_REQUIRE_PROBES=1 but {} is missing (the bundled probes live in ../shared/probes)",
            p.display()
        );
        eprintln!("skipping: {} not found", p.display());
        return None;
    }
    Some(probes::input::load_map(&p, false).unwrap().0)
}

/// The reference against the exact irradiance of the map — the piecewise-constant
/// radiance integrated over each texel's true area, not the reference's midpoint rule:
/// each texel's ∫max(0, n·ω)dω is computed here on a 16 × 16 sub-grid in (φ, cos θ)
/// (equal-area cells), at 24 output directions on uffizi (a sun-lit probe).
/// Error model, per texel of solid angle Ω and angular size h (max of Δθ and Δφ·sinθ):
/// the midpoint rule on c(ω) = n·ω errs by ≤ Ω·h²/8·max|∇²c| ≤ Ω·h²/8 where c > 0 on the
/// whole texel, and by ≤ Ω·h where the horizon (the kink of max(0, c)) crosses it; the
/// sub-grid oracle has the same model at h/16. The bound Σ L·(those terms)/π is computed
/// per direction and asserted; a wrong solid angle, centre or cosine breaks it by far more.
#[test]
fn reference_is_the_exact_map_irradiance_within_the_midpoint_bound() {
    let Some(map) = probe("uffizi") else { return };
    let g = map.geometry;
    let (w, h) = (g.width, g.height);
    let mut rng = sbf::sampling::Pcg32::new(9, 9);
    let dirs: Vec<DVec3> = (0..24).map(|_| sbf::sampling::uniform_sphere(rng.next_2d())).collect();
    let fast = reference::irradiance_image(&map, &dirs);
    const S: usize = 16;
    let mut worst = 0.0f64;
    for (d, f) in dirs.iter().zip(&fast) {
        let (mut exact, mut bound) = ([0.0f64; 3], 0.0f64);
        for j in 0..h {
            let (t0, t1) = (PI * j as f64 / h as f64, PI * (j + 1) as f64 / h as f64);
            let (z0, z1) = (t0.cos(), t1.cos());
            let omega = 2.0 * PI / w as f64 * (z0 - z1);
            let size = (PI / h as f64).max(2.0 * PI / w as f64 * t0.sin().max(t1.sin()));
            for i in 0..w {
                let t = map.texel(i, j);
                let lum = t.iter().fold(0.0f32, |a, v| a.max(*v)) as f64;
                let (p0, p1) = (PI * (2.0 * i as f64 / w as f64 - 1.0), PI * (2.0 * (i + 1) as f64 / w as f64 - 1.0));
                let (mut integral, mut lo, mut hi) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
                for a in 0..S {
                    let psi = p0 + (p1 - p0) * (a as f64 + 0.5) / S as f64;
                    for b in 0..S {
                        let y = z0 + (z1 - z0) * (b as f64 + 0.5) / S as f64;
                        let st = (1.0 - y * y).max(0.0).sqrt();
                        let dir = DVec3::new(st * psi.sin(), y, -st * psi.cos());
                        let c = d.dot(dir);
                        lo = lo.min(c);
                        hi = hi.max(c);
                        integral += c.max(0.0);
                    }
                }
                let integral = integral * omega / (S * S) as f64;
                for k in 0..3 {
                    exact[k] += t[k] as f64 * integral / PI;
                }
                // The texel straddles the horizon if the cosine changes sign inside it
                // (sub-grid extremes widened by one texel size).
                let kink = lo - size < 0.0 && hi + size > 0.0;
                let per = if kink {
                    omega * size * (1.0 + 1.0 / S as f64)
                } else if hi + size > 0.0 {
                    omega * size * size / 8.0 * (1.0 + 1.0 / (S * S) as f64)
                } else {
                    0.0
                };
                bound += lum * per / PI;
            }
        }
        for k in 0..3 {
            let err = (f[k] - exact[k]).abs();
            worst = worst.max(err / bound.max(1e-300));
            assert!(err <= bound, "{d} channel {k}: reference {} vs exact {} (error {err:.3e} > bound {bound:.3e})", f[k], exact[k]);
        }
    }
    println!("reference vs exact map irradiance: worst error / bound {worst:.3}");
}

/// SH L2 irradiance RMS from the mode equals an independent computation (hand-written
/// real SH L2 polynomials with the Condon–Shortley-free convention, texel projection,
/// band factors 1, 2/3, 1/4) within 2%.
#[test]
fn shl2_rms_matches_independent_computation() {
    let Some(map) = probe("pisa") else { return };
    let ctx = modes::Context::new(map.clone());
    let r = modes::run("shl2", &ctx, 1).unwrap();
    let ours = metrics::compute(ctx.grid, &r.irradiance, &ctx.irradiance).rms;
    let y = |d: DVec3| {
        let (x, yy, z) = (d.x, d.y, d.z);
        [
            0.282095,
            0.488603 * yy,
            0.488603 * z,
            0.488603 * x,
            1.092548 * x * yy,
            1.092548 * yy * z,
            0.315392 * (3.0 * z * z - 1.0),
            1.092548 * x * z,
            0.546274 * (x * x - yy * yy),
        ]
    };
    let g = map.geometry;
    let mut c = [[0.0f64; 3]; 9];
    for j in 0..g.height {
        for i in 0..g.width {
            let b = y(g.texel_direction(i, j));
            let t = map.texel(i, j);
            for k in 0..9 {
                for ch in 0..3 {
                    c[k][ch] += g.texel_solid_angle(j) * b[k] * t[ch] as f64;
                }
            }
        }
    }
    let band = [1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25];
    let mut se = 0.0;
    for (d, e) in ctx.dirs.iter().zip(&ctx.irradiance) {
        let b = y(*d);
        for ch in 0..3 {
            let v: f64 = (0..9).map(|k| band[k] * c[k][ch] * b[k]).sum::<f64>().max(0.0);
            se += (v - e[ch]).powi(2);
        }
    }
    let indep = (se / (3 * ctx.dirs.len()) as f64).sqrt();
    assert!((ours / indep - 1.0).abs() < 0.02, "shl2 RMS {ours} vs independent {indep}");
}

/// adrbf, shl2 and sgls coefficients as written to results.json equal a dense
/// design-matrix least-squares solve (QR on √Ω-weighted texels) within 1e-4 relative.
#[test]
fn results_json_coefficients_match_dense_ls() {
    let Some(map) = probe("wells") else { return };
    let ctx = modes::Context::new(map.clone());
    let rows: Vec<report::Row> = ["adrbf", "shl2", "sgls"]
        .iter()
        .map(|id| {
            let r = modes::run(id, &ctx, 1).unwrap();
            let irradiance = metrics::compute(ctx.grid, &r.irradiance, &ctx.irradiance);
            report::Row {
                result: r,
                radiance: None,
                irradiance,
                specular: Vec::new(),
                specular_images: Vec::new(),
                specular_parts: Vec::new(),
                split_sum_parts: Vec::new(),
                specular_cost: None,
            }
        })
        .collect();
    let json = probes::results::to_json(&[probes::results::from_report(
        &report::MapReport {
            path: "wells".into(),
            width: 256,
            height: 128,
            domain: "sphere",
            reference_method: String::new(),
            storage: probes::storage::Storage::F32,
            sanitized: 0,
            rows,
            specular_method: String::new(),
            specular_runtime: String::new(),
            runtime: Default::default(),
            convention: Default::default(),
            specular_samples: 0,
            specular_reference: Vec::new(),
            grid: ctx.grid,
            reference: ctx.irradiance.clone(),
            radiance: ctx.radiance(),
            slug: "wells".into(),
            stages: Default::default(),
        },
        false,
        None,
    )]);
    let v: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    let bases: Vec<(&str, Box<dyn sbf::Basis>)> = vec![
        ("adrbf", Box::new(sbf::AmbientDiceSrbf::twelve())),
        ("shl2", Box::new(sbf::ShBasis::new(2).unwrap())),
        ("sgls", Box::new(sbf::SgBasis::new(&vogel, 6.0, false).unwrap())),
    ];
    let g = map.geometry;
    for (k, (id, basis)) in bases.iter().enumerate() {
        let mode = &v[0]["modes"][k];
        assert_eq!(mode["id"], *id);
        let n = basis.len();
        let a = DMatrix::from_fn(g.texel_count(), n, |r, c| basis.eval(g.texel_direction(r % g.width, r / g.width))[c]);
        let y = DMatrix::from_fn(g.texel_count(), 3, |r, c| map.texel(r % g.width, r / g.width)[c] as f64);
        let w: Vec<f64> = (0..g.texel_count()).map(|r| g.texel_solid_angle(r / g.width)).collect();
        let dense = sbf::solve::solve_design(&a, &y, Some(&w), Default::default()).unwrap().coeffs;
        let scale = dense.abs().max();
        for i in 0..n {
            for c in 0..3 {
                let got = mode["coefficients"][i][c].as_f64().unwrap();
                assert!((got - dense[(i, c)]).abs() <= 1e-4 * scale, "{id} coefficient {i}/{c}: {got} vs {}", dense[(i, c)]);
            }
        }
    }
}

/// Irradiance RMS (unweighted) on the five probes ≤ 1.05 × the peer's figure for every
/// mode with a peer equivalent, with the default reconstruction (`--sg-irradiance auto`:
/// the peer's kernel for `sg` and `sgnnls`, the isotropic-prior estimate for `sgls` and
/// `sglsa`, Hill for the running averages), no exceptions. Printed for the SG LS/NNLS
/// modes: the figures with Hill and with the peer's kernel on the same coefficients.
/// Mutation tried: `auto` resolved to Hill for every SG mode — wells sgls, sglsa, sgnnls
/// fail (1.09, 1.13, 1.12).
#[test]
fn peer_figures() {
    let peer: [(&str, [f64; 5]); 17] = [
        ("shl2w", [0.6529, 0.01325, 0.005104, 0.2574, 0.007624]),
        ("ad", [0.03926, 0.007710, 0.003644, 0.01827, 0.005074]),
        ("adycocg", [0.04087, 0.009742, 0.005361, 0.01889, 0.006723]),
        ("sgra", [0.2446, 0.06620, 0.01344, 0.09502, 0.02785]),
        ("sgnnra", [0.8078, 0.1161, 0.02198, 0.1596, 0.04495]),
        ("ac", [0.3966, 0.04363, 0.03412, 0.1810, 0.04870]),
        ("acproj", [0.4644, 0.05156, 0.03809, 0.2189, 0.05559]),
        ("shl1g", [0.2921, 0.04117, 0.03757, 0.1355, 0.05467]),
        ("shl1zh3", [0.1615, 0.04191, 0.02514, 0.08505, 0.03505]),
        ("shl1", [0.5050, 0.08238, 0.02349, 0.2737, 0.05400]),
        ("shl2", [0.09402, 0.01325, 0.005104, 0.03877, 0.007624]),
        ("shl4", [0.03108, 0.005804, 0.001749, 0.01255, 0.004395]),
        ("adrbf-irr", [0.1053, 0.01484, 0.004273, 0.05691, 0.007150]),
        ("sg", [0.4330, 0.08526, 0.02263, 0.1618, 0.02957]),
        ("sgls", [0.4079, 0.09037, 0.01860, 0.1441, 0.02407]),
        ("sglsa", [0.4058, 0.09598, 0.01858, 0.1433, 0.02355]),
        ("sgnnls", [0.7927, 0.1235, 0.02434, 0.1937, 0.03816]),
    ];
    let names = ["ennis", "grace", "pisa", "uffizi", "wells"];
    let mut failures = Vec::new();
    for (pi, name) in names.iter().enumerate() {
        let Some(map) = probe(name) else { return };
        let mut ctx = modes::Context::new(map);
        for (id, figs) in &peer {
            ctx.sg_irradiance = modes::SgIrradiance::Auto;
            let r = modes::run(id, &ctx, 1).unwrap();
            let rms = metrics::compute(ctx.grid, &r.irradiance, &ctx.irradiance).rms;
            let ratio = rms / figs[pi];
            let mut line = format!("{name:>7} {id:>10}: {rms:.5} vs peer {:.5} ({ratio:.3})", figs[pi]);
            if matches!(*id, "sgls" | "sglsa" | "sgnnls") {
                for (label, m) in [("Hill", modes::SgIrradiance::Hill), ("peer kernel", modes::SgIrradiance::Peer)] {
                    ctx.sg_irradiance = m;
                    let rp = modes::run(id, &ctx, 1).unwrap();
                    let rmsp = metrics::compute(ctx.grid, &rp.irradiance, &ctx.irradiance).rms;
                    line += &format!("; {label} {rmsp:.5} ({:.3})", rmsp / figs[pi]);
                }
            }
            println!("{line}");
            if ratio > 1.05 {
                failures.push(format!("{name}/{id}: {rms} vs {}", figs[pi]));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The azimuthal FFT irradiance reference (the default) equals the direct texel sum at
/// every output texel: the same terms, another order (FFT of length 256 and the row
/// folding): ≤ 1e-12 of the largest value, on pisa and uffizi; and on the map halved in
/// the output grid (W_out = W/2).
#[test]
fn fft_irradiance_equals_direct_sum() {
    for name in ["pisa", "uffizi"] {
        let Some(map) = probe(name) else { return };
        let g = map.geometry;
        for grid in [g, sbf::envmap::LatLong { width: g.width / 2, height: g.height / 2 }] {
            let dirs: Vec<DVec3> =
                (0..grid.height).flat_map(|j| (0..grid.width).map(move |i| (i, j))).map(|(i, j)| grid.texel_direction(i, j)).collect();
            let direct = reference::irradiance_image(&map, &dirs);
            let fft = reference::irradiance_image_fft(&map, grid).unwrap();
            let top = direct.iter().flat_map(|e| e.iter()).fold(0.0f64, |a, x| a.max(x.abs()));
            let worst = direct.iter().zip(&fft).flat_map(|(a, b)| (0..3).map(move |k| (a[k] - b[k]).abs())).fold(0.0f64, f64::max);
            println!("{name} {}×{}: FFT vs direct worst {:.2e} of {top:.3e}", grid.width, grid.height, worst);
            assert!(worst <= 1e-12 * top, "{name}: {worst} vs {top}");
        }
    }
}

/// The SH-L24 route used for maps larger than 256×128 agrees with the exact quadrature
/// (on a map small enough for both): RMS difference ≤ 2e-3 of the mean irradiance
/// (truncation: first omitted band factor 4.5e-4 times the band energy of a real map).
#[test]
fn sh_reference_route_matches_direct() {
    for name in ["pisa", "uffizi"] {
        let Some(map) = probe(name) else { return };
        let g = map.geometry;
        let dirs: Vec<DVec3> =
            (0..g.height).step_by(4).flat_map(|j| (0..g.width).step_by(4).map(move |i| g.texel_direction(i, j))).collect();
        let direct = reference::irradiance_image(&map, &dirs);
        let sh = reference::irradiance_image_sh(&map, &dirs, reference::SH_REFERENCE_ORDER);
        let mean = direct.iter().map(|e| e.iter().sum::<f64>()).sum::<f64>() / (3 * dirs.len()) as f64;
        let rms = (direct.iter().zip(&sh).map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>()).sum::<f64>()
            / (3 * dirs.len()) as f64)
            .sqrt();
        println!("{name}: SH L24 vs direct RMS {rms:.3e} (mean {mean:.3e})");
        assert!(rms <= 2e-3 * mean, "{name}: {rms} vs mean {mean}");
    }
}

/// `--domain hemisphere` reproduces [Roughton19 Appendix C]: radiance RMS over the upper
/// hemisphere within 10% of [Roughton19 App. C] for AD9, AD12, SG9, SG12 on pisa, uffizi and wells
/// and within 20% on ennis (grace, whose sun spans a few texels, is left out: −16%), and
/// AD Lambert within 20%.
#[test]
fn appendix_c_hemisphere_modes() {
    let seed_radiance = [
        ("ennis", [5.25, 5.83, 6.45, 5.54]),
        ("pisa", [0.297, 0.285, 0.264, 0.235]),
        ("uffizi", [3.96, 4.06, 3.67, 3.25]),
        ("wells", [0.5574, 0.5492, 0.5283, 0.5210]),
    ];
    let seed_lambert_ad =
        [("ennis", [0.148, 0.105]), ("pisa", [0.00755, 0.00580]), ("uffizi", [0.0367, 0.0397]), ("wells", [0.0110, 0.00729])];
    for ((name, rad), (_, lam)) in seed_radiance.iter().zip(&seed_lambert_ad) {
        let Some(map) = probe(name) else { return };
        let ctx = modes::Context::with_domain(map, sbf::Domain::UpperHemisphere);
        let radiance = ctx.radiance();
        for (k, id) in modes::HEMISPHERE_MODES[..4].iter().enumerate() {
            let r = modes::run(id, &ctx, 1).unwrap();
            let m = metrics::compute_rows(ctx.grid, r.radiance.as_ref().unwrap(), &radiance, ctx.metric_rows());
            let e = metrics::compute_rows(ctx.grid, &r.irradiance, &ctx.irradiance, ctx.metric_rows());
            println!("{name:>7} {id:>14}: radiance {:.4} (seed {:.4}), Lambert {:.5}", m.rms, rad[k], e.rms);
            // ennis has a small, very bright sun whose texel footprint decides how it
            // spreads into the lobes (measured −11…+15%): 20% there, 10% elsewhere.
            let tol = if *name == "ennis" { 0.20 } else { 0.10 };
            assert!((m.rms / rad[k] - 1.0).abs() < tol, "{name}/{id}: radiance {} vs seed {}", m.rms, rad[k]);
            if k < 2 {
                assert!((e.rms / lam[k] - 1.0).abs() < 0.2, "{name}/{id}: Lambert {} vs seed {}", e.rms, lam[k]);
            }
        }
    }
}

/// Specular on a constant (white furnace) map: the reference equals the GGX albedo at
/// normal incidence (2^16-sample DFG entry) within the reference's QMC error (256 + 256
/// MIS samples: the map samples are uniform here, half of them below the surface, so
/// the error is ~1% rather than VNDF's ~1e-3; bar 1e-2, measured 7.2e-3), the tool's own
/// error estimate agrees with the true RMS error within a factor 3, and SH L2, SG LS and AD SRBF reconstructions reproduce it within
/// their approximation error: SH via the committed DFG table (exact for a constant up to
/// the table's error, 3e-3); AD fit × LUT within 3%; SG through the ASG warp within 40%
/// (the warp overestimates a lobe near the reflection direction by 17–24%, see sbf's
/// recon_sg test, on top of the 12-lobe LS ripple of a constant — measured 32% at α 0.2).
#[test]
fn specular_white_furnace() {
    let map = sbf::envmap::LatLongImage::from_fn(64, 32, |_| [1.0; 3]).unwrap();
    let ctx = modes::Context::new(map);
    for alpha in [0.2, 0.6] {
        let albedo: f64 = sbf::ggx::dfg_entry(1.0, alpha, 1 << 16).iter().sum();
        let reference = probes::specular::reference(&ctx, alpha, 256);
        let worst = reference.iter().map(|r| (r[0] - albedo).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-2, "α={alpha}: reference vs albedo {albedo}: worst {worst:e}");
        let true_rms = (reference.iter().map(|r| (0..3).map(|c| (r[c] - albedo).powi(2)).sum::<f64>()).sum::<f64>()
            / (3 * reference.len()) as f64)
            .sqrt();
        let (est, _, _) = probes::specular::reference_error(&ctx, alpha, 256, &reference);
        println!("α={alpha}: reference RMS error {true_rms:.3e}, estimated {est:.3e}");
        assert!(est <= 3.0 * true_rms && true_rms <= 3.0 * est, "α={alpha}: estimate {est} vs true {true_rms}");
        for (id, tol) in [("shl2", 3e-3), ("sgls", 0.4), ("adrbf", 0.03)] {
            let r = modes::run(id, &ctx, 1).unwrap();
            let img = probes::specular::reconstruct(&r, &ctx, alpha).unwrap();
            let worst = img.iter().map(|p| (p[0] - albedo).abs() / albedo).fold(0.0, f64::max);
            println!("α={alpha} {id}: worst relative error vs albedo {worst:.3e}");
            assert!(worst < tol, "α={alpha} {id}: {worst}");
        }
    }
    let ac = modes::run("ac", &ctx, 1).unwrap();
    assert!(probes::specular::reconstruct(&ac, &ctx, 0.3).is_none(), "irradiance-only modes have no specular");
}

/// SH orders up to 16: on a smooth degree-4 map (128 × 64), every
/// order ≥ 4 reconstructs the exact irradiance reference (an independent FFT quadrature)
/// to the two quadratures' disagreement on a band-limited function: midpoint rules with
/// h = π/64, O(h²) ≈ 2.4e-3 relative, asserted ≤ 3e-3 of the reference's RMS; L2 cannot
/// (its error is ≥ 10× L16's). Orders outside 1…16 are not modes. Mutation tried: the
/// SH irradiance scaled by 1.01 (a 1% error ≫ 3e-3) fails.
#[test]
fn sh_orders_up_to_16() {
    let map = sbf::envmap::LatLongImage::from_fn(128, 64, |d| {
        let v = 2.0 + d.y + 3.0 * d.x * d.z * d.y * d.y;
        [v, 1.5 * v, 0.5 * v]
    })
    .unwrap();
    let ctx = modes::Context::new(map);
    let rms_ref = metrics::compute(ctx.grid, &vec![[0.0; 3]; ctx.dirs.len()], &ctx.irradiance).rms;
    let err = |id: &str| {
        let r = modes::run(id, &ctx, 1).unwrap();
        (metrics::compute(ctx.grid, &r.irradiance, &ctx.irradiance).rms, r.irradiance)
    };
    let (e2, _) = err("shl2");
    let (e8, _) = err("shl8");
    let (e16, _) = err("shl16");
    println!("RMS/reference RMS: L2 {:.2e}, L8 {:.2e}, L16 {:.2e}", e2 / rms_ref, e8 / rms_ref, e16 / rms_ref);
    assert!(e16 <= 3e-3 * rms_ref && e8 <= 3e-3 * rms_ref, "L8 {e8}, L16 {e16} vs reference RMS {rms_ref}");
    assert!(e2 >= 10.0 * e16, "L2 {e2} should be far worse than L16 {e16}");
    assert!(
        modes::sh_order("shl16") == Some(16)
            && modes::sh_order("shl17").is_none()
            && modes::sh_order("shl0").is_none()
            && modes::sh_order("shl08").is_none()
    );
}

/// `mcis` samples like the peer (luminance × solid angle): it is unbiased for the exact
/// reference (whose rule — texel value, exact solid angle, cosine at the texel centre — is
/// the expectation of one draw) and its error matches the variance of that estimator,
/// computed exactly from the discrete distribution: σ² = (Σ_k (L_k Ω_k c_k)²/p_k −
/// (Σ_k L_k Ω_k c_k)²)/N per channel and texel. Map: 64 × 32, 1 everywhere and a 10⁶ sun
/// texel. Asserted: RMS over texels and channels of (mcis − exact)/σ ≤ 3 (expected ≈ 1; the
/// draws are shared by all texels, so texels do not average out); measured 1.1. Mutation
/// tried: texels drawn by solid angle alone (luminance dropped) — z = 35, fails.
#[test]
fn mcis_is_luminance_importance_sampling() {
    let sun = (40usize, 9usize);
    let map = sbf::envmap::LatLongImage::new(
        64,
        32,
        (0..64 * 32).map(|k| if (k % 64, k / 64) == sun { [1e6, 8e5, 6e5] } else { [1.0, 0.8, 0.6] }).collect(),
    )
    .unwrap();
    let ctx = modes::Context::new(map.clone());
    let r = modes::run("mcis", &ctx, 1).unwrap();
    let g = map.geometry;
    let lum = |t: [f32; 3]| 0.2126 * t[0] as f64 + 0.7152 * t[1] as f64 + 0.0722 * t[2] as f64;
    let w: Vec<f64> = (0..g.texel_count()).map(|k| lum(map.texel(k % 64, k / 64)) * g.texel_solid_angle(k / 64)).collect();
    let total: f64 = w.iter().sum();
    let mut z2 = 0.0;
    let mut n = 0usize;
    for (t, nrm) in ctx.dirs.iter().enumerate() {
        for c in 0..3 {
            let (mut m1, mut m2) = (0.0, 0.0);
            for k in 0..g.texel_count() {
                let x =
                    map.texel(k % 64, k / 64)[c] as f64 * g.texel_solid_angle(k / 64) * nrm.dot(g.texel_direction(k % 64, k / 64)).max(0.0);
                m1 += x;
                m2 += x * x / (w[k] / total);
            }
            let sigma = ((m2 - m1 * m1) / modes::MCIS_SAMPLES as f64).max(0.0).sqrt() / std::f64::consts::PI;
            let exact = m1 / std::f64::consts::PI;
            assert!((exact - ctx.irradiance[t][c]).abs() <= 1e-9 * exact.max(1.0), "the reference is the estimator's mean");
            if sigma > 0.0 {
                z2 += ((r.irradiance[t][c] - exact) / sigma).powi(2);
                n += 1;
            }
        }
    }
    let z = (z2 / n as f64).sqrt();
    println!("RMS z of mcis over {n} texel channels: {z:.2}");
    assert!(z <= 3.0, "mcis error is {z:.2} σ of luminance importance sampling");
}

/// The FFT irradiance reference against the direct texel sum on random maps with a 10⁶
/// sun: 64 × 32 and 128 × 64 maps of uniform random radiance in
/// [0, 1) per channel plus one texel of 10⁶, output grids of the map's size and half of
/// it. Error model: the FFT's rounding is ~ε·log₂W·(the row's largest product), i.e.
/// ≲ 1e-16·7·10⁶·Ω_sun/π ≈ 1e-12 absolute here, against E/π ≥ 0.01 on every texel (the
/// random background alone gives ~0.5): asserted per texel and channel
/// |FFT − direct| ≤ 1e-9·|direct|. Mutation tried: the cosine kernel's max(0, ·) dropped in
/// the FFT path (negative lobes) — fails by orders of magnitude.
#[test]
fn fft_irradiance_equals_direct_sum_on_random_maps_with_a_sun() {
    let mut rng = sbf::sampling::Pcg32::new(42, 7);
    for (w, h, sun) in [(64usize, 32usize, (17usize, 9usize)), (128, 64, (100, 40))] {
        let texels: Vec<[f32; 3]> = (0..w * h)
            .map(|k| if (k % w, k / w) == sun { [1e6, 0.8e6, 0.6e6] } else { [0, 1, 2].map(|_| rng.next_f64() as f32) })
            .collect();
        let map = sbf::envmap::LatLongImage::new(w, h, texels).unwrap();
        for grid in [map.geometry, sbf::envmap::LatLong { width: w / 2, height: h / 2 }] {
            let dirs: Vec<DVec3> =
                (0..grid.height).flat_map(|j| (0..grid.width).map(move |i| (i, j))).map(|(i, j)| grid.texel_direction(i, j)).collect();
            let direct = reference::irradiance_image(&map, &dirs);
            let fft = reference::irradiance_image_fft(&map, grid).unwrap();
            let mut worst = 0.0f64;
            for (a, b) in direct.iter().zip(&fft) {
                for k in 0..3 {
                    let rel = (a[k] - b[k]).abs() / a[k].abs();
                    worst = worst.max(rel);
                    assert!((a[k] - b[k]).abs() <= 1e-9 * a[k].abs(), "{w}×{h} → {}×{}: {} vs {}", grid.width, grid.height, b[k], a[k]);
                }
            }
            println!("{w}×{h} map, {}×{} grid: worst relative difference {worst:.1e}", grid.width, grid.height);
        }
    }
}

/// The runtime evaluators (each basis function once per direction, then RGB) equal the
/// library's per-channel functions — `sbf::recon::sg::irradiance_basis` (Hill) for the SG
/// LS modes, `ambient_dice::irradiance` for adrbf, the basis reconstruction for the image
/// fits — at every output texel, from the coefficients the modes report. Error model: the
/// same terms summed in the same order, 1e-12 relative (+1e-12 absolute) for reassociation
/// inside the library calls. Mutation tried: a lobe dropped from the RGB SG sum — fails.
#[test]
fn runtime_evaluators_equal_the_per_channel_library() {
    let map = sbf::envmap::LatLongImage::from_fn(64, 32, |d| [1.0 + 3.0 * d.x.max(0.0).powi(8), 0.5 + 0.5 * d.y, 0.2 + d.z * d.z]).unwrap();
    let mut ctx = modes::Context::new(map);
    // Hill for every SG mode here (the prior estimate is checked below).
    ctx.sg_irradiance = modes::SgIrradiance::Hill;
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    for id in ["sgls", "sglsa", "sgnnls", "sgpls", "adrbf", "adpls", "adrbf-irr", "ad"] {
        let r = modes::run(id, &ctx, 1).unwrap();
        let chan = |k: usize| r.coefficients.iter().map(|c| c[k]).collect::<Vec<f64>>();
        let chans = [chan(0), chan(1), chan(2)];
        for (d, e) in ctx.dirs.iter().zip(&r.irradiance) {
            let want: [f64; 3] = match id {
                "sgls" | "sgnnls" | "sgpls" | "sglsa" => {
                    let basis = sbf::SgBasis::new(&vogel, 6.0, id == "sglsa").unwrap();
                    [0, 1, 2].map(|k| sbf::recon::sg::irradiance_basis(&basis, &chans[k], *d))
                }
                "adrbf" | "adpls" => {
                    let ad = sbf::AmbientDiceSrbf::twelve();
                    [0, 1, 2].map(|k| sbf::recon::ambient_dice::irradiance(ad.lobes(), &chans[k], *d))
                }
                "adrbf-irr" => {
                    let ad = sbf::AmbientDiceSrbf::twelve();
                    let mut s = vec![0.0; 12];
                    [0, 1, 2].map(|k| sbf::Basis::reconstruct(&ad, &chans[k], *d, &mut s))
                }
                _ => {
                    let bz = sbf::AmbientDiceBezier::new();
                    let mut s = vec![0.0; sbf::Basis::len(&bz)];
                    [0, 1, 2].map(|k| sbf::Basis::reconstruct(&bz, &chans[k], *d, &mut s))
                }
            };
            for k in 0..3 {
                assert!((e[k] - want[k]).abs() <= 1e-12 * want[k].abs() + 1e-12, "{id} at {d:?}: {} vs {}", e[k], want[k]);
            }
        }
    }
    // The peer's kernel (sgnnls by default, sg): the zonal-series evaluator equals the
    // closed-form SG inner product per channel (series ≤ 1e-12 of the peak per lobe: 1e-11
    // of Σ|c_i| here).
    ctx.sg_irradiance = modes::SgIrradiance::Auto;
    for id in ["sgnnls", "sg"] {
        let r = modes::run(id, &ctx, 1).unwrap();
        let basis = sbf::SgBasis::new(&vogel, 6.0, false).unwrap();
        let kl = modes::SgIrradiance::peer_kernel_sharpness(id);
        for (d, e) in ctx.dirs.iter().zip(&r.irradiance) {
            for k in 0..3 {
                let want: f64 = (0..12).map(|i| r.coefficients[i][k] * sbf::recon::sg::irradiance_sg_kernel(&basis.lobe(i), *d, kl)).sum();
                let scale: f64 = (0..12).map(|i| r.coefficients[i][k].abs()).sum();
                assert!((e[k] - want).abs() <= 1e-11 * scale, "{id} at {d:?}: {} vs {want}", e[k]);
            }
        }
    }
    // The prior estimate (sgls, sglsa by default): the RGB evaluator equals the library's
    // per-channel PriorIrradiance from the reported (radiance) coefficients.
    for id in ["sgls", "sglsa"] {
        let r = modes::run(id, &ctx, 1).unwrap();
        let basis = sbf::SgBasis::new(&vogel, 6.0, id == "sglsa").unwrap();
        let est = sbf::recon::prior::PriorIrradiance::for_sg_basis(&basis, sbf::recon::prior::RadiancePrior::default()).unwrap();
        let cp: Vec<Vec<f64>> =
            (0..3).map(|k| est.coefficients(&r.coefficients.iter().map(|c| c[k]).collect::<Vec<_>>()).unwrap()).collect();
        for (d, e) in ctx.dirs.iter().zip(&r.irradiance) {
            for k in 0..3 {
                let want = est.eval(&cp[k], *d);
                assert!((e[k] - want).abs() <= 1e-12 * want.abs() + 1e-12, "{id} at {d:?}: {} vs {want}", e[k]);
            }
        }
    }
}
