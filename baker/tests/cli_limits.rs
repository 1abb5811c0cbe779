//! The `baker` command refuses unbounded or inconsistent input before any work: each case
//! exits with 2 within 1 s (no scene is loaded, nothing is traced), its message names the
//! option and the limit, and the output folder is not created. The cases are the ones that
//! used to run for minutes or abort after the bake (`--preview-width 200000` allocated
//! 360 GB after tracing; `--denoise-radius 100000`, `--probes 300,300,300` ran without
//! progress; `--adaptive-pilot 100 --passes 2` was accepted silently), and the other bounds
//! of `baker::run::limits`.
//!
//! Mutation tried: `Options::validate` called only after the passes (in `run::bake`, before
//! the outputs; not in `main`) — the first case fails: exit 1 after loading and baking the
//! scene (6 s for the whole test).

use baker::run::limits::{MAX_BOUNCES, MAX_DENOISE_RADIUS, MAX_PADDING, MAX_PASSES, MAX_PREVIEW_WIDTH, MAX_PROBES};
use std::process::Command;
use std::time::{Duration, Instant};

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("baker-limits-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `baker ARGS --out OUT`; returns (exit code, stderr, wall time).
fn run(args: &[&str], out: &std::path::Path) -> (Option<i32>, String, Duration) {
    let t = Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_baker")).args(args).arg("--out").arg(out).output().unwrap();
    (o.status.code(), String::from_utf8_lossy(&o.stderr).to_string(), t.elapsed())
}

#[test]
fn unbounded_inputs_are_refused_before_any_work() {
    let (w, r, p, n, b, pad) = (
        MAX_PREVIEW_WIDTH.to_string(),
        MAX_DENOISE_RADIUS.to_string(),
        MAX_PROBES.to_string(),
        MAX_PASSES.to_string(),
        MAX_BOUNCES.to_string(),
        MAX_PADDING.to_string(),
    );
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (vec!["--preview-width", "200000"], vec!["--preview-width 200000", &w]),
        (vec!["--preview-width", "4"], vec!["--preview-width 4", "8 to"]),
        (vec!["--denoise-radius", "100000"], vec!["--denoise-radius 100000", &r]),
        (vec!["--denoise", "on", "--denoise-radius", "17"], vec!["--denoise-radius 17", &r]),
        (vec!["--probes", "300,300,300"], vec!["--probes 300,300,300", "27000000", &p]),
        (vec!["--probes", "100000000000,100000000000,100000000000"], vec!["--probes", &p]),
        (vec!["--adaptive", "--adaptive-pilot", "100", "--passes", "2"], vec!["--adaptive-pilot 100", "--passes 2"]),
        (vec!["--passes", "5000000000"], vec!["--passes 5000000000", &n]),
        (vec!["--measure-rays", "0"], vec!["--measure-rays 0"]),
        (vec!["--bounces", "100000"], vec!["--bounces 100000", &b]),
        (vec!["--padding", "1000"], vec!["--padding 1000", &pad]),
        (vec!["--texels-per-unit", "inf"], vec!["--texels-per-unit inf"]),
        (vec!["--gpus", "2", "--device", "gpu", "--guiding"], vec!["--gpus 2", "--guiding"]),
        (vec!["--gpus", "2", "--device", "gpu", "--filter", "box"], vec!["--gpus 2", "--filter"]),
    ];
    for (args, want) in &cases {
        let out = tmp("refused");
        let (code, err, t) = run(args, &out);
        println!("{args:?}: exit {code:?} in {:.0} ms: {}", t.as_secs_f64() * 1e3, err.trim());
        assert_eq!(code, Some(2), "{args:?}: exit {code:?}: {err}");
        for w in want {
            assert!(err.contains(w), "{args:?}: the message does not name '{w}': {err}");
        }
        assert!(t < Duration::from_secs(1), "{args:?}: refused only after {t:?}");
        assert!(!out.exists(), "{args:?}: the output folder was created");
    }
}

/// An output folder that cannot be created is refused before the scene is traced (exit 1,
/// within 1 s, naming --out).
#[test]
fn an_unwritable_output_folder_is_refused_before_tracing() {
    let file = tmp("a-file");
    std::fs::write(&file, b"not a folder").unwrap();
    let out = file.join("bake");
    let (code, err, t) = run(&["--device", "cpu", "--passes", "100000"], &out);
    println!("exit {code:?} in {:.0} ms: {}", t.as_secs_f64() * 1e3, err.trim());
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("--out") && err.contains("cannot create the output folder"), "{err}");
    assert!(t < Duration::from_secs(1), "refused only after {t:?}");
    let _ = std::fs::remove_file(&file);
}
