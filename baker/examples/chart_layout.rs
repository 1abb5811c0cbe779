//! Draws a lightmap layout as a PNG: every valid texel coloured by its chart (a hash of
//! the chart id), empty texels black. `cargo run --release -p baker --example
//! chart_layout -- OUT.png [cornell|sphere6200] [texels-per-unit]`.

use baker::layout::lightmap::Lightmap;
use baker::scene::{self, Environment, Material, Scene};
use sbf::glam::Vec3;

/// A UV sphere of 6 200 triangles (50 rings × 62 segments), no lightmap UVs.
fn sphere6200() -> Scene {
    Scene {
        name: "sphere6200".into(),
        meshes: vec![scene::uv_sphere("sphere", Vec3::ZERO, 1.0, 50, 62, 0)],
        materials: vec![Material::lambert(Vec3::splat(0.5))],
        lights: vec![],
        environment: Environment::Black,
        textures: Vec::new(),
        normal_textures: Vec::new(),
    }
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = args.first().ok_or("usage: chart_layout OUT.png [cornell|sphere6200] [texels-per-unit]")?;
    let s = match args.get(1).map(|s| s.as_str()).unwrap_or("sphere6200") {
        "cornell" => scene::cornell(),
        "sphere6200" => sphere6200(),
        other => return Err(format!("unknown scene {other}")),
    };
    let tpu: f32 = args.get(2).map(|t| t.parse().map_err(|e| format!("{t}: {e}"))).transpose()?.unwrap_or(24.0);
    let lm = Lightmap::build(&s, tpu, 2).map_err(|e| e.to_string())?;
    let mut img = image::RgbImage::new(lm.width as u32, lm.height as u32);
    for (k, t) in lm.texels.iter().enumerate() {
        if t.is_valid() {
            let h = (t.chart as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            let c = [(h >> 16) as u8 | 0x40, (h >> 32) as u8 | 0x40, (h >> 48) as u8 | 0x40];
            img.put_pixel((k % lm.width) as u32, (k / lm.width) as u32, image::Rgb(c));
        }
    }
    img.save(out).map_err(|e| e.to_string())?;
    println!(
        "{}: {} charts ({} generated), atlas {}×{}, utilisation {:.3} → {out}",
        s.name,
        lm.chart_meshes.len(),
        lm.generated_charts,
        lm.width,
        lm.height,
        lm.utilisation()
    );
    Ok(())
}
