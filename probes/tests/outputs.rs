//! The report folder is complete and self-consistent: `results.json` parses, follows
//! the documented schema, and every image it names exists with the map's size.

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
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let m = &v[0];
    assert_eq!(m["map"]["width"], 64);
    let check = |rel: &serde_json::Value| {
        let p = out.join(rel.as_str().expect("a path"));
        let img = image::open(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert_eq!((img.width(), img.height()), (64, 32), "{}", p.display());
    };
    check(&m["reference"]["images"]["irradiance"]);
    for a in ["0.2", "0.6"] {
        check(&m["reference"]["images"]["specular"][a]);
        let e = &m["reference"]["specular_error"][a];
        assert!(e["rms"].as_f64().unwrap() >= 0.0 && e["texels_checked"].as_u64().unwrap() > 0);
    }
    let modes = m["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 5);
    for mode in modes {
        let id = mode["id"].as_str().unwrap();
        for key in ["irradiance", "irradiance_png", "irradiance_error_png"] {
            check(&mode["images"][key]);
        }
        let spec = mode["images"]["specular"].as_object().unwrap();
        // Every radiance mode reconstructs specular; `ac` stores irradiance only.
        assert_eq!(spec.len(), if id == "ac" { 0 } else { 2 }, "{id}");
        for p in spec.values() {
            check(p);
        }
        for sig in ["rms", "rms_weighted", "rel_rms", "max_abs", "smape", "negative_fraction"] {
            assert!(mode["metrics"]["irradiance"][sig].is_number(), "{id}/{sig}");
        }
        // The per-sample encoder reports error against 16, 32, …, 4096 samples.
        let conv = mode["convergence"].as_array().unwrap();
        assert_eq!(conv.len(), if id == "sgpls" { 9 } else { 0 }, "{id}");
        // Its last point is the reported result (same samples, same order, same f32 state;
        // the snapshot sums lobes in a different order: 1e-9 relative).
        if let Some(last) = conv.last() {
            let (n, e) = (last[0].as_u64().unwrap(), last[1].as_f64().unwrap());
            let rms = mode["metrics"]["irradiance"]["rms"].as_f64().unwrap();
            assert_eq!(n, 4096);
            assert!((e - rms).abs() <= 1e-9 * rms, "{id}: {e} vs {rms}");
        }
    }
    for f in ["report.html", "report.md", "sky/error_vs_encode_time.png", "sky/error_vs_eval_cost.png", "sky/error_vs_samples.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    std::fs::remove_dir_all(&d).ok();
}
