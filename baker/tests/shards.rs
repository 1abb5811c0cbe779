//! A bake spread over machines (`baker --shard I/N`, `baker merge`): the built-in scene
//! and the mixed-lighting glTF room (≈ 41 k triangles, authored lightmap UVs) baked whole
//! and as 1, 2, 3 and 7 shards on the CPU path; every merged output must equal the single
//! bake's file byte for byte (bake.json without the fields that measure the run: wall
//! times, device, pipeline). The oracle is the single bake, which never partitions its
//! items: a shard that bakes a wrong block, a merge that takes an item from the wrong
//! shard, or a shard file that drops or reorders an encoder changes a texel and a hash.
//! The CPU path is deterministic for any thread count, so the comparison is exact.
//!
//! Also: the merge's refusals (another seed, a missing shard, a duplicate, another
//! split, a corrupt file), each named; options that need the whole atlas every pass
//! refused with --shard; a re-run shard writing the same bytes.
//!
//! Mutations tried, each caught: `Partition::ranges` starting one block late (every shard
//! bakes and stores its neighbour's blocks, block 0 none: merged EXRs differ); the merge
//! filling every shard's items from the first shard's file (EXRs and probes differ); the
//! shard file writing encoders item-major while the reader reads them basis-major (the
//! merge fails); `check_complete` accepting a gap (the refusal test fails).

mod common;

use common::outputs::{hashes, scenes_dir};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("baker-shards-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn baker(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_baker")).args(args).output().unwrap()
}

fn ok(args: &[&str]) {
    let o = baker(args);
    assert!(o.status.success(), "baker {args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// A small bake's arguments: SH L2 + AD 9 lightmaps, 4×4×4 probes in SH L2 + AD 12 (64
/// probes: one block, so the probes go to shard 0; the texels spread over every shard),
/// denoised and seam-stitched (the defaults for short bakes: they run at the merge).
fn recipe<'a>(scene: &'a str, passes: &'a str, tpu: &'a str) -> Vec<&'a str> {
    vec![
        "--scene",
        scene,
        "--bases",
        "sh2,ad9",
        "--probe-bases",
        "sh2,ad12",
        "--probes",
        "4,4,4",
        "--preview-width",
        "48",
        "--passes",
        passes,
        "--texels-per-unit",
        tpu,
        "--device",
        "cpu",
    ]
}

/// Bakes `recipe` whole and as N shards for each N in `splits`; each merge's files must
/// be the single bake's.
fn shards_merge_to_the_single_bake(name: &str, recipe: &[&str], splits: &[usize]) {
    let root = tmp(name);
    let single = root.join("single");
    let mut args = recipe.to_vec();
    args.extend(["--out", single.to_str().unwrap()]);
    ok(&args);
    let want = hashes(&single);
    assert!(want.iter().any(|(f, _)| f.ends_with(".exr")) && want.iter().any(|(f, _)| f == "probes.json"), "{name}: {want:?}");
    for &n in splits {
        let dir = root.join(format!("shards-{n}"));
        let mut files = Vec::new();
        for i in 0..n {
            let spec = format!("{i}/{n}");
            let mut args = recipe.to_vec();
            args.extend(["--shard", &spec, "--out", dir.to_str().unwrap()]);
            ok(&args);
            files.push(dir.join(format!("shard-{i}-of-{n}.sbfshard")));
        }
        let merged = root.join(format!("merged-{n}"));
        let mut args = vec!["merge", merged.to_str().unwrap()];
        // In reverse order: the merge must not depend on the order it is given.
        files.iter().rev().for_each(|f| args.push(f.to_str().unwrap()));
        ok(&args);
        let got = hashes(&merged);
        assert_eq!(
            got.iter().map(|x| &x.0).collect::<Vec<_>>(),
            want.iter().map(|x| &x.0).collect::<Vec<_>>(),
            "{name}, {n} shards: other files than the single bake"
        );
        let differ: Vec<&str> = got.iter().zip(&want).filter(|(a, b)| a.1 != b.1).map(|(a, _)| a.0.as_str()).collect();
        assert!(differ.is_empty(), "{name}, {n} shards: {} of {} files differ from the single bake: {differ:?}", differ.len(), got.len());
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn builtin_scene_shards_merge_to_the_single_bake() {
    shards_merge_to_the_single_bake("cornell", &recipe("cornell", "8", "6"), &[1, 2, 3, 7]);
}

#[test]
fn gltf_room_shards_merge_to_the_single_bake() {
    let Some(scenes) = scenes_dir() else { return };
    let gltf = scenes.join("bevy_MixedLightingExample/MixedLightingExample.gltf");
    shards_merge_to_the_single_bake("room", &recipe(gltf.to_str().unwrap(), "4", "8"), &[1, 2, 3, 7]);
}

/// The peak resident memory a run recorded (bake.json, or a shard's run record).
fn peak_memory(json: &Path) -> u64 {
    let text = std::fs::read_to_string(json).unwrap_or_else(|e| panic!("{}: {e}", json.display()));
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["peak_memory_bytes"].as_u64().unwrap_or_else(|| panic!("{}: no peak_memory_bytes (not Linux?)", json.display()))
}

/// 8 shards of the glTF room at 64 texels per unit (48 832 texels): each shard holds only
/// its share. Its checkpoints: together ≤ 1.25× the single bake's checkpoint bytes (the
/// headers and the probe set, owned by shard 0 whole, are the excess) — before, each held
/// the whole atlas, 8×. Its memory: every shard's peak resident memory ≤ 1/4 of the single
/// bake's + a constant, the peak of the same bake at 4 texels per unit (240 texels: the
/// process, the scene with its textures, the BVH; measured here, not assumed) — a shard
/// holds 1/8 of the state and of the layout's points, so the bound leaves it 2× room; the
/// whole state and layout in every shard, as before, is ≈ 0.9× the single bake's peak
/// and fails it. And they resume: every shard baked to pass 1, then resumed to pass 2
/// from its checkpoint, merges to the single 2-pass bake byte for byte.
#[test]
fn gltf_room_shards_hold_only_their_share_and_resume() {
    let Some(scenes) = scenes_dir() else { return };
    let gltf = scenes.join("bevy_MixedLightingExample/MixedLightingExample.gltf");
    let g = gltf.to_str().unwrap();
    let root = tmp("share");
    let (tiny, single, dir, merged) = (root.join("tiny"), root.join("single"), root.join("shards"), root.join("merged"));
    let mut args = recipe(g, "2", "4");
    args.extend(["--out", tiny.to_str().unwrap()]);
    ok(&args);
    let constant = peak_memory(&tiny.join("bake.json"));
    let mut args = recipe(g, "2", "64");
    args.extend(["--checkpoint-every", "1", "--out", single.to_str().unwrap()]);
    ok(&args);
    let whole_peak = peak_memory(&single.join("bake.json"));
    let size = |p: PathBuf| std::fs::metadata(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display())).len();
    let whole = size(single.join("lightmap.checkpoint")) + size(single.join("probes.checkpoint"));
    let (n, mut parts, mut files) = (8, 0, Vec::new());
    let bound = whole_peak / 4 + constant;
    for i in 0..n {
        let spec = format!("{i}/{n}");
        for (passes, resume) in [("1", false), ("2", true)] {
            let mut args = recipe(g, passes, "64");
            args.extend(["--checkpoint-every", "1", "--shard", &spec, "--out", dir.to_str().unwrap()]);
            if resume {
                args.push("--resume");
            }
            let o = baker(&args);
            let log = String::from_utf8_lossy(&o.stderr);
            assert!(o.status.success(), "shard {spec}, {passes} passes: {log}");
            if resume {
                assert!(log.contains("lightmap: resuming from") && log.contains("at pass 1"), "shard {spec} did not resume: {log}");
            } else {
                parts += size(dir.join(format!("lightmap.shard-{i}-of-{n}.checkpoint")));
                // The probes (one block) are shard 0's: the others hold none and write none.
                let probes = dir.join(format!("probes.shard-{i}-of-{n}.checkpoint"));
                assert_eq!(probes.exists(), i == 0, "{}", probes.display());
                parts += if i == 0 { size(probes) } else { 0 };
            }
            let peak = peak_memory(&dir.join(format!("shard-{i}-of-{n}.json")));
            println!("shard {spec}, {passes} pass(es): peak {:.1} MB (bound {:.1} MB)", peak as f64 * 1e-6, bound as f64 * 1e-6);
            assert!(
                peak <= bound,
                "shard {spec} peaked at {peak} B: more than 1/4 of the single bake's {whole_peak} B + the 240-texel bake's {constant} B"
            );
        }
        files.push(dir.join(format!("shard-{i}-of-{n}.sbfshard")).to_str().unwrap().to_string());
    }
    println!("8 shards' checkpoints: {parts} bytes; the single bake's: {whole} bytes ({:.3}×)", parts as f64 / whole as f64);
    println!("peaks: single bake {:.1} MB, 240-texel bake {:.1} MB", whole_peak as f64 * 1e-6, constant as f64 * 1e-6);
    assert!(parts as f64 <= 1.25 * whole as f64, "8 shards' checkpoints hold {parts} bytes, the single bake's {whole}");
    let mut args = vec!["merge", merged.to_str().unwrap()];
    files.iter().for_each(|f| args.push(f));
    ok(&args);
    let (want, got) = (hashes(&single), hashes(&merged));
    assert_eq!(got, want, "the resumed shards' merge differs from the single bake");
    let _ = std::fs::remove_dir_all(&root);
}

fn refusal(args: &[&str], want: &[&str]) {
    let o = baker(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "baker {args:?} should exit 2: {err}");
    for w in want {
        assert!(err.contains(w), "baker {args:?}: the message should name '{w}': {err}");
    }
}

/// The merge refuses what would not give the single bake, naming the shard and the reason.
#[test]
fn merge_refuses_shards_of_another_bake_gaps_and_duplicates() {
    let root = tmp("refusals");
    let shard = |dir: &Path, i: usize, n: usize, extra: &[&str]| -> PathBuf {
        let spec = format!("{i}/{n}");
        let mut args = recipe("cornell", "2", "4");
        args.extend(["--shard", &spec, "--out", dir.to_str().unwrap()]);
        args.extend(extra);
        ok(&args);
        dir.join(format!("shard-{i}-of-{n}.sbfshard"))
    };
    let (a, b) = (root.join("a"), root.join("b"));
    let s: Vec<PathBuf> = (0..3).map(|i| shard(&a, i, 3, &[])).collect();
    let p = |x: &PathBuf| x.to_str().unwrap().to_string();
    let out = root.join("out");
    let out = out.to_str().unwrap();
    // Another seed.
    let other_seed = shard(&b, 1, 3, &["--seed", "2"]);
    refusal(&["merge", out, &p(&s[0]), &p(&other_seed), &p(&s[2])], &["different bakes", "config.seed: 1 vs 2", "shard 1 of 3"]);
    // Other passes (the shards' own pass counts would refuse them too; the spec names it).
    let c = root.join("c");
    let mut args = recipe("cornell", "3", "4");
    args.extend(["--shard", "1/3", "--out", c.to_str().unwrap()]);
    ok(&args);
    refusal(&["merge", out, &p(&s[0]), &p(&c.join("shard-1-of-3.sbfshard")), &p(&s[2])], &["different bakes", "passes: 2 vs 3"]);
    // A missing shard.
    refusal(&["merge", out, &p(&s[0]), &p(&s[2])], &["missing shard 1 of 3", "--shard 1/3"]);
    // A duplicate (the same shard twice, under two names).
    let copy = root.join("copy.sbfshard");
    std::fs::copy(&s[1], &copy).unwrap();
    refusal(&["merge", out, &p(&s[0]), &p(&s[1]), &p(&copy), &p(&s[2])], &["shard 1 of 3 is given twice", "copy.sbfshard"]);
    // Another split.
    let of_two = shard(&b, 1, 2, &[]);
    refusal(&["merge", out, &p(&s[0]), &p(&of_two), &p(&s[2])], &["different splits"]);
    // A corrupt file (one byte flipped in the items).
    let mut bytes = std::fs::read(&s[2]).unwrap();
    let at = bytes.len() - 100;
    bytes[at] ^= 1;
    let bad = root.join("bad.sbfshard");
    std::fs::write(&bad, &bytes).unwrap();
    refusal(&["merge", out, &p(&s[0]), &p(&s[1]), &p(&bad)], &["bad.sbfshard", "checksum"]);
    // Nothing was written by a refused merge.
    assert!(!Path::new(out).join("bake.json").exists(), "a refused merge wrote outputs");
    // Options that need every texel each pass cannot be sharded.
    for (extra, name) in [(&["--guiding"][..], "--guiding"), (&["--filter", "box"], "--filter"), (&["--adaptive"], "--adaptive")] {
        let mut args = recipe("cornell", "16", "4");
        args.extend(["--shard", "0/2", "--out", out]);
        args.extend(extra);
        refusal(&args, &[name, "--shard 0/2"]);
    }
    refusal(&["--shard", "3/3"], &["--shard"]);
    // A re-run shard writes the same bytes (a retried task is harmless).
    let before = std::fs::read(&s[0]).unwrap();
    shard(&a, 0, 3, &[]);
    assert!(std::fs::read(&s[0]).unwrap() == before, "a re-run shard wrote other bytes");
    let _ = std::fs::remove_dir_all(&root);
}

/// A scene edited at the same path after its shards were baked: the merge refuses (the
/// content fingerprint) and writes nothing — not even the output folder.
#[test]
fn merge_of_an_edited_scene_refuses_and_writes_nothing() {
    let Some(scenes) = scenes_dir() else { return };
    let root = tmp("edited");
    let src = scenes.join("bevy_MixedLightingExample");
    let dir = root.join("scene");
    std::fs::create_dir_all(&dir).unwrap();
    for e in std::fs::read_dir(&src).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), dir.join(e.file_name())).unwrap();
    }
    let gltf = dir.join("MixedLightingExample.gltf");
    let g = gltf.to_str().unwrap();
    let shards: Vec<String> = (0..2)
        .map(|i| {
            let (spec, out) = (format!("{i}/2"), root.join("shards"));
            let mut args = recipe(g, "2", "4");
            args.extend(["--material-maps", "factors", "--shard", &spec, "--out", out.to_str().unwrap()]);
            ok(&args);
            out.join(format!("shard-{i}-of-2.sbfshard")).to_str().unwrap().to_string()
        })
        .collect();
    // The first material's base colour changed, nothing else.
    let mut doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&gltf).unwrap()).unwrap();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = serde_json::json!([0.2, 0.9, 0.3, 1.0]);
    std::fs::write(&gltf, serde_json::to_string(&doc).unwrap()).unwrap();
    let out = root.join("out");
    refusal(&["merge", out.to_str().unwrap(), &shards[0], &shards[1]], &["belongs to another bake"]);
    assert!(!out.exists(), "a refused merge created {}", out.display());
    let _ = std::fs::remove_dir_all(&root);
}

/// docs/distributed/slurm-array.sh run as Slurm would run its array tasks (index and count
/// from SLURM_ARRAY_TASK_ID / SHARDS), then the merge: the single bake's files.
#[test]
fn the_slurm_array_script_bakes_shards_that_merge_to_the_single_bake() {
    let root = tmp("slurm");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/distributed/slurm-array.sh");
    let bake_args = "--scene cornell --passes 4 --texels-per-unit 5 --probes 2,2,2 --preview-width 48 --device cpu";
    let single = root.join("single");
    let mut args: Vec<&str> = bake_args.split(' ').collect();
    args.extend(["--out", single.to_str().unwrap()]);
    ok(&args);
    let shards = root.join("shards");
    // The baker as task 1 sees it: it fails once (status 3), then runs; the script's retry
    // loop must run it again. A second wrapper always fails: with RETRIES=1 the task gives
    // up after two attempts with the bake's status.
    let (flaky, broken, mark) = (root.join("flaky-baker"), root.join("broken-baker"), root.join("failed-once"));
    let flaky_sh = format!(
        "#!/bin/sh\nif [ \"$SLURM_ARRAY_TASK_ID\" = 1 ] && [ ! -e '{}' ]; then touch '{}'; echo 'fake failure' >&2; exit 3; fi\nexec '{}' \"$@\"\n",
        mark.display(),
        mark.display(),
        env!("CARGO_BIN_EXE_baker")
    );
    std::fs::write(&flaky, flaky_sh).unwrap();
    std::fs::write(&broken, "#!/bin/sh\necho 'fake failure' >&2\nexit 3\n").unwrap();
    for f in [&flaky, &broken] {
        let mut p = std::fs::metadata(f).unwrap().permissions();
        std::os::unix::fs::PermissionsExt::set_mode(&mut p, 0o755);
        std::fs::set_permissions(f, p).unwrap();
    }
    let task = |i: usize, baker: &Path, retries: &str| {
        Command::new("bash")
            .arg(&script)
            .env("SLURM_ARRAY_TASK_ID", i.to_string())
            .env("SHARDS", "3")
            .env("SHARD_DIR", &shards)
            .env("BAKER", baker)
            .env("RETRIES", retries)
            .env("BAKE_ARGS", bake_args)
            .output()
            .unwrap()
    };
    for i in 0..3 {
        let o = task(i, &flaky, "3");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "slurm-array.sh task {i}: {err}");
        assert_eq!(i == 1, err.contains("shard 1/3: status 3; retrying from its checkpoint (1 of 3)"), "task {i}: {err}");
    }
    let o = task(0, &broken, "1");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.code() == Some(3) && err.contains("failed with status 3 after 2 attempts"), "{:?}: {err}", o.status);
    let merged = root.join("merged");
    let files: Vec<String> = (0..3).map(|i| shards.join(format!("shard-{i}-of-3.sbfshard")).to_string_lossy().into_owned()).collect();
    let mut args = vec!["merge", merged.to_str().unwrap()];
    files.iter().for_each(|f| args.push(f));
    ok(&args);
    // The script checkpoints; the single bake above did too (every 32 passes, the default).
    assert_eq!(hashes(&merged), hashes(&single), "the Slurm tasks' merge differs from the single bake");
    // GPU pinning: Slurm's GPU_DEVICE_ORDINAL (the task's GPU; the first of a list) reaches
    // baker as SBF_GPU_INDEX (its --gpu-index), unless the job sets SBF_GPU_INDEX itself.
    let (spy, seen) = (root.join("spy-baker"), root.join("gpu-index"));
    std::fs::write(&spy, format!("#!/bin/sh\nprintf '%s' \"${{SBF_GPU_INDEX-unset}}\" > '{}'\n", seen.display())).unwrap();
    let mut p = std::fs::metadata(&spy).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut p, 0o755);
    std::fs::set_permissions(&spy, p).unwrap();
    for (ordinal, own, want) in [(Some("2"), None, "2"), (Some("1,3"), None, "1"), (Some("2"), Some("0"), "0"), (None, None, "unset")] {
        let mut c = Command::new("bash");
        c.arg(&script)
            .env("SLURM_ARRAY_TASK_ID", "0")
            .env("SHARDS", "3")
            .env("SHARD_DIR", &shards)
            .env("BAKER", &spy)
            .env_remove("SBF_GPU_INDEX");
        if let Some(o) = ordinal {
            c.env("GPU_DEVICE_ORDINAL", o);
        }
        if let Some(o) = own {
            c.env("SBF_GPU_INDEX", o);
        }
        assert!(c.output().unwrap().status.success());
        assert_eq!(std::fs::read_to_string(&seen).unwrap(), want, "GPU_DEVICE_ORDINAL {ordinal:?}, SBF_GPU_INDEX {own:?}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// A shard's layout and targets are the whole bake's part: [`Lightmap::build_part`] keeps
/// the chosen texels' points exactly as [`Lightmap::build`] lays them out and drops the
/// others', every texel's coverage, chart and point digest alike; [`Targets::lightmap_part`]
/// equals [`Targets::part`] of the whole targets item for item, point for point, with the
/// whole set's identity. The digest covers every point and its rank: one coordinate one
/// ulp off, or two points of a texel swapped, changes it.
/// Mutation tried: the digest's rank taken from the coverage so far instead of the first
/// pass's final coverage (digests differ from the whole build's).
#[test]
fn a_shards_layout_and_targets_are_the_whole_bakes_part() {
    use baker::accumulate::{Partition, Targets};
    use baker::layout::lightmap::{points_digest, Lightmap};
    let scene = baker::scene::cornell();
    let whole = Lightmap::build(&scene, 6.0, 2).unwrap();
    let targets = Targets::lightmap(&whole);
    let order = whole.item_order();
    assert_eq!(order.len(), targets.items.len());
    for (i, n) in [(0, 3), (2, 3), (1, 7)] {
        let part = Partition::of(i, n, order.len()).unwrap();
        let keep = |item: usize, items: usize| Partition::of(i, n, items).unwrap().owns(item);
        let lm = Lightmap::build_part(&scene, 6.0, 2, &keep).unwrap();
        assert!(lm.partial && !whole.partial);
        assert_eq!(lm.digests, whole.digests, "part {i}/{n}: digests");
        assert_eq!(lm.texel_charts, whole.texel_charts, "part {i}/{n}: texel charts");
        let mut kept = vec![false; whole.texels.len()];
        order.iter().enumerate().filter(|(item, _)| part.owns(*item)).for_each(|(_, k)| kept[*k] = true);
        for (k, (a, b)) in lm.texels.iter().zip(&whole.texels).enumerate() {
            assert_eq!((a.coverage, a.chart), (b.coverage, b.chart), "part {i}/{n}: texel {k}");
            assert_eq!(a.points, if kept[k] { b.points.clone() } else { Vec::new() }, "part {i}/{n}: texel {k}'s points");
        }
        let (mine, cut) = (Targets::lightmap_part(&lm, part).unwrap(), targets.part(part).unwrap());
        assert_eq!(mine.items, cut.items, "part {i}/{n}: items");
        assert_eq!(mine.points, cut.points, "part {i}/{n}: points");
        assert_eq!(mine.point_uv, cut.point_uv, "part {i}/{n}: point uv");
        assert_eq!((mine.identity, cut.identity), (targets.identity, targets.identity), "part {i}/{n}: identity");
        assert_eq!(mine.part, Some((part, order.len())));
        assert!(Targets::lightmap_part(&lm, Partition::of((i + 1) % n, n, order.len()).unwrap()).is_err(), "another part's targets");
    }
    let k = *order.iter().find(|k| whole.texels[**k].points.len() >= 2).expect("a texel with two points");
    let pts = &whole.texels[k].points;
    assert_eq!(points_digest(pts), whole.digests[k]);
    let mut moved = pts.clone();
    moved[1].position.x = f32::from_bits(moved[1].position.x.to_bits() + 1);
    assert_ne!(points_digest(&moved), whole.digests[k], "a point one ulp off");
    let mut swapped = pts.clone();
    swapped.swap(0, 1);
    assert!(pts[0] == pts[1] || points_digest(&swapped) != whole.digests[k], "two points swapped");
}
