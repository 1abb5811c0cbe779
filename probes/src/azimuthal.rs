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

/// The row spectra of a map, `rows[row][channel]`, length W (from [`Quadrature::spectra`]).
#[derive(Debug, Clone)]
pub struct Spectra {
    rows: Vec<[Vec<Complex64>; 3]>,
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
                    row
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
        self.integrate_many(&[&self.spectra], rows, sub, kernel).pop().expect("one map")
    }

    /// [`Quadrature::integrate`] for several maps of this geometry at once: the kernel is
    /// evaluated, folded and transformed once per (output row, source row) and applied to
    /// every map's spectra (the cost of one more map is 3·H·W products and 3 inverse FFTs
    /// per output row).
    pub fn integrate_many(
        &self,
        maps: &[&Spectra],
        rows: std::ops::Range<usize>,
        sub: usize,
        kernel: &(dyn Fn(usize, f64, f64) -> f64 + Sync),
    ) -> Vec<Vec<[f64; 3]>> {
        let (w, h, s) = (self.map.width, self.map.height, sub.max(1));
        let k = w / self.out.width;
        let per_row: Vec<Vec<Vec<[f64; 3]>>> = rows
            .clone()
            .into_par_iter()
            .map(|jv| {
                // The kernel folded per source row: g[r][Δ], Δ = k·i_out − m (mod W).
                let mut g = vec![vec![0.0f64; w]; h];
                let mut fine = vec![0.0f64; w * s];
                // Azimuth of fine index x: Δφ = 2π(x/S + c0)/W with c0 = k/2 − 1/(2S) (the
                // offset between an output column centre and sub-column 0's centre).
                let c0 = 0.5 * k as f64 - 0.5 / s as f64;
                for j in 0..h {
                    for b in 0..s {
                        // Sub-row b of row j: polar angles, exact ring solid angle per sub-cell.
                        let t0 = PI * (j as f64 + b as f64 / s as f64) / h as f64;
                        let t1 = PI * (j as f64 + (b + 1) as f64 / s as f64) / h as f64;
                        let tc = 0.5 * (t0 + t1);
                        let omega = (2.0 * PI / (w * s) as f64) * 2.0 * tc.sin() * (0.5 * (t1 - t0)).sin();
                        let mut any = false;
                        for (x, f) in fine.iter_mut().enumerate() {
                            *f = kernel(jv, tc, 2.0 * PI * (x as f64 / s as f64 + c0) / w as f64);
                            any |= *f != 0.0;
                        }
                        if !any {
                            continue;
                        }
                        // Bilinear rows of the sub-row centre (v·H − ½, clamped).
                        let y = (j as f64 + (b as f64 + 0.5) / s as f64 - 0.5).clamp(0.0, (h - 1) as f64);
                        let (r0, fy) = (y.floor() as usize, y - y.floor());
                        let r1 = (r0 + 1).min(h - 1);
                        // Fold: G(Δ) = Σ_a Σ_d hat_a(d)·fine[(Δ + d)·S − a].
                        for a in 0..s {
                            let e = (a as f64 + 0.5) / s as f64 - 0.5;
                            for d in -1i64..=1 {
                                let hat = (1.0 - (d as f64 - e).abs()).max(0.0);
                                if hat == 0.0 {
                                    continue;
                                }
                                for delta in 0..w {
                                    let x = ((delta as i64 + d) * s as i64 - a as i64).rem_euclid((w * s) as i64) as usize;
                                    let v = omega * hat * fine[x];
                                    g[r0][delta] += (1.0 - fy) * v;
                                    if fy > 0.0 {
                                        g[r1][delta] += fy * v;
                                    }
                                }
                            }
                        }
                    }
                }
                // Σ_r spectrum(T_r)·spectrum(G_r), one inverse FFT per map and channel.
                let mut acc: Vec<[Vec<Complex64>; 3]> = maps.iter().map(|_| [0, 1, 2].map(|_| vec![Complex64::new(0.0, 0.0); w])).collect();
                let mut buf = vec![Complex64::new(0.0, 0.0); w];
                for (r, gr) in g.iter().enumerate() {
                    if gr.iter().all(|x| *x == 0.0) {
                        continue;
                    }
                    for (b, x) in buf.iter_mut().zip(gr) {
                        *b = Complex64::new(*x, 0.0);
                    }
                    self.fft.process(&mut buf);
                    for (m, a) in maps.iter().zip(acc.iter_mut()) {
                        for c in 0..3 {
                            for (x, (t, gg)) in a[c].iter_mut().zip(m.rows[r][c].iter().zip(&buf)) {
                                *x += t * gg;
                            }
                        }
                    }
                }
                acc.into_iter()
                    .map(|mut a| {
                        for ch in a.iter_mut() {
                            self.ifft.process(ch);
                        }
                        (0..self.out.width).map(|i| [0, 1, 2].map(|c| a[c][k * i].re / w as f64)).collect::<Vec<[f64; 3]>>()
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        // per_row[row][map] → per map, rows concatenated.
        (0..maps.len()).map(|m| per_row.iter().flat_map(|r| r[m].iter().copied()).collect()).collect()
    }
}

/// The direction at polar angle θ (from +Y) and azimuth φ in the lat-long convention
/// (`LatLong::uv_to_direction`).
pub fn direction(theta: f64, phi: f64) -> sbf::glam::DVec3 {
    let (st, ct) = theta.sin_cos();
    sbf::glam::DVec3::new(st * phi.sin(), ct, -st * phi.cos())
}
