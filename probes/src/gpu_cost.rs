//! The GPU cost axis: nanoseconds per evaluation of the
//! `shaders` runtime function of each mode, measured by the same kernels `shaders bench`
//! times (each invocation reads its normal, view, α and one of 1024 coefficient sets from
//! a buffer and writes the RGB sum; mean of back-to-back dispatches after a warm-up).
//!
//! Modes map to the WGSL runtime they would use: SH L2 → `sh_l2_irradiance`; SG 9/12 →
//! Hill irradiance (+ for specular the per-lobe GGX tables, or the split sum over the
//! warped NDF with `--specular-runtime fit`); Ambient Dice SRBF 9/12 → `ad9`/`ad12` irradiance (+ the
//! tables, or the Listing 8.1 fit × LUT); the engine formats → their decodes
//! (`engine.wgsl`); the prefiltered maps → SH L2's kernel for diffuse and `PF8`…`PF64`
//! (SH L2 + a trilinear cube-map lookup × DFG) for specular. Modes without a WGSL runtime (ambient cube, SH L1 variants and L3+,
//! the Bézier/YCoCg Ambient Dice, the H-basis, the
//! Monte Carlo reference) get none and stay off the GPU front.

use serde::{Deserialize, Serialize};

/// One mode's GPU cost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GpuCost {
    /// The `shaders bench` kernel measured (e.g. `SG12`).
    pub kernel: String,
    /// Diffuse (irradiance) evaluation, ns per evaluation.
    pub ns: f64,
    /// Diffuse + specular evaluation, ns per evaluation, where the kernel has one.
    pub specular_ns: Option<f64>,
    /// The adapter that ran it.
    pub adapter: String,
}

/// Every kernel's time on one adapter.
#[derive(Debug, Clone)]
pub struct GpuCosts {
    pub adapter: String,
    pub software: bool,
    rows: Vec<shaders::bench::Row>,
}

/// Runs the `shaders bench` kernels once (`count` evaluations per dispatch, `repeats`
/// dispatches). Errors when no adapter is available.
pub fn measure(count: usize, repeats: usize) -> Result<GpuCosts, String> {
    let gpu = shaders::gpu::Gpu::new()?;
    let rows = shaders::bench::run(&gpu, count, repeats, shaders::bench::Inputs::Buffer)?;
    Ok(GpuCosts { adapter: gpu.adapter.clone(), software: gpu.software, rows })
}

/// The `shaders bench` kernel of a mode, if it has a WGSL runtime.
pub fn kernel_of(id: &str) -> Option<&'static str> {
    match id {
        "shl2" | "shl2w" => Some("SH9 (L2)"),
        "sg9h" => Some("SG9"),
        "sg" | "sgls" | "sglsa" | "sgnnls" | "sgra" | "sgnnra" | "sgpls" | "sgpnnls" | "sg12h" | "sgnnlsc" | "sgpnnlsc" => Some("SG12"),
        "ad9" => Some("AD9"),
        "adrbf" | "adrbf-irr" | "adrbf-tangent" | "adpls" | "adpnnls" | "adnnlsc" | "adpnnlsc" => Some("AD12"),
        // SH L2 + a prefiltered cube map of the mode's size.
        _ if crate::modes::prefiltered::parse(id).is_some() => match crate::modes::prefiltered::parse(id)?.size {
            8 => Some("PF8"),
            16 => Some("PF16"),
            32 => Some("PF32"),
            _ => Some("PF64"),
        },
        // The WGSL engine decodes are Godot ≥ 4.4's and MonoSH's linear one.
        "godot-l1" => Some("Godot L1"),
        "monosh-linear" => Some("MonoSH"),
        "enlighten" => Some("Enlighten"),
        "enlighten-rgb" => Some("Enlighten RGB"),
        _ => None,
    }
}

impl GpuCosts {
    /// The GPU cost of a mode with the specular runtime `runtime` (None without a WGSL
    /// runtime). SH has one specular path whatever `runtime` says.
    pub fn for_mode(&self, id: &str, runtime: crate::modes::SpecularRuntime) -> Option<GpuCost> {
        let k = kernel_of(id)?;
        let ns = |signal: &str| {
            self.rows.iter().find(|r| r.name == k && r.signal == signal).map(|r| r.seconds_per_dispatch * 1e9 / r.count as f64)
        };
        let specular = match runtime {
            crate::modes::SpecularRuntime::Table if !k.starts_with("SH") && !k.starts_with("PF") => shaders::bench::TABLE_SPECULAR,
            _ => "diffuse + specular",
        };
        // A prefiltered map's diffuse is SH L2's kernel.
        let diffuse = if k.starts_with("PF") {
            self.rows.iter().find(|r| r.name == "SH9 (L2)" && r.signal == "diffuse").map(|r| r.seconds_per_dispatch * 1e9 / r.count as f64)
        } else {
            ns("diffuse")
        };
        Some(GpuCost { kernel: k.to_string(), ns: diffuse?, specular_ns: ns(specular), adapter: self.adapter.clone() })
    }
}
