//! Irradiance from a zonal-lobe basis's coefficients as the best linear estimate under an
//! isotropic radiance prior (a Wiener / kriging estimator on the sphere).
//!
//! A basis of zonal functions B_i(ω) = f_i(a_i·ω) (SG lobes, a constant) stores c; its
//! fit saw the radiance only through the moments m = G·c (exactly so for least squares,
//! m_i = ⟨B_i, L⟩). The physical reconstruction E ≈ Σ c_i·(cosine ⊛ B_i) assumes the
//! radiance *is* Σ c_i B_i; what the basis does not span is dropped, and with 12 SG lobes
//! that residual still carries irradiance. Modelling the radiance as an isotropic random
//! field with angular power spectrum C_l (E[L_lm L_l'm'] = C_l δ), the linear estimate of
//! E(n)/π from m with the least expected squared error is
//!
//!   Ê(n) = g(n)ᵀ Σ⁻¹ m,   Σ_ij = Cov(m_i, m_j) = Σ_l C_l Λ_il Λ_jl (2l+1)/(4π) P_l(a_i·a_j),
//!   g_i(n) = Cov(E(n)/π, m_i) = Σ_l C_l (A_l/π) Λ_il (2l+1)/(4π) P_l(a_i·n),
//!
//! with Λ_il the Funk–Hecke (Legendre) coefficients of f_i — ∫ f_i(a·ω) Y_lm(ω) dω =
//! Λ_il Y_lm(a) — and A_l the clamped-cosine band factors ([`super::zonal`]); the sums
//! follow from the addition theorem Σ_m Y_lm(a) Y_lm(b) = (2l+1)/(4π) P_l(a·b). At run
//! time this is a lobe sum like Hill's, Ê(n) = Σ_i c'_i g_i(a_i·n) with c' = Σ⁻¹ G c
//! computed once per probe ([`PriorIrradiance::coefficients`]).
//!
//! Prior: C_l = l^(−p) for l ≥ 1 (p = 2 by default: the spherical-harmonic power spectra
//! of real-world illumination maps fall off about as 1/l², Dror, Willsky & Adelson 2004,
//! "Statistical characterization of real-world illumination", J. Vision 4(9)), and a
//! C_0 large enough that the mean is left to the data (the estimate does not depend on it
//! once C_0 ≫ C_1; [`RadiancePrior::dc_ratio`]). With a white spectrum (C_l ≡ 1) Σ = G,
//! c' = c and g_i is the exact irradiance of f_i: the physical reconstruction (test).

use crate::error::SbfError;
use crate::glam::DVec3;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// The radiance prior's angular power spectrum C_l.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiancePrior {
    /// C_l = l^(−exponent) for l ≥ 1.
    pub exponent: f64,
    /// C_0 / C_1: large, so that the mean is fitted, not shrunk.
    pub dc_ratio: f64,
    /// White spectrum (C_l ≡ 1): the estimate is the physical convolution.
    pub white: bool,
}

impl Default for RadiancePrior {
    /// C_l = 1/l², C_0 = 10³·C_1 (see the module docs).
    fn default() -> Self {
        RadiancePrior { exponent: 2.0, dc_ratio: 1e3, white: false }
    }
}

impl RadiancePrior {
    /// C_l.
    pub fn power(&self, l: usize) -> f64 {
        match (self.white, l) {
            (true, _) => 1.0,
            (false, 0) => self.dc_ratio,
            (false, l) => (l as f64).powf(-self.exponent),
        }
    }
}

/// One zonal function of the basis: an SG lobe or the constant 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Zonal {
    /// exp(λ(a·ω − 1)).
    Lobe {
        /// Unit axis a.
        axis: DVec3,
        /// λ.
        sharpness: f64,
    },
    /// 1 everywhere.
    Constant,
}

/// Funk–Hecke coefficients Λ_l = 2π ∫₋₁¹ exp(λ(t − 1)) P_l(t) dt of a unit SG lobe,
/// l = 0..=lmax, by Gauss–Legendre quadrature on segments that shrink geometrically
/// towards t = 1 (width 1/(4λ) there), 48 nodes each: the integrand is a polynomial of
/// degree ≤ lmax times an exponential that varies by less than e^(1/4)… per segment near
/// the peak. Checked against the closed form 4π e^(−λ) i_l(λ) (test).
pub fn sg_legendre_coefficients(sharpness: f64, lmax: usize) -> Vec<f64> {
    let lam = sharpness;
    let mut cuts = vec![1.0];
    let mut w = 0.25 / lam.max(1e-3);
    while 1.0 - w > -1.0 {
        cuts.push(1.0 - w);
        w *= 2.0;
    }
    cuts.push(-1.0);
    let (gx, gw) = crate::quadrature::gauss_legendre(48.max(lmax + 8));
    let mut out = vec![0.0; lmax + 1];
    let mut p = vec![0.0; lmax + 1];
    for seg in cuts.windows(2) {
        let (b, a) = (seg[0], seg[1]);
        for (x, wx) in gx.iter().zip(&gw) {
            let t = a + 0.5 * (b - a) * (x + 1.0);
            // exp(λ(t − 1)) with t − 1 formed from the segment ends (no cancellation at t ≈ 1).
            let f = (lam * ((t - b) + (b - 1.0))).exp() * 0.5 * (b - a) * wx;
            legendre_all(t, &mut p);
            for (o, pl) in out.iter_mut().zip(&p) {
                *o += 2.0 * PI * f * pl;
            }
        }
    }
    out
}

/// P_0(t)…P_lmax(t) by the upward three-term recurrence (stable on [−1, 1]).
fn legendre_all(t: f64, p: &mut [f64]) {
    if p.is_empty() {
        return;
    }
    p[0] = 1.0;
    if p.len() > 1 {
        p[1] = t;
    }
    for l in 1..p.len().saturating_sub(1) {
        p[l + 1] = ((2 * l + 1) as f64 * t * p[l] - l as f64 * p[l - 1]) / (l + 1) as f64;
    }
}

/// Highest degree evaluated as a monomial polynomial (Horner); above it, or where the
/// conversion would cost accuracy, the Legendre recurrence. Converting Σ a_l P_l to
/// monomials and evaluating by Horner on [−1, 1] errs by ≲ (degree + 1)·ε·Σ_l |a_l|·‖P_l‖₁
/// (‖P_l‖₁: the sum of |monomial coefficients| of P_l, 1.6e8 at l = 40); Horner is used only
/// when that bound is ≤ 1e-13·Σ|a_l| — for the smooth kernels here, whose a_l decay like
/// Gaussians, it is ~1e-15 (the white-prior and peer-kernel tests check 1e-12 against
/// direct quadrature and the closed form).
const HORNER_MAX_DEGREE: usize = 40;

/// A zonal kernel Σ_l a_l P_l(t), truncated where the rest of |a_l| sums to ≤ 1e-17 of
/// the whole (|P_l| ≤ 1 on [−1, 1], so that bounds the dropped part), stored for fast
/// evaluation: monomial coefficients (Horner) up to `HORNER_MAX_DEGREE`, else the
/// Legendre coefficients with the recurrence.
#[derive(Debug, Clone)]
pub enum Kernel {
    /// Monomial coefficients c_k of Σ c_k t^k, lowest first (Horner).
    Monomial(Vec<f64>),
    /// Legendre coefficients a_l, lowest first (the three-term recurrence).
    Legendre(Vec<f64>),
}

impl Kernel {
    /// From Legendre coefficients a_0, a_1, … (at least one).
    pub fn new(a: &[f64]) -> Kernel {
        let total: f64 = a.iter().map(|x| x.abs()).sum();
        let mut n = a.len();
        let mut tail = 0.0;
        while n > 1 && tail + a[n - 1].abs() <= 1e-17 * total {
            tail += a[n - 1].abs();
            n -= 1;
        }
        let a = &a[..n];
        if n - 1 > HORNER_MAX_DEGREE {
            return Kernel::Legendre(a.to_vec());
        }
        // Monomial coefficients of P_l by the recurrence (l+1)P_{l+1} = (2l+1)t P_l − l P_{l−1}.
        let mut out = vec![0.0; n];
        let mut amplified = 0.0;
        let (mut p0, mut p1) = (vec![0.0; n], vec![0.0; n]);
        p0[0] = 1.0;
        if n > 1 {
            p1[1] = 1.0;
        }
        for (l, al) in a.iter().enumerate() {
            let p = match l {
                0 => p0.clone(),
                1 => p1.clone(),
                _ => {
                    let k = (l - 1) as f64;
                    let mut p2 = vec![0.0; n];
                    for d in 0..n {
                        let shifted = if d > 0 { p1[d - 1] } else { 0.0 };
                        p2[d] = ((2.0 * k + 1.0) * shifted - k * p0[d]) / (k + 1.0);
                    }
                    p0 = std::mem::replace(&mut p1, p2);
                    p1.clone()
                }
            };
            for (o, c) in out.iter_mut().zip(&p) {
                *o += al * c;
            }
            amplified += al.abs() * p.iter().map(|c| c.abs()).sum::<f64>();
        }
        if n as f64 * f64::EPSILON * amplified > 1e-13 * total {
            return Kernel::Legendre(a.to_vec());
        }
        Kernel::Monomial(out)
    }

    /// The kernel at t ∈ [−1, 1].
    #[inline]
    pub fn eval(&self, t: f64) -> f64 {
        match self {
            Kernel::Monomial(c) => c.iter().rev().fold(0.0, |acc, ci| acc * t + ci),
            Kernel::Legendre(a) => {
                let (mut p0, mut p1) = (1.0, t);
                let mut s = a[0] + a.get(1).map_or(0.0, |a1| a1 * t);
                for (l, al) in a.iter().enumerate().skip(2) {
                    let k = (l - 1) as f64;
                    let p2 = ((2.0 * k + 1.0) * t * p1 - k * p0) / (k + 1.0);
                    s += al * p2;
                    (p0, p1) = (p1, p2);
                }
                s
            }
        }
    }
}

/// E/π of a unit SG lobe (sharpness λ) with the clamped cosine replaced by an SG kernel
/// of sharpness λ_k normalised to integrate to π — [`super::sg::irradiance_sg_kernel`] (the
/// peer tool's reconstruction) — as a zonal series in t = axis·n: by Funk–Hecke
/// Σ_l Λ_l(λ) Λ_l(λ_k) (2l+1)/(4π) P_l(t) / ∫K, with ∫K = Λ_0(λ_k). Bands up to
/// ⌈√(40·max(λ, λ_k))⌉ + 8, like [`PriorIrradiance::new`].
pub fn sg_kernel_series(sharpness: f64, kernel_sharpness: f64) -> Kernel {
    let lmax = (40.0 * sharpness.max(kernel_sharpness).max(1.0)).sqrt().ceil() as usize + 8;
    let (a, k) = (sg_legendre_coefficients(sharpness, lmax), sg_legendre_coefficients(kernel_sharpness, lmax));
    Kernel::new(&(0..=lmax).map(|l| a[l] * k[l] * (2 * l + 1) as f64 / (4.0 * PI) / k[0]).collect::<Vec<_>>())
}

/// The estimator of the module docs for one basis: per function its axis and the Legendre
/// coefficients of g_i, and the transform c ↦ c' = Σ⁻¹ G c.
#[derive(Debug, Clone)]
pub struct PriorIrradiance {
    axes: Vec<DVec3>,
    kernels: Vec<Kernel>,
    transform: DMatrix<f64>,
    gram: DMatrix<f64>,
    chol: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    prior: RadiancePrior,
    lmax: usize,
    /// Spectral condition number of Σ (its eigenvalue ratio).
    pub condition: f64,
}

impl PriorIrradiance {
    /// Builds the estimator for `functions` under `prior`. Bands up to
    /// l = ⌈√(40·λ_max)⌉ + 8 (Λ_l/Λ_0 ≈ exp(−l²/(2λ)) is below 1e-8 there, and its
    /// square, which Σ and G carry, below 1e-17). Errors for a sharpness outside
    /// (0, 1000] or a covariance that is not positive definite (e.g. a repeated function).
    pub fn new(functions: &[Zonal], prior: RadiancePrior) -> Result<PriorIrradiance, SbfError> {
        let mut lam_max: f64 = 1.0;
        for f in functions {
            if let Zonal::Lobe { axis, sharpness } = f {
                if !(*sharpness > 0.0 && *sharpness <= 1000.0) {
                    return Err(SbfError::InvalidParameter { name: "sharpness", value: *sharpness, reason: "must be in (0, 1000]" });
                }
                if !axis.is_finite() || (axis.length() - 1.0).abs() > 1e-9 {
                    return Err(SbfError::InvalidDirection { x: axis.x, y: axis.y, z: axis.z });
                }
                lam_max = lam_max.max(*sharpness);
            }
        }
        let lmax = (40.0 * lam_max).sqrt().ceil() as usize + 8;
        let coeffs: Vec<Vec<f64>> = functions
            .iter()
            .map(|f| match f {
                Zonal::Lobe { sharpness, .. } => sg_legendre_coefficients(*sharpness, lmax),
                Zonal::Constant => (0..=lmax).map(|l| if l == 0 { 4.0 * PI } else { 0.0 }).collect(),
            })
            .collect();
        let axes: Vec<DVec3> = functions.iter().map(|f| if let Zonal::Lobe { axis, .. } = f { *axis } else { DVec3::Y }).collect();
        let n = functions.len();
        let band = |l: usize| (2 * l + 1) as f64 / (4.0 * PI);
        let mut p = vec![0.0; lmax + 1];
        let mut sigma = DMatrix::zeros(n, n);
        let mut gram = DMatrix::zeros(n, n);
        for i in 0..n {
            for j in 0..=i {
                legendre_all(axes[i].dot(axes[j]).clamp(-1.0, 1.0), &mut p);
                let (mut s, mut g) = (0.0, 0.0);
                for l in 0..=lmax {
                    let t = coeffs[i][l] * coeffs[j][l] * band(l) * p[l];
                    s += prior.power(l) * t;
                    g += t;
                }
                sigma[(i, j)] = s;
                sigma[(j, i)] = s;
                gram[(i, j)] = g;
                gram[(j, i)] = g;
            }
        }
        let eig = sigma.clone().symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(*x), b.max(*x)));
        // Below 1e-13 of the largest eigenvalue Σ is singular to rounding (a repeated or
        // linearly dependent function): refused rather than solved into noise.
        if lo.partial_cmp(&(1e-13 * hi)) != Some(std::cmp::Ordering::Greater) {
            return Err(SbfError::NotPositiveDefinite { what: "radiance-prior moment covariance (functions numerically dependent)" });
        }
        let chol = sigma.cholesky().ok_or(SbfError::NotPositiveDefinite { what: "radiance-prior moment covariance" })?;
        let transform = chol.solve(&gram);
        let kernels = coeffs
            .iter()
            .map(|c| {
                Kernel::new(
                    &(0..=lmax).map(|l| prior.power(l) * super::zonal::lambert_band_factor(l) / PI * c[l] * band(l)).collect::<Vec<_>>(),
                )
            })
            .collect();
        Ok(PriorIrradiance { axes, kernels, transform, gram, chol, prior, lmax, condition: hi / lo })
    }

    /// For an SG basis (its lobes, and its constant when it has one).
    #[cfg(feature = "sg")]
    pub fn for_sg_basis(basis: &crate::SgBasis, prior: RadiancePrior) -> Result<PriorIrradiance, SbfError> {
        let mut f: Vec<Zonal> = (0..basis.lobe_count())
            .map(|i| {
                let l = basis.lobe(i);
                Zonal::Lobe { axis: l.axis, sharpness: l.sharpness }
            })
            .collect();
        if basis.has_ambient() {
            f.push(Zonal::Constant);
        }
        PriorIrradiance::new(&f, prior)
    }

    /// Number of basis functions.
    pub fn len(&self) -> usize {
        self.axes.len()
    }

    /// Whether the basis is empty.
    pub fn is_empty(&self) -> bool {
        self.axes.is_empty()
    }

    /// The Gram matrix ⟨B_i, B_j⟩ from the Legendre series (C_l ≡ 1).
    pub fn series_gram(&self) -> &DMatrix<f64> {
        &self.gram
    }

    /// c' = Σ⁻¹ G c: the per-probe coefficients the runtime sum takes. Errors on a wrong length.
    pub fn coefficients(&self, c: &[f64]) -> Result<Vec<f64>, SbfError> {
        if c.len() != self.len() {
            return Err(SbfError::LengthMismatch { what: "prior irradiance coefficients", expected: self.len(), got: c.len() });
        }
        Ok((0..self.len()).map(|i| (0..self.len()).map(|j| self.transform[(i, j)] * c[j]).sum()).collect())
    }

    /// g_i(a_i·n) for every function: the weights of c' at normal n.
    pub fn weights(&self, n: DVec3, out: &mut [f64]) {
        assert_eq!(out.len(), self.len(), "one weight per basis function");
        for ((o, a), k) in out.iter_mut().zip(&self.axes).zip(&self.kernels) {
            *o = k.eval(a.dot(n).clamp(-1.0, 1.0));
        }
    }

    /// The estimate's expected squared error at n under the prior (radiance fields of
    /// bands ≤ the estimator's lmax): Var(E(n)/π) − g(n)ᵀ Σ⁻¹ g(n), with
    /// Var(E(n)/π) = Σ_l C_l (A_l/π)² (2l+1)/(4π).
    pub fn expected_squared_error(&self, n: DVec3) -> f64 {
        let var: f64 = (0..=self.lmax)
            .map(|l| self.prior.power(l) * (super::zonal::lambert_band_factor(l) / PI).powi(2) * (2 * l + 1) as f64 / (4.0 * PI))
            .sum();
        let mut g = vec![0.0; self.len()];
        self.weights(n, &mut g);
        let gv = nalgebra::DVector::from_vec(g);
        var - gv.dot(&self.chol.solve(&gv))
    }

    /// Ê(n)/π = Σ_i c'_i g_i(a_i·n) for c' from [`PriorIrradiance::coefficients`].
    pub fn eval(&self, c_prime: &[f64], n: DVec3) -> f64 {
        c_prime.iter().zip(self.axes.iter().zip(&self.kernels)).map(|(c, (a, k))| c * k.eval(a.dot(n).clamp(-1.0, 1.0))).sum()
    }
}
