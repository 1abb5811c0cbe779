// filter_bindings.wgsl — filtered gather-based accumulation's parameters and buffers
// ([Roughton19 §3.2]; bindings 14–18; Rust twin baker::gpu::filter::FilterParams).

#define_import_path baker::filter_bindings

#import sbf::runtime::EncoderState

struct FilterParams {
    width: u32,
    height: u32,
    target_count: u32,
    kernel: u32,
    radius: f32,
    reach: u32,
    passes: u32,
    charts_offset: u32,
    items_offset: u32,
    row: u32,
    // Records per item, and 1 while gathering a batch (0: uniform passes).
    slots: u32,
    batch: u32,
    // Items in the bake (records are stored component-major: component c of slot s of
    // item i at (c·slots + s)·items + i, so a warp's stores and loads are contiguous).
    items: u32,
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
}

@group(0) @binding(14) var<storage, read_write> fsamples: array<vec4<f32>>;
@group(0) @binding(15) var<storage, read_write> fstates: array<EncoderState>;
// Per target: (mean.xyz, Σw), (M2.xyz, Σw²), (samples, negative-weight samples, 0, 0).
@group(0) @binding(16) var<storage, read_write> fmoments: array<vec4<f32>>;
// The gather targets' atlas ids, then per atlas texel its chart, then its item.
@group(0) @binding(17) var<storage, read> ftables: array<u32>;
@group(0) @binding(18) var<uniform> FP: FilterParams;

const FILTER_NONE: u32 = 0xffffffffu;
