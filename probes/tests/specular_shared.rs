//! The specular images of lobe modes on the table runtime share each lobe's response with
//! every mode of the same lobe layout (`specular::reconstruct`); they equal the runtime
//! evaluated texel by texel (`lobe_ggx_specular`, the WGSL's CPU twin) bit for bit — the
//! shared path sums the same f32 products in the same order. Both domains, with and without
//! an ambient function, SG and Ambient Dice layouts, three roughness values. Mutation tried:
//! summing the shared responses in reverse lobe order — fails (f32 sums differ).

use probes::modes::{run, Context};
use probes::specular::{reconstruct, runtime_image};
use sbf::envmap::LatLongImage;
use sbf::Domain;

#[test]
fn shared_lobe_responses_equal_the_runtime_bit_for_bit() {
    let map = LatLongImage::from_fn(64, 32, |d| [1.0 + 4.0 * d.x.max(0.0).powi(8), 0.5 + 0.5 * d.y, 0.3 + d.z * d.z]).unwrap();
    for domain in [Domain::Sphere, Domain::UpperHemisphere] {
        let ctx = Context::with_domain(map.clone(), domain);
        for id in ["sgls", "sgra", "sglsa", "adrbf", "adpls"] {
            let r = run(id, &ctx, 1).unwrap();
            for alpha in [0.1, 0.4, 0.8] {
                let shared = reconstruct(&r, &ctx, alpha).expect("a lobe mode has specular");
                let direct = runtime_image(&r, &ctx, alpha).unwrap();
                assert_eq!(shared.len(), direct.len());
                for (k, (a, b)) in shared.iter().zip(&direct).enumerate() {
                    assert!(
                        a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()),
                        "{id} α {alpha} {domain:?} texel {k}: {a:?} vs {b:?}"
                    );
                }
            }
        }
    }
}
