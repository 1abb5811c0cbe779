//! Progressive LS/NNLS against batch LS/NNLS on the five bundled probes
//! ([Roughton19 Fig. 7.8] and 7.6).
//!
//!     cargo test --release --test progressive_probes -- --nocapture
//! prints the RMSE-vs-samples table quoted in the closing note.

use sbf::envmap::LatLongImage;
use sbf::nalgebra::DMatrix;
use sbf::sampling::{halton2, hammersley2, uniform_sphere};
use sbf::solve::*;
use sbf::{AmbientDiceSrbf, Basis, SgBasis};
use sbf_tests::{load_probe, rmse_vs_map, PROBES};
use std::f64::consts::PI;

const COUNTS: [u64; 10] = [32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384];

fn sample(map: &LatLongImage, d: sbf::glam::DVec3, n: u64) -> RadianceSample {
    RadianceSample { direction: d, value: map.bilinear(d), weight: 4.0 * PI / n as f64 }
}

/// Batch NNLS per channel on the samples' own Gram form.
fn batch_nnls(basis: &dyn Basis, s: &[RadianceSample]) -> DMatrix<f64> {
    let g = sample_gram(basis, s);
    let m = moments(basis, s);
    let mut out = DMatrix::zeros(basis.len(), 3);
    for c in 0..3 {
        let col: Vec<f64> = m.column(c).iter().copied().collect();
        let sol = nnls_gram(&g, &col, NnlsOptions::default()).unwrap();
        assert_eq!(sol.status, NnlsStatus::Converged);
        for i in 0..basis.len() {
            out[(i, c)] = sol.coeffs[i];
        }
    }
    out
}

/// Bars: progressive LS within 3% of batch LS at 512 Halton samples and
/// within 0.5% at 16384; progressive NNLS within 5% of batch NNLS at 4096.
#[test]
fn progressive_vs_batch_on_probes() {
    let sg = SgBasis::new(&sbf::layout::vogel_sphere(12).unwrap(), 8.0, false).unwrap();
    let ad = AmbientDiceSrbf::twelve();
    let mut failures = Vec::new();
    for name in PROBES {
        let Some(map) = load_probe(name) else { return };
        for basis in [&sg as &dyn Basis, &ad] {
            let all: Vec<sbf::glam::DVec3> = (0..COUNTS[COUNTS.len() - 1]).map(|i| uniform_sphere(halton2(i))).collect();
            let mut enc = ProgressiveEncoder::<f64>::new(basis.len(), ProgressiveOptions::default());
            let mut enc_nn = ProgressiveEncoder::<f64>::new(basis.len(), ProgressiveOptions::non_negative());
            let mut done = 0u64;
            println!("\n{name} / {}: RMSE (radiance, all texels) vs Halton sample count", basis.name());
            println!(
                "{:>6} {:>10} {:>12} {:>7} {:>10} {:>12} {:>7}",
                "n", "batch LS", "progressive", "gap", "batch NNLS", "prog. NNLS", "gap"
            );
            for &n in &COUNTS {
                // One running encoder, snapshotted at each n: every sample gets the same
                // weight (only ratios matter to the encoder), so the snapshot at n equals
                // a fresh run over the first n samples.
                while done < n {
                    let s = sample(&map, all[done as usize], 1);
                    enc.add(basis, &s).unwrap();
                    enc_nn.add(basis, &s).unwrap();
                    done += 1;
                }
                let s: Vec<RadianceSample> = all[..n as usize].iter().map(|d| sample(&map, *d, n)).collect();
                let rb = rmse_vs_map(
                    basis,
                    &solve_gram(&sample_gram(basis, &s), &moments(basis, &s), LsOptions::default()).unwrap().coeffs,
                    &map,
                );
                let rp = rmse_vs_map(basis, &enc.coefficients(), &map);
                let rbn = rmse_vs_map(basis, &batch_nnls(basis, &s), &map);
                let rpn = rmse_vs_map(basis, &enc_nn.coefficients(), &map);
                let (gap, gapn) = ((rp - rb) / rb, (rpn - rbn) / rbn);
                println!("{n:>6} {rb:>10.5} {rp:>12.5} {:>6.2}% {rbn:>10.5} {rpn:>12.5} {:>6.2}%", 100.0 * gap, 100.0 * gapn);
                if n == 512 && gap.abs() > 0.03 {
                    failures.push(format!("{name}/{}: n=512 LS gap {:.2}%", basis.name(), 100.0 * gap));
                }
                if n == 16384 && gap.abs() > 0.005 {
                    failures.push(format!("{name}/{}: n=16384 LS gap {:.2}%", basis.name(), 100.0 * gap));
                }
                if n == 4096 && gapn.abs() > 0.05 {
                    failures.push(format!("{name}/{}: n=4096 NNLS gap {:.2}%", basis.name(), 100.0 * gapn));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Hammersley in index order vs Halton ([Roughton19 Fig. 7.6]) on every probe: the batch
/// solutions of both point sets agree, the progressive one on Hammersley is worse.
#[test]
fn hammersley_gap_on_probes() {
    let sg = SgBasis::new(&sbf::layout::vogel_sphere(12).unwrap(), 8.0, false).unwrap();
    let n = 4096u64;
    println!("\nSG12 λ=8, {n} samples: progressive RMSE with Halton vs Hammersley order");
    let mut gaps = Vec::new();
    for name in PROBES {
        let Some(map) = load_probe(name) else { return };
        let run = |dirs: Vec<sbf::glam::DVec3>| {
            let s: Vec<RadianceSample> = dirs.into_iter().map(|d| sample(&map, d, n)).collect();
            let mut enc = ProgressiveEncoder::<f64>::new(12, ProgressiveOptions::default());
            s.iter().for_each(|x| enc.add(&sg, x).unwrap());
            let batch = solve_gram(&sample_gram(&sg, &s), &moments(&sg, &s), LsOptions::default()).unwrap().coeffs;
            (rmse_vs_map(&sg, &enc.coefficients(), &map), rmse_vs_map(&sg, &batch, &map))
        };
        let (p_hal, b_hal) = run((0..n).map(|i| uniform_sphere(halton2(i))).collect());
        let (p_ham, b_ham) = run((0..n).map(|i| uniform_sphere(hammersley2(i, n))).collect());
        println!(
            "{name:>7}: Halton {p_hal:.4} (batch {b_hal:.4})  Hammersley {p_ham:.4} (batch {b_ham:.4})  gap {:+.1}%",
            100.0 * (p_ham / p_hal - 1.0)
        );
        gaps.push((name, p_ham / p_hal - 1.0));
        // Batch LS is order-independent and the two point sets are equally good.
        assert!((b_ham / b_hal - 1.0).abs() < 0.02, "{name}: batch {b_ham} vs {b_hal}");
    }
    // Never better than Halton beyond noise, and clearly worse on most probes. (On
    // grace the error is dominated by a sun no 12-lobe basis represents, so order
    // barely matters there.)
    assert!(gaps.iter().all(|(_, g)| *g > -0.005), "{gaps:?}");
    assert!(gaps.iter().filter(|(_, g)| *g > 0.05).count() >= 3, "{gaps:?}");
}
