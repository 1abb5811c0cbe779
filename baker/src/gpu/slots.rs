//! `wgsl/bases.wgsl`, the bake's encoder slots, is generated from its template
//! `wgsl/bases.in.wgsl`: each block between a `// @slots` line and a `// @end` line is
//! written once per encoder slot k < [`MAX_SLOTS`] with `{k}` replaced by k; the rest is
//! copied. `tests/bases_template.rs` holds the committed file to the template
//! (`SBF_BLESS=1` there rewrites it).

pub use super::kernel::MAX_SLOTS;

/// The template, as committed.
pub const TEMPLATE: &str = include_str!("wgsl/bases.in.wgsl");

/// The first lines of the generated file.
const HEADER: &str = "// Generated from bases.in.wgsl by baker::gpu::slots, one block per encoder slot:\n// do not edit; change the template and run `SBF_BLESS=1 cargo test -p baker --test bases_template`.\n";

/// `template` with every `// @slots` … `// @end` block written `slots` times; an error
/// for an unclosed or nested block.
pub fn expand(template: &str, slots: usize) -> Result<String, String> {
    let mut out = String::from(HEADER);
    let mut block: Option<Vec<&str>> = None;
    for (n, line) in template.lines().enumerate() {
        match (line.trim(), &mut block) {
            ("// @slots", None) => block = Some(Vec::new()),
            ("// @slots", Some(_)) => return Err(format!("bases.in.wgsl:{}: a @slots block inside another", n + 1)),
            ("// @end", Some(b)) => {
                let body = b.join("\n");
                for k in 0..slots {
                    out.push_str(&body.replace("{k}", &k.to_string()));
                    out.push('\n');
                }
                block = None;
            }
            ("// @end", None) => return Err(format!("bases.in.wgsl:{}: @end without @slots", n + 1)),
            (_, Some(b)) => b.push(line),
            (_, None) => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    match block {
        Some(_) => Err("bases.in.wgsl: a @slots block is not closed".into()),
        None => Ok(out),
    }
}
