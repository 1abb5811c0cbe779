//! The parity harness in HLSL and GLSL: a launch's kernel written in the target language
//! around the exported library, compiled to SPIR-V by glslang (`glslangValidator`, whose
//! HLSL front end takes HLSL) and run through wgpu's SPIR-V passthrough.
//!
//! The kernel file is what an engine writes: it `#include`s the exported library file as
//! [`crate::export::export_with`] writes it, declares the harness bindings in its own
//! language (set 0; the WGSL kernel's bindings in the same order) and has its own entry
//! point. Only the harness helpers (`ld3` and the test body, `sbf_body`) are translated from
//! the test's WGSL by [`crate::emit`] — so the library under test is the exported text,
//! byte for byte.

use super::Launch;
use crate::emit::{self, Options};
use crate::export::{self, Lang};
use std::path::{Path, PathBuf};

/// The glslang front end (Debian/Ubuntu: `apt-get install glslang-tools`).
pub const GLSLANG: &str = "glslangValidator";

/// The kernel's files: (library file name, library text, kernel file name, kernel text).
pub fn kernel_files(l: &Launch, wgsl: &str, row: u32, wg: u32) -> Result<[(String, String); 2], String> {
    if l.cube.is_some() {
        return Err("the prefiltered cube binding (env_cube) is bound in WGSL kernels only".into());
    }
    let lang = l.lang;
    let ext = lang.extension();
    let lib_name = format!("sbf_library.{ext}");
    let library = export::export_with(l.library, lang, &Options { title: "parity library".into(), ..Default::default() })?;
    let (module, info) = export::validate(wgsl)?;
    let skip = emit::item_names(l.library)?;
    let helpers =
        emit::library(wgsl, &module, &info, lang, &Options { skip, bare: true, included: Some(library.clone()), ..Default::default() })?;
    // wgpu's Vulkan back end numbers a layout's bindings 0, 1, 2, … in entry order (naga's
    // SPIR-V gets them remapped; passthrough SPIR-V must use them as they are): the
    // kernel's bindings are numbered in the order of the WGSL kernel's that are present.
    let mut next = 2;
    let mut slot = || {
        next += 1;
        next - 1
    };
    let count = l.count;
    // The harness buffers' struct types under the library's exported names.
    let lib_items = emit::item_names(l.library)?;
    let exported =
        |ty: &str| if lib_items.contains(ty) { emit::names::exported(emit::names::ItemKind::Struct, ty) } else { ty.to_string() };
    let uniform = l.uniform.map(|(ty, _)| exported(ty));
    let io = l.io.map(|(ty, _)| exported(ty));
    let text = match lang {
        Lang::Glsl(_) => {
            let mut b = format!(
                "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"{lib_name}\"\n\n\
                 layout(std430, set = 0, binding = 0) readonly buffer Inp {{ float inp[]; }};\n\
                 layout(std430, set = 0, binding = 1) buffer Outp {{ float outp[]; }};\n"
            );
            if l.lut.is_some() {
                b += &format!("layout(set = 0, binding = {}) uniform texture2D lut;\n", slot());
            }
            if let Some(ty) = &uniform {
                b += &format!("layout(std140, set = 0, binding = {}) uniform Uni {{ {ty} uni; }};\n", slot());
            }
            if let Some(ty) = &io {
                b += &format!("layout(std430, set = 0, binding = {}) buffer Io {{ {ty} io[]; }};\n", slot());
            }
            if l.lobe.is_some() {
                b += &format!("layout(set = 0, binding = {}) uniform texture2DArray lobe_tab;\n", slot());
            }
            if l.lobe_filtered.is_some() {
                b += &format!("layout(set = 0, binding = {}) uniform texture3D lobe_tex3;\n", slot());
                b += &format!("layout(set = 0, binding = {}) uniform sampler lobe_smp;\n", slot());
            }
            b += &format!(
                "\n{helpers}layout(local_size_x = {wg}) in;\nvoid main() {{\n    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * {row}u;\n    if (i >= {count}u) {{\n        return;\n    }}\n    sbf_body(i);\n}}\n"
            );
            b
        }
        Lang::Hlsl => {
            let mut b = format!(
                "#include \"{lib_name}\"\n\n[[vk::binding(0, 0)]] StructuredBuffer<float> inp;\n[[vk::binding(1, 0)]] RWStructuredBuffer<float> outp;\n"
            );
            if l.lut.is_some() {
                b += &format!("[[vk::binding({}, 0)]] Texture2D<float2> lut;\n", slot());
            }
            if let Some(ty) = &uniform {
                b += &format!("[[vk::binding({}, 0)]] cbuffer Uni {{ {ty} uni; }};\n", slot());
            }
            if let Some(ty) = &io {
                b += &format!("[[vk::binding({}, 0)]] RWStructuredBuffer<{ty}> io;\n", slot());
            }
            if l.lobe.is_some() {
                b += &format!("[[vk::binding({}, 0)]] Texture2DArray<float2> lobe_tab;\n", slot());
            }
            if l.lobe_filtered.is_some() {
                b += &format!("[[vk::binding({}, 0)]] Texture3D<float2> lobe_tex3;\n", slot());
                b += &format!("[[vk::binding({}, 0)]] SamplerState lobe_smp;\n", slot());
            }
            b += &format!(
                "\n{helpers}[numthreads({wg}, 1, 1)]\nvoid main(uint3 gid : SV_DispatchThreadID) {{\n    uint i = gid.x + gid.y * {row}u;\n    if (i >= {count}u) {{\n        return;\n    }}\n    sbf_body(i);\n}}\n"
            );
            b
        }
        other => return Err(format!("{other:?}: the SPIR-V harness takes HLSL or GLSL")),
    };
    Ok([(lib_name, library), (format!("kernel.{ext}"), text)])
}

/// A fresh directory under the system's temporary directory.
fn scratch() -> Result<PathBuf, String> {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("sbf-spirv-{}-{k}", std::process::id()));
    std::fs::create_dir_all(&d).map_err(|e| format!("creating {}: {e}", d.display()))?;
    Ok(d)
}

/// Compiles `kernel` (in `dir`, next to what it includes) to SPIR-V words.
pub fn compile(dir: &Path, kernel: &str, lang: Lang) -> Result<Vec<u32>, String> {
    let out = dir.join("kernel.spv");
    let mut cmd = std::process::Command::new(GLSLANG);
    cmd.arg("-V").arg("--target-env").arg("vulkan1.1").arg(format!("-I{}", dir.display())).arg("-o").arg(&out);
    if lang == Lang::Hlsl {
        cmd.args(["-D", "-S", "comp", "-e", "main"]);
    } else {
        cmd.args(["-S", "comp"]);
    }
    cmd.arg(dir.join(kernel));
    let o = cmd.output().map_err(|e| format!("running {GLSLANG} ({e}): install glslang-tools"))?;
    if !o.status.success() {
        return Err(format!(
            "{GLSLANG} rejected {} (kept in {}):\n{}{}",
            kernel,
            dir.display(),
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let bytes = std::fs::read(&out).map_err(|e| format!("reading {}: {e}", out.display()))?;
    if bytes.len() % 4 != 0 {
        return Err(format!("{}: {} bytes is not whole SPIR-V words", out.display(), bytes.len()));
    }
    Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
}

/// Writes a launch's kernel files and compiles them; the directory is removed on success
/// unless `SBF_SPIRV_KEEP` is set (its path is printed then).
pub fn build(l: &Launch, wgsl: &str, row: u32, wg: u32) -> Result<Vec<u32>, String> {
    let files = kernel_files(l, wgsl, row, wg)?;
    let dir = scratch()?;
    for (name, text) in &files {
        std::fs::write(dir.join(name), text).map_err(|e| format!("writing {name}: {e}"))?;
    }
    let words = compile(&dir, &files[1].0, l.lang)?;
    if std::env::var_os("SBF_SPIRV_KEEP").is_some() {
        eprintln!("kernel kept in {}", dir.display());
    } else {
        let _ = std::fs::remove_dir_all(&dir);
    }
    Ok(words)
}
