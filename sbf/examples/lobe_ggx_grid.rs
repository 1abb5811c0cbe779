//! Interpolation error of the per-lobe GGX tables against direct quadrature at random
//! points, for a few grid sizes (fitgen uses 12·12·32·24): `cargo run --release -p sbf
//! --example lobe_ggx_grid [quadrature n]`.
use sbf::recon::lobe_ggx::{response, Grid, RadialLobe, Table};
use std::time::Instant;

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let n = args.first().copied().unwrap_or(32);
    // Quadrature convergence n vs 2n.
    let mut worst: f64 = 0.0;
    for &lobe in &[RadialLobe::Sg { sharpness: 6.0 }, RadialLobe::AdSrbf] {
        for &nv in &[1.0, 0.7, 0.2, 0.02] {
            for &a in &[0.01, 0.1, 0.4, 1.0] {
                for &(tp, ph) in &[(0.0, 0.0), (1.0, 2.5), (2.0, 0.3), (0.6, 3.1)] {
                    let r1 = response(lobe, nv, a, tp, ph, n);
                    let r2 = response(lobe, nv, a, tp, ph, 2 * n);
                    worst = worst.max((r1[0] - r2[0]).abs().max((r1[1] - r2[1]).abs()));
                }
            }
        }
    }
    println!("quadrature n={n}: worst |R_n - R_2n| = {worst:.3e}");
    for sizes in [[8, 8, 24, 16], [12, 12, 32, 24], [16, 16, 48, 32]] {
        let grid = Grid { theta_v: sizes[0], alpha: sizes[1], gamma: sizes[2], psi: sizes[3] };
        for &lobe in &[RadialLobe::Sg { sharpness: 6.0 }, RadialLobe::AdSrbf] {
            let t0 = Instant::now();
            let table = Table::build(lobe, grid, n);
            let dt = t0.elapsed().as_secs_f64();
            let mut rng = 12345u64;
            let mut u = || {
                rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (rng >> 11) as f64 / (1u64 << 53) as f64
            };
            let (mut e2, mut emax, mut s2) = (0.0, 0.0f64, 0.0);
            let mut by = [[0.0f64; 4]; 2];
            let m = 2000;
            for _ in 0..m {
                let tv = u() * std::f64::consts::FRAC_PI_2;
                let a = (0.05 + 0.95 * u()).powi(2).max(0.0025);
                let tp = u() * std::f64::consts::PI;
                let ph = u() * std::f64::consts::PI;
                let exact = response(lobe, tv.cos(), a, tp, ph, n);
                let px = table.pixel(tv.cos(), a);
                let got = table.lobe(&px, tp, ph);
                let e = (got[0] + got[1]) - (exact[0] + exact[1]);
                e2 += e * e;
                s2 += (exact[0] + exact[1]).powi(2);
                emax = emax.max(e.abs());
                let bv = ((tv / std::f64::consts::FRAC_PI_2) * 4.0) as usize;
                let ba = (a.sqrt() * 4.0) as usize;
                by[0][bv.min(3)] = by[0][bv.min(3)].max(e.abs());
                by[1][ba.min(3)] = by[1][ba.min(3)].max(e.abs());
            }
            println!(
                "{:>4} grid {:?}: {} values, build {:.1} s; F=1 error rms {:.2e} (signal rms {:.3}), max {:.2e}",
                lobe.name(),
                sizes,
                grid.len(),
                dt,
                (e2 / m as f64).sqrt(),
                (s2 / m as f64).sqrt(),
                emax
            );
            println!(
                "   max by theta_v quarter {:.1e}, by sqrt(alpha) quarter {:.1e}",
                by[0].iter().cloned().fold(0.0, f64::max),
                by[1].iter().cloned().fold(0.0, f64::max)
            );
            println!("   {:?} {:?}", by[0].map(|x| (x * 1e4).round() / 1e4), by[1].map(|x| (x * 1e4).round() / 1e4));
        }
    }
}
