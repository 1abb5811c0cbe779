//! Material textures: the images a glTF material's base colour, metallic-roughness and
//! emissive maps refer to, and their sampling at a surface point (glTF 2.0 §3.8–3.9):
//! the texel grid with texel centres at (i + ½)/w, the sampler's wrap modes (repeat,
//! clamped, mirrored) and magnification filter (nearest or bilinear; one level — mip 0,
//! no minification filter: the bake samples each path vertex at a point), and
//! KHR_texture_transform's offset, rotation and scale applied to the texture coordinate.
//! Colour maps are stored as their 8-bit sRGB texels and decoded to linear before
//! filtering (the sRGB transfer function, IEC 61966-2-1).

use sbf::glam::{Vec2, Vec4};

/// How a texture coordinate outside [0, 1] maps into the image (glTF sampler wrapS/wrapT).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    Clamp,
    Mirror,
}

/// The sampler's magnification filter (glTF magFilter; LINEAR when absent).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Bilinear,
}

/// An 8-bit RGBA image with its sampler state.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major from the image's top row (glTF's v = 0), RGBA as stored.
    pub texels: Vec<[u8; 4]>,
    pub wrap: [Wrap; 2],
    pub filter: Filter,
}

/// What a material map reads: a texture, the mesh's texture-coordinate set, and the
/// affine map of KHR_texture_transform (uv' = m · (u, v, 1); the identity without it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureRef {
    pub texture: usize,
    /// TEXCOORD_n: 0 (the mesh's `uv`) or 1 (its lightmap UVs).
    pub texcoord: u32,
    /// Rows of the 2×3 matrix: u' = m₀·(u, v, 1), v' = m₁·(u, v, 1).
    pub transform: [[f32; 3]; 2],
}

impl TextureRef {
    /// `texture` through TEXCOORD_0 without a transform.
    pub fn new(texture: usize) -> Self {
        TextureRef { texture, texcoord: 0, transform: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] }
    }

    /// KHR_texture_transform: T(offset) · R(rotation) · S(scale), the UVs rotated
    /// counter-clockwise as seen on the image (v down): u' = cos·u + sin·v, v' = −sin·u +
    /// cos·v (the extension's worked example; its GLSL listing's column order disagrees with it).
    pub fn with_transform(self, offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Self {
        let (s, c) = rotation.sin_cos();
        let transform = [[c * scale[0], s * scale[1], offset[0]], [-s * scale[0], c * scale[1], offset[1]]];
        TextureRef { transform, ..self }
    }

    /// The transformed coordinate.
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let m = &self.transform;
        Vec2::new(m[0][0] * uv.x + m[0][1] * uv.y + m[0][2], m[1][0] * uv.x + m[1][1] * uv.y + m[1][2])
    }
}

/// The maps of a material (each multiplies its factor, glTF 2.0 §3.9.2).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Maps {
    /// sRGB colour and alpha.
    pub base_color: Option<TextureRef>,
    /// Linear: roughness in G, metallic in B.
    pub metallic_roughness: Option<TextureRef>,
    /// sRGB colour.
    pub emissive: Option<TextureRef>,
    /// glTF alphaMode MASK: the base colour's alpha (factor × map) below the cutoff is a
    /// hole rays pass through.
    pub mask: Option<AlphaMask>,
    /// Tangent-space normals (its texture is one of `Scene::normal_textures`): the
    /// renderer's shading reads it (`render --normal-maps`); the bake does not.
    pub normal: Option<NormalMap>,
}

/// A material's normal map (glTF 2.0 §3.9.3): linear RGB, each texel the tangent-space
/// normal (2·rgb − 1) with x and y scaled by `scale`, in the MikkTSpace frame of the
/// texture coordinates it reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalMap {
    pub texture: TextureRef,
    pub scale: f32,
}

/// glTF's alpha mask (§3.9.4): the base colour factor's alpha and the cutoff.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlphaMask {
    pub factor: f32,
    pub cutoff: f32,
}

impl Maps {
    /// No map the bake samples (the normal map is the renderer's alone).
    pub fn is_empty(&self) -> bool {
        self.base_color.is_none() && self.metallic_roughness.is_none() && self.emissive.is_none() && self.mask.is_none()
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1) for an 8-bit value.
pub fn srgb_to_linear(v: u8) -> f32 {
    let c = v as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The 256 decoded sRGB values.
fn srgb_table() -> &'static [f32; 256] {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as u8)))
}

/// Index of texel coordinate `i` (may lie outside [0, n)) under a wrap mode.
fn wrap_index(i: i64, n: u32, wrap: Wrap) -> u32 {
    let n = n as i64;
    (match wrap {
        Wrap::Clamp => i.clamp(0, n - 1),
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::Mirror => {
            let k = i.rem_euclid(2 * n);
            if k < n {
                k
            } else {
                2 * n - 1 - k
            }
        }
    }) as u32
}

impl Texture {
    /// Texel (x, y) as RGBA in [0, 1]: colour channels decoded from sRGB when `srgb`
    /// (alpha stays linear).
    fn texel(&self, x: u32, y: u32, srgb: bool) -> Vec4 {
        let t = self.texels[(y * self.width + x) as usize];
        let lin = |v: u8| v as f32 / 255.0;
        if srgb {
            let s = srgb_table();
            Vec4::new(s[t[0] as usize], s[t[1] as usize], s[t[2] as usize], lin(t[3]))
        } else {
            Vec4::new(lin(t[0]), lin(t[1]), lin(t[2]), lin(t[3]))
        }
    }

    /// The filtered value at texture coordinate `uv` (after the reference's transform).
    pub fn sample(&self, uv: Vec2, srgb: bool) -> Vec4 {
        let (w, h) = (self.width, self.height);
        // Texel space: texel i covers [i, i + 1); its centre is i + ½.
        let (x, y) = (uv.x as f64 * w as f64, uv.y as f64 * h as f64);
        if !(x.is_finite() && y.is_finite()) {
            return self.texel(0, 0, srgb);
        }
        match self.filter {
            Filter::Nearest => {
                let (i, j) = (x.floor() as i64, y.floor() as i64);
                self.texel(wrap_index(i, w, self.wrap[0]), wrap_index(j, h, self.wrap[1]), srgb)
            }
            Filter::Bilinear => {
                let (fx, fy) = (x - 0.5, y - 0.5);
                let (i, j) = (fx.floor() as i64, fy.floor() as i64);
                let (tx, ty) = ((fx - i as f64) as f32, (fy - j as f64) as f32);
                let (x0, x1) = (wrap_index(i, w, self.wrap[0]), wrap_index(i + 1, w, self.wrap[0]));
                let (y0, y1) = (wrap_index(j, h, self.wrap[1]), wrap_index(j + 1, h, self.wrap[1]));
                let top = self.texel(x0, y0, srgb).lerp(self.texel(x1, y0, srgb), tx);
                let bottom = self.texel(x0, y1, srgb).lerp(self.texel(x1, y1, srgb), tx);
                top.lerp(bottom, ty)
            }
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.texels.len() * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tex(filter: Filter, wrap: Wrap) -> Texture {
        // 2×1: black, white (linear values 0 and 1 either way).
        Texture { name: "t".into(), width: 2, height: 1, texels: vec![[0, 0, 0, 255], [255, 255, 255, 255]], wrap: [wrap; 2], filter }
    }

    #[test]
    fn srgb_decode_matches_the_standard_at_its_knots() {
        assert_eq!(srgb_to_linear(0), 0.0);
        assert_eq!(srgb_to_linear(255), 1.0);
        // 0.5 in sRGB is 0.2140 linear (IEC 61966-2-1).
        assert!((srgb_to_linear(128) - 0.2158605).abs() < 1e-6, "{}", srgb_to_linear(128));
        assert!((srgb_to_linear(10) - 10.0 / 255.0 / 12.92).abs() < 1e-9);
    }

    #[test]
    fn nearest_and_bilinear_follow_the_texel_centres_and_wraps() {
        let n = tex(Filter::Nearest, Wrap::Repeat);
        assert_eq!(n.sample(Vec2::new(0.49, 0.5), false).x, 0.0);
        assert_eq!(n.sample(Vec2::new(0.51, 0.5), false).x, 1.0);
        assert_eq!(n.sample(Vec2::new(1.2, 0.5), false).x, 0.0, "repeat");
        let b = tex(Filter::Bilinear, Wrap::Clamp);
        // Centres at u = ¼ (0) and ¾ (1): linear between, clamped outside.
        assert!((b.sample(Vec2::new(0.5, 0.5), false).x - 0.5).abs() < 1e-6);
        assert!((b.sample(Vec2::new(0.375, 0.5), false).x - 0.25).abs() < 1e-6);
        assert_eq!(b.sample(Vec2::new(0.1, 0.5), false).x, 0.0);
        assert_eq!(b.sample(Vec2::new(0.95, 0.5), false).x, 1.0);
        let r = tex(Filter::Bilinear, Wrap::Repeat);
        // Between the last centre (¾) and the first one repeated (1¼): halfway at 1.
        assert!((r.sample(Vec2::new(1.0, 0.5), false).x - 0.5).abs() < 1e-6);
        let m = tex(Filter::Nearest, Wrap::Mirror);
        assert_eq!(m.sample(Vec2::new(1.2, 0.5), false).x, 1.0, "mirrored: [1, 2) reads the texels backwards");
        assert_eq!(m.sample(Vec2::new(-0.2, 0.5), false).x, 0.0);
    }

    #[test]
    fn texture_transform_is_the_extensions_example() {
        // KHR_texture_transform's README: offset (0, 1), rotation ½π, scale ½ "utilizes only
        // the lower left quadrant of the source image, rotated clockwise 90°" — the unit
        // square's corners land on that quadrant's (v down: v ∈ [½, 1]).
        let r = TextureRef::new(0).with_transform([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
        let corners = [(0.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.5), (0.0, 1.0, 0.5, 1.0), (1.0, 1.0, 0.5, 0.5)];
        for (u, v, eu, ev) in corners {
            let p = r.apply(Vec2::new(u, v));
            assert!((p - Vec2::new(eu, ev)).length() < 1e-6, "({u}, {v}) → {p}, want ({eu}, {ev})");
        }
        // Scale and offset alone.
        let s = TextureRef::new(0).with_transform([0.25, 0.5], 0.0, [2.0, 3.0]);
        assert!((s.apply(Vec2::new(1.0, 1.0)) - Vec2::new(2.25, 3.5)).length() < 1e-6);
    }
}
