//! GPU frame times of a configuration on either path, from timestamp queries: the whole
//! frame (from the depth pre-pass's beginning) and its shading pass alone — the forward
//! pass, or the deferred path's compute pass.

use super::atlas::Atlas;
use super::deferred::{Deferred, Output};
use super::lighting::{FramePath, Lighting};
use super::raster::Renderer;
use crate::scene::camera::ViewCamera;

impl Renderer<'_> {
    /// GPU times (ms) of frames of `l` on `path` into one rgba16float target, from
    /// timestamp queries — forward: the depth pre-pass and the forward pass; deferred: the
    /// depth pre-pass, the G-buffer pass and the compute pass — `warmup` frames dropped,
    /// then `frames` measured, one submission each: per frame [whole frame, the shading
    /// pass alone (the forward pass; the compute pass)]. None when the adapter has no
    /// timestamp queries. `fetch_only`: the shading fetches the lobes and sums them, no
    /// runtime (the configuration's lightmap-bandwidth floor).
    #[allow(clippy::too_many_arguments)]
    pub fn frame_times(
        &self,
        path: FramePath,
        l: &Lighting,
        atlas: &Atlas,
        cam: &ViewCamera,
        (warmup, frames): (usize, usize),
        fetch_only: bool,
    ) -> Result<Option<Vec<[f64; 2]>>, String> {
        if !self.gpu.timestamps {
            return Ok(None);
        }
        let d = self.gpu.device();
        let (group, _frame) = self.bind(l, atlas, cam)?;
        let total = (warmup + frames) as u32;
        // Per frame: the frame's beginning, the shading pass's beginning, the end of both.
        let queries = d.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("render timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: 3 * total,
        });
        let depth_pipeline = self.pipeline(l, None, false);
        let depth = self.target(cam, wgpu::TextureFormat::Depth32Float, "render depth").create_view(&Default::default());
        match path {
            FramePath::Forward => {
                let shade = self.pipeline(l, Some(("fs_frame", &[wgpu::TextureFormat::Rgba16Float])), fetch_only);
                let colour = self.target(cam, wgpu::TextureFormat::Rgba16Float, "render frame").create_view(&Default::default());
                for k in 0..total {
                    let mut enc = d.create_command_encoder(&Default::default());
                    let (begin, timed) = (Some((&queries, 3 * k)), Some((&queries, 3 * k + 1, 3 * k + 2)));
                    self.record(&mut enc, &group, &depth_pipeline, &depth, &[(&shade, vec![&colour])], begin, timed);
                    self.gpu.queue().submit([enc.finish()]);
                }
            }
            FramePath::Deferred => {
                let pass = Deferred::new(self, l, cam, Output::Frame, fetch_only);
                for k in 0..total {
                    let mut enc = d.create_command_encoder(&Default::default());
                    pass.record(self, &mut enc, &group, &depth_pipeline, &depth, Some((&queries, 3 * k)));
                    self.gpu.queue().submit([enc.finish()]);
                }
            }
        }
        let resolve = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render timestamps"),
            size: 24 * total as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        enc.resolve_query_set(&queries, 0..3 * total, &resolve, 0);
        self.gpu.queue().submit([enc.finish()]);
        let ticks: Vec<u64> = bytemuck::cast_slice(&self.gpu.read_back(&resolve)?).to_vec();
        let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * self.gpu.timestamp_period() as f64 * 1e-6;
        Ok(Some((warmup..total as usize).map(|k| [ms(ticks[3 * k], ticks[3 * k + 2]), ms(ticks[3 * k + 1], ticks[3 * k + 2])]).collect()))
    }
}
