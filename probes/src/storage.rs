//! How a mode's coefficients are stored (`--storage`): f32 (the default), f16 (a GPU's
//! half-float texture), or BC6H (the HDR block compression engines stream lightmaps and
//! probe volumes in), each value rounded or compressed and decoded before any
//! reconstruction, so every error the report prints includes its storage.
//!
//! BC6H and one probe: a block holds 4 × 4 texels of one coefficient image (neighbouring
//! lightmap texels or probes of a volume) and its error depends on how they differ. The maps
//! this tool compares are distant light, the same at every point of a probe volume or a flat
//! lightmapped wall, so a block here is 16 copies of the probe — what BC6H does to a region
//! under that light: its endpoint and index precision (`sbf::bc`, ISPC's encoder at its
//! highest quality, bcdec's decoder). What neighbours that differ add (occlusion, local
//! lights) is the baker's to measure on a scene (`baker --compress bc6h`). Signed values are
//! stored shifted by a per-channel offset (−the minimum over the probe's values), as a
//! lightmap of signed coefficients is; the offset is part of the decode, not of the bytes (one
//! per texture, not per texel). Engine formats store their colour in BC6H and their 8-bit
//! direction textures in BC1 (RGB, ½ byte per texel) or BC7 (RGBA, 1 byte).

use sbf::bc;

/// A coefficient storage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    F32,
    F16,
    Bc6h,
}

impl Storage {
    pub const ALL: [Storage; 3] = [Storage::F32, Storage::F16, Storage::Bc6h];

    pub fn name(self) -> &'static str {
        match self {
            Storage::F32 => "f32",
            Storage::F16 => "f16",
            Storage::Bc6h => "bc6h",
        }
    }

    pub fn parse(s: &str) -> Result<Storage, String> {
        Self::ALL.into_iter().find(|x| x.name() == s).ok_or_else(|| format!("--storage '{s}': expected f32, f16 or bc6h"))
    }

    /// What a report says about the storage.
    pub fn describe(self) -> &'static str {
        match self {
            Storage::F32 => "f32 per coefficient",
            Storage::F16 => "f16 per coefficient (rounded to nearest), as a half-float texture",
            Storage::Bc6h => {
                "BC6H (1 byte per RGB coefficient; engine formats' directions in BC1/BC7), a uniform 4×4 block of the probe: the precision floor under distant light (ISPC encoder, bcdec decoder)"
            }
        }
    }

    /// Bytes per probe of `scalars` stored values: 4 or 2 each, or under BC6H one byte per
    /// texel of three (RGB, or three scalars packed).
    pub fn bytes(self, scalars: usize) -> f64 {
        match self {
            Storage::F32 => 4.0 * scalars as f64,
            Storage::F16 => 2.0 * scalars as f64,
            Storage::Bc6h => scalars.div_ceil(3) as f64,
        }
    }

    /// `values` as stored and read back.
    pub fn store(self, values: &[[f64; 3]]) -> Vec<[f64; 3]> {
        match self {
            Storage::F32 => values.to_vec(),
            Storage::F16 => values.iter().map(|v| v.map(|x| half::f16::from_f64(x).to_f64())).collect(),
            Storage::Bc6h => bc6h_uniform(values),
        }
    }

    /// Scalars (a mode storing one value per channel, e.g. YCoCg's) packed three to a texel.
    pub fn store_scalars(self, values: &[f64]) -> Vec<f64> {
        let texels: Vec<[f64; 3]> = values.chunks(3).map(|c| [0, 1, 2].map(|k| c.get(k).copied().unwrap_or(0.0))).collect();
        self.store(&texels).into_iter().flatten().take(values.len()).collect()
    }

    /// 8-bit RGBA values (in [0, 1]) of an engine format's direction textures as stored:
    /// unchanged at f32 and f16 (the engines store them 8-bit already), BC1 (`alpha` false)
    /// or BC7 under BC6H.
    pub fn store_unorm(self, values: &[[f64; 4]], alpha: bool) -> Vec<[f64; 4]> {
        if self != Storage::Bc6h || values.is_empty() {
            return values.to_vec();
        }
        let (w, rgba) = uniform_blocks(values);
        let (_, _, decoded) = bc::encode_unorm(w, 4, &rgba, alpha);
        (0..values.len()).map(|k| decoded[4 * k]).collect()
    }

    /// Bytes per texel of an 8-bit direction texture: 4 (RGBA8) or BC1's ½ / BC7's 1.
    pub fn unorm_bytes(self, alpha: bool) -> f64 {
        match (self, alpha) {
            (Storage::Bc6h, false) => 0.5,
            (Storage::Bc6h, true) => 1.0,
            _ => 4.0,
        }
    }
}

/// Each value as a 4 × 4 block of its own: a (4n) × 4 image, row-major.
fn uniform_blocks<T: Copy>(values: &[T]) -> (usize, Vec<T>) {
    let w = 4 * values.len();
    let img = (0..4 * w).map(|i| values[(i % w) / 4]).collect();
    (w, img)
}

/// Every RGB value through BC6H as a uniform block (see the module docs).
fn bc6h_uniform(values: &[[f64; 3]]) -> Vec<[f64; 3]> {
    if values.is_empty() {
        return Vec::new();
    }
    let f32s: Vec<[f32; 3]> = values.iter().map(|v| v.map(|x| x as f32)).collect();
    let (w, img) = uniform_blocks(&f32s);
    let (blocks, offset, _) = bc::encode_bc6h_offset(w, 4, &img);
    let decoded = bc::decode_bc6h_offset(w, 4, &blocks, offset);
    (0..values.len()).map(|k| decoded[4 * k].map(f64::from)).collect()
}

#[cfg(test)]
mod tests {
    use super::Storage;

    /// f16 rounding keeps 11 significant bits (relative error ≤ 2⁻¹¹); BC6H on a uniform
    /// block reproduces each value to its endpoint precision: the unsigned 16-bit mode
    /// (BC6H mode 11, 10-bit endpoints over the half's bit pattern) bounds the relative
    /// error by 2⁻⁶ of the value plus the offset, for values in f16's normal range.
    #[test]
    fn storage_round_trips_within_its_precision() {
        let v = vec![[1.0, 0.25, 3.5], [-0.4, 0.01, 0.0], [120.0, 7.0, 0.5], [0.3, -0.2, 2.0]];
        for s in Storage::ALL {
            let out = s.store(&v);
            assert_eq!(out.len(), v.len());
            for (a, b) in out.iter().zip(&v) {
                for k in 0..3 {
                    let offset = v.iter().map(|x| -x[k]).fold(0.0f64, f64::max);
                    let tol = match s {
                        Storage::F32 => 0.0,
                        Storage::F16 => b[k].abs() * 2f64.powi(-11),
                        Storage::Bc6h => (b[k] + offset).abs() * 2f64.powi(-6) + 1e-4,
                    };
                    assert!((a[k] - b[k]).abs() <= tol, "{s:?}: {} stored as {}", b[k], a[k]);
                }
            }
        }
        assert_eq!(Storage::F16.store(&[[1.0 + 2f64.powi(-12), 0.0, 0.0]])[0][0], 1.0);
        let s = Storage::Bc6h.store_scalars(&[0.5, 1.5, -0.25, 2.0]);
        assert_eq!(s.len(), 4);
    }
}
