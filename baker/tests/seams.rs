//! Seam stitching (`baker::post::seams`): seams found from the geometry (a plane cut into two UV
//! islands has exactly one, a fold has none), and a known seam closed by the least-squares
//! stitch while texels away from it keep their values and every coefficient set moves by
//! the same linear map.

mod common;

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

/// The glTF room at the golden test's settings (4 passes, 8 texels per unit): there the free
/// least-squares stitch took 32 texels of E/π below zero and Ambient Dice lobes with them
/// (a padding tap of small weight levers its texel by several times the seam's jump). E/π is
/// irradiance over π and AD 9's NNLS lobes are ≥ 0 by construction — an oracle from physics
/// and the solver, not from the stitch: no texel of irradiance.exr or of any `ad9_*.exr`,
/// valid or padding, may be negative, while the seams still close (the metric falls below
/// the texels' noise) and bake.json says how many texels the solve had to hold.
#[test]
fn stitching_keeps_irradiance_and_nnls_lobes_non_negative() {
    let Some(scenes) = common::outputs::scenes_dir() else { return };
    let gltf = scenes.join("bevy_MixedLightingExample/MixedLightingExample.gltf");
    let out = std::env::temp_dir().join(format!("sbf-seams-room-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_baker"))
        .args(["--device", "cpu", "--scene", gltf.to_str().unwrap(), "--passes", "4", "--texels-per-unit", "8", "--bases", "sh2,ad9"])
        .args(["--material-maps", "factors", "--probes", "0,0,0", "--preview-width", "16", "--checkpoint-every", "0", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("bake.json")).unwrap()).unwrap();
    let s = &meta["seams"];
    assert_eq!(s["stitched"], true, "{s}");
    let (before, after, noise) =
        (s["metric_before"].as_f64().unwrap(), s["metric_after"].as_f64().unwrap(), s["texel_noise"].as_f64().unwrap());
    assert!(after < before && after < noise, "seams not closed: {s}");
    let mut files = vec!["irradiance.exr".to_string()];
    files.extend((0..9).map(|l| format!("ad9_{l:02}.exr")));
    for f in files {
        let im = image::open(out.join(&f)).unwrap().to_rgba32f();
        let (neg, min) =
            im.pixels().flat_map(|p| [p[0], p[1], p[2]]).fold((0usize, 0.0f32), |(n, m), v| (n + usize::from(v < 0.0), m.min(v)));
        assert_eq!(neg, 0, "{f}: {neg} negative values, down to {min}");
    }
    assert!(s["held_texels"].as_u64().unwrap() > 0, "this bake exercises the held set: {s}");
    std::fs::remove_dir_all(&out).ok();
}
