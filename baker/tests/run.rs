//! The `baker` command end to end: kill and resume, glTF import, bad scenes, leave-out.

use baker::accumulate::{BakeConfig, BasisId, Solver};
use baker::output::runtime_features;
use baker::scene::import;
use baker::scene::SceneError;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("baker-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn baker(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_baker"));
    c.args(args);
    c
}

/// The device for the calling test alone, or None (printed) without one — unless
/// `SBF_REQUIRE_GPU=1`, where that fails the test. Held while the test's `baker` runs on
/// the GPU: GPU tests run one at a time (`shaders::gpu::lease`), so no two bakes of this
/// binary share the device.
fn have_gpu() -> Option<shaders::gpu::Lease> {
    common::gpu()
}

/// A GPU bake of the built-in scene at 6 texels per unit into `dir`, with `extra`
/// arguments and `env` variables; must succeed; returns its log.
fn gpu_bake(dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> String {
    let mut args = vec!["--device", "gpu", "--texels-per-unit", "6", "--preview-width", "32", "--out", dir.to_str().unwrap()];
    args.extend(extra);
    let o = baker(&args).envs(env.iter().copied()).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// Passes recorded in a checkpoint header (bytes 16..24, after magic and fingerprint).
fn checkpoint_passes(p: &Path) -> Option<u64> {
    let b = std::fs::read(p).ok()?;
    Some(u64::from_le_bytes(b.get(16..24)?.try_into().ok()?))
}

/// A bake killed (SIGKILL) mid-run and resumed from its checkpoint writes exactly the
/// same lightmap and probe files as an uninterrupted bake.
#[test]
fn killed_bake_resumes_to_the_identical_result() {
    let (a, b) = (tmp("uninterrupted"), tmp("killed"));
    let common = [
        "--device",
        "cpu",
        "--texels-per-unit",
        "6",
        "--passes",
        "300",
        "--checkpoint-every",
        "5",
        "--probes",
        "2,2,2",
        "--preview-width",
        "32",
    ];
    let run = |dir: &Path, extra: &[&str]| {
        let mut args: Vec<&str> = common.to_vec();
        args.extend(["--out", dir.to_str().unwrap()]);
        args.extend(extra);
        baker(&args).output().unwrap()
    };
    let out = run(&a, &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Kill the second bake as soon as it has written a checkpoint (mid-run: 300 passes).
    let mut args: Vec<&str> = common.to_vec();
    args.extend(["--out", b.to_str().unwrap()]);
    let mut child = baker(&args).stderr(std::process::Stdio::null()).spawn().unwrap();
    let ck = b.join("lightmap.checkpoint");
    let t = std::time::Instant::now();
    while !ck.exists() && t.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let at = checkpoint_passes(&ck).expect("a checkpoint was written before the kill");
    assert!(at > 0 && at < 300, "killed at pass {at}: not mid-run");
    assert!(!b.join("irradiance.exr").exists(), "the killed bake must not have finished");
    let out = run(&b, &["--resume"]);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    assert!(log.contains(&format!("resuming from {} at pass {at}", ck.display())), "{log}");
    let mut files = vec!["irradiance.exr".to_string(), "irradiance_se.exr".into(), "probes.json".into(), "preview.png".into()];
    files.extend((0..9).map(|l| format!("sh2_{l:02}.exr")));
    files.extend((0..9).map(|l| format!("ad9_{l:02}.exr")));
    for f in &files {
        let (x, y) = (std::fs::read(a.join(f)).unwrap(), std::fs::read(b.join(f)).unwrap());
        assert!(x == y, "{f} differs after kill + resume (killed at pass {at})");
    }
    println!("killed at pass {at} of 300, resumed: {} files identical", files.len());
}

/// A checkpoint of another bake is refused with a message, not silently mixed in.
#[test]
fn resume_refuses_a_different_bake() {
    let d = tmp("mismatch");
    let base = [
        "--device",
        "cpu",
        "--texels-per-unit",
        "4",
        "--passes",
        "4",
        "--checkpoint-every",
        "2",
        "--probes",
        "0,0,0",
        "--preview-width",
        "16",
    ];
    let mut a: Vec<&str> = base.to_vec();
    a.extend(["--out", d.to_str().unwrap()]);
    assert!(baker(&a).output().unwrap().status.success());
    a.extend(["--resume", "--seed", "7"]);
    let out = baker(&a).output().unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && log.contains("belong to a different bake") && log.contains("config.seed: 1 vs 7"), "{log}");
}

/// A checkpoint with one byte flipped, or cut short, is refused on resume with a message (its
/// trailing FNV-1a hash, checked before anything is read), never resumed: the flipped byte
/// sits in the encoder state, which the other checks (magic, fingerprint, sizes) do not see.
#[test]
fn resume_refuses_a_corrupt_checkpoint() {
    let d = tmp("corrupt");
    let mut a: Vec<&str> = vec!["--device", "cpu", "--texels-per-unit", "4", "--passes", "4", "--checkpoint-every", "2"];
    a.extend(["--probes", "0,0,0", "--preview-width", "16", "--out", d.to_str().unwrap()]);
    assert!(baker(&a).output().unwrap().status.success());
    let ck = d.join("lightmap.checkpoint");
    let good = std::fs::read(&ck).unwrap();
    a.push("--resume");
    for (what, bytes) in [
        ("one byte flipped", {
            let mut b = good.clone();
            let k = b.len() * 2 / 3;
            b[k] ^= 0x10;
            b
        }),
        ("cut short", good[..good.len() - 100].to_vec()),
    ] {
        std::fs::write(&ck, &bytes).unwrap();
        let out = baker(&a).output().unwrap();
        let log = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && log.contains("checksum mismatch"), "{what}: {log}");
    }
    // The intact checkpoint still resumes.
    std::fs::write(&ck, &good).unwrap();
    let out = baker(&a).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A folder reused for a shorter bake: its checkpoint is past the new --passes, and resuming
/// would write the longer bake under the shorter one's settings (a shard's header would say
/// 2 passes over a 4-pass state). Refused with a message naming both counts.
#[test]
fn resume_refuses_a_checkpoint_past_the_requested_passes() {
    let d = tmp("longer");
    let mut a: Vec<&str> = vec!["--device", "cpu", "--texels-per-unit", "4", "--passes", "4", "--checkpoint-every", "2"];
    a.extend(["--probes", "0,0,0", "--preview-width", "16", "--out", d.to_str().unwrap()]);
    assert!(baker(&a).output().unwrap().status.success());
    let bake_json = std::fs::read(d.join("bake.json")).unwrap();
    a[5] = "2";
    a.push("--resume");
    let out = baker(&a).output().unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && log.contains("at passes 4, past this bake's 2"), "{log}");
    assert!(std::fs::read(d.join("bake.json")).unwrap() == bake_json, "the refused bake rewrote bake.json");
}

/// `--exit-with-parent`: a bake whose parent is killed (SIGKILL: no chance to clean up, as
/// when a farm's worker dies) ends within a few seconds instead of baking on as an orphan.
/// The parent is `sh`, which starts the bake in the background and prints its pid; the bake
/// alone would run for minutes (10⁶ passes).
#[cfg(target_os = "linux")]
#[test]
fn a_bake_exits_with_its_killed_parent() {
    let d = tmp("orphan");
    let script = format!(
        "'{}' --device cpu --texels-per-unit 4 --passes 1000000 --probes 0,0,0 --checkpoint-every 0 --out '{}' --exit-with-parent & echo $!; wait",
        env!("CARGO_BIN_EXE_baker"),
        d.display()
    );
    let mut sh = std::process::Command::new("sh")
        .args(["-c", &script])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufRead::read_line(&mut std::io::BufReader::new(sh.stdout.take().unwrap()), &mut line).unwrap();
    let pid: u32 = line.trim().parse().unwrap();
    // Alive (not a zombie) while its parent lives.
    let alive = |pid: u32| {
        std::fs::read_to_string(format!("/proc/{pid}/stat"))
            .is_ok_and(|s| s.rsplit(')').next().is_some_and(|r| !r.trim_start().starts_with('Z')))
    };
    std::thread::sleep(std::time::Duration::from_millis(1500));
    assert!(alive(pid), "the bake {pid} should still run while its parent does");
    sh.kill().unwrap();
    sh.wait().unwrap();
    let t = std::time::Instant::now();
    while alive(pid) && t.elapsed().as_secs() < 10 {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let left = alive(pid);
    if left {
        let _ = std::process::Command::new("kill").args(["-9", &pid.to_string()]).status();
    }
    assert!(!left, "the bake {pid} outlived its killed parent by 10 s");
    println!("the orphaned bake ended {:.1} s after its parent", t.elapsed().as_secs_f64());
}

/// Two writers of one file — a retried shard beside an orphaned one — each through its own
/// temporary name: 4 threads × 50 atomic writes of one path all succeed and leave one whole
/// payload and no temporary file (a fixed temporary name fails here: one writer renames the
/// other's file away).
#[test]
fn concurrent_atomic_writes_do_not_collide() {
    let d = tmp("atomic");
    std::fs::create_dir_all(&d).unwrap();
    let path = d.join("x.checkpoint");
    std::thread::scope(|s| {
        for t in 0..4u8 {
            let path = path.clone();
            s.spawn(move || {
                for _ in 0..50 {
                    baker::checkpoint::write_atomic(&path, &vec![t; 4096]).unwrap();
                }
            });
        }
    });
    let b = std::fs::read(&path).unwrap();
    assert!(b.len() == 4096 && b.iter().all(|x| *x == b[0]), "a torn or mixed file");
    let left: Vec<_> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).filter(|n| n != "x.checkpoint").collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// The checkpoint identity is the content, not the path: an edited scene with the same
/// texel count, and a probe grid of the same size (2,2,2 → 1,1,8), are refused.
#[test]
fn resume_refuses_edited_scenes_and_other_probe_grids() {
    let d = tmp("content");
    let path = d.join("room.gltf");
    room(UNIT_UV, -1.0).write(&path);
    let out = d.join("out");
    let args = |probes: &'static str| {
        vec![
            "--scene".to_string(),
            path.to_str().unwrap().to_string(),
            "--device".into(),
            "cpu".into(),
            "--passes".into(),
            "4".into(),
            "--checkpoint-every".into(),
            "2".into(),
            "--texels-per-unit".into(),
            "4".into(),
            "--probes".into(),
            probes.into(),
            "--preview-width".into(),
            "16".into(),
            "--out".into(),
            out.to_str().unwrap().to_string(),
        ]
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(|s| s.as_str()).collect();
        baker(&a).output().unwrap()
    };
    assert!(run(args("2,2,2")).status.success());
    // Same file, same texel count, one material colour changed.
    let text = std::fs::read_to_string(&path).unwrap().replace("[0.7,0.7,0.7,1]", "[0.6,0.7,0.7,1]");
    std::fs::write(&path, text).unwrap();
    let mut a = args("2,2,2");
    a.push("--resume".into());
    let o = run(a);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && log.contains("belongs to a different bake"), "edited scene resumed: {log}");
    // Fresh bake of the edited scene, then the same probe count on another grid.
    assert!(run(args("2,2,2")).status.success());
    let mut a = args("1,1,8");
    a.push("--resume".into());
    let o = run(a);
    let log = String::from_utf8_lossy(&o.stderr);
    // (Refused by the recorded spec, which names the field, before any checkpoint is read.)
    assert!(
        !o.status.success() && log.contains("probes: [2,2,2] vs [1,1,8]") && log.contains("different bake"),
        "other grid resumed: {log}"
    );
    // Without the spec (a folder from another tool), the checkpoint's content fingerprint
    // (the probe positions) refuses it.
    std::fs::remove_file(out.join(baker::run::SPEC_FILE)).unwrap();
    let mut a = args("1,1,8");
    a.push("--resume".into());
    let o = run(a);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && log.contains("probes.checkpoint") && log.contains("different bake"), "other grid resumed: {log}");
}

/// Resume on the GPU path: 24 passes, then --resume to 48, writes the same files as 48
/// uninterrupted passes (the state round-trips exactly through the checkpoint).
#[test]
fn gpu_bake_resumes_to_the_identical_result() {
    let Some(_gpu) = have_gpu() else { return };
    let (a, b) = (tmp("gpu-straight"), tmp("gpu-resumed"));
    let run = |dir: &Path, passes: &str, extra: &[&str]| {
        gpu_bake(dir, &[&["--passes", passes, "--checkpoint-every", "8", "--probes", "2,2,2"][..], extra].concat(), &[])
    };
    let mut files = vec!["irradiance.exr".to_string(), "irradiance_se.exr".into(), "probes.json".into()];
    files.extend((0..9).map(|l| format!("sh2_{l:02}.exr")));
    files.extend((0..9).map(|l| format!("ad9_{l:02}.exr")));
    // Plain, then with filtered accumulation (its records, targets and gather state go
    // through the checkpoint too).
    for filter in [&[][..], &["--filter", "mitchell"][..]] {
        run(&a, "48", filter);
        run(&b, "24", filter);
        let log = run(&b, "48", &[filter, &["--resume"]].concat());
        assert!(log.contains("resuming from") && log.contains("at pass 24"), "{log}");
        for f in &files {
            let (x, y) = (std::fs::read(a.join(f)).unwrap(), std::fs::read(b.join(f)).unwrap());
            assert!(x == y, "{f} differs after a GPU resume ({filter:?})");
        }
    }
}

/// Minimal glTF writer for tests: one buffer as a base64 data URI.
struct Gltf {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
    meshes: Vec<String>,
}

fn b64(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            s.push(if k <= c.len() { T[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    s
}

impl Gltf {
    fn new() -> Self {
        Gltf { bin: vec![], views: vec![], accessors: vec![], meshes: vec![] }
    }
    fn accessor(&mut self, data: &[f32], ty: &str, n: usize) -> usize {
        let off = self.bin.len();
        for v in data {
            self.bin.extend_from_slice(&v.to_le_bytes());
        }
        self.views.push(format!(r#"{{"buffer":0,"byteOffset":{off},"byteLength":{}}}"#, data.len() * 4));
        // glTF requires min/max on POSITION; from the finite values (a NaN stays in the buffer).
        let k = data.len() / n;
        let (lo, hi): (Vec<String>, Vec<String>) = (0..k)
            .map(|c| {
                let v = data.iter().skip(c).step_by(k).filter(|x| x.is_finite());
                (format!("{:?}", v.clone().fold(f32::MAX, |a, b| a.min(*b))), format!("{:?}", v.fold(f32::MIN, |a, b| a.max(*b))))
            })
            .unzip();
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5126,"count":{n},"type":"{ty}","min":[{}],"max":[{}]}}"#,
            self.views.len() - 1,
            lo.join(","),
            hi.join(",")
        ));
        self.accessors.len() - 1
    }
    fn indices(&mut self, idx: &[u32]) -> usize {
        let off = self.bin.len();
        for v in idx {
            self.bin.extend_from_slice(&v.to_le_bytes());
        }
        self.views.push(format!(r#"{{"buffer":0,"byteOffset":{off},"byteLength":{}}}"#, idx.len() * 4));
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5125,"count":{},"type":"SCALAR"}}"#,
            self.views.len() - 1,
            idx.len()
        ));
        self.accessors.len() - 1
    }
    /// A mesh from positions, indices, optional TEXCOORD_1, material index.
    fn mesh(&mut self, pos: &[[f32; 3]], idx: &[u32], uv1: Option<&[[f32; 2]]>, material: usize, mode: u32) {
        let p: Vec<f32> = pos.iter().flatten().copied().collect();
        let pa = self.accessor(&p, "VEC3", pos.len());
        let ia = self.indices(idx);
        let uv = uv1.map(|u| {
            let f: Vec<f32> = u.iter().flatten().copied().collect();
            format!(r#","TEXCOORD_1":{}"#, self.accessor(&f, "VEC2", u.len()))
        });
        self.meshes.push(format!(
            r#"{{"name":"m{}","primitives":[{{"attributes":{{"POSITION":{pa}{}}},"indices":{ia},"material":{material},"mode":{mode}}}]}}"#,
            self.meshes.len(),
            uv.unwrap_or_default()
        ));
    }
    fn write(&self, path: &Path) {
        let nodes: Vec<String> = (0..self.meshes.len()).map(|k| format!(r#"{{"mesh":{k}}}"#)).collect();
        let node_ids: Vec<String> = (0..self.meshes.len()).map(|k| k.to_string()).collect();
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{}],
"materials":[{{"pbrMetallicRoughness":{{"baseColorFactor":[0.7,0.7,0.7,1],"metallicFactor":0,"roughnessFactor":1}}}},
{{"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1]}},"emissiveFactor":[1,1,1]}}],
"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]}}"#,
            node_ids.join(","),
            nodes.join(","),
            self.meshes.join(","),
            self.accessors.join(","),
            self.views.join(","),
            self.bin.len(),
            b64(&self.bin)
        );
        std::fs::write(path, json).unwrap();
    }
}

/// A floor quad with TEXCOORD_1, a wall without (charts generated), an emissive quad.
fn room(uv: [[f32; 2]; 4], floor_y: f32) -> Gltf {
    let mut g = Gltf::new();
    let q = [0, 1, 2, 0, 2, 3];
    g.mesh(&[[-1.0, floor_y, 1.0], [1.0, -1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, -1.0, -1.0]], &q, Some(&uv), 0, 4);
    g.mesh(&[[-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [-1.0, 1.0, -1.0]], &q, None, 0, 4);
    g.mesh(&[[-0.3, 0.9, -0.3], [0.3, 0.9, -0.3], [0.3, 0.9, 0.3], [-0.3, 0.9, 0.3]], &q, None, 1, 4);
    g
}

const UNIT_UV: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

/// A glTF scene imports (TEXCOORD_1 used as a scaled chart, charts generated for the
/// rest and said so), bakes, and the metadata carries the mesh's scale/bias.
#[test]
fn gltf_scene_imports_and_bakes() {
    let d = tmp("gltf");
    let path = d.join("room.gltf");
    room(UNIT_UV, -1.0).write(&path);
    let (scene, report) = import::load(&path).unwrap();
    assert_eq!(scene.meshes.len(), 3);
    assert!(scene.meshes[0].lightmap_uv.is_some() && !scene.meshes[2].lightmapped);
    assert!(report.notes.iter().any(|n| n.contains("no TEXCOORD_1")), "{:?}", report.notes);
    let out = d.join("out");
    let o = baker(&[
        "--scene",
        path.to_str().unwrap(),
        "--device",
        "cpu",
        "--passes",
        "8",
        "--texels-per-unit",
        "8",
        "--probes",
        "0,0,0",
        "--out",
        out.to_str().unwrap(),
    ])
    .output()
    .unwrap();
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{log}");
    assert!(log.contains("charts generated for"), "{log}");
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("bake.json")).unwrap()).unwrap();
    let m0 = &meta["meshes"][0];
    assert_eq!(m0["uv"], "TEXCOORD_1");
    // The 2 m × 2 m floor at 8 texels/unit: a 16-texel square chart; its scale is 16/W.
    let w = meta["layout"]["width"].as_f64().unwrap();
    // (f32 in the JSON: rounding 6e-8 relative.)
    assert!((m0["scale"][0].as_f64().unwrap() - 16.0 / w).abs() < 1e-6, "{m0}");
    assert_eq!(meta["meshes"][1]["uv"], "generated");
    // No glossy material (roughness 1 dielectric is glossy in glTF: F0 = 0.04), so the
    // runtime keeps specular; the report says which LUTs travel.
    assert!(meta["runtime"]["features"].as_array().unwrap().iter().any(|f| f == "ad9-irradiance"));
}

/// Bad scenes give errors that name the problem; degenerate triangles are skipped and
/// counted; nothing panics.
#[test]
fn bad_gltf_scenes_give_clear_errors() {
    let d = tmp("bad");
    // Missing file.
    match import::load(&d.join("missing.glb")) {
        Err(SceneError::Io(m)) => assert!(m.contains("missing.glb"), "{m}"),
        other => panic!("{other:?}"),
    }
    // A special file as the scene (read would never end).
    #[cfg(unix)]
    assert!(matches!(import::load(Path::new("/dev/zero")), Err(SceneError::Io(m)) if m.contains("not a regular file")));
    // Not glTF.
    std::fs::write(d.join("junk.gltf"), b"{not json").unwrap();
    assert!(matches!(import::load(&d.join("junk.gltf")), Err(SceneError::Io(m)) if m.contains("not a valid glTF")));
    // No triangles: a points primitive only.
    let mut g = Gltf::new();
    g.mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[0, 1, 2], None, 0, 0);
    g.write(&d.join("points.gltf"));
    assert_eq!(import::load(&d.join("points.gltf")).unwrap_err(), SceneError::Empty);
    // NaN vertex.
    room(UNIT_UV, f32::NAN).write(&d.join("nan.gltf"));
    assert!(matches!(import::load(&d.join("nan.gltf")), Err(SceneError::NonFinite { what: "positions", .. })));
    // Lightmap UV outside [0, 1].
    room([[0.0, 0.0], [1.5, 0.0], [1.0, 1.0], [0.0, 1.0]], -1.0).write(&d.join("uv.gltf"));
    assert!(matches!(import::load(&d.join("uv.gltf")), Err(SceneError::UvOutOfRange { u, .. }) if u == 1.5));
    // Degenerate triangles: skipped and reported.
    let mut g = room(UNIT_UV, -1.0);
    g.mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], &[0, 1, 2], None, 0, 4);
    g.write(&d.join("degenerate.gltf"));
    let (_, report) = import::load(&d.join("degenerate.gltf")).unwrap();
    assert!(report.notes.iter().any(|n| n.contains("1 degenerate")), "{:?}", report.notes);
    // Corrupt accessors, index types, node graphs, light values and buffers (the
    // mutation campaign's findings): each a clear error naming the problem, no panic.
    let base: serde_json::Value = {
        room(UNIT_UV, -1.0).write(&d.join("base.gltf"));
        serde_json::from_str(&std::fs::read_to_string(d.join("base.gltf")).unwrap()).unwrap()
    };
    let case = |name: &str, edit: &dyn Fn(&mut serde_json::Value), expect: &str| {
        let mut v = base.clone();
        edit(&mut v);
        let p = d.join(format!("{name}.gltf"));
        std::fs::write(&p, serde_json::to_string(&v).unwrap()).unwrap();
        let r = std::panic::catch_unwind(|| import::load(&p));
        let msg = match r {
            Ok(Err(e)) => e.to_string(),
            Ok(Ok(_)) => panic!("{name}: imported without an error"),
            Err(_) => panic!("{name}: the importer panicked"),
        };
        assert!(msg.contains(expect), "{name}: '{msg}' does not say '{expect}'");
        println!("{name}: {msg}");
    };
    case("index-past-buffer", &|v| v["accessors"][1]["count"] = 600.into(), "needs");
    case("truncated-position", &|v| v["accessors"][0]["count"] = 5.into(), "Position): count 5");
    case("truncated-uv", &|v| v["accessors"][2]["count"] = 5.into(), "LightmapUv): count 5");
    case("float-indices", &|v| v["accessors"][1]["componentType"] = 5126.into(), "not allowed");
    case("indices-are-positions", &|v| v["meshes"][0]["primitives"][0]["indices"] = 0.into(), "not allowed");
    case("self-child", &|v| v["nodes"][0]["children"] = serde_json::json!([0]), "reached twice");
    case(
        "mutual-children",
        &|v| {
            v["nodes"][0]["children"] = serde_json::json!([1]);
            v["nodes"][1]["children"] = serde_json::json!([0]);
        },
        "reached twice",
    );
    let with_light = |v: &mut serde_json::Value, intensity: f64| {
        v["extensionsUsed"] = serde_json::json!(["KHR_lights_punctual"]);
        v["extensions"] = serde_json::json!({"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": intensity}]}});
        v["nodes"][0]["extensions"] = serde_json::json!({"KHR_lights_punctual": {"light": 0}});
    };
    case("light-1e38", &|v| with_light(v, 1e38), "intensity in [0, 1e18]");
    case(
        "emissive-strength-1e38",
        &|v| {
            v["extensionsUsed"] = serde_json::json!(["KHR_materials_emissive_strength"]);
            v["materials"][1]["extensions"] = serde_json::json!({"KHR_materials_emissive_strength": {"emissiveStrength": 1e38}});
        },
        "emission above 1e18",
    );
    case(
        "emissive-strength-overflow",
        &|v| {
            v["extensionsUsed"] = serde_json::json!(["KHR_materials_emissive_strength"]);
            v["materials"][1]["emissiveFactor"] = serde_json::json!([1, 1, 1]);
            v["materials"][1]["extensions"] = serde_json::json!({"KHR_materials_emissive_strength": {"emissiveStrength": 3e38}});
            v["materials"][1]["emissiveFactor"] = serde_json::json!([10, 10, 10]);
        },
        "non-finite",
    );
    #[cfg(unix)]
    case("dev-zero-buffer", &|v| v["buffers"][0]["uri"] = "/dev/zero".into(), "not a regular file");
    case(
        "missing-buffer-bytes",
        &|v| {
            std::fs::write(d.join("short.bin"), [0u8; 16]).unwrap();
            v["buffers"][0]["uri"] = "short.bin".into();
        },
        "the asset declares",
    );
    // Spot cones and ranges are honoured (not reported as ignored).
    let mut v = base.clone();
    v["extensionsUsed"] = serde_json::json!(["KHR_lights_punctual"]);
    v["extensions"] = serde_json::json!({"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 5, "range": 3,
        "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}});
    v["nodes"][0]["extensions"] = serde_json::json!({"KHR_lights_punctual": {"light": 0}});
    std::fs::write(d.join("spot.gltf"), serde_json::to_string(&v).unwrap()).unwrap();
    let (sc, rep) = import::load(&d.join("spot.gltf")).unwrap();
    match sc.lights[0] {
        baker::scene::Light::Spot { cos_inner, cos_outer, range, direction, .. } => {
            assert!((cos_inner - 0.2f32.cos()).abs() < 1e-6 && (cos_outer - 0.5f32.cos()).abs() < 1e-6 && range == 3.0);
            assert!((direction - sbf::glam::Vec3::NEG_Z).length() < 1e-6, "spot shines along the node's −Z");
        }
        l => panic!("{l:?}"),
    }
    assert!(!rep.notes.iter().any(|n| n.contains("spot")), "{:?}", rep.notes);
    // The command reports the error and exits non-zero.
    let o = baker(&["--scene", d.join("nan.gltf").to_str().unwrap(), "--device", "cpu", "--out", d.join("o").to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("NaN"));
}

/// Leave-out: with no glossy material the runtime gets no specular features and no LUT.
#[test]
fn scenes_without_gloss_leave_specular_out() {
    let bases = [BasisId::Ad9, BasisId::Sg12, BasisId::Sh2];
    let (f, l) = runtime_features(&bases, &[], false);
    assert!(f.iter().all(|x| x.ends_with("irradiance")) && l.is_empty(), "{f:?} {l:?}");
    let (f, l) = runtime_features(&bases, &[sbf::profile::SpecularPath::Fit], false);
    assert!(
        f.contains(&"ad9-specular")
            && f.contains(&"sg-specular")
            && f.contains(&"sh-specular")
            && l == ["ad_specular_2d.sbflut", "dfg.sbflut"],
        "{f:?} {l:?}"
    );
    let (f, l) = runtime_features(&bases, &[sbf::profile::SpecularPath::Tables], false);
    assert!(
        f.contains(&"lobe-ggx-filtered")
            && !f.contains(&"ad9-specular")
            && l == ["dfg.sbflut", "lobe_ggx_ad.sbflut", "lobe_ggx_sg6.sbflut"],
        "{f:?} {l:?}"
    );
    let cfg = BakeConfig { max_bounces: 2, bases: bases.to_vec(), solver: Solver::Ls, ..Default::default() };
    let k = baker::gpu::kernel(&cfg, false, false).unwrap();
    assert!(!k.shader("megakernel.wgsl").unwrap().contains("fn ggx_d(") && k.left_out[0].starts_with("GGX layer"));
    let d = tmp("furnace");
    let o = baker(&[
        "--scene",
        "furnace",
        "--device",
        "cpu",
        "--passes",
        "2",
        "--texels-per-unit",
        "2",
        "--probes",
        "0,0,0",
        "--out",
        d.to_str().unwrap(),
    ])
    .output()
    .unwrap();
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && log.contains("leave-out: no glossy material"), "{log}");
    assert!(!d.join("ad_specular_2d.sbflut").exists());
}

/// The real glTF scenes in ../shared/scenes (lightmap UVs authored outside this project:
/// Bevy's Cornell box in millimetres, the mixed-lighting room with a 40 k-triangle chair)
/// import and bake; every mesh keeps its TEXCOORD_1 block and the blocks do not overlap.
/// Skipped when the folder is absent unless SBF_REQUIRE_PROBES=1.
#[test]
fn shared_gltf_scenes_import_and_bake() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes");
    if !root.exists() {
        assert!(std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"), "SBF_REQUIRE_PROBES=1 but {} is missing", root.display());
        println!("skipped: {} is absent", root.display());
        return;
    }
    for (file, tpu) in [("bevy_CornellBox/CornellBox.glb", "0.05"), ("bevy_MixedLightingExample/MixedLightingExample.gltf", "8")] {
        let out = tmp(&format!("shared-{}", file.len()));
        let o = baker(&[
            "--scene",
            root.join(file).to_str().unwrap(),
            "--device",
            "cpu",
            "--passes",
            "4",
            "--texels-per-unit",
            tpu,
            "--probes",
            "2,2,2",
            "--preview-width",
            "32",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
        let log = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{file}: {log}");
        let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("bake.json")).unwrap()).unwrap();
        let valid = meta["layout"]["valid_texels"].as_u64().unwrap();
        let uv1 = meta["meshes"].as_array().unwrap().iter().filter(|m| m["uv"] == "TEXCOORD_1").count();
        println!("{file}: {valid} valid texels, {uv1} meshes on their TEXCOORD_1, utilisation {}", meta["layout"]["utilisation"]);
        assert!(valid > 100 && uv1 >= 2, "{file}: {valid} texels, {uv1} TEXCOORD_1 meshes");
    }
}

/// The `slc` command end to end on the built-in scene (CPU): it writes
/// the image, the VPLs-per-pixel image and slc.json, and the culled image's mean is
/// close to the brute-force one (one ξ draw: within 5% — the unbiasedness itself is
/// tested over many draws in tests/slc.rs).
#[test]
fn slc_command_writes_its_outputs() {
    let d = tmp("slc");
    let slc = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_slc")).args(args).output().unwrap();
    let o = slc(&["--vpls", "512", "--size", "64x36", "--brute", "--device", "cpu", "--out", d.to_str().unwrap()]);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{log}");
    for f in ["slc.exr", "slc_vpls_per_pixel.exr", "slc_brute.exr", "slc.json"] {
        assert!(d.join(f).exists(), "{f} missing: {log}");
    }
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(d.join("slc.json")).unwrap()).unwrap();
    let (c, b) = (meta["brute_force"]["culled_mean"].as_f64().unwrap(), meta["brute_force"]["mean"].as_f64().unwrap());
    println!("{meta}");
    assert!(meta["vpls"].as_u64().unwrap() > 100 && (c - b).abs() <= 0.05 * b, "culled {c} vs brute {b}");
    let bad = slc(&["--vpls", "0", "--out", d.to_str().unwrap()]);
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("--vpls must be at least 1"));
    // The slit room is lit by its sky only: no VPL, an error that says why (it used to
    // write an empty image and exit 0).
    let none = slc(&["--scene", "slit", "--vpls", "64", "--size", "32x18", "--device", "cpu", "--out", d.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&none.stderr);
    assert!(!none.status.success() && err.contains("yields no VPLs") && err.contains("environment"), "{err}");
    // VPLs from reflective shadow maps: the built-in scene's light seen through a 16 × 16
    // map; with --sky (the environment has no shadow map) refused.
    let rd = tmp("slc-rsm");
    // With the culling comparison: per VPL set, clustered shading shades no more VPLs per
    // pixel than the tiles (it only drops false discoveries).
    let o = slc(&["--rsm", "16", "--size", "48x32", "--device", "cpu", "--compare-culling", "--out", rd.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(rd.join("slc.json")).unwrap()).unwrap();
    assert_eq!(meta["vpl_source"], "16×16 reflective shadow maps", "{meta}");
    assert!(meta["vpls"].as_u64().unwrap() > 0 && meta["light_paths"].is_null(), "{meta}");
    let rows = meta["culling_comparison"]["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4, "{meta}");
    for pair in rows.chunks(2) {
        assert_eq!(pair[0]["vpls"], pair[1]["vpls"]);
        assert!(pair[1]["vpls_per_pixel"].as_f64().unwrap() <= pair[0]["vpls_per_pixel"].as_f64().unwrap(), "{pair:?}");
        // … and drops some false discoveries (the rows are not the same scheme twice).
        assert!(pair[1]["false_discovery_rate"].as_f64().unwrap() < pair[0]["false_discovery_rate"].as_f64().unwrap(), "{pair:?}");
    }
    // The medium with 16 extra point lights: their count in slc.json, the FDR image written.
    let md = tmp("slc-medium");
    let o = slc(&[
        "--size",
        "32x18",
        "--vpls",
        "64",
        "--device",
        "cpu",
        "--medium",
        "0.2,0.3,0.5,4",
        "--point-lights",
        "16",
        "--out",
        md.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(md.join("slc.json")).unwrap()).unwrap();
    let diffuse = meta["vpls"].as_u64().unwrap() - meta["glossy_vpls"].as_u64().unwrap();
    assert_eq!(meta["medium"]["extra_point_lights"], 16);
    assert!(meta["medium"]["lights"].as_u64().unwrap() >= 16 + diffuse, "{meta}");
    assert!(md.join("slc_medium_fdr.png").exists() && md.join("slc_medium_fdr.exr").exists());
    let o = slc(&["--point-lights", "10", "--device", "cpu", "--out", rd.to_str().unwrap()]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--medium"));
    let o = slc(&["--rsm", "16", "--sky", "--device", "cpu", "--out", rd.to_str().unwrap()]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("no shadow map"));
    // The equal-time sweep: on the CPU every render is deterministic, so the spheroid at the
    // run's δ is the main image — its equal-time error is the main run's filtered error —
    // and every method reports a point per δ; a sweep without --delta is refused.
    let sw = tmp("slc-sweep");
    let o = slc(&["--vpls", "256", "--size", "48x32", "--device", "cpu", "--sweep", "3e-4,1e-3,3e-3", "--out", sw.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(sw.join("slc.json")).unwrap()).unwrap();
    assert_eq!(meta["sweep"]["points"].as_array().unwrap().len(), 9);
    let (at, own) = (
        meta["sweep"]["equal_time"]["relative_rmse_filtered"]["spheroid"].as_f64().unwrap(),
        meta["brute_force"]["error"]["filtered"]["relative_rmse"].as_f64().unwrap(),
    );
    assert!((at - own).abs() <= 1e-12 * own, "spheroid at δ {at} vs the main run's {own}");
    let spheroid = meta["sweep"]["points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["method"] == "spheroid" && p["delta"].as_f64() == Some(1e-3f32 as f64))
        .unwrap()
        .clone();
    let unfiltered = meta["brute_force"]["error"]["unfiltered"]["relative_rmse"].as_f64().unwrap();
    assert_eq!(spheroid["relative_rmse_unfiltered"].as_f64().unwrap(), unfiltered);
    // --filter-radius reaches the filter (slc.json states it, and the image changes).
    let r4 = tmp("slc-r4");
    let o = slc(&["--vpls", "256", "--size", "48x32", "--device", "cpu", "--brute", "--filter-radius", "4", "--out", r4.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m4: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(r4.join("slc.json")).unwrap()).unwrap();
    assert_eq!(m4["filter"]["radius"].as_u64(), Some(4));
    assert_ne!(m4["brute_force"]["error"]["filtered"]["relative_rmse"], meta["brute_force"]["error"]["filtered"]["relative_rmse"]);
    let bad = slc(&["--sweep", "1e-2", "--out", sw.to_str().unwrap()]);
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("include --delta"));
}

/// `--profile`: a Lambert-only profile on the glossy built-in scene bakes only its bases,
/// writes no specular runtime feature or LUT, exports the runtime in its language, records
/// the profile in bake.json and prints the profile and left-out lines; the AD9 + GGX profile
/// writes the AD specular runtime and its LUT.
#[test]
fn profile_leaves_out_what_it_does_not_need() {
    let profiles = Path::new(env!("CARGO_MANIFEST_DIR")).join("../profiles");
    let run = |name: &str| {
        let out = tmp(&format!("profile-{name}"));
        let o = baker(&["--device", "cpu", "--passes", "2", "--texels-per-unit", "4", "--probes", "2,2,2", "--profile"])
            .arg(profiles.join(format!("{name}.toml")))
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("bake.json")).unwrap()).unwrap();
        let files: Vec<String> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        (String::from_utf8_lossy(&o.stderr).into_owned() + &String::from_utf8_lossy(&o.stdout), json, files, out)
    };
    let (log, json, files, out) = run("mobile-sh-l1");
    assert!(log.contains("profile 'mobile diffuse SH L1': lightmap bases sh1"), "{log}");
    assert!(log.contains("no specular runtime features or LUTs"), "{log}");
    let features: Vec<&str> = json["runtime"]["features"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    assert_eq!(features, ["sh-l1-irradiance"]);
    assert!(json["runtime"]["specular"].as_str().unwrap().starts_with("left out"), "{}", json["runtime"]);
    assert_eq!(json["profile"]["name"], "mobile diffuse SH L1");
    assert!(files.iter().any(|f| f == "runtime.glsl"), "{files:?}");
    assert!(!files.iter().any(|f| f.ends_with(".sbflut") || f.starts_with("sh2") || f.starts_with("ad9")), "{files:?}");
    let wgsl = std::fs::read_to_string(out.join("runtime.wgsl")).unwrap();
    assert!(!wgsl.contains("specular"), "a Lambert-only runtime holds no specular code");
    let (_, json, files, _) = run("ad9-diffuse-specular");
    let features: Vec<&str> = json["runtime"]["features"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    // The lightmap's AD 9 and the probes' SH L2 (the profile's whole runtime).
    assert_eq!(features, ["ad9-irradiance", "ad9-specular", "sh-l2-irradiance", "sh-specular"]);
    assert!(
        files.iter().any(|f| f == "ad_specular_2d.sbflut")
            && files.iter().any(|f| f == "dfg.sbflut")
            && files.iter().any(|f| f == "ad9_08.exr"),
        "{files:?}"
    );
}

/// A profile with an unknown basis: the tool exits with 2 (as every tool does for a profile
/// it cannot use) and names the key with its line and column.
#[test]
fn bad_profile_exits_2_naming_key_line_and_column() {
    let p = std::env::temp_dir().join(format!("{}-bad-profile-{}.toml", env!("CARGO_PKG_NAME"), std::process::id()));
    std::fs::write(&p, "name = \"bad\"\n[lightmap]\nbases = [\"sh3\"]\n[brdf]\nmodels = [\"lambert\"]\n[runtime]\nprecision = \"f32\"\nlanguage = \"wgsl\"\n").unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_baker")).args(["--profile"]).arg(&p).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("line 3, column 9") && err.contains("lightmap.bases"), "{err}");
    std::fs::remove_file(&p).unwrap();
}

/// glTF cameras (glTF 2.0 §5.12: a camera node looks down its local −Z, +Y up): a yawed
/// camera, a rolled one under a translated parent and a pitched one under a stretched
/// parent (its up made perpendicular to the view) import with the eye, view and up
/// directions worked out here from the quaternions by hand; an orthographic camera is
/// skipped with a note; the view's rays follow them (centre ray = forward, the image's top
/// towards up, its right towards forward × up); `render --camera gltf:NAME` refuses an
/// unknown name before any work, listing the cameras. Mutations: the node's −Z taken as
/// +Z, the parent transform dropped, the up direction not made perpendicular — each fails.
#[test]
fn gltf_cameras_import_and_set_the_view() {
    use baker::scene::camera::ViewCamera;
    use sbf::glam::Vec3;
    let d = tmp("gltf_cameras");
    let path = d.join("room.gltf");
    room(UNIT_UV, -1.0).write(&path);
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    v["cameras"] = serde_json::json!([
        {"type": "perspective", "name": "yawed", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.01}},
        {"type": "perspective", "name": "rolled", "perspective": {"yfov": 0.6, "znear": 0.01}},
        {"type": "orthographic", "name": "flat", "orthographic": {"xmag": 1, "ymag": 1, "zfar": 10, "znear": 0.01}},
        {"type": "perspective", "name": "stretched", "perspective": {"yfov": 0.7, "znear": 0.01}}
    ]);
    let nodes = v["nodes"].as_array_mut().unwrap();
    let first = nodes.len();
    // Yaw +90° about Y: −Z ↦ −X. Roll +90° about Z: −Z stays, +Y ↦ −X; under a parent at (0, 1, 0).
    nodes.push(serde_json::json!({"camera": 0, "translation": [1, 2, 3], "rotation": [0, h, 0, h]}));
    nodes.push(serde_json::json!({"translation": [0, 1, 0], "children": [first + 2]}));
    nodes.push(serde_json::json!({"camera": 1, "translation": [0, 0, 5], "rotation": [0, 0, h, h]}));
    nodes.push(serde_json::json!({"camera": 2}));
    // Pitched 45° down (about X) under a parent stretched ×2 along y: the node's −Z and +Y
    // become (0, −2, −1)/√5·… and (0, 2, −1)/√5·…, no longer perpendicular.
    let s = (std::f64::consts::PI / 8.0).sin();
    let c = (std::f64::consts::PI / 8.0).cos();
    nodes.push(serde_json::json!({"scale": [1, 2, 1], "children": [first + 5]}));
    nodes.push(serde_json::json!({"camera": 3, "rotation": [-s, 0, 0, c]}));
    for k in [first, first + 1, first + 3, first + 4] {
        v["scenes"][0]["nodes"].as_array_mut().unwrap().push(k.into());
    }
    std::fs::write(&path, v.to_string()).unwrap();
    let (_, report) = import::load(&path).unwrap();
    assert_eq!(report.cameras.len(), 3, "{:?}", report.cameras);
    assert!(report.notes.iter().any(|n| n.contains("'flat' is orthographic")), "{:?}", report.notes);
    let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
    let (yawed, rolled) = (&report.cameras[0], &report.cameras[1]);
    assert_eq!((yawed.name.as_str(), rolled.name.as_str()), ("yawed", "rolled"));
    assert!(close(yawed.eye, Vec3::new(1.0, 2.0, 3.0)) && close(yawed.forward, -Vec3::X) && close(yawed.up, Vec3::Y), "{yawed:?}");
    assert!(close(rolled.eye, Vec3::new(0.0, 1.0, 5.0)) && close(rolled.forward, -Vec3::Z) && close(rolled.up, -Vec3::X), "{rolled:?}");
    assert_eq!((yawed.fov_y, yawed.aspect, rolled.aspect), (0.8, Some(1.5), None));
    // The stretched camera: forward (0, −2, −1)/√5; up = (0, 2, −1) less its part along
    // forward, normalised: (0, 2, −1) + (3/5)(0, −2, −1) = (0, 4/5, −8/5) → (0, 1, −2)/√5.
    let stretched = &report.cameras[2];
    let r5 = 5f32.sqrt();
    assert!(
        close(stretched.forward, Vec3::new(0.0, -2.0, -1.0) / r5) && close(stretched.up, Vec3::new(0.0, 1.0, -2.0) / r5),
        "{stretched:?}"
    );
    for c in [yawed, rolled, stretched] {
        let cam = ViewCamera::from_scene(c, 64, 48);
        let dir = |x: f32, y: f32| cam.ray(x, y).1;
        assert!(close(dir(32.0, 24.0), c.forward), "{}: centre ray {}", c.name, dir(32.0, 24.0));
        assert!(dir(32.0, 0.0).dot(c.up) > 0.2 && dir(64.0, 24.0).dot(c.forward.cross(c.up)) > 0.2, "{}", c.name);
        // The vertical field of view: the top edge's ray at fov/2 from the forward axis.
        assert!((dir(32.0, 0.0).angle_between(c.forward) - 0.5 * c.fov_y).abs() < 1e-5, "{}", c.name);
    }
    let out = d.join("render-out");
    let o = Command::new(env!("CARGO_BIN_EXE_render"))
        .args(["--scene", path.to_str().unwrap(), "--camera", "gltf:nope", "--device", "cpu", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{log}");
    assert!(log.contains("no such camera") && log.contains("0: 'yawed', 1: 'rolled'") && !out.join("bake").exists(), "{log}");
}

/// A GPU bake whose encoder states exceed one storage binding bakes its bases in groups
/// over the same paths (`--max-storage-binding` lowers the limit to force it): with the
/// six lightmap bases in three groups, every written file equals the one-group bake's bit
/// for bit (the groups trace the same paths with the same numbers; their moments agree),
/// and the log says how it split. Mutation: the later groups baked with another seed →
/// their moments differ and the bake stops with that error.
#[test]
fn gpu_bake_in_basis_groups_equals_the_single_bake() {
    let Some(_gpu) = have_gpu() else { return };
    let (a, b) = (tmp("groups-one"), tmp("groups-three"));
    let run = |dir: &Path, extra: &[&str]| {
        let base = ["--passes", "16", "--bases", "sh1,sh2,sg9,sg12,ad9,ad12", "--checkpoint-every", "0", "--probes", "0,0,0"];
        gpu_bake(dir, &[&base[..], extra].concat(), &[])
    };
    let targets =
        baker::accumulate::Targets::lightmap(&baker::layout::lightmap::Lightmap::build(&baker::scene::cornell(), 6.0, 2).unwrap());
    // Room for two bases' states.
    let two = 2 * targets.items.len() * std::mem::size_of::<shaders::progressive::EncoderState>();
    // Plain, and with filtered accumulation (each group gathers into its own filtered
    // encoders, joined as the plain ones are).
    for filter in [&[][..], &["--filter", "mitchell"][..]] {
        run(&a, filter);
        let log = run(&b, &[filter, &["--max-storage-binding", &two.to_string()]].concat());
        assert!(log.contains("baked in 3 groups") && log.contains("sh1+sh2, sg9+sg12, ad9+ad12"), "{log}");
        let (ha, hb) = (common::outputs::hashes(&a), common::outputs::hashes(&b));
        assert_eq!(ha.len(), hb.len());
        for (x, y) in ha.iter().zip(&hb) {
            assert_eq!(x, y, "{} differs between the single and the grouped bake ({filter:?})", x.0);
        }
    }
}

/// A GPU bake whose sample points exceed one storage binding splits them over two
/// (the device's limit lowered by `SBF_GPU_MAX_STORAGE_BINDING` to two thirds of the
/// points' bytes, while the encoder states and moments still fit one): every written file equals the
/// one-binding bake's bit for bit — the kernel reads the same point for every sample.
/// Mutations: the second binding read one point off, or every point read from the second
/// binding → the files differ.
#[test]
fn gpu_bake_with_points_in_two_bindings_equals_the_single_bake() {
    let Some(_gpu) = have_gpu() else { return };
    let targets =
        baker::accumulate::Targets::lightmap(&baker::layout::lightmap::Lightmap::build(&baker::scene::cornell(), 6.0, 2).unwrap());
    let point_bytes = targets.points.len() * 48;
    let cap = point_bytes * 2 / 3;
    let states = 2 * targets.items.len() * std::mem::size_of::<shaders::progressive::EncoderState>();
    assert!(states < cap && targets.items.len() * 48 < cap, "the cap must split the points alone ({states} B of states, cap {cap} B)");
    let (a, b) = (tmp("points-one"), tmp("points-two"));
    let args = ["--passes", "24", "--bases", "sh2,ad9", "--checkpoint-every", "0", "--probes", "0,0,0"];
    gpu_bake(&a, &args, &[]);
    gpu_bake(&b, &args, &[("SBF_GPU_MAX_STORAGE_BINDING", &cap.to_string())]);
    let (ha, hb) = (common::outputs::hashes(&a), common::outputs::hashes(&b));
    assert_eq!(ha.len(), hb.len());
    for (x, y) in ha.iter().zip(&hb) {
        assert_eq!(x, y, "{} differs between the one- and the two-binding bake", x.0);
    }
}

/// `--gpu-index I` pins the bake to the host's I-th adapter (how a farm gives each shard the
/// GPU its scheduler assigned), `SBF_GPU_INDEX` does when the option is absent: the bake
/// runs on the adapter `shaders::gpu::Gpu::at` names for that index and bake.json records it;
/// an index past the last adapter fails listing them, a bad variable and the CPU device are
/// refused, all before anything is written.
#[test]
fn gpu_index_pins_the_bake_to_an_adapter() {
    let Some(g) = have_gpu() else { return };
    let want = shaders::gpu::Gpu::at(0).unwrap().adapter;
    drop(g);
    for (how, args, env) in [("--gpu-index 0", vec!["--gpu-index", "0"], None), ("SBF_GPU_INDEX=0", vec![], Some("0"))] {
        let d = tmp(&format!("gpu-index-{}", how.len()));
        let _g = have_gpu();
        let mut c =
            baker(&["--device", "gpu", "--passes", "2", "--probes", "0,0,0", "--texels-per-unit", "4", "--preview-width", "16", "--out"]);
        c.arg(&d).args(&args);
        if let Some(v) = env {
            c.env("SBF_GPU_INDEX", v);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{how}: {}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&std::fs::read(d.join("bake.json")).unwrap()).unwrap();
        assert_eq!(j["device"].as_str(), Some(format!("GPU: {want}").as_str()), "{how}");
        let _ = std::fs::remove_dir_all(&d);
    }
    let d = tmp("gpu-index-bad");
    let out = d.join("out");
    for (args, env, needle) in [
        (vec!["--device", "gpu", "--gpu-index", "64"], None, "GPU index 64: this host has"),
        (vec!["--device", "cpu", "--gpu-index", "0"], None, "--gpu-index 0 picks one GPU"),
        (vec!["--device", "gpu"], Some("first"), "SBF_GPU_INDEX=first"),
    ] {
        let mut c = baker(&args);
        c.arg("--out").arg(&out);
        if let Some(v) = env {
            c.env("SBF_GPU_INDEX", v);
        }
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(needle), "{args:?}: {err}");
        assert!(!out.join("bake.json").exists(), "{args:?} wrote a bake");
    }
    let _ = std::fs::remove_dir_all(&d);
}
