//! Seam stitching (`baker::post::seams`): seams found from the geometry (a plane cut into two UV
//! islands has exactly one, a fold has none), and a known seam closed by the least-squares
//! stitch while texels away from it keep their values and every coefficient set moves by
//! the same linear map.

use baker::layout::lightmap::Lightmap;
use baker::post::images::LightmapImages;
use baker::post::seams::{find_seams, samples, seam_metric, stitch};
use baker::scene::{Mesh, Scene};
use sbf::glam::{Vec2, Vec3};

/// A unit square (z = 0, or folded 90° along its diagonal) as two triangles whose lightmap
/// UVs are separate islands: triangle A on [0, 0.45]², triangle B shifted right by 0.55.
fn cut_plane(folded: bool) -> Scene {
    let mut s = baker::scene::cornell();
    let p = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    // Folding lifts the far corner of B out of the plane about the diagonal 0–2.
    let p3 = if folded { Vec3::new(0.5, 0.5, std::f32::consts::FRAC_1_SQRT_2) } else { p[3] };
    let uv = |q: Vec3, du: f32| Vec2::new(0.45 * q.x + du, 0.45 * q.y);
    let positions = vec![p[0], p[1], p[2], p[0], p[2], p3];
    let lightmap_uv = vec![uv(p[0], 0.0), uv(p[1], 0.0), uv(p[2], 0.0), uv(p[0], 0.55), uv(p[2], 0.55), uv(p[3], 0.55)];
    let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
    let nb = (p[2] - p[0]).cross(p3 - p[0]).normalize();
    s.meshes = vec![Mesh {
        name: "cut".into(),
        positions,
        normals: vec![n, n, n, nb, nb, nb],
        indices: vec![[0, 1, 2], [3, 4, 5]],
        material: 0,
        lightmap_uv: Some(lightmap_uv),
        lightmapped: true,
        uv: None,
    }];
    s
}

/// Mutation tried: the crease test (face normals' cosine) removed — the fold gets a seam, fails.
#[test]
fn a_cut_plane_has_one_seam_and_a_fold_none() {
    let s = cut_plane(false);
    let lm = Lightmap::build(&s, 32.0, 2).unwrap();
    let seams = find_seams(&s, &lm);
    assert_eq!(seams.len(), 1, "{seams:?}");
    let e = seams[0];
    assert!((e.a[0] - e.b[0]).length() > 1.0 && (e.a[1] - e.b[1]).length() > 1.0, "the two sides sit in different places: {e:?}");
    let f = cut_plane(true);
    let lmf = Lightmap::build(&f, 32.0, 2).unwrap();
    assert!(find_seams(&f, &lmf).is_empty(), "a 90° fold is a crease, not a seam");
}

/// Triangle A's texels hold 1.0, B's 1.2 (E/π; the coefficient sets hold 0.5× and −2× of
/// it), standard error 0.05: lookups across the seam differ by ~0.2 before. After
/// stitching (and dilation keeping the stitched padding) the metric is below the noise
/// (0.05) and below 5% of before (λ = 100 against unit data weights leaves a residual of
/// order 1/λ of the jump); texels further than two texels from every tap keep their values
/// exactly; the coefficients equal 0.5× and −2× the stitched E/π (one linear map for all).
/// Mutations tried: the seam weight set to 0 (metric unchanged, fails); B's taps added with
/// + instead of − (the solve drives the sum, not the difference: fails).
#[test]
fn stitching_closes_a_known_seam() {
    let s = cut_plane(false);
    let lm = Lightmap::build(&s, 32.0, 2).unwrap();
    let n = lm.width * lm.height;
    let valid: Vec<bool> = lm.texels.iter().map(|t| t.is_valid()).collect();
    // Side of a texel: its first point's triangle is A where y ≤ x on the square.
    let side = |t: usize| {
        let p = lm.texels[t].points[0].position;
        if p.y <= p.x {
            1.0f32
        } else {
            1.2
        }
    };
    let val = |t: usize| if valid[t] { side(t) } else { 0.0 };
    let rgb = |k: f32| (0..n).map(|t| [k * val(t); 3]).collect::<Vec<[f32; 3]>>();
    let mut img = LightmapImages {
        width: lm.width,
        height: lm.height,
        validity: valid.iter().map(|v| if *v { 1.0 } else { 0.0 }).collect(),
        irradiance: rgb(1.0),
        standard_error: (0..n).map(|t| if valid[t] { [0.05; 3] } else { [0.0; 3] }).collect(),
        coefficients: vec![vec![rgb(0.5), rgb(-2.0)]],
        normals: (0..n).map(|t| if valid[t] { [0.0, 0.0, 1.0] } else { [0.0; 3] }).collect(),
    };
    let seams = find_seams(&s, &lm);
    let smp = samples(&seams, lm.width, lm.height);
    let mut plain = img.clone();
    plain.dilate(3);
    let before = seam_metric(&plain, &smp);
    let original = img.clone();
    let st = stitch(&mut img, &plain, &smp);
    img.dilate_keeping(3, &st.written_empty);
    let after = seam_metric(&img, &smp);
    println!(
        "{} samples, {} texels solved ({} empty), ≤ {} CG iterations: seam metric {before:.4} → {after:.2e}",
        st.samples,
        st.texels,
        st.written_empty.len(),
        st.iterations
    );
    assert!(before > 0.1, "the seam is there before: {before}");
    assert!(after < 0.05 && after < 0.05 * before, "seam metric {before} → {after}");
    // Far texels untouched.
    let (w, _) = (lm.width, lm.height);
    let near: Vec<bool> = (0..n)
        .map(|t| {
            smp.iter().any(|x| {
                x.a.iter()
                    .chain(&x.b)
                    .any(|(u, _)| ((u % w) as i64 - (t % w) as i64).abs() <= 2 && ((u / w) as i64 - (t / w) as i64).abs() <= 2)
            })
        })
        .collect();
    let far = (0..n).filter(|t| valid[*t] && !near[*t]).count();
    assert!(far > 100, "{far}");
    for t in 0..n {
        if valid[t] && !near[t] {
            assert_eq!(img.irradiance[t], original.irradiance[t], "far texel {t} moved");
        }
        if valid[t] {
            let e = img.irradiance[t][0];
            assert!(
                (img.coefficients[0][0][t][0] - 0.5 * e).abs() <= 1e-5 && (img.coefficients[0][1][t][0] + 2.0 * e).abs() <= 1e-5,
                "texel {t}"
            );
        }
    }
}
