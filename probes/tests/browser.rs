//! report.html's interactive view in a real headless browser: the
//! page loads from disk with no script errors, the canvases are not blank, and a self-test
//! (`#selftest`) renders every signal × mode × (value, error) of the page.
//!
//! Needs Chromium (`chromium`, or SBF_CHROMIUM=path). `.ci/run` installs Debian's package and
//! sets SBF_REQUIRE_BROWSER=1, so a missing browser fails there instead of skipping.
//! Mutations tried: a misspelt function in the renderer (`data-errors` = 1 with the
//! browser's message) and a renderer that writes 0 into every pixel (0 lit channels) —
//! both fail.

use std::path::PathBuf;
use std::process::Command;

fn chromium() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("SBF_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    ["chromium", "chromium-browser", "google-chrome"].iter().find_map(|n| {
        let o = Command::new("which").arg(n).output().ok()?;
        o.status.success().then(|| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim().to_string()))
    })
}

/// `data-*` attributes of `<body>` after the page's scripts ran.
/// Chromium (or None, which fails under SBF_REQUIRE_BROWSER=1), a fresh temporary folder
/// for `tag` and a 64-wide sky map in it.
fn setup(tag: &str) -> Option<(PathBuf, PathBuf, PathBuf)> {
    let Some(browser) = chromium() else {
        assert!(
            std::env::var("SBF_REQUIRE_BROWSER").map_or(true, |v| v != "1"),
            "SBF_REQUIRE_BROWSER=1 but no chromium found (apt-get install chromium, or set SBF_CHROMIUM)"
        );
        eprintln!("skipping: no chromium");
        return None;
    };
    let d = std::env::temp_dir().join(format!("probes-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let map = d.join("sky.hdr");
    let o = Command::new(env!("CARGO_BIN_EXE_probes")).args(["env", "--width", "64", "--out"]).arg(&map).output().unwrap();
    assert!(o.status.success());
    Some((browser, d, map))
}

fn body_attrs(browser: &PathBuf, url: &str) -> (String, String) {
    let out = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--window-size=1400,1000", "--virtual-time-budget=20000", "--dump-dom", url])
        .output()
        .expect("the browser runs");
    let dom = String::from_utf8_lossy(&out.stdout).to_string();
    let body = dom.split("<body").nth(1).and_then(|b| b.split('>').next()).unwrap_or_default().to_string();
    (body, String::from_utf8_lossy(&out.stderr).to_string())
}

fn attr_str<'a>(body: &'a str, name: &str) -> Option<&'a str> {
    let k = body.find(&format!("{name}=\""))? + name.len() + 2;
    body[k..].split('"').next()
}

fn attr(body: &str, name: &str) -> Option<i64> {
    attr_str(body, name)?.parse().ok()
}

#[test]
fn report_html_renders_in_a_headless_browser() {
    let Some((browser, d, map)) = setup("browser") else { return };
    let out = d.join("report");
    let o = Command::new(env!("CARGO_BIN_EXE_probes"))
        .arg("compare")
        .arg(&map)
        .args(["--modes", "shl2,adrbf,sgls,ac", "--alphas", "0.3", "--repeats", "1", "--images", "none", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let url = format!("file://{}", out.join("report.html").display());
    let (body, stderr) = body_attrs(&browser, &url);
    println!("<body{body}>");
    assert_eq!(attr(&body, "data-errors"), Some(0), "script errors: {body}\n{stderr}");
    assert!(!stderr.contains("Uncaught"), "{stderr}");
    // Two 240-px discs (≈ 45 000 pixels each, 3 channels): most channels of the sky are lit.
    let lit = attr(&body, "data-nonblank").expect("the renderer ran");
    assert!(lit > 100_000, "only {lit} lit channels: the canvases are (nearly) blank");
    // The view opens on the irradiance recommendation of results.json.
    let all = probes::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let rec = all[0].decision.signals[0].recommended.as_ref().expect("a recommendation").mode.id.clone();
    assert_eq!(attr_str(&body, "data-open-mode"), Some(rec.as_str()), "{body}");
    // Every signal × mode × (value, error): radiance 3 modes, irradiance 4, specular 3 → 10 × 2.
    let (body, _) = body_attrs(&browser, &format!("{url}#selftest"));
    assert_eq!(attr(&body, "data-selftest-renders"), Some(20), "{body}");
    assert_eq!(attr(&body, "data-selftest-blank"), Some(0), "{body}");
    assert_eq!(attr(&body, "data-errors"), Some(0), "{body}");
    std::fs::remove_dir_all(&d).ok();
}

/// The full default report (22 modes, specular at 5 α, PNG images) fits a 1 400 px window:
/// the page's scroll width in a 1 400 × 1 000 headless window is at most 1 400 px.
#[test]
fn report_html_fits_1400_px() {
    let Some((browser, d, map)) = setup("width") else { return };
    let out = d.join("report");
    let o = Command::new(env!("CARGO_BIN_EXE_probes"))
        .arg("compare")
        .arg(&map)
        .args(["--specular-samples", "16", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (body, _) = body_attrs(&browser, &format!("file://{}", out.join("report.html").display()));
    let w = attr(&body, "data-scroll-width").expect("the page reports its width");
    assert!(w <= 1400, "report.html is {w} px wide in a 1 400 px window");
    std::fs::remove_dir_all(&d).ok();
}
