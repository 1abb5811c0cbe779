//! Which adapter a [`Gpu`] is made on when there are several: the first `n` hardware
//! adapters (`--gpus`), or the one at an index (`--gpu-index`, a farm's pinning).

use super::Gpu;

impl Gpu {
    /// One device on each of the first `n` hardware adapters (Vulkan preferred over GL for
    /// the same GPU: adapters are taken in enumeration order, Vulkan first, and a GL adapter
    /// is skipped when a Vulkan one has the same name). Errs, listing what was found, when
    /// fewer than `n` exist.
    pub fn hardware(n: usize) -> Result<Vec<Gpu>, String> {
        let instance = Self::instance();
        let mut adapters = pollster::block_on(instance.enumerate_adapters(Self::backends()));
        adapters.sort_by_key(|a| a.get_info().backend != wgpu::Backend::Vulkan);
        let mut seen: Vec<(String, wgpu::Backend)> = Vec::new();
        let mut software = Vec::new();
        let mut picked = Vec::new();
        for a in adapters {
            let info = a.get_info();
            if info.device_type == wgpu::DeviceType::Cpu {
                software.push(info.name);
                continue;
            }
            if info.backend == wgpu::Backend::Gl && seen.iter().any(|(name, b)| *name == info.name && *b == wgpu::Backend::Vulkan) {
                continue;
            }
            seen.push((info.name.clone(), info.backend));
            picked.push(a);
        }
        if picked.len() < n {
            return Err(format!(
                "{n} GPUs requested, {} hardware adapter(s) found{}",
                picked.len(),
                if seen.is_empty() {
                    String::new()
                } else {
                    format!(": {}", seen.iter().map(|(n, b)| format!("{n} ({b:?})")).collect::<Vec<_>>().join(", "))
                }
            ));
        }
        picked.iter().take(n).map(Self::on).collect()
    }

    /// The adapters in the order [`Gpu::at`] indexes them: hardware ones first (Vulkan before
    /// GL, a GL adapter left out when a Vulkan one has its name), then software rasterisers —
    /// as `--gpus` takes them, so index i is the i-th GPU `--gpus` would use.
    fn ordered() -> Vec<wgpu::Adapter> {
        let instance = Self::instance();
        let mut adapters = pollster::block_on(instance.enumerate_adapters(Self::backends()));
        adapters.sort_by_key(|a| {
            let i = a.get_info();
            (i.device_type == wgpu::DeviceType::Cpu, i.backend != wgpu::Backend::Vulkan)
        });
        let mut seen: Vec<String> = Vec::new();
        adapters
            .into_iter()
            .filter(|a| {
                let i = a.get_info();
                let dup = i.backend == wgpu::Backend::Gl && seen.contains(&i.name);
                if i.backend == wgpu::Backend::Vulkan {
                    seen.push(i.name.clone());
                }
                !dup
            })
            .collect()
    }

    /// A device on the adapter at `index` of this host (a farm pins a shard to the GPU its
    /// scheduler gave it): hardware adapters first, in the order `--gpus` takes them, then
    /// software ones. Errs, listing the adapters, when there is no such index.
    pub fn at(index: usize) -> Result<Gpu, String> {
        let adapters = Self::ordered();
        match adapters.get(index) {
            Some(a) => Self::on(a),
            None => Err(format!(
                "GPU index {index}: this host has {} adapter(s){}",
                adapters.len(),
                if adapters.is_empty() {
                    String::new()
                } else {
                    format!(
                        " — {}",
                        adapters
                            .iter()
                            .enumerate()
                            .map(|(k, a)| {
                                let i = a.get_info();
                                format!("{k}: {} ({:?})", i.name, i.backend)
                            })
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                }
            )),
        }
    }
}
