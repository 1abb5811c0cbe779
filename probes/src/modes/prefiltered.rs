//! GGX-prefiltered cube maps, what engines ship for glossy specular, paired with SH L2 for
//! diffuse as they ship it: `pf8`, `pf16`, `pf32`, `pf64` (faces of N² texels at mip 0, a
//! mip chain to 1², prefiltered with Karis's kernel, stored as the run's `--storage`: f32,
//! f16 or BC6H blocks of each face), `pf8-ni` … `pf64-ni` (prefiltered with the GGX BRDF ×
//! cosine at normal incidence: [`PrefilterKernel`]) and `pf8-ni-rgb9e5` … (those stored in
//! the shared-exponent format). The map and its runtime
//! are [`sbf::recon::prefiltered`]'s: mip m holds α_m = min(1, κ·2^m/N), a lookup reads level
//! log₂(α·N/κ) trilinearly at the reflected direction, times the DFG terms (split sum).
//!
//! A pair answers both signals: its irradiance is SH L2's (the same coefficients, storage and
//! evaluator as `shl2`), its specular the map's; its storage is both, its encode both.
//!
//! Prefiltering: every mip is the map prefiltered at α_m by the azimuthal quadrature
//! ([`crate::prefilter::prefiltered_latlong`], exact for the bilinear radiance up to its
//! midpoint rule) on a lat-long grid of at least 8 texels per face texel, box-filtered onto
//! the face texels (k × k sub-samples, k from the ratio of the texel's angle to the grid's). Faces below 4 × 4 take a whole BC6H block (16 bytes).

use super::common::*;
use super::context::*;
use sbf::envmap::{CubeMap, LatLong, LatLongImage};
use sbf::glam::DVec3;
use sbf::recon::prefiltered::{mip_count, PrefilterKernel, PrefilteredCube};

/// Face sizes of the modes.
pub const SIZES: [usize; 4] = [8, 16, 32, 64];

/// Coefficients of the SH L2 part, stored first.
pub const SH_COEFFICIENTS: usize = 9;

/// A prefiltered mode: its face size, kernel and whether it is stored as RGB9E5.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Variant {
    pub size: usize,
    pub kernel: PrefilterKernel,
    pub rgb9e5: bool,
}

/// The variant of a prefiltered mode id — `pfN` (Karis's kernel), `pfN-ni` (the
/// normal-incidence kernel), `pfN-ni-rgb9e5` (that, stored as RGB9E5) — or None.
pub fn parse(id: &str) -> Option<Variant> {
    let rest = id.strip_prefix("pf")?;
    let (n, suffix) = rest.split_once('-').unwrap_or((rest, ""));
    let size: usize = n.parse().ok()?;
    let (kernel, rgb9e5) = match suffix {
        "" => (PrefilterKernel::Karis, false),
        "ni" => (PrefilterKernel::NormalIncidence, false),
        "ni-rgb9e5" => (PrefilterKernel::NormalIncidence, true),
        _ => return None,
    };
    (SIZES.contains(&size) && n == size.to_string()).then_some(Variant { size, kernel, rgb9e5 })
}

/// The cube map of `size` prefiltered from the context's map, before storage.
pub fn prefilter(ctx: &Context, size: usize, kernel: PrefilterKernel) -> Result<PrefilteredCube, String> {
    let map = &ctx.map;
    let count = mip_count(size);
    let mut mips = Vec::with_capacity(count);
    for m in 0..count {
        let n = size >> m;
        let alpha = sbf::recon::prefiltered::mip_alpha(m, size);
        let texels = {
            let grid = grid_for(map.geometry, n);
            let img = crate::prefilter::prefiltered_latlong(map, grid, alpha, kernel)?;
            let img = LatLongImage::new(grid.width, grid.height, img.iter().map(|v| v.map(|x| x as f32)).collect()).map_err(err)?;
            box_filtered(n, grid.height, |d| img.bilinear(d))
        };
        mips.push(texels);
    }
    Ok(PrefilteredCube { size, mips })
}

/// The lat-long grid for a mip of `n` texels per face side: the narrowest width dividing the
/// map's with at least 8 texels per face texel around the equator (4n face texels), height
/// half the width (the map's own grid where nothing narrower divides it).
fn grid_for(map: LatLong, n: usize) -> LatLong {
    let want = (32 * n).max(32);
    (want..map.width).find(|w| map.width % w == 0 && w % 2 == 0).map_or(map, |w| LatLong { width: w, height: w / 2 })
}

/// Each face texel of a face of `n` as the mean of `f` over k × k sub-sample directions
/// weighted by their solid angles, k from the texel's angle (π/2n) over the source's texel
/// angle (π/`rows`) (between 2 and 16).
fn box_filtered(n: usize, rows: usize, f: impl Fn(DVec3) -> [f64; 3] + Sync) -> Vec<[f32; 3]> {
    use rayon::prelude::*;
    let k = ((rows as f64 / (2.0 * n as f64)).ceil() as usize * 2).clamp(2, 16);
    let fine = CubeMap { size: n * k };
    (0..6 * n * n)
        .into_par_iter()
        .map(|t| {
            let (face, j, i) = (t / (n * n), (t / n) % n, t % n);
            let (mut acc, mut w) = ([0.0; 3], 0.0);
            for b in 0..k {
                for a in 0..k {
                    let (fi, fj) = (i * k + a, j * k + b);
                    let o = fine.texel_solid_angle(fi, fj);
                    let v = f(fine.texel_direction(face, fi, fj));
                    for c in 0..3 {
                        acc[c] += o * v[c];
                    }
                    w += o;
                }
            }
            acc.map(|x| (x / w) as f32)
        })
        .collect()
}

/// The cube as stored (`rgb9e5`, else the run's storage) and read back, with its bytes.
fn stored(ctx: &Context, cube: &PrefilteredCube, rgb9e5: bool) -> (PrefilteredCube, f64) {
    use crate::storage::Storage;
    let mut out = cube.clone();
    let mut bytes = 0.0;
    for (m, mip) in out.mips.iter_mut().enumerate() {
        let n = cube.size >> m;
        if rgb9e5 {
            mip.iter_mut().for_each(|v| *v = sbf::recon::prefiltered::rgb9e5_decode(sbf::recon::prefiltered::rgb9e5(*v)));
            bytes += 4.0 * mip.len() as f64;
            continue;
        }
        match ctx.storage {
            Storage::F32 => bytes += 12.0 * mip.len() as f64,
            Storage::F16 => {
                mip.iter_mut().for_each(|v| *v = v.map(|x| half::f16::from_f32(x).to_f32()));
                bytes += 6.0 * mip.len() as f64;
            }
            Storage::Bc6h => {
                for face in mip.chunks_mut(n * n) {
                    let b = sbf::bc::encode_bc6h_unsigned(n, n, face);
                    bytes += b.blocks.len() as f64;
                    face.copy_from_slice(&b.decode(n, n));
                }
            }
        }
    }
    (out, bytes)
}

/// Runs mode `id` ([`super::prepare`]): SH L2 as `shl2` does, then the map.
pub(super) fn prepare<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let Variant { size, kernel, rgb9e5 } = parse(id).ok_or_else(|| format!("mode '{id}' is not one of this family's"))?;
    let mut p = super::sh::prepare("shl2", ctx, repeats)?;
    let cube = prefilter(ctx, size, kernel)?;
    let (cube, map_bytes) = stored(ctx, &cube, rgb9e5);
    // The encode of the pair: the SH projection and the prefiltering, as an engine bakes both.
    let sh = sbf::ShBasis::new(2).map_err(err)?;
    p.encode = Some(EncodeJob::new(repeats, move || {
        std::hint::black_box(sbf::solve::moments(&sh, &ctx.samples));
        std::hint::black_box(prefilter(ctx, size, kernel).expect("prefiltered once already"));
    }));
    let r = &mut p.result;
    r.id = id;
    r.basis = format!("SH L2 + {size}² GGX-prefiltered cube map ({} mips)", cube.mips.len());
    r.solver = "SH projection; GGX prefilter (azimuthal quadrature), mip m at α = min(1, 2·2^m/N)";
    r.radiance = None;
    r.coefficients.extend(cube.texels().map(|v| v.map(f64::from)));
    r.stored_scalars = r.coefficients.len() * 3;
    r.engine_bytes = Some(ctx.storage.bytes(3 * SH_COEFFICIENTS) + map_bytes);
    r.precision = Some(if rgb9e5 { format!("rgb9e5 (SH L2: {})", ctx.storage.name()) } else { ctx.storage.name().into() });
    Ok(p)
}

/// The stored cube of a prefiltered mode's result (its coefficients after SH L2's).
pub fn cube_of(id: &str, coefficients: &[[f64; 3]]) -> Option<PrefilteredCube> {
    let size = parse(id)?.size;
    let texels: Vec<[f32; 3]> = coefficients.get(SH_COEFFICIENTS..)?.iter().map(|v| v.map(|x| x as f32)).collect();
    PrefilteredCube::from_texels(size, &texels).ok()
}
