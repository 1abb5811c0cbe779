//! Engine-style shaders around the committed library (`shaders/library/`), for the compile
//! tests: the engine's declarations first — its own `PI`, `INV_PI`, `saturate`,
//! `schlick_weight`, a struct and a helper macro named as the library's items are in the
//! WGSL sources — then one or several configurations' include files pasted where an
//! example has its `#include`, then that example's shading function and entry point.
#![allow(dead_code)] // each test binary uses its part

use std::path::PathBuf;

pub fn library_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("library")
}

/// Every preset and profile folder of the committed library.
pub fn slugs() -> Vec<String> {
    let mut s: Vec<String> = std::fs::read_dir(library_dir())
        .expect("shaders/library")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    s.sort();
    s
}

/// The committed include file of `slug` with extension `ext` (`glsl`, `gl.glsl`, `es.glsl`,
/// `hlsl`).
pub fn library_file(slug: &str, ext: &str) -> String {
    let name = format!("sbf_{}.{ext}", slug.replace('-', "_"));
    std::fs::read_to_string(library_dir().join(slug).join(&name)).unwrap_or_else(|e| panic!("{slug}/{name}: {e}"))
}

/// The example `example.<example_ext>` of `first`, with `prelude` and the include files of
/// `first` and of every slug in `also` (extension `lib_ext`) where its `#include` is.
pub fn assemble(first: &str, also: &[&str], example_ext: &str, lib_ext: &str, prelude: &str) -> String {
    let example = std::fs::read_to_string(library_dir().join(first).join(format!("example.{example_ext}"))).expect("the committed example");
    let mut out = String::new();
    let mut pasted = false;
    for line in example.lines() {
        if line.starts_with("#include \"") {
            out += prelude;
            out += "// --- sbf library ---\n";
            for s in std::iter::once(&first).chain(also) {
                out += &library_file(s, lib_ext);
            }
            out += "// --- the engine's shader ---\n";
            pasted = true;
        } else {
            out += line;
            out.push('\n');
        }
    }
    assert!(pasted, "{first}/example.{example_ext} has no #include");
    out
}

/// An engine's declarations in GLSL (any dialect): bare names the library's WGSL sources
/// use (`PI`, `INV_PI`, `HILL_C0`, `schlick_weight`, `tangent_frame` with the library's
/// signature, `LobeGgxPixel`, a `lut2_sample` macro), its own uniforms and a texture.
pub const ENGINE_GLSL: &str = "// --- engine declarations ---
#define PI 3.14159265
#define lut2_sample(t, uv) texture(t, uv)
const float INV_PI = 0.31830988618;
const float HILL_C0 = 0.0;
float saturate(float x) { return clamp(x, 0.0, 1.0); }
float schlick_weight(float v_dot_h) { float m = saturate(1.0 - v_dot_h); return m * m * m * m * m; }
vec3[2] tangent_frame(vec3 n) { return vec3[2](n, n); }
struct LobeGgxPixel { float engine_value; };
";

/// [`ENGINE_GLSL`] in HLSL (`saturate` is an intrinsic there: the engine shims it as a
/// macro, as cross-compiled engines do).
pub const ENGINE_HLSL: &str = "// --- engine declarations ---
#define PI 3.14159265f
#define saturate(x) clamp((x), 0.0, 1.0)
#define lut2_sample(t, uv) t.SampleLevel(engine_sampler, uv, 0)
static const float INV_PI = 0.31830988618f;
static const float HILL_C0 = 0.0f;
SamplerState engine_sampler : register(s3);
float schlick_weight(float v_dot_h) { float m = saturate(1.0 - v_dot_h); return m * m * m * m * m; }
struct LobeGgxPixel { float engine_value; };
";

/// Every unordered pair of distinct slugs, and every slug with itself (its file included
/// twice: the guards).
pub fn pairs(slugs: &[String]) -> Vec<(String, String)> {
    let mut p = Vec::new();
    for (i, a) in slugs.iter().enumerate() {
        for b in &slugs[i..] {
            p.push((a.clone(), b.clone()));
        }
    }
    p
}
