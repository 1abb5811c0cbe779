//! VPLs from reflective shadow maps (`slc::rsm`, [TH17 §7]) carry the light's power onto
//! the surfaces they see, against closed forms written here:
//! - a directional light (irradiance E per channel at normal incidence, straight down) over
//!   a quad of side 2 facing it: the orthographic map is the quad's footprint, so every
//!   texel hits and the diffuse VPLs' reflected flux Φ·k sums per channel to E·k·4 (k the
//!   albedo);
//! - a point light (intensity I) 1 above the centre of a quad of half side 1.0005: the
//!   bottom cube face's frustum (45° half angle) lands inside the quad and no other face's
//!   texel centre does (the nearest is half a texel above 45°: it meets the plane 1 + 1/n
//!   out), so the reflected flux sums to I·k·4π/6.
//!
//! Error model: each texel's flux is an f32 product of a few terms (relative 1e-6), summed
//! in f64 — 1e-5 relative. Mutations tried: the texel solid angle taken as its flat area
//! (the point case's sum becomes I·k·4 instead of I·k·4π/6); the directional texel's flux
//! × 1.02 — each fails.

use baker::scene::{Environment, Light, Material, Mesh, Scene};
use baker::slc::{rsm, Camera};
use sbf::glam::Vec3;

/// A one-quad scene: the square of half side `a` at y = 0 facing +Y, albedo `k`, lit by
/// `lights`.
fn quad_scene(a: f32, k: Vec3, lights: Vec<Light>) -> Scene {
    rect_scene(a, a, k, lights)
}

/// The rectangle of half sides `ax` (x) and `az` (z) at y = 0 facing +Y.
fn rect_scene(ax: f32, az: f32, k: Vec3, lights: Vec<Light>) -> Scene {
    let a = ax;
    let quad = Mesh {
        name: "quad".into(),
        positions: vec![Vec3::new(-a, 0.0, -az), Vec3::new(-a, 0.0, az), Vec3::new(a, 0.0, az), Vec3::new(a, 0.0, -az)],
        normals: vec![Vec3::Y; 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material: 0,
        lightmap_uv: None,
        lightmapped: true,
        uv: None,
    };
    Scene {
        name: "quad".into(),
        meshes: vec![quad],
        materials: vec![Material::lambert(k)],
        lights,
        environment: Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// Σ reflected flux Φ·k of the diffuse VPLs per channel, and their count.
fn total_flux(scene: &Scene, n: usize) -> ([f64; 3], usize) {
    let bvh = baker::scene::bvh::Bvh::build(scene);
    let cam = Camera { eye: Vec3::new(0.0, 2.0, 3.0), tan_x: 1.0 };
    let v = rsm::vpls_from_rsm(scene, &bvh, cam, n, 1).unwrap();
    let d: Vec<_> = v.iter().filter(|v| v.is_diffuse()).collect();
    (std::array::from_fn(|c| d.iter().map(|v| v.flux[c] as f64 * v.diffuse[c] as f64).sum()), d.len())
}

#[test]
fn rsm_vpls_carry_the_lights_power() {
    let k = Vec3::new(0.5, 0.4, 0.3);
    let e = Vec3::new(3.0, 2.0, 1.0);
    let n = 64;
    let (got, count) = total_flux(&quad_scene(1.0, k, vec![Light::Directional { direction: Vec3::Y, irradiance: e }]), n);
    assert_eq!(count, n * n, "every texel of the directional map sees the quad");
    for c in 0..3 {
        let want = e[c] as f64 * k[c] as f64 * 4.0;
        println!("directional, channel {c}: Σ flux {:.7} vs E·k·A {want:.7}", got[c]);
        assert!((got[c] - want).abs() <= 1e-5 * want, "directional channel {c}: {} vs {want}", got[c]);
    }
    // A 2 × 1 rectangle: the texel is not square (its area du·dv).
    let (got, count) = total_flux(&rect_scene(1.0, 0.5, k, vec![Light::Directional { direction: Vec3::Y, irradiance: e }]), n);
    assert_eq!(count, n * n);
    for c in 0..3 {
        let want = e[c] as f64 * k[c] as f64 * 2.0;
        assert!((got[c] - want).abs() <= 1e-5 * want, "directional on a 2 × 1 rectangle, channel {c}: {} vs {want}", got[c]);
    }
    let i = Vec3::new(2.0, 1.5, 1.0);
    let point = Light::Point { position: Vec3::Y, intensity: i, range: f32::INFINITY };
    let (got, count) = total_flux(&quad_scene(1.0005, k, vec![point]), n);
    assert_eq!(count, n * n, "the bottom face's texels, and no other");
    for c in 0..3 {
        let want = i[c] as f64 * k[c] as f64 * 4.0 * std::f64::consts::PI / 6.0;
        println!("point, channel {c}: Σ flux {:.7} vs I·k·4π/6 {want:.7}", got[c]);
        assert!((got[c] - want).abs() <= 1e-5 * want, "point channel {c}: {} vs {want}", got[c]);
    }
    // A spot light 1 above a quad wide enough for its cone (outer 36.87°: cos 0.8, the
    // attenuation's ramp from cos 0.8 to 0.801): Σ Φ·k = k·2πI[(ci − co)/3 + 1 − ci], the
    // ramp ((c − co)/(ci − co))² integrated over the cosine. The square map's texels that the
    // cone's edge crosses are the error: bounded here by their count (corners on both sides,
    // counted in the test) × the largest texel's solid angle (the axis texel's flat area),
    // × I·k.
    let (co, ci) = (0.8f32, 0.801f32);
    let spot = Light::Spot { position: Vec3::Y, direction: -Vec3::Y, intensity: i, cos_inner: ci, cos_outer: co, range: f32::INFINITY };
    let n = 128;
    let (got, _) = total_flux(&quad_scene(3.0, k, vec![spot]), n);
    let h = (1.0 - (co as f64).powi(2)).sqrt() / co as f64;
    let cosine = |x: f64, y: f64| 1.0 / (1.0 + x * x + y * y).sqrt();
    let at = |j: usize| -h + 2.0 * h * j as f64 / n as f64;
    let straddling = (0..n * n)
        .filter(|t| {
            let (a, b) = (t % n, t / n);
            let c = [cosine(at(a), at(b)), cosine(at(a + 1), at(b)), cosine(at(a), at(b + 1)), cosine(at(a + 1), at(b + 1))];
            c.iter().any(|c| *c < ci as f64) && c.iter().any(|c| *c > co as f64)
        })
        .count();
    let texel = (2.0 * h / n as f64).powi(2);
    for c in 0..3 {
        let want = k[c] as f64 * 2.0 * std::f64::consts::PI * i[c] as f64 * ((ci - co) as f64 / 3.0 + 1.0 - ci as f64);
        let bound = straddling as f64 * texel * i[c] as f64 * k[c] as f64 + 1e-5 * want;
        println!("spot, channel {c}: Σ flux {:.6} vs closed form {want:.6} (bound {bound:.2e}, {straddling} edge texels)", got[c]);
        assert!((got[c] - want).abs() <= bound, "spot channel {c}: {} vs {want} ± {bound}", got[c]);
    }
    // The museum (spot lights over a glossy floor): its maps give diffuse and GGX VPLs, the
    // GGX ones on the floor with its α and F0.
    let museum = baker::scene::museum();
    let bvh = baker::scene::bvh::Bvh::build(&museum);
    let v = rsm::vpls_from_rsm(&museum, &bvh, Camera::preview(&bvh), 16, 1).unwrap();
    let glossy: Vec<_> = v.iter().filter(|v| !v.is_diffuse()).collect();
    assert!(glossy.len() > 100 && v.len() > glossy.len() + 100, "{} VPLs, {} glossy", v.len(), glossy.len());
    assert!(glossy.iter().all(|g| (g.alpha - 0.09).abs() < 1e-6 && g.normal.y > 0.99 && g.f0.x > 0.5), "{:?}", glossy[0]);
    // Each VPL's incoming direction points back at the spot that lit it.
    let eye = Camera::preview(&bvh).eye;
    let spots: Vec<Vec3> =
        museum.lights.iter().map(|l| if let Light::Spot { position, .. } = l { *position } else { unreachable!() }).collect();
    for v in &v {
        let p = v.position + eye;
        let best = spots.iter().map(|s| v.incoming.dot((*s - p).normalize())).fold(f32::MIN, f32::max);
        assert!(best > 0.9999, "incoming {} at {p} points at no spot ({best})", v.incoming);
    }
    // A scene without punctual lights has no shadow map to render.
    let dark = quad_scene(1.0, k, vec![]);
    let bvh = baker::scene::bvh::Bvh::build(&dark);
    let err = rsm::vpls_from_rsm(&dark, &bvh, Camera { eye: Vec3::Z, tan_x: 1.0 }, 8, 1).unwrap_err();
    assert!(err.contains("no punctual"), "{err}");
}

/// Multi-bounce VPLs (`slc::add_bounces`) keep the light's power: inside a closed cube (side
/// 2, every face Lambert with albedo k, facing in) lit by a point light at its centre, the
/// point light's cube map meets the walls everywhere, so the first hits' VPLs receive P = 4πI
/// in total, and every diffuse bounce reflects all of its light onto the walls again: the
/// VPLs of bounce b receive P·k^b, and over B bounces Σ arriving flux = P·(1 + k + … + k^B)
/// per channel (an identity of the closed box, no sampling error; f32 rounding of the
/// products and the f64 sum: 1e-5). Mutations: the continued flux not multiplied by k, or
/// multiplied twice — each fails.
#[test]
fn bounces_keep_a_closed_boxs_power() {
    let (k, i) = (Vec3::new(0.6, 0.5, 0.4), Vec3::new(1.0, 2.0, 3.0));
    let face = |name: &str, corner: Vec3, u: Vec3, v: Vec3| Mesh {
        name: name.into(),
        positions: vec![corner, corner + u, corner + u + v, corner + v],
        normals: vec![u.cross(v).normalize(); 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material: 0,
        lightmap_uv: None,
        lightmapped: true,
        uv: None,
    };
    let (x, y, z) = (Vec3::X * 2.0, Vec3::Y * 2.0, Vec3::Z * 2.0);
    let o = Vec3::splat(-1.0);
    // u × v points into the box.
    let meshes = vec![
        face("floor", o, z, x),
        face("ceiling", o + y, x, z),
        face("back", o, x, y),
        face("front", o + z, y, x),
        face("left", o, y, z),
        face("right", o + x, z, y),
    ];
    let mut scene = quad_scene(1.0, k, vec![Light::Point { position: Vec3::ZERO, intensity: i, range: f32::INFINITY }]);
    scene.meshes = meshes;
    let bvh = baker::scene::bvh::Bvh::build(&scene);
    let cam = Camera { eye: Vec3::new(0.0, 0.0, 0.9), tan_x: 1.0 };
    let first = rsm::vpls_from_rsm(&scene, &bvh, cam, 32, 1).unwrap();
    // Light paths from the same point light: every path meets a wall, so the paths' diffuse
    // VPLs receive 4πI per channel — the colour carried per unit of luminance.
    let paths = baker::slc::vpls_from_scene(&scene, &bvh, cam, 5000, 1);
    for c in 0..3 {
        let got: f64 = paths.iter().filter(|v| v.is_diffuse()).map(|v| v.flux[c] as f64).sum();
        let want = 4.0 * std::f64::consts::PI * i[c] as f64;
        assert!((got - want).abs() <= 1e-5 * want, "light paths, channel {c}: Σ flux {got} vs 4πI {want}");
    }
    let bounces = 3;
    let all = baker::slc::add_bounces(&scene, &bvh, cam, first.clone(), bounces, 1);
    assert_eq!(all[..first.len()], first[..], "the first hits' VPLs come first, unchanged");
    for c in 0..3 {
        let got: f64 = all.iter().filter(|v| v.is_diffuse()).map(|v| v.flux[c] as f64).sum();
        let p = 4.0 * std::f64::consts::PI * i[c] as f64;
        let want: f64 = (0..=bounces).map(|b| p * (k[c] as f64).powi(b as i32)).sum();
        println!("closed box, channel {c}: Σ arriving flux {got:.6} vs P·Σ k^b {want:.6}");
        assert!((got - want).abs() <= 1e-5 * want, "channel {c}: {got} vs {want}");
    }
}
