//! Projects the built-in procedural sky onto every sphere basis by least squares
//! and prints radiance error against encode time. The README's main command until
//! the `probes` tool replaces it:
//!
//!     cargo run --release --example project_sky [WIDTH]
//!
//! Method: the sky is sampled on a WIDTH×WIDTH/2 lat-long map (default 256);
//! moments m_i = Σ_texels Ω·f·B_i (exact texel solid angles); G b = m is solved with
//! the basis's Gram matrix (closed form or quadrature); errors are over all texels,
//! both unweighted (as Probulator reports) and solid-angle weighted.

use sbf::envmap::{LatLongImage, ProceduralSky};
use sbf::gram::{gram_matrix, GramOptions};
use sbf::{AmbientCube, AmbientDiceBezier, AmbientDiceSrbf, Basis, Domain, SgBasis, ShBasis};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let width: usize = match std::env::args().nth(1) {
        Some(a) => a.parse().map_err(|e| format!("WIDTH must be a positive integer, got '{a}': {e}"))?,
        None => 256,
    };
    if width < 2 {
        return Err(format!("WIDTH must be >= 2, got {width}").into());
    }
    let sky = ProceduralSky::default();
    let no_sun = ProceduralSky { sun_radiance: [0.0; 3], ..sky };
    for (label, env) in [("sky + 3° sun of radiance 400", sky), ("sky only (sun off)", no_sun)] {
        let map = LatLongImage::from_fn(width, width / 2, |d| env.radiance(d))?;
        println!("\nBuilt-in procedural environment: {label}, {}×{} lat-long", width, width / 2);
        table(&map)?;
    }
    println!("\nRMS over all texels and RGB channels, in radiance units; encode = moments + solve, one core.");
    println!("A sharp sun cannot be represented by any low-order basis: its error dominates the first table.");
    Ok(())
}

fn table(map: &LatLongImage) -> Result<(), Box<dyn std::error::Error>> {
    let g = map.geometry;
    println!("{:<22} {:>6} {:>10} {:>12} {:>12} {:>10} {:>10}", "basis", "coeffs", "cond(G)", "RMS", "RMS (Ω-wt)", "encode ms", "gram ms");

    let vogel = sbf::layout::vogel_sphere(12)?;
    let bases: Vec<Box<dyn Basis>> = vec![
        Box::new(ShBasis::new(1)?),
        Box::new(ShBasis::new(2)?),
        Box::new(ShBasis::new(4)?),
        Box::new(ShBasis::new(8)?),
        Box::new(AmbientCube),
        Box::new(SgBasis::new(&vogel, 6.0, false)?),
        Box::new(SgBasis::new(&sbf::layout::icosahedron(), 3.4, false)?),
        Box::new(AmbientDiceSrbf::twelve()),
        Box::new(AmbientDiceBezier::new()),
    ];
    for basis in &bases {
        let n = basis.len();
        let t0 = Instant::now();
        let gram = gram_matrix(basis.as_ref(), Domain::Sphere, GramOptions::default())?;
        let gram_ms = t0.elapsed().as_secs_f64() * 1e3;

        let t1 = Instant::now();
        let mut b = vec![0.0; n];
        let mut moments = vec![[0.0f64; 3]; n];
        for j in 0..g.height {
            let w = g.texel_solid_angle(j);
            for i in 0..g.width {
                basis.eval_into(g.texel_direction(i, j), &mut b);
                let t = map.texel(i, j);
                for k in 0..n {
                    for c in 0..3 {
                        moments[k][c] += w * b[k] * t[c] as f64;
                    }
                }
            }
        }
        let coeffs: Vec<Vec<f64>> =
            (0..3).map(|c| gram.solve(&moments.iter().map(|m| m[c]).collect::<Vec<_>>())).collect::<Result<_, _>>()?;
        let encode_ms = t1.elapsed().as_secs_f64() * 1e3;

        let (mut se, mut swe, mut sw) = (0.0, 0.0, 0.0);
        for j in 0..g.height {
            let w = g.texel_solid_angle(j);
            for i in 0..g.width {
                basis.eval_into(g.texel_direction(i, j), &mut b);
                let t = map.texel(i, j);
                for c in 0..3 {
                    let r: f64 = coeffs[c].iter().zip(&b).map(|(x, y)| x * y).sum();
                    let e = r - t[c] as f64;
                    se += e * e;
                    swe += w * e * e;
                }
                sw += 3.0 * w;
            }
        }
        let rms = (se / (3 * g.texel_count()) as f64).sqrt();
        let wrms = (swe / sw).sqrt();
        println!(
            "{:<22} {:>6} {:>10.3e} {:>12.5} {:>12.5} {:>10.2} {:>10.2}",
            basis.name(),
            n,
            gram.condition,
            rms,
            wrms,
            encode_ms,
            gram_ms
        );
    }
    Ok(())
}
