//! The GPU pass (wgpu): the scene's triangles (position, vertex normal, lightmap UV in
//! atlas texels, material) drawn from the camera — a depth pre-pass, then forward shading
//! with depth test `Equal` (each pixel shaded once) — by `wgsl/render.wgsl` appended to
//! the runtime library composed by the `shaders` crate. The configuration (basis, path)
//! is chosen by pipeline-overridable constants; the lightmap is a texture array (a layer
//! per lobe, rgba32float or rgba16float) read by `textureLoad` and interpolated by hand,
//! as the CPU twin does — or, with [`LightmapFilter::Hardware`], through the sampler's
//! bilinear filter as engines read it. Three fragment entry points share the shading: `fs_frame` (the
//! engine's frame, one rgba16float target; timed by timestamp queries), `fs_terms`
//! (diffuse and specular apart) and `fs_surface` (what the rasteriser interpolated, so
//! that the CPU twin shades the very same inputs). The deferred path (`super::deferred`)
//! and the frame times (`super::timing`) build on this pass.

use super::atlas::Atlas;
use super::bindings::{depth_range, layouts, lightmap_sampler, material_rows, no_lobe_table, probe_rows, scene_vertices, Lattice, Vertex};
use super::lighting::{lobe_axes, Encoding, Lighting, LightmapFilter, Storage};
use super::probes::ProbeField;
use crate::accumulate::BasisId;
use crate::layout::lightmap::Lightmap;
use crate::scene::camera::ViewCamera;
use crate::scene::Scene;
use sbf::profile::SpecularPath;
use shaders::gpu::Gpu;
use wgpu::util::DeviceExt;

const RENDER_WGSL: &str = include_str!("wgsl/render.wgsl");

/// The `shaders` features the render shader calls: the B-spline lightmap filter, and every
/// lightmap basis's irradiance and both specular paths, from the registry (the pipeline
/// constants select one; the rest is folded away).
pub(crate) fn features() -> String {
    let mut f = vec!["lightmap-bicubic"];
    for b in sbf::BasisId::lightmap() {
        let i = b.info();
        f.extend(i.irradiance_feature.into_iter().chain(i.specular.iter().filter_map(|s| s.0)));
    }
    f.sort_unstable();
    f.dedup();
    f.join(",")
}

/// The full render module: the composed runtime library, then `render.wgsl`; validated.
pub fn module_source() -> Result<String, String> {
    let cfg = shaders::compose::Config::parse(&features())?;
    let roots: Vec<&str> = cfg.features.iter().flat_map(|f| f.roots().iter().copied()).chain(["tangent_frame"]).collect();
    let lib = shaders::compose::compose_roots(cfg.clone(), &roots)?;
    let src = format!("{}\n{RENDER_WGSL}", lib.source);
    shaders::export::validate(&src).map_err(|e| format!("render shader: {e}"))?;
    Ok(src)
}

/// WGSL `Frame`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameGpu {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    atlas: [u32; 4],
    axes: [[f32; 4]; 12],
    grid_dims: [u32; 4],
    grid_first: [f32; 4],
    grid_last: [f32; 4],
}

/// What `fs_terms` and `fs_surface` wrote, per pixel (row-major, y down).
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    pub width: usize,
    pub height: usize,
    /// xyz diffuse; w the material index + ½ (−1: nothing lightmapped or no surface).
    pub diffuse: Vec<[f32; 4]>,
    /// xyz specular; w 1 where shaded from the lightmap, 2 from the probes, 0 neither.
    pub specular: Vec<[f32; 4]>,
    /// xyz the interpolated normal (unnormalised); w lightmap u.
    pub normal_u: Vec<[f32; 4]>,
    /// xyz the world position; w lightmap v.
    pub position_v: Vec<[f32; 4]>,
}

/// The scene on the GPU and the render module.
#[derive(Debug)]
pub struct Renderer<'g> {
    pub(super) gpu: &'g Gpu,
    pub(super) module: wgpu::ShaderModule,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    materials: wgpu::Buffer,
    /// The scene's bounds (near and far planes per camera).
    bounds: (sbf::glam::Vec3, sbf::glam::Vec3),
    pub(super) group_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    /// SH L2 probes (9 rows of 4 floats per probe) and the lattice, or one zero row.
    probes: wgpu::Buffer,
    grid: Lattice,
    dfg: wgpu::Texture,
    filter: LightmapFilter,
    sampler: wgpu::Sampler,
    /// The per-lobe GGX tables' trilinear sampler.
    lobe_sampler: wgpu::Sampler,
}

impl<'g> Renderer<'g> {
    /// Uploads the scene's triangles (with `lm`'s atlas UVs), materials and the probes that
    /// shade its dynamic objects (None: they stay black).
    pub fn new(gpu: &'g Gpu, scene: &Scene, lm: &Lightmap, probes: Option<&ProbeField>) -> Result<Renderer<'g>, String> {
        let d = gpu.device();
        let src = module_source()?;
        let module =
            d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("render"), source: wgpu::ShaderSource::Wgsl(src.into()) });
        let (verts, (lo, hi)) = scene_vertices(scene, lm)?;
        let vertices = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("render vertices"),
            contents: bytemuck::cast_slice(&verts),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let mats = material_rows(scene);
        let materials = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("render materials"),
            contents: bytemuck::cast_slice(&mats),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let (group_layout, layout) = layouts(d, false);
        let (rows, grid) = probe_rows(probes);
        let probes = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("render probes"),
            contents: bytemuck::cast_slice(&rows),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let dfg = gpu.lut_texture(sbf::recon::tables::dfg());
        Ok(Renderer {
            gpu,
            module,
            vertices,
            vertex_count: verts.len() as u32,
            materials,
            bounds: (lo, hi),
            group_layout,
            layout,
            probes,
            grid,
            dfg,
            filter: LightmapFilter::Exact,
            sampler: lightmap_sampler(d, LightmapFilter::Exact),
            lobe_sampler: gpu.linear_clamp_sampler(),
        })
    }

    /// The renderer reading its lightmaps with `filter`.
    pub fn with_filter(mut self, filter: LightmapFilter) -> Renderer<'g> {
        let d = self.gpu.device();
        (self.group_layout, self.layout) = layouts(d, filter.samples());
        self.sampler = lightmap_sampler(d, filter);
        self.filter = filter;
        self
    }

    /// How the lightmap is interpolated.
    pub fn filter(&self) -> LightmapFilter {
        self.filter
    }

    fn depth_range(&self, cam: &ViewCamera) -> (f32, f32) {
        depth_range(self.bounds, cam)
    }

    /// The pipeline constants of `l` (`fetch_only`: the timing variant that only fetches
    /// the lobes).
    pub(super) fn constants(&self, l: &Lighting, fetch_only: bool) -> [(&'static str, f64); 6] {
        // ENCODING: 0 for the plain E/π lightmap, else the basis' GPU slot kind + 1.
        let (enc, lobes) = match l.encoding {
            Encoding::Irradiance => (0, 1),
            Encoding::Basis(b) => (1 + b.gpu_kind().expect("a lightmap basis has a GPU slot kind"), b.lobes()),
        };
        let tables = l.specular == SpecularPath::Tables && !matches!(l.encoding, Encoding::Basis(b) if b.is_sh());
        [
            ("ENCODING", enc as f64),
            ("TABLES", if tables { 1.0 } else { 0.0 }),
            ("LOBES", lobes as f64),
            ("FETCH_ONLY", fetch_only as u8 as f64),
            ("HW_FILTER", (self.filter == LightmapFilter::Hardware) as u8 as f64),
            ("BICUBIC", (self.filter == LightmapFilter::Bicubic) as u8 as f64),
        ]
    }

    /// The bind group of a configuration: frame uniform, materials, lightmap, table(s).
    pub(super) fn bind(&self, l: &Lighting, atlas: &Atlas, cam: &ViewCamera) -> Result<(wgpu::BindGroup, wgpu::Buffer), String> {
        let d = self.gpu.device();
        l.check()?;
        if atlas.lobes.len() != l.lobes() {
            return Err(format!("{}: the atlas has {} lobes, the configuration {}", l.name(), atlas.lobes.len(), l.lobes()));
        }
        let (near, far) = self.depth_range(cam);
        let mut axes = [[0.0f32; 4]; 12];
        for (k, a) in lobe_axes(l.encoding).iter().enumerate() {
            axes[k] = [a.x as f32, a.y as f32, a.z as f32, 0.0];
        }
        let frame = FrameGpu {
            view_proj: cam.view_proj([0.0; 2], near, far).to_cols_array_2d(),
            eye: [cam.eye.x, cam.eye.y, cam.eye.z, l.sg_sharpness as f32],
            atlas: [atlas.width as u32, atlas.height as u32, 0, 0],
            axes,
            grid_dims: self.grid.0,
            grid_first: self.grid.1,
            grid_last: self.grid.2,
        };
        let frame_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("render frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        if self.filter.samples() && l.storage == Storage::F32 && !d.features().contains(wgpu::Features::FLOAT32_FILTERABLE) {
            return Err(format!(
                "{}: this adapter cannot filter rgba32float textures (no FLOAT32_FILTERABLE): use f16 storage or --lightmap-filter exact",
                l.name()
            ));
        }
        let lightmap = self.lightmap_texture(atlas, l.storage)?;
        let lut = match l.encoding {
            Encoding::Basis(b) if b.is_sh() => self.gpu.lut_texture(sbf::recon::tables::dfg()),
            Encoding::Basis(BasisId::Ad9 | BasisId::Ad12) => self.gpu.lut_texture(sbf::recon::tables::ad_specular_2d()),
            _ => self.gpu.rg32_texture("no lut", [1, 1, 1], &[0.0, 0.0]),
        };
        let lobe = match l.encoding {
            Encoding::Basis(BasisId::Sg9 | BasisId::Sg12) if l.specular == SpecularPath::Tables => {
                self.gpu.lobe_texture_filtered(sbf::recon::tables::lobe_ggx_sg6())
            }
            Encoding::Basis(BasisId::Ad9 | BasisId::Ad12) if l.specular == SpecularPath::Tables => {
                self.gpu.lobe_texture_filtered(sbf::recon::tables::lobe_ggx_ad())
            }
            _ => no_lobe_table(d),
        };
        let array = wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() };
        let views = [
            lightmap.create_view(&array),
            lut.create_view(&Default::default()),
            lobe.create_view(&Default::default()),
            self.dfg.create_view(&Default::default()),
        ];
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("render"),
            layout: &self.group_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: self.materials.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&views[0]) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&views[1]) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&views[2]) },
                wgpu::BindGroupEntry { binding: 5, resource: self.probes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::TextureView(&views[3]) },
                wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::Sampler(&self.sampler) },
                wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::Sampler(&self.lobe_sampler) },
            ],
        });
        Ok((group, frame_buf))
    }

    /// The lightmap as a texture array, one layer per lobe (rgba32float or rgba16float).
    fn lightmap_texture(&self, atlas: &Atlas, storage: Storage) -> Result<wgpu::Texture, String> {
        let limits = self.gpu.device().limits();
        if atlas.width as u32 > limits.max_texture_dimension_2d || atlas.height as u32 > limits.max_texture_dimension_2d {
            return Err(format!(
                "atlas {}×{} exceeds the adapter's {} texels a side",
                atlas.width, atlas.height, limits.max_texture_dimension_2d
            ));
        }
        let mut stored = atlas.stored(storage)?;
        // At least two layers: wgpu's GL backend makes a one-layer texture a plain 2D
        // texture, which a 2D-array view cannot read. The shader reads LOBES layers only.
        if stored.lobes.len() == 1 {
            stored.lobes.push(vec![[0.0; 3]; atlas.width * atlas.height]);
        }
        let (format, bytes): (wgpu::TextureFormat, Vec<u8>) = match storage {
            Storage::F32 => {
                let v: Vec<f32> = stored.lobes.iter().flat_map(|l| l.iter().flat_map(|t| [t[0], t[1], t[2], 0.0])).collect();
                (wgpu::TextureFormat::Rgba32Float, bytemuck::cast_slice(&v).to_vec())
            }
            Storage::F16 => {
                let v: Vec<u16> = stored
                    .lobes
                    .iter()
                    .flat_map(|l| l.iter().flat_map(|t| [t[0], t[1], t[2], 0.0].map(|x| half::f16::from_f32(x).to_bits())))
                    .collect();
                (wgpu::TextureFormat::Rgba16Float, bytemuck::cast_slice(&v).to_vec())
            }
        };
        Ok(self.gpu.device().create_texture_with_data(
            self.gpu.queue(),
            &wgpu::TextureDescriptor {
                label: Some("lightmap"),
                size: wgpu::Extent3d {
                    width: atlas.width as u32,
                    height: atlas.height as u32,
                    depth_or_array_layers: stored.lobes.len() as u32,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &bytes,
        ))
    }

    /// A pipeline: the depth pre-pass (`fragment` None) or a shading entry point with its
    /// targets (depth test Equal, no depth write).
    pub(super) fn pipeline(
        &self,
        l: &Lighting,
        fragment: Option<(&str, &[wgpu::TextureFormat])>,
        fetch_only: bool,
    ) -> wgpu::RenderPipeline {
        let constants = self.constants(l, fetch_only);
        let options = wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let targets: Vec<Option<wgpu::ColorTargetState>> = fragment
            .map(|(_, f)| {
                f.iter().map(|f| Some(wgpu::ColorTargetState { format: *f, blend: None, write_mask: wgpu::ColorWrites::ALL })).collect()
            })
            .unwrap_or_default();
        let depth_only = fragment.is_none();
        self.gpu.device().create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(fragment.map_or("render depth", |f| f.0)),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_main"),
                compilation_options: options.clone(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Uint32, 4 => Float32x3],
                })],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(depth_only),
                depth_compare: Some(if depth_only { wgpu::CompareFunction::Less } else { wgpu::CompareFunction::Equal }),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: fragment.map(|(entry, _)| wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: options.clone(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// A render target of the camera's size.
    pub(super) fn target(&self, cam: &ViewCamera, format: wgpu::TextureFormat, label: &str) -> wgpu::Texture {
        self.gpu.device().create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: cam.width, height: cam.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    }

    /// Records the depth pre-pass, then one shading pass per (pipeline, targets);
    /// timestamps at the pre-pass's beginning (`begin`) and at the last pass's beginning
    /// and end (`timed`: the set and the two indices).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        depth_pipeline: &wgpu::RenderPipeline,
        depth: &wgpu::TextureView,
        shading: &[(&wgpu::RenderPipeline, Vec<&wgpu::TextureView>)],
        begin: Option<(&wgpu::QuerySet, u32)>,
        timed: Option<(&wgpu::QuerySet, u32, u32)>,
    ) {
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("render depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: begin.map(|(q, i)| wgpu::RenderPassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: Some(i),
                    end_of_pass_write_index: None,
                }),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(depth_pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.draw(0..self.vertex_count, 0..1);
        }
        for (k, (pipeline, views)) in shading.iter().enumerate() {
            let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = views
                .iter()
                .map(|v| {
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        // Alpha: the bits of −1.0f32 in the rgba32uint analysis targets (no surface).
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color { r: 0.0, g: 0.0, b: 0.0, a: f64::from((-1.0f32).to_bits()) }),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                })
                .collect();
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("render shading"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: timed.filter(|_| k + 1 == shading.len()).map(|(q, b, e)| wgpu::RenderPassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: Some(b),
                    end_of_pass_write_index: Some(e),
                }),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.draw(0..self.vertex_count, 0..1);
        }
    }

    /// Reads an rgba32uint target holding f32 bits back.
    pub(super) fn read_rgba32(&self, tex: &wgpu::Texture) -> Result<Vec<[f32; 4]>, String> {
        let (w, h) = (tex.width() as usize, tex.height() as usize);
        let row = (w * 16).div_ceil(256) * 256;
        let buf = self.gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("render read-back"),
            size: (row * h) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut enc = self.gpu.device().create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            tex.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buf,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row as u32), rows_per_image: None },
            },
            tex.size(),
        );
        self.gpu.queue().submit([enc.finish()]);
        let bytes = self.gpu.read_back(&buf)?;
        let mut out = Vec::with_capacity(w * h);
        for y in 0..h {
            let r: &[u32] = bytemuck::cast_slice(&bytes[y * row..y * row + w * 16]);
            out.extend(r.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]].map(f32::from_bits)));
        }
        Ok(out)
    }

    /// Renders `l` from `cam` into the analysis targets (diffuse and specular apart, and
    /// the interpolated inputs) and reads them back.
    pub fn analysis(&self, l: &Lighting, atlas: &Atlas, cam: &ViewCamera) -> Result<Analysis, String> {
        let (group, _frame) = self.bind(l, atlas, cam)?;
        let f = wgpu::TextureFormat::Rgba32Uint;
        let depth_pipeline = self.pipeline(l, None, false);
        let terms = self.pipeline(l, Some(("fs_terms", &[f, f])), false);
        let surface = self.pipeline(l, Some(("fs_surface", &[f, f])), false);
        let depth = self.target(cam, wgpu::TextureFormat::Depth32Float, "render depth").create_view(&Default::default());
        let tex: Vec<wgpu::Texture> = (0..4).map(|k| self.target(cam, f, &format!("render analysis {k}"))).collect();
        let views: Vec<wgpu::TextureView> = tex.iter().map(|t| t.create_view(&Default::default())).collect();
        let mut enc = self.gpu.device().create_command_encoder(&Default::default());
        self.record(
            &mut enc,
            &group,
            &depth_pipeline,
            &depth,
            &[(&terms, vec![&views[0], &views[1]]), (&surface, vec![&views[2], &views[3]])],
            None,
            None,
        );
        self.gpu.queue().submit([enc.finish()]);
        let mut out = tex.iter().map(|t| self.read_rgba32(t)).collect::<Result<Vec<_>, _>>()?;
        let (position_v, normal_u, specular, diffuse) = (out.pop().unwrap(), out.pop().unwrap(), out.pop().unwrap(), out.pop().unwrap());
        Ok(Analysis { width: cam.width as usize, height: cam.height as usize, diffuse, specular, normal_u, position_v })
    }
}
