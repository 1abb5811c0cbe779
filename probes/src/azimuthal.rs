//! Deterministic quadrature of kernels that depend only on two polar angles and an
//! azimuth difference, over a lat-long map, by FFT (the symmetry used for the specular
//! reference).
//!
//! A lat-long map's pole is +Y. For an output direction d at polar angle θ_d and azimuth
//! φ_d, ∫ L(ω) K(θ_d, θ_ω, φ_d − φ_ω) dω — the GGX lobe with the normal at the pole
//! ([Roughton19 Appendix C]), or any lobe that is zonal about d itself — is, on the map's
//! rows, a circular convolution in φ per (output row, source row) pair. Here:
//!
//! - **Radiance** is the map's bilinear interpolation (`LatLongImage::bilinear_uv`: wrap in
//!   φ, rows clamped at the poles), the same function the Monte Carlo references sample.
//! - **Quadrature**: every texel split into S × S sub-cells, midpoint rule with the
//!   sub-cell's exact solid angle (2π/(W S))·(cos θ₀ − cos θ₁). The bilinear weights of a
//!   sub-cell's centre are fixed offsets of the texel grid, so the whole sum is a
//!   convolution: per output row and source row, the kernel sampled on the S-times-finer
//!   azimuth grid, filtered by the hat weights and folded onto the W columns, times the
//!   row's spectrum.
//! - **Cost**: K is evaluated (output rows) × (H·S) × (W·S) times; one FFT of length W per
//!   (output row, source row) pair and per channel one inverse FFT per output row.
//!   Output rows are independent (rayon); the result is identical for any thread count.
//!   Kernels symmetric about the equator ([`RowKernel::mirror_symmetric`]) fold one row
//!   per mirror pair; products stop where both spectra have decayed ([`TAIL`]).
//!
//! The output grid must share the map's poles and have W_out dividing W (output column
//! centres then fall on the finer grid); [`Quadrature::new`] says why otherwise.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use sbf::envmap::{LatLong, LatLongImage};
use std::f64::consts::PI;
use std::sync::Arc;

/// FFT plans for a map geometry and an output grid, and the row spectra of one map.
pub struct Quadrature {
    map: LatLong,
    out: LatLong,
    /// Row spectra of the map given to [`Quadrature::new`].
    spectra: Spectra,
    fft: Arc<dyn rustfft::Fft<f64>>,
    ifft: Arc<dyn rustfft::Fft<f64>>,
}

/// The row spectra of a map, `rows[row][channel]`, bins 0..=W/2 of the length-W DFT (the
/// rest follows by Hermitian symmetry; from [`Quadrature::spectra`]).
#[derive(Debug, Clone)]
pub struct Spectra {
    /// (real parts, imaginary parts) per row and channel: split, so that the products
    /// below run as plain vector arithmetic.
    rows: Vec<[SplitComplex; 3]>,
    /// Per row and channel, the bins that carry the spectrum ([`significant_bins`]).
    bins: Vec<[usize; 3]>,
}

/// Relative size of the spectral tail left out of the products: bins from n on are
/// dropped when Σ_{b ≥ n} (|re_b| + |im_b|) ≤ TAIL · Σ_b (|re_b| + |im_b|).
///
/// Error bound: an output is (1/W)·Σ_b Σ_r T_rb·G_rb·e^{…} over all W bins; a row pair
/// keeps the bins below min(n_T, n_G), and a dropped bin (with its Hermitian mirror) costs
/// at most (2/W)·|T_rb|·|G_rb|. With |G_rb| ≤ ‖g_r‖₁ and |T_rb| ≤ ‖t_r‖₁ (the rows' sums
/// of absolute values) and S ≤ (W/2 + 1)·‖·‖₁ for a half spectrum's L1 sum, the change is
/// ≤ (4/W)·TAIL·(W/2 + 1)·Σ_r ‖t_r‖₁‖g_r‖₁ ≈ 2·TAIL·W × (the row mean of the quadrature
/// of |L| against |K|): 4e-10 of it at W = 2048 in the worst case, and in practice
/// ~TAIL (a smooth row's spectral L1 sum is a few times its DC bin). Broad spectra (a sun,
/// the clamped cosine with its kink at the horizon) keep every bin; smooth rows (basis
/// reconstructions: SH rows are trigonometric polynomials of degree ≤ L, SG rows decay
/// like Bessel functions) and the GGX lobes near the poles and at large α keep fewer.
pub const TAIL: f64 = 1e-13;

/// The number of leading bins of a split spectrum to keep (see [`TAIL`]).
pub fn significant_bins(re: &[f64], im: &[f64]) -> usize {
    let mag = |b: usize| re[b].abs() + im[b].abs();
    let total: f64 = (0..re.len()).map(mag).sum();
    let mut tail = 0.0;
    let mut n = re.len();
    while n > 0 {
        let t = tail + mag(n - 1);
        if t > TAIL * total {
            break;
        }
        tail = t;
        n -= 1;
    }
    n
}

/// A complex vector as split (real parts, imaginary parts).
type SplitComplex = (Vec<f64>, Vec<f64>);

/// a += t·g over complex vectors given as split (re, im) slices of equal length.
#[inline]
fn complex_mac(ar: &mut [f64], ai: &mut [f64], tr: &[f64], ti: &[f64], gr: &[f64], gi: &[f64]) {
    let n = ar.len();
    let (ai, tr, ti, gr, gi) = (&mut ai[..n], &tr[..n], &ti[..n], &gr[..n], &gi[..n]);
    for x in 0..n {
        ar[x] += tr[x] * gr[x] - ti[x] * gi[x];
        ai[x] += tr[x] * gi[x] + ti[x] * gr[x];
    }
}

impl std::fmt::Debug for Quadrature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Quadrature").field("map", &self.map).field("out", &self.out).finish_non_exhaustive()
    }
}

impl Quadrature {
    /// Prepares `map` for output grid `out` (W_out must divide W).
    pub fn new(map: &LatLongImage, out: LatLong) -> Result<Quadrature, String> {
        let g = map.geometry;
        if out.width == 0 || out.height == 0 || g.width % out.width != 0 {
            return Err(format!("azimuthal quadrature needs an output width dividing the map's ({}), not {}", g.width, out.width));
        }
        let mut planner = FftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(g.width);
        let ifft = planner.plan_fft_inverse(g.width);
        let mut q = Quadrature { map: g, out, spectra: Spectra { rows: Vec::new(), bins: Vec::new() }, fft, ifft };
        q.spectra = q.spectra(map)?;
        Ok(q)
    }

    /// The row spectra of another map of the same geometry (for [`Quadrature::integrate_many`]).
    pub fn spectra(&self, map: &LatLongImage) -> Result<Spectra, String> {
        if map.geometry != self.map {
            return Err(format!(
                "map is {}×{}, the quadrature {}×{}",
                map.geometry.width, map.geometry.height, self.map.width, self.map.height
            ));
        }
        Ok(self.spectra_of(|i, j, c| map.texel(i, j)[c] as f64))
    }

    /// The row spectra of row-major f64 texels on this quadrature's map geometry (e.g. a
    /// basis reconstruction, kept in f64: rounding to f32 would add a 1e-7 noise floor to
    /// spectra that are otherwise band-limited). Errors on a wrong length.
    pub fn spectra_f64(&self, texels: &[[f64; 3]]) -> Result<Spectra, String> {
        if texels.len() != self.map.texel_count() {
            return Err(format!("{} texels for a {}×{} quadrature", texels.len(), self.map.width, self.map.height));
        }
        Ok(self.spectra_of(|i, j, c| texels[j * self.map.width + i][c]))
    }

    fn spectra_of(&self, texel: impl Fn(usize, usize, usize) -> f64 + Sync) -> Spectra {
        // Rows in parallel (each row's FFTs are independent; collected in row order).
        let rows: Vec<[SplitComplex; 3]> = (0..self.map.height)
            .into_par_iter()
            .map(|j| {
                [0, 1, 2].map(|c| {
                    let mut row: Vec<Complex64> = (0..self.map.width).map(|i| Complex64::new(texel(i, j, c), 0.0)).collect();
                    self.fft.process(&mut row);
                    // Real rows: the spectrum is Hermitian, bins 0..=W/2 carry all of it.
                    row.truncate(self.map.width / 2 + 1);
                    (row.iter().map(|z| z.re).collect(), row.iter().map(|z| z.im).collect())
                })
            })
            .collect();
        let bins = rows.iter().map(|chans| chans.each_ref().map(|(re, im)| significant_bins(re, im))).collect();
        Spectra { rows, bins }
    }

    /// ∫ L_bilinear(ω)·K(j, θ_ω, φ_d − φ_ω) dω at every texel centre of output rows
    /// `rows` (row-major, `rows.len() × W_out` values), with `sub` × `sub` sub-cells per
    /// texel. `kernel(j, θ_ω, Δφ)` is the kernel for output row j (its θ_d is the row's
    /// centre), Δφ = φ_d − φ_ω in radians (any real; it must be 2π-periodic).
    pub fn integrate(&self, rows: std::ops::Range<usize>, sub: usize, kernel: &(dyn Fn(usize, f64, f64) -> f64 + Sync)) -> Vec<[f64; 3]> {
        self.integrate_rows(rows, sub, &Pointwise(kernel))
    }

    /// [`Quadrature::integrate`] with a kernel evaluated a fine azimuth row at a time.
    pub fn integrate_rows(&self, rows: std::ops::Range<usize>, sub: usize, kernel: &dyn RowKernel) -> Vec<[f64; 3]> {
        self.integrate_rows_at(&rows.collect::<Vec<_>>(), sub, kernel)
    }

    /// [`Quadrature::integrate_rows`] on any set of output rows (distinct, in any order;
    /// the result follows their order), all in parallel.
    pub fn integrate_rows_at(&self, rows: &[usize], sub: usize, kernel: &dyn RowKernel) -> Vec<[f64; 3]> {
        self.integrate_many(&[&self.spectra], rows, sub, kernel).pop().expect("one map")
    }

    /// [`Quadrature::integrate_rows`] for several maps of this geometry at once: the kernel
    /// is evaluated, folded and transformed once per (output row, source row) and applied
    /// to every map's spectra (the cost of one more map is 3·H·W products and 3 inverse
    /// FFTs per output row).
    pub fn integrate_many(&self, maps: &[&Spectra], rows: &[usize], sub: usize, kernel: &dyn RowKernel) -> Vec<Vec<[f64; 3]>> {
        let (w, h, s) = (self.map.width, self.map.height, sub.max(1));
        let k = w / self.out.width;
        // Azimuth of fine index x: Δφ = 2π(x/S + c0)/W with c0 = k/2 − 1/(2S) (the offset
        // between an output column centre and sub-column 0's centre); shared by every row.
        let c0 = 0.5 * k as f64 - 0.5 / s as f64;
        let dphi: Vec<f64> = (0..w * s).map(|x| 2.0 * PI * (x as f64 / s as f64 + c0) / w as f64).collect();
        let (sin, cos): (Vec<f64>, Vec<f64>) = dphi.iter().map(|p| p.sin_cos()).unzip();
        let az = Azimuths { dphi: &dphi, cos: &cos, sin: &sin };
        // Hat weights of sub-column a towards the texel columns d = −1, 0, +1 of its
        // bilinear footprint: e = (a + ½)/S − ½ is its offset from the texel centre.
        let hats: Vec<[f64; 3]> = (0..s)
            .map(|a| {
                let e = (a as f64 + 0.5) / s as f64 - 0.5;
                [-1.0f64, 0.0, 1.0].map(|d| (1.0 - (d - e).abs()).max(0.0))
            })
            .collect();
        // Output rows in blocks, so that each pass over the maps' spectra (3·H·(W/2 + 1)
        // complex values per map) serves several rows.
        let rows_v = rows;
        // Mirror pairs: for a kernel symmetric about the equator, output row j' = H_out − 1 − j
        // sees source row r as row j sees H − 1 − r (θ ↦ π − θ on both sides; the sub-rows,
        // solid angles and bilinear rows mirror with them), so one fold serves both rows.
        let h_out = self.out.height;
        let mut wanted = vec![false; h_out];
        for &j in rows_v {
            wanted[j] = true;
        }
        let primaries: Vec<(usize, Option<usize>)> = rows_v
            .iter()
            .filter_map(|&j| {
                let m = h_out - 1 - j;
                match kernel.mirror_symmetric() && wanted[m] && m != j {
                    true if m < j => None,
                    true => Some((j, Some(m))),
                    false => Some((j, None)),
                }
            })
            .collect();
        let nb = w / 2 + 1;
        // Blocks small enough that every thread gets at least two (a few rows — a check's —
        // then still spread over the machine), at most ROW_BLOCK.
        let block_rows = (primaries.len() / (2 * rayon::current_num_threads())).clamp(1, ROW_BLOCK);
        let per_block: Vec<Vec<(usize, PerMap)>> = primaries
            .par_chunks(block_rows)
            .map(|block| {
                // The kernel folded per source row: g[row of block][r][Δ], Δ = k·i_out − m (mod W).
                let g: Vec<Vec<Vec<f64>>> = block.iter().map(|&(jv, _)| self.fold(jv, s, kernel, &az, &hats)).collect();
                // Spectra of the folded kernels (Hermitian half) and their significant bins,
                // None for all-zero rows.
                let mut buf = vec![Complex64::new(0.0, 0.0); w];
                let gs: Vec<Vec<Option<(SplitComplex, usize)>>> = g
                    .iter()
                    .map(|gj| {
                        gj.iter()
                            .map(|gr| {
                                if gr.iter().all(|x| *x == 0.0) {
                                    return None;
                                }
                                for (b, x) in buf.iter_mut().zip(gr) {
                                    *b = Complex64::new(*x, 0.0);
                                }
                                self.fft.process(&mut buf);
                                let (re, im): (Vec<f64>, Vec<f64>) = buf[..nb].iter().map(|z| (z.re, z.im)).unzip();
                                let n = significant_bins(&re, &im);
                                Some(((re, im), n))
                            })
                            .collect()
                    })
                    .collect();
                // Output rows of the block: (row, its fold, source row order reversed?).
                let outs: Vec<(usize, usize, bool)> = block
                    .iter()
                    .enumerate()
                    .flat_map(|(b, &(j, m))| std::iter::once((j, b, false)).chain(m.map(|m| (m, b, true))))
                    .collect();
                // Σ_r spectrum(T_r)·spectrum(G_r) per map, channel and output row.
                let mut acc: Vec<Vec<[SplitComplex; 3]>> =
                    outs.iter().map(|_| maps.iter().map(|_| [0, 1, 2].map(|_| (vec![0.0; nb], vec![0.0; nb]))).collect()).collect();
                for r in 0..h {
                    for (m, map) in maps.iter().enumerate() {
                        for c in 0..3 {
                            let (tr, ti) = &map.rows[r][c];
                            let nt = map.bins[r][c];
                            for (o, &(_, b, mirrored)) in outs.iter().enumerate() {
                                let Some(((gr, gi), ng)) = &gs[b][if mirrored { h - 1 - r } else { r }] else { continue };
                                let n = nt.min(*ng);
                                let (ar, ai) = &mut acc[o][m][c];
                                complex_mac(&mut ar[..n], &mut ai[..n], &tr[..n], &ti[..n], &gr[..n], &gi[..n]);
                            }
                        }
                    }
                }
                // One inverse FFT per row, map and channel (the full spectrum rebuilt by symmetry).
                outs.iter()
                    .zip(acc)
                    .map(|(&(row, _, _), per_map)| {
                        let images = per_map
                            .into_iter()
                            .map(|chans| {
                                let chans = chans.map(|(hr, hi)| {
                                    for (x, v) in buf.iter_mut().enumerate() {
                                        *v = if x < nb { Complex64::new(hr[x], hi[x]) } else { Complex64::new(hr[w - x], -hi[w - x]) };
                                    }
                                    self.ifft.process(&mut buf);
                                    (0..self.out.width).map(|i| buf[k * i].re / w as f64).collect::<Vec<f64>>()
                                });
                                (0..self.out.width).map(|i| [chans[0][i], chans[1][i], chans[2][i]]).collect::<Vec<[f64; 3]>>()
                            })
                            .collect();
                        (row, images)
                    })
                    .collect()
            })
            .collect();
        // Back in the order of `rows`: per_row[row][map] → per map, rows concatenated.
        let mut by_row: Vec<Option<PerMap>> = vec![None; h_out];
        for (row, images) in per_block.into_iter().flatten() {
            by_row[row] = Some(images);
        }
        let per_row: Vec<Vec<Vec<[f64; 3]>>> = rows_v.iter().map(|&j| by_row[j].clone().expect("every row computed")).collect();
        (0..maps.len()).map(|m| per_row.iter().flat_map(|r| r[m].iter().copied()).collect()).collect()
    }
}

/// One output row's values for every map (`[map][column]`).
type PerMap = Vec<Vec<[f64; 3]>>;

/// Output rows per task of [`Quadrature::integrate_many`].
const ROW_BLOCK: usize = 8;

impl Quadrature {
    /// The kernel of output row `jv` sampled on the fine grid of every sub-row, weighted by
    /// the sub-cells' solid angles and the bilinear hat weights, folded onto the W columns
    /// of every source row: g[r][Δ].
    fn fold(&self, jv: usize, s: usize, kernel: &dyn RowKernel, az: &Azimuths, hats: &[[f64; 3]]) -> Vec<Vec<f64>> {
        let (w, h) = (self.map.width, self.map.height);
        let mut g = vec![vec![0.0f64; w]; h];
        let mut fine = vec![0.0f64; w * s];
        let mut u = [vec![0.0f64; w], vec![0.0f64; w], vec![0.0f64; w]];
        for j in 0..h {
            for b in 0..s {
                // Sub-row b of row j: polar angles, exact ring solid angle per sub-cell.
                let t0 = PI * (j as f64 + b as f64 / s as f64) / h as f64;
                let t1 = PI * (j as f64 + (b + 1) as f64 / s as f64) / h as f64;
                let tc = 0.5 * (t0 + t1);
                let omega = (2.0 * PI / (w * s) as f64) * 2.0 * tc.sin() * (0.5 * (t1 - t0)).sin();
                if !kernel.row(jv, tc, az, &mut fine) {
                    continue;
                }
                // Bilinear rows of the sub-row centre (v·H − ½, clamped).
                let y = (j as f64 + (b as f64 + 0.5) / s as f64 - 0.5).clamp(0.0, (h - 1) as f64);
                let (r0, fy) = (y.floor() as usize, y - y.floor());
                let r1 = (r0 + 1).min(h - 1);
                // G(Δ) = Σ_d u_d[Δ + d], u_d[q] = Σ_a hat_a(d)·fine[q·S − a] (hat d = −1, 0, +1).
                for q in 0..w {
                    let mut acc = [0.0f64; 3];
                    for (a, hat) in hats.iter().enumerate() {
                        let x = if q == 0 && a > 0 { w * s - a } else { q * s - a };
                        let f = fine[x];
                        for (t, hd) in acc.iter_mut().zip(hat) {
                            *t += hd * f;
                        }
                    }
                    for (ud, t) in u.iter_mut().zip(acc) {
                        ud[q] = omega * t;
                    }
                }
                for delta in 0..w {
                    let v = u[0][(delta + w - 1) % w] + u[1][delta] + u[2][(delta + 1) % w];
                    g[r0][delta] += (1.0 - fy) * v;
                    if fy > 0.0 {
                        g[r1][delta] += fy * v;
                    }
                }
            }
        }
        g
    }
}

/// The fine azimuth grid of one quadrature: Δφ_x and its cosine and sine (the same for
/// every row pair).
#[derive(Debug, Clone, Copy)]
pub struct Azimuths<'a> {
    pub dphi: &'a [f64],
    pub cos: &'a [f64],
    pub sin: &'a [f64],
}

/// A kernel evaluated along one fine azimuth row, so that what is constant along the row
/// (polar angles, masking terms) is computed once.
pub trait RowKernel: Sync {
    /// Writes K(j, θ_ω, Δφ_x) into `out[x]` for every fine azimuth x of `az` (output row
    /// j, source polar angle θ_ω); returns whether any value is non-zero.
    fn row(&self, j: usize, theta: f64, az: &Azimuths, out: &mut [f64]) -> bool;

    /// Whether K(H_out − 1 − j, π − θ, Δφ) = K(j, θ, Δφ) for every output row j (the
    /// kernel depends on the two polar angles only through cos θ_d·cos θ and
    /// sin θ_d·sin θ, like anything zonal about the output direction); then
    /// [`Quadrature::integrate_many`] folds one row of each mirror pair. Default false.
    fn mirror_symmetric(&self) -> bool {
        false
    }
}

/// A pointwise kernel (j, θ_ω, Δφ) ↦ K as a [`RowKernel`].
#[derive(Debug)]
pub struct Pointwise<F>(pub F);

impl<F: Fn(usize, f64, f64) -> f64 + Sync> RowKernel for Pointwise<F> {
    fn row(&self, j: usize, theta: f64, az: &Azimuths, out: &mut [f64]) -> bool {
        let mut any = false;
        for (o, p) in out.iter_mut().zip(az.dphi) {
            *o = (self.0)(j, theta, *p);
            any |= *o != 0.0;
        }
        any
    }
}

/// The direction at polar angle θ (from +Y) and azimuth φ in the lat-long convention
/// (`LatLong::uv_to_direction`).
pub fn direction(theta: f64, phi: f64) -> sbf::glam::DVec3 {
    let (st, ct) = theta.sin_cos();
    sbf::glam::DVec3::new(st * phi.sin(), ct, -st * phi.cos())
}
