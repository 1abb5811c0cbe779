// Generated from bases.in.wgsl by baker::gpu::slots, one block per encoder slot:
// do not edit; change the template and run `SBF_BLESS=1 cargo test -p baker --test bases_template`.
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
#ifdef SLOT_0
fn basis_0(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_0}(d);
}
#ifdef SLOT_0_PROJECTION
const ENCODER_0: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_0_LOBES}u, #{SLOT_0_FLAGS}u, #{SLOT_0_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_0: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_0_LOBES}u, #{SLOT_0_FLAGS}u, #{SLOT_0_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_0: array<vec3<f32>, 12>;
#endif
#ifdef SLOT_1
fn basis_1(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_1}(d);
}
#ifdef SLOT_1_PROJECTION
const ENCODER_1: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_1_LOBES}u, #{SLOT_1_FLAGS}u, #{SLOT_1_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_1: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_1_LOBES}u, #{SLOT_1_FLAGS}u, #{SLOT_1_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_1: array<vec3<f32>, 12>;
#endif
#ifdef SLOT_2
fn basis_2(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_2}(d);
}
#ifdef SLOT_2_PROJECTION
const ENCODER_2: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_2_LOBES}u, #{SLOT_2_FLAGS}u, #{SLOT_2_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_2: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_2_LOBES}u, #{SLOT_2_FLAGS}u, #{SLOT_2_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_2: array<vec3<f32>, 12>;
#endif
#ifdef SLOT_3
fn basis_3(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_3}(d);
}
#ifdef SLOT_3_PROJECTION
const ENCODER_3: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_3_LOBES}u, #{SLOT_3_FLAGS}u, #{SLOT_3_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_3: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_3_LOBES}u, #{SLOT_3_FLAGS}u, #{SLOT_3_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_3: array<vec3<f32>, 12>;
#endif
#ifdef SLOT_4
fn basis_4(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_4}(d);
}
#ifdef SLOT_4_PROJECTION
const ENCODER_4: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_4_LOBES}u, #{SLOT_4_FLAGS}u, #{SLOT_4_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_4: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_4_LOBES}u, #{SLOT_4_FLAGS}u, #{SLOT_4_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_4: array<vec3<f32>, 12>;
#endif
#ifdef SLOT_5
fn basis_5(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_5}(d);
}
#ifdef SLOT_5_PROJECTION
const ENCODER_5: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_5_LOBES}u, #{SLOT_5_FLAGS}u, #{SLOT_5_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_5: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_5_LOBES}u, #{SLOT_5_FLAGS}u, #{SLOT_5_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_5: array<vec3<f32>, 12>;
#endif
#ifdef SLOT_6
fn basis_6(d: vec3<f32>) -> array<f32, 12> {
    return basis_kind_#{SLOT_6}(d);
}
#ifdef SLOT_6_PROJECTION
const ENCODER_6: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_6_LOBES}u, #{SLOT_6_FLAGS}u, #{SLOT_6_DENOMINATOR}u, ORTHONORMAL_MEAN);
#else
const ENCODER_6: EncoderParams = EncoderParams(ACCELERATION, #{SLOT_6_LOBES}u, #{SLOT_6_FLAGS}u, #{SLOT_6_DENOMINATOR}u, array<vec4<f32>, 3>());
#endif
var<private> Q_6: array<vec3<f32>, 12>;
#endif
// A sample (direction d in the item's frame, radiance l, encoder weight w) into every
// slot's encoder of item `out`.
fn encode(out: u32, d: vec3<f32>, l: vec3<f32>, w: f32) {
    let md = vec3<f32>(d.x, d.y, -d.z);
#ifdef SLOT_0
    {
        let s = 0u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_0, basis_0(d), l, w, Q_0);
#ifdef SLOT_0_MIRROR
        progressive_update(&st, ENCODER_0, basis_0(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
#ifdef SLOT_1
    {
        let s = 1u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_1, basis_1(d), l, w, Q_1);
#ifdef SLOT_1_MIRROR
        progressive_update(&st, ENCODER_1, basis_1(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
#ifdef SLOT_2
    {
        let s = 2u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_2, basis_2(d), l, w, Q_2);
#ifdef SLOT_2_MIRROR
        progressive_update(&st, ENCODER_2, basis_2(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
#ifdef SLOT_3
    {
        let s = 3u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_3, basis_3(d), l, w, Q_3);
#ifdef SLOT_3_MIRROR
        progressive_update(&st, ENCODER_3, basis_3(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
#ifdef SLOT_4
    {
        let s = 4u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_4, basis_4(d), l, w, Q_4);
#ifdef SLOT_4_MIRROR
        progressive_update(&st, ENCODER_4, basis_4(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
#ifdef SLOT_5
    {
        let s = 5u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_5, basis_5(d), l, w, Q_5);
#ifdef SLOT_5_MIRROR
        progressive_update(&st, ENCODER_5, basis_5(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
#ifdef SLOT_6
    {
        let s = 6u * P.item_count + out;
        var st = states[s];
        progressive_update_projected(&st, ENCODER_6, basis_6(d), l, w, Q_6);
#ifdef SLOT_6_MIRROR
        progressive_update(&st, ENCODER_6, basis_6(md), vec3<f32>(0.0), w);
#endif
        states[s] = st;
    }
#endif
}

// A light sample's known projections (sbf update_projected): Q_k[i] += B_i(ω_l)·c.
fn project(d: vec3<f32>, c: vec3<f32>) {
#ifdef SLOT_0
    {
        let b = basis_0(d);
        for (var i = 0u; i < #{SLOT_0_LOBES}u; i++) {
            Q_0[i] += b[i] * c;
        }
    }
#endif
#ifdef SLOT_1
    {
        let b = basis_1(d);
        for (var i = 0u; i < #{SLOT_1_LOBES}u; i++) {
            Q_1[i] += b[i] * c;
        }
    }
#endif
#ifdef SLOT_2
    {
        let b = basis_2(d);
        for (var i = 0u; i < #{SLOT_2_LOBES}u; i++) {
            Q_2[i] += b[i] * c;
        }
    }
#endif
#ifdef SLOT_3
    {
        let b = basis_3(d);
        for (var i = 0u; i < #{SLOT_3_LOBES}u; i++) {
            Q_3[i] += b[i] * c;
        }
    }
#endif
#ifdef SLOT_4
    {
        let b = basis_4(d);
        for (var i = 0u; i < #{SLOT_4_LOBES}u; i++) {
            Q_4[i] += b[i] * c;
        }
    }
#endif
#ifdef SLOT_5
    {
        let b = basis_5(d);
        for (var i = 0u; i < #{SLOT_5_LOBES}u; i++) {
            Q_5[i] += b[i] * c;
        }
    }
#endif
#ifdef SLOT_6
    {
        let b = basis_6(d);
        for (var i = 0u; i < #{SLOT_6_LOBES}u; i++) {
            Q_6[i] += b[i] * c;
        }
    }
#endif
}

// The projections start at zero for every pass of an item (a dispatch may run several).
fn project_reset() {
#ifdef SLOT_0
    Q_0 = array<vec3<f32>, 12>();
#endif
#ifdef SLOT_1
    Q_1 = array<vec3<f32>, 12>();
#endif
#ifdef SLOT_2
    Q_2 = array<vec3<f32>, 12>();
#endif
#ifdef SLOT_3
    Q_3 = array<vec3<f32>, 12>();
#endif
#ifdef SLOT_4
    Q_4 = array<vec3<f32>, 12>();
#endif
#ifdef SLOT_5
    Q_5 = array<vec3<f32>, 12>();
#endif
#ifdef SLOT_6
    Q_6 = array<vec3<f32>, 12>();
#endif
}

#ifdef FILTERED
// Filtered accumulation: a gather target's states stay in private variables while it
// gathers (filter_gather.wgsl loads and stores them once per dispatch).
#ifdef SLOT_0
var<private> FST_0: EncoderState;
#endif
#ifdef SLOT_1
var<private> FST_1: EncoderState;
#endif
#ifdef SLOT_2
var<private> FST_2: EncoderState;
#endif
#ifdef SLOT_3
var<private> FST_3: EncoderState;
#endif
#ifdef SLOT_4
var<private> FST_4: EncoderState;
#endif
#ifdef SLOT_5
var<private> FST_5: EncoderState;
#endif
#ifdef SLOT_6
var<private> FST_6: EncoderState;
#endif

fn filtered_load(out: u32) {
#ifdef SLOT_0
    FST_0 = fstates[0u * FP.target_count + out];
#endif
#ifdef SLOT_1
    FST_1 = fstates[1u * FP.target_count + out];
#endif
#ifdef SLOT_2
    FST_2 = fstates[2u * FP.target_count + out];
#endif
#ifdef SLOT_3
    FST_3 = fstates[3u * FP.target_count + out];
#endif
#ifdef SLOT_4
    FST_4 = fstates[4u * FP.target_count + out];
#endif
#ifdef SLOT_5
    FST_5 = fstates[5u * FP.target_count + out];
#endif
#ifdef SLOT_6
    FST_6 = fstates[6u * FP.target_count + out];
#endif
}

fn filtered_store(out: u32) {
#ifdef SLOT_0
    fstates[0u * FP.target_count + out] = FST_0;
#endif
#ifdef SLOT_1
    fstates[1u * FP.target_count + out] = FST_1;
#endif
#ifdef SLOT_2
    fstates[2u * FP.target_count + out] = FST_2;
#endif
#ifdef SLOT_3
    fstates[3u * FP.target_count + out] = FST_3;
#endif
#ifdef SLOT_4
    fstates[4u * FP.target_count + out] = FST_4;
#endif
#ifdef SLOT_5
    fstates[5u * FP.target_count + out] = FST_5;
#endif
#ifdef SLOT_6
    fstates[6u * FP.target_count + out] = FST_6;
#endif
}

// The encoders' update on the gather target's states.
fn encode_filtered(d: vec3<f32>, l: vec3<f32>, w: f32) {
    let md = vec3<f32>(d.x, d.y, -d.z);
#ifdef SLOT_0
    {
        var st = FST_0;
        progressive_update_projected(&st, ENCODER_0, basis_0(d), l, w, Q_0);
#ifdef SLOT_0_MIRROR
        progressive_update(&st, ENCODER_0, basis_0(md), vec3<f32>(0.0), w);
#endif
        FST_0 = st;
    }
#endif
#ifdef SLOT_1
    {
        var st = FST_1;
        progressive_update_projected(&st, ENCODER_1, basis_1(d), l, w, Q_1);
#ifdef SLOT_1_MIRROR
        progressive_update(&st, ENCODER_1, basis_1(md), vec3<f32>(0.0), w);
#endif
        FST_1 = st;
    }
#endif
#ifdef SLOT_2
    {
        var st = FST_2;
        progressive_update_projected(&st, ENCODER_2, basis_2(d), l, w, Q_2);
#ifdef SLOT_2_MIRROR
        progressive_update(&st, ENCODER_2, basis_2(md), vec3<f32>(0.0), w);
#endif
        FST_2 = st;
    }
#endif
#ifdef SLOT_3
    {
        var st = FST_3;
        progressive_update_projected(&st, ENCODER_3, basis_3(d), l, w, Q_3);
#ifdef SLOT_3_MIRROR
        progressive_update(&st, ENCODER_3, basis_3(md), vec3<f32>(0.0), w);
#endif
        FST_3 = st;
    }
#endif
#ifdef SLOT_4
    {
        var st = FST_4;
        progressive_update_projected(&st, ENCODER_4, basis_4(d), l, w, Q_4);
#ifdef SLOT_4_MIRROR
        progressive_update(&st, ENCODER_4, basis_4(md), vec3<f32>(0.0), w);
#endif
        FST_4 = st;
    }
#endif
#ifdef SLOT_5
    {
        var st = FST_5;
        progressive_update_projected(&st, ENCODER_5, basis_5(d), l, w, Q_5);
#ifdef SLOT_5_MIRROR
        progressive_update(&st, ENCODER_5, basis_5(md), vec3<f32>(0.0), w);
#endif
        FST_5 = st;
    }
#endif
#ifdef SLOT_6
    {
        var st = FST_6;
        progressive_update_projected(&st, ENCODER_6, basis_6(d), l, w, Q_6);
#ifdef SLOT_6_MIRROR
        progressive_update(&st, ENCODER_6, basis_6(md), vec3<f32>(0.0), w);
#endif
        FST_6 = st;
    }
#endif
}

// The known projections Q_k to and from a record: 3 vec4 of header, then per slot its
// lobes, each a plane of the component-major record buffer.
fn filter_store_q(at: u32, plane: u32) {
#ifdef SLOT_0
    for (var i = 0u; i < #{SLOT_0_LOBES}u; i++) {
        fsamples[at + (#{SLOT_0_AT}u + i) * plane] = vec4<f32>(Q_0[i], 0.0);
    }
#endif
#ifdef SLOT_1
    for (var i = 0u; i < #{SLOT_1_LOBES}u; i++) {
        fsamples[at + (#{SLOT_1_AT}u + i) * plane] = vec4<f32>(Q_1[i], 0.0);
    }
#endif
#ifdef SLOT_2
    for (var i = 0u; i < #{SLOT_2_LOBES}u; i++) {
        fsamples[at + (#{SLOT_2_AT}u + i) * plane] = vec4<f32>(Q_2[i], 0.0);
    }
#endif
#ifdef SLOT_3
    for (var i = 0u; i < #{SLOT_3_LOBES}u; i++) {
        fsamples[at + (#{SLOT_3_AT}u + i) * plane] = vec4<f32>(Q_3[i], 0.0);
    }
#endif
#ifdef SLOT_4
    for (var i = 0u; i < #{SLOT_4_LOBES}u; i++) {
        fsamples[at + (#{SLOT_4_AT}u + i) * plane] = vec4<f32>(Q_4[i], 0.0);
    }
#endif
#ifdef SLOT_5
    for (var i = 0u; i < #{SLOT_5_LOBES}u; i++) {
        fsamples[at + (#{SLOT_5_AT}u + i) * plane] = vec4<f32>(Q_5[i], 0.0);
    }
#endif
#ifdef SLOT_6
    for (var i = 0u; i < #{SLOT_6_LOBES}u; i++) {
        fsamples[at + (#{SLOT_6_AT}u + i) * plane] = vec4<f32>(Q_6[i], 0.0);
    }
#endif
}

fn filter_load_q(at: u32, plane: u32) {
#ifdef SLOT_0
    for (var i = 0u; i < #{SLOT_0_LOBES}u; i++) {
        Q_0[i] = fsamples[at + (#{SLOT_0_AT}u + i) * plane].xyz;
    }
#endif
#ifdef SLOT_1
    for (var i = 0u; i < #{SLOT_1_LOBES}u; i++) {
        Q_1[i] = fsamples[at + (#{SLOT_1_AT}u + i) * plane].xyz;
    }
#endif
#ifdef SLOT_2
    for (var i = 0u; i < #{SLOT_2_LOBES}u; i++) {
        Q_2[i] = fsamples[at + (#{SLOT_2_AT}u + i) * plane].xyz;
    }
#endif
#ifdef SLOT_3
    for (var i = 0u; i < #{SLOT_3_LOBES}u; i++) {
        Q_3[i] = fsamples[at + (#{SLOT_3_AT}u + i) * plane].xyz;
    }
#endif
#ifdef SLOT_4
    for (var i = 0u; i < #{SLOT_4_LOBES}u; i++) {
        Q_4[i] = fsamples[at + (#{SLOT_4_AT}u + i) * plane].xyz;
    }
#endif
#ifdef SLOT_5
    for (var i = 0u; i < #{SLOT_5_LOBES}u; i++) {
        Q_5[i] = fsamples[at + (#{SLOT_5_AT}u + i) * plane].xyz;
    }
#endif
#ifdef SLOT_6
    for (var i = 0u; i < #{SLOT_6_LOBES}u; i++) {
        Q_6[i] = fsamples[at + (#{SLOT_6_AT}u + i) * plane].xyz;
    }
#endif
}
#endif
