// slc_cull.wgsl — stochastic light culling of VPLs on a view-space G-buffer ([TH17]
// §5–6), the GPU twin of baker::slc::render. Entry points:
//   slc_prepare     one thread per light: its bound (diffuse sphere or GGX spheroid) as
//                   the culling transform M = B·S and M·c (the shaders slc module);
//   slc_cull_shade  one 16 × 16 workgroup per tile of one interleaving subregion
//                   (workgroup z; pixel (I·(16·tile + lid) + s)): the tile's depth range from the
//                   G-buffer (workgroup atomics), split in two (Modified HalfZ); lights in
//                   chunks of 256, each thread testing one light and copying the kept
//                   ones, in the lights' order (a popcount prefix, so every pixel sums them
//                   in the same order on any hardware), into workgroup memory with what is
//                   per light, not per pixel (its ξ;
//                   a GGX VPL's ω_i in its frame and Λ(ω_i)); every pixel then shades them with the
//                   stochastic falloff L/p where p > ξ into its two RGB layers (irradiance E,
//                   the GGX layer's radiance S); per kept light a shared flag says whether
//                   any pixel accepted it (false positives for the FDR).
// The filters that follow (slc_filter, slc_filter_rows, slc_filter_cols) are in
// slc/filter.wgsl, appended to this file.
// Needs from `shaders`: the slc module, ggx_d, ggx_lambda, schlick_weight, tangent_frame, PI,
// INV_PI; slc_pcg_hash from hash.wgsl.

struct SlcParams {
    width: u32,
    height: u32,
    light_count: u32,
    // Bits 0–1: 0 culled (stochastic falloff), 1 brute force, 2 deterministic range cut
    // (ξ = ½); bits 2–3: glossy VPLs bounded by 0 their spheroid, 1 the sphere enclosing
    // it, 2 the TH16 sphere (centre at the VPL, radius r/α; [TH17 §7]); bit 4: some receiver
    // has a GGX layer (the specular layer is shaded and filtered).
    mode: u32,
    tan_x: f32,
    tan_y: f32,
    delta: f32,
    // Interleaved sampling ([TH17 §6]): I × I subregions, subregion s shading VPLs j ≡ s
    // (mod I²) weighted by I² (1: off).
    interleave: u32,
    // 0: each light's ξ as uploaded; otherwise drawn here from this seed (slc_gpu_xi).
    xi_seed: u32,
    // The filter joining the subregions: 0 the box of one period, R the cross-bilateral
    // filter of radius R (slc_filter).
    filter_radius: u32,
    // 0: the tile's depth range split in two (Modified HalfZ); n > 2: clustered shading,
    // n depth slices per tile, a pixel shading only the lights meeting its slice.
    clusters: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> SP: SlcParams;
// Two planes of 2 vec4 per pixel, the geometry the culling and the filter's taps read
// first, then the material: (view-space position, 1 if valid), (normal, GGX α) at 2k,
// 2k + 1; (albedo ρ, 0), (GGX F0, 0; zero: Lambert only) at 2N + 2k, 2N + 2k + 1 (N pixels).
@group(0) @binding(1) var<storage, read> gbuffer: array<vec4<f32>>;
// Per light 5 vec4: (position, ξ), (normal, α), (incoming ω_i, 1 diffuse / 0 GGX),
// (flux Φ, 0), (diffuse k or GGX F0, 0).
@group(0) @binding(2) var<storage, read> lights: array<vec4<f32>>;
// Per light 4 vec4: M's columns and M·c (w unused).
@group(0) @binding(3) var<storage, read_write> bounds: array<vec4<f32>>;
// Per pixel 2 vec4: (irradiance E, lights shaded), (the GGX layer's radiance S, of those
// lights the ones with p ≤ ξ (false discoveries)).
@group(0) @binding(4) var<storage, read_write> image: array<vec4<f32>>;
// Kept (tile, light) pairs and false positives.
@group(0) @binding(5) var<storage, read_write> stats: array<atomic<u32>, 2>;
// Per pixel: the radiance after the filter (rgb, 0).
@group(0) @binding(6) var<storage, read_write> filtered: array<vec4<f32>>;
// Per pixel 2 vec4: the layers after the bilateral filter's first pass (rows): (E, 1; 0:
// none passed), (S, 0).
@group(0) @binding(7) var<storage, read_write> filter_rows: array<vec4<f32>>;

struct SlcVpl {
    position: vec3<f32>,
    xi: f32,
    normal: vec3<f32>,
    alpha: f32,
    incoming: vec3<f32>,
    diffuse: bool,
    flux: vec3<f32>,
    // Diffuse k or GGX F0.
    refl: vec3<f32>,
}

// Pixel k's G-buffer entries (the layout above).
fn slc_gb_position(k: u32) -> vec4<f32> {
    return gbuffer[2u * k];
}

fn slc_gb_normal(k: u32) -> vec4<f32> {
    return gbuffer[2u * k + 1u];
}

fn slc_gb_albedo(k: u32) -> vec3<f32> {
    return gbuffer[2u * (SP.width * SP.height + k)].xyz;
}

fn slc_gb_f0(k: u32) -> vec3<f32> {
    return gbuffer[2u * (SP.width * SP.height + k) + 1u].xyz;
}

fn slc_max3(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// Light j's ξ ∈ (0, 1] of the GPU's own stream: 24 bits of pcg(pcg(seed) ^ j) — a generator
// unrelated to the CPU's (baker::slc::vpl_xi), so images made with it are an independent
// estimate of the same expectation ([TH17 eq. 3]).
fn slc_gpu_xi(seed: u32, j: u32) -> f32 {
    return 1.0 - f32(slc_pcg_hash(slc_pcg_hash(seed) ^ j) >> 8u) / 16777216.0;
}

// Light j's ξ: as uploaded, or from the GPU's own stream.
fn slc_light_xi(j: u32) -> f32 {
    if (SP.xi_seed != 0u) {
        return slc_gpu_xi(SP.xi_seed, j);
    }
    return lights[5u * j].w;
}

fn slc_load_vpl(j: u32) -> SlcVpl {
    let a = lights[5u * j];
    let b = lights[5u * j + 1u];
    let c = lights[5u * j + 2u];
    return SlcVpl(a.xyz, slc_light_xi(j), b.xyz, b.w, c.xyz, c.w > 0.5, lights[5u * j + 3u].xyz, lights[5u * j + 4u].xyz);
}

// The GGX BRDF f(a, b) per channel of f0 (height-correlated Smith G2, Schlick at a·h) for
// a, b in the tangent frame of their surface, given Λ(a) and Λ(b) (ignored where a_z or
// b_z ≤ 0: f = 0) (CPU twin: baker::slc::ggx_brdf).
fn slc_ggx_lambdas(a: vec3<f32>, b: vec3<f32>, lambda_a: f32, lambda_b: f32, alpha: f32, f0: vec3<f32>) -> vec3<f32> {
    if (a.z <= 0.0 || b.z <= 0.0) {
        return vec3<f32>(0.0);
    }
    let h = normalize(a + b);
    let g2 = 1.0 / (1.0 + lambda_a + lambda_b);
    return (f0 + (1.0 - f0) * schlick_weight(dot(a, h))) * (g2 * ggx_d(h, alpha) / (4.0 * a.z * b.z));
}

// Smith Λ(w) where w_z > 0, else 0 (unused there).
fn slc_lambda(w: vec3<f32>, alpha: f32) -> f32 {
    return select(0.0, ggx_lambda(w, alpha), w.z > 0.0);
}

// What shading a GGX VPL needs per light, not per pixel: ω_i in the VPL's tangent frame
// and Λ(ω_i) (0 for a diffuse VPL).
fn slc_vpl_incoming(v: SlcVpl) -> vec4<f32> {
    if (v.diffuse) {
        return vec4<f32>(0.0);
    }
    let fr = tangent_frame(v.normal);
    let wi = vec3<f32>(dot(v.incoming, fr[0]), dot(v.incoming, fr[1]), dot(v.incoming, v.normal));
    return vec4<f32>(wi, slc_lambda(wi, v.alpha));
}

@compute @workgroup_size(64)
fn slc_prepare(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = gid.x;
    if (j >= SP.light_count) {
        return;
    }
    var v = slc_load_vpl(j);
    // The range cut keeps every light within its range at ξ = ½: its bound is that range's.
    if ((SP.mode & 3u) == 2u) {
        v.xi = 0.5;
    }
    var e: SlcEllipsoid;
    // Each bound holds the largest channel (CPU twin: Vpl::bound).
    if (v.diffuse) {
        let s = slc_diffuse_sphere(v.position, v.normal, slc_max3(v.flux * v.refl), SP.delta, v.xi);
        e = SlcEllipsoid(s.center, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(s.radius));
    } else {
        let cos_i = dot(v.incoming, v.normal);
        let fmax = vec3<f32>(slc_schlick_max(v.refl.x, cos_i), slc_schlick_max(v.refl.y, cos_i), slc_schlick_max(v.refl.z, cos_i));
        let r = slc_spheroid_scale(slc_max3(v.flux * fmax), 1.0, slc_g1_dist(cos_i, v.alpha), cos_i, SP.delta, v.xi);
        e = slc_ggx_spheroid(v.position, v.incoming, v.normal, v.alpha, r);
        let ident = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
        let bound = (SP.mode >> 2u) & 3u;
        if (bound == 1u) {
            e = SlcEllipsoid(e.center, ident, vec3<f32>(e.radii.x));
        } else if (bound == 2u) {
            e = SlcEllipsoid(v.position, ident, vec3<f32>(r / v.alpha));
        }
    }
    let ident = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    let c = slc_cull_transform(e, ident, vec3<f32>(0.0));
    bounds[4u * j] = vec4<f32>(c.transform[0], 0.0);
    bounds[4u * j + 1u] = vec4<f32>(c.transform[1], 0.0);
    bounds[4u * j + 2u] = vec4<f32>(c.transform[2], 0.0);
    bounds[4u * j + 3u] = vec4<f32>(c.center, 0.0);
}

const SLC_TILE: u32 = 16u;
const SLC_CHUNK: u32 = 256u;

var<workgroup> wg_zmin: atomic<u32>;
var<workgroup> wg_zmax: atomic<u32>;
// Per chunk parity: which of the chunk's 256 lights its tile keeps (bit t: the light thread
// t culled) and, per kept light, whether some pixel accepted it — two of each, so one
// chunk's words are cleared and its statistics read while the next is culled (two barriers
// per chunk). A kept light's slot is the number of kept lights before it (a popcount
// prefix over the words): the slots, and so every pixel's sum, follow the lights' order on
// any hardware — an atomic counter's slots would follow the order threads arrive in.
var<workgroup> wg_kept: array<array<atomic<u32>, 8>, 2>;
var<workgroup> wg_accepted: array<array<atomic<u32>, 256>, 2>;
// Per kept light: the depth slices its bound meets (clustered shading; all bits otherwise).
var<workgroup> wg_mask: array<u32, 256>;
// Per kept light, what shading reads (slc_kept_intensity): (position, ξ), (normal, α),
// (Φ·k for a diffuse VPL, Φ for a GGX one; 1 diffuse / 0 GGX), (GGX F0, 0) and
// slc_vpl_incoming — loaded once per tile from `lights` by the thread that culls the light.
var<workgroup> wg_position: array<vec4<f32>, 256>;
var<workgroup> wg_normal: array<vec4<f32>, 256>;
var<workgroup> wg_power: array<vec4<f32>, 256>;
var<workgroup> wg_f0: array<vec4<f32>, 256>;
var<workgroup> wg_incoming: array<vec4<f32>, 256>;

// Radiant intensity of kept light s towards unit wo per channel, from the workgroup's copy
// (CPU twin: Vpl::intensity).
fn slc_kept_intensity(s: u32, wo: vec3<f32>) -> vec3<f32> {
    let nb = wg_normal[s];
    let c = dot(wo, nb.xyz);
    if (c <= 0.0) {
        return vec3<f32>(0.0);
    }
    let pw = wg_power[s];
    if (pw.w > 0.5) {
        return pw.xyz * (c * INV_PI);
    }
    let incoming = wg_incoming[s];
    let fr = tangent_frame(nb.xyz);
    let wl = vec3<f32>(dot(wo, fr[0]), dot(wo, fr[1]), c);
    return pw.xyz * slc_ggx_lambdas(incoming.xyz, wl, incoming.w, ggx_lambda(wl, nb.w), nb.w, wg_f0[s].xyz) * c;
}

// Depth slice s of n over [zmin, zmax], widened by 1e-4 of the range plus 1e-6 of zmax
// (CPU twin: baker::slc::cluster_range).
fn slc_cluster_range(zmin: f32, zmax: f32, s: u32, n: u32) -> vec2<f32> {
    let w = zmax - zmin;
    let pad = 1e-4 * w + 1e-6 * zmax;
    return vec2<f32>(zmin + w * f32(s) / f32(n) - pad, zmin + w * f32(s + 1u) / f32(n) + pad);
}

// The slice of depth z among n over [zmin, zmax] (CPU twin: baker::slc::cluster_of).
fn slc_cluster_of(z: f32, zmin: f32, zmax: f32, n: u32) -> u32 {
    let w = max(zmax - zmin, 1.17549435e-38);
    return min(u32(max((z - zmin) / w * f32(n), 0.0)), n - 1u);
}

// Whether the unit sphere about `center` meets the AABB of the points z·p, z ∈ {z0, z1}, p
// the four transformed corner rays.
fn slc_scaled_rays_hit(center: vec3<f32>, pa: vec3<f32>, pb: vec3<f32>, pc: vec3<f32>, pd: vec3<f32>, z0: f32, z1: f32) -> bool {
    let lo = min(min(min(pa * z0, pa * z1), min(pb * z0, pb * z1)), min(min(pc * z0, pc * z1), min(pd * z0, pd * z1)));
    let hi = max(max(max(pa * z0, pa * z1), max(pb * z0, pb * z1)), max(max(pc * z0, pc * z1), max(pd * z0, pd * z1)));
    return slc_unit_sphere_hits_aabb(center, lo, hi);
}

// Modified HalfZ's test of one light against the tile's two halves, depths [z.x, z.y] and
// [z.y, z.z]: slc_ellipsoid_hits_corners on each half's 8 corners, with M applied to the four
// corner rays r (depth 1) once instead of to 16 corners — M·(z·r) = z·(M·r), so a half's
// AABB is the per-axis min/max of z·(M·r) over its two depths (equal up to f32 rounding to
// the corners' own; H100, 1080p, 65 603 VPLs: culling + shading 1.325 → 0.976 ms).
fn slc_ellipsoid_hits_halves(c: SlcCullEllipsoid, rays: array<vec3<f32>, 8>, z: vec3<f32>) -> bool {
    let pa = c.transform * rays[0];
    let pb = c.transform * rays[1];
    let pc = c.transform * rays[2];
    let pd = c.transform * rays[3];
    return slc_scaled_rays_hit(c.center, pa, pb, pc, pd, z.x, z.y) || slc_scaled_rays_hit(c.center, pa, pb, pc, pd, z.y, z.z);
}

@compute @workgroup_size(16, 16)
fn slc_cull_shade(@builtin(workgroup_id) tile: vec3<u32>, @builtin(local_invocation_index) t: u32, @builtin(local_invocation_id) lid: vec3<u32>) {
    let il = SP.interleave;
    let sx = tile.z % il;
    let sy = tile.z / il;
    let px = il * (tile.x * SLC_TILE + lid.x) + sx;
    let py = il * (tile.y * SLC_TILE + lid.y) + sy;
    // This subregion's VPLs: j = tile.z + I²·m, m < its count.
    let stride = il * il;
    let sub_count = select(0u, (SP.light_count - tile.z + stride - 1u) / stride, tile.z < SP.light_count);
    let inside = px < SP.width && py < SP.height;
    let k = py * SP.width + px;
    var x = vec3<f32>(0.0);
    var n = vec3<f32>(0.0, 0.0, 1.0);
    var alpha = 1.0;
    var f0 = vec3<f32>(0.0);
    var valid = false;
    if (inside) {
        let a = slc_gb_position(k);
        let b = slc_gb_normal(k);
        valid = a.w > 0.5;
        x = a.xyz;
        n = b.xyz;
        alpha = b.w;
        if ((SP.mode & 16u) != 0u) {
            f0 = slc_gb_f0(k);
        }
    }
    // The GGX layer's frame and view direction (the camera at the origin).
    let glossy = valid && slc_max3(f0) > 0.0;
    let fr = tangent_frame(n);
    let wv = normalize(-x);
    let v_local = vec3<f32>(dot(wv, fr[0]), dot(wv, fr[1]), dot(wv, n));
    let lambda_v = slc_lambda(v_local, alpha);
    if (t == 0u) {
        atomicStore(&wg_zmin, 0x7f800000u);
        atomicStore(&wg_zmax, 0u);
    }
    if (t < 8u) {
        atomicStore(&wg_kept[0][t], 0u);
    }
    workgroupBarrier();
    if (valid) {
        // Positive floats order like their bits.
        atomicMin(&wg_zmin, bitcast<u32>(-x.z));
        atomicMax(&wg_zmax, bitcast<u32>(-x.z));
    }
    workgroupBarrier();
    let zmin_bits = atomicLoad(&wg_zmin);
    let zmin = bitcast<f32>(zmin_bits);
    let zmax = bitcast<f32>(atomicLoad(&wg_zmax));
    let any_valid = zmin_bits != 0x7f800000u;
    let mid = 0.5 * (zmin + zmax);
    // The tile's pixels span [x0, x1) × [y0, y1) on screen (every I-th pixel).
    let x0 = f32(il * tile.x * SLC_TILE + sx);
    let y0 = f32(il * tile.y * SLC_TILE + sy);
    let x1 = x0 + f32(il * (SLC_TILE - 1u) + 1u);
    let y1 = y0 + f32(il * (SLC_TILE - 1u) + 1u);
    let size = vec2<f32>(f32(SP.width), f32(SP.height));
    let tan_xy = vec2<f32>(SP.tan_x, SP.tan_y);
    // The tile's four corner rays at depth 1 (the first four corners).
    let rays = slc_tile_corners(x0, y0, x1, y1, size, tan_xy, 1.0, 1.0);
    let clustered = SP.clusters > 0u && (SP.mode & 3u) != 1u;
    var slice_bit = 0xffffffffu;
    if (clustered && valid) {
        slice_bit = 1u << slc_cluster_of(-x.z, zmin, zmax, SP.clusters);
    }
    var irradiance = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    var shaded = 0u;
    var false_hits = 0u;
    // Per chunk two barriers: after the culling (the kept words complete), and after the kept
    // lights' records are written at their slots (complete for shading). Chunk c keeps its
    // words and flags at parity c % 2; the other parity's words are cleared during c's
    // culling — their last reader, chunk c − 1's slot prefix, finished before c − 1's second
    // barrier. Chunk c − 1's statistics are read after c's first barrier (its shading done);
    // the last chunk's after the loop.
    var parity = 0u;
    var previous_count = 0u;
    for (var base = 0u; base < sub_count; base += SLC_CHUNK) {
        if (t < 8u) {
            atomicStore(&wg_kept[parity ^ 1u][t], 0u);
        }
        let m = base + t;
        let j = tile.z + stride * m;
        var mask = 0u;
        if (any_valid && m < sub_count) {
            mask = 0xffffffffu;
            if ((SP.mode & 3u) != 1u) {
                let c = SlcCullEllipsoid(mat3x3<f32>(bounds[4u * j].xyz, bounds[4u * j + 1u].xyz, bounds[4u * j + 2u].xyz), bounds[4u * j + 3u].xyz);
                if (clustered) {
                    mask = 0u;
                    for (var sl = 0u; sl < SP.clusters; sl++) {
                        let r = slc_cluster_range(zmin, zmax, sl, SP.clusters);
                        if (slc_ellipsoid_hits_corners(c, slc_tile_corners(x0, y0, x1, y1, size, tan_xy, r.x, r.y))) {
                            mask |= 1u << sl;
                        }
                    }
                } else if (!slc_ellipsoid_hits_halves(c, rays, vec3<f32>(zmin, mid, zmax))) {
                    mask = 0u;
                }
            }
        }
        // A kept light's record is read before the barrier (its latency hidden by the wait).
        var v: SlcVpl;
        if (mask != 0u) {
            v = slc_load_vpl(j);
            atomicOr(&wg_kept[parity][t / 32u], 1u << (t % 32u));
        }
        workgroupBarrier();
        // The slot: kept lights before this one; the count: all kept lights.
        var count = 0u;
        var slot = 0u;
        for (var w = 0u; w < 8u; w++) {
            let bits = countOneBits(atomicLoad(&wg_kept[parity][w]));
            if (w < t / 32u) {
                slot += bits;
            }
            count += bits;
        }
        slot += countOneBits(atomicLoad(&wg_kept[parity][t / 32u]) & ((1u << (t % 32u)) - 1u));
        if (mask != 0u) {
            wg_mask[slot] = mask;
            wg_position[slot] = vec4<f32>(v.position, v.xi);
            wg_normal[slot] = vec4<f32>(v.normal, v.alpha);
            wg_power[slot] = vec4<f32>(select(v.flux, v.flux * v.refl, v.diffuse), select(0.0, 1.0, v.diffuse));
            wg_f0[slot] = vec4<f32>(v.refl, 0.0);
            wg_incoming[slot] = slc_vpl_incoming(v);
            atomicStore(&wg_accepted[parity][slot], 0u);
        }
        // The previous chunk's statistics (its shading finished before this chunk's first
        // barrier; its flags are the other parity's, rewritten only after the next barrier).
        if ((SP.mode & 3u) == 0u && t < previous_count && atomicLoad(&wg_accepted[parity ^ 1u][t]) == 0u) {
            atomicAdd(&stats[1], 1u);
        }
        workgroupBarrier();
        if (valid) {
            for (var s = 0u; s < count; s++) {
                if ((wg_mask[s] & slice_bit) == 0u) {
                    continue;
                }
                let pos = wg_position[s];
                let xi = pos.w;
                let to = x - pos.xyz;
                let d2 = dot(to, to);
                let d = sqrt(d2);
                let wo = to / d;
                let intensity = slc_kept_intensity(s, wo);
                let i = slc_max3(intensity);
                shaded += 1u;
                // The estimator's factor on this (light, pixel) (CPU twin: render_subregion).
                var f = 1.0;
                if ((SP.mode & 3u) == 2u) {
                    f = select(0.0, 1.0, d <= slc_random_range(i, SP.delta, 0.5));
                } else if ((SP.mode & 3u) == 0u) {
                    let p = slc_acceptance(i, SP.delta, d);
                    if (p > xi) {
                        atomicStore(&wg_accepted[parity][s], 1u);
                    } else {
                        false_hits += 1u;
                    }
                    f = slc_culled_estimate(1.0, p, xi);
                }
                if (f > 0.0) {
                    let e = intensity * (max(dot(-wo, n), 0.0) / d2 * f);
                    irradiance += e;
                    if (glossy) {
                        let wl = -wo;
                        let l_local = vec3<f32>(dot(wl, fr[0]), dot(wl, fr[1]), dot(wl, n));
                        specular += e * slc_ggx_lambdas(l_local, v_local, slc_lambda(l_local, alpha), lambda_v, alpha, f0);
                    }
                }
            }
        }
        if (t == 0u) {
            atomicAdd(&stats[0], count);
        }
        previous_count = count;
        parity ^= 1u;
    }
    // The last chunk's statistics, once its shading is done.
    workgroupBarrier();
    if ((SP.mode & 3u) == 0u && t < previous_count && atomicLoad(&wg_accepted[parity ^ 1u][t]) == 0u) {
        atomicAdd(&stats[1], 1u);
    }
    if (inside) {
        image[2u * k] = vec4<f32>(irradiance * f32(stride), f32(shaded));
        image[2u * k + 1u] = vec4<f32>(specular * f32(stride), f32(false_hits));
    }
}
