//! Numerical quadrature on the sphere and hemisphere.
//!
//! The rule used everywhere is the product of Gauss–Legendre in z = cos θ and the
//! trapezoid rule in φ. It integrates any polynomial in (x, y, z) of degree
//! ≤ min(2·n_z − 1, n_φ − 1) exactly (Gauss–Legendre is exact to degree 2n − 1;
//! the periodic trapezoid rule with n_φ points is exact for trigonometric degree
//! < n_φ). For functions with kinks (clamped cosines) it converges algebraically;
//! callers estimate the error by comparing two resolutions ([`estimate_error`]).

use glam::DVec3;
use std::f64::consts::PI;

/// Gauss–Legendre nodes and weights on [-1, 1] (n ≥ 1), by Newton iteration on
/// P_n with the asymptotic initial guess cos(π(i − 1/4)/(n + 1/2)).
/// Accuracy: nodes to ~1e-15 for n up to several thousand.
///
/// # Panics
/// If `n == 0`.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 1, "gauss_legendre needs at least one node");
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    let m = n.div_ceil(2);
    for i in 0..m {
        let mut z = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            // Three-term recurrence for P_n(z) and its derivative.
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { z } else { p1 };
            let pnm1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (z * pn - pnm1) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    if n % 2 == 1 {
        x[n / 2] = 0.0;
    }
    (x, w)
}

/// Integration domain of a quadrature or a basis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Domain {
    /// The whole unit sphere (4π sr).
    Sphere,
    /// The upper hemisphere z ≥ 0 (tangent space, normal +Z; 2π sr).
    UpperHemisphere,
}

impl Domain {
    /// Solid angle of the domain.
    pub fn solid_angle(self) -> f64 {
        match self {
            Domain::Sphere => 4.0 * PI,
            Domain::UpperHemisphere => 2.0 * PI,
        }
    }
    /// Whether a unit direction lies in the (closed) domain.
    pub fn contains(self, d: DVec3) -> bool {
        match self {
            Domain::Sphere => true,
            Domain::UpperHemisphere => d.z >= 0.0,
        }
    }
    /// Short name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Domain::Sphere => "sphere",
            Domain::UpperHemisphere => "upper hemisphere",
        }
    }
}

/// A list of (direction, weight) pairs whose weights sum to the domain's solid angle.
#[derive(Debug, Clone)]
pub struct SphereQuadrature {
    /// Unit nodes.
    pub directions: Vec<DVec3>,
    /// Their weights (solid angle each node stands for).
    pub weights: Vec<f64>,
    /// The domain the rule covers.
    pub domain: Domain,
}

impl SphereQuadrature {
    /// Gauss–Legendre (n_z nodes in z) × trapezoid (n_phi nodes in φ) on `domain`.
    /// For the hemisphere, z ∈ [0, 1] is mapped affinely.
    pub fn gauss_product(domain: Domain, n_z: usize, n_phi: usize) -> Self {
        let (gx, gw) = gauss_legendre(n_z);
        let (z0, z1) = match domain {
            Domain::Sphere => (-1.0, 1.0),
            Domain::UpperHemisphere => (0.0, 1.0),
        };
        let half = 0.5 * (z1 - z0);
        let dphi = 2.0 * PI / n_phi as f64;
        let mut directions = Vec::with_capacity(n_z * n_phi);
        let mut weights = Vec::with_capacity(n_z * n_phi);
        for (xi, wi) in gx.iter().zip(&gw) {
            let z = z0 + half * (xi + 1.0);
            let r = (1.0 - z * z).max(0.0).sqrt();
            for j in 0..n_phi {
                // Offset by half a step so no node sits on φ = 0 seams.
                let phi = (j as f64 + 0.5) * dphi;
                directions.push(DVec3::new(r * phi.cos(), r * phi.sin(), z));
                weights.push(wi * half * dphi);
            }
        }
        SphereQuadrature { directions, weights, domain }
    }

    /// A rule exact for polynomials of total degree ≤ `degree` on the domain.
    pub fn exact_for_degree(domain: Domain, degree: usize) -> Self {
        let n_z = degree / 2 + 1;
        let n_phi = degree + 1;
        Self::gauss_product(domain, n_z, n_phi)
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// True when the rule has no nodes.
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// ∫ f over the domain, summed in node order (deterministic).
    pub fn integrate(&self, mut f: impl FnMut(DVec3) -> f64) -> f64 {
        let mut acc = KahanSum::default();
        for (d, w) in self.directions.iter().zip(&self.weights) {
            acc.add(w * f(*d));
        }
        acc.value()
    }
}

/// Compensated (Kahan–Babuška–Neumaier) summation: deterministic and accurate
/// to ~1 ulp of the result for the sums of many small weighted terms we do.
#[derive(Debug, Default, Clone, Copy)]
pub struct KahanSum {
    sum: f64,
    c: f64,
}

impl KahanSum {
    /// Adds `x`, carrying the rounding error (Neumaier's variant of Kahan summation).
    pub fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.c += (self.sum - t) + x;
        } else {
            self.c += (x - t) + self.sum;
        }
        self.sum = t;
    }
    /// The compensated sum so far.
    pub fn value(&self) -> f64 {
        self.sum + self.c
    }
}

/// Error estimate of a quadrature: |coarse − fine| elementwise maximum. Used by the
/// Gram matrix for non-polynomial bases; it overestimates the fine rule's error when
/// the rule converges (which both our rules do for continuous integrands).
pub fn estimate_error(coarse: &[f64], fine: &[f64]) -> f64 {
    coarse.iter().zip(fine).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
}
