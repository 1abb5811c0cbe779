//! A minimal OpenEXR writer (single-part scanline, FLOAT channels, no compression)
//! for the viewing twins of the tables. Deterministic bytes; any EXR viewer opens it.
//! Layout per the OpenEXR file-layout spec: magic, version 2, header attributes
//! (channels, compression, dataWindow, displayWindow, lineOrder, pixelAspectRatio,
//! screenWindowCenter, screenWindowWidth), an offset table with one entry per scanline,
//! then per scanline: y, byte count, and each channel's row (channels in name order).

fn attr(out: &mut Vec<u8>, name: &str, ty: &str, value: &[u8]) {
    out.extend_from_slice(name.as_bytes());
    out.push(0);
    out.extend_from_slice(ty.as_bytes());
    out.push(0);
    out.extend_from_slice(&(value.len() as i32).to_le_bytes());
    out.extend_from_slice(value);
}

fn box2i(w: usize, h: usize) -> Vec<u8> {
    [0i32, 0, w as i32 - 1, h as i32 - 1].iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Writes an RGB float image (`rgb[y * w + x]`) as uncompressed OpenEXR.
pub fn write_rgb(w: usize, h: usize, rgb: &[[f32; 3]]) -> Vec<u8> {
    assert_eq!(rgb.len(), w * h);
    let mut out = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    let mut ch = Vec::new();
    for name in ["B", "G", "R"] {
        ch.extend_from_slice(name.as_bytes());
        ch.push(0);
        ch.extend_from_slice(&2i32.to_le_bytes()); // FLOAT
        ch.extend_from_slice(&[0, 0, 0, 0]); // pLinear + reserved
        ch.extend_from_slice(&1i32.to_le_bytes());
        ch.extend_from_slice(&1i32.to_le_bytes());
    }
    ch.push(0);
    attr(&mut out, "channels", "chlist", &ch);
    attr(&mut out, "compression", "compression", &[0]);
    attr(&mut out, "dataWindow", "box2i", &box2i(w, h));
    attr(&mut out, "displayWindow", "box2i", &box2i(w, h));
    attr(&mut out, "lineOrder", "lineOrder", &[0]);
    attr(&mut out, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    attr(&mut out, "screenWindowCenter", "v2f", &[0u8; 8]);
    attr(&mut out, "screenWindowWidth", "float", &1f32.to_le_bytes());
    out.push(0);
    let line_bytes = 3 * 4 * w;
    let table_start = out.len();
    let first = table_start + 8 * h;
    for y in 0..h {
        out.extend_from_slice(&((first + y * (8 + line_bytes)) as u64).to_le_bytes());
    }
    for y in 0..h {
        out.extend_from_slice(&(y as i32).to_le_bytes());
        out.extend_from_slice(&(line_bytes as i32).to_le_bytes());
        for c in [2usize, 1, 0] {
            for x in 0..w {
                out.extend_from_slice(&rgb[y * w + x][c].to_le_bytes());
            }
        }
    }
    out
}

/// The viewing image of a table: channels 0, 1 → R, G (B = 0); a 3D table's slices
/// along its third axis are laid out left to right.
pub fn table_image(lut: &sbf::luts::LutFile) -> (usize, usize, Vec<[f32; 3]>) {
    let (a0, a1) = (lut.axes[0].size, lut.axes[1].size);
    let a2 = lut.axes.get(2).map_or(1, |a| a.size);
    let (w, h) = (a0 * a2, a1);
    let mut px = vec![[0.0f32; 3]; w * h];
    for k in 0..a2 {
        for j in 0..a1 {
            for i in 0..a0 {
                let base = ((k * a1 + j) * a0 + i) * lut.channels;
                let mut c = [0.0f32; 3];
                for (ch, v) in c.iter_mut().enumerate().take(lut.channels.min(3)) {
                    *v = lut.values[base + ch];
                }
                px[j * w + k * a0 + i] = c;
            }
        }
    }
    (w, h, px)
}
