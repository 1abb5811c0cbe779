//! ZH3 lightmaps (`--bases zh3`): SH L1's four coefficients, reconstructed at run time with
//! ZH3's hallucinated zonal band 2 (Roughton, Kuhlmann, Mitchell, Smith, "ZH3: Quadratic
//! Zonal Harmonics", i3D 2024). The bake stores exactly SH L1's coefficients; the Lambert
//! runtime adds, along the luminance-weighted L1 axis a, the zonal band-2 coefficient
//! L0·(0.08·r + 0.6·r²), r = |L1·a|/L0 per channel, convolved with the cosine lobe
//! (A₂/π = 1/4) — transcribed here from the paper, not from `sbf`. Mutations tried: the
//! runtime's ZH3 term dropped (zh3 = sh1), the luminance weights swapped for equal ones —
//! each fails.

use baker::accumulate::{Bake, BakeConfig, BakedBasis, BasisId, Solver, Targets};
use baker::estimator::trace::Tracer;
use baker::layout::lightmap::Lightmap;
use baker::scene::{self, bvh::Bvh};
use sbf::glam::DVec3;

#[test]
fn zh3_stores_sh_l1_and_adds_the_hallucinated_zonal_term() {
    let s = scene::cornell();
    let bvh = Bvh::build(&s);
    let lm = Lightmap::build(&s, 2.0, 1).unwrap();
    let cfg = BakeConfig { bases: vec![BasisId::Sh1, BasisId::Zh3], solver: Solver::Ls, ..Default::default() };
    let targets = Targets::lightmap(&lm);
    let mut bake = Bake::new(cfg.clone(), &targets, Tracer::new(&s, &bvh, cfg.max_bounces));
    for _ in 0..8 {
        bake.pass();
    }
    let (sh1, zh3) = (&bake.state.encoders[0], &bake.state.encoders[1]);
    let mut checked = 0;
    for (t, (a, b)) in sh1.iter().zip(zh3).enumerate() {
        // The same encoder on the same samples: the same coefficients, bit for bit.
        assert_eq!(a.coefficients(), b.coefficients(), "texel {t}: zh3 stores SH L1's coefficients");
        let c: Vec<DVec3> =
            (0..4).map(|i| DVec3::new(a.coefficients()[(i, 0)], a.coefficients()[(i, 1)], a.coefficients()[(i, 2)])).collect();
        if c[0].min_element() <= 0.0 {
            continue;
        }
        let n = DVec3::new(0.3, -0.2, 0.93).normalize();
        let linear = BasisId::Sh1.irradiance_at(&c, n, 6.0);
        let got = BasisId::Zh3.irradiance_at(&c, n, 6.0);
        // The paper's term: L1 as a vector (x, y, z) = (c₃, c₁, c₂); the axis from the
        // luminance (Rec. 709) of the three channels' L1 vectors.
        let l1 = |k: usize| DVec3::new(c[3][k], c[1][k], c[2][k]);
        let lum = l1(0) * 0.2126 + l1(1) * 0.7152 + l1(2) * 0.0722;
        if lum.length() < 1e-9 {
            continue;
        }
        let axis = lum.normalize();
        let y20 = |x: f64| (5.0 / (4.0 * std::f64::consts::PI)).sqrt() * 0.5 * (3.0 * x * x - 1.0);
        for k in 0..3 {
            let r = l1(k).dot(axis).abs() / c[0][k];
            let zh = c[0][k] * (0.08 * r + 0.6 * r * r);
            let want = linear[k] + 0.25 * zh * y20(n.dot(axis));
            // Both in f64 from the same coefficients: rounding only.
            assert!((got[k] - want).abs() <= 1e-12 * (1.0 + want.abs()), "texel {t} channel {k}: {} vs {want}", got[k]);
        }
        checked += 1;
    }
    assert!(checked > 50, "only {checked} texels with light and an L1 direction");
}
