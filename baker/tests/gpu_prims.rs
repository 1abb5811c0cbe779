//! GPU primitives (`baker::gpu::prims`) against their CPU twins on random inputs, including
//! empty, single-element, all-equal inputs and sizes not divisible by the 256-element
//! workgroup block — through one, two and three scan levels (up to 70 000 elements and
//! 300 000). Exact: integer arithmetic (wrapping, as the twins). Runs on any adapter
//! (lavapipe in CI); with SBF_REQUIRE_GPU=1 a missing adapter fails.

mod common;
use baker::gpu::prims::sort::{offsets, sort_pairs, sort_pairs_cpu, texel_range, texel_ranges_cpu, SortPrims};
use baker::gpu::prims::{compact, compact_cpu, exclusive_scan, exclusive_scan_cpu, Prims};
use baker::layout::tiles::{tile_coords, tile_index};
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
    let sp = SortPrims::new(g.device(), prims);
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
            let got = sort_pairs(g.device(), g.queue(), prims, &sp, &keys, &vals, bits);
            assert!(
                got == want,
                "{what} n = {n} bits {bits}, subgroups {}: first difference at {:?}",
                prims.subgroups,
                (0..n).find(|k| got.0[*k] != want.0[*k] || got.1[*k] != want.1[*k])
            );
        }
    }
}

/// The offset buffer (sentinel fill + one pass, Listing 3.1) read back with Roughton's rule
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
            let got = offsets(g.device(), g.queue(), &SortPrims::new(g.device(), &prims), &sorted, texels);
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
        let out = g.run(baker::gpu::prims::TILE_WGSL, &body, &[0.0], 3, count, None, 0).unwrap().0;
        for k in 0..count {
            let (x, y) = (k as u32 % w, k as u32 / w);
            let t = tile_index(x, y, log2_n, tpr);
            assert_eq!(tile_coords(t, log2_n, tpr), (x, y), "{w}×{h}, n {n}: ({x}, {y})");
            assert_eq!((out[3 * k] as u32, out[3 * k + 1] as u32, out[3 * k + 2] as u32), (t, x, y), "{w}×{h}, n {n}: ({x}, {y})");
        }
    }
}

/// The primitives' entry shaders compose with both block-scan variants and validate (the
/// subgroup variant with naga's subgroup capability) — on any machine, no device needed.
#[test]
fn primitive_shaders_compose_in_both_variants() {
    let [(scan_wg, scan_sg), (sort_wg, sort_sg)] = baker::gpu::prims::block_scan_sources().unwrap();
    for (what, src) in [("scan", &scan_wg), ("sort", &sort_wg)] {
        shaders::export::validate(src).unwrap_or_else(|e| panic!("{what} (workgroup): {e}"));
        assert!(!src.contains("subgroupInclusiveAdd"), "{what}: the workgroup variant uses subgroups");
    }
    for (what, src) in [("scan", &scan_sg), ("sort", &sort_sg)] {
        shaders::export::validate_subgroups(src).unwrap_or_else(|e| panic!("{what} (subgroups): {e}"));
        assert!(src.contains("subgroupInclusiveAdd"), "{what}: the subgroup variant has no subgroup scan");
    }
}
