//! Helpers shared by the baker's integration tests.

#[allow(dead_code)]
pub mod gltf;
#[allow(dead_code)]
pub mod outputs;

/// The process-wide device, leased for the calling test alone (GPU tests run one at a
/// time: see `shaders::gpu::Lease`), or None (printed) when there is none — unless
/// `SBF_REQUIRE_GPU=1` (CI), where a missing adapter fails the test. A watchdog fails the
/// binary loudly (status 124) if one test holds the device longer than 900 s
/// (`SBF_GPU_TEST_TIMEOUT_S`).
#[allow(dead_code)]
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

/// Runs `passes` passes (or pilot passes and batches) of `targets` on the GPU `gpu`, or on
/// the CPU reference path without one; returns the state.
#[allow(dead_code)]
pub fn bake_on(
    gpu: Option<&shaders::gpu::Gpu>,
    scene: &baker::scene::Scene,
    targets: &baker::accumulate::Targets,
    cfg: &baker::accumulate::BakeConfig,
    passes: u64,
) -> baker::accumulate::BakeState {
    use baker::estimator::trace::Tracer;
    let bvh = baker::scene::bvh::Bvh::build(scene);
    match gpu {
        Some(g) => {
            let mut b = baker::gpu::GpuBake::new(g, &Tracer::new(scene, &bvh, cfg.max_bounces), targets, cfg).unwrap();
            b.run(passes).unwrap();
            b.state().unwrap()
        }
        None => {
            let mut b = baker::accumulate::Bake::new(cfg.clone(), targets, Tracer::new(scene, &bvh, cfg.max_bounces));
            for _ in 0..passes {
                b.pass();
            }
            b.state
        }
    }
}
