// sh.wgsl — real spherical harmonics up to band 4 and their Lambert irradiance.
// Convention (sbf): orthonormal, no Condon–Shortley phase, index l(l+1)+m: band 1 is
// +K₁·(y, z, x) (m = −1, 0, 1). Code that keeps the phase (BakingLab's SH.hlsl, for one)
// has the opposite sign on every odd-m function (band 1's y and x, band 2's yz and xz, …):
// negate those coefficients when converting. The Cartesian forms follow Sloan, "Stupid
// Spherical Harmonics Tricks" (2008), App. A2, with the CS sign dropped; constants are
// written as their closed forms.
// CPU twins: sbf::basis::sh_fast::eval_sh_l{1,2,4}, sbf::recon::runtime::sh_l{1,2,4}_irradiance,
// sh_l1_geomerics_irradiance, and sbf::recon::sh::irradiance_l1_zh3.

const SH_K00: f32 = 0.5 / sqrt(PI);
const SH_K1: f32 = sqrt(3.0 / (4.0 * PI));
const SH_K2A: f32 = 0.5 * sqrt(15.0 / PI);
const SH_K20: f32 = 0.25 * sqrt(5.0 / PI);
const SH_K22: f32 = 0.25 * sqrt(15.0 / PI);
const SH_K33: f32 = 0.25 * sqrt(35.0 / (2.0 * PI));
const SH_K32A: f32 = 0.5 * sqrt(105.0 / PI);
const SH_K31: f32 = 0.25 * sqrt(21.0 / (2.0 * PI));
const SH_K30: f32 = 0.25 * sqrt(7.0 / PI);
const SH_K32B: f32 = 0.25 * sqrt(105.0 / PI);
const SH_K44: f32 = 0.75 * sqrt(35.0 / PI);
const SH_K43: f32 = 0.75 * sqrt(35.0 / (2.0 * PI));
const SH_K42: f32 = 0.75 * sqrt(5.0 / PI);
const SH_K41: f32 = 0.75 * sqrt(5.0 / (2.0 * PI));
const SH_K40: f32 = (3.0 / 16.0) * sqrt(1.0 / PI);
const SH_K42B: f32 = (3.0 / 8.0) * sqrt(5.0 / PI);
const SH_K44B: f32 = (3.0 / 16.0) * sqrt(35.0 / PI);

// A_l/π (Ramamoorthi & Hanrahan 2001): E/π band factors 1, 2/3, 1/4, 0, −1/24.
const SH_BAND1: f32 = 2.0 / 3.0;
const SH_BAND2: f32 = 0.25;
const SH_BAND4: f32 = -1.0 / 24.0;

// The 4 real SH basis functions of bands 0–1 at unit direction d, in the order
// Y00, Y1−1 (∝ y), Y10 (∝ z), Y11 (∝ x); no Condon–Shortley phase (band 1 is +K·(y, z, x)).
fn sh_eval_l1(d: vec3<f32>) -> array<f32, 4> {
    return array<f32, 4>(SH_K00, SH_K1 * d.y, SH_K1 * d.z, SH_K1 * d.x);
}

// The 9 real SH basis functions of bands 0–2 at unit direction d (index l(l+1)+m: band 1
// is +K·(y, z, x), band 2 ∝ xy, yz, 3z²−1, xz, x²−y²); no Condon–Shortley phase.
fn sh_eval_l2(d: vec3<f32>) -> array<f32, 9> {
    let x = d.x;
    let y = d.y;
    let z = d.z;
    return array<f32, 9>(
        SH_K00, SH_K1 * y, SH_K1 * z, SH_K1 * x,
        SH_K2A * x * y, SH_K2A * y * z, SH_K20 * (3.0 * z * z - 1.0), SH_K2A * x * z, SH_K22 * (x * x - y * y),
    );
}

// The 25 real SH basis functions of bands 0–4 at unit direction d (index l(l+1)+m); no
// Condon–Shortley phase.
fn sh_eval_l4(d: vec3<f32>) -> array<f32, 25> {
    let x = d.x;
    let y = d.y;
    let z = d.z;
    let x2 = x * x;
    let y2 = y * y;
    let z2 = z * z;
    return array<f32, 25>(
        SH_K00, SH_K1 * y, SH_K1 * z, SH_K1 * x,
        SH_K2A * x * y, SH_K2A * y * z, SH_K20 * (3.0 * z2 - 1.0), SH_K2A * x * z, SH_K22 * (x2 - y2),
        SH_K33 * y * (3.0 * x2 - y2), SH_K32A * x * y * z, SH_K31 * y * (5.0 * z2 - 1.0), SH_K30 * z * (5.0 * z2 - 3.0),
        SH_K31 * x * (5.0 * z2 - 1.0), SH_K32B * z * (x2 - y2), SH_K33 * x * (x2 - 3.0 * y2),
        SH_K44 * x * y * (x2 - y2), SH_K43 * y * z * (3.0 * x2 - y2), SH_K42 * x * y * (7.0 * z2 - 1.0),
        SH_K41 * y * z * (7.0 * z2 - 3.0), SH_K40 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0), SH_K41 * x * z * (7.0 * z2 - 3.0),
        SH_K42B * (x2 - y2) * (7.0 * z2 - 1.0), SH_K43 * x * z * (x2 - 3.0 * y2),
        SH_K44B * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2)),
    );
}

// E/π at unit normal n from RGB radiance coefficients.
fn sh_l1_irradiance(c: array<vec3<f32>, 4>, n: vec3<f32>) -> vec3<f32> {
    let y = sh_eval_l1(n);
    return c[0] * y[0] + (c[1] * y[1] + c[2] * y[2] + c[3] * y[3]) * SH_BAND1;
}

// E/π (irradiance over π) at unit normal n from 9 RGB SH L2 radiance coefficients c (this
// file's order and signs, the same frame as n): Σ Â_l c_lm Y_lm(n), Â = 1, 2/3, 1/4.
fn sh_l2_irradiance(c: array<vec3<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    let y = sh_eval_l2(n);
    var b1 = vec3<f32>(0.0);
    for (var i = 1; i < 4; i++) {
        b1 += c[i] * y[i];
    }
    var b2 = vec3<f32>(0.0);
    for (var i = 4; i < 9; i++) {
        b2 += c[i] * y[i];
    }
    return c[0] * y[0] + b1 * SH_BAND1 + b2 * SH_BAND2;
}

// E/π at unit normal n from 25 RGB SH L4 radiance coefficients c (same frame as n); bands 3
// and 4 of the clamped cosine are 0 and −1/24.
fn sh_l4_irradiance(c: array<vec3<f32>, 25>, n: vec3<f32>) -> vec3<f32> {
    let y = sh_eval_l4(n);
    var b1 = vec3<f32>(0.0);
    for (var i = 1; i < 4; i++) {
        b1 += c[i] * y[i];
    }
    var b2 = vec3<f32>(0.0);
    for (var i = 4; i < 9; i++) {
        b2 += c[i] * y[i];
    }
    var b4 = vec3<f32>(0.0);
    for (var i = 16; i < 25; i++) {
        b4 += c[i] * y[i];
    }
    return c[0] * y[0] + b1 * SH_BAND1 + b2 * SH_BAND2 + b4 * SH_BAND4;
}

// Geomerics' non-linear L1 reconstruction (Geomerics / Graham Hazel 2015, as in
// sbf::recon::sh::irradiance_l1_geomerics), per channel; E/π.
fn sh_l1_geomerics_channel(c0: f32, c1: vec3<f32>, n: vec3<f32>) -> f32 {
    let r0 = c0 * SH_K00;
    let r1 = c1 * (SH_K1 / 3.0);
    let len = length(r1);
    if (r0 <= 0.0 || len <= 0.0) {
        return r0 + 2.0 * dot(r1, n);
    }
    let q = 0.5 * (1.0 + dot(n, r1 / len));
    let ratio = len / r0;
    let p = 1.0 + 2.0 * ratio;
    let a = (1.0 - ratio) / (1.0 + ratio);
    return r0 * (a + (1.0 - a) * (p + 1.0) * pow(max(q, 0.0), p));
}

// E/π at unit normal n from 4 RGB SH L1 radiance coefficients c (same frame as n) by the
// non-linear reconstruction described above, per channel.
fn sh_l1_geomerics_irradiance(c: array<vec3<f32>, 4>, n: vec3<f32>) -> vec3<f32> {
    // Band-1 coefficient order is (y, z, x): the linear term is (c3, c1, c2).
    return vec3<f32>(
        sh_l1_geomerics_channel(c[0].x, vec3<f32>(c[3].x, c[1].x, c[2].x), n),
        sh_l1_geomerics_channel(c[0].y, vec3<f32>(c[3].y, c[1].y, c[2].y), n),
        sh_l1_geomerics_channel(c[0].z, vec3<f32>(c[3].z, c[1].z, c[2].z), n),
    );
}

// ZH3 hallucination for L1 (Roughton & Sloan 2024, "ZH3: Quadratic Zonal Harmonics",
// as in sbf::recon::sh::irradiance_l1_zh3): a zonal band-2 term about the luminance
// axis of the band-1 vectors, with coefficient c0·(0.08 r + 0.6 r²), r = |L1·axis|/c0.
const SH_LUMINANCE: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

// E/π at unit normal n from 4 RGB SH L1 radiance coefficients c plus the ZH3 band-2 term
// described above (same frame as n).
fn sh_l1_zh3_irradiance(c: array<vec3<f32>, 4>, n: vec3<f32>) -> vec3<f32> {
    // Band-1 vector per channel is (c3, c1, c2); each component below is an RGB triple.
    let lum = vec3<f32>(dot(c[3], SH_LUMINANCE), dot(c[1], SH_LUMINANCE), dot(c[2], SH_LUMINANCE));
    let len2 = dot(lum, lum);
    let axis = select(vec3<f32>(0.0, 0.0, 1.0), lum * inverseSqrt(len2), len2 > 0.0);
    let along = abs(c[3] * axis.x + c[1] * axis.y + c[2] * axis.z);
    let r = select(vec3<f32>(0.0), along / c[0], c[0] > vec3<f32>(0.0));
    let zh = c[0] * (0.08 * r + 0.6 * r * r);
    let t = dot(n, axis);
    let y20 = sqrt(5.0 / (4.0 * PI)) * 0.5 * (3.0 * t * t - 1.0);
    return sh_l1_irradiance(c, n) + SH_BAND2 * zh * y20;
}
