//! `drystone tilt`: the tilting-table test of a layout file.

use anyhow::{Context, Result};
use drystone::dem::drivers::nscd::{NscdParams, NsgsNorm};
use drystone::dem::SolverParams;
use drystone::io::series::{tilt_frames, write_series, Recorder};
use drystone::loading::tilt::{run_tilt_observed, MechanismKind, TiltParams, TiltResult};
use std::path::Path;
use std::process::ExitCode;

/// The non-smooth solver's NSGS settings on the command line (`--solver nscd`; the keys of
/// a study's `[solver.nscd]` table): each overrides [`NscdParams`]' default when given.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct NscdArgs {
    /// NSGS convergence norm of `--solver nscd`: `adaptive` (the default: the velocity norm,
    /// and the quadratic norm too once a step has done --nscd-quad-after-solves local
    /// solves), `velocity` or `quad` (docs/nscd.md).
    #[arg(long, value_name = "NORM", value_parser = parse_norm)]
    pub nscd_norm: Option<NsgsNorm>,
    /// NSGS tolerance of `--solver nscd` in its norm (velocity: over g h [default 1e-7];
    /// quad: dimensionless).
    #[arg(long, value_name = "TOL")]
    pub nscd_tolerance: Option<f64>,
    /// The quadratic norm's tolerance of the adaptive norm [default 1e-4].
    #[arg(long, value_name = "TOL")]
    pub nscd_quad_tolerance: Option<f64>,
    /// Local solves of a step after which the adaptive norm accepts the quadratic norm
    /// [default 1.5e5].
    #[arg(long, value_name = "SOLVES")]
    pub nscd_quad_after_solves: Option<f64>,
    /// Largest number of NSGS sweeps per step [default 2000].
    #[arg(long, value_name = "SWEEPS")]
    pub nscd_max_iterations: Option<u32>,
}

/// `--nscd-norm NAME`.
fn parse_norm(name: &str) -> Result<NsgsNorm, String> {
    match name {
        "adaptive" => Ok(NsgsNorm::Adaptive),
        "velocity" => Ok(NsgsNorm::Velocity),
        "quad" => Ok(NsgsNorm::Quad),
        other => Err(format!("{other:?}: expected adaptive, velocity or quad")),
    }
}

impl NscdArgs {
    /// Some option was given.
    pub fn given(&self) -> bool {
        self.nscd_norm.is_some()
            || self.nscd_tolerance.is_some()
            || self.nscd_quad_tolerance.is_some()
            || self.nscd_quad_after_solves.is_some()
            || self.nscd_max_iterations.is_some()
    }

    /// `base` with the options given; out-of-range values are refused by the solver
    /// (`NscdParams::validate`, naming the key).
    pub fn apply(&self, base: NscdParams) -> NscdParams {
        NscdParams {
            norm: self.nscd_norm.unwrap_or(base.norm),
            tolerance: self.nscd_tolerance.unwrap_or(base.tolerance),
            quad_tolerance: self.nscd_quad_tolerance.unwrap_or(base.quad_tolerance),
            quad_after_solves: self.nscd_quad_after_solves.unwrap_or(base.quad_after_solves),
            max_iterations: self.nscd_max_iterations.unwrap_or(base.max_iterations),
            ..base
        }
    }
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
    let mut observe = |a: f64, stable: bool, sim: &drystone::dem::Simulation| {
        if vtk.is_some() {
            rec.observe(a, stable, sim)
        }
    };
    let r = run_tilt_observed(&l, solver, params, &mut observe)
        .with_context(|| format!("tilting-table test of {}", layout.display()))?;
    if let Some(dir) = vtk {
        let (series, others) = tilt_frames(&rec, &r);
        let pvd = write_series(dir, "tilt", &rec, &series)?;
        write_series(dir, "unstable_trials", &rec, &others)?;
        eprintln!("ParaView series: {} ({} states)", pvd.display(), series.len());
    }
    if json {
        // The result with its collapse angle α_max (the last stable tilt) as a key of its own.
        let mut v = serde_json::to_value(&r)?;
        if let Some(o) = v.as_object_mut() {
            o.insert("collapse_angle_deg".into(), r.collapse_angle_deg().into());
        }
        out!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print(layout, &r);
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

fn print(layout: &Path, r: &TiltResult) {
    out!("layout            {}", layout.display());
    out!(
        "collapse angle    {:.2} deg (last stable), first unstable {}",
        r.collapse_angle_deg(),
        r.first_unstable_deg.map_or("none".into(), |a| format!("{a:.2} deg"))
    );
    if let Some(reason) = r.collapse_reason {
        let note = if reason == drystone::loading::tilt::CollapseReason::StepBudget {
            " (undecided: the step budget ran out; the critical tilt may lie above)"
        } else {
            ""
        };
        out!("unstable because  {}{note}", reason.name());
        if !r.bracket_reliable {
            out!("bracket           NOT RELIABLE: a step budget is not a collapse; read the collapse angle as a lower bound (raise max_steps_per_increment, or --solver nscd)");
        }
    }
    out!(
        "mechanism         {} at joint {} ({} blocks moving)",
        mechanism_name(r.mechanism.kind),
        r.mechanism.joint,
        r.mechanism.blocks.len()
    );
    out!(
        "work              {} implicit iterations, {} steps of dynamic relaxation (dt {:.3e} s); wall time {:.2} s",
        r.iterations,
        r.steps,
        r.dt_s,
        r.wall_time_s
    );
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
