// progressive.wgsl — progressive (per-sample) least squares and NNLS ([Roughton19 §7.3],
// Listing 7.1, with eq. 7.15's denominator). One call adds one radiance sample with its
// precomputed basis values b (the caller evaluates its basis; a hemisphere-mirrored
// solve calls again with the mirrored direction's values and a zero value).
// Per sample, with W the running weight and s = w/W:
//   Δ = f − Σ_j a_j b_j;  I_i ← I_i + s(b_i² − I_i);  Ī_i = s + (1 − s)·I_i (blend),
//   max(I_i, exact mean of B_i²) (running average) or I_i (raw);
//   a_i ← a_i + α·s·b_i·Δ/Ī_i (then max(a_i, 0) for NNLS); Gauss–Seidel also updates
//   Δ ← Δ − b_i·(a_i,new − a_i,old) after each lobe, Jacobi keeps the first Δ.
// Samples with weight ≤ 0 (or NaN) are ignored; values must be finite (the caller's
// check: a GPU cannot report an error from here).
// progressive_update_projected also takes known projections q (one RGB vector per lobe:
// p(ω)·E·B_i(ω_l) for a delta light, or an MIS-weighted light sample) and moves lobe i by
// α·s·(b_i·Δ + q_i)/Ī_i (sbf::solve::progressive's module documentation).
// CPU twins: sbf::solve::ProgressiveEncoder<f32>::update and ::update_projected. The two structs are shared
// with Rust (shaders::progressive, #[repr(C)] + bytemuck, layout checked against naga).

const ENCODER_MAX_LOBES: u32 = 12u;
const ENCODER_NON_NEGATIVE: u32 = 1u;
const ENCODER_GAUSS_SEIDEL: u32 = 2u;
const ENCODER_DENOM_BLEND: u32 = 0u;
const ENCODER_DENOM_CLAMP_TO_TRUE: u32 = 1u;
const ENCODER_DENOM_RAW: u32 = 2u;
// No residual: the amplitude is the running mean of (B_i·value + q_i)/true_mean_i (sbf's
// Denominator::Projection; unbiased for a basis orthogonal over the sampled measure).
const ENCODER_DENOM_PROJECTION: u32 = 3u;

// Encoder options (uniform or storage).
struct EncoderParams {
    acceleration: f32,
    lobes: u32,
    // ENCODER_NON_NEGATIVE | ENCODER_GAUSS_SEIDEL
    flags: u32,
    // ENCODER_DENOM_*
    denominator: u32,
    // For ENCODER_DENOM_CLAMP_TO_TRUE and _PROJECTION: the exact mean of B_i² (lobe i at
    // [i / 4][i % 4]).
    true_mean: array<vec4<f32>, 3>,
}

// One texel's encoder state: per lobe the RGB amplitude (xyz) and the running mean of
// B_i² (w), the total weight and the number of updates.
struct EncoderState {
    lobes: array<vec4<f32>, 12>,
    total_weight: f32,
    samples: u32,
}

// One progressive-fit step ([Roughton19 §7.3]): adds sample `value` (RGB radiance) with weight
// `weight` whose basis functions at the sample direction are b (the first p.lobes used) to
// `state`, under the update rule and clamping that `p` selects. The host keeps `state`
// per texel or probe between samples.
fn progressive_update(state: ptr<function, EncoderState>, p: EncoderParams, b: array<f32, 12>, value: vec3<f32>, weight: f32) {
    var q: array<vec3<f32>, 12>;
    progressive_update_projected(state, p, b, value, weight, q);
}

fn progressive_update_projected(
    state: ptr<function, EncoderState>,
    p: EncoderParams,
    b: array<f32, 12>,
    value: vec3<f32>,
    weight: f32,
    q: array<vec3<f32>, 12>,
) {
    if (!(weight > 0.0)) {
        return;
    }
    let n = min(p.lobes, ENCODER_MAX_LOBES);
    (*state).samples += 1u;
    (*state).total_weight += weight;
    let s = weight / (*state).total_weight;
    var delta = value;
    for (var i = 0u; i < n; i++) {
        delta -= (*state).lobes[i].xyz * b[i];
    }
    for (var i = 0u; i < n; i++) {
        let bi = b[i];
        var lobe = (*state).lobes[i];
        lobe.w = lobe.w + s * (bi * bi - lobe.w);
        if (p.denominator == ENCODER_DENOM_PROJECTION) {
            var amp = lobe.xyz + s * ((bi * value + q[i]) / p.true_mean[i / 4u][i % 4u] - lobe.xyz);
            if ((p.flags & ENCODER_NON_NEGATIVE) != 0u) {
                amp = max(amp, vec3<f32>(0.0));
            }
            (*state).lobes[i] = vec4<f32>(amp, lobe.w);
            continue;
        }
        var denom: f32;
        switch p.denominator {
            case ENCODER_DENOM_CLAMP_TO_TRUE: {
                denom = max(lobe.w, p.true_mean[i / 4u][i % 4u]);
            }
            case ENCODER_DENOM_RAW: {
                denom = lobe.w;
            }
            case ENCODER_DENOM_BLEND, default: {
                denom = s + (1.0 - s) * lobe.w;
            }
        }
        // denom ≤ 0: B_i has been zero on every sample so far; the amplitude stays.
        if (denom > 0.0) {
            let scale = p.acceleration * s / denom;
            let old = lobe.xyz;
            var amp = old + scale * (bi * delta + q[i]);
            if ((p.flags & ENCODER_NON_NEGATIVE) != 0u) {
                amp = max(amp, vec3<f32>(0.0));
            }
            lobe = vec4<f32>(amp, lobe.w);
            if ((p.flags & ENCODER_GAUSS_SEIDEL) != 0u) {
                delta -= bi * (amp - old);
            }
        }
        (*state).lobes[i] = lobe;
    }
}
