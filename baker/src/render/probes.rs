//! Dynamic objects — meshes without a lightmap that do not emit — are shaded from the bake's
//! probe grid: SH L2 probes in world space (probes.json), interpolated trilinearly on the
//! grid's lattice (cell centres of the scene bounds, `layout::probes::probe_grid`), probes
//! found inside geometry left out and the weights of the rest renormalised; positions
//! outside the lattice take its nearest face (clamped).

use sbf::glam::{DVec3, Vec3};
use std::path::Path;

/// SH L2 probes on a regular lattice.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeField {
    /// Probes along x, y, z (x fastest in `coefficients`).
    pub dims: [usize; 3],
    /// The lattice's first and last probe positions.
    pub first: Vec3,
    pub last: Vec3,
    /// Per probe, 9 RGB SH L2 radiance coefficients (world frame).
    pub coefficients: Vec<[DVec3; 9]>,
    pub valid: Vec<bool>,
}

impl ProbeField {
    /// Reads probes.json of a bake folder: its SH L2 coefficients and the lattice (the
    /// distinct original positions along each axis).
    pub fn read(dir: &Path) -> Result<ProbeField, String> {
        let path = dir.join("probes.json");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e} (bake with probes to shade dynamic objects)", path.display()))?;
        let j: serde_json::Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let probes = j["probes"].as_array().ok_or_else(|| format!("{}: no probes", path.display()))?;
        let v3 = |x: &serde_json::Value| -> Option<[f64; 3]> { Some([x[0].as_f64()?, x[1].as_f64()?, x[2].as_f64()?]) };
        let mut positions = Vec::new();
        let (mut coefficients, mut valid) = (Vec::new(), Vec::new());
        for (k, p) in probes.iter().enumerate() {
            let pos = v3(if p["relocated_from"].is_array() { &p["relocated_from"] } else { &p["position"] })
                .ok_or_else(|| format!("{}: probe {k} has no position", path.display()))?;
            let rows = p["coefficients"]["sh2"]
                .as_array()
                .ok_or_else(|| format!("{}: probe {k} has no sh2 coefficients (bake with --probe-bases sh2)", path.display()))?;
            if rows.len() != 9 {
                return Err(format!("{}: probe {k} has {} sh2 rows, not 9", path.display(), rows.len()));
            }
            let mut c = [DVec3::ZERO; 9];
            for (i, r) in rows.iter().enumerate() {
                c[i] = DVec3::from(v3(r).ok_or_else(|| format!("{}: probe {k} row {i} is not RGB", path.display()))?);
            }
            positions.push(pos);
            coefficients.push(c);
            valid.push(p["valid"].as_bool().unwrap_or(false));
        }
        let distinct = |a: usize| {
            let mut v: Vec<f64> = positions.iter().map(|p| p[a]).collect();
            v.sort_by(f64::total_cmp);
            v.dedup_by(|x, y| (*x - *y).abs() <= 1e-6 * (1.0 + y.abs()));
            v
        };
        let axes = [distinct(0), distinct(1), distinct(2)];
        let dims = [axes[0].len(), axes[1].len(), axes[2].len()];
        if dims.iter().product::<usize>() != positions.len() {
            return Err(format!(
                "{}: {} probes do not form a lattice ({}×{}×{})",
                path.display(),
                positions.len(),
                dims[0],
                dims[1],
                dims[2]
            ));
        }
        let first = Vec3::new(axes[0][0] as f32, axes[1][0] as f32, axes[2][0] as f32);
        let last = Vec3::new(axes[0][dims[0] - 1] as f32, axes[1][dims[1] - 1] as f32, axes[2][dims[2] - 1] as f32);
        Ok(ProbeField { dims, first, last, coefficients, valid })
    }

    /// The field with every probe deringed where its irradiance rings: per probe and
    /// channel, if its E/π is negative on any of 4096 spherical-Fibonacci directions, the
    /// radiance windowed by the widest sinc⁴ window that makes it non-negative
    /// (`sbf::recon::sh::dering_irradiance`, Sloan 2017; the probes tool's `shl2w`).
    /// Returns the field and the probe channels windowed.
    pub fn deringed(&self) -> Result<(ProbeField, usize), String> {
        let dirs: Vec<DVec3> = (0..4096).map(|i| sbf::sampling::spherical_fibonacci(i, 4096)).collect();
        let mut out = self.clone();
        let mut windowed = 0;
        for c in &mut out.coefficients {
            for k in 0..3 {
                let channel: Vec<f64> = c.iter().map(|x| x[k]).collect();
                if let Some((_, w)) = sbf::recon::sh::dering_irradiance(&channel, &dirs).map_err(|e| e.to_string())? {
                    for (x, v) in c.iter_mut().zip(w) {
                        x[k] = v;
                    }
                    windowed += 1;
                }
            }
        }
        Ok((out, windowed))
    }

    /// The lattice cell of `p` and the fractional position in it, per axis (clamped).
    pub fn cell(&self, p: Vec3) -> ([usize; 3], [f64; 3]) {
        let mut i = [0; 3];
        let mut f = [0.0; 3];
        for a in 0..3 {
            let n = self.dims[a];
            if n < 2 {
                continue;
            }
            let t = ((p[a] - self.first[a]) as f64 / (self.last[a] - self.first[a]) as f64 * (n - 1) as f64).clamp(0.0, (n - 1) as f64);
            let k = (t.floor() as usize).min(n - 2);
            i[a] = k;
            f[a] = t - k as f64;
        }
        (i, f)
    }

    /// The interpolated coefficients at `p` (None where all eight probes around it are
    /// invalid).
    pub fn at(&self, p: Vec3) -> Option<[DVec3; 9]> {
        let (i, f) = self.cell(p);
        let mut c = [DVec3::ZERO; 9];
        let mut wsum = 0.0;
        for corner in 0..8 {
            let d = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
            let idx: [usize; 3] = std::array::from_fn(|a| (i[a] + d[a]).min(self.dims[a] - 1));
            let w: f64 = (0..3).map(|a| if d[a] == 1 { f[a] } else { 1.0 - f[a] }).product();
            let k = idx[0] + self.dims[0] * (idx[1] + self.dims[1] * idx[2]);
            if w > 0.0 && self.valid[k] {
                for (o, x) in c.iter_mut().zip(&self.coefficients[k]) {
                    *o += w * *x;
                }
                wsum += w;
            }
        }
        (wsum > 0.0).then(|| c.map(|x| x / wsum))
    }
}
