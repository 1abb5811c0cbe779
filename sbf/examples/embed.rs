//! What an engine does with sbf, in seconds: project an HDR map (a file, or the built-in
//! sky) onto every lightmap basis, then shade a few normals with irradiance and GGX
//! specular — the f32 runtime the WGSL/HLSL/GLSL/MSL library mirrors.
//!
//!     cargo run --release --example embed [MAP.hdr|MAP.exr]
//!
//! Needs sbf's default features (and `io` for a file: `--features io`).

use sbf::envmap::{LatLongImage, ProceduralSky};
use sbf::glam::Vec3;
use sbf::probe::{Probe, ProbeBasis};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let map = match std::env::args().nth(1) {
        Some(path) => load(&path)?,
        None => {
            let sky = ProceduralSky::default();
            LatLongImage::from_fn(128, 64, |d| sky.radiance(d))?
        }
    };
    // A wall facing +Z: the normal every basis shares (a hemisphere basis is laid out about
    // +Z, a texel's tangent-space normal), viewed from 30° above the normal.
    let n = Vec3::Z;
    let view = Vec3::new(0.0, 0.5, 0.866);
    println!("{:<6} {:>28} {:>34}", "basis", "E/π at n = +Z (RGB)", "GGX α 0.3, f0 0.04 (RGB)");
    for basis in ProbeBasis::ALL {
        let t = std::time::Instant::now();
        let probe = Probe::project(&map, basis)?;
        let e = probe.irradiance(n);
        // The ambient cube and the H-basis hold E/π only: no specular.
        let s = match probe.specular(n, view, 0.3, 0.04) {
            Ok(s) => format!("{:>10.4} {:>10.4} {:>10.4}", s.x, s.y, s.z),
            Err(_) => format!("{:>32}", "(E/π only)"),
        };
        println!(
            "{:<6} {:>8.4} {:>8.4} {:>8.4}   {s}   ({:.1} ms to project)",
            basis.name(),
            e.x,
            e.y,
            e.z,
            t.elapsed().as_secs_f64() * 1e3
        );
    }
    println!("(sg9, sg12, ad9, h4 and h6 are hemisphere bases: fitted over the map's z > 0, as a texel's tangent frame)");
    Ok(())
}

#[cfg(feature = "io")]
fn load(path: &str) -> Result<LatLongImage, Box<dyn std::error::Error>> {
    let (map, _) = sbf::io::load_map(std::path::Path::new(path), false).map_err(|e| e.to_string())?;
    Ok(map)
}

#[cfg(not(feature = "io"))]
fn load(path: &str) -> Result<LatLongImage, Box<dyn std::error::Error>> {
    Err(format!("reading {path} needs sbf's `io` feature: cargo run --release --example embed --features io -- {path}").into())
}
