//! The prefiltered cube maps (`pf` modes) against closed forms and an independent
//! prefilter: a constant map, one bright texel's power, and a brute-force sum over the map's
//! texels at the documented roughness of every mip.

use probes::modes::prefiltered::prefilter;
use probes::modes::Context;
use sbf::envmap::{CubeMap, LatLong, LatLongImage};
use sbf::glam::DVec3;
use sbf::recon::prefiltered::{PrefilterKernel, PrefilteredCube};
use std::f64::consts::PI;

const KERNELS: [PrefilterKernel; 2] = [PrefilterKernel::Karis, PrefilterKernel::NormalIncidence];

fn map_of(w: usize, f: impl Fn(usize, usize) -> [f32; 3]) -> LatLongImage {
    let h = w / 2;
    LatLongImage::new(w, h, (0..w * h).map(|k| f(k % w, k / w)).collect()).unwrap()
}

/// Σ over a mip's texels of value × the texel's exact solid angle.
fn mip_integral(cube: &PrefilteredCube, m: usize) -> [f64; 3] {
    let n = cube.size >> m;
    let geo = CubeMap { size: n };
    let mut s = [0.0; 3];
    for (k, v) in cube.mips[m].iter().enumerate() {
        let o = geo.texel_solid_angle(k % n, (k / n) % n);
        for c in 0..3 {
            s[c] += o * v[c] as f64;
        }
    }
    s
}

/// A constant map stays constant in every mip, for both kernels, within f32: the prefilter
/// divides by the kernel's own sum and box-filters with weights summing to one, so the only
/// error left is the f32 storage of the intermediate image and of the texels (2 roundings
/// of 2⁻²⁴). The split sum of a constant is then the constant × the DFG terms (f0 A + f90 B)
/// at (n·v, α), within the same f32 bound. Mutation caught: dividing by the kernel's
/// closed-form integral instead of its quadrature sum (off by the rule's 1e-4–1e-3).
#[test]
fn a_constant_map_stays_constant() {
    let c = [0.7f32, 1.3, 2.9];
    let ctx = Context::new(map_of(64, |_, _| c));
    let dfg = sbf::recon::tables::dfg();
    for kernel in KERNELS {
        let cube = prefilter(&ctx, 8, kernel).unwrap();
        for (m, mip) in cube.mips.iter().enumerate() {
            for v in mip {
                for k in 0..3 {
                    assert!((v[k] - c[k]).abs() <= 2.0 * 2f32.powi(-24) * c[k], "{kernel:?} mip {m}: {v:?} vs {c:?}");
                }
            }
        }
        for (nv, alpha) in [(1.0f64, 0.1), (0.6, 0.3), (0.2, 0.7)] {
            let n = DVec3::Y;
            let v = DVec3::new((1.0 - nv * nv).sqrt(), nv, 0.0);
            let d = dfg.sample2(nv as f32, alpha as f32);
            let got = cube.specular(n, v, alpha, 1.0, 1.0, [d[0] as f64, d[1] as f64]);
            for k in 0..3 {
                let want = c[k] as f64 * (d[0] + d[1]) as f64;
                assert!((got[k] - want).abs() <= 4.0 * 2f64.powi(-24) * want, "{kernel:?} n·v {nv} α {alpha}: {got:?}");
            }
        }
    }
}

/// One bright texel (row 10 of 32, θ ≈ 59°, where a missing sin θ weight shows) of a black
/// 64 × 32 map: each mip integrates, over the sphere, to the texel's power (L times its exact
/// solid angle) — the normalised kernel integrates to one about any direction.
///
/// Error model, relative to the power: (a) the map's radiance is bilinear, so the power
/// prefiltered is that of the texel's tent, which differs from L·Ω_texel by the lat-long's
/// curvature across two rows, ≤ (Δθ)²/2·|cot θ| ≈ 0.3 % here (Δθ = π/32); (b) the mip's
/// midpoint sum over its texels of a lobe of half-width ≈ 2α sampled every h = π/(2n):
/// (h/2α)²/6 — at most 3.6 % for mip 0 of the 8² chain (α = 1/4, h = 11.25°), below 1 % from
/// mip 1 on; (c) the intermediate grid's bilinear reconstruction before box filtering, of the
/// same order as (b). The bound is 2·((a) + (b)) per mip. Mutation caught: the sin θ weight
/// of the quadrature dropped. Not caught: equal weights inside the box filter instead of the
/// sub-samples' solid angles (a lobe smooth over the texel moves its mean < 0.1 %).
#[test]
fn a_bright_texels_power_is_kept_in_every_mip() {
    let (i0, j0, l) = (20usize, 10usize, [100.0f32, 50.0, 25.0]);
    let ctx = Context::new(map_of(64, |i, j| if (i, j) == (i0, j0) { l } else { [0.0; 3] }));
    let geo = LatLong { width: 64, height: 32 };
    let omega = geo.texel_solid_angle(j0);
    let theta = PI * (j0 as f64 + 0.5) / 32.0;
    let a = (PI / 32.0).powi(2) / 2.0 / theta.tan().abs();
    for kernel in KERNELS {
        let cube = prefilter(&ctx, 8, kernel).unwrap();
        for m in 0..cube.mips.len() {
            let n = cube.size >> m;
            let alpha = (2.0 * (1u64 << m) as f64 / 8.0).min(1.0);
            let b = (PI / (2.0 * n as f64) / (2.0 * alpha)).powi(2) / 6.0;
            let bound = 2.0 * (a + b);
            let s = mip_integral(&cube, m);
            for c in 0..3 {
                let power = l[c] as f64 * omega;
                let rel = s[c] / power - 1.0;
                assert!(
                    rel.abs() <= bound,
                    "{kernel:?} mip {m} (α {alpha}): power {:.6} vs {power:.6} ({rel:+.2e}, bound {bound:.2e})",
                    s[c]
                );
            }
        }
    }
}

/// Every texel of every mip of the 8² chain against an independent prefilter: at the
/// documented α_m = min(1, 2·2^m/8) (written here, not read from the library), the kernel
/// summed over the source texels' centres with their exact solid angles (the map as
/// piecewise constant) and normalised by its own sum, box-filtered over the face texel with
/// 4 × 4 sub-samples. A smooth map with a bright spot, 64 × 32 (texels of 5.6°).
///
/// Error model: the two prefilters differ by the source's reconstruction (piecewise constant
/// against bilinear) — for a lobe of half-width w ≥ 2α_m ≥ 0.5 rad against texels of
/// h = π/32: ≈ (h/w)²/12 ≈ 0.3 % of the local value, up to ≈ 1 % beside the bright spot —
/// and by the box filters' sub-sampling (of the same order). Bound: 2 % RMS of the mip's
/// RMS. A mip prefiltered at the neighbour mip's α (twice or half the width) differs by
/// 10–30 %: mutation `mip_alpha` off by one mip caught.
#[test]
fn every_mip_matches_a_brute_force_prefilter() {
    let map = map_of(64, |i, j| {
        let d = LatLong { width: 64, height: 32 }.texel_direction(i, j);
        let spot = if (i, j) == (40, 12) { 200.0 } else { 0.0 };
        [(1.0 + 0.5 * d.x + 0.3 * d.y * d.z + spot) as f32, (0.6 + 0.4 * d.y) as f32, (0.8 - 0.3 * d.z) as f32]
    });
    let geo = map.geometry;
    let src: Vec<(DVec3, f64, [f32; 3])> = (0..geo.texel_count())
        .map(|k| {
            let (i, j) = (k % geo.width, k / geo.width);
            (geo.texel_direction(i, j), geo.texel_solid_angle(j), map.texel(i, j))
        })
        .collect();
    let ctx = Context::new(map);
    for kernel in KERNELS {
        let cube = prefilter(&ctx, 8, kernel).unwrap();
        for m in 0..cube.mips.len() {
            let n = 8 >> m;
            let alpha = (2.0 * (1u64 << m) as f64 / 8.0).min(1.0);
            let fine = CubeMap { size: 4 * n };
            let brute = |r: DVec3| -> [f64; 3] {
                let (mut acc, mut wsum) = ([0.0; 3], 0.0);
                for (d, o, v) in &src {
                    let c = r.dot(*d);
                    let w = kernel.weight(c, 0.5 * (r - *d).length_squared(), alpha) * o;
                    wsum += w;
                    for ch in 0..3 {
                        acc[ch] += w * v[ch] as f64;
                    }
                }
                acc.map(|x| x / wsum)
            };
            let (mut e2, mut s2) = (0.0, 0.0);
            for (k, got) in cube.mips[m].iter().enumerate() {
                let (f, j, i) = (k / (n * n), (k / n) % n, k % n);
                let (mut want, mut ow) = ([0.0; 3], 0.0);
                for b in 0..4 {
                    for a in 0..4 {
                        let o = fine.texel_solid_angle(4 * i + a, 4 * j + b);
                        let p = brute(fine.texel_direction(f, 4 * i + a, 4 * j + b));
                        for ch in 0..3 {
                            want[ch] += o * p[ch];
                        }
                        ow += o;
                    }
                }
                for ch in 0..3 {
                    e2 += (got[ch] as f64 - want[ch] / ow).powi(2);
                    s2 += (want[ch] / ow).powi(2);
                }
            }
            let rel = (e2 / s2).sqrt();
            println!("{kernel:?} mip {m} (α {alpha}): RMS difference {rel:.2e} of the RMS");
            assert!(rel <= 0.02, "{kernel:?} mip {m} (α {alpha}): {rel:.3e} of the RMS");
        }
    }
}

/// The modes of the main job (`probes::modes::DEFAULT_MODES`) but the 64² maps, and SH L8.
fn compared_modes() -> String {
    let mut ids: Vec<&str> = probes::modes::DEFAULT_MODES.iter().copied().filter(|id| !id.starts_with("pf64")).collect();
    ids.push("shl8");
    ids.join(",")
}

/// `probes compare` of `maps` with [`compared_modes`] at α 0.05, 0.1, 0.2 into `out`.
fn compare(maps: &[std::path::PathBuf], out: &std::path::Path) -> Vec<probes::results::MapResults> {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_probes"))
        .arg("compare")
        .args(maps)
        .args(["--modes", &compared_modes(), "--alphas", "0.05,0.1,0.2", "--repeats", "1", "--images", "none", "--force", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    probes::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap()
}

/// On the five bundled probes, at α 0.05, 0.1 and 0.2 (glossy specular):
/// - the prefiltered maps' errors do not grow with the face size, for each kernel: a map
///   twice as large holds the same mips plus a sharper one, so its error is equal where both
///   read the same mips (α ≥ 2/N, the smaller map's sharpest mip) and lower where only the
///   larger has a mip sharp enough (α < 2/N) — asserted both ways;
/// - from 32² faces on, every prefiltered map (both kernels) has a lower error than every
///   basis the main job compares (SH L1–L4, Ambient Dice, SG and their solvers) and SH L8;
/// - the decisions are identical when the run is repeated (on the two sun-lit probes, grace
///   and uffizi: a map's decision depends on its own results and the committed calibration).
#[test]
fn on_the_probes_prefiltered_maps_beat_every_basis_for_glossy_specular() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/probes");
    let names = ["ennis", "grace", "pisa", "uffizi", "wells"];
    let maps: Vec<std::path::PathBuf> = names.iter().map(|n| dir.join(format!("{n}.hdr"))).collect();
    if maps.iter().any(|p| !p.exists()) {
        assert!(
            std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"),
            "SBF_REQUIRE_PROBES=1 but {} lacks the probes",
            dir.display()
        );
        eprintln!("skipping: {} lacks the probes", dir.display());
        return;
    }
    let out = std::env::temp_dir().join(format!("probes-pf-{}", std::process::id()));
    let all = compare(&maps, &out.join("a"));
    for r in &all {
        let err = |id: &str, a: &str| -> Option<f64> {
            r.modes.iter().find(|m| m.id == id).and_then(|m| m.metrics.specular.get(a)).map(|s| s.metrics.rms)
        };
        for a in ["0.05", "0.1", "0.2"] {
            let alpha: f64 = a.parse().unwrap();
            for suffix in ["", "-ni"] {
                for (small, large) in [(8usize, 16usize), (16, 32)] {
                    let (es, el) = (err(&format!("pf{small}{suffix}"), a).unwrap(), err(&format!("pf{large}{suffix}"), a).unwrap());
                    let what = format!("{} α {a}: pf{small}{suffix} {es:.5} vs pf{large}{suffix} {el:.5}", r.map.path);
                    if alpha < 2.0 / small as f64 {
                        assert!(el < es, "{what}: the larger map should be better");
                    } else {
                        assert!((el - es).abs() <= 1e-9 * es, "{what}: the same mips should give the same error");
                    }
                }
            }
            let bases: Vec<(&str, f64)> = r
                .modes
                .iter()
                .filter(|m| !m.id.starts_with("pf"))
                .filter_map(|m| m.metrics.specular.get(a).map(|s| (m.id.as_str(), s.metrics.rms)))
                .collect();
            assert!(bases.len() >= 10, "{}: only {} bases with specular", r.map.path, bases.len());
            let (best_id, best) = bases.iter().copied().min_by(|x, y| x.1.total_cmp(&y.1)).unwrap();
            for id in ["pf32", "pf32-ni"] {
                let e = err(id, a).unwrap();
                assert!(e < best, "{} α {a}: {id} {e:.5} is not below {best_id} {best:.5}", r.map.path);
            }
            println!(
                "{} α {a}: best basis {best_id} {best:.4}; pf32 {:.4}, pf32-ni {:.4}",
                r.map.path,
                err("pf32", a).unwrap(),
                err("pf32-ni", a).unwrap()
            );
        }
    }
    let again = compare(&[maps[1].clone(), maps[3].clone()], &out.join("b"));
    for r in &again {
        let first = all.iter().find(|x| x.map.path == r.map.path).unwrap();
        assert_eq!(
            serde_json::to_string(&first.decision).unwrap(),
            serde_json::to_string(&r.decision).unwrap(),
            "{}: the decision changed on a repeated run",
            r.map.path
        );
    }
    std::fs::remove_dir_all(&out).ok();
}
