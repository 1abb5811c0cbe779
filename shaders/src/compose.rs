//! Composition with pruning: a configuration names the runtime functions it calls;
//! the composed module holds those, everything they use (transitively), and nothing
//! else, and says what it left out.
//!
//! Items are the top-level declarations of our WGSL files (`fn`, `const`, `struct`,
//! `alias`, `override`), each starting at column 0 with its comment lines just above
//! it; an item depends on every other item whose name appears as an identifier in its
//! text (comments stripped). This is exact for our own sources, which follow that
//! layout (a test checks that every module splits into items that re-assemble to the
//! original and that naga validates each composition).

use crate::modules::{self, Module};
use std::collections::{BTreeSet, HashMap};

/// A runtime capability a configuration can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Feature {
    ShEval,
    ShL1Irradiance,
    ShL2Irradiance,
    ShL4Irradiance,
    ShL1Geomerics,
    ShL1Zh3,
    ShSpecular,
    ShRotate,
    SgEval,
    SgIrradiance,
    SgSpecular,
    SgSpecularAsg,
    AdEval,
    Ad9Irradiance,
    Ad12Irradiance,
    Ad9Specular,
    Ad12Specular,
    LobeGgxSpecular,
    LobeGgxFiltered,
    Ggx,
    GgxEnergyCompensation,
    AdBezier,
    LightmapBicubic,
    EngineFormats,
    Progressive,
    Slc,
}

impl Feature {
    /// Every feature with its command-line name.
    pub const ALL: [(Feature, &'static str); 26] = [
        (Feature::ShEval, "sh-eval"),
        (Feature::ShL1Irradiance, "sh-l1-irradiance"),
        (Feature::ShL2Irradiance, "sh-l2-irradiance"),
        (Feature::ShL4Irradiance, "sh-l4-irradiance"),
        (Feature::ShL1Geomerics, "sh-l1-geomerics"),
        (Feature::ShL1Zh3, "sh-l1-zh3"),
        (Feature::ShSpecular, "sh-specular"),
        (Feature::ShRotate, "sh-rotate"),
        (Feature::SgEval, "sg-eval"),
        (Feature::SgIrradiance, "sg-irradiance"),
        (Feature::SgSpecular, "sg-specular"),
        (Feature::SgSpecularAsg, "sg-specular-asg"),
        (Feature::AdEval, "ad-eval"),
        (Feature::Ad9Irradiance, "ad9-irradiance"),
        (Feature::Ad12Irradiance, "ad12-irradiance"),
        (Feature::Ad9Specular, "ad9-specular"),
        (Feature::Ad12Specular, "ad12-specular"),
        (Feature::LobeGgxSpecular, "lobe-ggx-specular"),
        (Feature::LobeGgxFiltered, "lobe-ggx-filtered"),
        (Feature::Ggx, "ggx"),
        (Feature::GgxEnergyCompensation, "ggx-energy-compensation"),
        (Feature::AdBezier, "ad-bezier"),
        (Feature::LightmapBicubic, "lightmap-bicubic"),
        (Feature::EngineFormats, "engine-formats"),
        (Feature::Progressive, "progressive"),
        (Feature::Slc, "slc"),
    ];

    /// The WGSL functions this feature exposes (the roots of its composition).
    pub fn roots(self) -> &'static [&'static str] {
        match self {
            Feature::ShEval => &["sh_eval_l1", "sh_eval_l2", "sh_eval_l4"],
            Feature::ShL1Irradiance => &["sh_l1_irradiance"],
            Feature::ShL2Irradiance => &["sh_l2_irradiance"],
            Feature::ShL4Irradiance => &["sh_l4_irradiance"],
            Feature::ShL1Geomerics => &["sh_l1_geomerics_irradiance"],
            Feature::ShL1Zh3 => &["sh_l1_zh3_irradiance"],
            Feature::ShSpecular => &["sh_l1_specular", "sh_l2_specular"],
            Feature::ShRotate => &["sh_rotate_l1", "sh_rotate_l2", "sh_rotate_l4"],
            Feature::SgEval => &["sg_eval", "sg_integral"],
            Feature::SgIrradiance => &["sg_hill_irradiance", "sg9_irradiance", "sg12_irradiance"],
            Feature::SgSpecular => &["sg_split_sum_setup", "sg_split_sum_lobe", "sg9_specular", "sg12_specular"],
            Feature::SgSpecularAsg => &["sg_asg_warp", "sg_asg_lobe"],
            Feature::AdEval => &["ad_srbf_eval"],
            Feature::Ad9Irradiance => &["ad9_irradiance"],
            Feature::Ad12Irradiance => &["ad12_irradiance"],
            Feature::Ad9Specular => &["ad9_specular"],
            Feature::Ad12Specular => &["ad12_specular"],
            Feature::LobeGgxSpecular => &["lobe_ggx_pixel", "lobe_ggx_lobe"],
            Feature::LobeGgxFiltered => &["lobe_ggx_filtered_pixel", "lobe_ggx_filtered_lobe"],
            Feature::Ggx => &["ggx_d", "ggx_g1", "ggx_g2", "ggx_lambda", "schlick_weight"],
            Feature::GgxEnergyCompensation => &["ggx_energy_compensation"],
            Feature::AdBezier => &["ad_bezier_weights", "ad_bezier_eval", "ad_ycocg_eval"],
            Feature::LightmapBicubic => &["lightmap_bicubic_taps", "lightmap_bspline_axis"],
            Feature::EngineFormats => &[
                "godot_l1_irradiance",
                "godot_l1_legacy_irradiance",
                "monosh_irradiance",
                "monosh_linear_irradiance",
                "enlighten_irradiance",
                "enlighten_rgb_irradiance",
            ],
            Feature::Progressive => &["progressive_update"],
            Feature::Slc => &[
                "slc_acceptance",
                "slc_random_range",
                "slc_culled_estimate",
                "slc_schlick_max",
                "slc_dielectric_max",
                "slc_g1_dist",
                "slc_spheroid_scale",
                "slc_bound_surface",
                "slc_ggx_spheroid",
                "slc_diffuse_sphere",
                "slc_diffuse_intensity_bound",
                "slc_point_sphere",
                "slc_ray_sphere",
                "slc_equiangular_sample",
                "slc_equiangular_pdf",
                "slc_cull_transform",
                "slc_tile_corners",
                "slc_ellipsoid_hits_corners",
            ],
        }
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Option<Feature> {
        Feature::ALL.iter().find(|(_, n)| *n == s).map(|(f, _)| *f)
    }
}

/// Named configurations (a preset or a comma-separated feature list is accepted).
pub const PRESETS: [(&str, &[&str]); 9] = [
    ("all", &[]),
    ("ad9-irradiance", &["ad9-irradiance"]),
    ("ad9", &["ad9-irradiance", "ad9-specular"]),
    ("ad12", &["ad12-irradiance", "ad12-specular"]),
    ("sh-l2", &["sh-l2-irradiance"]),
    ("sh-l1", &["sh-l1-irradiance", "sh-l1-geomerics", "sh-l1-zh3"]),
    ("sg", &["sg-irradiance", "sg-specular"]),
    ("lambert", &["sh-l2-irradiance", "sg-irradiance", "ad9-irradiance", "ad12-irradiance"]),
    ("engine-lightmaps", &["engine-formats", "lightmap-bicubic"]),
];

/// A set of features.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    pub name: String,
    pub features: BTreeSet<Feature>,
}

impl Config {
    /// A preset name ("all", "ad9-irradiance", …) or a comma-separated list of features and
    /// presets (a preset stands for its features: `sh-l2,sg` is the union of the two).
    pub fn parse(s: &str) -> Result<Config, String> {
        if let Some((name, feats)) = PRESETS.iter().find(|(n, _)| *n == s) {
            let features: BTreeSet<Feature> = if *name == "all" {
                Feature::ALL.iter().map(|(f, _)| *f).collect()
            } else {
                feats.iter().filter_map(|f| Feature::parse(f)).collect()
            };
            return Ok(Config { name: name.to_string(), features });
        }
        let mut features = BTreeSet::new();
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            if Feature::parse(part).is_none() && PRESETS.iter().any(|(n, _)| *n == part) {
                features.extend(Config::parse(part)?.features);
                continue;
            }
            let f = Feature::parse(part).ok_or_else(|| {
                let presets: Vec<&str> = PRESETS.iter().map(|(n, _)| *n).collect();
                let feats: Vec<&str> = Feature::ALL.iter().map(|(_, n)| *n).collect();
                format!("unknown configuration or feature '{part}' (presets: {}; features: {})", presets.join(", "), feats.join(", "))
            })?;
            features.insert(f);
        }
        if features.is_empty() {
            return Err("empty configuration".into());
        }
        Ok(Config { name: s.to_string(), features })
    }
}

/// One top-level WGSL declaration.
#[derive(Debug, Clone)]
pub struct Item {
    pub module: &'static str,
    pub name: String,
    /// The declaration with the comment lines just above it.
    pub text: String,
}

/// A module split into its header (leading comment block) and items.
#[derive(Debug, Clone)]
pub struct Split {
    pub module: &'static str,
    pub header: String,
    pub items: Vec<Item>,
}

fn item_name(line: &str) -> Option<String> {
    for kw in ["fn ", "const ", "struct ", "alias ", "override "] {
        if let Some(rest) = line.strip_prefix(kw) {
            let name: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            return (!name.is_empty()).then_some(name);
        }
    }
    None
}

/// Splits a module into header and items (see the module docs for the layout).
pub fn split(m: &Module) -> Split {
    let lines: Vec<&str> = m.source.lines().collect();
    let starts: Vec<(usize, String)> = lines.iter().enumerate().filter_map(|(i, l)| item_name(l).map(|n| (i, n))).collect();
    // An item's text begins at its run of comment lines directly above it.
    let begin = |i: usize| {
        let mut b = i;
        while b > 0 && lines[b - 1].starts_with("//") {
            b -= 1;
        }
        b
    };
    let first = starts.first().map(|(i, _)| begin(*i)).unwrap_or(lines.len());
    let header = lines[..first].join("\n");
    let mut items = Vec::new();
    for (k, (i, name)) in starts.iter().enumerate() {
        let end = starts.get(k + 1).map(|(j, _)| begin(*j)).unwrap_or(lines.len());
        let text = lines[begin(*i)..end].join("\n");
        items.push(Item { module: m.name, name: name.clone(), text: text.trim_end().to_string() });
    }
    Split { module: m.name, header: header.trim_end().to_string(), items }
}

/// Identifiers in WGSL text with `//` comments removed.
fn identifiers(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut cur = String::new();
        for c in code.chars().chain(std::iter::once(' ')) {
            if c.is_ascii_alphanumeric() || c == '_' {
                cur.push(c);
            } else if !cur.is_empty() {
                out.insert(std::mem::take(&mut cur));
            }
        }
    }
    out
}

/// A composed module and what was left out.
#[derive(Debug, Clone)]
pub struct Composed {
    pub config: Config,
    pub source: String,
    /// (module, item) included, in order.
    pub included: Vec<(String, String)>,
    /// (module, item, bytes) left out.
    pub left_out: Vec<(String, String, usize)>,
}

impl Composed {
    /// Bytes of the items left out.
    pub fn left_out_bytes(&self) -> usize {
        self.left_out.iter().map(|x| x.2).sum()
    }

    /// One-line summary: size, items kept, what was left out.
    pub fn summary(&self) -> String {
        let fns_out = self.left_out.len();
        format!(
            "{}: {} bytes, {} items kept, {} left out ({} bytes)",
            self.config.name,
            self.source.len(),
            self.included.len(),
            fns_out,
            self.left_out_bytes()
        )
    }
}

/// Composes the modules a configuration needs, pruned to the items reachable from its roots.
pub fn compose(config: &Config) -> Result<Composed, String> {
    let roots: Vec<&str> = config.features.iter().flat_map(|f| f.roots().iter().copied()).collect();
    compose_roots(config.clone(), &roots)
}

/// Composes the items reachable from `roots` (any top-level WGSL names: functions,
/// constants, structs), e.g. for a kernel that calls helpers no feature exposes;
/// `config` only names the result.
pub fn compose_roots(config: Config, roots: &[&str]) -> Result<Composed, String> {
    let splits: Vec<Split> = modules::all().iter().map(split).collect();
    let mut by_name: HashMap<&str, &Item> = HashMap::new();
    for s in &splits {
        for it in &s.items {
            if by_name.insert(it.name.as_str(), it).is_some() {
                return Err(format!("WGSL item '{}' is declared twice", it.name));
            }
        }
    }
    let mut keep: BTreeSet<String> = BTreeSet::new();
    let mut stack: Vec<String> = Vec::new();
    for r in roots {
        if !by_name.contains_key(r) {
            return Err(format!("configuration '{}' names '{r}', which no module declares", config.name));
        }
        stack.push(r.to_string());
    }
    while let Some(n) = stack.pop() {
        if !keep.insert(n.clone()) {
            continue;
        }
        let it = by_name[n.as_str()];
        for id in identifiers(&it.text) {
            if id != n && by_name.contains_key(id.as_str()) && !keep.contains(&id) {
                stack.push(id);
            }
        }
    }
    let mut source = format!("// Composed by the sbf `shaders` crate for configuration '{}'. Generated; do not edit.\n", config.name);
    let (mut included, mut left_out) = (Vec::new(), Vec::new());
    for s in &splits {
        let kept: Vec<&Item> = s.items.iter().filter(|it| keep.contains(&it.name)).collect();
        for it in s.items.iter().filter(|it| !keep.contains(&it.name)) {
            left_out.push((s.module.to_string(), it.name.clone(), it.text.len() + 2));
        }
        if kept.is_empty() {
            continue;
        }
        source += "\n";
        source += &s.header;
        source += "\n";
        for it in kept {
            source += "\n";
            source += &it.text;
            source += "\n";
            included.push((s.module.to_string(), it.name.clone()));
        }
    }
    Ok(Composed { config, source, included, left_out })
}

#[cfg(test)]
mod tests {
    use super::{Config, Feature, PRESETS};

    /// Every preset lists known features (an unknown name would be dropped silently), and a
    /// preset named like a feature is that feature alone — `Config::parse` prefers presets,
    /// so anything else would change what the feature's name composes.
    #[test]
    fn presets_are_known_features_and_do_not_shadow_one() {
        for (name, feats) in PRESETS {
            for f in feats {
                assert!(Feature::parse(f).is_some(), "preset '{name}' lists unknown feature '{f}'");
            }
            if let Some(f) = Feature::parse(name) {
                let c = Config::parse(name).unwrap();
                assert_eq!(c.features.into_iter().collect::<Vec<_>>(), vec![f], "preset '{name}' shadows the feature of that name");
            }
        }
    }
}
