//! The bake on an existing distributed engine: `baker/distributed/dask_bake.py` runs the
//! shards as Dask tasks on a local cluster of 3 worker processes; the Dask worker process
//! running one shard is killed (SIGKILL) mid-bake, after the shard's first checkpoint — the
//! machine-loss case: its `baker` child must end with it (`--exit-with-parent`) instead of
//! baking on as an orphan beside the retry; Dask's nanny restarts the worker and the
//! scheduler runs the task again, the retry resumes from the checkpoint, and the merged
//! outputs must equal the single-process bake byte for byte (bake.json without the fields
//! that measure the run).
//!
//! The oracle is the single bake (no partition, no checkpoint, no resume). Needs Python
//! with `distributed` (baker/distributed/requirements.txt): the interpreter is
//! `SBF_PYTHON` (default `python3`); without the package the test is skipped, unless
//! `SBF_REQUIRE_DASK=1` (CI), where it fails.
//!
//! Mutations tried, each caught: the driver starting `baker` without `--exit-with-parent`
//! (the killed worker's bake runs on: "outlived its killed worker by 5 s"); the driver
//! submitting with `retries=0` (the killed shard fails for good: the driver exits 1,
//! nothing merged — checked when the test killed the bake itself); the retry run without `--resume`
//! (it restarts from pass 0: the outputs still match — a restart is also correct — but the
//! log's "resumed at pass" check fails); the driver not setting its cancel event on SIGTERM
//! (the bakes run on until the cluster closes, 10 s later: `sigterm_…` fails).

mod common;

use common::outputs::hashes;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn python() -> Option<String> {
    let py = std::env::var("SBF_PYTHON").unwrap_or_else(|_| "python3".into());
    // `import dask.distributed` from a neutral folder: run from baker/ (the test's working
    // directory), a bare `import distributed` finds baker/distributed/ as a namespace package
    // and passes without Dask installed.
    let ok = Command::new(&py)
        .args(["-c", "import dask.distributed"])
        .current_dir(std::env::temp_dir())
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        return Some(py);
    }
    assert!(
        std::env::var("SBF_REQUIRE_DASK").map_or(true, |v| v != "1"),
        "SBF_REQUIRE_DASK=1 but `{py} -c 'import dask.distributed'` fails: pip install -r baker/distributed/requirements.txt"
    );
    println!("skipped: {py} has no dask distributed (pip install -r baker/distributed/requirements.txt; SBF_PYTHON names the interpreter)");
    None
}

/// The parent of process `pid` (Linux /proc/PID/stat, the field after the parenthesised name).
fn parent(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    stat.rsplit_once(')')?.1.split_whitespace().nth(1)?.parse().ok()
}

/// Whether process `pid` is alive (a zombie counts as gone: it has exited).
fn alive(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .is_ok_and(|s| s.rsplit_once(')').is_some_and(|(_, r)| !r.trim_start().starts_with('Z')))
}

/// The pid of the running `baker` process whose arguments include `--shard SPEC` and
/// `--out DIR` (Linux /proc).
fn shard_pid(spec: &str, dir: &Path) -> Option<u32> {
    shard_pid_in(spec, Some(dir))
}

/// [`shard_pid`], the output folder `dir` checked only where given.
fn shard_pid_in(spec: &str, dir: Option<&Path>) -> Option<u32> {
    for e in std::fs::read_dir("/proc").ok()?.flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else { continue };
        let Ok(cmd) = std::fs::read(e.path().join("cmdline")) else { continue };
        let args: Vec<String> = cmd.split(|b| *b == 0).map(|a| String::from_utf8_lossy(a).into_owned()).collect();
        let has = |k: &str, v: &str| args.windows(2).any(|w| w[0] == k && w[1] == v);
        if args.first().is_some_and(|a| a.ends_with("baker"))
            && has("--shard", spec)
            && dir.is_none_or(|d| has("--out", d.to_str().unwrap()))
        {
            return Some(pid);
        }
    }
    None
}

#[test]
fn a_killed_worker_takes_its_bake_along_and_the_merge_equals_the_single_bake() {
    let Some(py) = python() else { return };
    let root = std::env::temp_dir().join(format!("baker-dask-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let baker = env!("CARGO_BIN_EXE_baker");
    // 256 passes of the built-in scene at 16 texels per unit (7 337 texels, 64 probes):
    // long enough that a shard is still baking after its first checkpoint (16 passes).
    let recipe = ["--device", "cpu", "--passes", "256", "--texels-per-unit", "16", "--probes", "4,4,4", "--preview-width", "48"];
    let single = root.join("single");
    let t = Instant::now();
    let o = Command::new(baker).args(recipe).args(["--out", single.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "single bake: {}", String::from_utf8_lossy(&o.stderr));
    let single_seconds = t.elapsed().as_secs_f64();

    let (shards, merged) = (root.join("shards"), root.join("merged"));
    let driver = Path::new(env!("CARGO_MANIFEST_DIR")).join("distributed/dask_bake.py");
    let log = root.join("driver.log");
    let t = Instant::now();
    let mut child = Command::new(&py)
        .arg(&driver)
        .args(["--baker", baker, "--shards", "3", "--local-workers", "3", "--retries", "2"])
        .args(["--shard-dir", shards.to_str().unwrap(), "--out", merged.to_str().unwrap(), "--"])
        .args(recipe)
        .stdout(std::fs::File::create(&log).unwrap())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    // Kill the worker running shard 1 once the shard's first checkpoint is on disk.
    let ckpt: PathBuf = shards.join("lightmap.shard-1-of-3.checkpoint");
    let deadline = Instant::now() + Duration::from_secs(300);
    while !ckpt.exists() {
        assert!(Instant::now() < deadline, "shard 1 wrote no checkpoint in 300 s");
        assert!(child.try_wait().unwrap().is_none(), "the driver ended before shard 1's first checkpoint");
        std::thread::sleep(Duration::from_millis(10));
    }
    let pid = shard_pid("1/3", &shards).expect("shard 1's baker process finished before it could be killed: lengthen the bake");
    let worker = parent(pid).expect("the baker's parent");
    let k = Command::new("kill").args(["-9", &worker.to_string()]).status().unwrap();
    assert!(k.success(), "kill -9 {worker}");
    // Its bake ends with it (the watcher polls its parent): no orphan baking the shard.
    let t_kill = Instant::now();
    while alive(pid) && t_kill.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(!alive(pid), "shard 1's baker (pid {pid}) outlived its killed worker (pid {worker}) by 5 s");
    println!("the killed worker's bake ended {:.2} s after the worker", t_kill.elapsed().as_secs_f64());
    let status = child.wait().unwrap();
    let cluster_seconds = t.elapsed().as_secs_f64();
    let text = std::fs::read_to_string(&log).unwrap();
    println!("{text}");
    assert!(status.success(), "the driver failed: {text}");
    // No bake of this run is left behind.
    let left: Vec<u32> = (0..3).filter_map(|i| shard_pid(&format!("{i}/3"), &shards)).collect();
    assert!(left.is_empty(), "bakes left running after the driver finished: {left:?}");
    let attempts = std::fs::read_to_string(shards.join("shard-1-of-3.attempts")).unwrap();
    assert_eq!(attempts.lines().count(), 2, "shard 1 should have run twice (killed, retried): {attempts}");
    assert!(
        text.contains("shard 1/3: done") && text.contains("after 1 retry, resumed at pass "),
        "the driver's log should report the retry, resumed from the checkpoint: {text}"
    );
    let (want, got) = (hashes(&single), hashes(&merged));
    let checkpointless: Vec<_> = want.iter().filter(|(f, _)| !f.ends_with(".checkpoint")).collect();
    assert!(checkpointless.iter().any(|(f, _)| f.ends_with(".exr")), "{want:?}");
    assert_eq!(got, want, "the merged outputs differ from the single bake");
    println!(
        "single process: {single_seconds:.1} s; local Dask cluster of 3 workers (3 shards, one killed and retried): {cluster_seconds:.1} s"
    );
    let _ = std::fs::remove_dir_all(&root);
}

/// SIGTERM to the driver mid-bake: it sets the cancel event its tasks poll, every running
/// `baker` is terminated, the cluster closes and nothing is merged — within 10 s no shard
/// process is left. (Without the event, Dask cannot stop a task's subprocess: the bakes
/// ran on to their last pass.)
#[test]
fn sigterm_to_the_driver_leaves_no_bake_running() {
    let Some(py) = python() else { return };
    let root = std::env::temp_dir().join(format!("baker-dask-term-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let baker = env!("CARGO_BIN_EXE_baker");
    // Minutes of work per shard: still baking when the signal comes.
    let recipe = ["--device", "cpu", "--passes", "100000", "--texels-per-unit", "8", "--probes", "0,0,0", "--preview-width", "16"];
    let (shards, merged) = (root.join("shards"), root.join("merged"));
    let driver = Path::new(env!("CARGO_MANIFEST_DIR")).join("distributed/dask_bake.py");
    let mut child = Command::new(&py)
        .arg(&driver)
        .args(["--baker", baker, "--shards", "3", "--local-workers", "3", "--retries", "2", "--threads", "1"])
        .args(["--shard-dir", shards.to_str().unwrap(), "--out", merged.to_str().unwrap(), "--"])
        .args(recipe)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let running = || (0..3).filter_map(|i| shard_pid(&format!("{i}/3"), &shards)).collect::<Vec<u32>>();
    let deadline = Instant::now() + Duration::from_secs(120);
    while running().len() < 3 {
        assert!(Instant::now() < deadline, "three shards did not start in 120 s");
        assert!(child.try_wait().unwrap().is_none(), "the driver ended before its shards started");
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_millis(500));
    let k = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
    assert!(k.success());
    let t = Instant::now();
    while !running().is_empty() && t.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(100));
    }
    let (left, gone) = (running(), t.elapsed().as_secs_f64());
    for pid in &left {
        let _ = Command::new("kill").args(["-9", &pid.to_string()]).status();
    }
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(t.elapsed() < Duration::from_secs(60), "the driver did not exit within 60 s of SIGTERM");
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    println!("bakes gone {gone:.1} s after SIGTERM; driver exited {status:?} after {:.1} s; {err}", t.elapsed().as_secs_f64());
    assert!(left.is_empty(), "bakes still running 10 s after SIGTERM to the driver: {left:?}");
    assert_eq!(status.code(), Some(128 + 15), "the driver's status after SIGTERM: {err}");
    assert!(!merged.exists(), "a cancelled run merged into {}", merged.display());
    let _ = std::fs::remove_dir_all(&root);
}

/// No shared filesystem: the shards go through an fsspec store (`--shard-dir memory://…`,
/// the workers as threads of the driver's process so that they share it) and the merged bake
/// to a `file://` URL. Each task bakes in its own scratch folder, uploads each checkpoint as
/// it appears and the shard file at the end; shard 1's `baker` is killed after its first
/// checkpoint is in the store, and the retry — a fresh scratch folder — downloads it and
/// resumes there. The merge (shards fetched to a local folder, the output uploaded) equals
/// the single bake byte for byte, and nothing is written under the shard store's name on
/// the local disk.
#[test]
fn shards_through_an_fsspec_store_merge_to_the_single_bake() {
    let Some(py) = python() else { return };
    let root = std::env::temp_dir().join(format!("baker-dask-fsspec-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let baker = env!("CARGO_BIN_EXE_baker");
    // Long enough (≈ 3 s a shard on one thread) that shard 1 still bakes when its first
    // checkpoint has reached the store (the driver reports it within 0.05 s; the kill follows).
    let recipe = ["--device", "cpu", "--passes", "128", "--texels-per-unit", "12", "--probes", "3,3,3", "--preview-width", "32"];
    let single = root.join("single");
    let o = Command::new(baker).args(recipe).args(["--out", single.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "single bake: {}", String::from_utf8_lossy(&o.stderr));
    let merged = root.join("merged");
    let store = format!("memory://sbf-test-{}/shards", std::process::id());
    let driver = Path::new(env!("CARGO_MANIFEST_DIR")).join("distributed/dask_bake.py");
    let log = root.join("driver.log");
    let mut child = Command::new(&py)
        .arg(&driver)
        .args(["--baker", baker, "--shards", "2", "--local-workers", "2", "--local-in-process", "--retries", "2", "--threads", "1"])
        .args(["--checkpoint-every", "8", "--shard-dir", &store, "--out", &format!("file://{}", merged.display()), "--"])
        .args(recipe)
        .current_dir(&root)
        .stdout(std::fs::File::create(&log).unwrap())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    // The driver reads the store: its log says when shard 1's first checkpoint is there.
    let deadline = Instant::now() + Duration::from_secs(300);
    while !std::fs::read_to_string(&log)
        .unwrap_or_default()
        .lines()
        .any(|l| l.starts_with("shard 1/2: ") && l.ends_with("lightmap passes checkpointed"))
    {
        assert!(Instant::now() < deadline, "shard 1's first checkpoint did not reach the store in 300 s");
        assert!(child.try_wait().unwrap().is_none(), "the driver ended early: {}", std::fs::read_to_string(&log).unwrap());
        std::thread::sleep(Duration::from_millis(10));
    }
    let pid = (0..200)
        .find_map(|_| {
            let p = running_shard("1/2");
            if p.is_none() {
                std::thread::sleep(Duration::from_millis(5));
            }
            p
        })
        .expect("shard 1's baker finished before it could be killed: lengthen the bake");
    assert!(Command::new("kill").args(["-9", &pid.to_string()]).status().unwrap().success());
    let status = child.wait().unwrap();
    let text = std::fs::read_to_string(&log).unwrap();
    println!("{text}");
    assert!(status.success(), "the driver failed: {text}");
    assert!(text.contains("shard 1/2: done") && text.contains("after 1 retry, resumed at pass "), "{text}");
    assert_eq!(hashes(&merged), hashes(&single), "the merged outputs differ from the single bake");
    assert!(!root.join("memory:").exists() && !Path::new(&store).exists(), "the memory store was written to the local disk");
    let _ = std::fs::remove_dir_all(&root);
}

/// The pid of a running `baker --shard SPEC` (any output folder).
fn running_shard(spec: &str) -> Option<u32> {
    shard_pid_in(spec, None).filter(|p| alive(*p))
}
