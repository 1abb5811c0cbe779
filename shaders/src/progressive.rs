//! Rust twins of `progressive.wgsl`'s structs (the progressive LS/NNLS encoder's
//! options and per-texel state), built from `sbf`'s [`ProgressiveOptions`] and read back
//! into coefficients. Layouts are checked against naga's reflection in the tests
//! ([`crate::layout::check`]).

use sbf::solve::{Denominator, Iteration, ProgressiveOptions};

/// Lobes a state holds (SH L1/L2, SG 9/12, AD 9/12 fit; WGSL `ENCODER_MAX_LOBES`).
pub const MAX_LOBES: usize = 12;
/// `flags` bit: clamp amplitudes to ≥ 0 (progressive NNLS).
pub const NON_NEGATIVE: u32 = 1;
/// `flags` bit: Gauss–Seidel lobe order (else Jacobi).
pub const GAUSS_SEIDEL: u32 = 2;
/// `denominator` values.
pub const DENOM_BLEND: u32 = 0;
pub const DENOM_CLAMP_TO_TRUE: u32 = 1;
pub const DENOM_RAW: u32 = 2;
pub const DENOM_PROJECTION: u32 = 3;

/// WGSL `EncoderParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EncoderParams {
    pub acceleration: f32,
    pub lobes: u32,
    pub flags: u32,
    pub denominator: u32,
    /// Exact mean of B_i² for the clamped denominator; lobe i at `[i / 4][i % 4]`.
    pub true_mean: [[f32; 4]; 3],
}
crate::gpu_struct!(EncoderParams, "EncoderParams", [acceleration, lobes, flags, denominator, true_mean]);

impl EncoderParams {
    /// The GPU form of `opts` for `lobes` lobes. The mirrored-hemisphere option is the
    /// caller's job on the GPU (a second update with the mirrored basis values and a zero
    /// value), so it is refused here rather than silently dropped.
    pub fn new(opts: &ProgressiveOptions, lobes: usize) -> Result<Self, String> {
        if lobes == 0 || lobes > MAX_LOBES {
            return Err(format!("the GPU encoder holds 1..={MAX_LOBES} lobes, not {lobes}"));
        }
        if opts.mirror_hemisphere {
            return Err("mirror_hemisphere: issue the mirrored update from the kernel (progressive_update with the mirrored basis values and value 0)".into());
        }
        if !(opts.acceleration.is_finite() && opts.acceleration > 0.0) {
            return Err(format!("acceleration must be finite and > 0, not {}", opts.acceleration));
        }
        let mut true_mean = [[0.0f32; 4]; 3];
        let denominator = match &opts.denominator {
            Denominator::Blend => DENOM_BLEND,
            Denominator::Raw => DENOM_RAW,
            Denominator::ClampToTrue(t) | Denominator::Projection(t) => {
                if t.len() != lobes {
                    return Err(format!("the exact means of B_i² have {} values for {lobes} lobes", t.len()));
                }
                let projection = matches!(opts.denominator, Denominator::Projection(_));
                if let Some(v) = t.iter().find(|v| projection && !(v.is_finite() && **v > 0.0)) {
                    return Err(format!("the projection's exact mean of B_i² must be finite and > 0, not {v}"));
                }
                for (i, v) in t.iter().enumerate() {
                    true_mean[i / 4][i % 4] = *v as f32;
                }
                if projection {
                    DENOM_PROJECTION
                } else {
                    DENOM_CLAMP_TO_TRUE
                }
            }
        };
        let flags =
            if opts.non_negative { NON_NEGATIVE } else { 0 } | if opts.iteration == Iteration::GaussSeidel { GAUSS_SEIDEL } else { 0 };
        Ok(EncoderParams { acceleration: opts.acceleration as f32, lobes: lobes as u32, flags, denominator, true_mean })
    }
}

/// WGSL `EncoderState`: one texel's progressive state (208 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EncoderState {
    /// Per lobe: RGB amplitude and the running mean of B_i².
    pub lobes: [[f32; 4]; MAX_LOBES],
    pub total_weight: f32,
    pub samples: u32,
    /// WGSL rounds the struct to its 16-byte alignment.
    pub _pad: [u32; 2],
}
crate::gpu_struct!(EncoderState, "EncoderState", [lobes, total_weight, samples]);

impl EncoderState {
    /// RGB amplitudes of the first `lobes` lobes.
    pub fn coefficients(&self, lobes: usize) -> Vec<[f32; 3]> {
        self.lobes[..lobes.min(MAX_LOBES)].iter().map(|l| [l[0], l[1], l[2]]).collect()
    }
    /// Running means of B_i² of the first `lobes` lobes.
    pub fn integrals(&self, lobes: usize) -> Vec<f32> {
        self.lobes[..lobes.min(MAX_LOBES)].iter().map(|l| l[3]).collect()
    }
}
