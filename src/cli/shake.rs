//! `drystone shake`: a layout on a shaking table, under a record or a built-in pulse.

use super::solver::NscdArgs;
use anyhow::{anyhow, bail, Context, Result};
use drystone::dem::{PenaltyParams, SolverKind, SolverParams};
use drystone::ground::{
    read_record_with, ColumnMap, Motion, Pulse, PulseError, MIN_SAMPLES_PER_PERIOD, PLAUSIBLE_PGA_G,
};
use drystone::io::series::{check_series_dir, motion_frames, write_series, Recorder};
use drystone::loading::shake::{ShakeError, ShakeParams, ShakeResult};
use drystone::nscd::NscdParams;
use drystone::protocol::run_shake_observed;
use drystone::protocol::shake::{method_notes, restitutions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone shake`.
#[derive(clap::Args)]
pub struct ShakeArgs {
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
    #[arg(long, default_value_t = drystone::protocol::Loading::Shake.default_solver(), value_parser = super::solver::parse_solver)]
    solver: SolverKind,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
    /// Write the motion as a ParaView time series into DIR (shake.pvd, time in s).
    #[arg(long, value_name = "DIR")]
    vtk: Option<PathBuf>,
    #[command(flatten)]
    nscd: NscdArgs,
}

/// `drystone shake`: the base motion, the solver and the test's parameters from the
/// options, then [`run`].
///
/// # Errors
/// Those of [`motion`], `--nscd-*` options without `--solver nscd`, or those of [`run`].
pub fn command(a: ShakeArgs) -> Result<ExitCode> {
    let from_record = a.record.is_some();
    let args = MotionArgs {
        record: a.record,
        pulse: a.pulse,
        amplitude_g: a.amplitude_g,
        period_s: a.period_s,
        scale_pga_g: a.scale_pga_g,
        baseline: a.baseline_correction,
        columns: a.columns,
        dt_s: a.dt_s,
    };
    let motion = motion(&args, a.dt_s.min(0.001))?;
    let d = ShakeParams::default();
    let (nscd_e, contact_e) = restitutions(a.solver, a.restitution);
    let base = NscdParams { dt_s: a.dt_s, restitution: nscd_e, ..NscdParams::default() };
    let nscd = a.nscd.params_for(a.solver, base)?;
    if a.solver.method().solves_steps_to_a_tolerance() {
        for (key, why) in nscd.motion_cost_warnings() {
            eprintln!("warning: --nscd-{} {why}", key.replace('_', "-"));
        }
    }
    let penalty = PenaltyParams { contact_restitution: contact_e, ..PenaltyParams::default() };
    let solver = SolverParams { kind: a.solver, nscd, penalty, ..SolverParams::default() };
    let params =
        ShakeParams { duration_s: a.duration_s, tail_s: a.tail_s, stop_at_collapse: !a.no_stop_at_collapse, ..d };
    if let Some(w) = duration_warning(&motion, a.duration_s) {
        eprintln!("warning: {w}");
    }
    // A method of a fixed step (nscd's) receives the record's mean over each step.
    let fixed_step = drystone::protocol::shake::step_rule(&solver).and_then(|r| r.fixed_dt_s);
    if from_record && fixed_step.is_some_and(|dt| dt > motion.dt_s * (1.0 + 1e-9)) {
        eprintln!(
            "warning: the solver's step --dt-s {} s is coarser than the record's sampling {} s: each step receives the \
             record's mean over it (its impulse), and a peak shorter than the step is spread over the step",
            a.dt_s, motion.dt_s
        );
    }
    run(&a.layout, &motion, solver, &params, a.json, a.vtk.as_deref())
}

/// The base motion of `drystone shake`.
pub struct MotionArgs {
    /// A record file (`.AT2`, `.csv`, `.tsv`).
    pub record: Option<PathBuf>,
    /// A built-in pulse: `one-sine` or `ricker`.
    pub pulse: Option<String>,
    /// Its amplitude, g.
    pub amplitude_g: Option<f64>,
    /// Its period, s.
    pub period_s: Option<f64>,
    /// Scale the motion to this PGA, g.
    pub scale_pga_g: Option<f64>,
    /// Remove the velocity's linear trend (baseline correction).
    pub baseline: bool,
    /// The record's columns named explicitly (`--columns time=t,h=acc_x_g,v=acc_z_g`).
    pub columns: Option<ColumnMap>,
    /// The solver's time step `--dt-s`, s.
    pub dt_s: f64,
}

/// Coarsest record sampling interval run without a warning, s \[0.05\]: 20 samples per
/// second keep content up to 10 Hz, the range of a wall's rocking and of strong motion.
pub const COARSE_RECORD_DT_S: f64 = drystone::ground::COARSE_RECORD_DT_S;

/// The motion the arguments describe.
///
/// # Errors
/// A record refused (naming file and line), a pulse without amplitude or period, or both
/// or neither of `--record` and `--pulse`.
pub fn motion(args: &MotionArgs, dt_s: f64) -> Result<Motion> {
    if !(args.dt_s.is_finite() && args.dt_s > 0.0) {
        bail!("--dt-s must be > 0 (the solver's time step, s), got {}", args.dt_s);
    }
    let m = match (&args.record, &args.pulse) {
        (Some(path), None) => {
            if args.amplitude_g.is_some() || args.period_s.is_some() {
                bail!("--amplitude-g and --period-s shape a built-in --pulse; a --record is scaled with --scale-pga-g");
            }
            let m = read_record_with(path, args.columns.as_ref())?;
            if m.dt_s > COARSE_RECORD_DT_S {
                eprintln!(
                    "warning: {} is sampled every {} s ({:.1} samples per second): content above {:.1} Hz is lost",
                    path.display(),
                    m.dt_s,
                    1.0 / m.dt_s,
                    0.5 / m.dt_s
                );
            }
            m
        }
        (None, Some(name)) => {
            if args.columns.is_some() {
                bail!("--columns names the columns of a --record file; a --pulse has none");
            }
            let (Some(a), Some(t)) = (args.amplitude_g, args.period_s) else {
                bail!("--pulse {name} needs --amplitude-g and --period-s");
            };
            let p = Pulse::from_name(name, a, t)
                .with_context(|| format!("--pulse {name:?}: expected one-sine or ricker"))?;
            p.validate().map_err(|e| match e {
                PulseError::Amplitude(v) => anyhow!("--amplitude-g must be finite, got {v}"),
                PulseError::Period(v) => anyhow!("--period-s must be > 0, got {v}"),
                e => e.into(),
            })?;
            if t / dt_s < MIN_SAMPLES_PER_PERIOD {
                bail!(
                    "--period-s {t}: the pulse spans {:.1} steps of {dt_s:e} s, too few to resolve it (at least \
                     {MIN_SAMPLES_PER_PERIOD}); give --period-s >= {:e} or a smaller --dt-s",
                    t / dt_s,
                    MIN_SAMPLES_PER_PERIOD * dt_s
                );
            }
            let span = if name == "ricker" { 2.0 * t } else { t };
            drystone::ground::check_motion_size((span / dt_s).ceil() + 1.0, span)
                .map_err(|m| anyhow::anyhow!("--period-s {t} sampled at the step {dt_s:e} s (--dt-s): {m}"))?;
            p.sampled(dt_s, 0.0)
        }
        (Some(_), Some(_)) => bail!("give either --record or --pulse, not both"),
        (None, None) => bail!("give the base motion: --record FILE or --pulse one-sine|ricker"),
    };
    let m = if args.baseline { m.baseline_corrected() } else { m };
    let m = match args.scale_pga_g {
        Some(p) if !(p.is_finite() && p > 0.0) => bail!("--scale-pga-g must be > 0, got {p}"),
        Some(p) if m.pga_g() == 0.0 => {
            bail!("--scale-pga-g {p}: the motion {} has no acceleration (PGA 0): there is nothing to scale", m.name)
        }
        Some(p) => m.scaled_to_pga(p),
        None => m,
    };
    if m.pga_g() > PLAUSIBLE_PGA_G {
        eprintln!(
            "warning: PGA {:.3e} g is implausible for a ground motion (above {PLAUSIBLE_PGA_G} g): check the record's unit \
             or the pulse's amplitude",
            m.pga_g()
        );
    }
    Ok(m)
}

/// The warning for `--duration-s` longer than the motion, which is simulated to its end
/// only (then the tail), or `None`.
pub fn duration_warning(motion: &Motion, duration_s: Option<f64>) -> Option<String> {
    let d = duration_s?;
    (d > motion.duration_s() * (1.0 + 1e-9) + 1e-12).then(|| {
        format!(
            "--duration-s {d} is longer than the motion {} ({} s): its {} s are simulated, then --tail-s of free motion",
            motion.name,
            motion.duration_s(),
            motion.duration_s()
        )
    })
}

/// Whether the run drives a vertical component: the motion has one and the shaking
/// parameters drive it.
fn vertical_applied(motion: &Motion, params: &ShakeParams) -> bool {
    params.vertical && motion.vertical_g.is_some()
}

/// Runs the test and prints a summary, or one JSON object with `json`; with `vtk`, writes
/// the motion as a ParaView series (time in s).
pub fn run(
    layout: &Path,
    motion: &Motion,
    solver: SolverParams,
    params: &ShakeParams,
    json: bool,
    vtk: Option<&Path>,
) -> Result<ExitCode> {
    let l = super::read_layout(layout)?;
    if let Some(dir) = vtk {
        check_series_dir(dir).context("--vtk: the ParaView series cannot be written there")?;
    }
    let mut rec = Recorder::default();
    let r = run_shake_observed(&l, solver, motion, params, &mut |t, bodies| {
        if vtk.is_some() {
            rec.observe_bodies(t, true, bodies, Vec::new());
        }
    })
    .map_err(|e| match e {
        ShakeError::Unsupported(_) => anyhow!("{e}; on the command line: `--solver nscd` or `--solver penalty`"),
        e => e.into(),
    })
    .with_context(|| format!("shaking-table test of {}", layout.display()))?;
    if let Some(dir) = vtk {
        let pvd = write_series(dir, "shake", &rec, &motion_frames(&rec))?;
        eprintln!("ParaView series: {} ({} states)", pvd.display(), rec.states.len());
    }
    if json {
        let mut v = serde_json::to_value(&r)?;
        if let Some(o) = v.as_object_mut() {
            o.insert("vertical_applied".into(), vertical_applied(motion, params).into());
            if let Some((key, value)) = method_notes(&solver, &r).json {
                o.insert(key.into(), value);
            }
        }
        out!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print(layout, &r, &solver);
        match &motion.vertical_g {
            Some(v) if params.vertical => {
                let peak = v.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
                out!("vertical          applied (peak {peak:.3} g)");
            }
            Some(_) => out!("vertical          not applied (the motion has one)"),
            None => out!("vertical          none (horizontal motion only)"),
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn print(layout: &Path, r: &ShakeResult, solver: &SolverParams) {
    out!("layout            {} ({} blocks, height {:.3} m)", layout.display(), r.blocks, r.height_m);
    out!("motion            {} (PGA {:.3} g)", r.motion, r.pga_g);
    match r.collapse_time_s {
        Some(t) => out!("overturned        yes, at {t:.3} s ({} blocks fallen)", r.blocks_fallen),
        None => out!("overturned        no"),
    }
    out!("max rotation      {:.3} deg (about x, the rocking axis)", r.max_rotation_deg);
    out!("drift             max {:.4}, residual {:.4}", r.max_drift, r.residual_drift);
    let notes = method_notes(solver, r);
    if !notes.work.is_empty() {
        out!("work              {}", notes.work);
    }
    out!("solver            {}", notes.solver);
}
