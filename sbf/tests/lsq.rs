//! Batch least squares: orthonormal closed form, design vs Gram form, stiff cases.

use sbf::envmap::{LatLongImage, ProceduralSky};
use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::nalgebra::DMatrix;
use sbf::quadrature::SphereQuadrature;
use sbf::solve::{map_samples, moments, sample_gram, solve_design, solve_gram, LsMethod, LsOptions, RadianceSample};
use sbf::{AmbientDiceSrbf, Basis, Domain, SgBasis, ShBasis};

fn sky_samples() -> Vec<RadianceSample> {
    let sky = ProceduralSky::default();
    map_samples(&LatLongImage::from_fn(128, 64, |d| sky.radiance(d)).unwrap())
}

/// Known coefficients come back: radiance f = Σ c_i Y_i (L6, random c) sampled on a rule
/// exact for degree 12 (so the moments ∫f·Y_i are exact), fitted by the library's Gram
/// (closed form for SH) and Cholesky solve, returns c. The oracle is c itself, chosen
/// before any library call. Error model: exact rule, G = I, so only rounding of ~10³-term
/// sums (≈ 1e-13·‖c‖₁); bar 1e-11·‖c‖∞. A wrong Gram, moment or solve is an O(1) error.
#[test]
fn batch_ls_recovers_known_sh_coefficients() {
    let sh = ShBasis::new(6).unwrap();
    let n = sh.len();
    let mut rng = sbf::sampling::Pcg32::new(77, 3);
    let c: Vec<f64> = (0..n).map(|_| 2.0 * rng.next_2d()[0] - 1.0).collect();
    let rule = SphereQuadrature::exact_for_degree(Domain::Sphere, 12);
    let samples: Vec<RadianceSample> = rule
        .directions
        .iter()
        .zip(&rule.weights)
        .map(|(d, w)| {
            let f: f64 = sh.eval(*d).iter().zip(&c).map(|(y, ci)| y * ci).sum();
            RadianceSample { direction: *d, value: [f, 2.0 * f, -f], weight: *w }
        })
        .collect();
    let m = moments(&sh, &samples);
    let g = gram_matrix(&sh, Domain::Sphere, GramOptions::default()).unwrap();
    let sol = solve_gram(&g.matrix, &m, LsOptions::default()).unwrap();
    assert_eq!(sol.method, LsMethod::Cholesky);
    assert_eq!(sol.rank, 49);
    let cmax = c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for (ch, scale) in [(0, 1.0), (1, 2.0), (2, -1.0)] {
        let err = (0..n).map(|i| (sol.coeffs[(i, ch)] - scale * c[i]).abs()).fold(0.0, f64::max);
        assert!(err < 1e-11 * cmax, "channel {ch}: max |b − c| = {err:e}");
    }
}

/// Design-matrix LS on an exact quadrature rule (weights = rule weights) gives the
/// same SH coefficients as projection, since the rule's sample Gram is I.
#[test]
fn design_form_matches_projection_on_exact_rule() {
    let sh = ShBasis::new(3).unwrap();
    let rule = SphereQuadrature::exact_for_degree(Domain::Sphere, 6);
    let sky = ProceduralSky { sun_radiance: [0.0; 3], ..ProceduralSky::default() };
    let n = sh.len();
    let a = DMatrix::from_fn(rule.len(), n, |r, c| sh.eval(rule.directions[r])[c]);
    let y = DMatrix::from_fn(rule.len(), 3, |r, c| sky.radiance(rule.directions[r])[c]);
    let sol = solve_design(&a, &y, Some(&rule.weights), LsOptions::default()).unwrap();
    assert_eq!(sol.method, LsMethod::Qr);
    let samples: Vec<RadianceSample> = rule
        .directions
        .iter()
        .zip(&rule.weights)
        .map(|(d, w)| RadianceSample { direction: *d, value: sky.radiance(*d), weight: *w })
        .collect();
    let m = moments(&sh, &samples);
    let err = (&sol.coeffs - &m).abs().max();
    assert!(err < 1e-12, "design vs projection {err:e}");
}

/// Gram form with the samples' own Gram equals design-form LS on the same samples.
#[test]
fn gram_and_design_forms_agree() {
    let ad = AmbientDiceSrbf::twelve();
    let mut rng = sbf::sampling::Pcg32::new(5, 5);
    let sky = ProceduralSky::default();
    let samples: Vec<RadianceSample> = (0..2000)
        .map(|_| {
            let d = sbf::sampling::uniform_sphere(rng.next_2d());
            RadianceSample { direction: d, value: sky.radiance(d), weight: 4.0 * std::f64::consts::PI / 2000.0 }
        })
        .collect();
    let g = sample_gram(&ad, &samples);
    let m = moments(&ad, &samples);
    let a = DMatrix::from_fn(samples.len(), 12, |r, c| ad.eval(samples[r].direction)[c]);
    let y = DMatrix::from_fn(samples.len(), 3, |r, c| samples[r].value[c]);
    let gs = solve_gram(&g, &m, LsOptions::default()).unwrap();
    let ds = solve_design(&a, &y, None, LsOptions::default()).unwrap();
    // cond ≈ 13² for the normal equations: agreement to ~1e-12 relative.
    let err = (&gs.coeffs - &ds.coeffs).abs().max() / ds.coeffs.abs().max();
    assert!(err < 1e-10, "{err:e}");
    assert!((gs.condition - ds.condition).abs() / ds.condition < 1e-8, "{} vs {}", gs.condition, ds.condition);
}

/// Stiff cases: SG 12 at λ = 0.25 (cond ~3e7) and SG 12 + ambient at λ = 0.05 solve
/// without NaN and report condition number and rank; duplicated lobes are rank
/// deficient and go through the pseudo-inverse; Tikhonov shrinks the solution.
#[test]
fn stiff_cases_report_condition_and_rank() {
    let vogel = sbf::layout::vogel_sphere(12).unwrap();
    let samples = sky_samples();
    for (label, basis) in
        [("λ=0.25", SgBasis::new(&vogel, 0.25, false).unwrap()), ("λ=0.05 + ambient", SgBasis::new(&vogel, 0.05, true).unwrap())]
    {
        let g = gram_matrix(&basis, Domain::Sphere, GramOptions::default()).unwrap();
        let m = moments(&basis, &samples);
        let sol = solve_gram(&g.matrix, &m, LsOptions::default()).unwrap();
        println!("SG12 {label}: cond {:.3e}, rank {}/{}, method {:?}", sol.condition, sol.rank, basis.len(), sol.method);
        assert!(sol.coeffs.iter().all(|v| v.is_finite()), "{label}: NaN/Inf in solution");
        assert!(sol.condition > 1e6, "{label}: cond {}", sol.condition);
        // The fit reproduces the moments (the quantity LS controls) to cond·ε.
        let resid = (&g.matrix * &sol.coeffs - &m).abs().max() / m.abs().max();
        assert!(resid < 1e-6, "{label}: moment residual {resid:e}");
    }
    // math.md: SG12 λ = 0.25 has cond ≈ 3e7.
    let c = sbf::gram::condition_number(
        &gram_matrix(&SgBasis::new(&vogel, 0.25, false).unwrap(), Domain::Sphere, GramOptions::default()).unwrap().matrix,
    );
    assert!(c > 1e7 && c < 1e8, "cond {c:e}");

    let dup = AmbientDiceSrbf::from_axes(&[DVec3::Z, DVec3::Z, DVec3::X, DVec3::NEG_Z], Domain::Sphere).unwrap();
    let g = gram_matrix(&dup, Domain::Sphere, GramOptions::default()).unwrap();
    let m = moments(&dup, &samples);
    let sol = solve_gram(&g.matrix, &m, LsOptions::default()).unwrap();
    assert_eq!(sol.method, LsMethod::EigenPseudoInverse);
    assert_eq!(sol.rank, 3);
    assert!((sol.coeffs[(0, 0)] - sol.coeffs[(1, 0)]).abs() < 1e-9, "minimum-norm splits duplicates evenly");
    let reg = solve_gram(&g.matrix, &m, LsOptions { tikhonov: 1e-2, ..LsOptions::default() }).unwrap();
    assert_eq!(reg.rank, 4);
    assert!(reg.coeffs.norm() <= sol.coeffs.norm() * (1.0 + 1e-12));
}

#[test]
fn ls_bad_input() {
    let g = DMatrix::<f64>::identity(3, 3);
    assert!(solve_gram(&g, &DMatrix::zeros(2, 3), LsOptions::default()).is_err());
    let mut bad = g.clone();
    bad[(0, 1)] = f64::NAN;
    assert!(solve_gram(&bad, &DMatrix::zeros(3, 1), LsOptions::default()).is_err());
    assert!(solve_gram(&g, &DMatrix::zeros(3, 1), LsOptions { tikhonov: -1.0, ..LsOptions::default() }).is_err());
    assert!(solve_design(&DMatrix::zeros(2, 3), &DMatrix::zeros(2, 1), None, LsOptions::default()).is_err());
    assert!(solve_design(&DMatrix::zeros(4, 3), &DMatrix::zeros(4, 1), Some(&[1.0, -1.0, 1.0, 1.0]), LsOptions::default()).is_err());
}
