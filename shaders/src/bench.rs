//! GPU reconstruction throughput (`shaders bench`): evaluations per second for SH9,
//! SG9/SG12 (Hill + ASG warp) and AD9/AD12 (quadratic + Listing 8.1 fit × LUT), diffuse
//! only and diffuse + specular. Each invocation reads its normal, view and α from a
//! buffer and one of 1024 coefficient sets (as a lightmap fetch would), evaluates, and
//! writes the sum of the RGB result, so that nothing is optimised away.

use crate::compose::{self, Config};
use crate::gpu::Gpu;

/// One measured kernel.
#[derive(Debug, Clone)]
pub struct Row {
    pub name: &'static str,
    pub lobes: usize,
    pub specular: bool,
    pub seconds_per_dispatch: f64,
    pub evals_per_second: f64,
}

const SETS: usize = 1024;

/// Where the per-invocation normal, view and α come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Inputs {
    /// Read from a buffer (28 bytes per evaluation: memory traffic included).
    Buffer,
    /// Generated in the shader from the invocation index (a spherical Fibonacci normal,
    /// a perturbed view, a hashed α): arithmetic cost only.
    Generated,
}

/// (name, configuration, lobes, specular, WGSL body).
fn kernels(inputs: Inputs) -> Vec<(&'static str, &'static str, usize, bool, String)> {
    // Input layout: 12 axes (36 floats), then SETS × 12 RGB coefficients, then per
    // invocation n (3), v (3), α (1) when read from the buffer.
    let geometry = match inputs {
        Inputs::Buffer => "    let pb = 36u + SETS_U * 36u + i * 7u;\n    let n = ld3(pb);\n    let v = ld3(pb + 3u);\n    let a = inp[pb + 6u];\n".replace("SETS_U", &format!("{SETS}u")),
        Inputs::Generated => "    let fi = f32(i) + 0.5;\n    let z = 1.0 - 2.0 * fract(fi * 0.000123456);\n    let phi = 2.39996323 * fi;\n    let rr = sqrt(max(1.0 - z * z, 0.0));\n    let n = vec3<f32>(rr * cos(phi), rr * sin(phi), z);\n    let v = normalize(n + 0.6 * vec3<f32>(sin(1.7 * phi), cos(2.3 * phi), sin(0.7 * phi)));\n    let a = 0.05 + 0.9 * fract(fi * 0.618034);\n".to_string(),
    };
    let pre = move |k: usize| {
        format!(
            "    let cb = 36u + (i % {SETS}u) * 36u;\n{geometry}    var c: array<vec3<f32>, {k}>;\n    for (var j = 0u; j < {k}u; j++) {{\n        c[j] = ld3(cb + 3u * j);\n    }}\n"
        )
    };
    let sg = |k: usize, spec: bool| {
        let mut b = pre(k);
        b += &format!("    var e = vec3<f32>(0.0);\n    for (var j = 0u; j < {k}u; j++) {{\n        e += c[j] * sg_hill_irradiance(ld3(3u * j), 6.0, n);\n    }}\n");
        if spec {
            b += &format!("    let w = sg_asg_warp(n, v, a, 0.04, 1.0);\n    for (var j = 0u; j < {k}u; j++) {{\n        e += c[j] * sg_asg_lobe(w, ld3(3u * j), 6.0);\n    }}\n");
        }
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
    vec![
        ("SH9 (L2)", "sh-l2-irradiance", 9, false, sh),
        ("SG9", "sg-irradiance", 9, false, sg(9, false)),
        ("SG9", "sg-irradiance,sg-specular", 9, true, sg(9, true)),
        ("SG12", "sg-irradiance", 12, false, sg(12, false)),
        ("SG12", "sg-irradiance,sg-specular", 12, true, sg(12, true)),
        ("AD9", "ad9-irradiance", 9, false, ad(9, false)),
        ("AD9", "ad9-irradiance,ad9-specular", 9, true, ad(9, true)),
        ("AD12", "ad12-irradiance", 12, false, ad(12, false)),
        ("AD12", "ad12-irradiance,ad12-specular", 12, true, ad(12, true)),
    ]
}

/// Runs every kernel over `count` invocations, `repeats` dispatches each (after a warm-up).
pub fn run(gpu: &Gpu, count: usize, repeats: usize, inputs: Inputs) -> Result<Vec<Row>, String> {
    let mut rng = sbf::sampling::Pcg32::new(99, 7);
    let mut inp: Vec<f32> = Vec::with_capacity(36 + SETS * 36 + count * 7);
    for a in sbf::layout::vogel_hemisphere(12).map_err(|e| e.to_string())? {
        inp.extend([a.x as f32, a.y as f32, a.z as f32]);
    }
    for _ in 0..SETS * 36 {
        inp.push(rng.next_2d()[0] as f32);
    }
    for _ in 0..if inputs == Inputs::Buffer { count } else { 0 } {
        let n = sbf::sampling::uniform_sphere(rng.next_2d());
        let v = sbf::sampling::uniform_sphere(rng.next_2d());
        let v = if v.dot(n) < 0.0 { -v } else { v };
        inp.extend([n.x as f32, n.y as f32, n.z as f32, v.x as f32, v.y as f32, v.z as f32, (0.05 + 0.9 * rng.next_2d()[0]) as f32]);
    }
    let lut = sbf::luts::committed::ad_specular_2d();
    let mut rows = Vec::new();
    for (name, cfg, lobes, specular, body) in kernels(inputs) {
        let lib = compose::compose(&Config::parse(cfg)?)?.source;
        let uses_lut = body.contains("lut");
        let (out, t) = gpu.run(&lib, &body, &inp, 1, count, if uses_lut { Some(lut) } else { None }, repeats)?;
        if let Some(x) = out.iter().find(|x| !x.is_finite()) {
            return Err(format!("{name}: non-finite output {x}"));
        }
        rows.push(Row { name, lobes, specular, seconds_per_dispatch: t, evals_per_second: count as f64 / t });
    }
    Ok(rows)
}

/// A Markdown table of the rows with the AD/SG cost ratios (seed Table 8.1 compares
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
            if r.specular { "diffuse + specular" } else { "diffuse" },
            r.seconds_per_dispatch * 1e3,
            r.evals_per_second * 1e-6
        );
    }
    let find = |n: &str, sp: bool| rows.iter().find(|r| r.name == n && r.specular == sp).map(|r| r.seconds_per_dispatch);
    for sp in [false, true] {
        if let (Some(a), Some(b)) = (find("AD9", sp), find("SG9", sp)) {
            s += &format!("\nAD9/SG9 time ratio ({}): {:.3}", if sp { "diffuse + specular" } else { "diffuse" }, a / b);
        }
    }
    s += "\n(seed 004 Table 8.1: frame times AD9 2.30 ms / SG9 3.27 ms = 0.70; above the 1.39 ms no-lightmap base, 0.91/1.88 = 0.48.)\n";
    s
}
