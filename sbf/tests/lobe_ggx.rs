//! The per-lobe GGX response (recon::lobe_ggx): its quadrature against an independent
//! Monte Carlo estimate, its mirror limit by value, and the tables against the quadrature
//! within an interpolation error model.
//!
//! Mutations tried (each fails at least one test here): only one half of the azimuths in
//! `nodes` (the y → −y mirror dropped), node weights × 1.02, the Fresnel split swapped,
//! ψ measured from the other side (π − ψ) in `MirrorFrame::angles`, the γ fraction
//! off by one node in `Table::lobe`, and √α replaced by α in `Table::pixel`.

use sbf::ggx;
use sbf::glam::DVec3;
use sbf::recon::lobe_ggx::{axis, response, Grid, MirrorFrame, RadialLobe, Table};
use sbf::sampling::Pcg32;

const LOBES: [RadialLobe; 3] = [RadialLobe::Sg { sharpness: 6.0 }, RadialLobe::Sg { sharpness: 40.0 }, RadialLobe::AdSrbf];

/// Independent estimate: visible-normal sampling (Heitz 2018) with a PRNG, returning the
/// mean and standard error of (R₀, R₁). For v in the xz-plane and n = +Z the VNDF weight
/// of f·cos is G2/G1 (F split by Schlick's weight at v·h).
fn monte_carlo(lobe: RadialLobe, nv: f64, alpha: f64, p: DVec3, n: usize, seed: u64) -> ([f64; 2], [f64; 2]) {
    let v = DVec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let mut rng = Pcg32::new(seed, 7);
    let (mut s, mut s2) = ([0.0; 2], [0.0; 2]);
    let g1 = ggx::g1(v, alpha);
    for _ in 0..n {
        let h = ggx::sample_vndf(v, alpha, [rng.next_f64(), rng.next_f64()]);
        let l = ggx::reflect(v, h);
        if l.z <= 0.0 {
            continue;
        }
        let w = ggx::g2(v, l, alpha) / g1 * lobe.eval(p.dot(l));
        let fc = ggx::schlick_weight(v.dot(h));
        for (c, x) in [(0, w * (1.0 - fc)), (1, w * fc)] {
            s[c] += x;
            s2[c] += x * x;
        }
    }
    let m = s.map(|x| x / n as f64);
    let se = [0, 1].map(|c| ((s2[c] / n as f64 - m[c] * m[c]).max(0.0) / n as f64).sqrt());
    (m, se)
}

/// Quadrature = Monte Carlo within 4σ (+ the quadrature's own n-vs-2n change) over lobes,
/// grazing and normal views, α from 0.02 to 1 and axes on both sides of the mirror direction.
/// 2^18 samples: σ ≈ 0.2% of the response, so a 2% weight error is ≥ 10σ.
#[test]
fn quadrature_matches_vndf_monte_carlo() {
    let mut worst: f64 = 0.0;
    for (li, &lobe) in LOBES.iter().enumerate() {
        for &(nv, alpha) in &[(1.0, 0.3), (0.7, 0.1), (0.3, 0.6), (0.05, 0.2), (0.5, 1.0), (0.9, 0.02)] {
            for &(gamma, psi) in &[(0.0, 0.0), (0.4, 0.5), (0.9, 2.4), (1.8, 1.2)] {
                let theta_v = f64::acos(nv);
                let p = axis(theta_v, gamma, psi);
                let q = response(lobe, nv, alpha, gamma, psi, 32);
                let q2 = response(lobe, nv, alpha, gamma, psi, 64);
                let (m, se) = monte_carlo(lobe, nv, alpha, p, 1 << 18, 11 + li as u64);
                for c in 0..2 {
                    let tol = 4.0 * se[c] + (q[c] - q2[c]).abs() + 1e-12;
                    let z = (q[c] - m[c]).abs() / tol;
                    worst = worst.max(z);
                    assert!(
                        z <= 1.0,
                        "{lobe:?} n·v {nv} α {alpha} γ {gamma} ψ {psi} channel {c}: quadrature {} vs MC {} ± {}",
                        q[c],
                        m[c],
                        se[c]
                    );
                }
            }
        }
    }
    println!("worst |quadrature − MC| / (4σ + quadrature change) = {worst:.2}");
}

/// Mirror limit by value: at α → 0 the BRDF·cos is a delta at r with weight F(v·n), so
/// R₀ + R₁ → K(cos γ) (G → 1) and R₁/(R₀ + R₁) → Schlick's weight at n·v. At α = 1e-3 the
/// lobe's angular width ~2α bounds the smoothing: |ΔK| ≤ ½·K''·(2α)² with K'' ≤ λ² for an SG.
#[test]
fn mirror_limit_by_value() {
    for &lobe in &LOBES {
        for &nv in &[1.0, 0.6, 0.2] {
            for &gamma in &[0.0, 0.3, 1.0, 2.0] {
                let alpha = 1e-3;
                let r = response(lobe, nv, alpha, gamma, 0.7, 32);
                let k = lobe.eval(gamma.cos());
                let fc = ggx::schlick_weight(nv);
                let tol = 0.5 * 40.0f64.powi(2) * (2.0 * alpha).powi(2) + 1e-6;
                assert!((r[0] + r[1] - k).abs() <= tol, "{lobe:?} n·v {nv} γ {gamma}: {} vs K {k}", r[0] + r[1]);
                assert!((r[1] - fc * k).abs() <= tol, "{lobe:?} Fresnel part {} vs {}", r[1], fc * k);
            }
        }
    }
}

/// The per-pixel frame recovers (γ, ψ) of an axis built by [`axis`] for any normal and
/// view: the table's coordinates are the quadrature's.
#[test]
fn mirror_frame_inverts_axis() {
    let mut rng = Pcg32::new(5, 1);
    for _ in 0..200 {
        let theta_v = 0.05 + 1.5 * rng.next_f64();
        let (gamma, psi) = (0.01 + 3.1 * rng.next_f64(), 0.01 + 3.1 * rng.next_f64());
        let p = axis(theta_v, gamma, psi);
        let v = DVec3::new(theta_v.sin(), 0.0, theta_v.cos());
        // A random rotation applied to n, v and p changes nothing.
        let rot = sbf::glam::DQuat::from_axis_angle(
            DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, 0.3).normalize(),
            6.0 * rng.next_f64(),
        );
        let (g, s) = MirrorFrame::new(rot * DVec3::Z, rot * v).angles(rot * p);
        assert!((g - gamma).abs() < 1e-9 && (s - psi).abs() < 1e-7, "({gamma}, {psi}) → ({g}, {s})");
    }
}

/// The table against direct quadrature at random points inside cells, within the error
/// model of multilinear interpolation: |f − I f| ≤ ⅛ Σ_d h_d²·max|∂²f/∂x_d²| over the cell,
/// the second derivatives taken as the largest centred second difference of the exact
/// function at the cell's corners (×2 for their variation inside the cell), plus the
/// quadrature's n-vs-2n change and f32 storage. A coarse grid keeps the test quick; the
/// bound does not depend on the size.
#[test]
fn table_interpolation_is_within_its_error_model() {
    let grid = Grid { theta_v: 6, alpha: 6, gamma: 13, psi: 9 };
    let n = 24;
    let mut rng = Pcg32::new(77, 3);
    for lobe in [RadialLobe::Sg { sharpness: 6.0 }, RadialLobe::AdSrbf] {
        let table = Table::build(lobe, grid, n);
        let exact = |x: [f64; 4]| {
            let r = response(lobe, x[0], x[1] * x[1], x[2], x[3], n);
            r[0] + r[1]
        };
        let h: Vec<f64> = (0..4).map(|d| grid.node(d, 1) - grid.node(d, 0)).collect();
        let mut worst: f64 = 0.0;
        for _ in 0..60 {
            // Interior cells (a second difference needs both neighbours).
            let cell: Vec<usize> = grid.sizes().iter().map(|&s| 1 + (rng.next_f64() * (s - 3) as f64) as usize).collect();
            let frac: Vec<f64> = (0..4).map(|_| rng.next_f64()).collect();
            let x: [f64; 4] = std::array::from_fn(|d| grid.node(d, cell[d]) + frac[d] * h[d]);
            let got = {
                let r = table.lobe(&table.pixel(x[0], x[1] * x[1]), x[2], x[3]);
                r[0] + r[1]
            };
            let mut bound = 0.0;
            for d in 0..4 {
                let mut m2: f64 = 0.0;
                for corner in 0..16 {
                    let c: [f64; 4] = std::array::from_fn(|e| grid.node(e, cell[e] + (corner >> e & 1)));
                    let mut lo = c;
                    let mut hi = c;
                    lo[d] -= h[d];
                    hi[d] += h[d];
                    if hi[d] > Grid::RANGES[d].1 + 1e-12 {
                        continue;
                    }
                    m2 = m2.max((exact(lo) - 2.0 * exact(c) + exact(hi)).abs());
                }
                bound += 2.0 * m2 / 8.0;
            }
            let direct = exact(x);
            bound += 1e-3 * direct.abs() + 1e-6;
            let err = (got - direct).abs();
            worst = worst.max(err / bound);
            assert!(err <= bound, "{lobe:?} at {x:?}: table {got} vs quadrature {direct}, bound {bound}");
        }
        println!("{lobe:?}: worst error / bound {worst:.2}");
    }
}

/// The committed tables are the quadrature on their nodes (f16 storage): every 97th node.
#[cfg(all(feature = "lut-lobe-ggx-sg6", feature = "lut-lobe-ggx-ad"))]
#[test]
fn committed_tables_hold_the_quadrature_on_their_nodes() {
    for (table, lobe) in
        [(sbf::recon::tables::lobe_ggx_sg6(), RadialLobe::Sg { sharpness: 6.0 }), (sbf::recon::tables::lobe_ggx_ad(), RadialLobe::AdSrbf)]
    {
        let g = table.grid;
        for k in (0..g.len()).step_by(97) {
            let (ip, ig, ia, iv) = (k % g.psi, (k / g.psi) % g.gamma, (k / (g.psi * g.gamma)) % g.alpha, k / (g.psi * g.gamma * g.alpha));
            let (nv, sa, gamma, psi) = (g.node(0, iv), g.node(1, ia), g.node(2, ig), g.node(3, ip));
            let q = response(lobe, nv, sa * sa, gamma, psi, 32);
            let got = table.lobe(&table.pixel(nv, sa * sa), gamma, psi);
            for c in 0..2 {
                // f16: half an ulp, 2^−11 relative (plus the subnormal floor).
                assert!((got[c] - q[c]).abs() <= q[c].abs() * 4.9e-4 + 1e-7, "{lobe:?} node {k} channel {c}: {} vs {}", got[c], q[c]);
            }
        }
    }
}

/// The f32 runtime twin (`runtime::lobe_ggx_specular`, the WGSL's formulas) equals the f64
/// path (`lobe_ggx::specular_rgb`) on the committed tables. Error model: f32 rounding of
/// the 16-tap sums, 1e-5 of Σ|c_i|·(R₀ + R₁)_i, plus input conditioning: γ comes from acos of an
/// f32 dot product (≈ 3.5e-4 rad of rounding near γ = 0), so 4× the change of the f64 value
/// when n, v and the axes move by 1.2e-7 is allowed too.
#[cfg(all(feature = "lut-lobe-ggx-sg6", feature = "lut-lobe-ggx-ad"))]
#[test]
fn f32_runtime_matches_the_f64_path() {
    use sbf::glam::Vec3;
    use sbf::recon::lobe_ggx::specular_rgb;
    let mut rng = Pcg32::new(41, 2);
    let unit = |rng: &mut Pcg32| sbf::sampling::uniform_sphere([rng.next_f64(), rng.next_f64()]);
    for table in [sbf::recon::tables::lobe_ggx_sg6(), sbf::recon::tables::lobe_ggx_ad()] {
        let axes: Vec<DVec3> = (0..9).map(|_| unit(&mut rng)).collect();
        let coeffs: Vec<[f64; 3]> = (0..9).map(|_| [0; 3].map(|_| (2.0 * rng.next_f64() - 0.5) as f32 as f64)).collect();
        let axes32: Vec<Vec3> = axes.iter().map(|a| a.as_vec3()).collect();
        let c32: Vec<Vec3> = coeffs.iter().map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)).collect();
        for _ in 0..400 {
            let n = unit(&mut rng).as_vec3().as_dvec3();
            let mut v = unit(&mut rng);
            if v.dot(n) < 0.0 {
                v = -v;
            }
            let v = v.as_vec3().as_dvec3();
            let alpha = (rng.next_f64() as f32) as f64;
            let (f0, f90) = (0.04, 1.0);
            let want = specular_rgb(table, &axes, &coeffs, n, v, alpha, f0, f90);
            let got =
                sbf::recon::runtime::lobe_ggx_specular(table, &axes32, &c32, n.as_vec3(), v.as_vec3(), alpha as f32, f0 as f32, f90 as f32);
            let abs: Vec<[f64; 3]> = coeffs.iter().map(|c| c.map(f64::abs)).collect();
            let scale = specular_rgb(table, &axes, &abs, n, v, alpha, 1.0, 1.0);
            let mut dmax = [0.0f64; 3];
            for _ in 0..4 {
                let mut jit = |x: DVec3| (x + unit(&mut rng) * 1.2e-7).normalize();
                let (nj, vj) = (jit(n), jit(v));
                let aj: Vec<DVec3> = axes.iter().map(|a| jit(*a)).collect();
                let w = specular_rgb(table, &aj, &coeffs, nj, vj, alpha, f0, f90);
                for c in 0..3 {
                    dmax[c] = dmax[c].max((w[c] - want[c]).abs());
                }
            }
            for c in 0..3 {
                let tol = 1e-5 * scale[c] + 4.0 * dmax[c] + 1e-9;
                assert!((got[c] as f64 - want[c]).abs() <= tol, "channel {c}: f32 {} vs f64 {} (tol {tol})", got[c], want[c]);
            }
        }
    }
}
