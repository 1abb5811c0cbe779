//! One device per process shared by the tests that lease it one at a time, each under a
//! watchdog.

use super::Gpu;

/// One device per process, created on first use and shared by every caller (tests run
/// on many threads: one device avoids N concurrent device creations and N first-time
/// pipeline compilations competing on a freshly started driver). The error is kept too,
/// so every caller sees the same reason.
pub fn shared() -> Result<&'static Gpu, String> {
    static GPU: std::sync::OnceLock<Result<Gpu, String>> = std::sync::OnceLock::new();
    GPU.get_or_init(Gpu::new).as_ref().map_err(|e| e.clone())
}

/// Exclusive use of the process-wide device for one test: holds a process-wide lock (GPU
/// tests of one binary run one at a time — wgpu's GL backend guards its context with a
/// lock that times out after a second, so concurrent tests on GL llvmpipe panicked with
/// "Could not lock adapter context"), then arms a [`Watchdog`] for the test's own run time
/// (waiting for the lock is not counted), then gets the device. Derefs to [`Gpu`].
#[derive(Debug)]
pub struct Lease {
    gpu: &'static Gpu,
    _watchdog: Watchdog,
    _guard: std::sync::MutexGuard<'static, ()>,
}

impl std::ops::Deref for Lease {
    type Target = Gpu;
    fn deref(&self) -> &Gpu {
        self.gpu
    }
}

/// Takes the lease (see [`Lease`]): `what` names the test in the watchdog's message,
/// `limit_s` is its default limit. Errors when no adapter exists.
pub fn lease(what: &str, limit_s: u64) -> Result<Lease, String> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    // A test that panicked while holding the lock leaves it poisoned; the device is still
    // usable for the next test.
    let guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let watchdog = Watchdog::start(what, limit_s);
    let gpu = shared()?;
    Ok(Lease { gpu, _watchdog: watchdog, _guard: guard })
}

/// Fails the process loudly if a GPU test runs longer than its limit: a kernel or a driver
/// call that hangs cannot be unwound, so the watchdog prints what was running and exits
/// with status 124 (as `timeout` does). Dropping the guard disarms it. The limit is
/// `SBF_GPU_TEST_TIMEOUT_S` seconds when set, else `default_s`.
#[derive(Debug)]
pub struct Watchdog {
    done: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl Watchdog {
    pub fn start(what: &str, default_s: u64) -> Watchdog {
        let limit = std::env::var("SBF_GPU_TEST_TIMEOUT_S").ok().and_then(|v| v.parse::<u64>().ok()).unwrap_or(default_s);
        let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = done.clone();
        let what = what.to_string();
        std::thread::spawn(move || {
            let start = std::time::Instant::now();
            while start.elapsed().as_secs() < limit {
                std::thread::sleep(std::time::Duration::from_millis(200));
                if flag.load(std::sync::atomic::Ordering::Relaxed) {
                    return;
                }
            }
            // Straight to the process's stderr: the test harness captures eprintln! and
            // would drop it when the process exits.
            use std::io::Write;
            let _ = writeln!(
                std::io::stderr(),
                "GPU watchdog: '{what}' still running after {limit} s (SBF_GPU_TEST_TIMEOUT_S) — exiting with status 124"
            );
            std::process::exit(124);
        });
        Watchdog { done }
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.done.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}
