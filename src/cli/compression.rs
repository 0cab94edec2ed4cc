//! `drystone compression`: the vertical compression test of a layout file.

use super::solver::SolverChoice;
use anyhow::Result;
use drystone::dem::{PenaltyParams, SolverParams};
use drystone::loading::compression::{CompressionParams, CompressionResult};
use drystone::loading::inplane::BeamRotation;
use drystone::protocol::{Compression, CompressionRun};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone compression`.
#[derive(clap::Args)]
pub struct CompressionArgs {
    /// Layout file (JSON).
    layout: PathBuf,
    /// The vertical stress on the wall's top at which the modulus is read, MPa (the loading
    /// beam's weight part of it; the wall's self-weight comes on top).
    #[arg(long, value_name = "MPA")]
    sigma0_mpa: f64,
    /// Load–unload cycles to σ0 [default: 3].
    #[arg(long)]
    cycles: Option<u32>,
    /// The stress each unloading goes down to, MPa [default: the beam's own weight over the
    /// wall's plan area, the actuator at zero].
    #[arg(long, value_name = "MPA")]
    unload_to_mpa: Option<f64>,
    /// A stress to raise to after the cycles, MPa, in --points-per-branch increments,
    /// stopping where equilibrium is lost (the compressive strength's bracket).
    #[arg(long, value_name = "MPA")]
    raise_to_mpa: Option<f64>,
    /// Curve points per branch [default: 4] (the readings do not depend on it, but the
    /// raise's increments).
    #[arg(long)]
    points_per_branch: Option<u32>,
    /// The loading beam's rotation in the wall's plane: `fixed` (held level) or `free`
    /// (about the actuator's point at --shear-span-m, the in-plane test's rig).
    #[arg(long, value_enum, default_value = "fixed")]
    beam_rotation: Rotation,
    /// The actuator's height above the base, m (with --beam-rotation free; it sets the
    /// beam's depth as the in-plane test's shear span does).
    #[arg(long, value_name = "M")]
    shear_span_m: Option<f64>,
    /// Unbalanced-force ratio of equilibrium of each static solve [default: 1e-4].
    #[arg(long)]
    tolerance: Option<f64>,
    #[command(flatten)]
    solver: SolverChoice,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

/// The loading beam's rotation, as the command line spells it.
#[derive(clap::ValueEnum, Clone, Copy)]
enum Rotation {
    Fixed,
    Free,
}

/// `drystone compression`: runs the test through the protocol seam and prints its readings.
///
/// # Errors
/// A layout that cannot be read, a refused solver or parameter (named), a wall that does
/// not stand.
pub fn command(a: CompressionArgs) -> Result<ExitCode> {
    let beam_rotation = match a.beam_rotation {
        Rotation::Fixed => BeamRotation::Fixed,
        Rotation::Free => BeamRotation::Free,
    };
    if beam_rotation == BeamRotation::Fixed && a.shear_span_m.is_some() {
        anyhow::bail!(
            "--shear-span-m is read with --beam-rotation free only (a beam held level has no actuator's lever)"
        );
    }
    if beam_rotation == BeamRotation::Free && a.shear_span_m.is_none() {
        anyhow::bail!(
            "--beam-rotation free needs --shear-span-m (the height of the actuator's point the beam turns about, m)"
        );
    }
    let d = CompressionParams::default();
    let params = CompressionParams {
        sigma0_mpa: a.sigma0_mpa,
        cycles: a.cycles.unwrap_or(d.cycles),
        unload_to_mpa: a.unload_to_mpa,
        raise_to_mpa: a.raise_to_mpa,
        points_per_branch: a.points_per_branch.unwrap_or(d.points_per_branch),
        beam_rotation,
        shear_span_m: a.shear_span_m,
    };
    // On the command line a parameter is named by its flag (`--sigma0-mpa`), not by the
    // study file's key (`compression.sigma0_mpa`).
    params.validate().map_err(|e| anyhow::anyhow!("--{}", e.to_string().replace('_', "-")))?;
    let penalty = PenaltyParams {
        tolerance: a.tolerance.unwrap_or(PenaltyParams::default().tolerance),
        ..PenaltyParams::default()
    };
    let solver = SolverParams { kind: a.solver.solver, penalty, ..SolverParams::default() };
    let layout = super::read_layout(&a.layout)?;
    let run = drystone::protocol::run(&Compression(params), &layout, solver, &mut ())
        .map_err(|e| anyhow::anyhow!("{e}; on the command line: --solver NAME"))?;
    let CompressionRun::Penalty(r) = run;
    let r =
        r.map_err(|e| anyhow::anyhow!("compression test of {}: {}", a.layout.display(), as_flags(&e.to_string())))?;
    if a.json {
        out!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        print(&a.layout, &r);
    }
    Ok(ExitCode::SUCCESS)
}

fn print(layout: &Path, r: &CompressionResult) {
    let fmt = |v: &[f64], digits: usize| v.iter().map(|x| format!("{x:.digits$}")).collect::<Vec<_>>().join(", ");
    out!("layout            {}", layout.display());
    out!(
        "wall              L {:.3} m, H {:.3} m, t {:.3} m, weight {:.2} kN",
        r.length_m,
        r.height_m,
        r.thickness_m,
        r.wall_weight_kn
    );
    out!(
        "stresses          σ0 {} MPa, unloaded to {:.5} MPa (the beam alone: {:.5} MPa){}",
        r.sigma0_mpa,
        r.unload_to_mpa,
        r.beam_stress_mpa,
        r.raise_to_mpa.map_or(String::new(), |x| format!(", raised to {x} MPa"))
    );
    out!("vertical modulus  {:.1} MPa (secant of the first loading branch, Epc)", r.wall_vertical_modulus_mpa);
    out!("cycle secants     {} MPa", fmt(&r.loading_secants_mpa, 1));
    out!("residuals         {} mm (after each unloading)", fmt(&r.residual_settlements_mm, 5));
    if r.raise_to_mpa.is_some() {
        match r.strength_bracket_mpa {
            Some([lo, hi]) => out!("strength          between {lo:.4} and {hi:.4} MPa (equilibrium lost)"),
            None => out!("strength          above the stress raised to (every increment in equilibrium)"),
        }
    }
    out!("curve             stress [MPa], shortening [mm], branch, converged");
    for p in &r.curve {
        out!("  {:>10.5} {:>10.5}  {:?} {} {}", p.stress_mpa, p.shortening_mm, p.branch, p.cycle, p.converged);
    }
    out!(
        "work              {} unconverged solves, {} steps (dt {:.3e} s); wall time {:.2} s",
        r.unconverged,
        r.steps,
        r.dt_s,
        r.wall_time_s
    );
}

/// `msg` with the study file's keys of the test (`compression.shear_span_m`) named by their
/// flags (`--shear-span-m`): the checks that need the layout word their refusals for a
/// study file.
fn as_flags(msg: &str) -> String {
    const KEYS: [&str; 7] =
        ["sigma0_mpa", "cycles", "unload_to_mpa", "raise_to_mpa", "points_per_branch", "beam_rotation", "shear_span_m"];
    KEYS.iter()
        .fold(msg.to_string(), |m, k| m.replace(&format!("compression.{k}"), &format!("--{}", k.replace('_', "-"))))
}
