//! The one interface every bake engine offers — the CPU reference bake, a GPU bake, a bake
//! over several GPUs — so the command's pass loop (progress, checkpoints, resume) and
//! tests drive them alike.

use super::BakeState;

/// A progressive bake: passes (or pilot passes and batches) run in steps, its state read
/// at any point.
pub trait Progressive {
    /// Runs `n` more passes (adaptive and camera-based bakes: pilot passes, then batches).
    fn run(&mut self, n: u64) -> Result<(), String>;
    /// The state so far (moments, encoders, guiding sums, filtered state).
    fn state(&self) -> Result<BakeState, String>;
    /// Passes (and batches) run so far.
    fn passes(&self) -> u64;
}

impl Progressive for super::Bake<'_> {
    fn run(&mut self, n: u64) -> Result<(), String> {
        for _ in 0..n {
            self.pass();
        }
        Ok(())
    }
    fn state(&self) -> Result<BakeState, String> {
        Ok(self.state.clone())
    }
    fn passes(&self) -> u64 {
        self.state.passes
    }
}
