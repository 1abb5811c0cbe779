//! The bake kernel's WGSL, composed per bake: the `shaders` items it calls (the encoder,
//! the configured bases' evaluators, the GGX terms only when a material is glossy) plus a
//! generated part (SG lobe tables, per-basis `basis_k` and the `encode` function with each
//! basis's encoder options as constants). What was left out is reported.

use crate::accumulate::{BakeConfig, BasisKind};
use shaders::progressive::EncoderParams;

const TRACE_WGSL: &str = include_str!("wgsl/trace.wgsl");
/// The sample sequences in WGSL (`wgsl/sampler.wgsl`; reads `P.seed`, `P.sampler`).
pub const SAMPLER_WGSL: &str = include_str!("wgsl/sampler.wgsl");
const GLOSSY_WGSL: &str = include_str!("wgsl/glossy.wgsl");
const GLOSSY_NONE_WGSL: &str = include_str!("wgsl/glossy_none.wgsl");
const GUIDE_WGSL: &str = include_str!("wgsl/guide.wgsl");
const ADAPT_BATCH_WGSL: &str = include_str!("wgsl/adapt_batch.wgsl");
const ADAPT_NONE_WGSL: &str = include_str!("wgsl/adapt_none.wgsl");
const GUIDE_NONE_WGSL: &str = include_str!("wgsl/guide_none.wgsl");
const FILTER_WGSL: &str = include_str!("wgsl/filter.wgsl");
const FILTER_NONE_WGSL: &str = include_str!("wgsl/filter_none.wgsl");
const GUIDE_COMMON_WGSL: &str = include_str!("wgsl/guide_common.wgsl");
const GUIDE_BUILD_WGSL: &str = include_str!("wgsl/guide_build.wgsl");
const GUIDE_BUILD_SUBGROUP_WGSL: &str = include_str!("wgsl/guide_build_subgroup.wgsl");

/// The WGSL of ray guiding's kernels: (gather + workgroup build, subgroup build).
pub fn guide_build_sources() -> (String, String) {
    (format!("{GUIDE_COMMON_WGSL}\n{GUIDE_BUILD_WGSL}"), format!("{GUIDE_COMMON_WGSL}\n{GUIDE_BUILD_SUBGROUP_WGSL}"))
}

/// How ray guiding's distributions are built on this device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GuideBuild {
    /// Row and marginal prefix sums by subgroup scans (seed 003's wave prefix sums).
    Subgroup,
    /// Serial sums in workgroup memory (no subgroups, or subgroups narrower than a row).
    Workgroup,
}

/// The kernel source for a bake and what its composition left out.
#[derive(Debug, Clone)]
pub struct Kernel {
    pub source: String,
    /// One line per left-out part ("GGX layer: no glossy material", shaders items).
    pub left_out: Vec<String>,
}

fn f(x: f64) -> String {
    format!("{:?}", x as f32)
}

fn v3(a: sbf::glam::DVec3) -> String {
    format!("vec3<f32>({}, {}, {})", f(a.x), f(a.y), f(a.z))
}

/// Composes the bake kernel for `config` (`glossy`: whether any material has a GGX layer).
#[allow(clippy::too_many_lines)] // To split: over the 120-line limit the crate holds (lib.rs).
pub fn kernel(config: &BakeConfig, sphere_targets: bool, glossy: bool) -> Result<Kernel, String> {
    let mut roots =
        vec!["progressive_update", "progressive_update_projected", "EncoderState", "EncoderParams", "tangent_frame", "PI", "INV_PI"];
    if glossy {
        roots.extend(["ggx_d", "ggx_g1", "ggx_g2", "schlick_weight"]);
    }
    let mut gen = String::from("// ---- generated for this bake by baker::gpu::kernel ----\n");
    let mut left_out = Vec::new();
    let mut encode = String::from("fn encode(out: u32, d: vec3<f32>, l: vec3<f32>, w: f32) {\n    let md = vec3<f32>(d.x, d.y, -d.z);\n");
    // Known projections of the baked point's light samples, per basis (sbf
    // update_projected): Q_k[i] += B_i(ω_l)·c for each light sample (ω_l, c).
    let mut project = String::from("fn project(d: vec3<f32>, c: vec3<f32>) {\n");
    // The projections start at zero for every pass of an item (a dispatch may run several).
    let mut project_reset = String::from("fn project_reset() {\n");
    let (mut filtered_vars, mut filtered_load, mut filtered_store, mut filtered_update) = (
        String::new(),
        String::from("fn filtered_load(out: u32) {\n"),
        String::from("fn filtered_store(out: u32) {\n"),
        String::from("fn encode_filtered(d: vec3<f32>, l: vec3<f32>, w: f32) {\n    let md = vec3<f32>(d.x, d.y, -d.z);\n"),
    );
    for (k, b) in config.bases.iter().enumerate() {
        let lobes = b.basis().len();
        let body = match b {
            BasisKind::ShL1 | BasisKind::ShL2 => {
                let (name, n) = if *b == BasisKind::ShL1 { ("sh_eval_l1", 4) } else { ("sh_eval_l2", 9) };
                roots.push(name);
                format!("    let v = {name}(d);\n    for (var i = 0u; i < {n}u; i++) {{\n        b[i] = v[i];\n    }}\n")
            }
            BasisKind::Sg9 | BasisKind::Sg12 => {
                roots.push("sg_eval");
                let (axes, lambda) = b.sg_lobes();
                let items: Vec<String> = axes.iter().map(|a| format!("    {},", v3(*a))).collect();
                gen += &format!(
                    "const BASIS_{k}_AXES: array<vec3<f32>, {lobes}> = array<vec3<f32>, {lobes}>(\n{}\n);\nconst BASIS_{k}_SHARPNESS: f32 = {};\n",
                    items.join("\n"),
                    f(lambda)
                );
                format!("    for (var i = 0u; i < {lobes}u; i++) {{\n        b[i] = sg_eval(BASIS_{k}_AXES[i], BASIS_{k}_SHARPNESS, d);\n    }}\n")
            }
            BasisKind::Ad9 | BasisKind::Ad12 => {
                let axes = if *b == BasisKind::Ad9 { "AD9_AXES" } else { "AD12_AXES" };
                roots.extend(["ad_srbf_eval", axes]);
                format!("    for (var i = 0u; i < {lobes}u; i++) {{\n        b[i] = ad_srbf_eval({axes}[i], d);\n    }}\n")
            }
        };
        gen += &format!(
            "// {} ({lobes} lobes)\nfn basis_{k}(d: vec3<f32>) -> array<f32, 12> {{\n    var b: array<f32, 12>;\n{body}    return b;\n}}\n",
            b.name()
        );
        let opts = config.encoder_options(*b, sphere_targets);
        let mirror = opts.mirror_hemisphere;
        let p = EncoderParams::new(&sbf::solve::ProgressiveOptions { mirror_hemisphere: false, ..opts }, lobes)?;
        let tm: Vec<String> = p
            .true_mean
            .iter()
            .map(|r| format!("vec4<f32>({}, {}, {}, {})", f(r[0] as f64), f(r[1] as f64), f(r[2] as f64), f(r[3] as f64)))
            .collect();
        gen += &format!(
            "const ENCODER_{k}: EncoderParams = EncoderParams({}, {}u, {}u, {}u, array<vec4<f32>, 3>({}));\n\n",
            f(p.acceleration as f64),
            p.lobes,
            p.flags,
            p.denominator,
            tm.join(", ")
        );
        gen += &format!("var<private> Q_{k}: array<vec3<f32>, 12>;\n");
        project_reset += &format!("    Q_{k} = array<vec3<f32>, 12>();\n");
        project += &format!("    {{\n        let b = basis_{k}(d);\n        for (var i = 0u; i < {lobes}u; i++) {{\n            Q_{k}[i] += b[i] * c;\n        }}\n    }}\n");
        let update = format!("        progressive_update_projected(&st, ENCODER_{k}, basis_{k}(d), l, w, Q_{k});\n");
        // The mirrored zero-radiance twin (sbf's mirror_hemisphere, same order).
        let twin = if mirror {
            format!("        progressive_update(&st, ENCODER_{k}, basis_{k}(md), vec3<f32>(0.0), w);\n")
        } else {
            String::new()
        };
        encode += &format!("    {{\n        let s = {k}u * P.item_count + out;\n        var st = states[s];\n{update}{twin}        states[s] = st;\n    }}\n");
        // Filtered accumulation: a gather target's states stay in private variables while
        // it gathers (wgsl/filter.wgsl loads and stores them once per dispatch).
        filtered_vars += &format!("var<private> FST_{k}: EncoderState;\n");
        filtered_load += &format!("    FST_{k} = fstates[{k}u * FP.target_count + out];\n");
        filtered_store += &format!("    fstates[{k}u * FP.target_count + out] = FST_{k};\n");
        filtered_update += &format!("    {{\n        var st = FST_{k};\n{update}{twin}        FST_{k} = st;\n    }}\n");
    }
    encode += "}\n";
    project += "}\n";
    project_reset += "}\n";
    let filtered = config.filter.is_some() && !sphere_targets;
    if filtered {
        // The same encoders on the filtered targets' states (wgsl/filter.wgsl), and the
        // known projections Q_k to and from a record: 3 vec4 of header, then per basis
        // its lobes, each a plane of the component-major record buffer.
        let (mut store, mut load, mut at) =
            (String::from("fn filter_store_q(at: u32, plane: u32) {\n"), String::from("fn filter_load_q(at: u32, plane: u32) {\n"), 3usize);
        for (k, b) in config.bases.iter().enumerate() {
            let lobes = b.basis().len();
            store += &format!(
                "    for (var i = 0u; i < {lobes}u; i++) {{\n        fsamples[at + ({at}u + i) * plane] = vec4<f32>(Q_{k}[i], 0.0);\n    }}\n"
            );
            load += &format!(
                "    for (var i = 0u; i < {lobes}u; i++) {{\n        Q_{k}[i] = fsamples[at + ({at}u + i) * plane].xyz;\n    }}\n"
            );
            at += lobes;
        }
        encode += &format!("{filtered_vars}{filtered_load}}}\n{filtered_store}}}\n{filtered_update}}}\n{store}}}\n{load}}}\n");
    }
    encode += &project;
    encode += &project_reset;
    let config_name = shaders::compose::Config { name: "baker".into(), features: Default::default() };
    let lib = shaders::compose::compose_roots(config_name, &roots)?;
    if !glossy {
        left_out.push("GGX layer (no material in the scene is glossy): glossy sampling and the shaders GGX terms".to_string());
    }
    let guiding = match config.guiding {
        Some(g) if !sphere_targets => format!("const GUIDED_FRACTION: f32 = {};\n{GUIDE_WGSL}", f(g.guided_fraction)),
        _ => {
            left_out.push("ray guiding (not enabled, or probes): the guide bindings, sampler and pdf".to_string());
            GUIDE_NONE_WGSL.to_string()
        }
    };
    let adapt = if (config.adaptive.is_some() || config.camera.is_some()) && !sphere_targets {
        ADAPT_BATCH_WGSL
    } else {
        left_out.push("adaptive and camera-based sampling (not enabled, or probes): the batch bindings".to_string());
        ADAPT_NONE_WGSL
    };
    left_out.push(format!("{} shaders items ({} bytes) the bake does not call", lib.left_out.len(), lib.left_out_bytes()));
    let wavefront = match config.pipeline {
        crate::accumulate::Pipeline::Wavefront => crate::gpu::wavefront::WGSL,
        crate::accumulate::Pipeline::Megakernel => {
            left_out.push("the wavefront passes (the megakernel pipeline)".to_string());
            ""
        }
    };
    let filter = if filtered {
        format!("{}\n{FILTER_WGSL}", crate::gpu::filter::FILTER_KERNEL_WGSL)
    } else {
        left_out.push("filtered accumulation (no --filter, or probes): the records and the gather".to_string());
        FILTER_NONE_WGSL.to_string()
    };
    let source = format!(
        "{}\n{gen}{encode}\n{TRACE_WGSL}\n{SAMPLER_WGSL}\n{}\n{guiding}\n{adapt}\n{filter}\n{wavefront}",
        lib.source,
        if glossy { GLOSSY_WGSL } else { GLOSSY_NONE_WGSL }
    );
    shaders::export::validate(&source).map_err(|e| format!("bake kernel: {e}"))?;
    Ok(Kernel { source, left_out })
}
