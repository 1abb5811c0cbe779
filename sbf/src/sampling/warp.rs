//! Warps from [0,1)² to directions, with pdfs (w.r.t. solid angle or area) and
//! inverses.

use glam::{DVec2, DVec3};
use std::f64::consts::{FRAC_PI_4, PI};

/// Uniform direction on the unit sphere (Archimedes): z = 1 − 2u₀, φ = 2πu₁.
pub fn uniform_sphere(u: [f64; 2]) -> DVec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`uniform_sphere`] w.r.t. solid angle: 1/(4π).
pub const UNIFORM_SPHERE_PDF: f64 = 1.0 / (4.0 * PI);

/// Inverse of [`uniform_sphere`] for a unit direction.
pub fn uniform_sphere_inv(d: DVec3) -> [f64; 2] {
    [(1.0 - d.z) * 0.5, phi_unit(d)]
}

/// Uniform direction on the upper hemisphere: z = 1 − u₀, φ = 2πu₁.
pub fn uniform_hemisphere(u: [f64; 2]) -> DVec3 {
    let z = 1.0 - u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`uniform_hemisphere`]: 1/(2π) on z ≥ 0.
pub const UNIFORM_HEMISPHERE_PDF: f64 = 1.0 / (2.0 * PI);

/// Inverse of [`uniform_hemisphere`] for a unit direction with z ≥ 0.
pub fn uniform_hemisphere_inv(d: DVec3) -> [f64; 2] {
    [1.0 - d.z, phi_unit(d)]
}

/// φ/(2π) in [0, 1).
fn phi_unit(d: DVec3) -> f64 {
    let p = d.y.atan2(d.x) / (2.0 * PI);
    let p = if p < 0.0 { p + 1.0 } else { p };
    if p >= 1.0 {
        0.0
    } else {
        p
    }
}

/// Shirley–Chiu concentric map from [0,1)² to the unit disk (area-preserving up
/// to the constant π: pdf 1/π w.r.t. area).
pub fn concentric_disk(u: [f64; 2]) -> DVec2 {
    let a = 2.0 * u[0] - 1.0;
    let b = 2.0 * u[1] - 1.0;
    if a == 0.0 && b == 0.0 {
        return DVec2::ZERO;
    }
    let (r, theta) = if a.abs() > b.abs() { (a, FRAC_PI_4 * (b / a)) } else { (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b)) };
    DVec2::new(r * theta.cos(), r * theta.sin())
}

/// Density of [`concentric_disk`] w.r.t. area: 1/π.
pub const CONCENTRIC_DISK_PDF: f64 = 1.0 / PI;

/// Inverse of [`concentric_disk`] for a point in the closed unit disk.
pub fn concentric_disk_inv(p: DVec2) -> [f64; 2] {
    let r = p.length();
    if r == 0.0 {
        return [0.5, 0.5];
    }
    // θ ∈ (−π, π]; pick the wedge by comparing |x| and |y|.
    let theta = p.y.atan2(p.x);
    let (a, b) = if p.x.abs() >= p.y.abs() {
        // a = ±r; θ = (π/4)(b/a) with θ measured from the ±x axis.
        let a = if p.x >= 0.0 { r } else { -r };
        let t = if p.x >= 0.0 { theta } else { wrap_pi(theta - PI) };
        (a, t / FRAC_PI_4 * a)
    } else {
        let b = if p.y >= 0.0 { r } else { -r };
        // θ = π/2 − (π/4)(a/b), measured for b > 0; for b < 0 rotate by π.
        let t = if p.y >= 0.0 { theta } else { wrap_pi(theta + PI) };
        (((2.0 * FRAC_PI_4 - t) / FRAC_PI_4) * b, b)
    };
    [(a + 1.0) * 0.5, (b + 1.0) * 0.5]
}

fn wrap_pi(t: f64) -> f64 {
    if t > PI {
        t - 2.0 * PI
    } else if t <= -PI {
        t + 2.0 * PI
    } else {
        t
    }
}

/// Uniform hemisphere direction through the concentric disk: [0,1)² → disk (Shirley–Chiu,
/// area-preserving) → hemisphere by z = 1 − r², (x, y) = p·√(2 − r²) (the disk's area
/// element r dr dφ maps to dz dφ/2, so equal areas of the square are equal solid angles:
/// pdf 1/2π). Ray guiding bins directions on this square (\[HWRTL\], "concentric mapping").
pub fn uniform_hemisphere_concentric(u: [f64; 2]) -> DVec3 {
    let p = concentric_disk(u);
    let r2 = p.length_squared().min(1.0);
    let s = (2.0 - r2).sqrt();
    DVec3::new(p.x * s, p.y * s, 1.0 - r2)
}

/// Inverse of [`uniform_hemisphere_concentric`] for a unit direction with z ≥ 0 (z < 0
/// is treated as the horizon).
pub fn uniform_hemisphere_concentric_inv(d: DVec3) -> [f64; 2] {
    // r² = 1 − z; |p| = sinθ/√(1 + z) = √(1 − z) for a unit d (written with sinθ so a
    // slightly non-unit d keeps its azimuth).
    let z = d.z.clamp(0.0, 1.0);
    let p = DVec2::new(d.x, d.y) / (1.0 + z).sqrt();
    concentric_disk_inv(if p.length_squared() > 1.0 { p.normalize() } else { p })
}

/// Cosine-weighted hemisphere direction (Malley's method on the concentric disk).
pub fn cosine_hemisphere(u: [f64; 2]) -> DVec3 {
    let p = concentric_disk(u);
    let z = (1.0 - p.length_squared()).max(0.0).sqrt();
    DVec3::new(p.x, p.y, z)
}

/// Density of [`cosine_hemisphere`] w.r.t. solid angle: cos θ/π.
pub fn cosine_hemisphere_pdf(d: DVec3) -> f64 {
    d.z.max(0.0) / PI
}

/// Inverse of [`cosine_hemisphere`].
pub fn cosine_hemisphere_inv(d: DVec3) -> [f64; 2] {
    concentric_disk_inv(DVec2::new(d.x, d.y))
}

/// Point i of the n-point spherical Fibonacci set (Keinert et al. 2015, with the
/// golden-angle spiral of [`crate::layout::vogel_sphere`]): z = 1 − (2i + 1)/n,
/// φ = i·π(3 − √5). Each point represents 4π/n sr.
pub fn spherical_fibonacci(i: u64, n: u64) -> DVec3 {
    debug_assert!(i < n);
    let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = i as f64 * crate::layout::GOLDEN_ANGLE;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Inverse of [`spherical_fibonacci`]: the index of the point nearest to unit `d`.
///
/// Exact: any point closer than the best candidate found must lie in the z band
/// |z_i − d.z| < chord distance (|Δz| ≤ chord), so the search widens the band until
/// it covers the best chord distance. Cost O(√n) per query.
///
/// # Panics
/// If `n == 0` (there is no nearest point of an empty set).
pub fn spherical_fibonacci_nearest(d: DVec3, n: u64) -> u64 {
    assert!(n > 0, "spherical_fibonacci_nearest needs n > 0");
    let nf = n as f64;
    let index_of_z = |z: f64| ((1.0 - z) * nf * 0.5 - 0.5).clamp(0.0, nf - 1.0);
    let mut band = 4.0 / nf.sqrt();
    loop {
        let lo = index_of_z(d.z + band).floor() as u64;
        let hi = (index_of_z(d.z - band).ceil() as u64).min(n - 1);
        let mut best = (f64::INFINITY, 0u64);
        for i in lo..=hi {
            let c = (spherical_fibonacci(i, n) - d).length_squared();
            if c < best.0 {
                best = (c, i);
            }
        }
        if best.0.sqrt() <= band || band >= 2.0 {
            return best.1;
        }
        band *= 2.0;
    }
}
