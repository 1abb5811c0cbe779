//! Ray guiding on the GPU (\[HWRTL\]): the learning records of each pass, the learned sums
//! and distributions, and the gather and build kernels.

use super::kernel::{guide_build_sources, GuideBuild};
use crate::accumulate::Targets;
use wgpu::util::DeviceExt;

/// Ray guiding on the GPU: the per-pass learning records, the learned sums, the
/// distributions, and the gather and build kernels (`wgsl/guide_build.wgsl`).
#[derive(Debug)]
pub(crate) struct GuideGpu {
    pub(crate) gather: wgpu::ComputePipeline,
    pub(crate) gather_bind: wgpu::BindGroup,
    pub(crate) build: wgpu::ComputePipeline,
    pub(crate) build_bind: wgpu::BindGroup,
    pub(crate) sums_buf: wgpu::Buffer,
    /// The sums the current stage's distributions were built from.
    pub(crate) basis_buf: wgpu::Buffer,
    pub(crate) rec_buf: wgpu::Buffer,
    pub(crate) dist_buf: wgpu::Buffer,
    pub(crate) clusters: u32,
    pub(crate) learn_passes: u64,
    /// The distributions were built from the sums.
    pub(crate) built: bool,
    pub(crate) path: GuideBuild,
}

/// Workgroups for `n` threads of `wg` each, as a 2D grid within the 65 535 limit.
pub(crate) fn grid(n: u32, wg: u32) -> (u32, u32) {
    let g = n.div_ceil(wg);
    if g <= 65535 {
        (g, 1)
    } else {
        (65535, g.div_ceil(65535))
    }
}

impl GuideGpu {
    /// Ray guiding of a bake of `targets`: zeroed records, sums and distributions for its
    /// clusters, and the kernels for this device's subgroup sizes.
    pub(crate) fn for_bake(
        d: &wgpu::Device,
        targets: &Targets,
        g: crate::sampling::guiding::GuidingOptions,
        subgroup_sizes: Option<(u32, u32)>,
    ) -> Result<Self, String> {
        use crate::sampling::guiding::{BIN_COUNT, CDF_LEN};
        let storage = |label: &str, bytes: &[u8], extra| super::buffers::storage(d, label, bytes, extra);
        let rw = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let (items, clusters) = (targets.items.len(), targets.cluster_count);
        let rec = storage("guide records", &vec![0xffu8; items * 24], wgpu::BufferUsages::empty());
        let dist = storage("guide distributions", &vec![0u8; clusters * CDF_LEN * 4], wgpu::BufferUsages::COPY_SRC);
        let sums = storage("guide sums", &vec![0u8; clusters * BIN_COUNT * 4], rw);
        GuideGpu::new(d, targets, g, rec, dist, sums, subgroup_sizes)
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        d: &wgpu::Device,
        targets: &Targets,
        opts: crate::sampling::guiding::GuidingOptions,
        rec_buf: wgpu::Buffer,
        dist_buf: wgpu::Buffer,
        sums_buf: wgpu::Buffer,
        subgroup_sizes: Option<(u32, u32)>,
    ) -> Result<GuideGpu, String> {
        use crate::sampling::guiding::BIN_COUNT;
        let clusters = targets.cluster_count as u32;
        // CSR of the clusters' items in ascending item order.
        let mut offsets = vec![0u32; clusters as usize + 1];
        for c in &targets.clusters {
            offsets[*c as usize + 1] += 1;
        }
        for k in 0..clusters as usize {
            offsets[k + 1] += offsets[k];
        }
        let mut fill = offsets.clone();
        let mut members = vec![0u32; targets.clusters.len()];
        for (i, c) in targets.clusters.iter().enumerate() {
            members[fill[*c as usize] as usize] = i as u32;
            fill[*c as usize] += 1;
        }
        offsets.extend(members);
        let csr = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("guide clusters"),
            contents: bytemuck::cast_slice(&offsets),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let params = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("guide params"),
            contents: bytemuck::cast_slice(&[clusters, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // Subgroup scans need every row of 16 bins inside one subgroup.
        let path = match subgroup_sizes {
            Some((min, _)) if min >= crate::sampling::guiding::BINS as u32 => GuideBuild::Subgroup,
            _ => GuideBuild::Workgroup,
        };
        let module = |label: &str, src: String| {
            d.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(src.into()) })
        };
        let (fallback_src, subgroup_src) = guide_build_sources()?;
        let fallback = module("guide_build", fallback_src);
        let pipe = |m: &wgpu::ShaderModule, entry: &str| super::compute_pipeline(d, m, entry);
        let gather = pipe(&fallback, "guide_gather");
        let build = match path {
            GuideBuild::Subgroup => {
                let m = module("guide_build_subgroup", subgroup_src);
                pipe(&m, "guide_build")
            }
            GuideBuild::Workgroup => pipe(&fallback, "guide_build"),
        };
        let bind = |p: &wgpu::ComputePipeline, e: &[(u32, &wgpu::Buffer)]| {
            let entries: Vec<wgpu::BindGroupEntry> =
                e.iter().map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() }).collect();
            d.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &p.get_bind_group_layout(0), entries: &entries })
        };
        let gather_bind = bind(&gather, &[(0, &params), (1, &csr), (2, &rec_buf), (3, &sums_buf)]);
        let build_bind = bind(&build, &[(0, &params), (3, &sums_buf), (4, &dist_buf)]);
        debug_assert_eq!(sums_buf.size(), (clusters as usize * BIN_COUNT * 4).max(4) as u64);
        let basis_buf = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("guide basis"),
            size: sums_buf.size(),
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(GuideGpu {
            basis_buf,
            gather,
            gather_bind,
            build,
            build_bind,
            sums_buf,
            rec_buf,
            dist_buf,
            clusters,
            learn_passes: opts.learn_passes,
            built: false,
            path,
        })
    }

    /// Records the build and the copy of the sums it used into the stage's basis.
    pub(crate) fn record_build(&self, enc: &mut wgpu::CommandEncoder) {
        self.record(enc, true);
        enc.copy_buffer_to_buffer(&self.sums_buf, 0, &self.basis_buf, 0, self.sums_buf.size());
    }

    /// Records the gather (after a learning pass) or the build into `enc`.
    pub(crate) fn record(&self, enc: &mut wgpu::CommandEncoder, build: bool) {
        let mut pass = enc.begin_compute_pass(&Default::default());
        if build {
            let g = grid(self.clusters, 1);
            pass.set_pipeline(&self.build);
            pass.set_bind_group(0, &self.build_bind, &[]);
            pass.dispatch_workgroups(g.0, g.1, 1);
        } else {
            let g = grid(self.clusters, 64);
            pass.set_pipeline(&self.gather);
            pass.set_bind_group(0, &self.gather_bind, &[]);
            pass.dispatch_workgroups(g.0, g.1, 1);
        }
    }
}
