//! First-bounce ray guiding for lightmap texels (\[HWRTL\], "First Bounce Ray Guiding",
//! after Call of Duty's "ray guiding" and Unreal GPULM).
//!
//! **Clusters.** Texels share one learned distribution per cluster: an 8×8 tile of the
//! atlas ([`TILE`]), split by chart and by normal — a texel joins the first cluster of
//! its tile and chart whose first normal is within 25° ([`CLUSTER_COS`]) and on the same
//! side of the z = 0 plane (the tangent frame, Duff et al., flips there), else starts a
//! new one. Directions are binned in each texel's own tangent frame, so texels of one
//! cluster see the same directions in the same bins.
//!
//! **Bins.** The hemisphere is the unit square through the equal-area concentric map
//! (`sbf::sampling::uniform_hemisphere_concentric`): 16×16 bins ([`BINS`]) of equal solid
//! angle 2π/256.
//!
//! **Learning.** During the first `learn_passes` passes the point samples are uniform
//! (pdf 1/2π). Every pass — these and all later ones — adds to its cluster's bins each
//! texel's estimates of (1/2π)·∫_bin L cosθ, the irradiance integrand: the point
//! sample's lum(L)·cosθ·(1/2π)/p (L MIS-weighted; importance-weighted so guided samples
//! estimate the same as uniform ones) and each area-light sample's lum(L·w/p_l)·cosθ/2π
//! (the environment and emitter samples of next-event estimation, MIS-weighted: together
//! with the point sample an MIS estimate of the bin's integral; delta lights cannot be
//! reached by any direction and are left out). Up to three values per texel and pass,
//! gathered per cluster in item order, so the sums are deterministic on the GPU too. The
//! learning samples are ordinary unguided samples with their correct pdf and are **kept**
//! in the estimate: nothing is wasted.
//!
//! **Stages** (iterative refinement with doubling, as in Müller et al.'s practical path
//! guiding): the distribution is built from all sums at the start of pass L (L =
//! `learn_passes`) and rebuilt at passes 2L, 4L, 8L, … ([`stage`]). Each stage draws all
//! its numbers — the texels' points, their light samples, the paths — from its own
//! scrambled Sobol' sequences (a per-stage seed, [`crate::sampling::sequence::PathSampler::staged`]),
//! numbered from the stage's first pass. (Staging only the point sample's direction left
//! the light samples at the baked point continuing one sequence across stages; their MIS
//! weights use the learned pdf, and a chart of the built-in scene came out 3.8σ off.) That independence is what keeps the estimate unbiased: a
//! quasi-random point is predictable from the earlier points of its own sequence (it
//! falls in their gaps), and a distribution learned from those earlier points is lower
//! exactly there — a texel's samples would be weighted up where it had not looked yet
//! (+0.3% on the furnace when the distribution was rebuilt every pass from one sequence).
//! With a fresh seed per stage, a stage's points are independent of everything its
//! distribution was built from.
//!
//! **Relaxation and CDF.** The sums are smoothed over the quadtree of the 16×16 grid
//! (Call of Duty's "hierarchical smoothing"): a bin's value becomes
//! ½·v₀ + ¼·v₁ + ⅛·v₂ + 1/16·v₃ + 1/16·v₄ where v_l is the mean of its ancestor at level l
//! (v₄ the cluster mean), which keeps the cluster total and leaves no bin empty unless the
//! cluster learned nothing (then the guided part is uniform). Per cluster the marginal
//! CDF over the 16 rows and the conditional CDF of each row are stored ([`CDF_LEN`] f32),
//! last entries exactly 1.
//!
//! **Sampling.** After learning, a point sample is drawn from the mixture
//! (1 − m)·uniform + m·guided ([`GUIDED_FRACTION`]): guided samples invert the CDFs
//! (row, then column, the stratified point warped inside the bin). The mixture pdf is
//! evaluated for every direction (the point sample's and the light samples' for MIS) from
//! the stored CDFs — the same f32 values the sampler compares, so the pdf is the sampling
//! probability exactly. The estimate divides by it; the basis encoders take the sample
//! with weight (1/2π)/p and the light samples' known projections scaled by p (see
//! [`crate::accumulate`]): unbiased by construction, whatever was learned.
//!
//! **On the GPU** (`wgsl/guide.wgsl` in the bake kernel, `guide_common.wgsl`,
//! `guide_build.wgsl`, `guide_build_subgroup.wgsl`): the bake pass writes the records, a
//! gather kernel adds them per cluster, and the CDFs are built one workgroup per cluster —
//! by subgroup prefix sums where every subgroup holds whole rows of 16 bins, else by serial
//! sums in workgroup memory ([`crate::gpu::GuideBuild`]); [`build_cluster`] is their twin.
//!
//! **Measured** (`examples/options_gain.rs`, H200): in the `slit` room E/π error 1.30× lower
//! at 128 passes and 1.46× at 512 at +13% time per pass; on the built-in scene 0.96× (the
//! light is mostly already found by next-event estimation) — so `--guiding` is off by default.

use crate::layout::lightmap::Lightmap;
use sbf::glam::DVec3;
use std::f64::consts::PI;

/// Atlas texels per cluster side.
pub const TILE: usize = 8;
/// Directional bins per side of the concentric square.
pub const BINS: usize = 16;
/// Bins per cluster.
pub const BIN_COUNT: usize = BINS * BINS;
/// f32 per cluster in the distribution: 256 conditional CDF entries (row-major) and 16
/// marginal ones.
pub const CDF_LEN: usize = BIN_COUNT + BINS;
/// Cosine of the largest angle between the normals of one cluster's texels (25°).
pub const CLUSTER_COS: f32 = 0.906_307_8;
/// Probability of drawing the point sample from the guided distribution after learning.
pub const GUIDED_FRACTION: f64 = 0.5;

/// The stage of pass `p` for `learn` learning passes: (index, first pass). Stage 0 is the
/// learning [0, L); stage k ≥ 1 is [L·2^(k−1), L·2^k).
pub fn stage(p: u64, learn: u64) -> (u32, u64) {
    if p < learn || learn == 0 {
        return (0, 0);
    }
    let k = 64 - (p / learn).leading_zeros();
    (k, learn << (k - 1))
}

/// Guiding settings of a bake.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuidingOptions {
    /// Uniform passes that learn the distribution; guiding starts after them.
    pub learn_passes: u64,
    /// Probability of the guided component of the mixture, in (0, 1].
    pub guided_fraction: f64,
}

impl GuidingOptions {
    /// The default for a `passes`-pass bake: learning for 1/16 of the passes, at least 4
    /// and at most 32 (stages then double from there). Measured on the `slit` scene at 128
    /// passes (CPU, `examples/options_gain.rs`, reference 4 096 passes): E/π RMS error
    /// 0.01634, 0.01621, 0.01613 and 0.01682 for 4, 8, 16 and 32 learning passes (the
    /// unguided bake 0.0207) — flat up to 16, worse at 32, which leaves fewer refinements.
    pub fn for_passes(passes: u64) -> Self {
        GuidingOptions { learn_passes: (passes / 16).clamp(4, 32), guided_fraction: GUIDED_FRACTION }
    }
    /// Checks the settings.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.guided_fraction > 0.0 && self.guided_fraction <= 1.0) {
            return Err(format!("guided fraction must be in (0, 1], not {}", self.guided_fraction));
        }
        if self.learn_passes == 0 {
            return Err("guiding needs at least one learning pass".into());
        }
        Ok(())
    }
}

/// The cluster of every valid texel in row-major texel order (which
/// [`crate::accumulate::Targets::lightmap`] maps to its tile-ordered items)
/// and the number of clusters.
pub fn clusters(lm: &Lightmap) -> (Vec<u32>, usize) {
    let tiles_x = lm.width.div_ceil(TILE);
    // Per tile: (chart, first normal, cluster id) of its clusters so far.
    let mut tiles: Vec<Vec<(u32, sbf::glam::Vec3, u32)>> = vec![Vec::new(); tiles_x * lm.height.div_ceil(TILE)];
    let mut of_item = Vec::new();
    let mut count = 0u32;
    for (k, t) in lm.texels.iter().enumerate() {
        if !t.is_valid() {
            continue;
        }
        let n = t.points.iter().map(|p| p.normal).sum::<sbf::glam::Vec3>().normalize_or_zero();
        let (x, y) = (k % lm.width, k / lm.width);
        let tile = &mut tiles[(y / TILE) * tiles_x + x / TILE];
        let found = tile.iter().find(|(c, m, _)| *c == t.chart && m.dot(n) >= CLUSTER_COS && (m.z >= 0.0) == (n.z >= 0.0));
        let id = match found {
            Some(c) => c.2,
            None => {
                tile.push((t.chart, n, count));
                count += 1;
                count - 1
            }
        };
        of_item.push(id);
    }
    (of_item, count as usize)
}

/// The bin of a tangent-space direction (z ≥ 0): index y·16 + x on the concentric square.
pub fn bin_of(local: DVec3) -> usize {
    let [u, v] = sbf::sampling::uniform_hemisphere_concentric_inv(local);
    let b = |t: f64| ((t * BINS as f64) as usize).min(BINS - 1);
    b(v) * BINS + b(u)
}

/// Adds a learning sample (tangent-space direction, luminance of L) to a cluster's sums.
pub fn record(sums: &mut [f32], cluster: u32, local: DVec3, luminance: f32) {
    let v = luminance * local.z.max(0.0) as f32;
    if v.is_finite() && v > 0.0 {
        sums[cluster as usize * BIN_COUNT + bin_of(local)] += v;
    }
}

/// Smoothed values and CDFs of one cluster from its 256 sums (the CPU twin of
/// `guide_build` in `wgsl/guide_build.wgsl`, same f32 operations in the same order).
pub fn build_cluster(sums: &[f32], out: &mut [f32]) {
    debug_assert_eq!((sums.len(), out.len()), (BIN_COUNT, CDF_LEN));
    // Quadtree means: level l has (16 >> l)² cells, stored one level after another.
    const OFFSET: [usize; 5] = [0, 256, 320, 336, 340];
    let mut lv = [0f32; 341];
    for (d, s) in lv.iter_mut().zip(sums) {
        *d = s.max(0.0);
    }
    for l in 1..5 {
        let (side, ps) = (BINS >> l, BINS >> (l - 1));
        for c in 0..side * side {
            let (x, y) = (c % side, c / side);
            let i = OFFSET[l - 1] + 2 * y * ps + 2 * x;
            lv[OFFSET[l] + c] = ((lv[i] + lv[i + 1]) + (lv[i + ps] + lv[i + ps + 1])) * 0.25;
        }
    }
    let total = lv[OFFSET[4]];
    let mut value = [1f32; BIN_COUNT];
    if total > 0.0 {
        for (b, v) in value.iter_mut().enumerate() {
            let (x, y) = (b % BINS, b / BINS);
            let at = |l: usize| lv[OFFSET[l] + (y >> l) * (BINS >> l) + (x >> l)];
            *v = 0.5 * at(0) + 0.25 * at(1) + 0.125 * at(2) + 0.0625 * at(3) + 0.0625 * at(4);
        }
    }
    // Conditional CDF per row, then the marginal over the row totals.
    let mut rows = [0f32; BINS];
    for y in 0..BINS {
        let row = &mut out[y * BINS..(y + 1) * BINS];
        let mut acc = 0f32;
        for x in 0..BINS {
            acc += value[y * BINS + x];
            row[x] = acc;
        }
        rows[y] = acc;
        for (x, r) in row.iter_mut().enumerate() {
            *r = if x == BINS - 1 {
                1.0
            } else if acc > 0.0 {
                *r / acc
            } else {
                (x + 1) as f32 / BINS as f32
            };
        }
    }
    let marg = &mut out[BIN_COUNT..];
    let mut acc = 0f32;
    for y in 0..BINS {
        acc += rows[y];
        marg[y] = acc;
    }
    for (y, m) in marg.iter_mut().enumerate() {
        *m = if y == BINS - 1 { 1.0 } else { *m / acc };
    }
}

/// The distribution of every cluster from the learned sums (`clusters × 256`).
pub fn build(sums: &[f32]) -> Vec<f32> {
    let n = sums.len() / BIN_COUNT;
    let mut out = vec![0f32; n * CDF_LEN];
    for (s, o) in sums.chunks_exact(BIN_COUNT).zip(out.chunks_exact_mut(CDF_LEN)) {
        build_cluster(s, o);
    }
    out
}

/// The entry below index `i` of a CDF (0 for the first).
fn below(cdf: &[f32], i: usize) -> f32 {
    if i == 0 {
        0.0
    } else {
        cdf[i - 1]
    }
}

/// Inverts a 16-entry CDF at `u`: the index and `u` rescaled to [0, 1) inside it.
fn invert(cdf: &[f32], u: f32) -> (usize, f32) {
    let i = cdf.iter().position(|c| u < *c).unwrap_or(BINS - 1);
    let (lo, hi) = (below(cdf, i), cdf[i]);
    let t = if hi > lo { (u - lo) / (hi - lo) } else { 0.5 };
    (i, t.clamp(0.0, 1.0 - f32::EPSILON))
}

/// Probability of the guided distribution choosing bin `b` (from the stored CDFs).
pub fn bin_probability(dist: &[f32], b: usize) -> f32 {
    let (x, y) = (b % BINS, b / BINS);
    let row = &dist[y * BINS..(y + 1) * BINS];
    let marg = &dist[BIN_COUNT..];
    (marg[y] - below(marg, y)) * (row[x] - below(row, x))
}

/// A tangent-space direction from the guided distribution of one cluster (`dist`:
/// its [`CDF_LEN`] values) for a point `u` of the unit square.
pub fn sample_guided(dist: &[f32], u: [f32; 2]) -> DVec3 {
    let (y, ty) = invert(&dist[BIN_COUNT..], u[1]);
    let (x, tx) = invert(&dist[y * BINS..(y + 1) * BINS], u[0]);
    let s = [(x as f64 + tx as f64) / BINS as f64, (y as f64 + ty as f64) / BINS as f64];
    sbf::sampling::uniform_hemisphere_concentric(s)
}

/// Solid-angle density of the guided distribution at a tangent-space direction (z ≥ 0).
pub fn guided_pdf(dist: &[f32], local: DVec3) -> f64 {
    bin_probability(dist, bin_of(local)) as f64 * BIN_COUNT as f64 / (2.0 * PI)
}

/// Solid-angle density of the mixture (1 − m)/2π + m·guided.
pub fn mixture_pdf(dist: &[f32], local: DVec3, m: f64) -> f64 {
    (1.0 - m) / (2.0 * PI) + m * guided_pdf(dist, local)
}
