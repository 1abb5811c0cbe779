// slc_media.wgsl — stochastic light culling for single scattering in a homogeneous slab
// (Fujieda, Tokuyoshi & Harada 2022, [FTH22-supp]), the GPU twin of baker::slc::media::render. Entry point
// media_cull_shade: one 16 × 16 workgroup per tile; the tile's medium from the slab's near
// depth to its farthest surface (workgroup atomics), split in two; lights in chunks of 256,
// each thread testing one light's sphere against both halves and appending the kept ones to
// a shared list; every pixel then takes one distance sample per kept light (equiangular
// inside the inner sphere, uniform between the inner and the outer one, weighted by the
// acceptance probability of 001 supp. eq. 1). Distance samples: the GPU's own PCG hash of
// (seed, pixel, light), unrelated to the CPU's SplitMix64 chain; each light's ξ as uploaded.
// Needs from `shaders`: the slc module and PI; slc_pcg_hash from hash.wgsl.

struct MediaParams {
    width: u32,
    height: u32,
    light_count: u32,
    // 0 culled, 1 brute force (every light, equiangular over the whole segment).
    mode: u32,
    tan_x: f32,
    tan_y: f32,
    delta: f32,
    seed: u32,
    sigma_s: f32,
    sigma_t: f32,
    near: f32,
    far: f32,
}

@group(0) @binding(0) var<uniform> MP: MediaParams;
// Per pixel: the distance along its camera ray to the surface (3.4e38: none).
@group(0) @binding(1) var<storage, read> surface_distance: array<f32>;
// Per light 3 vec4: (position, peak: the largest channel of the power Φ or Φ ⊙ k), (normal
// (zero: a point light), ξ), (power / peak per channel, 0) — estimated in the peak channel,
// scaled per channel (CPU twin: MediaLight::peak, tint).
@group(0) @binding(2) var<storage, read> mlights: array<vec4<f32>>;
// Per pixel 2 vec4: (RGB radiance, lights kept by the tile), (of those the ones whose sphere
// the pixel's segment misses (false discoveries), 0, 0, 0).
@group(0) @binding(3) var<storage, read_write> mout: array<vec4<f32>>;

struct MediaLight {
    position: vec3<f32>,
    // The peak channel's power.
    power: f32,
    normal: vec3<f32>,
    xi: f32,
    tint: vec3<f32>,
}

fn media_light(j: u32) -> MediaLight {
    let a = mlights[3u * j];
    let b = mlights[3u * j + 1u];
    return MediaLight(a.xyz, a.w, b.xyz, b.w, mlights[3u * j + 2u].xyz);
}

fn media_is_point(l: MediaLight) -> bool {
    return all(l.normal == vec3<f32>(0.0));
}

fn media_intensity(l: MediaLight, d: vec3<f32>) -> f32 {
    if (media_is_point(l)) {
        return l.power / (4.0 * PI);
    }
    return l.power * max(dot(d, l.normal), 0.0) / PI;
}

// The acceptance probability's directional term (CPU twin: MediaLight::intensity_bound).
fn media_intensity_bound(l: MediaLight, d: vec3<f32>) -> f32 {
    if (media_is_point(l)) {
        return l.power / (4.0 * PI);
    }
    return slc_diffuse_intensity_bound(dot(d, l.normal), l.power);
}

fn media_sphere(l: MediaLight, xi: f32) -> SlcSphere {
    if (media_is_point(l)) {
        return slc_point_sphere(l.position, l.power / (4.0 * PI), MP.delta, xi);
    }
    return slc_diffuse_sphere(l.position, l.normal, l.power, MP.delta, xi);
}

// The length of the segment a → b inside the slab (CPU twin: Medium::length_inside).
fn media_length_inside(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let da = -a.z;
    let db = -b.z;
    let len = length(b - a);
    if (abs(db - da) <= 1.1920929e-7 * (abs(da) + abs(db))) {
        return select(0.0, len, da >= MP.near && da <= MP.far);
    }
    let s0 = (MP.near - da) / (db - da);
    let s1 = (MP.far - da) / (db - da);
    let lo = max(min(s0, s1), 0.0);
    let hi = min(max(s0, s1), 1.0);
    return max(hi - lo, 0.0) * len;
}

// σ_s/(4π)·I(ω)/l²·T(camera → y)·T(light → y) at y = t·d: (f, ω, l).
struct MediaSample {
    f: f32,
    w: vec3<f32>,
    dist: f32,
}

fn media_integrand(l: MediaLight, d: vec3<f32>, t: f32) -> MediaSample {
    let y = d * t;
    let to = y - l.position;
    let dist = length(to);
    if (!(dist > 0.0)) {
        return MediaSample(0.0, vec3<f32>(0.0, 0.0, 1.0), 0.0);
    }
    let w = to / dist;
    let tr = exp(-MP.sigma_t * (media_length_inside(vec3<f32>(0.0), y) + media_length_inside(l.position, y)));
    return MediaSample(MP.sigma_s / (4.0 * PI) * media_intensity(l, w) / (dist * dist) * tr, w, dist);
}

// A chord clipped to [t0, t1]: (a, b, 1) or 0 when empty.
fn media_clip(c: vec3<f32>, t0: f32, t1: f32) -> vec3<f32> {
    if (c.z < 0.5) {
        return vec3<f32>(0.0);
    }
    let a = max(c.x, t0);
    let b = min(c.y, t1);
    return select(vec3<f32>(0.0), vec3<f32>(a, b, 1.0), b > a);
}

// One estimate of light l's in-scattering along unit ray d over [t0, t1] from uniforms u
// (CPU twin: baker::slc::media::estimate): (value, 1), or (0, 0) when the ray misses the
// light's sphere in culled mode (a false discovery of the tile).
fn media_estimate(l: MediaLight, d: vec3<f32>, t0: f32, t1: f32, u: vec2<f32>) -> vec2<f32> {
    let tc = dot(d, l.position);
    let h = max(length(l.position - d * tc), 1e-6 * (1.0 + length(l.position)));
    if (MP.mode == 1u) {
        let s = slc_equiangular_sample(tc, h, t0, t1, u.y);
        return vec2<f32>(select(0.0, media_integrand(l, d, s.x).f / s.y, s.y > 0.0), 1.0);
    }
    let outer = media_clip(slc_ray_sphere(vec3<f32>(0.0), d, media_sphere(l, l.xi)), t0, t1);
    if (outer.z < 0.5) {
        return vec2<f32>(0.0);
    }
    // The inner chord lies inside the outer one (spheres homothetic about the light).
    var inner = media_clip(slc_ray_sphere(vec3<f32>(0.0), d, media_sphere(l, 1.0)), t0, t1);
    if (inner.z > 0.5) {
        inner = vec3<f32>(max(inner.x, outer.x), min(inner.y, outer.y), 1.0);
    }
    // The outer parts: before and after the inner chord, or the whole outer chord.
    var p0 = vec2<f32>(outer.x, outer.y);
    var p1 = vec2<f32>(0.0);
    if (inner.z > 0.5) {
        p0 = vec2<f32>(outer.x, max(inner.x, outer.x));
        p1 = vec2<f32>(min(inner.y, outer.y), outer.y);
    }
    let len0 = max(p0.y - p0.x, 0.0);
    let len1 = max(p1.y - p1.x, 0.0);
    let outer_len = len0 + len1;
    let empty = !(outer_len > 0.0);
    var representative = l.power / PI;
    if (media_is_point(l)) {
        representative = l.power / (4.0 * PI);
    }
    var w_in = 0.0;
    if (inner.z > 0.5) {
        w_in = representative * (atan2(inner.y - tc, h) - atan2(inner.x - tc, h)) / h;
    }
    let w_out = MP.delta * outer_len;
    var p_in = 0.0;
    if (inner.z > 0.5) {
        if (empty || !(abs(w_in) <= 3.4e38)) {
            p_in = 1.0;
        } else {
            p_in = w_in / (w_in + w_out);
        }
    }
    var t: f32;
    var pdf: f32;
    if (empty || u.x < p_in) {
        let s = slc_equiangular_sample(tc, h, inner.x, inner.y, u.y);
        t = s.x;
        pdf = p_in * s.y;
    } else {
        let s = u.y * outer_len;
        if (s <= len0 && len0 > 0.0) {
            t = p0.x + s;
        } else if (len1 > 0.0) {
            t = min(p1.x + (s - len0), p1.y);
        } else {
            t = p0.y;
        }
        pdf = (1.0 - p_in) / outer_len;
    }
    let m = media_integrand(l, d, t);
    let p = slc_acceptance(media_intensity_bound(l, m.w), MP.delta, m.dist);
    return vec2<f32>(select(0.0, m.f / (p * pdf), pdf > 0.0 && p > 0.0), 1.0);
}

// Two uniforms in [0, 1) for (seed, pixel, light): the PCG hash (Jarzynski and Olano 2020).
fn media_uniforms(pixel: u32, light: u32) -> vec2<f32> {
    let h = slc_pcg_hash(slc_pcg_hash(slc_pcg_hash(MP.seed) ^ pixel) ^ light);
    let h2 = slc_pcg_hash(h ^ 0x5bd1e995u);
    return vec2<f32>(f32(h >> 8u), f32(h2 >> 8u)) / 16777216.0;
}

const MEDIA_TILE: u32 = 16u;
var<workgroup> mwg_zmax: atomic<u32>;
// Which of the chunk's 256 lights the tile keeps (bit m of word m / 32), walked in order so
// every pixel sums its lights in light order, whatever order the culling threads finish in.
var<workgroup> mwg_kept: array<atomic<u32>, 8>;

@compute @workgroup_size(16, 16)
fn media_cull_shade(@builtin(workgroup_id) tile: vec3<u32>, @builtin(local_invocation_index) t: u32, @builtin(local_invocation_id) lid: vec3<u32>) {
    let px = tile.x * MEDIA_TILE + lid.x;
    let py = tile.y * MEDIA_TILE + lid.y;
    let inside = px < MP.width && py < MP.height;
    let k = py * MP.width + px;
    let d = normalize(vec3<f32>((2.0 * (f32(px) + 0.5) / f32(MP.width) - 1.0) * MP.tan_x, (1.0 - 2.0 * (f32(py) + 0.5) / f32(MP.height)) * MP.tan_y, -1.0));
    var surface = 3.4e38;
    if (inside) {
        surface = surface_distance[k];
    }
    if (t == 0u) {
        atomicStore(&mwg_zmax, bitcast<u32>(MP.near));
    }
    workgroupBarrier();
    if (inside) {
        // The pixel's medium depth: its surface's, or the slab's far depth.
        atomicMax(&mwg_zmax, bitcast<u32>(min(select(MP.far, surface * -d.z, surface < 3.0e38), MP.far)));
    }
    workgroupBarrier();
    let zmax = bitcast<f32>(atomicLoad(&mwg_zmax));
    let mid = 0.5 * (MP.near + zmax);
    let x0 = f32(tile.x * MEDIA_TILE);
    let y0 = f32(tile.y * MEDIA_TILE);
    let x1 = min(x0 + f32(MEDIA_TILE), f32(MP.width));
    let y1 = min(y0 + f32(MEDIA_TILE), f32(MP.height));
    let size = vec2<f32>(f32(MP.width), f32(MP.height));
    let tan_xy = vec2<f32>(MP.tan_x, MP.tan_y);
    let near_half = slc_tile_corners(x0, y0, x1, y1, size, tan_xy, max(MP.near, 1e-6), mid);
    let far_half = slc_tile_corners(x0, y0, x1, y1, size, tan_xy, max(mid, 1e-6), zmax);
    let ident = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    // The pixel's segment in the medium (CPU twin: ray_segment).
    let per_depth = 1.0 / -d.z;
    let seg0 = MP.near * per_depth;
    let seg1 = min(MP.far * per_depth, surface);
    let has_segment = seg1 > seg0;
    var radiance = vec3<f32>(0.0);
    var kept = 0u;
    var misses = 0u;
    for (var base = 0u; base < MP.light_count; base += 256u) {
        if (t < 8u) {
            atomicStore(&mwg_kept[t], 0u);
        }
        workgroupBarrier();
        let j = base + t;
        if (j < MP.light_count) {
            var keep = true;
            if (MP.mode == 0u) {
                let s = media_sphere(media_light(j), media_light(j).xi);
                let c = slc_cull_transform(SlcEllipsoid(s.center, ident, vec3<f32>(s.radius)), ident, vec3<f32>(0.0));
                keep = zmax > MP.near && (slc_ellipsoid_hits_corners(c, near_half) || slc_ellipsoid_hits_corners(c, far_half));
            }
            if (keep) {
                atomicOr(&mwg_kept[t / 32u], 1u << (t % 32u));
            }
        }
        workgroupBarrier();
        for (var w = 0u; w < 8u; w++) {
            var bits = atomicLoad(&mwg_kept[w]);
            let count = countOneBits(bits);
            kept += count;
            if (!(inside && has_segment)) {
                misses += count;
                continue;
            }
            while (bits != 0u) {
                let lj = base + 32u * w + firstTrailingBit(bits);
                bits &= bits - 1u;
                let l = media_light(lj);
                let e = media_estimate(l, d, seg0, seg1, media_uniforms(k, lj));
                radiance += e.x * l.tint;
                misses += u32(e.y < 0.5);
            }
        }
        workgroupBarrier();
    }
    if (inside) {
        mout[2u * k] = vec4<f32>(radiance, f32(kept));
        mout[2u * k + 1u] = vec4<f32>(f32(misses), 0.0, 0.0, 0.0);
    }
}
