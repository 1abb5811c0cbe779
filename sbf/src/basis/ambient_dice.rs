//! Ambient Dice (Iwanicki & Sloan 2017) on the icosahedron: geometry, the
//! cosine-lobe SRBF variant (12 lobes, and the 9-lobe hemisphere set of \[Roughton19\]
//! §8.3.1) and a piecewise-linear variant (used for chroma by YCoCg).
//!
//! SRBF lobe ([Roughton19 eq. 8.3]/8.4): B(c) = 0.7·½c² + 0.3·⅚c⁴ = 0.35c² + 0.25c⁴ for
//! c = v·p > 0, else 0. Each of ½c² and ⅚c⁴ sums to 1 over the 12 icosahedron
//! vertices (a spherical 5-design), so the 12 lobes are a partition of unity.

pub use super::icosahedron::{Icosahedron, ICOSAHEDRON_EDGE_COS, ICOSAHEDRON_T};
use super::Basis;
use crate::error::SbfError;
use crate::quadrature::Domain;
use glam::DVec3;

/// Cosine-lobe SRBF profile B(c) = 0.35c² + 0.25c⁴ for c > 0, else 0 ([Roughton19 eq. 8.3]).
#[inline]
pub fn srbf_lobe(c: f64) -> f64 {
    if c > 0.0 {
        let c2 = c * c;
        c2 * (0.35 + 0.25 * c2)
    } else {
        0.0
    }
}

/// f32 twin of [`srbf_lobe`].
#[inline]
pub fn srbf_lobe_f32(c: f32) -> f32 {
    let c = c.max(0.0);
    let c2 = c * c;
    c2 * (0.35 + 0.25 * c2)
}

/// Ambient Dice cosine-lobe SRBF basis: B_i(v) = srbf_lobe(v·p_i).
#[derive(Debug, Clone, PartialEq)]
pub struct AmbientDiceSrbf {
    lobes: Vec<DVec3>,
    domain: Domain,
    name: String,
}

impl AmbientDiceSrbf {
    /// 12 lobes on the standard icosahedron (sphere). Partition of unity.
    pub fn twelve() -> Self {
        AmbientDiceSrbf { lobes: Icosahedron::standard().vertices().to_vec(), domain: Domain::Sphere, name: "AD SRBF 12".into() }
    }

    /// The 9-lobe hemisphere set of [Roughton19 §8.3.1]: the icosahedron with a face
    /// centred on +Z, minus the three vertices of the bottom face. Fitted on the
    /// upper hemisphere (tangent space, normal +Z).
    pub fn nine_hemisphere() -> Self {
        let ico = Icosahedron::face_up();
        AmbientDiceSrbf { lobes: ico.vertices()[..9].to_vec(), domain: Domain::UpperHemisphere, name: "AD SRBF 9 (hemisphere)".into() }
    }

    /// Arbitrary lobe axes (normalised), on the given domain.
    pub fn from_axes(axes: &[DVec3], domain: Domain) -> Result<Self, SbfError> {
        let lobes = axes.iter().map(|a| crate::error::normalize_direction(*a)).collect::<Result<Vec<_>, _>>()?;
        if lobes.is_empty() {
            return Err(SbfError::InvalidParameter { name: "AD lobe count", value: 0.0, reason: "need at least one lobe" });
        }
        Ok(AmbientDiceSrbf { name: format!("AD SRBF {}", lobes.len()), lobes, domain })
    }

    /// Unit lobe axes.
    pub fn lobes(&self) -> &[DVec3] {
        &self.lobes
    }
}

impl Basis for AmbientDiceSrbf {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn len(&self) -> usize {
        self.lobes.len()
    }
    fn domain(&self) -> Domain {
        self.domain
    }
    fn eval_into(&self, dir: DVec3, out: &mut [f64]) {
        debug_assert!(super::is_unit(dir), "direction must be unit length: {dir:?}");
        // A short or long `out` would silently drop lobes or leave stale values.
        assert_eq!(out.len(), self.lobes.len(), "AmbientDiceSrbf::eval_into: out has {} values for {} lobes", out.len(), self.lobes.len());
        for (o, p) in out.iter_mut().zip(&self.lobes) {
            *o = srbf_lobe(dir.dot(*p));
        }
    }
}

/// Piecewise-linear interpolation over the icosahedron's spherical triangles:
/// weights are the gnomonic barycentrics normalised to sum to 1 (a partition of
/// unity that reproduces constants exactly). Used for Co/Cg in [`super::AmbientDiceYCoCg`].
#[derive(Debug, Clone)]
pub struct AmbientDiceLinear {
    ico: Icosahedron,
}

impl AmbientDiceLinear {
    /// On the standard icosahedron.
    pub fn new() -> Self {
        AmbientDiceLinear { ico: Icosahedron::standard() }
    }
    /// The underlying geometry.
    pub fn icosahedron(&self) -> &Icosahedron {
        &self.ico
    }
}

impl Default for AmbientDiceLinear {
    fn default() -> Self {
        Self::new()
    }
}

impl Basis for AmbientDiceLinear {
    fn name(&self) -> String {
        "AD linear 12".into()
    }
    fn len(&self) -> usize {
        12
    }
    fn domain(&self) -> Domain {
        Domain::Sphere
    }
    fn eval_into(&self, dir: DVec3, out: &mut [f64]) {
        debug_assert!(super::is_unit(dir), "direction must be unit length: {dir:?}");
        assert_eq!(out.len(), 12, "AmbientDiceLinear::eval_into: out has {} values for 12 vertices", out.len());
        out.fill(0.0);
        let (f, b) = self.ico.locate(dir);
        let s = b[0] + b[1] + b[2]; // ≥ 1 for unit d inside the face
        for k in 0..3 {
            out[self.ico.faces()[f][k]] = b[k] / s;
        }
    }
}
