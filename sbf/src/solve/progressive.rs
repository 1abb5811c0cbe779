//! Progressive (per-sample) least squares and non-negative least squares
//! ([Roughton19 §7.3, Listing 7.1]), plus the naive projection and the "running
//! average" found in public tools, for comparison.
//!
//! Per sample (direction ω, RGB value f, weight w), with W the running total weight
//! and s = w/W (= 1/k for unit weights):
//!   Δ = f − Σ_j b_j B_j(ω)
//!   I_i ← I_i + s·(B_i(ω)² − I_i)                      (running mean of B_i²)
//!   Ī_i = s + (1 − s)·I_i                              (eq. 7.15; Listing 7.1's
//!                                                      parenthesis differs — we follow the equation)
//!   b_i ← b_i + α·s·B_i(ω)·Δ/Ī_i,   optionally b_i ← max(b_i, 0)
//!   Gauss–Seidel: Δ ← Δ − B_i(ω)·(b_i,new − b_i,old)  (= the listing's Δ·(1 − α·s·B_i²/Ī)
//!                                                      without the clamp; exact with it)
//! Jacobi uses the Δ computed before any lobe moves.
//!
//! **Known projections** ([`ProgressiveEncoder::update_projected`]): a sample may carry,
//! besides its value at ω, a vector q_i that is an unbiased estimate of
//! p(ω)·∫B_i(ω')L'(ω')dω' for radiance L' that point samples cannot reach — delta lights
//! (directional, point, spot: q_i = p(ω)·E·B_i(ω_l)·V) or light samples combined with
//! the point sample by multiple importance sampling (q_i = p(ω)·w_l·B_i(ω_l)L(ω_l)/p_l).
//! p(ω) is the pdf of the point sample's direction. The lobe update becomes
//!   b_i ← b_i + α·s·(B_i(ω)·Δ + q_i)/Ī_i
//! Its expectation per unit weight is (1/Ω)(∫B_i(L + L') − (Gb)_i) for uniform ω, so the
//! stochastic iteration converges to the LS (or, with the clamp, NNLS) fit of L + L' —
//! the normal equations of a delta light are well defined although its radiance is not
//! a function ([Roughton19 §6.1] explains why such lights need explicit sampling).
//!
//! **Sample order matters.** The update is a stochastic iteration: consecutive samples
//! must be decorrelated (Halton, R2, shuffled). A Hammersley set consumed in index
//! order sweeps one coordinate monotonically and the encoder chases it ([Roughton19 Fig. 7.6];
//! a test shows the error gap).
//!
//! The encoder state is exactly what a GPU texel stores: per lobe an RGB amplitude
//! and the running ∫B², plus one total weight. [`ProgressiveEncoder<f32>`] keeps that
//! state and does the arithmetic in f32, to show the precision effect the seed
//! describes; [`ProgressiveEncoder<f64>`] is the reference.

use super::RadianceSample;
use crate::basis::Basis;
use crate::error::SbfError;
use glam::DVec3;
use nalgebra::DMatrix;

/// Floating-point storage for the encoder state (f32 as on a GPU, or f64).
pub trait Real:
    Copy
    + std::fmt::Debug
    + PartialOrd
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// `x` rounded to this type.
    fn from_f64(x: f64) -> Self;
    /// The value as f64 (exact).
    fn to_f64(self) -> f64;
    /// The larger of the two.
    fn max(self, o: Self) -> Self;
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
    fn max(self, o: Self) -> Self {
        f32::max(self, o)
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn max(self, o: Self) -> Self {
        f64::max(self, o)
    }
}

/// Order of lobe updates within a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Iteration {
    /// Every lobe updated from the residual before the sample's updates.
    Jacobi,
    /// Each lobe updated from the residual after the lobes before it (Roughton's choice).
    GaussSeidel,
}

/// Denominator used for lobe i.
#[derive(Debug, Clone, PartialEq)]
pub enum Denominator {
    /// Eq. 7.15: s + (1 − s)·I_i, blending from the naive 1 to the running ∫B².
    Blend,
    /// max(I_i, true ∫B_i²): Roughton's first mitigation, and the public "running
    /// average" (after Pettineo's SG series, as in Probulator). Values are the exact
    /// ∫B_i² divided by the domain's solid angle (the mean of B_i² per unit weight).
    ClampToTrue(Vec<f64>),
    /// The raw running mean I_i (noisy at low counts; for comparison).
    Raw,
    /// No residual: b_i is the running mean of the projection (B_i(ω)·f + q_i)/t_i, t_i the
    /// exact mean of B_i² per unit weight (as in [`Denominator::ClampToTrue`]). For a basis
    /// orthogonal over the sampled measure (SH over the sphere, or over the upper hemisphere
    /// with mirrored zero samples) that is the Monte Carlo projection ∫B_i f / ∫B_i²:
    /// unbiased after any number of samples (with unit weights), where the residual update's
    /// ratio of running means converges from below at low counts. The acceleration is not
    /// used; the non-negative clamp still applies.
    Projection(Vec<f64>),
}

/// Options of the progressive encoder.
#[derive(Debug, Clone, PartialEq)]
pub struct ProgressiveOptions {
    /// Acceleration α (seed: 1–5, 3 converges fastest).
    pub acceleration: f64,
    /// Jacobi or Gauss–Seidel updates within a sample.
    pub iteration: Iteration,
    /// Clamp amplitudes to ≥ 0 after every update (progressive NNLS).
    pub non_negative: bool,
    /// Hemisphere samples in a sphere solve: after each sample at ω, add a
    /// zero-radiance sample of the same weight at ω mirrored below the tangent plane
    /// (z → −z).
    pub mirror_hemisphere: bool,
    /// The per-lobe step's denominator.
    pub denominator: Denominator,
}

impl Default for ProgressiveOptions {
    /// Roughton's recommendation: Gauss–Seidel, α = 3, eq. 7.15, no clamp, no mirror.
    fn default() -> Self {
        ProgressiveOptions {
            acceleration: 3.0,
            iteration: Iteration::GaussSeidel,
            non_negative: false,
            mirror_hemisphere: false,
            denominator: Denominator::Blend,
        }
    }
}

impl ProgressiveOptions {
    /// Progressive NNLS: the default with the non-negative clamp.
    pub fn non_negative() -> Self {
        ProgressiveOptions { non_negative: true, ..Self::default() }
    }
    /// The Monte Carlo projection ([`Denominator::Projection`]) with `exact_mean_b2` the
    /// exact mean of B_i² per unit weight over the sampled measure (1/4π for every
    /// orthonormal SH function over the sphere).
    pub fn projection(exact_mean_b2: Vec<f64>, non_negative: bool) -> Self {
        ProgressiveOptions { non_negative, denominator: Denominator::Projection(exact_mean_b2), ..Self::default() }
    }
    /// The public "running average" for a basis: Jacobi, α = 1, denominator clamped
    /// to the exact mean of B_i² over `domain_gram_diagonal`/solid angle.
    pub fn running_average(gram_diagonal: &[f64], solid_angle: f64, non_negative: bool) -> Self {
        ProgressiveOptions {
            acceleration: 1.0,
            iteration: Iteration::Jacobi,
            non_negative,
            mirror_hemisphere: false,
            denominator: Denominator::ClampToTrue(gram_diagonal.iter().map(|g| g / solid_angle).collect()),
        }
    }
}

/// Progressive per-sample encoder; state in `T` (f32 like a GPU texel, or f64).
#[derive(Debug, Clone)]
pub struct ProgressiveEncoder<T: Real> {
    opts: ProgressiveOptions,
    amplitudes: Vec<[T; 3]>,
    integrals: Vec<T>,
    total_weight: T,
    samples: u64,
    scratch: Vec<f64>,
    scratch_t: Vec<T>,
}

impl<T: Real> ProgressiveEncoder<T> {
    /// An empty encoder for `n` lobes.
    pub fn new(n: usize, opts: ProgressiveOptions) -> Self {
        ProgressiveEncoder {
            opts,
            amplitudes: vec![[T::ZERO; 3]; n],
            integrals: vec![T::ZERO; n],
            total_weight: T::ZERO,
            samples: 0,
            scratch: vec![0.0; n],
            scratch_t: vec![T::ZERO; n],
        }
    }

    /// Rebuilds an encoder from saved state (a checkpoint, or a GPU texel read back):
    /// per-lobe RGB amplitudes, running means of B_i², total weight and update count.
    /// Values are converted to `T` (exact for state that was saved from a `T` encoder).
    /// Mismatched lengths, non-finite values or a negative weight are errors.
    pub fn from_state(
        opts: ProgressiveOptions,
        amplitudes: &[[f64; 3]],
        integrals: &[f64],
        total_weight: f64,
        samples: u64,
    ) -> Result<Self, SbfError> {
        crate::error::check_len("saved integrals vs amplitudes", amplitudes.len(), integrals.len())?;
        if let Some(v) = amplitudes.iter().flatten().chain(integrals).find(|v| !v.is_finite()) {
            return Err(SbfError::InvalidParameter { name: "saved progressive state", value: *v, reason: "must be finite" });
        }
        if !(total_weight.is_finite() && total_weight >= 0.0) {
            return Err(SbfError::InvalidParameter { name: "saved total weight", value: total_weight, reason: "must be finite and >= 0" });
        }
        let mut e = Self::new(amplitudes.len(), opts);
        for (dst, src) in e.amplitudes.iter_mut().zip(amplitudes) {
            *dst = src.map(T::from_f64);
        }
        for (dst, src) in e.integrals.iter_mut().zip(integrals) {
            *dst = T::from_f64(*src);
        }
        e.total_weight = T::from_f64(total_weight);
        e.samples = samples;
        Ok(e)
    }

    /// The options this encoder runs with.
    pub fn options(&self) -> &ProgressiveOptions {
        &self.opts
    }

    /// Adds one sample (and its mirrored zero twin if configured). Zero-weight
    /// samples are ignored; a negative or non-finite weight, a non-finite value, or a
    /// basis of the wrong size is an error (the state is left unchanged).
    pub fn add_sample(&mut self, basis: &dyn Basis, direction: DVec3, value: [f64; 3], weight: f64) -> Result<(), SbfError> {
        crate::error::check_len("basis size vs encoder lobes", self.amplitudes.len(), basis.len())?;
        if !weight.is_finite() || weight < 0.0 {
            return Err(SbfError::InvalidParameter { name: "sample weight", value: weight, reason: "must be finite and >= 0" });
        }
        if let Some(v) = value.iter().find(|v| !v.is_finite()) {
            return Err(SbfError::InvalidParameter { name: "sample value", value: *v, reason: "must be finite" });
        }
        if weight == 0.0 {
            return Ok(());
        }
        let mut b = std::mem::take(&mut self.scratch);
        basis.eval_into(direction, &mut b);
        self.update(&b, value, weight);
        if self.opts.mirror_hemisphere {
            basis.eval_into(DVec3::new(direction.x, direction.y, -direction.z), &mut b);
            self.update(&b, [0.0; 3], weight);
        }
        self.scratch = b;
        Ok(())
    }

    /// [`Self::add_sample`] plus known projections from `lights`: pairs (direction ω_l,
    /// RGB c_l) with q_i = Σ_l B_i(ω_l)·c_l, where c_l is already scaled by the point
    /// sample's pdf (module documentation). The mirrored twin, if configured, carries
    /// none. Non-finite light values are errors (the state is left unchanged).
    pub fn add_sample_projected(
        &mut self,
        basis: &dyn Basis,
        direction: DVec3,
        value: [f64; 3],
        weight: f64,
        lights: &[(DVec3, [f64; 3])],
    ) -> Result<(), SbfError> {
        if lights.is_empty() {
            return self.add_sample(basis, direction, value, weight);
        }
        crate::error::check_len("basis size vs encoder lobes", self.amplitudes.len(), basis.len())?;
        if !weight.is_finite() || weight < 0.0 {
            return Err(SbfError::InvalidParameter { name: "sample weight", value: weight, reason: "must be finite and >= 0" });
        }
        if let Some(v) = value.iter().chain(lights.iter().flat_map(|l| l.1.iter())).find(|v| !v.is_finite()) {
            return Err(SbfError::InvalidParameter { name: "sample or light value", value: *v, reason: "must be finite" });
        }
        if weight == 0.0 {
            return Ok(());
        }
        let n = self.amplitudes.len();
        let mut b = std::mem::take(&mut self.scratch);
        let mut q = vec![[0.0f64; 3]; n];
        for (d, c) in lights {
            basis.eval_into(*d, &mut b);
            for i in 0..n {
                for ch in 0..3 {
                    q[i][ch] += b[i] * c[ch];
                }
            }
        }
        basis.eval_into(direction, &mut b);
        self.update_projected(&b, value, weight, &q);
        if self.opts.mirror_hemisphere {
            basis.eval_into(DVec3::new(direction.x, direction.y, -direction.z), &mut b);
            self.update(&b, [0.0; 3], weight);
        }
        self.scratch = b;
        Ok(())
    }

    /// Adds a [`RadianceSample`] (see [`Self::add_sample`]).
    pub fn add(&mut self, basis: &dyn Basis, s: &RadianceSample) -> Result<(), SbfError> {
        self.add_sample(basis, s.direction, s.value, s.weight)
    }

    /// One update with precomputed basis values `b` (the GPU kernel's body).
    /// Preconditions (debug-asserted): `b.len()` = lobes, `weight` > 0 and finite.
    pub fn update(&mut self, b: &[f64], value: [f64; 3], weight: f64) {
        self.update_projected(b, value, weight, &[]);
    }

    /// [`Self::update`] with known projections `q` (one RGB vector per lobe, or empty
    /// for none; see the module documentation): lobe i moves by α·s·(B_i·Δ + q_i)/Ī_i.
    /// The WGSL twin is `progressive_update_projected`.
    pub fn update_projected(&mut self, b: &[f64], value: [f64; 3], weight: f64, q: &[[f64; 3]]) {
        debug_assert_eq!(b.len(), self.amplitudes.len());
        debug_assert!(q.is_empty() || q.len() == b.len());
        debug_assert!(weight > 0.0 && weight.is_finite());
        let n = self.amplitudes.len();
        self.samples += 1;
        self.total_weight = self.total_weight + T::from_f64(weight);
        let s = T::from_f64(weight) / self.total_weight;
        let acc = T::from_f64(self.opts.acceleration);
        let bt = &mut self.scratch_t;
        for i in 0..n {
            bt[i] = T::from_f64(b[i]);
        }
        let value_t = [T::from_f64(value[0]), T::from_f64(value[1]), T::from_f64(value[2])];
        let mut delta = value_t;
        for i in 0..n {
            for c in 0..3 {
                delta[c] = delta[c] - self.amplitudes[i][c] * bt[i];
            }
        }
        for i in 0..n {
            let bi = bt[i];
            self.integrals[i] = self.integrals[i] + s * (bi * bi - self.integrals[i]);
            let denom = match &self.opts.denominator {
                Denominator::Blend => s + (T::ONE - s) * self.integrals[i],
                Denominator::ClampToTrue(t) => self.integrals[i].max(T::from_f64(t[i])),
                Denominator::Raw => self.integrals[i],
                Denominator::Projection(t) => {
                    let ti = T::from_f64(t[i]);
                    if ti.partial_cmp(&T::ZERO) != Some(std::cmp::Ordering::Greater) {
                        continue; // not a mean of B_i²: the amplitude stays
                    }
                    for c in 0..3 {
                        let old = self.amplitudes[i][c];
                        let f = match q.get(i) {
                            Some(qi) => bi * value_t[c] + T::from_f64(qi[c]),
                            None => bi * value_t[c],
                        };
                        let mut new = old + s * (f / ti - old);
                        if self.opts.non_negative {
                            new = new.max(T::ZERO);
                        }
                        self.amplitudes[i][c] = new;
                    }
                    continue;
                }
            };
            if denom.partial_cmp(&T::ZERO) != Some(std::cmp::Ordering::Greater) {
                continue; // B_i has been zero on every sample so far
            }
            let scale = acc * s / denom;
            for c in 0..3 {
                let old = self.amplitudes[i][c];
                let g = match q.get(i) {
                    Some(qi) => bi * delta[c] + T::from_f64(qi[c]),
                    None => bi * delta[c],
                };
                let mut new = old + scale * g;
                if self.opts.non_negative {
                    new = new.max(T::ZERO);
                }
                self.amplitudes[i][c] = new;
                if self.opts.iteration == Iteration::GaussSeidel {
                    delta[c] = delta[c] - bi * (new - old);
                }
            }
        }
    }

    /// Current coefficients (n × 3, f64).
    pub fn coefficients(&self) -> DMatrix<f64> {
        DMatrix::from_fn(self.amplitudes.len(), 3, |i, c| self.amplitudes[i][c].to_f64())
    }
    /// The RGB amplitudes per lobe as stored (no copy: [`Self::coefficients`] in `T`).
    pub fn amplitudes(&self) -> &[[T; 3]] {
        &self.amplitudes
    }
    /// The running means of B_i² per lobe as stored (no copy: [`Self::integrals`] in `T`).
    pub fn lobe_integrals(&self) -> &[T] {
        &self.integrals
    }
    /// Running mean of B_i² per lobe (the GPU's per-lobe alpha channel).
    pub fn integrals(&self) -> Vec<f64> {
        self.integrals.iter().map(|v| v.to_f64()).collect()
    }
    /// Total accumulated weight.
    pub fn total_weight(&self) -> f64 {
        self.total_weight.to_f64()
    }
    /// Number of updates applied (mirrored twins included).
    pub fn sample_count(&self) -> u64 {
        self.samples
    }
    /// Bytes of state per texel for RGB: (3 amplitudes + 1 integral) per lobe + 1 weight.
    pub fn state_bytes(&self) -> usize {
        (4 * self.amplitudes.len() + 1) * std::mem::size_of::<T>()
    }
}

/// Naive projection (Pettineo & Neubelt's "as if orthonormal", [Roughton19 §7.2] footnote 2):
/// b_i = m_i / G_ii, i.e. the Gram matrix replaced by its diagonal.
pub fn naive_projection(moments: &DMatrix<f64>, gram_diagonal: &[f64]) -> DMatrix<f64> {
    DMatrix::from_fn(moments.nrows(), moments.ncols(), |i, c| moments[(i, c)] / gram_diagonal[i])
}
