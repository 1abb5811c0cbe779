//! Reports: `report.md` (the decision section first, then a table per signal),
//! `report.html` (the same with the interactive view, [`crate::viewer`]) and each map's
//! images and plots. Renders what [`crate::outcome`] and [`crate::results`] hold; decides
//! nothing.

pub use crate::outcome::{specular_stem, MapReport, Row, SpecularReference, StageTimes};
use std::fmt::Write;

/// The decision section of one map: per signal, the recommendation, the best mode within
/// each budget of storage (rows) and CPU cost tier (columns), the tiers and the fronts.
pub fn decision_markdown(r: &crate::results::MapResults) -> String {
    use crate::decision_text as dt;
    let mut s = String::new();
    for sd in &r.decision.signals {
        let _ = write!(
            s,
            "\n**{}**\n\nBest mode (lowest error, as % of the reference's RMS) within a budget of storage per probe (f32) and CPU cost tier:\n\n",
            dt::recommendation(r, sd, dt::md_code)
        );
        let (head, rows) = dt::budget_cells(sd, dt::md_code);
        let _ = writeln!(s, "| {} |\n|{}", head.join(" | "), "---|".repeat(head.len()));
        for (label, cells) in rows {
            let _ = writeln!(s, "| {label} | {} |", cells.join(" | "));
        }
        let _ = writeln!(s, "\n{}", dt::tier_legend(r, sd, dt::md_code));
        for line in dt::front_lines(sd, dt::md_code) {
            let _ = writeln!(s, "\n{line}");
        }
    }
    s
}

/// The terminal's lines for one map: a recommendation per signal.
pub fn summary_lines(r: &crate::results::MapResults) -> Vec<String> {
    use crate::decision_text as dt;
    r.decision.signals.iter().map(|sd| format!("{} {}", r.map.path, dt::recommendation(r, sd, dt::plain))).collect()
}

/// `report.md`: per map, the decision section, then the tables of errors and costs.
pub fn markdown(maps: &[MapReport], results: &[crate::results::MapResults], images: bool) -> String {
    let mut s = String::from("# probes report\n\n");
    if let Some(p) = results.first().map(|r| r.profile.as_str()).filter(|p| !p.is_empty()) {
        let _ = write!(s, "Lighting profile: {p} (the run follows it: its modes, roughness values and runtime path).\n\n");
    }
    s.push_str("Irradiance images store **E/π** (the radiance a white Lambertian surface reflects), as Probulator does. RMS is over texels, unweighted unless marked Ω (solid-angle weighted). Costs: storage per probe at f32; CPU ns per evaluation, steady state (every mode's evaluation measured side by side: the median of 15 rounds of one pass per mode; spread in results.json); encode time from the radiance map (modes that fit the irradiance reference are charged for making it). Decisions compare cost tiers — modes whose costs overlap within their spread are one tier — so they hold from run to run. A recommendation is the cheapest mode on the CPU front whose error is within 25 % of the best.\n\n## Recommendations\n\n");
    for res in results {
        for sd in &res.decision.signals {
            let _ = writeln!(s, "- {}: {}", res.map.path, crate::decision_text::recommendation(res, sd, crate::decision_text::md_code));
        }
    }
    for (m, res) in maps.iter().zip(results) {
        let _ = write!(s, "\n## {} — which basis\n", m.path);
        if let Some(g) = res.modes.iter().find_map(|m| m.cost.gpu.as_ref()) {
            let _ = write!(s, "\nGPU costs on {} (the `shaders bench` kernels; ns per evaluation):", g.adapter);
            for m in &res.modes {
                if let Some(g) = &m.cost.gpu {
                    let _ = write!(
                        s,
                        " `{}` {} {:.3}{}",
                        m.id,
                        g.kernel,
                        g.ns,
                        g.specular_ns.map_or(String::new(), |x| format!(" (+ specular {x:.3})"))
                    );
                }
            }
            s.push('\n');
        }
        s.push_str(&decision_markdown(res));
        let _ = write!(
            s,
            "\n![irradiance error vs CPU cost]({}/error_vs_eval_cost.png) ![irradiance error vs storage]({}/error_vs_storage.png)\n",
            m.slug, m.slug
        );
    }
    for m in maps {
        let _ = write!(
            s,
            "\n## {} ({}×{}, {})\n\nReference: {}. Storage: {}.",
            m.path,
            m.width,
            m.height,
            m.domain,
            m.reference_method,
            m.storage.describe()
        );
        if m.sanitized > 0 {
            let _ = write!(s, " {} texel channels were sanitised to 0.", m.sanitized);
        }
        s.push_str("\n\n| mode | basis | solver | coeffs | bytes | irradiance RMS | Ω-RMS | rel | mean × | max | neg. | radiance RMS | encode ms (from map) | eval ns/dir (min–max) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in &m.rows {
            let x = &r.result;
            let rad = r.radiance.map_or("—".to_string(), |v| format!("{:.4}", v.rms));
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {} | {} | {:.5} | {:.5} | {:.4} | {:.4} | {:.4} | {:.3} | {} | {:.3}{} | {:.1} ({:.1}–{:.1}) |",
                x.id,
                x.basis,
                x.solver,
                x.coefficients.len(),
                x.storage_bytes(),
                r.irradiance.rms,
                r.irradiance.rms_weighted,
                r.irradiance.rel_rms,
                r.irradiance.mean_ratio,
                r.irradiance.max_abs,
                r.irradiance.negative_fraction,
                rad,
                x.encode_total_s(m.stages.reference_irradiance) * 1e3,
                if x.needs_reference { " ‡" } else { "" },
                x.eval.median_ns,
                x.eval.min_ns,
                x.eval.max_ns
            );
        }
        s.push_str("\n‡ fits the irradiance reference: charged the reference's time.\n");
        specular_markdown(&mut s, m);
        if images {
            let _ = write!(s, "\nIrradiance (E/π), reference then each mode, and |error| at 4 EV more:\n\n![reference]({}/reference_irradiance.png)\n\n| mode | irradiance | error |\n|---|---|---|\n", m.slug);
            for r in &m.rows {
                let _ = writeln!(
                    s,
                    "| `{0}` | ![{0}]({1}/{0}_irradiance.png) | ![{0} error]({1}/{0}_irradiance_error.png) |",
                    r.result.id, m.slug
                );
            }
        }
        convergence_markdown(&mut s, m);
    }
    s
}

/// The GGX specular tables of one map's report (RMS per α, and its decomposition into
/// basis-limited and runtime parts), where the run measured specular.
fn specular_markdown(s: &mut String, m: &MapReport) {
    let alphas: Vec<f64> = m.rows.iter().flat_map(|r| r.specular.iter().map(|(a, _)| *a)).fold(Vec::new(), |mut v, a| {
        if !v.contains(&a) {
            v.push(a);
        }
        v
    });
    if !alphas.is_empty() {
        let _ = write!(
            s,
            "\nGGX specular ({}), RMS per α. Reference: {}. Runtime: {}.\n\n| mode |",
            crate::appendix_c::label(m.convention),
            m.specular_method,
            m.specular_runtime
        );
        for a in &alphas {
            let _ = write!(s, " α = {a} |");
        }
        s.push_str("\n|---|");
        s.push_str(&"---|".repeat(alphas.len()));
        s.push('\n');
        s.push_str("| *reference error (est.)* |");
        for a in &alphas {
            match m.specular_reference.iter().find(|r| r.alpha == *a) {
                Some(r) => {
                    let _ = write!(s, " *{:.1e}* |", r.error_rms);
                }
                None => s.push_str(" — |"),
            }
        }
        s.push('\n');
        for r in m.rows.iter().filter(|r| !r.specular.is_empty()) {
            let _ = write!(s, "| `{}` |", r.result.id);
            for a in &alphas {
                match r.specular.iter().find(|(x, _)| x == a) {
                    Some((_, mm)) => {
                        let _ = write!(s, " {:.5} |", mm.rms);
                    }
                    None => s.push_str(" — |"),
                }
            }
            s.push('\n');
        }
    }
    if m.rows.iter().any(|r| !r.specular_parts.is_empty()) {
        s.push_str("\nGGX specular error decomposition, RMS per α: *basis-limited* (the exact GGX integral of the mode's reconstructed radiance against the reference) / *runtime* (the mode's runtime path against that integral). Where the runtime part dominates, the runtime approximation, not the basis, limits the mode.\n\n| mode |");
        for a in &alphas {
            let _ = write!(s, " α = {a} |");
        }
        s.push_str("\n|---|");
        s.push_str(&"---|".repeat(alphas.len()));
        s.push('\n');
        for r in m.rows.iter().filter(|r| !r.specular_parts.is_empty()) {
            let _ = write!(s, "| `{}` |", r.result.id);
            for a in &alphas {
                match r.specular_parts.iter().find(|p| p.0 == *a) {
                    Some(p) => {
                        let _ = write!(s, " {:.4} / {:.4} |", p.1, p.2);
                    }
                    None => s.push_str(" — |"),
                }
            }
            s.push('\n');
        }
    }
    split_sum_markdown(s, m, &alphas);
}

/// The prefiltered maps' error split of one map's report (where the run has them).
fn split_sum_markdown(s: &mut String, m: &MapReport, alphas: &[f64]) {
    let rows: Vec<&Row> = m.rows.iter().filter(|r| !r.split_sum_parts.is_empty()).collect();
    if rows.is_empty() {
        return;
    }
    s.push_str("\nPrefiltered maps, RMS per α: *split sum* (the map prefiltered exactly at α, read at the reflected direction, times the DFG terms, against the reference: the split-sum approximation's own error, the same for every map) / *map* (the mode against that: face resolution, interpolation between mips, storage).\n\n| mode |");
    for a in alphas {
        let _ = write!(s, " α = {a} |");
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(alphas.len()));
    s.push('\n');
    for r in rows {
        let _ = write!(s, "| `{}` |", r.result.id);
        for a in alphas {
            match r.split_sum_parts.iter().find(|p| p.0 == *a) {
                Some(p) => {
                    let _ = write!(s, " {:.4} / {:.4} |", p.1, p.2);
                }
                None => s.push_str(" — |"),
            }
        }
        s.push('\n');
    }
}

/// The per-sample encoders' convergence table of one map's report.
fn convergence_markdown(s: &mut String, m: &MapReport) {
    let conv: Vec<&Row> = m.rows.iter().filter(|r| !r.result.convergence.is_empty()).collect();
    if !conv.is_empty() {
        s.push_str("\nPer-sample encoders: irradiance RMS against samples taken.\n\n| samples |");
        for r in &conv {
            let _ = write!(s, " `{}` |", r.result.id);
        }
        s.push_str("\n|---|");
        s.push_str(&"---|".repeat(conv.len()));
        s.push('\n');
        let counts: Vec<u64> = conv.iter().flat_map(|r| r.result.convergence.iter().map(|(n, _)| *n)).fold(Vec::new(), |mut v, n| {
            if !v.contains(&n) {
                v.push(n);
            }
            v
        });
        let mut counts = counts;
        counts.sort_unstable();
        for n in counts {
            let _ = write!(s, "| {n} |");
            for r in &conv {
                match r.result.convergence.iter().find(|(k, _)| *k == n) {
                    Some((_, e)) => {
                        let _ = write!(s, " {e:.5} |");
                    }
                    None => s.push_str(" — |"),
                }
            }
            s.push('\n');
        }
    }
}

/// The decision sections of report.html: per map and signal, the budget table, the tiers and
/// the front.
fn decisions_html(s: &mut String, maps: &[MapReport], results: &[crate::results::MapResults]) {
    for (i, (m, res)) in maps.iter().zip(results).enumerate() {
        let _ = write!(s, "<h2>{} — which basis</h2>", esc_html(&m.path));
        s.push_str(&crate::viewer::section(i));
        for sd in &res.decision.signals {
            use crate::decision_text as dt;
            let code: fn(&str) -> String = |id| format!("<code>{id}</code>");
            let _ = write!(
                s,
                "<h3>{}</h3><p>Best mode (lowest error, as % of the reference's RMS) within a budget of storage per probe (f32, rows) and CPU cost tier (columns):</p><table><tr>",
                dt::recommendation(res, sd, code)
            );
            let (head, rows) = dt::budget_cells(sd, code);
            for h in head {
                let _ = write!(s, "<th>{}</th>", esc_html(&h));
            }
            s.push_str("</tr>");
            for (label, cells) in rows {
                let _ = write!(s, "<tr><td>{label}</td>");
                for c in cells {
                    let _ = write!(s, "<td>{c}</td>");
                }
                s.push_str("</tr>");
            }
            let _ = write!(s, "</table><p>{}</p><ul>", dt::tier_legend(res, sd, code));
            for line in dt::front_lines(sd, code) {
                let _ = write!(s, "<li>{line}</li>");
            }
            s.push_str("</ul>");
        }
    }
}

/// The GGX specular table of one map in report.html (images per α, RMS under each).
fn specular_html(s: &mut String, m: &MapReport) {
    if !m.specular_reference.is_empty() {
        let _ = write!(
            s,
            "<h3>GGX specular ({})</h3><p>Reference: {}. Runtime: {}. Same exposure per α as the reference; error images at 4 EV more. RMS under each image.</p><table><tr><th>mode</th>",
            esc_html(crate::appendix_c::label(m.convention)),
            esc_html(&m.specular_method),
            esc_html(&m.specular_runtime)
        );
        for r in &m.specular_reference {
            let _ = write!(s, "<th>α = {}</th>", r.alpha);
        }
        s.push_str("</tr><tr><td class=\"l\">reference</td>");
        for r in &m.specular_reference {
            let _ = write!(
                s,
                "<td><img class=\"s\" src=\"{}/reference_{}.png\"><br><small>est. error {:.1e}</small></td>",
                m.slug,
                specular_stem(r.alpha),
                r.error_rms
            );
        }
        s.push_str("</tr>");
        for r in m.rows.iter().filter(|r| !r.specular.is_empty()) {
            let _ = write!(s, "<tr><td class=\"l\"><code>{}</code></td>", r.result.id);
            for sr in &m.specular_reference {
                match r.specular.iter().find(|(a, _)| *a == sr.alpha) {
                    Some((a, mm)) => {
                        let st = specular_stem(*a);
                        let _ = write!(
                            s,
                            "<td><img class=\"s\" src=\"{0}/{1}_{2}.png\"> <img class=\"s\" src=\"{0}/{1}_{2}_error.png\"><br><small>{3:.5}</small></td>",
                            m.slug, r.result.id, st, mm.rms
                        );
                    }
                    None => s.push_str("<td>—</td>"),
                }
            }
            s.push_str("</tr>");
        }
        s.push_str("</table>");
    }
}

/// `report.html`: the markdown table's content with the irradiance and error images.
pub fn html(maps: &[MapReport], results: &[crate::results::MapResults]) -> String {
    let mut s = String::from("<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>probes report</title><style>body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 8px;text-align:right}td.l{text-align:left;max-width:260px}img{width:160px;image-rendering:pixelated}img.s{width:128px}p img{max-width:100%}</style></head><body><h1>probes report</h1>");
    if let Some(p) = results.first().map(|r| r.profile.as_str()).filter(|p| !p.is_empty()) {
        let _ = write!(s, "<p>Lighting profile: {} (the run follows it: its modes, roughness values and runtime path).</p>", esc_html(p));
    }
    s.push_str("<p>Irradiance images store <b>E/π</b> (the radiance a white Lambertian surface reflects), as Probulator does. PNGs are tone-mapped (Reinhard, gamma 2.2) at the exposure stated per map; error images show |approximation − reference| at 4 EV more. RMS is over texels, unweighted unless marked Ω.</p><h2>Recommendations</h2><ul>");
    for res in results {
        for sd in &res.decision.signals {
            let _ = write!(
                s,
                "<li>{}: {}</li>",
                esc_html(&res.map.path),
                crate::decision_text::recommendation(res, sd, |id| format!("<code>{id}</code>"))
            );
        }
    }
    s.push_str("</ul>");
    decisions_html(&mut s, maps, results);
    for m in maps {
        let exposure = crate::images::auto_exposure(&m.reference);
        let _ = write!(
            s,
            "<h2>{} ({}×{}, {})</h2><p>Reference: {}. Storage: {}. Exposure {:+.2} EV.</p><p><img src=\"{}/reference_irradiance.png\"></p>",
            esc_html(&m.path),
            m.width,
            m.height,
            m.domain,
            esc_html(&m.reference_method),
            esc_html(m.storage.describe()),
            exposure,
            m.slug
        );
        let _ = write!(s, "<p><img src=\"{0}/error_vs_encode_time.png\" style=\"width:480px\"> <img src=\"{0}/error_vs_eval_cost.png\" style=\"width:480px\"> <img src=\"{0}/error_vs_storage.png\" style=\"width:480px\">", m.slug);
        if m.rows.iter().any(|r| !r.result.convergence.is_empty()) {
            let _ = write!(s, " <img src=\"{0}/error_vs_samples.png\" style=\"width:480px\">", m.slug);
        }
        s.push_str("</p>");
        s.push_str("<table><tr><th>mode</th><th>basis / solver</th><th>coeffs</th><th>irradiance RMS</th><th>Ω-RMS</th><th>max</th><th>neg.</th><th>encode ms</th><th>eval ns/dir</th><th>radiance</th><th>irradiance</th><th>error</th></tr>");
        for r in &m.rows {
            let x = &r.result;
            let _ = write!(
                s,
                "<tr><td class=\"l\"><code>{}</code></td><td class=\"l\">{}<br><small>{}</small></td><td>{}</td><td>{:.5}</td><td>{:.5}</td><td>{:.4}</td><td>{:.3}</td><td>{:.3}</td><td>{:.1}</td><td>{}</td><td><img src=\"{}/{}_irradiance.png\"></td><td><img src=\"{}/{}_irradiance_error.png\"></td></tr>",
                x.id,
                esc_html(&x.basis),
                esc_html(x.solver),
                x.coefficients.len(),
                r.irradiance.rms,
                r.irradiance.rms_weighted,
                r.irradiance.max_abs,
                r.irradiance.negative_fraction,
                x.encode_s * 1e3,
                x.eval.median_ns,
                if x.radiance.is_some() { format!("<img src=\"{}/{}_radiance.png\">", m.slug, x.id) } else { "—".into() },
                m.slug,
                x.id,
                m.slug,
                x.id
            );
        }
        s.push_str("</table>");
        specular_html(&mut s, m);
    }
    // The viewer opens each signal on its recommended mode.
    let recommended: Vec<crate::viewer::Recommended> = results
        .iter()
        .map(|r| {
            let rec = |signal: &str| {
                r.decision.signals.iter().find(|sd| sd.signal == signal).and_then(|sd| sd.recommended.as_ref()).map(|x| x.mode.id.clone())
            };
            crate::viewer::Recommended {
                irradiance: rec("irradiance"),
                specular: r
                    .reference
                    .specular_error
                    .keys()
                    .filter_map(|a| Some((a.parse::<f64>().ok()?, rec(&format!("specular α={a}"))?)))
                    .collect(),
            }
        })
        .collect();
    s.push_str(&crate::viewer::script(maps, &recommended));
    s.push_str("</body></html>\n");
    s
}

fn esc_html(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// Writes every image and plot of one map into `dir/<slug>/`: /// (file, title, x label, labelled points) of one cost plot.
type Plot = (&'static str, String, &'static str, Vec<(String, f64, f64)>);

/// PNG previews always; float EXRs when `exr`.
pub fn write_images(out: &crate::outdir::OutDir, m: &MapReport, exr: bool) -> Result<(), String> {
    use crate::images;
    let d = out.path().join(&m.slug);
    std::fs::create_dir_all(&d).map_err(|e| format!("creating {}: {e}", d.display()))?;
    let ev = images::auto_exposure(&m.reference);
    if exr {
        images::write_exr(&out.file(d.join("reference_irradiance.exr")), m.grid, &m.reference)?;
    }
    images::write_png(&out.file(d.join("reference_irradiance.png")), m.grid, &m.reference, ev)?;
    // Each mode's images on its own task (encoding dominates; the files are distinct),
    // alongside the plots.
    let (modes, plots) = rayon::join(|| write_mode_images(out, &d, m, exr, ev), || write_plots(out, &d, m));
    modes?;
    plots
}

/// The images of every mode (and of the specular references) of one map.
fn write_mode_images(out: &crate::outdir::OutDir, d: &std::path::Path, m: &MapReport, exr: bool, ev: f64) -> Result<(), String> {
    use crate::images;
    use rayon::prelude::*;
    m.rows.par_iter().try_for_each(|r| -> Result<(), String> {
        let x = &r.result;
        if exr {
            images::write_exr(&out.file(d.join(format!("{}_irradiance.exr", x.id))), m.grid, &x.irradiance)?;
        }
        images::write_png(&out.file(d.join(format!("{}_irradiance.png", x.id))), m.grid, &x.irradiance, ev)?;
        let err: Vec<[f64; 3]> = x.irradiance.iter().zip(&m.reference).map(|(a, b)| [0, 1, 2].map(|k| (a[k] - b[k]).abs())).collect();
        images::write_png(&out.file(d.join(format!("{}_irradiance_error.png", x.id))), m.grid, &err, ev + 4.0)?;
        if let Some(rad) = &x.radiance {
            if exr {
                images::write_exr(&out.file(d.join(format!("{}_radiance.exr", x.id))), m.grid, rad)?;
            }
            images::write_png(&out.file(d.join(format!("{}_radiance.png", x.id))), m.grid, rad, ev)?;
        }
        for ((a, _), img) in r.specular.iter().zip(&r.specular_images) {
            let Some(sr) = m.specular_reference.iter().find(|s| s.alpha == *a) else { continue };
            let sev = images::auto_exposure(&sr.image);
            let st = specular_stem(*a);
            if exr {
                images::write_exr(&out.file(d.join(format!("{}_{st}.exr", x.id))), m.grid, img)?;
            }
            images::write_png(&out.file(d.join(format!("{}_{st}.png", x.id))), m.grid, img, sev)?;
            let err: Vec<[f64; 3]> = img.iter().zip(&sr.image).map(|(p, q)| [0, 1, 2].map(|k| (p[k] - q[k]).abs())).collect();
            images::write_png(&out.file(d.join(format!("{}_{st}_error.png", x.id))), m.grid, &err, sev + 4.0)?;
        }
        Ok(())
    })?;
    for sr in &m.specular_reference {
        let st = specular_stem(sr.alpha);
        if exr {
            images::write_exr(&out.file(d.join(format!("reference_{st}.exr"))), m.grid, &sr.image)?;
        }
        images::write_png(&out.file(d.join(format!("reference_{st}.png"))), m.grid, &sr.image, images::auto_exposure(&sr.image))?;
    }
    Ok(())
}

/// The error-vs-samples plot and the three cost plots of one map, each on its own task.
fn write_plots(out: &crate::outdir::OutDir, d: &std::path::Path, m: &MapReport) -> Result<(), String> {
    use crate::images;
    use rayon::prelude::*;
    let series: Vec<(String, Vec<(f64, f64)>)> = m
        .rows
        .iter()
        .filter(|r| !r.result.convergence.is_empty())
        .map(|r| (r.result.id.to_string(), r.result.convergence.iter().map(|(n, e)| (*n as f64, *e)).collect()))
        .collect();
    let lines = || -> Result<(), String> {
        if series.is_empty() {
            return Ok(());
        }
        images::lines(
            &out.file(d.join("error_vs_samples.png")),
            &format!("{}: per-sample encoders, irradiance error vs samples", m.path),
            "samples taken",
            "irradiance RMS (E/π)",
            &series,
        )
    };
    let pts = |f: &dyn Fn(&Row) -> f64| m.rows.iter().map(|r| (r.result.id.to_string(), f(r), r.irradiance.rms)).collect::<Vec<_>>();
    // The three cost plots, each on its own task.
    let plots: [Plot; 3] = [
        (
            "error_vs_encode_time.png",
            format!("{}: irradiance error vs encode time", m.path),
            "encode time (s)",
            pts(&|r| r.result.encode_total_s(m.stages.reference_irradiance)),
        ),
        (
            "error_vs_storage.png",
            format!("{}: irradiance error vs storage", m.path),
            "bytes per probe (as stored, --storage)",
            pts(&|r| r.result.storage_bytes()),
        ),
        (
            "error_vs_eval_cost.png",
            format!("{}: irradiance error vs reconstruction cost", m.path),
            "CPU reconstruction (ns per direction)",
            pts(&|r| r.result.eval.median_ns),
        ),
    ];
    let (a, b) = rayon::join(lines, || {
        plots
            .par_iter()
            .try_for_each(|(file, title, xlabel, p)| images::scatter(&out.file(d.join(file)), title, xlabel, "irradiance RMS (E/π)", p))
    });
    a.and(b)
}
