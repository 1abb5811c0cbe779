// wave.wgsl — the wavefront's buffers (group 1) and what every pass shares.
// A wave: the jobs of one dispatch range, each job's samples one path in a slot of the
// path pool.

#define_import_path baker::wave

#import baker::path::PathState

// Per slot: the path's state between its segments, its last segment's hit (t as bits,
// triangle), and its sampler (key, sample index).
@group(1) @binding(0) var<storage, read_write> paths: array<PathState>;
@group(1) @binding(1) var<storage, read_write> hits: array<vec2<u32>>;
@group(1) @binding(2) var<storage, read_write> path_keys: array<vec2<u32>>;
// This bounce's active slots (its first `wave[WAVE_LENGTH]` entries); the other queue of
// the ping-pong pair is the compaction's output and is not bound here.
@group(1) @binding(3) var<storage, read_write> queue: array<u32>;
// Per queue position: 1 where the path goes on after shading (the compaction's flags).
@group(1) @binding(4) var<storage, read_write> path_flags: array<u32>;
// [WAVE_LENGTH] the queue's length, [WAVE_SLOTS] slots taken by generate, [WAVE_OVERFLOW]
// samples that found the pool full (an error on the host; the pool is sized so that it
// cannot happen).
@group(1) @binding(5) var<storage, read_write> wave: array<atomic<u32>, 4>;
// Per job position of the dispatch: (item, first sample index, samples, first slot).
@group(1) @binding(6) var<storage, read_write> jobs: array<vec4<u32>>;
// The indirect arguments of the queue's passes (written by wave_args only).
@group(1) @binding(7) var<storage, read_write> wave_args: array<u32, 3>;

const WAVE_LENGTH: u32 = 0u;
const WAVE_SLOTS: u32 = 1u;
const WAVE_OVERFLOW: u32 = 2u;
const WG_ROW: u32 = 65535u;
// A path that never left its baked point (below the surface's horizon): nothing to trace.
const PATH_DONE: u32 = 4u;

fn flat_id(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return gid.x + gid.y * nwg.x * 64u;
}

// Indirect arguments (2D, ≤ 65 535 workgroups per row) for the queue's length.
fn write_wave_args() {
    let groups = (atomicLoad(&wave[WAVE_LENGTH]) + 63u) / 64u;
    let x = min(groups, WG_ROW);
    wave_args[0] = max(x, 1u);
    wave_args[1] = select((groups + x - 1u) / max(x, 1u), 0u, groups == 0u);
    wave_args[2] = 1u;
}
