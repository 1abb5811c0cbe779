//! The lighting profile: one small TOML file that says what a scene's lighting needs —
//! the bases per signal, the BRDF set and roughness range, the runtime precision and the
//! target shading language — so that every tool leaves out the rest (`--profile FILE` on
//! fitgen, shaders, baker and probes). Behind the `profile` feature.
//!
//! ```toml
//! name = "AD9 diffuse + specular"
//!
//! [lightmap]
//! bases = ["ad9"]             # sh1, sh2, sg9, sg12, ad9, ad12, zh3
//!
//! [probes]
//! bases = ["sh2"]             # sphere bases: sh1, sh2, ad12, zh3 ([] = no probes)
//!
//! [brdf]
//! models = ["lambert", "ggx"] # lambert and optionally ggx (specular)
//! roughness = [0.1, 0.8]      # GGX α range, required with "ggx"
//! multiple_scattering = "compensated"  # optional with "ggx": "single" (default) or
//!                             # "compensated" (energy compensation, recon::multiscatter)
//!
//! [runtime]
//! precision = "f32"           # the runtime library is f32
//! language = "wgsl"           # wgsl, hlsl, glsl (Vulkan), glsl-gl, glsl-es, msl
//! specular = ["fit"]          # with "ggx": "fit" and/or "tables" (see SpecularPath)
//! ```
//!
//! Every table is required except `[probes]` (no probes) — an omitted key is an error
//! naming it, as is an unknown key or value; errors give the line and column of the value
//! at fault (every tool exits with status 2 for a profile it cannot use).

use serde::Deserialize;
use std::fmt;
use toml::Spanned;

use crate::registry::BasisId;

/// BRDF models.
pub const BRDF_MODELS: [&str; 2] = ["lambert", "ggx"];
/// Target shading languages (`shaders export --lang`).
/// `glsl` is Vulkan GLSL; `glsl-gl` OpenGL 3.3+ core; `glsl-es` OpenGL ES 3.0 / WebGL 2.
pub const LANGUAGES: [&str; 6] = ["wgsl", "hlsl", "glsl", "glsl-gl", "glsl-es", "msl"];
/// Specular runtime paths (`runtime.specular`).
pub const SPECULAR_PATHS: [&str; 2] = ["fit", "tables"];

/// How SG and Ambient Dice lobes reflect GGX at runtime — the one choice every tool reads
/// from the profile: fitgen generates the tables it reads, shaders exports its functions,
/// the baker writes both, probes measures it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecularPath {
    /// Closed-form fits: SG through the ASG warp, AD through [Roughton19 Listing 8.1] × the
    /// Listing 8.2 table (`ad-specular-2d`).
    Fit,
    /// Per-lobe GGX response tables (`lobe-ggx-sg6`, `lobe-ggx-ad`): interpolation is the
    /// only approximation.
    Tables,
}

impl SpecularPath {
    /// `fit` or `tables`.
    pub fn name(self) -> &'static str {
        match self {
            SpecularPath::Fit => "fit",
            SpecularPath::Tables => "tables",
        }
    }
}

/// What a basis's GGX specular needs at runtime on a path: the `shaders` composition
/// feature (None: none) and the fitgen table it reads (None: none). SH has one path on
/// both names: the zonal filter about the dominant direction with the split-sum DFG; SG's
/// fit path is a split sum too and reads the same table.
pub fn specular_runtime(basis: BasisId, path: SpecularPath) -> (Option<&'static str>, Option<&'static str>) {
    basis.specular_runtime(path as usize)
}

/// The file a fitgen table is committed as (`ad-specular-2d` → `ad_specular_2d.sbflut`).
pub fn table_file(table: &str) -> String {
    format!("{}.sbflut", table.replace('-', "_"))
}

/// A validated lighting profile.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Its `name` key.
    pub name: String,
    /// Lightmap bases, in the order given.
    pub lightmap_bases: Vec<BasisId>,
    /// Probe bases ([] = no probes).
    pub probe_bases: Vec<BasisId>,
    /// GGX specular is part of the BRDF set.
    pub specular: bool,
    /// GGX α range (lo, hi), 0 < lo ≤ hi ≤ 1, when `specular`.
    pub roughness: Option<(f64, f64)>,
    /// GGX specular with multiple-scattering energy compensation (`brdf.multiple_scattering
    /// = "compensated"`; [`crate::recon::multiscatter`]); false: single scattering.
    pub multiple_scattering: bool,
    /// Always "f32" today (the only runtime precision the library has).
    pub precision: String,
    /// The shading language its runtime is exported in: "wgsl", "hlsl", "glsl" (Vulkan),
    /// "glsl-gl" (OpenGL 3.3+ core), "glsl-es" (OpenGL ES 3.0) or "msl".
    pub language: String,
    /// The specular runtime paths (one or both; empty without GGX).
    pub specular_paths: Vec<SpecularPath>,
}

/// A profile that cannot be used, with the key at fault.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileError {
    /// Dotted key ("brdf.roughness"), or "" for a syntax error.
    pub key: String,
    /// What is wrong with it.
    pub message: String,
    /// 1-based (line, column) of the value at fault (or of the syntax error); None when
    /// the text has no place for it (a missing key).
    pub at: Option<(usize, usize)>,
}

impl fmt::Display for ProfileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "lighting profile")?;
        if let Some((l, c)) = self.at {
            write!(f, " (line {l}, column {c})")?;
        }
        if self.key.is_empty() {
            write!(f, ": {}", self.message)
        } else {
            write!(f, ": `{}`: {}", self.key, self.message)
        }
    }
}

/// 1-based (line, column) of byte `offset` in `text` (columns count characters).
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

impl std::error::Error for ProfileError {}

// Every value keeps its place in the text (toml's Spanned) so an error can say where.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    name: Spanned<String>,
    lightmap: RawBases,
    probes: Option<RawBases>,
    brdf: RawBrdf,
    runtime: RawRuntime,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBases {
    bases: Spanned<Vec<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBrdf {
    models: Spanned<Vec<String>>,
    roughness: Option<Spanned<Vec<f64>>>,
    multiple_scattering: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRuntime {
    precision: Spanned<String>,
    language: Spanned<String>,
    specular: Option<Spanned<Vec<String>>>,
}

/// Builds errors that point into one profile's text.
struct At<'t>(&'t str);

impl At<'_> {
    fn err<T>(&self, key: &str, value: &Spanned<T>, message: impl Into<String>) -> ProfileError {
        ProfileError { key: key.into(), message: message.into(), at: Some(line_column(self.0, value.span().start)) }
    }

    fn names(&self, key: &str, given: &Spanned<Vec<String>>, allowed: &[&str], allow_empty: bool) -> Result<Vec<String>, ProfileError> {
        if given.get_ref().is_empty() && !allow_empty {
            return Err(self.err(key, given, format!("must name at least one of {}", allowed.join(", "))));
        }
        let mut out: Vec<String> = Vec::new();
        for g in given.get_ref() {
            if !allowed.contains(&g.as_str()) {
                return Err(self.err(key, given, format!("unknown '{g}' (expected one of {})", allowed.join(", "))));
            }
            if out.contains(g) {
                return Err(self.err(key, given, format!("'{g}' is named twice")));
            }
            out.push(g.clone());
        }
        Ok(out)
    }
}

impl Profile {
    /// Parses and validates a profile's TOML text.
    pub fn parse(text: &str) -> Result<Profile, ProfileError> {
        let raw: Raw = toml::from_str(text).map_err(|e| {
            // toml names the missing or unknown key in its message; keep it whole.
            ProfileError { key: String::new(), message: e.message().to_string(), at: e.span().map(|s| line_column(text, s.start)) }
        })?;
        let at = At(text);
        if raw.name.get_ref().trim().is_empty() {
            return Err(at.err("name", &raw.name, "must not be empty"));
        }
        let ids = |names: Vec<String>| names.iter().filter_map(|n| BasisId::from_name(n)).collect::<Vec<_>>();
        let lightmap: Vec<&str> = BasisId::lightmap().map(BasisId::name).collect();
        let lightmap_bases = ids(at.names("lightmap.bases", &raw.lightmap.bases, &lightmap, false)?);
        let probe: Vec<&str> = BasisId::probe().map(BasisId::name).collect();
        let probe_bases = match &raw.probes {
            Some(p) => ids(at.names("probes.bases", &p.bases, &probe, true)?),
            None => Vec::new(),
        };
        let models = at.names("brdf.models", &raw.brdf.models, &BRDF_MODELS, false)?;
        if !models.iter().any(|m| m == "lambert") {
            return Err(at.err("brdf.models", &raw.brdf.models, "must include \"lambert\" (every basis reconstructs diffuse irradiance)"));
        }
        let specular = models.iter().any(|m| m == "ggx");
        let roughness = match (&raw.brdf.roughness, specular) {
            (None, true) => {
                return Err(at.err("brdf.roughness", &raw.brdf.models, "is required with \"ggx\": [lo, hi], 0 < lo <= hi <= 1"))
            }
            (Some(r), false) => return Err(at.err("brdf.roughness", r, "is only meaningful with \"ggx\" in brdf.models")),
            (None, false) => None,
            (Some(rs), true) => {
                let r = rs.get_ref();
                let ok = r.len() == 2 && r.iter().all(|x| x.is_finite()) && r[0] > 0.0 && r[0] <= r[1] && r[1] <= 1.0;
                if !ok {
                    return Err(at.err("brdf.roughness", rs, format!("{r:?} is not [lo, hi] with 0 < lo <= hi <= 1")));
                }
                Some((r[0], r[1]))
            }
        };
        let multiple_scattering = match (&raw.brdf.multiple_scattering, specular) {
            (None, _) => false,
            (Some(m), false) => return Err(at.err("brdf.multiple_scattering", m, "is only meaningful with \"ggx\" in brdf.models")),
            (Some(m), true) => match m.get_ref().as_str() {
                "single" => false,
                "compensated" => true,
                other => {
                    return Err(at.err(
                        "brdf.multiple_scattering",
                        m,
                        format!("unknown '{other}' (expected \"single\" or \"compensated\")"),
                    ))
                }
            },
        };
        let precision = raw.runtime.precision.get_ref();
        if precision != "f32" {
            return Err(at.err(
                "runtime.precision",
                &raw.runtime.precision,
                format!("'{precision}' is not available: the runtime library (sbf f32 API and WGSL) computes in f32"),
            ));
        }
        let language = raw.runtime.language.get_ref();
        if !LANGUAGES.contains(&language.as_str()) {
            return Err(at.err(
                "runtime.language",
                &raw.runtime.language,
                format!("unknown '{language}' (expected one of {})", LANGUAGES.join(", ")),
            ));
        }
        let specular_paths = match (&raw.runtime.specular, specular) {
            (None, true) => {
                return Err(at.err("runtime.specular", &raw.brdf.models, "is required with \"ggx\": [\"fit\"], [\"tables\"] or both"))
            }
            (Some(p), false) => return Err(at.err("runtime.specular", p, "is only meaningful with \"ggx\" in brdf.models")),
            (None, false) => Vec::new(),
            (Some(p), true) => at
                .names("runtime.specular", p, &SPECULAR_PATHS, false)?
                .iter()
                .map(|n| if n == "fit" { SpecularPath::Fit } else { SpecularPath::Tables })
                .collect(),
        };
        Ok(Profile {
            specular_paths,
            name: raw.name.into_inner(),
            lightmap_bases,
            probe_bases,
            specular,
            roughness,
            multiple_scattering,
            precision: raw.runtime.precision.into_inner(),
            language: raw.runtime.language.into_inner(),
        })
    }

    /// Reads and validates a profile file (errors name the file).
    pub fn load(path: &std::path::Path) -> Result<Profile, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Profile::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The profile as TOML text that [`Profile::parse`] turns back into it (keys in the
    /// module example's order; bake specs record a profile this way).
    pub fn to_toml(&self) -> String {
        let list = |v: &[&str]| v.iter().map(|s| format!("{s:?}")).collect::<Vec<_>>().join(", ");
        let bases = |v: &[BasisId]| list(&v.iter().map(|b| b.name()).collect::<Vec<_>>());
        let mut t = format!("name = {:?}\n\n[lightmap]\nbases = [{}]\n", self.name, bases(&self.lightmap_bases));
        if !self.probe_bases.is_empty() {
            t += &format!("\n[probes]\nbases = [{}]\n", bases(&self.probe_bases));
        }
        t += &format!("\n[brdf]\nmodels = [{}]\n", list(if self.specular { &["lambert", "ggx"] } else { &["lambert"] }));
        if let Some((lo, hi)) = self.roughness {
            // `{:?}` of an f64 is its shortest round-trip text, with a '.' or an exponent
            // (both TOML floats).
            t += &format!("roughness = [{lo:?}, {hi:?}]\n");
        }
        if self.specular {
            t += &format!("multiple_scattering = {:?}\n", if self.multiple_scattering { "compensated" } else { "single" });
        }
        t += &format!("\n[runtime]\nprecision = {:?}\nlanguage = {:?}\n", self.precision, self.language);
        if !self.specular_paths.is_empty() {
            t += &format!("specular = [{}]\n", list(&self.specular_paths.iter().map(|p| p.name()).collect::<Vec<_>>()));
        }
        t
    }

    /// Every basis the profile names, lightmap then probes, without repeats.
    pub fn all_bases(&self) -> Vec<BasisId> {
        let mut v: Vec<BasisId> = Vec::new();
        for b in self.lightmap_bases.iter().chain(&self.probe_bases) {
            if !v.contains(b) {
                v.push(*b);
            }
        }
        v
    }

    /// The embedded tables (fitgen output names) the profile's runtime paths read
    /// ([`specular_runtime`] of every basis on every path it names); the fit constants always.
    pub fn tables(&self) -> Vec<&'static str> {
        let mut t = vec!["fits", "fits-wgsl"];
        for b in self.all_bases() {
            for p in &self.specular_paths {
                if let (_, Some(table)) = specular_runtime(b, *p) {
                    if !t.contains(&table) {
                        t.push(table);
                    }
                }
            }
        }
        // The energy compensation reads the DFG table's single-scattering albedo.
        if self.multiple_scattering && !t.contains(&"dfg") {
            t.push("dfg");
        }
        t
    }

    /// The `shaders` composition features of the profile's specular runtime (every basis
    /// on every path), sorted and unique.
    pub fn specular_features(&self) -> Vec<&'static str> {
        let mut f: Vec<&'static str> =
            self.all_bases().iter().flat_map(|b| self.specular_paths.iter().filter_map(|p| specular_runtime(*b, *p).0)).collect();
        if self.multiple_scattering {
            f.push("ggx-energy-compensation");
        }
        f.sort_unstable();
        f.dedup();
        f
    }

    /// The `sbf` cargo features an engine needs for this profile: the basis families it
    /// names and the tables its runtime paths read.
    pub fn cargo_features(&self) -> Vec<&'static str> {
        let mut f = Vec::new();
        for b in self.all_bases() {
            let fam = b.family().cargo_feature();
            if !f.contains(&fam) {
                f.push(fam);
            }
        }
        for t in self.tables() {
            match t {
                "dfg" => f.push("lut-dfg"),
                "ad-specular-2d" => f.push("lut-ad-specular-2d"),
                "lobe-ggx-sg6" => f.push("lut-lobe-ggx-sg6"),
                "lobe-ggx-ad" => f.push("lut-lobe-ggx-ad"),
                _ => {}
            }
        }
        f
    }

    /// One line describing the profile (for logs, bake.json and reports).
    pub fn summary(&self) -> String {
        format!(
            "{}: lightmap {}, probes {}, BRDF lambert{}, {} {}",
            self.name,
            names(&self.lightmap_bases),
            if self.probe_bases.is_empty() { "none".to_string() } else { names(&self.probe_bases) },
            match self.roughness {
                Some((lo, hi)) => format!(
                    " + ggx α {lo}–{hi} ({}{})",
                    self.specular_paths.iter().map(|p| p.name()).collect::<Vec<_>>().join(" + "),
                    if self.multiple_scattering { ", multiple scattering compensated" } else { "" }
                ),
                None => String::new(),
            },
            self.precision,
            self.language
        )
    }
}

/// Basis names joined by `+` (`sh2+ad9`).
fn names(bases: &[BasisId]) -> String {
    bases.iter().map(|b| b.name()).collect::<Vec<_>>().join("+")
}
