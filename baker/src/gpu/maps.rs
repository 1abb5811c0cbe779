//! The materials' texture maps for the GPU kernels (`wgsl/maps.wgsl`, composed where the
//! scene has maps): every material's factors and map references, the textures' headers
//! and texels, and per BVH triangle its texture coordinates and its NEE share — one u32
//! buffer, laid out as maps.wgsl reads it.

use crate::estimator::trace::{mean_emission, Tracer};
use crate::scene::texture::{Filter, Wrap};

/// Words per material, per map reference and per triangle (maps.wgsl's MAT_WORDS,
/// MAP_WORDS, TRI_WORDS).
const MAT_WORDS: usize = 36;
const TRI_WORDS: usize = 14;

/// The maps buffer of `tracer`'s scene (see maps.wgsl for the layout).
pub(crate) fn maps_data(tracer: &Tracer) -> Vec<u32> {
    let scene = tracer.scene;
    let f = f32::to_bits;
    let mut out = vec![0u32; 4];
    out[0] = out.len() as u32;
    for m in &scene.materials {
        let b = m.base_color;
        let e = m.emissive;
        out.extend([f(b.x), f(b.y), f(b.z), f(m.metallic), f(m.roughness), f(m.specular), f(e.x), f(e.y), f(e.z)]);
        out.push(!m.maps.is_empty() as u32);
        for r in [m.maps.base_color, m.maps.metallic_roughness, m.maps.emissive] {
            match r {
                None => out.extend([0u32; 8]),
                Some(r) => {
                    out.extend([r.texture as u32 + 1, r.texcoord]);
                    out.extend(r.transform.iter().flatten().map(|x| f(*x)));
                }
            }
        }
        // The alpha mask's cutoff (−1: none) and the base colour factor's alpha.
        let (cutoff, alpha) = m.maps.mask.map_or((-1.0, 1.0), |k| (k.cutoff, k.factor));
        out.extend([f(cutoff), f(alpha)]);
    }
    debug_assert_eq!(out.len(), 4 + MAT_WORDS * scene.materials.len());
    out[1] = out.len() as u32;
    let mut first = 0u32;
    for t in &scene.textures {
        let wrap = |w: Wrap| match w {
            Wrap::Repeat => 0u32,
            Wrap::Clamp => 1,
            Wrap::Mirror => 2,
        };
        let nearest = (t.filter == Filter::Nearest) as u32;
        out.extend([first, t.width, t.height, wrap(t.wrap[0]) | wrap(t.wrap[1]) << 2 | nearest << 4]);
        first += t.texels.len() as u32;
    }
    out[2] = out.len() as u32;
    for tri in &tracer.bvh.tris {
        let mesh = &scene.meshes[tri.mesh as usize];
        let idx = mesh.indices[tri.prim as usize];
        let mut present = 0u32;
        for (set, uv) in [mesh.uv.as_ref(), mesh.lightmap_uv.as_ref()].into_iter().enumerate() {
            match uv {
                Some(uv) => {
                    present |= 1 << set;
                    out.extend(idx.iter().flat_map(|i| [f(uv[*i as usize].x), f(uv[*i as usize].y)]));
                }
                None => out.extend([0u32; 6]),
            }
        }
        out.push(present);
        let m = &scene.materials[tri.material as usize];
        let share =
            if m.maps.emissive.is_some() { crate::scene::lights::luminance(mean_emission(scene, tri)).max(1e-12) as f32 } else { 0.0 };
        out.push(f(share));
    }
    debug_assert_eq!(out.len() as u32 - out[2], (TRI_WORDS * tracer.bvh.tris.len()) as u32);
    out[3] = out.len() as u32;
    for t in &scene.textures {
        out.extend(t.texels.iter().map(|p| u32::from_le_bytes(*p)));
    }
    out
}
