// The PCG hash (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering"), shared by the
// light-culling kernels (cull.wgsl, media.wgsl): their GPU random numbers.
fn slc_pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
