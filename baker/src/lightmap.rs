//! Lightmap layout: charts, packing, and per-texel sample points (seed 004 ch. 4).
//!
//! Charts: the triangles of each lightmapped mesh grouped by plane (same normal and
//! offset to 1e-4), projected onto the plane's tangent frame ("planar grouping by
//! normal"). Packing: a shelf packer (charts sorted by height, rows left to right) with
//! `padding` texels around every chart; the measured utilisation is reported.
//! Coverage (§4.2): every texel has 16 fixed sub-texel sample positions (a 4 × 4 grid);
//! the bits of a `u16` say which lie on a triangle, and each covered position stores the
//! surface point it maps to. A texel is valid when any bit is set.

use crate::scene::Scene;
use sbf::glam::{Vec2, Vec3};

/// Sub-texel positions per texel (4 × 4).
pub const SUBSAMPLES: usize = 16;

/// A surface point a texel samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    pub position: Vec3,
    /// Unit shading normal: the mesh's vertex normals interpolated barycentrically
    /// (glTF NORMAL, or generated), the face normal where they vanish or face away from
    /// it. The texel's hemisphere, cosine and basis frame are about this normal.
    pub normal: Vec3,
    /// Unit geometric (face) normal: ray offsets and the surface's own horizon.
    pub geometric: Vec3,
}

impl SurfacePoint {
    /// A point whose shading and geometric normals coincide.
    pub fn flat(position: Vec3, normal: Vec3) -> Self {
        SurfacePoint { position, normal, geometric: normal }
    }
}

/// One texel: coverage bits and the points of its covered sub-positions (in bit order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Texel {
    pub coverage: u16,
    pub points: Vec<SurfacePoint>,
}

impl Texel {
    pub fn is_valid(&self) -> bool {
        self.coverage != 0
    }
}

/// A chart: a planar group of one mesh's triangles and its place in the atlas.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    pub mesh: usize,
    /// Triangle indices within the mesh.
    pub triangles: Vec<usize>,
    pub normal: Vec3,
    /// Plane axes (tangent, bitangent) and the plane coordinates of the chart's corner.
    pub axes: (Vec3, Vec3),
    pub origin: Vec2,
    /// Size in texels, padding included.
    pub size: (usize, usize),
    /// Top-left texel in the atlas.
    pub offset: (usize, usize),
    /// The mesh's own lightmap UVs (TEXCOORD_1) scaled into this chart (one chart per
    /// such mesh; `normal`/`axes`/`origin` unused).
    pub from_uv: bool,
}

/// A packed lightmap.
#[derive(Debug, Clone)]
pub struct Lightmap {
    pub width: usize,
    pub height: usize,
    pub texels_per_unit: f32,
    pub padding: usize,
    pub charts: Vec<Chart>,
    /// Row-major, `width × height`.
    pub texels: Vec<Texel>,
    /// Atlas UV (in texels) of every vertex of every triangle: `uv[mesh][tri]`.
    pub triangle_uv: Vec<Vec<[Vec2; 3]>>,
    /// Lightmapped meshes that had no lightmap UVs (charts were generated for them).
    pub generated_for: Vec<String>,
}

/// Layout errors.
#[derive(Debug, Clone, PartialEq)]
pub enum LayoutError {
    BadResolution(f32),
    TooLarge { width: usize, height: usize },
    NothingToBake,
}

impl std::fmt::Display for LayoutError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LayoutError::BadResolution(r) => write!(f, "texels per unit must be finite and > 0, not {r}"),
            LayoutError::TooLarge { width, height } => {
                write!(f, "the lightmap would be {width}×{height} texels (limit 8192 per side): lower the resolution")
            }
            LayoutError::NothingToBake => write!(f, "no lightmapped mesh has a non-degenerate triangle"),
        }
    }
}

impl std::error::Error for LayoutError {}

impl Lightmap {
    /// Number of valid texels.
    pub fn valid_count(&self) -> usize {
        self.texels.iter().filter(|t| t.is_valid()).count()
    }
    /// Valid texels / atlas texels.
    pub fn utilisation(&self) -> f64 {
        self.valid_count() as f64 / (self.width * self.height) as f64
    }

    /// Lays out every lightmapped mesh of `scene` at `texels_per_unit` with `padding`.
    /// A mesh with its own lightmap UVs becomes one square chart of side
    /// ⌈√(surface area / UV area)·texels_per_unit⌉ (so the texel density matches) holding
    /// its UV square; other meshes get generated planar charts (listed in `generated_for`).
    pub fn build(scene: &Scene, texels_per_unit: f32, padding: usize) -> Result<Lightmap, LayoutError> {
        if !(texels_per_unit.is_finite() && texels_per_unit > 0.0) {
            return Err(LayoutError::BadResolution(texels_per_unit));
        }
        let mut charts = Vec::new();
        let mut generated_for = Vec::new();
        for (mi, m) in scene.meshes.iter().enumerate().filter(|(_, m)| m.lightmapped) {
            if let Some(uv) = &m.lightmap_uv {
                let (mut area, mut uv_area) = (0.0f64, 0.0f64);
                for t in &m.indices {
                    let [a, b, c] = t.map(|i| m.positions[i as usize]);
                    area += 0.5 * (b - a).cross(c - a).length() as f64;
                    let [p, q, r] = t.map(|i| uv[i as usize]);
                    uv_area += 0.5 * cross2(q - p, r - p).abs() as f64;
                }
                if area <= 0.0 {
                    continue;
                }
                let side = if uv_area > 0.0 { ((area / uv_area).sqrt() * texels_per_unit as f64).ceil() as usize } else { 1 }.max(1);
                charts.push(Chart {
                    mesh: mi,
                    triangles: (0..m.indices.len()).collect(),
                    normal: Vec3::Z,
                    axes: (Vec3::X, Vec3::Y),
                    origin: Vec2::ZERO,
                    size: (side + 2 * padding, side + 2 * padding),
                    offset: (0, 0),
                    from_uv: true,
                });
                continue;
            }
            generated_for.push(m.name.clone());
            // Group by plane: key = quantised (normal, offset).
            let mut groups: Vec<(Vec3, f32, Vec<usize>)> = Vec::new();
            for (ti, t) in m.indices.iter().enumerate() {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                let n = (b - a).cross(c - a);
                if n.length() <= 0.0 {
                    continue; // degenerate: no texels
                }
                let n = n.normalize();
                let d = n.dot(a);
                match groups.iter_mut().find(|(gn, gd, _)| gn.dot(n) > 1.0 - 1e-4 && (gd - d).abs() < 1e-4) {
                    Some(g) => g.2.push(ti),
                    None => groups.push((n, d, vec![ti])),
                }
            }
            for (n, _, tris) in groups {
                let (t, b) = frame(n);
                let mut lo = Vec2::splat(f32::INFINITY);
                let mut hi = Vec2::splat(f32::NEG_INFINITY);
                for &ti in &tris {
                    for &i in &m.indices[ti] {
                        let p = m.positions[i as usize];
                        let q = Vec2::new(p.dot(t), p.dot(b));
                        lo = lo.min(q);
                        hi = hi.max(q);
                    }
                }
                let ext = (hi - lo) * texels_per_unit;
                let size = ((ext.x.ceil() as usize).max(1) + 2 * padding, (ext.y.ceil() as usize).max(1) + 2 * padding);
                charts.push(Chart { mesh: mi, triangles: tris, normal: n, axes: (t, b), origin: lo, size, offset: (0, 0), from_uv: false });
            }
        }
        if charts.is_empty() {
            return Err(LayoutError::NothingToBake);
        }
        let (width, height) = pack(&mut charts);
        if width > 8192 || height > 8192 {
            return Err(LayoutError::TooLarge { width, height });
        }
        let mut texels = vec![Texel::default(); width * height];
        let mut triangle_uv: Vec<Vec<[Vec2; 3]>> = scene.meshes.iter().map(|m| vec![[Vec2::ZERO; 3]; m.indices.len()]).collect();
        for c in &charts {
            let m = &scene.meshes[c.mesh];
            let to_atlas = |p: Vec3| {
                let q = Vec2::new(p.dot(c.axes.0), p.dot(c.axes.1));
                (q - c.origin) * texels_per_unit + Vec2::new((c.offset.0 + padding) as f32, (c.offset.1 + padding) as f32)
            };
            let corner = Vec2::new((c.offset.0 + padding) as f32, (c.offset.1 + padding) as f32);
            let side = (c.size.0 - 2 * padding) as f32;
            for &ti in &c.triangles {
                let p = m.indices[ti].map(|i| m.positions[i as usize]);
                let n = (p[1] - p[0]).cross(p[2] - p[0]);
                if n.length() <= 0.0 {
                    continue; // degenerate: no texels
                }
                let normal = n.normalize();
                let uv = match (&m.lightmap_uv, c.from_uv) {
                    (Some(uvs), true) => m.indices[ti].map(|i| corner + uvs[i as usize] * side),
                    _ => p.map(to_atlas),
                };
                triangle_uv[c.mesh][ti] = uv;
                let vn = m.indices[ti].map(|i| m.normals[i as usize]);
                rasterise(&mut texels, width, uv, p, normal, vn);
            }
        }
        Ok(Lightmap { width, height, texels_per_unit, padding, charts, texels, triangle_uv, generated_for })
    }
}

/// Duff et al.'s orthonormal frame as f32 (see `sbf::basis::ambient_dice_bezier::tangent_frame`).
pub fn frame(n: Vec3) -> (Vec3, Vec3) {
    let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(n.as_dvec3());
    (t.as_vec3(), b.as_vec3())
}

/// Shelf packing; returns the atlas size. Width: the square root of the total chart area
/// (10% slack), at least the widest chart, rounded up to a multiple of 4.
fn pack(charts: &mut [Chart]) -> (usize, usize) {
    let area: usize = charts.iter().map(|c| c.size.0 * c.size.1).sum();
    let widest = charts.iter().map(|c| c.size.0).max().unwrap_or(1);
    let width = (((area as f64 * 1.1).sqrt().ceil() as usize).max(widest)).div_ceil(4) * 4;
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by(|&a, &b| charts[b].size.1.cmp(&charts[a].size.1).then(a.cmp(&b)));
    let (mut x, mut y, mut row_h) = (0, 0, 0);
    for k in order {
        let (w, h) = charts[k].size;
        if x + w > width {
            x = 0;
            y += row_h;
            row_h = 0;
        }
        charts[k].offset = (x, y);
        x += w;
        row_h = row_h.max(h);
    }
    (width, (y + row_h).div_ceil(4) * 4)
}

/// The shading normal at barycentrics (w0, w1, w2): interpolated vertex normals, or the
/// face normal `ng` where they cancel or turn more than 90° away from it.
pub fn shading_normal(vn: [Vec3; 3], w: [f32; 3], ng: Vec3) -> Vec3 {
    let n = vn[0] * w[0] + vn[1] * w[1] + vn[2] * w[2];
    match n.try_normalize() {
        Some(n) if n.dot(ng) > 0.0 => n,
        _ => ng,
    }
}

/// Marks the sub-positions of the texels under triangle `uv` (atlas texel coordinates)
/// and records their surface points (face normal `normal`, vertex normals `vn`).
fn rasterise(texels: &mut [Texel], width: usize, uv: [Vec2; 3], p: [Vec3; 3], normal: Vec3, vn: [Vec3; 3]) {
    let lo = uv[0].min(uv[1]).min(uv[2]).floor().max(Vec2::ZERO);
    let hi = uv[0].max(uv[1]).max(uv[2]).ceil();
    let height = texels.len() / width;
    let area = cross2(uv[1] - uv[0], uv[2] - uv[0]);
    if area == 0.0 {
        return;
    }
    for ty in lo.y as usize..(hi.y as usize).min(height) {
        for tx in lo.x as usize..(hi.x as usize).min(width) {
            let texel = &mut texels[ty * width + tx];
            for s in 0..SUBSAMPLES {
                if texel.coverage & (1 << s) != 0 {
                    continue; // first triangle wins
                }
                let q = Vec2::new(tx as f32 + ((s % 4) as f32 + 0.5) / 4.0, ty as f32 + ((s / 4) as f32 + 0.5) / 4.0);
                let w1 = cross2(q - uv[0], uv[2] - uv[0]) / area;
                let w2 = cross2(uv[1] - uv[0], q - uv[0]) / area;
                let w0 = 1.0 - w1 - w2;
                // Inclusive by 1e-6 so that shared edges leave no gaps.
                if w0 < -1e-6 || w1 < -1e-6 || w2 < -1e-6 {
                    continue;
                }
                let position = p[0] * w0 + p[1] * w1 + p[2] * w2;
                texel.coverage |= 1 << s;
                // Keep `points` in bit order.
                let before = (texel.coverage & ((1u16 << s) - 1)).count_ones() as usize;
                let shading = shading_normal(vn, [w0, w1, w2], normal);
                texel.points.insert(before, SurfacePoint { position, normal: shading, geometric: normal });
            }
        }
    }
}

fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}
