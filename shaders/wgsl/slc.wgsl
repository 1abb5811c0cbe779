// slc.wgsl — stochastic light culling for many VPLs ([TH17; TH17-supp; FTH22-supp]: Tokuyoshi & Harada,
// Fujieda et al.): one uniform ξ per light decides its random range by Russian roulette;
// the range is bounded by a sphere (diffuse VPL) or a spheroid (VPL on a GGX
// microsurface), and culling stores M = B·S and M·c per light so that an ellipsoid–frustum
// test becomes a sphere–AABB test. Conventions as sbf::slc: ω_i points from the VPL to
// where its light came from, n is the VPL's unit normal, ξ ∈ (0, 1], δ > 0.
// CPU twins: sbf::slc::runtime (same names without the slc_ prefix).

// p = min(I/(δl²), 1) ([TH17 eq. 2]); 1 at the light.
fn slc_acceptance(intensity: f32, delta: f32, l: f32) -> f32 {
    if (l <= 0.0) {
        return 1.0;
    }
    return min(intensity / (delta * l * l), 1.0);
}

// The largest finite f32, 0x1.fffffep127 = 3.4028234664e38. Written with fewer digits above
// it, as 3.4028235e38, it rounds to the same f32 in naga but is out of f32's range for tint
// (Chrome's WGSL compiler), which converts literals without rounding to the largest value.
const SLC_F32_MAX: f32 = 3.40282346e38;

// l_max = √(I/(δξ)) ([TH17 eq. 5]); ∞ (the largest f32) for ξ ≤ 0.
fn slc_random_range(intensity: f32, delta: f32, xi: f32) -> f32 {
    if (xi <= 0.0) {
        return SLC_F32_MAX;
    }
    return sqrt(max(intensity, 0.0) / (delta * xi));
}

// L/p if p > ξ, else 0 ([TH17 eq. 3]): unbiased over ξ.
fn slc_culled_estimate(radiance: f32, p: f32, xi: f32) -> f32 {
    return select(0.0, radiance / p, p > xi);
}

// cos θ_h^max = √((1 − √(1 − cos_i²))/2) ([TH17-supp eq. 2]), as |cos_i|/√(2(1 + s)), s =
// √(1 − cos_i²) (no cancellation at grazing incidence).
fn slc_cos_theta_h_max(cos_i: f32) -> f32 {
    let s = sqrt(max(1.0 - cos_i * cos_i, 0.0));
    return abs(cos_i) / sqrt(2.0 * (1.0 + s));
}

// Maximum Schlick Fresnel over the outgoing hemisphere ([TH17-supp eq. 1–2]).
fn slc_schlick_max(f0: f32, cos_i: f32) -> f32 {
    let m = 1.0 - slc_cos_theta_h_max(cos_i);
    return f0 + (1.0 - f0) * (m * m) * (m * m) * m;
}

// Unpolarised dielectric Fresnel ([TH17-supp eq. 3–5]); 1 under total internal reflection.
fn slc_dielectric_fresnel(eta: f32, cos_h: f32) -> f32 {
    let c = clamp(cos_h, 0.0, 1.0);
    let g2 = eta * eta - (1.0 - c * c);
    if (g2 <= 0.0) {
        return 1.0;
    }
    let g = sqrt(g2);
    let perp = (c - g) / (c + g);
    let e2c = eta * eta * c;
    let par = (g - e2c) / (g + e2c);
    return 0.5 * (perp * perp + par * par);
}

// Maximum dielectric Fresnel over the outgoing hemisphere ([TH17-supp eq. 6]): the larger end.
fn slc_dielectric_max(eta: f32, cos_i: f32) -> f32 {
    return max(slc_dielectric_fresnel(eta, 1.0), slc_dielectric_fresnel(eta, slc_cos_theta_h_max(cos_i)));
}

// G1_dist = 2|cos_i|/(|cos_i| + √((1 − α²)cos_i² + α²)) ([TH17 eq. 8]).
fn slc_g1_dist(cos_i: f32, alpha: f32) -> f32 {
    let c = abs(cos_i);
    let den = c + sqrt((1.0 - alpha * alpha) * c * c + alpha * alpha);
    return select(0.0, 2.0 * c / den, den > 0.0);
}

// GGX NDF of cos θ_m ([TH17 eq. 7]).
fn slc_ggx_ndf(cos_m: f32, alpha: f32) -> f32 {
    if (cos_m <= 0.0) {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = a2 * cos_m * cos_m + max(1.0 - cos_m * cos_m, 0.0);
    return a2 / (PI * t * t);
}

// r = √(Φ·F_max·G1_dist/(4πδξ|cos_i|)) ([TH17 eq. 12]).
fn slc_spheroid_scale(phi: f32, f_max: f32, g1: f32, cos_i: f32, delta: f32, xi: f32) -> f32 {
    if (xi <= 0.0) {
        return SLC_F32_MAX;
    }
    return sqrt(phi * f_max * g1 / (4.0 * PI * delta * xi * abs(cos_i)));
}

// s = r·√(π·D(cos(θ/2))) ([TH17 eq. 12]).
fn slc_bound_surface(theta: f32, r: f32, alpha: f32) -> f32 {
    return r * sqrt(PI * slc_ggx_ndf(cos(0.5 * theta), alpha));
}

// An ellipsoid: centre, unit axes as the columns of R, semi-axes.
struct SlcEllipsoid {
    center: vec3<f32>,
    axes: mat3x3<f32>,
    radii: vec3<f32>,
}

// Duff et al.'s any orthonormal vector (glam's any_orthonormal_vector; sign(0) = +1).
fn slc_any_orthonormal(v: vec3<f32>) -> vec3<f32> {
    let sign = select(-1.0, 1.0, v.z >= 0.0);
    let a = -1.0 / (sign + v.z);
    let b = v.x * v.y * a;
    return vec3<f32>(b, sign + v.y * v.y * a, -v.y);
}

// The GGX VPL's bounding spheroid ([TH17 eq. 13–15]): axes ω_u, ω_w × ω_u, ω_w; semi-axes
// ((1 + α²)/(2α)r, r, r); centre q + (1 − α²)/(2α)·r·ω_u.
fn slc_ggx_spheroid(q: vec3<f32>, wi: vec3<f32>, n: vec3<f32>, alpha: f32, r: f32) -> SlcEllipsoid {
    let wu = normalize(n * (2.0 * dot(wi, n)) - wi);
    let c = cross(wu, n);
    var ww = slc_any_orthonormal(wu);
    if (dot(c, c) > 1e-12) {
        ww = normalize(c);
    }
    let wv = cross(ww, wu);
    let ru = (1.0 + alpha * alpha) / (2.0 * alpha) * r;
    return SlcEllipsoid(q + wu * ((1.0 - alpha * alpha) / (2.0 * alpha) * r), mat3x3<f32>(wu, wv, ww), vec3<f32>(ru, r, r));
}

// S = R·diag(1/r)·Rᵀ ([TH17 eq. 16]).
fn slc_stretching(e: SlcEllipsoid) -> mat3x3<f32> {
    let inv = 1.0 / e.radii;
    let d = mat3x3<f32>(vec3<f32>(inv.x, 0.0, 0.0), vec3<f32>(0.0, inv.y, 0.0), vec3<f32>(0.0, 0.0, inv.z));
    return e.axes * d * transpose(e.axes);
}

struct SlcSphere {
    center: vec3<f32>,
    radius: f32,
}

// The diffuse VPL's bounding sphere ([FTH22-supp eq. 2–3]): A = √(Φk/(πδξ)), centre
// q + (1/3)^{3/4}·A·n, radius (4/27)^{1/4}·A.
fn slc_diffuse_sphere(q: vec3<f32>, n: vec3<f32>, phi_k: f32, delta: f32, xi: f32) -> SlcSphere {
    let a = slc_random_range(phi_k / PI, delta, xi);
    return SlcSphere(q + n * (pow(1.0 / 3.0, 0.75) * a), pow(4.0 / 27.0, 0.25) * a);
}

// A point light's bounding sphere: its random range √(I/(δξ)) about q.
fn slc_point_sphere(q: vec3<f32>, intensity: f32, delta: f32, xi: f32) -> SlcSphere {
    return SlcSphere(q, slc_random_range(intensity, delta, xi));
}

// The chord of the ray o + t·d (unit d) through sphere s: (t0, t1, 1) with t0 ≤ t1, or
// (0, 0, 0) when it misses. Stable roots q = −(b + sign(b)√disc), q and c/q.
fn slc_ray_sphere(o: vec3<f32>, d: vec3<f32>, s: SlcSphere) -> vec3<f32> {
    let oc = o - s.center;
    let b = dot(d, oc);
    let c = dot(oc, oc) - s.radius * s.radius;
    let disc = b * b - c;
    if (!(disc >= 0.0)) {
        return vec3<f32>(0.0);
    }
    let q = -(b + select(-sqrt(disc), sqrt(disc), b >= 0.0));
    if (q == 0.0) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let t0 = q;
    let t1 = c / q;
    return vec3<f32>(min(t0, t1), max(t0, t1), 1.0);
}

// The pdf of equiangular sampling on [a, b] (closest point t_c, distance h > 0) at t:
// h/((θ_b − θ_a)(h² + (t − t_c)²)).
fn slc_equiangular_pdf(tc: f32, h: f32, a: f32, b: f32, t: f32) -> f32 {
    let ta = atan2(a - tc, h);
    let tb = atan2(b - tc, h);
    return h / ((tb - ta) * (h * h + (t - tc) * (t - tc)));
}

// Equiangular distance sampling (Kulla & Fajardo 2012; [FTH22-supp §2.1]): (t, pdf) for u ∈ [0, 1).
fn slc_equiangular_sample(tc: f32, h: f32, a: f32, b: f32, u: f32) -> vec2<f32> {
    let ta = atan2(a - tc, h);
    let tb = atan2(b - tc, h);
    let t = clamp(tc + h * tan(ta + u * (tb - ta)), a, b);
    return vec2<f32>(t, slc_equiangular_pdf(tc, h, a, b, t));
}

// I_max(d) = Φ((d·n) + √((d·n)² + 1))²/(3√3·π) ([FTH22-supp eq. 7]).
fn slc_diffuse_intensity_bound(d_dot_n: f32, phi: f32) -> f32 {
    let t = d_dot_n + sqrt(d_dot_n * d_dot_n + 1.0);
    return phi * t * t / (3.0 * sqrt(3.0) * PI);
}

// The test-space rotation B ([TH17 eq. 17]).
fn slc_test_space_rotation(s: mat3x3<f32>) -> mat3x3<f32> {
    let bx = s[0];
    let by = s[1];
    let z = normalize(cross(bx, by));
    var x: vec3<f32>;
    var y: vec3<f32>;
    if (dot(bx, bx) > dot(by, by)) {
        x = normalize(bx);
        y = cross(z, x);
    } else {
        y = normalize(by);
        x = cross(y, z);
    }
    return transpose(mat3x3<f32>(x, y, z));
}

// What culling stores per light ([TH17 §5.2]): M = B·S and M·c in view space
// (x_view = view·x + origin).
struct SlcCullEllipsoid {
    transform: mat3x3<f32>,
    center: vec3<f32>,
}

// The ellipsoid e (world space) as the culling test needs it in view space: view the
// world-to-view rotation, origin the world origin in view space (x_view = view·x + origin).
fn slc_cull_transform(e: SlcEllipsoid, view: mat3x3<f32>, origin: vec3<f32>) -> SlcCullEllipsoid {
    let axes = view * e.axes;
    let s = slc_stretching(SlcEllipsoid(vec3<f32>(0.0), axes, e.radii));
    let m = slc_test_space_rotation(s) * s;
    return SlcCullEllipsoid(m, m * (view * e.center + origin));
}

// The 8 view-space corners of a tile's frustum part between view distances z0 and z1
// (along −z): pixel rectangle [x0, x1) × [y0, y1) of a width × height image, symmetric
// perspective with tan(half field of view) tan_x, tan_y.
fn slc_tile_corners(x0: f32, y0: f32, x1: f32, y1: f32, size: vec2<f32>, tan_xy: vec2<f32>, z0: f32, z1: f32) -> array<vec3<f32>, 8> {
    let a = vec3<f32>((2.0 * x0 / size.x - 1.0) * tan_xy.x, (1.0 - 2.0 * y0 / size.y) * tan_xy.y, -1.0);
    let b = vec3<f32>((2.0 * x1 / size.x - 1.0) * tan_xy.x, (1.0 - 2.0 * y0 / size.y) * tan_xy.y, -1.0);
    let c = vec3<f32>((2.0 * x0 / size.x - 1.0) * tan_xy.x, (1.0 - 2.0 * y1 / size.y) * tan_xy.y, -1.0);
    let d = vec3<f32>((2.0 * x1 / size.x - 1.0) * tan_xy.x, (1.0 - 2.0 * y1 / size.y) * tan_xy.y, -1.0);
    return array<vec3<f32>, 8>(a * z0, b * z0, c * z0, d * z0, a * z1, b * z1, c * z1, d * z1);
}

// Whether the unit sphere about `center` meets the box [lo, hi].
fn slc_unit_sphere_hits_aabb(center: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let d = center - clamp(center, lo, hi);
    return dot(d, d) <= 1.0;
}

// The conservative ellipsoid–frustum test ([TH17 §5]): the corners transformed by M = B·S,
// their AABB, the unit sphere about M·c.
fn slc_ellipsoid_hits_corners(e: SlcCullEllipsoid, corners: array<vec3<f32>, 8>) -> bool {
    var lo = vec3<f32>(SLC_F32_MAX);
    var hi = vec3<f32>(-SLC_F32_MAX);
    for (var k = 0u; k < 8u; k++) {
        let p = e.transform * corners[k];
        lo = min(lo, p);
        hi = max(hi, p);
    }
    return slc_unit_sphere_hits_aabb(e.center, lo, hi);
}
