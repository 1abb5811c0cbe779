//! Reports: `results.json` (machine-readable) and `report.md` (a table per signal).

use crate::metrics::Metrics;
use crate::modes::ModeResult;
use std::fmt::Write;

/// One mode's result with its metrics.
#[derive(Debug, Clone)]
pub struct Row {
    pub result: ModeResult,
    pub radiance: Option<Metrics>,
    pub irradiance: Metrics,
}

/// Everything about one map.
#[derive(Debug, Clone)]
pub struct MapReport {
    pub path: String,
    pub width: usize,
    pub height: usize,
    pub domain: &'static str,
    pub reference_method: String,
    pub sanitized: usize,
    pub rows: Vec<Row>,
}

fn esc(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.9e}")
    } else {
        "null".into()
    }
}

fn metrics_json(m: &Metrics) -> String {
    format!(
        "{{\"rms\": {}, \"rms_weighted\": {}, \"rel_rms\": {}, \"max_abs\": {}, \"smape\": {}, \"negative_fraction\": {}}}",
        num(m.rms),
        num(m.rms_weighted),
        num(m.rel_rms),
        num(m.max_abs),
        num(m.smape),
        num(m.negative_fraction)
    )
}

/// `results.json` for several maps (an array of map objects).
pub fn json(maps: &[MapReport]) -> String {
    let mut s = String::from("[\n");
    for (mi, m) in maps.iter().enumerate() {
        let _ = writeln!(
            s,
            "  {{\"map\": {{\"path\": \"{}\", \"width\": {}, \"height\": {}, \"sanitized_texels\": {}}}, \"domain\": \"{}\", \"reference\": {{\"method\": \"{}\"}}, \"modes\": [",
            esc(&m.path),
            m.width,
            m.height,
            m.sanitized,
            m.domain,
            esc(&m.reference_method)
        );
        for (ri, r) in m.rows.iter().enumerate() {
            let x = &r.result;
            let coeffs =
                x.coefficients.iter().map(|c| format!("[{}, {}, {}]", num(c[0]), num(c[1]), num(c[2]))).collect::<Vec<_>>().join(", ");
            let lobes = x
                .lobes
                .iter()
                .map(|(a, l)| format!("{{\"axis\": [{}, {}, {}], \"sharpness\": {}}}", num(a.x), num(a.y), num(a.z), num(*l)))
                .collect::<Vec<_>>()
                .join(", ");
            let rad = r.radiance.as_ref().map_or("null".to_string(), metrics_json);
            let _ = writeln!(
                s,
                "    {{\"id\": \"{}\", \"name\": \"{}\", \"basis\": \"{}\", \"solver\": \"{}\", \"coefficient_count\": {}, \"coefficients\": [{}], \"lobes\": [{}], \"metrics\": {{\"radiance\": {}, \"irradiance\": {}}}, \"timing\": {{\"encode_s\": {}, \"eval_ns_per_dir\": {}}}}}{}",
                x.id,
                esc(x.name),
                esc(&x.basis),
                esc(x.solver),
                x.coefficients.len(),
                coeffs,
                lobes,
                rad,
                metrics_json(&r.irradiance),
                num(x.encode_s),
                num(x.eval_ns_per_dir),
                if ri + 1 < m.rows.len() { "," } else { "" }
            );
        }
        let _ = writeln!(s, "  ]}}{}", if mi + 1 < maps.len() { "," } else { "" });
    }
    s.push_str("]\n");
    s
}

/// `report.md`: per map, a table of irradiance and radiance errors and timings.
pub fn markdown(maps: &[MapReport]) -> String {
    let mut s = String::from("# probes report\n\nIrradiance images store **E/π** (the radiance a white Lambertian surface reflects), as Probulator does. RMS is over texels, unweighted unless marked Ω (solid-angle weighted).\n");
    for m in maps {
        let _ = write!(s, "\n## {} ({}×{}, {})\n\nReference: {}.", m.path, m.width, m.height, m.domain, m.reference_method);
        if m.sanitized > 0 {
            let _ = write!(s, " {} texel channels were sanitised to 0.", m.sanitized);
        }
        s.push_str("\n\n| mode | basis | solver | coeffs | irradiance RMS | Ω-RMS | rel | max | neg. | radiance RMS | encode ms | eval ns/dir |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in &m.rows {
            let x = &r.result;
            let rad = r.radiance.map_or("—".to_string(), |v| format!("{:.4}", v.rms));
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {} | {:.5} | {:.5} | {:.4} | {:.4} | {:.3} | {} | {:.3} | {:.1} |",
                x.id,
                x.basis,
                x.solver,
                x.coefficients.len(),
                r.irradiance.rms,
                r.irradiance.rms_weighted,
                r.irradiance.rel_rms,
                r.irradiance.max_abs,
                r.irradiance.negative_fraction,
                rad,
                x.encode_s * 1e3,
                x.eval_ns_per_dir
            );
        }
    }
    s
}
