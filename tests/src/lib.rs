//! Shared support for the cross-crate tests in `tests/tests/`: loading the bundled
//! HDR probes (skipping with a message when `../shared/probes` is absent) and the
//! error metrics the tests report.

#![deny(clippy::too_many_lines, clippy::cognitive_complexity)]

use sbf::envmap::LatLongImage;
use sbf::nalgebra::DMatrix;
use sbf::Basis;
use std::path::PathBuf;

/// The five probes bundled in `../shared/probes`, in the order the peer tables use.
pub const PROBES: [&str; 5] = ["ennis", "grace", "pisa", "uffizi", "wells"];

/// Folder of the bundled probes (`<workspace>/../shared/probes`).
pub fn probe_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/probes")
}

/// Loads a bundled probe as a lat-long image, or `None` (with a message on stderr)
/// when the folder is absent — unless `SBF_REQUIRE_PROBES=1` (CI), where a missing folder
/// fails the test with a message naming it. Panics on a present but unreadable file: a
/// corrupt probe must fail loudly.
pub fn load_probe(name: &str) -> Option<LatLongImage> {
    let path = probe_dir().join(format!("{name}.hdr"));
    if !probe_dir().is_dir() {
        assert!(
            std::env::var("SBF_REQUIRE_PROBES").map_or(true, |v| v != "1"),
            "SBF_REQUIRE_PROBES=1 but {} is missing (the bundled probes live in ../shared/probes)",
            probe_dir().display()
        );
        eprintln!("skipping: {} not found (the bundled probes live in ../shared/probes)", probe_dir().display());
        return None;
    }
    let img = image::open(&path).unwrap_or_else(|e| panic!("reading probe '{}': {e}", path.display())).to_rgb32f();
    let (w, h) = img.dimensions();
    let texels = img.pixels().map(|p| p.0).collect();
    Some(LatLongImage::new(w as usize, h as usize, texels).unwrap_or_else(|e| panic!("probe '{}': {e}", path.display())))
}

/// RMS error of `coeffs` (n × 3) against every texel of `map`, unweighted over
/// texels and averaged over RGB (as Probulator reports).
pub fn rmse_vs_map(basis: &dyn Basis, coeffs: &DMatrix<f64>, map: &LatLongImage) -> f64 {
    let g = map.geometry;
    let mut b = vec![0.0; basis.len()];
    let mut se = 0.0;
    for j in 0..g.height {
        for i in 0..g.width {
            basis.eval_into(g.texel_direction(i, j), &mut b);
            let t = map.texel(i, j);
            for c in 0..3 {
                let r: f64 = (0..basis.len()).map(|k| coeffs[(k, c)] * b[k]).sum();
                se += (r - t[c] as f64).powi(2);
            }
        }
    }
    (se / (3 * g.texel_count()) as f64).sqrt()
}
