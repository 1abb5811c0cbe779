//! The `.sbflut` binary table format (written by fitgen, read by `sbf` from
//! `include_bytes!` — no file I/O here).
//!
//! Little-endian throughout:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 8 | magic `SBFLUT01` |
//! | 8 | 4 | u32 data offset (header size, a multiple of 16) |
//! | 12 | 4 | u32 number of axes (1–4) |
//! | 16 | 4 | u32 channels |
//! | 20 | 4 | u32 value format: 0 = f32, 1 = f16 (IEEE binary16) |
//! | 24 | 32 × axes | per axis: u32 size, f32 lo, f32 hi, 20-byte NUL-padded name |
//! | … | 4 + n | u32 byte length of the note, then the note (UTF-8: the command that made it) |
//! | data offset | … | values, channel fastest, then axis 0, axis 1, axis 2, axis 3 |
//!
//! Axis semantics: texel k of an axis of size n sits at lo + (hi − lo)(k + ½)/n
//! (texel centres), which is how every table here is sampled.

use crate::error::SbfError;

/// Magic bytes at the start of every table.
pub const MAGIC: &[u8; 8] = b"SBFLUT01";

/// Storage format of the values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueFormat {
    /// IEEE single precision.
    F32,
    /// IEEE half precision (widened to f32 on reading).
    F16,
}

/// One axis of a table.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// What the axis measures (e.g. "n_dot_v", "alpha").
    pub name: String,
    /// Texels along it.
    pub size: usize,
    /// The coordinate at the first texel's lower edge.
    pub lo: f32,
    /// The coordinate at the last texel's upper edge.
    pub hi: f32,
}

impl Axis {
    /// Coordinate of texel centre k.
    pub fn centre(&self, k: usize) -> f64 {
        self.lo as f64 + (self.hi as f64 - self.lo as f64) * (k as f64 + 0.5) / self.size as f64
    }
}

/// A parsed (or to-be-written) table: axes, channels and values as f32.
#[derive(Debug, Clone, PartialEq)]
pub struct LutFile {
    /// Its axes, 1 to 3.
    pub axes: Vec<Axis>,
    /// Values per texel.
    pub channels: usize,
    /// How the values are stored in the file.
    pub format: ValueFormat,
    /// Free text: how the table was made and its error.
    pub note: String,
    /// Values, channel fastest then axis 0, 1, 2 (already widened from f16).
    pub values: Vec<f32>,
}

fn bad(reason: &'static str) -> SbfError {
    SbfError::InvalidParameter { name: "LUT file", value: f64::NAN, reason }
}

fn u32_at(b: &[u8], o: usize) -> Result<u32, SbfError> {
    b.get(o..o + 4).map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]])).ok_or(bad("truncated header"))
}

fn f32_at(b: &[u8], o: usize) -> Result<f32, SbfError> {
    Ok(f32::from_bits(u32_at(b, o)?))
}

/// f32 → IEEE binary16 with round-to-nearest-even (overflow → ±inf, NaN kept).
pub fn f32_to_f16(x: f32) -> u16 {
    let b = x.to_bits();
    let sign = ((b >> 16) & 0x8000) as u16;
    let exp = ((b >> 23) & 0xff) as i32;
    let man = b & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        // Subnormal: shift the mantissa with the implicit bit, round to nearest even.
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let rem = m & ((1u32 << shift) - 1);
        let mut r = m >> shift;
        if rem > half || (rem == half && (r & 1) == 1) {
            r += 1;
        }
        return sign | r as u16;
    }
    let mut r = ((e as u32) << 10) | (man >> 13);
    let rem = man & 0x1fff;
    if rem > 0x1000 || (rem == 0x1000 && (r & 1) == 1) {
        r += 1; // may carry into the exponent, which is the correct rounding
    }
    sign | r as u16
}

/// IEEE binary16 → f32 (exact).
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = ((h & 0x8000) as u32) << 16;
    let exp = ((h >> 10) & 0x1f) as u32;
    let man = (h & 0x3ff) as u32;
    let bits = match (exp, man) {
        (0, 0) => sign,
        (0, m) => {
            // Subnormal: value = m·2^−24.
            return f32::from_bits(sign) + (if sign != 0 { -1.0 } else { 1.0 }) * (m as f32) * (1.0 / 16_777_216.0);
        }
        (0x1f, 0) => sign | 0x7f80_0000,
        (0x1f, m) => sign | 0x7f80_0000 | (m << 13),
        (e, m) => sign | ((e + 127 - 15) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}

impl LutFile {
    /// Number of values: channels × Π axis sizes.
    pub fn value_count(&self) -> usize {
        self.channels * self.axes.iter().map(|a| a.size).product::<usize>()
    }

    /// Parses a table, checking magic, sizes and that the data length matches.
    pub fn parse(bytes: &[u8]) -> Result<Self, SbfError> {
        if bytes.get(0..8) != Some(&MAGIC[..]) {
            return Err(bad("bad magic (not an SBFLUT01 table)"));
        }
        let data_off = u32_at(bytes, 8)? as usize;
        let naxes = u32_at(bytes, 12)? as usize;
        let channels = u32_at(bytes, 16)? as usize;
        let format = match u32_at(bytes, 20)? {
            0 => ValueFormat::F32,
            1 => ValueFormat::F16,
            _ => return Err(bad("unknown value format")),
        };
        if !(1..=4).contains(&naxes) || channels == 0 {
            return Err(bad("axis count must be 1–4 and channels > 0"));
        }
        let mut axes = Vec::with_capacity(naxes);
        for a in 0..naxes {
            let o = 24 + 32 * a;
            let size = u32_at(bytes, o)? as usize;
            let (lo, hi) = (f32_at(bytes, o + 4)?, f32_at(bytes, o + 8)?);
            let raw = bytes.get(o + 12..o + 32).ok_or(bad("truncated axis"))?;
            let end = raw.iter().position(|c| *c == 0).unwrap_or(20);
            let name = std::str::from_utf8(&raw[..end]).map_err(|_| bad("axis name is not UTF-8"))?.to_string();
            if size == 0 || !(lo.is_finite() && hi.is_finite()) {
                return Err(bad("axis size 0 or non-finite range"));
            }
            axes.push(Axis { name, size, lo, hi });
        }
        let no = 24 + 32 * naxes;
        let nlen = u32_at(bytes, no)? as usize;
        let note = std::str::from_utf8(bytes.get(no + 4..no + 4 + nlen).ok_or(bad("truncated note"))?)
            .map_err(|_| bad("note is not UTF-8"))?
            .to_string();
        let mut lut = LutFile { axes, channels, format, note, values: Vec::new() };
        let n = lut.value_count();
        let width = if format == ValueFormat::F32 { 4 } else { 2 };
        let data = bytes.get(data_off..).ok_or(bad("data offset beyond the end"))?;
        if data.len() != n * width {
            return Err(bad("data length does not match the header"));
        }
        lut.values = match format {
            ValueFormat::F32 => data.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect(),
            ValueFormat::F16 => data.chunks_exact(2).map(|c| f16_to_f32(u16::from_le_bytes([c[0], c[1]]))).collect(),
        };
        Ok(lut)
    }

    /// Serialises the table (values are rounded to f16 when the format says so).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut h = Vec::new();
        h.extend_from_slice(MAGIC);
        h.extend_from_slice(&0u32.to_le_bytes()); // patched below
        h.extend_from_slice(&(self.axes.len() as u32).to_le_bytes());
        h.extend_from_slice(&(self.channels as u32).to_le_bytes());
        h.extend_from_slice(&(if self.format == ValueFormat::F32 { 0u32 } else { 1 }).to_le_bytes());
        for a in &self.axes {
            h.extend_from_slice(&(a.size as u32).to_le_bytes());
            h.extend_from_slice(&a.lo.to_le_bytes());
            h.extend_from_slice(&a.hi.to_le_bytes());
            let mut name = [0u8; 20];
            let nb = a.name.as_bytes();
            name[..nb.len().min(20)].copy_from_slice(&nb[..nb.len().min(20)]);
            h.extend_from_slice(&name);
        }
        h.extend_from_slice(&(self.note.len() as u32).to_le_bytes());
        h.extend_from_slice(self.note.as_bytes());
        while h.len() % 16 != 0 {
            h.push(0);
        }
        let off = h.len() as u32;
        h[8..12].copy_from_slice(&off.to_le_bytes());
        for v in &self.values {
            match self.format {
                ValueFormat::F32 => h.extend_from_slice(&v.to_le_bytes()),
                ValueFormat::F16 => h.extend_from_slice(&f32_to_f16(*v).to_le_bytes()),
            }
        }
        h
    }
}
