//! [Roughton19 Appendix C] on the five probes: radiance, Lambert (E/π) and GGX
//! (α = 0.1 … 0.8, normal +Z, view over the upper hemisphere) RMSE for AD9, AD12,
//! SG9 and SG12 (λ = 6, Vogel spiral on the upper hemisphere), solved by least
//! squares over the sphere, next to Roughton's figures.
//!
//!     cargo test --release --test appendix_c -- --nocapture
//!
//! This is the physical pipeline (the GGX integral, F ≡ 1) with sbf alone; Roughton's own
//! conventions, to compare with its printed figures cell by cell, are `probes compare
//! --reference appendix-c` (test `probes/tests/appendix_c.rs`).
//!
//! Conventions: tangent space has +Z = the probe's up (+Y), the peer's frame: world
//! d = (t.x, t.z, t.y); the error images are the upper-hemisphere half of a 128×64
//! lat-long grid (2048 texels), RMSE unweighted over texels and averaged over RGB as
//! in Probulator. References: exact quadrature over the map's texels for Lambert and
//! for GGX, with f0 = f90 = 1 (\[Roughton19\] does not state its Fresnel;
//! white-furnace albedo is the natural reading of its magnitudes).

use sbf::envmap::LatLong;
use sbf::glam::DVec3;
use sbf::gram::{gram_matrix, GramOptions};
use sbf::nalgebra::DMatrix;
use sbf::recon::{ambient_dice as ad, lut, reference, sg as sgr};
use sbf::solve::{moments, solve_gram, LsOptions, RadianceSample};
use sbf::{AmbientDiceSrbf, Basis, Domain, SgBasis};
use sbf_tests::{load_probe, PROBES};

// Seed Appendix C's figures ([probe][row][AD9, AD12, SG9, SG12]; rows radiance, Lambert,
// GGX of ALPHAS) and roughness rows, as the probes tool's compatible mode records them.
use probes::appendix_c::{ALPHAS, SEED};

/// The peer's z-up frame read in our world: a swap of y and z (see
/// `probes::modes::tangent_to_world`), its own inverse.
fn to_world(t: DVec3) -> DVec3 {
    DVec3::new(t.x, t.z, t.y)
}
fn to_tangent(w: DVec3) -> DVec3 {
    DVec3::new(w.x, w.z, w.y)
}

enum Kind {
    Ad(Vec<DVec3>),
    Sg(Vec<DVec3>),
}

fn rmse(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let s: f64 = a.iter().zip(b).map(|(x, y)| (0..3).map(|c| (x[c] - y[c]).powi(2)).sum::<f64>()).sum();
    (s / (3 * a.len()) as f64).sqrt()
}

#[test]
fn appendix_c_table() {
    let ad9 = AmbientDiceSrbf::nine_hemisphere();
    let ad12 = AmbientDiceSrbf::twelve();
    let sg9 = SgBasis::new(&sbf::layout::vogel_hemisphere(9).unwrap(), 6.0, false).unwrap();
    let sg12 = SgBasis::new(&sbf::layout::vogel_hemisphere(12).unwrap(), 6.0, false).unwrap();
    let bases: [(&str, &dyn Basis, Kind); 4] = [
        ("AD9", &ad9, Kind::Ad(ad9.lobes().to_vec())),
        ("AD12", &ad12, Kind::Ad(ad12.lobes().to_vec())),
        ("SG9", &sg9, Kind::Sg(sg9.axes().to_vec())),
        ("SG12", &sg12, Kind::Sg(sg12.axes().to_vec())),
    ];
    let grams: Vec<DMatrix<f64>> =
        bases.iter().map(|(_, b, _)| gram_matrix(*b, Domain::Sphere, GramOptions::default()).unwrap().matrix).collect();
    let spec_lut = lut::ad_specular_lut(32, 32, 2048).unwrap();
    let out = LatLong::new(128, 64).unwrap();
    let texels: Vec<DVec3> =
        (0..out.height / 2).flat_map(|j| (0..out.width).map(move |i| (i, j))).map(|(i, j)| to_tangent(out.texel_direction(i, j))).collect();
    let rows = ["radiance", "Lambert", "GGX α=0.1", "GGX α=0.2", "GGX α=0.4", "GGX α=0.6", "GGX α=0.8"];
    for (pi, name) in PROBES.iter().enumerate() {
        let Some(map) = load_probe(name) else { return };
        // Samples over the whole sphere, in tangent space, weighted by texel solid angle.
        let g = map.geometry;
        let samples: Vec<RadianceSample> = (0..g.height)
            .flat_map(|j| (0..g.width).map(move |i| (i, j)))
            .map(|(i, j)| {
                let t = map.texel(i, j);
                RadianceSample {
                    direction: to_tangent(g.texel_direction(i, j)),
                    value: [t[0] as f64, t[1] as f64, t[2] as f64],
                    weight: g.texel_solid_angle(j),
                }
            })
            .collect();
        let truth_rad: Vec<[f64; 3]> = texels.iter().map(|t| map.bilinear(to_world(*t))).collect();
        let truth_irr: Vec<[f64; 3]> = texels.iter().map(|t| reference::irradiance_map(&map, to_world(*t))).collect();
        // GGX reference: exact quadrature over the map's texels (a sharp sun makes Monte
        // Carlo references noisy at every roughness), split over two threads.
        let upper: Vec<RadianceSample> = samples.iter().filter(|s| s.direction.z > 0.0).copied().collect();
        let truth_ggx: Vec<Vec<[f64; 3]>> = ALPHAS
            .iter()
            .map(|&a| {
                let half = texels.len() / 2;
                std::thread::scope(|scope| {
                    let parts: Vec<_> = texels
                        .chunks(half.max(1))
                        .map(|chunk| {
                            scope.spawn(|| {
                                chunk.iter().map(|v| reference::ggx_specular_samples(&upper, *v, a, 1.0, 1.0)).collect::<Vec<_>>()
                            })
                        })
                        .collect();
                    parts.into_iter().flat_map(|p| p.join().unwrap()).collect()
                })
            })
            .collect();
        println!("\n{name}: RMSE (ours / [Roughton19 Appendix C])");
        println!("{:>10} {:>18} {:>18} {:>18} {:>18}", "", "AD9", "AD12", "SG9", "SG12");
        let mut table = vec![[0.0f64; 4]; 7];
        let mut floors = vec![[(0.0f64, 0.0f64); 4]; 5];
        for (bi, (_, basis, kind)) in bases.iter().enumerate() {
            let c = solve_gram(&grams[bi], &moments(*basis, &samples), LsOptions::default()).unwrap().coeffs;
            let ch = |k: usize| c.column(k).iter().copied().collect::<Vec<f64>>();
            let chans = [ch(0), ch(1), ch(2)];
            let mut scratch = vec![0.0; basis.len()];
            let rad: Vec<[f64; 3]> = texels.iter().map(|t| [0, 1, 2].map(|k| basis.reconstruct(&chans[k], *t, &mut scratch))).collect();
            table[0][bi] = rmse(&rad, &truth_rad);
            let irr: Vec<[f64; 3]> = texels
                .iter()
                .map(|n| {
                    [0, 1, 2].map(|k| match kind {
                        Kind::Ad(l) => ad::irradiance_fit(l, &chans[k], *n, &ad::DIFFUSE_FIT_EQ_8_14),
                        Kind::Sg(a) => sgr::sum_lobes(a, &vec![6.0; a.len()], &chans[k], |s| sgr::irradiance_hill(s, *n)),
                    })
                })
                .collect();
            table[1][bi] = rmse(&irr, &truth_irr);
            for (ai, &alpha) in ALPHAS.iter().enumerate() {
                let spec: Vec<[f64; 3]> = texels
                    .iter()
                    .map(|v| {
                        let l = spec_lut.sample2(v.z as f32, alpha as f32);
                        [0, 1, 2].map(|k| match kind {
                            Kind::Ad(lobes) => ad::specular(lobes, &chans[k], DVec3::Z, *v, alpha, 1.0, 1.0, [l[0] as f64, l[1] as f64]),
                            Kind::Sg(a) => sgr::sum_lobes(a, &vec![6.0; a.len()], &chans[k], |s| {
                                sgr::specular_asg_warp(s, DVec3::Z, *v, alpha, 1.0, 1.0)
                            }),
                        })
                    })
                    .collect();
                table[2 + ai][bi] = rmse(&spec, &truth_ggx[ai]);
                // Floor: exact GGX of the *reconstructed* radiance (every 4th output
                // texel): what any specular method reading these coefficients can reach.
                let rec: Vec<RadianceSample> = upper
                    .iter()
                    .map(|s| RadianceSample { value: [0, 1, 2].map(|k| basis.reconstruct(&chans[k], s.direction, &mut scratch)), ..*s })
                    .collect();
                let pick = |x: &[[f64; 3]]| x.iter().step_by(4).copied().collect::<Vec<_>>();
                let floor: Vec<[f64; 3]> =
                    texels.iter().step_by(4).map(|v| reference::ggx_specular_samples(&rec, *v, alpha, 1.0, 1.0)).collect();
                floors[ai][bi] = (rmse(&floor, &pick(&truth_ggx[ai])), rmse(&pick(&spec), &pick(&truth_ggx[ai])));
            }
        }
        for (ri, row) in rows.iter().enumerate() {
            let cells: Vec<String> = (0..4).map(|b| format!("{:.4} / {:.4}", table[ri][b], SEED[pi][ri][b])).collect();
            println!("{row:>10} {:>18} {:>18} {:>18} {:>18}", cells[0], cells[1], cells[2], cells[3]);
        }
        println!("  GGX floor (exact GGX of the reconstructed radiance) / method, every 4th texel:");
        for (ai, alpha) in ALPHAS.iter().enumerate() {
            let cells: Vec<String> = (0..4).map(|b| format!("{:.4} / {:.4}", floors[ai][b].0, floors[ai][b].1)).collect();
            println!("{:>10} {:>18} {:>18} {:>18} {:>18}", format!("α={alpha}"), cells[0], cells[1], cells[2], cells[3]);
        }
        for row in &table {
            assert!(row.iter().all(|v| v.is_finite()), "{name}: non-finite error");
        }
        // Agreement with [Roughton19 App. C] where the setups coincide: radiance within 15% for
        // every basis (grace excepted: its sun is a few texels, resolved differently),
        // Ambient Dice Lambert (eq. 8.14 fit) within 20%.
        for b in 0..4 {
            if *name != "grace" {
                let r = table[0][b] / SEED[pi][0][b];
                assert!((r - 1.0).abs() < 0.15, "{name} basis {b}: radiance ratio {r}");
            }
        }
        for b in 0..2 {
            let r = table[1][b] / SEED[pi][1][b];
            assert!((r - 1.0).abs() < 0.2, "{name} AD basis {b}: Lambert ratio {r}");
        }
        // Ambient Dice specular (fit + 2D LUT) stays within 1.6× of the floor for
        // α ≤ 0.4, where [Roughton19] says the fit is good; beyond, the 2D LUT's own error
        // shows ([Roughton19] suggests a 3D LUT; fitgen's issue measures it).
        for ai in 0..3 {
            for b in 0..2 {
                let (floor, method) = floors[ai][b];
                assert!(method <= 1.6 * floor, "{name} AD basis {b} α={}: method {method} vs floor {floor}", ALPHAS[ai]);
            }
        }
    }
}
