//! GPU parity: every WGSL function against its `sbf` twin on 10⁵ random inputs
//! (directions uniform, coefficients in [−1, 1], α log-uniform in [1e-3, 1], N·V in
//! [1e-4, 1]), run through wgpu (lavapipe in CI, an NVIDIA GPU on the device machine).
//!
//! Error measure: |gpu − cpu| / max(|cpu|, s), where s is the sum of the magnitudes of
//! the terms the function adds (Σ|c_i·w_i|, computed on the CPU). For a sum of signed
//! terms that cancels, |cpu| alone would measure cancellation, not the shader; s is the
//! scale the f32 rounding of either side is proportional to. Bar: 1e-4, and no
//! NaN/Inf. Skips with a message when no adapter exists, unless SBF_REQUIRE_GPU=1 (CI).

use sbf::glam::{DVec3, Vec3};
use sbf::sampling::Pcg32;
use shaders::compose::{self, Config};
use shaders::export::Lang;
use shaders::gpu::{Launch, Lease, Output};

const N: usize = 100_000;
const BAR: f64 = 1e-4;

/// The process-wide device, leased for this test alone (GPU tests run one at a time), with
/// a watchdog that fails the run loudly if the test exceeds 300 s (warm, the whole binary
/// takes seconds; lavapipe < 60 s), and the language its kernels are written in: WGSL, or
/// the exported HLSL/GLSL library included into a kernel in that language, compiled by
/// glslang to SPIR-V (`shaders::spirv`). The same bodies, inputs and bars in every language.
fn gpu(lang: Lang) -> Option<G> {
    let name = std::thread::current().name().unwrap_or("gpu parity test").to_string();
    // HLSL and GLSL need glslang: skipped without it (a fresh machine), a failure in CI.
    if lang != Lang::Wgsl {
        let glslang = std::process::Command::new(shaders::spirv::GLSLANG).arg("--version").output().is_ok_and(|o| o.status.success());
        if !glslang {
            assert!(
                std::env::var("SBF_REQUIRE_GPU").is_err(),
                "SBF_REQUIRE_GPU is set but {} is not installed (apt-get install glslang-tools)",
                shaders::spirv::GLSLANG
            );
            eprintln!("skipping {lang:?} parity: {} is not installed (apt-get install glslang-tools)", shaders::spirv::GLSLANG);
            return None;
        }
    }
    match shaders::gpu::lease(&name, 300) {
        Ok(g) => {
            // HLSL and GLSL run as glslang's SPIR-V: a GL adapter (a machine without a
            // Vulkan driver) cannot take it, so they skip there with a message; on Vulkan
            // (what CI promises) a missing passthrough is a failure under SBF_REQUIRE_GPU.
            if let Some(why) = g.spirv_unavailable().filter(|_| lang != Lang::Wgsl) {
                assert!(
                    g.backend != wgpu::Backend::Vulkan || std::env::var("SBF_REQUIRE_GPU").is_err(),
                    "SBF_REQUIRE_GPU is set but {why}"
                );
                eprintln!("skipping {lang:?} parity: {why}");
                return None;
            }
            eprintln!("GPU parity ({lang:?}) on {}", g.adapter);
            Some(G { lease: g, lang })
        }
        Err(e) => {
            assert!(std::env::var("SBF_REQUIRE_GPU").is_err(), "SBF_REQUIRE_GPU is set but {e}");
            eprintln!("skipping GPU parity: {e}");
            None
        }
    }
}

/// A leased device and the language of its kernels.
struct G {
    lease: Lease,
    lang: Lang,
}

impl G {
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        library: &str,
        body: &str,
        input: &[f32],
        out_per_item: usize,
        count: usize,
        lut: Option<&sbf::recon::lut::Lut2>,
        repeats: usize,
    ) -> Result<(Vec<f32>, f64), String> {
        let o = self.launch(&Launch { library, body, input, out_per_item, count, lut, repeats, ..Default::default() })?;
        Ok((o.out, o.seconds_per_dispatch))
    }

    fn launch(&self, l: &Launch) -> Result<Output, String> {
        self.lease.launch(&Launch { lang: self.lang, ..*l })
    }
}

/// `#[test]`s running a parity check in WGSL, GLSL and HLSL.
macro_rules! in_every_language {
    ($($check:ident),* $(,)?) => {
        mod wgsl {
            $(#[test] fn $check() { super::$check(super::Lang::Wgsl) })*
        }
        mod glsl {
            $(#[test] fn $check() { super::$check(super::Lang::GLSL) })*
        }
        mod hlsl {
            $(#[test] fn $check() { super::$check(super::Lang::Hlsl) })*
        }
    };
}

in_every_language!(
    sg_lobe_loops_parity,
    sh_parity,
    sh_specular_parity,
    sh_rotation_parity,
    ggx_parity,
    sg_parity,
    sg_split_sum_parity,
    ambient_dice_parity,
    lobe_ggx_parity,
    lobe_ggx_filtered_parity,
    lut_parity,
    progressive_parity,
    ambient_dice_bezier_parity,
    helper_parity,
    slc_parity,
    slc_media_parity,
    slc_tile_parity,
    engine_parity,
    lightmap_parity,
);

/// The engine lightmap formats' decodes (engine.wgsl) against `sbf::recon::engine::decode`
/// (f64 on the same f32 inputs): colours in [0, 2], unit textures in [0, 1] with rescaling
/// factors in [0.05, 1]; Godot 4.0–4.3's signed layers are the unit values times (w − ½)·4.
/// Scale: the sum of the magnitudes of each decode's terms (Godot |L0| + Σ 8|L0||s − ½||n_k|;
/// Godot 4.0–4.3 0.282095|L0| + 0.32573·Σ|l_k||n_k|; MonoSH linear |L0|(1 + 2|nL1·n|), and
/// non-linear that times the rescaling factor's terms, 1 + w(5.5·ΣL0 + |Σsh|)/|Σsh| (Geomerics'
/// curve is at most (p + 1)·R₀ with p ≤ 1 + 2√3 < 4.5); Enlighten |C|(Σ|n_k||t_k − ½| + ½)/w).
fn engine_parity(lang: Lang) {
    use sbf::recon::engine::{decode, EngineFormat, Texel};
    let Some(g) = gpu(lang) else { return };
    let lib = library("engine-formats");
    let mut r = Pcg32::new(41, 6);
    let (mut inp, mut items) = (Vec::new(), Vec::new());
    for _ in 0..N {
        let n = dir(&mut r);
        let c = [0; 3].map(|_| 2.0 * r.next_2d()[0] as f32);
        let mut unit = [[0.0f32; 4]; 3];
        for t in unit.iter_mut() {
            for (k, v) in t.iter_mut().enumerate() {
                let u = r.next_2d()[0] as f32;
                *v = if k == 3 { 0.05 + 0.95 * u } else { u };
            }
        }
        push3(&mut inp, n);
        inp.extend_from_slice(&c);
        inp.extend(unit.iter().flatten());
        items.push((n, c, unit));
    }
    let body = "    let o = i * 18u;\n    let n = ld3(o);\n    let c = ld3(o + 3u);\n    let t0 = vec4<f32>(ld3(o + 6u), inp[o + 9u]);\n    let t1 = vec4<f32>(ld3(o + 10u), inp[o + 13u]);\n    let t2 = vec4<f32>(ld3(o + 14u), inp[o + 17u]);\n    let e = array<vec3<f32>, 6>(godot_l1_irradiance(c, t0.xyz, t1.xyz, t2.xyz, n), godot_l1_legacy_irradiance(c, (t0.w - 0.5) * 4.0 * t0.xyz, (t1.w - 0.5) * 4.0 * t1.xyz, (t2.w - 0.5) * 4.0 * t2.xyz, n), monosh_irradiance(c, t0.xyz, n), monosh_linear_irradiance(c, t0.xyz, n), enlighten_irradiance(c, t0, n), enlighten_rgb_irradiance(c, t0, t1, t2, n));\n    for (var k = 0u; k < 6u; k++) {\n        outp[i * 18u + 3u * k] = e[k].x;\n        outp[i * 18u + 3u * k + 1u] = e[k].y;\n        outp[i * 18u + 3u * k + 2u] = e[k].z;\n    }";
    let (out, _) = g.run(&lib, body, &inp, 18, N, None, 0).unwrap();
    let names = [
        "godot_l1_irradiance",
        "godot_l1_legacy_irradiance",
        "monosh_irradiance",
        "monosh_linear_irradiance",
        "enlighten_irradiance",
        "enlighten_rgb_irradiance",
    ];
    let formats = [
        EngineFormat::GodotL1,
        EngineFormat::GodotL1Legacy,
        EngineFormat::MonoSh,
        EngineFormat::MonoShLinear,
        EngineFormat::Enlighten,
        EngineFormat::EnlightenRgb,
    ];
    for (f, format) in formats.into_iter().enumerate() {
        let (mut cpu, mut scale, mut gpu_f) = (Vec::new(), Vec::new(), Vec::new());
        for (j, (n, c, unit)) in items.iter().enumerate() {
            let mut t = Texel { colour: c.map(f64::from), unit: unit.map(|u| u.map(f64::from)) };
            if format == EngineFormat::GodotL1Legacy {
                // Signed layers: the unit values times (w − ½)·4 of their layer, as the shader
                // body passes them (f32 products, so the same inputs on both sides).
                t.unit = unit.map(|u| {
                    let s = (u[3] - 0.5) * 4.0;
                    [s * u[0], s * u[1], s * u[2], u[3]].map(f64::from)
                });
            }
            let nd = n.as_dvec3();
            let e = decode(format, &t, nd);
            let na = [nd.x.abs(), nd.y.abs(), nd.z.abs()];
            for ch in 0..3 {
                let l0 = t.colour[ch].abs();
                let half = |u: &[f64; 4]| (0..3).map(|k| na[k] * (u[k] - 0.5).abs()).sum::<f64>() + 0.5;
                let s = match format {
                    EngineFormat::GodotL1 => {
                        l0 + (0..3).map(|layer| 8.0 * l0 * (t.unit[layer][ch] - 0.5).abs() * na[[1, 2, 0][layer]]).sum::<f64>()
                    }
                    EngineFormat::GodotL1Legacy => {
                        0.282095 * l0 + 0.32573 * (0..3).map(|layer| t.unit[layer][ch].abs() * na[[1, 2, 0][layer]]).sum::<f64>()
                    }
                    EngineFormat::MonoShLinear => l0 * (1.0 + 2.0 * half(&t.unit[0]) * 2.0),
                    EngineFormat::MonoSh => {
                        // The linear terms' magnitude times the factor's: 1 + w(|luma_sh| +
                        // |Σsh|)/|Σsh|, luma_sh from Geomerics' curve (≤ (p + 1)·ΣL0 ≤ 5.5·ΣL0).
                        let nl1 = DVec3::new(t.unit[0][0], t.unit[0][1], t.unit[0][2]) * 2.0 - DVec3::ONE;
                        let x = nl1.dot(nd);
                        let luma: f64 = t.colour.iter().sum();
                        let regular = luma * (1.0 + 2.0 * x);
                        let w = (16.0 * regular).clamp(0.0, 1.0);
                        let f = if w > 0.0 { 1.0 + w * (5.5 * luma + regular.abs()) / regular.abs() } else { 1.0 };
                        l0 * (1.0 + 2.0 * x.abs()) * f
                    }
                    EngineFormat::Enlighten => l0 * half(&t.unit[0]) / t.unit[0][3],
                    EngineFormat::EnlightenRgb => l0 * half(&t.unit[ch]) / t.unit[ch][3],
                };
                cpu.push(e[ch]);
                scale.push(s);
                gpu_f.push(out[j * 18 + 3 * f + ch]);
            }
        }
        check(names[f], &gpu_f, &cpu, &scale);
    }
}

/// The B-spline lightmap taps (lightmap.wgsl) against the B-spline itself: the GPU's four
/// taps, each a bilinear lookup (done here in f64) of the texture T(i, j) = sin(0.3i) +
/// cos(0.2j) + 0.01·i·j/size, weighted as the function's comment says, must give the
/// 16-texel sum Σ w_a(fx)·w_b(fy)·T with `sbf::recon::lut::bspline_weights` (comparing tap
/// positions would be ill-posed: where c − ½ is an integer, f32 and f64 may floor to
/// neighbouring texels with equal results). uv uniform in [0.1, 0.9]² (taps inside), 16 to
/// 1024 texels per side. Error model: f32 keeps c = uv·size to size·2⁻²⁴ ≤ 6e-5 texels,
/// times T's slope ≤ 0.4: ≤ 3e-5 of T's magnitude (scale 2).
fn lightmap_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("lightmap-bicubic");
    let mut r = Pcg32::new(43, 7);
    let (mut inp, mut items) = (Vec::new(), Vec::new());
    for _ in 0..N {
        let [u, v] = r.next_2d();
        let [a, b] = r.next_2d();
        let size = [(16.0 + 1008.0 * a).floor() as f32, (16.0 + 1008.0 * b).floor() as f32];
        let uv = [(0.1 + 0.8 * u) as f32, (0.1 + 0.8 * v) as f32];
        inp.extend_from_slice(&[uv[0], uv[1], size[0], size[1]]);
        items.push((uv, size));
    }
    let body = "    let o = i * 4u;\n    let t = lightmap_bicubic_taps(vec2<f32>(inp[o], inp[o + 1u]), vec2<f32>(inp[o + 2u], inp[o + 3u]));\n    for (var k = 0u; k < 4u; k++) {\n        outp[i * 8u + k] = t.pos[k];\n        outp[i * 8u + 4u + k] = t.w[k];\n    }";
    let (out, _) = g.run(&lib, body, &inp, 8, N, None, 0).unwrap();
    let (mut gpu_v, mut cpu_v) = (Vec::new(), Vec::new());
    for (j, (uv, size)) in items.iter().enumerate() {
        let (sx, sy) = (size[0] as f64, size[1] as f64);
        let tex = |i: f64, j: f64| (0.3 * i).sin() + (0.2 * j).cos() + 0.01 * i * j / sx;
        // Bilinear at a point in texels (centres at i + ½).
        let bilinear = |px: f64, py: f64| {
            let (x, y) = (px - 0.5, py - 0.5);
            let (i, j) = (x.floor(), y.floor());
            let (fx, fy) = (x - i, y - j);
            (tex(i, j) * (1.0 - fx) + tex(i + 1.0, j) * fx) * (1.0 - fy) + (tex(i, j + 1.0) * (1.0 - fx) + tex(i + 1.0, j + 1.0) * fx) * fy
        };
        let o = &out[j * 8..j * 8 + 8];
        let (px, py) = ([o[0] as f64 * sx, o[1] as f64 * sx], [o[2] as f64 * sy, o[3] as f64 * sy]);
        let w = [o[4] as f64, o[5] as f64, o[6] as f64, o[7] as f64];
        let gpu_sum = w[2] * (w[0] * bilinear(px[0], py[0]) + w[1] * bilinear(px[1], py[0]))
            + w[3] * (w[0] * bilinear(px[0], py[1]) + w[1] * bilinear(px[1], py[1]));
        let (cx, cy) = (uv[0] as f64 * sx - 0.5, uv[1] as f64 * sy - 0.5);
        let (i, jj) = (cx.floor(), cy.floor());
        let (wx, wy) = (sbf::recon::lut::bspline_weights(cx - i), sbf::recon::lut::bspline_weights(cy - jj));
        let mut sum = 0.0;
        for (b, wyb) in wy.iter().enumerate() {
            for (a, wxa) in wx.iter().enumerate() {
                sum += wxa * wyb * tex(i - 1.0 + a as f64, jj - 1.0 + b as f64);
            }
        }
        gpu_v.push(gpu_sum as f32);
        cpu_v.push(sum);
    }
    check("lightmap_bicubic_taps", &gpu_v, &cpu_v, &vec![2.0; cpu_v.len()]);
}

fn library(cfg: &str) -> String {
    compose::compose(&Config::parse(cfg).unwrap()).unwrap().source
}

fn dir(r: &mut Pcg32) -> Vec3 {
    let u = r.next_2d();
    sbf::sampling::uniform_sphere(u).as_vec3().normalize()
}

fn coeff(r: &mut Pcg32) -> f32 {
    (2.0 * r.next_2d()[0] - 1.0) as f32
}

fn alpha(r: &mut Pcg32) -> f32 {
    (1e-3f64 * 1e3f64.powf(r.next_2d()[0])) as f32
}

/// A view with n·v = c ∈ [1e-4, 1] in a random azimuth about n.
fn view(r: &mut Pcg32, n: Vec3) -> Vec3 {
    let c = 1e-4 + (1.0 - 1e-4) * r.next_2d()[0];
    let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(n.as_dvec3());
    let phi = 2.0 * std::f64::consts::PI * r.next_2d()[0];
    let s = (1.0 - c * c).max(0.0).sqrt();
    (n.as_dvec3() * c + (t * phi.cos() + b * phi.sin()) * s).normalize().as_vec3()
}

/// Compares `gpu` (k per item) with `cpu` and their scales; returns the worst error.
fn check(name: &str, gpu: &[f32], cpu: &[f64], scale: &[f64]) -> f64 {
    let worst = worst_error(name, gpu, cpu, scale);
    let lang = std::thread::current().name().and_then(|t| t.split("::").next()).unwrap_or("").to_string();
    assert!(worst <= BAR, "{lang} {name}: {worst:.3e} > {BAR:e}");
    worst
}

/// The largest |gpu − cpu| / max(|cpu|, scale), printed with where it was.
fn worst_error(name: &str, gpu: &[f32], cpu: &[f64], scale: &[f64]) -> f64 {
    assert_eq!(gpu.len(), cpu.len(), "{name}: output length");
    let mut worst = (0.0f64, 0usize);
    for (k, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        assert!(g.is_finite(), "{name}: GPU output {k} is {g}");
        let e = (*g as f64 - c).abs() / c.abs().max(scale[k]).max(1e-30);
        if e > worst.0 {
            worst = (e, k);
        }
    }
    let lang = std::thread::current().name().and_then(|t| t.split("::").next()).unwrap_or("").to_string();
    println!("{lang:<5} {name:<28} worst relative error {:.3e} (output {}: gpu {} cpu {})", worst.0, worst.1, gpu[worst.1], cpu[worst.1]);
    worst.0
}

fn push3(v: &mut Vec<f32>, x: Vec3) {
    v.extend_from_slice(&[x.x, x.y, x.z]);
}

fn sh_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("sh-eval,sh-l1-irradiance,sh-l2-irradiance,sh-l4-irradiance,sh-l1-geomerics,sh-l1-zh3");
    let mut r = Pcg32::new(7, 1);
    let (mut inp, mut dirs, mut coeffs) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..N {
        let d = dir(&mut r);
        let c: Vec<Vec3> = (0..25).map(|_| Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r))).collect();
        push3(&mut inp, d);
        for x in &c {
            push3(&mut inp, *x);
        }
        dirs.push(d);
        coeffs.push(c);
    }
    // Evaluation: 25 values per direction.
    let body = "    let d = ld3(i * 78u);\n    let y = sh_eval_l4(d);\n    for (var k = 0u; k < 25u; k++) {\n        outp[i * 25u + k] = y[k];\n    }";
    let (out, _) = g.run(&lib, body, &inp, 25, N, None, 0).unwrap();
    let cpu: Vec<f64> = dirs.iter().flat_map(|d| sbf::basis::sh_fast::eval_sh_l4(*d).map(|x| x as f64)).collect();
    // SH values are bounded by ~1.1 (band 4 peak); scale 1 measures absolute error.
    check("sh_eval_l4", &out, &cpu, &vec![1.0; cpu.len()]);

    // Irradiance: L1, L2, L4, Geomerics, ZH3 (3 floats each).
    let body = "    let d = ld3(i * 78u);\n    var c4: array<vec3<f32>, 4>;\n    var c9: array<vec3<f32>, 9>;\n    var c25: array<vec3<f32>, 25>;\n    for (var k = 0u; k < 25u; k++) {\n        let x = ld3(i * 78u + 3u + 3u * k);\n        c25[k] = x;\n        if (k < 9u) { c9[k] = x; }\n        if (k < 4u) { c4[k] = x; }\n    }\n    let e = array<vec3<f32>, 5>(sh_l1_irradiance(c4, d), sh_l2_irradiance(c9, d), sh_l4_irradiance(c25, d), sh_l1_geomerics_irradiance(c4, d), sh_l1_zh3_irradiance(c4, d));\n    for (var k = 0u; k < 5u; k++) {\n        outp[i * 15u + 3u * k] = e[k].x;\n        outp[i * 15u + 3u * k + 1u] = e[k].y;\n        outp[i * 15u + 3u * k + 2u] = e[k].z;\n    }";
    let (out, _) = g.run(&lib, body, &inp, 15, N, None, 0).unwrap();
    let rt = sbf::recon::runtime::SH_IRRADIANCE_BAND;
    let band = |k: usize| (k as f64).sqrt().floor() as usize;
    let names = ["sh_l1_irradiance", "sh_l2_irradiance", "sh_l4_irradiance", "sh_l1_geomerics_irradiance", "sh_l1_zh3_irradiance"];
    for (f, name) in names.iter().enumerate() {
        let (mut cpu, mut scale) = (Vec::new(), Vec::new());
        let mut gpu_f = Vec::new();
        for (j, (d, c)) in dirs.iter().zip(&coeffs).enumerate() {
            let c4: [Vec3; 4] = c[..4].try_into().unwrap();
            let y = sbf::basis::sh_fast::eval_sh_l4(*d);
            let n_terms = [4, 9, 25, 4, 4][f];
            let e: [f64; 3] = match f {
                0 => sbf::recon::runtime::sh_l1_irradiance(&c4, *d).as_dvec3().to_array(),
                1 => sbf::recon::runtime::sh_l2_irradiance(&c[..9].try_into().unwrap(), *d).as_dvec3().to_array(),
                2 => sbf::recon::runtime::sh_l4_irradiance(&c[..25].try_into().unwrap(), *d).as_dvec3().to_array(),
                3 => sbf::recon::runtime::sh_l1_geomerics_irradiance(&c4, *d).as_dvec3().to_array(),
                _ => {
                    let rgb = [0, 1, 2].map(|ch| [0, 1, 2, 3].map(|k| c[k][ch] as f64));
                    sbf::recon::sh::irradiance_l1_zh3(&rgb, d.as_dvec3()).unwrap()
                }
            };
            for ch in 0..3 {
                cpu.push(e[ch]);
                // Σ|c_k·y_k·A_k| (ZH3 adds a band-2 term of size ≤ |c0|·0.68·0.32; Geomerics
                // is bounded by 2|r0| + 2|r1|).
                let s: f64 = (0..n_terms).map(|k| (c[k][ch] * y[k] * rt[band(k)]).abs() as f64).sum::<f64>()
                    + if f >= 3 { c[0][ch].abs() as f64 } else { 0.0 };
                scale.push(s + if f == 3 { geomerics_pow_scale(c, *d, ch) } else { 0.0 });
                gpu_f.push(out[j * 15 + 3 * f + ch]);
            }
        }
        check(name, &gpu_f, &cpu, &scale);
    }
}

/// SH rotation (sh_rotation.wgsl, f32 recurrence) against sbf::basis::sh_rotation
/// (f64) on 8 192 random rotations (axis uniform, angle uniform, assembled in f32) and
/// random RGB coefficients, for the L1, L2 and L4 entry points. Scale: Σ_n |M_mn·c_n| per
/// output, the size the f32 rounding of the products and the matrix entries is relative
/// to (band 4's entries carry ~4 recurrence steps of a few ulp each: ≪ BAR).
fn sh_rotation_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("sh-rotate");
    const M: usize = 8192;
    let mut r = Pcg32::new(31, 4);
    let (mut inp, mut mats, mut coeffs) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..M {
        let axis = dir(&mut r);
        let angle = 2.0 * std::f32::consts::PI * r.next_2d()[0] as f32;
        let m = sbf::glam::Mat3::from_quat(sbf::glam::Quat::from_axis_angle(axis, angle));
        inp.extend_from_slice(&m.to_cols_array());
        let c: Vec<Vec3> = (0..25).map(|_| Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r))).collect();
        for x in &c {
            push3(&mut inp, *x);
        }
        mats.push(m.as_dmat3());
        coeffs.push(c);
    }
    let body = "    let b = i * 84u;\n    let r = mat3x3<f32>(ld3(b), ld3(b + 3u), ld3(b + 6u));\n    var c4: array<vec3<f32>, 4>;\n    var c9: array<vec3<f32>, 9>;\n    var c25: array<vec3<f32>, 25>;\n    for (var k = 0u; k < 25u; k++) {\n        let x = ld3(b + 9u + 3u * k);\n        c25[k] = x;\n        if (k < 9u) { c9[k] = x; }\n        if (k < 4u) { c4[k] = x; }\n    }\n    var o4 = sh_rotate_l1(c4, r);\n    var o9 = sh_rotate_l2(c9, r);\n    var o25 = sh_rotate_l4(c25, r);\n    for (var k = 0u; k < 38u; k++) {\n        var v: vec3<f32>;\n        if (k < 4u) { v = o4[k]; } else if (k < 13u) { v = o9[k - 4u]; } else { v = o25[k - 13u]; }\n        outp[i * 114u + 3u * k] = v.x;\n        outp[i * 114u + 3u * k + 1u] = v.y;\n        outp[i * 114u + 3u * k + 2u] = v.z;\n    }";
    let (out, _) = g.run(&lib, body, &inp, 114, M, None, 0).unwrap();
    for (name, order, off) in [("sh_rotate_l1", 1usize, 0usize), ("sh_rotate_l2", 2, 4), ("sh_rotate_l4", 4, 13)] {
        let n = sbf::basis::sh::sh_count(order);
        let (mut cpu, mut scale, mut gk) = (Vec::new(), Vec::new(), Vec::new());
        for (j, (m, c)) in mats.iter().zip(&coeffs).enumerate() {
            let rot = sbf::ShRotation::new(order, *m).unwrap();
            for ch in 0..3 {
                let src: Vec<f64> = c[..n].iter().map(|v| v[ch] as f64).collect();
                let want = rot.apply(&src).unwrap();
                for l in 0..=order {
                    let w = 2 * l + 1;
                    let band = rot.band(l);
                    for mi in 0..w {
                        let k = l * l + mi;
                        cpu.push(want[k]);
                        scale.push((0..w).map(|ni| (band[mi * w + ni] * src[l * l + ni]).abs()).sum::<f64>());
                        gk.push(out[j * 114 + 3 * (off + k) + ch]);
                    }
                }
            }
        }
        check(name, &gk, &cpu, &scale);
    }
}

/// The conditioning of Geomerics' r0·(1 − a)(p + 1)·q^p in f32, as a parity scale (the
/// error allowed is BAR × scale). A conformant pow is exp2(p·log2 q) (Vulkan/GLSL
/// precision: log2 to 2⁻²¹ absolute in [0.5, 2], 3 ulp outside; exp2 to 3 + 2|x| ulp), and
/// q = ½(1 + n·r1/|r1|) carries ~4 roundings of 2⁻²⁴ absolute, which p multiplies:
/// relative error ε = p·ln 2·(2⁻²¹ + 4·2⁻²⁴/(q ln 2)) + (3 + 2|p log2 q|)·2⁻²⁴ on the power
/// term. Backends that fuse or round differently (GL llvmpipe) land inside ε; ×2 margin.
fn geomerics_pow_scale(c: &[Vec3], n: Vec3, ch: usize) -> f64 {
    let k0 = 0.5 / std::f64::consts::PI.sqrt();
    let k1 = (3.0 / (4.0 * std::f64::consts::PI)).sqrt() / 3.0;
    let r0 = c[0][ch] as f64 * k0;
    let r1 = sbf::glam::DVec3::new(c[3][ch] as f64, c[1][ch] as f64, c[2][ch] as f64) * k1;
    let len = r1.length();
    if r0 <= 0.0 || len <= 0.0 {
        return 0.0;
    }
    let q = (0.5 * (1.0 + n.as_dvec3().dot(r1 / len))).max(1e-30);
    let ratio = len / r0;
    let p = 1.0 + 2.0 * ratio;
    let a = (1.0 - ratio) / (1.0 + ratio);
    let term = (r0 * (1.0 - a) * (p + 1.0) * q.powf(p)).abs();
    let u = 2f64.powi(-24);
    let ln2 = std::f64::consts::LN_2;
    let eps = p * ln2 * (2f64.powi(-21) + 4.0 * u / (q * ln2)) + (3.0 + 2.0 * (p * q.log2()).abs()) * u;
    2.0 * term * eps / BAR
}

fn ggx_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("ggx,ggx-energy-compensation");
    let mut r = Pcg32::new(11, 2);
    let mut inp = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..N {
        // Tangent space: h and l on the upper hemisphere, v with v_z = N·V ∈ [1e-4, 1].
        let h = {
            let d = dir(&mut r);
            Vec3::new(d.x, d.y, d.z.abs())
        };
        let l = {
            let d = dir(&mut r);
            Vec3::new(d.x, d.y, d.z.abs().max(1e-4)).normalize()
        };
        let v = view(&mut r, Vec3::Z);
        let a = alpha(&mut r);
        for x in [h, v, l] {
            push3(&mut inp, x);
        }
        inp.push(a);
        // schlick_weight takes v·h: passed as computed here, so both sides see one f32
        // input ((1 − x)^5 near x = 1 amplifies any difference in x itself).
        let x = v.dot((v + l).normalize());
        inp.push(x);
        // A DFG value (E = dfg.0 + dfg.1 in [0.05, 1], as the table holds) and f0.
        let dfg = [(0.05 + 0.9 * r.next_f64()) as f32, (0.05 * r.next_f64()) as f32];
        let f0 = r.next_f64() as f32;
        inp.extend([dfg[0], dfg[1], f0]);
        cases.push((h, v, l, a, x, dfg, f0));
    }
    let body = "    let h = ld3(i * 14u);\n    let v = ld3(i * 14u + 3u);\n    let l = ld3(i * 14u + 6u);\n    let a = inp[i * 14u + 9u];\n    outp[i * 5u] = ggx_d(h, a);\n    outp[i * 5u + 1u] = ggx_g1(v, a);\n    outp[i * 5u + 2u] = ggx_g2(v, l, a);\n    outp[i * 5u + 3u] = schlick_weight(inp[i * 14u + 10u]);\n    outp[i * 5u + 4u] = ggx_energy_compensation(vec2<f32>(inp[i * 14u + 11u], inp[i * 14u + 12u]), inp[i * 14u + 13u]);";
    let (out, _) = g.run(&lib, body, &inp, 5, N, None, 0).unwrap();
    let mut cpu = Vec::new();
    for (h, v, l, a, x, dfg, f0) in &cases {
        // The twins in f64 at the same f32 inputs.
        let (h, v, l, a) = (h.as_dvec3(), v.as_dvec3(), l.as_dvec3(), *a as f64);
        let comp = sbf::recon::multiscatter::energy_compensation(dfg[0] as f64 + dfg[1] as f64, *f0 as f64);
        cpu.extend([sbf::ggx::d(h, a), sbf::ggx::g1(v, a), sbf::ggx::g2(v, l, a), sbf::ggx::schlick_weight(*x as f64), comp]);
    }
    for (k, name) in ["ggx_d", "ggx_g1", "ggx_g2", "schlick_weight", "ggx_energy_compensation"].iter().enumerate() {
        let gk: Vec<f32> = out.iter().skip(k).step_by(5).copied().collect();
        let ck: Vec<f64> = cpu.iter().skip(k).step_by(5).copied().collect();
        // D's f32 evaluation of α² h_z² + sin²θ near its peak (α = 1e-3) has a relative
        // conditioning of ~1 (a sum of positives): the plain relative error applies.
        check(name, &gk, &ck, &vec![0.0; ck.len()]);
    }
}

fn sg_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("sg-eval,sg-irradiance,sg-specular-asg");
    let mut r = Pcg32::new(13, 3);
    let mut inp = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..N {
        let axis = dir(&mut r);
        let n = dir(&mut r);
        let v = view(&mut r, n);
        // Runtime range of the Hill fit and typical lobe sharpness: λ ∈ [2, 64].
        let lam = (2.0 * 32f64.powf(r.next_2d()[0])) as f32;
        let a = alpha(&mut r);
        let (f0, f90) = (r.next_2d()[0] as f32, 1.0f32);
        for x in [axis, n, v] {
            push3(&mut inp, x);
        }
        inp.extend([lam, a, f0, f90]);
        cases.push((axis, n, v, lam, a, f0, f90));
    }
    let body = "    let b = i * 13u;\n    let axis = ld3(b);\n    let n = ld3(b + 3u);\n    let v = ld3(b + 6u);\n    let lam = inp[b + 9u];\n    let a = inp[b + 10u];\n    outp[i * 3u] = sg_eval(axis, lam, v);\n    outp[i * 3u + 1u] = sg_hill_irradiance(axis, lam, n);\n    let w = sg_asg_warp(n, v, a, inp[b + 11u], inp[b + 12u]);\n    outp[i * 3u + 2u] = sg_asg_lobe(w, axis, lam);";
    let (out, _) = g.run(&lib, body, &inp, 3, N, None, 0).unwrap();
    let (mut ce, mut ch, mut cs, mut ss) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut r2 = Pcg32::new(23, 6);
    for (axis, n, v, lam, a, f0, f90) in &cases {
        let (axis, n, v) = (axis.as_dvec3(), n.as_dvec3(), v.as_dvec3());
        let sg = sbf::Sg { axis, sharpness: *lam as f64, amplitude: 1.0 };
        ce.push(sg.eval(v));
        ch.push(
            sbf::recon::sg::hill_curve(sbf::luts::committed::constants::HILL_C0, *lam as f64, axis.dot(n)) * sg.integral()
                / std::f64::consts::PI,
        );
        let w = sbf::recon::sg::AsgWarp::new(n, v, *a as f64, *f0 as f64, *f90 as f64);
        let val = w.lobe(&sg);
        cs.push(val);
        // The warp is a product of positives (μ·amp·cos·exp·tail), relative-accurate in
        // f32 except through its clamped cosine axis·z (z = reflect(v, n)): near 0 that
        // factor inherits the ~1e-7 absolute rounding of the unit vectors, so the scale
        // replaces it by max(axis·z, 1e-3) (an absolute error of 1e-7 in it costs 1e-4).
        // As for sg_eval, far-tail values (below 1e-6 of the lobe's peak, reached with the
        // light on the reflection direction) are measured against that floor.
        let z = sbf::ggx::reflect(v, n).normalize();
        let smooth = axis.dot(z).max(0.0);
        let peak = w.lobe(&sbf::Sg { axis: z, sharpness: *lam as f64, amplitude: 1.0 });
        // Input conditioning: at grazing view the bandwidth λ/(8 (n·v)²) makes the value
        // sensitive to n·v, whose f32 evaluation from unit vectors carries ~1.2e-7
        // absolute error (4e-4 relative at n·v = 3e-4) in any f32 implementation; so the
        // change of the value when n, v and the axis move by 1.2e-7 (one f32 ulp at 1, in
        // four random directions) is an allowed error too (×1e4 = 1/BAR).
        let mut dmax = 0.0f64;
        for _ in 0..4 {
            let mut jitter = |x: sbf::glam::DVec3| (x + dir(&mut r2).as_dvec3() * 1.2e-7).normalize();
            let (ap, np, vp) = (jitter(axis), jitter(n), jitter(v));
            let sp = sbf::Sg { axis: ap, sharpness: *lam as f64, amplitude: 1.0 };
            dmax = dmax.max((sbf::recon::sg::AsgWarp::new(np, vp, *a as f64, *f0 as f64, *f90 as f64).lobe(&sp) - val).abs());
        }
        ss.push((if smooth > 0.0 { val / smooth * smooth.max(1e-3) } else { 0.0 }).max(1e-6 * peak).max(dmax * 1e4));
    }
    let col = |k: usize| out.iter().skip(k).step_by(3).copied().collect::<Vec<f32>>();
    // sg_eval and Hill: values in [0, 1] and [0, ~1]: the plain relative error, floored at
    // 1e-6 of the lobe's peak where the value is a far tail (exp of −2λ ≈ 1e-56).
    check("sg_eval", &col(0), &ce, &vec![1e-6; N]);
    check("sg_hill_irradiance", &col(1), &ch, &vec![1e-6; N]);
    check("sg_asg_warp+lobe", &col(2), &cs, &ss);
}

/// sg_split_sum_setup + sg_split_sum_lobe against the f64 split sum
/// (`sbf::recon::sg::SplitSumWarp`, the dfg table sampled by the CPU's `Lut2`), one light
/// lobe of λ ∈ [2, 64] per case. Scale: the lobe's value with its axis on the reflection
/// direction (its peak) × 1e-5 — where the product lobe's sharpness falls below 2 (λ_D
/// within 2 of λ, the lobe facing away from R) the f64 reference's zonal branch and the
/// WGSL's Hill curve differ by ≤ 2 % of a product amplitude ≤ e^(−4): < 1e-5 of the peak.
/// Input conditioning as in the SG and SH tests: the change of the f64 value when n, v and
/// the axis move by 1.2e-7 (four random directions) ×1e4 (= 1/BAR) is an allowed error.
fn sg_split_sum_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("sg-specular");
    let lut = sbf::recon::tables::dfg();
    let mut r = Pcg32::new(17, 9);
    let (mut inp, mut cases) = (Vec::new(), Vec::new());
    for _ in 0..N {
        let axis = dir(&mut r);
        let n = dir(&mut r);
        let v = view(&mut r, n);
        let lam = (2.0 * 32f64.powf(r.next_2d()[0])) as f32;
        let a = alpha(&mut r);
        let (f0, f90) = (r.next_2d()[0] as f32, 1.0f32);
        for x in [axis, n, v] {
            push3(&mut inp, x);
        }
        inp.extend([lam, a, f0, f90]);
        cases.push((axis, n, v, lam, a, f0, f90));
    }
    let body = "    let b = i * 13u;\n    let w = sg_split_sum_setup(lut, ld3(b + 3u), ld3(b + 6u), inp[b + 10u], inp[b + 11u], inp[b + 12u]);\n    outp[i] = sg_split_sum_lobe(w, ld3(b), inp[b + 9u]);";
    let (out, _) = g.run(&lib, body, &inp, 1, N, Some(lut), 0).unwrap();
    let mut r2 = Pcg32::new(19, 4);
    let (mut cpu, mut scale) = (Vec::new(), Vec::new());
    for (axis, n, v, lam, a, f0, f90) in &cases {
        let eval = |axis: sbf::glam::DVec3, n: sbf::glam::DVec3, v: sbf::glam::DVec3| {
            let d = lut.sample2(n.dot(v).clamp(0.0, 1.0) as f32, *a);
            let w = sbf::recon::sg::SplitSumWarp::new(n, v, *a as f64, *f0 as f64, *f90 as f64, [d[0] as f64, d[1] as f64]);
            (
                w.lobe(&sbf::Sg { axis, sharpness: *lam as f64, amplitude: 1.0 }),
                w.lobe(&sbf::Sg { axis: sbf::ggx::reflect(v, n), sharpness: *lam as f64, amplitude: 1.0 }),
            )
        };
        let (nd, vd, ad) = (n.as_dvec3(), v.as_dvec3(), axis.as_dvec3());
        let (val, peak) = eval(ad, nd, vd);
        let mut dmax = 0.0f64;
        for _ in 0..4 {
            let mut jitter = |x: sbf::glam::DVec3| (x + dir(&mut r2).as_dvec3() * 1.2e-7).normalize();
            let (ap, np, vp) = (jitter(ad), jitter(nd), jitter(vd));
            dmax = dmax.max((eval(ap, np, vp).0 - val).abs());
        }
        cpu.push(val);
        scale.push((1e-5 * peak).max(dmax * 1e4));
    }
    check("sg_split_sum_setup+lobe", &out, &cpu, &scale);
}

/// The SG lightmap lobe loops (`sg9_irradiance`, `sg12_irradiance`, `sg9_specular`,
/// `sg12_specular`) against their f32 CPU twins (`sbf::recon::runtime::sg_irradiance`,
/// `sg_specular_split_sum`) on the `sbf::layout::vogel_hemisphere` axes, λ ∈ [2, 64], RGB
/// amplitudes in [−1, 1]. Scale: the same sum with |c| (the terms the sum adds); for the
/// specular also the change of the f64 sum (`SplitSumWarp`) when n and v move by 1.2e-7 ×1e4
/// (= 1/BAR), the input conditioning `sg_split_sum_parity` states, and the flush of
/// subnormals: GPUs may flush f32 subnormals to zero (NVIDIA's `exp` and multiplies do; the
/// CPU twin keeps them), which loses up to `f32::MIN_POSITIVE` at each of the four steps per
/// lobe where the sum can fall below it (e^(…), ·E/π, ·c, +) before the per-pixel factor
/// `SplitSumWarp::scale` multiplies it (up to ~1e13 at α 1e-3, grazing view): a floor of
/// 4·K·MIN_POSITIVE·scale for K lobes (|c| ≤ 1, the runtime's E/π ≤ 1 for λ ≥ 2), /BAR as
/// the conditioning term.
fn sg_lobe_loops_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("sg-irradiance,sg-specular");
    let lut = sbf::recon::tables::dfg();
    let axes = |k: usize| -> Vec<Vec3> { sbf::layout::vogel_hemisphere(k).unwrap().iter().map(|a| a.as_vec3()).collect() };
    let (sg9, sg12) = (axes(9), axes(12));
    let mut r = Pcg32::new(23, 5);
    let (mut inp, mut cases) = (Vec::new(), Vec::new());
    for _ in 0..N {
        let n = dir(&mut r);
        let v = view(&mut r, n);
        let a = alpha(&mut r);
        let lam = (2.0 * 32f64.powf(r.next_2d()[0])) as f32;
        let (f0, f90) = (r.next_2d()[0] as f32, 1.0f32);
        let c: Vec<Vec3> = (0..12).map(|_| Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r))).collect();
        push3(&mut inp, n);
        push3(&mut inp, v);
        inp.extend([a, f0, f90, lam]);
        for x in &c {
            push3(&mut inp, *x);
        }
        cases.push((n, v, a, f0, f90, lam, c));
    }
    let body = "    let b = i * 46u;\n    let n = ld3(b);\n    let v = ld3(b + 3u);\n    let a = inp[b + 6u];\n    let lam = inp[b + 9u];\n    var c12: array<vec3<f32>, 12>;\n    var c9: array<vec3<f32>, 9>;\n    for (var k = 0u; k < 12u; k++) {\n        c12[k] = ld3(b + 10u + 3u * k);\n        if (k < 9u) { c9[k] = c12[k]; }\n    }\n    let e = array<vec3<f32>, 4>(sg12_irradiance(c12, lam, n), sg9_irradiance(c9, lam, n), sg12_specular(c12, lam, lut, n, v, a, inp[b + 7u], inp[b + 8u]), sg9_specular(c9, lam, lut, n, v, a, inp[b + 7u], inp[b + 8u]));\n    for (var k = 0u; k < 4u; k++) {\n        outp[i * 12u + 3u * k] = e[k].x;\n        outp[i * 12u + 3u * k + 1u] = e[k].y;\n        outp[i * 12u + 3u * k + 2u] = e[k].z;\n    }";
    let (out, _) = g.run(&lib, body, &inp, 12, N, Some(lut), 0).unwrap();
    let mut r2 = Pcg32::new(29, 2);
    let names = ["sg12_irradiance", "sg9_irradiance", "sg12_specular", "sg9_specular"];
    for (f, name) in names.iter().enumerate() {
        let (mut cpu, mut scale, mut gk) = (Vec::new(), Vec::new(), Vec::new());
        for (j, (n, v, a, f0, f90, lam, c)) in cases.iter().enumerate() {
            let lobes = if f % 2 == 0 { &sg12 } else { &sg9 };
            let cc = &c[..lobes.len()];
            let abs: Vec<Vec3> = cc.iter().map(|x| x.abs()).collect();
            let dfg = lut.sample2(n.dot(*v).clamp(0.0, 1.0), *a);
            let twin = |c: &[Vec3]| {
                if f < 2 {
                    sbf::recon::runtime::sg_irradiance(lobes, *lam, c, *n)
                } else {
                    sbf::recon::runtime::sg_specular_split_sum(lobes, *lam, c, *n, *v, *a, *f0, *f90, dfg)
                }
            };
            let (e, s) = (twin(cc), twin(&abs));
            // The specular's input conditioning, in f64.
            let mut dmax = [0.0f64; 3];
            let mut ftz = 0.0f64;
            if f >= 2 {
                let sum = |n: sbf::glam::DVec3, v: sbf::glam::DVec3| {
                    let d = lut.sample2(n.dot(v).clamp(0.0, 1.0) as f32, *a);
                    let w = sbf::recon::sg::SplitSumWarp::new(n, v, *a as f64, *f0 as f64, *f90 as f64, [d[0] as f64, d[1] as f64]);
                    let mut t = sbf::glam::DVec3::ZERO;
                    for (axis, ci) in lobes.iter().zip(cc) {
                        t += ci.as_dvec3() * w.lobe(&sbf::Sg { axis: axis.as_dvec3(), sharpness: *lam as f64, amplitude: 1.0 });
                    }
                    t
                };
                let (nd, vd) = (n.as_dvec3(), v.as_dvec3());
                let d = [dfg[0] as f64, dfg[1] as f64];
                let warp = sbf::recon::sg::SplitSumWarp::new(nd, vd, *a as f64, *f0 as f64, *f90 as f64, d);
                ftz = 4.0 * lobes.len() as f64 * f32::MIN_POSITIVE as f64 * warp.scale() / BAR;
                let base = sum(nd, vd);
                for _ in 0..4 {
                    let mut jitter = |x: sbf::glam::DVec3| (x + dir(&mut r2).as_dvec3() * 1.2e-7).normalize();
                    let d = sum(jitter(nd), jitter(vd)) - base;
                    for ch in 0..3 {
                        dmax[ch] = dmax[ch].max(d[ch].abs());
                    }
                }
            }
            for ch in 0..3 {
                cpu.push(e[ch] as f64);
                scale.push((s[ch] as f64).max(dmax[ch] * 1e4).max(ftz));
                gk.push(out[j * 12 + 3 * f + ch]);
            }
        }
        check(name, &gk, &cpu, &scale);
    }
}

/// sh_l1_specular and sh_l2_specular against the f64 zonal path
/// (`sbf::recon::sh::specular_zonal_rgb`, the dfg table sampled by the CPU's `Lut2`).
/// Scale: Σ_lm |g_l·c_lm·Y_lm(R_d)| times the split-sum factor (the terms the sum adds).
/// Input conditioning: R_d and the dfg lookup move with n·v, whose f32 evaluation from
/// unit vectors carries ~1.2e-7 absolute error in any f32 implementation; the change of
/// the f64 value when n and v move by 1.2e-7 (four random directions) ×1e4 (= 1/BAR) is
/// an allowed error, as in the SG test. The band ratios lose ≤ 6 bits at λ = 0.5 (see the
/// WGSL): ≤ 1e-5 relative, inside the bar.
fn sh_specular_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    use sbf::Basis as _;
    let lib = library("sh-specular");
    let lut = sbf::recon::tables::dfg();
    let mut r = Pcg32::new(29, 6);
    let (mut inp, mut cases) = (Vec::new(), Vec::new());
    for _ in 0..N {
        let n = dir(&mut r);
        let v = view(&mut r, n);
        let a = alpha(&mut r);
        let (f0, f90) = (r.next_2d()[0] as f32, 1.0f32);
        let c: Vec<Vec3> = (0..9).map(|_| Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r))).collect();
        push3(&mut inp, n);
        push3(&mut inp, v);
        inp.extend([a, f0, f90]);
        for x in &c {
            push3(&mut inp, *x);
        }
        cases.push((n, v, a, f0, f90, c));
    }
    let body = "    let b = i * 36u;\n    let n = ld3(b);\n    let v = ld3(b + 3u);\n    let a = inp[b + 6u];\n    var c9: array<vec3<f32>, 9>;\n    var c4: array<vec3<f32>, 4>;\n    for (var k = 0u; k < 9u; k++) {\n        c9[k] = ld3(b + 9u + 3u * k);\n        if (k < 4u) { c4[k] = c9[k]; }\n    }\n    let e = array<vec3<f32>, 2>(sh_l1_specular(c4, lut, n, v, a, inp[b + 7u], inp[b + 8u]), sh_l2_specular(c9, lut, n, v, a, inp[b + 7u], inp[b + 8u]));\n    for (var k = 0u; k < 2u; k++) {\n        outp[i * 6u + 3u * k] = e[k].x;\n        outp[i * 6u + 3u * k + 1u] = e[k].y;\n        outp[i * 6u + 3u * k + 2u] = e[k].z;\n    }";
    let (out, _) = g.run(&lib, body, &inp, 6, N, Some(lut), 0).unwrap();
    let mut r2 = Pcg32::new(31, 2);
    for (f, name) in ["sh_l1_specular", "sh_l2_specular"].iter().enumerate() {
        let order = f + 1;
        let sh = sbf::ShBasis::new(order).unwrap();
        let (mut cpu, mut scale, mut gk) = (Vec::new(), Vec::new(), Vec::new());
        for (j, (n, v, a, f0, f90, c)) in cases.iter().enumerate() {
            let eval = |n: sbf::glam::DVec3, v: sbf::glam::DVec3, rgb: &[[f64; 3]]| {
                let nv = n.dot(v);
                let gl = sbf::recon::sh::specular_zonal_filter(order, nv, *a as f64);
                let d = lut.sample2(nv.clamp(0.0, 1.0) as f32, *a);
                sbf::recon::sh::specular_zonal_rgb(&sh, rgb, &gl, n, v, *a as f64, *f0 as f64, *f90 as f64, [d[0] as f64, d[1] as f64])
                    .unwrap()
            };
            let rgb: Vec<[f64; 3]> = c[..sh.len()].iter().map(|x| x.as_dvec3().to_array()).collect();
            let abs: Vec<[f64; 3]> = rgb.iter().map(|x| x.map(f64::abs)).collect();
            let (nd, vd) = (n.as_dvec3(), v.as_dvec3());
            let e = eval(nd, vd, &rgb);
            // Σ|g_l c_lm Y_lm|: |Y_lm| summed with |c| (g_l ≥ 0), via the same filter.
            let y_abs = {
                let rd = sbf::ggx::dominant_direction(nd, sbf::ggx::reflect(vd, nd), (*a as f64).clamp(1e-4, 1.0));
                let mut y = vec![0.0; sh.len()];
                sh.try_eval_into(rd, &mut y).unwrap();
                let gl = sbf::recon::sh::specular_zonal_filter(order, nd.dot(vd), *a as f64);
                let d = lut.sample2(nd.dot(vd).clamp(0.0, 1.0) as f32, *a);
                let split = *f0 as f64 * d[0] as f64 + *f90 as f64 * d[1] as f64;
                (0..3)
                    .map(|ch| (0..sh.len()).map(|k| gl[(k as f64).sqrt() as usize] * (y[k] * abs[k][ch]).abs()).sum::<f64>() * split)
                    .collect::<Vec<_>>()
            };
            let mut dmax = [0.0f64; 3];
            for _ in 0..4 {
                let mut jitter = |x: sbf::glam::DVec3| (x + dir(&mut r2).as_dvec3() * 1.2e-7).normalize();
                let (np, vp) = (jitter(nd), jitter(vd));
                let ep = eval(np, vp, &rgb);
                for ch in 0..3 {
                    dmax[ch] = dmax[ch].max((ep[ch] - e[ch]).abs());
                }
            }
            for ch in 0..3 {
                cpu.push(e[ch]);
                scale.push(y_abs[ch].max(dmax[ch] * 1e4));
                gk.push(out[j * 6 + 3 * f + ch]);
            }
        }
        check(name, &gk, &cpu, &scale);
    }
}

fn ambient_dice_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("ad-eval,ad9-irradiance,ad12-irradiance,ad9-specular,ad12-specular");
    let lut = sbf::recon::tables::ad_specular_2d();
    let ad12: Vec<Vec3> = sbf::AmbientDiceSrbf::twelve().lobes().iter().map(|a| a.as_vec3()).collect();
    let ad9: Vec<Vec3> = sbf::AmbientDiceSrbf::nine_hemisphere().lobes().iter().map(|a| a.as_vec3()).collect();
    let mut r = Pcg32::new(17, 4);
    let mut inp = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..N {
        let n = dir(&mut r);
        let v = view(&mut r, n);
        let a = alpha(&mut r);
        let (f0, f90) = (r.next_2d()[0] as f32, 1.0f32);
        let c: Vec<Vec3> = (0..12).map(|_| Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r))).collect();
        push3(&mut inp, n);
        push3(&mut inp, v);
        inp.extend([a, f0, f90]);
        for x in &c {
            push3(&mut inp, *x);
        }
        cases.push((n, v, a, f0, f90, c));
    }
    let body = "    let b = i * 45u;\n    let n = ld3(b);\n    let v = ld3(b + 3u);\n    let a = inp[b + 6u];\n    var c12: array<vec3<f32>, 12>;\n    var c9: array<vec3<f32>, 9>;\n    for (var k = 0u; k < 12u; k++) {\n        c12[k] = ld3(b + 9u + 3u * k);\n        if (k < 9u) { c9[k] = c12[k]; }\n    }\n    let e = array<vec3<f32>, 4>(ad12_irradiance(c12, n), ad9_irradiance(c9, n), ad12_specular(c12, lut, n, v, a, inp[b + 7u], inp[b + 8u]), ad9_specular(c9, lut, n, v, a, inp[b + 7u], inp[b + 8u]));\n    for (var k = 0u; k < 4u; k++) {\n        outp[i * 13u + 3u * k] = e[k].x;\n        outp[i * 13u + 3u * k + 1u] = e[k].y;\n        outp[i * 13u + 3u * k + 2u] = e[k].z;\n    }\n    outp[i * 13u + 12u] = ad_srbf_eval(AD12_AXES[i % 12u], n);";
    let (out, _) = g.run(&lib, body, &inp, 13, N, Some(lut), 0).unwrap();
    let names = ["ad12_irradiance", "ad9_irradiance", "ad12_specular", "ad9_specular"];
    for (f, name) in names.iter().enumerate() {
        let (mut cpu, mut scale, mut gk) = (Vec::new(), Vec::new(), Vec::new());
        for (j, (n, v, a, f0, f90, c)) in cases.iter().enumerate() {
            let lobes = if f % 2 == 0 { &ad12 } else { &ad9 };
            let cc = &c[..lobes.len()];
            let e = if f < 2 {
                sbf::recon::runtime::ad_irradiance(lobes, cc, *n)
            } else {
                sbf::recon::runtime::ad_specular(lobes, cc, *n, *v, *a, *f0, *f90, lut)
            };
            let abs: Vec<Vec3> = cc.iter().map(|x| x.abs()).collect();
            // Σ|c_i|·w_i: the same function of |c| (its per-lobe weights are ≥ 0 for the
            // irradiance quadratic on [−1, 1] and for the specular blend).
            let s = if f < 2 {
                sbf::recon::runtime::ad_irradiance(lobes, &abs, *n)
            } else {
                sbf::recon::runtime::ad_specular(lobes, &abs, *n, *v, *a, *f0, *f90, lut)
            };
            for ch in 0..3 {
                cpu.push(e[ch] as f64);
                scale.push(s[ch] as f64);
                gk.push(out[j * 13 + 3 * f + ch]);
            }
        }
        check(name, &gk, &cpu, &scale);
    }
    let ge: Vec<f32> = (0..N).map(|j| out[j * 13 + 12]).collect();
    let ce: Vec<f64> =
        cases.iter().enumerate().map(|(j, c)| sbf::basis::ambient_dice::srbf_lobe_f32(ad12[j % 12].dot(c.0)) as f64).collect();
    // The lobe value is in [0, 0.6]; scale 0.6 (its peak) floors the relative error near its zero.
    check("ad_srbf_eval", &ge, &ce, &vec![0.6; N]);
}

/// lobe_ggx_pixel + lobe_ggx_lobe against the f64 table lookup (`Table::lobe` at the
/// `MirrorFrame` angles) on the same f32 table values, both tables. Error model: f32
/// rounding of the multilinear sum (values ≤ ~1, 16 taps) and input conditioning — γ and ψ
/// come from acos of f32 dot products, so near γ = 0 a rounding of 6e-8 in r·p moves γ by
/// ~3.5e-4 rad in any f32 implementation; as in the SG test, the change of the f64 value
/// when n, v and the axis move by 1.2e-7 (four random directions) ×1e4 (= 1/BAR) is an
/// allowed error, and values are measured against a floor of 1e-3 of the table's peak.
fn lobe_ggx_parity(lang: Lang) {
    lobe_table_parity(lang, false);
}

/// lobe_ggx_filtered_pixel + lobe_ggx_filtered_lobe (the same tables through the texture
/// unit's trilinear filter, two fetches per lobe) against the same f64 lookup on the same
/// cases. Error model: `lobe_ggx_parity`'s, plus the filter's ([`filter_precision`],
/// `Table::filter_error`), the sources added.
fn lobe_ggx_filtered_parity(lang: Lang) {
    lobe_table_parity(lang, true);
}

/// The adapter's texture filter on an f16 3D texture of the table's size (its rg16float),
/// measured by `shaders::sampler` — weight bits and whether they truncate, the returned
/// value's rounding — and printed: wgpu does not report Vulkan's `subTexelPrecisionBits`, so
/// the probe asks the sampler itself. Returns (weight error per axis, relative error of the
/// result).
fn filter_precision(g: &shaders::gpu::Gpu, table: &sbf::recon::lobe_ggx::Table) -> (f64, f64) {
    let size = shaders::gpu::lobe_filtered_texels(table).0;
    let p = shaders::sampler::measure(g, shaders::sampler::ProbeFormat::F16, size, true).unwrap();
    println!(
        "sampler on {}, {size:?} texels: {} weight bits ({}), weight error ≤ {:.3e} (seen {:.3e}), result error ≤ {:.3e} (seen {:.3e})",
        g.adapter,
        p.weight_bits,
        if p.truncates { "truncated" } else { "rounded" },
        p.weight_error(),
        p.weight_error_seen,
        p.result_error(),
        p.result_error_seen
    );
    (p.weight_error(), p.result_error())
}

/// The error model's own test: the filtered tables' parity run with every value the GPU
/// reads scaled by 1 + 2⁻⁹ — more than the model allows wherever the table is smooth
/// (there it allows 1e-4 plus the result's rounding, 2⁻¹¹ on hardware) — must fail, on any
/// adapter. A model loose enough to hide a changed table would pass it.
#[test]
fn lobe_ggx_filtered_parity_sees_a_changed_table() {
    let Some(g) = gpu(Lang::Wgsl) else { return };
    let worst = table_parity_worst(&g, true, 1.0 + 2f32.powi(-9));
    println!("changed table: worst error {:.1} × the bound", worst / BAR);
    assert!(worst > BAR, "a table scaled by 1 + 2⁻⁹ passed the filtered parity check ({worst:.3e} ≤ {BAR:e}): its bound is too loose");
}

fn lobe_table_parity(lang: Lang, filtered: bool) {
    let Some(g) = gpu(lang) else { return };
    let worst = table_parity_worst(&g, filtered, 1.0);
    assert!(worst <= BAR, "{lang:?} lobe tables (filtered: {filtered}): {worst:.3e} > {BAR:e}");
}

/// The tables' parity: the worst error over both tables in the units of `check` (≤ BAR
/// passes), the GPU reading the tables' values × `gpu_scale` (1: as committed).
fn table_parity_worst(g: &G, filtered: bool, gpu_scale: f32) -> f64 {
    let lib = library(if filtered { "lobe-ggx-filtered" } else { "lobe-ggx-specular" });
    let mut worst = 0.0f64;
    for (table, seed) in [(sbf::recon::tables::lobe_ggx_sg6(), 31), (sbf::recon::tables::lobe_ggx_ad(), 32)] {
        let (weight_error, result_error) = if filtered { filter_precision(&g.lease, table) } else { (0.0, 0.0) };
        let mut gpu_table = table.clone();
        gpu_table.values.iter_mut().for_each(|v| *v *= gpu_scale);
        let peak = table.values.iter().fold(0.0f32, |a, b| a.max(b.abs())) as f64;
        let mut r = Pcg32::new(seed, 9);
        let mut inp = Vec::new();
        let mut cases = Vec::new();
        let count = N / 4;
        for _ in 0..count {
            let n = dir(&mut r);
            let v = view(&mut r, n);
            let axis = dir(&mut r);
            let a = alpha(&mut r);
            for x in [n, v, axis] {
                push3(&mut inp, x);
            }
            inp.push(a);
            cases.push((n, v, axis, a));
        }
        let body = if filtered {
            "    let b = i * 10u;\n    let px = lobe_ggx_filtered_pixel(lobe_tex3, ld3(b), ld3(b + 3u), inp[b + 9u]);\n    let e = lobe_ggx_filtered_lobe(lobe_tex3, lobe_smp, px, ld3(b + 6u));\n    outp[i * 2u] = e.x;\n    outp[i * 2u + 1u] = e.y;"
        } else {
            "    let b = i * 10u;\n    let px = lobe_ggx_pixel(lobe_tab, ld3(b), ld3(b + 3u), inp[b + 9u]);\n    let e = lobe_ggx_lobe(lobe_tab, px, ld3(b + 6u));\n    outp[i * 2u] = e.x;\n    outp[i * 2u + 1u] = e.y;"
        };
        let o = g
            .launch(&Launch {
                library: &lib,
                body,
                input: &inp,
                out_per_item: 2,
                count,
                lobe: (!filtered).then_some(&gpu_table),
                lobe_filtered: filtered.then_some(&gpu_table),
                ..Default::default()
            })
            .unwrap();
        let mut r2 = Pcg32::new(seed, 10);
        let f64_at = |n: sbf::glam::DVec3, v: sbf::glam::DVec3, p: sbf::glam::DVec3, a: f64| {
            let (gm, ps) = sbf::recon::lobe_ggx::MirrorFrame::new(n, v).angles(p);
            table.lobe(&table.pixel(n.dot(v), a), gm, ps)
        };
        let (mut cpu, mut scale) = (Vec::new(), Vec::new());
        for (n, v, axis, a) in &cases {
            let (n, v, p, a) = (n.as_dvec3(), v.as_dvec3(), axis.as_dvec3(), *a as f64);
            let val = f64_at(n, v, p, a);
            let mut dmax = [0.0f64; 2];
            for _ in 0..4 {
                let mut jitter = |x: sbf::glam::DVec3| (x + dir(&mut r2).as_dvec3() * 1.2e-7).normalize();
                let (np, vp, pp) = (jitter(n), jitter(v), jitter(p));
                let w = f64_at(np, vp, pp, a);
                for c in 0..2 {
                    dmax[c] = dmax[c].max((w[c] - val[c]).abs());
                }
            }
            let filter = if filtered {
                let (gm, ps) = sbf::recon::lobe_ggx::MirrorFrame::new(n, v).angles(p);
                table.filter_error(&table.pixel(n.dot(v), a), gm, ps, weight_error, result_error)
            } else {
                [0.0; 2]
            };
            // The sources add: the shader's f32 arithmetic (BAR of the value, floored at
            // 1e-3 of the table's peak), its inputs' rounding (dmax) and the filter's —
            // written as the scale the error is divided by, so `check`'s bar is the sum.
            for c in 0..2 {
                cpu.push(val[c]);
                scale.push(val[c].abs().max(1e-3 * peak) + (dmax[c] + filter[c]) / BAR);
            }
        }
        let name = match (seed, filtered) {
            (31, false) => "lobe_ggx (sg6)",
            (_, false) => "lobe_ggx (ad)",
            (31, true) => "lobe_ggx_filtered (sg6)",
            (_, true) => "lobe_ggx_filtered (ad)",
        };
        worst = worst.max(worst_error(name, &o.out, &cpu, &scale));
    }
    worst
}

/// What the texture unit's filter does to the tables' error: at 1024 pseudo-random points
/// uniform in (n·v, √α, γ, ψ) (as luts/MANIFEST measures the tables), the filtered lookup
/// on the GPU and the exact multilinear lookup of the same f16 values (f64), each against
/// direct quadrature (n = 64, `sbf::recon::lobe_ggx::response`). Printed; asserted: the
/// filtered RMS is at most the lookup's plus the RMS of `Table::filter_error` (the triangle
/// inequality under that error model) — a filter reaching into the next √α tile or reading
/// the wrong node fails it by far more.
#[test]
fn lobe_ggx_filtered_keeps_the_tables_error() {
    use sbf::recon::lobe_ggx::{axis, response, RadialLobe};
    use std::f64::consts::PI;
    let Some(g) = gpu(Lang::Wgsl) else { return };
    let lib = library("lobe-ggx-filtered");
    for (table, lobe, seed) in [
        (sbf::recon::tables::lobe_ggx_sg6(), RadialLobe::Sg { sharpness: 6.0 }, 61),
        (sbf::recon::tables::lobe_ggx_ad(), RadialLobe::AdSrbf, 62),
    ] {
        let (weight_error, result_error) = filter_precision(&g.lease, table);
        let mut r = Pcg32::new(seed, 3);
        let pts: Vec<[f64; 4]> = (0..1024).map(|_| [r.next_2d(), r.next_2d()]).map(|[a, b]| [a[0], a[1], b[0], b[1]]).collect();
        let mut inp = Vec::new();
        for u in &pts {
            let (nv, alpha, gamma, psi) = (u[0], u[1] * u[1], u[2] * PI, u[3] * PI);
            let tv = nv.acos();
            let v = sbf::glam::DVec3::new(tv.sin(), 0.0, nv);
            for x in [sbf::glam::DVec3::Z, v, axis(tv, gamma, psi)] {
                push3(&mut inp, x.as_vec3());
            }
            inp.push(alpha as f32);
        }
        let body = "    let b = i * 10u;\n    let px = lobe_ggx_filtered_pixel(lobe_tex3, ld3(b), ld3(b + 3u), inp[b + 9u]);\n    let e = lobe_ggx_filtered_lobe(lobe_tex3, lobe_smp, px, ld3(b + 6u));\n    outp[i * 2u] = e.x;\n    outp[i * 2u + 1u] = e.y;";
        let o = g
            .launch(&Launch {
                library: &lib,
                body,
                input: &inp,
                out_per_item: 2,
                count: pts.len(),
                lobe_filtered: Some(table),
                ..Default::default()
            })
            .unwrap();
        let (mut gpu_sq, mut cpu_sq, mut bound_sq, mut gpu_max, mut cpu_max) = (0.0, 0.0, 0.0, 0.0f64, 0.0f64);
        for (k, u) in pts.iter().enumerate() {
            let (nv, alpha, gamma, psi) = (u[0], u[1] * u[1], u[2] * PI, u[3] * PI);
            let exact = response(lobe, nv, alpha, gamma, psi, 64);
            let lookup = table.lobe(&table.pixel(nv, alpha), gamma, psi);
            let bound = table.filter_error(&table.pixel(nv, alpha), gamma, psi, weight_error, result_error);
            for c in 0..2 {
                let (eg, ec) = (o.out[2 * k + c] as f64 - exact[c], lookup[c] - exact[c]);
                gpu_sq += eg * eg;
                cpu_sq += ec * ec;
                bound_sq += bound[c] * bound[c];
                gpu_max = gpu_max.max(eg.abs());
                cpu_max = cpu_max.max(ec.abs());
            }
        }
        let m = 2.0 * pts.len() as f64;
        let (gpu_rms, cpu_rms, bound_rms) = ((gpu_sq / m).sqrt(), (cpu_sq / m).sqrt(), (bound_sq / m).sqrt());
        println!(
            "{}: error against quadrature — filtered on {}: RMS {gpu_rms:.4e}, max {gpu_max:.4e}; exact lookup: RMS {cpu_rms:.4e}, max {cpu_max:.4e}; filter bound RMS {bound_rms:.4e}",
            lobe.name(),
            g.lease.adapter
        );
        assert!(gpu_rms <= cpu_rms + bound_rms, "{}: filtered RMS {gpu_rms:e} > lookup {cpu_rms:e} + bound {bound_rms:e}", lobe.name());
    }
}

fn lut_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    // lut2_sample is reached through ad specular; compose a config holding it.
    let lib = library("ad12-specular");
    let lut = sbf::recon::tables::ad_specular_2d();
    let mut r = Pcg32::new(19, 5);
    let mut inp = Vec::new();
    for _ in 0..N {
        // Include coordinates outside [0, 1] (clamped to the edge texel centres).
        let u = r.next_2d();
        inp.extend([(1.2 * u[0] - 0.1) as f32, (1.2 * u[1] - 0.1) as f32]);
    }
    let body = "    let s = lut2_sample(lut, inp[2u * i], inp[2u * i + 1u]);\n    outp[2u * i] = s.x;\n    outp[2u * i + 1u] = s.y;";
    let (out, _) = g.run(&lib, body, &inp, 2, N, Some(lut), 0).unwrap();
    let cpu: Vec<f64> = inp.chunks(2).flat_map(|uv| lut.sample2(uv[0], uv[1]).map(|x| x as f64)).collect();
    check("lut2_sample", &out, &cpu, &vec![0.0; cpu.len()]);
}

/// One progressive-encoder parity case: `texels` independent texels, each fed
/// `samples` samples of `basis` at random directions, on the GPU (EncoderParams as a
/// uniform, EncoderState as a read-write storage array: the Rust byte layouts go through
/// the GPU both ways) and in `ProgressiveEncoder<f32>`. With `projected`, every sample
/// also carries known projections q (random RGB per lobe, a delta light's size) through
/// `progressive_update_projected` / `update_projected`.
#[allow(clippy::too_many_arguments)]
fn progressive_case(
    g: &G,
    name: &str,
    basis: &dyn sbf::Basis,
    opts: sbf::solve::ProgressiveOptions,
    texels: usize,
    samples: usize,
    seed: u64,
    projected: bool,
) {
    use shaders::progressive::{EncoderParams, EncoderState};
    let lib = library("progressive");
    let n = basis.len();
    let params = EncoderParams::new(&opts, n).unwrap();
    let mut r = Pcg32::new(seed, 9);
    let nq = if projected { 3 * n } else { 0 };
    let per = n + 4 + nq;
    let mut inp = Vec::with_capacity(texels * samples * per);
    let mut b64 = vec![0.0; n];
    let hemi = basis.domain() == sbf::Domain::UpperHemisphere;
    for _ in 0..texels * samples {
        let mut d = dir(&mut r).as_dvec3();
        if hemi {
            d.z = d.z.abs();
        }
        basis.eval_into(d, &mut b64);
        inp.extend(b64.iter().map(|x| *x as f32));
        // Radiance in [0, 2] with a 2% chance of a 50× spike (a sun hit), weight in [0.05, 1].
        let spike = if r.next_2d()[0] < 0.02 { 50.0 } else { 1.0 };
        for _ in 0..3 {
            inp.push((2.0 * r.next_2d()[0] * spike) as f32);
        }
        inp.push((0.05 + 0.95 * r.next_2d()[0]) as f32);
        // q: signed, up to a sun's projection (E·B/4π with E ~ 60).
        for _ in 0..nq {
            inp.push(((r.next_2d()[0] - 0.3) * 10.0) as f32);
        }
    }
    let update = if projected {
        format!("var q: array<vec3<f32>, 12>;\n        for (var j = 0u; j < {n}u; j++) {{\n            q[j] = ld3(o + {n}u + 4u + 3u * j);\n        }}\n        progressive_update_projected(&st, uni, b, ld3(o + {n}u), inp[o + {n}u + 3u], q);")
    } else {
        format!("progressive_update(&st, uni, b, ld3(o + {n}u), inp[o + {n}u + 3u]);")
    };
    let body = format!(
        "    var st = io[i];\n    for (var k = 0u; k < {samples}u; k++) {{\n        let o = (i * {samples}u + k) * {per}u;\n        var b: array<f32, 12>;\n        for (var j = 0u; j < {n}u; j++) {{\n            b[j] = inp[o + j];\n        }}\n        {update}\n    }}\n    io[i] = st;\n    outp[i] = st.total_weight;"
    );
    let init = vec![<EncoderState as bytemuck::Zeroable>::zeroed(); texels];
    let o = g
        .launch(&Launch {
            library: &lib,
            body: &body,
            input: &inp,
            out_per_item: 1,
            count: texels,
            uniform: Some(("EncoderParams", bytemuck::bytes_of(&params))),
            io: Some(("EncoderState", bytemuck::cast_slice(&init))),
            ..Default::default()
        })
        .unwrap();
    let states: &[EncoderState] = bytemuck::cast_slice(&o.io);
    let (mut ga, mut ca, mut sa, mut gi, mut ci) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for t in 0..texels {
        let mut enc = sbf::solve::ProgressiveEncoder::<f32>::new(n, opts.clone());
        for k in 0..samples {
            let s = &inp[(t * samples + k) * per..][..per];
            let b: Vec<f64> = s[..n].iter().map(|x| *x as f64).collect();
            let q: Vec<[f64; 3]> = s[n + 4..].chunks(3).map(|c| [c[0] as f64, c[1] as f64, c[2] as f64]).collect();
            enc.update_projected(&b, [s[n] as f64, s[n + 1] as f64, s[n + 2] as f64], s[n + 3] as f64, &q);
        }
        let st = &states[t];
        assert_eq!(st.samples as u64, enc.sample_count(), "{name}: texel {t} sample count");
        assert_eq!(o.out[t], st.total_weight, "{name}: texel {t}: outp and io disagree");
        let c = enc.coefficients();
        // Scale: the texel's largest amplitude. Every update mixes all lobes through Δ,
        // so a lobe's rounding error is proportional to the whole coefficient vector,
        // not to its own (possibly cancelled) value.
        let amax = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (i, g3) in st.coefficients(n).iter().enumerate() {
            for ch in 0..3 {
                ga.push(g3[ch]);
                ca.push(c[(i, ch)]);
                sa.push(amax);
            }
        }
        gi.extend(st.integrals(n));
        ci.extend(enc.integrals());
        gi.push(st.total_weight);
        ci.push(enc.total_weight());
    }
    let big = sa.iter().fold(0.0f64, |m, x| m.max(*x));
    println!("progressive {name}: largest amplitude {big:.3e}");
    check(&format!("progressive {name} amplitudes"), &ga, &ca, &sa);
    // Running means of B² and the total weight: sums of positives, plain relative error.
    check(&format!("progressive {name} ∫B², W"), &gi, &ci, &vec![0.0; ci.len()]);
}

fn progressive_parity(lang: Lang) {
    use sbf::solve::{Denominator, Iteration, ProgressiveOptions};
    let Some(g) = gpu(lang) else { return };
    let ad12 = sbf::AmbientDiceSrbf::twelve();
    let ad9 = sbf::AmbientDiceSrbf::nine_hemisphere();
    let sh2 = sbf::ShBasis::new(2).unwrap();
    let sh1 = sbf::ShBasis::new(1).unwrap();
    // 10⁵ texels × 8 samples per configuration: Roughton's progressive LS (Gauss–Seidel,
    // α = 3, eq. 7.15) on AD12, progressive NNLS on SH L2 (signed basis values, so the
    // clamp is active), and the public running average (Jacobi, α = 1, clamp to the exact
    // mean of Y² = 1/4π for orthonormal SH) on SH L1.
    progressive_case(&g, "LS/AD12", &ad12, ProgressiveOptions::default(), N, 8, 31, false);
    progressive_case(&g, "NNLS/SH2", &sh2, ProgressiveOptions::non_negative(), N, 8, 32, false);
    let ra = ProgressiveOptions::running_average(&[1.0; 4], 4.0 * std::f64::consts::PI, false);
    progressive_case(&g, "running-average/SH1", &sh1, ra, N, 8, 33, false);
    // The raw running mean as denominator (noisy at low counts by design: amplitudes reach
    // 1e10 here) on short runs, where the GPU's rounding differences cannot compound far.
    let raw = ProgressiveOptions { denominator: Denominator::Raw, iteration: Iteration::Jacobi, ..ProgressiveOptions::default() };
    progressive_case(&g, "raw-Jacobi/SH2", &sh2, raw, N, 8, 34, false);
    // Long runs: s = w/W falls to ~1e-3, where f32 updates lose the most digits.
    progressive_case(&g, "LS/AD9 long", &ad9, ProgressiveOptions::default(), 2000, 1024, 36, false);
    progressive_case(&g, "NNLS/AD9 long", &ad9, ProgressiveOptions::non_negative(), 2000, 1024, 35, false);
    // Known projections (delta lights, MIS light samples) on the bake's configurations.
    let bake = ProgressiveOptions { acceleration: 1.0, ..ProgressiveOptions::default() };
    progressive_case(&g, "projected LS/SH2", &sh2, bake.clone(), N, 8, 37, true);
    progressive_case(&g, "projected NNLS/AD9 long", &ad9, ProgressiveOptions { non_negative: true, ..bake }, 2000, 256, 38, true);
    // The bake's SH update: the projection with the exact mean of Y² (1/4π), light samples
    // included.
    let projection = ProgressiveOptions::projection(vec![0.25 / std::f64::consts::PI; 9], false);
    progressive_case(&g, "projection/SH2", &sh2, projection, N, 8, 39, true);
}

fn ambient_dice_bezier_parity(lang: Lang) {
    let Some(g) = gpu(lang) else { return };
    let lib = library("ad-bezier");
    let bez = sbf::AmbientDiceBezier::new();
    let ycocg = sbf::AmbientDiceYCoCg::new();
    let ico = bez.icosahedron();
    let mut r = Pcg32::new(37, 10);
    let (mut inp, mut cases) = (Vec::new(), Vec::new());
    for k in 0..N {
        // 2% of the directions sit on a vertex (the interior weight's D = 0 branch) and 2%
        // on an edge's midpoint (two faces tie): the places a face search can disagree.
        let d = match k % 50 {
            0 => ico.vertices()[k / 50 % 12].as_vec3(),
            1 => {
                let f = ico.faces()[k / 50 % 20];
                (ico.vertices()[f[0]] + ico.vertices()[f[1]]).normalize().as_vec3()
            }
            _ => dir(&mut r),
        };
        let c: Vec<Vec3> = (0..36).map(|_| Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r))).collect();
        push3(&mut inp, d);
        for x in &c {
            push3(&mut inp, *x);
        }
        cases.push((d, c));
    }
    let body = "    let o = i * 111u;\n    let d = ld3(o);\n    var c: array<vec3<f32>, 36>;\n    var y: array<f32, 36>;\n    var co: array<f32, 12>;\n    var cg: array<f32, 12>;\n    for (var k = 0u; k < 36u; k++) {\n        c[k] = ld3(o + 3u + 3u * k);\n        y[k] = c[k].x;\n        if (k < 12u) {\n            co[k] = c[k].y;\n            cg[k] = c[k].z;\n        }\n    }\n    let e = ad_bezier_eval(c, d);\n    let q = ad_ycocg_eval(y, co, cg, d);\n    outp[i * 6u] = e.x;\n    outp[i * 6u + 1u] = e.y;\n    outp[i * 6u + 2u] = e.z;\n    outp[i * 6u + 3u] = q.x;\n    outp[i * 6u + 4u] = q.y;\n    outp[i * 6u + 5u] = q.z;";
    let (out, _) = g.run(&lib, body, &inp, 6, N, None, 0).unwrap();
    let (mut cb, mut sb, mut cy, mut sy) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut lw = [0.0; 12];
    let mut r2 = Pcg32::new(41, 11);
    // RGB value of the Bézier patch and its Σ|terms| per channel.
    let patch = |c: &[Vec3], d: sbf::glam::DVec3| {
        let (idx, w) = bez.weights(d);
        let (mut v, mut s) = ([0.0f64; 3], [0.0f64; 3]);
        for ch in 0..3 {
            for k in 0..3 {
                for j in 0..3 {
                    let t = w[k][j] * c[3 * idx[k] + j][ch] as f64;
                    v[ch] += t;
                    s[ch] += t.abs();
                }
            }
        }
        (v, s)
    };
    for (d, c) in &cases {
        let d = d.as_dvec3();
        let y: [f64; 36] = std::array::from_fn(|k| c[k].x as f64);
        let co: [f64; 12] = std::array::from_fn(|k| c[k].y as f64);
        let cg: [f64; 12] = std::array::from_fn(|k| c[k].z as f64);
        let (v, s) = patch(c, d);
        let q = ycocg.eval_rgb(&y, &co, &cg, d);
        // Input conditioning: the barycentrics b_k = d·n_k carry ~1e-7 absolute f32
        // rounding in any implementation, which matters where a value is a small sum
        // (near a vertex the other corners' b are ~0). The change of the value when d
        // moves by 1.2e-7 (four random directions) is an allowed error (×1e4 = 1/BAR).
        let (mut dv, mut dq) = (0.0f64, 0.0f64);
        for _ in 0..4 {
            let dp = (d + dir(&mut r2).as_dvec3() * 1.2e-7).normalize();
            let (vp, _) = patch(c, dp);
            let qp = ycocg.eval_rgb(&y, &co, &cg, dp);
            for ch in 0..3 {
                dv = dv.max((vp[ch] - v[ch]).abs());
                dq = dq.max((qp[ch] - q[ch]).abs());
            }
        }
        cb.extend(v);
        sb.extend(s.map(|x| x.max(dv * 1e4)));
        cy.extend(q);
        // Scale: Σ|luma terms| + Σ|chroma terms| (RGB is a ±1 combination of Y, Co, Cg).
        let (idx, w) = bez.weights(d);
        let luma: f64 = (0..3).flat_map(|k| (0..3).map(move |j| (k, j))).map(|(k, j)| (w[k][j] * y[3 * idx[k] + j]).abs()).sum();
        sbf::Basis::eval_into(&ycocg.chroma, d, &mut lw);
        let chroma: f64 = (0..12).map(|v| lw[v] * (co[v].abs() + cg[v].abs())).sum();
        sy.extend([(luma + chroma).max(dq * 1e4); 3]);
    }
    let col = |a: usize| (0..N).flat_map(|j| (0..3).map(move |ch| (j, ch))).map(|(j, ch)| out[j * 6 + a + ch]).collect::<Vec<f32>>();
    check("ad_bezier_eval", &col(0), &cb, &sb);
    check("ad_ycocg_eval", &col(3), &cy, &sy);
}

/// The helpers the functions above are built from, each against its own twin (so a
/// helper's error cannot hide inside a larger sum).
fn helper_parity(lang: Lang) {
    use sbf::recon::ambient_dice::{
        lobe_irradiance_fit, SpecularFit, DIFFUSE_FIT_LISTING_8_1, DIFFUSE_FIT_MINIMAX, SPECULAR_FIT_LISTING_8_1,
    };
    let Some(g) = gpu(lang) else { return };
    let lib = library("all");
    let lut = sbf::recon::tables::ad_specular_2d();
    let ad12: Vec<sbf::glam::DVec3> = sbf::AmbientDiceSrbf::twelve().lobes().iter().map(|a| a.as_vec3().as_dvec3()).collect();
    let bez = sbf::AmbientDiceBezier::new();
    let ico = bez.icosahedron();
    let mut r = Pcg32::new(43, 12);
    const IN: usize = 22;
    const OUT: usize = 52;
    let mut inp = Vec::with_capacity(N * IN);
    for _ in 0..N {
        let (d, n) = (dir(&mut r), dir(&mut r));
        let v = view(&mut r, n);
        let w = view(&mut r, Vec3::Z);
        let a = alpha(&mut r);
        // λ log-uniform in [1e-6, 1e4] (sg_integral's small-λ limit and large λ); expm1's
        // x = ±10^u, u ∈ [−8, 1.3] (the Taylor branch, its switch at 1e-2, and exp − 1).
        let lam = (1e-6 * 1e10f64.powf(r.next_2d()[0])) as f32;
        let x = (10f64.powf(-8.0 + 9.3 * r.next_2d()[0]) * if r.next_2d()[0] < 0.5 { -1.0 } else { 1.0 }) as f32;
        let f0 = r.next_2d()[0] as f32;
        let (c0, c1) = (coeff(&mut r), Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r)));
        let xl = (2.4 * r.next_2d()[0] - 1.2) as f32;
        for p in [d, n, v, w] {
            push3(&mut inp, p);
        }
        inp.extend([a, lam, x, f0, c0]);
        push3(&mut inp, c1);
        inp.extend([n.dot(v), xl]);
    }
    let body = format!(
        "    let o = i * {IN}u;\n    let d = ld3(o);\n    let n = ld3(o + 3u);\n    let v = ld3(o + 6u);\n    let w = ld3(o + 9u);\n    let a = inp[o + 12u];\n    let f0 = inp[o + 15u];\n    let axis = AD12_AXES[i % 12u];\n    var r: array<f32, {OUT}>;\n    let tb = tangent_frame(d);\n    let rf = reflect_about(v, n);\n    let l1 = sh_eval_l1(d);\n    let l2 = sh_eval_l2(d);\n    let fit = ad_specular_fit(n, v, a);\n    let loc = ad_ico_locate(d);\n    let bw = ad_bezier_weights(d);\n    for (var k = 0u; k < 3u; k++) {{\n        r[k] = tb[0][k];\n        r[3u + k] = tb[1][k];\n        r[6u + k] = rf[k];\n        r[29u + k] = fit.r[k];\n        r[37u + k] = loc.b[k];\n        r[40u + 3u * k] = bw.w[k].x;\n        r[41u + 3u * k] = bw.w[k].y;\n        r[42u + 3u * k] = bw.w[k].z;\n        r[49u + k] = f32(bw.vertices[k]);\n    }}\n    r[9] = ggx_lambda(w, a);\n    r[10] = ggx_a_term(w, a);\n    r[11] = sg_integral(inp[o + 13u]);\n    r[12] = expm1_f32(inp[o + 14u]);\n    for (var k = 0u; k < 4u; k++) {{\n        r[13u + k] = l1[k];\n    }}\n    for (var k = 0u; k < 9u; k++) {{\n        r[17u + k] = l2[k];\n    }}\n    r[26] = sh_l1_geomerics_channel(inp[o + 16u], ld3(o + 17u), n);\n    r[27] = ad_srbf_lobe(inp[o + 21u]);\n    r[28] = ad_lobe_irradiance(axis, n);\n    r[32] = fit.focus;\n    r[33] = fit.alpha_lerp;\n    r[34] = ad_specular_lobe(fit, axis);\n    r[35] = ad_specular_scale(lut, inp[o + 20u], a, f0, 1.0);\n    r[36] = f32(loc.face);\n    for (var k = 0u; k < {OUT}u; k++) {{\n        outp[i * {OUT}u + k] = r[k];\n    }}"
    );
    let (out, _) = g.run(&lib, &body, &inp, OUT, N, Some(lut), 0).unwrap();
    // (name, output slots) → CPU values and scales.
    let mut cpu = vec![0.0f64; N * OUT];
    let mut scale = vec![0.0f64; N * OUT];
    let mut face_ties = 0;
    for j in 0..N {
        let s = &inp[j * IN..][..IN];
        let v3 = |k: usize| sbf::glam::DVec3::new(s[k] as f64, s[k + 1] as f64, s[k + 2] as f64);
        let (d, n, v, w) = (v3(0), v3(3), v3(6), v3(9));
        let (a, lam, x, f0, c0, c1, nv, xl) =
            (s[12] as f64, s[13] as f64, s[14] as f64, s[15] as f64, s[16] as f64, v3(17), s[20], s[21] as f64);
        let axis = ad12[j % 12];
        let c = &mut cpu[j * OUT..][..OUT];
        let sc = &mut scale[j * OUT..][..OUT];
        let (t, b) = sbf::basis::ambient_dice_bezier::tangent_frame(d);
        let rf = sbf::ggx::reflect(v, n);
        let fit = SpecularFit::new(&SPECULAR_FIT_LISTING_8_1, &DIFFUSE_FIT_LISTING_8_1, n, v, a);
        let (face, bary) = ico.locate(d);
        let (verts, bw) = bez.weights(d);
        for k in 0..3 {
            (c[k], c[3 + k], c[6 + k], c[29 + k], c[37 + k]) = (t[k], b[k], rf[k], fit.reflection()[k], bary[k]);
            (c[40 + 3 * k], c[41 + 3 * k], c[42 + 3 * k], c[49 + k]) = (bw[k][0], bw[k][1], bw[k][2], verts[k] as f64);
        }
        // Unit vectors, barycentrics (≤ 1.3) and Bézier weights (≤ 1): absolute error (scale 1).
        for k in [0, 1, 2, 3, 4, 5, 6, 7, 8, 29, 30, 31, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46, 47, 48] {
            sc[k] = 1.0;
        }
        // Λ, a, the SG integral and expm1 are relative-accurate: plain relative error (0).
        (c[9], c[10]) = (sbf::ggx::lambda(w, a), a * a * (w.x * w.x + w.y * w.y) / (w.z * w.z));
        c[11] = sbf::Sg { axis: sbf::glam::DVec3::Z, sharpness: lam, amplitude: 1.0 }.integral();
        c[12] = x.exp_m1();
        let y1 = sbf::basis::sh_fast::eval_sh_l1(d.as_vec3());
        let y2 = sbf::basis::sh_fast::eval_sh_l2(d.as_vec3());
        for k in 0..4 {
            (c[13 + k], sc[13 + k]) = (y1[k] as f64, 1.0);
        }
        for k in 0..9 {
            (c[17 + k], sc[17 + k]) = (y2[k] as f64, 1.0);
        }
        // Geomerics per channel: the twin through the RGB function (band-1 order y, z, x);
        // scale |c0| + 2|c1| bounds its terms (r0 + 2|r1|, with K00, K1/3 < 1).
        let cc = [c0, c1.y, c1.z, c1.x].map(|q| Vec3::new(q as f32, 0.0, 0.0));
        c[26] = sbf::recon::runtime::sh_l1_geomerics_irradiance(&cc, n.as_vec3()).x as f64;
        sc[26] = c0.abs() + 2.0 * c1.length();
        // The SRBF lobe is in [0, 0.6]: absolute against its peak.
        (c[27], sc[27]) = (sbf::basis::ambient_dice::srbf_lobe(xl), 0.6);
        // Quadratics: Σ|terms| (the minimax quadratic nearly vanishes at cos ≈ −0.92).
        let quad_scale = |p: &[f64; 3], x: f64| p[0] + (p[1] * x).abs() + p[2] * x * x;
        let xd = axis.dot(n).clamp(-1.0, 1.0);
        (c[28], sc[28]) = (lobe_irradiance_fit(&DIFFUSE_FIT_MINIMAX, xd), quad_scale(&DIFFUSE_FIT_MINIMAX, xd));
        (c[32], c[33], sc[32], sc[33]) = (fit.focus(), fit.alpha_lerp(), 1.0, 1.0);
        c[34] = fit.lobe(axis);
        let cm = fit.reflection().dot(axis);
        let cb = cm + (n.dot(axis) - cm) * fit.focus();
        sc[34] = sbf::basis::ambient_dice::srbf_lobe(cm).max(quad_scale(&DIFFUSE_FIT_LISTING_8_1, cb));
        let l = lut.sample2(nv.clamp(0.0, 1.0), a as f32);
        (c[35], sc[35]) = ((f0 * l[0] as f64) + l[1] as f64, f0 * (l[0] as f64).abs() + (l[1] as f64).abs());
        c[36] = face as f64;
        // Two faces tie on an edge (their centres' dots agree to f32 rounding): there
        // the GPU may pick the other face, and its barycentrics and weights differ in
        // layout while the values they give agree (ad_bezier_eval's parity covers that).
        let gface = out[j * OUT + 36] as usize;
        if gface != face {
            let gap = (ico.centre(face).dot(d) - ico.centre(gface).dot(d)).abs();
            assert!(gap < 1e-6, "ad_ico_locate: face {gface} vs {face} with a dot gap of {gap:e}");
            face_ties += 1;
            for k in (36..52).filter(|&k| k != 36) {
                c[k] = out[j * OUT + k] as f64;
            }
            c[36] = gface as f64;
        }
    }
    println!("ad_ico_locate: {face_ties} edge ties resolved to the neighbouring face");
    assert!(face_ties < N / 1000, "{face_ties} face disagreements");
    let groups: [(&str, std::ops::Range<usize>); 20] = [
        ("tangent_frame", 0..6),
        ("reflect_about", 6..9),
        ("ggx_lambda", 9..10),
        ("ggx_a_term", 10..11),
        ("sg_integral", 11..12),
        ("expm1_f32", 12..13),
        ("sh_eval_l1", 13..17),
        ("sh_eval_l2", 17..26),
        ("sh_l1_geomerics_channel", 26..27),
        ("ad_srbf_lobe", 27..28),
        ("ad_lobe_irradiance", 28..29),
        ("ad_specular_fit.r", 29..32),
        ("ad_specular_fit.focus", 32..33),
        ("ad_specular_fit.alpha_lerp", 33..34),
        ("ad_specular_lobe", 34..35),
        ("ad_specular_scale", 35..36),
        ("ad_ico_locate.face", 36..37),
        ("ad_ico_locate.b", 37..40),
        ("ad_bezier_weights.w", 40..49),
        ("ad_bezier_weights.vertices", 49..52),
    ];
    for (name, range) in groups {
        let pick = |v: &dyn Fn(usize) -> f64| (0..N).flat_map(|j| range.clone().map(move |k| j * OUT + k)).map(v).collect::<Vec<f64>>();
        let gk: Vec<f32> = pick(&|i| out[i] as f64).iter().map(|x| *x as f32).collect();
        check(name, &gk, &pick(&|i| cpu[i]), &pick(&|i| scale[i]));
    }
}

/// Every WGSL function runs in a parity kernel (CPU-only check, so a new function without
/// a parity test fails CI even where no adapter exists). A function counts as tested when
/// a call `name(` appears inside a string literal of this file — the kernel bodies; a
/// mention in a comment or in Rust code does not count — or when a tested function calls
/// it (the composer's dependency closure, which `compose.rs` checks against naga's call
/// graph), so helpers are tested through their callers.
#[test]
fn every_wgsl_function_has_a_parity_test() {
    let literals = string_literals(include_str!("gpu_parity.rs"));
    let mut all_fns = Vec::new();
    for m in shaders::modules::all() {
        for it in compose::split(&m).items {
            if it.text.lines().any(|l| l.starts_with("fn ")) {
                all_fns.push((m.name, it.name));
            }
        }
    }
    let called: Vec<&str> = all_fns.iter().filter(|(_, n)| literals.contains(&format!("{n}("))).map(|(_, n)| n.as_str()).collect();
    let covered = compose::compose_roots(Config::parse("all").unwrap(), &called).unwrap();
    let covered: std::collections::BTreeSet<&str> = covered.included.iter().map(|(_, n)| n.as_str()).collect();
    let missing: Vec<String> = all_fns.iter().filter(|(_, n)| !covered.contains(n.as_str())).map(|(m, n)| format!("{m}::{n}")).collect();
    // 39 functions at the time of writing: the split must have found them.
    assert!(all_fns.len() >= 39, "only {} WGSL functions found", all_fns.len());
    assert!(missing.is_empty(), "WGSL functions no parity kernel runs: {missing:?}");
}

/// The contents of the Rust string literals in `src` (plain and raw), concatenated with
/// newlines; comments, char literals and code are skipped.
fn string_literals(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let (mut out, mut i) = (String::new(), 0);
    while i < b.len() {
        let c = b[i];
        if c == '/' && b.get(i + 1) == Some(&'/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && b.get(i + 1) == Some(&'*') {
            while i + 1 < b.len() && !(b[i] == '*' && b[i + 1] == '/') {
                i += 1;
            }
            i += 2;
        } else if c == '\'' {
            // A char literal ('x', '\n', '\'') or a lifetime ('a).
            if b.get(i + 1) == Some(&'\\') {
                i += 2;
                while i < b.len() && b[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if b.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                i += 1;
            }
        } else if c == 'r'
            && (b.get(i + 1) == Some(&'"') || b.get(i + 1) == Some(&'#'))
            && (i == 0 || !(b[i - 1].is_alphanumeric() || b[i - 1] == '_'))
        {
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                i += 1;
                continue;
            }
            let close: String = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
            let rest: String = b[j + 1..].iter().collect();
            let end = rest.find(&close).unwrap_or(rest.len());
            out += &rest[..end];
            out.push('\n');
            i = j + 1 + rest[..end].chars().count() + close.chars().count();
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                if i < b.len() {
                    out.push(b[i]);
                }
                i += 1;
            }
            out.push('\n');
            i += 1;
        } else {
            i += 1;
        }
    }
    out
}

/// Stochastic light culling (slc.wgsl) against sbf::slc::runtime on 10⁵ random lights:
/// α log-uniform in [0.01, 1], cos θ_i in [1e-3, 1], η in [0.2, 5], ξ in [0.01, 1], random
/// view transforms. Scales: a vector's or matrix row's largest magnitude (rounding is
/// relative to it). Items where a branch is decided by a near tie — p ≈ ξ in the culled
/// estimate, |b_x| ≈ |b_y| in eq. 17 — are excluded (both branches are valid; rounding
/// picks one) and counted.
fn slc_parity(lang: Lang) {
    use sbf::slc::runtime as rt;
    let Some(g) = gpu(lang) else { return };
    let lib = library("slc");
    let mut r = Pcg32::new(77, 3);
    const PER: usize = 30;
    const OUT: usize = 64;
    let delta = 1e-3f32;
    let mut inp = Vec::with_capacity(N * PER);
    for _ in 0..N {
        let n = dir(&mut r);
        let mut wi = dir(&mut r);
        let c = (1e-3 + (1.0 - 1e-3) * r.next_2d()[0]) as f32;
        // ω_i at cos θ_i = c from n.
        let t = (wi - n * wi.dot(n)).normalize_or(n.any_orthonormal_vector());
        wi = (n * c + t * (1.0 - c * c).max(0.0).sqrt()).normalize();
        let q = Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r)) * 5.0;
        let alpha = (0.01f64 * 100f64.powf(r.next_2d()[0])) as f32;
        let xi = (0.01 + 0.99 * r.next_2d()[0]) as f32;
        let phi = (0.1 + 10.0 * r.next_2d()[0]) as f32;
        let eta = (0.2 * 25f64.powf(r.next_2d()[0])) as f32;
        let f0 = r.next_2d()[0] as f32;
        let view = sbf::glam::Mat3::from_quat(sbf::glam::Quat::from_axis_angle(dir(&mut r), (6.0 * r.next_2d()[0]) as f32));
        let origin = Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r)) * 3.0;
        let (intensity, l, theta, dn) =
            ((r.next_2d()[0] * 2.0) as f32, (r.next_2d()[0] * 30.0) as f32, (r.next_2d()[0] * std::f64::consts::PI) as f32, coeff(&mut r));
        for x in [q, wi, n] {
            push3(&mut inp, x);
        }
        inp.extend_from_slice(&[alpha, xi, phi, eta, f0]);
        inp.extend_from_slice(&view.to_cols_array());
        push3(&mut inp, origin);
        inp.extend_from_slice(&[intensity, l, theta, dn]);
        assert_eq!(inp.len() % PER, 0);
    }
    let body = format!(
        "    let o = i * {PER}u;\n    let q = ld3(o);\n    let wi = ld3(o + 3u);\n    let n = ld3(o + 6u);\n    let alpha = inp[o + 9u];\n    let xi = inp[o + 10u];\n    let phi = inp[o + 11u];\n    let eta = inp[o + 12u];\n    let f0 = inp[o + 13u];\n    let view = mat3x3<f32>(ld3(o + 14u), ld3(o + 17u), ld3(o + 20u));\n    let origin = ld3(o + 23u);\n    let intensity = inp[o + 26u];\n    let l = inp[o + 27u];\n    let theta = inp[o + 28u];\n    let dn = inp[o + 29u];\n    let delta = {delta:?};\n    let cos_i = dot(wi, n);\n    var v: array<f32, {OUT}>;\n    let p = slc_acceptance(intensity, delta, l);\n    v[0] = p;\n    v[1] = slc_random_range(intensity, delta, xi);\n    v[2] = slc_culled_estimate(intensity / (l * l), p, xi);\n    v[3] = slc_schlick_max(f0, cos_i);\n    v[4] = slc_dielectric_max(eta, cos_i);\n    v[5] = slc_g1_dist(cos_i, alpha);\n    let r = slc_spheroid_scale(phi, v[4], v[5], cos_i, delta, xi);\n    v[6] = r;\n    v[7] = slc_bound_surface(theta, r, alpha);\n    let e = slc_ggx_spheroid(q, wi, n, alpha, r);\n    for (var k = 0u; k < 3u; k++) {{\n        v[8u + k] = e.center[k];\n        v[11u + k] = e.axes[0][k];\n        v[14u + k] = e.axes[1][k];\n        v[17u + k] = e.axes[2][k];\n        v[20u + k] = e.radii[k];\n    }}\n    let s = slc_diffuse_sphere(q, n, phi, delta, xi);\n    v[23] = s.center.x;\n    v[24] = s.center.y;\n    v[25] = s.center.z;\n    v[26] = s.radius;\n    v[27] = slc_diffuse_intensity_bound(dn, phi);\n    let c = slc_cull_transform(e, view, origin);\n    for (var k = 0u; k < 3u; k++) {{\n        v[28u + k] = c.transform[0][k];\n        v[31u + k] = c.transform[1][k];\n        v[34u + k] = c.transform[2][k];\n        v[37u + k] = c.center[k];\n    }}\n    v[40] = slc_cos_theta_h_max(cos_i);\n    v[41] = slc_dielectric_fresnel(eta, cos_i);\n    v[42] = slc_ggx_ndf(cos_i, alpha);\n    let ao = slc_any_orthonormal(n);\n    let sw = slc_stretching(e);\n    let bw = slc_test_space_rotation(sw);\n    for (var k = 0u; k < 3u; k++) {{\n        v[43u + k] = ao[k];\n        v[46u + k] = sw[0][k];\n        v[49u + k] = sw[1][k];\n        v[52u + k] = sw[2][k];\n        v[55u + k] = bw[0][k];\n        v[58u + k] = bw[1][k];\n        v[61u + k] = bw[2][k];\n    }}\n    for (var k = 0u; k < {OUT}u; k++) {{\n        outp[i * {OUT}u + k] = v[k];\n    }}"
    );
    let (out, _) = g.run(&lib, &body, &inp, OUT, N, None, 0).unwrap();
    let (mut gk, mut cpu, mut scale) = (Vec::new(), Vec::new(), Vec::new());
    let (mut ties_p, mut ties_b, mut ties_f) = (0, 0, 0);
    for k in 0..N {
        let s = &inp[k * PER..(k + 1) * PER];
        let v3 = |j: usize| Vec3::new(s[j], s[j + 1], s[j + 2]);
        let (q, wi, n) = (v3(0), v3(3), v3(6));
        let (alpha, xi, phi, eta, f0) = (s[9], s[10], s[11], s[12], s[13]);
        let view = sbf::glam::Mat3::from_cols(v3(14), v3(17), v3(20));
        let origin = v3(23);
        let (intensity, l, theta, dn) = (s[26], s[27], s[28], s[29]);
        let cos_i = wi.dot(n);
        let p = rt::acceptance_probability(intensity, delta, l);
        let fmax = rt::dielectric_max(eta, cos_i);
        let g1 = rt::g1_dist(cos_i, alpha);
        let rr = rt::spheroid_scale(phi, fmax, g1, cos_i, delta, xi);
        let e = rt::ggx_spheroid(q, wi, n, alpha, rr);
        let sph = rt::diffuse_sphere(q, n, phi, delta, xi);
        let (m, mc) = rt::cull_transform(&e, view, origin);
        // Near ties: skip the item (both branches valid).
        let axes_v = view * e.axes;
        let sv = axes_v * sbf::glam::Mat3::from_diagonal(e.radii.recip()) * axes_v.transpose();
        let (bx, by) = ((sv * Vec3::X).length_squared(), (sv * Vec3::Y).length_squared());
        if (p - xi).abs() < 1e-5 {
            ties_p += 1;
            continue;
        }
        // η → 1: F_max → 0 cancels in f32 (relative error ~2e-7/√F), and every bound
        // output scales with √F_max; below 1e-5 that conditioning, not the shader, sets the
        // error. Excluded and counted (a light that reflects nothing has no range to cull).
        // Near the critical angle (η² − sin²θ → 0⁺) F's slope in cos θ is unbounded
        // (g = √(η² − sin²θ)): f32 rounding of g² becomes an O(1e-7/g) error in F. Items
        // within g² < 1e-3 at cos θ_i or cos θ_h^max are excluded and counted with them.
        let g2 = |c: f32| eta * eta - (1.0 - c * c);
        let near_tir = |c: f32| (0.0..1e-3).contains(&g2(c));
        if fmax < 1e-5 || near_tir(cos_i) || near_tir(rt::cos_theta_h_max(cos_i)) {
            ties_f += 1;
            continue;
        }
        let sw = e.stretching();
        let (wx, wy) = ((sw * Vec3::X).length_squared(), (sw * Vec3::Y).length_squared());
        if (bx - by).abs() < 2e-5 * bx.max(by) || (wx - wy).abs() < 2e-5 * wx.max(wy) {
            ties_b += 1;
            continue;
        }
        let mut c = vec![
            p,
            rt::random_range(intensity, delta, xi),
            rt::culled_estimate(intensity / (l * l), p, xi),
            rt::schlick_max(f0, cos_i),
            fmax,
            g1,
            rr,
            rt::bound_surface(theta, rr, alpha),
        ];
        c.extend(e.center.to_array());
        c.extend(e.axes.to_cols_array());
        c.extend(e.radii.to_array());
        c.extend(sph.center.to_array());
        c.push(sph.radius);
        c.push(rt::diffuse_intensity_bound(dn, phi));
        c.extend(m.to_cols_array());
        c.extend(mc.to_array());
        c.push(rt::cos_theta_h_max(cos_i));
        c.push(rt::dielectric_fresnel(eta, cos_i));
        c.push(rt::ggx_ndf(cos_i, alpha));
        c.extend(n.any_orthonormal_vector().to_array());
        c.extend(sw.to_cols_array());
        c.extend(rt::test_space_rotation(sw).to_cols_array());
        let mag = |v: &[f32]| v.iter().fold(0.0f64, |a, x| a.max(x.abs() as f64));
        let mut sc = vec![0.0f64; OUT];
        for j in [0, 1, 2, 3, 4, 5, 6, 7, 40, 41, 42] {
            sc[j] = c[j].abs() as f64;
        }
        // GGX D = α²/(π t²), t = α²c² + (1 − c²), at c = cos θ_i from a 3-term dot product
        // (≤ 3·2⁻²⁴ relative on either side, so c² may differ by 6·2⁻²⁴) plus the roundings
        // of c² and 1 − c² (2·2⁻²⁴ absolute): t is off by up to 8·2⁻²⁴ absolute, and D ∝ 1/t²
        // by twice that relative to t. Near the peak (c → 1, small α: t ~ α²) that is
        // 16·2⁻²⁴/t — a backend that fuses or orders these differently (GL llvmpipe) does.
        let t_ndf = {
            let (c2, a2) = ((cos_i as f64).powi(2), (alpha as f64).powi(2));
            a2 * c2 + (1.0 - c2).max(0.0)
        };
        sc[42] *= (16.0 * 2f64.powi(-24) / t_ndf / BAR).max(1.0);
        // The bounding surface s = r·√(π·D(cos(θ/2))) = r·α/t, t = α²c² + (1 − c²), calls
        // the backend's cos, whose conformance bound (Vulkan/SPIR-V precision for sin/cos)
        // is 2⁻¹¹ absolute on [−π, π] — hardware usually does far better, but only that is
        // guaranteed (the H200's cos is off by ~1e-6, a 2e-3 relative error of s at small t,
        // measured). ∂ln s/∂c = 2c(1 − α²)/t,
        // so the allowed error is |s|·2c(1 − α²)/t·2⁻¹¹ (rounding of t itself, as for D
        // above, is smaller); BAR applies where that is below it.
        let t_bound = {
            let c = (0.5 * theta as f64).cos();
            let a2 = (alpha as f64).powi(2);
            (a2 * c * c + (1.0 - c * c).max(0.0), 2.0 * c * (1.0 - a2))
        };
        sc[7] *= (t_bound.1 / t_bound.0 * 2f64.powi(-11) / BAR).max(1.0);
        // Dielectric Fresnel F = ((c − g)/(c + g))² (and its parallel twin) cancels for
        // η → 1: c − g carries an absolute rounding of ~1e-7·(c + g), so F's absolute error
        // is ~2√F·1e-7 ≤ 1e-4·(2e-3·√F); the scale is max(F, 2e-3·√F)·… with 5× headroom.
        for j in [4, 41] {
            sc[j] = sc[j].max(1e-2 * (c[j].abs() as f64).sqrt());
        }
        // Two more f32 terms of F's error, each side's rounding (CPU reference and shader,
        // which may fuse a·b + c differently — glslang's HLSL path emits Fma):
        // - g² = η² − (1 − c²) is rounded to ≤ 2⁻²⁴(η² + c² + 1 + g²) ≈ 1.8e-7 per side, and
        //   g = √g² turns that into 1.8e-7/(2g): large at grazing angles with η → 1, where
        //   c − g also cancels (measured: η 1.0002, cos θ 0.079, the f32 CPU value itself
        //   1.8e-4 from f64).
        // - cos θ_i = dot(ω_i, n) is computed in the kernel: ≤ 3·2⁻²⁴ ≈ 1.8e-7.
        // Each moves F by |slope| × its size; the slopes come from F written here (000
        // eq. 3–5 in f64: F = ½[((c − g)/(c + g))² + ((g − η²c)/(g + η²c))²]) by central
        // differences. Scale = 2 sides × the sum / BAR, with 5× headroom.
        {
            let e64 = eta as f64;
            let fresnel_g2 = |c: f64, g2: f64| {
                let g = g2.max(0.0).sqrt();
                let (a, b) = ((c - g) / (c + g), (g - e64 * e64 * c) / (g + e64 * e64 * c));
                0.5 * (a * a + b * b)
            };
            let g2_of = |c: f64| e64 * e64 - (1.0 - c * c);
            let slope = |f: &dyn Fn(f64) -> f64, x: f64, h: f64| ((f(x + h) - f(x - h)) / (2.0 * h)).abs();
            let budget = |c: f64| {
                let g2 = g2_of(c);
                let by_g2 = slope(&|x| fresnel_g2(c, x), g2, 1e-3 * g2) * 1.8e-7;
                let by_cos = slope(&|x| fresnel_g2(x, g2_of(x)), c, 1e-6_f64.min(0.5 * c)) * 1.8e-7;
                2.0 * 5.0 * (by_g2 + by_cos) / BAR
            };
            let ci = cos_i as f64;
            sc[41] = sc[41].max(budget(ci));
            let ch = sbf::slc::reference::cos_theta_h_max(ci);
            sc[4] = sc[4].max(if fresnel_g2(1.0, g2_of(1.0)) >= fresnel_g2(ch, g2_of(ch)) { budget(1.0 - 1e-6) } else { budget(ch) });
        }
        let ranges = [(8, 11), (11, 20), (20, 23), (23, 26), (26, 28), (28, 37), (37, 40), (43, 46), (46, 55), (55, 64)];
        for (a, b) in ranges {
            let m = mag(&c[a..b]);
            for x in sc.iter_mut().take(b).skip(a) {
                *x = m;
            }
        }
        // The centre comes from q + offset: its rounding scales with |q| + r_u.
        for x in sc.iter_mut().take(11).skip(8) {
            *x = *x + q.length() as f64 + e.radii.x as f64;
        }
        for x in sc.iter_mut().take(26).skip(23) {
            *x = *x + q.length() as f64 + sph.radius as f64;
        }
        // M·c: |M|·|c| (the product's rounding scale).
        let cscale = mag(&m.to_cols_array()) * ((view * e.center + origin).length() as f64) * 3.0;
        for x in sc.iter_mut().take(40).skip(37) {
            *x = x.max(cscale);
        }
        gk.extend_from_slice(&out[k * OUT..(k + 1) * OUT]);
        cpu.extend(c.iter().map(|x| *x as f64));
        scale.extend(sc);
    }
    println!(
        "slc parity: {} items compared, {ties_p} near p = ξ, {ties_b} near |b_x| = |b_y| and {ties_f} with F_max < 1e-5 or near total internal reflection excluded",
        cpu.len() / OUT
    );
    assert!(ties_p + ties_b + ties_f < N / 100, "too many items excluded");
    check("slc (all outputs)", &gk, &cpu, &scale);
}

/// The single-scattering helpers (slc_point_sphere, slc_ray_sphere, slc_equiangular_sample
/// and _pdf) against sbf::slc::runtime on 10⁵ random rays, lights and spheres. Error
/// model: the chord's roots carry the rounding of b and √disc, relative to |b| + √|c| +
/// their own size (not to the root, which cancels for a grazing ray — scale = |t| +
/// |b| + √|c|); equiangular t = t_c + h·tan θ moves by (h² + (t − t_c)²)/h per unit of θ,
/// and θ = atan2 carries ~1e-7 rad of rounding, so t's scale is that factor plus |t|, and
/// the pdf's relative scale 1 + 2|t − t_c|/h; near-tangent rays (disc < 1e-4·(b² + |c|))
/// whose hit/miss may flip are excluded and counted.
fn slc_media_parity(lang: Lang) {
    use sbf::slc::runtime as rt;
    let Some(g) = gpu(lang) else { return };
    let lib = library("slc");
    let mut r = Pcg32::new(79, 5);
    const PER: usize = 12;
    const OUT: usize = 10;
    let mut inp = Vec::with_capacity(N * PER);
    for _ in 0..N {
        let o = Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r)) * 2.0;
        let d = dir(&mut r);
        let q = Vec3::new(coeff(&mut r), coeff(&mut r), coeff(&mut r)) * 6.0;
        let intensity = (0.01 + 2.0 * r.next_2d()[0]) as f32;
        let xi = (0.01 + 0.99 * r.next_2d()[0]) as f32;
        let u = r.next_2d()[0] as f32;
        push3(&mut inp, o);
        push3(&mut inp, d);
        push3(&mut inp, q);
        inp.extend_from_slice(&[intensity, xi, u]);
    }
    let body = format!(
        "    let o = i * {PER}u;\n    let ro = ld3(o);\n    let d = ld3(o + 3u);\n    let q = ld3(o + 6u);\n    let s = slc_point_sphere(q, inp[o + 9u], 0.01, inp[o + 10u]);\n    let c = slc_ray_sphere(ro, d, s);\n    let tc = dot(d, q - ro);\n    let h = max(length(q - ro - d * tc), 1e-3);\n    let e = slc_equiangular_sample(tc, h, tc - 4.0, tc + 3.0, inp[o + 11u]);\n    outp[i * {OUT}u] = s.center.x;\n    outp[i * {OUT}u + 1u] = s.center.y;\n    outp[i * {OUT}u + 2u] = s.center.z;\n    outp[i * {OUT}u + 3u] = s.radius;\n    outp[i * {OUT}u + 4u] = c.x;\n    outp[i * {OUT}u + 5u] = c.y;\n    outp[i * {OUT}u + 6u] = c.z;\n    outp[i * {OUT}u + 7u] = e.x;\n    outp[i * {OUT}u + 8u] = e.y;\n    outp[i * {OUT}u + 9u] = slc_equiangular_pdf(tc, h, tc - 4.0, tc + 3.0, tc + 0.5);"
    );
    let (out, _) = g.run(&lib, &body, &inp, OUT, N, None, 0).unwrap();
    let (mut gk, mut cpu, mut scale, mut grazing) = (Vec::new(), Vec::new(), Vec::new(), 0);
    for k in 0..N {
        let s = &inp[k * PER..(k + 1) * PER];
        let v3 = |j: usize| Vec3::new(s[j], s[j + 1], s[j + 2]);
        let (o, d, q) = (v3(0), v3(3), v3(6));
        let sph = rt::point_sphere(q, s[9], 0.01, s[10]);
        let oc = o - sph.center;
        let (b, c) = (d.dot(oc), oc.length_squared() - sph.radius * sph.radius);
        if (b * b - c).abs() < 1e-4 * (b * b + c.abs()) {
            grazing += 1;
            continue;
        }
        let chord = rt::ray_sphere(o, d, &sph);
        let tc = d.dot(q - o);
        let h = (q - o - d * tc).length().max(1e-3);
        let (t, pdf) = rt::equiangular_sample(tc, h, tc - 4.0, tc + 3.0, s[11]);
        let (t0, t1, hit) = chord.map_or((0.0, 0.0, 0.0), |(a, b)| (a, b, 1.0));
        let root = (b.abs() + c.abs().sqrt()) as f64;
        let dt = ((h * h + (t - tc) * (t - tc)) / h) as f64;
        gk.extend_from_slice(&out[k * OUT..(k + 1) * OUT]);
        let pdf_mid = rt::equiangular_pdf(tc, h, tc - 4.0, tc + 3.0, tc + 0.5);
        cpu.extend([sph.center.x, sph.center.y, sph.center.z, sph.radius, t0, t1, hit, t, pdf, pdf_mid].map(|x| x as f64));
        let cs = sph.center.length() as f64;
        scale.extend([
            cs,
            cs,
            cs,
            sph.radius as f64,
            t0.abs() as f64 + root,
            t1.abs() as f64 + root,
            1.0,
            dt + t.abs() as f64,
            pdf as f64 * (1.0 + 2.0 * ((t - tc).abs() / h) as f64),
            // At a fixed t the pdf is well conditioned: relative.
            pdf_mid as f64,
        ]);
    }
    println!("slc media parity: {} items, {grazing} near-tangent rays excluded", cpu.len() / OUT);
    assert!(grazing < N / 100, "too many near-tangent rays");
    check("slc media helpers", &gk, &cpu, &scale);
}

/// The tile test (slc_tile_corners, slc_ellipsoid_hits_corners, slc_unit_sphere_hits_aabb)
/// against sbf::slc::runtime on 10⁵ random (spheroid, tile) pairs: the corners to f32
/// rounding, and the same keep/cull decision wherever the CPU's squared distance from the
/// transformed centre to the AABB is not within 1e-4 of 1 (a tie rounding may flip).
fn slc_tile_parity(lang: Lang) {
    use sbf::slc::runtime as rt;
    let Some(g) = gpu(lang) else { return };
    let lib = library("slc");
    let mut r = Pcg32::new(78, 3);
    let (w, h, tx, ty) = (1920.0f32, 1080.0f32, 0.8f32, 0.45f32);
    let mut inp = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..N {
        let q = Vec3::new(coeff(&mut r) * 4.0, coeff(&mut r) * 2.0, -1.0 - 9.0 * r.next_2d()[0] as f32);
        let n = dir(&mut r);
        let mut wi = dir(&mut r);
        if wi.dot(n) < 0.0 {
            wi = -wi;
        }
        let alpha = (0.05 + 0.95 * r.next_2d()[0]) as f32;
        let rr = (0.2 + 2.0 * r.next_2d()[0]) as f32;
        let e = rt::ggx_spheroid(q, wi, n, alpha, rr);
        let (m, mc) = rt::cull_transform(&e, sbf::glam::Mat3::IDENTITY, Vec3::ZERO);
        let (x0, y0) = ((r.next_2d()[0] * 119.0).floor() as f32 * 16.0, (r.next_2d()[0] * 67.0).floor() as f32 * 16.0);
        let z0 = (0.5 + 8.0 * r.next_2d()[0]) as f32;
        let z1 = z0 + (6.0 * r.next_2d()[0]) as f32;
        inp.extend_from_slice(&m.to_cols_array());
        push3(&mut inp, mc);
        inp.extend_from_slice(&[x0, y0, z0, z1]);
        cases.push((m, mc, x0, y0, z0, z1));
    }
    let body = format!(
        "    let o = i * 16u;\n    let c = SlcCullEllipsoid(mat3x3<f32>(ld3(o), ld3(o + 3u), ld3(o + 6u)), ld3(o + 9u));\n    let x0 = inp[o + 12u];\n    let y0 = inp[o + 13u];\n    let corners = slc_tile_corners(x0, y0, x0 + 16.0, y0 + 16.0, vec2<f32>({w:?}, {h:?}), vec2<f32>({tx:?}, {ty:?}), inp[o + 14u], inp[o + 15u]);\n    for (var k = 0u; k < 8u; k++) {{\n        outp[i * 25u + 3u * k] = corners[k].x;\n        outp[i * 25u + 3u * k + 1u] = corners[k].y;\n        outp[i * 25u + 3u * k + 2u] = corners[k].z;\n    }}\n    outp[i * 25u + 24u] = select(0.0, 1.0, slc_ellipsoid_hits_corners(c, corners));\n    outp[N_OUT + i] = select(0.0, 1.0, slc_unit_sphere_hits_aabb(c.center, min(corners[0], corners[7]), max(corners[0], corners[7])));"
    );
    // A second block of N outputs after the 25 per case: the plain sphere–AABB test.
    let body = body.replace("N_OUT", &format!("{}u", 25 * N));
    let (out, _) = g.run(&lib, &body, &inp, 26, N, None, 0).unwrap();
    let (mut gk, mut cpu, mut scale) = (Vec::new(), Vec::new(), Vec::new());
    let (mut ties, mut kept) = (0, 0);
    for (k, (m, mc, x0, y0, z0, z1)) in cases.iter().enumerate() {
        let corners = rt::tile_corners(*x0, *y0, x0 + 16.0, y0 + 16.0, w, h, tx, ty, *z0, *z1);
        for c in &corners {
            let s = c.abs().max_element() as f64;
            for j in 0..3 {
                cpu.push(c[j] as f64);
                scale.push(s);
            }
        }
        gk.extend_from_slice(&out[k * 25..k * 25 + 24]);
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for c in &corners {
            lo = lo.min(*m * *c);
            hi = hi.max(*m * *c);
        }
        let d2 = (*mc - mc.clamp(lo, hi)).length_squared();
        let hit = rt::ellipsoid_hits_corners(*m, *mc, &corners);
        kept += hit as usize;
        if (d2 - 1.0).abs() < 1e-4 {
            ties += 1;
            continue;
        }
        assert_eq!(out[k * 25 + 24] == 1.0, hit, "case {k}: GPU and CPU disagree (d² = {d2})");
        let (a, b) = (corners[0].min(corners[7]), corners[0].max(corners[7]));
        let d2 = (*mc - mc.clamp(a, b)).length_squared();
        if (d2 - 1.0).abs() >= 1e-4 {
            assert_eq!(out[25 * N + k] == 1.0, rt::unit_sphere_hits_aabb(*mc, a, b), "case {k}: sphere–AABB test");
        }
    }
    println!("slc tile test: {N} cases, {kept} kept, {ties} near-ties not compared");
    check("slc_tile_corners", &gk, &cpu, &scale);
}
