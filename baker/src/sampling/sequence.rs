//! Per-item, per-vertex sample sequences ([Roughton19 §6.2]: a progressive low-discrepancy
//! sequence for every bounce, not only the first direction).
//!
//! Every random number of a pass is a pure function of (seed, item id, pass, vertex,
//! use): the path's vertex 0 is the baked point, vertex v ≥ 1 its v-th hit. Each vertex
//! draws three 4D points, one per *use*:
//!
//! | use | dims | vertex 0 (baked point) | vertex ≥ 1 (path hit) |
//! |---|---|---|---|
//! | [`DIRECTION`] | u₀ u₁ (u₂) u₃ | direction (u₀, u₁), guided mixture choice u₃ | BSDF layer choice u₀, direction (u₁, u₂), Russian roulette u₃ |
//! | [`EMITTER`] | u₀ u₁ u₂ | NEE: emitter triangle by power u₀, point on it (u₁, u₂) | same |
//! | [`ENVIRONMENT`] | u₀ u₁ u₂ | NEE: environment direction | same |
//!
//! [`Sequence::Sobol`] (the default): each (item, vertex, use) group is its own shuffled,
//! Owen-scrambled 4D Sobol' sequence over the passes ([`sbf::sampling::sobol`], Burley
//! 2020's padding), so for every use the passes of an item are stratified jointly in its
//! dimensions and every power-of-two prefix of passes is a net (the ordering §7.3.1 asks
//! of the progressive encoder); groups are decorrelated by their seeds. The sub-texel
//! point is the sample index modulo the point count (exactly balanced for any count);
//! the shuffle makes the Sobol' points' order depend on all bits of the index, so the
//! samples of one point still spread over every stratum of directions (unshuffled, the
//! index mod 2^k would fix the first k digits of dimension 0).
//! [`Sequence::Independent`]: hashed white noise in the same layout, for comparisons.
//!
//! The WGSL twin (`gpu/wgsl/sequence.wgsl`) computes the same 32-bit values.

use sbf::sampling::sobol::{hash_combine, owen_sobol4_u32, pcg_hash};

/// The direction (and path-continuation) use of a vertex.
pub const DIRECTION: u32 = 0;
/// Next-event estimation of an emissive triangle.
pub const EMITTER: u32 = 1;
/// Next-event estimation of the environment.
pub const ENVIRONMENT: u32 = 2;
/// Uses per vertex.
pub const USES: u32 = 3;

/// Which numbers feed the estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Sequence {
    /// Shuffled, Owen-scrambled Sobol' points per (item, vertex, use).
    #[default]
    Sobol,
    /// Independent uniform numbers (hashes), the same layout.
    Independent,
}

impl Sequence {
    pub fn parse(s: &str) -> Option<Sequence> {
        match s {
            "sobol" => Some(Sequence::Sobol),
            "independent" | "random" => Some(Sequence::Independent),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Sequence::Sobol => "sobol",
            Sequence::Independent => "independent",
        }
    }

    /// The value the WGSL kernels read (`TraceParams::sampler`).
    pub fn code(self) -> u32 {
        match self {
            Sequence::Sobol => 0,
            Sequence::Independent => 1,
        }
    }
}

/// The 32-bit seed the GPU kernels receive for a 64-bit bake seed.
pub fn gpu_seed(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

/// The item's key: all its groups' seeds derive from it.
pub fn item_key(seed: u64, id: u32) -> u32 {
    pcg_hash(gpu_seed(seed) ^ pcg_hash(id.wrapping_add(0x68e3_1da4)))
}

/// The 4D point of one group: `group_seed` from [`PathSampler::group_seed`], `index` the
/// pass (or the pass within a guiding stage). 32-bit fractions.
pub fn group_point(sequence: Sequence, group_seed: u32, index: u32) -> [u32; 4] {
    match sequence {
        Sequence::Sobol => owen_sobol4_u32(index, group_seed),
        Sequence::Independent => {
            let h = pcg_hash(group_seed ^ pcg_hash(index ^ 0x2c1b_3c6d));
            std::array::from_fn(|d| pcg_hash(h.wrapping_add(0x9e37_79b9u32.wrapping_mul(d as u32 + 1))))
        }
    }
}

/// The sample source of one pass at one item, walked vertex by vertex along the path.
#[derive(Debug, Clone, Copy)]
pub struct PathSampler {
    pub sequence: Sequence,
    key: u32,
    index: u32,
    vertex: u32,
}

impl PathSampler {
    /// Pass `pass` of item `id` (the pass index modulo 2³²).
    pub fn new(sequence: Sequence, seed: u64, id: u32, pass: u64) -> PathSampler {
        PathSampler { sequence, key: item_key(seed, id), index: pass as u32, vertex: 0 }
    }

    /// The seed of group (vertex, use): hashed, so that the groups' seeds are unrelated
    /// (`hash_combine` alone changes few bits, and the Laine–Karras scramble mixes
    /// weakly).
    pub fn group_seed(key: u32, vertex: u32, use_: u32) -> u32 {
        pcg_hash(hash_combine(key, vertex * USES + use_))
    }

    /// Moves to path vertex `v` (0: the baked point; v: the v-th hit).
    pub fn at_vertex(&mut self, v: u32) {
        self.vertex = v;
    }

    /// The 4D point of `use_` at the current vertex, on [0,1)⁴.
    pub fn get(&self, use_: u32) -> [f64; 4] {
        to_unit(group_point(self.sequence, Self::group_seed(self.key, self.vertex, use_), self.index))
    }

    /// The sampler of a ray-guiding stage (`guiding::stage`): every group reseeded per
    /// stage and indexed by the pass within the stage, so a stage's numbers are
    /// independent of the earlier stages its distributions were learned from (a
    /// quasi-random point falls in the gaps of its own sequence's earlier points — which a
    /// distribution, or an MIS weight, learned from those points would bias).
    pub fn staged(self, stage: u32, start: u64) -> PathSampler {
        PathSampler { key: pcg_hash(hash_combine(self.key, 0x5a0e_0000 + stage)), index: self.index.wrapping_sub(start as u32), ..self }
    }
}

fn to_unit(x: [u32; 4]) -> [f64; 4] {
    x.map(|v| v as f64 * (1.0 / 4_294_967_296.0))
}
