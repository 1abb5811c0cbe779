//! The bake viewer (`render --web`) in a real browser: headless Chromium (Debian's
//! `chromium`, or SBF_CHROMIUM=path) opens the folder from a local HTTP server, draws the
//! built-in scene at the reference camera through WebGL 2 (SwiftShader; the library's GLSL ES
//! export) and WebGPU (SwiftShader's Vulkan; the library's WGSL export with render.wgsl), and
//! posts each canvas back; every pixel is compared with `render`'s CPU twin (f64 shading in
//! `sbf`) of the same camera, basis and f16 lightmap values.
//!
//! Error model, per pixel and channel, on the 8-bit sRGB code c = 255·srgb(t(e·x)), t(y) =
//! y/(1 + y) (the report's display; e the viewer's exposure):
//! - the page's conversion to 8 bits rounds: ½ code, plus 0.01 for the display pass' f32
//!   (pow's highp error, GLSL ES 3.0 §4.5.1: ≈ 1e-6 relative, 3e-4 codes);
//! - the rasteriser's attributes: vertices snap to a sub-pixel grid (Vulkan guarantees 2⁻⁴
//!   pixel), so a pixel's interpolated position, normal and lightmap UV are those of a point
//!   within 2⁻⁴ pixel of its centre: the twin's largest change over the four diagonal
//!   offsets ±2⁻⁴ (pixels whose offsets see another triangle are edges, left out and
//!   counted);
//! - f32 shading against f64: 1e-4 × (|diffuse| + |specular|) (the GPU twin test's bar,
//!   baker/tests/render.rs), and one f16 rounding of nothing: both read the same f16 values.
//!
//! The change of x is carried through the display curve by evaluating c at x ± the bound.
//! Also: no console or WebGPU error, no request outside the folder (Chromium's proxy is the
//! test's server, so a request to any other host reaches it and is logged), the first
//! frame's wall time from the page's request to its beacon ≤ 2 s.
//! Mutations: see the closing note of the change that added this test.

use baker::layout::lightmap::Lightmap;
use baker::render::atlas::Atlas;
use baker::render::lighting::{Encoding, Lighting, LightmapFilter, Storage};
use baker::render::shade::Shader;
use baker::render::visible::{self, Visible};
use baker::scene::bvh::Bvh;
use baker::scene::camera::ViewCamera;
use sbf::glam::{DVec3, Vec3};
use sbf::profile::SpecularPath;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

fn chromium() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("SBF_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    ["chromium", "chromium-browser", "google-chrome"].iter().find_map(|n| {
        let o = Command::new("which").arg(n).output().ok()?;
        o.status.success().then(|| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim().to_string()))
    })
}

/// What the server saw.
#[derive(Default)]
struct Log {
    /// Request targets, in order ("GET /index.html", "GET http://elsewhere/…"), and whether a
    /// page made it (the fetch metadata a browser adds to a page's requests, `Sec-Fetch-Mode`;
    /// the browser's own traffic — its clock, updates, sign-in — has none).
    requests: Vec<(String, bool)>,
    /// (api, configuration) → RGBA8 rows from the top.
    captures: BTreeMap<(String, String), Vec<u8>>,
    report: Option<String>,
    index_at: Option<Instant>,
    first_frame_at: Option<Instant>,
}

/// A minimal HTTP/1.1 server for `root` on 127.0.0.1 (also Chromium's proxy: absolute-form
/// targets to another host are logged and refused).
fn serve(root: PathBuf, log: Arc<Mutex<Log>>) -> u16 {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let (root, log) = (root.clone(), log.clone());
            std::thread::spawn(move || {
                let _ = handle(stream, &root, &log, port);
            });
        }
    });
    port
}

fn handle(stream: TcpStream, root: &Path, log: &Mutex<Log>, port: u16) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut out = stream;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line)? == 0 {
            return Ok(());
        }
        let mut parts = line.split_whitespace();
        let (method, target) = (parts.next().unwrap_or("").to_string(), parts.next().unwrap_or("").to_string());
        let mut length = 0usize;
        let mut from_page = false;
        loop {
            let mut h = String::new();
            reader.read_line(&mut h)?;
            if h.trim().is_empty() {
                break;
            }
            let lower = h.to_ascii_lowercase();
            if let Some(v) = lower.strip_prefix("content-length:") {
                length = v.trim().parse().unwrap_or(0);
            }
            from_page |= lower.starts_with("sec-fetch-mode:");
        }
        let mut body = vec![0u8; length];
        reader.read_exact(&mut body)?;
        log.lock().unwrap().requests.push((format!("{method} {target}"), from_page));
        let local = format!("http://127.0.0.1:{port}");
        let path = if let Some(p) = target.strip_prefix(&local) {
            p.to_string()
        } else if target.starts_with('/') {
            target.clone()
        } else {
            // Another host (through the proxy) or a CONNECT tunnel: refused.
            out.write_all(b"HTTP/1.1 403 Forbidden\r\nContent-Length: 0\r\n\r\n")?;
            continue;
        };
        let (file, query) = path.split_once('?').unwrap_or((&path, ""));
        let mut status = "200 OK";
        let mut reply = b"ok".to_vec();
        let mut kind = "text/plain";
        match (method.as_str(), file) {
            ("POST", "/__capture") => {
                let q: BTreeMap<&str, &str> = query.split('&').filter_map(|kv| kv.split_once('=')).collect();
                log.lock().unwrap().captures.insert((q["api"].to_string(), q["config"].to_string()), body);
            }
            ("POST", "/__first_frame") => log.lock().unwrap().first_frame_at = Some(Instant::now()),
            ("POST", "/__report") => log.lock().unwrap().report = Some(String::from_utf8_lossy(&body).to_string()),
            ("GET", f) => {
                let name = f.trim_start_matches('/');
                if name == "index.html" {
                    log.lock().unwrap().index_at.get_or_insert(Instant::now());
                }
                match std::fs::read(root.join(name)).ok().filter(|_| !name.contains("..") && !name.is_empty()) {
                    Some(b) => {
                        reply = b;
                        kind = match name.rsplit('.').next() {
                            Some("html") => "text/html",
                            Some("js") => "text/javascript",
                            Some("json") => "application/json",
                            _ => "application/octet-stream",
                        };
                    }
                    None => {
                        status = "404 Not Found";
                        reply = Vec::new();
                    }
                }
            }
            _ => {
                status = "405 Method Not Allowed";
                reply = Vec::new();
            }
        }
        write!(out, "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\n\r\n", reply.len())?;
        out.write_all(&reply)?;
    }
}

/// The display's 8-bit code of linear value `x` at exposure `e` (unrounded).
fn code(x: f64, e: f64) -> f64 {
    let y = (x.max(0.0) * e).max(0.0);
    let t = (y / (1.0 + y)).clamp(0.0, 1.0);
    255.0 * if t <= 0.003_130_8 { 12.92 * t } else { 1.055 * t.powf(1.0 / 2.4) - 0.055 }
}

/// The visible surface through image position (px, py) (pixels, y down) and its triangle.
fn surface(scene: &baker::scene::Scene, bvh: &Bvh, lm: &Lightmap, cam: &ViewCamera, px: f32, py: f32) -> Option<(u32, Visible)> {
    let (o, d) = cam.ray(px, py);
    let h = bvh.intersect(o, d, 0.0, f32::INFINITY)?;
    Some((h.tri, visible::surface_at(scene, bvh, lm, None, o, d, &h)))
}

/// Opens `dir`'s viewer in headless Chromium with `query` from a fresh local server; the
/// server's log, the page's report and Chromium's stderr.
fn open(browser: &Path, dir: &Path, profile: &Path, query: &str) -> (Log, serde_json::Value, String, u16) {
    let log = Arc::new(Mutex::new(Log::default()));
    let port = serve(dir.to_path_buf(), log.clone());
    let url = format!("http://127.0.0.1:{port}/index.html?{query}");
    let mut child = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--enable-unsafe-webgpu", "--enable-features=Vulkan", "--enable-unsafe-swiftshader"])
        // The browser's own traffic (component updates, its clock, sign-in) is not the page's.
        .args(["--disable-background-networking", "--disable-component-update", "--no-first-run", "--disable-sync"])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--proxy-server=http://127.0.0.1:{port}"))
        .arg("--proxy-bypass-list=<-loopback>")
        .arg(&url)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while log.lock().unwrap().report.is_none() && start.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = child.kill();
    let mut stderr = String::new();
    let _ = child.stderr.take().unwrap().read_to_string(&mut stderr);
    let _ = child.wait();
    let log = std::mem::take(&mut *log.lock().unwrap());
    let report: serde_json::Value = serde_json::from_str(
        log.report.as_deref().unwrap_or_else(|| panic!("no report from the page within 120 s; Chromium said:\n{stderr}")),
    )
    .unwrap();
    println!("report: {report}");
    assert_eq!(report["errors"].as_array().map(Vec::len), Some(0), "the page's errors: {report}");
    assert!(!stderr.contains("Uncaught"), "{stderr}");
    (log, report, stderr, port)
}

/// Per lobe, the largest error of the GPU's B-spline at atlas position `uv` (texels): each of
/// its four bilinear taps reads at a position within ε_w = 2⁻⁴ texel per axis of the exact one
/// (Vulkan's least sub-texel precision), so it is off by at most ε_w × (its cell's largest
/// texel difference along x + along y), weighted by the tap's weight; plus 2⁻¹⁰ of each tap's
/// magnitude, for a filtered result rounded to f16.
fn bicubic_bound(atlas: &Atlas, uv: [f64; 2]) -> Vec<DVec3> {
    const EPS_W: f64 = 1.0 / 16.0;
    let taps = baker::render::atlas::bspline_taps(uv);
    let texel = |lobe: &[[f32; 3]], i: i64, j: i64| {
        let (x, y) = (i.clamp(0, atlas.width as i64 - 1) as usize, j.clamp(0, atlas.height as i64 - 1) as usize);
        let t = lobe[y * atlas.width + x];
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    };
    atlas
        .lobes
        .iter()
        .map(|lobe| {
            let mut b = DVec3::ZERO;
            for (px, gx) in taps[0].0.iter().zip(taps[0].1) {
                for (py, gy) in taps[1].0.iter().zip(taps[1].1) {
                    let (i, j) = ((px - 0.5).floor() as i64, (py - 0.5).floor() as i64);
                    let [a, bb, c, d] = [texel(lobe, i, j), texel(lobe, i + 1, j), texel(lobe, i, j + 1), texel(lobe, i + 1, j + 1)];
                    let dx = (bb - a).abs().max((d - c).abs());
                    let dy = (c - a).abs().max((d - bb).abs());
                    let mag = a.abs().max(bb.abs()).max(c.abs()).max(d.abs());
                    b += (EPS_W * (dx + dy) + mag * (1.0 / 1024.0)) * (gx * gy);
                }
            }
            b
        })
        .collect()
}

/// The CPU twin of a viewer folder: the scene `render` loaded (material factors), the bake's
/// layout, the reference camera, the probes, and per pixel the centre's surface and the four
/// offsets' (None: an edge — an offset sees another triangle or nothing: the rasteriser may
/// give the pixel to either side, and at a chart seam the two sides read different texels).
struct Twin {
    lm: Lightmap,
    cam: ViewCamera,
    exposure: f64,
    materials: Vec<baker::render::lighting::SurfaceMaterial>,
    probes: Option<baker::render::probes::ProbeField>,
    bake: PathBuf,
    pixels: Vec<Option<[Visible; 5]>>,
}

impl Twin {
    fn new(scene_arg: &str, out: &Path, web: &Path) -> Twin {
        let (scene, _) = baker::scene::load::load_with_cameras(scene_arg, None, &mut |_| {}).unwrap();
        let scene = if scene.has_textures() { scene.without_maps() } else { scene };
        let bake_dir = out.join("bake");
        let bake: serde_json::Value = serde_json::from_slice(&std::fs::read(bake_dir.join("bake.json")).unwrap()).unwrap();
        let lm = Lightmap::build(
            &scene,
            bake["layout"]["texels_per_unit"].as_f64().unwrap() as f32,
            bake["layout"]["padding"].as_u64().unwrap() as usize,
        )
        .unwrap();
        let sj: serde_json::Value = serde_json::from_slice(&std::fs::read(web.join("scene.json")).unwrap()).unwrap();
        let v3 = |k: &str| {
            let a = sj["camera"][k].as_array().unwrap();
            Vec3::new(a[0].as_f64().unwrap() as f32, a[1].as_f64().unwrap() as f32, a[2].as_f64().unwrap() as f32)
        };
        let cam = ViewCamera {
            eye: v3("eye"),
            target: v3("target"),
            up: v3("up"),
            fov_y: (sj["camera"]["fov_y_degrees"].as_f64().unwrap() as f32).to_radians(),
            width: sj["camera"]["width"].as_u64().unwrap() as u32,
            height: sj["camera"]["height"].as_u64().unwrap() as u32,
        };
        let bvh = Bvh::build(&scene);
        const SUBPIXEL: f32 = 1.0 / 16.0;
        let (w, h) = (cam.width as usize, cam.height as usize);
        let pixels: Vec<Option<[Visible; 5]>> = (0..w * h)
            .map(|k| {
                let (x, y) = ((k % w) as f32 + 0.5, (k / w) as f32 + 0.5);
                let c = surface(&scene, &bvh, &lm, &cam, x, y);
                let mut s = [c?.1; 5];
                for (j, (dx, dy)) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)].into_iter().enumerate() {
                    let o = surface(&scene, &bvh, &lm, &cam, x + dx * SUBPIXEL, y + dy * SUBPIXEL)?;
                    if o.0 != c?.0 {
                        return None;
                    }
                    s[j + 1] = o.1;
                }
                Some(s)
            })
            .collect();
        let hits = (0..w * h).filter(|k| surface(&scene, &bvh, &lm, &cam, (k % w) as f32 + 0.5, (k / w) as f32 + 0.5).is_some()).count();
        let edges = hits - pixels.iter().filter(|p| p.is_some()).count();
        println!("{scene_arg}: {edges} of {hits} pixels with a surface are at a triangle's edge (left out)");
        // Most of the image is compared (a dense mesh has many edges: the atrium at 2 texels per pixel).
        assert!(edges * 2 < hits, "{edges} edge pixels of {hits}");
        // Dynamic objects (no lightmap, not an emitter) are shaded from the bake's probes.
        let probes = scene
            .meshes
            .iter()
            .any(|m| !m.lightmapped && scene.materials[m.material].emissive.max_element() <= 0.0)
            .then(|| baker::render::probes::ProbeField::read(&bake_dir).unwrap());
        Twin {
            materials: scene.materials.iter().map(baker::render::lighting::SurfaceMaterial::of).collect(),
            lm,
            cam,
            exposure: sj["exposure"].as_f64().unwrap() as f32 as f64,
            probes,
            bake: bake_dir,
            pixels,
        }
    }

    /// Every pixel of the page's image `img` of configuration `name` (`NAME` or
    /// `NAME:bicubic`) within the error model; (channels checked, of them probed, worst
    /// error over its bound).
    fn check(&self, img: &[u8], api: &str, name: &str) -> (usize, usize, f64) {
        let (base, filter) = match name.split_once(':') {
            Some((b, "bicubic")) => (b, LightmapFilter::Bicubic),
            _ => (name, LightmapFilter::Exact),
        };
        let encoding =
            if base == "none" { Encoding::Irradiance } else { Encoding::Basis(baker::accumulate::lightmap_basis(base).unwrap()) };
        let l = Lighting {
            encoding,
            specular: SpecularPath::Fit,
            storage: Storage::F16,
            sg_sharpness: baker::accumulate::SG_HEMISPHERE_SHARPNESS,
        };
        let atlas = Atlas::read(&self.bake, encoding, self.lm.width, self.lm.height).unwrap().stored(Storage::F16).unwrap();
        let shader = Shader::new(l);
        let eye = self.cam.eye.as_dvec3();
        let shade = |s: &Visible| visible::shade_one(&shader, &atlas, filter, self.probes.as_ref(), &self.materials, eye, s);
        let w = self.cam.width as usize;
        assert_eq!(img.len(), self.pixels.len() * 4);
        let (mut worst, mut checked, mut probed) = (0.0f64, 0usize, 0usize);
        for (k, p) in self.pixels.iter().enumerate() {
            let Some(s) = p else { continue };
            let t = shade(&s[0]);
            let x = t.total();
            let mut bound = (t.diffuse.abs() + t.specular.abs()) * 1e-4;
            let mut dr = DVec3::ZERO;
            for o in &s[1..] {
                dr = dr.max((shade(o).total() - x).abs());
            }
            bound += dr;
            if filter == LightmapFilter::Bicubic && s[0].lightmapped {
                // |w_l|: the pixel's shading of lobe l alone (linear in the lobes, per channel).
                let v = (eye - s[0].position.as_dvec3()).normalize();
                let (fnorm, n) = (s[0].frame_normal.as_dvec3().normalize(), s[0].normal.as_dvec3().normalize());
                for (li, b) in bicubic_bound(&atlas, [s[0].uv[0] as f64, s[0].uv[1] as f64]).iter().enumerate() {
                    let mut unit = vec![DVec3::ZERO; atlas.lobes.len()];
                    unit[li] = DVec3::ONE;
                    bound += shader.terms_at(&unit, &self.materials[s[0].material as usize], fnorm, n, v).total().abs() * *b;
                }
            }
            for c in 0..3 {
                let want = code(x[c], self.exposure);
                let allowed = 0.51 + (code(x[c] + bound[c], self.exposure) - want).max(want - code(x[c] - bound[c], self.exposure));
                let got = img[4 * k + c] as f64;
                worst = worst.max((got - want).abs() / allowed);
                assert!(
                    (got - want).abs() <= allowed,
                    "{api} {name}: pixel ({}, {}) channel {c}: {got} vs the twin's {want:.3} (allowed ±{allowed:.3}; linear {:.5}{})",
                    k % w,
                    k / w,
                    x[c],
                    if s[0].probed { ", a dynamic object" } else { "" }
                );
                checked += 1;
                probed += s[0].probed as usize;
            }
        }
        (checked, probed, worst)
    }
}

/// The APIs the page ran (WebGL 2 must have).
fn apis(report: &serde_json::Value) -> Vec<&'static str> {
    let apis: Vec<&str> = ["webgl2", "webgpu"]
        .into_iter()
        .filter(|api| {
            let a = report["apis"][api].as_str().unwrap_or("missing");
            println!("{api}: {a}");
            !a.starts_with("unavailable") && a != "missing"
        })
        .collect();
    assert!(apis.contains(&"webgl2"), "WebGL 2 did not run: {report}");
    if !apis.contains(&"webgpu") {
        println!("WebGPU was not rendered here (the WGSL was not compiled by the browser)");
    }
    apis
}

/// `render --device cpu … --out OUT --web WEB` with `args` (16 passes, 16 reference samples).
fn render(out: &Path, web: &Path, args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_render"))
        .args(["--device", "cpu", "--frames", "0", "--passes", "16", "--reference-samples", "16", "--reference-noise", "0"])
        .args(args)
        .arg("--out")
        .arg(out)
        .arg("--web")
        .arg(web)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn browser_or_skip() -> Option<PathBuf> {
    let b = chromium();
    if b.is_none() {
        assert!(
            std::env::var("SBF_REQUIRE_BROWSER").map_or(true, |v| v != "1"),
            "SBF_REQUIRE_BROWSER=1 but no chromium found (apt-get install chromium, or set SBF_CHROMIUM)"
        );
        eprintln!("skipping: no chromium");
    }
    b
}

#[test]
fn viewer_matches_the_cpu_twin_in_headless_chromium() {
    let Some(browser) = browser_or_skip() else { return };
    let tmp = std::env::temp_dir().join(format!("sbf-web-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let (out, web) = (tmp.join("render"), tmp.join("web"));
    render(&out, &web, &["--bases", "sh2,ad9,sg9", "--size", "240x135"]);
    let bytes: u64 = std::fs::read_dir(&web).unwrap().map(|e| e.unwrap().metadata().unwrap().len()).sum();
    println!("viewer folder: {:.2} MB", bytes as f64 / 1e6);
    assert!(bytes <= 10_000_000, "the viewer folder of the built-in scene is {bytes} bytes");

    let configs = ["none", "sh2", "ad9", "sg9", "sh2:bicubic"];
    let query = format!("test=1&apis=webgl2,webgpu&configs={}", configs.join(","));
    let (log, report, _, port) = open(&browser, &web, &tmp.join("profile"), &query);
    // Offline: every request the page made is its own folder or the test's endpoints (the
    // browser's own traffic is listed, not counted), and the viewer's files name no other
    // place (its requests over TLS would be tunnels the proxy cannot look into).
    let browser_own: Vec<&String> = log.requests.iter().filter(|r| !r.1).map(|r| &r.0).collect();
    println!("the browser's own requests (no fetch metadata; not the page's): {browser_own:?}");
    for f in ["index.html", "viewer.js"] {
        let text = std::fs::read_to_string(web.join(f)).unwrap();
        assert!(!text.contains("http://") && !text.contains("https://") && !text.contains("src=\"//"), "{f} names another place");
    }
    let foreign: Vec<&String> = log
        .requests
        .iter()
        .filter(|r| r.1)
        .map(|r| &r.0)
        .filter(|r| {
            let t = r.split_once(' ').map_or("", |x| x.1);
            let t = t.strip_prefix(&format!("http://127.0.0.1:{port}")).unwrap_or(t);
            !(t.starts_with("/__") || (t.starts_with('/') && web.join(t.trim_start_matches('/').split('?').next().unwrap()).is_file()))
        })
        .collect();
    assert!(foreign.is_empty(), "requests outside the viewer's folder: {foreign:?}");
    let first = log.first_frame_at.unwrap().duration_since(log.index_at.unwrap()).as_secs_f64();
    println!("first frame {first:.3} s after the page was requested");
    assert!(first <= 2.0, "first frame after {first:.2} s");

    let twin = Twin::new("cornell", &out, &web);
    for api in apis(&report) {
        for name in configs {
            let (n, _, worst) = twin.check(&log.captures[&(api.to_string(), name.to_string())], api, name);
            println!("{api} {name}: {n} channels within the model, worst {worst:.3} of its bound");
        }
    }
    let (lm, w, h) = (&twin.lm, twin.cam.width as usize, twin.cam.height as usize);
    // The report links to the viewer.
    let results: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(results["viewer"].as_str(), Some("../web/index.html"));
    assert!(std::fs::read_to_string(out.join("report.html")).unwrap().contains("href=\"../web/index.html\""));

    // A texture limit below the atlas (88 × 132): downsampled 4× (132 → 66 > 64 → 33), the E/π
    // error stated (a relative RMS: positive, below 1), the UVs scaled, and the page draws.
    let web2 = tmp.join("web-small");
    let o = Command::new(env!("CARGO_BIN_EXE_render"))
        .args([
            "--device",
            "cpu",
            "--frames",
            "0",
            "--reference-samples",
            "4",
            "--reference-noise",
            "0",
            "--bases",
            "sh2",
            "--size",
            "240x135",
        ])
        .arg("--bake")
        .arg(out.join("bake"))
        .arg("--out")
        .arg(tmp.join("render-small"))
        .arg("--web")
        .arg(&web2)
        .args(["--web-max-texture", "64"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let sj2: serde_json::Value = serde_json::from_slice(&std::fs::read(web2.join("scene.json")).unwrap()).unwrap();
    assert_eq!(sj2["downsampled"]["factor"].as_u64(), Some(4));
    assert_eq!(sj2["atlas"], serde_json::json!([lm.width.div_ceil(4), lm.height.div_ceil(4)]));
    let e = sj2["downsampled"]["irradiance_relative_rms"].as_f64().unwrap();
    assert!(e > 0.0 && e < 1.0, "stated downsampling error {e}");
    let (log2, _, _, _) = open(&browser, &web2, &tmp.join("profile2"), "test=1&apis=webgl2&configs=sh2");
    let img = &log2.captures[&("webgl2".to_string(), "sh2".to_string())];
    assert!(img.chunks(4).filter(|p| p[0] > 0).count() > w * h / 2, "the downsampled viewer drew little");
    let _ = std::fs::remove_dir_all(&tmp);
}

/// The glTF room (`../shared/scenes`, its first camera; textures dropped as `render` drops
/// them): the viewer opens with no error in both APIs, and SH L2 and AD 9 match the twin —
/// the chair and the floor from the lightmap, the dynamic sphere from the SH L2 probes (the
/// probe path of both shaders).
#[test]
fn the_gltf_room_opens_and_matches_its_twin() {
    let Some(browser) = browser_or_skip() else { return };
    let gltf = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/bevy_MixedLightingExample/MixedLightingExample.gltf");
    if !gltf.is_file() {
        assert!(std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"), "SBF_REQUIRE_PROBES=1 but {} is missing", gltf.display());
        eprintln!("skipping: {} is missing", gltf.display());
        return;
    }
    let tmp = std::env::temp_dir().join(format!("sbf-web-room-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let (out, web) = (tmp.join("render"), tmp.join("web"));
    let scene = gltf.to_str().unwrap();
    render(&out, &web, &["--scene", scene, "--bases", "sh2,ad9", "--size", "240x135"]);
    let (log, report, _, _) = open(&browser, &web, &tmp.join("profile"), "test=1&apis=webgl2,webgpu&configs=sh2,ad9");
    let twin = Twin::new(scene, &out, &web);
    for api in apis(&report) {
        for name in ["sh2", "ad9"] {
            let (n, probed, worst) = twin.check(&log.captures[&(api.to_string(), name.to_string())], api, name);
            println!("room {api} {name}: {n} channels ({probed} of a dynamic object) within the model, worst {worst:.3} of its bound");
            assert!(twin.probes.is_none() || probed > 0, "no pixel of a dynamic object was compared");
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
}

/// The atrium (a 0.29 M-triangle hall; a coarse layout, 2 texels per unit, to stay small): the
/// viewer opens in both APIs, and SH L2 matches the twin — the gold statue, a dynamic object,
/// shaded from the bake's SH L2 probes by each API's probe lookup (trilinear, invalid probes
/// left out).
#[test]
fn the_atrium_opens_and_its_dynamic_object_matches_the_probes() {
    let Some(browser) = browser_or_skip() else { return };
    let tmp = std::env::temp_dir().join(format!("sbf-web-atrium-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let (out, web) = (tmp.join("render"), tmp.join("web"));
    render(
        &out,
        &web,
        // 32 × 12 × 24 probes: more than one WebGL 2 texture column of 9-texel rows holds.
        &[
            "--scene",
            "atrium",
            "--texels-per-unit",
            "2",
            "--bases",
            "sh2",
            "--size",
            "320x180",
            "--camera",
            "0,1.7,3.2:0,2.8,-6:80",
            "--probes",
            "32,12,24",
        ],
    );
    let (log, report, _, _) = open(&browser, &web, &tmp.join("profile"), "test=1&apis=webgl2,webgpu&configs=sh2");
    let twin = Twin::new("atrium", &out, &web);
    assert!(twin.probes.is_some(), "the atrium's statue is a dynamic object");
    for api in apis(&report) {
        let (n, probed, worst) = twin.check(&log.captures[&(api.to_string(), "sh2".to_string())], api, "sh2");
        println!("atrium {api} sh2: {n} channels ({probed} of the dynamic statue) within the model, worst {worst:.3} of its bound");
        assert!(probed > 0, "no pixel of the statue was compared");
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
