//! GPU reconstruction throughput (`shaders bench`): evaluations per second for SH9,
//! SG9/SG12 (Hill + ASG warp) and AD9/AD12 (quadratic + Listing 8.1 fit × LUT), diffuse
//! only and diffuse + specular, SH9 with a prefiltered cube map of 8²–64² (PF8–PF64,
//! trilinear through the texture unit), the engines' directional lightmap decodes (Godot L1,
//! MonoSH, Enlighten single/RGB), and the progressive encoder's per-sample update (state
//! loaded and stored, as a baker does). Each invocation reads its normal, view and α from a
//! buffer and one of 1024 coefficient sets (as a lightmap fetch would), evaluates, and
//! writes the sum of the RGB result, so that nothing is optimised away.

use crate::compose::{self, Config};
use crate::gpu::{Gpu, Launch};
use crate::progressive::{EncoderParams, EncoderState};

/// One measured kernel.
#[derive(Debug, Clone)]
pub struct Row {
    pub name: &'static str,
    pub lobes: usize,
    /// "diffuse", "diffuse + specular", one of the variants "diffuse + specular (…)" or
    /// "encode" (one progressive update).
    pub signal: &'static str,
    /// Evaluations per dispatch.
    pub count: usize,
    pub seconds_per_dispatch: f64,
    pub evals_per_second: f64,
}

/// The encode kernel keeps one 208-byte state per invocation; its count is capped so
/// that the state array stays within a 2 GiB storage binding (1 GiB here).
pub const MAX_ENCODE_COUNT: usize = 1 << 22;

const SETS: usize = 1024;

/// Where the per-invocation normal, view and α come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Inputs {
    /// Read from a buffer (28 bytes per evaluation: memory traffic included).
    Buffer,
    /// Generated in the shader from the invocation index (a spherical Fibonacci normal,
    /// a perturbed view, a hashed α): arithmetic cost only; neighbouring invocations get
    /// unrelated inputs (the worst case for table lookups' caches).
    Generated,
    /// Generated as a raster pass sees them: invocation i is pixel (i mod 2048, i / 2048)
    /// of a screen looking down at a gently curved surface (normals and views vary slowly
    /// across neighbouring pixels) with α constant over 64 × 64-pixel material patches —
    /// the coherence a frame's shading has (the representative workload for tables).
    Screen,
}

/// (name, configuration, lobes, signal, WGSL body).
/// The signal of the kernels that take specular through the per-lobe GGX tables.
pub const TABLE_SPECULAR: &str = "diffuse + specular (lobe tables)";
/// The signal of the kernels that take it through the same tables, hardware-filtered.
pub const FILTERED_SPECULAR: &str = "diffuse + specular (lobe tables, filtered)";

fn kernels(inputs: Inputs) -> Vec<(&'static str, &'static str, usize, &'static str, String)> {
    // Input layout: 12 axes (36 floats), the SG sharpness (read, so the compiler cannot
    // fold exp(−λ)), then SETS × 12 RGB coefficients, then per invocation n (3), v (3),
    // α (1) when read from the buffer.
    let geometry = match inputs {
        Inputs::Buffer => "    let pb = 37u + SETS_U * 36u + i * 7u;\n    let n = ld3(pb);\n    let v = ld3(pb + 3u);\n    let a = inp[pb + 6u];\n".replace("SETS_U", &format!("{SETS}u")),
        Inputs::Screen => "    let sx = f32(i % 2048u) / 2048.0;\n    let sy = f32(i / 2048u) / 2048.0;\n    let n = normalize(vec3<f32>(0.35 * sin(9.42 * sx) * cos(3.1 * sy), 1.0, 0.35 * cos(7.3 * sy + 1.0)));\n    let v = normalize(vec3<f32>(0.0, 1.2, -0.4) - vec3<f32>(sx - 0.5, 0.0, sy - 0.5));\n    let a = 0.05 + 0.9 * fract(floor(sx * 32.0) * 0.618034 + floor(sy * 32.0) * 0.414214);\n".to_string(),
        Inputs::Generated => "    let fi = f32(i) + 0.5;\n    let z = 1.0 - 2.0 * fract(fi * 0.000123456);\n    let phi = 2.39996323 * fi;\n    let rr = sqrt(max(1.0 - z * z, 0.0));\n    let n = vec3<f32>(rr * cos(phi), rr * sin(phi), z);\n    let v = normalize(n + 0.6 * vec3<f32>(sin(1.7 * phi), cos(2.3 * phi), sin(0.7 * phi)));\n    let a = 0.05 + 0.9 * fract(fi * 0.618034);\n".to_string(),
    };
    let pre = move |k: usize| {
        format!(
            "    let cb = 37u + (i % {SETS}u) * 36u;\n    let lam = inp[36u];\n{geometry}    var c: array<vec3<f32>, {k}>;\n    for (var j = 0u; j < {k}u; j++) {{\n        c[j] = ld3(cb + 3u * j);\n    }}\n"
        )
    };
    // The anisotropic warp (sg-specular-asg), SG's fit path before the split sum, for the
    // cost side by side.
    let sg_kernel = |k: usize, spec: bool, asg: bool| {
        let mut b = pre(k);
        b += &format!("    var e = vec3<f32>(0.0);\n    for (var j = 0u; j < {k}u; j++) {{\n        e += c[j] * sg_hill_irradiance(ld3(3u * j), lam, n);\n    }}\n");
        if asg {
            b += &format!("    let w = sg_asg_warp(n, v, a, 0.04, 1.0);\n    for (var j = 0u; j < {k}u; j++) {{\n        e += c[j] * sg_asg_lobe(w, ld3(3u * j), lam);\n    }}\n");
        } else if spec {
            // The split sum reads the dfg table, bound as `lut` for these kernels.
            b += &format!("    let w = sg_split_sum_setup(lut, n, v, a, 0.04, 1.0);\n    for (var j = 0u; j < {k}u; j++) {{\n        e += c[j] * sg_split_sum_lobe(w, ld3(3u * j), lam);\n    }}\n");
        }
        b + "    outp[i] = e.x + e.y + e.z;"
    };
    let sg = |k: usize, spec: bool| sg_kernel(k, spec, false);
    // The per-lobe GGX tables (lobe_ggx.wgsl) instead of the fits: SG axes from the buffer,
    // AD axes from the layout constants; f0 = 0.04, f90 = 1. One loop over the lobes adds
    // each lobe's irradiance and specular, as a shader using the tables would: with the AD
    // irradiance as a separate call taking the coefficient array by value
    // (`ad{k}_irradiance(c, n)`) before the table loop, the NVIDIA driver kept the array in
    // local memory and AD 9 took 0.6 ms more than SG 9 at 4 M evaluations (H200).
    // `filtered`: the same tables through the texture unit's filter (lobe_ggx_filtered_*,
    // two fetches per lobe) instead of 16 loads.
    let table = |k: usize, sg: bool, filtered: bool| {
        let mut b = pre(k);
        let (axis, diffuse) = if sg {
            ("ld3(3u * j)".to_string(), "sg_hill_irradiance(axis, lam, n)")
        } else {
            (format!("AD{k}_AXES[j]"), "ad_lobe_irradiance(axis, n)")
        };
        let (pixel, lobe) = if filtered {
            ("lobe_ggx_filtered_pixel(lobe_tex3, n, v, a)", "lobe_ggx_filtered_lobe(lobe_tex3, lobe_smp, px, axis)")
        } else {
            ("lobe_ggx_pixel(lobe_tab, n, v, a)", "lobe_ggx_lobe(lobe_tab, px, axis)")
        };
        b += &format!(
            "    var e = vec3<f32>(0.0);\n    let px = {pixel};\n    for (var j = 0u; j < {k}u; j++) {{\n        let axis = {axis};\n        let r = {lobe};\n        e += c[j] * ({diffuse} + 0.04 * r.x + r.y);\n    }}\n"
        );
        b + "    outp[i] = e.x + e.y + e.z;"
    };
    let ad = |k: usize, spec: bool| {
        let mut b = pre(k);
        b += &format!("    var e = ad{k}_irradiance(c, n);\n");
        if spec {
            b += &format!("    e += ad{k}_specular(c, lut, n, v, a, 0.04, 1.0);\n");
        }
        b + "    outp[i] = e.x + e.y + e.z;"
    };
    let sh = pre(9) + "    let e = sh_l2_irradiance(c, n);\n    outp[i] = e.x + e.y + e.z;";
    // The engines' directional lightmap formats (engine.wgsl): the colour in c[0], the unit
    // textures' RGB in c[1..], Enlighten's rescaling factors in the last set's xyz. The values
    // come from the f32 buffer like every other kernel's (an engine's f16/8-bit texture
    // fetch is not modelled).
    let engine = |k: usize, call: &str| pre(k) + &format!("    let e = {call};\n    outp[i] = e.x + e.y + e.z;");
    // Progressive encoding as a baker does it: load the texel's state, evaluate the
    // basis at the sample direction (here n, radiance from the coefficient set), add the
    // sample, store the state (208 bytes read and written per sample).
    let encode = |k: usize| {
        pre(k)
            + &format!(
                "    var b: array<f32, 12>;\n    for (var j = 0u; j < {k}u; j++) {{\n        b[j] = ad_srbf_eval(ld3(3u * j), n);\n    }}\n    var st = io[i];\n    progressive_update(&st, uni, b, c[0], 1.0);\n    io[i] = st;\n    outp[i] = st.total_weight;"
            )
    };
    // A prefiltered environment map with SH L2 for diffuse (`probes`' `pf` modes): the cube
    // read trilinearly at the reflected direction at level log₂(α·N/2)
    // (`sbf::recon::prefiltered::lod`), times the DFG terms (`lut` is the dfg table here),
    // f0 = 0.04, f90 = 1.
    let prefiltered = |size: usize| {
        let top = sbf::recon::prefiltered::lod(1.0, size);
        pre(9)
            + &format!(
                "    var e = sh_l2_irradiance(c, n);\n    let lod = clamp(log2(max(a, 1e-4) * {size}.0 / 2.0), 0.0, {top:.1});\n    let p = textureSampleLevel(env_cube, env_smp, reflect(-v, n), lod).rgb;\n    let d = lut2_sample(lut, max(dot(n, v), 0.0), a);\n    e += p * (0.04 * d.x + d.y);\n    outp[i] = e.x + e.y + e.z;"
            )
    };
    vec![
        ("SH9 (L2)", "sh-l2-irradiance", 9, "diffuse", sh),
        ("PF8", "sh-l2-irradiance,sh-specular", 9, "diffuse + specular", prefiltered(8)),
        ("PF16", "sh-l2-irradiance,sh-specular", 9, "diffuse + specular", prefiltered(16)),
        ("PF32", "sh-l2-irradiance,sh-specular", 9, "diffuse + specular", prefiltered(32)),
        ("PF64", "sh-l2-irradiance,sh-specular", 9, "diffuse + specular", prefiltered(64)),
        ("SG9", "sg-irradiance", 9, "diffuse", sg(9, false)),
        ("SG9", "sg-irradiance,sg-specular", 9, "diffuse + specular", sg(9, true)),
        ("SG9", "sg-irradiance,sg-specular-asg", 9, "diffuse + specular (ASG warp)", sg_kernel(9, true, true)),
        ("SG12", "sg-irradiance", 12, "diffuse", sg(12, false)),
        ("SG12", "sg-irradiance,sg-specular", 12, "diffuse + specular", sg(12, true)),
        ("AD9", "ad9-irradiance", 9, "diffuse", ad(9, false)),
        ("AD9", "ad9-irradiance,ad9-specular", 9, "diffuse + specular", ad(9, true)),
        ("AD12", "ad12-irradiance", 12, "diffuse", ad(12, false)),
        ("AD12", "ad12-irradiance,ad12-specular", 12, "diffuse + specular", ad(12, true)),
        ("SG9", "sg-irradiance,lobe-ggx-specular", 9, TABLE_SPECULAR, table(9, true, false)),
        ("SG12", "sg-irradiance,lobe-ggx-specular", 12, TABLE_SPECULAR, table(12, true, false)),
        ("AD9", "ad9-irradiance,lobe-ggx-specular", 9, TABLE_SPECULAR, table(9, false, false)),
        ("AD12", "ad12-irradiance,lobe-ggx-specular", 12, TABLE_SPECULAR, table(12, false, false)),
        ("SG9", "sg-irradiance,lobe-ggx-filtered", 9, FILTERED_SPECULAR, table(9, true, true)),
        ("SG12", "sg-irradiance,lobe-ggx-filtered", 12, FILTERED_SPECULAR, table(12, true, true)),
        ("AD9", "ad9-irradiance,lobe-ggx-filtered", 9, FILTERED_SPECULAR, table(9, false, true)),
        ("AD12", "ad12-irradiance,lobe-ggx-filtered", 12, FILTERED_SPECULAR, table(12, false, true)),
        ("AD12 progressive LS", "ad-eval,progressive", 12, "encode", encode(12)),
        ("Godot L1", "engine-formats", 4, "diffuse", engine(4, "godot_l1_irradiance(c[0], c[1], c[2], c[3], n)")),
        ("MonoSH (Bakery default, non-linear)", "engine-formats", 2, "diffuse", engine(2, "monosh_irradiance(c[0], c[1], n)")),
        ("MonoSH linear", "engine-formats", 2, "diffuse", engine(2, "monosh_linear_irradiance(c[0], c[1], n)")),
        ("Enlighten", "engine-formats", 3, "diffuse", engine(3, "enlighten_irradiance(c[0], vec4<f32>(c[1], c[2].x), n)")),
        (
            "Enlighten RGB",
            "engine-formats",
            5,
            "diffuse",
            engine(5, "enlighten_rgb_irradiance(c[0], vec4<f32>(c[1], c[4].x), vec4<f32>(c[2], c[4].y), vec4<f32>(c[3], c[4].z), n)"),
        ),
    ]
}

/// Bytes of one encoder state (`EncoderState`).
const STATE_BYTES: usize = std::mem::size_of::<EncoderState>();

/// Runs every kernel over `count` invocations, `repeats` dispatches each (after a warm-up).
/// Where a buffer of `count` items would exceed the device's storage-binding limit, that
/// kernel runs fewer invocations per dispatch (its row says how many): the time per
/// evaluation does not depend on the count once the device is full.
pub fn run(gpu: &Gpu, count: usize, repeats: usize, inputs: Inputs) -> Result<Vec<Row>, String> {
    let limit = gpu.device().limits().max_storage_buffer_binding_size as usize;
    // The input buffer: 36 lobe floats + SETS coefficient sets of 36, then 7 per item.
    let fixed = 36 + SETS * 36;
    let count = if inputs == Inputs::Buffer { count.min((limit / 4).saturating_sub(fixed) / 7) } else { count };
    // One f32 out per item.
    let count = count.min(limit / 4);
    if count == 0 {
        return Err(format!("the device's storage-binding limit ({limit} bytes) holds no evaluation"));
    }
    let mut rng = sbf::sampling::Pcg32::new(99, 7);
    let mut inp: Vec<f32> = Vec::with_capacity(36 + SETS * 36 + count * 7);
    for a in sbf::layout::vogel_hemisphere(12).map_err(|e| e.to_string())? {
        inp.extend([a.x as f32, a.y as f32, a.z as f32]);
    }
    inp.push(6.0); // SG sharpness
    for _ in 0..SETS * 36 {
        inp.push(rng.next_2d()[0] as f32);
    }
    for _ in 0..if inputs == Inputs::Buffer { count } else { 0 } {
        let n = sbf::sampling::uniform_sphere(rng.next_2d());
        let v = sbf::sampling::uniform_sphere(rng.next_2d());
        let v = if v.dot(n) < 0.0 { -v } else { v };
        inp.extend([n.x as f32, n.y as f32, n.z as f32, v.x as f32, v.y as f32, v.z as f32, (0.05 + 0.9 * rng.next_2d()[0]) as f32]);
    }
    let lut = sbf::recon::tables::ad_specular_2d();
    let dfg = sbf::recon::tables::dfg();
    let mut rows = Vec::new();
    let params = EncoderParams::new(&sbf::solve::ProgressiveOptions::default(), 12)?;
    for (name, cfg, lobes, signal, body) in kernels(inputs) {
        let lib = compose::compose(&Config::parse(cfg)?)?.source;
        let uses_lut = body.contains("lut");
        let encodes = signal == "encode";
        let count = if encodes { count.min(MAX_ENCODE_COUNT).min(limit / STATE_BYTES) } else { count };
        let states = if encodes { vec![<EncoderState as bytemuck::Zeroable>::zeroed(); count] } else { Vec::new() };
        let table = if name.starts_with("SG") { sbf::recon::tables::lobe_ggx_sg6() } else { sbf::recon::tables::lobe_ggx_ad() };
        // The map's content does not change the cost (a smooth sky-like function).
        let cube = name
            .strip_prefix("PF")
            .and_then(|n| n.parse::<usize>().ok())
            .map(|size| {
                sbf::recon::prefiltered::PrefilteredCube::build(size, |m, _, f, i, j| {
                    let x = (f * 31 + i * 7 + j * 3 + m) as f32;
                    [1.0 + 0.5 * (0.1 * x).sin(), 0.8 + 0.3 * (0.07 * x).cos(), 0.6]
                })
            })
            .transpose()
            .map_err(|e| e.to_string())?;
        let o = gpu.launch(&Launch {
            lobe: body.contains("lobe_tab").then_some(table),
            lobe_filtered: body.contains("lobe_tex3").then_some(table),
            library: &lib,
            body: &body,
            input: &inp,
            out_per_item: 1,
            count,
            lut: uses_lut.then_some(if body.contains("sg_split_sum") || body.contains("env_cube") { dfg } else { lut }),
            cube: cube.as_ref(),
            uniform: encodes.then_some(("EncoderParams", bytemuck::bytes_of(&params))),
            io: encodes.then_some(("EncoderState", bytemuck::cast_slice(&states))),
            repeats,
            lang: crate::export::Lang::Wgsl,
        })?;
        if let Some(x) = o.out.iter().find(|x| !x.is_finite()) {
            return Err(format!("{name}: non-finite output {x}"));
        }
        let t = o.seconds_per_dispatch;
        rows.push(Row { name, lobes, signal, count, seconds_per_dispatch: t, evals_per_second: count as f64 / t });
    }
    Ok(rows)
}

/// A Markdown table of the rows with the AD/SG cost ratios ([Roughton19 Table 8.1] compares
/// AD9 with SG9 frame times).
pub fn table(gpu: &Gpu, count: usize, repeats: usize, inputs: Inputs, rows: &[Row]) -> String {
    let mut s = format!(
        "GPU: {}\n{count} evaluations per dispatch ({inputs:?} inputs), mean of {repeats} back-to-back dispatches after a warm-up (wall clock around submit and wait).\n\n| basis | lobes | signal | ms per dispatch | M evals/s |\n|---|---|---|---|---|\n",
        gpu.adapter
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.3} | {:.1} |\n",
            r.name,
            r.lobes,
            r.signal,
            r.seconds_per_dispatch * 1e3,
            r.evals_per_second * 1e-6
        );
    }
    for r in rows.iter().filter(|r| r.count != count) {
        s += &format!("\n{} ({}): {} invocations per dispatch (capped: one encoder state each).", r.name, r.signal, r.count);
    }
    let find = |n: &str, sp: &str| rows.iter().find(|r| r.name == n && r.signal == sp).map(|r| r.seconds_per_dispatch);
    for sp in ["diffuse", "diffuse + specular", TABLE_SPECULAR, FILTERED_SPECULAR] {
        if let (Some(a), Some(b)) = (find("AD9", sp), find("SG9", sp)) {
            s += &format!("\nAD9/SG9 time ratio ({sp}): {:.3}", a / b);
        }
    }
    for b in ["SG9", "SG12", "AD9", "AD12"] {
        if let (Some(fit), Some(t), Some(f)) = (find(b, "diffuse + specular"), find(b, TABLE_SPECULAR), find(b, FILTERED_SPECULAR)) {
            s += &format!("\n{b} tables / fits: {:.2} (16 loads per lobe), {:.2} (filtered, 2 fetches)", t / fit, f / fit);
        }
    }
    s +=
        "\n([Roughton19 Table 8.1]: frame times AD9 2.30 ms / SG9 3.27 ms = 0.70; above the 1.39 ms no-lightmap base, 0.91/1.88 = 0.48.)\n";
    s
}
