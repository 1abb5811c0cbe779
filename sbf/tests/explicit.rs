//! Behaviour that used to be silent, made explicit (issue 20 item 6): LUT lookups
//! propagate NaN coordinates instead of reading a corner, `MapSampler` counts texels with
//! non-finite radiance, and the Ambient Dice bases refuse an output of the wrong length.

use sbf::envmap::LatLongImage;
use sbf::glam::DVec3;
use sbf::recon::lut::{Lut2, Lut3};
use sbf::recon::reference::MapSampler;
use sbf::{AmbientDiceLinear, AmbientDiceSrbf, Basis};

/// Values by hand on a 2 × 2 table: centres, the bilinear midpoint, ±∞ clamped to edges,
/// NaN in either coordinate → NaN (was: the (0, ·) corner).
#[test]
fn lut2_nan_is_nan_and_infinities_clamp() {
    let t = Lut2::new(2, 2, 1, vec![1.0, 2.0, 3.0, 4.0]).unwrap();
    let s = |u: f32, v: f32| t.sample2(u, v)[0];
    assert_eq!(s(0.25, 0.25), 1.0);
    assert_eq!(s(0.75, 0.75), 4.0);
    assert_eq!(s(0.5, 0.5), 2.5);
    assert_eq!(s(f32::INFINITY, f32::NEG_INFINITY), 2.0);
    assert!(s(f32::NAN, 0.5).is_nan() && s(0.5, f32::NAN).is_nan());
}

#[test]
fn lut3_nan_is_nan() {
    let t = Lut3 { dims: [2, 2, 2], channels: 1, range2: (0.0, 1.0), data: (1..=8).map(|x| x as f32).collect() };
    let mut o = [0.0f32];
    t.sample_into(0.25, 0.25, 0.25, &mut o);
    assert_eq!(o[0], 1.0);
    t.sample_into(0.5, 0.5, 0.5, &mut o);
    assert_eq!(o[0], 4.5);
    for (u, v, w) in [(f32::NAN, 0.5, 0.5), (0.5, f32::NAN, 0.5), (0.5, 0.5, f32::NAN)] {
        t.sample_into(u, v, w, &mut o);
        assert!(o[0].is_nan(), "({u}, {v}, {w}) gave {}", o[0]);
    }
}

/// Two NaN texels and one infinite texel are counted and never sampled.
#[test]
fn map_sampler_counts_non_finite_texels() {
    let mut texels = vec![[1.0f32; 3]; 16 * 8];
    texels[5] = [f32::NAN, 1.0, 1.0];
    texels[40] = [1.0, f32::INFINITY, 1.0];
    texels[77] = [f32::NAN; 3];
    let map = LatLongImage::new(16, 8, texels).unwrap();
    let s = MapSampler::new(&map).unwrap();
    assert_eq!(s.non_finite_texels(), 3);
    let clean = MapSampler::new(&LatLongImage::new(16, 8, vec![[1.0f32; 3]; 128]).unwrap()).unwrap();
    assert_eq!(clean.non_finite_texels(), 0);
}

#[test]
#[should_panic(expected = "out has 11 values for 12 lobes")]
fn srbf_eval_into_refuses_a_short_output() {
    AmbientDiceSrbf::twelve().eval_into(DVec3::Z, &mut [0.0; 11]);
}

#[test]
#[should_panic(expected = "out has 13 values for 12 lobes")]
fn srbf_eval_into_refuses_a_long_output() {
    AmbientDiceSrbf::twelve().eval_into(DVec3::Z, &mut [0.0; 13]);
}

#[test]
#[should_panic(expected = "out has 11 values for 12 vertices")]
fn linear_eval_into_refuses_a_short_output() {
    AmbientDiceLinear::new().eval_into(DVec3::Z, &mut [0.0; 11]);
}
