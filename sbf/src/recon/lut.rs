//! Small 2D look-up tables over [0, 1]² with texel-centre sampling, the Ambient
//! Dice specular LUT of [Roughton19 Listing 8.2] built from [`super::ambient_dice`], and the
//! cubic B-spline texture filter by four bilinear taps that lightmaps are read with
//! ([`bspline_taps`]; WGSL twin `lightmap_bicubic_taps`).
//!
//! Layout: `width × height` texels, `channels` values each, row-major, row j for
//! the second axis. Texel (i, j) holds the function at ((i + ½)/width, (j + ½)/height);
//! lookups interpolate bilinearly and clamp to the outermost texel centres (no
//! extrapolation). The committed binary form is fitgen's job; this type is what
//! `sbf` samples at run time.

use crate::error::{check_len, SbfError};

/// A 2D table over [0, 1]² (see module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Lut2 {
    /// Texels along the first axis.
    pub width: usize,
    /// Texels along the second axis.
    pub height: usize,
    /// Values per texel.
    pub channels: usize,
    /// `width × height × channels` values, row-major, channel fastest.
    pub data: Vec<f32>,
}

impl Lut2 {
    /// Wraps data; errors on empty dimensions or a wrong length.
    pub fn new(width: usize, height: usize, channels: usize, data: Vec<f32>) -> Result<Self, SbfError> {
        if width == 0 || height == 0 || channels == 0 {
            return Err(SbfError::InvalidParameter { name: "LUT size", value: 0.0, reason: "dimensions must be > 0" });
        }
        check_len("LUT data", width * height * channels, data.len())?;
        Ok(Lut2 { width, height, channels, data })
    }

    /// Tabulates `f(u, v)` at texel centres (u along width, v along height).
    pub fn from_fn(width: usize, height: usize, channels: usize, mut f: impl FnMut(f64, f64) -> Vec<f64>) -> Result<Self, SbfError> {
        let mut data = Vec::with_capacity(width * height * channels);
        for j in 0..height {
            for i in 0..width {
                let v = f((i as f64 + 0.5) / width as f64, (j as f64 + 0.5) / height as f64);
                check_len("LUT entry channels", channels, v.len())?;
                data.extend(v.iter().map(|x| *x as f32));
            }
        }
        Lut2::new(width, height, channels, data)
    }

    /// Texel (i, j), channel c.
    pub fn texel(&self, i: usize, j: usize, c: usize) -> f32 {
        self.data[(j * self.width + i) * self.channels + c]
    }

    /// Bilinear lookup at (u, v) ∈ [0, 1]², clamped to texel centres (±∞ to the edges);
    /// writes `channels` values into `out`. A NaN coordinate gives NaN values: an invalid
    /// input stays visible instead of reading the table's corner.
    pub fn sample_into(&self, u: f32, v: f32, out: &mut [f32]) {
        debug_assert_eq!(out.len(), self.channels);
        if u.is_nan() || v.is_nan() {
            out.fill(f32::NAN);
            return;
        }
        let coord = |t: f32, n: usize| {
            let x = (t * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            let i0 = (x.floor() as usize).min(n - 1);
            (i0, (i0 + 1).min(n - 1), x - i0 as f32)
        };
        let (i0, i1, fx) = coord(u, self.width);
        let (j0, j1, fy) = coord(v, self.height);
        for (c, o) in out.iter_mut().enumerate() {
            let a = self.texel(i0, j0, c) * (1.0 - fx) + self.texel(i1, j0, c) * fx;
            let b = self.texel(i0, j1, c) * (1.0 - fx) + self.texel(i1, j1, c) * fx;
            *o = a * (1.0 - fy) + b * fy;
        }
    }

    /// Two-channel convenience lookup.
    pub fn sample2(&self, u: f32, v: f32) -> [f32; 2] {
        let mut o = [0.0; 2];
        self.sample_into(u, v, &mut o[..self.channels.min(2)]);
        o
    }
}

impl Lut2 {
    /// A 2-axis [`crate::luts::LutFile`] over [0, 1]² as a sampler.
    pub fn from_file(f: &crate::luts::LutFile) -> Result<Self, SbfError> {
        if f.axes.len() != 2 || f.axes.iter().any(|a| a.lo != 0.0 || a.hi != 1.0) {
            return Err(SbfError::InvalidParameter { name: "LUT axes", value: f.axes.len() as f64, reason: "expected 2 axes over [0, 1]" });
        }
        Lut2::new(f.axes[0].size, f.axes[1].size, f.channels, f.values.clone())
    }
}

/// A 3D table; axes 0 and 1 over [0, 1], axis 2 over [lo2, hi2]; texel centres,
/// trilinear, clamped (see [`Lut2`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Lut3 {
    /// Texels along each axis.
    pub dims: [usize; 3],
    /// Values per texel.
    pub channels: usize,
    /// (lo, hi) of axis 2.
    pub range2: (f32, f32),
    /// The values, channel fastest, then axis 0, 1, 2.
    pub data: Vec<f32>,
}

impl Lut3 {
    /// A 3-axis [`crate::luts::LutFile`] (axes 0, 1 over [0, 1]) as a sampler.
    pub fn from_file(f: &crate::luts::LutFile) -> Result<Self, SbfError> {
        if f.axes.len() != 3 || f.axes[..2].iter().any(|a| a.lo != 0.0 || a.hi != 1.0) {
            return Err(SbfError::InvalidParameter {
                name: "LUT axes",
                value: f.axes.len() as f64,
                reason: "expected 3 axes, the first two over [0, 1]",
            });
        }
        check_len("LUT data", f.value_count(), f.values.len())?;
        Ok(Lut3 {
            dims: [f.axes[0].size, f.axes[1].size, f.axes[2].size],
            channels: f.channels,
            range2: (f.axes[2].lo, f.axes[2].hi),
            data: f.values.clone(),
        })
    }

    fn at(&self, i: usize, j: usize, k: usize, c: usize) -> f32 {
        self.data[((k * self.dims[1] + j) * self.dims[0] + i) * self.channels + c]
    }

    /// Trilinear lookup at (u, v, w), u, v ∈ [0, 1], w ∈ [lo2, hi2]; clamped (±∞ to the
    /// edges). A NaN coordinate gives NaN values (see [`Lut2::sample_into`]).
    pub fn sample_into(&self, u: f32, v: f32, w: f32, out: &mut [f32]) {
        let wn = (w - self.range2.0) / (self.range2.1 - self.range2.0);
        if u.is_nan() || v.is_nan() || wn.is_nan() {
            out.fill(f32::NAN);
            return;
        }
        let coord = |t: f32, n: usize| {
            let x = (t * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            let i0 = (x.floor() as usize).min(n - 1);
            (i0, (i0 + 1).min(n - 1), x - i0 as f32)
        };
        let (i0, i1, fx) = coord(u, self.dims[0]);
        let (j0, j1, fy) = coord(v, self.dims[1]);
        let (k0, k1, fz) = coord(wn, self.dims[2]);
        for (c, o) in out.iter_mut().enumerate() {
            let lerp2 = |k: usize| {
                let a = self.at(i0, j0, k, c) * (1.0 - fx) + self.at(i1, j0, k, c) * fx;
                let b = self.at(i0, j1, k, c) * (1.0 - fx) + self.at(i1, j1, k, c) * fx;
                a * (1.0 - fy) + b * fy
            };
            *o = lerp2(k0) * (1.0 - fz) + lerp2(k1) * fz;
        }
    }
}

/// The Ambient Dice specular LUT (Listing 8.2) over (n·v, α) at texel centres,
/// two channels (f0, f90 scales), each entry from `samples` visible-normal samples.
#[cfg(feature = "ambient-dice")]
pub fn ad_specular_lut(n_nv: usize, n_alpha: usize, samples: u32) -> Result<Lut2, SbfError> {
    ad_specular_lut_with(n_nv, n_alpha, samples, crate::ggx::Convention::Physical)
}

/// [`ad_specular_lut`] whose ground truth weighs samples by `convention`.
#[cfg(feature = "ambient-dice")]
pub fn ad_specular_lut_with(n_nv: usize, n_alpha: usize, samples: u32, convention: crate::ggx::Convention) -> Result<Lut2, SbfError> {
    Lut2::from_fn(n_nv, n_alpha, 2, |nv, alpha| super::ambient_dice::specular_lut_entry_with(nv, alpha, samples, convention).to_vec())
}

/// The cubic B-spline's weights of the four texels around a lookup, for the fractional
/// position f ∈ [0, 1) past the second (de Boor; Sigg and Hadwiger 2005, eq. 1).
pub fn bspline_weights(f: f64) -> [f64; 4] {
    let (f2, f3) = (f * f, f * f * f);
    [(1.0 - f).powi(3) / 6.0, (3.0 * f3 - 6.0 * f2 + 4.0) / 6.0, (-3.0 * f3 + 3.0 * f2 + 3.0 * f + 1.0) / 6.0, f3 / 6.0]
}

/// The GPU's four bilinear taps of the B-spline at `uv` (texels): per axis two positions
/// (texels, the sampler's coordinates × size) and weights — tap k at i − 1 + w₁/(w₀ + w₁)
/// and i + 1 + w₃/(w₂ + w₃) (+ ½: centres), weighted w₀ + w₁ and w₂ + w₃ (Sigg and
/// Hadwiger 2005): a bilinear lookup there weights its two texels w₀:w₁, w₂:w₃.
pub fn bspline_taps(uv: [f64; 2]) -> [([f64; 2], [f64; 2]); 2] {
    [0, 1].map(|a| {
        let x = uv[a] - 0.5;
        let i = x.floor();
        let w = bspline_weights(x - i);
        let (g0, g1) = (w[0] + w[1], w[2] + w[3]);
        ([i - 1.0 + w[1] / g0 + 0.5, i + 1.0 + w[3] / g1 + 0.5], [g0, g1])
    })
}
