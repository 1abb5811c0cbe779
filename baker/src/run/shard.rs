//! A bake spread over machines: a shard's run ends by writing its partial state
//! ([`crate::checkpoint::shard`]) and a small record of the run beside it; `baker merge`
//! reads every shard, checks that they are the N parts of one bake, rebuilds the scene,
//! layout and probe grid from the [`BakeSpec`] recorded in them, and writes the outputs the
//! single bake writes — the post-processing (denoising, seams, dilation) runs here, on the
//! whole atlas — and the whole state is written as the single bake's checkpoint, so the
//! merged bake can be continued on one machine (`baker resume --out OUT --passes M`).

use super::options::{BakeSpec, Options, RunOptions, ShardSpec, Summary};
use super::outputs::{write_outputs, OutputContext, StageTimes};
use crate::accumulate::{BakeConfig, BakeState, Partition, Targets};
use crate::checkpoint::shard::{self, SetState, Shard};
use crate::checkpoint::{content_fingerprint, write_atomic};
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a shard's run measured (`shard-I-of-N.json` beside the shard file; not part of
/// the shard's bytes, so a re-run shard file stays identical).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShardRun {
    pub index: usize,
    pub count: usize,
    pub device: String,
    pub pipeline: String,
    pub lightmap_passes_seconds: f64,
    pub probe_passes_seconds: Option<f64>,
    pub seconds: f64,
    /// The shard process's peak resident memory, in bytes (Linux: VmHWM; None elsewhere).
    #[serde(default)]
    pub peak_memory_bytes: Option<u64>,
}

/// The record file of shard `index` of `count`.
fn run_file(dir: &Path, index: usize, count: usize) -> PathBuf {
    dir.join(format!("shard-{index}-of-{count}.json"))
}

/// One set of targets a shard baked.
pub(crate) struct BakedSet<'a> {
    pub(crate) what: &'a str,
    pub(crate) scene: &'a Scene,
    pub(crate) targets: &'a Targets,
    pub(crate) config: &'a BakeConfig,
    pub(crate) state: &'a BakeState,
}

/// Writes shard `spec`'s file (its items of every set) and its run record into `o.run.out`.
pub(crate) fn write_shard(
    o: &Options,
    spec: &ShardSpec,
    sets: &[BakedSet],
    run: &ShardRun,
    log: &mut dyn FnMut(String),
) -> Result<(), String> {
    let mut states = Vec::with_capacity(sets.len());
    for s in sets {
        let (part, items) = match s.targets.part {
            Some(p) => p,
            None => (Partition::of(spec.index, spec.count, s.targets.items.len())?, s.targets.items.len()),
        };
        if (part.index, part.count) != (spec.index, spec.count) || s.state.moments.len() != part.share(items) {
            return Err(format!("{}: the state holds other items than shard {} of {}", s.what, spec.index, spec.count));
        }
        states.push(SetState {
            what: s.what,
            fingerprint: content_fingerprint(s.scene, s.targets, s.config, s.what),
            part,
            items,
            lobes: s.config.bases.iter().map(|b| b.lobes()).collect(),
            state: s.state,
        });
    }
    let recorded: serde_json::Value = serde_json::from_str(&o.spec.canonical()).expect("canonical json");
    let bytes = shard::to_bytes(spec.index, spec.count, &recorded, &states);
    let path = o.run.out.join(shard::file_name(spec.index, spec.count));
    shard::write(&path, &bytes)?;
    let json = serde_json::to_string_pretty(run).map_err(|e| e.to_string())?;
    write_atomic(&run_file(&o.run.out, spec.index, spec.count), json.as_bytes())?;
    let peak = run.peak_memory_bytes.map_or(String::new(), |b| format!(", peak memory {:.1} MB", b as f64 * 1e-6));
    log(format!(
        "shard {} of {}: {} ({} bytes{peak}); merge all {} with `baker merge OUT SHARD…`",
        spec.index,
        spec.count,
        path.display(),
        bytes.len(),
        spec.count
    ));
    Ok(())
}

/// Merges shard files into the outputs of the single bake, in `out`, from the
/// [`BakeSpec`] recorded in them (the files it names must be readable here). Refuses shards
/// of different bakes (naming the fields that differ), of different splits, duplicates
/// and gaps, and shards whose scene content no longer matches the files named.
pub fn merge(out: &Path, files: &[PathBuf], log: &mut dyn FnMut(String)) -> Result<Summary, String> {
    let t0 = Instant::now();
    let shards: Vec<Shard> = files.iter().map(|f| Shard::read(f)).collect::<Result<_, _>>()?;
    let first = shards.first().ok_or("merge needs the shard files (shard-I-of-N.sbfshard)")?;
    let spec_of = |s: &Shard| -> Result<BakeSpec, String> {
        serde_json::from_value(s.header.spec.clone()).map_err(|e| format!("{}: its recorded bake spec: {e}", s.name()))
    };
    let spec = spec_of(first)?;
    for s in &shards[1..] {
        let other = spec_of(s)?;
        let diff = spec.differences(&other, true);
        if !diff.is_empty() {
            return Err(format!("{} and {} are shards of different bakes: {}", first.name(), s.name(), diff.join("; ")));
        }
    }
    let o = Options { spec, run: RunOptions { out: out.to_path_buf(), ..RunOptions::default() } };
    o.validate()?;
    let n = shard::check_complete(&shards)?;
    log(format!("merge: {n} shards of one bake (scene {}, {} passes)", o.spec.scene, o.spec.passes));
    let p = super::prepare(&o, log)?;
    let mut sets = vec![("lightmap", &p.targets, &p.config)];
    let probe_targets = p.probes.as_ref().map(|(pos, _)| Targets::probes(pos));
    let probe_config = super::probe_config(&o);
    if let Some(t) = &probe_targets {
        sets.push(("probes", t, &probe_config));
    }
    // Every refusal (a scene edited since the shards were baked fails the fingerprint here)
    // before the output folder is created: a refused merge writes nothing.
    let mut merged = Vec::new();
    for (k, (what, targets, config)) in sets.iter().enumerate() {
        let fp = content_fingerprint(&p.scene, targets, config, what);
        merged.push((*what, fp, targets.items.len(), shard::merge(&shards, k, fp, config, targets)?));
    }
    super::limits::check_writable(out)?;
    // The spec beside the checkpoints: `baker resume` continues the merged bake from it.
    super::options::record_spec(&o.spec, out, false)?;
    let mut states = Vec::new();
    for (what, fp, items, state) in merged {
        // The whole state as the single bake's checkpoint: `baker resume --passes M`
        // continues the merged bake on one machine.
        write_atomic(&out.join(format!("{what}.checkpoint")), &crate::checkpoint::to_bytes(&state, fp))?;
        log(format!("merge: {what}: {items} items from {n} shards, {} passes", state.passes));
        states.push(state);
    }
    let runs: Vec<Option<ShardRun>> = shards
        .iter()
        .map(|s| {
            let dir = s.path.parent().unwrap_or(Path::new("."));
            std::fs::read(run_file(dir, s.header.index, n)).ok().and_then(|b| serde_json::from_slice(&b).ok())
        })
        .collect();
    let (device, pipeline, times) = merged_run(&runs);
    let (positions, relocated) = p.probes.clone().unwrap_or_default();
    let ctx = OutputContext {
        probe_positions: &positions,
        relocated: &relocated,
        device: &device,
        pipeline,
        glossy: p.scene.has_glossy(),
        t0,
        times,
    };
    let mut it = states.into_iter();
    let lightmap = it.next().expect("the lightmap set");
    let probes = it.next();
    write_outputs(&o, &p.scene, &p.bvh, &p.lm, &p.targets, &lightmap, probes.as_ref(), &ctx, log)?;
    Ok(Summary { device, lightmap, probes, passes_run: 0, seconds: t0.elapsed().as_secs_f64() })
}

/// bake.json's device, pipeline and stage times of a merged bake: the shards' devices,
/// their pipeline (or "mixed"), their pass seconds summed (the work, not the wall time).
fn merged_run(runs: &[Option<ShardRun>]) -> (String, &'static str, StageTimes) {
    let mut devices: Vec<&str> = runs.iter().flatten().map(|r| r.device.as_str()).collect();
    devices.sort_unstable();
    devices.dedup();
    let missing = runs.iter().filter(|r| r.is_none()).count();
    let device = format!(
        "{} shards merged; baked on {}{}",
        runs.len(),
        if devices.is_empty() { "unrecorded devices".to_string() } else { devices.join(" | ") },
        if missing > 0 && !devices.is_empty() { format!(" ({missing} shard records missing)") } else { String::new() }
    );
    let mut pipelines: Vec<&str> = runs.iter().flatten().map(|r| r.pipeline.as_str()).collect();
    pipelines.sort_unstable();
    pipelines.dedup();
    let pipeline = match pipelines.as_slice() {
        [one] => crate::accumulate::Pipeline::parse(one).map_or("none (CPU path)", |p| p.name()),
        [] => "unrecorded",
        _ => "mixed",
    };
    let sum = |f: &dyn Fn(&ShardRun) -> Option<f64>| runs.iter().flatten().filter_map(f).sum::<f64>();
    let times = StageTimes {
        lightmap_passes: sum(&|r| Some(r.lightmap_passes_seconds)),
        probe_passes: runs.iter().flatten().any(|r| r.probe_passes_seconds.is_some()).then(|| sum(&|r| r.probe_passes_seconds)),
    };
    (device, pipeline, times)
}
