//! Deterministic quadrature of kernels that depend only on two polar angles and an
//! azimuth difference, over a lat-long map, by FFT (the symmetry used for the specular
//! reference; issue 19 item 1).
//!
//! A lat-long map's pole is +Y. For an output direction d at polar angle θ_d and azimuth
//! φ_d, ∫ L(ω) K(θ_d, θ_ω, φ_d − φ_ω) dω — the GGX lobe with the normal at the pole
//! (seed 004 Appendix C), or any lobe that is zonal about d itself — is, on the map's
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
        let mut q = Quadrature { map: g, out, spectra: Spectra { rows: Vec::new() }, fft, ifft };
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
        let rows = (0..self.map.height)
            .map(|j| {
                [0, 1, 2].map(|c| {
                    let mut row: Vec<Complex64> = (0..self.map.width).map(|i| Complex64::new(map.texel(i, j)[c] as f64, 0.0)).collect();
                    self.fft.process(&mut row);
                    // Real rows: the spectrum is Hermitian, bins 0..=W/2 carry all of it.
                    row.truncate(self.map.width / 2 + 1);
                    (row.iter().map(|z| z.re).collect(), row.iter().map(|z| z.im).collect())
                })
            })
            .collect();
        Ok(Spectra { rows })
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
        self.integrate_many(&[&self.spectra], rows, sub, kernel).pop().expect("one map")
    }

    /// [`Quadrature::integrate_rows`] for several maps of this geometry at once: the kernel
    /// is evaluated, folded and transformed once per (output row, source row) and applied
    /// to every map's spectra (the cost of one more map is 3·H·W products and 3 inverse
    /// FFTs per output row).
    pub fn integrate_many(
        &self,
        maps: &[&Spectra],
        rows: std::ops::Range<usize>,
        sub: usize,
        kernel: &dyn RowKernel,
    ) -> Vec<Vec<[f64; 3]>> {
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
        let rows_v: Vec<usize> = rows.collect();
        let per_block: Vec<Vec<Vec<Vec<[f64; 3]>>>> = rows_v
            .par_chunks(ROW_BLOCK)
            .map(|block| {
                // The kernel folded per source row: g[row of block][r][Δ], Δ = k·i_out − m (mod W).
                let g: Vec<Vec<Vec<f64>>> = block.iter().map(|&jv| self.fold(jv, s, kernel, &az, &hats)).collect();
                // Spectra of the folded kernels (Hermitian half), None for all-zero rows.
                let nb = w / 2 + 1;
                let mut buf = vec![Complex64::new(0.0, 0.0); w];
                let gs: Vec<Vec<Option<SplitComplex>>> = g
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
                                Some((buf[..nb].iter().map(|z| z.re).collect(), buf[..nb].iter().map(|z| z.im).collect()))
                            })
                            .collect()
                    })
                    .collect();
                // Σ_r spectrum(T_r)·spectrum(G_r) per map, channel and row of the block.
                let mut acc: Vec<Vec<[SplitComplex; 3]>> =
                    block.iter().map(|_| maps.iter().map(|_| [0, 1, 2].map(|_| (vec![0.0; nb], vec![0.0; nb]))).collect()).collect();
                for r in 0..h {
                    for (m, map) in maps.iter().enumerate() {
                        for c in 0..3 {
                            let (tr, ti) = &map.rows[r][c];
                            for (bj, gj) in gs.iter().enumerate() {
                                let Some((gr, gi)) = &gj[r] else { continue };
                                let (ar, ai) = &mut acc[bj][m][c];
                                complex_mac(ar, ai, tr, ti, gr, gi);
                            }
                        }
                    }
                }
                // One inverse FFT per row, map and channel (the full spectrum rebuilt by symmetry).
                acc.into_iter()
                    .map(|per_map| {
                        per_map
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
                            .collect()
                    })
                    .collect()
            })
            .collect();
        let per_row: Vec<Vec<Vec<[f64; 3]>>> = per_block.into_iter().flatten().collect();
        // per_row[row][map] → per map, rows concatenated.
        (0..maps.len()).map(|m| per_row.iter().flat_map(|r| r[m].iter().copied()).collect()).collect()
    }
}

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
