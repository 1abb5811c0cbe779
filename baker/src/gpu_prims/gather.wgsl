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
    // 0 box, 1 Gaussian (σ = radius/2, shifted to 0 at the radius), 2 Mitchell–Netravali
    // (B = C = 1/3) over [−radius, radius].
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

fn filter_1d(d: f32) -> f32 {
    let r = params.radius;
    let a = abs(d);
    switch params.kernel {
        case 0u: {
            return select(0.0, 1.0, a < r);
        }
        case 1u: {
            let s2 = 2.0 * (0.5 * r) * (0.5 * r);
            return max(exp(-d * d / s2) - exp(-r * r / s2), 0.0);
        }
        default: {
            let x = 2.0 * a / r;
            let b = 1.0 / 3.0;
            let c = 1.0 / 3.0;
            if (x < 1.0) {
                return ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)) / 6.0;
            }
            if (x < 2.0) {
                return ((-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)) / 6.0;
            }
            return 0.0;
        }
    }
}

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
                let w = filter_1d(d.x) * filter_1d(d.y);
                if (w != 0.0) {
                    sum += w * values[p].xyz;
                    weight += w;
                }
            }
        }
    }
    acc[t] += vec4<f32>(sum, weight);
}
