//! The OpenEXR viewing twins of the tables, written with the `exr` crate (single-part
//! scanline, FLOAT channels, no compression), with the generating command in a header
//! attribute. Deterministic bytes; any EXR viewer opens them.

/// Writes an RGB float image (`rgb[y * w + x]`) as uncompressed single-part scanline
/// OpenEXR with the `exr` crate, carrying `command` (the fitgen command that generated the
/// table) as a text attribute of the image header. Deterministic: uncompressed blocks,
/// one custom attribute, no timestamps.
pub fn write_rgb(w: usize, h: usize, rgb: &[[f32; 3]], command: &str) -> Vec<u8> {
    use exr::prelude::*;
    assert_eq!(rgb.len(), w * h);
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let [r, g, b] = rgb[p.y() * w + p.x()];
        (r, g, b)
    });
    let layer = Layer::new((w, h), LayerAttributes::default(), Encoding::UNCOMPRESSED, channels);
    let mut image = Image::from_layer(layer);
    image.attributes.other.insert(Text::from("command"), AttributeValue::Text(Text::from(command)));
    let mut buf = std::io::Cursor::new(Vec::new());
    image.write().non_parallel().to_buffered(&mut buf).expect("writing an EXR to memory cannot fail");
    buf.into_inner()
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
