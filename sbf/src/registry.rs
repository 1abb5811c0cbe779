//! The basis registry: every basis the tools bake, store, export and compare, as one
//! [`BasisId`] with one `const` [`BasisInfo`] — its name, lobes, domain, sign, layout,
//! storage, runtime features and tables, and GPU slot kind. Every crate reads these facts
//! here (the baker's `--bases`, profiles, the shader features a bake ships, the probes
//! tool's modes); a new basis starts with a row of [`BASES`] (docs/adding-a-basis.md).

use crate::quadrature::Domain;
#[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice", feature = "h-basis", feature = "ambient-cube"))]
use {
    crate::basis::{AmbientCube, AmbientDiceSrbf, Basis, HBasis, SgBasis, ShBasis},
    glam::DVec3,
};

/// A basis of the registry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BasisId {
    /// SH L1: 4 coefficients.
    Sh1,
    /// SH L2: 9 coefficients.
    Sh2,
    /// 9 SG lobes, Vogel spiral over the upper hemisphere.
    Sg9,
    /// 12 SG lobes, Vogel spiral over the upper hemisphere.
    Sg12,
    /// Ambient Dice SRBF, Roughton's 9 upper-hemisphere lobes.
    Ad9,
    /// Ambient Dice SRBF, 12 icosahedron lobes.
    Ad12,
    /// SH L1's four coefficients reconstructed with ZH3's zonal band 2 (Roughton et al.
    /// 2024): the storage of SH L1, irradiance closer to SH L2's.
    Zh3,
    /// Ambient cube: E/π at ±X, ±Y, ±Z (an irradiance basis).
    AmbientCube,
    /// H-basis 4: E/π over the upper hemisphere (an irradiance basis).
    H4,
    /// H-basis 6: E/π over the upper hemisphere (an irradiance basis).
    H6,
}

impl std::fmt::Display for BasisId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The family a basis belongs to: what its runtime functions and lobe shapes are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Real spherical harmonics (no Condon–Shortley phase; band 1 as (y, z, x)).
    Sh,
    /// Spherical Gaussians of one sharpness.
    Sg,
    /// Ambient Dice SRBF lobes ([Roughton19 §8]).
    AmbientDice,
    /// The ambient cube (six E/π values).
    AmbientCube,
    /// The H-basis (E/π over the hemisphere).
    HBasis,
}

impl Family {
    /// The `sbf` cargo feature that compiles the family in.
    pub const fn cargo_feature(self) -> &'static str {
        match self {
            Family::Sh => "sh",
            Family::Sg => "sg",
            Family::AmbientDice => "ambient-dice",
            Family::AmbientCube => "ambient-cube",
            Family::HBasis => "h-basis",
        }
    }
}

/// What the coefficients hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Holds {
    /// Radiance: irradiance and specular are convolutions at run time.
    Radiance,
    /// E/π itself (no specular).
    Irradiance,
}

/// Everything the tools need to know of one basis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BasisInfo {
    /// The basis.
    pub id: BasisId,
    /// Its name in commands, profiles, file names and reports (`sh1`, `ad12`, `ac`, …).
    pub name: &'static str,
    /// A short title for reports ("SH L2", "AD 9").
    pub title: &'static str,
    /// Its family.
    pub family: Family,
    /// Coefficients (lobes) per RGB value.
    pub lobes: usize,
    /// Where its functions live: the sphere, or the upper hemisphere of the texel's frame.
    pub domain: Domain,
    /// Whether every basis function is ≥ 0 (so a non-negativity constraint means something).
    pub non_negative: bool,
    /// What the coefficients hold.
    pub holds: Holds,
    /// A lightmap basis of the baker (`--bases`) and of profiles' `lightmap.bases`.
    pub lightmap: bool,
    /// A probe basis of the baker (`--probe-bases`) and of profiles' `probes.bases`.
    pub probe: bool,
    /// The `shaders` composition feature of its Lambert runtime (None: not in the library).
    pub irradiance_feature: Option<&'static str>,
    /// Its GGX specular runtime per `profile::SpecularPath` (feature `profile`) (fit, tables): the
    /// `shaders` feature and the fitgen table it reads (None: none).
    pub specular: [(Option<&'static str>, Option<&'static str>); 2],
    /// The `probes` comparison mode that evaluates it as its runtime does: in a texel's
    /// tangent frame (a lightmap) and on the sphere (a probe); None where it is not one.
    pub probes_modes: [Option<&'static str>; 2],
    /// Its kind index in the baker's GPU encoder slots (`KIND_n` of bases.wgsl) and, plus
    /// one, its `ENCODING` in the renderer (0 is the plain E/π lightmap); None: not baked.
    pub gpu_kind: Option<u32>,
}

/// The SG lobes' sharpness the registry's SG bases have unless a tool sets another (λ 6:
/// the lobes of [`crate::layout::vogel_hemisphere`] overlap about as Roughton's).
pub const SG_SHARPNESS: f64 = 6.0;

const SH_SPECULAR: [(Option<&str>, Option<&str>); 2] = [(Some("sh-specular"), Some("dfg")), (Some("sh-specular"), Some("dfg"))];
const SG_SPECULAR: [(Option<&str>, Option<&str>); 2] =
    [(Some("sg-specular"), Some("dfg")), (Some("lobe-ggx-filtered"), Some("lobe-ggx-sg6"))];
const NO_SPECULAR: [(Option<&str>, Option<&str>); 2] = [(None, None), (None, None)];

/// Every basis, in [`BasisId`] order: the radiance bases (lightmap and probe), then the
/// irradiance bases.
pub const BASES: [BasisInfo; 10] = [
    BasisInfo {
        id: BasisId::Sh1,
        name: "sh1",
        title: "SH L1",
        family: Family::Sh,
        lobes: 4,
        domain: Domain::Sphere,
        non_negative: false,
        holds: Holds::Radiance,
        lightmap: true,
        probe: true,
        irradiance_feature: Some("sh-l1-irradiance"),
        specular: SH_SPECULAR,
        probes_modes: [Some("shl1"), Some("shl1")],
        gpu_kind: Some(0),
    },
    BasisInfo {
        id: BasisId::Sh2,
        name: "sh2",
        title: "SH L2",
        family: Family::Sh,
        lobes: 9,
        domain: Domain::Sphere,
        non_negative: false,
        holds: Holds::Radiance,
        lightmap: true,
        probe: true,
        irradiance_feature: Some("sh-l2-irradiance"),
        specular: SH_SPECULAR,
        probes_modes: [Some("shl2"), Some("shl2")],
        gpu_kind: Some(1),
    },
    BasisInfo {
        id: BasisId::Sg9,
        name: "sg9",
        title: "SG 9",
        family: Family::Sg,
        lobes: 9,
        domain: Domain::UpperHemisphere,
        non_negative: true,
        holds: Holds::Radiance,
        lightmap: true,
        probe: false,
        irradiance_feature: Some("sg-irradiance"),
        specular: SG_SPECULAR,
        probes_modes: [Some("sg9h"), None],
        gpu_kind: Some(2),
    },
    BasisInfo {
        id: BasisId::Sg12,
        name: "sg12",
        title: "SG 12",
        family: Family::Sg,
        lobes: 12,
        domain: Domain::UpperHemisphere,
        non_negative: true,
        holds: Holds::Radiance,
        lightmap: true,
        probe: false,
        irradiance_feature: Some("sg-irradiance"),
        specular: SG_SPECULAR,
        probes_modes: [Some("sg12h"), None],
        gpu_kind: Some(3),
    },
    BasisInfo {
        id: BasisId::Ad9,
        name: "ad9",
        title: "AD 9",
        family: Family::AmbientDice,
        lobes: 9,
        domain: Domain::UpperHemisphere,
        non_negative: true,
        holds: Holds::Radiance,
        lightmap: true,
        probe: false,
        irradiance_feature: Some("ad9-irradiance"),
        specular: [(Some("ad9-specular"), Some("ad-specular-2d")), (Some("lobe-ggx-filtered"), Some("lobe-ggx-ad"))],
        probes_modes: [Some("ad9"), None],
        gpu_kind: Some(4),
    },
    BasisInfo {
        id: BasisId::Ad12,
        name: "ad12",
        title: "AD 12",
        family: Family::AmbientDice,
        lobes: 12,
        domain: Domain::Sphere,
        non_negative: true,
        holds: Holds::Radiance,
        lightmap: true,
        probe: true,
        irradiance_feature: Some("ad12-irradiance"),
        specular: [(Some("ad12-specular"), Some("ad-specular-2d")), (Some("lobe-ggx-filtered"), Some("lobe-ggx-ad"))],
        probes_modes: [Some("adrbf-tangent"), Some("adrbf")],
        gpu_kind: Some(5),
    },
    BasisInfo {
        id: BasisId::Zh3,
        name: "zh3",
        title: "SH L1 + ZH3",
        family: Family::Sh,
        lobes: 4,
        domain: Domain::Sphere,
        non_negative: false,
        holds: Holds::Radiance,
        lightmap: true,
        probe: true,
        irradiance_feature: Some("sh-l1-zh3"),
        specular: SH_SPECULAR,
        probes_modes: [Some("shl1zh3"), Some("shl1zh3")],
        gpu_kind: Some(6),
    },
    BasisInfo {
        id: BasisId::AmbientCube,
        name: "ac",
        title: "ambient cube",
        family: Family::AmbientCube,
        lobes: 6,
        domain: Domain::Sphere,
        non_negative: true,
        holds: Holds::Irradiance,
        lightmap: false,
        probe: false,
        irradiance_feature: None,
        specular: NO_SPECULAR,
        probes_modes: [None, Some("acproj")],
        gpu_kind: None,
    },
    BasisInfo {
        id: BasisId::H4,
        name: "h4",
        title: "H-basis 4",
        family: Family::HBasis,
        lobes: 4,
        domain: Domain::UpperHemisphere,
        non_negative: false,
        holds: Holds::Irradiance,
        lightmap: false,
        probe: false,
        irradiance_feature: None,
        specular: NO_SPECULAR,
        probes_modes: [Some("h4"), None],
        gpu_kind: None,
    },
    BasisInfo {
        id: BasisId::H6,
        name: "h6",
        title: "H-basis 6",
        family: Family::HBasis,
        lobes: 6,
        domain: Domain::UpperHemisphere,
        non_negative: false,
        holds: Holds::Irradiance,
        lightmap: false,
        probe: false,
        irradiance_feature: None,
        specular: NO_SPECULAR,
        probes_modes: [Some("h6"), None],
        gpu_kind: None,
    },
];

impl BasisId {
    /// Every basis, in registry order.
    pub const ALL: [BasisId; 10] = [
        BasisId::Sh1,
        BasisId::Sh2,
        BasisId::Sg9,
        BasisId::Sg12,
        BasisId::Ad9,
        BasisId::Ad12,
        BasisId::Zh3,
        BasisId::AmbientCube,
        BasisId::H4,
        BasisId::H6,
    ];

    /// Its registry row.
    pub const fn info(self) -> &'static BasisInfo {
        &BASES[self as usize]
    }

    /// Its name (`sh1` … `ad12`, `ac`, `h4`, `h6`).
    pub const fn name(self) -> &'static str {
        self.info().name
    }

    /// The basis of a name, if it is one.
    pub fn from_name(name: &str) -> Option<BasisId> {
        BASES.iter().find(|b| b.name == name).map(|b| b.id)
    }

    /// The lightmap bases (the baker's `--bases`), in registry order.
    pub fn lightmap() -> impl Iterator<Item = BasisId> {
        BASES.iter().filter(|b| b.lightmap).map(|b| b.id)
    }

    /// The probe bases (the baker's `--probe-bases`), in registry order.
    pub fn probe() -> impl Iterator<Item = BasisId> {
        BASES.iter().filter(|b| b.probe).map(|b| b.id)
    }

    /// Number of coefficients (lobes).
    pub const fn lobes(self) -> usize {
        self.info().lobes
    }

    /// Number of coefficients (the probes' name for [`Self::lobes`]).
    pub const fn coefficient_count(self) -> usize {
        self.lobes()
    }

    /// Its family.
    pub const fn family(self) -> Family {
        self.info().family
    }

    /// Whether it is a set of spherical Gaussians (its sharpness matters).
    pub fn is_sg(self) -> bool {
        self.family() == Family::Sg
    }

    /// Whether it is SH.
    pub fn is_sh(self) -> bool {
        self.family() == Family::Sh
    }

    /// Whether every basis function is ≥ 0.
    pub const fn non_negative(self) -> bool {
        self.info().non_negative
    }

    /// Whether it covers the whole sphere (else the upper hemisphere).
    pub fn is_sphere(self) -> bool {
        self.info().domain == Domain::Sphere
    }

    /// Whether the coefficients hold E/π rather than radiance.
    pub fn holds_irradiance(self) -> bool {
        self.info().holds == Holds::Irradiance
    }

    /// Its Lambert runtime's `shaders` feature (None: not in the shader library).
    pub const fn irradiance_feature(self) -> Option<&'static str> {
        self.info().irradiance_feature
    }

    /// Its GGX specular runtime on `path` (0: the fit, 1: the per-lobe tables; see
    /// `profile::SpecularPath`): the `shaders` feature and the fitgen table it reads.
    pub const fn specular_runtime(self, path: usize) -> (Option<&'static str>, Option<&'static str>) {
        self.info().specular[path]
    }

    /// Its GPU slot kind (`KIND_n`), for the baked bases.
    pub const fn gpu_kind(self) -> Option<u32> {
        self.info().gpu_kind
    }
}

/// The bases themselves (with every basis family's feature). The rows are fixed, so
/// constructing one cannot fail (`every_row_builds` in sbf/tests/registry.rs).
#[cfg(all(feature = "sh", feature = "sg", feature = "ambient-dice", feature = "h-basis", feature = "ambient-cube"))]
impl BasisId {
    /// Lobe axes of the SG and AD layouts in coefficient order (empty for the others): SG
    /// on a Vogel spiral over the upper hemisphere, AD Roughton's 9 or the 12 icosahedron
    /// vertices.
    pub fn axes(self) -> Vec<DVec3> {
        match self {
            BasisId::Sg9 | BasisId::Sg12 => crate::layout::vogel_hemisphere(self.lobes()).expect("a Vogel layout of 9 or 12 lobes"),
            BasisId::Ad9 => AmbientDiceSrbf::nine_hemisphere().lobes().to_vec(),
            BasisId::Ad12 => AmbientDiceSrbf::twelve().lobes().to_vec(),
            BasisId::Sh1 | BasisId::Sh2 | BasisId::Zh3 | BasisId::AmbientCube | BasisId::H4 | BasisId::H6 => Vec::new(),
        }
    }

    /// The f64 basis, SG lobes of sharpness `sg_sharpness` (> 0; the caller validates a
    /// user's value).
    pub fn basis_with(self, sg_sharpness: f64) -> Box<dyn Basis + Send + Sync> {
        match self {
            BasisId::Sh1 | BasisId::Zh3 => Box::new(ShBasis::new(1).expect("SH order 1")),
            BasisId::Sh2 => Box::new(ShBasis::new(2).expect("SH order 2")),
            BasisId::Sg9 | BasisId::Sg12 => {
                Box::new(SgBasis::new(&self.axes(), sg_sharpness, false).expect("SG lobes of a positive sharpness"))
            }
            BasisId::Ad9 => Box::new(AmbientDiceSrbf::nine_hemisphere()),
            BasisId::Ad12 => Box::new(AmbientDiceSrbf::twelve()),
            BasisId::AmbientCube => Box::new(AmbientCube),
            BasisId::H4 => Box::new(HBasis::new(4).expect("H-basis 4")),
            BasisId::H6 => Box::new(HBasis::new(6).expect("H-basis 6")),
        }
    }

    /// The f64 basis the coefficients are in, SG at [`SG_SHARPNESS`].
    pub fn basis(self) -> Box<dyn Basis + Send + Sync> {
        self.basis_with(SG_SHARPNESS)
    }
}
