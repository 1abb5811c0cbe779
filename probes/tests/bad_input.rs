//! The bad-input corpus, generated here: every case makes `probes compare` exit
//! non-zero with a message naming the file and the problem, and never panic.

use std::path::{Path, PathBuf};
use std::process::Command;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("probes-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write_exr(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 3]) {
    let img = image::Rgb32FImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)));
    img.save(path).unwrap();
}

fn run(path: &Path, extra: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_probes"))
        .arg("compare")
        .arg(path)
        .args(["--modes", "shl2", "--repeats", "1", "--out"])
        .arg(path.with_extension("report"))
        .args(extra)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{}: panic: {stderr}", path.display());
    (out.status.success(), stderr)
}

#[test]
fn bad_inputs_are_clear_errors() {
    let d = dir();
    // Good baseline: a tiny valid EXR.
    let good = d.join("good.exr");
    write_exr(&good, 16, 8, |x, y| [0.1 * x as f32, 0.2 * y as f32, 1.0]);
    let (ok, err) = run(&good, &[]);
    assert!(ok, "valid map failed: {err}");

    let mut cases: Vec<(PathBuf, &str)> = Vec::new();
    let p = d.join("nan.exr");
    write_exr(&p, 16, 8, |x, y| if (x, y) == (3, 2) { [f32::NAN, 0.0, 0.0] } else { [1.0; 3] });
    cases.push((p, "NaN; first at texel (3, 2)"));
    let p = d.join("inf.exr");
    write_exr(&p, 16, 8, |x, y| if (x, y) == (5, 7) { [0.0, f32::INFINITY, 0.0] } else { [1.0; 3] });
    cases.push((p, "infinite; first at texel (5, 7)"));
    let p = d.join("negative.exr");
    write_exr(&p, 16, 8, |x, _| if x < 2 { [-1.0, 0.0, 0.0] } else { [1.0; 3] });
    cases.push((p, "16 texel channel(s) are negative"));
    let p = d.join("aspect.exr");
    write_exr(&p, 16, 16, |_, _| [1.0; 3]);
    cases.push((p, "is not a 2:1 lat-long map"));
    let p = d.join("truncated.exr");
    let bytes = std::fs::read(&good).unwrap();
    std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
    cases.push((p, "cannot decode"));
    let p = d.join("garbage.hdr");
    std::fs::write(&p, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n\x01\x02").unwrap();
    cases.push((p, "cannot decode"));
    // Radiance files the `image` decoder would accept: a scanline whose RLE width field
    // disagrees with the image width, and non-finite or non-positive EXPOSURE headers.
    let sky = d.join("sky-source.hdr");
    let env = Command::new(env!("CARGO_BIN_EXE_probes")).args(["env", "--width", "32", "--out"]).arg(&sky).output().unwrap();
    assert!(env.status.success());
    let src = std::fs::read(&sky).unwrap();
    let (ok, err) = run(&sky, &[]);
    assert!(ok, "the tool's own .hdr must load: {err}");
    let data = src.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let first = data + src[data..].iter().position(|b| *b == b'\n').unwrap() + 1;
    // Scanline 0 starts at `first`: 2 2 hi lo. Say 31 pixels.
    let mut bad = src.clone();
    assert_eq!(&bad[first..first + 4], &[2, 2, 0, 32]);
    bad[first + 3] = 31;
    let p = d.join("rle-width.hdr");
    std::fs::write(&p, &bad).unwrap();
    cases.push((p, "RLE scanline 0 says it is 31 pixels wide, the image is 32"));
    for (name, value, want) in [
        ("exposure-nan.hdr", "nan", "must be finite and positive"),
        ("exposure-inf.hdr", "inf", "must be finite and positive"),
        ("exposure-zero.hdr", "0", "must be finite and positive"),
        ("exposure-text.hdr", "abc", "is not a number"),
    ] {
        let header_end = src.windows(2).position(|w| w == b"\n\n").unwrap() + 1;
        let mut b = src[..header_end].to_vec();
        b.extend_from_slice(format!("EXPOSURE={value}\n").as_bytes());
        b.extend_from_slice(&src[header_end..]);
        let p = d.join(name);
        std::fs::write(&p, &b).unwrap();
        cases.push((p, want));
    }
    let p = d.join("notes.txt");
    std::fs::write(&p, b"hello").unwrap();
    cases.push((p, "not a Radiance HDR or OpenEXR file (extension '.txt'"));
    let p = d.join("png-in-disguise.hdr");
    std::fs::write(&p, b"\x89PNG\r\n\x1a\n").unwrap();
    cases.push((p, "not a Radiance HDR file"));
    let p = d.join("png-in-disguise.exr");
    std::fs::write(&p, b"\x89PNG\r\n\x1a\n").unwrap();
    cases.push((p, "not an OpenEXR file"));
    cases.push((d.join("missing.hdr"), "missing.hdr: not found"));
    let p = d.join("a-folder.hdr");
    std::fs::create_dir_all(&p).unwrap();
    cases.push((p, "is a directory"));
    for (path, want) in &cases {
        let (ok, err) = run(path, &[]);
        assert!(!ok, "{} should fail", path.display());
        let name = path.file_name().unwrap().to_string_lossy();
        assert!(err.contains(&*name) && err.contains(want), "{}: message '{err}' should name the file and say '{want}'", path.display());
    }
    // --sanitize turns the texel cases into successes and says how many were replaced.
    let (ok, err) = run(&d.join("nan.exr"), &["--sanitize"]);
    assert!(ok && err.contains("sanitised 1 NaN"), "{err}");
    std::fs::remove_dir_all(&d).ok();
}

/// Bad input is found before any work: with a valid map of the tool's usual size first
/// (whose default run takes seconds: the reference, 22 modes, specular at 5 α), a bad
/// second map, a bad flag or an unusable output folder fails at once, and writes nothing.
///
/// Error model for the bound: the process start, argument parsing and decoding one 256×128
/// map take ~10–30 ms here; the work that must not happen first takes > 1 s on this
/// machine (the irradiance and specular references alone ≈ 0.4 s). 0.2 s (the issue's
/// bound) lies between them with a margin of ≥ 5× on the fast side.
#[test]
fn bad_input_fails_before_any_work() {
    let d = std::env::temp_dir().join(format!("probes-early-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let good = d.join("good.exr");
    write_exr(&good, 256, 128, |x, y| [0.01 * x as f32, 0.02 * y as f32, 1.0]);
    let bad = d.join("bad.hdr");
    std::fs::write(&bad, b"not a map").unwrap();
    let foreign = d.join("someone-elses");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), b"keep me").unwrap();
    let file_out = d.join("a-file");
    std::fs::write(&file_out, b"x").unwrap();
    let out = d.join("never-written");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let cases: Vec<(Vec<String>, String)> = vec![
        (vec![s(&good), s(&bad), "--out".into(), s(&out)], "bad.hdr: not a Radiance HDR file".into()),
        (vec![s(&good), s(&d.join("gone.exr")), "--out".into(), s(&out)], "gone.exr: not found".into()),
        (vec![s(&good), s(&d), "--out".into(), s(&out)], "is a directory".into()),
        (vec![s(&good), "--images".into(), "jpg".into(), "--out".into(), s(&out)], "--images jpg".into()),
        (vec![s(&good), "--alphas".into(), "2".into(), "--out".into(), s(&out)], "--alphas: 2 is outside".into()),
        (vec![s(&good), "--out".into(), s(&foreign)], "no probes run wrote it".into()),
        (vec![s(&good), "--out".into(), s(&file_out)], "exists and is not a folder".into()),
    ];
    for (args, want) in &cases {
        let t = std::time::Instant::now();
        let o = Command::new(env!("CARGO_BIN_EXE_probes")).arg("compare").args(args).output().unwrap();
        let secs = t.elapsed().as_secs_f64();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: exit status {:?}, {err}", o.status.code());
        assert!(err.contains(want.as_str()), "{args:?}: message '{err}' should say '{want}'");
        assert!(secs < 0.2, "{args:?}: failed after {secs:.3} s, not before the work");
        assert!(!out.exists(), "{args:?}: the output folder was created");
    }
    assert_eq!(std::fs::read_dir(&foreign).unwrap().count(), 1, "the foreign folder was written to");
    std::fs::remove_dir_all(&d).ok();
}
