#define_import_path baker::filter_kernel

// The gather's separable reconstruction filters (baker::gpu_prims::GatherFilter::weight_1d,
// the same f32 steps): the 1D weight at offset d for radius r; kernel 0 box (1 inside r),
// 1 Gaussian (σ = r/2, shifted to 0 at r), 2 Mitchell–Netravali (B = C = 1/3) over
// [−r, r], negative lobes included. Used by the filter's gather (filter_gather.wgsl).
fn filter_kernel_1d(kernel: u32, r: f32, d: f32) -> f32 {
    let a = abs(d);
    switch kernel {
        case 0u: {
            return select(0.0, 1.0, a < r);
        }
        case 1u: {
            let s2 = 2.0 * (0.5 * r) * (0.5 * r);
            return max(exp(-d * d / s2) - exp(-r * r / s2), 0.0);
        }
        default: {
            let x = 2.0 * a / r;
            let b = 1.0 / 3.0;
            let c = 1.0 / 3.0;
            if (x < 1.0) {
                return ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)) / 6.0;
            }
            if (x < 2.0) {
                return ((-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)) / 6.0;
            }
            return 0.0;
        }
    }
}
