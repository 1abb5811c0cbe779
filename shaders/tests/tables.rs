//! The tables as KTX 2.0 files (`shaders::tables`), read back by the `ktx2` crate's
//! reader: the header an engine's loader checks (Vulkan format numbers from the Vulkan
//! specification, written here: R32G32_SFLOAT = 103, R16G16_SFLOAT = 83), one level, the
//! layout key, and every texel equal to the committed table's value at the node the
//! library's WGSL documents for that texel (lut.wgsl, lobe_ggx.wgsl) — indexed here, not
//! through the writer's code. (Once read also by npm's ktx-parse 2.0.0, another reader:
//! same formats, sizes, levels and keys.)

use ktx2::Reader;
use sbf::recon::tables as c;
use shaders::tables::{self, Kind};

const R32G32_SFLOAT: u32 = 103;
const R16G16_SFLOAT: u32 = 83;

fn read(t: &tables::TableTexture) -> (Vec<u8>, ktx2::Header) {
    let bytes = tables::ktx2(t).unwrap();
    let r = Reader::new(&bytes[..]).unwrap_or_else(|e| panic!("{}: not a KTX2 file: {e:?}", t.name));
    let h = r.header();
    assert_eq!(r.levels().len(), 1, "{}: one level", t.name);
    let level = r.levels().next().unwrap();
    assert_eq!(level.uncompressed_byte_length as usize, level.data.len());
    let kv: Vec<(String, Vec<u8>)> = r.key_value_data().map(|(k, v)| (k.to_string(), v.to_vec())).collect();
    assert_eq!(kv.iter().map(|(k, _)| k.as_str()).collect::<Vec<_>>(), ["KTXwriter", "sbf.layout"], "{}", t.name);
    let layout = String::from_utf8(kv[1].1.clone()).unwrap();
    assert!(layout.contains("n·v") && layout.ends_with('\0'), "{}: {layout}", t.name);
    let basic = r.basic_dfd().unwrap_or_else(|| panic!("{}: no basic data format descriptor", t.name));
    assert_eq!(basic.sample_information.len(), 2, "{}: two channels", t.name);
    (level.data.to_vec(), h)
}

fn f32s(b: &[u8]) -> Vec<f32> {
    b.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
}

fn f16s(b: &[u8]) -> Vec<f32> {
    b.chunks_exact(2).map(|c| sbf::luts::format::f16_to_f32(u16::from_le_bytes([c[0], c[1]]))).collect()
}

#[test]
fn two_d_tables_are_rg32float_with_n_dot_v_along_x_and_alpha_along_y() {
    for (name, l) in [("dfg", c::dfg()), ("ad_specular_2d", c::ad_specular_2d())] {
        let t = tables::all().into_iter().find(|t| t.name == name).unwrap();
        let (data, h) = read(&t);
        assert_eq!(h.format.map(|f| f.value()), Some(R32G32_SFLOAT), "{name}");
        assert_eq!((h.pixel_width, h.pixel_height, h.pixel_depth, h.layer_count, h.face_count), (l.width as u32, l.height as u32, 0, 0, 1));
        let v = f32s(&data);
        assert_eq!(v.len(), 2 * l.width * l.height);
        for j in 0..l.height {
            for i in 0..l.width {
                for ch in 0..2 {
                    let want = l.texel(i, j, ch.min(l.channels - 1));
                    assert_eq!(v[2 * (j * l.width + i) + ch], want, "{name} texel ({i}, {j}) channel {ch}");
                }
            }
        }
    }
}

/// The table's node (n·v node i, √α node j, γ node k, ψ node l), channel ch: the table is
/// stored ψ fastest, then γ, √α, n·v (sbf::recon::lobe_ggx::Table).
fn node(t: &sbf::recon::lobe_ggx::Table, i: usize, j: usize, k: usize, l: usize, ch: usize) -> f32 {
    let g = t.grid;
    t.values[2 * (((i * g.alpha + j) * g.gamma + k) * g.psi + l) + ch]
}

#[test]
fn lobe_tables_follow_the_layouts_the_wgsl_documents() {
    for (name, table) in [("lobe_ggx_sg6", c::lobe_ggx_sg6()), ("lobe_ggx_ad", c::lobe_ggx_ad())] {
        let g = table.grid;
        // lobe_ggx.wgsl: x = ψ node, y = γ node, layer = n·v node × N√α + √α node.
        let t = tables::all().into_iter().find(|t| t.name == name).unwrap();
        assert_eq!(t.kind, Kind::D2Array);
        let (data, h) = read(&t);
        assert_eq!(h.format.map(|f| f.value()), Some(R32G32_SFLOAT), "{name}");
        assert_eq!(
            (h.pixel_width, h.pixel_height, h.pixel_depth, h.layer_count),
            (g.psi as u32, g.gamma as u32, 0, (g.theta_v * g.alpha) as u32)
        );
        let v = f32s(&data);
        let (w, hgt) = (g.psi, g.gamma);
        for i in 0..g.theta_v {
            for j in 0..g.alpha {
                for k in 0..g.gamma {
                    for l in 0..g.psi {
                        let layer = i * g.alpha + j;
                        for ch in 0..2 {
                            assert_eq!(
                                v[2 * ((layer * hgt + k) * w + l) + ch],
                                node(table, i, j, k, l, ch),
                                "{name} array ({i}, {j}, {k}, {l})"
                            );
                        }
                    }
                }
            }
        }
        // lobe_ggx.wgsl, the filtered tables: x = √α node × Nψ + ψ node, y = γ node,
        // z = n·v node; rg16float (the committed values are f16, so exact).
        let t = tables::all().into_iter().find(|t| t.name == format!("{name}_filtered")).unwrap();
        assert_eq!(t.kind, Kind::D3);
        let (data, h) = read(&t);
        assert_eq!(h.format.map(|f| f.value()), Some(R16G16_SFLOAT), "{name}_filtered");
        assert_eq!(
            (h.pixel_width, h.pixel_height, h.pixel_depth, h.layer_count),
            ((g.alpha * g.psi) as u32, g.gamma as u32, g.theta_v as u32, 0)
        );
        let v = f16s(&data);
        let (w, hgt) = (g.alpha * g.psi, g.gamma);
        for i in 0..g.theta_v {
            for j in 0..g.alpha {
                for k in 0..g.gamma {
                    for l in 0..g.psi {
                        let x = j * g.psi + l;
                        for ch in 0..2 {
                            assert_eq!(
                                v[2 * ((i * hgt + k) * w + x) + ch],
                                node(table, i, j, k, l, ch),
                                "{name} filtered ({i}, {j}, {k}, {l})"
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn a_texture_with_the_wrong_number_of_texels_is_an_error() {
    let mut t = tables::all().swap_remove(0);
    t.data.pop();
    let e = tables::ktx2(&t).unwrap_err();
    assert!(e.contains("bytes of level data"), "{e}");
}

/// A bake's runtime gets the lobe tables in the layout of its lobe feature.
#[test]
fn a_runtime_gets_its_tables_in_the_layouts_its_functions_read() {
    let luts = ["dfg.sbflut".to_string(), "lobe_ggx_sg6.sbflut".to_string()];
    let names = |f: &[&str]| tables::for_runtime(&luts, f).iter().map(|t| t.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&["lobe-ggx-filtered"]), ["dfg", "lobe_ggx_sg6_filtered"]);
    assert_eq!(names(&["lobe-ggx-specular"]), ["dfg", "lobe_ggx_sg6"]);
}
