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
/// same order as (b). The bound is 2·((a) + (b)) per mip. Mutations caught: the sin θ weight
/// of the quadrature dropped, the box filter's solid-angle weights dropped (equal weights).
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
