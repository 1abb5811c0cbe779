//! The committed CPU cost calibration (`probes/data/cpu_costs.json`, which the decisions
//! use): it parses, says where and when it was measured, covers every evaluator a run can
//! produce — each mode of `probes list` with a runtime, each SG irradiance reconstruction,
//! each specular runtime — and every cost is finite and positive with low ≤ median ≤ high.
//! A new mode or runtime without a recalibration fails here (`probes calibrate`).

use probes::calibration::{committed, irradiance_key, specular_key, variants};
use probes::modes::{prepare, Context, MODES};

#[test]
fn committed_calibration_covers_every_evaluator() {
    let c = committed();
    assert!(!c.machine.is_empty() && !c.date.is_empty() && c.batches > 0, "provenance: {} {} {}", c.machine, c.date, c.batches);
    let map = sbf::envmap::LatLongImage::from_fn(16, 8, |d| [1.0 + d.x.max(0.0), 0.5 + 0.5 * d.y, 0.3]).unwrap();
    let mut missing = Vec::new();
    for (sgi, runtime) in variants() {
        let mut ctx = Context::new(map.clone());
        ctx.sg_irradiance = sgi;
        ctx.specular_runtime = runtime;
        for probes::modes::Mode { id, .. } in MODES {
            let p = prepare(id, &ctx, 1).unwrap();
            if p.eval.is_none() {
                continue; // the Monte Carlo reference: no runtime
            }
            let mut keys = vec![irradiance_key(p.result.id, p.result.irradiance_variant)];
            keys.extend(specular_key(id, runtime));
            for k in keys {
                match c.costs.get(&k) {
                    None => missing.push(k),
                    Some(s) => assert!(
                        s.low_ns > 0.0 && s.low_ns <= s.median_ns && s.median_ns <= s.high_ns && s.high_ns.is_finite(),
                        "{k}: {s:?}"
                    ),
                }
            }
        }
    }
    missing.sort();
    missing.dedup();
    assert!(missing.is_empty(), "not calibrated (run `probes calibrate`): {missing:?}");
}
