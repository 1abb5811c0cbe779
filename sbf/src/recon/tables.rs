//! The committed tables of `luts/` ([`crate::luts::committed`]) as samplers, each parsed
//! once on first use. Each is compiled in only with its cargo feature (`lut-dfg`,
//! `lut-ad-specular-2d`, `lut-lobe-ggx-sg6`, `lut-lobe-ggx-ad`; all in the default `luts`).

// Used by whichever tables are enabled (none, some or all).
#[allow(unused_imports)]
use {
    super::{lobe_ggx::Table, lut::Lut2},
    crate::luts::{committed, LutFile},
    std::sync::OnceLock,
};

#[cfg(any(feature = "lut-dfg", feature = "lut-ad-specular-2d"))]
fn parse2(bytes: &'static [u8], what: &str) -> Lut2 {
    // The bytes are compiled in and checked by fitgen --check in CI: a parse failure is
    // a build defect, not user input.
    Lut2::from_file(&LutFile::parse(bytes).unwrap_or_else(|e| panic!("committed {what}: {e}")))
        .unwrap_or_else(|e| panic!("committed {what}: {e}"))
}

/// The split-sum DFG table: sample with (n·v, α) → (f0 scale, f90 scale).
#[cfg(feature = "lut-dfg")]
pub fn dfg() -> &'static Lut2 {
    static L: OnceLock<Lut2> = OnceLock::new();
    L.get_or_init(|| parse2(committed::DFG_DATA, "dfg.sbflut"))
}

/// The Ambient Dice specular LUT ([Roughton19 Listing 8.2]): (n·v, α) → (f0, f90 scale).
#[cfg(feature = "lut-ad-specular-2d")]
pub fn ad_specular_2d() -> &'static Lut2 {
    static L: OnceLock<Lut2> = OnceLock::new();
    L.get_or_init(|| parse2(committed::AD_SPECULAR_2D_DATA, "ad_specular_2d.sbflut"))
}

#[cfg(any(feature = "lut-lobe-ggx-sg6", feature = "lut-lobe-ggx-ad"))]
fn parse_lobe(bytes: &'static [u8], what: &str) -> Table {
    Table::from_file(&LutFile::parse(bytes).unwrap_or_else(|e| panic!("committed {what}: {e}")))
        .unwrap_or_else(|e| panic!("committed {what}: {e}"))
}

/// The GGX response table of an SG lobe of sharpness 6 (every SG basis of `probes`):
/// see [`super::lobe_ggx`].
#[cfg(feature = "lut-lobe-ggx-sg6")]
pub fn lobe_ggx_sg6() -> &'static Table {
    static T: OnceLock<Table> = OnceLock::new();
    T.get_or_init(|| parse_lobe(committed::LOBE_GGX_SG6_DATA, "lobe_ggx_sg6.sbflut"))
}

/// The GGX response table of an Ambient Dice SRBF lobe: see [`super::lobe_ggx`].
#[cfg(feature = "lut-lobe-ggx-ad")]
pub fn lobe_ggx_ad() -> &'static Table {
    static T: OnceLock<Table> = OnceLock::new();
    T.get_or_init(|| parse_lobe(committed::LOBE_GGX_AD_DATA, "lobe_ggx_ad.sbflut"))
}
