#define_import_path baker::guide

#import baker::bindings::P
#import sbf::runtime::{INV_PI, PI}

// ---- first-bounce ray guiding (baker::guiding; [HWRTL]) ----
// Bindings of the guided bake: per item three learning records of this pass (point
// sample, emitter sample, environment sample: bin and bits of the value; bin 0xffffffff:
// none) and per cluster the CDFs (256 conditional, row-major, then 16 marginal; built by
// guide_build.wgsl).
@group(0) @binding(9) var<storage, read_write> guide_rec: array<vec2<u32>>;
@group(0) @binding(10) var<storage, read> guide_dist: array<f32>;

// The share of point samples drawn from the learned distributions
// (baker::sampling::guiding::GuidingOptions::guided_fraction), the shader def
// GUIDED_FRACTION_BITS as f32 bits (a constant the driver folds).
fn guided_fraction() -> f32 {
    return bitcast<f32>(#{GUIDED_FRACTION_BITS}u);
}

const GUIDE_BINS: u32 = 16u;
const GUIDE_CDF_LEN: u32 = 272u;
const GUIDE_NONE: u32 = 0xffffffffu;
const GUIDE_RECORDS: u32 = 3u;

// Shirley–Chiu concentric map [0,1)² → unit disk (sbf::sampling::concentric_disk).
fn guide_disk(u: vec2<f32>) -> vec2<f32> {
    let a = 2.0 * u.x - 1.0;
    let b = 2.0 * u.y - 1.0;
    if (a == 0.0 && b == 0.0) {
        return vec2<f32>(0.0);
    }
    var r: f32;
    var t: f32;
    if (abs(a) > abs(b)) {
        r = a;
        t = 0.25 * PI * (b / a);
    } else {
        r = b;
        t = 0.5 * PI - 0.25 * PI * (a / b);
    }
    return r * vec2<f32>(cos(t), sin(t));
}

// Its inverse: in the wedge |x| ≥ |y|, a = sign(x)·r and b = a·atan(y/x)/(π/4); in the
// other, b = sign(y)·r and a = b·atan(x/y)/(π/4).
fn guide_disk_inv(p: vec2<f32>) -> vec2<f32> {
    let r = length(p);
    if (r == 0.0) {
        return vec2<f32>(0.5);
    }
    var a: f32;
    var b: f32;
    if (abs(p.x) >= abs(p.y)) {
        a = select(-r, r, p.x >= 0.0);
        b = a * atan(p.y / p.x) / (0.25 * PI);
    } else {
        b = select(-r, r, p.y >= 0.0);
        a = b * atan(p.x / p.y) / (0.25 * PI);
    }
    return vec2<f32>((a + 1.0) * 0.5, (b + 1.0) * 0.5);
}

// Equal-area square ↔ hemisphere (sbf::sampling::uniform_hemisphere_concentric).
fn guide_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let p = guide_disk(u);
    let r2 = min(dot(p, p), 1.0);
    return vec3<f32>(p * sqrt(2.0 - r2), 1.0 - r2);
}

fn guide_bin(local: vec3<f32>) -> u32 {
    let z = clamp(local.z, 0.0, 1.0);
    var p = local.xy / sqrt(1.0 + z);
    if (dot(p, p) > 1.0) {
        p = normalize(p);
    }
    let s = guide_disk_inv(p);
    let b = min(vec2<u32>(s * f32(GUIDE_BINS)), vec2<u32>(GUIDE_BINS - 1u));
    return b.y * GUIDE_BINS + b.x;
}

fn guide_below(at: u32, i: u32) -> f32 {
    return select(guide_dist[at + i - 1u], 0.0, i == 0u);
}

// Inverts the 16-entry CDF at `at` for u: (index, u rescaled inside it).
fn guide_invert(at: u32, u: f32) -> vec2<f32> {
    var i = GUIDE_BINS - 1u;
    for (var k = 0u; k < GUIDE_BINS; k++) {
        if (u < guide_dist[at + k]) {
            i = k;
            break;
        }
    }
    let lo = guide_below(at, i);
    let hi = guide_dist[at + i];
    let t = select(0.5, (u - lo) / (hi - lo), hi > lo);
    return vec2<f32>(f32(i), clamp(t, 0.0, 0.99999988));
}

// A tangent-space direction from cluster c's guided distribution.
fn guide_sample(c: u32, u: vec2<f32>) -> vec3<f32> {
    let at = c * GUIDE_CDF_LEN;
    let ry = guide_invert(at + GUIDE_BINS * GUIDE_BINS, u.y);
    let y = u32(ry.x);
    let rx = guide_invert(at + y * GUIDE_BINS, u.x);
    let s = vec2<f32>(rx.x + rx.y, ry.x + ry.y) / f32(GUIDE_BINS);
    return guide_hemisphere(s);
}

// Solid-angle pdf of the point-sample strategy at a tangent-space direction: the mixture
// (1 − m)/2π + m·guided once guiding runs, else uniform 1/2π.
fn guide_pdf(c: u32, local: vec3<f32>) -> f32 {
    if (P.guide_phase != 2u) {
        return 0.5 * INV_PI;
    }
    let b = guide_bin(local);
    let x = b % GUIDE_BINS;
    let y = b / GUIDE_BINS;
    let at = c * GUIDE_CDF_LEN;
    let marg = at + GUIDE_BINS * GUIDE_BINS;
    let row = at + y * GUIDE_BINS;
    let pb = (guide_dist[marg + y] - guide_below(marg, y)) * (guide_dist[row + x] - guide_below(row, x));
    let guided = pb * f32(GUIDE_BINS * GUIDE_BINS) * 0.5 * INV_PI;
    return (1.0 - guided_fraction()) * 0.5 * INV_PI + guided_fraction() * guided;
}

// Clears item i's learning records of this pass (a rejected sample records nothing).
fn guide_clear(i: u32) {
    if (P.guide_phase != 0u) {
        for (var k = 0u; k < GUIDE_RECORDS; k++) {
            guide_rec[GUIDE_RECORDS * i + k] = vec2<u32>(GUIDE_NONE, 0u);
        }
    }
}

// Learning record `slot` of item i for this pass (after guide_clear): an estimate of the
// bin's (1/2π)·∫L dω (the point sample's lum(L)·(1/2π)/p, a light sample's lum(c)/2π),
// times cosθ below.
fn guide_record(i: u32, slot: u32, local: vec3<f32>, lum: f32) {
    if (P.guide_phase == 0u) {
        return;
    }
    let v = lum * max(local.z, 0.0);
    var r = vec2<u32>(GUIDE_NONE, 0u);
    if (v > 0.0 && v < 3.0e38) {
        r = vec2<u32>(guide_bin(local), bitcast<u32>(v));
    }
    guide_rec[GUIDE_RECORDS * i + slot] = r;
}
