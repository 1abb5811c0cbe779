//! The tables the kernels bind, as textures: fitgen's 2D tables, the lobe GGX tables (array and
//! filtered 3D layouts), their sampler.

use super::{lobe_filtered_texels, Gpu};
use wgpu::util::DeviceExt;

impl Gpu {
    /// A fitgen 2D table as the `lut: texture_2d<f32>` the library's `lut2_sample` reads:
    /// rg32float, the table's two channels (a one-channel table repeats its value).
    pub fn lut_texture(&self, l: &sbf::recon::lut::Lut2) -> wgpu::Texture {
        let data: Vec<f32> = (0..l.width * l.height)
            .flat_map(|k| {
                let a = l.data[k * l.channels];
                let b = if l.channels > 1 { l.data[k * l.channels + 1] } else { a };
                [a, b]
            })
            .collect();
        self.rg32_texture("lut", [l.width as u32, l.height as u32, 1], &data)
    }

    /// A per-lobe GGX table as the `texture_2d_array<f32>` the library's `lobe_ggx_*`
    /// functions read (x = ψ, y = γ, layer = n·v node × N_√α + √α node; rg32float).
    pub fn lobe_texture(&self, t: &sbf::recon::lobe_ggx::Table) -> wgpu::Texture {
        let g = t.grid;
        self.rg32_texture("lobe_tab", [g.psi as u32, g.gamma as u32, (g.theta_v * g.alpha) as u32], &t.values)
    }

    /// A per-lobe GGX table as the `texture_3d<f32>` the library's `lobe_ggx_filtered_*`
    /// functions sample: rg16float holding the table's values (committed as f16, so exact),
    /// x = √α node × N_ψ + ψ node, y = γ node, z = n·v node.
    pub fn lobe_texture_filtered(&self, t: &sbf::recon::lobe_ggx::Table) -> wgpu::Texture {
        let (size, texels) = lobe_filtered_texels(t);
        self.device.create_texture_with_data(
            &self.queue,
            &wgpu::TextureDescriptor {
                label: Some("lobe_tex3"),
                size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: size[2] },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D3,
                format: wgpu::TextureFormat::Rg16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&texels),
        )
    }

    /// A prefiltered environment map as an engine uploads it: a cube texture (six layers in
    /// `CUBE_FACES` order) of rgba16float with the chain's mips (alpha 1).
    pub fn cube_texture(&self, c: &sbf::recon::prefiltered::PrefilteredCube) -> wgpu::Texture {
        // Layer-major: each face with all its mips.
        let mut data: Vec<u16> = Vec::new();
        for face in 0..6 {
            for (m, mip) in c.mips.iter().enumerate() {
                let n = c.size >> m;
                for t in &mip[face * n * n..(face + 1) * n * n] {
                    data.extend(t.iter().map(|x| half::f16::from_f32(*x).to_bits()));
                    data.push(half::f16::ONE.to_bits());
                }
            }
        }
        self.device.create_texture_with_data(
            &self.queue,
            &wgpu::TextureDescriptor {
                label: Some("env_cube"),
                size: wgpu::Extent3d { width: c.size as u32, height: c.size as u32, depth_or_array_layers: 6 },
                mip_level_count: c.mips.len() as u32,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&data),
        )
    }

    /// Trilinear filtering (linear within and between mips), clamp to edge: how a
    /// prefiltered environment map is sampled.
    pub fn trilinear_sampler(&self) -> wgpu::Sampler {
        self.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("env_smp"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        })
    }

    /// The sampler `lobe_ggx_filtered_lobe` expects: linear in every axis, clamp to edge, mip 0.
    pub fn linear_clamp_sampler(&self) -> wgpu::Sampler {
        self.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("lobe_smp"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        })
    }

    /// An rg32float 2D texture (array: `size[2]` layers) holding `data` (two floats per
    /// texel, layer-major), for sampling by textureLoad.
    pub fn rg32_texture(&self, label: &str, size: [u32; 3], data: &[f32]) -> wgpu::Texture {
        self.device.create_texture_with_data(
            &self.queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: size[2] },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rg32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(data),
        )
    }
}
