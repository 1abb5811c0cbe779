//! The engine-format modes end to end (fit → encode → engine precision → decode) on a map
//! whose irradiance has a closed form: L(ω) = a + b·ω (non-negative for |b| < a) has
//! E/π(n) = a + (2/3)·b·n exactly (A₀/π = 1, A₁/π = 2/3), and all of it lives in SH L1.
//!
//! Oracles (independent of the library): Godot's (both versions) and MonoSH's linear decodes
//! must return that linear irradiance; Bakery's default non-linear MonoSH decode, with every
//! channel's L1 along the same d = (2/3)b/2 = b/3 (its luminance direction a₁/(2a₀)), must
//! return Geomerics' curve a_k·(α + (1 − α)(p + 1)q^p) with q = ½(1 + d̂·n), p = 1 + 2|d|,
//! α = (1 − |d|)/(1 + |d|) (Hill 2015; the rescale's weight is 1 here: Σa·(1 + 2d·n) ≥ 1/16);
//! Enlighten's must return C·(1 + n·d)/(1 + n₀·d) with C the exact E/π at n₀ = +Y. Error model: the SH
//! projection integrates texel centres over exact solid angles (midpoint rule, relative
//! error ≲ 2·(π/64)²/24 × the integrand's second-derivative ratio ≲ 2: 4e-4 at 128 × 64),
//! the colour is rounded to f16 (2⁻¹¹ relative, × a decode factor ≤ 3), MonoSH's and
//! Enlighten's directions to 8 bits (1/510 per component, × 4·a₀ summed over |n_k| ≤ √3 for
//! MonoSH — × 3 for the non-linear curve, whose slope in q, p(p + 1)q^(p−1) ≤ 12 at p ≤ 3, is
//! three times the linear decode's; Enlighten's rescaling factor too, relative 1/(510·w)).

use probes::modes::{prepare, Context};
use sbf::envmap::LatLongImage;
use sbf::glam::DVec3;

#[test]
fn engine_modes_decode_the_closed_form_irradiance_of_a_linear_map() {
    let a = [1.0, 0.6, 0.3];
    let b = DVec3::new(0.3, 0.45, -0.2);
    let map = LatLongImage::from_fn(128, 64, |d| a.map(|ak| ak * (1.0 + b.dot(d)))).unwrap();
    let ctx = Context::new(map);
    let lin = |n: DVec3| a.map(|ak| ak * (1.0 + (2.0 / 3.0) * b.dot(n)));
    let up = DVec3::Y;
    let d = b * (2.0 / 3.0) / 2.0;
    let quad = 4e-4 * 3.0;
    let geomerics = |n: DVec3| {
        let dl = d.length();
        let q = 0.5 * (1.0 + n.dot(d / dl));
        let p = 1.0 + 2.0 * dl;
        let alpha = (1.0 - dl) / (1.0 + dl);
        a.map(|ak| ak * (alpha + (1.0 - alpha) * (p + 1.0) * q.powf(p)))
    };
    for id in ["godot-l1", "godot-l1-legacy", "monosh", "monosh-linear", "enlighten", "enlighten-rgb"] {
        let r = prepare(id, &ctx, 1).unwrap().result;
        assert_eq!(r.irradiance.len(), ctx.dirs.len());
        let mut worst = 0.0f64;
        for (n, got) in ctx.dirs.iter().zip(&r.irradiance) {
            let want = match id {
                "godot-l1" | "godot-l1-legacy" | "monosh-linear" => lin(*n),
                "monosh" => geomerics(*n),
                _ => {
                    let c = lin(up);
                    [0, 1, 2].map(|k| c[k] * (1.0 + n.dot(d)) / (1.0 + up.dot(d)))
                }
            };
            let dir_err = match id {
                "godot-l1" | "godot-l1-legacy" => 8.0 * 2f64.powi(-12) * 3f64.sqrt(),
                "monosh-linear" => 4.0 / 510.0 * 3f64.sqrt(),
                "monosh" => 3.0 * 4.0 / 510.0 * 3f64.sqrt(),
                // Half-Lambert over w ≥ ½(1 − |d|): direction 1/510 per component and w
                // 1/510, relative to w.
                _ => (3f64.sqrt() / 510.0 + 1.0 / 510.0) / (0.5 * (1.0 - d.length())),
            };
            for k in 0..3 {
                let tol = a[k] * (quad + 3.0 * 2f64.powi(-11) + dir_err);
                let e = (got[k] - want[k]).abs();
                worst = worst.max(e / tol);
                assert!(e <= tol, "{id} at {n} channel {k}: {} vs {} (tol {tol:.2e})", got[k], want[k]);
            }
        }
        println!("{id}: worst error / tolerance {worst:.3}");
        assert!(r.storage_bytes() < 48.0, "{id}: an engine format stores less than f32 SH L1 ({} B)", r.storage_bytes());
    }
}
