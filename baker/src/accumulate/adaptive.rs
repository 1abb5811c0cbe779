//! Adaptive sampling of lightmap texels ([Roughton19 §3.3–3.4]): variable paths per texel,
//! drawn where the error is.
//!
//! A bake starts with `pilot_passes` uniform passes (every texel, every pass). After
//! them it runs **batches**: texel k's expected samples in a batch are
//!
//! λ_k = min(L, f·((1 − m)·N·s_k / Σ_j s_j + m)),
//!
//! where f is the batch size as a fraction of the texels (the expected paths per batch
//! are about f·N for N texels; the default 1 makes a batch cost about a pass), m the
//! defensive share (every texel keeps at least f·m, so none starves and a preview of the
//! whole atlas keeps refining, §3.4), L the most samples a texel takes per batch
//! (`max_per_batch`: one thread takes them in order, so L bounds a batch's critical path
//! at L path lengths), and s_k the mean over
//! the texel's 8×8 atlas tile of σ_j, each texel's per-sample standard deviation of E/π
//! (RMS over the channels, from its running moments). Drawing paths ∝ σ minimises
//! Σ_k σ_k²/n_k for a fixed total (the Neyman allocation); averaging σ over the tile
//! smooths the noisy per-texel estimate. The texel takes ⌊λ⌋ samples, plus one with
//! probability λ − ⌊λ⌋; texels with none are left out, so a batch is a random subset —
//! the GPU compacts it into a list and dispatches it indirectly, one thread per listed
//! texel taking its samples in order.
//!
//! Each texel's samples stay one progressive sequence: its k-th sample is sample k of its
//! [`crate::sampling::sequence`] streams whatever batch it lands in. The fractional part's decision
//! uses one more stream of its own (an Owen-scrambled Sobol' dimension over the
//! batches): stratified, so for a steady λ its samples over B batches stay close to λ·B.
//!
//! **Bias** (Kirk & Arvo 1991, the section's caveat): how many samples a texel gets
//! depends on σ estimated from its own (and its tile's) earlier samples, so its mean is
//! not exactly unbiased. Measured, not assumed: `tests/adaptive.rs` compares adaptive bakes
//! with a long uniform one per chart and for the scene (within 3σ), and the note reports
//! the difference.

use crate::accumulate::{Moments, Targets};
use crate::sampling::sequence::{group_point, item_key, Sequence};
use sbf::sampling::sobol::{hash_combine, pcg_hash};

/// Tile edge in texels.
pub const TILE: u32 = 8;

/// The largest allowed `max_per_batch` (L).
pub const MAX_SAMPLES_PER_BATCH: u32 = 64;

/// Adaptive-sampling settings.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveOptions {
    /// Uniform passes before the first batch.
    pub pilot_passes: u64,
    /// Expected paths per batch as a fraction f of the texels, in (0, L]: a texel gets
    /// at most L samples per batch, L/f times the uniform rate.
    pub batch_fraction: f64,
    /// L: the most samples a texel takes in one batch, 1 to [`MAX_SAMPLES_PER_BATCH`].
    pub max_per_batch: u32,
    /// The defensive share m in [0, 1]: every texel joins with probability ≥ f·m.
    pub floor: f64,
}

impl AdaptiveOptions {
    /// Checks the ranges (clear errors for bad input).
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=MAX_SAMPLES_PER_BATCH).contains(&self.max_per_batch) {
            return Err(format!("adaptive samples per batch {} must be in 1..={MAX_SAMPLES_PER_BATCH}", self.max_per_batch));
        }
        if !(self.batch_fraction > 0.0 && self.batch_fraction <= self.max_per_batch as f64) {
            return Err(format!(
                "adaptive batch fraction {} must be in (0, {}] (the samples per batch)",
                self.batch_fraction, self.max_per_batch
            ));
        }
        if !(0.0..=1.0).contains(&self.floor) {
            return Err(format!("adaptive floor {} must be in [0, 1]", self.floor));
        }
        if self.pilot_passes < 2 {
            return Err(format!("adaptive sampling needs at least 2 pilot passes (a variance), not {}", self.pilot_passes));
        }
        Ok(())
    }

    /// Batches that spend about the paths of `passes` uniform passes: the pilot, then
    /// (passes − pilot)/f batches.
    pub fn batches_for(&self, passes: u64) -> u64 {
        let rest = passes.saturating_sub(self.pilot_passes);
        self.pilot_passes.min(passes) + (rest as f64 / self.batch_fraction).round() as u64
    }
}

impl Default for AdaptiveOptions {
    fn default() -> Self {
        AdaptiveOptions { pilot_passes: 8, batch_fraction: 1.0, floor: 0.2, max_per_batch: 8 }
    }
}

/// The texels' tiles: per item its tile, and the tiles' item ranges (items sorted by
/// tile) — the layout both the CPU and the GPU reduce over.
#[derive(Debug, Clone)]
pub struct Tiles {
    /// Per item, its tile index.
    pub tile_of: Vec<u32>,
    /// Items grouped by tile; tile t holds `order[start[t]..start[t + 1]]`.
    pub order: Vec<u32>,
    pub start: Vec<u32>,
}

impl Tiles {
    /// The 8×8 tiles of an atlas `width` texels wide (texel id = y·width + x).
    pub fn new(targets: &Targets, width: usize) -> Result<Tiles, String> {
        if targets.sphere || width == 0 {
            return Err("adaptive sampling applies to lightmap texels, not probes".into());
        }
        let tiles_x = width.div_ceil(TILE as usize);
        let tile_of: Vec<u32> = targets
            .items
            .iter()
            .map(|&[_, _, id]| {
                let (x, y) = (id as usize % width, id as usize / width);
                ((y / TILE as usize) * tiles_x + x / TILE as usize) as u32
            })
            .collect();
        let tiles = tile_of.iter().map(|t| *t as usize + 1).max().unwrap_or(0);
        let mut start = vec![0u32; tiles + 1];
        for t in &tile_of {
            start[*t as usize + 1] += 1;
        }
        for t in 0..tiles {
            start[t + 1] += start[t];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; tile_of.len()];
        for (k, t) in tile_of.iter().enumerate() {
            order[fill[*t as usize] as usize] = k as u32;
            fill[*t as usize] += 1;
        }
        Ok(Tiles { tile_of, order, start })
    }

    pub fn count(&self) -> usize {
        self.start.len() - 1
    }
}

/// A texel's per-sample standard deviation of E/π, RMS over the channels (0 with fewer
/// than 2 samples).
pub fn sigma(m: &Moments) -> f64 {
    let n = m.accepted as f64;
    if n < 2.0 {
        return 0.0;
    }
    let var: f64 = (0..3).map(|c| (m.sum_sq[c] / n - (m.sum[c] / n).powi(2)).max(0.0) * n / (n - 1.0)).sum::<f64>() / 3.0;
    var.sqrt()
}

/// Per item, its expected samples λ_k in the next batch (see the module docs).
pub fn rates(tiles: &Tiles, moments: &[Moments], o: &AdaptiveOptions) -> Vec<f64> {
    let n = moments.len();
    let mut tile_mean = vec![0.0; tiles.count()];
    let mut total = 0.0;
    for t in 0..tiles.count() {
        let items = &tiles.order[tiles.start[t] as usize..tiles.start[t + 1] as usize];
        let sum: f64 = items.iter().map(|k| sigma(&moments[*k as usize])).sum();
        tile_mean[t] = if items.is_empty() { 0.0 } else { sum / items.len() as f64 };
        total += sum;
    }
    (0..n)
        .map(|k| {
            let share = if total > 0.0 { tile_mean[tiles.tile_of[k] as usize] * n as f64 / total } else { 1.0 };
            (o.batch_fraction * ((1.0 - o.floor) * share + o.floor)).min(o.max_per_batch as f64)
        })
        .collect()
}

/// The seed of item `id`'s join stream.
pub fn join_seed(seed: u64, id: u32) -> u32 {
    pcg_hash(hash_combine(item_key(seed, id), 0x5e1e_c700))
}

/// The samples item `id` takes in batch `batch` at rate λ: ⌊λ⌋, plus one if u < λ − ⌊λ⌋
/// for u the batch's point of the item's join stream (24-bit fractions and f32
/// arithmetic, as the GPU computes them).
pub fn samples_in_batch(sequence: Sequence, seed: u64, id: u32, batch: u64, rate: f64) -> u32 {
    let u = (group_point(sequence, join_seed(seed, id), batch as u32)[0] >> 8) as f32 * (1.0 / 16_777_216.0);
    let r = rate as f32;
    let whole = r.floor();
    whole as u32 + (u < r - whole) as u32
}
