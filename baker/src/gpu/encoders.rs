//! A GPU bake's state and the CPU's: encoder states as the GPU holds them
//! (`EncoderState`, basis-major) and `sbf`'s progressive encoders, both ways; reading a
//! bake's state back ([`GpuBake::state`]) and uploading a saved one ([`GpuBake::upload`]).

use super::GpuBake;
use crate::accumulate::{BakeConfig, BakeState, Moments};
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
        let lobes = kind.lobes();
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

impl GpuBake<'_> {
    /// Reads the progressive state back (moments as f64, encoder states exactly).
    pub fn state(&self) -> Result<BakeState, String> {
        crate::gpu::buffers::check_cut_traversals(self.gpu, &self.counters_buf)?;
        let m: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&self.gpu.read_back(&self.moments_buf)?);
        let moments = (0..self.items)
            .map(|i| Moments {
                sum: std::array::from_fn(|c| m[3 * i][c] as f64),
                sum_sq: std::array::from_fn(|c| m[3 * i + 1][c] as f64),
                accepted: m[3 * i][3] as u64,
                back_faces: m[3 * i + 1][3] as u64,
                non_finite: m[3 * i + 2][0] as u64,
            })
            .collect();
        let raw: Vec<EncoderState> = bytemuck::pod_collect_to_vec(&self.gpu.read_back(&self.states_buf)?);
        let encoders = encoders_from_raw(&raw, self.items, &self.config, self.sphere)?;
        let (guide_sums, guide_basis) = match &self.guide {
            Some(g) => (
                bytemuck::pod_collect_to_vec(&self.gpu.read_back(&g.sums_buf)?),
                bytemuck::pod_collect_to_vec(&self.gpu.read_back(&g.basis_buf)?),
            ),
            None => (Vec::new(), Vec::new()),
        };
        let filtered = match &self.filter {
            Some(f) => Some(f.state(self.gpu, &self.config)?),
            None => None,
        };
        Ok(BakeState { passes: self.passes, moments, encoders, guide_sums, guide_basis, filtered })
    }

    /// Replaces the GPU state with `state` (resuming a checkpoint).
    pub fn upload(&mut self, state: &BakeState) -> Result<(), String> {
        if state.moments.len() != self.items || state.encoders.len() != self.config.bases.len() {
            return Err("the saved state does not match this bake's targets and bases".into());
        }
        let m: Vec<[f32; 4]> = state
            .moments
            .iter()
            .flat_map(|m| {
                [
                    [m.sum[0] as f32, m.sum[1] as f32, m.sum[2] as f32, m.accepted as f32],
                    [m.sum_sq[0] as f32, m.sum_sq[1] as f32, m.sum_sq[2] as f32, m.back_faces as f32],
                    [m.non_finite as f32, 0.0, 0.0, 0.0],
                ]
            })
            .collect();
        let q = self.gpu.queue();
        q.write_buffer(&self.moments_buf, 0, bytemuck::cast_slice(&m));
        let raw = raw_from_encoders(&state.encoders);
        if !raw.is_empty() {
            q.write_buffer(&self.states_buf, 0, bytemuck::cast_slice(&raw));
        }
        match (&self.filter, &state.filtered) {
            (Some(f), Some(fs)) => f.upload(q, fs)?,
            (None, None) => {}
            _ => return Err("the saved state and this bake differ in filtered accumulation".into()),
        }
        self.passes = state.passes;
        if let Some(g) = &mut self.guide {
            let n = g.clusters as usize * crate::sampling::guiding::BIN_COUNT;
            if state.guide_sums.len() != n || state.guide_basis.len() != n {
                return Err(format!(
                    "the saved state has {} ray-guiding sums, this bake {} clusters × {}",
                    state.guide_sums.len(),
                    g.clusters,
                    crate::sampling::guiding::BIN_COUNT
                ));
            }
            // The stage's distributions from its basis, then the running sums.
            q.write_buffer(&g.basis_buf, 0, bytemuck::cast_slice(&state.guide_basis));
            g.built = false;
            if self.passes >= g.learn_passes {
                q.write_buffer(&g.sums_buf, 0, bytemuck::cast_slice(&state.guide_basis));
                let mut enc = self.gpu.device().create_command_encoder(&Default::default());
                g.record(&mut enc, true);
                g.built = true;
                q.submit([enc.finish()]);
            }
            q.write_buffer(&g.sums_buf, 0, bytemuck::cast_slice(&state.guide_sums));
        }
        self.gpu.wait()
    }
}
