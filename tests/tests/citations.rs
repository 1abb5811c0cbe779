//! Citations users can follow: code, WGSL and docs cite published works by the keys of
//! docs/references.md (`[Roughton19 §7.3]`), never the project's local copies of them
//! ("seed 004", "the seed's …", "the fork"), which users do not have.
//!
//! Oracle: the bibliography's own table (its first column) and the forbidden phrasings,
//! written here. Mutations tried: a planted "seed 004 §7.3" in a comment, and a
//! `[Roughton20 §1]` key that the bibliography lacks, each fail the test.

use std::path::{Path, PathBuf};

/// The workspace root (this crate lives in `tests/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("workspace root").to_path_buf()
}

/// Every source (.rs, .wgsl, the shader library's .hlsl/.glsl/.metal) and .md file of the
/// workspace, outside build outputs, reports and this file (which spells the forbidden
/// phrases out).
fn sources() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else { return };
        for e in entries.flatten() {
            let p = e.path();
            let name = e.file_name().to_string_lossy().to_string();
            if p.is_dir() {
                if !(name.starts_with('.') || name == "target" || name == "probes-report" || name == "node_modules") {
                    walk(&p, out);
                }
            } else if ["rs", "wgsl", "hlsl", "glsl", "metal", "frag", "md"].iter().any(|x| name.ends_with(&format!(".{x}")))
                && !p.ends_with("tests/tests/citations.rs")
            {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&root(), &mut out);
    out.sort();
    out
}

/// The keys of docs/references.md: the first cell of each table row below its header.
fn keys() -> Vec<String> {
    let text = std::fs::read_to_string(root().join("docs/references.md")).expect("docs/references.md");
    text.lines()
        .filter_map(|l| l.strip_prefix("| "))
        .filter_map(|l| l.split(" |").next())
        .filter(|k| *k != "key" && !k.starts_with("---"))
        .map(str::to_string)
        .collect()
}

/// Whether `t` has the shape of a citation key: a capitalised name of two or more letters and a
/// two-digit year
/// (`Roughton19`, `TH17`, an optional `-supp`), or one of the named software keys.
fn is_key_shaped(t: &str) -> bool {
    let base = t.strip_suffix("-supp").unwrap_or(t);
    let b = base.as_bytes();
    let year = b.len() > 3 && b[b.len() - 2..].iter().all(u8::is_ascii_digit) && b[..b.len() - 2].iter().all(u8::is_ascii_alphabetic);
    (year && b[0].is_ascii_uppercase()) || ["HWRTL", "Probulator", "RoughtonFork"].contains(&t)
}

/// The key-shaped tokens of every `[…]` on one line: `[TH17; TH17-supp]` gives both.
fn cited(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find('[') {
        rest = &rest[i + 1..];
        let Some(j) = rest.find(']') else { break };
        for part in rest[..j].split(';') {
            // Doc comments escape a bare key (`\[Roughton19\]`) so that rustdoc does not take it for a link.
            let first = part.trim().trim_start_matches('\\').split([' ', ',']).next().unwrap_or("").trim_end_matches('\\');
            if is_key_shaped(first) {
                out.push(first.to_string());
            }
        }
    }
    out
}

/// "seed" followed by a space and three digits (a local file's number).
fn names_a_local_seed(line: &str) -> bool {
    let l = line.to_lowercase();
    l.match_indices("seed").any(|(i, _)| {
        let after = &l.as_bytes()[i + 4..];
        let after = after.strip_prefix(b"s").unwrap_or(after);
        after.len() >= 4 && after[0] == b' ' && after[1..4].iter().all(u8::is_ascii_digit)
    })
}

#[test]
fn citations_name_published_works_by_their_keys() {
    let keys = keys();
    assert!(keys.contains(&"Roughton19".to_string()) && keys.len() >= 8, "docs/references.md lists {keys:?}");
    let mut bad = Vec::new();
    let mut cites = 0usize;
    for path in sources() {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let rel = path.strip_prefix(root()).unwrap_or(&path).display().to_string();
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            if names_a_local_seed(line) || lower.contains("the seed's") || lower.contains("the seeds'") || lower.contains("the fork") {
                bad.push(format!("{rel}:{}: a local source document: {}", n + 1, line.trim()));
            }
            for k in cited(line) {
                cites += 1;
                if !keys.contains(&k) {
                    bad.push(format!("{rel}:{}: [{k}] is not in docs/references.md", n + 1));
                }
            }
        }
    }
    println!("{cites} citations by key");
    assert!(cites > 100, "only {cites} citations by key were found: is the scan reading the workspace?");
    assert!(bad.is_empty(), "{} citation problems:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn the_checks_recognise_what_they_must() {
    assert!(names_a_local_seed("as in seed 004 §7.3") && names_a_local_seed("seeds 000–002") && !names_a_local_seed("seed 0x1f"));
    assert_eq!(cited(r"/// \[Roughton19\] and \[TH17 §7\]"), ["Roughton19", "TH17"]);
    assert!(!is_key_shaped("Y00") && is_key_shaped("TH17") && is_key_shaped("TH17-supp"));
    assert_eq!(
        cited("([Roughton19 §7.3], [`foo`]) [TH17; TH17-supp; FTH22-supp] [0, 1] [N]"),
        ["Roughton19", "TH17", "TH17-supp", "FTH22-supp"]
    );
}
