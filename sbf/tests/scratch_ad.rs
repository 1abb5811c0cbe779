use glam::DVec3;
use sbf::recon::ambient_dice as ad;
#[test]
fn scratch() {
    let lobes = sbf::layout::icosahedron_hemisphere();
    let lut = sbf::luts::committed::ad_specular_2d();
    for &alpha in &[0.05, 0.1, 0.2, 0.3, 0.5, 0.8] {
        for &tv in &[0.0f64, 30.0, 60.0, 75.0, 85.0] {
            let nv = tv.to_radians().cos().max(1e-3);
            let n = DVec3::Z;
            let v = DVec3::new(0.0, (1.0 - nv * nv).sqrt(), nv);
            let l = lut.sample2(nv as f32, alpha as f32);
            let mut line = format!("a {alpha:.2} tv {tv:4.0}: ");
            let (mut sf, mut sq) = (0.0, 0.0);
            for az in [0.0f64, 1.0, 2.0] {
                let rot = glam::DQuat::from_rotation_z(az);
                for lb in &lobes {
                    let p = rot * *lb;
                    let f =
                        ad::lobe_specular_fit(&ad::SPECULAR_FIT_LISTING_8_1, &ad::DIFFUSE_FIT_LISTING_8_1, p, n, v, alpha) * l[0] as f64;
                    let q = ad::lobe_specular_quadrature(p, nv, alpha, 96)[0];
                    sf += f;
                    sq += q;
                    if az == 0.0 {
                        line += &format!("{:.2}({:.1e}) ", f / q.max(1e-12), q);
                    }
                }
            }
            println!("{line} | sum {:.3}", sf / sq);
        }
    }
}
