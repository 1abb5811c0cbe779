//! The directional lightmap formats engines ship, as encodings of L1 irradiance, each
//! decoded exactly as its engine's shader does by default — and the variants a user may have
//! switched to, by name.
//!
//! Every format stores a colour (HDR) and one or three more textures, and its shader turns
//! them into E/π — the value the engine multiplies by albedo — at the shading normal n
//! (in the engine's frame, [`EngineFrame`]):
//!
//! | id | engine, version | stored per texel | decode (E/π at n) |
//! |---|---|---|---|
//! | `godot-l1` | Godot ≥ 4.4 LightmapGI, "Use Spherical Harmonics" | L0 (RGB) + three RGB layers s_y, s_z, s_x ∈ [0, 1] | L0 + Σ_k 4·L0·(2s_k − 1)·n_k |
//! | `godot-l1-legacy` | Godot 4.0–4.3, the same setting | L0 + three signed RGB layers l_y, l_z, l_x (SH radiance coefficients) | 0.282095·L0 + 0.32573·Σ_k l_k·n_k |
//! | `monosh` | Bakery (Unity), MonoSH, "SH non-linear mode" on — Bakery's default | L0 (RGB) + one direction t (RGB8) | the linear value below, rescaled by Geomerics' curve of its channel sum |
//! | `monosh-linear` | Bakery, MonoSH, non-linear mode off | as `monosh` | max(0, L0 + 2·L0·((2t − 1)·n)) |
//! | `enlighten` | Unity (Enlighten, baked "Directional" lightmaps) | irradiance C (RGB) + t (RGBA8) | C·((t.xyz − ½)·n + ½)/max(t.w, 10⁻⁴) |
//! | `enlighten-rgb` | **no shipping engine**: a research layout (BakingLab-derived code) | C + one RGBA8 t per channel | per channel as `enlighten` |
//!
//! Sources of the decodes (transcribed in [`decode`]; the tests transcribe them again, line
//! by line, in f32):
//! - Godot ≥ 4.4: `godotengine/godot`, `servers/rendering/renderer_rd/shaders/
//!   forward_clustered/scene_forward_clustered.glsl` (`USE_LIGHTMAP`, `uses_sh`:
//!   `lm_light_l1* = (textureLod(…) − 0.5)·2`, `ambient_light += lm_light_l1*·n_k·(lm_light_l0·en·4)`,
//!   layers in the order l1n1 (y), l1_0 (z), l1p1 (x)); its packing pass
//!   `modules/lightmapper_rd/lm_compute.glsl` `MODE_PACK_L1_COEFFS` (c/(8·L0) + ½, clamped
//!   to [0, 1]). `en` is the exposure normalisation, 1 without camera attributes.
//! - Godot 4.0–4.3: the same shader before the packing (tags 4.0-stable … 4.3-stable):
//!   `ambient_light += lm_light_l0·0.282095·en` and `+= lm_light_l1*·0.32573·n_k·en` —
//!   Y₀₀ = 0.282095 and (2/3)·0.488603 = 0.32573, the Lambert band factors over π: the
//!   layers hold SH radiance coefficients, signed, in RGBA16F.
//! - Bakery: `Bakery.cginc` (Bakery — GPU Lightmapper for Unity, shipped with the asset),
//!   `BakeryMonoSH`: `nL1 = dominantDir·2 − 1`, `L1x = nL1.x·L0·2` …; under
//!   `#if BAKERY_SHNONLINEAR` (the "SH non-linear mode" setting, on by default)
//!   `lumaSH = shEvaluateDiffuseL1Geomerics(dot(L0, 1), (dot(L1x, 1), dot(L1y, 1), dot(L1z, 1)), n)`,
//!   `sh = L0 + n.x·L1x + n.y·L1y + n.z·L1z`, `sh *= lerp(1, lumaSH/dot(sh, 1), saturate(16·dot(sh, 1)))`;
//!   `diffuseColor = max(sh, 0)` on both branches. `shEvaluateDiffuseL1Geomerics` is
//!   [`super::sh::geomerics_l1`] (Hill, CEDEC 2015).
//! - Unity: `UnityCG.cginc` `DecodeDirectionalLightmap` (`halfLambert = dot(n, dirTex.xyz − 0.5) + 0.5`,
//!   `color·halfLambert/max(1e-4, dirTex.w)`), whose texture Enlighten's SDK documents
//!   ("Solving for directional irradiance": the luminance-based dominant direction in RGB,
//!   8 bits per channel, its length the directionality — 1 for light from one direction, ½
//!   for light uniform over the hemisphere — and the rescaling factor in alpha).
//!
//! The encodes are in [`encode`]; how each engine stores the textures is
//! [`EngineFormat::engine_bytes`] (uncompressed) and [`EngineFormat::compressed`].

mod codec;

pub use codec::{decode, encode, round_f16, round_unorm8, Encoded, EnlightenInput, L1Irradiance, Moments, Texel};
use glam::DVec3;

/// A directional lightmap format an engine ships, with the decode it runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EngineFormat {
    /// Godot ≥ 4.4 LightmapGI with "Use Spherical Harmonics": L1 SH, L1 packed relative to L0.
    GodotL1,
    /// Godot 4.0–4.3, the same setting: L1 SH coefficients stored as they are (signed).
    GodotL1Legacy,
    /// Bakery's MonoSH (RGB L0 and one luminance L1 direction) with the non-linear decode
    /// Bakery's shaders run by default.
    MonoSh,
    /// Bakery's MonoSH with "SH non-linear mode" off: the linear L1 decode.
    MonoShLinear,
    /// Enlighten's directional irradiance (one luminance dominant direction), Unity's decode.
    Enlighten,
    /// One dominant direction per colour channel, each decoded as Unity decodes one — a
    /// research layout no shipping engine decodes.
    EnlightenRgb,
}

/// How a texture channel is stored at the engine's precision.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// IEEE half float.
    F16,
    /// 8-bit unsigned normalised: k/255.
    Unorm8,
}

/// A block-compressed texture format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockFormat {
    /// BC6H, unsigned half floats (1 B/texel).
    Bc6hUf16,
    /// BC6H, signed half floats (1 B/texel).
    Bc6hSf16,
    /// BC1 RGB (0.5 B/texel).
    Bc1,
    /// BC7 RGBA (1 B/texel).
    Bc7,
}

impl BlockFormat {
    /// Bytes per texel.
    pub fn bytes_per_texel(self) -> f64 {
        match self {
            BlockFormat::Bc1 => 0.5,
            _ => 1.0,
        }
    }
}

/// A block-compressed layout of a format's textures: the colour's block format, the other
/// textures', and what it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompressedLayout {
    /// The colour texture's block format.
    pub colour: BlockFormat,
    /// The other textures' block format.
    pub units: BlockFormat,
    /// What the layout is: who ships it.
    pub label: &'static str,
}

/// The frame and handedness the engine reads directions in. The bake's world is glTF's:
/// right-handed, +Y up, +Z forward (towards the viewer of the front).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EngineFrame {
    /// glTF's axes unchanged: Godot's own (right-handed, +Y up, −Z forward; its glTF import
    /// keeps the axes), also what `--engine-frame gltf` asks of every format.
    Gltf,
    /// Unity's left-handed frame (+Y up, +Z forward, +X right), reached from glTF as Unity's
    /// glTF importers do — x negated (UnityGLTF's `CoordinateSpaceConversionScale =
    /// (−1, 1, 1)`, `SchemaExtensions.cs`; glTFast likewise).
    UnityLeftHanded,
}

impl EngineFrame {
    /// A glTF-frame direction in this frame (a reflection: its own inverse).
    pub fn from_gltf(self, v: DVec3) -> DVec3 {
        match self {
            EngineFrame::Gltf => v,
            EngineFrame::UnityLeftHanded => DVec3::new(-v.x, v.y, v.z),
        }
    }

    /// Short name (bake.json, docs).
    pub fn id(self) -> &'static str {
        match self {
            EngineFrame::Gltf => "gltf: right-handed, +Y up (glTF's and Godot's axes)",
            EngineFrame::UnityLeftHanded => "unity: left-handed, +Y up, x negated from glTF (as Unity's glTF importers)",
        }
    }
}

impl EngineFormat {
    /// Every format, in report order.
    pub const ALL: [EngineFormat; 6] = [
        EngineFormat::GodotL1,
        EngineFormat::GodotL1Legacy,
        EngineFormat::MonoSh,
        EngineFormat::MonoShLinear,
        EngineFormat::Enlighten,
        EngineFormat::EnlightenRgb,
    ];

    /// Short identifier (probes mode ids, file names).
    pub fn id(self) -> &'static str {
        match self {
            EngineFormat::GodotL1 => "godot-l1",
            EngineFormat::GodotL1Legacy => "godot-l1-legacy",
            EngineFormat::MonoSh => "monosh",
            EngineFormat::MonoShLinear => "monosh-linear",
            EngineFormat::Enlighten => "enlighten",
            EngineFormat::EnlightenRgb => "enlighten-rgb",
        }
    }

    /// The engine and version whose default decode this is.
    pub fn engine(self) -> &'static str {
        match self {
            EngineFormat::GodotL1 => "Godot 4.4 and later, LightmapGI with Use Spherical Harmonics",
            EngineFormat::GodotL1Legacy => "Godot 4.0 to 4.3, LightmapGI with Use Spherical Harmonics",
            EngineFormat::MonoSh => "Bakery for Unity, MonoSH, SH non-linear mode on (Bakery's default)",
            EngineFormat::MonoShLinear => "Bakery for Unity, MonoSH, SH non-linear mode off",
            EngineFormat::Enlighten => "Unity, Enlighten directional lightmaps (UnityCG DecodeDirectionalLightmap)",
            EngineFormat::EnlightenRgb => {
                "no shipping engine: one Enlighten direction per channel (research layout), Unity's decode per channel"
            }
        }
    }

    /// The engine and version in a few words (reports' tables).
    pub fn engine_short(self) -> &'static str {
        match self {
            EngineFormat::GodotL1 => "Godot ≥ 4.4",
            EngineFormat::GodotL1Legacy => "Godot 4.0–4.3",
            EngineFormat::MonoSh => "Bakery, default non-linear decode",
            EngineFormat::MonoShLinear => "Bakery, linear decode",
            EngineFormat::Enlighten => "Unity",
            EngineFormat::EnlightenRgb => "no shipping engine",
        }
    }

    /// The shader function whose decode this is (see the module docs for the lines).
    pub fn decode_source(self) -> &'static str {
        match self {
            EngineFormat::GodotL1 => "godotengine/godot 4.4+ scene_forward_clustered.glsl (USE_LIGHTMAP, uses_sh, packed L1)",
            EngineFormat::GodotL1Legacy => {
                "godotengine/godot 4.0-4.3 scene_forward_clustered.glsl (USE_LIGHTMAP, uses_sh: 0.282095, 0.32573)"
            }
            EngineFormat::MonoSh => "Bakery.cginc BakeryMonoSH, #if BAKERY_SHNONLINEAR branch (shEvaluateDiffuseL1Geomerics)",
            EngineFormat::MonoShLinear => "Bakery.cginc BakeryMonoSH, linear branch",
            EngineFormat::Enlighten => "UnityCG.cginc DecodeDirectionalLightmap",
            EngineFormat::EnlightenRgb => "UnityCG.cginc DecodeDirectionalLightmap, once per channel",
        }
    }

    /// The frame the engine reads the format's directions in.
    pub fn frame(self) -> EngineFrame {
        match self {
            EngineFormat::GodotL1 | EngineFormat::GodotL1Legacy => EngineFrame::Gltf,
            _ => EngineFrame::UnityLeftHanded,
        }
    }

    /// Textures per texel besides the colour (RGBA each).
    pub fn unit_textures(self) -> usize {
        match self {
            EngineFormat::GodotL1 | EngineFormat::GodotL1Legacy | EngineFormat::EnlightenRgb => 3,
            EngineFormat::MonoSh | EngineFormat::MonoShLinear | EngineFormat::Enlighten => 1,
        }
    }

    /// Channels of those textures the decode reads: RGB, or RGBA for Enlighten (the
    /// rescaling factor in alpha).
    pub fn unit_channels(self) -> usize {
        match self {
            EngineFormat::Enlighten | EngineFormat::EnlightenRgb => 4,
            _ => 3,
        }
    }

    /// Whether the textures besides the colour hold signed values (Godot 4.0–4.3's raw
    /// coefficients) rather than values in [0, 1].
    pub fn signed_units(self) -> bool {
        self == EngineFormat::GodotL1Legacy
    }

    /// How the textures besides the colour are stored: Godot keeps its SH layers in RGBA16F,
    /// Bakery and Unity their directions in RGBA8.
    pub fn unit_storage(self) -> Channel {
        match self {
            EngineFormat::GodotL1 | EngineFormat::GodotL1Legacy => Channel::F16,
            _ => Channel::Unorm8,
        }
    }

    /// Scalars the decode reads per texel: the RGB colour and the other textures' channels.
    pub fn scalars(self) -> usize {
        3 + self.unit_textures() * self.unit_channels()
    }

    /// Bytes per texel as the engine stores it uncompressed: the colour as RGBA16F (8 B;
    /// RGB textures are padded to four channels by GPUs) and each other texture as RGBA16F
    /// (Godot's four layers of one RGBA16F texture array) or RGBA8.
    pub fn engine_bytes(self) -> usize {
        let unit = match self.unit_storage() {
            Channel::F16 => 8,
            Channel::Unorm8 => 4,
        };
        8 + unit * self.unit_textures()
    }

    /// The block-compressed layout the engine ships: Godot's VRAM-compressed lightmap is one
    /// texture array, every layer BC6H (4.0–4.3 ships none: its signed layers are given as
    /// BC6H_SF16 for comparison, labelled so); Unity's
    /// lightmaps are BC6H with the direction in a BC1 (Bakery's RGB direction) or BC7
    /// (Enlighten's RGBA) texture.
    pub fn compressed(self) -> CompressedLayout {
        match self {
            EngineFormat::GodotL1 => CompressedLayout {
                colour: BlockFormat::Bc6hUf16,
                units: BlockFormat::Bc6hUf16,
                label: "Godot's shipped storage: the four layers of one texture array, all BC6H",
            },
            EngineFormat::GodotL1Legacy => CompressedLayout {
                colour: BlockFormat::Bc6hSf16,
                units: BlockFormat::Bc6hSf16,
                label: "not shipped (Godot 4.0-4.3 keeps the layers uncompressed): the four layers all BC6H signed, for comparison",
            },
            EngineFormat::MonoSh | EngineFormat::MonoShLinear => {
                CompressedLayout { colour: BlockFormat::Bc6hUf16, units: BlockFormat::Bc1, label: "BC6H colour, BC1 direction" }
            }
            EngineFormat::Enlighten | EngineFormat::EnlightenRgb => CompressedLayout {
                colour: BlockFormat::Bc6hUf16,
                units: BlockFormat::Bc7,
                label: "BC6H colour, BC7 direction and rescaling factor",
            },
        }
    }

    /// Other compressed layouts worth comparing, labelled: for Godot ≥ 4.4 the open proposal
    /// for compressed SH lightmaps (BC6H L0 + BC1 L1 layers, 2.5 B/texel), which Godot does
    /// not ship.
    pub fn compressed_variants(self) -> Vec<CompressedLayout> {
        match self {
            EngineFormat::GodotL1 => vec![CompressedLayout {
                colour: BlockFormat::Bc6hUf16,
                units: BlockFormat::Bc1,
                label: "proposal (not shipped by Godot): BC6H L0 + three BC1 L1 layers",
            }],
            _ => Vec::new(),
        }
    }

    /// Bytes per texel of a compressed layout of this format.
    pub fn compressed_bytes(self, layout: CompressedLayout) -> f64 {
        layout.colour.bytes_per_texel() + self.unit_textures() as f64 * layout.units.bytes_per_texel()
    }
}
