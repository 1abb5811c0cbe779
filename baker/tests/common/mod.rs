//! Helpers shared by the baker's integration tests.

/// The process-wide device, leased for the calling test alone (GPU tests run one at a
/// time: see `shaders::gpu::Lease`), or None (printed) when there is none — unless
/// `SBF_REQUIRE_GPU=1` (CI), where a missing adapter fails the test. A watchdog fails the
/// binary loudly (status 124) if one test holds the device longer than 900 s
/// (`SBF_GPU_TEST_TIMEOUT_S`).
pub fn gpu() -> Option<shaders::gpu::Lease> {
    let name = std::thread::current().name().unwrap_or("baker GPU test").to_string();
    match shaders::gpu::lease(&name, 900) {
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
