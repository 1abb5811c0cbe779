//! The report folder is complete and self-consistent: `results.json` reads back into the
//! tool's serde types and writes out identically, every image it names exists with the
//! map's size, maps with equal file names get separate folders, `--images exr` adds the
//! float images, and the decision section equals a brute-force recomputation.

use std::process::Command;

#[test]
fn results_json_names_existing_images() {
    let d = std::env::temp_dir().join(format!("probes-outputs-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let map = d.join("sky.exr");
    let env =
        Command::new(env!("CARGO_BIN_EXE_probes")).args(["env", "--preset", "sky", "--width", "64", "--out"]).arg(&map).output().unwrap();
    assert!(env.status.success(), "{}", String::from_utf8_lossy(&env.stderr));
    let out = d.join("report");
    let run = Command::new(env!("CARGO_BIN_EXE_probes"))
        .arg("compare")
        .arg(&map)
        .args(["--modes", "shl2,adrbf,sgls,sgpls,ac", "--alphas", "0.2,0.6", "--specular-samples", "16", "--repeats", "1", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    // Read back with the same serde types the tool writes.
    let text = std::fs::read_to_string(out.join("results.json")).unwrap();
    let all = probes::results::from_json(&text).unwrap();
    assert_eq!(probes::results::from_json(&probes::results::to_json(&all)).unwrap(), all, "results.json round-trips");
    let m = &all[0];
    assert_eq!(m.map.width, 64);
    let check = |rel: &str| {
        let p = out.join(rel);
        let img = image::open(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert_eq!((img.width(), img.height()), (64, 32), "{}", p.display());
    };
    // Default images: PNG previews only.
    check(&m.reference.images.irradiance.png);
    assert!(m.reference.images.irradiance.exr.is_none());
    for a in ["0.2", "0.6"] {
        check(&m.reference.images.specular[a].png);
        let e = &m.reference.specular_error[a];
        assert!(e.rms >= 0.0 && e.texels_checked > 0);
    }
    assert_eq!(m.modes.len(), 5);
    for mode in &m.modes {
        let id = mode.id.as_str();
        check(&mode.images.irradiance.png);
        check(&mode.images.irradiance_error_png);
        // Every radiance mode reconstructs specular; `ac` stores irradiance only.
        assert_eq!(mode.images.specular.len(), if id == "ac" { 0 } else { 2 }, "{id}");
        for p in mode.images.specular.values() {
            check(&p.image.png);
            check(&p.error_png);
        }
        assert!(mode.metrics.irradiance.rms.is_finite(), "{id}");
        // Cost axes: a measured steady state with its spread, storage at f32, and the
        // reference's time charged to the one mode here that fits it (`ac`).
        let c = &mode.cost;
        assert!(
            c.eval.repeats >= 5
                && c.eval.batch >= probes::cost::MIN_BATCH
                && c.eval.min_ns <= c.eval.median_ns
                && c.eval.median_ns <= c.eval.max_ns,
            "{id}: {:?}",
            c.eval
        );
        assert_eq!(c.storage_bytes, 12.0 * mode.coefficient_count as f64, "{id}");
        let charged = c.encode_total_s - c.encode_s;
        if id == "ac" {
            assert_eq!(c.encode_input, "irradiance reference");
            assert!((charged - m.reference.irradiance_seconds).abs() < 1e-12, "{id}: {charged}");
        } else {
            assert_eq!(charged, 0.0, "{id}");
        }
        assert_eq!(c.specular_eval.is_some(), id != "ac", "{id}");
        // The per-sample encoder reports error against 16, 32, …, 4096 samples.
        let conv = &mode.convergence;
        assert_eq!(conv.len(), if id == "sgpls" { 9 } else { 0 }, "{id}");
        // Its last point is the reported result (same samples, same order, same f32 state;
        // the snapshot sums lobes in a different order: 1e-9 relative).
        if let Some(&(n, e)) = conv.last() {
            let rms = mode.metrics.irradiance.rms;
            assert_eq!(n, 4096);
            assert!((e - rms).abs() <= 1e-9 * rms, "{id}: {e} vs {rms}");
        }
    }
    for f in [
        "report.html",
        "report.md",
        "sky/error_vs_encode_time.png",
        "sky/error_vs_eval_cost.png",
        "sky/error_vs_storage.png",
        "sky/error_vs_samples.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(
        !std::fs::read_dir(out.join("sky")).unwrap().any(|e| e.unwrap().path().extension().is_some_and(|x| x == "exr")),
        "no EXR by default"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// A fresh temporary folder for `tag` and a 32-wide procedural sky map in it.
fn sky_map(tag: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let d = std::env::temp_dir().join(format!("probes-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let map = d.join("sky.hdr");
    run(&["env".as_ref(), "--preset".as_ref(), "sky".as_ref(), "--width".as_ref(), "32".as_ref(), "--out".as_ref(), map.as_os_str()]);
    (d, map)
}

fn run(args: &[&std::ffi::OsStr]) {
    let o = Command::new(env!("CARGO_BIN_EXE_probes")).args(args).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Two maps named `sky` in different folders: two image folders, each map's images in its
/// own; `--images exr` writes the EXRs results.json names.
#[test]
fn equal_names_get_their_own_folders_and_exr_on_request() {
    let d = std::env::temp_dir().join(format!("probes-names-{}", std::process::id()));
    for (sub, preset) in [("a", "sky"), ("b", "sky-nosun")] {
        std::fs::create_dir_all(d.join(sub)).unwrap();
        let p = d.join(sub).join("sky.hdr");
        run(&["env".as_ref(), "--preset".as_ref(), preset.as_ref(), "--width".as_ref(), "32".as_ref(), "--out".as_ref(), p.as_os_str()]);
    }
    let out = d.join("report");
    run(&[
        "compare".as_ref(),
        d.join("a/sky.hdr").as_os_str(),
        d.join("b/sky.hdr").as_os_str(),
        "--modes".as_ref(),
        "shl2,ac".as_ref(),
        "--no-specular".as_ref(),
        "--repeats".as_ref(),
        "1".as_ref(),
        "--images".as_ref(),
        "exr".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let all = probes::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(all.len(), 2);
    assert_eq!((all[0].map.folder.as_str(), all[1].map.folder.as_str()), ("sky", "sky-2"));
    // Different maps, different reference images in the two folders.
    let img = |rel: &str| image::open(out.join(rel)).unwrap().to_rgb32f().into_raw();
    let (a, b) = (all[0].reference.images.irradiance.exr.clone().unwrap(), all[1].reference.images.irradiance.exr.clone().unwrap());
    assert_ne!(a, b);
    assert_ne!(img(&a), img(&b), "the second map overwrote the first");
    for m in &all {
        for mode in &m.modes {
            img(mode.images.irradiance.exr.as_deref().expect("exr requested"));
        }
    }
    std::fs::remove_dir_all(&d).ok();
}

/// The decision section against brute force, on a real run's results.json: the CPU costs
/// come from the committed calibration; the CPU tiers
/// partition the candidates, cheapest first, and no tier's cost interval starts beyond its
/// anchor's; every front point is dominated by no candidate in (tier or bytes, error), every
/// other candidate is dominated by or equal to a front point; every budget cell holds the
/// lowest error among the candidates that fit; the recommendation is the cheapest front
/// point within 25 % of the best error and the usability threshold, or the best, unusable,
/// where none is within it (checked at four thresholds). Mutations tried: a front that keeps points up to 1.5×
/// the last error, a budget using `<` for the byte limit, tiers merged by chained overlap,
/// a recommendation within 2× — each fails here.
#[test]
fn decision_matches_brute_force_from_results_json() {
    let (d, map) = sky_map("decide");
    let out = d.join("report");
    run(&[
        "compare".as_ref(),
        map.as_os_str(),
        "--modes".as_ref(),
        "ac,acproj,shl1,shl2,shl4,adrbf,adrbf-irr,sgls,sglsa".as_ref(),
        "--alphas".as_ref(),
        "0.3".as_ref(),
        "--repeats".as_ref(),
        "1".as_ref(),
        "--images".as_ref(),
        "none".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let all = probes::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let r = &all[0];
    // What the tool wrote equals what the library computes from the file.
    assert_eq!(probes::decide::decide(r), r.decision);
    assert_eq!(r.decision.signals.len(), 2, "irradiance and specular α=0.3");
    for sd in &r.decision.signals {
        // Candidates: (id, error, bytes, CPU interval [lo, hi] of the committed calibration,
        // widened as documented).
        assert!(sd.cpu_costs.starts_with("calibrated"), "{}", sd.cpu_costs);
        let floor = probes::decide::NOISE_FLOOR;
        let cal = probes::calibration::committed();
        let cands: Vec<(String, f64, f64, (f64, f64))> = r
            .modes
            .iter()
            .filter_map(|m| {
                let (err, key) = if sd.signal == "irradiance" {
                    (m.metrics.irradiance.rms, m.cost_keys.irradiance.clone())
                } else {
                    (m.metrics.specular.get("0.3")?.metrics.rms, m.cost_keys.specular.clone()?)
                };
                let c = cal.costs[&key];
                let mid = (c.low_ns * c.high_ns).sqrt();
                Some((m.id.clone(), err, m.cost.storage_bytes, (c.low_ns.min(mid / (1.0 + floor)), c.high_ns.max(mid * (1.0 + floor)))))
            })
            .collect();
        // 9 modes with irradiance; 6 of them store radiance and have specular.
        assert_eq!(cands.len(), if sd.signal == "irradiance" { 9 } else { 6 }, "{}", sd.signal);
        let tiers = &sd.tiers.iter().find(|t| t.axis == "eval_ns").expect("CPU tiers").tiers;
        let tier_of = |id: &str| tiers.iter().position(|g| g.iter().any(|x| x == id)).expect("every candidate has a tier") + 1;
        let mut seen: Vec<&String> = tiers.iter().flatten().collect();
        seen.sort();
        seen.dedup();
        assert_eq!(seen.len(), cands.len(), "{}: the tiers partition the candidates", sd.signal);
        let iv = |id: &str| cands.iter().find(|c| c.0 == id).unwrap().3;
        for (k, g) in tiers.iter().enumerate() {
            let anchor = g.iter().map(|id| iv(id)).min_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
            for id in g {
                assert!(iv(id).0 <= anchor.1, "{}: {id} starts beyond its tier's anchor", sd.signal);
            }
            if let Some(next) = tiers.get(k + 1) {
                for id in next {
                    assert!(iv(id).0 > anchor.1, "{}: {id} of tier {} starts inside tier {}'s anchor", sd.signal, k + 2, k + 1);
                }
            }
        }
        // Fronts: dominance in (cost rank, error), rank = bytes or CPU tier.
        for f in &sd.fronts {
            let rank = |c: &(String, f64, f64, (f64, f64))| -> Option<f64> {
                match f.axis.as_str() {
                    "storage_bytes" => Some(c.2),
                    "eval_ns" => Some(tier_of(&c.0) as f64),
                    _ => None,
                }
            };
            if rank(&cands[0]).is_none() {
                continue;
            }
            let on: Vec<&str> = f.points.iter().map(|p| p.id.as_str()).collect();
            let dominates = |a: &(String, f64, f64, (f64, f64)), b: &(String, f64, f64, (f64, f64))| {
                let (ra, rb) = (rank(a).unwrap(), rank(b).unwrap());
                ra <= rb && a.1 <= b.1 && (ra < rb || a.1 < b.1)
            };
            for c in &cands {
                let dominated = cands.iter().any(|o| dominates(o, c));
                if on.contains(&c.0.as_str()) {
                    assert!(!dominated, "{} {}: {} is on the front but dominated", sd.signal, f.axis, c.0);
                } else {
                    assert!(
                        dominated || cands.iter().any(|o| on.contains(&o.0.as_str()) && o.1 == c.1 && rank(o) == rank(c)),
                        "{} {}: {} is missing from the front",
                        sd.signal,
                        f.axis,
                        c.0
                    );
                }
            }
        }
        // Budget cells.
        for (bi, b) in sd.budget.bytes.iter().enumerate() {
            for (ti, t) in sd.budget.cpu_tiers.iter().enumerate() {
                let fit: Vec<_> = cands.iter().filter(|c| c.2 <= *b && tier_of(&c.0) <= *t).collect();
                let want = fit.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
                match &sd.budget.best[bi][ti] {
                    Some(p) => assert_eq!(p.error, want, "{} ≤ {b} B, ≤ tier {t}", sd.signal),
                    None => assert!(fit.is_empty(), "{} ≤ {b} B, ≤ tier {t}: {} fit but none chosen", sd.signal, fit.len()),
                }
            }
        }
        // The recommendation, at the run's usability threshold and at thresholds that bind
        // differently (recomputed from the same results): the cheapest tier holding a
        // candidate within 25 % of the best error and within the threshold, its best such
        // candidate; where no candidate is within the threshold, the best one, unusable.
        let pct = |id: &str| {
            let m = r.modes.iter().find(|m| m.id == id).unwrap();
            100.0 * if sd.signal == "irradiance" { m.metrics.irradiance.rel_rms } else { m.metrics.specular["0.3"].metrics.rel_rms }
        };
        let best = cands.iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
        for threshold in [r.usable_error_percent, 1.05 * pct(&best.0), 0.95 * pct(&best.0), 1e3] {
            let mut j = r.clone();
            j.usable_error_percent = threshold;
            let got = probes::decide::decide(&j).signals.into_iter().find(|x| x.signal == sd.signal).unwrap();
            let usable = pct(&best.0) <= threshold;
            let want = if usable {
                let ok: Vec<_> = cands.iter().filter(|c| c.1 <= 1.25 * best.1 && pct(&c.0) <= threshold).collect();
                let t = ok.iter().map(|c| tier_of(&c.0)).min().unwrap();
                ok.iter().filter(|c| tier_of(&c.0) == t).map(|c| c.1).fold(f64::INFINITY, f64::min)
            } else {
                best.1
            };
            assert_eq!(got.usable, usable, "{} at {threshold} %", sd.signal);
            assert_eq!(got.recommended.as_ref().expect("a recommendation").mode.error, want, "{} at {threshold} %", sd.signal);
        }
    }
    // A threshold that binds inside the 25 % window: a cheaper candidate moved to 1.2× the
    // best irradiance error is recommended without a threshold and not at 1.1× the best's.
    let sd = &r.decision.signals[0];
    let tier = |id: &str| sd.tiers[0].tiers.iter().position(|g| g.iter().any(|x| x == id)).unwrap();
    let best = sd.fronts.iter().find(|f| f.axis == "eval_ns").unwrap().points.last().unwrap().clone();
    let cheap = r
        .modes
        .iter()
        .filter(|m| m.id != best.id && sd.tiers[0].tiers.iter().flatten().any(|x| *x == m.id))
        .min_by_key(|m| tier(&m.id))
        .unwrap();
    assert!(tier(&cheap.id) < tier(&best.id), "a cheaper tier than the best's");
    let mut j = r.clone();
    let irr = &mut j.modes.iter_mut().find(|m| m.id == cheap.id).unwrap().metrics.irradiance;
    let scale = 1.2 * best.error / irr.rms;
    (irr.rms, irr.rel_rms) = (irr.rms * scale, irr.rel_rms * scale);
    let rec = |j: &probes::results::MapResults, t: f64| {
        let mut j = j.clone();
        j.usable_error_percent = t;
        probes::decide::decide(&j).signals[0].recommended.clone().unwrap().mode.id
    };
    assert_eq!(rec(&j, 1e3), cheap.id);
    assert_eq!(rec(&j, 1.1 * best.error_percent), best.id);
    // The run's threshold is the default; below the best specular error the report line says
    // that no mode fits.
    assert_eq!(r.usable_error_percent, probes::decide::USABLE_ERROR_PERCENT);
    let mut j = r.clone();
    j.usable_error_percent = 0.5 * r.decision.signals[1].recommended.as_ref().unwrap().mode.error_percent;
    j.decision = probes::decide::decide(&j);
    let line = probes::decision_text::recommendation(&j, &j.decision.signals[1], probes::decision_text::plain);
    assert!(!j.decision.signals[1].usable && line.contains("no mode within"), "{line}");
    std::fs::remove_dir_all(&d).ok();
}

/// Every file in the folder (relative, `/`-separated, sorted), the manifest excepted.
fn files_in(dir: &std::path::Path) -> Vec<String> {
    fn walk(root: &std::path::Path, d: &std::path::Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.push(p.strip_prefix(root).unwrap().components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"));
            }
        }
    }
    let mut v = Vec::new();
    walk(dir, dir, &mut v);
    v.retain(|f| f != probes::outdir::MANIFEST);
    v.sort();
    v
}

/// A run owns its folder: rerunning into it with fewer modes and another map leaves only
/// the new run's files (exactly those its manifest lists), a foreign folder is written only
/// with `--force`, and what was there before is kept.
#[test]
fn a_run_replaces_its_own_files_and_keeps_foreign_ones() {
    let d = std::env::temp_dir().join(format!("probes-owns-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let (a, b) = (d.join("first.exr"), d.join("second.exr"));
    for p in [&a, &b] {
        run(&["env".as_ref(), "--width".as_ref(), "16".as_ref(), "--out".as_ref(), p.as_os_str()]);
    }
    let out = d.join("report");
    let compare = |map: &std::path::Path, modes: &str, extra: &[&str]| {
        let mut args: Vec<&std::ffi::OsStr> = vec!["compare".as_ref(), map.as_os_str(), "--modes".as_ref(), modes.as_ref()];
        args.extend(["--alphas", "0.5", "--specular-samples", "8", "--repeats", "1", "--out"].map(std::ffi::OsStr::new));
        args.push(out.as_os_str());
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        run(&args);
    };
    let manifest = |dir: &std::path::Path| -> Vec<String> {
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join(probes::outdir::MANIFEST)).unwrap()).unwrap();
        v["files"].as_array().unwrap().iter().map(|f| f.as_str().unwrap().to_string()).collect()
    };
    compare(&a, "shl2,adrbf,sgls", &["--images", "exr"]);
    let first = files_in(&out);
    assert!(first.iter().any(|f| f == "first/sgls_irradiance.exr"), "{first:?}");
    assert_eq!(manifest(&out), first, "the manifest lists every file written");
    compare(&b, "shl2", &[]);
    let second = files_in(&out);
    assert_eq!(manifest(&out), second, "after the rerun the folder holds exactly the manifest's files");
    assert!(second.iter().all(|f| !f.starts_with("first/")), "the first run's images are gone: {second:?}");
    assert!(second.iter().any(|f| f == "second/shl2_irradiance.png"), "{second:?}");
    assert!(!out.join("first").exists(), "the first run's emptied folder is removed");
    // A folder someone else filled: refused, then written with --force, their file kept.
    let foreign = d.join("foreign");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), b"keep").unwrap();
    let refused = Command::new(env!("CARGO_BIN_EXE_probes"))
        .args(["compare".as_ref(), a.as_os_str(), "--modes".as_ref(), "shl2".as_ref(), "--no-specular".as_ref(), "--out".as_ref()])
        .arg(&foreign)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--force"));
    run(&[
        "compare".as_ref(),
        a.as_os_str(),
        "--modes".as_ref(),
        "shl2".as_ref(),
        "--no-specular".as_ref(),
        "--force".as_ref(),
        "--out".as_ref(),
        foreign.as_os_str(),
    ]);
    run(&[
        "compare".as_ref(),
        b.as_os_str(),
        "--modes".as_ref(),
        "ac".as_ref(),
        "--no-specular".as_ref(),
        "--out".as_ref(),
        foreign.as_os_str(),
    ]);
    assert_eq!(std::fs::read(foreign.join("notes.txt")).unwrap(), b"keep");
    let left = files_in(&foreign);
    assert_eq!(left.iter().filter(|f| f.as_str() != "notes.txt").cloned().collect::<Vec<_>>(), manifest(&foreign));
    std::fs::remove_dir_all(&d).ok();
}

/// Decisions hold under cost noise: every measured cost of a real run's results.json moved
/// to a random point of its own spread (CPU and specular medians within [low, high], encode
/// within [fastest, slowest], 50 draws, fixed seed) gives byte-identical decision records —
/// they compare the calibration's tiers, not this run's timings. Where the calibration lacks
/// a candidate, the signal falls back to this run's costs and says so. Mutations tried: tiers
/// from this run's medians (± the floor) — fails here; from this run's spread — the
/// brute-force test fails (it checks the calibrated intervals).
#[test]
fn decisions_hold_when_costs_move_within_their_spread() {
    let (d, map) = sky_map("jitter");
    let out = d.join("report");
    run(&[
        "compare".as_ref(),
        map.as_os_str(),
        "--alphas".as_ref(),
        "0.3,0.7".as_ref(),
        "--specular-samples".as_ref(),
        "16".as_ref(),
        "--images".as_ref(),
        "none".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let text = std::fs::read_to_string(out.join("results.json")).unwrap();
    let r = probes::results::from_json(&text).unwrap().remove(0);
    let want = serde_json::to_string(&r.decision).unwrap();
    let mut rng = sbf::sampling::Pcg32::new(7, 1);
    let mut within = |lo: f64, hi: f64| lo + (hi - lo) * rng.next_f64();
    for _ in 0..50 {
        let mut j = r.clone();
        for m in &mut j.modes {
            m.cost.eval.median_ns = within(m.cost.eval.low_ns, m.cost.eval.high_ns);
            if let Some(s) = &mut m.cost.specular_eval {
                s.median_ns = within(s.low_ns, s.high_ns);
            }
            let [lo, hi] = m.cost.encode_total_range_s;
            m.cost.encode_total_s = within(lo, hi);
        }
        assert_eq!(serde_json::to_string(&probes::decide::decide(&j)).unwrap(), want);
    }
    let mut j = r.clone();
    j.modes.iter_mut().find(|m| m.id == "shl2").unwrap().cost_keys.irradiance = "irradiance/not-calibrated".into();
    let fallback = probes::decide::decide(&j);
    let s = &fallback.signals;
    assert!(s[0].cpu_costs.starts_with("measured in this run (the calibration lacks shl2)"), "{}", s[0].cpu_costs);
    assert!(s[1].cpu_costs.starts_with("calibrated"), "{}", s[1].cpu_costs);
    std::fs::remove_dir_all(&d).ok();
}
