//! Normal-mapped shading (`render --normal-maps`) against glTF 2.0's definition of the
//! tangent frame, on a square written by the test (common::gltf::plane: facing +Y, u along
//! +x, v along +z) whose normal map is one constant texel.
//!
//! Oracle (glTF 2.0 §3.9.3, KHR_texture_transform): the tangent points where u grows, the
//! bitangent up the image — where v falls, glTF's v running down the image — and a texel
//! (r, g, b) is the tangent-space normal (2·rgb/255 − 1) with x, y × scale. Rotating the
//! texture coordinates by ρ (u′ = cos ρ·u + sin ρ·v, v′ = −sin ρ·u + cos ρ·v) turns the frame
//! with them: at ρ = π/2, u′ = v grows along +z and v′ = −u falls along +x. Shading: SH L2
//! holding the linear radiance L(ω) = a + β·ω_z of the texel's frame (c₀₀ = 2√π·a,
//! c₁₀ = √(4π/3)·β) gives E/π(n′) = a + (2/3)·β·(n′·N) at a mapped normal n′ (A₀/π = 1,
//! A₁/π = 2/3) — no frame convention of the library enters the expected value.
//! Error model: f32 tangents, normals and texel decode (≲ 1e-6 relative), f64 shading.

mod common;

use baker::accumulate::BasisId;
use baker::layout::lightmap::Lightmap;
use baker::render::atlas::Atlas;
use baker::render::lighting::{Encoding, Lighting, LightmapFilter, Storage};
use baker::render::normal_map::NormalMaps;
use baker::render::shade::Shader;
use baker::scene::camera::ViewCamera;
use baker::scene::Scene;
use sbf::glam::{DVec3, Vec3};
use sbf::profile::SpecularPath;

const TEXEL: [u8; 3] = [200, 90, 230];

/// A fresh folder for this test's asset.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sbf-normal-maps-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 4 × 4 PNG of one colour.
fn constant_png(rgb: [u8; 3]) -> Vec<u8> {
    let img = image::RgbaImage::from_pixel(4, 4, image::Rgba([rgb[0], rgb[1], rgb[2], 255]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// The square with a normal map of `TEXEL`, `scale`, its coordinates rotated by `rotation`.
fn scene(dir: &std::path::Path, scale: f32, rotation: f32) -> Scene {
    scene_with(dir, scale, rotation, &constant_png(TEXEL))
}

/// [`scene`] with the normal map `png`.
fn scene_with(dir: &std::path::Path, scale: f32, rotation: f32, png: &[u8]) -> Scene {
    let material = format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0,"roughnessFactor":1}},
        "normalTexture":{{"index":0,"scale":{scale},"extensions":{{"KHR_texture_transform":{{"rotation":{rotation}}}}}}}}}"#
    );
    let image = format!(r#"{{"uri":"data:image/png;base64,{}"}}"#, common::gltf::b64(png));
    let path = common::gltf::plane(dir, 1.0, 0.0, &material, &image);
    let (scene, report) = baker::scene::import::load(&path).unwrap();
    println!("import notes: {:?}", report.notes);
    scene
}

/// The mapped normal by glTF's definition: tangent `t`, bitangent `b`, normal +Y.
fn expected(t: Vec3, b: Vec3, scale: f32) -> Vec3 {
    let m = TEXEL.map(|c| 2.0 * c as f32 / 255.0 - 1.0);
    (t * m[0] * scale + b * m[1] * scale + Vec3::Y * m[2]).normalize()
}

#[test]
fn normal_maps_load_apart_and_perturb_in_gltfs_frame() {
    let dir = scratch("frame");
    for (rotation, t, b) in [(0.0, Vec3::X, Vec3::NEG_Z), (std::f32::consts::FRAC_PI_2, Vec3::Z, Vec3::X)] {
        for scale in [1.0, 0.5] {
            let s = scene(&dir, scale, rotation);
            // The bake's maps and textures do not hold it; the renderer's do.
            assert!(s.textures.is_empty() && s.materials[0].maps.is_empty(), "the bake would sample the normal map");
            assert_eq!(s.normal_textures.len(), 1);
            assert_eq!(s.materials[0].maps.normal.map(|n| n.scale), Some(scale));
            let maps = NormalMaps::build(&s, &mut |m| panic!("{m}")).expect("a normal map");
            assert!(maps.applies_to(0));
            let want = expected(t, b, scale);
            for prim in 0..2 {
                for w in [[1.0 / 3.0; 3], [0.8, 0.1, 0.1], [0.05, 0.05, 0.9]] {
                    let got = maps.perturb(&s, 0, prim, w, Vec3::Y);
                    assert!((got - want).length() < 2e-6, "rotation {rotation}, scale {scale}, triangle {prim} at {w:?}: {got} vs {want}");
                }
            }
            // An interpolated normal tilted off the face: the tangent made orthogonal to it
            // (Gram–Schmidt), the bitangent n × t.
            let n = (Vec3::Y + 0.4 * t + 0.2 * b).normalize();
            let t2 = (t - n * n.dot(t)).normalize();
            let b2 = n.cross(t2);
            let m = TEXEL.map(|c| 2.0 * c as f32 / 255.0 - 1.0);
            let want = (t2 * m[0] * scale + b2 * m[1] * scale + n * m[2]).normalize();
            let got = maps.perturb(&s, 0, 0, [1.0 / 3.0; 3], n);
            assert!((got - want).length() < 2e-6, "tilted normal, rotation {rotation}, scale {scale}: {got} vs {want}");
        }
    }
}

#[test]
fn shading_evaluates_the_lightmap_at_the_mapped_normal() {
    let dir = scratch("shading");
    let s = scene(&dir, 1.0, 0.0);
    let maps = NormalMaps::build(&s, &mut |m| panic!("{m}")).unwrap();
    let scene = s.without_maps();
    let lm = Lightmap::build(&scene, 8.0, 2).unwrap();
    let cam = ViewCamera::parse("0,1.2,1.6:0,0,0:50", 64, 48).unwrap();
    let bvh = baker::scene::bvh::Bvh::build(&scene);
    let visible = baker::render::visible::cast_mapped(&scene, &bvh, &lm, Some(&maps), &cam);
    let (a, beta) = (0.7, 0.4);
    let mut lobes = vec![vec![[0.0f32; 3]; lm.width * lm.height]; 9];
    let c00 = (2.0 * std::f64::consts::PI.sqrt() * a) as f32;
    let c10 = ((4.0 * std::f64::consts::PI / 3.0).sqrt() * beta) as f32;
    lobes[0].iter_mut().for_each(|t| *t = [c00; 3]);
    lobes[2].iter_mut().for_each(|t| *t = [c10; 3]);
    let atlas = Atlas { width: lm.width, height: lm.height, lobes };
    let shader = Shader::new(Lighting {
        encoding: Encoding::Basis(BasisId::Sh2),
        specular: SpecularPath::Fit,
        storage: Storage::F32,
        sg_sharpness: 6.0,
    });
    let terms = baker::render::visible::shade_pixels(&shader, &atlas, LightmapFilter::Exact, None, &scene, cam.eye, &visible);
    let n_mapped = expected(Vec3::X, Vec3::NEG_Z, 1.0);
    let want = 0.8 * (a + 2.0 / 3.0 * beta * n_mapped.dot(Vec3::Y) as f64);
    let unmapped = 0.8 * (a + 2.0 / 3.0 * beta);
    assert!((want - unmapped).abs() > 1e-2, "the map must change the shading");
    let mut n = 0;
    for (v, t) in visible.iter().zip(&terms) {
        let Some(v) = v.filter(|v| v.lightmapped) else { continue };
        n += 1;
        assert!((v.normal - n_mapped).length() < 2e-6 && (v.frame_normal - Vec3::Y).length() < 1e-6, "{} / {}", v.normal, v.frame_normal);
        let d = t.diffuse;
        assert!((d - DVec3::splat(want)).abs().max_element() < 1e-5 * want, "diffuse {d} vs {want} (unmapped {unmapped})");
    }
    assert!(n > 500, "{n} lightmapped pixels");
}

/// `--normal-maps` on a scene without one is refused, naming the option (exit 2).
#[test]
fn normal_maps_on_a_scene_without_one_is_refused() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_render"))
        .args(["--scene", "cornell", "--normal-maps", "--out"])
        .arg(scratch("refused").join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--normal-maps") && err.contains("no normal map"), "{err}");
}

/// Shading at a mapped normal n′ (`Shader::terms_at`, the texel's frame +Z) equals shading
/// the same light turned by the rotation R that takes n′ to +Z, at +Z — rotation invariance
/// of the Lambert and GGX integrals. The oracle takes the +Z paths: SH L2 through its
/// rotated coefficients (`ShRotation`) and the shader's own +Z functions; SG and AD through
/// the `sbf` runtimes called directly on the lobe axes turned by R (Hill's fit and the ASG
/// warp, the minimax quadratic and Listing 8.1 with its table at the turned view's n·v, the
/// per-lobe tables). The view is below the texel's horizon but above the mapped normal's
/// (v·Z < 0 < v·n′), so the specular gate must use n′. Error model: both sides f64 on the
/// same tables; only the tables' f32 coordinates differ by rounding (≤ 1e-6 relative).
/// Mutations: the SH zonal filter or the AD table at v·Z instead of n′·v; specular at +Z;
/// the gate on v·Z; SG/AD irradiance at +Z — each fails.
#[test]
fn shading_at_a_mapped_normal_is_shading_at_z_with_the_light_turned() {
    use baker::render::lighting::SurfaceMaterial;
    use sbf::glam::{DMat3, DQuat};
    use sbf::recon::{ambient_dice, lobe_ggx, sg};
    let nt = DVec3::new(40f64.to_radians().sin(), 0.1, 40f64.to_radians().cos()).normalize();
    let vt = DVec3::new(1.0, 0.2, -0.15).normalize();
    assert!(vt.z < 0.0 && nt.dot(vt) > 0.2);
    let r = DMat3::from_quat(DQuat::from_rotation_arc(nt, DVec3::Z));
    assert!((r * nt - DVec3::Z).length() < 1e-12);
    let rv = r * vt;
    let m = SurfaceMaterial { albedo: DVec3::splat(0.6), alpha: 0.35, f0: DVec3::splat(0.5) };
    let mut rng = sbf::sampling::Pcg32::new(7, 7);
    for (kind, path) in [
        (BasisId::Sh2, SpecularPath::Fit),
        (BasisId::Sg12, SpecularPath::Fit),
        (BasisId::Sg12, SpecularPath::Tables),
        (BasisId::Ad12, SpecularPath::Fit),
        (BasisId::Ad12, SpecularPath::Tables),
    ] {
        let shader = Shader::new(Lighting { encoding: Encoding::Basis(kind), specular: path, storage: Storage::F32, sg_sharpness: 6.0 });
        let lobes = if kind == BasisId::Sh2 { 9 } else { 12 };
        let c: Vec<DVec3> = (0..lobes)
            .map(|k| {
                let u = rng.next_2d();
                if kind == BasisId::Sh2 && k == 0 {
                    DVec3::new(1.5, 1.4, 1.2)
                } else if kind == BasisId::Sh2 {
                    DVec3::new(0.6 * u[0] - 0.3, 0.6 * u[1] - 0.3, 0.2)
                } else {
                    DVec3::new(0.2 + u[0], 0.2 + u[1], 0.5)
                }
            })
            .collect();
        let got = shader.terms_at(&c, &m, DVec3::Z, nt, vt);
        let rgb: Vec<[f64; 3]> = c.iter().map(|x| x.to_array()).collect();
        let axes: Vec<DVec3> = kind.axes().iter().map(|a| r * *a).collect();
        let (f0, f90) = (m.f0.x, 1.0);
        let (e, s): (DVec3, DVec3) = match (kind, path) {
            (BasisId::Sh2, _) => {
                let rot = sbf::ShRotation::new(2, r).unwrap();
                let ch: Vec<Vec<f64>> = (0..3).map(|k| rot.apply(&c.iter().map(|x| x[k]).collect::<Vec<_>>()).unwrap()).collect();
                let cr: Vec<DVec3> = (0..9).map(|i| DVec3::new(ch[0][i], ch[1][i], ch[2][i])).collect();
                (shader.irradiance(&cr), shader.specular(&cr, rv, m.alpha, f0, f90))
            }
            (BasisId::Sg12, p) => {
                let e = axes.iter().zip(&c).fold(DVec3::ZERO, |acc, (a, ci)| {
                    acc + *ci * sg::HillLobe::new(&sbf::Sg { axis: *a, sharpness: 6.0, amplitude: 1.0 }).eval(DVec3::Z)
                });
                let s = if p == SpecularPath::Tables {
                    DVec3::from(lobe_ggx::specular_rgb(sbf::recon::tables::lobe_ggx_sg6(), &axes, &rgb, DVec3::Z, rv, m.alpha, f0, f90))
                } else {
                    let d = sbf::recon::tables::dfg().sample2(rv.z.clamp(0.0, 1.0) as f32, m.alpha as f32);
                    let w = sg::SplitSumWarp::new(DVec3::Z, rv, m.alpha, f0, f90, [d[0] as f64, d[1] as f64]);
                    axes.iter()
                        .zip(&c)
                        .fold(DVec3::ZERO, |acc, (a, ci)| acc + *ci * w.lobe(&sbf::Sg { axis: *a, sharpness: 6.0, amplitude: 1.0 }))
                };
                (e, s)
            }
            (_, p) => {
                let e = axes.iter().zip(&c).fold(DVec3::ZERO, |acc, (a, ci)| {
                    acc + *ci * ambient_dice::lobe_irradiance_fit(&ambient_dice::DIFFUSE_FIT_MINIMAX, a.z)
                });
                let s = if p == SpecularPath::Tables {
                    DVec3::from(lobe_ggx::specular_rgb(sbf::recon::tables::lobe_ggx_ad(), &axes, &rgb, DVec3::Z, rv, m.alpha, f0, f90))
                } else {
                    let l = sbf::recon::tables::ad_specular_2d().sample2(rv.z as f32, m.alpha as f32);
                    DVec3::from(ambient_dice::specular_rgb(&axes, &rgb, DVec3::Z, rv, m.alpha, f0, f90, [l[0] as f64, l[1] as f64]))
                };
                (e, s)
            }
        };
        let want = (m.albedo * e, s);
        println!("{kind:?} {path:?}: diffuse {} vs {}, specular {} vs {}", got.diffuse, want.0, got.specular, want.1);
        assert!(want.1.min_element() > 1e-3, "{kind:?}: the turned view must see specular");
        let close = |a: DVec3, b: DVec3| (a - b).abs().max_element() <= 1e-6 * b.abs().max_element().max(1e-3);
        assert!(close(got.diffuse, want.0), "{kind:?} {path:?} diffuse: {} vs {}", got.diffuse, want.0);
        assert!(close(got.specular, want.1), "{kind:?} {path:?} specular: {} vs {}", got.specular, want.1);
    }
}

/// The texel is read at the transformed coordinates: a 2 × 1 map (left texel `TEXEL`, right
/// another), NEAREST, REPEAT, rotated by π/2 (u′ = v, v′ = −u); at (u, v) = (¼, ¾) — triangle
/// 0's barycentrics (¼, ½, ¼) of corners uv (0, 0), (0, 1), (1, 1) — u′ = ¾ reads the right
/// texel (untransformed, u = ¼ would read the left). Mutation: the texel read at the raw
/// coordinates fails.
#[test]
fn the_normal_map_is_read_at_its_transformed_coordinates() {
    let right = [60u8, 200, 210];
    let img = image::RgbaImage::from_fn(2, 1, |x, _| {
        let c = if x == 0 { TEXEL } else { right };
        image::Rgba([c[0], c[1], c[2], 255])
    });
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let dir = scratch("transform");
    let s = scene_with(&dir, 1.0, std::f32::consts::FRAC_PI_2, png.get_ref());
    let maps = NormalMaps::build(&s, &mut |m| panic!("{m}")).unwrap();
    let m = right.map(|c| 2.0 * c as f32 / 255.0 - 1.0);
    let want = (Vec3::Z * m[0] + Vec3::X * m[1] + Vec3::Y * m[2]).normalize();
    let got = maps.perturb(&s, 0, 0, [0.25, 0.5, 0.25], Vec3::Y);
    assert!((got - want).length() < 2e-6, "{got} vs {want}");
}
