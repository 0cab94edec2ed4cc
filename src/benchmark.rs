//! The paper's element-cost case (Santa-Cruz et al. 2021, Table 6): a 0.40 m cube built of
//! 16 boxes 0.2 × 0.2 × 0.1 m resting on the table under gravity; Kn = 5e7, Ks = 2.5e7 Pa/m,
//! φ = 35°, local damping 0.8.

use crate::dem::{Simulation, SolverParams};
use crate::layout::{BaseSliding, Layout};
use crate::verify::{box_vertices, layout_of};
use serde::Serialize;
use std::time::Instant;

/// The cube of 16 boxes (2 × 2 in plan, 4 layers), resting exactly on each other.
pub fn cube16() -> Layout {
    let mut blocks = Vec::new();
    for k in 0..4 {
        for j in 0..2 {
            for i in 0..2 {
                let min = [0.2 * i as f64, 0.2 * j as f64, 0.1 * k as f64];
                blocks.push(box_vertices(min, [min[0] + 0.2, min[1] + 0.2, min[2] + 0.1]));
            }
        }
    }
    layout_of(blocks, 5e7, 2.5e7, 35.0, BaseSliding::Free)
}

/// Result of the cube16 benchmark.
#[derive(Debug, Clone, Serialize)]
pub struct BenchResult {
    /// Number of blocks.
    pub bodies: usize,
    /// Steps timed.
    pub steps: u64,
    /// Steps per second of wall time (one thread).
    pub steps_per_s: f64,
    /// Contacts and sub-contacts at the end.
    pub contacts: usize,
    /// Sub-contacts at the end.
    pub sub_contacts: usize,
    /// Time step, s.
    pub dt_s: f64,
    /// Steps from the first step to an unbalanced-force ratio below 1e-4.
    pub steps_to_equilibrium: u64,
    /// Wall time to that equilibrium, s.
    pub equilibrium_wall_time_s: f64,
}

/// Runs `steps` steps of the cube under gravity and, separately, the settling from the
/// first step to equilibrium (unbalanced-force ratio 1e-4).
pub fn run_cube16(steps: u64, params: SolverParams) -> BenchResult {
    let layout = cube16();
    let mut eq = Simulation::new(&layout, params);
    let t0 = Instant::now();
    let mut steps_to_eq = 0;
    for i in 1..=10_000_000u64 {
        eq.step().expect("cube16 is stable");
        if i > 10 && eq.stats.unbalanced_ratio < 1e-4 {
            steps_to_eq = i;
            break;
        }
    }
    let eq_time = t0.elapsed().as_secs_f64();
    let mut sim = Simulation::new(&layout, params);
    let t0 = Instant::now();
    for _ in 0..steps {
        sim.step().expect("cube16 is stable");
    }
    let el = t0.elapsed().as_secs_f64();
    BenchResult {
        bodies: sim.bodies.len(),
        steps,
        steps_per_s: steps as f64 / el,
        contacts: sim.contacts.len(),
        sub_contacts: sim.contacts.iter().map(|c| c.subs.len()).sum(),
        dt_s: sim.dt,
        steps_to_equilibrium: steps_to_eq,
        equilibrium_wall_time_s: eq_time,
    }
}
