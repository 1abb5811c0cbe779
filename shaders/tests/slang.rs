//! The HLSL library under Slang's HLSL front end with warnings as errors — the rules DXC's
//! HLSL 2021 default enforces that glslang does not (a vector condition in `?:` is an error
//! there; Slang reports it as "non-short-circuiting `?:` is deprecated"): every pair of
//! configurations (each with itself too) after an engine's declarations
//! ([`common::ENGINE_HLSL`]), with the first one's example shading as a fragment shader.
//!
//! Slang runs from its Python package (`shaders/slang/requirements.txt`, CPU device, no
//! GPU) through `shaders/slang/check.py`, with the interpreter `SBF_SLANG_PYTHON` names
//! (`.ci/run` makes the virtual environment). Without it the test says so and passes;
//! `SBF_REQUIRE_SLANG=1` (CI) makes that a failure.

mod common;

use std::path::PathBuf;

fn python() -> Option<PathBuf> {
    let p = std::env::var_os("SBF_SLANG_PYTHON").map(PathBuf::from);
    let ok =
        p.as_ref().is_some_and(|p| std::process::Command::new(p).args(["-c", "import slangpy"]).output().is_ok_and(|o| o.status.success()));
    if ok {
        return p;
    }
    assert!(
        std::env::var("SBF_REQUIRE_SLANG").is_err(),
        "SBF_REQUIRE_SLANG is set but SBF_SLANG_PYTHON ({p:?}) is not a Python with slangpy (pip install -r shaders/slang/requirements.txt)"
    );
    eprintln!("skipping: SBF_SLANG_PYTHON is not a Python with slangpy (pip install -r shaders/slang/requirements.txt)");
    None
}

#[test]
fn hlsl_builds_under_slang_with_warnings_as_errors_for_every_pair_of_presets() {
    let Some(py) = python() else { return };
    let dir = std::env::temp_dir().join(format!("sbf-slang-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let slugs = common::slugs();
    let pairs = common::pairs(&slugs);
    for (a, b) in &pairs {
        std::fs::write(dir.join(format!("{a}+{b}.hlsl")), common::assemble(a, &[b.as_str()], "hlsl", "hlsl", common::ENGINE_HLSL)).unwrap();
    }
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("slang/check.py");
    let o = std::process::Command::new(&py).arg(&script).arg(&dir).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    let built = out.lines().filter(|l| l.ends_with(": ok")).count();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        o.status.success() && built == pairs.len(),
        "Slang built {built} of {} shaders:\n{out}\n{}",
        pairs.len(),
        String::from_utf8_lossy(&o.stderr)
    );
}
