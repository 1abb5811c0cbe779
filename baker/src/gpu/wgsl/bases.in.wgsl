// bases.wgsl — the bake's encoders (CPU twin: baker::accumulate's per-sample update with
// sbf's progressive encoders, [Roughton19 §7.3]): every configured basis is a slot k with its
// basis values `basis_k`, its encoder parameters `ENCODER_k` and the light samples' known
// projections `Q_k`; `encode` feeds a sample to every slot's encoder (with the mirrored
// zero twin where a sphere basis bakes a texel's hemisphere), `project` adds a light
// sample's projections. Shader defs (baker::gpu::kernel) say which kinds and slots a bake
// has: KIND_n (basis kind n used), SLOT_k = the kind of slot k, SLOT_k_LOBES, SLOT_k_FLAGS,
// SLOT_k_DENOMINATOR, SLOT_k_PROJECTION (the projection encoder of an orthonormal basis),
// SLOT_k_MIRROR, SLOT_k_AT (its first record plane, FILTERED); kinds are the registry's
// GPU slot kinds (sbf::registry::BasisInfo::gpu_kind): 0 sh1, 1 sh2, 2 sg9, 3 sg12, 4 ad9,
// 5 ad12, 6 zh3 (SH L1's coefficients; KIND_SH_L1 with 0 or 6). FILTERED adds the same
// updates on a gather target's states (filter_gather.wgsl).
//
// bases.in.wgsl is the template of bases.wgsl (baker::gpu::slots): each block between a
// `// @slots` line and a `// @end` line is written once per encoder slot k (MAX_SLOTS of
// them) with `{k}` replaced by k. The slots are spelled out (WGSL has no macros, and a
// loop over a run-time slot list would make each encoder's parameters run-time values
// instead of constants).

#define_import_path baker::bases

#import baker::bindings::{P, states}
#import sbf::runtime::{EncoderParams, EncoderState, progressive_update, progressive_update_projected}
#ifdef KIND_SH_L1
#import sbf::runtime::sh_eval_l1
#endif
#ifdef KIND_1
#import sbf::runtime::sh_eval_l2
#endif
#ifdef KIND_SG
#import sbf::runtime::sg_eval
#endif
#ifdef KIND_AD
#import sbf::runtime::ad_srbf_eval
#endif
#ifdef KIND_4
#import sbf::runtime::AD9_AXES
#endif
#ifdef KIND_5
#import sbf::runtime::AD12_AXES
#endif
#ifdef FILTERED
#import baker::filter_bindings::{FP, fsamples, fstates}
#endif

// Acceleration α of every encoder (baker::accumulate::BAKE_ACCELERATION; the kernel
// refuses another value).
const ACCELERATION: f32 = 1.0;

// The exact mean of B_i² of a basis orthonormal over the sphere (1/4π): the true means of
// a slot whose encoder is the projection (SLOT_k_PROJECTION; the kernel refuses others).
const ORTHONORMAL_MEAN: array<vec4<f32>, 3> = array<vec4<f32>, 3>(vec4<f32>(0.07957747), vec4<f32>(0.07957747), vec4<f32>(0.07957747));

// The hemisphere SG lobes (sbf::layout::vogel_hemisphere, as f32; a test holds them to
// the CPU's) and their sharpness, the bake's (BakeConfig::sg_sharpness) as f32 bits (a
// constant the driver folds).
fn sg_sharpness() -> f32 {
    return bitcast<f32>(#{SG_SHARPNESS_BITS}u);
}
#ifdef KIND_2
const SG9_AXES: array<vec3<f32>, 9> = array<vec3<f32>, 9>(
    vec3<f32>(0.3286711, 0.0, 0.9444444),
    vec3<f32>(-0.407596, 0.3733913, 0.8333333),
    vec3<f32>(0.06046897, -0.68901277, 0.7222222),
    vec3<f32>(0.48160663, 0.62817055, 0.6111111),
    vec3<f32>(-0.8527869, -0.15084599, 0.5),
    vec3<f32>(0.7773388, -0.49447933, 0.3888889),
    vec3<f32>(-0.24938767, 0.9277097, 0.2777778),
    vec3<f32>(-0.45446044, -0.87503594, 0.16666667),
    vec3<f32>(0.9378706, 0.34250885, 0.055555556),
);
#endif
#ifdef KIND_3
const SG12_AXES: array<vec3<f32>, 12> = array<vec3<f32>, 12>(
    vec3<f32>(0.28565228, 0.0, 0.9583333),
    vec3<f32>(-0.35697716, 0.32702035, 0.875),
    vec3<f32>(0.053413033, -0.60861397, 0.7916667),
    vec3<f32>(0.42948365, 0.5601854, 0.7083333),
    vec3<f32>(-0.7686917, -0.13597074, 0.625),
    vec3<f32>(0.7092551, -0.45117006, 0.5416667),
    vec3<f32>(-0.2307312, 0.8583086, 0.45833334),
    vec3<f32>(-0.42727226, -0.82268673, 0.375),
    vec3<f32>(0.89847964, 0.32812333, 0.29166666),
    vec3<f32>(-0.90406346, 0.37318426, 0.20833333),
    vec3<f32>(0.42052165, -0.8986304, 0.125),
    vec3<f32>(0.29902396, 0.95333546, 0.041666668),
);
#endif
#ifdef KIND_SH_L1
// SH L1's four basis values (sh1 and zh3 store the same coefficients)
fn sh_l1_values(d: vec3<f32>) -> array<f32, 12> {
    var b: array<f32, 12>;
    let v = sh_eval_l1(d);
    for (var i = 0u; i < 4u; i++) {
        b[i] = v[i];
    }
    return b;
}
#endif
#ifdef KIND_0
// sh1 (4 lobes)
fn basis_kind_0(d: vec3<f32>) -> array<f32, 12> {
    return sh_l1_values(d);
}
#endif
#ifdef KIND_6
// zh3 (SH L1's 4 lobes, reconstructed with ZH3 at run time)
fn basis_kind_6(d: vec3<f32>) -> array<f32, 12> {
    return sh_l1_values(d);
}
#endif
#ifdef KIND_1
// sh2 (9 lobes)
fn basis_kind_1(d: vec3<f32>) -> array<f32, 12> {
    var b: array<f32, 12>;
    let v = sh_eval_l2(d);
    for (var i = 0u; i < 9u; i++) {
        b[i] = v[i];
    }
    return b;
}
#endif
#ifdef KIND_2
// sg9 (9 lobes)
fn basis_kind_2(d: vec3<f32>) -> array<f32, 12> {
    var b: array<f32, 12>;
    for (var i = 0u; i < 9u; i++) {
        b[i] = sg_eval(SG9_AXES[i], sg_sharpness(), d);
    }
    return b;
}
#endif
#ifdef KIND_3
// sg12 (12 lobes)
fn basis_kind_3(d: vec3<f32>) -> array<f32, 12> {
    var b: array<f32, 12>;
    for (var i = 0u; i < 12u; i++) {
        b[i] = sg_eval(SG12_AXES[i], sg_sharpness(), d);
    }
    return b;
}
#endif
#ifdef KIND_4
// ad9 (9 lobes)
fn basis_kind_4(d: vec3<f32>) -> array<f32, 12> {
    var b: array<f32, 12>;
    for (var i = 0u; i < 9u; i++) {
        b[i] = ad_srbf_eval(AD9_AXES[i], d);
    }
    return b;
}
#endif
#ifdef KIND_5
// ad12 (12 lobes)
fn basis_kind_5(d: vec3<f32>) -> array<f32, 12> {
    var b: array<f32, 12>;
    for (var i = 0u; i < 12u; i++) {
        b[i] = ad_srbf_eval(AD12_AXES[i], d);
    }
    return b;
}
#endif
// @slots
#ifdef SLOT_{k}
fn basis_{k}(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_{k}}(d);
}
#ifdef SLOT_{k}_PROJECTION
const ENCODER_{k}: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_{k}_LOBES}u, #{SLOT_{k}_FLAGS}u, #{SLOT_{k}_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_{k}: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_{k}_LOBES}u, #{SLOT_{k}_FLAGS}u, #{SLOT_{k}_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_{k}: array<vec3<f32>, 12>;
#endif
// @end
// A sample (direction d in the item's frame, radiance l, encoder weight w) into every
// slot's encoder of item `out`.
fn encode(out: u32, d: vec3<f32>, l: vec3<f32>, w: f32) {
    let md = vec3<f32>(d.x, d.y, -d.z);
// @slots
#ifdef SLOT_{k}
    {
        let s = {k}u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_{k}, basis_{k}(d), l, w, Q_{k});
#ifdef SLOT_{k}_MIRROR
        progressive_update(&st, ENCODER_{k}, basis_{k}(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
// @end
}

// A light sample's known projections (sbf update_projected): Q_k[i] += B_i(ω_l)·c.
fn project(d: vec3<f32>, c: vec3<f32>) {
// @slots
#ifdef SLOT_{k}
    {
        let b = basis_{k}(d);
        for (var i = 0u; i < #{SLOT_{k}_LOBES}u; i++) {
            Q_{k}[i] += b[i] * c;
        }
    }
#endif
// @end
}

// The projections start at zero for every pass of an item (a dispatch may run several).
fn project_reset() {
// @slots
#ifdef SLOT_{k}
    Q_{k} = array<vec3<f32>, 12>();
#endif
// @end
}

#ifdef FILTERED
// Filtered accumulation: a gather target's states stay in private variables while it
// gathers (filter_gather.wgsl loads and stores them once per dispatch).
// @slots
#ifdef SLOT_{k}
var<private> FST_{k}: EncoderState;
#endif
// @end

fn filtered_load(out: u32) {
// @slots
#ifdef SLOT_{k}
    FST_{k} = fstates[{k}u * FP.target_count + out];
#endif
// @end
}

fn filtered_store(out: u32) {
// @slots
#ifdef SLOT_{k}
    fstates[{k}u * FP.target_count + out] = FST_{k};
#endif
// @end
}

// The encoders' update on the gather target's states.
fn encode_filtered(d: vec3<f32>, l: vec3<f32>, w: f32) {
    let md = vec3<f32>(d.x, d.y, -d.z);
// @slots
#ifdef SLOT_{k}
    {
        var st = FST_{k};
        progressive_update_projected(&st, ENCODER_{k}, basis_{k}(d), l, w, Q_{k});
#ifdef SLOT_{k}_MIRROR
        progressive_update(&st, ENCODER_{k}, basis_{k}(md), vec3<f32>(0.0), w);
#endif
        FST_{k} = st;
    }
#endif
// @end
}

// The known projections Q_k to and from a record: 3 vec4 of header, then per slot its
// lobes, each a plane of the component-major record buffer.
fn filter_store_q(at: u32, plane: u32) {
// @slots
#ifdef SLOT_{k}
    for (var i = 0u; i < #{SLOT_{k}_LOBES}u; i++) {
        fsamples[at + (#{SLOT_{k}_AT}u + i) * plane] = vec4<f32>(Q_{k}[i], 0.0);
    }
#endif
// @end
}

fn filter_load_q(at: u32, plane: u32) {
// @slots
#ifdef SLOT_{k}
    for (var i = 0u; i < #{SLOT_{k}_LOBES}u; i++) {
        Q_{k}[i] = fsamples[at + (#{SLOT_{k}_AT}u + i) * plane].xyz;
    }
#endif
// @end
}
#endif
