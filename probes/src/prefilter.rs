//! The azimuthal quadrature's cells for a kernel of width α on a lat-long map ([`subdivision`],
//! [`coarsening`]; shared by the specular reference) and the map prefiltered with a GGX
//! kernel at α on a lat-long grid ([`prefiltered_latlong`]), which the prefiltered cube maps
//! of [`crate::modes::prefiltered`] are box-filtered from.

use sbf::envmap::{LatLong, LatLongImage};

/// Sub-cells per texel side for the deterministic reference at roughness α on a map of
/// `height` rows: the sub-cell's angular size at most α/16 (the lobe's half-vector width
/// is ~α, its reflected width ~2α), between 1 and 16, and even above 1. Even, so that the
/// bilinear radiance's kinks (at texel centres) fall on sub-cell edges and the midpoint rule
/// keeps its h² error on every sub-cell (with odd S > 1 a kink sits off-centre inside a
/// sub-cell and costs O(h)). S = 1 — texels already below α/16 — puts each kink exactly at
/// its cell's centre, where the midpoint rule's error is b·h²/4 per unit length for a slope
/// jump b, and b is the texels' second difference (O(h) for smooth radiance): still O(h²)
/// overall, O(h) only at sharp features — which the reported error (the comparison with 2S
/// on every 8th row) measures.
pub fn subdivision(alpha: f64, height: usize) -> usize {
    let s = ((16.0 * std::f64::consts::PI / height as f64 / alpha.max(1e-3)).ceil() as usize).clamp(1, 16);
    if s == 1 {
        1
    } else {
        s + s % 2
    }
}

/// Coarsening of the map for the deterministic reference at roughness α: the largest power
/// of two D such that the D×D-block texels (solid-angle-weighted means,
/// [`crate::reference::downsample`]) are still below α/16 — the same angular bound as
/// [`subdivision`]'s, whose S = 1 case is D = 1 — while the output grid's width still
/// divides the coarse map's (D ≤ W/W_out) and the map halves evenly. Maps no wider than
/// the output grid (every map up to 512 wide) always get D = 1.
pub fn coarsening(alpha: f64, map: LatLong, out: LatLong) -> usize {
    let mut d = 1;
    loop {
        let next = 2 * d;
        let (w, h) = (map.width / d, map.height / d);
        let fits = w % 2 == 0 && h % 2 == 0 && (w / 2) % out.width == 0 && h / 2 >= out.height;
        if !fits || std::f64::consts::PI * next as f64 / map.height as f64 > alpha.max(1e-3) / 16.0 {
            return d;
        }
        d = next;
    }
}

/// The map box-filtered by `d` (a power of two) in both directions.
pub fn coarsened(map: &LatLongImage, d: usize) -> LatLongImage {
    let mut m = map.clone();
    let mut k = 1;
    while k < d {
        m = crate::reference::downsample(&m);
        k *= 2;
    }
    m
}

/// A prefilter kernel of [`sbf::recon::prefiltered`] (Karis 2013's D(h)·(r·l), or the GGX
/// BRDF × cosine at normal incidence) along a fine azimuth row of the quadrature: r at output row j's polar angle, l at
/// (θ_l, Δφ); cos γ = r·l and 1 − cos γ = |r − l|²/2 (no cancellation near r), as the sphere
/// branch of `crate::specular::GgxRows`. Zonal about r, so mirror-symmetric.
#[derive(Debug, Clone, Copy)]
pub struct PrefilterRows {
    pub kernel: sbf::recon::prefiltered::PrefilterKernel,
    pub alpha: f64,
    /// Output grid rows (θ_r of row j is π(j + ½)/h_out).
    pub h_out: usize,
}

impl crate::azimuthal::RowKernel for PrefilterRows {
    fn row(&self, j: usize, theta_l: f64, az: &crate::azimuthal::Azimuths, out: &mut [f64]) -> bool {
        let (sv, cv) = (std::f64::consts::PI * (j as f64 + 0.5) / self.h_out as f64).sin_cos();
        let (sl, cl) = theta_l.sin_cos();
        let mut any = false;
        for (o, (c, s)) in out.iter_mut().zip(az.cos.iter().zip(az.sin)) {
            let cos_gamma = cv * cl + sv * sl * c;
            let (x, y, z) = (sv * s, cv - cl, sl - sv * c);
            *o = self.kernel.weight(cos_gamma, 0.5 * (x * x + y * y + z * z), self.alpha);
            any |= *o != 0.0;
        }
        any
    }

    fn mirror_symmetric(&self) -> bool {
        true
    }
}

/// The map prefiltered at roughness α ([`sbf::recon::prefiltered`]) at the texel centres of
/// `grid` (its width dividing the map's): the azimuthal quadrature of [`crate::specular::reference_fft`] (the
/// same coarsening and subdivision for α) with [`PrefilterRows`], divided by the same
/// quadrature of the kernel alone, as a prefilter divides by its total weight (Karis 2013).
pub fn prefiltered_latlong(
    map: &LatLongImage,
    grid: LatLong,
    alpha: f64,
    kernel: sbf::recon::prefiltered::PrefilterKernel,
) -> Result<Vec<[f64; 3]>, String> {
    let alpha = alpha.clamp(1e-4, 1.0);
    let d = coarsening(alpha, map.geometry, grid);
    let source = coarsened(map, d);
    let q = crate::azimuthal::Quadrature::new(&source, grid)?;
    let sub = if d > 1 { 1 } else { subdivision(alpha, map.geometry.height) };
    let kernel = PrefilterRows { kernel, alpha, h_out: grid.height };
    // Σ L·K / Σ K: the kernel's own quadrature sum per output texel (from a map of ones; its
    // deviation from the closed-form integral is the rule's error, which the division cancels
    // for slowly varying radiance) — a constant map stays constant to rounding.
    // Both in one pass: the kernel folded once for the map and for the ones.
    let values: Vec<[f64; 3]> = (0..source.geometry.height)
        .flat_map(|j| (0..source.geometry.width).map(move |i| (i, j)))
        .map(|(i, j)| source.texel(i, j).map(f64::from))
        .collect();
    let map = q.spectra_f64(&values)?;
    let ones = q.spectra_f64(&vec![[1.0; 3]; values.len()])?;
    let rows: Vec<usize> = (0..grid.height).collect();
    let mut parts = q.integrate_many(&[&map, &ones], &rows, sub, &kernel).into_iter();
    let (image, sums) = (parts.next().expect("two maps"), parts.next().expect("two maps"));
    Ok(image.into_iter().zip(sums).map(|(v, w)| v.map(|x| x / w[0])).collect())
}
