//! GPU primitives (`baker::gpu_prims`) against their CPU twins on random inputs, including
//! empty, single-element, all-equal inputs and sizes not divisible by the 256-element
//! workgroup block — through one, two and three scan levels (up to 70 000 elements and
//! 300 000). Exact: integer arithmetic (wrapping, as the twins). Runs on any adapter
//! (lavapipe in CI); with SBF_REQUIRE_GPU=1 a missing adapter fails.

mod common;
use baker::gpu_prims::{
    compact, compact_cpu, exclusive_scan, exclusive_scan_cpu, gather, gather_cpu, gather_reach, offsets, sort_pairs, sort_pairs_cpu,
    texel_range, texel_ranges_cpu, tile_coords, tile_index, GatherFilter, GatherInput, Prims, INVALID_CHART,
};
use sbf::sampling::Pcg32;

const SIZES: [usize; 12] = [0, 1, 2, 255, 256, 257, 511, 1000, 65_535, 65_536, 65_537, 300_001];

/// Mutations tried: the add-back pass skipped (every block restarts at 0), the scan made
/// inclusive (`data[i] = tmp[lid.x]`) — both fail.
#[test]
fn scan_equals_its_cpu_twin() {
    let Some(g) = common::gpu() else { return };
    for prims in variants(g.device()) {
        scan_case(&g, &prims);
    }
}

/// The kernels with the workgroup-memory block scan and, where the device has subgroups,
/// with the subgroup one (both must pass every test here).
fn variants(d: &wgpu::Device) -> Vec<Prims> {
    let mut v = vec![Prims::with_subgroups(d, false)];
    if d.features().contains(wgpu::Features::SUBGROUP) {
        v.push(Prims::with_subgroups(d, true));
    } else {
        println!("no subgroups on this adapter: the subgroup block scan is not run");
    }
    v
}

fn scan_case(g: &shaders::gpu::Gpu, prims: &Prims) {
    let mut r = Pcg32::new(21, 5);
    for n in SIZES {
        let cases: [(&str, Vec<u32>); 3] = [
            ("random", (0..n).map(|_| r.next_u32()).collect()),
            ("small", (0..n).map(|_| r.next_u32() % 4).collect()),
            ("all equal", vec![7; n]),
        ];
        for (what, v) in cases {
            let (want, want_total) = exclusive_scan_cpu(&v);
            let (got, total) = exclusive_scan(g.device(), g.queue(), prims, &v);
            assert_eq!(total, want_total, "{what} n = {n}, subgroups {}: total", prims.subgroups);
            if let Some(k) = (0..n).find(|k| got[*k] != want[*k]) {
                panic!("{what} n = {n}, subgroups {}: first difference at {k}: {} vs {}", prims.subgroups, got[k], want[k]);
            }
        }
    }
}

/// Mutation tried: scatter to `offsets[i] + 1` — fails.
#[test]
fn compaction_equals_its_cpu_twin() {
    let Some(g) = common::gpu() else { return };
    for prims in variants(g.device()) {
        compaction_case(&g, &prims);
    }
}

fn compaction_case(g: &shaders::gpu::Gpu, prims: &Prims) {
    let mut r = Pcg32::new(8, 13);
    for n in SIZES {
        let items: Vec<u32> = (0..n).map(|_| r.next_u32()).collect();
        for (what, flags) in [
            ("30%", (0..n).map(|_| (r.next_f64() < 0.3) as u32).collect::<Vec<u32>>()),
            ("none", vec![0; n]),
            ("all", vec![1; n]),
            ("last only", (0..n).map(|k| (k + 1 == n) as u32).collect()),
        ] {
            let want = compact_cpu(&items, &flags);
            let got = compact(g.device(), g.queue(), prims, &items, &flags);
            assert_eq!(got, want, "{what} n = {n}, subgroups {}", prims.subgroups);
        }
    }
}

/// Stable radix sort of (key, value) pairs (values = the input index, so stability shows):
/// full 32-bit keys, 20-bit keys (5 passes: odd, ends in the scratch buffers), keys with
/// only 3 distinct values, all-equal keys, already sorted and reversed input.
/// Mutations tried: the rank taken from the inclusive count without − 1 (off by one), the
/// histogram laid out block-major instead of digit-major — both fail.
#[test]
fn radix_sort_equals_its_cpu_twin() {
    let Some(g) = common::gpu() else { return };
    for prims in variants(g.device()) {
        sort_case(&g, &prims);
    }
}

fn sort_case(g: &shaders::gpu::Gpu, prims: &Prims) {
    let mut r = Pcg32::new(2, 9);
    for n in SIZES.into_iter().filter(|n| *n <= 65_537) {
        let vals: Vec<u32> = (0..n as u32).collect();
        let cases: [(&str, Vec<u32>, u32); 6] = [
            ("random 32-bit", (0..n).map(|_| r.next_u32()).collect(), 32),
            ("random 20-bit", (0..n).map(|_| r.next_u32() & 0xf_ffff).collect(), 20),
            ("three values", (0..n).map(|_| [5u32, 1 << 20, 77][(r.next_u32() % 3) as usize]).collect(), 24),
            ("all equal", vec![42; n], 32),
            ("sorted", (0..n as u32).map(|k| 3 * k).collect(), 32),
            ("reversed", (0..n as u32).rev().collect(), 32),
        ];
        for (what, keys, bits) in cases {
            let want = sort_pairs_cpu(&keys, &vals, bits);
            let got = sort_pairs(g.device(), g.queue(), prims, &keys, &vals, bits);
            assert!(
                got == want,
                "{what} n = {n} bits {bits}, subgroups {}: first difference at {:?}",
                prims.subgroups,
                (0..n).find(|k| got.0[*k] != want.0[*k] || got.1[*k] != want.1[*k])
            );
        }
    }
}

/// The offset buffer (sentinel fill + one pass, Listing 3.1) read back with the seed's rule
/// equals the per-texel ranges found by counting: sorted path texels with gaps, dense, one
/// path, none, every path on one texel, paths on the last texel only; 1 000 and 10 000
/// texels. Mutation tried: the write at the previous texel + 1 dropped — texels after a gap
/// read the wrong range, fails.
#[test]
fn offset_buffer_equals_the_counted_ranges() {
    let Some(g) = common::gpu() else { return };
    let prims = Prims::new(g.device());
    let mut r = Pcg32::new(6, 1);
    for texels in [1000usize, 10_000] {
        let mut gaps: Vec<u32> = (0..3 * texels).map(|_| (r.next_u32() as usize % texels) as u32).filter(|t| t % 7 != 3).collect();
        gaps.sort_unstable();
        let cases: [(&str, Vec<u32>); 6] = [
            ("gaps", gaps),
            ("dense", (0..texels as u32).flat_map(|t| std::iter::repeat_n(t, 1 + (t as usize % 3))).collect()),
            ("one path", vec![(texels / 2) as u32]),
            ("none", Vec::new()),
            ("one texel", vec![17; 600]),
            ("last texel", vec![texels as u32 - 1; 300]),
        ];
        for (what, sorted) in cases {
            let want = texel_ranges_cpu(&sorted, texels);
            let got = offsets(g.device(), g.queue(), &prims, &sorted, texels);
            for (t, w) in want.iter().enumerate() {
                assert_eq!(texel_range(&got, t), *w, "{what}, {texels} texels: texel {t}");
            }
        }
    }
}

/// Tile-format indices (eq. 5.2/5.3): the WGSL functions equal the Rust twins on every
/// texel of grids whose sides are and are not multiples of the tile (8×8 and 4×4 tiles),
/// and the inverse returns the texel. Mutation tried: the within-tile index as
/// n·(x mod n) + (y mod n) in WGSL only — fails.
#[test]
fn tile_index_equals_its_twin_and_inverts() {
    let Some(g) = common::gpu() else { return };
    for (w, h, log2_n) in [(64u32, 32u32, 3u32), (37, 19, 3), (21, 50, 2)] {
        let n = 1u32 << log2_n;
        let tpr = w.div_ceil(n);
        let count = (w * h) as usize;
        let body = format!(
            "    let x = i % {w}u + u32(inp[0]);\n    let y = i / {w}u;\n    let t = tile_index(x, y, {log2_n}u, {tpr}u);\n    let c = tile_coords(t, {log2_n}u, {tpr}u);\n    outp[3u * i] = f32(t);\n    outp[3u * i + 1u] = f32(c.x);\n    outp[3u * i + 2u] = f32(c.y);"
        );
        let out = g.run(baker::gpu_prims::TILE_WGSL, &body, &[0.0], 3, count, None, 0).unwrap().0;
        for k in 0..count {
            let (x, y) = (k as u32 % w, k as u32 / w);
            let t = tile_index(x, y, log2_n, tpr);
            assert_eq!(tile_coords(t, log2_n, tpr), (x, y), "{w}×{h}, n {n}: ({x}, {y})");
            assert_eq!((out[3 * k] as u32, out[3 * k + 1] as u32, out[3 * k + 2] as u32), (t, x, y), "{w}×{h}, n {n}: ({x}, {y})");
        }
    }
}

/// A gather test case: a `w` × `h` atlas split into charts (left and right halves, a band
/// of invalid texels), `k`-ish paths per texel at random positions inside their texels
/// (some texels none, `all_in_one`: every path in one texel), sorted by texel, with the
/// offset buffer built by the CPU oracle's ranges.
struct GatherCase {
    w: usize,
    h: usize,
    offsets: Vec<u32>,
    positions: Vec<[f32; 2]>,
    values: Vec<[f32; 4]>,
    charts: Vec<u32>,
}

fn gather_case(w: usize, h: usize, per_texel: u32, all_in_one: bool, r: &mut Pcg32) -> GatherCase {
    let texels = w * h;
    let charts: Vec<u32> = (0..texels)
        .map(|t| {
            let (x, y) = (t % w, t / w);
            if y == h / 2 && x % 5 == 0 {
                INVALID_CHART
            } else {
                (x >= w / 2) as u32
            }
        })
        .collect();
    let mut path_texels = Vec::new();
    if all_in_one && texels > 0 {
        path_texels = vec![(texels / 2) as u32; (per_texel as usize).max(1) * 7];
    } else {
        for t in 0..texels {
            let n = r.next_u32() % (2 * per_texel + 1);
            path_texels.extend(std::iter::repeat_n(t as u32, n as usize));
        }
    }
    let positions = path_texels
        .iter()
        .map(|t| {
            let (x, y) = ((*t as usize % w) as f32, (*t as usize / w) as f32);
            let [a, b] = r.next_2d();
            [x + a as f32, y + b as f32]
        })
        .collect();
    let values = path_texels.iter().map(|_| [r.next_f64() as f32 * 4.0, r.next_f64() as f32, 1.0 - r.next_f64() as f32, 0.0]).collect();
    let mut offsets = vec![u32::MAX; texels + 1];
    for (t, range) in texel_ranges_cpu(&path_texels, texels).into_iter().enumerate() {
        if !range.is_empty() {
            offsets[t] = range.start as u32;
            offsets[t + 1] = range.end as u32;
        }
    }
    GatherCase { w, h, offsets, positions, values, charts }
}

/// The gather's CPU twin against an independent brute force (every path against every
/// texel, positions only — no offset buffer, no neighbourhood bounds, f64 sums), and the
/// GPU against the twin, for the three filters at radius 1.5 and 2.5, on atlases whose
/// texel counts are not multiples of the workgroup, with empty texels, charts, invalid
/// texels, an empty atlas of paths and all paths in one texel. Tolerances: the twin and
/// the GPU run the same f32 steps in the same order but exp may differ by a few ulp and a
/// GPU may fuse a·b + c — 1e-5 × Σ|w·v| per texel; the brute force in f64 — the twin's
/// f32 sums of ≤ N terms are within N·2⁻²⁴·Σ|w·v|. Mutations tried: the chart test
/// dropped in WGSL, the reach one texel short (`gather_reach` − 1), the Mitchell outer
/// lobe's sign flipped — each fails.
#[test]
fn gather_equals_its_cpu_twin_and_the_brute_force() {
    let gpu = common::gpu();
    let prims = gpu.as_ref().map(|g| Prims::new(g.device()));
    let mut r = Pcg32::new(31, 7);
    for (w, h, per, one) in
        [(1, 1, 3, false), (17, 9, 2, false), (33, 31, 3, false), (40, 20, 0, false), (23, 19, 4, true), (300, 3, 1, false)]
    {
        let c = gather_case(w, h, per, one, &mut r);
        for filter in [GatherFilter::Box, GatherFilter::Gaussian, GatherFilter::Mitchell] {
            for radius in [1.5f32, 2.5] {
                let g = GatherInput {
                    width: c.w,
                    height: c.h,
                    offsets: &c.offsets,
                    positions: &c.positions,
                    values: &c.values,
                    charts: &c.charts,
                    filter,
                    radius,
                };
                let start: Vec<[f32; 4]> = (0..w * h).map(|t| [t as f32 * 0.01, 0.0, 1.0, 0.5]).collect();
                let mut twin = start.clone();
                gather_cpu(&g, &mut twin).unwrap();
                // Brute force: a path belongs to the texel its position falls in.
                let what = format!("{w}×{h}, {per}/texel{}, {filter:?} r {radius}", if one { ", all in one" } else { "" });
                for t in 0..w * h {
                    let (x, y) = ((t % w) as f64 + 0.5, (t / w) as f64 + 0.5);
                    let (mut want, mut scale, mut terms) = ([0f64; 4], 0f64, 0usize);
                    if c.charts[t] != INVALID_CHART {
                        for (p, v) in c.positions.iter().zip(&c.values) {
                            let n = p[1] as usize * w + p[0] as usize;
                            if c.charts[n] != c.charts[t] {
                                continue;
                            }
                            let wgt = filter.weight_1d(radius, (p[0] as f64 - x) as f32) as f64
                                * filter.weight_1d(radius, (p[1] as f64 - y) as f32) as f64;
                            if wgt != 0.0 {
                                for k in 0..3 {
                                    want[k] += wgt * v[k] as f64;
                                    scale += (wgt * v[k] as f64).abs();
                                }
                                want[3] += wgt;
                                scale += wgt.abs();
                                terms += 1;
                            }
                        }
                    }
                    for k in 0..4 {
                        let tol = (terms as f64 + 4.0) * 2f64.powi(-24) * (scale + start[t][k].abs() as f64);
                        let got = twin[t][k] as f64 - start[t][k] as f64;
                        assert!(
                            (got - want[k]).abs() <= tol + 1e-30,
                            "{what}: texel {t} component {k}: twin {got} vs brute force {}",
                            want[k]
                        );
                    }
                }
                if let (Some(gpu), Some(prims)) = (gpu.as_ref(), prims.as_ref()) {
                    let got = gather(gpu.device(), gpu.queue(), prims, &g, &start).unwrap();
                    for t in 0..w * h {
                        let scale: f32 = twin[t].iter().chain(&start[t]).map(|v| v.abs()).sum::<f32>().max(1e-20);
                        for k in 0..4 {
                            assert!(
                                (got[t][k] - twin[t][k]).abs() <= 1e-5 * scale,
                                "{what}: texel {t} component {k}: GPU {} vs twin {}",
                                got[t][k],
                                twin[t][k]
                            );
                        }
                    }
                }
            }
        }
    }
    // The filters against their closed-form integrals over [−r, r] (midpoint rule with
    // 200 000 cells; the kernels are C¹ or have one jump, error ≪ 1e-6 relative): box 2r,
    // Mitchell–Netravali r/2 (it integrates to 1 over its [−2, 2] argument), the shifted
    // Gaussian r·(√(2π)/2·erf(√2) − 2e⁻²) with erf(√2) = 0.9544997361036416.
    let gauss = 0.5 * (2.0 * std::f64::consts::PI).sqrt() * 0.954_499_736_103_641_6 - 2.0 * (-2f64).exp();
    for r in [1.5f32, 2.5] {
        for (filter, want) in
            [(GatherFilter::Box, 2.0 * r as f64), (GatherFilter::Mitchell, 0.5 * r as f64), (GatherFilter::Gaussian, gauss * r as f64)]
        {
            let n = 200_000;
            let h = 2.0 * r as f64 / n as f64;
            let got: f64 = (0..n).map(|i| filter.weight_1d(r, (-(r as f64) + (i as f64 + 0.5) * h) as f32) as f64 * h).sum();
            assert!((got - want).abs() < 1e-5 * want, "{filter:?} r {r}: ∫ = {got}, want {want}");
            assert_eq!(filter.weight_1d(r, r), 0.0, "{filter:?} is not zero at its radius");
        }
    }
    assert!((GatherFilter::Mitchell.weight_1d(2.0, 0.0) - 8.0 / 9.0).abs() < 1e-6);
    // Reach: a path k texels away is at least k − ½ from the centre.
    assert_eq!((gather_reach(1.5), gather_reach(2.0), gather_reach(2.5), gather_reach(0.4)), (1, 2, 2, 0));
    // Bad input is refused with a message.
    let c = gather_case(4, 4, 1, false, &mut r);
    let mut acc = vec![[0f32; 4]; 16];
    let bad = GatherInput {
        width: 4,
        height: 4,
        offsets: &c.offsets,
        positions: &c.positions,
        values: &c.values,
        charts: &c.charts,
        filter: GatherFilter::Box,
        radius: 0.0,
    };
    assert!(gather_cpu(&bad, &mut acc).unwrap_err().contains("radius"));
    let short = GatherInput { offsets: &c.offsets[..16], radius: 1.5, ..bad };
    assert!(gather_cpu(&short, &mut acc).unwrap_err().contains("offsets"));
}

/// Both block-scan variants of the prefix sum and the radix sort are valid WGSL (the
/// subgroup ones with the subgroup capabilities, and not without them).
#[test]
fn block_scan_variants_validate() {
    for (workgroup, subgroup) in baker::gpu_prims::block_scan_sources() {
        shaders::export::validate(&workgroup).unwrap();
        shaders::export::validate_subgroups(&subgroup).unwrap();
        assert!(shaders::export::validate(&subgroup).is_err());
    }
}
