// Camera-based lightmap sampling (CPU twin: baker::camera). The scene is rasterised with
// a jittered projection into a texel-index target (u32, 0xffffffff where no lightmapped
// surface is seen); count_pixels adds one sample per pixel to its texel's item, and
// camera_flags turns the counts into the batch's samples (capped) and flags for the
// compaction, resetting the counts.

struct CameraParams {
    view_proj: mat4x4<f32>,
    atlas_width: u32,
    atlas_height: u32,
    image_width: u32,
    image_height: u32,
    items: u32,
    max_per_batch: u32,
    pad_a: u32,
    pad_b: u32,
}

const NO_TEXEL: u32 = 0xffffffffu;

@group(0) @binding(0) var<uniform> C: CameraParams;

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    // Atlas position in texels (negative: not lightmapped).
    @location(0) uv: vec2<f32>,
}

@vertex
fn raster_vs(@location(0) p: vec3<f32>, @location(1) uv: vec2<f32>) -> VertexOut {
    return VertexOut(C.view_proj * vec4<f32>(p, 1.0), uv);
}

@fragment
fn raster_fs(v: VertexOut) -> @location(0) u32 {
    let t = floor(v.uv);
    if (v.uv.x < 0.0 || t.x < 0.0 || t.y < 0.0 || t.x >= f32(C.atlas_width) || t.y >= f32(C.atlas_height)) {
        return NO_TEXEL;
    }
    return u32(t.y) * C.atlas_width + u32(t.x);
}

@group(0) @binding(1) var texel_image: texture_2d<u32>;
// Per atlas texel, its item (0xffffffff: no valid texel).
@group(0) @binding(2) var<storage, read> texel_item: array<u32>;
@group(0) @binding(3) var<storage, read_write> pixel_counts: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> batch_samples: array<u32>;
@group(0) @binding(5) var<storage, read_write> flags: array<u32>;

@compute @workgroup_size(8, 8)
fn count_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= C.image_width || gid.y >= C.image_height) {
        return;
    }
    let t = textureLoad(texel_image, vec2<i32>(gid.xy), 0).x;
    if (t == NO_TEXEL || t >= C.atlas_width * C.atlas_height) {
        return;
    }
    let item = texel_item[t];
    if (item != NO_TEXEL) {
        atomicAdd(&pixel_counts[item], 1u);
    }
}

@compute @workgroup_size(64)
fn camera_flags(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = gid.x + gid.y * nwg.x * 64u;
    if (i >= C.items) {
        return;
    }
    let n = min(atomicExchange(&pixel_counts[i], 0u), C.max_per_batch);
    batch_samples[i] = n;
    flags[i] = select(0u, 1u, n > 0u);
}
