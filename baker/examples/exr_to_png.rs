//! Tone-maps an EXR (a baked lightmap: RGB, alpha = validity) to an sRGB PNG for
//! viewing: Reinhard x/(1 + x) after `exposure`, invalid texels (alpha 0) dark blue.
//! `cargo run --release -p baker --example exr_to_png -- IN.exr OUT.png [exposure] [scale]`.

fn main() -> Result<(), String> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (inp, out) = match (a.first(), a.get(1)) {
        (Some(i), Some(o)) => (i, o),
        _ => return Err("usage: exr_to_png IN.exr OUT.png [exposure] [scale]".into()),
    };
    let exposure: f32 = a.get(2).map(|s| s.parse().map_err(|e| format!("{s}: {e}"))).transpose()?.unwrap_or(1.0);
    let scale: u32 = a.get(3).map(|s| s.parse().map_err(|e| format!("{s}: {e}"))).transpose()?.unwrap_or(4);
    let img = image::open(inp).map_err(|e| format!("{inp}: {e}"))?.into_rgba32f();
    let srgb = |x: f32| {
        let v = x * exposure / (1.0 + x * exposure);
        let s = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
        (s.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
    };
    let mut png = image::RgbImage::new(img.width() * scale, img.height() * scale);
    for (x, y, p) in png.enumerate_pixels_mut() {
        let t = img.get_pixel(x / scale, y / scale);
        *p = if t[3] > 0.0 { image::Rgb([srgb(t[0]), srgb(t[1]), srgb(t[2])]) } else { image::Rgb([10, 10, 40]) };
    }
    png.save(out).map_err(|e| format!("{out}: {e}"))
}
