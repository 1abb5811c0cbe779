//! Nonlinear fits through argmin: Brent's method for one parameter (Hill's c0), Nelder–Mead
//! for several (Listing 8.1's eight). Each returns the minimiser with how the solver ended,
//! which the MANIFEST records.

use argmin::core::{CostFunction, Executor, State, TerminationReason};
use argmin::solver::brent::BrentOpt;
use argmin::solver::neldermead::NelderMead;
use std::marker::PhantomData;

/// How a solver ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Convergence {
    pub solver: &'static str,
    pub iterations: u64,
    /// Cost-function evaluations.
    pub evaluations: u64,
    /// Why it stopped (argmin's reason: converged, or the iteration cap).
    pub reason: String,
    /// The cost at the minimiser.
    pub cost: f64,
}

impl Convergence {
    /// One line for the MANIFEST.
    pub fn summary(&self) -> String {
        format!("{}: {} ({} iterations, {} evaluations)", self.solver, self.reason, self.iterations, self.evaluations)
    }

    /// Whether the solver reports convergence (not the iteration cap).
    pub fn converged(&self) -> bool {
        self.reason == TerminationReason::SolverConverged.text()
    }
}

/// An argmin cost from a closure.
struct Cost<P, F>(F, PhantomData<fn(&P)>);

impl<P, F: Fn(&P) -> f64> CostFunction for Cost<P, F> {
    type Param = P;
    type Output = f64;
    fn cost(&self, p: &P) -> Result<f64, argmin::core::Error> {
        Ok((self.0)(p))
    }
}

fn convergence<S: State>(solver: &'static str, state: &S, cost: f64) -> Convergence {
    Convergence {
        solver,
        iterations: state.get_iter(),
        evaluations: state.get_func_counts().get("cost_count").copied().unwrap_or(0),
        reason: state.get_termination_reason().map_or_else(|| "not terminated".into(), |r| r.text().to_string()),
        cost,
    }
}

/// Brent's minimisation (argmin `BrentOpt`) of `f` on [lo, hi], which must bracket one
/// minimum, to within 3·(ε|x| + t) with ε = 1e-12 and t = 1e-13 (below √(machine ε): the
/// minimax costs here have a V-shaped minimum, where golden-section steps keep gaining).
pub fn brent(lo: f64, hi: f64, f: impl Fn(f64) -> f64) -> Result<(f64, Convergence), String> {
    let solver = BrentOpt::new(lo, hi).set_tolerance(1e-12, 1e-13);
    let res = Executor::new(Cost(move |x: &f64| f(*x), PhantomData), solver)
        .configure(|s| s.max_iters(500).counting(true))
        .run()
        .map_err(|e| format!("Brent: {e}"))?;
    let st = res.state();
    let x = *st.get_best_param().ok_or("Brent: no parameter")?;
    Ok((x, convergence("Brent (argmin)", st, st.get_best_cost())))
}

/// Nelder–Mead (argmin) from `start`, the initial simplex `start` and each parameter moved
/// by `step` of its magnitude (or by `step` where it is 0), until the simplex's costs have
/// a standard deviation below 1e-14 or `max_iters`.
pub fn nelder_mead(start: &[f64], step: f64, max_iters: u64, f: impl Fn(&[f64]) -> f64) -> Result<(Vec<f64>, Convergence), String> {
    let mut simplex = vec![start.to_vec()];
    for i in 0..start.len() {
        let mut p = start.to_vec();
        p[i] += if p[i] != 0.0 { step * p[i].abs() } else { step };
        simplex.push(p);
    }
    let solver = NelderMead::new(simplex).with_sd_tolerance(1e-14).map_err(|e| format!("Nelder–Mead: {e}"))?;
    let res = Executor::new(Cost(move |p: &Vec<f64>| f(p), PhantomData), solver)
        .configure(|s| s.max_iters(max_iters).counting(true))
        .run()
        .map_err(|e| format!("Nelder–Mead: {e}"))?;
    let st = res.state();
    let p = st.get_best_param().ok_or("Nelder–Mead: no parameter")?.clone();
    Ok((p, convergence("Nelder–Mead (argmin)", st, st.get_best_cost())))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both solvers find known minima: a parabola's vertex (Brent, to its tolerance) and
    /// Rosenbrock's (1, 1) (Nelder–Mead, to 1e-6), and say they converged.
    #[test]
    fn solvers_find_known_minima() {
        let (x, c) = brent(0.0, 3.0, |x| (x - 1.234_567).powi(2) + 2.0).unwrap();
        assert!((x - 1.234_567).abs() < 1e-7 && c.converged(), "{x} {c:?}");
        let (p, c) = nelder_mead(&[-1.2, 1.0], 0.1, 5000, |p| 100.0 * (p[1] - p[0] * p[0]).powi(2) + (1.0 - p[0]).powi(2)).unwrap();
        assert!((p[0] - 1.0).abs() < 1e-6 && (p[1] - 1.0).abs() < 1e-6 && c.converged(), "{p:?} {c:?}");
    }
}
