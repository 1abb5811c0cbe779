//! Lightmap layout: charts, packing, and per-texel sample points ([Roughton19 ch. 4]).
//!
//! Charts: a mesh with its own lightmap UVs (glTF TEXCOORD_1) becomes one square chart
//! holding its UV square at the requested texel density. The other lightmapped meshes
//! are unwrapped together by the `uvunwrap` crate (pure Rust, after xatlas): faces
//! grouped by region growing within a normal cone ([`MAX_CHART_ANGLE`]), each chart
//! flattened by planar projection when flat or least-squares conformal maps otherwise,
//! charts with flipped triangles, overlaps or area distortion beyond
//! [`MAX_AREA_DISTORTION`] split and retried, then shape-packed at the requested texel
//! density into one block (ARCHITECTURE.md says why this crate). Packing of the blocks:
//! a shelf packer (sorted by height, rows left to right) with `padding` texels around
//! every chart; the measured utilisation is reported.
//! Coverage (§4.2): every texel has 16 fixed sub-texel sample positions (a 4 × 4 grid);
//! the bits of a `u16` say which lie on a triangle, and each covered position stores the
//! surface point it maps to. A texel is valid when any bit is set.

use super::digest::point_term;
use super::tiles::item_order;
use crate::scene::geometry::shading_normal;
use crate::scene::Scene;
use sbf::glam::{Vec2, Vec3};

/// Sub-texel positions per texel (4 × 4).
pub const SUBSAMPLES: usize = 16;

/// Largest angle (degrees) between a face normal and its generated chart's mean normal.
pub const MAX_CHART_ANGLE: f32 = 60.0;

/// Largest ratio of a triangle's share of its chart's UV area to its share of the
/// surface area (either way) before a generated chart is split.
pub const MAX_AREA_DISTORTION: f32 = 2.0;

/// [`Lightmap::texel_charts`] of a texel no triangle overlaps.
pub const NO_CHART: u32 = u32::MAX;

/// How far (texels) a triangle must reach into a texel's square along every separating
/// axis to touch it: edges that merely graze a texel's border do not claim it.
pub const TOUCH_EPSILON: f32 = 1e-3;

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

    /// Its position, shading and geometric normals.
    pub fn vectors(&self) -> [Vec3; 3] {
        [self.position, self.normal, self.geometric]
    }
}

/// The digest of a texel's points in bit order: the wrapping sum of their
/// [`point_term`]s — independent of the order the terms arrive in, so a rasteriser that
/// meets the points triangle by triangle sums it without keeping them
/// ([`Lightmap::build_part`]).
pub fn points_digest(points: &[SurfacePoint]) -> u64 {
    points.iter().enumerate().fold(0u64, |d, (r, p)| d.wrapping_add(point_term(r, p.vectors())))
}

/// One texel: coverage bits, the points of its covered sub-positions (in bit order),
/// and the chart its first covering triangle belongs to.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Texel {
    pub coverage: u16,
    pub points: Vec<SurfacePoint>,
    /// Index into [`Lightmap::chart_meshes`] (meaningful when valid).
    pub chart: u32,
}

impl Texel {
    pub fn is_valid(&self) -> bool {
        self.coverage != 0
    }
}

/// A packed block of the atlas: the bounding rectangle of one TEXCOORD_1 mesh's UVs, or
/// the block of generated charts.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// The mesh whose own UVs fill the block; None for the generated block.
    pub mesh: Option<usize>,
    /// TEXCOORD_1 blocks: the smallest UV of the mesh and the texels per UV unit
    /// (atlas texel = offset + padding + (uv − uv_min)·uv_scale).
    pub uv_min: Vec2,
    pub uv_scale: f32,
    /// Size in texels, padding included.
    pub size: (usize, usize),
    /// Top-left texel in the atlas.
    pub offset: (usize, usize),
}

/// A packed lightmap.
#[derive(Debug, Clone)]
pub struct Lightmap {
    pub width: usize,
    pub height: usize,
    pub texels_per_unit: f32,
    pub padding: usize,
    /// The packed blocks.
    pub charts: Vec<Chart>,
    /// Row-major, `width × height`.
    pub texels: Vec<Texel>,
    /// Atlas UV (in texels) of every vertex of every triangle: `uv[mesh][tri]`.
    pub triangle_uv: Vec<Vec<[Vec2; 3]>>,
    /// Lightmapped meshes that had no lightmap UVs (charts were generated for them).
    pub generated_for: Vec<String>,
    /// The mesh of every chart (TEXCOORD_1 squares and generated charts), by the id
    /// stored in [`Texel::chart`].
    pub chart_meshes: Vec<usize>,
    /// Per texel (row-major), the chart its filtered gather belongs to ([Roughton19 §3.2]:
    /// texels a chart's triangles overlap but whose 16 sub-positions all miss): a valid
    /// texel's [`Texel::chart`]; an uncovered texel that some triangle overlaps by more
    /// than [`TOUCH_EPSILON`], the first such triangle's chart; [`NO_CHART`] otherwise.
    pub texel_charts: Vec<u32>,
    /// Per texel (row-major), the digest of its surface points
    /// ([`points_digest`]; 0 for an uncovered texel).
    pub digests: Vec<u64>,
    /// Built by [`Lightmap::build_part`]: only the kept texels hold their points.
    pub partial: bool,
    /// Generated charts: how many, and the generated block's own utilisation.
    pub generated_charts: usize,
    pub generated_utilisation: f64,
}

/// Layout errors.
#[derive(Debug, Clone, PartialEq)]
pub enum LayoutError {
    BadResolution(f32),
    TooLarge { width: usize, height: usize, fits: f32 },
    NothingToBake,
    Unwrap(String),
}

impl std::fmt::Display for LayoutError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LayoutError::BadResolution(r) => write!(f, "texels per unit must be finite and > 0, not {r}"),
            LayoutError::TooLarge { width, height, fits } => write!(
                f,
                "the lightmap would be {width}×{height} texels (limit 8192 per side): lower the resolution (about --texels-per-unit {fits:.3} fits; check the scene's units)"
            ),
            LayoutError::NothingToBake => write!(f, "no lightmapped mesh has a non-degenerate triangle"),
            LayoutError::Unwrap(e) => write!(f, "generating lightmap charts: {e}"),
        }
    }
}

impl std::error::Error for LayoutError {}

/// Side limit of the atlas (texels).
const MAX_SIDE: usize = 8192;

/// The texel density at which an atlas of `side` texels at `tpu` would shrink to 90% of
/// the side limit (a suggestion for the error message; padding makes it approximate).
fn too_large_fit(tpu: f32, side: f64) -> f32 {
    (tpu as f64 * 0.9 * MAX_SIDE as f64 / side.max(1.0)) as f32
}

impl Lightmap {
    /// Number of valid texels.
    pub fn valid_count(&self) -> usize {
        self.texels.iter().filter(|t| t.is_valid()).count()
    }
    /// Valid texels / atlas texels.
    pub fn utilisation(&self) -> f64 {
        self.valid_count() as f64 / (self.width * self.height) as f64
    }

    /// The charts, their packing, every triangle's atlas UVs and the texel charts: all of
    /// a layout but its texels; with the triangles to rasterise, in order.
    fn plan(scene: &Scene, texels_per_unit: f32, padding: usize) -> Result<(Lightmap, Vec<Placed>), LayoutError> {
        if !(texels_per_unit.is_finite() && texels_per_unit > 0.0) {
            return Err(LayoutError::BadResolution(texels_per_unit));
        }
        let mut charts = Vec::new();
        let mut generated_for = Vec::new();
        let mut gen_meshes = Vec::new();
        for (mi, m) in scene.meshes.iter().enumerate().filter(|(_, m)| m.lightmapped) {
            let (mut area, mut uv_area) = (0.0f64, 0.0f64);
            for t in &m.indices {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                area += 0.5 * (b - a).cross(c - a).length() as f64;
                if let Some(uv) = &m.lightmap_uv {
                    let [p, q, r] = t.map(|i| uv[i as usize]);
                    uv_area += 0.5 * cross2(q - p, r - p).abs() as f64;
                }
            }
            if area <= 0.0 {
                continue;
            }
            if let Some(uv) = &m.lightmap_uv {
                let scale = if uv_area > 0.0 { (area / uv_area).sqrt() * texels_per_unit as f64 } else { 1.0 };
                let (lo, hi) =
                    uv.iter().fold((Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)), |(a, b), p| (a.min(*p), b.max(*p)));
                // Checked with the others' below; saturate so the product cannot overflow.
                let ext = |e: f32| ((e as f64 * scale).ceil().min(1e6) as usize).max(1) + 2 * padding;
                let uv_scale = scale.min(1e9) as f32;
                charts.push(Chart { mesh: Some(mi), uv_min: lo, uv_scale, size: (ext(hi.x - lo.x), ext(hi.y - lo.y)), offset: (0, 0) });
            } else {
                generated_for.push(m.name.clone());
                gen_meshes.push(mi);
            }
        }
        // Generated charts: one uvunwrap block (its own padding inside, `padding` texels
        // around and between charts), per-triangle UVs in block texels.
        let generated = generate_charts(scene, &gen_meshes, texels_per_unit, padding)?;
        let (generated_charts, generated_utilisation) = generated.as_ref().map_or((0, 0.0), |g| (g.charts, g.utilisation));
        if let Some(g) = &generated {
            charts.push(Chart { mesh: None, uv_min: Vec2::ZERO, uv_scale: 0.0, size: g.size, offset: (0, 0) });
        }
        let (gen_uv, gen_chart_ids) = generated.map_or((Vec::new(), Vec::new()), |g| (g.uv, g.chart_ids));
        if charts.is_empty() {
            return Err(LayoutError::NothingToBake);
        }
        // The blocks cannot fit one atlas if their area alone exceeds it.
        let total: f64 = charts.iter().map(|c| (c.size.0 * c.size.1) as f64).sum();
        if total > (MAX_SIDE * MAX_SIDE) as f64 {
            let side = total.sqrt();
            return Err(LayoutError::TooLarge { width: side as usize, height: side as usize, fits: too_large_fit(texels_per_unit, side) });
        }
        let (width, height) = pack(&mut charts);
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(LayoutError::TooLarge { width, height, fits: too_large_fit(texels_per_unit, width.max(height) as f64) });
        }
        let mut texel_charts = vec![NO_CHART; width * height];
        let mut triangle_uv: Vec<Vec<[Vec2; 3]>> = scene.meshes.iter().map(|m| vec![[Vec2::ZERO; 3]; m.indices.len()]).collect();
        // Chart ids: TEXCOORD_1 squares first (in block order), then the generated charts.
        let mut chart_meshes: Vec<usize> = charts.iter().filter_map(|c| c.mesh).collect();
        let first_generated = chart_meshes.len() as u32;
        chart_meshes.extend(std::iter::repeat_n(usize::MAX, generated_charts));
        let (mut own, mut placed) = (0u32, Vec::new());
        for c in &charts {
            let corner = Vec2::new((c.offset.0 + padding) as f32, (c.offset.1 + padding) as f32);
            match c.mesh {
                Some(mi) => {
                    let m = &scene.meshes[mi];
                    let uvs = m.lightmap_uv.as_ref().expect("TEXCOORD_1 chart");
                    for (ti, t) in m.indices.iter().enumerate() {
                        let uv = t.map(|i| corner + (uvs[i as usize] - c.uv_min) * c.uv_scale);
                        triangle_uv[mi][ti] = uv;
                        placed.push(Placed { mesh: mi, tri: ti, uv, chart: own });
                    }
                    own += 1;
                }
                None => {
                    let block = Vec2::new(c.offset.0 as f32, c.offset.1 as f32);
                    for (g, mi) in gen_meshes.iter().enumerate() {
                        for ti in 0..scene.meshes[*mi].indices.len() {
                            let uv = gen_uv[g][ti].map(|p| p + block);
                            triangle_uv[*mi][ti] = uv;
                            let id = gen_chart_ids[g][ti];
                            if id == u32::MAX {
                                continue; // degenerate: no chart, no texels
                            }
                            chart_meshes[(first_generated + id) as usize] = *mi;
                            placed.push(Placed { mesh: *mi, tri: ti, uv, chart: first_generated + id });
                        }
                    }
                }
            }
        }
        // Degenerate triangles (no area in space or in the atlas) cover nothing.
        placed.retain(|t| {
            let m = &scene.meshes[t.mesh];
            let p = m.indices[t.tri].map(|i| m.positions[i as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]).length() > 0.0 && cross2(t.uv[1] - t.uv[0], t.uv[2] - t.uv[0]) != 0.0
        });
        for t in &placed {
            touch(&mut texel_charts, width, t.uv, t.chart);
        }
        let lm = Lightmap {
            width,
            height,
            texels_per_unit,
            padding,
            charts,
            texels: Vec::new(),
            triangle_uv,
            generated_for,
            chart_meshes,
            texel_charts,
            digests: Vec::new(),
            partial: false,
            generated_charts,
            generated_utilisation,
        };
        Ok((lm, placed))
    }

    /// Lays out every lightmapped mesh of `scene` at `texels_per_unit` with `padding`.
    /// A mesh with its own lightmap UVs becomes one block holding the bounding rectangle
    /// of its UVs at √(surface area / UV area)·texels_per_unit texels per UV unit (so the
    /// texel density matches; meshes that share an authored atlas each use their own
    /// part); the other meshes get generated charts (listed in `generated_for`).
    pub fn build(scene: &Scene, texels_per_unit: f32, padding: usize) -> Result<Lightmap, LayoutError> {
        let (mut lm, placed) = Lightmap::plan(scene, texels_per_unit, padding)?;
        let mut texels = vec![Texel::default(); lm.width * lm.height];
        for t in &placed {
            rasterise_triangle(&mut texels, lm.width, scene, t, &mut |texel, _, s, point| {
                // Keep `points` in bit order.
                let before = (texel.coverage & ((1u16 << s) - 1)).count_ones() as usize;
                texel.points.insert(before, point);
            });
        }
        lm.digests = texels.iter().map(|t| points_digest(&t.points)).collect();
        lm.texels = texels;
        lm.claim_covered();
        Ok(lm)
    }

    /// [`Lightmap::build`] for one part of a bake spread over machines: the whole atlas —
    /// charts, coverage, texel charts, every texel's point digest — but the surface points
    /// of only the valid texels `keep(item, items)` selects, `item` being the texel's place
    /// in [`Lightmap::item_order`] of `items`. It rasterises twice (coverage first: the
    /// item order needs every texel's validity; then the points, summed into the digests
    /// as they come and kept where selected), so the others' points are never held: a
    /// part's layout memory follows its share, plus a few bytes per atlas texel. The kept
    /// texels, coverage, charts and digests equal [`Lightmap::build`]'s.
    pub fn build_part(
        scene: &Scene,
        texels_per_unit: f32,
        padding: usize,
        keep: &dyn Fn(usize, usize) -> bool,
    ) -> Result<Lightmap, LayoutError> {
        let (mut lm, placed) = Lightmap::plan(scene, texels_per_unit, padding)?;
        let n = lm.width * lm.height;
        let mut texels = vec![Texel::default(); n];
        for t in &placed {
            rasterise_triangle(&mut texels, lm.width, scene, t, &mut |_, _, _, _| {});
        }
        let coverage: Vec<u16> = texels.iter().map(|t| t.coverage).collect();
        let order = item_order(lm.width, n, |k| coverage[k] != 0);
        let mut kept = vec![false; n];
        for (i, k) in order.iter().enumerate() {
            kept[*k] = keep(i, order.len());
        }
        drop(order);
        texels.iter_mut().for_each(|t| *t = Texel::default());
        let mut digests = vec![0u64; n];
        for t in &placed {
            rasterise_triangle(&mut texels, lm.width, scene, t, &mut |texel, k, s, point| {
                let below = (1u16 << s) - 1;
                // The point's rank among the texel's final points (coverage known from the first pass).
                digests[k] = digests[k].wrapping_add(point_term((coverage[k] & below).count_ones() as usize, point.vectors()));
                if kept[k] {
                    texel.points.insert((texel.coverage & below).count_ones() as usize, point);
                }
            });
        }
        (lm.texels, lm.digests, lm.partial) = (texels, digests, true);
        lm.claim_covered();
        Ok(lm)
    }

    /// A covered texel gathers within the chart of its first covering triangle.
    fn claim_covered(&mut self) {
        for (c, t) in self.texel_charts.iter_mut().zip(&self.texels) {
            if t.is_valid() {
                *c = t.chart;
            }
        }
    }

    /// The valid texels in a bake's item order ([`item_order`]: 8 × 8 tiles).
    pub fn item_order(&self) -> Vec<usize> {
        item_order(self.width, self.texels.len(), |k| self.texels[k].is_valid())
    }
}

/// A triangle placed in the atlas: its mesh and index, its atlas UVs (texels) and chart.
struct Placed {
    mesh: usize,
    tri: usize,
    uv: [Vec2; 3],
    chart: u32,
}

/// Charts generated by `uvunwrap` for lightmapped meshes without lightmap UVs: one block.
struct Generated {
    /// Per mesh, per triangle: the UVs in block texels.
    uv: Vec<Vec<[Vec2; 3]>>,
    /// Per mesh, per triangle: its chart (u32::MAX for a degenerate triangle).
    chart_ids: Vec<Vec<u32>>,
    charts: usize,
    utilisation: f64,
    size: (usize, usize),
}

/// Unwraps `meshes` of `scene` together at `texels_per_unit` (None when there are none),
/// refusing an atlas that cannot fit before unwrapping it.
fn generate_charts(scene: &Scene, meshes: &[usize], texels_per_unit: f32, padding: usize) -> Result<Option<Generated>, LayoutError> {
    if meshes.is_empty() {
        return Ok(None);
    }
    let (mut gen_uv, mut gen_chart_ids) = (Vec::new(), Vec::new());
    // A surface needs area·tpu² texels: refuse before unwrapping an atlas that
    // cannot fit (a mutated scene may declare kilometres at 16 texels/unit).
    let area: f64 = meshes
        .iter()
        .flat_map(|mi| scene.meshes[*mi].indices.iter().map(move |t| t.map(|i| scene.meshes[*mi].positions[i as usize])))
        .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).length() as f64)
        .sum();
    let texels = area * (texels_per_unit as f64).powi(2);
    if texels > (MAX_SIDE * MAX_SIDE) as f64 {
        let side = texels.sqrt();
        return Err(LayoutError::TooLarge { width: side as usize, height: side as usize, fits: too_large_fit(texels_per_unit, side) });
    }
    let pos: Vec<Vec<[f32; 3]>> = meshes.iter().map(|mi| scene.meshes[*mi].positions.iter().map(|p| p.to_array()).collect()).collect();
    let idx: Vec<Vec<u32>> = meshes.iter().map(|mi| scene.meshes[*mi].indices.iter().flatten().copied().collect()).collect();
    let inputs: Vec<uvunwrap::MeshInput> = pos.iter().zip(&idx).map(|(p, i)| uvunwrap::MeshInput::new(p, i)).collect();
    let opts = uvunwrap::Options {
        max_chart_angle: MAX_CHART_ANGLE,
        max_area_distortion: MAX_AREA_DISTORTION,
        density: uvunwrap::Density::Fixed { texels_per_unit, page_size: None },
        padding: padding as u32,
        ..Default::default()
    };
    let atlas = uvunwrap::generate(&inputs, &opts).map_err(|e| LayoutError::Unwrap(e.to_string()))?;
    let (w, h) = (atlas.width as usize, atlas.height as usize);
    if w > MAX_SIDE || h > MAX_SIDE || atlas.page_count != 1 {
        return Err(LayoutError::TooLarge { width: w, height: h, fits: too_large_fit(texels_per_unit, w.max(h) as f64) });
    }
    for out in &atlas.meshes {
        let uv = |k: usize| {
            let v = &out.vertices[out.indices[k] as usize];
            Vec2::new(v.uv[0] * w as f32, v.uv[1] * h as f32)
        };
        let chart = |k: usize| out.vertices[out.indices[k] as usize].chart.unwrap_or(u32::MAX);
        gen_uv.push((0..out.indices.len() / 3).map(|t| [uv(3 * t), uv(3 * t + 1), uv(3 * t + 2)]).collect());
        gen_chart_ids.push((0..out.indices.len() / 3).map(|t| chart(3 * t).min(chart(3 * t + 1)).min(chart(3 * t + 2))).collect());
    }

    Ok(Some(Generated {
        uv: gen_uv,
        chart_ids: gen_chart_ids,
        charts: atlas.chart_count as usize,
        utilisation: atlas.utilization as f64,
        size: (w, h),
    }))
}

/// What the rasteriser hands on for each sub-position a triangle newly covers: the
/// texel (its coverage and chart already updated), its row-major index, the sub-position
/// and the surface point there.
type Emit<'a> = dyn FnMut(&mut Texel, usize, usize, SurfacePoint) + 'a;

/// Rasterises the placed triangle `t` (non-degenerate).
fn rasterise_triangle(texels: &mut [Texel], width: usize, scene: &Scene, t: &Placed, emit: &mut Emit) {
    let m = &scene.meshes[t.mesh];
    let p = m.indices[t.tri].map(|i| m.positions[i as usize]);
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let vn = m.indices[t.tri].map(|i| m.normals[i as usize]);
    rasterise(texels, width, t.uv, p, n.normalize(), vn, t.chart, emit);
}

/// Shelf packing; returns the atlas size (multiples of 4). Charts sorted by height fill
/// rows left to right; the row width is chosen among the widest chart and √(total area)
/// × {1, 1.1, 1.25, 1.5} as the one giving the smallest atlas.
fn pack(charts: &mut [Chart]) -> (usize, usize) {
    let area: usize = charts.iter().map(|c| c.size.0 * c.size.1).sum();
    let widest = charts.iter().map(|c| c.size.0).max().unwrap_or(1);
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by(|&a, &b| charts[b].size.1.cmp(&charts[a].size.1).then(a.cmp(&b)));
    let shelf = |width: usize, charts: &mut [Chart], place: bool| -> usize {
        let (mut x, mut y, mut row_h) = (0, 0, 0);
        for &k in &order {
            let (w, h) = charts[k].size;
            if x + w > width {
                x = 0;
                y += row_h;
                row_h = 0;
            }
            if place {
                charts[k].offset = (x, y);
            }
            x += w;
            row_h = row_h.max(h);
        }
        (y + row_h).div_ceil(4) * 4
    };
    let candidates = [1.0, 1.1, 1.25, 1.5].map(|f| ((area as f64 * f).sqrt().ceil() as usize).max(widest).div_ceil(4) * 4);
    let widest4 = widest.div_ceil(4) * 4;
    let width = std::iter::once(widest4).chain(candidates).min_by_key(|w| (w * shelf(*w, charts, false), *w)).expect("candidates");
    let height = shelf(width, charts, true);
    (width, height)
}

/// Marks the sub-positions of the texels under triangle `uv` (atlas texel coordinates)
/// and hands on their surface points (face normal `normal`, vertex normals `vn`).
#[allow(clippy::too_many_arguments)]
fn rasterise(texels: &mut [Texel], width: usize, uv: [Vec2; 3], p: [Vec3; 3], normal: Vec3, vn: [Vec3; 3], chart: u32, emit: &mut Emit) {
    let lo = uv[0].min(uv[1]).min(uv[2]).floor().max(Vec2::ZERO);
    let hi = uv[0].max(uv[1]).max(uv[2]).ceil();
    let height = texels.len() / width;
    let area = cross2(uv[1] - uv[0], uv[2] - uv[0]);
    if area == 0.0 {
        return;
    }
    for ty in lo.y as usize..(hi.y as usize).min(height) {
        for tx in lo.x as usize..(hi.x as usize).min(width) {
            let k = ty * width + tx;
            let texel = &mut texels[k];
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
                if texel.coverage == 0 {
                    texel.chart = chart;
                }
                texel.coverage |= 1 << s;
                let shading = shading_normal(vn, [w0, w1, w2], normal);
                emit(texel, k, s, SurfacePoint { position, normal: shading, geometric: normal });
            }
        }
    }
}

/// Claims for `chart` every still unclaimed texel whose square the triangle `uv` overlaps
/// (separating-axis test on the square's two axes and the triangle's three edge normals,
/// each overlap deeper than [`TOUCH_EPSILON`]).
fn touch(texel_charts: &mut [u32], width: usize, uv: [Vec2; 3], chart: u32) {
    let lo = uv[0].min(uv[1]).min(uv[2]).floor().max(Vec2::ZERO);
    let hi = uv[0].max(uv[1]).max(uv[2]).ceil();
    let height = texel_charts.len() / width;
    let axes = [0, 1, 2].map(|k| {
        let e = uv[(k + 1) % 3] - uv[k];
        Vec2::new(-e.y, e.x)
    });
    for ty in lo.y as usize..(hi.y as usize).min(height) {
        for tx in lo.x as usize..(hi.x as usize).min(width) {
            let c = &mut texel_charts[ty * width + tx];
            if *c != NO_CHART {
                continue;
            }
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(a, b)| Vec2::new(tx as f32 + a, ty as f32 + b));
            let separated = |axis: Vec2| {
                let len = axis.length();
                if len == 0.0 {
                    return false;
                }
                let range = |pts: &mut dyn Iterator<Item = Vec2>| {
                    pts.map(|q| q.dot(axis) / len).fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
                };
                let (t0, t1) = range(&mut uv.iter().copied());
                let (s0, s1) = range(&mut corners.iter().copied());
                t1.min(s1) - t0.max(s0) <= TOUCH_EPSILON
            };
            if !separated(Vec2::X) && !separated(Vec2::Y) && !axes.iter().any(|a| separated(*a)) {
                *c = chart;
            }
        }
    }
}

fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}
