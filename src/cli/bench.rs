//! `drystone bench`: the benchmarks of [`drystone::benchmark`], printed.

use anyhow::{bail, Result};
use drystone::benchmark::{run_cube16, run_tilt_bench, BenchmarkRun};
use drystone::dem::{Isa, PenaltyParams, SolverParams};
use drystone::generator::{DistributionSource, Wall};
use drystone::loading::tilt::TiltParams;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Which benchmark: `cube16` or `tilt`.
    case: String,
    /// Steps to time (`cube16`).
    #[arg(long, default_value_t = 20_000)]
    steps: u64,
    /// Wall description (`tilt`).
    #[arg(long, default_value = "studies/walls/sbl.toml")]
    wall: PathBuf,
    /// Master seed of the wall (`tilt`).
    #[arg(long, default_value_t = 20210917)]
    seed: u64,
    /// Realizations 0..N of the wall, run one after the other (`tilt`). A single
    /// realization's step count moves by ±10 % with any change of the numerics (the
    /// near-collapse trials are path-sensitive); compare changes on the total of several.
    #[arg(long, default_value_t = 1)]
    realizations: u64,
    /// Without the secant predictor of the tilting table (`tilt`; for comparison).
    #[arg(long)]
    no_predictor: bool,
    /// (`tilt`)
    #[command(flatten)]
    solver: super::solver::SolverArgs,
    /// The step compiled for the baseline instruction set (x86-64: SSE2) instead of the
    /// widest one this CPU runs (`cube16`; for comparison: the results are the same
    /// bit for bit, only the speed differs).
    #[arg(long)]
    portable: bool,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// `drystone bench`: the benchmark `case` with its options.
///
/// # Errors
/// An unknown benchmark, or those of [`tilt`] and [`cube16`].
pub fn command(a: BenchArgs) -> Result<ExitCode> {
    match a.case.as_str() {
        "tilt" => {
            let kind = a.solver.kind();
            let params = a.solver.tilt_params();
            let penalty = PenaltyParams { predictor: !a.no_predictor, ..PenaltyParams::default() };
            let solver = SolverParams { kind, penalty, ..SolverParams::default() };
            tilt(&a.wall, a.seed, a.realizations, solver, &params, a.json)
        }
        "cube16" => cube16(a.steps, a.portable, a.json),
        case => bail!("unknown benchmark {case:?}; available: cube16, tilt"),
    }
}

/// `bench tilt`: realizations `0..realizations` of the wall, one after the other.
pub fn tilt(
    wall: &Path,
    seed: u64,
    realizations: u64,
    solver: SolverParams,
    params: &TiltParams,
    json: bool,
) -> Result<ExitCode> {
    if realizations == 0 {
        bail!("--realizations must be at least 1");
    }
    let w = Wall::from_file_with(wall, &DistributionSource::default_for(wall))?;
    if !json {
        out!(
            "tilt: {}, seed {seed}, realizations 0..{realizations}, one thread, solver {}, predictor {}, acceleration {}, implicit {}",
            wall.display(),
            solver.kind,
            if solver.penalty.predictor { "on" } else { "off" },
            if params.cascade(solver.kind).accelerate { "on" } else { "off" },
            if params.cascade(solver.kind).implicit { "on" } else { "off" }
        );
    }
    let print_run = |r: &BenchmarkRun| {
        if !json {
            out!(
                "  realization {} ({} blocks): alpha_max {:.4} deg (first unstable {}), {} steps of {:.3e} s, {} implicit iterations, {:.2} s{}",
                r.realization,
                r.blocks,
                r.collapse_angle_deg,
                r.first_unstable_deg.map_or("none".into(), |a| format!("{a:.4} deg")),
                r.steps,
                r.dt_s,
                r.iterations,
                r.wall_time_s,
                per_step(r.us_per_step)
            );
        }
    };
    let b = run_tilt_bench(&w, &wall.display().to_string(), seed, realizations, solver, params, print_run)?;
    if json {
        out!("{}", serde_json::to_string_pretty(&b)?);
    } else if realizations > 1 {
        out!(
            "  total: {} steps, {} implicit iterations, {:.2} s{}; mean {:.2} s per test",
            b.steps,
            b.iterations,
            b.wall_time_s,
            per_step(b.us_per_step),
            b.wall_time_s / realizations as f64
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// ` (N us/step)` for a run of dynamic relaxation alone, nothing otherwise.
fn per_step(us: Option<f64>) -> String {
    us.map_or(String::new(), |v| format!(" ({v:.1} us/step)"))
}

/// `bench cube16`: `steps` engine steps of the 16-box cube, and its settling; with the
/// step compiled for the baseline instruction set if `portable`.
pub fn cube16(steps: u64, portable: bool, json: bool) -> Result<ExitCode> {
    let isa = if portable { Isa::Portable } else { Isa::best() };
    let r = run_cube16(steps, SolverParams::default(), isa);
    if json {
        out!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        out!(
            "cube16: {} bodies, {} contacts, {} sub-contacts, dt {:.3e} s",
            r.bodies,
            r.contacts,
            r.sub_contacts,
            r.dt_s
        );
        out!("  {} steps at {:.0} steps/s (one thread)", r.steps, r.steps_per_s);
        out!(
            "  equilibrium (unbalanced-force ratio < 1e-4) after {} steps, {:.3} s",
            r.steps_to_equilibrium,
            r.equilibrium_wall_time_s
        );
    }
    Ok(ExitCode::SUCCESS)
}
