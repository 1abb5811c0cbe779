//! SG irradiance (exact, Hill, cosine-SG, punctual) and specular warps.
use crate::common;

use sbf::glam::DVec3;
use sbf::quadrature::{Domain, SphereQuadrature};
use sbf::recon::reference::ggx_specular;
use sbf::recon::sg::*;
use sbf::Sg;
use std::f64::consts::PI;

fn lobe_at(theta: f64, lambda: f64) -> Sg {
    Sg::new(DVec3::new(theta.sin(), 0.0, theta.cos()), lambda, 1.0).unwrap()
}

/// The numeric convolution equals a brute-force product rule on the hemisphere
/// (1000×2000 nodes, accurate to ~1e-9 for λ ≤ 16) to 1e-8 relative to the lobe's
/// peak irradiance.
#[test]
fn exact_matches_brute_force() {
    let q = SphereQuadrature::gauss_product(Domain::UpperHemisphere, 1000, 2000);
    for lambda in [1e-3, 0.5, 4.0, 16.0] {
        let peak = irradiance_exact(&lobe_at(0.0, lambda), DVec3::Z);
        for theta in [0.0, 0.7, 1.5, 2.2, 3.0] {
            let sg = lobe_at(theta, lambda);
            let e = irradiance_exact(&sg, DVec3::Z);
            let b = q.integrate(|w| sg.eval(w) * w.z) / PI;
            assert!((e - b).abs() < 1e-8 * peak, "λ={lambda} θ={theta}: {e} vs {b}");
        }
    }
}

/// Hill's fit vs the exact convolution over λ ∈ [0.5, 64] and θ ∈ [0, π]: the table
/// (max and RMS absolute error relative to the lobe's peak E/π) for the published
/// fit and for the runtime function (zonal expansion below λ = 2) is printed and
/// quoted in the closing note. Bars: on fitgen's own grid (λ ∈ {2, 3, …, 64} × 91
/// angles) the runtime function reaches exactly the error fitgen recorded for the
/// committed constant (`HILL_C0_MAX_ERROR`, the minimax value of the refit; bar: that
/// value + 1e-12 for rounding) — an independent re-evaluation of the fit's claim — and
/// below λ = 2 it is the zonal expansion (exact to 1e-6, tested below). The published
/// fit's breakdown below λ = 1 is asserted (> 50% at λ = 0.5) so a change in it is noticed.
#[test]
fn hill_fit_table() {
    println!("{:>6} {:>12} {:>12} {:>14} {:>12}   (error / peak E/π, 181 angles)", "λ", "fit max", "fit RMS", "runtime max", "runtime RMS");
    let mut worst_runtime = 0.0f64;
    for lambda in [0.5, 1.0, 2.0, 4.0, 6.0, 8.0, 16.0, 32.0, 64.0] {
        let peak = irradiance_exact(&lobe_at(0.0, lambda), DVec3::Z);
        let (mut mx, mut ss, mut mr, mut sr) = (0.0f64, 0.0, 0.0f64, 0.0);
        for k in 0..=180 {
            let sg = lobe_at(PI * k as f64 / 180.0, lambda);
            let e = irradiance_exact(&sg, DVec3::Z);
            let d = (hill_fit(&sg, DVec3::Z) - e) / peak;
            let r = (irradiance_hill(&sg, DVec3::Z) - e) / peak;
            mx = mx.max(d.abs());
            ss += d * d;
            mr = mr.max(r.abs());
            sr += r * r;
        }
        println!("{lambda:>6} {mx:>12.3e} {:>12.3e} {mr:>14.3e} {:>12.3e}", (ss / 181.0).sqrt(), (sr / 181.0).sqrt());
        worst_runtime = worst_runtime.max(mr);
        if lambda == 0.5 {
            assert!(mx > 0.5, "published fit at λ = 0.5: {mx}");
        }
    }
    println!("runtime worst on this 181-angle grid: {worst_runtime:.4e}");
    let bound = sbf::luts::committed::constants::HILL_C0_MAX_ERROR;
    let mut on_fitgen_grid = 0.0f64;
    for lambda in [2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0] {
        let peak = irradiance_exact(&lobe_at(0.0, lambda), DVec3::Z);
        for k in 0..=90 {
            let sg = lobe_at(PI * k as f64 / 90.0, lambda);
            on_fitgen_grid = on_fitgen_grid.max((irradiance_hill(&sg, DVec3::Z) - irradiance_exact(&sg, DVec3::Z)).abs() / peak);
        }
    }
    println!("runtime worst on fitgen's grid: {on_fitgen_grid:.6e} (recorded HILL_C0_MAX_ERROR {bound:.6e})");
    assert!(on_fitgen_grid <= bound + 1e-12, "runtime Hill error {on_fitgen_grid} exceeds the recorded {bound}");
}

/// The zonal expansion equals the exact convolution for broad lobes (λ ≤ 2) to 1e-6
/// of the peak.
#[test]
fn zonal_expansion_matches_exact() {
    for lambda in [0.0, 1e-6, 0.1, 1.0, 2.0] {
        let peak = irradiance_exact(&lobe_at(0.0, lambda), DVec3::Z);
        for k in 0..=36 {
            let sg = lobe_at(PI * k as f64 / 36.0, lambda);
            let d = (irradiance_zonal(&sg, DVec3::Z) - irradiance_exact(&sg, DVec3::Z)).abs();
            assert!(d < 1e-6 * peak, "λ={lambda} k={k}: {d:e}");
        }
    }
}

/// λ → 0: the lobe becomes the constant μ, so E/π → μ at every normal (no π
/// factor lost), continuously across the small-λ switch at 0.01.
#[test]
fn hill_small_lambda() {
    for lambda in [0.0, 1e-8, 1e-4, 0.01, 1.0] {
        for theta in [0.0, 1.0, 2.0, PI] {
            let sg = Sg::new(DVec3::new(theta.sin(), 0.0, theta.cos()), lambda, 2.0).unwrap();
            let h = irradiance_hill(&sg, DVec3::Z);
            let e = irradiance_exact(&sg, DVec3::Z);
            assert!(h.is_finite() && (h - e).abs() < 1e-6 * 2.0, "λ={lambda} θ={theta}: hill {h} exact {e}");
        }
    }
    let tiny = Sg::new(DVec3::X, 1e-9, 2.0).unwrap();
    assert!((irradiance_hill(&tiny, DVec3::Z) - 2.0).abs() < 1e-8);
    // The switch to Hill's fit at λ = 2 jumps by at most its error there (< 2% of peak).
    let a = irradiance_hill(&lobe_at(0.3, 2.0 - 1e-9), DVec3::Z);
    let b = irradiance_hill(&lobe_at(0.3, 2.0), DVec3::Z);
    assert!((a - b).abs() < 0.02 * irradiance_exact(&lobe_at(0.0, 2.0), DVec3::Z), "switch jump {}", (a - b).abs());
}

/// Cosine-SG and punctual approximations: finite, and right in their limits
/// (punctual exact for λ → ∞; cosine-SG within 5% of exact for a broad lobe).
#[test]
fn other_irradiance_approximations() {
    let sharp = lobe_at(0.4, 1e4);
    let (p, e) = (irradiance_punctual(&sharp, DVec3::Z), irradiance_exact(&sharp, DVec3::Z));
    assert!((p - e).abs() < 1e-3 * e, "punctual {p} vs exact {e}");
    let broad = lobe_at(0.4, 2.0);
    let (c, e) = (irradiance_cosine_sg(&broad, DVec3::Z), irradiance_exact(&broad, DVec3::Z));
    assert!((c - e).abs() < 0.05 * e, "cosine-SG {c} vs exact {e}");
}

/// Specular warps against the visible-normal reference with the SG as the light,
/// f0 = f90 = 1, normal +Z: printed table of relative errors; the ASG warp must be
/// within 25% for these moderate cases (the warps are approximations; their error
/// is what probes reports), and both are finite everywhere.
#[test]
fn specular_warps_vs_reference() {
    for (alpha, theta_v, lam) in [(0.3, 0.3f64, 6.0), (0.5, 0.8, 6.0), (0.3, 1.2, 16.0)] {
        let v = DVec3::new(theta_v.sin(), 0.0, theta_v.cos());
        let r = sbf::ggx::reflect(v, DVec3::Z);
        let light = Sg::new(r, lam, 1.0).unwrap();
        let reference = ggx_specular(|w| [light.eval(w); 3], DVec3::Z, v, alpha, 1.0, 1.0, 1 << 15)[0];
        let asg = specular_asg_warp(&light, DVec3::Z, v, alpha, 1.0, 1.0);
        let sgw = specular_sg_warp(&light, DVec3::Z, v, alpha, 1.0, 1.0);
        println!(
            "α={alpha} θv={theta_v} λ={lam}: reference {reference:.5}, ASG {asg:.5} ({:+.1}%), SG {sgw:.5} ({:+.1}%)",
            100.0 * (asg / reference - 1.0),
            100.0 * (sgw / reference - 1.0)
        );
        assert!((asg / reference - 1.0).abs() < 0.25);
    }
}

/// The split sum (`SplitSumWarp`) against its definition and against GGX.
/// (a) Karis' split sum is exact for constant radiance: a lobe of λ 1e-7 (constant to
///     2λ = 2e-7) reflects (f0·A + f90·B) × its amplitude — bar 1e-6 relative (O(λ/λ_D)
///     plus rounding), at α ∈ [1e-4, 1] and n·v ∈ [1e-4, 1]. Scaling, dropping the n·l
///     weight of either integral or the DFG factor fails it.
/// (b) Its definition, L̄ = ∫G·D̃·(n·l)⁺ / ∫D̃·(n·l)⁺, by the exact convolution
///     (`irradiance_exact`, numeric, no Hill) of the product lobe and of D̃: the runtime
///     replaces both by Hill's fit, whose error fitgen recorded (≤ h·peak E/π over
///     λ ∈ [2, 64], h = HILL_C0_MAX_ERROR; ×1.5 for λ and angles between fitgen's grid
///     points). So |ΔL̄| ≤ (h_N + L̄·h_D)/(E_D − h_D) with h_X = 1.5·h·peak_X. Cases: α ∈
///     [0.25, 1], n·v ≥ 0.25, λ ∈ {3, 6, 24}: the lobes' sharpness stays in [2, 64] (the
///     cases where the product falls below 2 are counted and left to (a) and the extremes).
/// (`split_sum_beats_the_asg_warp`: against GGX.)
#[test]
fn split_sum_specular() {
    let z = DVec3::Z;
    // (a)
    for alpha in [1e-4, 0.05, 0.3, 1.0] {
        for nv in [1e-4, 0.1, 0.7, 1.0] {
            let v = DVec3::new((1.0f64 - nv * nv).sqrt(), 0.0, nv);
            for axis in [z, DVec3::X, DVec3::NEG_Z] {
                let (f0, f90, dfg) = (0.04, 1.0, [0.61, 0.07]);
                let got = specular_split_sum(&Sg::new(axis, 1e-7, 3.0).unwrap(), z, v, alpha, f0, f90, dfg);
                let want = 3.0 * (f0 * dfg[0] + f90 * dfg[1]);
                assert!((got - want).abs() <= 1e-6 * want, "α {alpha} n·v {nv} axis {axis}: constant {got} vs {want}");
            }
        }
    }
    // (b)
    let h = 1.5 * sbf::luts::committed::constants::HILL_C0_MAX_ERROR;
    let (mut checked, mut below2, mut worst) = (0, 0, 0.0f64);
    let dfg = [0.5, 0.1];
    for alpha in [0.25, 0.4, 0.6, 1.0] {
        for tv in [0.0f64, 0.6, 1.0, 1.3] {
            let v = DVec3::new(tv.sin(), 0.0, tv.cos());
            let nv = tv.cos();
            let lw = (0.5 / (alpha * alpha * nv)).max(2.0);
            let ndf = Sg::new(sbf::ggx::reflect(v, z), lw, 1.0).unwrap();
            for lam in [3.0, 6.0, 24.0] {
                for k in 0..12 {
                    let (t, p) = (PI * (k as f64 + 0.5) / 12.0, 2.4 * k as f64);
                    let light = Sg::new(DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()), lam, 1.0).unwrap();
                    let prod = ndf.product(&light);
                    if prod.sharpness < 2.0 {
                        below2 += 1;
                        continue;
                    }
                    let (en, ed) = (irradiance_exact(&prod, z), irradiance_exact(&ndf, z));
                    let peak = |g: &Sg| irradiance_exact(&Sg { axis: z, ..*g }, z);
                    let (hn, hd) = (h * peak(&prod), h * peak(&ndf));
                    let lbar = en / ed;
                    let want = lbar * (0.04 * dfg[0] + dfg[1]);
                    let bound = (hn + lbar * hd) / (ed - hd) * (0.04 * dfg[0] + dfg[1]);
                    let got = specular_split_sum(&light, z, v, alpha, 0.04, 1.0, dfg);
                    assert!(
                        (got - want).abs() <= bound,
                        "α {alpha} θv {tv} λ {lam} lobe {k}: {got} vs definition {want} (bound {bound:e})"
                    );
                    worst = worst.max((got - want).abs() / bound);
                    checked += 1;
                }
            }
        }
    }
    println!("(b) {checked} cases against the definition, worst error {worst:.3} of its bound; {below2} with the product below λ 2");
    assert!(checked >= 500);
}

/// The split sum against the GGX reference (visible-normal quadrature, 2¹⁴ Halton samples:
/// its error is far below the approximations'), over the nine λ 6 lightmap lobes with unit,
/// single and random amplitudes, α ∈ {0.1, 0.2, 0.4, 0.6, 0.8, 1}, θv ∈ {0.2 … 1.4} rad, three
/// azimuths, with the committed DFG table: the relative RMS error of each configuration,
/// printed for the split sum and the ASG warp; the split sum must have the lower error in
/// every one — the reason it is the runtime's default.
#[cfg(feature = "lut-dfg")]
#[test]
fn split_sum_beats_the_asg_warp() {
    let z = DVec3::Z;
    let axes = sbf::layout::vogel_hemisphere(9).unwrap();
    let mut rng = sbf::sampling::Pcg32::new(3, 4);
    let mut configs: Vec<(String, Vec<f64>)> = vec![("unit".into(), vec![1.0; 9])];
    for i in [0usize, 4, 8] {
        let mut c = vec![0.0; 9];
        c[i] = 1.0;
        configs.push((format!("lobe {i}"), c));
    }
    for k in 0..3 {
        configs.push((format!("random {k}"), (0..9).map(|_| rng.next_f64().powi(3)).collect()));
    }
    println!("configuration | split sum: mean ×, relative RMS | ASG warp: mean ×, relative RMS");
    for (name, coef) in &configs {
        let (mut split, mut asg) = (Vec::new(), Vec::new());
        for alpha in [0.1, 0.2, 0.4, 0.6, 0.8, 1.0] {
            for tv in [0.2f64, 0.5, 0.8, 1.0, 1.2, 1.4] {
                for phi in [0.0f64, 1.3, 2.9] {
                    let v = DVec3::new(tv.sin() * phi.cos(), tv.sin() * phi.sin(), tv.cos());
                    let lobes: Vec<Sg> = axes.iter().map(|a| Sg::new(*a, 6.0, 1.0).unwrap()).collect();
                    let f = |d: DVec3| {
                        let s: f64 = lobes.iter().zip(coef).map(|(l, c)| c * l.eval(d)).sum();
                        [s; 3]
                    };
                    let reference = ggx_specular(f, z, v, alpha, 0.04, 1.0, 1 << 14)[0];
                    let d = sbf::recon::tables::dfg().sample2(tv.cos() as f32, alpha as f32);
                    let w = SplitSumWarp::new(z, v, alpha, 0.04, 1.0, [d[0] as f64, d[1] as f64]);
                    let a = AsgWarp::new(z, v, alpha, 0.04, 1.0);
                    split.push((lobes.iter().zip(coef).map(|(l, c)| c * w.lobe(l)).sum::<f64>(), reference));
                    asg.push((lobes.iter().zip(coef).map(|(l, c)| c * a.lobe(l)).sum::<f64>(), reference));
                }
            }
        }
        let stats = |x: &[(f64, f64)]| {
            let rms = (x.iter().map(|(g, r)| (g - r) * (g - r)).sum::<f64>() / x.iter().map(|(_, r)| r * r).sum::<f64>()).sqrt();
            (x.iter().map(|(g, _)| g).sum::<f64>() / x.iter().map(|(_, r)| r).sum::<f64>(), rms)
        };
        let ((sm, sr), (am, ar)) = (stats(&split), stats(&asg));
        println!("{name:9} | ×{sm:.3}, {sr:.3} | ×{am:.3}, {ar:.3}");
        assert!(sr < ar, "{name}: split sum {sr} vs ASG {ar}");
    }
}

/// Stiff and extreme inputs (α ∈ [1e-4, 1], n·v ∈ [1e-6, 1], λ up to 1e4, amplitude
/// 1e6), by value: every function is linear in the amplitude, so its value at amplitude
/// 1e6 is 1e6 × its value at 1 (bar 1e-13 relative: one rounding of the scale) and
/// non-negative; the exact convolution against a closed form in the two limits it has
/// (λ → 0: a constant A gives E/π = A, to O(λ); λ = 1e4 along the normal: E/π → A·2π/(λπ)
/// to O(1/λ)); Hill within fitgen's recorded error of the exact convolution (λ ≥ 2) or
/// equal to the zonal expansion (λ < 2, exact to 1e-6); the punctual form equals the
/// lobe's integral/π times the clamped cosine of its axis.
#[test]
fn extremes_by_value() {
    let hill_bound = sbf::luts::committed::constants::HILL_C0_MAX_ERROR;
    for alpha in [1e-4, 1e-2, 0.5, 1.0] {
        for nv in [1e-6, 1e-3, 0.5, 1.0] {
            let v = DVec3::new((1.0f64 - nv * nv).sqrt(), 0.0, nv);
            for lam in [1e-4, 1.0, 1e4] {
                for light_axis in [DVec3::Z, sbf::ggx::reflect(v, DVec3::Z), DVec3::NEG_Z, DVec3::X] {
                    let all = |amp: f64| {
                        let l = Sg::new(light_axis, lam, amp).unwrap();
                        [
                            specular_asg_warp(&l, DVec3::Z, v, alpha, 0.04, 1.0),
                            specular_sg_warp(&l, DVec3::Z, v, alpha, 0.04, 1.0),
                            specular_split_sum(&l, DVec3::Z, v, alpha, 0.04, 1.0, [0.7, 0.05]),
                            irradiance_hill(&l, DVec3::Z),
                            irradiance_exact(&l, DVec3::Z),
                            irradiance_cosine_sg(&l, DVec3::Z),
                            irradiance_punctual(&l, DVec3::Z),
                        ]
                    };
                    let (big, one) = (all(1e6), all(1.0));
                    for (k, (b, o)) in big.iter().zip(&one).enumerate() {
                        assert!(
                            *b >= 0.0 && (b - 1e6 * o).abs() <= 1e-13 * b.abs().max(1e-300),
                            "α={alpha} n·v={nv} λ={lam} axis={light_axis} f{k}: {b} vs 1e6 × {o}"
                        );
                    }
                    let (hill, exact, punctual) = (one[3], one[4], one[6]);
                    let integral = sbf::basis::sg::sg_unit_integral(lam) / PI;
                    assert!((punctual - integral * light_axis.z.max(0.0)).abs() <= 1e-14 * integral, "punctual {punctual}");
                    let peak = irradiance_exact(&Sg::new(DVec3::Z, lam, 1.0).unwrap(), DVec3::Z);
                    let bar = if lam >= 2.0 { hill_bound + 1e-12 } else { 1e-6 };
                    assert!((hill - exact).abs() <= bar * peak, "λ={lam} axis={light_axis}: Hill {hill} vs exact {exact}");
                    if lam == 1e-4 {
                        assert!((exact - 1.0).abs() <= 2.0 * lam, "λ → 0: E/π {exact} vs 1");
                    }
                    if lam == 1e4 && light_axis == DVec3::Z {
                        let limit = 2.0 * PI / (lam * PI);
                        assert!((exact - limit).abs() <= 2.0 / lam * limit, "λ = 1e4: E/π {exact} vs {limit}");
                    }
                }
            }
        }
    }
}

/// Constant radiance through the ambient function: E/π = L at every normal.
#[test]
fn ambient_lobe_constant() {
    let b = sbf::SgBasis::new(&sbf::layout::vogel_sphere(12).unwrap(), 6.0, true).unwrap();
    let mut c = vec![0.0; 13];
    c[12] = 2.5;
    for n in common::random_directions(8, 100) {
        assert_eq!(irradiance_basis(&b, &c, n), 2.5);
    }
}

/// The peer's SG-kernel irradiance: (a) a constant (λ = 0 lobe of amplitude c)
/// reflects exactly c, because the kernel integrates to π — to 1e-12 (rounding);
/// (b) it equals a brute-force sphere quadrature of G·K/π (1000×2000 Gauss product,
/// accurate to ~1e-9 at these λ) to 1e-8 relative.
#[test]
fn sg_kernel_irradiance() {
    for kl in [3.0, 8.5] {
        let c = Sg::new(DVec3::Y, 0.0, 2.5).unwrap();
        let e = irradiance_sg_kernel(&c, DVec3::new(0.3, 0.4, 0.866).normalize(), kl);
        assert!((e - 2.5).abs() < 1e-12, "constant through λ_k={kl}: {e}");
    }
    let q = SphereQuadrature::gauss_product(Domain::Sphere, 1000, 2000);
    for (lambda, kl, theta) in [(6.0, 3.0, 0.4), (6.0, 8.5, 1.2), (0.5, 3.0, 2.5)] {
        let sg = lobe_at(theta, lambda);
        let k = Sg::new(DVec3::Z, kl, 1.0).unwrap();
        let b = q.integrate(|w| sg.eval(w) * k.eval(w)) * PI / k.integral() / PI;
        let e = irradiance_sg_kernel(&sg, DVec3::Z, kl);
        assert!((e - b).abs() < 1e-8 * b.abs().max(1e-3), "λ={lambda} λk={kl} θ={theta}: {e} vs {b}");
    }
}
