//! `drystone tilt`: the tilting-table test of a layout file.

use super::solver::{LimitFlags, NscdArgs, SolverArgs};
use anyhow::{bail, Context, Result};
use drystone::dem::{DensityScaling, PenaltyParams, SolverParams};
use drystone::io::series::{tilt_frames, write_series, Recorder};
use drystone::loading::tilt::{MechanismKind, TiltError, TiltParams, TiltResult};
use drystone::loading::tilt_hand::HandTilt;
use drystone::nscd::NscdParams;
use drystone::protocol::{run_tilt, Loading, Observer, Tilt, TiltRun};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone tilt`.
#[derive(clap::Args)]
pub struct TiltArgs {
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
    #[arg(long, default_value_t = PenaltyParams::default().tolerance)]
    tolerance: f64,
    /// Step budget of one increment or trial (`max_steps` in a study's [solver.penalty]
    /// table); an increment that runs out of it is undecided (`step_budget`) and the
    /// result says its bracket is not reliable.
    #[arg(long, default_value_t = PenaltyParams::default().max_steps)]
    max_steps: u64,
    /// Start every increment from the last stable state at rest instead of the secant
    /// prediction of its equilibrium (`predictor = false` in a study's [solver.penalty]
    /// table).
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
    nscd: NscdArgs,
    #[command(flatten)]
    limit: LimitFlags,
    #[command(flatten)]
    hand: HandArgs,
}

/// The table rolled by hand (`loading::tilt_hand`): each increment run as a motion.
#[derive(clap::Args)]
pub struct HandArgs {
    /// Roll the table by hand: each increment is a start, a roll, a stop and a hold for the
    /// reading, run by non-smooth contact dynamics in the rotating table's frame (the stops
    /// kick the wall downhill); needs --solver nscd.
    #[arg(long)]
    by_hand: bool,
    /// Increment between stops, degrees [default: 5, the paper's].
    #[arg(long)]
    hand_increment_deg: Option<f64>,
    /// Angular speed of the roll, degrees per second [default: 2.5].
    #[arg(long)]
    hand_rate_deg_s: Option<f64>,
    /// Duration of each start and stop, s [default: 0.1].
    #[arg(long)]
    hand_ramp_s: Option<f64>,
    /// The table held still at each stop, s [default: 1].
    #[arg(long)]
    hand_hold_s: Option<f64>,
    /// Depth of the table's axis of rotation below its surface, m [default: 0.34].
    #[arg(long)]
    table_axis_depth_m: Option<f64>,
}

impl HandArgs {
    /// The motion of the table, if `--by-hand` was given.
    ///
    /// # Errors
    /// A `--hand-*` or `--table-axis-depth-m` option without `--by-hand`, or `--by-hand`
    /// without `--solver nscd`.
    fn motion(&self, kind: drystone::dem::SolverKind) -> Result<Option<HandTilt>> {
        let given = [
            self.hand_increment_deg,
            self.hand_rate_deg_s,
            self.hand_ramp_s,
            self.hand_hold_s,
            self.table_axis_depth_m,
        ]
        .iter()
        .any(Option::is_some);
        if !self.by_hand {
            if given {
                bail!("the --hand-* and --table-axis-depth-m options set the table rolled by hand: give them with --by-hand");
            }
            return Ok(None);
        }
        // The compatibility table's row of the hand-rolled table.
        let refused = drystone::protocol::check(Loading::TiltByHand, kind);
        if let Err(e) = refused {
            // The default kind (`penalty`) is also what no --solver gives: the message does
            // not say the user named it.
            if kind.is_default() {
                bail!(
                    "--by-hand: the table rolled by hand runs by non-smooth contact dynamics only: give it with \
                     --solver nscd (tilt's solver is the penalty DEM unless --solver names another)"
                );
            }
            bail!("--by-hand: {e}: give it with --solver nscd");
        }
        let d = HandTilt::default();
        Ok(Some(HandTilt {
            increment_deg: self.hand_increment_deg.unwrap_or(d.increment_deg),
            rate_deg_per_s: self.hand_rate_deg_s.unwrap_or(d.rate_deg_per_s),
            ramp_s: self.hand_ramp_s.unwrap_or(d.ramp_s),
            hold_s: self.hand_hold_s.unwrap_or(d.hold_s),
            axis_depth_m: self.table_axis_depth_m.unwrap_or(d.axis_depth_m),
        }))
    }
}

/// The flag of each field of [`HandTilt`], for its errors.
fn hand_flag(key: &str) -> &'static str {
    match key {
        "increment_deg" => "--hand-increment-deg",
        "rate_deg_per_s" => "--hand-rate-deg-s",
        "ramp_s" => "--hand-ramp-s",
        "hold_s" => "--hand-hold-s",
        "axis_depth_m" => "--table-axis-depth-m",
        _ => "",
    }
}

/// `drystone tilt`: the solver and the test's parameters from the options, then [`run`].
///
/// # Errors
/// `--nscd-*` options without `--solver nscd`, an unknown `--density-scaling`, or an error
/// of [`run`].
pub fn command(a: TiltArgs) -> Result<ExitCode> {
    let kind = a.solver.kind();
    let nscd = a.nscd.params_for(kind, NscdParams::default())?;
    a.nscd.refuse_motion_options(if a.hand.by_hand {
        "the table rolled by hand (tilt --by-hand)"
    } else {
        "the tilting table (tilt)"
    })?;
    let limit = a.limit.params_for(kind, drystone::dem::LimitParams::default())?;
    let hand = a.hand.motion(kind)?;
    let density_scaling = match a.density_scaling.as_str() {
        "block" => DensityScaling::Block { mass_floor: a.block_mass_floor },
        "scalar" => DensityScaling::Scalar,
        "off" => DensityScaling::Off,
        other => bail!("--density-scaling {other}: expected block, scalar or off"),
    };
    let solver = SolverParams {
        kind,
        damping: a.damping,
        subcontact_subdivisions: a.subdivisions,
        timestep_safety: a.timestep_safety,
        density_scaling,
        penalty: PenaltyParams {
            tolerance: a.tolerance,
            max_steps: a.max_steps,
            predictor: !a.no_predictor,
            ..PenaltyParams::default()
        },
        nscd,
        limit,
        ..SolverParams::default()
    };
    let params = TiltParams { step_deg: a.step_deg, resolution_deg: a.resolution_deg, ..a.solver.tilt_params() };
    if let Some(hand) = hand {
        if a.vtk.is_some() {
            bail!("--vtk is not written for a table rolled by hand (--by-hand)");
        }
        let (dt, ds) = (TiltParams::default(), SolverParams::default());
        let ignored = [
            ("--step-deg", a.step_deg != dt.step_deg),
            ("--resolution-deg", a.resolution_deg != dt.resolution_deg),
            ("--max-steps", a.max_steps != ds.penalty.max_steps),
            ("--damping", a.damping != ds.damping),
            ("--density-scaling", density_scaling != ds.density_scaling),
            ("--timestep-safety", a.timestep_safety != ds.timestep_safety),
            ("--no-predictor", a.no_predictor),
        ];
        for (flag, _) in ignored.iter().filter(|(_, given)| *given) {
            eprintln!(
                "warning: {flag} is not read with --by-hand: the table rolled by hand runs non-smooth contact \
                 dynamics over its own increments (--hand-increment-deg)"
            );
        }
        if let Ok(l) = drystone::layout::Layout::from_file(&a.layout) {
            let keys = "--hand-rate-deg-s, --hand-ramp-s, --table-axis-depth-m";
            if let Some(w) = hand.plausibility_warning(l.bounds().max.z, l.gravity, keys) {
                eprintln!("warning: {w}");
            }
        }
        return run_by_hand(&a.layout, &nscd, &params, &hand, a.json);
    }
    run(&a.layout, solver, &params, a.json, a.vtk.as_deref())
}

/// Runs the test with the table rolled by hand and prints it as [`run`] does.
fn run_by_hand(layout: &Path, nscd: &NscdParams, params: &TiltParams, hand: &HandTilt, json: bool) -> Result<ExitCode> {
    let l = super::read_layout(layout)?;
    let solver = SolverParams { kind: drystone::dem::SolverKind::Nscd, nscd: *nscd, ..SolverParams::default() };
    let r = run_tilt(&l, solver, &TiltParams { by_hand: Some(*hand), ..*params })
        .map_err(|e| match e {
            TiltError::Parameter(p) if !hand_flag(&p.key).is_empty() => {
                anyhow::anyhow!("{} {}", hand_flag(&p.key), p.reason())
            }
            e => e.into(),
        })
        .with_context(|| format!("tilting-table test of {} rolled by hand", layout.display()))?;
    if json {
        let mut v = serde_json::to_value(&r)?;
        if let Some(o) = v.as_object_mut() {
            o.insert("collapse_angle_deg".into(), r.collapse_angle_deg().into());
            o.insert("by_hand".into(), serde_json::to_value(hand)?);
        }
        out!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        out!(
            "table rolled by hand: {}° increments at {}°/s, starts and stops of {} s (peak {:.3} rad/s²), holds of {} s, axis {} m below the surface",
            hand.increment_deg,
            hand.rate_deg_per_s,
            hand.ramp_s,
            hand.peak_angular_acceleration(),
            hand.hold_s,
            hand.axis_depth_m
        );
        print(layout, &r, true);
    }
    Ok(ExitCode::SUCCESS)
}

/// Runs the test and prints a table, or one JSON object with `json`; with `vtk`, writes
/// the states of the test as a ParaView time series into that directory.
pub fn run(
    layout: &Path,
    solver: SolverParams,
    params: &TiltParams,
    json: bool,
    vtk: Option<&Path>,
) -> Result<ExitCode> {
    let l = super::read_layout(layout)?;
    let mut rec = Recorder::default();
    let observer: &mut dyn Observer = if vtk.is_some() { &mut rec } else { &mut () };
    // The one choice of a method: the protocol seam.
    let run = drystone::protocol::run(&Tilt(*params), &l, solver, observer)
        .map_err(|e| anyhow::anyhow!("{e}; on the command line: --solver NAME"))?;
    // Whether the run was nscd's (rigid joints: its work is time steps and sweeps).
    let (r, rigid) = match run {
        TiltRun::Penalty(r) => (r.with_context(|| format!("tilting-table test of {}", layout.display()))?, false),
        TiltRun::Nscd(r) => (r.with_context(|| format!("tilting-table test of {}", layout.display()))?, true),
        TiltRun::Limit(r) => {
            if vtk.is_some() {
                bail!("--vtk draws the states of a DEM run; limit analysis has none (its mechanism: `drystone limit LAYOUT.json --svg FILE`)");
            }
            let r = r.with_context(|| format!("limit analysis of {}", layout.display()))?;
            return super::limit::report(layout, &l, &r, json, None);
        }
    };
    if let Some(dir) = vtk {
        let (series, others) = tilt_frames(&rec, &r);
        let pvd = write_series(dir, "tilt", &rec, &series)?;
        write_series(dir, "unstable_trials", &rec, &others)?;
        eprintln!("ParaView series: {} ({} states)", pvd.display(), series.len());
    }
    let newton = solver.kind.runs_newton();
    if json {
        // The result with its collapse angle α_max (the last stable tilt) as a key of its own.
        let mut v = serde_json::to_value(&r)?;
        if let Some(o) = v.as_object_mut() {
            o.insert("collapse_angle_deg".into(), r.collapse_angle_deg().into());
            if newton {
                let handed = r.increments.iter().filter(|i| i.newton_handed_over).count();
                o.insert("newton_handed_over".into(), handed.into());
            }
        }
        out!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print(layout, &r, rigid);
        if newton {
            let handed = r.increments.iter().filter(|i| i.newton_handed_over).count();
            out!(
                "newton            {handed} of {} increments and trials handed over to the protocol's own static solve",
                r.increments.len()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The mechanism's name as printed.
fn mechanism_name(k: MechanismKind) -> &'static str {
    match k {
        MechanismKind::Sliding => "Sliding",
        MechanismKind::Toppling => "Toppling",
        MechanismKind::Mixed => "Mixed",
        MechanismKind::None => "None",
    }
}

/// Prints the result `r` of the test of `layout`; `rigid` for a run by nscd (quasi-static
/// or rolled by hand), whose work is time steps and NSGS sweeps.
fn print(layout: &Path, r: &TiltResult, rigid: bool) {
    out!("layout            {}", layout.display());
    out!(
        "collapse angle    {:.2} deg (last stable), first unstable {}",
        r.collapse_angle_deg(),
        r.first_unstable_deg.map_or("none".into(), |a| format!("{a:.2} deg"))
    );
    if let Some(c) = &r.after_snap {
        out!(
            "snap              the wall jumps past {:.2} deg and its ropes catch it ({:.1} mm out of plane)",
            r.collapse_angle_deg(),
            c.caught_displacement_m * 1e3
        );
        out!(
            "falls             {}",
            match c.falls_first_unstable_deg {
                Some(a) => format!(
                    "at {:.2} deg (last stable), first unstable {a:.2} deg ({})",
                    c.falls_last_stable_deg,
                    c.falls_reason.map_or("", |x| x.name())
                ),
                None => format!("never: it stands to {:.2} deg", c.falls_last_stable_deg),
            }
        );
    }
    if let Some(reason) = r.collapse_reason {
        let note = if reason == drystone::loading::tilt::CollapseReason::StepBudget {
            " (undecided: the step budget ran out; the critical tilt may lie above)"
        } else {
            ""
        };
        out!("unstable because  {}{note}", reason.name());
        if !r.bracket_reliable {
            out!("bracket           NOT RELIABLE: a step budget is not a collapse; read the collapse angle as a lower bound (raise --max-steps, or --solver nscd)");
        }
    }
    out!(
        "mechanism         {} at joint {} ({} blocks moving)",
        mechanism_name(r.mechanism.kind),
        r.mechanism.joint,
        r.mechanism.blocks.len()
    );
    if rigid {
        // nscd's result counts time steps of its release trials and NSGS sweeps.
        out!(
            "work              {} time steps of non-smooth contact dynamics (dt {:.3e} s), {} NSGS sweeps; wall time {:.2} s",
            r.steps,
            r.dt_s,
            r.iterations,
            r.wall_time_s
        );
    } else {
        out!(
            "work              {} implicit iterations, {} steps of dynamic relaxation (dt {:.3e} s); wall time {:.2} s",
            r.iterations,
            r.steps,
            r.dt_s,
            r.wall_time_s
        );
    }
    if !r.scalar_fallbacks_deg.is_empty() {
        let at: Vec<String> = r.scalar_fallbacks_deg.iter().map(|a| format!("{a:.3}")).collect();
        out!(
            "block scaling     blew up at {} deg; repeated with scalar scaling (with true masses where that blew up too), kept from there on",
            at.join(", ")
        );
    }
    out!("out-of-plane displacement of the top points [cm]:");
    out!("  alpha_deg  {}", r.monitors.join("  "));
    for inc in r.increments.iter().filter(|i| i.stable) {
        let d: Vec<String> = inc.displacement_m.iter().map(|d| format!("{:>9.3}", d * 100.0)).collect();
        out!("  {:>9.2}  {}", inc.alpha_deg, d.join("  "));
    }
}
