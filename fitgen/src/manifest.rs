//! `luts/MANIFEST`: JSON Lines, one object per output, in generation order:
//! file, command, parameters, samples, seed, error {rms, max, against}, wall_time_s,
//! sha256, and after a full run a `(all)` line with the total wall time. Everything but
//! `wall_time_s` is deterministic; [`check`](crate::check) ignores that field when
//! comparing (the tables, constants and EXR twins are byte-identical run to run).

use crate::outputs::Output;
use sha2::{Digest, Sha256};

fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            '\n' => o.push_str("\\n"),
            c if (c as u32) < 0x20 => o.push_str(&format!("\\u{:04x}", c as u32)),
            c => o.push(c),
        }
    }
    o
}

/// Lower-case hex SHA-256.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// One manifest line for an output.
pub fn line(o: &Output) -> String {
    format!(
        "{{\"file\": \"{}\", \"command\": \"fitgen {}\", \"parameters\": \"{}\", \"samples\": {}, \"seed\": \"{}\", \"error\": {{\"rms\": {:.6e}, \"max\": {:.6e}, \"against\": \"{}\"}}, \"wall_time_s\": {:.3}, \"sha256\": \"{}\"}}",
        esc(&o.file),
        o.name,
        esc(&o.parameters),
        o.samples,
        esc(&o.seed),
        o.error.0,
        o.error.1,
        esc(&o.error.2),
        o.wall_time_s,
        sha256_hex(&o.bytes)
    )
}

/// The summary line of a full `fitgen all` run (total wall time; file "(all)").
pub fn total_line(wall_time_s: f64) -> String {
    format!("{{\"file\": \"(all)\", \"command\": \"fitgen all\", \"wall_time_s\": {wall_time_s:.3}}}")
}

/// The `"file"` value of a manifest line.
pub fn file_of(line: &str) -> Option<&str> {
    let rest = line.strip_prefix("{\"file\": \"")?;
    rest.split('"').next()
}

/// A manifest line with its wall time blanked (for comparisons).
pub fn without_wall_time(line: &str) -> String {
    match line.find("\"wall_time_s\": ") {
        Some(i) => {
            let rest = &line[i + 15..];
            let end = rest.find(',').unwrap_or(rest.len());
            format!("{}\"wall_time_s\": _{}", &line[..i], &rest[end..])
        }
        None => line.to_string(),
    }
}

/// Merges freshly generated lines into an existing manifest: lines for the same file
/// are replaced in place, new ones appended; the result ends with a newline.
pub fn merge(existing: &str, fresh: &[String]) -> String {
    let mut lines: Vec<String> = existing.lines().filter(|l| !l.trim().is_empty()).map(String::from).collect();
    for f in fresh {
        let file = file_of(f);
        match lines.iter_mut().find(|l| file_of(l) == file) {
            Some(l) => *l = f.clone(),
            None => lines.push(f.clone()),
        }
    }
    let mut s = lines.join("\n");
    s.push('\n');
    s
}
