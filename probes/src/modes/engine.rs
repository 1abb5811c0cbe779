//! The directional lightmap formats engines ship (`sbf::recon::engine`) as comparison
//! modes: Godot's L1 SH (≥ 4.4 packed, 4.0–4.3 signed), Bakery's MonoSH (its default
//! non-linear decode and the linear one) and Enlighten's single- and RGB-direction maps. Each
//! fits SH L1 to the map (the `shl1` projection), encodes it as its engine does, rounds every
//! stored value to the engine's precision (colour f16; directions 8-bit, or f16 for Godot)
//! and decodes with the engine's shader — so the error includes the format's storage. Under
//! `--storage bc6h` the textures are stored in the layout the engine ships
//! (`EngineFormat::compressed`: Godot's four layers all BC6H, 4 B/texel), and the bytes
//! reported are that layout's. Enlighten keeps the exact E/π at its baking normal, the probe's "up"
//! (+Y in the map, the hemisphere domain's normal), and its direction is the radiance's
//! mean over the sphere (a probe sees all of it); its encode is charged the one exact
//! irradiance it needs.

use super::common::{eval_cost, timed, Prepared};
use super::context::Context;
use crate::cost::{CostJob, EncodeJob};
use crate::reference;
use sbf::glam::DVec3;
use sbf::recon::engine::{self, EngineFormat, EnlightenInput, L1Irradiance, Moments, Texel};
use sbf::solve::moments;
use sbf::ShBasis;

/// The format of an engine-format mode id.
pub fn format(id: &str) -> Option<EngineFormat> {
    EngineFormat::ALL.into_iter().find(|f| f.id() == id)
}

/// The probe's baking normal for the Enlighten formats (world +Y: `modes::tangent_to_world`'s
/// image of the tangent normal).
pub const BAKING_NORMAL: DVec3 = DVec3::Y;

/// What an engine-format mode produced.
#[derive(Debug)]
pub struct EngineRun<'a> {
    /// Basis text for the report (format, bytes per texel, clamped values).
    pub basis: String,
    /// The stored values: the colour, then each unit texture's RGB, then (Enlighten) the
    /// rescaling factors of the unit textures.
    pub stored: Vec<[f64; 3]>,
    pub irradiance: Vec<[f64; 3]>,
    pub encode: EncodeJob<'a>,
    pub eval: Option<CostJob<'a>>,
    pub scalars: usize,
    pub bytes: f64,
    /// Fraction of output texels whose decode hit the format's clamp at 0 (MonoSH's `max`).
    pub clamped_negative_fraction: Option<f64>,
}

/// The stored values as RGB rows (see [`EngineRun::stored`]).
fn rows(format: EngineFormat, t: &Texel) -> Vec<[f64; 3]> {
    let n = format.unit_textures();
    let mut out = vec![t.colour];
    out.extend(t.unit[..n].iter().map(|u| [u[0], u[1], u[2]]));
    if format.unit_channels() == 4 {
        let mut w = [0.0; 3];
        for (k, u) in t.unit[..n].iter().enumerate() {
            w[k] = u[3];
        }
        out.push(w);
    }
    out
}

/// Runs an engine-format mode (see the module docs).
pub fn prepare<'a>(format: EngineFormat, ctx: &'a Context, repeats: usize) -> Result<EngineRun<'a>, String> {
    let sh = ShBasis::new(1).map_err(|e| e.to_string())?;
    let enlighten = matches!(format, EngineFormat::Enlighten | EngineFormat::EnlightenRgb);
    let (enc, encode) = timed(repeats, move || {
        let m = moments(&sh, &ctx.samples);
        let rgb: [[f64; 4]; 3] = [0, 1, 2].map(|k| [m[(0, k)], m[(1, k)], m[(2, k)], m[(3, k)]]);
        let input = enlighten.then(|| EnlightenInput {
            normal: BAKING_NORMAL,
            irradiance: reference::irradiance_at(&ctx.map, BAKING_NORMAL),
            moments: Moments::sphere(&rgb),
        });
        engine::encode(format, &L1Irradiance::from_sh(&rgb), input.as_ref())
    });
    let enc = enc.ok_or("an Enlighten format without its input")?;
    let mut stored = enc.texel.stored(format);
    // Under --storage bc6h the engine's textures compressed in the layout it ships (the
    // colour BC6H; the other textures BC6H for Godot, BC1 (RGB) or BC7 (RGBA) for Unity's);
    // f16 and f32 leave the engine's own precision.
    let storage = ctx.storage;
    let alpha = format.unit_channels() == 4;
    let n = format.unit_textures();
    stored.colour = storage.store(&[stored.colour])[0];
    let layout = format.compressed();
    if matches!(layout.units, engine::BlockFormat::Bc6hUf16 | engine::BlockFormat::Bc6hSf16) {
        let rgb: Vec<[f64; 3]> = stored.unit[..n].iter().map(|u| [u[0], u[1], u[2]]).collect();
        for (u, s) in stored.unit[..n].iter_mut().zip(storage.store(&rgb)) {
            u[..3].copy_from_slice(&s);
        }
    } else {
        let units = storage.store_unorm(&stored.unit[..n], alpha);
        stored.unit[..n].copy_from_slice(&units);
    }
    let bytes = match storage {
        crate::storage::Storage::Bc6h => format.compressed_bytes(layout),
        _ => format.engine_bytes() as f64,
    };
    let (irradiance, eval) = eval_cost(ctx, move |d| engine::decode(format, &stored, d));
    // MonoSH's decode clamps at 0: the texels where it did (the linear value was negative).
    let clamped_negative_fraction = matches!(format, EngineFormat::MonoSh | EngineFormat::MonoShLinear).then(|| {
        let nl1 = DVec3::new(stored.unit[0][0], stored.unit[0][1], stored.unit[0][2]) * 2.0 - DVec3::ONE;
        let neg = ctx.dirs.iter().filter(|d| stored.colour.iter().any(|l0| l0 + 2.0 * l0 * nl1.dot(**d) < 0.0)).count();
        neg as f64 / ctx.dirs.len().max(1) as f64
    });
    let clamp_note = if enc.clamped > 0 { format!(", {} stored values clamped", enc.clamped) } else { String::new() };
    Ok(EngineRun {
        basis: format!("{} ({}; {bytes} B/texel as the engine stores it{clamp_note})", format.id(), format.engine_short()),
        stored: rows(format, &stored),
        irradiance,
        encode,
        eval,
        scalars: format.scalars(),
        bytes,
        clamped_negative_fraction,
    })
}

/// Runs engine-format mode `id` up to its cost measurement ([`super::prepare`]).
pub(super) fn mode<'a>(id: &'static str, ctx: &'a Context, repeats: usize) -> Result<Prepared<'a>, String> {
    let format = format(id).ok_or_else(|| format!("mode '{id}' is not an engine format"))?;
    let e = prepare(format, ctx, repeats)?;
    let mut r = super::common::mk!(id, ctx;
        e.basis,
        "SH L1 projection, encoded and stored as the engine does",
        e.stored,
        Vec::new(),
        None,
        e.irradiance,
        e.encode,
        e.eval,
    );
    r.result.stored_scalars = e.scalars;
    r.result.engine_bytes = Some(e.bytes);
    r.result.clamped_negative_fraction = e.clamped_negative_fraction;
    Ok(r)
}
