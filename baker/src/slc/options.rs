//! What the `slc` command renders ([`SlcOptions`]), shared by the run ([`super::harness`])
//! and its comparisons ([`super::compare`]).

use std::path::PathBuf;

/// What the `slc` command renders.
#[derive(Debug, Clone, PartialEq)]
pub struct SlcOptions {
    /// A built-in scene name or a glTF file ([`crate::scene::load::load`]).
    pub scene: String,
    /// A lat-long environment map replacing the scene's.
    pub environment: Option<PathBuf>,
    /// Seed of the VPL light paths.
    pub seed: u64,
    /// Output folder.
    pub out: PathBuf,
    /// Light paths traced from the scene's emitters (VPLs at their hits).
    pub vpls: usize,
    pub width: usize,
    pub height: usize,
    pub delta: f32,
    /// Also render the brute-force reference (every VPL at every pixel).
    pub brute: bool,
    /// Timed GPU frames: medians of as many isolated and timestamped frames; frames back to
    /// back at least as many.
    pub frames: usize,
    /// Interleaved sampling: I × I subregions each shading 1/I² of the VPLs (1: off).
    pub interleave: usize,
    /// The filter joining the subregions.
    pub filter: crate::slc::Filter,
    /// The bound of glossy VPLs (the spheroid, or its enclosing sphere for comparison).
    pub bound: crate::slc::Bound,
    /// Which VPLs: "both", "diffuse" (glossy ones dropped) or "glossy" (every VPL made a
    /// GGX VPL of α `glossy_alpha` and F0 0.9 — Tokuyoshi & Harada's glossy-only workload).
    pub kind: String,
    pub glossy_alpha: f32,
    /// Also cull the same VPLs with each glossy bound (spheroid, enclosing sphere, TH16
    /// sphere) and report their false discovery rates and times.
    pub compare_bounds: bool,
    /// Also time tiled culling (Modified HalfZ) against clustered shading (32 depth slices
    /// per tile) on diffuse-only and glossy-only VPL sets ([TH17 Table 2]'s comparison).
    pub compare_culling: bool,
    /// Also render single scattering in this medium (culled and brute force, on the run's
    /// device).
    pub medium: Option<crate::slc::media::Medium>,
    /// Diffuse bounces after the first hit ([`crate::slc::add_bounces`]; 0: single-bounce
    /// VPLs as Tokuyoshi & Harada's).
    pub bounces: usize,
    /// Point lights scattered uniformly through the scene's bounds for the medium run
    /// ([FTH22-supp Fig. 1]: 2 560 point lights).
    pub point_lights: usize,
    /// The environment is a source of light paths too ([`crate::slc::vpls_from_scene_with`]).
    pub sky: bool,
    /// VPLs from a reflective shadow map of this many texels a side per punctual light
    /// ([`crate::slc::rsm`]) instead of `vpls` light paths.
    pub rsm: Option<usize>,
    /// The equal-time experiment over these δ ([`crate::slc::sweep`]; needs `brute`).
    pub sweep: Vec<f32>,
}

/// The GPU's own ξ stream for `--seed` (cull.wgsl's PCG hash): the GPU leg is an independent
/// estimate, not a replay of the CPU's `slc::vpl_xi` (the VPLs themselves are the same).
pub fn gpu_xi_seed(seed: u64) -> u32 {
    ((seed ^ (seed >> 32)) as u32).max(1)
}
