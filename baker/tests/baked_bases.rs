//! What a bake and the renderer accept of the registry's bases, and the Lambert twin of the
//! bases they do not bake: a bake encodes into the bases with a GPU slot (probes only into
//! the sphere ones), the renderer shades the lightmap bases, and the irradiance bases'
//! coefficients reconstruct E/π itself (the ambient cube at an axis is that axis' value —
//! its closed form). Each refusal is an error naming the basis, never a panic later.

use baker::accumulate::{BakeConfig, BakedBasis, BasisId, Targets};
use baker::layout::lightmap::Lightmap;
use baker::render::lighting::{Encoding, Lighting, Storage};
use sbf::glam::DVec3;
use sbf::profile::SpecularPath;

#[test]
fn bakes_and_renders_refuse_bases_they_cannot_encode_or_shade() {
    let s = baker::scene::cornell();
    let lm = Lightmap::build(&s, 2.0, 1).unwrap();
    let texels = Targets::lightmap(&lm);
    let probes = Targets::probes(&[sbf::glam::Vec3::ZERO]);
    for b in BasisId::ALL {
        let cfg = BakeConfig { bases: vec![b], ..Default::default() };
        let baked = b.gpu_kind().is_some();
        match cfg.check(&texels) {
            Ok(()) => assert!(baked, "{b}: a bake accepted an irradiance basis"),
            Err(e) => assert!(!baked && e.contains(b.name()), "{b}: {e}"),
        }
        match cfg.check(&probes) {
            Ok(()) => assert!(baked && b.is_sphere(), "{b}: probes accepted a hemisphere or irradiance basis"),
            Err(e) => assert!((!baked || !b.is_sphere()) && e.contains(b.name()), "{b}: {e}"),
        }
        let l = Lighting { encoding: Encoding::Basis(b), specular: SpecularPath::Fit, storage: Storage::F32, sg_sharpness: 6.0 };
        assert_eq!(l.check().is_ok(), b.info().lightmap, "{b}: the renderer's check");
    }
}

#[test]
fn the_irradiance_bases_reconstruct_their_own_values() {
    // Ambient cube: E/π at +X, −X, +Y, −Y, +Z, −Z; at an axis the cube is that value.
    let c: Vec<DVec3> = (0..6).map(|i| DVec3::new(1.0 + i as f64, 10.0 + i as f64, 100.0 + i as f64)).collect();
    let axes = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
    for (i, a) in axes.iter().enumerate() {
        let e = BasisId::AmbientCube.irradiance_at(&c, *a, 6.0);
        assert!((e - c[i]).abs().max_element() < 1e-12, "axis {i}: {e} vs {}", c[i]);
    }
}
