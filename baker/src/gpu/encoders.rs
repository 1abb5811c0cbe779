//! Encoder states as the GPU holds them (`EncoderState`, basis-major) and `sbf`'s
//! progressive encoders, both ways.

use crate::accumulate::BakeConfig;
use shaders::progressive::EncoderState;

/// Encoder states as the GPU holds them (`n` per basis, basis-major) → sbf encoders.
pub(crate) fn encoders_from_raw(
    raw: &[EncoderState],
    n: usize,
    config: &BakeConfig,
    sphere: bool,
) -> Result<Vec<Vec<sbf::solve::ProgressiveEncoder<f32>>>, String> {
    let mut encoders = Vec::new();
    for (b, kind) in config.bases.iter().enumerate() {
        let lobes = kind.basis().len();
        let opts = config.encoder_options(*kind, sphere);
        let mut encs = Vec::with_capacity(n);
        for st in &raw[b * n..(b + 1) * n] {
            let amp: Vec<[f64; 3]> = st.coefficients(lobes).iter().map(|c| c.map(|x| x as f64)).collect();
            let integ: Vec<f64> = st.integrals(lobes).iter().map(|x| *x as f64).collect();
            encs.push(
                sbf::solve::ProgressiveEncoder::from_state(opts.clone(), &amp, &integ, st.total_weight as f64, st.samples as u64)
                    .map_err(|e| format!("GPU encoder state {}: {e}", encs.len()))?,
            );
        }
        encoders.push(encs);
    }
    Ok(encoders)
}

/// sbf encoders → the GPU's encoder states (basis-major).
pub(crate) fn raw_from_encoders(encoders: &[Vec<sbf::solve::ProgressiveEncoder<f32>>]) -> Vec<EncoderState> {
    let mut raw = Vec::new();
    for encs in encoders {
        for e in encs {
            let mut st: EncoderState = bytemuck::Zeroable::zeroed();
            let c = e.coefficients();
            for (i, g) in e.integrals().iter().enumerate() {
                st.lobes[i] = [c[(i, 0)] as f32, c[(i, 1)] as f32, c[(i, 2)] as f32, *g as f32];
            }
            st.total_weight = e.total_weight() as f32;
            st.samples = e.sample_count() as u32;
            raw.push(st);
        }
    }
    raw
}
