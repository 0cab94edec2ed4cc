//! The `drystone` command line: parsing (clap) and dispatch to one function per
//! subcommand in [`cli`]; errors end the program with status 2 (and `run` or `merge` with
//! status 3 when every realization failed). `anyhow` lives in the command line only.

mod cli;

use clap::{Parser, Subcommand};
use drystone::dem::drivers::nscd::NscdParams;
use drystone::dem::{DensityScaling, SolverKind, SolverParams};
use drystone::loading::lateral::LateralParams;
use drystone::loading::shake::ShakeParams;
use drystone::loading::tilt::TiltParams;
use std::path::PathBuf;
use std::process::ExitCode;

/// The exit statuses of `run` and `merge`.
const EXIT_STATUS: &str = "Exit status: 0 when the outputs are written and at least one realization succeeded \
(if some failed, a warning on stderr gives their count; their rows carry the status and the error); \
2 on an error (bad input, a file that cannot be read or written, a journal or shard of another run); \
3 when every realization failed (the outputs are written all the same).";

/// The worker threads of a command that runs realizations in parallel.
#[derive(clap::Args)]
struct Workers {
    /// Worker threads: 0 or absent means all cores; more than the cores available is
    /// reduced to that number. The results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Parser)]
#[command(name = "drystone", version = drystone::study::BUILD, about = "Out-of-plane collapse of dry stone walls with a rigid-block DEM")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Tilting-table test of a layout to collapse.
    Tilt {
        /// Layout file (JSON).
        layout: PathBuf,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Tilt increment, degrees.
        #[arg(long, default_value_t = TiltParams::default().step_deg)]
        step_deg: f64,
        /// Width of the final collapse bracket, degrees.
        #[arg(long, default_value_t = TiltParams::default().resolution_deg)]
        resolution_deg: f64,
        /// Local damping coefficient.
        #[arg(long, default_value_t = SolverParams::default().damping)]
        damping: f64,
        /// Sub-contact subdivisions per fan-triangle edge.
        #[arg(long, default_value_t = SolverParams::default().subcontact_subdivisions)]
        subdivisions: u32,
        /// Fraction of the critical time-step bound used, in (0, 1].
        #[arg(long, default_value_t = SolverParams::default().timestep_safety)]
        timestep_safety: f64,
        /// Density scaling: `block` (6 × 6 per body), `scalar` or `off` (`density_scaling` in
        /// a study's [solver] table); an increment whose block-scaled dynamics blow up is
        /// repeated with scalar scaling.
        #[arg(long, default_value = "block")]
        density_scaling: String,
        /// Share of the scalar-scaled mass in each block mass (`block` scaling), in (0, 10].
        #[arg(long, default_value_t = SolverParams::default().density_scaling.mass_floor())]
        block_mass_floor: f64,
        /// Unbalanced-force ratio of equilibrium.
        #[arg(long, default_value_t = TiltParams::default().tolerance)]
        tolerance: f64,
        /// Step budget of one increment or trial (`max_steps_per_increment` in a study's
        /// [tilt] table); an increment that runs out of it is undecided (`step_budget`) and
        /// the result says its bracket is not reliable.
        #[arg(long, default_value_t = TiltParams::default().max_steps_per_increment)]
        max_steps: u64,
        /// Start every increment from the last stable state at rest instead of the secant
        /// prediction of its equilibrium (`predictor = false` in a study's [tilt] table).
        #[arg(long)]
        no_predictor: bool,
        #[command(flatten)]
        solver: SolverArgs,
        /// Write the states of the test as a ParaView time series into DIR (tilt.pvd: every
        /// stable increment and the first unstable state; unstable_trials.pvd: the other
        /// failed trials).
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
        #[command(flatten)]
        nscd: cli::tilt::NscdArgs,
    },
    /// Static lateral load: a trapezoidal pressure on the wall face (pushing towards +y),
    /// solved to equilibrium; prints the top displacements and the drift.
    #[command(allow_negative_numbers = true)]
    Lateral {
        /// Layout file (JSON).
        layout: PathBuf,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Pressure at the base of the wall, Pa.
        #[arg(long, default_value_t = LateralParams::default().pressure_base_pa)]
        pressure_base_pa: f64,
        /// Pressure at the top of the wall, Pa.
        #[arg(long, default_value_t = LateralParams::default().pressure_top_pa)]
        pressure_top_pa: f64,
        /// Unbalanced-force ratio of equilibrium.
        #[arg(long, default_value_t = LateralParams::default().tolerance)]
        tolerance: f64,
        /// Solver: `penalty` (the default: the penalty DEM with the protocol's own static
        /// method), `implicit`, `accelerated` or `relaxation` (penalty DEM, one static method
        /// forced), `nscd` (non-smooth contact dynamics, rigid joints), `limit` (limit
        /// analysis, rigid joints); `kind` in a study's [solver] table.
        #[arg(long, default_value = "penalty", value_parser = parse_solver)]
        solver: SolverKind,
        /// Write the settled and the loaded state as a ParaView time series into DIR
        /// (lateral.pvd, time = load factor 0 and 1).
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
        /// Push the wall over: raise the pressure by a load multiplier λ (doubling from 1,
        /// then bisection) to the collapse; prints the bracket [last stable, first unstable]
        /// of λ, the collapse reason and the mechanism. With the penalty DEM (the default
        /// solver); `--solver nscd` always pushes over (rigid blocks).
        #[arg(long)]
        pushover: bool,
        /// Relative width of the pushover's final bracket of λ.
        #[arg(long, default_value_t = LateralParams::default().pushover_resolution)]
        pushover_resolution: f64,
    },
    /// Shaking table: the layout on a base that moves with a recorded or a built-in
    /// acceleration along y (out of plane), by non-smooth contact dynamics (rigid blocks);
    /// prints whether it overturned, the largest rocking rotation and the drifts.
    #[command(allow_negative_numbers = true)]
    Shake {
        /// Layout file (JSON).
        layout: PathBuf,
        /// Ground-motion record: PEER NGA `.AT2` (in g), or `.csv`/`.tsv` with columns
        /// `time_s` and the acceleration with its unit in the name (`accel_g`, `accel_m_s2`,
        /// `accel_cm_s2`; optionally a vertical column `vert_g`, ...).
        #[arg(long, value_name = "FILE")]
        record: Option<PathBuf>,
        /// The record's columns by name: `time=t,h=acc_x_g,v=acc_z_g` (`time` defaults to
        /// `time_s`; without `v`, no vertical component).
        #[arg(long, value_name = "time=COL,h=COL,v=COL")]
        columns: Option<drystone::ground::ColumnMap>,
        /// Built-in pulse instead of a record: `one-sine` (a = A g sin(2πt/T) for 0 ≤ t ≤ T,
        /// Zhang & Makris 2001) or `ricker` (the Ricker wavelet of period T, peak A at t = T).
        #[arg(long)]
        pulse: Option<String>,
        /// Pulse amplitude A, g.
        #[arg(long)]
        amplitude_g: Option<f64>,
        /// Pulse period T, s.
        #[arg(long)]
        period_s: Option<f64>,
        /// Scale the motion (both components) to this peak ground acceleration, g.
        #[arg(long)]
        scale_pga_g: Option<f64>,
        /// Remove the linear trend of the record's velocity (baseline correction).
        #[arg(long)]
        baseline_correction: bool,
        /// Simulate this much of the motion, s [default: all of it].
        #[arg(long)]
        duration_s: Option<f64>,
        /// Free motion after the record ends, s.
        #[arg(long, default_value_t = ShakeParams::default().tail_s)]
        tail_s: f64,
        /// Time step of the solver, s.
        #[arg(long, default_value_t = NscdParams::default().dt_s)]
        dt_s: f64,
        /// Coefficient of restitution at impacts, in [0, 1]: Newton's (nscd) [default: 0], or
        /// that of the contact dashpots (penalty) [default: 0.05].
        #[arg(long)]
        restitution: Option<f64>,
        /// Keep simulating after the first block falls (to the end of the motion and tail).
        #[arg(long)]
        no_stop_at_collapse: bool,
        /// Solver: `nscd` (non-smooth contact dynamics, rigid blocks) or `penalty` (explicit
        /// dynamics of the joint springs with contact dashpots; its time step comes from
        /// the joint stiffness, not --dt-s).
        #[arg(long, default_value = "nscd", value_parser = parse_solver)]
        solver: SolverKind,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
        /// Write the motion as a ParaView time series into DIR (shake.pvd, time in s).
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
        #[command(flatten)]
        nscd: cli::tilt::NscdArgs,
    },
    /// Limit analysis: the rigid collapse load multiplier of a layout from statics alone (a
    /// second-order cone program over the contact polygons; tilting table: λ = tan α_max).
    #[command(allow_negative_numbers = true)]
    Limit {
        /// Layout file (JSON).
        layout: PathBuf,
        /// The live load: the tilting table's weight along +y, or the lateral pressure.
        #[arg(long, value_enum, default_value = "tilt")]
        protocol: cli::limit::ProtocolArg,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Lateral pressure at the base of the wall, Pa (`--protocol lateral`).
        #[arg(long, default_value_t = LateralParams::default().pressure_base_pa)]
        pressure_base_pa: f64,
        /// Lateral pressure at the top of the wall, Pa (`--protocol lateral`).
        #[arg(long, default_value_t = LateralParams::default().pressure_top_pa)]
        pressure_top_pa: f64,
        /// The associative answer only (no non-associative correction).
        #[arg(long)]
        associative: bool,
        /// Draw the collapse mechanism into this SVG file.
        #[arg(long, value_name = "FILE")]
        svg: Option<PathBuf>,
    },
    /// Runs a study (ensembles of realizations) and writes tables, plots and a report.
    ///
    /// Every finished realization goes at once to DIR/journal.jsonl (synced); after a crash
    /// or a kill, the same command with --resume runs only what is missing and writes
    /// outputs identical to an uninterrupted run (except the wall_time_s column).
    #[command(after_help = EXIT_STATUS)]
    Run {
        /// Study file (TOML).
        study: PathBuf,
        /// Output directory, checked writable before anything runs. Default: out/<study name>.
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        workers: Workers,
        /// Run only shard K of N (1-based, e.g. 3/8 for a job array); merge with `drystone merge`.
        #[arg(long)]
        shard: Option<String>,
        /// Realizations per group and sweep point, overriding the study file.
        #[arg(long)]
        realizations: Option<u64>,
        /// For a suite (e.g. studies/paper.toml): run every study at its own full size
        /// instead of the suite's reduced default.
        #[arg(long)]
        full: bool,
        /// Continue the run whose journal is in --out: skip the realizations it holds, run
        /// the rest. Refused if the journal is of another run (drystone build, seed, study,
        /// wall, distribution or measured files, realizations, shard) or has a damaged line;
        /// without a journal, starts afresh. Without --resume, a journal of an unfinished
        /// run in --out is refused.
        #[arg(long)]
        resume: bool,
        /// Replace a journal in --out that would be refused (another run's, a damaged one,
        /// or an unfinished one without --resume): its finished realizations are lost.
        #[arg(long)]
        force: bool,
        /// Also write the ParaView time series of these realizations (e.g. 0,3) of every
        /// group and sweep point into DIR/vtk/ (each is run again with the recording on;
        /// the rows do not change).
        #[arg(long, value_name = "I,J,...", value_delimiter = ',')]
        vtk_realizations: Vec<u64>,
    },
    /// Calibrates joint parameters (Kn, φ) of a study's walls against the measured collapse
    /// angles, step by step as its [[calibrate]] table says (Brent root finding, argmin).
    Calibrate {
        /// Study file (TOML) with [[calibrate]] steps.
        study: PathBuf,
        /// Output directory. Default: out/<study name>.
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        workers: Workers,
        /// Realizations per evaluation, overriding the study file.
        #[arg(long)]
        realizations: Option<u64>,
    },
    /// Merges shard directories of one study run into what an unsharded run writes.
    ///
    /// The shards must agree on the drystone version, the master seed, the realizations,
    /// the number of shards and every input file (by SHA-256); the first difference is
    /// named with both values. The study is rebuilt from the input files stored in the
    /// manifests, so the study file need not be unchanged or where it was.
    #[command(after_help = EXIT_STATUS)]
    Merge {
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Shard directories.
        #[arg(required = true)]
        shards: Vec<PathBuf>,
    },
    /// Closed-form verification cases; exit status 1 if any is out of tolerance.
    Verify {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Generates a wall layout from a wall description (TOML), a seed and a realization index.
    Generate {
        /// Wall description, e.g. studies/walls/sbl.toml.
        wall: PathBuf,
        /// Master seed.
        #[arg(long)]
        seed: u64,
        /// Realization index.
        #[arg(long, default_value_t = 0)]
        realization: u64,
        /// Output file, format by extension: .json (layout for `drystone tilt`), .vtk (ParaView), .svg (drawing).
        #[arg(long)]
        out: PathBuf,
        /// Directory of named distributions [default: the nearest `distributions/` at or above the wall file].
        #[arg(long)]
        distributions: Option<PathBuf>,
    },
    /// Model discrepancy: what the simulation gets wrong against the study's measured data,
    /// the physical effect that explains it (from a library of candidate effects, ranked by
    /// held-out error with margins calibrated on null data), the extended model and its gain.
    Discrepancy(cli::discrepancy::DiscrepancyArgs),
    /// Synthetic measured data: the study's walls built with seeds the study does not use,
    /// hidden effects applied, tilted to collapse, with measurement noise; written in the
    /// format of the paper's data files (a power analysis for planning tests).
    Synthesize {
        /// Study file (TOML).
        study: PathBuf,
        /// Hidden effects, `NAME=VALUE[,NAME=VALUE]` (two-parameter effects `NAME=V1:V2`);
        /// absent: null data from the baseline model.
        #[arg(long)]
        effect: Option<String>,
        /// Seed of the synthetic specimens and noise.
        #[arg(long)]
        seed: u64,
        /// Specimens per group.
        #[arg(long, default_value_t = 3)]
        specimens: u64,
        /// Output directory. Default: out/<study name>-synthetic-<seed>.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Benchmarks: `cube16` (the paper's Table 6 element-cost case: `--steps` engine steps of
    /// 16 boxes) or `tilt` (tilting-table tests to collapse of a generated wall, one after
    /// the other on one thread: by default the SBL preset, seed 20210917, realization 0;
    /// `--realizations N` runs realizations 0..N and gives the totals).
    Bench {
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
        solver: SolverArgs,
        /// The step compiled for the baseline instruction set (x86-64: SSE2) instead of the
        /// widest one this CPU runs (`cube16`; for comparison: the results are the same
        /// bit for bit, only the speed differs).
        #[arg(long)]
        portable: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes joined by `: `, each cause left out when the message before it
/// already ends with it (most errors here print their cause themselves).
fn message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.ends_with(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

/// `--solver NAME`.
fn parse_solver(name: &str) -> Result<SolverKind, String> {
    name.parse()
}

/// The solver flags of the tilting-table commands (`tilt`, `bench tilt`): the solver and the
/// deprecated switches of the penalty cascade, which keep working with a deprecation line.
#[derive(clap::Args, Debug, Clone, Copy)]
struct SolverArgs {
    /// Solver: `penalty` (the default: the penalty DEM with the protocol's own static
    /// method), `implicit`, `accelerated` or `relaxation` (penalty DEM, one static method
    /// forced), `nscd` (non-smooth contact dynamics, rigid joints), `limit` (limit
    /// analysis, rigid joints); `kind` in a study's [solver] table.
    #[arg(long, default_value = "penalty", value_parser = parse_solver)]
    solver: SolverKind,
    /// Deprecated (`--solver relaxation`): without the secant acceleration of slow creep
    /// and its stability indicator.
    #[arg(long, hide = true)]
    no_acceleration: bool,
    /// Deprecated (`--solver accelerated`): without the implicit relaxation of each
    /// increment.
    #[arg(long, hide = true)]
    no_implicit: bool,
}

impl SolverArgs {
    /// The solver kind, after printing the deprecation line of an old switch given.
    fn kind(self) -> SolverKind {
        if self.no_implicit || self.no_acceleration {
            let instead = if self.no_acceleration && self.no_implicit { "relaxation" } else { "accelerated" };
            let flag = if self.no_implicit { "--no-implicit" } else { "--no-acceleration" };
            eprintln!("warning: {flag} is deprecated; the solver is chosen with --solver (here: --solver {instead})");
        }
        self.solver
    }

    /// The tilting table's parameters with the old switches applied (`accelerate`,
    /// `implicit`) and the secant predictor on or off.
    fn tilt_params(self, predictor: bool) -> TiltParams {
        TiltParams {
            predictor,
            accelerate: !self.no_acceleration,
            implicit: !self.no_implicit,
            ..TiltParams::default()
        }
    }
}

fn run() -> anyhow::Result<ExitCode> {
    match Cli::parse().command {
        Command::Tilt {
            layout,
            json,
            step_deg,
            resolution_deg,
            damping,
            subdivisions,
            timestep_safety,
            density_scaling,
            block_mass_floor,
            tolerance,
            max_steps,
            no_predictor,
            solver: solver_args,
            vtk,
            nscd,
        } => {
            let kind = solver_args.kind();
            if nscd.given() && kind != SolverKind::Nscd {
                anyhow::bail!("the --nscd-* options set the non-smooth solver: give them with --solver nscd");
            }
            let density_scaling = match density_scaling.as_str() {
                "block" => DensityScaling::Block { mass_floor: block_mass_floor },
                "scalar" => DensityScaling::Scalar,
                "off" => DensityScaling::Off,
                other => anyhow::bail!("--density-scaling {other}: expected block, scalar or off"),
            };
            let solver = SolverParams {
                kind,
                damping,
                subcontact_subdivisions: subdivisions,
                timestep_safety,
                density_scaling,
                nscd: nscd.apply(NscdParams::default()),
                ..SolverParams::default()
            };
            let params = TiltParams {
                step_deg,
                resolution_deg,
                tolerance,
                max_steps_per_increment: max_steps,
                ..solver_args.tilt_params(!no_predictor)
            };
            cli::tilt::run(&layout, solver, &params, json, vtk.as_deref())
        }
        Command::Lateral {
            layout,
            json,
            pressure_base_pa,
            pressure_top_pa,
            tolerance,
            solver,
            vtk,
            pushover,
            pushover_resolution,
        } => {
            let params = LateralParams {
                pressure_base_pa,
                pressure_top_pa,
                tolerance,
                pushover,
                pushover_resolution,
                ..LateralParams::default()
            };
            let solver = SolverParams { kind: solver, ..SolverParams::default() };
            cli::lateral::run(&layout, solver, &params, json, vtk.as_deref())
        }
        Command::Shake {
            layout,
            record,
            columns,
            pulse,
            amplitude_g,
            period_s,
            scale_pga_g,
            baseline_correction,
            duration_s,
            tail_s,
            dt_s,
            restitution,
            no_stop_at_collapse,
            solver,
            json,
            vtk,
            nscd: nscd_args,
        } => {
            let args = cli::shake::MotionArgs {
                record,
                pulse,
                amplitude_g,
                period_s,
                scale_pga_g,
                baseline: baseline_correction,
                columns,
                dt_s,
            };
            let motion = cli::shake::motion(&args, dt_s.min(0.001))?;
            if nscd_args.given() && solver != SolverKind::Nscd {
                anyhow::bail!("the --nscd-* options set the non-smooth solver: give them with --solver nscd");
            }
            let d = ShakeParams::default();
            let (nscd_e, contact_e) = match (solver, restitution) {
                (SolverKind::Nscd, Some(e)) => (e, d.contact_restitution),
                (_, Some(e)) => (NscdParams::default().restitution, e),
                (_, None) => (NscdParams::default().restitution, d.contact_restitution),
            };
            let nscd = nscd_args.apply(NscdParams { dt_s, restitution: nscd_e, ..NscdParams::default() });
            let solver = SolverParams { kind: solver, nscd, ..SolverParams::default() };
            let params = ShakeParams {
                duration_s,
                tail_s,
                stop_at_collapse: !no_stop_at_collapse,
                contact_restitution: contact_e,
                ..d
            };
            cli::shake::run(&layout, &motion, solver, &params, json, vtk.as_deref())
        }
        Command::Limit { layout, protocol, json, pressure_base_pa, pressure_top_pa, associative, svg } => {
            cli::limit::run(&cli::limit::LimitArgs {
                layout: &layout,
                protocol,
                pressure_pa: (pressure_base_pa, pressure_top_pa),
                associative,
                json,
                svg: svg.as_deref(),
            })
        }
        Command::Run { study, out, workers, shard, realizations, full, resume, force, vtk_realizations } => {
            cli::study::run(cli::study::RunArgs {
                study: &study,
                out,
                threads: workers.threads,
                shard: shard.as_deref(),
                realizations,
                full,
                resume,
                force,
                vtk_realizations,
            })
        }
        Command::Calibrate { study, out, workers, realizations } => {
            cli::study::calibrate(&study, out, workers.threads, realizations)
        }
        Command::Merge { out, shards } => cli::study::merge(&out, &shards),
        Command::Verify { json } => cli::verify::run(json),
        Command::Generate { wall, seed, realization, out, distributions } => {
            cli::generate::run(&wall, seed, realization, &out, distributions)
        }
        Command::Discrepancy(args) => {
            cli::discrepancy::discrepancy(args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Synthesize { study, effect, seed, specimens, out } => {
            cli::discrepancy::synthesize(&study, effect.as_deref(), seed, specimens, out)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench { case, steps, wall, seed, realizations, no_predictor, solver, portable, json } => {
            match case.as_str() {
                "tilt" => {
                    let solver_kind = solver.kind();
                    let params = solver.tilt_params(!no_predictor);
                    let solver = SolverParams { kind: solver_kind, ..SolverParams::default() };
                    cli::bench::tilt(&wall, seed, realizations, solver, &params, json)
                }
                "cube16" => cli::bench::cube16(steps, portable, json),
                _ => anyhow::bail!("unknown benchmark {case:?}; available: cube16, tilt"),
            }
        }
    }
}
