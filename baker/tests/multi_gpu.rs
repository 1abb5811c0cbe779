//! One bake on several GPUs (`baker::gpu::multi`): the item split, and the merged state
//! against the single-device bake — bit for bit, since every item's samples depend on
//! (item, pass) only — here with two and three logical devices on one adapter (lavapipe in
//! CI; the measurement on real GPUs is `baker/examples/multi_gpu_scaling.rs`).
//!
//! Mutations tried, each caught: the WGSL mapping without the device's block offset (every
//! device bakes the first device's blocks), the merge taking the first device's state for
//! every item, and a share one item short (the last item of a device keeps its zero state);
//! the dispatch's item offset ignored in `jobs.wgsl` (every chunk of a pass bakes the first
//! chunk's items) — caught by the chunked case ("lightmap, Megakernel, 2 devices, chunk 32:
//! moments differ").

mod common;
use baker::accumulate::{BakeConfig, BakeState, BasisId, Pipeline, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::gpu::multi::{owner, partition_block, MultiGpuBake};
use baker::gpu::GpuBake;
use baker::layout::lightmap::Lightmap;
use baker::scene;
use baker::scene::bvh::Bvh;
use common::gpu;

#[test]
fn partition_deals_every_item_once_in_balanced_shares() {
    for (items, n) in [(10_000usize, 2usize), (7_001, 3), (493_680, 2), (65, 2), (18, 3), (1, 2)] {
        let block = partition_block(items, n);
        assert!(block % 64 == 0 && (64..=4096).contains(&block), "{items} on {n}: block {block}");
        let mut share = vec![0usize; n];
        for i in 0..items {
            share[owner(i, block, n)] += 1;
        }
        assert_eq!(share.iter().sum::<usize>(), items);
        // Shares differ by at most one block.
        let (lo, hi) = (share.iter().min().unwrap(), share.iter().max().unwrap());
        assert!(hi - lo <= block, "{items} on {n}: shares {share:?} with blocks of {block}");
        if items >= 64 * 32 * n {
            assert!(items / block >= 32 * n - n, "{items} on {n}: only {} blocks", items / block);
        }
    }
}

fn same(a: &BakeState, b: &BakeState, what: &str) {
    assert_eq!(a.passes, b.passes, "{what}: passes");
    assert_eq!(a.moments, b.moments, "{what}: moments differ");
    for (x, y) in a.encoders.iter().flatten().zip(b.encoders.iter().flatten()) {
        assert_eq!(x.coefficients(), y.coefficients(), "{what}: encoders differ");
        assert_eq!(x.sample_count(), y.sample_count(), "{what}: encoder sample counts differ");
    }
}

/// Lightmap texels (SH L2 + AD 9, NNLS) and sphere probes (SH L2), on the megakernel and
/// the wavefront pipeline: 2 and 3 logical devices give the single-device state bit for
/// bit, with one dispatch per pass and with each pass split into several dispatches (a
/// chunk of 32 items: 2–18 per device and pass here); a guided bake is refused across
/// devices. The single-device reference runs one dispatch per pass on the same pipeline.
#[test]
fn merged_bakes_equal_the_single_device_bake() {
    let Some(_lease) = gpu() else { return };
    let gpus = shaders::gpu::Gpu::logical(3).unwrap();
    let scene = scene::cornell();
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, 6.0, 2).unwrap();
    let lightmap = Targets::lightmap(&lm);
    let probes = Targets::probes(&baker::layout::probes::probe_grid(&bvh, [6, 6, 6]));
    let tracer_of = || Tracer::new(&scene, &bvh, 3);
    for pipeline in [Pipeline::Megakernel, Pipeline::Wavefront] {
        for (targets, bases, what) in [(&lightmap, vec![BasisId::Sh2, BasisId::Ad9], "lightmap"), (&probes, vec![BasisId::Sh2], "probes")] {
            let cfg = BakeConfig { seed: 7, max_bounces: 3, bases, pipeline, ..Default::default() };
            let mut one = GpuBake::new(&gpus[0], &tracer_of(), targets, &cfg).unwrap();
            one.set_chunk(usize::MAX);
            one.run(6).unwrap();
            let reference = one.state().unwrap();
            for n in [2, 3] {
                for chunk in [usize::MAX, 32] {
                    let label = format!(
                        "{what}, {pipeline:?}, {n} devices, chunk {}",
                        if chunk == usize::MAX { "whole".to_string() } else { chunk.to_string() }
                    );
                    let mut multi = MultiGpuBake::new(&gpus[..n], &tracer_of, targets, &cfg).unwrap();
                    multi.set_chunk(chunk);
                    multi.run(4).unwrap();
                    multi.run(2).unwrap();
                    let dispatches: Vec<u64> = multi.devices().iter().map(|d| d.submissions()).collect();
                    println!("{label}: {} items: {multi:?}, dispatches per device {dispatches:?}", targets.items.len());
                    if chunk != usize::MAX {
                        assert!(
                            dispatches.iter().all(|d| *d > 6),
                            "{label}: a pass was not split ({dispatches:?} dispatches for 6 passes)"
                        );
                    }
                    same(&multi.state().unwrap(), &reference, &label);
                    // Each device baked its blocks and nothing else (the work is divided, not repeated).
                    for (di, d) in multi.devices().iter().enumerate() {
                        let st = d.state().unwrap();
                        for (k, m) in st.moments.iter().enumerate() {
                            let mine = owner(k, multi.block(), n) == di;
                            assert_eq!(d.owns(k), mine);
                            assert_eq!(m.accepted > 0, mine && reference.moments[k].accepted > 0, "{label}: item {k}, device {di}");
                        }
                    }
                }
            }
        }
    }
    let guided = BakeConfig {
        max_bounces: 2,
        bases: vec![BasisId::Sh2],
        solver: Solver::Ls,
        guiding: Some(baker::sampling::guiding::GuidingOptions { learn_passes: 4, guided_fraction: 0.5 }),
        ..Default::default()
    };
    let err = MultiGpuBake::new(&gpus[..2], &tracer_of, &lightmap, &guided).unwrap_err();
    assert!(err.contains("guiding"), "{err}");
}

/// A shard of a bake on several GPUs (`baker --shard I/N --gpus G`): device g of shard I
/// bakes the blocks b ≡ I + N·g (mod N·G) of the shard's dealing; the 3 shards, each on 2
/// logical devices, put together (each item from the shard that owns it) give the
/// single-device state bit for bit, and no shard bakes an item of another.
/// Mutation tried: `Partition::split` dealing device g the blocks b ≡ g (mod N·G) (the
/// shard's index dropped) — shards 1 and 2 bake shard 0's blocks: moments differ.
#[test]
fn shards_on_several_devices_put_together_equal_the_single_device_bake() {
    let Some(_lease) = gpu() else { return };
    let gpus = shaders::gpu::Gpu::logical(2).unwrap();
    let scene = scene::cornell();
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, 6.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let tracer_of = || Tracer::new(&scene, &bvh, 3);
    let cfg = BakeConfig { seed: 5, max_bounces: 3, bases: vec![BasisId::Sh2, BasisId::Ad9], ..Default::default() };
    let mut one = GpuBake::new(&gpus[0], &tracer_of(), &targets, &cfg).unwrap();
    one.set_chunk(usize::MAX);
    one.run(4).unwrap();
    let reference = one.state().unwrap();
    let n = 3;
    let mut merged = BakeState::new(&cfg, &targets);
    merged.passes = 4;
    for i in 0..n {
        let part = baker::accumulate::Partition::of(i, n, targets.items.len()).unwrap();
        let mut multi = MultiGpuBake::for_part(&gpus, &tracer_of, &targets, &cfg, part).unwrap();
        multi.set_chunk(usize::MAX);
        multi.run(4).unwrap();
        let st = multi.state().unwrap();
        for (k, m) in st.moments.iter().enumerate() {
            if part.owns(k) {
                merged.moments[k] = *m;
                for (e, f) in merged.encoders.iter_mut().zip(&st.encoders) {
                    e[k] = f[k].clone();
                }
            } else {
                assert_eq!(m.count(), 0, "shard {i} baked item {k} of another shard");
            }
        }
    }
    same(&merged, &reference, "3 shards × 2 devices");
}

/// Several passes per dispatch (each thread takes its item through them in order) give the
/// one-pass-per-dispatch bake bit for bit; a generous target makes the batching reach the
/// maximum passes per dispatch, and a call for fewer passes than that runs exactly those.
/// Mutation tried: `pass_index` not advanced inside the dispatch (every pass of a dispatch
/// repeats the first) — the states differ.
#[test]
fn several_passes_per_dispatch_give_the_identical_bake() {
    let Some(g) = gpu() else { return };
    let scene = scene::cornell();
    let bvh = Bvh::build(&scene);
    let lm = Lightmap::build(&scene, 4.0, 2).unwrap();
    let targets = Targets::lightmap(&lm);
    let cfg = BakeConfig { seed: 3, max_bounces: 2, bases: vec![BasisId::Sh2, BasisId::Sg9], solver: Solver::Ls, ..Default::default() };
    let run = |target: Option<f64>| {
        let mut b = GpuBake::new(&g, &Tracer::new(&scene, &bvh, cfg.max_bounces), &targets, &cfg).unwrap();
        match target {
            Some(t) => b.set_batch_target(Some(t)),
            None => b.set_chunk(usize::MAX),
        }
        b.run(29).unwrap();
        b.run(3).unwrap();
        (b.state().unwrap(), b.passes_per_dispatch())
    };
    let (one, k1) = run(None);
    let (many, k) = run(Some(1e3));
    assert_eq!(k1, 1);
    assert_eq!(k, baker::gpu::MAX_PASSES_PER_DISPATCH, "the batching did not grow the passes per dispatch");
    same(&many, &one, "8 passes per dispatch");
}
