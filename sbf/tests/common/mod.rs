//! Shared test support: random directions and a χ² goodness-of-fit test.
#![allow(dead_code)]

use sbf::glam::DVec3;
use sbf::quadrature::gauss_legendre;
use sbf::sampling::{uniform_sphere, Pcg32};
use std::f64::consts::PI;

/// `n` uniformly distributed unit directions from a fixed seed.
pub fn random_directions(seed: u64, n: usize) -> Vec<DVec3> {
    let mut rng = Pcg32::new(seed, 7);
    (0..n).map(|_| uniform_sphere(rng.next_2d())).collect()
}

/// Upper-tail χ² test via the Wilson–Hilferty normal approximation. Returns the
/// standard-normal z score; z > 3.3 corresponds to p < 5e-4.
pub fn chi2_z(observed: &[f64], expected: &[f64]) -> (f64, f64, usize) {
    // Pool cells with expected < 5 into one.
    let (mut chi2, mut k) = (0.0, 0usize);
    let (mut po, mut pe) = (0.0, 0.0);
    for (o, e) in observed.iter().zip(expected) {
        if *e < 5.0 {
            po += o;
            pe += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            k += 1;
        }
    }
    if pe > 0.0 {
        chi2 += (po - pe) * (po - pe) / pe.max(1e-300);
        k += 1;
    }
    let dof = (k - 1) as f64;
    let z = ((chi2 / dof).cbrt() - (1.0 - 2.0 / (9.0 * dof))) / (2.0 / (9.0 * dof)).sqrt();
    (z, chi2, k - 1)
}

/// χ² z-score of directions against a solid-angle pdf, binned in (z, φ) cells of
/// [z_lo, 1] × [0, 2π). Expected counts integrate the pdf over each cell with a
/// 16×16 Gauss–Legendre rule (dΩ = dz dφ); fewer nodes mis-integrate the kink of
/// max(0, v·h) in the GGX visible-normal pdf at grazing views.
pub fn chi2_directions(samples: &[DVec3], pdf: impl Fn(DVec3) -> f64, z_lo: f64, nz: usize, nphi: usize) -> f64 {
    let mut obs = vec![0.0; nz * nphi];
    for d in samples {
        let zi = (((d.z - z_lo) / (1.0 - z_lo)) * nz as f64).floor().clamp(0.0, nz as f64 - 1.0) as usize;
        let mut phi = d.y.atan2(d.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let pi = ((phi / (2.0 * PI)) * nphi as f64).floor().clamp(0.0, nphi as f64 - 1.0) as usize;
        obs[zi * nphi + pi] += 1.0;
    }
    let (gx, gw) = gauss_legendre(16);
    let n = samples.len() as f64;
    let dz = (1.0 - z_lo) / nz as f64;
    let dp = 2.0 * PI / nphi as f64;
    let mut exp = vec![0.0; nz * nphi];
    for a in 0..nz {
        for b in 0..nphi {
            let mut s = 0.0;
            for (xi, wi) in gx.iter().zip(&gw) {
                let z = z_lo + dz * (a as f64 + 0.5 * (xi + 1.0));
                let r = (1.0 - z * z).max(0.0).sqrt();
                for (xj, wj) in gx.iter().zip(&gw) {
                    let p = dp * (b as f64 + 0.5 * (xj + 1.0));
                    s += wi * wj * pdf(DVec3::new(r * p.cos(), r * p.sin(), z));
                }
            }
            exp[a * nphi + b] = n * s * 0.25 * dz * dp;
        }
    }
    chi2_z(&obs, &exp).0
}

/// Relative difference |a − b|/max(|b|, tiny).
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// RMS radiance error of `coeffs` (n × 3) against every texel of `map`, unweighted
/// over texels and averaged over RGB (as Probulator reports).
pub fn rmse_vs_map(basis: &dyn sbf::Basis, coeffs: &sbf::nalgebra::DMatrix<f64>, map: &sbf::envmap::LatLongImage) -> f64 {
    let g = map.geometry;
    let mut b = vec![0.0; basis.len()];
    let mut se = 0.0;
    for j in 0..g.height {
        for i in 0..g.width {
            basis.eval_into(g.texel_direction(i, j), &mut b);
            let t = map.texel(i, j);
            for c in 0..3 {
                let r: f64 = (0..basis.len()).map(|k| coeffs[(k, c)] * b[k]).sum();
                se += (r - t[c] as f64).powi(2);
            }
        }
    }
    (se / (3 * g.texel_count()) as f64).sqrt()
}
