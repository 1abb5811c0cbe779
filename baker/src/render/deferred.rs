//! The deferred path, as current engines light a frame: after the depth pre-pass the
//! raster pass writes a G-buffer (`fs_gbuffer`: the forward fragments' inputs — normal,
//! position, lightmap UV — in f32, and the material with what the pixel shades), then a
//! compute pass over 8×8-pixel tiles shades every pixel from it with the same `shade` of
//! `wgsl/render.wgsl` (`cs_frame`: the frame, rgba16float; `cs_terms`: diffuse and specular
//! apart, as `fs_terms` writes them). Shading in compute runs on all of a GPU's compute
//! units, where the raster pass's fragment work may be confined to its graphics units.

use super::atlas::Atlas;
use super::lighting::Lighting;
use super::raster::{Analysis, Renderer};
use crate::scene::camera::ViewCamera;

/// The G-buffer's targets: normal | u, position | v (f32 bits), material | kind << 30.
const GBUFFER: [wgpu::TextureFormat; 3] = [wgpu::TextureFormat::Rgba32Uint, wgpu::TextureFormat::Rgba32Uint, wgpu::TextureFormat::R32Uint];

/// What the compute pass writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Output {
    /// `cs_frame`: reflected radiance, one rgba16float image (timing).
    Frame,
    /// `cs_terms`: diffuse and specular apart, rgba32uint holding f32 bits (analysis).
    Terms,
}

/// One configuration's deferred frame: the G-buffer pass, the compute pass and their targets.
pub(super) struct Deferred {
    gbuffer_pipeline: wgpu::RenderPipeline,
    compute: wgpu::ComputePipeline,
    gbuffer: Vec<wgpu::Texture>,
    /// The G-buffer's views as render targets.
    targets: Vec<wgpu::TextureView>,
    /// The compute pass's outputs (one for `Frame`, two for `Terms`).
    outputs: Vec<wgpu::Texture>,
    group: wgpu::BindGroup,
    tiles: [u32; 2],
}

impl Deferred {
    /// The passes of `l` at `cam`'s size writing `output`; `fetch_only` as for
    /// [`Renderer::frame_times`].
    pub(super) fn new(r: &Renderer, l: &Lighting, cam: &ViewCamera, output: Output, fetch_only: bool) -> Deferred {
        let d = r.gpu.device();
        let gbuffer_pipeline = r.pipeline(l, Some(("fs_gbuffer", &GBUFFER)), fetch_only);
        let read = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let gbuffer: Vec<wgpu::Texture> =
            GBUFFER.iter().map(|f| image(d, cam, *f, read | wgpu::TextureUsages::RENDER_ATTACHMENT)).collect();
        let (entry, formats): (&str, &[(u32, wgpu::TextureFormat)]) = match output {
            Output::Frame => ("cs_frame", &[(3, wgpu::TextureFormat::Rgba16Float)]),
            Output::Terms => ("cs_terms", &[(4, wgpu::TextureFormat::Rgba32Uint), (5, wgpu::TextureFormat::Rgba32Uint)]),
        };
        let outputs: Vec<wgpu::Texture> =
            formats.iter().map(|(_, f)| image(d, cam, *f, wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC)).collect();
        let mut entries: Vec<wgpu::BindGroupLayoutEntry> = (0..3)
            .map(|binding| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            })
            .collect();
        entries.extend(formats.iter().map(|(binding, format)| wgpu::BindGroupLayoutEntry {
            binding: *binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format: *format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        }));
        let gbuffer_layout =
            d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("render G-buffer"), entries: &entries });
        let layout = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("render deferred"),
            bind_group_layouts: &[Some(&r.group_layout), Some(&gbuffer_layout)],
            immediate_size: 0,
        });
        let constants = r.constants(l, fetch_only);
        let compute = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&layout),
            module: &r.module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
            cache: None,
        });
        let views: Vec<wgpu::TextureView> = gbuffer.iter().chain(&outputs).map(|t| t.create_view(&Default::default())).collect();
        let bindings: Vec<u32> = (0..3).chain(formats.iter().map(|(b, _)| *b)).collect();
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("render G-buffer"),
            layout: &gbuffer_layout,
            entries: &bindings
                .iter()
                .zip(&views)
                .map(|(b, v)| wgpu::BindGroupEntry { binding: *b, resource: wgpu::BindingResource::TextureView(v) })
                .collect::<Vec<_>>(),
        });
        let targets = gbuffer.iter().map(|t| t.create_view(&Default::default())).collect();
        Deferred { gbuffer_pipeline, compute, gbuffer, targets, outputs, group, tiles: [cam.width.div_ceil(8), cam.height.div_ceil(8)] }
    }

    /// Records the depth pre-pass (timestamp `i` of `timestamps` at its beginning), the
    /// G-buffer pass and the compute pass (timestamps `i + 1` and `i + 2` at its beginning
    /// and end).
    pub(super) fn record(
        &self,
        r: &Renderer,
        enc: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        depth_pipeline: &wgpu::RenderPipeline,
        depth: &wgpu::TextureView,
        timestamps: Option<(&wgpu::QuerySet, u32)>,
    ) {
        r.record(enc, group, depth_pipeline, depth, &[(&self.gbuffer_pipeline, self.targets.iter().collect())], timestamps, None);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("render deferred shading"),
            timestamp_writes: timestamps.map(|(q, i)| wgpu::ComputePassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(i + 1),
                end_of_pass_write_index: Some(i + 2),
            }),
        });
        pass.set_pipeline(&self.compute);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, &self.group, &[]);
        pass.dispatch_workgroups(self.tiles[0], self.tiles[1], 1);
    }
}

/// A G-buffer target or a compute pass's output, the camera's size.
fn image(d: &wgpu::Device, cam: &ViewCamera, format: wgpu::TextureFormat, usage: wgpu::TextureUsages) -> wgpu::Texture {
    d.create_texture(&wgpu::TextureDescriptor {
        label: Some("render deferred"),
        size: wgpu::Extent3d { width: cam.width, height: cam.height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl Renderer<'_> {
    /// [`Renderer::analysis`] on the deferred path: the compute pass's diffuse and specular,
    /// and the G-buffer's inputs it shaded.
    pub fn analysis_deferred(&self, l: &Lighting, atlas: &Atlas, cam: &ViewCamera) -> Result<Analysis, String> {
        let (group, _frame) = self.bind(l, atlas, cam)?;
        let depth_pipeline = self.pipeline(l, None, false);
        let depth = self.target(cam, wgpu::TextureFormat::Depth32Float, "render depth").create_view(&Default::default());
        let pass = Deferred::new(self, l, cam, Output::Terms, false);
        let mut enc = self.gpu.device().create_command_encoder(&Default::default());
        pass.record(self, &mut enc, &group, &depth_pipeline, &depth, None);
        self.gpu.queue().submit([enc.finish()]);
        let read = |t: &wgpu::Texture| self.read_rgba32(t);
        Ok(Analysis {
            width: cam.width as usize,
            height: cam.height as usize,
            diffuse: read(&pass.outputs[0])?,
            specular: read(&pass.outputs[1])?,
            normal_u: read(&pass.gbuffer[0])?,
            position_v: read(&pass.gbuffer[1])?,
        })
    }
}
