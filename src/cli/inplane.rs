//! `drystone in-plane`: the in-plane shear–compression test of a layout file.

use super::solver::SolverChoice;
use anyhow::{bail, Context, Result};
use drystone::dem::{PenaltyParams, SolverParams};
use drystone::io::inplane::crack_map_svg;
use drystone::limit::inplane::InPlaneLimit;
use drystone::limit::LimitParams;
use drystone::loading::inplane::{
    mechanism_joints, BeamRotation, DirectionResult, History, InPlaneParams, InPlaneResult, OutOfPlane, Rig,
    READING_DRIFTS_PCT,
};
use drystone::protocol::{InPlane, InPlaneRun, States, Unsupported};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone in-plane`.
#[derive(clap::Args)]
pub struct InPlaneArgs {
    /// Layout file (JSON).
    layout: PathBuf,
    /// Vertical stress applied through the loading beam, MPa (the wall's self-weight comes
    /// on top).
    #[arg(long, value_name = "MPA")]
    sigma0_mpa: f64,
    /// Shear span H0: the height above the base at which the horizontal force acts, m (at
    /// least the wall's height; the beam's rotation is free). Not read with
    /// `--beam-rotation fixed`.
    #[arg(long, value_name = "M")]
    shear_span_m: Option<f64>,
    /// The height above the base of the point where the displacement is read, m (on the
    /// loading beam; the drift is the displacement there over this height). Default: the
    /// actuator's height (the shear span with a free beam rotation, as the Stone Masonry
    /// Database reads a test that reports none; the wall's height with a fixed one).
    #[arg(long, value_name = "M")]
    measuring_height_m: Option<f64>,
    /// The largest drift of the imposed path, % [default: 3]: the actuator travels this
    /// share of its lever (the shear span; the wall's height with the beam held level), so
    /// a drift read at another --measuring-height-m ends elsewhere (the penalty DEM: at most
    /// 8.8 % with its default face-angle tolerance; nscd: up to 50 %; not read by limit
    /// analysis, which has no path).
    #[arg(long, value_name = "PCT")]
    drift_pct: Option<f64>,
    /// Cycles of growing amplitude (each amplitude `--cycles` times) instead of a monotonic
    /// push.
    #[arg(long)]
    cyclic: bool,
    /// The cyclic amplitudes, drift %, growing (default: 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1,
    /// 1.5, 2, 2.5, 3, 4 … up to --drift-pct).
    #[arg(long, value_name = "PCT,PCT,...", value_delimiter = ',')]
    amplitudes_pct: Option<Vec<f64>>,
    /// A cyclic history replayed point by point: the drifts the actuator turns at, %, signed,
    /// in order (e.g. 0.1,-0.1,0.2,-0.2,0); implies --cyclic.
    #[arg(
        long,
        value_name = "PCT,PCT,...",
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with_all = ["amplitudes_pct", "replay"]
    )]
    reversals_pct: Option<Vec<f64>>,
    /// A measured curve file (`top_displacement, horizontal_force, drift` in mm, kN, %, four
    /// header lines, as the bundled data's `curves/FD_*.csv`) whose history is replayed: its
    /// drift column's turning points (a retreat of more than 0.02 % of drift from the running
    /// extreme turns it), in the file's order; implies --cyclic.
    #[arg(long, value_name = "FILE", conflicts_with = "amplitudes_pct")]
    replay: Option<PathBuf>,
    /// Cycles per amplitude (with --cyclic; default 2).
    #[arg(long)]
    cycles: Option<u32>,
    /// The loading beam's rotation: `free` (cantilever, the force at the shear span) or
    /// `fixed` (double-fixed).
    #[arg(long, value_enum, default_value = "free")]
    beam_rotation: Rotation,
    /// What holds the wall's blocks out of its plane in the penalty DEM: `held` (the plane
    /// model of the test: each block's translation across the wall and its rotations about
    /// x and z held) or `free` (a 3D run) [default: held]; not read by nscd or limit
    /// analysis, whose walls are 3D.
    #[arg(long, value_enum)]
    out_of_plane: Option<Plane>,
    /// Static solves per quarter cycle of a cyclic history, at most 1000 (with --cyclic;
    /// default 8).
    #[arg(long)]
    quarter_increments: Option<u32>,
    /// The imposed displacement's increment per static solve of a monotonic run (and its
    /// largest in a cyclic one), mm [default: 0.25] (the penalty DEM and nscd; not read by
    /// limit analysis).
    #[arg(long, value_name = "MM")]
    step_mm: Option<f64>,
    /// Unbalanced-force ratio of equilibrium of each static solve of the penalty DEM
    /// [default: 1e-4] (not read by nscd or limit analysis, which have no such solve).
    #[arg(long)]
    tolerance: Option<f64>,
    /// Sub-contact subdivisions of the penalty DEM's joints per fan-triangle edge, 1–64
    /// [default: 1] (`subcontact_subdivisions` of a study's `[solver]`; not read by nscd or
    /// limit analysis, which take a contact polygon's corners).
    #[arg(long, value_name = "M")]
    subdivisions: Option<u32>,
    #[command(flatten)]
    solver: SolverChoice,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Write the force–displacement curve as CSV (top_mm, drift_pct, force_kn, converged).
    #[arg(long, value_name = "FILE")]
    curve: Option<PathBuf>,
    /// Draw the mechanism over the wall (SVG; the moving joints red, the blocks moving with
    /// the beam shaded).
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
}

/// The most static solves a quarter cycle of `--quarter-increments` may ask: at the limit, the
/// default ladder of eleven amplitudes run twice is 88 000 solves, hours of a run; past it
/// the history (one displacement a solve, all held before the run) and the run grow without
/// a useful end (a million asked ran on, its memory growing).
pub use drystone::loading::inplane::MAX_QUARTER_INCREMENTS;

/// The turning points of the measured curve `file` (its drift column, %), checked to lie
/// within ±`drift_pct`.
///
/// # Errors
/// The file unreadable, a header that does not name the columns, a line that is not three
/// finite numbers (or a break of `NaN` in every column), each naming the file, the line and
/// the column (`study::inplane::read_envelope`, the reader of the study's measured curves);
/// no turning point, or a point past `drift_pct` (naming `--drift-pct`).
fn replayed(file: &std::path::Path, drift_pct: f64) -> Result<Vec<f64>> {
    let points = drystone::study::inplane::read_envelope(file)?;
    let drifts: Vec<f64> = points.iter().map(|p| p.0).collect();
    let turns =
        drystone::loading::inplane_loops::turning_points(&drifts, drystone::loading::inplane_loops::TURNING_NOISE_PCT);
    if turns.is_empty() {
        bail!("{}: no turning point: the drift column never leaves ±0.02 %", file.display());
    }
    let largest = turns.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if largest > drift_pct {
        bail!(
            "{}: the history reaches {largest} % of drift, past --drift-pct {drift_pct}: give --drift-pct {largest} or more",
            file.display()
        );
    }
    Ok(turns)
}

/// Refuses the options that the chosen solver's method does not read, each by name with what
/// to do (`--cyclic` and `--curve` with limit analysis are refused beside the history's own
/// checks): limit analysis gives the collapse load of the first direction from statics, with
/// no path (`--drift-pct`, `--step-mm`), no reading of a displacement
/// (`--measuring-height-m`) and no static solve (`--tolerance`, `--out-of-plane`); nscd has
/// no static solve (`--tolerance`) and runs its wall in 3D (`--out-of-plane`). The penalty
/// DEM reads every option.
///
/// # Errors
/// The first such option given, by name.
fn refuse_unread(a: &InPlaneArgs) -> Result<()> {
    use drystone::dem::Method;
    let kind = a.solver.solver;
    let method = kind.method();
    if a.cyclic && !method.draws_curves() {
        bail!("--cyclic is not read by {} (the collapse load of the first direction, no history): drop it, or choose another --solver", method.describe());
    }
    // The methods that read each option, as they declare it: a path of states (the methods
    // that draw curves), static solves to a tolerance (the penalty DEM's).
    let path: Vec<Method> = Method::ALL.into_iter().filter(|m| m.draws_curves()).collect();
    let statics: Vec<Method> = Method::ALL.into_iter().filter(|m| m.kind().is_penalty()).collect();
    for (flag, given, readers, what) in [
        ("--drift-pct", a.drift_pct.is_some(), &path, "the path's largest drift"),
        ("--step-mm", a.step_mm.is_some(), &path, "the path's increment"),
        ("--measuring-height-m", a.measuring_height_m.is_some(), &path, "where the curve's displacement is read"),
        (
            "--tolerance",
            a.tolerance.is_some(),
            &statics,
            "the equilibrium tolerance of the penalty DEM's static solves",
        ),
        (
            "--out-of-plane",
            a.out_of_plane.is_some(),
            &statics,
            "what holds the penalty DEM's blocks out of the wall's plane",
        ),
        ("--subdivisions", a.subdivisions.is_some(), &statics, "the density of the penalty DEM's sub-contacts"),
    ] {
        super::solver::only_with_methods(kind, readers, flag, given, what)?;
    }
    Ok(())
}

/// The beam's rotation on the command line.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Rotation {
    Free,
    Fixed,
}

/// What holds the blocks out of the wall's plane, on the command line.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Plane {
    Held,
    Free,
}

/// The test's parameters from the options, each checked and a wrong combination refused
/// naming its options.
///
/// # Errors
/// An option out of its range or given without the one it needs (named), a replayed file
/// that cannot be read.
fn params_of(a: &InPlaneArgs) -> Result<InPlaneParams> {
    let drift_pct = a.drift_pct.unwrap_or(InPlaneParams::default().drift_pct);
    let reversals_pct = match (&a.reversals_pct, &a.replay) {
        (Some(r), _) => Some(r.clone()),
        (None, Some(file)) => Some(replayed(file, drift_pct)?),
        (None, None) => None,
    };
    let cyclic = a.cyclic || reversals_pct.is_some();
    let params = InPlaneParams {
        sigma0_mpa: a.sigma0_mpa,
        shear_span_m: a.shear_span_m,
        drift_pct,
        history: if cyclic { History::Cyclic } else { History::Monotonic },
        amplitudes_pct: a.amplitudes_pct.clone(),
        reversals_pct,
        cycles: a.cycles.unwrap_or(InPlaneParams::default().cycles),
        beam_rotation: match a.beam_rotation {
            Rotation::Free => BeamRotation::Free,
            Rotation::Fixed => BeamRotation::Fixed,
        },
        out_of_plane: match a.out_of_plane {
            None | Some(Plane::Held) => OutOfPlane::Held,
            Some(Plane::Free) => OutOfPlane::Free,
        },
        step_mm: a.step_mm.unwrap_or(InPlaneParams::default().step_mm),
        quarter_increments: a.quarter_increments.unwrap_or(InPlaneParams::default().quarter_increments),
        measuring_height_m: a.measuring_height_m,
        mirror_reading: false,
    };
    if params.quarter_increments > MAX_QUARTER_INCREMENTS {
        bail!(
            "--quarter-increments = {} must be at most {MAX_QUARTER_INCREMENTS} (static solves per quarter cycle; the \
             default is {})",
            params.quarter_increments,
            InPlaneParams::default().quarter_increments
        );
    }
    if a.amplitudes_pct.is_some() && !a.cyclic {
        bail!("--amplitudes-pct gives the cycles' amplitudes: add --cyclic");
    }
    if a.cycles.is_some() && !cyclic {
        bail!("--cycles gives the cycles per amplitude of a cyclic history: add --cyclic");
    }
    if a.quarter_increments.is_some() && !cyclic {
        bail!("--quarter-increments gives the static solves per quarter cycle of a cyclic history: add --cyclic");
    }
    if a.shear_span_m.is_some() && matches!(a.beam_rotation, Rotation::Fixed) {
        bail!(
            "--shear-span-m is not read with --beam-rotation fixed (the beam held level has no shear span): drop one"
        );
    }
    params.validate().map_err(|e| anyhow::anyhow!("--{}", e.to_string().replace('_', "-")))?;
    Ok(params)
}

/// `drystone in-plane`.
///
/// # Errors
/// A bad option or layout (named), a refused solver, a run that fails, an output that
/// cannot be written.
pub fn command(a: InPlaneArgs) -> Result<ExitCode> {
    refuse_unread(&a)?;
    let params = params_of(&a)?;
    let cyclic = params.history == History::Cyclic;
    for p in [&a.curve, &a.svg].into_iter().flatten() {
        super::check_writable(p)?;
    }
    // A method that draws no path (limit analysis) reads no history and writes no curve.
    let method = a.solver.solver.method();
    if cyclic && !method.draws_curves() {
        bail!("--reversals-pct and --replay give a cyclic history, which {} does not read (the collapse load of the first direction, no history): drop it, or choose another --solver", method.describe());
    }
    if a.curve.is_some() && !method.draws_curves() {
        bail!("--curve writes the penalty DEM's force-displacement curve; {} has none", method.describe());
    }
    let l = super::read_layout(&a.layout)?;
    let kind = a.solver.solver;
    let penalty = PenaltyParams {
        tolerance: a.tolerance.unwrap_or(PenaltyParams::default().tolerance),
        ..PenaltyParams::default()
    };
    let subcontact_subdivisions = a.subdivisions.unwrap_or(SolverParams::default().subcontact_subdivisions);
    if !(1..=64).contains(&subcontact_subdivisions) {
        bail!("--subdivisions {subcontact_subdivisions} is out of range: an integer in [1, 64]");
    }
    let solver = SolverParams {
        kind,
        penalty,
        limit: LimitParams::default(),
        subcontact_subdivisions,
        ..SolverParams::default()
    };
    let unsupported = |e: Unsupported| anyhow::anyhow!("{e}; on the command line: --solver NAME");
    let mut observe = States(|_: f64, _: bool, _: &drystone::dem::Simulation| {});
    let run = drystone::protocol::run(&InPlane(params.clone()), &l, solver, &mut observe).map_err(unsupported)?;
    let what = || format!("in-plane test of {}", a.layout.display());
    // The method that ran, by its name and its phrase ("penalty DEM" in the table's title).
    let (method, engine) = (run.method().name(), run.method().describe().trim_start_matches("the "));
    match run {
        InPlaneRun::Penalty(r) | InPlaneRun::Nscd(r) => {
            let r = r.with_context(what)?;
            if let Some(p) = &a.curve {
                write_curve(p, &r)?;
            }
            if let Some(p) = &a.svg {
                let rig = Rig::build(&l, &params)?;
                let sim = drystone::dem::Simulation::new(&rig.layout, solver);
                let joints = mechanism_joints(&sim);
                let title = format!(
                    "{}: {} at drift {:.2} %",
                    a.layout.display(),
                    r.mechanism.kind.name(),
                    r.positive.map_or(0.0, |d| d.ultimate_drift_pct.max(d.drift_at_peak_pct))
                );
                let svg = crack_map_svg(&rig.layout, &r.poses_at_reading, &joints, &r.mechanism, &title);
                drystone::io::replace_file(p, svg.as_bytes())?;
            }
            if !r.shed_block.is_empty() {
                eprintln!(
                    "warning: block {} was shed from the wall (its excursion from its course passed a quarter of \
                     its smallest extent): the increments from then on are counted unconverged and the \
                     readings are no whole wall's",
                    r.shed_block
                );
            }
            if a.json {
                let mut j = penalty_json(&r, method, params.beam_rotation);
                // The solver chosen, where it names more than the method (`newton`,
                // `implicit`, … are the penalty DEM with one static solve).
                j["solver"] = json!(kind.name());
                j["out_of_plane"] = json!(params.out_of_plane.name());
                out!("{}", serde_json::to_string_pretty(&j)?);
            } else {
                let engine = if kind.names_cascade() {
                    format!("{engine}, --solver {}", kind.name())
                } else {
                    engine.to_string()
                };
                print_penalty(&a.layout, &params, &r, &engine);
            }
        }
        InPlaneRun::Limit(r) => {
            let r = r.with_context(what)?;
            if let Some(p) = &a.svg {
                let rig = Rig::build(&l, &params)?;
                let sim = drystone::dem::Simulation::new(&rig.layout, solver);
                let joints = mechanism_joints(&sim);
                // The mechanism at a virtual displacement of 2 % of the wall's height.
                let k = 0.02 * rig.height_m / r.limit.velocities[rig.beam].translation.x.abs().max(1e-300);
                let poses: Vec<_> = sim
                    .state
                    .bodies
                    .iter()
                    .zip(&r.limit.velocities)
                    .map(|(b, v)| (b.pos + v.translation * k, v.rotation * k))
                    .collect();
                let title = format!("{}: limit analysis, {}", a.layout.display(), r.mechanism.kind.name());
                let svg = crack_map_svg(&rig.layout, &poses, &joints, &r.mechanism, &title);
                drystone::io::replace_file(p, svg.as_bytes())?;
            }
            if a.json {
                out!("{}", serde_json::to_string_pretty(&limit_json(&r, params.beam_rotation))?);
            } else {
                print_limit(&a.layout, &r, params.beam_rotation);
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn dir_json(d: &Option<DirectionResult>) -> serde_json::Value {
    match d {
        Some(d) => json!({
            "peak_force_kn": d.peak_force_kn,
            "drift_at_peak_pct": d.drift_at_peak_pct,
            "ultimate_drift_pct": d.ultimate_drift_pct,
            "ultimate_by_drop": d.dropped,
            "initial_stiffness_kn_per_mm": d.initial_stiffness_kn_per_mm,
            "force_at_drift_kn": READING_DRIFTS_PCT
                .iter()
                .zip(d.force_at_drift_kn)
                .map(|(d, f)| json!({ "drift_pct": d, "force_kn": f }))
                .collect::<Vec<_>>(),
            "drift_at_80_pct_of_peak": d.drift_at_80_pct,
            "drift_at_95_pct_of_peak": d.drift_at_95_pct,
            "plateau_slope_kn_per_pct": d.plateau_slope_kn_per_pct,
        }),
        None => serde_json::Value::Null,
    }
}

/// What the JSON's `shear_span_m` is (its `shear_span_definition`).
const SHEAR_SPAN_DEFINITION: &str = "the height above the base at which the horizontal force acts, m, with the beam's \
     rotation free (cantilever); null with the beam held level (beam_rotation fixed: double curvature), which has no \
     shear span";

/// The shear span the report gives for the beam's `rotation`: `h0` (m) with it free, none
/// with it held level (the force's height is then not read: the beam's held rotation sets the
/// moment, and the rig's anchor is only where the constraint acts).
fn shear_span(rotation: BeamRotation, h0: f64) -> Option<f64> {
    match rotation {
        BeamRotation::Free => Some(h0),
        BeamRotation::Fixed => None,
    }
}

/// The report's words for the beam's `rotation`: its name, the shear span's text and the
/// rigid rocking capacity's formula.
fn rotation_words(rotation: BeamRotation, h0: f64) -> (&'static str, String, &'static str) {
    match rotation {
        BeamRotation::Free => ("free", format!("H0 {h0:.3} m"), "N_total L / (2 H0)"),
        BeamRotation::Fixed => ("fixed", "beam held level: no shear span".into(), "(N L + W L / 2) / H"),
    }
}

/// The JSON of a curve (the penalty DEM's or nscd's, `method`): the positive direction's
/// outputs at the top level, then both directions, the mechanism, the forces and the curve;
/// the shear span only with the beam's `rotation` free.
fn penalty_json(r: &InPlaneResult, method: &str, rotation: BeamRotation) -> serde_json::Value {
    let p = r.positive;
    let (rotation_name, _, rocking) = rotation_words(rotation, r.shear_span_m);
    json!({
        "method": method,
        "peak_force_kn": p.map(|d| d.peak_force_kn),
        "drift_at_peak_pct": p.map(|d| d.drift_at_peak_pct),
        "ultimate_drift_pct": p.map(|d| d.ultimate_drift_pct),
        "initial_stiffness_kn_per_mm": p.map(|d| d.initial_stiffness_kn_per_mm),
        "mechanism": r.mechanism.kind.name(),
        "failure_type": r.mechanism.kind.failure_type(),
        "positive": dir_json(&r.positive),
        "negative": dir_json(&r.negative),
        "mechanism_detail": r.mechanism,
        "vertical_force_kn": r.vertical_force_kn,
        "n_total_kn": r.n_total_kn,
        "rocking_force_kn": r.rocking_force_kn,
        "rocking_force_definition": format!("rigid rocking capacity of the monolithic wall, {rocking}"),
        "beam_rotation": rotation_name,
        "shear_span_m": shear_span(rotation, r.shear_span_m),
        "shear_span_definition": SHEAR_SPAN_DEFINITION,
        "measuring_height_m": r.measuring_height_m,
        "drift_definition": "displacement at the measuring point over its height",
        "wall_vertical_modulus_mpa": r.wall_vertical_modulus_mpa,
        "largest_block_excursion_mm": r.largest_block_excursion_mm,
        "excursion_block": r.excursion_block,
        "shed_block": r.shed_block,
        "course_widening_mm": r.course_widening_mm,
        "widened_course": r.widened_course,
        "length_m": r.length_m,
        "height_m": r.height_m,
        "thickness_m": r.thickness_m,
        "unconverged_increments": r.unconverged,
        "retried_increments": r.retried,
        "newton_handed_over": r.newton_handed_over,
        "increments": r.curve.len() - 1,
        "steps": r.steps,
        "dt_s": r.dt_s,
        "wall_time_s": r.wall_time_s,
        "curve": r.curve,
    })
}

/// The JSON of limit analysis's answer; the shear span only with the beam's `rotation` free.
fn limit_json(r: &InPlaneLimit, rotation: BeamRotation) -> serde_json::Value {
    let (rotation_name, _, rocking) = rotation_words(rotation, r.shear_span_m);
    json!({
        "method": "limit",
        "peak_force_kn": r.peak_force_kn,
        "drift_at_peak_pct": null,
        "initial_stiffness_kn_per_mm": null,
        "mechanism": r.mechanism.kind.name(),
        "failure_type": r.mechanism.kind.failure_type(),
        "load_multiplier": r.limit.load_multiplier,
        "governing": r.limit.governing,
        "mechanism_detail": r.mechanism,
        "vertical_force_kn": r.vertical_force_kn,
        "n_total_kn": r.n_total_kn,
        "rocking_force_kn": r.rocking_force_kn,
        "rocking_force_definition": format!("rigid rocking capacity of the monolithic wall, {rocking}"),
        "beam_rotation": rotation_name,
        "shear_span_m": shear_span(rotation, r.shear_span_m),
        "shear_span_definition": SHEAR_SPAN_DEFINITION,
        "wall_time_s": r.limit.wall_time_s,
    })
}

fn print_penalty(layout: &Path, params: &InPlaneParams, r: &InPlaneResult, engine: &str) {
    let (_, span, rocking) = rotation_words(params.beam_rotation, r.shear_span_m);
    out!("in-plane test of {} ({engine})", layout.display());
    out!(
        "  wall {:.3} x {:.3} x {:.3} m (L x H x t); sigma0 {} MPa: N {:.1} kN, N_total {:.1} kN; {span}",
        r.length_m,
        r.height_m,
        r.thickness_m,
        params.sigma0_mpa,
        r.vertical_force_kn,
        r.n_total_kn,
    );
    for (name, d) in [("positive", r.positive), ("negative", r.negative)] {
        if let Some(d) = d {
            out!(
                "  {name}: peak {:.2} kN at drift {:.2} %; ultimate drift {:.2} %{}; initial stiffness {}",
                d.peak_force_kn,
                d.drift_at_peak_pct,
                d.ultimate_drift_pct,
                if d.dropped { " (20 % drop)" } else { " (largest drift run)" },
                if d.initial_stiffness_kn_per_mm.is_nan() {
                    "none (rigid joints)".to_string()
                } else {
                    format!("{:.2} kN/mm", d.initial_stiffness_kn_per_mm)
                }
            );
        }
    }
    out!(
        "  mechanism: {} (opening share {:.2}, crack {}, {} joints, {} blocks move with the beam)",
        r.mechanism.kind.name(),
        r.mechanism.opening_share,
        r.mechanism.crack,
        r.mechanism.joints.len(),
        r.mechanism.moving_blocks.len()
    );
    out!("  rigid rocking capacity {rocking}: {:.2} kN", r.rocking_force_kn);
    out!(
        "  displacement read at {:.3} m (drift = displacement / {:.3} m); wall's vertical modulus {:.0} MPa; largest \
         block excursion from its course {:.2} mm{}",
        r.measuring_height_m,
        r.measuring_height_m,
        r.wall_vertical_modulus_mpa,
        r.largest_block_excursion_mm,
        if r.excursion_block.is_empty() { String::new() } else { format!(" ({})", r.excursion_block) }
    );
    if let Some(c) = r.widened_course {
        out!(
            "  widest course at the history's end: course {c}, {:.2} mm wider than under the vertical force",
            r.course_widening_mm
        );
    }
    out!(
        "  {} increments, {} unconverged{}; {} steps, dt {:.2e} s; {:.2} s",
        r.curve.len() - 1,
        r.unconverged,
        r.newton_handed_over.map_or(String::new(), |n| format!(", {n} handed over by the Newton solve to relaxation")),
        r.steps,
        r.dt_s,
        r.wall_time_s
    );
}

fn print_limit(layout: &Path, r: &InPlaneLimit, rotation: BeamRotation) {
    let (_, span, rocking) = rotation_words(rotation, r.shear_span_m);
    out!("in-plane test of {} (limit analysis)", layout.display());
    out!(
        "  peak horizontal force {:.2} kN (lambda = V / N_total = {:.4}, {:?} flow rule); N_total {:.1} kN; {span}",
        r.peak_force_kn,
        r.limit.load_multiplier,
        r.limit.governing,
        r.n_total_kn,
    );
    out!(
        "  mechanism: {} (opening share {:.2}, crack {}, {} joints)",
        r.mechanism.kind.name(),
        r.mechanism.opening_share,
        r.mechanism.crack,
        r.mechanism.joints.len()
    );
    out!("  rigid rocking capacity {rocking}: {:.2} kN", r.rocking_force_kn);
}

fn write_curve(path: &Path, r: &InPlaneResult) -> Result<()> {
    let mut s = String::from("top_mm,drift_pct,force_kn,converged\n");
    for p in &r.curve {
        s.push_str(&format!("{},{},{},{}\n", p.top_mm, p.drift_pct, p.force_kn, p.converged));
    }
    drystone::io::replace_file(path, s.as_bytes()).with_context(|| format!("curve {}", path.display()))?;
    Ok(())
}
