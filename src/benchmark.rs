//! Benchmarks (`drystone bench`):
//!
//! * `cube16`: the paper's element-cost case (Santa-Cruz et al. 2021, Table 6): a 0.40 m
//!   cube built of 16 boxes 0.2 × 0.2 × 0.1 m resting on the table under gravity;
//!   Kn = 5e7, Ks = 2.5e7 Pa/m, φ = 35°, local damping 0.8.
//! * `tilt`: tilting-table tests to collapse of generated walls, one after the other on one
//!   thread.

use crate::dem::{Isa, Simulation, SolverParams};
use crate::generator::{generate, GeneratorError, Wall};
use crate::layout::{BaseSliding, Layout};
use crate::loading::tilt::{TiltError, TiltParams};
use crate::protocol::run_tilt;
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
/// first step to equilibrium (unbalanced-force ratio 1e-4), with the step compiled for
/// `isa` ([`Isa::best`] for the default step; an instruction set this CPU does not run
/// falls back to the default).
pub fn run_cube16(steps: u64, params: SolverParams, isa: Isa) -> BenchResult {
    let isa = if isa.available() { isa } else { Isa::best() };
    let step = |sim: &mut Simulation| sim.step_with(isa).expect("available").expect("cube16 is stable");
    let layout = cube16();
    let mut eq = Simulation::new(&layout, params);
    let t0 = Instant::now();
    let mut steps_to_eq = 0;
    for i in 1..=10_000_000u64 {
        step(&mut eq);
        if i > 10 && eq.stats().unbalanced_ratio < 1e-4 {
            steps_to_eq = i;
            break;
        }
    }
    let eq_time = t0.elapsed().as_secs_f64();
    let mut sim = Simulation::new(&layout, params);
    let t0 = Instant::now();
    for _ in 0..steps {
        step(&mut sim);
    }
    let el = t0.elapsed().as_secs_f64();
    BenchResult {
        bodies: sim.state.bodies.len(),
        steps,
        steps_per_s: steps as f64 / el,
        contacts: sim.state.contacts.len(),
        sub_contacts: sim.state.contacts.iter().map(|c| c.subs.len()).sum(),
        dt_s: sim.dt(),
        steps_to_equilibrium: steps_to_eq,
        equilibrium_wall_time_s: eq_time,
    }
}

/// Errors of the tilt benchmark.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BenchError {
    /// A layout could not be generated or did not check.
    #[error(transparent)]
    Generator(#[from] GeneratorError),
    /// A tilting-table test failed.
    #[error(transparent)]
    Tilt(#[from] TiltError),
}

/// One tilting-table test of the tilt benchmark. Fields in alphabetical order (the order of
/// the keys of `drystone bench tilt --json`).
#[derive(Debug, Clone, Serialize)]
pub struct BenchmarkRun {
    /// Blocks of the layout.
    pub blocks: usize,
    /// Collapse angle (last stable tilt), degrees.
    pub collapse_angle_deg: f64,
    /// Time step, s.
    pub dt_s: f64,
    /// First unstable tilt, degrees.
    pub first_unstable_deg: Option<f64>,
    /// Iterations of the implicit relaxation.
    pub iterations: u64,
    /// Realization index.
    pub realization: u64,
    /// Engine steps (dynamic relaxation).
    pub steps: u64,
    /// Wall time per step, µs, for a test of dynamic relaxation alone (`None` when it took
    /// implicit iterations: their time is not the steps').
    pub us_per_step: Option<f64>,
    /// Wall time, s.
    pub wall_time_s: f64,
}

/// The tilt benchmark: tilting-table tests to collapse of realizations `0..realizations` of
/// a wall, one after the other on one thread. Fields in alphabetical order (the order of
/// the keys of `drystone bench tilt --json`).
#[derive(Debug, Clone, Serialize)]
pub struct TiltBench {
    /// Secant predictor of the tilting table on.
    pub predictor: bool,
    /// Secant acceleration of slow creep (and its stability indicator) on.
    pub accelerate: bool,
    /// Implicit relaxation of the increments on.
    pub implicit: bool,
    /// Implicit iterations of all tests.
    pub iterations: u64,
    /// Realizations run.
    pub realizations: u64,
    /// Each test.
    pub runs: Vec<BenchmarkRun>,
    /// Master seed of the wall.
    pub seed: u64,
    /// The solver (`SolverKind` name).
    pub solver: String,
    /// Engine steps of all tests.
    pub steps: u64,
    /// Wall time per step over all tests, µs, for dynamic relaxation alone (`None` when
    /// implicit iterations were taken).
    pub us_per_step: Option<f64>,
    /// The wall (its file).
    pub wall: String,
    /// Wall time of all tests, s.
    pub wall_time_s: f64,
}

/// Runs the tilt benchmark on `wall` (named `name` in the result) with `solver`;
/// `on_run` sees each test as it finishes.
///
/// # Errors
/// [`BenchError`] for the first realization that cannot be generated or tilted.
pub fn run_tilt_bench(
    wall: &Wall,
    name: &str,
    seed: u64,
    realizations: u64,
    solver: SolverParams,
    params: &TiltParams,
    mut on_run: impl FnMut(&BenchmarkRun),
) -> Result<TiltBench, BenchError> {
    let mut runs = Vec::new();
    let (mut steps, mut iterations, mut time) = (0u64, 0u64, 0.0);
    for k in 0..realizations {
        let layout = generate(wall, seed, k)?.check()?;
        let r = run_tilt(&layout, solver, params)?;
        steps += r.steps;
        iterations += r.iterations;
        time += r.wall_time_s;
        let run = BenchmarkRun {
            blocks: layout.blocks.len(),
            collapse_angle_deg: r.collapse_angle_deg(),
            dt_s: r.dt_s,
            first_unstable_deg: r.first_unstable_deg,
            iterations: r.iterations,
            realization: k,
            steps: r.steps,
            us_per_step: (r.iterations == 0).then(|| 1e6 * r.wall_time_s / r.steps as f64),
            wall_time_s: r.wall_time_s,
        };
        on_run(&run);
        runs.push(run);
    }
    Ok(TiltBench {
        predictor: crate::dem::with_moved(solver, &params.moved()).penalty.predictor,
        accelerate: params.cascade(solver.kind).accelerate,
        implicit: params.cascade(solver.kind).implicit,
        solver: solver.kind.name().to_string(),
        iterations,
        realizations,
        runs,
        seed,
        steps,
        us_per_step: (iterations == 0).then(|| 1e6 * time / steps as f64),
        wall: name.to_string(),
        wall_time_s: time,
    })
}
