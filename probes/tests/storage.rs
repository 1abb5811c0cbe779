//! `--storage`: every mode reconstructs from its coefficients as stored, and the storage
//! axis counts the stored bytes.
//!
//! Oracle: a map whose SH L1 projection is known in closed form. L(ω) = a·(1 + b·ω) projects
//! to c₀₀ = 2√π·a and c₁ₘ = √(4π/3)·a·(b_y, b_z, b_x) (∫Y₀₀ = 2√π·Y₀₀², ∫ω_k·Y₁ₘ = √(4π/3)
//! for the matching axis), and SH L1's E/π(n) = c₀₀·Y₀₀ + (2/3)·Σ c₁ₘ·Y₁ₘ(n)
//! (A₀/π = 1, A₁/π = 2/3), written here. Error models: the projection's midpoint rule over
//! 128 × 64 texels (relative ≲ 4e-4, see engine_modes.rs); f16 keeps 11 significant bits
//! (2⁻¹¹ relative); BC6H of a uniform block: the 10-bit endpoint mode's step over the half's
//! bit pattern, 2⁻⁶ of the value plus the block's offset (sbf::bc; the unit test in
//! probes/src/storage.rs).

use probes::modes::{prepare, Context};
use probes::storage::Storage;
use sbf::envmap::LatLongImage;
use sbf::glam::DVec3;

const Y00: f64 = 0.282_094_791_773_878_14;
const Y1: f64 = 0.488_602_511_902_919_9;

fn ctx(storage: Storage) -> Context {
    let a = [1.0 + 1.0 / 3.0, 0.6 + 1e-3, 0.3 + 1.0 / 7.0];
    let b = DVec3::new(0.3, 0.45, -0.2);
    let map = LatLongImage::from_fn(128, 64, |d| a.map(|ak| ak * (1.0 + b.dot(d)))).unwrap();
    let mut c = Context::new(map);
    c.storage = storage;
    c
}

/// SH L1 E/π at `n` from coefficients (Y₁ₘ = √(3/4π)·(y, z, x)).
fn sh_l1_irradiance(c: &[[f64; 3]], n: DVec3) -> [f64; 3] {
    let y = [Y00, Y1 * n.y, Y1 * n.z, Y1 * n.x];
    [0, 1, 2].map(|k| c[0][k] * y[0] + (2.0 / 3.0) * (1..4).map(|i| c[i][k] * y[i]).sum::<f64>())
}

#[test]
fn sh_l1_reconstructs_from_its_stored_coefficients() {
    let a = [1.0 + 1.0 / 3.0, 0.6 + 1e-3, 0.3 + 1.0 / 7.0];
    let b = [0.45, -0.2, 0.3]; // (b_y, b_z, b_x)
    let exact: Vec<[f64; 3]> =
        (0..4)
            .map(|i| {
                a.map(|ak| {
                    if i == 0 {
                        2.0 * std::f64::consts::PI.sqrt() * ak
                    } else {
                        (4.0 * std::f64::consts::PI / 3.0).sqrt() * ak * b[i - 1]
                    }
                })
            })
            .collect();
    let f32_run = prepare("shl1", &ctx(Storage::F32), 1).unwrap().result;
    for s in Storage::ALL {
        let r = prepare("shl1", &ctx(s), 1).unwrap().result;
        let want_bytes = match s {
            Storage::F32 => 48.0,
            Storage::F16 => 24.0,
            Storage::Bc6h => 4.0,
        };
        assert_eq!(r.storage_bytes(), want_bytes, "{s:?}");
        assert_eq!(r.storage, s);
        for (i, (c, e)) in r.coefficients.iter().zip(&exact).enumerate() {
            for k in 0..3 {
                let offset = exact.iter().map(|x| -x[k]).fold(0.0f64, f64::max);
                let store = match s {
                    Storage::F32 => 0.0,
                    Storage::F16 => e[k].abs() * 2f64.powi(-11),
                    Storage::Bc6h => (e[k] + offset).abs() * 2f64.powi(-6) + 1e-4,
                };
                let tol = 4e-4 * e[0].abs().max(exact[0][k]) + store;
                assert!((c[k] - e[k]).abs() <= tol, "{s:?} c[{i}][{k}] = {} vs {} (tol {tol:.2e})", c[k], e[k]);
                if s == Storage::F16 {
                    assert_eq!(c[k], half::f16::from_f64(c[k]).to_f64(), "f16: c[{i}][{k}] = {} is not a half", c[k]);
                }
            }
        }
        // The image is the stored coefficients' (clamped at 0, as the mode does).
        for (n, got) in ctx(s).dirs.iter().zip(&r.irradiance) {
            let want = sh_l1_irradiance(&r.coefficients, *n).map(|x| x.max(0.0));
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() <= 1e-12 * (1.0 + want[k].abs()), "{s:?} at {n}: {} vs {}", got[k], want[k]);
            }
        }
        if s != Storage::F32 {
            assert_ne!(r.coefficients, f32_run.coefficients, "{s:?}: stored as f32");
        }
    }
}

/// Engine formats keep their own precision at f16 and are compressed under BC6H in the layout
/// their engine ships: Godot's four layers all BC6H (4 × 1 B); Unity's colour BC6H (1 B) with
/// RGB directions BC1 (½ B) or RGBA directions BC7 (1 B).
#[test]
fn engine_formats_count_their_compressed_bytes() {
    for (id, engine, bc) in [
        ("godot-l1", 32.0, 4.0),
        ("godot-l1-legacy", 32.0, 4.0),
        ("monosh", 12.0, 1.5),
        ("monosh-linear", 12.0, 1.5),
        ("enlighten", 12.0, 2.0),
        ("enlighten-rgb", 20.0, 4.0),
    ] {
        let mut runs = Vec::new();
        for (s, want) in [(Storage::F32, engine), (Storage::F16, engine), (Storage::Bc6h, bc)] {
            let r = prepare(id, &ctx(s), 1).unwrap().result;
            assert_eq!(r.storage_bytes(), want, "{id} {s:?}");
            runs.push(r);
        }
        // f16 is the engine's own precision (nothing changes); BC6H changes the stored colour
        // (row 0) and the direction textures (the rows after it), and so the image.
        assert_eq!(runs[1].coefficients, runs[0].coefficients, "{id}: f16 changed the engine's own storage");
        assert_ne!(runs[2].coefficients[0], runs[0].coefficients[0], "{id}: the colour was not compressed");
        assert_ne!(runs[2].coefficients[1..], runs[0].coefficients[1..], "{id}: the directions were not compressed");
        assert_ne!(runs[2].irradiance, runs[0].irradiance, "{id}: the image is not the compressed data's");
    }
}

/// Every lobe mode's stored coefficients are halves under f16 (the storage reached it).
#[test]
fn every_coefficient_mode_stores_halves() {
    let c = ctx(Storage::F16);
    for id in ["ac", "shl2", "shl2w", "adrbf", "sg", "sgls", "sgnnls", "ad", "adycocg", "sgpls", "ad9", "sg9h", "h4"] {
        let r = prepare(id, &c, 1).unwrap().result;
        assert!(!r.coefficients.is_empty(), "{id}");
        for v in &r.coefficients {
            for x in v {
                assert_eq!(*x, half::f16::from_f64(*x).to_f64(), "{id}: {x} is not a half");
            }
        }
        assert_eq!(r.storage_bytes(), 2.0 * r.stored_scalars as f64, "{id}");
    }
}

/// The prior estimate's runtime reads c′ = Σ⁻¹G·c: under f16 its image must be that of the
/// stored c′ — different from the f32 image (where storage reached c alone, the image would
/// be unchanged).
#[test]
fn the_prior_estimate_reads_its_stored_vector() {
    let (a, b) = (prepare("sgls", &ctx(Storage::F32), 1).unwrap().result, prepare("sgls", &ctx(Storage::F16), 1).unwrap().result);
    assert_ne!(a.irradiance, b.irradiance);
}
