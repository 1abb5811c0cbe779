//! Texture maps in the bake: a glTF floor written by the test (its buffers as a data URI,
//! its checker image as a PNG file next to it or inside a data URI), imported, and baked into
//! light probes above it, against the closed form of what each probe sees.
//!
//! A probe stores the mean radiance over its sphere, M = (1/4π) ∫ L dω. Nothing but the
//! floor is in the scene (a probe is not geometry), so each direction below the horizon
//! sees either a floor cell — a rectangle of constant radiance — or, past the floor's
//! edge, the environment. The solid angle of a rectangle [x₀, x₁] × [z₀, z₁] at depth h
//! below a point over (0, 0) is Σ± atan(x·z / (h·√(h² + x² + z²))) over its corners
//! (the corner rectangle's closed form, summed with signs). The cells come from the
//! texture grid written here, the sRGB decode from IEC 61966-2-1 written here — neither
//! from the code under test.

mod common;
use baker::accumulate::{BakeConfig, BasisId, Solver, Targets};
use baker::scene::{Environment, Scene};
use sbf::glam::Vec3;
use std::f64::consts::PI;

/// Half the floor's side (m): the floor is [−A, A]² at y = 0, TEXCOORD_0 = ((x + A)/2A, (z + A)/2A).
const A: f64 = 4.0;
/// The checker texture: 4×4 texels, texel (i, j) (column i, row j from the top = v 0)
/// coloured COLOURS[(i + 2j) mod 3] — not symmetric under a transposition or a flip.
const N: usize = 4;
const COLOURS: [[u8; 3]; 3] = [[230, 40, 120], [40, 200, 10], [128, 128, 250]];

fn srgb(v: u8) -> f64 {
    let c = v as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn checker_png() -> Vec<u8> {
    checker_png_with(&|_| 255)
}

/// The checker with alpha `alpha(colour index)`.
fn checker_png_with(alpha: &dyn Fn(usize) -> u8) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(N as u32, N as u32, |i, j| {
        let k = (i as usize + 2 * j as usize) % 3;
        let c = COLOURS[k];
        image::Rgba([c[0], c[1], c[2], alpha(k)])
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// The floor as a .gltf in `dir` with `material` (JSON) and the checker as `image` (JSON),
/// NEAREST magnification and REPEAT wrapping; returns the imported scene.
fn floor(dir: &std::path::Path, material: &str, image: &str) -> Scene {
    plane(dir, material, image, 0.0)
}

/// [`floor`] at height `y`.
fn plane(dir: &std::path::Path, material: &str, image: &str, y: f32) -> Scene {
    let path = common::gltf::plane(dir, A as f32, y, material, image);
    let (scene, report) = baker::scene::import::load(&path).unwrap();
    println!("import notes: {:?}", report.notes);
    assert!(!report.notes.iter().any(|n| n.contains("not sampled")), "{:?}", report.notes);
    scene
}

/// The floor's cells as world rectangles [x₀, x₁] × [z₀, z₁] with the texel each reads:
/// the texture coordinate of a cell's centre through `uv_map` (the material's transform),
/// wrapped (REPEAT), to a texel (NEAREST). `cuts` per axis: the world coordinates where
/// the texel changes.
fn cells(cuts: &[f64], uv_map: &dyn Fn(f64, f64) -> (f64, f64)) -> Vec<([f64; 4], [u8; 3])> {
    let mut out = Vec::new();
    for xs in cuts.windows(2) {
        for zs in cuts.windows(2) {
            let (xc, zc) = (0.5 * (xs[0] + xs[1]), 0.5 * (zs[0] + zs[1]));
            let (u, v) = uv_map((xc + A) / (2.0 * A), (zc + A) / (2.0 * A));
            let (i, j) = (((u * N as f64).floor() as i64).rem_euclid(N as i64), ((v * N as f64).floor() as i64).rem_euclid(N as i64));
            out.push(([xs[0], xs[1], zs[0], zs[1]], COLOURS[(i + 2 * j) as usize % 3]));
        }
    }
    out
}

/// Solid angle of the world rectangle `r` seen from `p` (above the floor).
fn solid_angle(r: [f64; 4], p: Vec3) -> f64 {
    let h = p.y as f64;
    let f = |x: f64, z: f64| (x * z / (h * (h * h + x * x + z * z).sqrt())).atan();
    let (x0, x1, z0, z1) = (r[0] - p.x as f64, r[1] - p.x as f64, r[2] - p.z as f64, r[3] - p.z as f64);
    f(x1, z1) - f(x0, z1) - f(x1, z0) + f(x0, z0)
}

/// Bakes probes at `positions` on the CPU path and on the GPU (megakernel, and the
/// wavefront pipeline where `wavefront`) and checks each channel of their mean radiance
/// against `want` within 4σ of the bake's own standard error (the estimator is unbiased;
/// σ from its per-probe sample variance; f32 texture sampling on the GPU moves a probe's
/// mean by ≪ σ).
fn check_probes(scene: &Scene, positions: &[Vec3], want: &dyn Fn(Vec3) -> [f64; 3], what: &str, wavefront: bool) {
    let targets = Targets::probes(positions);
    let cfg = BakeConfig { seed: 3, max_bounces: 2, bases: vec![BasisId::Sh1], solver: Solver::Ls, ..Default::default() };
    let gpu = common::gpu();
    let mut runs = vec![("CPU", common::bake_on(None, scene, &targets, &cfg, 16384))];
    if let Some(g) = &gpu {
        runs.push(("GPU megakernel", common::bake_on(Some(g), scene, &targets, &cfg, 4096)));
        if wavefront {
            let w = BakeConfig { pipeline: baker::accumulate::Pipeline::Wavefront, ..cfg.clone() };
            runs.push(("GPU wavefront", common::bake_on(Some(g), scene, &targets, &w, 4096)));
        }
    }
    for (engine, st) in &runs {
        let (m, se) = (st.mean(), st.standard_error());
        for (k, p) in positions.iter().enumerate() {
            let w = want(*p);
            println!("{what}, {engine}: probe at {p}: {:.5?} ± {:.3?} vs closed form {w:.5?}", m[k], se[k]);
            for c in 0..3 {
                let ok = (m[k][c] - w[c]).abs() <= 4.0 * se[k][c] + 1e-6 * w[c];
                assert!(ok, "{what}, {engine}: probe {k} at {p}, channel {c}: {} vs {}", m[k][c], w[c]);
            }
        }
    }
    let se = runs[0].1.standard_error();
    // The probes tell the cells apart: neighbouring probes' closed forms differ by ≫ σ.
    let spread = (0..3).map(|c| (want(positions[0])[c] - want(positions[1])[c]).abs()).fold(0.0, f64::max);
    assert!(spread > 20.0 * se[0].iter().cloned().fold(0.0, f64::max), "{what}: the probes do not discriminate the cells");
}

/// Probes 0.5 m above the centres of four cells of the 2 m grid.
fn probe_positions() -> Vec<Vec3> {
    [(-3.0, -3.0), (-1.0, -3.0), (1.0, 1.0), (3.0, -1.0)].iter().map(|&(x, z)| Vec3::new(x, 0.5, z)).collect()
}

/// A base-colour map on a Lambert floor under a constant sky: each cell reflects ρ·L (the
/// floor sees only the sky), directions past the floor see the sky, so
/// M = L·[1 − Σ_cells (1 − ρ_cell)·Ω_cell / 4π]. The image is a file next to the asset.
/// Mutations: the map ignored (`material_at` returns the factors; on the GPU
/// `textured_material` returns `load_material`), its rows flipped, its texels not
/// sRGB-decoded (CPU and GPU) — each fails.
#[test]
fn base_colour_map_gives_each_cell_its_bounce_colour() {
    let dir = std::env::temp_dir().join(format!("sbf-textures-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("checker.png"), checker_png()).unwrap();
    let material = r#"{"name":"checker","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,1],"metallicFactor":0,"roughnessFactor":1,"baseColorTexture":{"index":0}}}"#;
    let mut scene = floor(&dir, material, r#"{"uri":"checker.png"}"#);
    // glTF's dielectric layer (F0 0.04) set to 0 after import: the floor is Lambert, ρ·L exactly.
    scene.materials[0].specular = 0.0;
    assert!(scene.has_textures() && scene.textures[0].width == N as u32);
    let l = 1.5f64;
    scene.environment = Environment::Constant(Vec3::splat(l as f32));
    let cuts: Vec<f64> = (0..=N).map(|k| -A + 2.0 * A * k as f64 / N as f64).collect();
    let grid = cells(&cuts, &|u, v| (u, v));
    let want = |p: Vec3| -> [f64; 3] {
        std::array::from_fn(|c| {
            let dark: f64 = grid.iter().map(|(r, col)| (1.0 - srgb(col[c])) * solid_angle(*r, p)).sum();
            l * (1.0 - dark / (4.0 * PI))
        })
    };
    check_probes(&scene, &probe_positions(), &want, "base colour map", false);
    std::fs::remove_dir_all(&dir).ok();
}

/// An emissive map under KHR_texture_transform (scale 2, offset (¼, 0): the checker twice
/// across the floor, shifted by one texel) on a black floor in a black world: each cell
/// emits its colour × the emissive strength 4, so M = Σ_cells L_e,cell·Ω_cell / 4π; the
/// probes sample the emitter by NEE (its share of power from the map's mean) and by their
/// point samples, MIS-weighted. The image is a data URI.
/// Mutations: the transform ignored, the emissive map ignored — each fails.
#[test]
fn emissive_map_with_texture_transform_emits_each_cells_colour() {
    let dir = std::env::temp_dir().join(format!("sbf-textures-e-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let material = r#"{"name":"lamp","pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1],"metallicFactor":0,"roughnessFactor":1},
        "emissiveFactor":[1,1,1],"emissiveTexture":{"index":0,"extensions":{"KHR_texture_transform":{"scale":[2,2],"offset":[0.25,0]}}},
        "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}}"#;
    let image = format!(r#"{{"uri":"data:image/png;base64,{}"}}"#, common::gltf::b64(&checker_png()));
    let mut scene = floor(&dir, material, &image);
    scene.materials[0].specular = 0.0;
    scene.environment = Environment::Black;
    // Texel boundaries where 4·(2u + ¼) is an integer: u = (k − 1)/8, every metre.
    let cuts: Vec<f64> = (0..=2 * N).map(|k| -A + 2.0 * A * k as f64 / (2 * N) as f64).collect();
    let grid = cells(&cuts, &|u, v| (2.0 * u + 0.25, 2.0 * v));
    let want = |p: Vec3| -> [f64; 3] {
        std::array::from_fn(|c| grid.iter().map(|(r, col)| 4.0 * srgb(col[c]) * solid_angle(*r, p)).sum::<f64>() / (4.0 * PI))
    };
    check_probes(&scene, &probe_positions(), &want, "emissive map", true);
    std::fs::remove_dir_all(&dir).ok();
}

/// An alpha-masked plane 0.5 m above the probes (alphaMode MASK, cutoff 0.5; its base
/// colour map's alpha 0 on the checker's colour-0 cells, 1 elsewhere; black, double-sided)
/// under a constant sky: the probes see the sky below, through the holes and past the
/// plane, and nothing where it is solid, so M = L·[1 − Σ_solid cells Ω_cell / 4π].
/// Mutations: the mask ignored (CPU `is_hole` false; GPU `is_hole` false), the cutoff
/// compared the wrong way — each fails.
#[test]
fn alpha_mask_lets_light_through_its_holes() {
    let dir = std::env::temp_dir().join(format!("sbf-textures-m-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let material = r#"{"name":"screen","doubleSided":true,"alphaMode":"MASK","alphaCutoff":0.5,
        "pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1],"metallicFactor":0,"roughnessFactor":1,"baseColorTexture":{"index":0}}}"#;
    let image = format!(r#"{{"uri":"data:image/png;base64,{}"}}"#, common::gltf::b64(&checker_png_with(&|k| if k == 0 { 0 } else { 255 })));
    let mut scene = plane(&dir, material, &image, 1.0);
    scene.materials[0].specular = 0.0;
    let l = 1.5f64;
    scene.environment = Environment::Constant(Vec3::splat(l as f32));
    let cuts: Vec<f64> = (0..=N).map(|k| -A + 2.0 * A * k as f64 / N as f64).collect();
    let grid = cells(&cuts, &|u, v| (u, v));
    // The plane is 0.5 m above each probe: the same solid angles as a floor 0.5 m below.
    let want = |p: Vec3| -> [f64; 3] {
        let solid: f64 = grid.iter().filter(|(_, col)| *col != COLOURS[0]).map(|(r, _)| solid_angle(*r, p)).sum();
        [l * (1.0 - solid / (4.0 * PI)); 3]
    };
    check_probes(&scene, &probe_positions(), &want, "alpha mask", false);
    std::fs::remove_dir_all(&dir).ok();
}
