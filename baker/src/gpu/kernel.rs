//! The bake's WGSL, composed per bake from modules by `naga_oil` (Bevy's composer).
//!
//! Every file of `wgsl/` and `wavefront/` that starts with `#define_import_path` is a
//! module (`baker::bindings`, `baker::sequence`, `baker::traverse`, `baker::lights`,
//! `baker::bsdf`, `baker::guide`, `baker::path`, `baker::jobs`, `baker::vertex`,
//! `baker::bases`, `baker::item`, `baker::filter_bindings`, `baker::filter_kernel`,
//! `baker::wave`); the `shaders` crate's runtime items the bake calls are one more,
//! `sbf::runtime`, pruned by that crate's composer to what the configured bases need. Each
//! pipeline's entry shader imports what it uses: `megakernel.wgsl` (the megakernel), the
//! wavefront's `generate`, `queue`, `intersect`, `shade` and `accumulate`, and
//! `filter_gather.wgsl` with a filter — a bake composes only the entry shaders it runs.
//!
//! What a bake needs is said by shader defs, not by generating source: `SEQUENCE`, and
//! `GLOSSY`, `GUIDING` (with `GUIDED_FRACTION_BITS`), `BATCH` (adaptive or camera-based
//! batches), `FILTERED` where the bake has them; `KIND_n` and per encoder slot k `SLOT_k`
//! (its basis kind), `SLOT_k_LOBES`, `SLOT_k_FLAGS`, `SLOT_k_DENOMINATOR`, `SLOT_k_MIRROR`,
//! `SLOT_k_AT` (`bases.wgsl` says what each means). The composed WGSL is written back by
//! naga with the composer's module suffixes removed from names wherever that is unique, so
//! a kernel reads like its sources.

use super::compose::{add_module, compose};
use crate::accumulate::{BakeConfig, BasisId, Pipeline, BAKE_ACCELERATION};
use crate::sampling::sequence::Sequence;
use naga_oil::compose::{Composer, ShaderDefValue};
use sbf::registry::Family;
use shaders::progressive::EncoderParams;
use std::collections::HashMap;

/// The composable modules (file, source).
const MODULES: [(&str, &str); 15] = [
    ("bindings.wgsl", include_str!("wgsl/bindings.wgsl")),
    ("maps.wgsl", include_str!("wgsl/maps.wgsl")),
    ("sequence.wgsl", include_str!("wgsl/sequence.wgsl")),
    ("traverse.wgsl", include_str!("wgsl/traverse.wgsl")),
    ("lights.wgsl", include_str!("wgsl/lights.wgsl")),
    ("bsdf.wgsl", include_str!("wgsl/bsdf.wgsl")),
    ("guide.wgsl", include_str!("wgsl/guide.wgsl")),
    ("path.wgsl", include_str!("wgsl/path.wgsl")),
    ("jobs.wgsl", include_str!("wgsl/jobs.wgsl")),
    ("vertex.wgsl", include_str!("wgsl/vertex.wgsl")),
    ("filter_bindings.wgsl", include_str!("wgsl/filter_bindings.wgsl")),
    ("bases.wgsl", include_str!("wgsl/bases.wgsl")),
    ("item.wgsl", include_str!("wgsl/item.wgsl")),
    ("filter_kernel.wgsl", include_str!("wgsl/filter_kernel.wgsl")),
    ("wave.wgsl", include_str!("wavefront/wave.wgsl")),
];

/// The entry shaders (name, file, source).
const MEGAKERNEL: (&str, &str) = ("megakernel.wgsl", include_str!("wgsl/megakernel.wgsl"));
/// The wavefront passes' entry shaders, in pass-graph order.
pub const WAVEFRONT: [(&str, &str); 5] = [
    ("generate.wgsl", include_str!("wavefront/generate.wgsl")),
    ("queue.wgsl", include_str!("wavefront/queue.wgsl")),
    ("intersect.wgsl", include_str!("wavefront/intersect.wgsl")),
    ("shade.wgsl", include_str!("wavefront/shade.wgsl")),
    ("accumulate.wgsl", include_str!("wavefront/accumulate.wgsl")),
];
const FILTER_GATHER: (&str, &str) = ("filter_gather.wgsl", include_str!("wgsl/filter_gather.wgsl"));
const ADAPT: (&str, &str) = ("adapt.wgsl", include_str!("wgsl/adapt.wgsl"));
const GUIDE_COMMON: (&str, &str) = ("guide_common.wgsl", include_str!("wgsl/guide_common.wgsl"));
const GUIDE_BUILD: (&str, &str) = ("guide_build.wgsl", include_str!("wgsl/guide_build.wgsl"));
const GUIDE_BUILD_SUBGROUP: (&str, &str) = ("guide_build_subgroup.wgsl", include_str!("wgsl/guide_build_subgroup.wgsl"));

/// The most encoder slots (bases) of one bake: one per basis kind.
pub const MAX_SLOTS: usize = 7;

/// How ray guiding's distributions are built on this device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GuideBuild {
    /// Row and marginal prefix sums by subgroup scans (\[HWRTL\]'s wave prefix sums).
    Subgroup,
    /// Serial sums in workgroup memory (no subgroups, or subgroups narrower than a row).
    Workgroup,
}

/// The composed shaders of a bake and what its composition left out.
#[derive(Debug, Clone)]
pub struct Kernel {
    /// (entry shader file, composed WGSL) of every pipeline the bake runs.
    pub shaders: Vec<(&'static str, String)>,
    /// One line per left-out part ("GGX layer: no glossy material", shaders items).
    pub left_out: Vec<String>,
}

impl Kernel {
    /// The composed WGSL of entry shader `file` (e.g. "megakernel.wgsl").
    pub fn shader(&self, file: &str) -> Result<&str, String> {
        self.shaders.iter().find(|s| s.0 == file).map(|s| s.1.as_str()).ok_or_else(|| format!("the bake composed no {file}"))
    }
}

/// A composer holding every module, `sbf::runtime` being `runtime` (the `shaders` items).
fn composer(runtime: &str) -> Result<Composer, String> {
    let mut c = super::compose::composer();
    let modules = std::iter::once(("sbf_runtime.wgsl", runtime)).chain(MODULES.iter().copied());
    for (file, source) in modules {
        add_module(&mut c, file, source, (file == "sbf_runtime.wgsl").then(|| "sbf::runtime".to_string()))?;
    }
    Ok(c)
}

/// The shader defs of a bake of `config` on texels or probes (`sphere_targets`), and the
/// `shaders` items it calls.
fn defs(config: &BakeConfig, sphere_targets: bool, glossy: bool) -> Result<(HashMap<String, ShaderDefValue>, Vec<&'static str>), String> {
    if config.bases.len() > MAX_SLOTS {
        return Err(format!("a GPU bake encodes into at most {MAX_SLOTS} bases, not {}", config.bases.len()));
    }
    if BAKE_ACCELERATION != 1.0 {
        return Err(format!("bases.wgsl's ACCELERATION is 1.0, the bake's {BAKE_ACCELERATION}"));
    }
    let mut d: HashMap<String, ShaderDefValue> = HashMap::new();
    let on = |d: &mut HashMap<String, ShaderDefValue>, name: &str| {
        d.insert(name.to_string(), ShaderDefValue::Bool(true));
    };
    let mut roots =
        vec!["progressive_update", "progressive_update_projected", "EncoderState", "EncoderParams", "tangent_frame", "PI", "INV_PI"];
    if glossy {
        on(&mut d, "GLOSSY");
        roots.extend(["ggx_d", "ggx_g1", "ggx_g2", "schlick_weight"]);
    }
    if config.guiding.is_some() && !sphere_targets {
        on(&mut d, "GUIDING");
    }
    if (config.adaptive.is_some() || config.camera.is_some()) && !sphere_targets {
        on(&mut d, "BATCH");
    }
    if config.filter.is_some() && !sphere_targets {
        on(&mut d, "FILTERED");
    }
    let mut at = 3u32;
    for (k, b) in config.bases.iter().enumerate() {
        let kind = b.gpu_kind().expect("a lightmap basis has a GPU slot kind");
        on(&mut d, &format!("KIND_{kind}"));
        match b.family() {
            Family::Sh => {
                // SH L1 and ZH3 store the same four coefficients.
                if b.lobes() == 4 {
                    on(&mut d, "KIND_SH_L1");
                }
                roots.push(if b.lobes() == 4 { "sh_eval_l1" } else { "sh_eval_l2" })
            }
            Family::Sg => {
                on(&mut d, "KIND_SG");
                roots.push("sg_eval");
            }
            Family::AmbientDice => {
                on(&mut d, "KIND_AD");
                roots.extend(["ad_srbf_eval", if *b == BasisId::Ad9 { "AD9_AXES" } else { "AD12_AXES" }]);
            }
            Family::AmbientCube | Family::HBasis => unreachable!("{b}: not a lightmap basis (BakeConfig::check refuses it)"),
        }
        let lobes = b.lobes();
        let opts = config.encoder_options(*b, sphere_targets);
        let p = EncoderParams::new(&sbf::solve::ProgressiveOptions { mirror_hemisphere: false, ..opts.clone() }, lobes)?;
        let projection = p.denominator == shaders::progressive::DENOM_PROJECTION;
        // The projection of an orthonormal basis: every true mean 1/4π (bases.wgsl's
        // ORTHONORMAL_MEAN) on the lobes, zero past them.
        let orthonormal = (0..12).all(|i| p.true_mean[i / 4][i % 4] == if i < lobes { (0.25 / std::f64::consts::PI) as f32 } else { 0.0 });
        if p.acceleration != 1.0 || (projection && !orthonormal) || (!projection && p.true_mean != [[0.0; 4]; 3]) {
            return Err(format!(
                "{}: bases.wgsl's encoders take acceleration 1, no clamp-to-true denominator, and the projection only with the exact means 1/4π of an orthonormal basis",
                b.name()
            ));
        }
        if projection {
            d.insert(format!("SLOT_{k}_PROJECTION"), ShaderDefValue::Bool(true));
        }
        let slot = |what: &str| if what.is_empty() { format!("SLOT_{k}") } else { format!("SLOT_{k}_{what}") };
        d.insert(slot(""), ShaderDefValue::UInt(kind));
        d.insert(slot("LOBES"), ShaderDefValue::UInt(p.lobes));
        d.insert(slot("FLAGS"), ShaderDefValue::UInt(p.flags));
        d.insert(slot("DENOMINATOR"), ShaderDefValue::UInt(p.denominator));
        d.insert(slot("AT"), ShaderDefValue::UInt(at));
        if opts.mirror_hemisphere {
            d.insert(slot("MIRROR"), ShaderDefValue::Bool(true));
        }
        at += lobes as u32;
    }
    d.insert("SEQUENCE".into(), ShaderDefValue::UInt(config.sampler.code()));
    d.insert("SG_SHARPNESS_BITS".into(), ShaderDefValue::UInt((config.sg_sharpness as f32).to_bits()));
    let fraction = config.guiding.map_or(0.0, |g| g.guided_fraction as f32);
    d.insert("GUIDED_FRACTION_BITS".into(), ShaderDefValue::UInt(fraction.to_bits()));
    Ok((d, roots))
}

/// Composes the shaders of a bake of `config` (`glossy`: whether any material has a GGX
/// layer): the megakernel or the wavefront's passes, and the filter's gather.
pub fn kernel(config: &BakeConfig, sphere_targets: bool, glossy: bool) -> Result<Kernel, String> {
    kernel_with(config, sphere_targets, glossy, false)
}

/// [`kernel`], with the materials' texture maps (maps.wgsl, binding 20) where `textured`.
pub fn kernel_with(config: &BakeConfig, sphere_targets: bool, glossy: bool, textured: bool) -> Result<Kernel, String> {
    let (mut defs, roots) = defs(config, sphere_targets, glossy)?;
    if textured {
        defs.insert("TEXTURES".into(), ShaderDefValue::Bool(true));
    }
    let lib = shaders::compose::compose_roots(shaders::compose::Config { name: "baker".into(), features: Default::default() }, &roots)?;
    let mut c = composer(&lib.source)?;
    let mut entries = Vec::new();
    let mut left_out = Vec::new();
    if !glossy {
        left_out.push("GGX layer (no material in the scene is glossy): glossy sampling and the shaders GGX terms".to_string());
    }
    if !textured {
        left_out.push("texture maps (no material has one): the maps binding and their sampling".to_string());
    }
    if !defs.contains_key("GUIDING") {
        left_out.push("ray guiding (not enabled, or probes): the guide bindings, sampler and pdf".to_string());
    }
    if !defs.contains_key("BATCH") {
        left_out.push("adaptive and camera-based sampling (not enabled, or probes): the batch bindings".to_string());
    }
    left_out.push(format!("{} shaders items ({} bytes) the bake does not call", lib.left_out.len(), lib.left_out_bytes()));
    match config.pipeline {
        Pipeline::Wavefront => entries.extend(WAVEFRONT),
        Pipeline::Megakernel => {
            left_out.push("the wavefront passes (the megakernel pipeline)".to_string());
            entries.push(MEGAKERNEL);
        }
    }
    if defs.contains_key("FILTERED") {
        entries.push(FILTER_GATHER);
    } else {
        left_out.push("filtered accumulation (no --filter, or probes): the records and the gather".to_string());
    }
    let shaders = entries.into_iter().map(|e| Ok((e.0, compose(&mut c, e, &defs)?))).collect::<Result<Vec<_>, String>>()?;
    Ok(Kernel { shaders, left_out })
}

/// The composer with the bake's modules and the runtime items no bake leaves out, for the
/// kernels beside the bake's own.
fn plain_composer() -> Result<Composer, String> {
    let roots = ["progressive_update", "progressive_update_projected", "EncoderState", "EncoderParams", "tangent_frame", "PI", "INV_PI"];
    let lib = shaders::compose::compose_roots(shaders::compose::Config { name: "baker".into(), features: Default::default() }, &roots)?;
    composer(&lib.source)
}

/// Entry shader `entry` (file, source) composed beside the bake's modules with the
/// white-noise sequence (independent numbers per sample), and `GLOSSY` with the GGX
/// runtime items where `glossy`: for kernels of other layers that run the bake's
/// estimator (the renderer's path-traced reference).
pub fn estimator_kernel(entry: (&str, &str), glossy: bool) -> Result<String, String> {
    let mut roots =
        vec!["progressive_update", "progressive_update_projected", "EncoderState", "EncoderParams", "tangent_frame", "PI", "INV_PI"];
    let mut defs = HashMap::from([
        ("SEQUENCE".to_string(), ShaderDefValue::UInt(Sequence::Independent.code())),
        ("SG_SHARPNESS_BITS".to_string(), ShaderDefValue::UInt((crate::accumulate::SG_HEMISPHERE_SHARPNESS as f32).to_bits())),
    ]);
    if glossy {
        roots.extend(["ggx_d", "ggx_g1", "ggx_g2", "schlick_weight"]);
        defs.insert("GLOSSY".into(), ShaderDefValue::Bool(true));
    }
    let lib = shaders::compose::compose_roots(shaders::compose::Config { name: "baker".into(), features: Default::default() }, &roots)?;
    compose(&mut composer(&lib.source)?, entry, &defs)
}

/// The adaptive batch selection's kernel (`adapt.wgsl`) for `sequence`.
pub fn adapt_kernel(sequence: Sequence) -> Result<String, String> {
    let defs = HashMap::from([("SEQUENCE".to_string(), ShaderDefValue::UInt(sequence.code()))]);
    compose(&mut plain_composer()?, ADAPT, &defs)
}

/// The WGSL of ray guiding's kernels: (gather + workgroup build, subgroup build).
pub fn guide_build_sources() -> Result<(String, String), String> {
    let mut c = plain_composer()?;
    add_module(&mut c, GUIDE_COMMON.0, GUIDE_COMMON.1, None)?;
    Ok((compose(&mut c, GUIDE_BUILD, &HashMap::new())?, compose(&mut c, GUIDE_BUILD_SUBGROUP, &HashMap::new())?))
}

/// The sample sequences of `sequence` as plain WGSL (`Sampler`, `group_point`,
/// `sampler_new`, `sample4`, `sampler_staged` and what they use), for a test harness.
pub fn sequence_library(sequence: Sequence) -> Result<String, String> {
    let defs = HashMap::from([("SEQUENCE".to_string(), ShaderDefValue::UInt(sequence.code()))]);
    let source = "#import baker::sequence::{Sampler, group_point, sample4, sampler_new, sampler_staged}\n\
                  fn library_uses(s: Sampler) -> vec4<f32> {\n    \
                  return sample4(sampler_staged(sampler_new(0u, 0u, 0u), 0u, 0u), 0u) + vec4<f32>(group_point(0u, 0u)) + sample4(s, 0u);\n}\n";
    compose(&mut plain_composer()?, ("sequence_library.wgsl", source), &defs)
}
