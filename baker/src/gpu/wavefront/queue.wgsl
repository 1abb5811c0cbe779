// ---- wavefront passes: wave_start and wave_args ([Roughton19 §5.1]) ----
// One thread each: the first queue's length, and the indirect dispatch arguments of the
// queue's passes from its length after each compaction.

#import baker::wave::{WAVE_LENGTH, WAVE_SLOTS, paths, wave, write_wave_args}

// The first queue: the slots generate took (all of them; a full pool took none more).
@compute @workgroup_size(1)
fn wave_start() {
    atomicStore(&wave[WAVE_LENGTH], min(atomicLoad(&wave[WAVE_SLOTS]), arrayLength(&paths)));
    write_wave_args();
}

@compute @workgroup_size(1)
fn wave_args_from_length() {
    write_wave_args();
}
