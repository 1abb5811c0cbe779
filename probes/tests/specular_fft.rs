//! The deterministic GGX reference (azimuthal FFT quadrature): its FFT and
//! folding machinery against a direct sum of the same quadrature rule, and the reference
//! against a 2^20-sample MIS estimate (16 Cranley–Patterson replicates) on the five
//! probes. The probe part needs `../shared/probes`; with SBF_REQUIRE_PROBES=1 (CI) a
//! missing folder fails instead of skipping.

use probes::modes::Context;
use probes::specular::{ggx_kernel, reference_fft, subdivision};
use sbf::envmap::{LatLong, LatLongImage};
use sbf::glam::DVec3;
use sbf::sampling::Pcg32;
use sbf::Domain;
use std::f64::consts::PI;
use std::path::PathBuf;

/// The quadrature rule written out directly: every sub-cell of every texel, bilinear
/// radiance at its centre (`bilinear_uv`), the kernel at (output direction, centre), the
/// sub-cell's exact solid angle — no FFT, no folding.
fn direct(map: &LatLongImage, out: LatLong, domain: Domain, alpha: f64, sub: usize, i: usize, j: usize) -> [f64; 3] {
    let g = map.geometry;
    let d = out.texel_direction(i, j);
    let mut acc = [0.0; 3];
    for row in 0..g.height * sub {
        let (t0, t1) = (PI * row as f64 / (g.height * sub) as f64, PI * (row + 1) as f64 / (g.height * sub) as f64);
        let omega = 2.0 * PI / (g.width * sub) as f64 * (t0.cos() - t1.cos());
        let v = (row as f64 + 0.5) / (g.height * sub) as f64;
        for col in 0..g.width * sub {
            let u = (col as f64 + 0.5) / (g.width * sub) as f64;
            let l = LatLong::uv_to_direction(u, v);
            let k = match domain {
                Domain::Sphere => ggx_kernel(d, d, l, alpha),
                Domain::UpperHemisphere => ggx_kernel(DVec3::Y, d, l, alpha),
            };
            if k != 0.0 {
                let r = map.bilinear_uv(u, v);
                for c in 0..3 {
                    acc[c] += omega * k * r[c];
                }
            }
        }
    }
    acc
}

/// A 32 × 16 map of random radiance with a few bright texels (a dynamic range of 10⁴).
fn random_map() -> LatLongImage {
    let mut r = Pcg32::new(5, 5);
    let texels = (0..32 * 16)
        .map(|k| {
            let spike = if k % 97 == 13 { 1e4 } else { 1.0 };
            [0, 1, 2].map(|_| (r.next_f64() * spike) as f32)
        })
        .collect();
    LatLongImage::new(32, 16, texels).unwrap()
}

/// FFT + folding = the direct sum, to f64 rounding: both domains, α 0.1 and 0.6,
/// subdivisions 1–3, output grids of the map's width and of half of it, every output
/// texel. Tolerance 1e-11 of Σ|terms| (≈ the largest value here): the FFT of length 32
/// and the folding reorder ~10⁵ products, each rounded to 2⁻⁵³.
#[test]
fn fft_quadrature_equals_the_direct_sum() {
    let map = random_map();
    for domain in [Domain::UpperHemisphere, Domain::Sphere] {
        for (alpha, sub) in [(0.1, 3), (0.6, 1), (0.6, 2)] {
            for out in [LatLong { width: 32, height: 16 }, LatLong { width: 16, height: 8 }] {
                let q = probes::azimuthal::Quadrature::new(&map, out).unwrap();
                let theta = |j: usize| PI * (j as f64 + 0.5) / out.height as f64;
                let kernel = |j: usize, tl: f64, dphi: f64| {
                    let l = probes::azimuthal::direction(tl, 0.0);
                    let v = probes::azimuthal::direction(theta(j), dphi);
                    match domain {
                        Domain::Sphere => ggx_kernel(v, v, l, alpha),
                        Domain::UpperHemisphere => ggx_kernel(DVec3::Y, v, l, alpha),
                    }
                };
                let fft = q.integrate(0..out.height, sub, &kernel);
                let top = fft.iter().flat_map(|x| x.iter()).fold(0.0f64, |a, x| a.max(x.abs()));
                for j in 0..out.height {
                    for i in 0..out.width {
                        let want = direct(&map, out, domain, alpha, sub, i, j);
                        let got = fft[j * out.width + i];
                        for c in 0..3 {
                            assert!(
                                (got[c] - want[c]).abs() <= 1e-11 * top.max(1.0),
                                "{domain:?} α {alpha} S {sub} {}×{} texel ({i}, {j}): {} vs {}",
                                out.width,
                                out.height,
                                got[c],
                                want[c]
                            );
                        }
                    }
                }
            }
        }
    }
    // Widths that do not divide are refused, not approximated.
    assert!(probes::azimuthal::Quadrature::new(&map, LatLong { width: 12, height: 6 }).is_err());
}

fn probe(name: &str) -> Option<LatLongImage> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../shared/probes/{name}.hdr"));
    if !p.exists() {
        assert!(std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"), "SBF_REQUIRE_PROBES=1 but {} is missing", p.display());
        eprintln!("skipping: {} not found", p.display());
        return None;
    }
    Some(probes::input::load_map(&p, true).expect("probe loads").0)
}

/// The reference against Monte Carlo: on each of the five probes,
/// Appendix C geometry (normal +Y, view over the upper hemisphere), α 0.1, 0.2, 0.4, 0.6,
/// 0.8, three output texels (θ_v ≈ 22°, 45°, 67°), the MIS estimator of the same
/// bilinear radiance with 2^20 visible-normal and 2^20 map samples — 16 independent
/// Cranley–Patterson replicates of 2^16, σ from their spread — must contain the reference
/// within 3σ + the reference's own quadrature error (4/3·|R_S − R_2S| at that texel,
/// computed here), per channel. Reported: the largest |z| and the cells beyond 3σ — where
/// the quadrature error (≈ 1e-4 of the signal beside uffizi's bright window at S = 2–4)
/// exceeds the MIS estimate's σ (a few 1e-5): 2^20 QMC samples resolve it.
#[test]
fn fft_reference_matches_mis_within_3_sigma() {
    let names = ["ennis", "grace", "pisa", "uffizi", "wells"];
    let mut worst = 0.0f64;
    for name in names {
        let Some(map) = probe(name) else { return };
        let ctx = Context::with_domain(map, Domain::UpperHemisphere);
        let sampler = sbf::recon::reference::MapSampler::new(&ctx.map).expect("the probes are not black");
        let (w, h) = (ctx.grid.width, ctx.grid.height);
        let texels = [(w / 5, h / 8), (w / 2, h / 4), (4 * w / 5, 3 * h / 8)];
        for alpha in [0.1, 0.2, 0.4, 0.6, 0.8] {
            let img = reference_fft(&ctx, alpha).unwrap().image;
            let sub = subdivision(alpha, ctx.map.geometry.height);
            let q = probes::azimuthal::Quadrature::new(&ctx.map, ctx.grid).unwrap();
            let kernel = |j: usize, tl: f64, dphi: f64| {
                let v = probes::azimuthal::direction(PI * (j as f64 + 0.5) / h as f64, dphi);
                ggx_kernel(DVec3::Y, v, probes::azimuthal::direction(tl, 0.0), alpha)
            };
            for (i, j) in texels {
                let fine = q.integrate(j..j + 1, 2 * sub, &kernel)[i];
                let v = ctx.grid.texel_direction(i, j);
                let mut rng = Pcg32::new(0x5eed ^ (i * 1000 + j) as u64, (alpha * 100.0) as u64);
                let reps: Vec<[f64; 3]> = (0..16)
                    .map(|_| {
                        let s = [rng.next_f64(), rng.next_f64(), rng.next_f64(), rng.next_f64()];
                        sbf::recon::reference::ggx_specular_mis_shifted(&ctx.map, &sampler, DVec3::Y, v, alpha, 1.0, 1.0, 1 << 16, s)
                    })
                    .collect();
                for c in 0..3 {
                    let mean = reps.iter().map(|r| r[c]).sum::<f64>() / 16.0;
                    let sigma = (reps.iter().map(|r| (r[c] - mean).powi(2)).sum::<f64>() / 15.0 / 16.0).sqrt();
                    let quad = 4.0 / 3.0 * (img[j * w + i][c] - fine[c]).abs();
                    let diff = (img[j * w + i][c] - mean).abs();
                    worst = worst.max(diff / sigma.max(1e-300));
                    if diff > 3.0 * sigma {
                        println!(
                            "{name} α {alpha} ({i}, {j}) channel {c}: reference {:.6e}, MIS {mean:.6e} ± {sigma:.1e}: {diff:.1e} apart, quadrature error {quad:.1e}",
                            img[j * w + i][c]
                        );
                    }
                    assert!(
                        diff <= 3.0 * sigma + quad,
                        "{name} α {alpha} texel ({i}, {j}) channel {c}: reference {} vs MIS {mean} ± {sigma} (quadrature {quad:.1e})",
                        img[j * w + i][c]
                    );
                }
            }
        }
    }
    println!("largest |reference − MIS|/σ over 5 probes × 5 α × 3 texels × 3 channels: {worst:.2}");
}

/// The basis-limited image's plumbing: when the "reconstruction" is the
/// map itself (its radiance at the output texel centres, which are the map's texel
/// centres here), the basis-limited image is the reference computed with (at most) half
/// the subdivision, so they differ only by quadrature error. Error model: midpoint rule on
/// even subdivisions, error ∝ h², so R_{S/2} is off by ≤ 4e where e ≈ the reference's
/// stated error (4/3 × RMS of R_S − R_2S): RMS(B − R) ≤ 5e, asserted ≤ 6·error_rms. A 64 × 32 smooth map with a bright spot,
/// both domains, α 0.2 and 0.6; the same map with the radiance × 1.01 must fail the bound.
#[test]
fn basis_limited_image_of_the_map_itself_is_the_reference() {
    let map = LatLongImage::from_fn(64, 32, |d| {
        let spot = (40.0 * (d.dot(DVec3::new(0.6, 0.6, 0.529).normalize()) - 1.0)).exp() * 20.0;
        [1.0 + 0.5 * d.x + spot, 0.7 + 0.3 * d.y * d.z, 0.4 + spot * 0.5]
    })
    .unwrap();
    for domain in [Domain::UpperHemisphere, Domain::Sphere] {
        let ctx = Context::with_domain(map.clone(), domain);
        for alpha in [0.2, 0.6] {
            let r = reference_fft(&ctx, alpha).unwrap();
            let rad = ctx.radiance();
            let rms = |img: &[[f64; 3]]| {
                let s: f64 = img.iter().zip(&r.image).map(|(a, b)| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>()).sum();
                (s / (3 * img.len()) as f64).sqrt()
            };
            let b = probes::specular::basis_limited(&ctx, &[&rad], alpha).unwrap().remove(0);
            let bound = 6.0 * r.error_rms;
            println!("{domain:?} α {alpha}: RMS(B − R) {:.2e}, bound {bound:.2e} (signal RMS {:.3})", rms(&b), r.signal_rms);
            assert!(rms(&b) <= bound, "{domain:?} α {alpha}: {} > {bound}", rms(&b));
            let scaled: Vec<[f64; 3]> = rad.iter().map(|c| c.map(|x| 1.01 * x)).collect();
            let both = probes::specular::basis_limited(&ctx, &[&scaled, &rad], alpha).unwrap();
            assert!(rms(&both[0]) > bound, "the bound must catch 1%");
            // Several maps in one pass give each map's own result.
            assert!(both[1].iter().zip(&b).all(|(x, y)| x == y), "integrate_many mixes maps");
        }
    }
}

/// Two independent integrators of the same GGX albedo: on a constant map (L = 1) the
/// deterministic reference at output row j is ∫ f·cos dω = dfg₀ + dfg₁ at n·v = cos θ_j
/// (F ≡ 1), which `sbf::ggx::dfg_quadrature` computes in half-vector space with the NDF's
/// CDF. Per row: |FFT − quadrature| ≤ 2·|R_S − R_2S| (the FFT rule's Richardson error,
/// doubled) + |q_128 − q_256| + 1e-9; α 0.1, 0.3, 0.7, every 4th upper-hemisphere row of a
/// 128 × 64 map.
#[test]
fn constant_map_reflects_the_dfg_quadrature() {
    let map = LatLongImage::from_fn(128, 64, |_| [1.0; 3]).unwrap();
    let ctx = Context::with_domain(map, Domain::UpperHemisphere);
    let (w, h) = (ctx.grid.width, ctx.grid.height);
    let q = probes::azimuthal::Quadrature::new(&ctx.map, ctx.grid).unwrap();
    for alpha in [0.1, 0.3, 0.7] {
        let sub = subdivision(alpha, h);
        let kernel = |j: usize, tl: f64, dphi: f64| {
            let v = probes::azimuthal::direction(PI * (j as f64 + 0.5) / h as f64, dphi);
            ggx_kernel(DVec3::Y, v, probes::azimuthal::direction(tl, 0.0), alpha)
        };
        let img = reference_fft(&ctx, alpha).unwrap().image;
        for j in (0..h / 2).step_by(4) {
            let nv = (PI * (j as f64 + 0.5) / h as f64).cos();
            let fine = q.integrate(j..j + 1, 2 * sub, &kernel)[0][0];
            let (a, b) = (sbf::ggx::dfg_quadrature(nv, alpha, 256), sbf::ggx::dfg_quadrature(nv, alpha, 128));
            let want = a[0] + a[1];
            let got = img[j * w][0];
            let tol = 2.0 * (got - fine).abs() + (want - b[0] - b[1]).abs() + 1e-9;
            assert!((got - want).abs() <= tol, "α {alpha} n·v {nv}: FFT {got} vs quadrature {want} (tolerance {tol:.1e})");
        }
    }
}

/// The reference's row kernel (`GgxRows`: half-vector cosines as ratios of squared lengths,
/// masking constant along a row) against the pointwise `ggx_kernel` (normalised vectors,
/// `sbf::ggx`): both domains, α from 1e-4 to 1, every output row of a 64-row grid, light
/// polar angles across the sphere (poles and horizon included), 512 azimuths. Error model:
/// each side is ≲ 30 correctly rounded operations (≲ 1e-14 relative) except for one sum
/// that can cancel — n·l = c_v c_l + s_v s_l cos Δφ on the sphere, the half-vector's
/// q = x² + (s_v cos Δφ + s_l)² on the hemisphere — whose rounding is amplified by its
/// condition number κ (Σ|terms| / |sum|) and by the kernel's sensitivity to it (≤ 4 in
/// log-log: G2 through tan², D through (α²p + q)²); asserted ≤ 1e-13·(1 + κ) relative to
/// the larger value (absolute 1e-300 for zeros). Mutations tried: G2's Λ(l) dropped
/// in the sphere branch, the hemisphere branch scaled by 1.01 — both fail.
#[test]
fn row_kernel_equals_the_pointwise_kernel() {
    use probes::azimuthal::{Azimuths, RowKernel};
    use probes::specular::GgxRows;
    let h_out = 64;
    let dphi: Vec<f64> = (0..512).map(|x| 2.0 * PI * (x as f64 + 0.37) / 512.0 - 0.3).collect();
    let (sin, cos): (Vec<f64>, Vec<f64>) = dphi.iter().map(|p| p.sin_cos()).unzip();
    let az = Azimuths { dphi: &dphi, cos: &cos, sin: &sin };
    let mut out = vec![0.0; 512];
    let mut checked = 0usize;
    for domain in [Domain::UpperHemisphere, Domain::Sphere] {
        for alpha in [1e-4, 0.01, 0.1, 0.37, 1.0] {
            let k = GgxRows { domain, alpha, h_out, convention: Default::default() };
            for j in 0..h_out {
                for tl in [1e-9, 0.05, 0.4, 1.0, PI / 2.0 - 1e-6, PI / 2.0, 2.0, PI - 1e-9] {
                    k.row(j, tl, &az, &mut out);
                    let v_theta = PI * (j as f64 + 0.5) / h_out as f64;
                    for (x, p) in dphi.iter().enumerate() {
                        let l = probes::azimuthal::direction(tl, 0.0);
                        let v = probes::azimuthal::direction(v_theta, *p);
                        let want = match domain {
                            Domain::Sphere => ggx_kernel(v, v, l, alpha),
                            Domain::UpperHemisphere => ggx_kernel(DVec3::Y, v, l, alpha),
                        };
                        let got = out[x];
                        let (cv, sv, cl, sl, c) = (v_theta.cos(), v_theta.sin(), tl.cos(), tl.sin(), p.cos());
                        let kappa = match domain {
                            Domain::Sphere => ((cv * cl).abs() + (sv * sl * c).abs()) / (cv * cl + sv * sl * c).abs(),
                            Domain::UpperHemisphere => {
                                let x2 = (sv * p.sin()).powi(2);
                                (x2 + ((sv * c).abs() + sl).powi(2)) / (x2 + (sv * c + sl).powi(2))
                            }
                        };
                        assert!(
                            (got - want).abs() <= 1e-13 * (1.0 + kappa) * got.abs().max(want.abs()) + 1e-300,
                            "{domain:?} α {alpha} row {j} θ_l {tl} Δφ {p}: {got} vs {want} (κ {kappa:.1e})"
                        );
                        checked += usize::from(want > 0.0);
                    }
                }
            }
        }
    }
    assert!(checked > 100_000, "only {checked} non-zero values compared");
}

/// The Appendix C row kernel against Roughton's estimator written pointwise: the density
/// of the reflected direction under visible-normal sampling (`vndf_reflected_pdf`, Heitz
/// 2018 eq. 17) times Roughton's per-sample weight (`Convention::AppendixC.vndf_weight`:
/// G2·G1(v), Λ(l) from |cos θ_l|) times Schlick's F with f0 0.9 at v·h — a different route
/// from the row kernel's closed form F·D·G2·G1²/(4 n·v); zero where n·h ≤ 0 (no visible
/// normal reflects there). Light below the surface is included (θ_l > π/2). Tolerance as
/// in `row_kernel_equals_the_pointwise_kernel` (the same cancellations). Mutations tried:
/// G1² dropped from the row kernel, f0 1 instead of 0.9, the horizon cut kept — each fails.
#[test]
fn appendix_c_row_kernel_is_the_seed_estimators_density() {
    use probes::azimuthal::{Azimuths, RowKernel};
    use probes::specular::GgxRows;
    use sbf::ggx::{self, Convention};
    let h_out = 64;
    let dphi: Vec<f64> = (0..256).map(|x| 2.0 * PI * (x as f64 + 0.37) / 256.0 - 0.3).collect();
    let (sin, cos): (Vec<f64>, Vec<f64>) = dphi.iter().map(|p| p.sin_cos()).unzip();
    let az = Azimuths { dphi: &dphi, cos: &cos, sin: &sin };
    let mut out = vec![0.0; dphi.len()];
    let (mut checked, mut below) = (0usize, 0usize);
    // World (+Y up) to a frame with the normal at +Z.
    let t = |w: DVec3| DVec3::new(w.x, w.z, w.y);
    for alpha in [0.01, 0.1, 0.4, 0.8, 1.0] {
        let k = GgxRows { domain: Domain::UpperHemisphere, alpha, h_out, convention: Convention::AppendixC };
        for j in 0..h_out / 2 {
            for tl in [1e-9, 0.05, 0.4, 1.0, PI / 2.0 - 1e-6, 1.7, 2.0, 2.6, PI - 1e-9] {
                k.row(j, tl, &az, &mut out);
                let v_theta = PI * (j as f64 + 0.5) / h_out as f64;
                for (x, p) in dphi.iter().enumerate() {
                    let (l, v) = (t(probes::azimuthal::direction(tl, 0.0)), t(probes::azimuthal::direction(v_theta, *p)));
                    let h = (v + l).normalize();
                    let want = if h.z > 0.0 {
                        let f = 0.9 + 0.1 * ggx::schlick_weight(v.dot(h));
                        f * Convention::AppendixC.vndf_weight(v, l, alpha) * ggx::vndf_reflected_pdf(v, l, alpha)
                    } else {
                        0.0
                    };
                    let got = out[x];
                    let (sv, c, sl) = (v_theta.sin(), p.cos(), tl.sin());
                    let x2 = (sv * p.sin()).powi(2);
                    let kappa = (x2 + ((sv * c).abs() + sl).powi(2)) / (x2 + (sv * c + sl).powi(2));
                    assert!(
                        (got - want).abs() <= 1e-13 * (1.0 + kappa) * got.abs().max(want.abs()) + 1e-300,
                        "α {alpha} row {j} θ_l {tl} Δφ {p}: {got} vs {want} (κ {kappa:.1e})"
                    );
                    checked += usize::from(want > 0.0);
                    below += usize::from(want > 0.0 && l.z < 0.0);
                }
            }
        }
    }
    assert!(checked > 50_000 && below > 10_000, "only {checked} non-zero values compared ({below} below the surface)");
}

/// The row kernels through the full machinery — `GgxRows` (mirror pairs over the sphere,
/// spectral truncation) — against the direct sum of the same rule: both domains, α 0.1
/// and 0.6, subdivisions 1–2, on the random map (broad spectra: every bin kept) and on a
/// band-limited one (texels of a degree-2 polynomial in the direction: three φ bins per
/// row, the rest truncated), every output texel. Tolerance as above plus the row kernel's
/// own deviation from `ggx_kernel` (≤ 1e-13·(1 + κ), test below) — 1e-11 of the largest
/// value. Mutations tried: the mirrored row reading source row r instead of H − 1 − r;
/// truncation at 3 bins for every row; both fail.
#[test]
fn row_kernels_with_mirror_pairs_and_truncation_equal_the_direct_sum() {
    let smooth =
        LatLongImage::from_fn(32, 16, |d| [1.0 + 0.5 * d.x + 0.3 * d.y * d.z, 0.8 - 0.2 * d.y + 0.1 * d.x * d.x, 0.5 + 0.4 * d.z]).unwrap();
    for map in [random_map(), smooth] {
        for domain in [Domain::UpperHemisphere, Domain::Sphere] {
            for (alpha, sub) in [(0.1, 2), (0.6, 1)] {
                let out = LatLong { width: 16, height: 8 };
                let q = probes::azimuthal::Quadrature::new(&map, out).unwrap();
                let kernel = probes::specular::GgxRows { domain, alpha, h_out: out.height, convention: Default::default() };
                let got = q.integrate_rows(0..out.height, sub, &kernel);
                let top = got.iter().flat_map(|x| x.iter()).fold(0.0f64, |a, x| a.max(x.abs()));
                for j in 0..out.height {
                    for i in 0..out.width {
                        let want = direct(&map, out, domain, alpha, sub, i, j);
                        for c in 0..3 {
                            let g = got[j * out.width + i][c];
                            assert!(
                                (g - want[c]).abs() <= 1e-11 * top.max(1.0),
                                "{domain:?} α {alpha} S {sub} texel ({i}, {j}): {g} vs {}",
                                want[c]
                            );
                        }
                    }
                }
            }
        }
    }
}

/// Spectral truncation keeps what matters: a trigonometric polynomial of degree 3 keeps
/// 4 bins (its spectrum beyond is rounding noise), a flat spectrum keeps all, and the
/// dropped tail is ≤ TAIL of the L1 sum (the bound the quadrature's error model uses).
#[test]
fn significant_bins_keep_the_spectrum() {
    use probes::azimuthal::{significant_bins, TAIL};
    let n = 64;
    let mut re = vec![0.0; n / 2 + 1];
    let mut im = vec![0.0; n / 2 + 1];
    for (b, (r, i)) in re.iter_mut().zip(im.iter_mut()).enumerate() {
        // Exact low bins, then noise at 1e-17 of them.
        (*r, *i) = if b <= 3 { (1.0 / (b + 1) as f64, 0.5 / (b + 1) as f64) } else { (1e-17 * (b as f64).sin(), 1e-17) };
    }
    assert_eq!(significant_bins(&re, &im), 4);
    let flat = vec![1.0; n / 2 + 1];
    assert_eq!(significant_bins(&flat, &flat), n / 2 + 1);
    let decay: Vec<f64> = (0..=n / 2).map(|b| (-(b as f64)).exp()).collect();
    let k = significant_bins(&decay, &vec![0.0; decay.len()]);
    let total: f64 = decay.iter().sum();
    let tail: f64 = decay[k..].iter().sum();
    assert!(tail <= TAIL * total && tail + decay[k - 1] > TAIL * total, "kept {k}: tail {tail:e} of {total}");
}

/// The coarsening rule: every map no wider than its output grid keeps D = 1 (the probes,
/// 512-wide maps); a 2048 × 1024 map (output 512 × 256) merges 2 × 2 texels at α = 0.1
/// (π·2/1024 ≤ 0.1/16) and 4 × 4 (the output width's limit) from α = 0.2.
#[test]
fn coarsening_follows_the_lobe_and_the_output_grid() {
    use probes::specular::coarsening;
    let g = |w: usize| LatLong { width: w, height: w / 2 };
    for alpha in [1e-4, 0.1, 0.8, 1.0] {
        assert_eq!(coarsening(alpha, g(256), g(256)), 1);
        assert_eq!(coarsening(alpha, g(512), g(512)), 1);
    }
    assert_eq!(coarsening(0.1, g(2048), g(512)), 2);
    assert_eq!(coarsening(0.05, g(2048), g(512)), 1);
    for alpha in [0.2, 0.4, 0.8] {
        assert_eq!(coarsening(alpha, g(2048), g(512)), 4);
    }
    assert_eq!(coarsening(0.8, g(1024), g(512)), 2);
}

/// The coarsened reference against a finer quadrature: a 1024 × 512 map (smooth sky, a
/// sun of 1000 over a 0.05 rad disk) at α = 0.4 — D = 2, one cell per 2 × 2 texels —
/// against the map itself at S = 2 (cells a quarter of the size: their own error ≈ 1/16
/// of D = 2's for an h² rule), on output rows 4, 12, 20, … (not the rows the reference's
/// own check uses). Both domains. The stated error is a Richardson estimate on other rows,
/// so the measured RMS must lie within [½, 2]× of it: too low means the check does not see
/// the coarsening, too high that the estimate hides error; and below 3× the h² model's
/// (c/α)²/24 of the signal. Mutations tried: the coarse map × 1.01 (the stated error
/// follows it, the h² bar fails), the check run at D instead of D/2 (stated error 0) —
/// both fail.
#[test]
fn coarsened_reference_is_within_its_stated_error() {
    let sun = DVec3::new(0.3, 0.8, -0.52).normalize();
    let map = LatLongImage::from_fn(1024, 512, |d| {
        let s = if d.dot(sun) > (0.05f64).cos() { 1000.0 } else { 0.0 };
        [0.5 + 0.3 * d.y + s, 0.6 + 0.2 * d.x * d.y + s, 0.8 + 0.1 * d.z + 0.9 * s]
    })
    .unwrap();
    for domain in [Domain::Sphere, Domain::UpperHemisphere] {
        let ctx = Context::with_domain(map.clone(), domain);
        let alpha = 0.4;
        let r = reference_fft(&ctx, alpha).unwrap();
        assert_eq!(r.coarsening, 2);
        let (w, h) = (ctx.grid.width, ctx.grid.height);
        let q = probes::azimuthal::Quadrature::new(&ctx.map, ctx.grid).unwrap();
        let kernel = probes::specular::GgxRows { domain, alpha, h_out: h, convention: Default::default() };
        let rows = if domain == Domain::Sphere { h } else { h / 2 };
        let (mut e2, mut n) = (0.0, 0usize);
        for j in (4..rows).step_by(8) {
            let fine = q.integrate_rows(j..j + 1, 2, &kernel);
            for (i, f) in fine.iter().enumerate() {
                for c in 0..3 {
                    e2 += (r.image[j * w + i][c] - f[c]).powi(2);
                }
                n += 3;
            }
        }
        let measured = (e2 / n as f64).sqrt();
        println!("{domain:?}: measured RMS {measured:.3e}, stated {:.3e}, signal {:.3}", r.error_rms, r.signal_rms);
        assert!(
            measured <= 2.0 * r.error_rms && measured >= 0.5 * r.error_rms,
            "{domain:?}: measured {measured:e} vs stated {:e}",
            r.error_rms
        );
        // And small: a midpoint rule with cells of side c on a lobe of width α errs by
        // ~(c/α)²/24 of the signal (the lobe's curvature); 3× that, c = 2π/512.
        let c = 2.0 * PI / 512.0;
        let bar = 3.0 * (c / alpha).powi(2) / 24.0 * r.signal_rms;
        assert!(measured <= bar, "{domain:?}: measured {measured:e} above the h² model's {bar:e}");
    }
}

/// Any set of output rows, in any order, gives the full integration's rows, and the same
/// bits on any number of threads (row blocks shrink with the thread count; each output row
/// is summed on its own, in source-row order). The subset holds a mirror pair (4, 3), rows
/// whose mirror is absent (6, 0), in no sorted order; the full image itself is checked
/// against the direct sum above. A row folded on its own rather than as its partner's mirror
/// evaluates the kernel at π − θ: equal to rounding, bounded by 1e-12 of the largest value
/// (a few ulps per kernel value times 2·H·S² ≈ 10³ terms per output). Mutations tried:
/// results in sorted instead of requested order; a mirror pair folded as if the subset held
/// every row — both fail.
#[test]
fn rows_in_any_order_and_thread_count_equal_the_full_integration() {
    let map = random_map();
    let out = LatLong { width: 16, height: 8 };
    let q = probes::azimuthal::Quadrature::new(&map, out).unwrap();
    for domain in [Domain::Sphere, Domain::UpperHemisphere] {
        let kernel = probes::specular::GgxRows { domain, alpha: 0.3, h_out: out.height, convention: Default::default() };
        let pool = |n: usize| rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap();
        let full = pool(1).install(|| q.integrate_rows(0..out.height, 2, &kernel));
        let top = full.iter().flat_map(|x| x.iter()).fold(0.0f64, |a, x| a.max(x.abs()));
        let rows = [6usize, 4, 3, 0];
        let one = pool(1).install(|| q.integrate_rows_at(&rows, 2, &kernel));
        assert_eq!(one.len(), rows.len() * out.width);
        for (n, &j) in rows.iter().enumerate() {
            let want = &full[j * out.width..(j + 1) * out.width];
            for (a, b) in one[n * out.width..(n + 1) * out.width].iter().zip(want) {
                for c in 0..3 {
                    assert!((a[c] - b[c]).abs() <= 1e-12 * top, "{domain:?}: row {j}: {} vs {}", a[c], b[c]);
                }
            }
        }
        for threads in [3, 7] {
            let got = pool(threads).install(|| q.integrate_rows_at(&rows, 2, &kernel));
            assert!(got == one, "{domain:?}: {threads} threads differ from one");
        }
    }
}
