//! The encoder slots' WGSL (`src/gpu/wgsl/bases.wgsl`) is its template expanded
//! (`baker::gpu::slots`), one slot per lightmap basis of the registry. `SBF_BLESS=1`
//! rewrites the committed file. Mutations tried: a changed line in the committed file,
//! a slot count of 5 — each fails.

use baker::gpu::slots::{expand, MAX_SLOTS, TEMPLATE};
use std::path::Path;

#[test]
fn bases_wgsl_is_its_template_expanded() {
    // One slot per lightmap basis: a bake may encode into every one.
    assert_eq!(MAX_SLOTS, sbf::BasisId::lightmap().count());
    let want = expand(TEMPLATE, MAX_SLOTS).unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/gpu/wgsl/bases.wgsl");
    if std::env::var("SBF_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &want).unwrap();
    }
    let got = std::fs::read_to_string(&path).unwrap();
    if got != want {
        let line = got.lines().zip(want.lines()).position(|(a, b)| a != b).map_or(got.lines().count().min(want.lines().count()), |i| i);
        panic!(
            "{} is not bases.in.wgsl expanded (first difference at line {}): run `SBF_BLESS=1 cargo test -p baker --test bases_template`",
            path.display(),
            line + 1
        );
    }
}

/// The expansion's own rules: a block per slot with `{k}` replaced, the rest copied,
/// malformed templates refused.
#[test]
fn the_expansion_repeats_blocks_and_refuses_malformed_templates() {
    let t = "a\n// @slots\nx{k}\n// @end\nb\n";
    let e = expand(t, 3).unwrap();
    assert!(e.ends_with("a\nx0\nx1\nx2\nb\n"), "{e}");
    assert!(e.lines().take(2).any(|l| l.contains("do not")));
    assert!(expand("// @slots\nx\n", 2).is_err());
    assert!(expand("x\n// @end\n", 2).is_err());
    assert!(expand("// @slots\n// @slots\n// @end\n", 2).is_err());
}
