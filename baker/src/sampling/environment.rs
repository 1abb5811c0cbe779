//! The environment's importance sampler: luminance × solid angle over a lat-long grid.

use crate::scene::lights::luminance;
use crate::scene::Environment;
use sbf::glam::Vec3;

/// Importance sampling of the environment by luminance × solid angle on a lat-long grid
/// (rows from the zenith, columns as `scene::latlong_texel`): a marginal CDF over rows,
/// a conditional CDF per row, and a direction uniform in (φ, cos θ) within the chosen
/// cell, so the solid-angle pdf is P(cell)/Ω(cell) exactly. A map uses its own texels
/// (its nearest-texel radiance is then constant per cell: zero-variance cells); analytic
/// environments are tabulated at 64 × 32. Cells of zero luminance are never chosen; the
/// point/BSDF sample covers them (MIS stays unbiased since that strategy's pdf is > 0
/// wherever the environment is seen).
#[derive(Debug, Clone, PartialEq)]
pub struct EnvSampler {
    pub width: usize,
    pub height: usize,
    /// Marginal CDF over rows (height entries, last = 1).
    pub row_cdf: Vec<f32>,
    /// Conditional CDF within each row (width × height, row-major, each row ends at 1;
    /// an all-zero row is uniform).
    pub col_cdf: Vec<f32>,
    /// Probability of each cell (row-major).
    pub cell_p: Vec<f32>,
    /// ∫ luminance(L) dω over the sphere as tabulated (Σ cells luminance × solid angle):
    /// the luminance-weighted power of the environment per unit of cross-section.
    pub total: f64,
}

impl EnvSampler {
    /// The sampler for `env`, or None for a black environment.
    pub fn new(env: &Environment) -> Option<EnvSampler> {
        type Luminance<'e> = Box<dyn Fn(usize, usize) -> f64 + 'e>;
        let (w, h, lum): (usize, usize, Luminance) = match env {
            Environment::Black => return None,
            Environment::Map(m) => {
                let w = m.geometry.width;
                (w, w / 2, Box::new(move |i, j| luminance(Vec3::from(m.texel(i, j))).max(0.0)))
            }
            e => {
                let (w, h) = (64, 32);
                let e = e.clone();
                (
                    w,
                    h,
                    Box::new(move |i, j| {
                        let th = std::f64::consts::PI * (j as f64 + 0.5) / h as f64;
                        let u = (i as f64 + 0.5) / w as f64;
                        luminance(e.radiance(dir_of(u, th.cos()))).max(0.0)
                    }),
                )
            }
        };
        let mut cell = vec![0.0f64; w * h];
        for j in 0..h {
            let omega = cell_solid_angle(j, w, h);
            for i in 0..w {
                cell[j * w + i] = lum(i, j) * omega;
            }
        }
        let total: f64 = cell.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let (mut row_cdf, mut col_cdf, mut cell_p) = (Vec::with_capacity(h), Vec::with_capacity(w * h), Vec::with_capacity(w * h));
        let mut acc_rows = 0.0;
        for j in 0..h {
            let row = &cell[j * w..(j + 1) * w];
            let rs: f64 = row.iter().sum();
            acc_rows += rs;
            row_cdf.push((acc_rows / total) as f32);
            let mut acc = 0.0;
            for (i, c) in row.iter().enumerate() {
                acc += if rs > 0.0 { c / rs } else { 1.0 / w as f64 };
                col_cdf.push(if i + 1 == w { 1.0 } else { acc as f32 });
                cell_p.push((c / total) as f32);
            }
        }
        if let Some(l) = row_cdf.last_mut() {
            *l = 1.0;
        }
        Some(EnvSampler { width: w, height: h, row_cdf, col_cdf, cell_p, total })
    }

    /// A direction for uniform `u` in [0,1)³ and its solid-angle pdf.
    pub fn sample(&self, u: [f64; 3]) -> (Vec3, f64) {
        let j = self.row_cdf.partition_point(|c| (*c as f64) <= u[0]).min(self.height - 1);
        let row = &self.col_cdf[j * self.width..(j + 1) * self.width];
        let i = row.partition_point(|c| (*c as f64) <= u[1]).min(self.width - 1);
        let (w, h) = (self.width as f64, self.height as f64);
        let (c0, c1) = ((std::f64::consts::PI * j as f64 / h).cos(), (std::f64::consts::PI * (j + 1) as f64 / h).cos());
        let cos_t = c0 + (c1 - c0) * u[2];
        // A second uniform for φ within the cell: the fractional position of u[1] in the
        // cell's CDF interval (stratified, no extra random number).
        let lo = if i == 0 { 0.0 } else { row[i - 1] as f64 };
        let hi = row[i] as f64;
        let f = if hi > lo { ((u[1] - lo) / (hi - lo)).clamp(0.0, 1.0) } else { 0.5 };
        let d = dir_of((i as f64 + f) / w, cos_t);
        (d, self.pdf_cell(i, j))
    }

    /// Solid-angle pdf of sampling direction `d`.
    pub fn pdf(&self, d: Vec3) -> f64 {
        let (i, j) = crate::scene::latlong_texel(d, self.width);
        self.pdf_cell(i, j.min(self.height - 1))
    }

    fn pdf_cell(&self, i: usize, j: usize) -> f64 {
        self.cell_p[j * self.width + i] as f64 / cell_solid_angle(j, self.width, self.height)
    }
}

/// Solid angle of a cell in row `j` of a w × h lat-long grid: (2π/w)(cos θ_j − cos θ_j+1).
pub fn cell_solid_angle(j: usize, w: usize, h: usize) -> f64 {
    let t = |k: usize| (std::f64::consts::PI * k as f64 / h as f64).cos();
    2.0 * std::f64::consts::PI / w as f64 * (t(j) - t(j + 1))
}

/// The direction at lat-long coordinate u (column fraction) and cos θ from +Y, inverse of
/// `scene::latlong_texel`'s mapping u = ½(1 + atan2(x, −z)/π).
fn dir_of(u: f64, cos_t: f64) -> Vec3 {
    let phi = (2.0 * u - 1.0) * std::f64::consts::PI;
    let s = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    Vec3::new((s * phi.sin()) as f32, cos_t as f32, (-s * phi.cos()) as f32)
}
