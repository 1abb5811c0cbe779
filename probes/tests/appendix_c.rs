//! `--reference appendix-c` against the figures \[Roughton19\] prints in Appendix C (Figs.
//! C.1–C.5): radiance, Lambert and GGX RMSE of AD 9, AD 12, SG 9 and SG 12 on the five
//! probes, through the same `compare` the command runs. Prints every cell (ours /
//! Roughton's = ratio) and both counts the docs quote.
//!
//!     cargo test --release -p probes --test appendix_c -- --nocapture
//!
//! Needs `../shared/probes`; with SBF_REQUIRE_PROBES=1 (CI) a missing folder fails.
//!
//! What is asserted, and why those tolerances (the issue's, not fitted to these numbers):
//! - radiance, every cell within 1.10× either way: the fits are Roughton's method (least
//!   squares over the sphere); grace's sun, a few texels, is the largest difference;
//! - every SG 9 and SG 12 GGX cell (46) and every AD GGX cell at α ≤ 0.4 (30) within 1.10×
//!   either way — the reproduction; AD at α 0.6–0.8 is reported, not asserted cell by cell
//!   (docs/probes.md says which cells are not reproduced and why);
//! - the count: at least 88 of the 92 GGX cells no more than 1.10× Roughton's (its
//!   own reproduction of \[RoughtonFork\], "90 of 92 within 1.10× (AD mean 0.86)", counts that way);
//! - Lambert: every cell no more than 1.15× Roughton's, and SG's within 1.15× either way —
//!   Roughton's Lambert reference is a 5000-sample Monte Carlo estimate whose noise only
//!   adds to its errors (ours is exact), which leaves AD's small errors below Roughton's.
//!
//! Mutations tried: the reference kernel made physical (G2/G1, horizon cut, F ≡ 1) under
//! the compatible runtimes — every probe fails (ennis AD 9 α 0.4: 3.1×); the physical
//! Listing 8.2 table in the compatible mode — AD fails (ennis AD 9 α 0.4: 3.2×); the ASG
//! warp's frame in the plane of n and R instead of Roughton's — SG fails (ennis SG 12 α 0.4:
//! 1.20, uffizi SG 9: 1.16); Listing 8.1 × its G2·G1 table for \[RoughtonFork\]'s AD fit and
//! per-pixel table — AD fails (wells AD 9 α 0.4: 1.34, pisa 1.17); the environment lit below the horizon (no
//! `clip_below_horizon` anywhere) — SG fails (wells SG 12 α 0.2: 1.24, α 0.4: 1.29); the map
//! not clipped in `compare` but the SG samples' map still clipped — fails (82 of 92; wells
//! SG 12 Lambert 4.5×).

use probes::appendix_c::{ALPHAS, MODES, PROBES, SEED};
use probes::compare::{compare, Settings};
use probes::modes::{SgIrradiance, SpecularRuntime};
use sbf::ggx::Convention;
use std::path::PathBuf;

/// `x` to four significant figures (\[Roughton19\] prints three or four).
fn four_figures(x: f64) -> String {
    let decimals = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

fn probe(name: &str) -> Option<sbf::envmap::LatLongImage> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../shared/probes/{name}.hdr"));
    if !p.exists() {
        assert!(std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"), "SBF_REQUIRE_PROBES=1 but {} is missing", p.display());
        eprintln!("skipping: {} not found", p.display());
        return None;
    }
    Some(probes::input::load_map(&p, false).expect("probe loads").0)
}

/// The compatible run's settings: the four modes, `alphas`, the reference exact (None) or by
/// Roughton's Monte Carlo estimator with that many samples.
fn compatible(alphas: &[f64], seed_estimator: Option<u32>) -> Settings {
    Settings {
        ids: MODES.iter().map(|(_, id)| id.to_string()).collect(),
        repeats: 1,
        domain: sbf::Domain::UpperHemisphere,
        alphas: alphas.to_vec(),
        specular_samples: 256,
        sg_irradiance: SgIrradiance::Auto,
        specular_runtime: SpecularRuntime::Fit,
        convention: Convention::AppendixC,
        storage: probes::storage::Storage::F32,
        seed_estimator,
    }
}

#[test]
fn compatible_mode_reproduces_the_seeds_figures() {
    let settings = compatible(&ALPHAS, None);
    let (mut ggx_two_sided, mut ggx_one_sided, mut ggx_cells) = (0, 0, 0);
    let (mut lambert_two_sided, mut lambert_one_sided) = (0, 0);
    let mut failures = Vec::new();
    for (pi, name) in PROBES.iter().enumerate() {
        let Some(map) = probe(name) else { return };
        let report = compare(name, map, 0, &settings).expect("the compatible run");
        assert!(report.specular_method.contains("azimuthal FFT"), "{name}: {}", report.specular_method);
        println!("\n{name}: RMSE ours / Roughton's = ratio");
        let labels = ["radiance", "Lambert", "GGX 0.1", "GGX 0.2", "GGX 0.4", "GGX 0.6", "GGX 0.8"];
        for (ri, label) in labels.iter().enumerate() {
            let mut line = format!("{label:>9}");
            for (bi, (basis, id)) in MODES.iter().enumerate() {
                let seed = SEED[pi][ri][bi];
                if seed.is_nan() {
                    continue;
                }
                let row = report.rows.iter().find(|r| r.result.id == *id).expect("mode ran");
                let ours = match ri {
                    0 => row.radiance.as_ref().expect("radiance").rms,
                    1 => row.irradiance.rms,
                    _ => row.specular.iter().find(|(a, _)| *a == ALPHAS[ri - 2]).expect("α ran").1.rms,
                };
                let r = ours / seed;
                line += &format!("  {basis:>4} {:>9} / {seed:<8} = {r:.2}", four_figures(ours));
                let within = |k: f64| r <= k && r >= 1.0 / k;
                match ri {
                    0 if !within(1.10) => failures.push(format!("{name} {basis} radiance: {r:.3}")),
                    1 => {
                        lambert_two_sided += usize::from(within(1.15));
                        lambert_one_sided += usize::from(r <= 1.15);
                        if r > 1.15 || (bi >= 2 && !within(1.15)) {
                            failures.push(format!("{name} {basis} Lambert: {r:.3}"));
                        }
                    }
                    2.. => {
                        ggx_cells += 1;
                        ggx_two_sided += usize::from(within(1.10));
                        ggx_one_sided += usize::from(r <= 1.10);
                        if (bi >= 2 || ALPHAS[ri - 2] <= 0.4) && !within(1.10) {
                            failures.push(format!("{name} {basis} {label}: {r:.3}"));
                        }
                    }
                    _ => {}
                }
            }
            println!("{line}");
        }
    }
    println!(
        "\nGGX cells within 1.10× either way: {ggx_two_sided} of {ggx_cells}; at most 1.10× Roughton's: {ggx_one_sided}\n\
         Lambert within 1.15× either way: {lambert_two_sided} of 20; at most 1.15× Roughton's: {lambert_one_sided}"
    );
    assert_eq!(ggx_cells, 92, "Appendix C has 92 GGX cells");
    assert!(ggx_one_sided >= 88, "{ggx_one_sided} of 92 GGX cells no more than 1.10× Roughton's (the issue asks ≥ 88)");
    assert!(failures.is_empty(), "cells outside the tolerance:\n{}", failures.join("\n"));
}

/// Under the physical reference, the specular error the runtime adds — its image against the
/// exact GGX integral of the same reconstructed radiance (the azimuthal quadrature, an
/// independent method) — is no larger through the per-lobe tables than through the fits
/// (ASG warp, Listing 8.1 × its table) in every cell: 5 probes × AD 9, AD 12, SG 9, SG 12 ×
/// α 0.1–0.8 (100 cells; docs/probes.md lists them). Strict comparison: the claim itself.
/// Mutation tried: each lobe response × 1.05 (`sbf::recon::runtime::lobe_ggx_responses`, which
/// the tables path sums)
/// — fails (grace AD 9 α 0.6: 1.72e-2 against the fits' 1.11e-2).
#[test]
fn tables_add_no_more_error_than_the_fits_in_any_cell() {
    let settings = |runtime| Settings {
        ids: MODES.iter().map(|(_, id)| id.to_string()).collect(),
        repeats: 1,
        domain: sbf::Domain::UpperHemisphere,
        alphas: ALPHAS.to_vec(),
        specular_samples: 256,
        sg_irradiance: SgIrradiance::Auto,
        specular_runtime: runtime,
        convention: Convention::Physical,
        storage: probes::storage::Storage::F32,
        seed_estimator: None,
    };
    let mut cells = 0;
    let mut worst: (f64, String) = (0.0, String::new());
    for name in PROBES {
        let Some(map) = probe(name) else { return };
        let tables = compare(name, map.clone(), 0, &settings(SpecularRuntime::Table)).expect("table run");
        let fits = compare(name, map, 0, &settings(SpecularRuntime::Fit)).expect("fit run");
        for (t, f) in tables.rows.iter().zip(&fits.rows) {
            assert_eq!(t.result.id, f.result.id);
            for ((a, _, rt), (b, _, rf)) in t.specular_parts.iter().zip(&f.specular_parts) {
                assert_eq!(a, b);
                cells += 1;
                assert!(rt <= rf, "{name} {} α {a}: tables add {rt:.4e}, the fits {rf:.4e}", t.result.id);
                if rt / rf > worst.0 {
                    worst = (rt / rf, format!("{name} {} α {a}", t.result.id));
                }
            }
        }
    }
    assert_eq!(cells, 100);
    println!("tables' runtime error / the fits': at most {:.3} ({})", worst.0, worst.1);
}

/// Roughton's Monte Carlo estimator converges to the exact integral of its kernel (the
/// azimuthal quadrature, an independent method): on a smooth synthetic map (64×32, colour
/// varying with both angles, black below the horizon), 1024 samples per texel, α 0.2 and
/// 0.6, the reported RMS difference is at most 2 % of the signal — a Hammersley estimate of a
/// smooth integrand cut at the horizon errs by O(N^-¾) ≈ 0.5 % here, times a constant of a
/// few. Mutation tried: the physical weight G2/G1(v) in the estimator — fails (the kernels
/// differ by G1(v)², 0.5 and less at grazing views).
#[test]
fn seeds_estimator_converges_to_the_exact_integral() {
    let (w, h) = (64usize, 32usize);
    let texels = (0..w * h)
        .map(|k| {
            let (u, v) = ((k % w) as f32 + 0.5, (k / w) as f32 + 0.5);
            let (phi, theta) = (2.0 * std::f32::consts::PI * u / w as f32, std::f32::consts::PI * v / h as f32);
            [1.0 + 0.5 * phi.cos() * theta.sin(), 0.8 + 0.3 * theta.cos(), 0.6 + 0.2 * (2.0 * phi).sin()]
        })
        .collect();
    let map = sbf::envmap::LatLongImage::new(w, h, texels).unwrap();
    let report = compare("smooth", map, 0, &compatible(&[0.2, 0.6], Some(1024))).expect("the run");
    assert!(report.specular_method.contains("Monte Carlo estimator"), "{}", report.specular_method);
    for r in &report.specular_reference {
        println!("α {}: estimator − exact RMS {:.3e}, signal {:.3e}", r.alpha, r.error_rms, r.signal_rms);
        assert!(r.error_rms <= 0.02 * r.signal_rms, "α {}: {} of {}", r.alpha, r.error_rms, r.signal_rms);
    }
}

/// With Roughton's own reference estimator (8192 samples, as \[RoughtonFork\]) the printed figures
/// come back to their digits on the four probes without a sun: every SG GGX cell and every
/// AD cell at α ≤ 0.4 within 1.02× either way on ennis, pisa, uffizi and wells; grace (its
/// sun: the estimator's own error there exceeds the printed AD errors) is printed, not
/// asserted. Slow (minutes on two cores): `cargo test --release -p probes --test appendix_c
/// -- --ignored --nocapture`.
#[test]
#[ignore]
fn the_seeds_estimator_reproduces_its_figures() {
    let settings = compatible(&ALPHAS, Some(8192));
    let mut failures = Vec::new();
    for (pi, name) in PROBES.iter().enumerate() {
        let Some(map) = probe(name) else { return };
        let report = compare(name, map, 0, &settings).expect("the compatible run");
        println!("\n{name}, Roughton's estimator: RMSE ours / Roughton's = ratio");
        for (ai, alpha) in ALPHAS.iter().enumerate() {
            let mut line = format!("  GGX {alpha}");
            for (bi, (basis, id)) in MODES.iter().enumerate() {
                let seed = SEED[pi][ai + 2][bi];
                if seed.is_nan() {
                    continue;
                }
                let row = report.rows.iter().find(|r| r.result.id == *id).expect("mode ran");
                let ours = row.specular.iter().find(|(a, _)| a == alpha).expect("α ran").1.rms;
                let r = ours / seed;
                line += &format!("  {basis:>4} {:>9} / {seed:<8} = {r:.3}", four_figures(ours));
                if *name != "grace" && (bi >= 2 || *alpha <= 0.4) && !(1.0 / 1.02..=1.02).contains(&r) {
                    failures.push(format!("{name} {basis} GGX {alpha}: {r:.3}"));
                }
            }
            println!("{line}");
        }
    }
    assert!(failures.is_empty(), "cells outside 1.02×:\n{}", failures.join("\n"));
}
