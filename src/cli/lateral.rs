//! `drystone lateral`: the static lateral load on a layout file.

use super::solver::SolverChoice;
use anyhow::{bail, Context, Result};
use drystone::dem::{PenaltyParams, SolverParams};
use drystone::io::series::{check_series_dir, lateral_frames, write_series, Recorder};
use drystone::limit::LimitParams;
use drystone::loading::lateral::{LateralError, LateralParams, LateralResult};
use drystone::loading::lateral_nscd::LateralLimit;
use drystone::loading::lateral_pushover::LateralPushover;
use drystone::protocol::{supports, Lateral, LateralRun, Observer, Protocol, Pushover, PushoverRun, Unsupported};

use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone lateral`.
#[derive(clap::Args)]
pub struct LateralArgs {
    /// Layout file (JSON).
    layout: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    pressure: super::solver::Pressure,
    /// Unbalanced-force ratio of equilibrium.
    #[arg(long, default_value_t = PenaltyParams::default().tolerance)]
    tolerance: f64,
    #[command(flatten)]
    solver: SolverChoice,
    #[command(flatten)]
    limit: super::solver::LimitFlags,
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
    /// Relative width of the pushover's final bracket of λ, in (0, 1) [default 0.02 with
    /// the penalty DEM, 0.01 with --solver nscd].
    #[arg(long, value_name = "FRACTION")]
    pushover_resolution: Option<f64>,
}

/// `drystone lateral`: the load's parameters from the options, then [`run`].
///
/// # Errors
/// Those of [`run`].
pub fn command(a: LateralArgs) -> Result<ExitCode> {
    let params = a.pressure.apply(LateralParams {
        pushover: a.pushover,
        pushover_resolution: a.pushover_resolution,
        ..LateralParams::default()
    });
    let kind = a.solver.solver;
    let limit = a.limit.params_for(kind, LimitParams::default())?;
    let penalty = PenaltyParams { tolerance: a.tolerance, ..PenaltyParams::default() };
    let solver = SolverParams { kind, limit, penalty, ..SolverParams::default() };
    run(&a.layout, solver, &params, a.json, a.vtk.as_deref())
}

/// Solves the load to equilibrium and prints a table, or one JSON object with `json`;
/// with `vtk`, writes the settled and the loaded state as a ParaView time series there.
pub fn run(
    layout: &Path,
    solver: SolverParams,
    params: &LateralParams,
    json: bool,
    vtk: Option<&Path>,
) -> Result<ExitCode> {
    let l = super::read_layout(layout)?;
    if let Some(dir) = vtk {
        check_series_dir(dir).context("--vtk: the ParaView series cannot be written there")?;
    }
    let mut params = *params;
    // A method that runs the pushover but not the service load (by the compatibility
    // table: nscd, the rigid pushover) runs the pushover without --pushover too, a spelling
    // kept working with a note.
    let method = solver.kind.method();
    let (chosen, pushed) =
        (Protocol::lateral(params).loading(), Protocol::lateral(LateralParams { pushover: true, ..params }).loading());
    if !supports(chosen, method) && supports(pushed, method) {
        eprintln!(
            "note: `--solver {}` runs the rigid pushover; give it with --pushover (without it is deprecated)",
            solver.kind.name()
        );
        params.pushover = true;
    }
    let mut rec = Recorder::default();
    let observer: &mut dyn Observer = if vtk.is_some() { &mut rec } else { &mut () };
    let unsupported = |e: Unsupported| anyhow::anyhow!("{e}; on the command line: --solver NAME");
    // The one choice of a method: the protocol seam.
    if params.pushover {
        let run = drystone::protocol::run(&Pushover(params), &l, solver, observer).map_err(unsupported)?;
        return match run {
            PushoverRun::Penalty { service, collapse } => {
                service.map_err(hint).with_context(|| format!("static lateral load on {}", layout.display()))?;
                let pushed = collapse.map(|c| c.0).context("the pushover did not run")?;
                let r = pushed.map_err(hint).with_context(|| format!("DEM pushover of {}", layout.display()))?;
                recorded(vtk, "pushover", &rec)?;
                dem_pushover(layout, &r, &params, json)
            }
            PushoverRun::Nscd(r) => {
                no_states(vtk)?;
                let r = r.with_context(|| format!("rigid pushover of {}", layout.display()))?;
                rigid_pushover(layout, &r, &params, json)
            }
            PushoverRun::Limit(r) => {
                no_states(vtk)?;
                let r = r.with_context(|| format!("limit analysis of {}", layout.display()))?;
                super::limit::report(layout, &l, &r, json, None)
            }
        };
    }
    let r = match drystone::protocol::run(&Lateral(params), &l, solver, observer).map_err(unsupported)? {
        LateralRun::Penalty(r) => {
            r.map_err(hint).with_context(|| format!("static lateral load on {}", layout.display()))?
        }
        LateralRun::Limit(r) => {
            no_states(vtk)?;
            let r = r.with_context(|| format!("limit analysis of {}", layout.display()))?;
            return super::limit::report(layout, &l, &r, json, None);
        }
    };
    recorded(vtk, "lateral", &rec)?;
    if json {
        out!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        print(layout, &params, &r);
    }
    Ok(ExitCode::SUCCESS)
}

/// Refuses `--vtk` for a run that has no DEM states to draw (nscd's rigid pushover, limit
/// analysis).
fn no_states(vtk: Option<&Path>) -> Result<()> {
    if vtk.is_some() {
        bail!("--vtk draws the states of a DEM run; the rigid pushover and limit analysis have none");
    }
    Ok(())
}

/// Writes the states `rec` recorded as the ParaView series `name` (time = the load factor)
/// into `vtk`, when it is given.
fn recorded(vtk: Option<&Path>, name: &str, rec: &Recorder) -> Result<()> {
    if let Some(dir) = vtk {
        let pvd = write_series(dir, name, rec, &lateral_frames(rec))?;
        eprintln!("ParaView series: {}", pvd.display());
    }
    Ok(())
}

/// The library's error, with the command-line spelling of the solvers that do run the load.
fn hint(e: LateralError) -> anyhow::Error {
    match e {
        LateralError::Unsupported(_) => anyhow::anyhow!("{e}; on the command line: --solver NAME"),
        e => e.into(),
    }
}

/// The load line of a lateral run: the pressures (`at`: the load multiplier they are given
/// at, if any), their resultant in y against the weight, and the faces they load.
fn print_load(params: &LateralParams, at: &str, resultant_y: f64, weight_n: f64, loaded_faces: usize) {
    out!(
        "load              {:.0} Pa at the base, {:.0} Pa at the top{at}: resultant {:.1} N in y ({:.3} of the weight {:.1} N), {} loaded faces",
        params.pressure_base_pa,
        params.pressure_top_pa,
        resultant_y,
        resultant_y / weight_n,
        weight_n,
        loaded_faces
    );
}

fn print(layout: &Path, params: &LateralParams, r: &LateralResult) {
    out!("layout            {}", layout.display());
    print_load(params, "", r.resultant_n.y, r.weight_n, r.loaded_faces);
    match &r.collapse_reason {
        None => out!("equilibrium       yes (unbalanced-force ratio {:.2e})", r.unbalanced_ratio),
        Some(why) => out!("equilibrium       NO: collapsed ({why})"),
    }
    out!("top displacement  [cm]");
    for (m, d) in r.monitors.iter().zip(&r.displacement_m) {
        out!("  {m:<12} {:>9.4}", d * 100.0);
    }
    out!("  {:<12} {:>9.4}", "max", r.max_displacement_m * 100.0);
    out!("drift             {:.3e} (max / H, H = {:.3} m)", r.drift, r.height_m);
    out!("steps             {}  (dt {:.3e} s, wall time {:.2} s)", r.steps, r.dt_s, r.wall_time_s);
}

/// `lateral --pushover --solver nscd`: prints the rigid pushover `r`, the collapse load
/// multiplier λ of the pressure by non-smooth contact dynamics (bisection to
/// --pushover-resolution, 1 % of λ by default).
fn rigid_pushover(path: &Path, r: &LateralLimit, params: &LateralParams, json: bool) -> Result<ExitCode> {
    if json {
        return pushover_json(
            r,
            r.lambda_stable,
            &[("rigid_joints", "the joints' Kn and Ks are not used (rigid blocks)")],
        );
    }
    out!("layout            {}", path.display());
    out!(
        "load multiplier   {:.4} (stable), first unstable {} (the pressure {:.0} Pa at the base, {:.0} Pa at the top, times λ)",
        r.lambda_stable,
        r.lambda_unstable.map_or("none".into(), |l| format!("{l:.4}")),
        params.pressure_base_pa,
        params.pressure_top_pa
    );
    if let Some(m) = &r.mechanism {
        out!("mechanism         {:?} at joint {} ({} blocks moving)", m.kind, m.joint, m.blocks.len());
    }
    out!("work              {} trials, {} time steps; wall time {:.2} s", r.trials, r.steps, r.wall_time_s);
    out!("solver            nscd (rigid blocks: the joints' Kn and Ks are not used)");
    Ok(ExitCode::SUCCESS)
}

/// Prints a pushover's result `r` as one JSON object, with its stable load multiplier
/// `lambda` as `load_multiplier` and the `notes` as keys of their own.
fn pushover_json(r: &impl serde::Serialize, lambda: f64, notes: &[(&str, &str)]) -> Result<ExitCode> {
    let mut v = serde_json::to_value(r)?;
    if let Some(o) = v.as_object_mut() {
        o.insert("load_multiplier".into(), lambda.into());
        for (key, note) in notes {
            o.insert((*key).into(), (*note).into());
        }
    }
    out!("{}", serde_json::to_string_pretty(&v)?);
    Ok(ExitCode::SUCCESS)
}

/// `lateral --pushover`: prints the DEM pushover `r`, the collapse load multiplier λ of the
/// pressure by the penalty DEM (`loading::lateral_pushover`).
fn dem_pushover(path: &Path, r: &LateralPushover, params: &LateralParams, json: bool) -> Result<ExitCode> {
    if json {
        return pushover_json(r, r.lambda_stable, &[]);
    }
    out!("layout            {}", path.display());
    print_load(params, " (λ = 1)", r.resultant_n.y, r.weight_n, r.loaded_faces);
    out!(
        "load multiplier   {:.4} (stable), first unstable {}{}",
        r.lambda_stable,
        r.lambda_unstable.map_or("none".into(), |l| format!("{l:.4}")),
        r.collapse_reason.map_or(String::new(), |c| format!(" ({})", c.name()))
    );
    if let Some(m) = &r.mechanism {
        out!("mechanism         {:?} at joint {} ({} blocks moving)", m.kind, m.joint, m.blocks.len());
    }
    out!("increments        λ, stable, top displacement max [cm], relaxation steps, implicit iterations");
    for i in &r.increments {
        let max = i.displacement_m.iter().fold(0.0_f64, |a, d| a.max(d.abs()));
        out!("  {:>10.4} {:<6} {:>10.4} {:>9} {:>6}", i.load_multiplier, i.stable, max * 100.0, i.steps, i.iterations);
    }
    out!(
        "work              {} trials, {} steps (dt {:.3e} s); wall time {:.2} s",
        r.trials,
        r.steps,
        r.dt_s,
        r.wall_time_s
    );
    out!("solver            penalty DEM (Kn, Ks, friction, cohesion and tension of the joints)");
    Ok(ExitCode::SUCCESS)
}
