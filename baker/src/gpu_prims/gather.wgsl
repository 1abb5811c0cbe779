// Filtered gather-based accumulation (seed 004 §3.2.2, Listing 3.2): one thread per texel
// reads, through the offset buffer, the paths of every texel within `reach` texels whose
// chart is its own, weights each by the separable filter of its continuous position's
// offset from this texel's centre, and adds (Σ w·v, Σ w) to its accumulator. Texels of
// chart 0xffffffff (invalid) neither gather nor are gathered from. The neighbourhood is
// scanned row by row, left to right, paths in order — the CPU twin's order.

struct GatherParams {
    width: u32,
    height: u32,
    row: u32,
    // filter_kernel.wgsl's kernel code.
    kernel: u32,
    radius: f32,
    reach: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<storage, read> offsets: array<u32>;
@group(0) @binding(1) var<storage, read> positions: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> values: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> charts: array<u32>;
@group(0) @binding(4) var<storage, read_write> acc: array<vec4<f32>>;
@group(0) @binding(5) var<uniform> params: GatherParams;

const INVALID_CHART: u32 = 0xffffffffu;
const NO_PATH: u32 = 0xffffffffu;

@compute @workgroup_size(256)
fn gather(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let t = (wid.x + wid.y * params.row) * 256u + lid.x;
    if (t >= params.width * params.height) {
        return;
    }
    let chart = charts[t];
    if (chart == INVALID_CHART) {
        return;
    }
    let x = i32(t % params.width);
    let y = i32(t / params.width);
    let centre = vec2<f32>(f32(x) + 0.5, f32(y) + 0.5);
    let reach = i32(params.reach);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var ny = max(y - reach, 0); ny <= min(y + reach, i32(params.height) - 1); ny++) {
        for (var nx = max(x - reach, 0); nx <= min(x + reach, i32(params.width) - 1); nx++) {
            let n = u32(ny) * params.width + u32(nx);
            if (charts[n] != chart) {
                continue;
            }
            // The seed's reading of the offset buffer: no paths if either end is the
            // sentinel or the range is empty.
            let first = offsets[n];
            let next = offsets[n + 1u];
            if (first == NO_PATH || next == NO_PATH || first >= next) {
                continue;
            }
            for (var p = first; p < next; p++) {
                let d = positions[p] - centre;
                let w = filter_kernel_1d(params.kernel, params.radius, d.x) * filter_kernel_1d(params.kernel, params.radius, d.y);
                if (w != 0.0) {
                    sum += w * values[p].xyz;
                    weight += w;
                }
            }
        }
    }
    acc[t] += vec4<f32>(sum, weight);
}
