//! Projection (convolution) matrices and basis conversion ([Roughton19 §7.4]).
//!
//! For a source basis A, a target basis B and a kernel C(ω, s):
//!   P_ij = ∫_{D_B} B_i(s) K_j(s) ds,   K_j(s) = ∫ C(ω, s) A_j(ω) dω      (eq. 7.20)
//! so that target coefficients b = G_B⁻¹ P a (eq. 7.21) represent the kernel-convolved
//! signal, and b = (G_B⁻¹ P G_A⁻¹) m maps source moments directly (eq. 7.22).
//!
//! Kernels:
//! - [`Kernel::Delta`]: K_j = A_j (plain basis conversion, e.g. SG ↔ AD, SH → H-basis).
//! - [`Kernel::Lambert`]: K_j(s) = (1/π)∫_{ω·s>0} A_j(ω)(ω·s) dω, i.e. E/π — the
//!   "irradiance" signal as reports store it. Inner rule: Gauss–Legendre × trapezoid
//!   on the hemisphere about s (exact for polynomial A, such as SH). A source basis on
//!   the upper hemisphere (H-basis, AD 9) contributes no radiance below z = 0.
//! - [`Kernel::Ggx`]: view-parameterised GGX at fixed α with normal +Z and Fresnel 1:
//!   K_j(v) = ∫ A_j(l)·D·G2/(4 n·v) dl, estimated by visible-normal sampling with a
//!   fixed R2 point set (weight G2/G1, Heitz 2018), 0 for v below the horizon.

use super::lsq::{solve_gram, LsOptions};
use crate::basis::Basis;
use crate::error::SbfError;
use crate::frame::tangent_frame;
use crate::ggx;
use crate::gram::{gram_matrix, Gram, GramOptions};
use crate::quadrature::{Domain, SphereQuadrature};
use crate::sampling::R2;
use glam::DVec3;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// The convolution kernel C(ω, s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kernel {
    /// K_j = A_j: plain basis conversion.
    Delta,
    /// E/π: the clamped cosine about s, over π.
    Lambert,
    /// GGX reflection at roughness α, normal +Z, Fresnel 1 (view-parameterised).
    Ggx {
        /// GGX α.
        alpha: f64,
    },
}

/// Quadrature resolution of [`projection_matrix`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProjectionOptions {
    /// Gauss–Legendre nodes in z of the outer rule over the target domain (φ: 2×).
    pub outer_n_z: usize,
    /// Nodes in z of the inner hemisphere rule (Lambert; φ: 2×).
    pub inner_n_z: usize,
    /// Visible-normal samples per view (GGX).
    pub ggx_samples: usize,
}

impl Default for ProjectionOptions {
    fn default() -> Self {
        ProjectionOptions { outer_n_z: 64, inner_n_z: 48, ggx_samples: 4096 }
    }
}

/// Evaluates K_j(s) for all j into `out`.
struct KernelEval<'a> {
    source: &'a dyn Basis,
    kernel: Kernel,
    /// Lambert: hemisphere rule about +Z with weights × cosθ/π.
    hemi: Option<SphereQuadrature>,
    ggx_u: Vec<[f64; 2]>,
    scratch: Vec<f64>,
}

impl<'a> KernelEval<'a> {
    fn new(source: &'a dyn Basis, kernel: Kernel, opts: ProjectionOptions) -> Self {
        let hemi = (kernel == Kernel::Lambert).then(|| {
            let mut q = SphereQuadrature::gauss_product(Domain::UpperHemisphere, opts.inner_n_z, 2 * opts.inner_n_z);
            for (d, w) in q.directions.iter().zip(q.weights.iter_mut()) {
                *w *= d.z / PI;
            }
            q
        });
        let ggx_u = if matches!(kernel, Kernel::Ggx { .. }) {
            let r2 = R2::new();
            (0..opts.ggx_samples as u64).map(|i| r2.point(i)).collect()
        } else {
            Vec::new()
        };
        KernelEval { source, kernel, hemi, ggx_u, scratch: vec![0.0; source.len()] }
    }

    fn eval(&mut self, s: DVec3, out: &mut [f64]) {
        match self.kernel {
            Kernel::Delta => self.source.eval_into(s, out),
            Kernel::Lambert => {
                out.fill(0.0);
                let (t, b) = tangent_frame(s);
                let q = self.hemi.as_ref().expect("Lambert rule");
                let clip = self.source.domain() == Domain::UpperHemisphere;
                for (d, w) in q.directions.iter().zip(&q.weights) {
                    let world = t * d.x + b * d.y + s * d.z;
                    if clip && world.z < 0.0 {
                        continue; // a hemisphere basis represents zero radiance below
                    }
                    self.source.eval_into(world, &mut self.scratch);
                    for (o, v) in out.iter_mut().zip(&self.scratch) {
                        *o += w * v;
                    }
                }
            }
            Kernel::Ggx { alpha } => {
                out.fill(0.0);
                if s.z <= 0.0 {
                    return;
                }
                let g1 = ggx::g1(s, alpha);
                let inv = 1.0 / self.ggx_u.len() as f64;
                for u in &self.ggx_u {
                    let h = ggx::sample_vndf(s, alpha, *u);
                    let l = ggx::reflect(s, h);
                    if l.z <= 0.0 {
                        continue;
                    }
                    let w = inv * ggx::g2(s, l, alpha) / g1;
                    self.source.eval_into(l, &mut self.scratch);
                    for (o, v) in out.iter_mut().zip(&self.scratch) {
                        *o += w * v;
                    }
                }
            }
        }
    }
}

fn check_kernel(kernel: Kernel) -> Result<(), SbfError> {
    if let Kernel::Ggx { alpha } = kernel {
        if !(alpha.is_finite() && (1e-4..=1.0).contains(&alpha)) {
            return Err(SbfError::InvalidParameter { name: "GGX alpha", value: alpha, reason: "must be in [1e-4, 1]" });
        }
    }
    Ok(())
}

/// P_ij = ∫_{D_B} B_i(s) K_j(s) ds over the target basis' domain.
pub fn projection_matrix(
    target: &dyn Basis,
    source: &dyn Basis,
    kernel: Kernel,
    opts: ProjectionOptions,
) -> Result<DMatrix<f64>, SbfError> {
    check_kernel(kernel)?;
    if opts.outer_n_z < 2 || opts.inner_n_z < 2 || (matches!(kernel, Kernel::Ggx { .. }) && opts.ggx_samples == 0) {
        return Err(SbfError::InvalidParameter {
            name: "projection resolution",
            value: opts.outer_n_z.min(opts.inner_n_z) as f64,
            reason: "n_z must be >= 2 and GGX samples > 0",
        });
    }
    let outer = SphereQuadrature::gauss_product(target.domain(), opts.outer_n_z, 2 * opts.outer_n_z);
    let (nb, na) = (target.len(), source.len());
    let mut p = DMatrix::zeros(nb, na);
    let mut kv = KernelEval::new(source, kernel, opts);
    let mut bi = vec![0.0; nb];
    let mut kj = vec![0.0; na];
    for (s, w) in outer.directions.iter().zip(&outer.weights) {
        target.eval_into(*s, &mut bi);
        if bi.iter().all(|v| *v == 0.0) {
            continue;
        }
        kv.eval(*s, &mut kj);
        for i in 0..nb {
            let wb = w * bi[i];
            for j in 0..na {
                p[(i, j)] += wb * kj[j];
            }
        }
    }
    Ok(p)
}

/// A basis conversion through a kernel, with every piece kept for inspection.
#[derive(Debug, Clone)]
pub struct Conversion {
    /// P (target × source).
    pub projection: DMatrix<f64>,
    /// G_B⁻¹ P: source coefficients → target coefficients (eq. 7.21).
    pub matrix: DMatrix<f64>,
    /// G_B⁻¹ P G_A⁻¹: source moments → target coefficients (eq. 7.22).
    pub folded: DMatrix<f64>,
    /// G_B, the target basis's Gram matrix.
    pub target_gram: Gram,
    /// G_A, the source basis's Gram matrix.
    pub source_gram: Gram,
}

impl Conversion {
    /// Builds P and both Gram matrices (each on its basis' own domain) and folds them.
    pub fn new(target: &dyn Basis, source: &dyn Basis, kernel: Kernel, opts: ProjectionOptions) -> Result<Self, SbfError> {
        let projection = projection_matrix(target, source, kernel, opts)?;
        let target_gram = gram_matrix(target, target.domain(), GramOptions::default())?;
        let source_gram = gram_matrix(source, source.domain(), GramOptions::default())?;
        let matrix = solve_gram(&target_gram.matrix, &projection, LsOptions::default())?.coeffs;
        // folded = (G_B⁻¹ P) G_A⁻¹ = ((G_A⁻¹)ᵀ (G_B⁻¹ P)ᵀ)ᵀ, G_A symmetric.
        let folded = solve_gram(&source_gram.matrix, &matrix.transpose(), LsOptions::default())?.coeffs.transpose();
        Ok(Conversion { projection, matrix, folded, target_gram, source_gram })
    }

    /// Target coefficients (target × channels) from source coefficients.
    pub fn apply(&self, source_coeffs: &DMatrix<f64>) -> DMatrix<f64> {
        &self.matrix * source_coeffs
    }

    /// Target coefficients from source moments m_j = ∫ f A_j.
    pub fn apply_moments(&self, source_moments: &DMatrix<f64>) -> DMatrix<f64> {
        &self.folded * source_moments
    }
}
