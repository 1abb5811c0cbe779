//! The exported library in a real OpenGL driver, as an engine uses it: every preset's and
//! profile's OpenGL 4.5 core (`.gl.glsl`) and OpenGL ES 3.0 (`.es.glsl`) include file,
//! pasted where its example shader has `#include` (OpenGL has none) after the engine's own
//! declarations, compiled and linked with a vertex shader by the driver behind EGL
//! (Mesa's llvmpipe in CI: surfaceless, no window system).
//!
//! glslang alone is no oracle here: it accepts `GL_EXT_samplerless_texture_functions` in
//! an OpenGL or ES shader, which Mesa (and every desktop GL driver) rejects. The test
//! asserts the context is the version asked for, so a driver that silently gives an older
//! or compatibility context does not pass for a 4.5 core one.
//!
//! Without EGL or a GL driver the tests skip with a message; `SBF_REQUIRE_GPU=1` (CI, where
//! `.ci/run` installs Mesa's EGL and GLES) turns that into a failure.
#![allow(unsafe_code)] // EGL and OpenGL are C APIs (workspace lints: the second allowed use)

use glow::HasContext;
use khronos_egl as egl;
mod common;

/// EGL_PLATFORM_SURFACELESS_MESA (EGL_MESA_platform_surfaceless).
const PLATFORM_SURFACELESS_MESA: egl::Enum = 0x31DD;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Api {
    /// OpenGL 4.5, core profile.
    Gl45Core,
    /// OpenGL ES 3.0 (WebGL 2's dialect).
    Es30,
}

/// A current GL context of one API on this thread, with the EGL objects that own it.
struct Driver {
    egl: egl::DynamicInstance<egl::EGL1_5>,
    display: egl::Display,
    context: egl::Context,
    gl: glow::Context,
    version: String,
}

impl std::fmt::Debug for Driver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Driver({})", self.version)
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.egl.make_current(self.display, None, None, None);
        let _ = self.egl.destroy_context(self.display, self.context);
        let _ = self.egl.terminate(self.display);
    }
}

impl Driver {
    fn new(api: Api) -> Result<Driver, String> {
        let egl = unsafe { egl::DynamicInstance::<egl::EGL1_5>::load_required() }.map_err(|e| format!("loading libEGL (1.5): {e}"))?;
        let display = unsafe { egl.get_platform_display(PLATFORM_SURFACELESS_MESA, egl::DEFAULT_DISPLAY, &[egl::ATTRIB_NONE]) }
            .map_err(|e| format!("EGL surfaceless display: {e}"))?;
        egl.initialize(display).map_err(|e| format!("eglInitialize: {e}"))?;
        let (bind, renderable, attribs) = match api {
            Api::Gl45Core => (
                egl::OPENGL_API,
                egl::OPENGL_BIT,
                vec![
                    egl::CONTEXT_MAJOR_VERSION,
                    4,
                    egl::CONTEXT_MINOR_VERSION,
                    5,
                    egl::CONTEXT_OPENGL_PROFILE_MASK,
                    egl::CONTEXT_OPENGL_CORE_PROFILE_BIT,
                    egl::NONE,
                ],
            ),
            Api::Es30 => {
                (egl::OPENGL_ES_API, egl::OPENGL_ES3_BIT, vec![egl::CONTEXT_MAJOR_VERSION, 3, egl::CONTEXT_MINOR_VERSION, 0, egl::NONE])
            }
        };
        egl.bind_api(bind).map_err(|e| format!("eglBindAPI: {e}"))?;
        let config = egl
            .choose_first_config(display, &[egl::RENDERABLE_TYPE, renderable, egl::SURFACE_TYPE, egl::PBUFFER_BIT, egl::NONE])
            .map_err(|e| format!("eglChooseConfig: {e}"))?
            .ok_or_else(|| format!("no EGL config renders {api:?}"))?;
        let context = egl.create_context(display, config, None, &attribs).map_err(|e| format!("eglCreateContext for {api:?}: {e}"))?;
        egl.make_current(display, None, None, Some(context)).map_err(|e| format!("eglMakeCurrent (surfaceless): {e}"))?;
        let gl = unsafe {
            glow::Context::from_loader_function(|name| {
                egl.get_proc_address(name).map_or(std::ptr::null(), |f| f as *const std::ffi::c_void)
            })
        };
        let version = unsafe { gl.get_parameter_string(glow::VERSION) };
        let renderer = unsafe { gl.get_parameter_string(glow::RENDERER) };
        let version = format!("{version} ({renderer})");
        Ok(Driver { egl, display, context, gl, version })
    }

    /// Compiles and links `fragment` with a vertex shader that feeds its `normal` input;
    /// the driver's log on failure.
    fn build(&self, vertex: &str, fragment: &str) -> Result<(), String> {
        let gl = &self.gl;
        unsafe {
            let program = gl.create_program()?;
            let mut shaders = Vec::new();
            let mut result = Ok(());
            for (kind, src) in [(glow::VERTEX_SHADER, vertex), (glow::FRAGMENT_SHADER, fragment)] {
                let s = gl.create_shader(kind)?;
                gl.shader_source(s, src);
                gl.compile_shader(s);
                if !gl.get_shader_compile_status(s) {
                    result = Err(format!("compile: {}", gl.get_shader_info_log(s)));
                }
                gl.attach_shader(program, s);
                shaders.push(s);
            }
            if result.is_ok() {
                gl.link_program(program);
                if !gl.get_program_link_status(program) {
                    result = Err(format!("link: {}", gl.get_program_info_log(program)));
                }
            }
            for s in shaders {
                gl.detach_shader(program, s);
                gl.delete_shader(s);
            }
            gl.delete_program(program);
            result
        }
    }
}

/// The driver for `api`, or None (after a message) when the machine has none and nothing
/// requires one.
fn driver(api: Api) -> Option<Driver> {
    match Driver::new(api) {
        Ok(d) => {
            let want = match api {
                Api::Gl45Core => "4.5",
                Api::Es30 => "OpenGL ES 3.",
            };
            assert!(d.version.contains(want), "asked for {api:?}, the driver gave {}", d.version);
            eprintln!("{api:?}: {}", d.version);
            Some(d)
        }
        Err(e) => {
            assert!(
                std::env::var("SBF_REQUIRE_GPU").is_err(),
                "SBF_REQUIRE_GPU is set but no {api:?} context could be made: {e} (apt-get install libegl-mesa0 libgl1-mesa-dri libgles2)"
            );
            eprintln!("skipping the {api:?} compile test: {e}");
            None
        }
    }
}

const VERTEX_GL: &str =
    "#version 450 core\nlayout(location = 0) in vec3 position;\nlayout(location = 0) out vec3 normal;\nvoid main() {\n    normal = position;\n    gl_Position = vec4(position, 1.0);\n}\n";
const VERTEX_ES: &str = "#version 300 es\nin vec3 position;\nout vec3 normal;\nvoid main() {\n    normal = position;\n    gl_Position = vec4(position, 1.0);\n}\n";

/// Every pair of configurations (each with itself too) in one shader after the engine's
/// declarations ([`common::ENGINE_GLSL`]: its own `PI`, `schlick_weight`, `LobeGgxPixel`, …),
/// with the first one's example shading: each compiles and links.
fn build_all(api: Api) {
    let Some(d) = driver(api) else { return };
    let (dialect, vertex) = match api {
        Api::Gl45Core => ("gl", VERTEX_GL),
        Api::Es30 => ("es", VERTEX_ES),
    };
    let slugs = common::slugs();
    assert!(slugs.len() >= 12, "the committed library has {} folders", slugs.len());
    let pairs = common::pairs(&slugs);
    let mut failures = Vec::new();
    for (a, b) in &pairs {
        let src = common::assemble(a, &[b.as_str()], &format!("{dialect}.frag"), &format!("{dialect}.glsl"), common::ENGINE_GLSL);
        if let Err(e) = d.build(vertex, &src) {
            failures.push(format!("{a} + {b}: {}", e.lines().take(4).collect::<Vec<_>>().join("\n    ")));
        }
    }
    eprintln!("{api:?}: {} of {} pairs build", pairs.len() - failures.len(), pairs.len());
    assert!(failures.is_empty(), "{api:?} ({}) rejects:\n{}", d.version, failures.join("\n"));
}

#[test]
fn opengl_45_core_builds_every_pair_of_presets_after_engine_declarations() {
    build_all(Api::Gl45Core);
}

#[test]
fn opengl_es_30_builds_every_pair_of_presets_after_engine_declarations() {
    build_all(Api::Es30);
}

/// The Vulkan dialect's extension is what OpenGL drivers reject: the oracle fails when it
/// is there (so a passing build above is not a driver that accepts anything).
#[test]
fn the_vulkan_dialect_is_rejected_by_opengl() {
    let Some(d) = driver(Api::Gl45Core) else { return };
    let src = common::assemble("sh-l1", &[], "gl.frag", "gl.glsl", common::ENGINE_GLSL).replacen(
        "// --- sbf library ---\n",
        "// --- sbf library ---\n#extension GL_EXT_samplerless_texture_functions : require\n",
        1,
    );
    assert!(d.build(VERTEX_GL, &src).is_err(), "{} accepted GL_EXT_samplerless_texture_functions", d.version);
}
