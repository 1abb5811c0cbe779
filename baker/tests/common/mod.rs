//! Helpers shared by the baker's integration tests.

use shaders::gpu::Gpu;

/// The GPU adapter, or None (printed) when there is none — unless `SBF_REQUIRE_GPU=1`
/// (CI), where a missing adapter fails the test.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => {
            println!("adapter: {}", g.adapter);
            Some(g)
        }
        Err(e) if std::env::var("SBF_REQUIRE_GPU").is_ok_and(|v| v == "1") => panic!("SBF_REQUIRE_GPU=1 but {e}"),
        Err(e) => {
            println!("GPU part skipped: {e}");
            None
        }
    }
}
