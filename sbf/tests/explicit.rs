//! Behaviour that used to be silent, made explicit: LUT lookups
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

/// Lut3 sampling by value: a table of the trilinear function
/// f(x, y, z) = 1 + 2x − 3y + 0.5z + 4xy − xz + 2yz + 3xyz stored at texel centres
/// (non-cubic dims, axis 2 over the range −1 to 3, two channels) reproduces f exactly (to
/// f32 rounding of about 10 operations on values up to 20: bar 1e-5) anywhere between the
/// first and last centres, since trilinear interpolation is exact for trilinear functions,
/// and clamps to the edge centres outside, per axis.
#[test]
fn lut3_samples_trilinear_functions_exactly_and_clamps() {
    let f = |x: f64, y: f64, z: f64| 1.0 + 2.0 * x - 3.0 * y + 0.5 * z + 4.0 * x * y - x * z + 2.0 * y * z + 3.0 * x * y * z;
    let dims = [5usize, 3, 4];
    let (lo2, hi2) = (-1.0f64, 3.0f64);
    let centre = |i: usize, n: usize| (i as f64 + 0.5) / n as f64;
    let z_of = |k: usize| lo2 + (hi2 - lo2) * centre(k, dims[2]);
    let mut data = Vec::new();
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let v = f(centre(i, dims[0]), centre(j, dims[1]), z_of(k));
                data.extend_from_slice(&[v as f32, (-2.0 * v) as f32]);
            }
        }
    }
    let t = Lut3 { dims, channels: 2, range2: (lo2 as f32, hi2 as f32), data };
    let mut rng = sbf::sampling::Pcg32::new(4, 4);
    let mut out = [0.0f32; 2];
    for _ in 0..10_000 {
        let r = rng.next_2d();
        let r2 = rng.next_2d()[0];
        // Inside the centres' box.
        let x = centre(0, 5) + r[0] * (centre(4, 5) - centre(0, 5));
        let y = centre(0, 3) + r[1] * (centre(2, 3) - centre(0, 3));
        let z = z_of(0) + r2 * (z_of(3) - z_of(0));
        t.sample_into(x as f32, y as f32, z as f32, &mut out);
        let want = f(x, y, z);
        assert!((out[0] as f64 - want).abs() < 1e-5 && (out[1] as f64 + 2.0 * want).abs() < 2e-5, "({x}, {y}, {z}): {out:?} vs {want}");
        // Outside on every axis: clamped to the nearest centre per axis.
        let (xo, yo, zo) = (-0.3 - r[0], 1.2 + r[1], hi2 + 5.0 * r2);
        t.sample_into(xo as f32, yo as f32, zo as f32, &mut out);
        let want = f(centre(0, 5), centre(2, 3), z_of(3));
        assert!((out[0] as f64 - want).abs() < 1e-5, "clamped ({xo}, {yo}, {zo}): {} vs {want}", out[0]);
    }
}
