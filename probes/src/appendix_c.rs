//! [Roughton19 Appendix C]'s pipeline where it differs from the physical one — what
//! `--reference appendix-c` changes, read from the author's Probulator fork (github
//! troughton/Probulator, branch `ambient-dice`, commit 2a6cfda4e011ecdecf286c1975679c716a97369f):
//!
//! - the GGX reference weighs each visible-normal sample by G2·G1(v) instead of G2/G1(v),
//!   lets light from below the surface in (none comes: see the last point), and uses
//!   Schlick's Fresnel with f0 0.9, f90 1 ([`sbf::ggx::Convention::AppendixC`]; the kernel
//!   is [`crate::specular::GgxRows`]);
//! - the runtimes are Roughton's: SG lobes through the ASG warp (with the physical
//!   visibility, as Roughton's SG code computes it, and its arbitrary frame about the
//!   reflected direction, [`asg_warp`]) and AD lobes through \[RoughtonFork\]'s own specular fit
//!   and its per-pixel table ([`ad_lobe_fit`], [`ad_table`]: the printed AD figures are
//!   that code's, not Listing 8.1's — see [`AD_FIT`]); both with f0 0.9;
//! - the SG fits point-sample the map: 20 000 Halton directions over the sphere, each the
//!   nearest texel of the map resized to 512×256 ([`sg_samples`]), equal weights;
//! - RMS over the upper half of the output rows, every texel equal (as `--domain
//!   hemisphere` always does);
//! - the environment is black below the horizon ([`clip_below_horizon`]): "the images are
//!   clipped to the upper hemisphere to represent lightmap use cases" (Appendix C) — a
//!   lightmap texel facing up receives no light from below. No code of \[RoughtonFork\] does this
//!   (its `upperHemisphereOnly`, false in the commit, clips the output images only); the printed
//!   figures say it: with the lower half black, every radiance cell and every SG GGX cell
//!   comes within 1.00–1.05× of Roughton's, with it lit wells' SG cells sit at 1.25–1.29×
//!   (docs/probes.md has both tables).
//!
//! The lobe layouts are Roughton's in both modes ([`crate::frame::tangent_to_world`]).

use sbf::envmap::{LatLong, LatLongImage};
use sbf::glam::DVec3;
use sbf::solve::RadianceSample;

/// How reports name the specular signal under `convention`.
pub fn label(convention: sbf::ggx::Convention) -> &'static str {
    match convention {
        sbf::ggx::Convention::Physical => "f0 = f90 = 1, physical reference",
        sbf::ggx::Convention::AppendixC => {
            "APPENDIX C COMPATIBLE reference, not the physical integral: the environment black below the horizon, Roughton's G2·G1 visibility, Schlick f0 0.9 / f90 1; Roughton's runtimes; SG fits point-sampled"
        }
    }
}

/// How reports name the compatible mode's runtimes.
pub const RUNTIMES: &str = "Roughton's runtimes: SG lobes through the ASG warp (Xu et al. 2013) in [RoughtonFork]'s frame about R; AD lobes through [RoughtonFork]'s committed specular fit × its per-pixel 512-sample table (not Listing 8.1: Appendix C's figures are that code's); SH by its zonal GGX convolution × DFG";

/// The peer's output (and resize) size: `outputImageSize(512, 256)` in its CLI.
pub const SIZE: LatLong = LatLong { width: 512, height: 256 };
/// Halton samples of the point-sampled fits (`sampleCount = 20000`).
pub const SAMPLES: u32 = 20_000;

/// The map with every texel whose centre lies below the horizon set to black: rows j with
/// polar angle π(j + ½)/h > π/2, i.e. 2j + 1 > h (both tools' lat-long rows run from the
/// zenith; an odd height's middle row, centred on the horizon, is kept). What Roughton's
/// figures measure (module docs); the rows above are returned bit for bit.
pub fn clip_below_horizon(map: &LatLongImage) -> LatLongImage {
    let g = map.geometry;
    let texels = (0..g.height)
        .flat_map(|j| (0..g.width).map(move |i| (i, j)))
        .map(|(i, j)| if 2 * j + 1 > g.height { [0.0; 3] } else { map.texel(i, j) })
        .collect();
    LatLongImage::new(g.width, g.height, texels).expect("same geometry as a valid map")
}

/// The Ambient Dice specular fit in \[RoughtonFork\]'s `ExperimentAmbientDice.cpp` at 2a6cfda
/// (`parameters[10]`): alphaLerp = Σ pᵢ·αⁱ (i = 0..4) blends the lobe in the mirror
/// direction towards its diffuse response, evaluated at a direction focusLerp = Σ p₅₊ᵢ·αⁱ
/// of the way from R to n. The thesis prints another fit (Listing 8.1: √α polynomials, eight
/// constants, with the 2D table of Listing 8.2), but Appendix C's AD figures are this code's:
/// with it, and the table [`ad_table`] it computes per pixel, the AD cells at α 0.4–0.6 come
/// within 0.99–1.12× of the printed ones, against 0.50–1.34× with Listing 8.1 × its table
/// (docs/probes.md).
pub const AD_FIT: [f64; 10] = [
    -0.03480017115306019,
    1.5767277269939315,
    3.2915521747760006,
    -8.886052306193424,
    5.289174934167271,
    0.658318188157326,
    -0.9258960547724002,
    2.9786527829025813,
    -2.0077225608393703,
    0.2642150798240006,
];

/// [`AD_FIT`]'s value for a lobe at cosine `r_dot` to the mirror direction and `n_dot` to
/// the normal: mix(B(r_dot), L(mix(r_dot, n_dot, focusLerp)), alphaLerp) with B the lobe
/// ([Roughton19 eq. 8.3]) and L its irradiance quadratic (eq. 8.14), both lerps clamped to [0, 1].
fn ad_fit_value(r_dot: f64, n_dot: f64, alpha: f64) -> f64 {
    let quartic = |p: &[f64]| p.iter().rev().fold(0.0, |acc, c| acc * alpha + c);
    let focus = quartic(&AD_FIT[5..]).clamp(0.0, 1.0);
    let x = r_dot + (n_dot - r_dot) * focus;
    let diffuse = sbf::recon::ambient_dice::DIFFUSE_FIT_LISTING_8_1.iter().rev().fold(0.0, |acc, c| acc * x + c);
    let mirror = sbf::basis::ambient_dice::srbf_lobe(r_dot);
    mirror + (diffuse - mirror) * quartic(&AD_FIT[..5]).clamp(0.0, 1.0)
}

/// One AD lobe's specular weight before the table (\[RoughtonFork\]'s
/// `estimateSRBFBasisWeightGGXCustomFit` without its `lutValueApprox` factor): 0 below the
/// horizon (n·v < 0).
pub fn ad_lobe_fit(lobe: DVec3, n: DVec3, v: DVec3, alpha: f64) -> f64 {
    let nv = n.dot(v);
    if nv < 0.0 {
        return 0.0;
    }
    let r = 2.0 * nv * n - v;
    ad_fit_value(lobe.dot(r), n.dot(lobe), alpha)
}

/// Samples of \[RoughtonFork\]'s table: `sampleHammersley(i, 512)` = (i/512, radical inverse of i).
pub const AD_TABLE_SAMPLES: u32 = 512;

/// A visible normal for view `v` (z-up tangent frame) by Heitz 2017, "A Simpler and Exact
/// Sampling Routine for the GGX Distribution of Visible Normals" — \[RoughtonFork\]'s
/// `sampleGGXVNDF`, which the table's estimate depends on at 512 samples (the 2018 routine in
/// `sbf::ggx` maps the square differently).
fn vndf_2017(v: DVec3, alpha: f64, u1: f64, u2: f64) -> DVec3 {
    use std::f64::consts::PI;
    let vs = DVec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let t1 = if vs.z < 0.9999 { vs.cross(DVec3::Z).normalize() } else { DVec3::X };
    let t2 = t1.cross(vs);
    let a = 1.0 / (1.0 + vs.z);
    let r = u1.sqrt();
    let phi = if u2 < a { u2 / a * PI } else { PI + (u2 - a) / (1.0 - a) * PI };
    let (p1, p2) = (r * phi.cos(), r * phi.sin() * if u2 < a { 1.0 } else { vs.z });
    let m = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vs;
    DVec3::new(alpha * m.x, alpha * m.y, m.z.max(0.0)).normalize()
}

/// \[RoughtonFork\]'s per-pixel table `lutValueApprox(n·v, α)`: the (f0, f90) scales that turn
/// [`ad_lobe_fit`] into the G2·G1-weighted ground truth for a lobe along the GGX dominant
/// direction — Σ B(lobe·l)·(1 − w, w)·G2·G1(v) over `samples` visible normals (Hammersley
/// (i/N, radical inverse), the coordinates swapped as in \[RoughtonFork\]; l above the surface only;
/// w = (1 − v·h)⁵) divided by N and by the fit's value there. n·v and α clamped to
/// [0.5/256, 0.999] as \[RoughtonFork\] does.
pub fn ad_table(n_dot_v: f64, alpha: f64, samples: u32) -> [f64; 2] {
    let nv = n_dot_v.clamp(0.5 / 256.0, 0.999);
    let a = alpha.clamp(0.5 / 256.0, 0.999);
    let v = DVec3::new(0.0, (1.0 - nv * nv).sqrt(), nv);
    let r = DVec3::new(-v.x, -v.y, v.z);
    let lobe = sbf::ggx::dominant_direction(DVec3::Z, r, a);
    let value = ad_fit_value(r.dot(lobe), lobe.z, a);
    let mut gt = [0.0; 2];
    for i in 0..samples {
        let h = vndf_2017(v, a, sbf::sampling::radical_inverse(2, i as u64), i as f64 / samples as f64);
        let l = 2.0 * v.dot(h) * h - v;
        if l.z <= 0.0 {
            continue;
        }
        let weight = sbf::ggx::Convention::AppendixC.vndf_weight(v, l, a) * sbf::basis::ambient_dice::srbf_lobe(lobe.dot(l));
        let w = sbf::ggx::schlick_weight(v.dot(h));
        gt[0] += (1.0 - w) * weight;
        gt[1] += w * weight;
    }
    gt.map(|g| g / samples as f64 / value)
}

/// Roughton's GGX reference as \[RoughtonFork\] computes it (`ExperimentMonteCarlo.h`, its
/// `upperHemisphereOnly` branch): per output texel with view `views[k]` (world; None: no
/// signal) and normal +Y, `samples` visible normals (\[RoughtonFork\]'s Hammersley points through
/// Heitz's 2017 routine, as [`ad_table`]), each reflected to l and weighted by
/// F·G2·G1(v) (Schlick f0 0.9, f90 1 at saturate(v·h)), the radiance read bilinearly —
/// the peer's `sampleBilinear`, texel corners at integer coordinates — from the map resized
/// to 512×256 and black below the horizon, averaged. A quasi-Monte Carlo estimate with the
/// same points at every texel: its error is structured, and is Roughton's (the exact
/// integral of the same kernel is the default reference).
pub fn monte_carlo_reference(map: &LatLongImage, views: &[Option<DVec3>], alpha: f64, samples: u32) -> Result<Vec<[f64; 3]>, String> {
    use rayon::prelude::*;
    let m = clip_below_horizon(&resized(map)?);
    let (w, h) = (m.geometry.width, m.geometry.height);
    let points: Vec<(f64, f64)> = (0..samples).map(|i| (i as f64 / samples as f64, sbf::sampling::radical_inverse(2, i as u64))).collect();
    let bilinear = |p: DVec3| -> [f64; 3] {
        let pi = std::f64::consts::PI;
        let (x, y) = (0.5 * (1.0 + p.x.atan2(-p.y) / pi) * w as f64, p.z.clamp(-1.0, 1.0).acos() / pi * h as f64);
        let (x0, y0) = ((x.floor().max(0.0) as usize).min(w - 1), (y.floor().max(0.0) as usize).min(h - 1));
        let (x1, y1) = ((x.ceil().max(0.0) as usize).min(w - 1), (y.ceil().max(0.0) as usize).min(h - 1));
        let (fx, fy) = (x - x0 as f64, y - y0 as f64);
        let t = |i: usize, j: usize| m.texel(i, j);
        [0, 1, 2].map(|c| {
            t(x0, y0)[c] as f64 * (1.0 - fx) * (1.0 - fy)
                + t(x0, y1)[c] as f64 * (1.0 - fx) * fy
                + t(x1, y0)[c] as f64 * fx * (1.0 - fy)
                + t(x1, y1)[c] as f64 * fx * fy
        })
    };
    Ok(views
        .par_iter()
        .map(|view| {
            let Some(view) = view else { return [0.0; 3] };
            let v = crate::frame::world_to_tangent(*view);
            let mut acc = [0.0; 3];
            for &(u2, u1) in &points {
                let hm = vndf_2017(v, alpha, u1, u2);
                let l = 2.0 * v.dot(hm) * hm - v;
                let f = 0.9 + 0.1 * sbf::ggx::schlick_weight(v.dot(hm));
                let weight = f * sbf::ggx::Convention::AppendixC.vndf_weight(v, l, alpha);
                let radiance = bilinear(l.normalize());
                for c in 0..3 {
                    acc[c] += weight * radiance[c];
                }
            }
            acc.map(|a| a / samples as f64)
        })
        .collect())
}

/// Roughton's SG runtime for normal n, view v (world): the ASG warp with the orthonormal
/// basis of Duff et al. 2017 ("Building an Orthonormal Basis, Revisited", Listing 3) about
/// the reflected direction in the peer's z-up tangent frame, as its `sgWarpDistribution`
/// builds it.
pub fn asg_warp(n: DVec3, v: DVec3, alpha: f64, f0: f64, f90: f64) -> sbf::recon::sg::AsgWarp {
    use crate::frame::{tangent_to_world, world_to_tangent};
    sbf::recon::sg::AsgWarp::with_frame(n, v, alpha, f0, f90, |z| {
        let t = world_to_tangent(z);
        let sign = 1.0f64.copysign(t.z);
        let a = -1.0 / (sign + t.z);
        let b = t.x * t.y * a;
        let b1 = DVec3::new(1.0 + sign * t.x * t.x * a, sign * b, -sign * t.x);
        let b2 = DVec3::new(b, sign + t.y * t.y * a, -t.y);
        (tangent_to_world(b1), tangent_to_world(b2))
    })
}

/// The radical inverse in f32 as the peer's `sampleHalton` computes it.
fn halton(mut index: u32, base: u32) -> f32 {
    let (mut f, mut r) = (1.0f32, 0.0f32);
    while index > 0 {
        f /= base as f32;
        r += f * (index % base) as f32;
        index /= base;
    }
    r
}

/// The Catmull–Rom kernel (B = 0, C = ½), stb_image_resize's default for upsampling.
fn catmull_rom(x: f64) -> f64 {
    let x = x.abs();
    if x < 1.0 {
        1.5 * x * x * x - 2.5 * x * x + 1.0
    } else if x < 2.0 {
        -0.5 * x * x * x + 2.5 * x * x - 4.0 * x + 2.0
    } else {
        0.0
    }
}

/// Per output index: (first input index, weights), output centre (o + ½)/s in input texels,
/// weights normalised to sum 1, indices clamped at the edges (stb's `STBIR_EDGE_CLAMP`).
fn upsample_weights(n_in: usize, n_out: usize) -> Vec<Vec<(usize, f64)>> {
    let s = n_out as f64 / n_in as f64;
    (0..n_out)
        .map(|o| {
            let c = (o as f64 + 0.5) / s;
            let lo = (c - 2.5).floor() as i64;
            let mut w: Vec<(usize, f64)> = (lo..lo + 6)
                .map(|i| ((i.clamp(0, n_in as i64 - 1)) as usize, catmull_rom(i as f64 + 0.5 - c)))
                .filter(|(_, w)| *w != 0.0)
                .collect();
            let total: f64 = w.iter().map(|(_, x)| x).sum();
            w.iter_mut().for_each(|(_, x)| *x /= total);
            w
        })
        .collect()
}

/// The map at the peer's 512×256 (`imageResize`: stb_image_resize, Catmull–Rom, separable,
/// edges clamped). Maps of that size are used as they are; larger maps would need the
/// peer's downsampling filter (Mitchell) and are refused.
pub fn resized(map: &LatLongImage) -> Result<LatLongImage, String> {
    let g = map.geometry;
    if g.width == SIZE.width && g.height == SIZE.height {
        return Ok(map.clone());
    }
    if g.width > SIZE.width || g.height > SIZE.height {
        return Err(format!(
            "--reference appendix-c: Roughton's point-sampled fits read the map resized to 512×256; a {}×{} map would be downsampled (stb's Mitchell filter), which is not reproduced — give a map of at most 512×256",
            g.width, g.height
        ));
    }
    let wx = upsample_weights(g.width, SIZE.width);
    let wy = upsample_weights(g.height, SIZE.height);
    // Horizontal pass, then vertical.
    let mut rows = vec![[0.0f64; 3]; SIZE.width * g.height];
    for j in 0..g.height {
        for (o, w) in wx.iter().enumerate() {
            let mut acc = [0.0; 3];
            for &(i, k) in w {
                let t = map.texel(i, j);
                for c in 0..3 {
                    acc[c] += k * t[c] as f64;
                }
            }
            rows[j * SIZE.width + o] = acc;
        }
    }
    let mut out = vec![[0.0f32; 3]; SIZE.width * SIZE.height];
    for (o, w) in wy.iter().enumerate() {
        for i in 0..SIZE.width {
            let mut acc = [0.0; 3];
            for &(j, k) in w {
                for c in 0..3 {
                    acc[c] += k * rows[j * SIZE.width + i][c];
                }
            }
            out[o * SIZE.width + i] = acc.map(|x| x as f32);
        }
    }
    LatLongImage::new(SIZE.width, SIZE.height, out).map_err(|e| e.to_string())
}

/// Roughton's SG fitting samples of `map` (already [`clip_below_horizon`]ed), in our world frame: Halton (2, 3) points 1..=20 000 mapped
/// uniformly onto the sphere (`sampleUniformSphere`), each valued by the nearest texel of the
/// resized map at the peer's `cartesianToLatLongTexcoord`, weight 4π/N (its sample Gram and
/// moments). Computed in f32 like the peer, so each sample reads the same texel.
pub fn sg_samples(map: &LatLongImage) -> Result<Vec<RadianceSample>, String> {
    // Black below the horizon at the resized size too: Catmull–Rom's lobes would carry
    // the upper rows a little way below it.
    let m = clip_below_horizon(&resized(map)?);
    let weight = 4.0 * std::f64::consts::PI / SAMPLES as f64;
    let pi = std::f32::consts::PI;
    Ok((1..=SAMPLES)
        .map(|i| {
            let (u, v) = (halton(i, 2), halton(i, 3));
            let z = 1.0 - 2.0 * u;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let (s, c) = (2.0 * pi * v).sin_cos();
            let p = [r * c, r * s, z];
            // The peer's lat-long lookup in its z-up frame, nearest texel, clamped.
            let tu = 0.5 * (1.0 + p[0].atan2(-p[1]) / pi);
            let tv = p[2].clamp(-1.0, 1.0).acos() / pi;
            let x = ((tu * SIZE.width as f32).floor() as i64).clamp(0, SIZE.width as i64 - 1) as usize;
            let y = ((tv * SIZE.height as f32).floor() as i64).clamp(0, SIZE.height as i64 - 1) as usize;
            let t = m.texel(x, y);
            RadianceSample {
                direction: crate::frame::tangent_to_world(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)),
                value: [t[0] as f64, t[1] as f64, t[2] as f64],
                weight,
            }
        })
        .collect())
}

/// The probes Appendix C prints figures for, in its order.
pub const PROBES: [&str; 5] = ["ennis", "grace", "pisa", "uffizi", "wells"];
/// Its bases, in column order, and our mode for each.
pub const MODES: [(&str, &str); 4] = [("AD9", "ad9"), ("AD12", "adrbf-tangent"), ("SG9", "sg9h"), ("SG12", "sg12h")];
/// Its GGX roughness rows.
pub const ALPHAS: [f64; 5] = [0.1, 0.2, 0.4, 0.6, 0.8];

/// The figures Appendix C prints (Figs. C.1–C.5): per probe of [`PROBES`], rows radiance,
/// Lambert, GGX α of [`ALPHAS`]; columns as [`MODES`]; NaN where it has no row.
pub const SEED: [[[f64; 4]; 7]; 5] = {
    const N: f64 = f64::NAN;
    [
        // ennis
        [
            [5.25, 5.83, 6.45, 5.54],
            [0.148, 0.105, 0.327, 0.225],
            [2.17, 2.74, 2.97, 2.34],
            [0.947, 1.37, 1.47, 1.12],
            [0.276, 0.409, 0.566, 0.574],
            [0.130, 0.137, 0.378, 0.466],
            [0.119, 0.091, 0.299, 0.374],
        ],
        // grace
        [
            [27.6, 27.6, 27.7, 27.7],
            [0.0118, 0.0130, 0.300, 0.303],
            [0.956, 0.936, 1.22, 1.22],
            [0.395, 0.377, 0.670, 0.671],
            [0.0809, 0.0733, 0.316, 0.319],
            [0.0178, 0.0170, 0.191, 0.192],
            [0.0127, 0.0144, 0.121, 0.122],
        ],
        // pisa
        [
            [0.297, 0.285, 0.264, 0.235],
            [0.00755, 0.00580, 0.0150, 0.0138],
            [0.145, 0.133, 0.109, 0.076],
            [0.0749, 0.0698, 0.0542, 0.0404],
            [0.0158, 0.0202, 0.0353, 0.0378],
            [0.00869, 0.0119, 0.0388, 0.0391],
            [N, N, N, N],
        ],
        // uffizi
        [
            [3.96, 4.06, 3.67, 3.25],
            [0.0367, 0.0397, 0.0662, 0.0573],
            [2.01, 2.10, 1.77, 1.41],
            [1.04, 1.10, 0.827, 0.680],
            [0.270, 0.291, 0.411, 0.455],
            [0.0691, 0.0735, 0.299, 0.323],
            [0.0323, 0.0300, 0.198, 0.207],
        ],
        // wells
        [
            [0.5574, 0.5492, 0.5283, 0.5210],
            [0.0110, 0.00729, 0.0217, 0.011408],
            [0.227, 0.219, 0.195, 0.192],
            [0.0955, 0.0894, 0.0848, 0.0948],
            [0.0169, 0.0176, 0.0574, 0.0617],
            [0.00964, 0.0118, 0.0537, 0.0526],
            [N, N, N, N],
        ],
    ]
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_matches_the_radical_inverse() {
        // 1/2, 1/4, 3/4, 1/8 in base 2; 1/3, 2/3, 1/9 in base 3.
        assert_eq!([1, 2, 3, 4].map(|i| halton(i, 2)), [0.5, 0.25, 0.75, 0.125]);
        assert_eq!([1, 2, 3].map(|i| halton(i, 3)), [1.0 / 3.0, 2.0 / 3.0, 1.0 / 9.0]);
    }

    /// Each point sample reads the texel the peer's lookup names: on a 512×256 map (used as
    /// it is) whose texels hold their own index + 1, black below the horizon, sample k
    /// (Halton point k + 1) reads the texel at floor(u·512), floor(v·256) of the peer's
    /// `cartesianToLatLongTexcoord` of `sampleUniformSphere`, written here from its source
    /// in f64 — equal except where a point lies within f32 rounding of a texel edge (at most
    /// a few of 2000). Mutations tried: `round` for `floor`; the Halton index from 0 — both
    /// fail (the clip after the resize: `samples_below_the_horizon_read_black_after_the_resize`).
    #[test]
    fn point_samples_read_the_peers_texels() {
        let (w, h) = (SIZE.width, SIZE.height);
        let map = LatLongImage::new(w, h, (0..w * h).map(|k| [k as f32 + 1.0, 0.0, 0.0]).collect()).unwrap();
        let s = sg_samples(&map).unwrap();
        let radical = |mut i: u64, b: u64| {
            let (mut f, mut r) = (1.0, 0.0);
            while i > 0 {
                f /= b as f64;
                r += f * (i % b) as f64;
                i /= b;
            }
            r
        };
        let mut differ = 0;
        for k in 0..2000 {
            let (u, v) = (radical(k as u64 + 1, 2), radical(k as u64 + 1, 3));
            let z = 1.0 - 2.0 * u;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let p = 2.0 * std::f64::consts::PI * v;
            let (x, y) = (r * p.cos(), r * p.sin());
            let tu = 0.5 * (1.0 + x.atan2(-y) / std::f64::consts::PI);
            let tv = z.acos() / std::f64::consts::PI;
            let (x, y) = (((tu * w as f64).floor() as usize).min(w - 1), ((tv * h as f64).floor() as usize).min(h - 1));
            // Texel index + 1 above the horizon; black below it (`clip_below_horizon`).
            let want = if 2 * y + 1 > h { 0.0 } else { (y * w + x + 1) as f64 };
            differ += usize::from(s[k].value[0] != want);
        }
        assert!(differ <= 4, "{differ} of 2000 samples read another texel than the peer's");
    }

    /// Rows whose centre lies below the horizon are black, the rest untouched, for an even
    /// and an odd height (the odd one's middle row sits on the horizon and stays). Mutations
    /// tried: `>=` for `>` (the odd middle row goes), `j >= h / 2` (odd: the same).
    #[test]
    fn clipping_blackens_exactly_the_rows_below_the_horizon() {
        for (h, kept) in [(4, 2), (5, 3), (128, 64)] {
            let map = LatLongImage::new(3, h, (0..3 * h).map(|k| [k as f32 + 1.0, 2.0, 3.0]).collect()).unwrap();
            let c = clip_below_horizon(&map);
            for j in 0..h {
                for i in 0..3 {
                    let want = if j < kept { map.texel(i, j) } else { [0.0; 3] };
                    assert_eq!(c.texel(i, j), want, "h {h}: texel ({i}, {j})");
                }
            }
        }
    }

    /// \[RoughtonFork\]'s table estimator (its 2017 VNDF routine, its Hammersley points) converges to
    /// the same G2·G1-weighted integral as sbf's independent one (Heitz 2018's routine,
    /// centred Hammersley points): at 2¹⁴ against 2¹⁶ samples, over n·v 0.1–0.95 and α
    /// 0.1–0.8, both Fresnel channels (the fit's value, common to both, multiplied back).
    /// Tolerance 1 % of the f0 channel: both are quasi-Monte Carlo estimates of an integrand
    /// cut at the horizon (error ~N^-¾ there: 2¹⁴ gives ≈ 7e-4 of the integral, times a
    /// constant of a few). Mutations tried: the 2017 routine without its V.z scale of P2; the
    /// Hammersley coordinates unswapped is not caught (same integral) — its effect shows only
    /// at \[RoughtonFork\]'s 512 samples, in the compatible mode's figures.
    #[test]
    fn the_forks_table_estimates_the_same_integral_as_sbfs() {
        for nv in [0.1, 0.4, 0.7, 0.95] {
            for alpha in [0.1, 0.4, 0.8] {
                let v = DVec3::new(0.0, (1.0f64 - nv * nv).sqrt(), nv);
                let r = DVec3::new(-v.x, -v.y, v.z);
                let lobe = sbf::ggx::dominant_direction(DVec3::Z, r, alpha);
                let value = ad_fit_value(r.dot(lobe), lobe.z, alpha);
                let ours = ad_table(nv, alpha, 1 << 14).map(|x| x * value);
                let theirs =
                    sbf::recon::ambient_dice::lobe_specular_reference_with(lobe, nv, alpha, 1 << 16, sbf::ggx::Convention::AppendixC);
                for c in 0..2 {
                    assert!(
                        (ours[c] - theirs[c]).abs() <= 0.01 * theirs[0],
                        "n·v {nv} α {alpha} channel {c}: {} vs {}",
                        ours[c],
                        theirs[c]
                    );
                }
            }
        }
    }

    /// The map the SG samples read is black below the horizon even where the resize's
    /// Catmull–Rom lobes would carry the upper rows across it: a 256×128 map lit everywhere,
    /// clipped (as `compare` passes it), then resized — every sample in a 512×256 row ≥ 128
    /// (by the peer's lookup, in f64) reads exactly 0, but for at most 4 within f32 rounding
    /// of the horizon row's edge. Mutation tried: no clip after the resize — fails (the rows
    /// just below the horizon ring).
    #[test]
    fn samples_below_the_horizon_read_black_after_the_resize() {
        let map = clip_below_horizon(&LatLongImage::new(256, 128, vec![[1.0, 2.0, 3.0]; 256 * 128]).unwrap());
        let s = sg_samples(&map).unwrap();
        let lit_below = s
            .iter()
            .filter(|x| {
                let p = crate::frame::world_to_tangent(x.direction);
                let row = (p.z.clamp(-1.0, 1.0).acos() / std::f64::consts::PI * 256.0).floor();
                row >= 128.0 && x.value != [0.0; 3]
            })
            .count();
        assert!(lit_below <= 4, "{lit_below} samples below the horizon read light");
    }

    #[test]
    fn upsampling_keeps_constants_and_linear_ramps() {
        // Catmull–Rom reproduces linear functions away from the clamped edges and any
        // constant everywhere (normalised weights).
        let w = upsample_weights(8, 16);
        for (o, ws) in w.iter().enumerate() {
            let total: f64 = ws.iter().map(|(_, x)| x).sum();
            assert!((total - 1.0).abs() < 1e-12);
            if (3..13).contains(&o) {
                let v: f64 = ws.iter().map(|(i, x)| *i as f64 * x).sum();
                assert!((v - ((o as f64 + 0.5) / 2.0 - 0.5)).abs() < 1e-12, "{o}: {v}");
            }
        }
    }
}
