//! Helpers shared by the baker's integration tests.

use shaders::gpu::Gpu;

/// The process-wide device (shared by every test of the binary), or None (printed) when
/// there is none — unless `SBF_REQUIRE_GPU=1` (CI), where a missing adapter fails the test.
/// The first call arms a watchdog: the whole test binary must finish within 1 200 s
/// (`SBF_GPU_TEST_TIMEOUT_S`), or it exits loudly with status 124 instead of hanging.
pub fn gpu() -> Option<&'static Gpu> {
    static WATCHDOG: std::sync::OnceLock<shaders::gpu::Watchdog> = std::sync::OnceLock::new();
    WATCHDOG.get_or_init(|| shaders::gpu::Watchdog::start("baker GPU tests (this binary)", 1200));
    match shaders::gpu::shared() {
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
