//! The decision section as text: the recommendation lines, the budget table's cells
//! (markdown and HTML render the same cells), the cost-tier legend and the fronts.
//! Renders [`crate::results`] records; decides nothing.

use crate::results::{MapResults, ModeRecord, Point, SignalDecision};

/// Measured CPU ns of a mode for a signal (the median; for display only — decisions use
/// tiers).
fn cpu_ns(r: &MapResults, sd: &SignalDecision, id: &str) -> Option<f64> {
    let m: &ModeRecord = r.modes.iter().find(|m| m.id == id)?;
    if sd.signal == "irradiance" {
        Some(m.cost.eval.median_ns)
    } else {
        m.cost.specular_eval.map(|s| s.median_ns)
    }
}

fn percent(x: f64) -> String {
    if x >= 10.0 {
        format!("{x:.1} %")
    } else {
        format!("{x:.2} %")
    }
}

fn ns(x: Option<f64>) -> String {
    x.map_or("—".into(), |x| if x >= 100.0 { format!("{x:.0} ns") } else { format!("{x:.1} ns") })
}

/// "`id` — 2.10 % error, 36 B, 20.1 ns" (`code` wraps the id); a prefiltered mode is named
/// as the pair it is ("`pf32-ni` (SH L2 for diffuse + a 32² prefiltered map for specular) —
/// …", its bytes and cost those of both).
fn describe(r: &MapResults, sd: &SignalDecision, p: &Point, code: fn(&str) -> String) -> String {
    let pair = crate::modes::prefiltered::parse(&p.id)
        .map_or(String::new(), |v| format!(" (SH L2 for diffuse + a {}² prefiltered map for specular)", v.size));
    format!("{}{pair} — {} error, {} B, {}", code(&p.id), percent(p.error_percent), p.bytes, ns(cpu_ns(r, sd, &p.id)))
}

/// Whether any mode that is not a prefiltered map reaches the usability threshold on a
/// specular signal.
fn a_basis_is_usable(r: &MapResults, sd: &SignalDecision) -> bool {
    let Some(key) = sd.signal.strip_prefix("specular α=") else { return true };
    r.modes.iter().filter(|m| m.coefficient_count > 0 && crate::modes::prefiltered::parse(&m.id).is_none()).any(|m| {
        m.metrics.specular.get(key).is_some_and(|s| s.metrics.rel_rms.is_finite() && 100.0 * s.metrics.rel_rms <= r.usable_error_percent)
    })
}

/// Whether the run compared prefiltered maps.
fn has_prefiltered(r: &MapResults) -> bool {
    r.modes.iter().any(|m| crate::modes::prefiltered::parse(&m.id).is_some())
}

/// One line: the signal's recommended mode and the next cheaper one on the CPU front.
pub fn recommendation(r: &MapResults, sd: &SignalDecision, code: fn(&str) -> String) -> String {
    match &sd.recommended {
        None => format!("{}: no candidate", sd.signal),
        Some(rec) if !sd.usable => format!(
            "{}: no mode within {} error (--usable-error) — the best is {}{}",
            sd.signal,
            percent(r.usable_error_percent),
            describe(r, sd, &rec.mode, code),
            match (sd.signal.starts_with("specular"), has_prefiltered(r)) {
                (true, false) => "; for sharp specular, engines ship a prefiltered environment map: add the `pf` modes (`probes list`)",
                (true, true) => "; not even the run's prefiltered maps reach it",
                _ => "",
            }
        ),
        Some(rec) => format!(
            "{}: {}{}{}",
            sd.signal,
            if crate::modes::prefiltered::parse(&rec.mode.id).is_some() && !a_basis_is_usable(r, sd) {
                format!("no basis within {} error (--usable-error) — use ", percent(r.usable_error_percent))
            } else {
                String::new()
            },
            describe(r, sd, &rec.mode, code),
            rec.next_cheaper
                .as_ref()
                .map_or("; nothing cheaper on the front".into(), |n| format!("; next cheaper: {}", describe(r, sd, n, code)))
        ),
    }
}

/// Plain ids (terminal).
pub fn plain(id: &str) -> String {
    id.to_string()
}

/// Markdown code spans.
pub fn md_code(id: &str) -> String {
    format!("`{id}`")
}

/// The budget table: header cells, then per storage row its label and cells
/// (`code`-wrapped id and error %).
pub fn budget_cells(sd: &SignalDecision, code: fn(&str) -> String) -> (Vec<String>, Vec<(String, Vec<String>)>) {
    let last = sd.budget.cpu_tiers.last().copied();
    let mut head = vec!["≤ bytes".to_string()];
    head.extend(sd.budget.cpu_tiers.iter().map(|t| if Some(*t) == last { "any CPU cost".to_string() } else { format!("≤ tier {t}") }));
    let rows = sd
        .budget
        .bytes
        .iter()
        .zip(&sd.budget.best)
        .map(|(b, row)| {
            let cells = row
                .iter()
                .map(|c| c.as_ref().map_or("—".to_string(), |p| format!("{} {}", code(&p.id), percent(p.error_percent))))
                .collect();
            (b.to_string(), cells)
        })
        .collect();
    (head, rows)
}

/// The calibrated CPU ns of a mode for a signal (the calibration's median), if any.
fn calibrated_ns(r: &MapResults, sd: &SignalDecision, id: &str) -> Option<f64> {
    let m = r.modes.iter().find(|m| m.id == id)?;
    let key = if sd.signal == "irradiance" { Some(&m.cost_keys.irradiance) } else { m.cost_keys.specular.as_ref() }?;
    crate::calibration::committed().costs.get(key).map(|s| s.median_ns)
}

/// "CPU cost tiers — costs calibrated (…): 1 = `ac` 7.1 ns (here 9.0 ns), …; 2 = …": the
/// costs the tiers come from and, for reference, this run's measurement.
pub fn tier_legend(r: &MapResults, sd: &SignalDecision, code: fn(&str) -> String) -> String {
    let Some(t) = sd.tiers.iter().find(|t| t.axis == "eval_ns") else { return String::new() };
    let calibrated = sd.cpu_costs.starts_with("calibrated");
    let groups: Vec<String> = t
        .tiers
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let members: Vec<String> = g
                .iter()
                .map(|id| {
                    if calibrated {
                        format!("{} {} (here {})", code(id), ns(calibrated_ns(r, sd, id)), ns(cpu_ns(r, sd, id)))
                    } else {
                        format!("{} {}", code(id), ns(cpu_ns(r, sd, id)))
                    }
                })
                .collect();
            format!("{} = {}", k + 1, members.join(", "))
        })
        .collect();
    format!(
        "CPU cost tiers — costs {}; modes whose costs overlap within their spread (at least ±10 %) are one tier: {}",
        sd.cpu_costs,
        groups.join("; ")
    )
}

/// The fronts, one line each: "error vs storage: `ac` (24 B, 9.1 %) → …".
pub fn front_lines(sd: &SignalDecision, code: fn(&str) -> String) -> Vec<String> {
    sd.fronts
        .iter()
        .map(|f| {
            let tier_axis = f.axis != "storage_bytes";
            let tiers = sd.tiers.iter().find(|t| t.axis == f.axis);
            let pts: Vec<String> = f
                .points
                .iter()
                .map(|p| {
                    let cost = if tier_axis {
                        let t = tiers.and_then(|t| t.tiers.iter().position(|g| g.contains(&p.id))).map_or(0, |k| k + 1);
                        format!("tier {t}")
                    } else {
                        format!("{} B", p.bytes)
                    };
                    format!("{} ({cost}, {})", code(&p.id), percent(p.error_percent))
                })
                .collect();
            format!("Pareto front, error vs {}: {}", f.axis, pts.join(" → "))
        })
        .collect()
}
