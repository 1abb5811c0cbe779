//! Encodes and decodes of the engine formats ([`super::EngineFormat`]; the module docs there
//! give the decodes and their sources).
//!
//! Encodes, from the linear L1 irradiance E/π = a₀ + a₁·n of each channel
//! ([`L1Irradiance`], from SH L1 radiance coefficients):
//! - Godot: L0 = a₀, s = a₁/(8a₀) + ½ (Godot's own packing; s ∈ [¼, ¾] for any
//!   non-negative radiance, since |a₁| ≤ 2a₀). The decode then returns a₀ + a₁·n: the
//!   L1 irradiance itself. (Godot's own baker scales its direct lights' L1 to a ratio of
//!   4 — the comments in `lm_compute.glsl` — not the Lambert ratio 2 used here.)
//! - Godot 4.0–4.3: L0 = a₀/0.282095, l = a₁/0.32573 (the inverse of its decode's rounded
//!   constants, so the decode returns a₀ + a₁·n exactly; Godot's baker stores the SH
//!   coefficients c with exact constants: a relative difference of 2·10⁻⁵ in L1). Signed,
//!   never clamped.
//! - MonoSH (both decodes store the same textures): L0 = a₀ per channel, one direction d = Y(a₁)/(2·Y(a₀)) with Y the Rec. 709
//!   luminance (Bakery's format stores the luminance L1; its encoder is not published).
//!   For radiance from one colour the linear decode is the L1 irradiance exactly; the
//!   non-linear one is Geomerics' curve through it (exact for a single delta light at
//!   the light's direction).
//! - Enlighten: d = ∫Y(L)ω dω/∫Y(L) dω, the luminance-weighted mean incident direction
//!   (length 1 for one direction, ½ for a uniform hemisphere, as the SDK describes), from
//!   the radiance's moments over what the texel or probe sees ([`Moments`], from SH L1:
//!   d = Y(a₁)/(2·Y(a₀)), MonoSH's vector, where the radiance is zero below a texel); C = E/π at the baking normal n₀ (the caller's exact value), and the
//!   rescaling factor w = ½(1 + n₀·d) (BakingLab's encoder: `dot(tau, (d, 1))`,
//!   τ = ½(n₀, 1)), so the decode returns C exactly at n₀ and C·(1 + n·d)/(1 + n₀·d)
//!   elsewhere — half the directional contrast of the L1 irradiance (1 + 2d·n).
//!
//! Values a texture cannot hold (a unit channel outside [0, 1], a direction longer than
//! 1) are clamped as the engines' packers clamp, and counted in [`Encoded::clamped`].

use super::{Channel, EngineFormat};
use crate::recon::sh::{geomerics_l1, LUMINANCE};
use glam::DVec3;
use std::f64::consts::PI;

/// Godot's SH layers after L0: the world axis of each (l1n1 ∝ y, l1_0 ∝ z, l1p1 ∝ x).
const GODOT_LAYER_AXES: [usize; 3] = [1, 2, 0];
/// Godot 4.0–4.3's decode constants: Y₀₀ and (2/3)·0.488603, as typed in its shader.
const GODOT_Y00: f64 = 0.282095;
const GODOT_L1: f64 = 0.32573;

/// Linear L1 irradiance of each channel: E/π(n) = a₀ + a₁·n.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct L1Irradiance {
    /// a₀ per channel.
    pub a0: [f64; 3],
    /// a₁ per channel.
    pub a1: [DVec3; 3],
}

impl L1Irradiance {
    /// From SH L1 radiance coefficients per channel (order Y₀₀, Y₁₋₁ ∝ y, Y₁₀ ∝ z,
    /// Y₁₁ ∝ x, as [`crate::basis::sh`]): a₀ = c₀/(2√π), a₁ = (2/3)√(3/4π)·(c₃, c₁, c₂)
    /// (Ramamoorthi & Hanrahan 2001: A₀ = π, A₁ = 2π/3, divided by π).
    pub fn from_sh(rgb: &[[f64; 4]; 3]) -> L1Irradiance {
        let k0 = 0.5 / PI.sqrt();
        let k1 = (2.0 / 3.0) * (3.0 / (4.0 * PI)).sqrt();
        L1Irradiance { a0: rgb.map(|c| c[0] * k0), a1: rgb.map(|c| DVec3::new(c[3], c[1], c[2]) * k1) }
    }

    /// E/π at `n` (linear, unclamped).
    pub fn eval(&self, n: DVec3) -> [f64; 3] {
        [0, 1, 2].map(|k| self.a0[k] + self.a1[k].dot(n))
    }

    /// The luminance-weighted direction Y(a₁)/(2·Y(a₀)): MonoSH's L1 (over the sphere also
    /// Enlighten's dominant direction, [`Moments::sphere`]); zero when Y(a₀) ≤ 0.
    pub fn luminance_direction(&self) -> DVec3 {
        let y0: f64 = (0..3).map(|k| LUMINANCE[k] * self.a0[k]).sum();
        let y1: DVec3 = (0..3).map(|k| self.a1[k] * LUMINANCE[k]).sum();
        if y0 > 0.0 {
            y1 / (2.0 * y0)
        } else {
            DVec3::ZERO
        }
    }
}

/// The radiance's moments per channel over a domain: m₀ = ∫L dω and m₁ = ∫L·ω dω —
/// what Enlighten's dominant direction m₁/m₀ summarises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    /// m₀ per channel.
    pub m0: [f64; 3],
    /// m₁ per channel.
    pub m1: [DVec3; 3],
}

impl Moments {
    /// Over the sphere, of radiance with SH L1 projection `rgb` (order as
    /// [`L1Irradiance::from_sh`]): m₀ = 4π·Y₀₀·c₀ = 2√π·c₀, m₁ = (4π/3)·√(3/4π)·(c₃, c₁, c₂)
    /// (∫ω_iω_j = (4π/3)δ_ij). Exact for any radiance, since 1 and ω are in SH L1's span:
    /// for a lightmap texel whose radiance is projected with zero below the surface (the
    /// baker's hemisphere handling), these are the moments over its upper hemisphere.
    pub fn sphere(rgb: &[[f64; 4]; 3]) -> Moments {
        let k1 = (3.0 / (4.0 * PI)).sqrt();
        Moments { m0: rgb.map(|c| 2.0 * PI.sqrt() * c[0]), m1: rgb.map(|c| DVec3::new(c[3], c[1], c[2]) * (k1 * 4.0 * PI / 3.0)) }
    }

    /// The moments with m₁ in another frame: m₁ ↦ t·m₁.x + b·m₁.y + n·m₁.z.
    pub fn to_frame(&self, t: DVec3, b: DVec3, n: DVec3) -> Moments {
        Moments { m0: self.m0, m1: self.m1.map(|m| t * m.x + b * m.y + n * m.z) }
    }

    /// Y(m₁)/Y(m₀) (Rec. 709 luminance Y); zero when Y(m₀) ≤ 0.
    pub fn luminance_direction(&self) -> DVec3 {
        let y0: f64 = (0..3).map(|k| LUMINANCE[k] * self.m0[k]).sum();
        let y1: DVec3 = (0..3).map(|k| self.m1[k] * LUMINANCE[k]).sum();
        if y0 > 0.0 {
            y1 / y0
        } else {
            DVec3::ZERO
        }
    }

    /// m₁/m₀ of channel `k`; zero when m₀ ≤ 0.
    pub fn channel_direction(&self, k: usize) -> DVec3 {
        if self.m0[k] > 0.0 {
            self.m1[k] / self.m0[k]
        } else {
            DVec3::ZERO
        }
    }
}

/// What the Enlighten formats need: the baking normal n₀, the E/π
/// there, and the radiance's moments (world frame) for the dominant direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnlightenInput {
    /// The baking normal n₀ (unit).
    pub normal: DVec3,
    /// E/π at n₀.
    pub irradiance: [f64; 3],
    /// The radiance's moments over the domain the texel or probe sees.
    pub moments: Moments,
}

/// A texel as its textures hold it: the colour and up to three more textures (RGBA;
/// unused channels are 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texel {
    /// The HDR colour (L0, or Enlighten's irradiance, in E/π; Godot 4.0–4.3's L0
    /// coefficient).
    pub colour: [f64; 3],
    /// The other textures as sampled: values in [0, 1], or Godot 4.0–4.3's signed L1
    /// coefficients ([`EngineFormat::signed_units`]).
    pub unit: [[f64; 4]; 3],
}

/// An encoded texel and how many stored values had to be clamped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoded {
    /// The texel at full precision ([`Texel::stored`] rounds it as the engine stores it).
    pub texel: Texel,
    /// Stored values that were out of range and clamped.
    pub clamped: usize,
}

/// Clamps to [0, 1], counting a value that was outside (NaN counts and becomes ½).
fn unit(x: f64, clamped: &mut usize) -> f64 {
    if (0.0..=1.0).contains(&x) {
        x
    } else {
        *clamped += 1;
        if x.is_nan() {
            0.5
        } else {
            x.clamp(0.0, 1.0)
        }
    }
}

/// A direction packed as (d + 1)/2 per axis, its length first limited to 1 (counted).
fn pack_direction(d: DVec3, clamped: &mut usize) -> [f64; 3] {
    let len = d.length();
    let d = if len > 1.0 {
        *clamped += 1;
        d / len
    } else {
        d
    };
    [d.x, d.y, d.z].map(|v| unit(0.5 * v + 0.5, clamped))
}

/// Encodes one texel from its L1 irradiance (Godot, MonoSH) or its [`EnlightenInput`]
/// (the Enlighten formats; `None` for those returns `None`).
pub fn encode(format: EngineFormat, l1: &L1Irradiance, enlighten: Option<&EnlightenInput>) -> Option<Encoded> {
    let mut clamped = 0;
    let mut texel = Texel { colour: l1.a0, unit: [[1.0; 4]; 3] };
    match format {
        EngineFormat::GodotL1 => {
            // Layers in Godot's order: l1n1 (y), l1_0 (z), l1p1 (x); c/(8·L0) + ½ where
            // L0 ≠ 0, c + ½ where it is 0 (MODE_PACK_L1_COEFFS).
            for (layer, axis) in GODOT_LAYER_AXES.into_iter().enumerate() {
                for k in 0..3 {
                    let c = l1.a1[k].to_array()[axis];
                    let s = if l1.a0[k] != 0.0 { c / (8.0 * l1.a0[k]) } else { c };
                    texel.unit[layer][k] = unit(s + 0.5, &mut clamped);
                }
            }
        }
        EngineFormat::GodotL1Legacy => {
            texel.colour = l1.a0.map(|a| a / GODOT_Y00);
            for (layer, axis) in GODOT_LAYER_AXES.into_iter().enumerate() {
                for k in 0..3 {
                    texel.unit[layer][k] = l1.a1[k].to_array()[axis] / GODOT_L1;
                }
            }
        }
        EngineFormat::MonoSh | EngineFormat::MonoShLinear => {
            let t = pack_direction(l1.luminance_direction(), &mut clamped);
            texel.unit[0][..3].copy_from_slice(&t);
        }
        EngineFormat::Enlighten | EngineFormat::EnlightenRgb => {
            let input = enlighten?;
            let n0 = input.normal;
            texel.colour = input.irradiance;
            let dirs: Vec<DVec3> = if format == EngineFormat::Enlighten {
                vec![input.moments.luminance_direction()]
            } else {
                (0..3).map(|k| input.moments.channel_direction(k)).collect()
            };
            for (t, d) in texel.unit.iter_mut().zip(dirs) {
                let p = pack_direction(d, &mut clamped);
                // The rescaling factor from the direction as stored, so the decode
                // returns the colour at n₀ exactly.
                let ds = DVec3::new(p[0], p[1], p[2]) * 2.0 - DVec3::ONE;
                t[..3].copy_from_slice(&p);
                t[3] = unit((0.5 * n0.dot(ds) + 0.5).max(1e-4), &mut clamped);
            }
        }
    }
    Some(Encoded { texel, clamped })
}

/// Rounds a value to the nearest IEEE half (round-to-nearest-even).
pub fn round_f16(x: f64) -> f64 {
    half::f16::from_f64(x).to_f64()
}

/// Rounds a [0, 1] value to the nearest k/255.
pub fn round_unorm8(x: f64) -> f64 {
    (x.clamp(0.0, 1.0) * 255.0).round() / 255.0
}

impl Texel {
    /// The texel as the engine's textures hold it: colour in f16, unit textures in the
    /// format's [`EngineFormat::unit_storage`].
    pub fn stored(&self, format: EngineFormat) -> Texel {
        let r: fn(f64) -> f64 = match format.unit_storage() {
            Channel::F16 => round_f16,
            Channel::Unorm8 => round_unorm8,
        };
        Texel { colour: self.colour.map(round_f16), unit: self.unit.map(|t| t.map(r)) }
    }
}

/// E/π at unit normal `n` (in the engine's frame, [`EngineFormat::frame`]), as the format's
/// shader computes it (the module docs of [`super`]).
pub fn decode(format: EngineFormat, t: &Texel, n: DVec3) -> [f64; 3] {
    let dir = |u: &[f64; 4]| DVec3::new(u[0], u[1], u[2]) * 2.0 - DVec3::ONE;
    let nk = GODOT_LAYER_AXES.map(|a| n.to_array()[a]);
    match format {
        EngineFormat::GodotL1 => [0, 1, 2].map(|k| {
            let l0 = t.colour[k];
            l0 + (0..3).map(|layer| (t.unit[layer][k] - 0.5) * 2.0 * nk[layer] * (l0 * 4.0)).sum::<f64>()
        }),
        EngineFormat::GodotL1Legacy => {
            [0, 1, 2].map(|k| t.colour[k] * GODOT_Y00 + (0..3).map(|layer| t.unit[layer][k] * GODOT_L1 * nk[layer]).sum::<f64>())
        }
        EngineFormat::MonoShLinear => {
            let nl1 = dir(&t.unit[0]);
            t.colour.map(|l0| (l0 + 2.0 * l0 * nl1.dot(n)).max(0.0))
        }
        EngineFormat::MonoSh => {
            let nl1 = dir(&t.unit[0]);
            let sh = t.colour.map(|l0| l0 + 2.0 * l0 * nl1.dot(n));
            // The channel sums ("luma" in Bakery.cginc: dot(·, 1)); L1 = 2·L0·nL1 per channel.
            let luma_l0: f64 = t.colour.iter().sum();
            let luma_sh = geomerics_l1(luma_l0, nl1 * (2.0 * luma_l0), n);
            let regular: f64 = sh.iter().sum();
            // lerp(1, lumaSH/regular, saturate(16·regular)); where the weight is 0 the
            // shader's ratio is undefined (0/0) and the factor is 1.
            let w = (16.0 * regular).clamp(0.0, 1.0);
            let factor = if w > 0.0 { 1.0 + w * (luma_sh / regular - 1.0) } else { 1.0 };
            sh.map(|v| (v * factor).max(0.0))
        }
        EngineFormat::Enlighten => {
            let u = &t.unit[0];
            let half_lambert = n.dot(DVec3::new(u[0], u[1], u[2]) - DVec3::splat(0.5)) + 0.5;
            t.colour.map(|c| c * half_lambert / u[3].max(1e-4))
        }
        EngineFormat::EnlightenRgb => [0, 1, 2].map(|k| {
            let u = &t.unit[k];
            let half_lambert = n.dot(DVec3::new(u[0], u[1], u[2]) - DVec3::splat(0.5)) + 0.5;
            t.colour[k] * half_lambert / u[3].max(1e-4)
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Radiance of one white delta light of unit integral from `w`, projected on SH L1:
    /// c₀ = Y₀₀ = 1/(2√π), (c₁, c₂, c₃) = √(3/4π)·(w_y, w_z, w_x).
    fn delta_sh(w: DVec3, rgb: [f64; 3]) -> [[f64; 4]; 3] {
        let k1 = (3.0 / (4.0 * PI)).sqrt();
        rgb.map(|s| [0.5 / PI.sqrt() * s, k1 * w.y * s, k1 * w.z * s, k1 * w.x * s])
    }

    #[test]
    fn l1_irradiance_of_a_delta_light_is_the_closed_form() {
        // E/π of a unit delta light in L1 is (1 + 2 w·n)/(4π) (A₀ = π, A₁ = 2π/3).
        let w = DVec3::new(0.3, 0.8, -0.52).normalize();
        let l1 = L1Irradiance::from_sh(&delta_sh(w, [1.0; 3]));
        for n in [DVec3::X, DVec3::Y, DVec3::new(0.2, -0.9, 0.4).normalize()] {
            let want = (1.0 + 2.0 * w.dot(n)) / (4.0 * PI);
            assert!((l1.eval(n)[0] - want).abs() < 1e-15, "{n}: {} vs {want}", l1.eval(n)[0]);
        }
        // Its luminance direction is w itself (length 1: one direction).
        assert!((l1.luminance_direction() - w).length() < 1e-14);
    }

    #[test]
    fn stored_rounding_is_half_and_unorm8() {
        assert_eq!(round_f16(1.0 + 1.0 / 4096.0), 1.0); // below half an f16 ulp (2⁻¹¹)
        assert_eq!(round_f16(1.0 + 1.0 / 1024.0), 1.0 + 1.0 / 1024.0);
        assert_eq!(round_unorm8(0.5), 128.0 / 255.0);
        assert_eq!(round_unorm8(1.2), 1.0);
    }
}
