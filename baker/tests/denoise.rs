//! The lightmap denoiser (`baker::post::denoise`) on the built-in scene's real atlas (charts,
//! padding, empty texels) with synthetic signals whose truth is known: it never reads
//! invalid texels, keeps flat and per-chart-constant signals exactly (a convex combination
//! of equal values), lowers noise on a smooth signal, and is independent of the thread
//! count.

use baker::layout::lightmap::Lightmap;
use baker::post::denoise::{denoise, DenoiseOptions};
use baker::post::images::LightmapImages;
use sbf::sampling::Pcg32;

fn atlas() -> Lightmap {
    Lightmap::build(&baker::scene::cornell(), 16.0, 2).unwrap()
}

/// Images on `lm` with E/π and two bases' coefficients from `value(texel, channel)`,
/// standard error `se`, validity from the atlas; invalid texels hold `fill`.
fn images(lm: &Lightmap, se: f32, fill: f32, value: impl Fn(usize, usize) -> f32) -> LightmapImages {
    let n = lm.width * lm.height;
    let valid: Vec<bool> = lm.texels.iter().map(|t| t.is_valid()).collect();
    let v = |t: usize, c: usize| if valid[t] { value(t, c) } else { fill };
    let rgb = |scale: f32| (0..n).map(|t| [0, 1, 2].map(|c| scale * v(t, c))).collect::<Vec<[f32; 3]>>();
    LightmapImages {
        width: lm.width,
        height: lm.height,
        validity: valid.iter().map(|b| if *b { 1.0 } else { 0.0 }).collect(),
        irradiance: rgb(1.0),
        standard_error: (0..n).map(|t| if valid[t] { [se; 3] } else { [fill; 3] }).collect(),
        coefficients: vec![vec![rgb(0.5), rgb(-0.25)], vec![rgb(2.0)]],
        normals: (0..n)
            .map(|t| {
                if valid[t] {
                    let s: sbf::glam::Vec3 = lm.texels[t].points.iter().map(|p| p.normal).sum();
                    s.normalize().to_array()
                } else {
                    [fill; 3]
                }
            })
            .collect(),
    }
}

fn gauss(r: &mut Pcg32) -> f32 {
    let (u, v) = (r.next_f64().max(1e-300), r.next_f64());
    ((-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()) as f32
}

/// NaN in every field of every invalid texel changes nothing: the filtered valid texels
/// equal, bit for bit, those of the same images with zeros there, and are finite; the
/// invalid texels are left as they were. Mutation tried: the patch loop reading a
/// neighbour without the validity check — NaN spreads, fails.
#[test]
fn invalid_texels_are_never_read() {
    let lm = atlas();
    let mut r = Pcg32::new(1, 2);
    let noise: Vec<f32> = (0..lm.width * lm.height * 3).map(|_| 0.1 * gauss(&mut r)).collect();
    let value = |t: usize, c: usize| 1.0 + noise[3 * t + c];
    let mut a = images(&lm, 0.1, f32::NAN, value);
    let mut b = images(&lm, 0.1, 0.0, value);
    denoise(&mut a, &lm, DenoiseOptions::default()).unwrap();
    denoise(&mut b, &lm, DenoiseOptions::default()).unwrap();
    for t in 0..lm.width * lm.height {
        if lm.texels[t].is_valid() {
            assert!(a.irradiance[t].iter().all(|x| x.is_finite()), "texel {t}");
            assert_eq!(a.irradiance[t], b.irradiance[t], "texel {t}");
            assert_eq!(a.coefficients[1][0][t], b.coefficients[1][0][t], "texel {t}");
        } else {
            assert!(a.irradiance[t][0].is_nan() && b.irradiance[t][0] == 0.0, "invalid texel {t} was written");
        }
    }
}

/// A signal constant per chart (the chart id; noise-free, σ 0.1 claimed) comes out
/// unchanged to f32 rounding — every output is a convex combination of its own chart's
/// values, in every coefficient set (scaled copies here). (Removing the chart guide is not
/// caught here — position and normal already separate this scene's charts; the coplanar
/// test below catches it.)
#[test]
fn constant_charts_stay_constant_and_do_not_mix() {
    let lm = atlas();
    let img0 = images(&lm, 0.1, 0.0, |t, _| 1.0 + lm.texels[t].chart as f32);
    let mut img = img0.clone();
    let st = denoise(&mut img, &lm, DenoiseOptions::default()).unwrap();
    assert!(st.texels == lm.valid_count() && st.mean_effective_neighbours > 10.0, "{st:?}");
    for t in 0..lm.width * lm.height {
        for (x, y) in img.irradiance[t].iter().zip(&img0.irradiance[t]) {
            assert!((x - y).abs() <= 1e-6 * y.abs(), "texel {t}: {x} vs {y}");
        }
        for (bx, by) in img.coefficients.iter().zip(&img0.coefficients) {
            for (lx, ly) in bx.iter().zip(by) {
                for (x, y) in lx[t].iter().zip(&ly[t]) {
                    assert!((x - y).abs() <= 1e-6 * y.abs().max(1e-30), "texel {t} coefficient: {x} vs {y}");
                }
            }
        }
    }
}

/// Noise on a smooth signal (1 + 0.3·sin of the position, per channel, white noise of
/// σ = 0.1 with that standard error): the RMS error against the truth drops by ≥ 2×.
/// Model: with ≥ 10 effective neighbours of independent noise the noise alone falls by
/// √10 ≈ 3.2; the bias of averaging a signal whose curvature scale (1 unit) is ≥ 5 window
/// radii (5 texels at 16 per unit) costs ≤ 0.3·(5/16)²/2 ≈ 0.015 — well below 0.05. Also
/// the mean of every chart with ≥ 100 texels moves by < 1% (the acceptance bar; a weighted
/// re-averaging of the chart's own noise moves it by ~σ/√N ≤ 0.01 there). Mutation tried:
/// the NLM weight replaced by 1 (a bilateral box filter) still passes here; the step test
/// below fails.
#[test]
fn noise_drops_on_a_smooth_signal() {
    let lm = atlas();
    let pos: Vec<sbf::glam::Vec3> = lm
        .texels
        .iter()
        .map(|t| {
            if t.points.is_empty() {
                sbf::glam::Vec3::ZERO
            } else {
                t.points.iter().map(|p| p.position).sum::<sbf::glam::Vec3>() / t.points.len() as f32
            }
        })
        .collect();
    let truth = |t: usize, c: usize| 1.0 + 0.3 * (pos[t].x + 0.7 * pos[t].y + 0.4 * c as f32 * pos[t].z).sin();
    let mut r = Pcg32::new(7, 3);
    let noise: Vec<f32> = (0..lm.width * lm.height * 3).map(|_| 0.1 * gauss(&mut r)).collect();
    let mut img = images(&lm, 0.1, 0.0, |t, c| truth(t, c) + noise[3 * t + c]);
    let before = img.irradiance.clone();
    let st = denoise(&mut img, &lm, DenoiseOptions::default()).unwrap();
    let rms = |v: &[[f32; 3]]| {
        let (mut s, mut n) = (0.0f64, 0usize);
        for t in 0..lm.width * lm.height {
            if lm.texels[t].is_valid() {
                for c in 0..3 {
                    s += ((v[t][c] - truth(t, c)) as f64).powi(2);
                    n += 1;
                }
            }
        }
        (s / n as f64).sqrt()
    };
    let (e0, e1) = (rms(&before), rms(&img.irradiance));
    println!("RMS error {e0:.4} → {e1:.4} ({:.2}×), {:.1} effective neighbours", e0 / e1, st.mean_effective_neighbours);
    assert!(e0 / e1 >= 2.0, "noise dropped only {:.2}×", e0 / e1);
    // Per-chart energy.
    let charts = lm.chart_meshes.len();
    for ch in 0..charts as u32 {
        let ts: Vec<usize> = (0..lm.width * lm.height).filter(|t| lm.texels[*t].is_valid() && lm.texels[*t].chart == ch).collect();
        if ts.len() < 100 {
            continue;
        }
        let mean = |v: &[[f32; 3]]| ts.iter().map(|t| v[*t].iter().sum::<f32>() as f64).sum::<f64>() / (3 * ts.len()) as f64;
        let (m0, m1) = (mean(&before), mean(&img.irradiance));
        assert!((m1 - m0).abs() <= 0.01 * m0, "chart {ch}: mean {m0} → {m1}");
    }
}

/// A sharp feature well above the noise survives: a chart's texels left of a line hold 1,
/// right of it 3, σ 0.05; after filtering, texels two or more texels away from the step keep
/// their side's value within 0.1 (a box filter over the window would smear the step by up to
/// 1 across 5 texels). The patch distance there is (Δ² − 2σ²)/(2k²σ²) ≈ 4/(0.001) ≫ 1.
#[test]
fn steps_above_the_noise_keep_their_edges() {
    let lm = atlas();
    let mut r = Pcg32::new(9, 9);
    let noise: Vec<f32> = (0..lm.width * lm.height * 3).map(|_| 0.05 * gauss(&mut r)).collect();
    let w = lm.width;
    let step = |t: usize| if (t % w) % 16 < 8 { 1.0 } else { 3.0 };
    let mut img = images(&lm, 0.05, 0.0, |t, c| step(t) + noise[3 * t + c]);
    denoise(&mut img, &lm, DenoiseOptions::default()).unwrap();
    let mut checked = 0;
    for t in 0..lm.width * lm.height {
        let x = (t % w) % 16;
        if !lm.texels[t].is_valid() || !(2..=5).contains(&x) && !(10..=13).contains(&x) {
            continue;
        }
        for c in 0..3 {
            assert!((img.irradiance[t][c] - step(t)).abs() <= 0.1, "texel {t}: {} vs {}", img.irradiance[t][c], step(t));
        }
        checked += 1;
    }
    assert!(checked > 500, "{checked}");
}

/// Identical output on 1 and 2 threads.
#[test]
fn denoise_is_independent_of_the_thread_count() {
    let lm = atlas();
    let mut r = Pcg32::new(4, 4);
    let noise: Vec<f32> = (0..lm.width * lm.height * 3).map(|_| 0.1 * gauss(&mut r)).collect();
    let img0 = images(&lm, 0.1, 0.0, |t, c| 1.0 + noise[3 * t + c]);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut img = img0.clone();
        pool.install(|| denoise(&mut img, &lm, DenoiseOptions::default()).unwrap());
        img
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.irradiance, b.irradiance);
    assert_eq!(a.coefficients, b.coefficients);
}

/// The chart guide on its own: two charts side by side in the atlas *and* on the surface
/// (one plane, the same normal, continuous positions — a seam the position and normal guides
/// cannot see), holding 1.00 and 1.02 with σ 0.1 claimed (the patch distance cannot tell
/// them apart either). Each must keep its value exactly. Mutation tried: the chart guide
/// removed — texels near the seam move by ~0.01, fails.
#[test]
fn coplanar_neighbouring_charts_do_not_mix() {
    use baker::layout::lightmap::{SurfacePoint, Texel};
    use sbf::glam::Vec3;
    let (w, h) = (24usize, 8usize);
    let texels: Vec<Texel> = (0..w * h)
        .map(|t| {
            let (x, y) = ((t % w) as f32, (t / w) as f32);
            Texel {
                coverage: 1,
                points: vec![SurfacePoint::flat(Vec3::new(x / 16.0, y / 16.0, 0.0), Vec3::Z)],
                chart: (t % w >= 12) as u32,
            }
        })
        .collect();
    let mut lm = Lightmap::build(&baker::scene::cornell(), 16.0, 2).unwrap();
    lm.width = w;
    lm.height = h;
    lm.texels = texels;
    let value = |t: usize| if t % w >= 12 { 1.02 } else { 1.0 };
    let mut img = images(&lm, 0.1, 0.0, |t, _| value(t));
    denoise(&mut img, &lm, DenoiseOptions::default()).unwrap();
    for t in 0..w * h {
        assert!((img.irradiance[t][0] - value(t)).abs() <= 1e-6, "texel {t}: {}", img.irradiance[t][0]);
    }
}

/// A real bake of the furnace (a closed box emitting L_e with albedo a: E/π = L_e/(1 − a)
/// at every texel), 64 passes on the CPU path, denoised: every texel's E/π stays within 4
/// of its *input* standard errors of the truth (the filter only averages unbiased texels
/// of the same flat signal — its output error is at most the input's, usually far below),
/// and the atlas mean moves by < 1% (measured 0.13%). Mutation tried: the output scaled by
/// 1.02 — fails.
#[test]
fn furnace_bake_stays_within_noise() {
    use baker::accumulate::{Bake, BakeConfig, BasisId, Solver, Targets};
    let (le, a) = (1.0f32, 0.5f32);
    let s = baker::scene::furnace(le, a);
    let bvh = baker::scene::bvh::Bvh::build(&s);
    let lm = Lightmap::build(&s, 4.0, 1).unwrap();
    let cfg = BakeConfig { seed: 3, max_bounces: 64, bases: vec![BasisId::Sh2], solver: Solver::Ls, ..Default::default() };
    let targets = Targets::lightmap(&lm);
    let mut bake = Bake::new(cfg, &targets, baker::estimator::trace::Tracer::new(&s, &bvh, 64));
    for _ in 0..64 {
        bake.pass();
    }
    let raw = LightmapImages::new(&lm, &targets, &bake.state);
    let mut img = raw.clone();
    let st = denoise(&mut img, &lm, DenoiseOptions::default()).unwrap();
    let truth = le / (1.0 - a);
    let (mut sum, mut var, mut n, mut e_in, mut e_out) = (0.0f64, 0.0f64, 0usize, 0.0f64, 0.0f64);
    for t in 0..lm.width * lm.height {
        if img.validity[t] <= 0.0 {
            continue;
        }
        for c in 0..3 {
            let (x, se) = (img.irradiance[t][c], raw.standard_error[t][c]);
            assert!((x - truth).abs() <= 4.0 * se, "texel {t}: {x} vs {truth} ± {se}");
            sum += x as f64;
            var += (se as f64).powi(2);
            n += 1;
            e_in += ((raw.irradiance[t][c] - truth) as f64).powi(2);
            e_out += ((x - truth) as f64).powi(2);
        }
    }
    let (mean, se_mean) = (sum / n as f64, var.sqrt() / n as f64);
    let mean_in =
        (0..lm.width * lm.height).filter(|t| img.validity[*t] > 0.0).map(|t| raw.irradiance[t].iter().sum::<f32>() as f64).sum::<f64>()
            / n as f64;
    println!(
        "furnace: mean in {mean_in:.5}, out {mean:.5} (truth {truth} ± {se_mean:.1e}), RMS error {:.2e} → {:.2e}, {:.1} effective neighbours",
        (e_in / n as f64).sqrt(),
        (e_out / n as f64).sqrt(),
        st.mean_effective_neighbours
    );
    // The bake's own mean is tested against the truth in cpu.rs; the filter must not move it
    // by 1% (the acceptance bar; NLM down-weights outliers, so it is not exactly conservative).
    assert!((mean / mean_in - 1.0).abs() < 0.01, "mean {mean_in} → {mean}");
}

/// A real bake: the built-in scene on the CPU path (SH L1, 32 passes), denoised at the
/// defaults, against a second bake with another seed as an unbiased noisy reference — no
/// long reference bake needed. With A and B independent bakes of the same expectation T
/// (error σ² per texel-channel): E[(A − B)²/2] = σ² is A's own mean squared error, and
/// E[(D(A) − B)² − (A − B)²/2] = E[(D(A) − T)²] the denoised bake's. Their difference Δ
/// over all valid texel-channels is measured on R = 4 independent pairs (seeds 1–8); its
/// standard error is the spread of the four Δ / 2 (texels of one chart are filtered
/// together, so their errors correlate: a per-texel spread would understate it).
/// Asserts: (1) mean Δ > 10.2 standard errors (one-sided 0.1 % of Student's t with 3
/// degrees of freedom): the denoiser lowers the error; (2) in every pair, no chart of
/// ≥ 30 texel-channels has its mean E/π moved by the filter by more than 4 standard
/// errors of that mean (σ̂/√n from (A − B)²/2 over the chart): the filter's bias stays below
/// the noise of the quantity it could bias. Mutations tried: the NLM weight exp(−d) →
/// exp(+d) (prefers dissimilar patches): the MSE 22× higher, chart 2's mean moved by 17.6
/// standard errors — (2) fails first; every texel averaging its right-hand neighbours'
/// window: the MSE 3.3× higher, chart 0 moved by 11.8 — (2) fails first.
#[test]
fn a_real_bake_gets_closer_to_the_truth_and_keeps_its_chart_means() {
    use baker::accumulate::{Bake, BakeConfig, BasisId, Solver, Targets};
    use baker::estimator::trace::Tracer;
    let scene = baker::scene::cornell();
    let bvh = baker::scene::bvh::Bvh::build(&scene);
    let lm = atlas();
    let targets = Targets::lightmap(&lm);
    let bake = |seed: u64| {
        let cfg = BakeConfig { seed, max_bounces: 3, bases: vec![BasisId::Sh1], solver: Solver::Ls, ..Default::default() };
        let mut b = Bake::new(cfg, &targets, Tracer::new(&scene, &bvh, 3));
        for _ in 0..32 {
            b.pass();
        }
        LightmapImages::new(&lm, &targets, &b.state)
    };
    let (mut deltas, mut worst) = (Vec::new(), 0.0f64);
    let (mut raw_sum, mut den_sum) = (0.0, 0.0);
    for pair in 0..4u64 {
        let (a, b) = (bake(2 * pair + 1), bake(2 * pair + 2));
        let mut d = a.clone();
        denoise(&mut d, &lm, DenoiseOptions::default()).unwrap();
        // Per chart: (texel-channels, Σ (A − B)²/2, Σ [(D − B)² − (A − B)²/2], Σ (D − A)).
        let mut per = vec![(0usize, 0.0f64, 0.0f64, 0.0f64); lm.chart_meshes.len()];
        for t in (0..lm.width * lm.height).filter(|t| a.validity[*t] > 0.0 && b.validity[*t] > 0.0) {
            let c = lm.texels[t].chart as usize;
            for ch in 0..3 {
                let (x, y, z) = (a.irradiance[t][ch] as f64, b.irradiance[t][ch] as f64, d.irradiance[t][ch] as f64);
                let raw = 0.5 * (x - y).powi(2);
                per[c] = (per[c].0 + 1, per[c].1 + raw, per[c].2 + (z - y).powi(2) - raw, per[c].3 + z - x);
            }
        }
        let n: usize = per.iter().map(|p| p.0).sum();
        let (raw, den) = (per.iter().map(|p| p.1).sum::<f64>() / n as f64, per.iter().map(|p| p.2).sum::<f64>() / n as f64);
        println!("pair {pair}: {n} texel-channels, MSE raw {raw:.4e}, denoised {den:.4e} ({:.2}× lower)", raw / den);
        deltas.push(raw - den);
        (raw_sum, den_sum) = (raw_sum + raw, den_sum + den);
        for (c, p) in per.iter().enumerate().filter(|(_, p)| p.0 >= 30) {
            let shift = p.3 / p.0 as f64;
            let se_mean = (p.1 / p.0 as f64 / p.0 as f64).sqrt();
            worst = worst.max(shift.abs() / se_mean);
            assert!(
                shift.abs() <= 4.0 * se_mean,
                "pair {pair}, chart {c}: the filter moves its mean E/π by {shift:.3e} ({:.1} standard errors of the mean)",
                shift.abs() / se_mean
            );
        }
    }
    let r = deltas.len() as f64;
    let m = deltas.iter().sum::<f64>() / r;
    let se = (deltas.iter().map(|g| (g - m).powi(2)).sum::<f64>() / (r - 1.0) / r).sqrt();
    println!(
        "mean over pairs: MSE raw {:.4e}, denoised {:.4e} ({:.2}× lower); Δ {m:.3e} ± {se:.2e} ({:.0} SE); largest chart-mean shift {worst:.2} SE of that mean",
        raw_sum / r,
        den_sum / r,
        raw_sum / den_sum,
        m / se
    );
    assert!(m > 10.2 * se, "the denoiser does not lower the error: Δ {m:.3e} ± {se:.2e}");
}
