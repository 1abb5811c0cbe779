//! CPU reference path: furnace, BVH against brute force, layout invariants, bad scenes.

use baker::accumulate::{Bake, BakeConfig, BasisId, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::layout::lightmap::Lightmap;
use baker::scene::bvh::{intersect_tri, Bvh};
use baker::scene::{self, Scene, SceneError};
use sbf::glam::{Vec2, Vec3};
use sbf::sampling::Pcg32;

/// Furnace: a closed box emitting L_e with Lambert albedo a everywhere has radiance
/// L_e/(1 − a) in every direction, so every texel's E/π is L_e/(1 − a).
#[test]
fn furnace_cpu() {
    let (le, a) = (1.0f32, 0.5f32);
    let s = scene::furnace(le, a);
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 4.0, 1).unwrap();
    // 64 bounces: the truncated tail a^65 ≈ 3e-20 is far below the MC error; Russian
    // roulette keeps the estimator unbiased anyway.
    let tracer = Tracer::new(&s, &bvh, 64);
    let cfg = BakeConfig { max_bounces: 64, bases: vec![BasisId::Ad9], solver: Solver::Ls, ..Default::default() };
    let targets = Targets::lightmap(&lm);
    let mut bake = Bake::new(cfg, &targets, tracer);
    for _ in 0..64 {
        bake.pass();
    }
    let expect = (le / (1.0 - a)) as f64;
    let e = bake.state.mean();
    let se = bake.state.standard_error();
    let (mut n, mut within, mut sum, mut var) = (0, 0, 0.0, 0.0);
    for k in 0..targets.items.len() {
        for c in 0..3 {
            n += 1;
            sum += e[k][c];
            var += se[k][c] * se[k][c];
            if (e[k][c] - expect).abs() <= 4.0 * se[k][c] {
                within += 1;
            }
        }
    }
    let mean = sum / n as f64;
    let se_mean = var.sqrt() / n as f64;
    println!("furnace: {n} texel-channels, mean {mean:.5} (expected {expect}, ± {se_mean:.2e}), {within} within 4σ");
    // The mean over all texels: within 4 standard errors of the mean (independent texels).
    assert!((mean - expect).abs() <= 4.0 * se_mean, "mean {mean} vs {expect} ± {se_mean}");
    // Per texel: 4σ holds for 99.99% of normal errors; 99% leaves room for the
    // heavier-than-normal tail of a 64-sample mean.
    assert!(within as f64 >= 0.99 * n as f64, "{within}/{n} texels within 4σ");
}

/// The BVH finds the same closest hit as testing every triangle.
#[test]
fn bvh_matches_brute_force() {
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    assert!(bvh.depth() < 64, "depth {} exceeds the traversal stack", bvh.depth());
    let mut r = Pcg32::new(5, 5);
    for _ in 0..20_000 {
        let o = Vec3::new(r.next_f64() as f32 * 2.2 - 1.1, r.next_f64() as f32 * 2.2 - 1.1, r.next_f64() as f32 * 2.2 - 1.1);
        let d = sbf::sampling::uniform_sphere(r.next_2d()).as_vec3();
        let fast = bvh.intersect(o, d, 0.0, f32::INFINITY).map(|h| h.t);
        let slow = bvh.tris.iter().filter_map(|t| intersect_tri(t, o, d, 0.0, f32::INFINITY).map(|x| x.0)).reduce(f32::min);
        assert_eq!(fast, slow, "ray {o} {d}");
        if let Some(t) = slow {
            assert!(bvh.occluded(o, d, 0.0, t * 1.001));
            assert!(!bvh.occluded(o, d, 0.0, t * 0.999));
        }
    }
}

/// Layout: charts do not overlap, every valid texel's points lie on its chart's plane,
/// and the covered area matches the surface area (16 sub-samples per texel).
#[test]
fn layout_covers_the_surfaces() {
    let s = scene::cornell();
    let tpu = 16.0;
    let lm = Lightmap::build(&s, tpu, 1).unwrap();
    for (i, a) in lm.charts.iter().enumerate() {
        for b in &lm.charts[i + 1..] {
            let sep = a.offset.0 + a.size.0 <= b.offset.0
                || b.offset.0 + b.size.0 <= a.offset.0
                || a.offset.1 + a.size.1 <= b.offset.1
                || b.offset.1 + b.size.1 <= a.offset.1;
            assert!(sep, "charts overlap: {:?} {:?}", a.offset, b.offset);
        }
    }
    let covered: f64 = lm.texels.iter().map(|t| t.coverage.count_ones() as f64 / 16.0).sum();
    let area: f64 = s
        .meshes
        .iter()
        .filter(|m| m.lightmapped)
        .flat_map(|m| m.indices.iter().map(move |t| t.map(|i| m.positions[i as usize])))
        .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).length() as f64)
        .sum();
    let expected = area * (tpu * tpu) as f64;
    println!("area {area:.3} m² → {expected:.0} texels; covered {covered:.0}; utilisation {:.3}", lm.utilisation());
    // Sub-sampling a texel edge at 4 positions misplaces at most ¼ texel along each
    // chart border: the perimeter term is ≤ 2% of the area at this resolution.
    assert!((covered - expected).abs() / expected < 0.02, "covered {covered} vs {expected}");
    assert!(lm.utilisation() > 0.5, "utilisation {}", lm.utilisation());
}

fn tri_mesh(p: Vec<Vec3>, idx: Vec<[u32; 3]>) -> Scene {
    let n = p.len();
    Scene {
        name: "bad".into(),
        meshes: vec![scene::Mesh {
            name: "m".into(),
            positions: p,
            normals: vec![Vec3::Y; n],
            indices: idx,
            material: 0,
            lightmap_uv: None,
            lightmapped: true,
            uv: None,
        }],
        materials: vec![scene::Material::lambert(Vec3::splat(0.5))],
        lights: vec![],
        environment: scene::Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

#[test]
fn bad_scenes_give_clear_errors() {
    let ok = vec![Vec3::ZERO, Vec3::X, Vec3::Z];
    assert_eq!(tri_mesh(ok.clone(), vec![[0, 1, 2]]).validate(), Ok(0));
    assert_eq!(tri_mesh(ok.clone(), vec![]).validate(), Err(SceneError::Empty));
    let nan = vec![Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Z];
    assert!(matches!(tri_mesh(nan, vec![[0, 1, 2]]).validate(), Err(SceneError::NonFinite { .. })));
    assert!(matches!(tri_mesh(ok.clone(), vec![[0, 1, 3]]).validate(), Err(SceneError::BadIndex { index: 3, .. })));
    // Degenerate triangles are counted and skipped; a scene of only those is empty.
    assert_eq!(tri_mesh(ok.clone(), vec![[0, 1, 2], [0, 0, 1]]).validate(), Ok(1));
    assert_eq!(tri_mesh(ok.clone(), vec![[0, 0, 1]]).validate(), Err(SceneError::Empty));
    let mut uv = tri_mesh(ok.clone(), vec![[0, 1, 2]]);
    uv.meshes[0].lightmap_uv = Some(vec![Vec2::ZERO, Vec2::new(1.5, 0.0), Vec2::ONE]);
    assert!(matches!(uv.validate(), Err(SceneError::UvOutOfRange { .. })));
    let e = uv.validate().unwrap_err().to_string();
    assert!(e.contains("outside [0, 1]"), "{e}");
    let mut m = tri_mesh(ok, vec![[0, 1, 2]]);
    m.meshes[0].material = 3;
    assert!(matches!(m.validate(), Err(SceneError::BadMaterial { .. })));
    assert!(Lightmap::build(&scene::cornell(), f32::NAN, 1).is_err());
}

/// Same seed → identical result on any thread count (rayon pools of 1 and 2).
#[test]
fn deterministic_across_thread_counts() {
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 3.0, 1).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let cfg = BakeConfig { seed: 7, bases: vec![BasisId::Sh2, BasisId::Sg9], ..Default::default() };
            let targets = Targets::lightmap(&lm);
            let mut b = Bake::new(cfg, &targets, Tracer::new(&s, &bvh, 4));
            for _ in 0..4 {
                b.pass();
            }
            let coeffs: Vec<Vec<f64>> =
                b.state.encoders.iter().flat_map(|e| e.iter().map(|x| x.coefficients().as_slice().to_vec())).collect();
            (b.state.mean(), coeffs)
        })
    };
    assert_eq!(run(1), run(2));
}

/// The depth bound: a triangle soup whose SAH tree is deeper than a tight bound is built
/// within it (object-median splits below the point where SAH could overrun), and
/// traversal still finds the brute-force closest hit. The production bound is MAX_DEPTH
/// (62, for the 64-entry traversal stacks); a bound of 10 exercises the same code on a
/// test-sized scene.
#[test]
fn bvh_depth_is_bounded() {
    use baker::scene::bvh::{Tri, MAX_DEPTH};
    let mut r = Pcg32::new(9, 9);
    let mut rnd = || r.next_f64() as f32;
    let tris: Vec<Tri> = (0..2000)
        .map(|k| {
            let v0 = [rnd() * 4.0 - 2.0, rnd() * 4.0 - 2.0, rnd() * 4.0 - 2.0];
            Tri {
                corner: v0,
                material: 0,
                edge_u: [rnd() * 0.05, rnd() * 0.05, 0.0],
                mesh: 0,
                edge_v: [0.0, rnd() * 0.05, rnd() * 0.05],
                prim: k,
            }
        })
        .collect();
    let free = Bvh::from_tris_bounded(tris.clone(), usize::MAX / 2);
    let bvh = Bvh::from_tris_bounded(tris.clone(), 10);
    println!("2000-triangle soup: SAH depth {}, bounded to 10: depth {} (production bound {MAX_DEPTH})", free.depth(), bvh.depth());
    assert!(free.depth() > 11, "the soup must need the bound (SAH depth {})", free.depth());
    assert!(bvh.depth() <= 11, "depth {}", bvh.depth());
    assert!(Bvh::from_tris(tris).depth() <= MAX_DEPTH + 1);
    let mut r = Pcg32::new(10, 10);
    for _ in 0..5000 {
        let o = Vec3::new(r.next_f64() as f32 * 5.0 - 2.5, r.next_f64() as f32 * 5.0 - 2.5, r.next_f64() as f32 * 5.0 - 2.5);
        let d = sbf::sampling::uniform_sphere(r.next_2d()).as_vec3();
        let fast = bvh.intersect(o, d, 0.0, f32::INFINITY).map(|h| h.t);
        let slow = bvh.tris.iter().filter_map(|t| intersect_tri(t, o, d, 0.0, f32::INFINITY).map(|x| x.0)).reduce(f32::min);
        assert_eq!(fast, slow);
    }
}

/// A UV sphere of exactly 6 200 triangles (50 rings × 62 segments) without lightmap UVs.
fn sphere_6200() -> Scene {
    let mut s = tri_mesh(vec![Vec3::ZERO, Vec3::X, Vec3::Z], vec![[0, 1, 2]]);
    s.meshes[0] = scene::uv_sphere("sphere", Vec3::ZERO, 1.0, 50, 62, 0);
    s
}

/// Generated charts a user can live with: the 6 200-triangle sphere gets a handful of
/// charts (≤ 24) and an atlas utilisation ≥ 0.5; every triangle's UVs keep its winding
/// (no flips: positive signed area, as uvunwrap promises and this checks independently),
/// and the covered texel area matches the surface area within the parameterisation's
/// distortion bound (every chart's area ratio is within MAX_AREA_DISTORTION of its
/// mean, so the total coverage is within ±50% of area·tpu²; measured much closer).
#[test]
fn generated_charts_for_a_sphere() {
    let s = sphere_6200();
    assert_eq!(s.meshes[0].indices.len(), 6200);
    let tpu = 24.0;
    let lm = Lightmap::build(&s, tpu, 2).unwrap();
    let area: f64 = s.meshes[0]
        .indices
        .iter()
        .map(|t| t.map(|i| s.meshes[0].positions[i as usize]))
        .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).length() as f64)
        .sum();
    let covered: f64 = lm.texels.iter().map(|t| t.coverage.count_ones() as f64 / 16.0).sum();
    println!(
        "sphere of 6200 triangles at {tpu} texels/unit: {} charts, atlas {}×{}, utilisation {:.3} (block {:.3}); covered {covered:.0} texels for {:.0} of surface",
        lm.generated_charts,
        lm.width,
        lm.height,
        lm.utilisation(),
        lm.generated_utilisation,
        area * (tpu * tpu) as f64
    );
    assert!(lm.generated_charts >= 2 && lm.generated_charts <= 24, "{} charts", lm.generated_charts);
    assert!(lm.utilisation() >= 0.5, "utilisation {}", lm.utilisation());
    // (Near-)degenerate triangles — the poles' collapsed quad halves, whose f32 corners
    // differ by sin(π) ≈ 1e-7 at the south pole — get no chart (uvunwrap's own
    // tolerance); only triangles of real area must keep their winding.
    let m = &s.meshes[0];
    let mean = area / m.indices.len() as f64;
    let solid = |k: &usize| {
        let [a, b, c] = m.indices[*k].map(|i| m.positions[i as usize]);
        0.5 * (b - a).cross(c - a).length() as f64 > 1e-6 * mean
    };
    let flips = (0..m.indices.len()).filter(solid).filter(|k| {
        let t = lm.triangle_uv[0][*k];
        (t[1] - t[0]).perp_dot(t[2] - t[0]) <= 0.0
    });
    let flips = flips.count();
    assert_eq!(flips, 0, "{flips} flipped triangles");
    let ratio = covered / (area * (tpu * tpu) as f64);
    assert!((0.5..1.5).contains(&ratio), "coverage ratio {ratio}");
}

/// The built-in scene: no valid texel is exactly zero (every one sees the area light, the
/// sky or the sun, directly or by a bounce), the texels inside the blocks and above the
/// light are invalid, and the probe inside the matte block is found and can be moved out.
#[test]
fn builtin_scene_has_no_black_valid_texels_and_frees_its_probe() {
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 8.0, 1).unwrap();
    let targets = Targets::lightmap(&lm);
    let cfg = BakeConfig { seed: 2, max_bounces: 3, bases: vec![], solver: Solver::Ls, ..Default::default() };
    let mut b = Bake::new(cfg, &targets, Tracer::new(&s, &bvh, 3));
    for _ in 0..32 {
        b.pass();
    }
    let (mean, valid) = (b.state.mean(), b.state.valid());
    let black = (0..mean.len()).filter(|k| valid[*k] && mean[*k].iter().all(|x| *x == 0.0)).count();
    let invalid = valid.iter().filter(|v| !**v).count();
    println!("cornell at 8 texels/m: {} texels, {invalid} invalid (inside geometry), {black} valid and black", mean.len());
    assert_eq!(black, 0);
    assert!(invalid > 0, "the texels under the blocks must be found");
    // The default 3×3×3 grid puts probe 4 (centre column, lowest layer … ) inside the
    // matte block; whichever it is, the inside test finds it and relocation frees it.
    let grid = baker::layout::probes::probe_grid(&bvh, [3, 3, 3]);
    let inside: Vec<usize> = (0..grid.len()).filter(|k| baker::layout::probes::back_face_hits(&bvh, &s, grid[*k]).0 > 0.5).collect();
    assert!(!inside.is_empty(), "a default probe sits inside the matte block");
    for k in inside {
        let q = baker::layout::probes::relocate(&bvh, &s, grid[k], 0.5, 1e-3).expect("relocated");
        let (f, _) = baker::layout::probes::back_face_hits(&bvh, &s, q);
        println!("probe {k}: {} → {q} (back-face fraction {f:.3})", grid[k]);
        assert!(f <= 0.5 && (q - grid[k]).length() < 1.0);
    }
}

/// The fair benchmark scene (`room-1m`): at least 1 M triangles, every one in a
/// lightmapped mesh with lightmap UVs; every surface gets texels; from points inside the
/// room no ray meets a back face (every wall and pillar side faces the room; mutation: the
/// floor's two edge vectors swapped → fails).
#[test]
fn room_1m_is_a_fair_benchmark_scene() {
    let scene = baker::scene::room_1m();
    let lit: usize = scene.meshes.iter().filter(|m| m.lightmapped).map(|m| m.indices.len()).sum();
    let all: usize = scene.meshes.iter().map(|m| m.indices.len()).sum();
    assert!(lit >= 1_000_000, "{lit} lightmapped triangles");
    assert_eq!(all - lit, 4, "only the two ceiling panels are not lightmapped");
    assert!(scene.meshes.iter().filter(|m| m.lightmapped).all(|m| m.lightmap_uv.is_some()));
    let bvh = Bvh::build(&scene);
    for p in [Vec3::new(0.0, 1.5, 0.0), Vec3::new(2.5, 0.5, -2.5), Vec3::new(-0.7, 2.5, 1.9)] {
        let (fraction, _) = baker::layout::probes::back_face_hits(&bvh, &scene, p);
        assert_eq!(fraction, 0.0, "back faces seen from {p}");
    }
    let lm = Lightmap::build(&scene, 8.0, 1).unwrap();
    let mut per_chart = vec![0usize; lm.chart_meshes.len()];
    lm.texels.iter().filter(|t| t.is_valid()).for_each(|t| per_chart[t.chart as usize] += 1);
    assert!(per_chart.iter().all(|n| *n > 0), "a surface without texels: {per_chart:?}");
}
