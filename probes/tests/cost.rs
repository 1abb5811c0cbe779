//! The CPU cost axis measures what it claims: a mode whose runtime
//! evaluation is made twice as expensive (the test-only `eval_work = 2`, which evaluates
//! every direction twice inside the timed loop) shows ≥ 1.6× the cost, and two
//! measurements of the same mode agree within 20%. The jobs go through the tool's own
//! path — `modes::prepare`, then `cost::measure_side_by_side` over all of them, as
//! `probes compare` does. One test function in its own binary, so no other test of this
//! process competes for the cores while it times.
//!
//! Error model: each cost is the median of 15 rounds; in a round every job runs one pass of
//! ≥ 512 evaluations and ≥ 0.25 ms, so the k-th passes of the two copies of a mode run
//! within a millisecond of each other and see the same machine state: the slow drift of a
//! shared machine (1.6× on the CI VM, for seconds at a time) cancels. What remains is the
//! noise between adjacent passes. Measured here with a busy loop on the other core (the
//! worst case of this 2-core VM; three runs of 60 processes, ≈ 540 pairs, at 7 and at 15
//! rounds), 98–99% of the pairs' medians agreed within 1.10× and the worst was 1.29× —
//! the machine's state flips within milliseconds at times. So a
//! measurement whose pairs disagree by more than 20% is repeated, up to three attempts in
//! all (≈ 1e-6 that three noisy attempts fail in a row); a measurement that is wrong (a job
//! measured for another, a cost not scaling with the work) fails all three. 1.6 leaves 20%
//! for noise on the 2× and for the loop's own overhead, which does not double.

use probes::cost::measure_side_by_side;
use probes::modes::{prepare, Context};
use sbf::envmap::LatLongImage;

const ATTEMPTS: usize = 3;

#[test]
fn doubling_the_work_shows_in_the_cost_and_repeats_agree() {
    let map = LatLongImage::from_fn(128, 64, |d| [1.0 + d.x.max(0.0) * 5.0, 0.5 + 0.5 * d.y, 0.3 + d.z * d.z]).unwrap();
    let once = Context::new(map.clone());
    let mut twice = Context::new(map);
    twice.eval_work = 2;
    let ids = ["shl2", "sgls", "adrbf"];
    let mut failures = Vec::new();
    for attempt in 1..=ATTEMPTS {
        let mut jobs = Vec::new();
        for id in ids {
            for ctx in [&once, &once, &twice] {
                jobs.push(prepare(id, ctx, 1).unwrap().eval.expect("a runtime mode has a cost job"));
            }
        }
        let costs = measure_side_by_side(&mut jobs);
        let mut failed = Vec::new();
        for (id, c) in ids.iter().zip(costs.chunks(3)) {
            let (a, b, double) = (c[0].median_ns, c[1].median_ns, c[2].median_ns);
            let ratio = double / a.min(b);
            let agree = a.max(b) / a.min(b);
            println!("attempt {attempt}, {id}: {a:.1} / {b:.1} ns, twice the work {double:.1} ns ({ratio:.2}×)");
            if ratio < 1.6 {
                failed.push(format!("{id}: doubling the work shows only {ratio:.2}×"));
            }
            if agree > 1.2 {
                failed.push(format!("{id}: two runs {a:.1} and {b:.1} ns disagree by {agree:.2}×"));
            }
        }
        if failed.is_empty() {
            return;
        }
        failures.push(format!("attempt {attempt}: {}", failed.join("; ")));
    }
    panic!("every attempt failed:\n{}", failures.join("\n"));
}
