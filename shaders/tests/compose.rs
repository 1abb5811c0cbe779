//! CPU-only checks of the WGSL library: every module and every composed configuration
//! validates with naga and exports to HLSL, GLSL and MSL; composition prunes.

use shaders::compose::{self, Config, Feature};
use shaders::export::{self, Glsl, Lang};
use shaders::modules;

/// The item splitter sees all of every source: header + items re-assemble to the file
/// (up to blank lines), so nothing outside an item could be lost by composition.
#[test]
fn modules_split_losslessly() {
    for m in modules::all() {
        let s = compose::split(&m);
        assert!(!s.items.is_empty(), "{}: no items", m.name);
        let joined: String = std::iter::once(s.header.clone()).chain(s.items.iter().map(|i| i.text.clone())).collect::<Vec<_>>().join("\n");
        let squash = |t: &str| t.lines().map(str::trim_end).filter(|l| !l.is_empty()).collect::<Vec<_>>().join("\n");
        assert_eq!(squash(&joined), squash(&m.source), "{}", m.name);
    }
}

/// Each module on its own (all its items as roots, plus what they use) validates.
#[test]
fn every_module_validates() {
    for m in modules::all() {
        let s = compose::split(&m);
        // A configuration with one pseudo-feature per module is not expressible through
        // Feature, so validate the module's items composed with everything before it.
        let mut src = String::new();
        for prev in modules::all() {
            src += &prev.source;
            src += "\n";
            if prev.name == m.name {
                break;
            }
        }
        export::validate(&src).unwrap_or_else(|e| panic!("{} (with its predecessors): {e}", m.name));
        assert!(s.items.iter().all(|i| src.contains(&i.text)));
    }
}

/// Every preset and every single feature composes, validates, and exports to all
/// languages; exported text is non-trivial and names the root functions.
#[test]
fn every_configuration_validates_and_exports() {
    let mut configs: Vec<Config> = compose::PRESETS.iter().map(|(n, _)| Config::parse(n).unwrap()).collect();
    configs.extend(Feature::ALL.iter().map(|(_, n)| Config::parse(n).unwrap()));
    for c in &configs {
        let composed = compose::compose(c).unwrap();
        for lang in Lang::ALL {
            let out = export::export(&composed.source, lang).unwrap_or_else(|e| panic!("{} → {lang:?}: {e}", c.name));
            for f in &c.features {
                for r in f.roots() {
                    assert!(out.contains(r), "{} → {lang:?}: {r} missing", c.name);
                }
            }
        }
    }
}

/// The filtered lobe tables' texture operations in each language, as written by hand here:
/// the 3D size query per axis and the explicit-level sample through the sampler (GLSL and
/// HLSL also run in the GPU parity tests; MSL has no compiler here, so its text is checked).
#[test]
fn filtered_tables_export_their_texture_operations() {
    let composed = compose::compose(&Config::parse("lobe-ggx-filtered").unwrap()).unwrap();
    let want = [
        (
            Lang::Msl,
            vec![
                "uint3(tab.get_width(), tab.get_height(), tab.get_depth())",
                "tab.sample(smp, ",
                ", level(0.0f))",
                "texture3d<float> tab, sampler smp",
            ],
        ),
        (Lang::GLSL, vec!["uvec3(textureSize(tab, 0))", "textureLod(sampler3D(tab, smp), ", "texture3D tab, sampler smp"]),
        // OpenGL: the texture is the combined sampler; no sampler parameter or argument.
        (
            Lang::Glsl(Glsl::Gl),
            vec!["uvec3(textureSize(tab, 0))", "textureLod(tab, ", "(sampler3D tab, SbfLobeGgxFilteredPixel px, vec3 axis)"],
        ),
        (
            Lang::Glsl(Glsl::Es),
            vec!["uvec3(textureSize(tab, 0))", "textureLod(tab, ", "(highp sampler3D tab, SbfLobeGgxFilteredPixel px, vec3 axis)"],
        ),
        (
            Lang::Hlsl,
            vec![
                "t.GetDimensions(w, h, d);\n    return uint3(w, h, d);",
                "tab.SampleLevel(smp, ",
                "Texture3D<float2> tab, SamplerState smp",
            ],
        ),
    ];
    for (lang, needles) in want {
        let out = export::export(&composed.source, lang).unwrap();
        for n in needles {
            assert!(out.contains(n), "{lang:?}: `{n}` missing");
        }
        if lang.combined_samplers() {
            let code: String = out.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
            assert!(!code.contains("smp") && !code.contains("sampler "), "{lang:?}: a separate sampler is left");
        }
    }
}

/// Pruning: "AD9 irradiance only" is a fraction of "all", keeps no SH/SG/GGX/LUT code,
/// and the two together account for every byte (kept + left out = all items).
#[test]
fn pruning_leaves_out_what_is_not_needed() {
    let all = compose::compose(&Config::parse("all").unwrap()).unwrap();
    let ad9 = compose::compose(&Config::parse("ad9-irradiance").unwrap()).unwrap();
    println!("{}\n{}", all.summary(), ad9.summary());
    assert!(ad9.source.len() * 4 < all.source.len(), "{} vs {}", ad9.source.len(), all.source.len());
    for (m, _) in &ad9.included {
        assert!(["common", "fits", "layouts", "ambient_dice"].contains(&m.as_str()), "AD9 irradiance pulled in {m}");
    }
    let names: Vec<&str> = ad9.included.iter().map(|(_, n)| n.as_str()).collect();
    for must in ["ad9_irradiance", "ad_lobe_irradiance", "AD9_AXES", "AD_DIFFUSE_QUADRATIC"] {
        assert!(names.contains(&must), "{must}");
    }
    for never in ["AD12_AXES", "lut2_sample", "ggx_d", "sh_eval_l2", "ad_specular_fit"] {
        assert!(!names.contains(&never), "{never}");
    }
    assert_eq!(ad9.included.len() + ad9.left_out.len(), all.included.len() + all.left_out.len());
}

/// Bad configurations are errors that list the valid names.
#[test]
fn bad_configuration_is_an_error() {
    let e = Config::parse("ad9-irradiance,nonsense").unwrap_err();
    assert!(e.contains("nonsense") && e.contains("ad12-specular") && e.contains("presets"), "{e}");
    assert!(Config::parse("").is_err());
    assert!(Lang::parse("spirv").is_err());
}

/// The Rust twins of the shared WGSL structs match naga's reflection (offsets, sizes,
/// total size) and the flag constants agree.
#[test]
fn shared_structs_match_naga_layout() {
    use shaders::layout;
    use shaders::progressive::{self as p, EncoderParams, EncoderState};
    let src = compose::compose(&Config::parse("progressive").unwrap()).unwrap().source;
    layout::check::<EncoderParams>(&src).unwrap();
    layout::check::<EncoderState>(&src).unwrap();
    assert_eq!(std::mem::size_of::<EncoderState>(), 208);
    for (name, v) in [
        ("ENCODER_MAX_LOBES", p::MAX_LOBES as u32),
        ("ENCODER_NON_NEGATIVE", p::NON_NEGATIVE),
        ("ENCODER_GAUSS_SEIDEL", p::GAUSS_SEIDEL),
        ("ENCODER_DENOM_BLEND", p::DENOM_BLEND),
        ("ENCODER_DENOM_CLAMP_TO_TRUE", p::DENOM_CLAMP_TO_TRUE),
        ("ENCODER_DENOM_RAW", p::DENOM_RAW),
    ] {
        assert_eq!(layout::constant_u32(&src, name).unwrap(), v, "{name}");
    }
    // The check can fail: a struct with a member moved is reported.
    let moved = src.replace("    total_weight: f32,\n    samples: u32,", "    samples: u32,\n    total_weight: f32,");
    assert_ne!(moved, src);
    let err = layout::check::<EncoderState>(&moved).unwrap_err();
    assert!(err.contains("total_weight"), "{err}");
}

/// The text pruner is exact for functions, with naga's IR as the oracle: for every single
/// feature, the functions in the composed module are exactly those naga's call graph
/// reaches from the feature's roots. Validation (above) shows nothing needed
/// is missing; this shows nothing unneeded is kept.
#[test]
fn pruning_keeps_exactly_what_nagas_call_graph_reaches() {
    use naga::{Block, Handle, Statement};
    use std::collections::BTreeSet;
    fn calls(b: &Block, out: &mut Vec<Handle<naga::Function>>) {
        for s in b.iter() {
            match s {
                Statement::Call { function, .. } => out.push(*function),
                Statement::Block(b) => calls(b, out),
                Statement::If { accept, reject, .. } => {
                    calls(accept, out);
                    calls(reject, out);
                }
                Statement::Switch { cases, .. } => cases.iter().for_each(|c| calls(&c.body, out)),
                Statement::Loop { body, continuing, .. } => {
                    calls(body, out);
                    calls(continuing, out);
                }
                _ => {}
            }
        }
    }
    for (feature, name) in Feature::ALL {
        let composed = compose::compose(&Config::parse(name).unwrap()).unwrap();
        let (module, _) = export::validate(&composed.source).unwrap();
        let by_name: std::collections::HashMap<String, Handle<naga::Function>> =
            module.functions.iter().map(|(h, f)| (f.name.clone().unwrap(), h)).collect();
        let mut reached = BTreeSet::new();
        let mut stack: Vec<Handle<naga::Function>> = feature.roots().iter().map(|r| by_name[*r]).collect();
        while let Some(h) = stack.pop() {
            if reached.insert(h) {
                calls(&module.functions[h].body, &mut stack);
            }
        }
        let kept: BTreeSet<Handle<naga::Function>> = by_name.values().copied().collect();
        let extra: Vec<&String> = by_name.iter().filter(|(_, h)| !reached.contains(*h)).map(|(n, _)| n).collect();
        assert_eq!(kept, reached, "{name}: functions kept but not called: {extra:?}");
        // Constants are not checked this way: naga's constant evaluator folds every constant
        // expression (SH_K00 = 0.5 / sqrt(PI) keeps no reference to PI, `SH_K1 / 3.0` inside a
        // function becomes a literal), so the IR cannot tell which constants the source
        // names. The text pruner follows names in the source, which is what must compile.
    }
}

/// A component-wise select of vectors in HLSL: `sbf_select`, which is `select()` under
/// DXC's HLSL 2021 rules (a vector condition in `?:` is an error there) and `?:` for FXC
/// and older DXC; a scalar select stays `?:`.
#[test]
fn hlsl_vector_select_holds_under_hlsl_2021() {
    let src = "fn pick(v: vec3<f32>, s: f32) -> vec3<f32> {\n    let a = select(vec3<f32>(0.0), v, v > vec3<f32>(0.0));\n    return a * select(1.0, 2.0, s > 0.0);\n}\n";
    let out = export::export(src, Lang::Hlsl).unwrap();
    assert!(out.contains("sbf_select(v > ((float3)0.0), v, ((float3)0.0))"), "{out}");
    assert!(
        out.contains(
            "#if (defined(__HLSL_VERSION) && __HLSL_VERSION >= 2021) || defined(__SLANG__)\n    return select(c, a, b);\n#else\n    return c ? a : b;\n#endif"
        ),
        "{out}"
    );
    assert!(out.contains("s > 0.0 ? 2.0 : 1.0"), "{out}");
}

/// A list may name presets: `sh-l2,sg` is the union of the two presets' features (what a
/// WGSL engine exports to use both: WGSL cannot include two files).
#[test]
fn a_list_of_presets_is_their_union() {
    let both = Config::parse("sh-l2,sg").unwrap();
    let (a, b) = (Config::parse("sh-l2").unwrap(), Config::parse("sg").unwrap());
    assert_eq!(both.features, a.features.union(&b.features).copied().collect());
    assert!(both.features.len() > a.features.len().max(b.features.len()));
    assert!(Config::parse("sh-l2,nonsense").unwrap_err().contains("nonsense"));
}
