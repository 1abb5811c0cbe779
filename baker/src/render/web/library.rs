//! The shaders the viewer runs: the runtime library's exports for the renderer's features
//! (every lightmap basis, both specular paths, the B-spline filter, the tangent frame) and
//! the viewer's own stages.

/// The viewer's WebGL 2 stages (vertex, fragment: render.wgsl's shading in GLSL ES, display).
pub const VIEWER_ES_GLSL: &str = include_str!("viewer.es.glsl");
/// The WebGPU display pass.
pub const DISPLAY_WGSL: &str = include_str!("display.wgsl");

/// The GLSL ES 3.0 export of the library the renderer composes (every lightmap basis, both
/// specular paths, the B-spline filter, the tangent frame).
pub fn library_glsl_es() -> Result<String, String> {
    let (cfg, roots) = library_config()?;
    let lib = shaders::compose::compose_roots(cfg, &roots)?;
    let opts = shaders::emit::Options {
        title: "sbf runtime library for the bake viewer (render --web): the renderer's features".into(),
        roots: roots.iter().map(|r| r.to_string()).collect(),
        ..Default::default()
    };
    shaders::export::export_with(&lib.source, shaders::export::Lang::Glsl(shaders::export::Glsl::Es), &opts)
}

/// WebGPU's module: the WGSL export of the library (names prefixed `sbf_`, `Sbf`, `SBF_`)
/// followed by `wgsl/render.wgsl` calling them by those names; validated.
pub fn viewer_wgsl() -> Result<String, String> {
    let (cfg, roots) = library_config()?;
    let lib = shaders::compose::compose_roots(cfg, &roots)?;
    let (lib_module, _) = shaders::export::validate(&lib.source)?;
    let renames = shaders::emit::names::renames(&lib_module);
    let full = crate::render::raster::module_source()?;
    let (module, _) = shaders::export::validate(&full)?;
    let out = shaders::emit::names::prefix_wgsl(&full, &module, &renames)?;
    shaders::export::validate(&out).map_err(|e| format!("the viewer's WGSL: {e}"))?;
    Ok(out)
}

fn library_config() -> Result<(shaders::compose::Config, Vec<&'static str>), String> {
    let cfg = shaders::compose::Config::parse(&crate::render::raster::features())?;
    let roots: Vec<&'static str> = cfg.features.iter().flat_map(|f| f.roots().iter().copied()).chain(["tangent_frame"]).collect();
    Ok((cfg, roots))
}
