//! `check_workgroup_memory` against sizes counted by hand from WGSL's layout rules
//! (WGSL §14.4: vec4<f32> 16 bytes, u32 4, an array its element's stride × its length,
//! atomic<u32> 4).

use shaders::gpu::check_workgroup_memory;

const SOURCE: &str = "
var<workgroup> records: array<vec4<f32>, 256>;
var<workgroup> flags: array<atomic<u32>, 3>;
var<workgroup> count: atomic<u32>;
var<private> not_shared: array<vec4<f32>, 64>;
@compute @workgroup_size(64)
fn main(@builtin(local_invocation_index) t: u32) {
    records[t] = vec4<f32>(f32(t));
    atomicAdd(&flags[t % 3u], 1u);
    atomicAdd(&count, 1u);
    not_shared[t] = records[t];
}
";

// 256 × 16 + 3 × 4 + 4 bytes; the private array is not workgroup memory.
const BYTES: u32 = 256 * 16 + 3 * 4 + 4;

#[test]
fn sums_the_workgroup_variables_and_nothing_else() {
    assert_eq!(check_workgroup_memory("test", SOURCE, BYTES), Ok(()));
    let e = check_workgroup_memory("test", SOURCE, BYTES - 1).unwrap_err();
    assert!(e.contains(&format!("needs {BYTES} bytes")) && e.contains(&format!("allows {}", BYTES - 1)), "{e}");
}

#[test]
fn bad_wgsl_is_an_error() {
    assert!(check_workgroup_memory("test", "fn f( {", 1 << 16).unwrap_err().starts_with("test: "));
}
