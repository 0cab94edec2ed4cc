//! The non-associative correction: Gilbert, Casapulla & Ahmed (2006), "Limit analysis of
//! masonry block structures with non-associative frictional joints using linear
//! programming", Comput. Struct. 84:873.
//!
//! With associative friction the Coulomb cone is also the plastic potential: a sliding
//! joint dilates by tan φ, and the dilatancy can do work against the normal forces of the
//! surrounding blocks, so where sliding governs the associative λ is an upper estimate of
//! the collapse load of real, non-dilatant joints. Gilbert et al. replace the friction limit
//! `‖f_t‖ ≤ μ f_n` by a fixed shear capacity `μ N̂` from the normal forces N̂ of the previous
//! solution (a cohesive, non-dilatant joint, for which the flow rule is non-dilatant),
//! solve again, and iterate with under-relaxation `N̂ ← N̂ + ω (f_n − N̂)` until λ and the
//! normal forces stop changing. The converged solution satisfies equilibrium, the
//! Coulomb condition `‖f_t‖ ≤ μ f_n` at the fixed point and the non-associative flow rule;
//! such solutions need not be unique, and the iteration need not converge (the paper adds a
//! perturbation; here the last iterate is reported with `converged = false`).

use super::model::{Friction, Model, Solution};
use clarabel::solver::SolverStatus;
use serde::{Deserialize, Serialize};

/// The outcome of the non-associative iteration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NonAssociative {
    /// λ of the last iterate.
    pub load_multiplier: f64,
    /// Iterations (cone programs solved).
    pub iterations: u32,
    /// Whether λ and the normal forces converged within the tolerance.
    pub converged: bool,
    /// λ at every iteration, first to last.
    pub history: Vec<f64>,
    /// Clarabel's time over the iteration's programs, s.
    pub solve_time_s: f64,
}

/// Runs the iteration from the associative solution. Returns the outcome and the last
/// iterate's solution (for its mechanism), or `None` when the first fixed-friction program
/// fails.
pub(crate) fn gilbert(
    model: &Model,
    associative: &Solution,
    max_iterations: u32,
    relaxation: f64,
    tolerance: f64,
) -> Option<(NonAssociative, Solution)> {
    let mut nhat: Vec<f64> = associative.normal.iter().map(|n| n.max(0.0)).collect();
    let mut history = Vec::new();
    let mut last: Option<Solution> = None;
    let mut converged = false;
    let mut solve_time_s = 0.0;
    let mut small = 0;
    for _ in 0..max_iterations {
        let s = model.solve(Friction::Fixed(&nhat));
        solve_time_s += s.solve_time_s;
        if !matches!(s.status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            break;
        }
        let lambda_change = history.last().map_or(f64::INFINITY, |l: &f64| (s.lambda - l).abs());
        let s_lambda = s.lambda;
        history.push(s_lambda);
        for (h, n) in nhat.iter_mut().zip(&s.normal) {
            *h += relaxation * (n.max(0.0) - *h);
        }
        last = Some(s);
        // Two changes in a row below the tolerance: one may be a crossing of a wandering λ.
        small = if lambda_change <= tolerance * s_lambda.abs().max(1.0) { small + 1 } else { 0 };
        if small >= 2 {
            converged = true;
            break;
        }
    }
    let s = last?;
    Some((
        NonAssociative {
            load_multiplier: s.lambda,
            iterations: history.len() as u32,
            converged,
            history,
            solve_time_s,
        },
        s,
    ))
}
