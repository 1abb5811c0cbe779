//! The built-in procedural scenes: a Cornell-style room with a window (the default), the
//! furnace box the tests use, a room lit through a slit (ray guiding) or by a sun through
//! it (adaptive sampling), a room of 1 M lightmapped triangles (the fair benchmark), and
//! the Cornell room with a dense sphere (ray-throughput timing) — with the shapes they
//! are built from.

use super::geometry::frame;
use super::{Environment, Light, Material, Mesh, Scene};
use sbf::glam::Vec3;

/// A quad a, b, c, d (counter-clockwise seen from the side its normal faces).
fn quad(name: &str, a: Vec3, b: Vec3, c: Vec3, d: Vec3, material: usize, lightmapped: bool) -> Mesh {
    let n = (b - a).cross(d - a).normalize();
    Mesh {
        name: name.into(),
        positions: vec![a, b, c, d],
        normals: vec![n; 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material,
        lightmap_uv: None,
        lightmapped,
        uv: None,
    }
}

/// An axis-aligned box's five visible faces (no bottom), normals outwards.
fn block(name: &str, lo: Vec3, hi: Vec3, material: usize) -> Vec<Mesh> {
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let (a, b) = (lo, hi);
    vec![
        quad(&format!("{name}.top"), v(a.x, b.y, a.z), v(a.x, b.y, b.z), v(b.x, b.y, b.z), v(b.x, b.y, a.z), material, true),
        quad(&format!("{name}.+x"), v(b.x, a.y, a.z), v(b.x, b.y, a.z), v(b.x, b.y, b.z), v(b.x, a.y, b.z), material, true),
        quad(&format!("{name}.-x"), v(a.x, a.y, b.z), v(a.x, b.y, b.z), v(a.x, b.y, a.z), v(a.x, a.y, a.z), material, true),
        quad(&format!("{name}.+z"), v(b.x, a.y, b.z), v(b.x, b.y, b.z), v(a.x, b.y, b.z), v(a.x, a.y, b.z), material, true),
        quad(&format!("{name}.-z"), v(a.x, a.y, a.z), v(a.x, b.y, a.z), v(b.x, b.y, a.z), v(b.x, a.y, a.z), material, true),
    ]
}

/// The six inward-facing walls of the box [−h, h]³, all with `material`, except that
/// the front wall (z = +h) may have a window hole `window` = (x0, x1, y0, y1).
fn room(h: f32, material: [usize; 6], window: Option<(f32, f32, f32, f32)>) -> Vec<Mesh> {
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let [floor, ceiling, back, left, right, front] = material;
    let mut m = vec![
        quad("floor", v(-h, -h, -h), v(-h, -h, h), v(h, -h, h), v(h, -h, -h), floor, true),
        quad("ceiling", v(-h, h, -h), v(h, h, -h), v(h, h, h), v(-h, h, h), ceiling, true),
        quad("back", v(-h, -h, -h), v(h, -h, -h), v(h, h, -h), v(-h, h, -h), back, true),
        quad("left", v(-h, -h, -h), v(-h, h, -h), v(-h, h, h), v(-h, -h, h), left, true),
        quad("right", v(h, -h, -h), v(h, -h, h), v(h, h, h), v(h, h, -h), right, true),
    ];
    // Front wall z = +h, normal −Z: quads around the window.
    let fq =
        |name: &str, x0: f32, x1: f32, y0: f32, y1: f32| quad(name, v(x1, y0, h), v(x0, y0, h), v(x0, y1, h), v(x1, y1, h), front, true);
    match window {
        None => m.push(fq("front", -h, h, -h, h)),
        Some((x0, x1, y0, y1)) => {
            m.push(fq("front.below", -h, h, -h, y0));
            m.push(fq("front.above", -h, h, y1, h));
            m.push(fq("front.left", -h, x0, y0, y1));
            m.push(fq("front.right", x1, h, y0, y1));
        }
    }
    m
}

/// A disk area light: a fan of `segments` emissive triangles (normal `normal`, one-sided)
/// whose polygon has the disk's area (circumradius r·√(2π/(n·sin(2π/n)))). Not lightmapped.
pub fn disk_light(name: &str, centre: Vec3, normal: Vec3, radius: f32, material: usize, segments: usize) -> Mesh {
    let n = normal.normalize();
    let (t, b) = frame(n);
    let k = segments.max(3);
    let step = 2.0 * std::f64::consts::PI / k as f64;
    let rc = radius as f64 * (2.0 * std::f64::consts::PI / (k as f64 * step.sin())).sqrt();
    let mut positions = vec![centre];
    for i in 0..k {
        let a = step * i as f64;
        positions.push(centre + (t * a.cos() as f32 + b * a.sin() as f32) * rc as f32);
    }
    let indices = (0..k as u32).map(|i| [0, 1 + i, 1 + (i + 1) % k as u32]).collect();
    Mesh { name: name.into(), normals: vec![n; k + 1], positions, indices, material, lightmap_uv: None, lightmapped: false, uv: None }
}

/// A UV sphere of `rings` × `segments` quads (2·rings·segments triangles; the poles'
/// quads collapse to near-degenerate halves), outward normals and winding, lightmapped,
/// without lightmap UVs.
pub fn uv_sphere(name: &str, centre: Vec3, radius: f32, rings: usize, segments: usize, material: usize) -> Mesh {
    let (nv, nu) = (rings.max(2), segments.max(3));
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    for j in 0..=nv {
        let th = std::f32::consts::PI * j as f32 / nv as f32;
        for i in 0..=nu {
            let ph = 2.0 * std::f32::consts::PI * i as f32 / nu as f32;
            let d = Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin());
            positions.push(centre + d * radius);
            normals.push(d);
        }
    }
    let at = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    let mut indices = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            indices.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Mesh { name: name.into(), positions, normals, indices, material, lightmap_uv: None, lightmapped: true, uv: None }
}

/// A sphere area light: a UV sphere of `rings` × 2·`rings` quads, normals outwards.
/// Not lightmapped.
pub fn sphere_light(name: &str, centre: Vec3, radius: f32, material: usize, rings: usize) -> Mesh {
    Mesh { lightmapped: false, ..uv_sphere(name, centre, radius, rings.max(3), 2 * rings.max(3), material) }
}

/// The embedded default: a 2 m Cornell-style room (white floor/ceiling/back/front, red
/// left, green right wall), a 0.5 m² area light under the ceiling, a glossy block and a
/// matte block, and a window in the front wall open to a sky with a sun.
pub fn cornell() -> Scene {
    let materials = vec![
        Material::lambert(Vec3::splat(0.73)),
        Material::lambert(Vec3::new(0.63, 0.065, 0.05)),
        Material::lambert(Vec3::new(0.14, 0.45, 0.091)),
        Material::glossy(Vec3::new(0.8, 0.75, 0.6), 0.3),
        Material::emitter(Vec3::splat(12.0)),
    ];
    let mut meshes = room(1.0, [0, 0, 0, 1, 2, 0], Some((-0.4, 0.4, -0.2, 0.5)));
    meshes.extend(block("glossy", Vec3::new(-0.65, -1.0, -0.6), Vec3::new(-0.05, 0.2, 0.0), 3));
    meshes.extend(block("matte", Vec3::new(0.15, -1.0, -0.1), Vec3::new(0.7, -0.45, 0.45), 0));
    let s = 0.35;
    let y = 0.999;
    // Wound to face down (−Y).
    meshes.push(quad("light", Vec3::new(-s, y, -s), Vec3::new(s, y, -s), Vec3::new(s, y, s), Vec3::new(-s, y, s), 4, false));
    Scene {
        name: "cornell".into(),
        meshes,
        materials,
        lights: vec![Light::Directional { direction: Vec3::new(-0.3, 0.55, 1.0).normalize(), irradiance: Vec3::new(6.0, 5.6, 5.0) }],
        environment: Environment::Sky {
            zenith: Vec3::new(0.25, 0.45, 0.9),
            horizon: Vec3::new(0.8, 0.85, 0.9),
            ground: Vec3::new(0.2, 0.18, 0.15),
        },
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// A planar grid of `nu` × `nv` quads (2 triangles each) spanning corner + s·u + t·v
/// (s, t ∈ [0, 1]), facing u × v, lightmapped, with planar lightmap UVs (s·|u|, t·|v|)
/// divided by the longer side (in the unit square, aspect kept): every triangle carries
/// texels.
fn grid(name: &str, corner: Vec3, u: Vec3, v: Vec3, nu: usize, nv: usize, material: usize) -> Mesh {
    let n = u.cross(v).normalize();
    bent_grid(name, nu, nv, (u.length(), v.length()), material, |a, b| corner + u * a + v * b, |_, _| n)
}

/// Quads per metre of [`room_1m`]'s surfaces (1.8 cm cells).
const ROOM_1M_CELLS_PER_METRE: f32 = 55.5;

/// The fair benchmark scene of the wavefront pipeline: a 6 × 3 × 6 m room and four
/// 0.4 m pillars, every surface tessellated into 1.8 cm quads — 1.05 M triangles, all
/// lightmapped (planar lightmap UVs), so every ray meets triangles that carry texels and
/// the pillars make paths incoherent. Lit by two ceiling panels (not lightmapped), a spot
/// light and nothing outside (closed).
pub fn room_1m() -> Scene {
    let materials = vec![
        Material::lambert(Vec3::splat(0.7)),
        Material::lambert(Vec3::new(0.6, 0.3, 0.2)),
        Material::lambert(Vec3::new(0.25, 0.4, 0.6)),
        Material::emitter(Vec3::splat(20.0)),
    ];
    let v = Vec3::new;
    let cells = |len: f32| (len * ROOM_1M_CELLS_PER_METRE).ceil() as usize;
    let (h, y) = (3.0f32, 3.0f32);
    let g = |name: &str, c: Vec3, u: Vec3, w: Vec3, m: usize| grid(name, c, u, w, cells(u.length()), cells(w.length()), m);
    let mut meshes = vec![
        // Inward-facing walls (u × v points into the room).
        g("floor", v(-h, 0.0, -h), v(0.0, 0.0, 2.0 * h), v(2.0 * h, 0.0, 0.0), 0),
        g("ceiling", v(-h, y, -h), v(2.0 * h, 0.0, 0.0), v(0.0, 0.0, 2.0 * h), 0),
        g("back", v(-h, 0.0, -h), v(2.0 * h, 0.0, 0.0), v(0.0, y, 0.0), 1),
        g("front", v(h, 0.0, h), v(-2.0 * h, 0.0, 0.0), v(0.0, y, 0.0), 0),
        g("left", v(-h, 0.0, h), v(0.0, 0.0, -2.0 * h), v(0.0, y, 0.0), 2),
        g("right", v(h, 0.0, -h), v(0.0, 0.0, 2.0 * h), v(0.0, y, 0.0), 0),
    ];
    // Pillars: four outward-facing sides each.
    for (k, (px, pz)) in [(-1.5f32, -1.5f32), (1.5, -1.5), (-1.5, 1.5), (1.5, 1.5)].into_iter().enumerate() {
        let (a, b) = (v(px - 0.2, 0.0, pz - 0.2), v(px + 0.2, y, pz + 0.2));
        let up = v(0.0, y, 0.0);
        meshes.push(g(&format!("pillar{k}.-z"), v(b.x, 0.0, a.z), v(a.x - b.x, 0.0, 0.0), up, 0));
        meshes.push(g(&format!("pillar{k}.+z"), v(a.x, 0.0, b.z), v(b.x - a.x, 0.0, 0.0), up, 0));
        meshes.push(g(&format!("pillar{k}.-x"), v(a.x, 0.0, a.z), v(0.0, 0.0, b.z - a.z), up, 0));
        meshes.push(g(&format!("pillar{k}.+x"), v(b.x, 0.0, b.z), v(0.0, 0.0, a.z - b.z), up, 0));
    }
    // Two ceiling panels facing down.
    for (k, x) in [-1.5f32, 1.5].into_iter().enumerate() {
        let (s, yy) = (0.5f32, y - 0.001);
        meshes.push(quad(&format!("panel{k}"), v(x - s, yy, -s), v(x + s, yy, -s), v(x + s, yy, s), v(x - s, yy, s), 3, false));
    }
    Scene {
        name: "room-1m".into(),
        meshes,
        materials,
        lights: vec![Light::Spot {
            position: v(0.0, 2.8, 2.5),
            direction: v(0.0, -0.6, -1.0).normalize(),
            intensity: Vec3::splat(30.0),
            cos_inner: 0.9,
            cos_outer: 0.8,
            range: f32::INFINITY,
        }],
        environment: Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// A 2 m room lit only through a vertical slit (0.1 m × 1.2 m) in its front wall: a
/// uniform sky outside, dark grey walls inside (albedo 0.3) — the scene where first-bounce
/// ray guiding ([`crate::sampling::guiding`]) should help: texels see the sky only through the slit,
/// about 0.3% of a uniform hemisphere's samples, and the walls add little.
pub fn slit() -> Scene {
    Scene {
        name: "slit".into(),
        meshes: room(1.0, [0; 6], Some((-0.05, 0.05, -0.6, 0.6))),
        materials: vec![Material::lambert(Vec3::splat(0.3))],
        lights: vec![],
        environment: Environment::Constant(Vec3::new(3.0, 3.3, 3.9)),
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// A 1 m hut with a slit in its front wall on an 8 m × 8 m ground, under a sky and a
/// sun that shines straight in through the slit at 26.6° elevation: inside, a bright
/// stripe on the floor and the back wall lights the hut indirectly — a small bright
/// indirect region (about a tenth of the texels) whose texels are far noisier than the
/// ground's (sun by next-event estimation, exact; the sky by MIS, smooth). The scene
/// adaptive sampling ([`crate::accumulate::adaptive`]) is for.
pub fn sunbeam() -> Scene {
    let h = 0.5;
    let mut hut = room(h, [0; 6], Some((-0.03, 0.03, -0.3, 0.3)));
    for m in &mut hut {
        m.name = format!("hut.{}", m.name);
        m.positions.iter_mut().for_each(|p| p.y += h);
    }
    let g = 4.0;
    let v = Vec3::new;
    hut.push(quad("ground", v(-g, -0.002, -g), v(-g, -0.002, g), v(g, -0.002, g), v(g, -0.002, -g), 1, true));
    let mut walls = Material::lambert(Vec3::splat(0.6));
    walls.double_sided = true;
    Scene {
        name: "sunbeam".into(),
        meshes: hut,
        materials: vec![walls, Material::lambert(Vec3::splat(0.4))],
        lights: vec![Light::Directional { direction: Vec3::new(0.0, 0.5, 1.0).normalize(), irradiance: Vec3::new(40.0, 38.0, 34.0) }],
        // A dim dusk sky: the ground's noise (≈ L/√3 per sample from a constant sky under
        // uniform hemisphere sampling) stays well below the hut's.
        environment: Environment::Constant(Vec3::new(0.1, 0.11, 0.13)),
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// A closed box whose every wall emits `le` and reflects with Lambert albedo `albedo`:
/// the radiance everywhere is exactly le/(1 − albedo) (the furnace test).
pub fn furnace(le: f32, albedo: f32) -> Scene {
    let mut mat = Material::lambert(Vec3::splat(albedo));
    mat.emissive = Vec3::splat(le);
    Scene {
        name: "furnace".into(),
        meshes: room(1.0, [0; 6], None),
        materials: vec![mat],
        lights: vec![],
        environment: Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// The built-in scene plus a displaced sphere of at least `min_triangles` triangles
/// (not lightmapped: it only makes rays expensive) — the ray-throughput test scene.
pub fn dense(min_triangles: usize) -> Scene {
    let mut s = cornell();
    // A UV sphere has 2·nu·nv triangles (poles included as thin quads' halves).
    let nv = ((min_triangles as f64 / 4.0).sqrt().ceil() as usize).max(4);
    let nu = 2 * nv;
    let (centre, r0) = (Vec3::new(0.4, 0.1, 0.35), 0.3f32);
    let mut positions = Vec::with_capacity((nu + 1) * (nv + 1));
    let mut normals = Vec::with_capacity(positions.capacity());
    for j in 0..=nv {
        let th = std::f32::consts::PI * j as f32 / nv as f32;
        for i in 0..=nu {
            let ph = 2.0 * std::f32::consts::PI * i as f32 / nu as f32;
            let d = Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin());
            // A bumpy surface: ±5% radius at 12 cycles per turn.
            let r = r0 * (1.0 + 0.05 * (12.0 * th).sin() * (12.0 * ph).sin());
            positions.push(centre + d * r);
            normals.push(d);
        }
    }
    let mut indices = Vec::with_capacity(2 * nu * nv);
    let at = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    for j in 0..nv {
        for i in 0..nu {
            indices.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
            indices.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
        }
    }
    s.materials.push(Material::lambert(Vec3::splat(0.6)));
    let material = s.materials.len() - 1;
    s.meshes.push(Mesh {
        name: "dense sphere".into(),
        positions,
        normals,
        indices,
        material,
        lightmap_uv: None,
        lightmapped: false,
        uv: None,
    });
    s.name = "dense".into();
    s
}

/// A surface of revolution or any bent grid: `nu` × `nv` quads at `p(a, b)` for a, b ∈ [0, 1],
/// normals `n(a, b)`, lightmap UVs (a·len_u, b·len_v) over the longer side (its own chart).
#[allow(clippy::too_many_arguments)]
fn bent_grid(
    name: &str,
    nu: usize,
    nv: usize,
    len: (f32, f32),
    material: usize,
    p: impl Fn(f32, f32) -> Vec3,
    n: impl Fn(f32, f32) -> Vec3,
) -> Mesh {
    let side = len.0.max(len.1);
    let (mut positions, mut normals, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..=nv {
        for i in 0..=nu {
            let (a, b) = (i as f32 / nu as f32, j as f32 / nv as f32);
            positions.push(p(a, b));
            normals.push(n(a, b).normalize());
            uv.push(sbf::glam::Vec2::new(a * len.0, b * len.1) / side);
        }
    }
    let at = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    let mut indices = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            indices.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Mesh { name: name.into(), positions, normals, indices, material, lightmap_uv: Some(uv), lightmapped: true, uv: None }
}

/// An atrium at the scale of \[Roughton19\]'s Table 8.1 workload (a hall with columns, arches and
/// banners): 24 × 12 × 10 m, two rows of eight marble columns (r 0.45 m, 6 m, 64 × 72
/// quads), seven round arches between the columns of each row (intrados and both faces),
/// a gallery slab over each row, fourteen hanging banners (16 × 48 quads), a polished
/// glossy floor, a gold sphere on a pedestal in the centre without a lightmap (a dynamic
/// object: shaded from the probes), and a 12 × 4 m skylight in the ceiling through which a sun and the sky
/// light the hall — ≈ 0.29 M triangles, all lightmapped with their own UVs (one chart per
/// mesh).
pub fn atrium() -> Scene {
    use std::f32::consts::PI;
    let materials = vec![
        Material::glossy(Vec3::new(0.55, 0.52, 0.48), 0.35), // 0 polished floor
        Material::lambert(Vec3::new(0.75, 0.7, 0.62)),       // 1 walls, ceiling
        Material::glossy(Vec3::new(0.85, 0.84, 0.8), 0.25),  // 2 marble columns
        Material::lambert(Vec3::new(0.7, 0.66, 0.6)),        // 3 arches, gallery
        Material::lambert(Vec3::new(0.6, 0.08, 0.06)),       // 4 red banners
        Material::lambert(Vec3::new(0.08, 0.15, 0.55)),      // 5 blue banners
        Material { metallic: 1.0, ..Material::glossy(Vec3::new(1.0, 0.78, 0.34), 0.4) }, // 6 gold statue
    ];
    let v = Vec3::new;
    let (hx, hz, top) = (12.0f32, 6.0f32, 10.0f32);
    let g = |name: &str, c: Vec3, u: Vec3, w: Vec3, m: usize| {
        grid(name, c, u, w, (u.length() * 5.0).ceil() as usize, (w.length() * 5.0).ceil() as usize, m)
    };
    let mut meshes = vec![
        grid("floor", v(-hx, 0.0, -hz), v(0.0, 0.0, 2.0 * hz), v(2.0 * hx, 0.0, 0.0), 120, 60, 0),
        g("back", v(-hx, 0.0, -hz), v(2.0 * hx, 0.0, 0.0), v(0.0, top, 0.0), 1),
        g("front", v(hx, 0.0, hz), v(-2.0 * hx, 0.0, 0.0), v(0.0, top, 0.0), 1),
        g("left", v(-hx, 0.0, hz), v(0.0, 0.0, -2.0 * hz), v(0.0, top, 0.0), 1),
        g("right", v(hx, 0.0, -hz), v(0.0, 0.0, 2.0 * hz), v(0.0, top, 0.0), 1),
        // The ceiling around the skylight (x ∈ [−6, 6], z ∈ [−2, 2]), facing down.
        g("ceiling-back", v(-hx, top, -hz), v(2.0 * hx, 0.0, 0.0), v(0.0, 0.0, hz - 2.0), 1),
        g("ceiling-front", v(-hx, top, 2.0), v(2.0 * hx, 0.0, 0.0), v(0.0, 0.0, hz - 2.0), 1),
        g("ceiling-left", v(-hx, top, -2.0), v(hx - 6.0, 0.0, 0.0), v(0.0, 0.0, 4.0), 1),
        g("ceiling-right", v(6.0, top, -2.0), v(hx - 6.0, 0.0, 0.0), v(0.0, 0.0, 4.0), 1),
    ];
    // A dynamic object on a pedestal in the hall's centre: a gold sphere without a lightmap,
    // shaded from the probe grid.
    meshes.extend(block("pedestal", v(-0.6, 0.0, -0.6), v(0.6, 0.4, 0.6), 3));
    meshes.push(Mesh { lightmapped: false, ..uv_sphere("statue", v(0.0, 1.2, 0.0), 0.8, 32, 64, 6) });
    let (r, h) = (0.45f32, 6.0f32);
    for (row, z) in [-3.5f32, 3.5].into_iter().enumerate() {
        let xs: Vec<f32> = (0..8).map(|i| -10.5 + 3.0 * i as f32).collect();
        for (i, x) in xs.iter().enumerate() {
            let c = v(*x, 0.0, z);
            meshes.push(bent_grid(
                &format!("column{row}.{i}"),
                64,
                72,
                (2.0 * PI * r, h),
                2,
                |a, b| c + v(r * (2.0 * PI * a).cos(), h * b, -r * (2.0 * PI * a).sin()),
                |a, _| v((2.0 * PI * a).cos(), 0.0, -(2.0 * PI * a).sin()),
            ));
        }
        // Round arches from column to column: springing at 4.5 m, span 3 m − 2r, depth 0.6 m.
        for i in 0..7 {
            let (x0, x1) = (xs[i] + r, xs[i + 1] - r);
            let (cx, rad, y0, d) = (0.5 * (x0 + x1), 0.5 * (x1 - x0), 4.5f32, 0.3f32);
            let arc = |a: f32| PI * (1.0 - a);
            meshes.push(bent_grid(
                &format!("arch{row}.{i}.intrados"),
                64,
                8,
                (PI * rad, 2.0 * d),
                3,
                |a, b| v(cx + rad * arc(a).cos(), y0 + rad * arc(a).sin(), z - d + 2.0 * d * b),
                |a, _| -v(arc(a).cos(), arc(a).sin(), 0.0),
            ));
            for (side, s) in [(0usize, -1.0f32), (1, 1.0)] {
                // The arch's face: between the intrados and the gallery's underside (6 m).
                meshes.push(bent_grid(
                    &format!("arch{row}.{i}.face{side}"),
                    64,
                    8,
                    (PI * rad, h - y0),
                    3,
                    move |a, b| {
                        let (ix, iy) = (cx + rad * arc(a).cos(), y0 + rad * arc(a).sin());
                        let (ox, oy) = (cx + (a - 0.5) * 2.0 * rad, h);
                        let p = v(ix + (ox - ix) * b, iy + (oy - iy) * b, z + s * d);
                        // Mirrored on the −z face so that the winding's normal is −z.
                        if s > 0.0 {
                            p
                        } else {
                            v(2.0 * cx - p.x, p.y, p.z)
                        }
                    },
                    move |_, _| v(0.0, 0.0, s),
                ));
            }
        }
        // The gallery slab over the row: its underside (facing down) and top (facing up).
        let zz = if z < 0.0 { -hz } else { z - 0.3 };
        let depth = hz - 3.2;
        meshes.push(g(&format!("gallery{row}.under"), v(-hx, h, zz), v(2.0 * hx, 0.0, 0.0), v(0.0, 0.0, depth), 3));
        meshes.push(g(&format!("gallery{row}.top"), v(-hx, h + 0.3, zz + depth), v(2.0 * hx, 0.0, 0.0), v(0.0, 0.0, -depth), 3));
        // Banners hanging from the gallery's edge, between the columns, facing the hall.
        for i in 0..7 {
            let x = xs[i] + 1.5;
            let facing = if z < 0.0 { 1.0 } else { -1.0 };
            let bz = z + facing * 0.45;
            let (w, len) = (1.0f32, 3.0f32);
            meshes.push(bent_grid(
                &format!("banner{row}.{i}"),
                16,
                48,
                (w, len),
                4 + (i + row) % 2,
                move |a, b| v(x - facing * (a - 0.5) * w, h - 0.2 - len * b, bz + facing * 0.05 * (PI * b).sin()),
                move |_, _| v(0.0, 0.0, facing),
            ));
        }
    }
    Scene {
        name: "atrium".into(),
        meshes,
        materials,
        lights: vec![Light::Directional { direction: v(0.35, 0.9, 0.25).normalize(), irradiance: Vec3::new(20.0, 19.0, 17.0) }],
        environment: Environment::Sky {
            zenith: Vec3::new(0.9, 1.2, 1.8),
            horizon: Vec3::new(1.6, 1.7, 1.8),
            ground: Vec3::new(0.3, 0.28, 0.25),
        },
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

/// A gallery where glossy VPLs matter (after \[TH17\]'s Museum scene: "glossy caustics"
/// from a polished floor under spot lights): an 8 × 4 × 10 m room whose floor is polished
/// stone-like metal (base (0.85, 0.8, 0.75), metallic 0.7, roughness 0.3: GGX α 0.09, F0
/// ≈ 0.6), Lambert walls (one blue-grey) and ceiling, lit only by three spot lights from the
/// ceiling aimed at the floor in front of the back wall — their light reaches the walls
/// mostly by the floor's glossy reflection. Planar lightmap UVs, 4 cells per metre.
pub fn museum() -> Scene {
    let mut floor = Material::glossy(Vec3::new(0.85, 0.8, 0.75), 0.3);
    floor.metallic = 0.7;
    let materials = vec![floor, Material::lambert(Vec3::splat(0.75)), Material::lambert(Vec3::new(0.5, 0.55, 0.65))];
    let v = Vec3::new;
    let (w, h, d) = (4.0f32, 4.0f32, 5.0f32);
    let cells = |len: f32| (len * 4.0).ceil() as usize;
    let g = |name: &str, c: Vec3, u: Vec3, w: Vec3, m: usize| grid(name, c, u, w, cells(u.length()), cells(w.length()), m);
    let meshes = vec![
        // Inward-facing (u × v points into the room).
        g("floor", v(-w, 0.0, -d), v(0.0, 0.0, 2.0 * d), v(2.0 * w, 0.0, 0.0), 0),
        g("ceiling", v(-w, h, -d), v(2.0 * w, 0.0, 0.0), v(0.0, 0.0, 2.0 * d), 1),
        g("back", v(-w, 0.0, -d), v(2.0 * w, 0.0, 0.0), v(0.0, h, 0.0), 1),
        g("front", v(w, 0.0, d), v(-2.0 * w, 0.0, 0.0), v(0.0, h, 0.0), 1),
        g("left", v(-w, 0.0, d), v(0.0, 0.0, -2.0 * d), v(0.0, h, 0.0), 2),
        g("right", v(w, 0.0, -d), v(0.0, 0.0, 2.0 * d), v(0.0, h, 0.0), 1),
    ];
    let spot = |x: f32| Light::Spot {
        position: v(x, h - 0.05, -1.0),
        direction: v(0.0, -1.0, -0.45).normalize(),
        intensity: Vec3::new(60.0, 56.0, 50.0),
        cos_inner: 20f32.to_radians().cos(),
        cos_outer: 28f32.to_radians().cos(),
        range: f32::INFINITY,
    };
    Scene {
        name: "museum".into(),
        meshes,
        materials,
        lights: vec![spot(-2.5), spot(0.0), spot(2.5)],
        environment: Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}
