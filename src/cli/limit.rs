//! `drystone limit`: limit analysis of a layout file (the rigid collapse load multiplier
//! from statics alone).

use anyhow::{Context, Result};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use drystone::dem::{Method, SolverKind, SolverParams};
use drystone::io::mechanism::{mechanism_svg, MechanismFigure};
use drystone::layout::Layout;
use drystone::limit::{FlowRule, LimitParams, LimitResult};
use drystone::loading::lateral::LateralParams;
use drystone::protocol::{supports, Protocol, ProtocolKind, ProtocolRun, RunOutcome, Unsupported};
use drystone::Vec3;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `--protocol NAME` of `drystone limit`: the protocols of the registry
/// ([`ProtocolKind`]) that limit analysis runs by the compatibility table
/// ([`drystone::protocol::methods`]), `tilt` and `lateral`, each described in `--help` as
/// the protocol its study-file name runs.
fn limit_protocol() -> impl TypedValueParser<Value = ProtocolKind> {
    let runs = |k: &ProtocolKind| k.loadings().iter().any(|&l| supports(l, Method::Limit));
    let values = ProtocolKind::ALL.into_iter().filter(runs).map(|k| {
        let what = k.loadings().first().map_or("", |l| l.describe());
        PossibleValue::new(k.name()).help(what)
    });
    PossibleValuesParser::new(values).try_map(|name| name.parse::<ProtocolKind>())
}

/// Options of `drystone limit`.
#[derive(clap::Args)]
pub struct LimitArgs {
    /// Layout file (JSON).
    layout: PathBuf,
    /// The live load: `tilt`, the tilting table's weight along +y (λ = tan α_max), or
    /// `lateral`, the lateral pressure of `drystone lateral` (λ multiplies it).
    #[arg(long, value_parser = limit_protocol(), default_value = "tilt")]
    protocol: ProtocolKind,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    // The lateral pressure (`--protocol lateral`).
    #[command(flatten)]
    pressure: super::solver::Pressure,
    /// The associative answer only (no non-associative correction); the same as
    /// --limit-associative.
    #[arg(long)]
    associative: bool,
    #[command(flatten)]
    limit: super::solver::LimitFlags,
    /// Draw the collapse mechanism into this SVG file.
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
}

/// Runs the analysis and prints a table, or one JSON object with `json`; with `svg`, draws
/// the mechanism there as the DEM's mechanism figure is drawn.
pub fn run(a: &LimitArgs) -> Result<ExitCode> {
    let mut limit = a.limit.apply(LimitParams::default());
    limit.non_associative &= !a.associative;
    let solver = SolverParams { kind: SolverKind::Limit, limit, ..SolverParams::default() };
    let l = super::read_layout(&a.layout)?;
    // The protocol by limit analysis, through the protocol seam.
    let lateral = a.pressure.apply(LateralParams::default());
    // A kind without a live load is not offered by `--protocol`.
    let protocol = Protocol::live_load(a.protocol, lateral)
        .ok_or(Unsupported { protocol: a.protocol.loadings()[0], kind: SolverKind::Limit })?;
    let run = protocol.run(&l, solver);
    if let ProtocolRun::Unsupported(e) = run {
        return Err(e.into());
    }
    let run = run.limit().cloned();
    let r = run.context("the seam ran another method than limit analysis")?;
    let r = r.with_context(|| format!("limit analysis of {}", a.layout.display()))?;
    report(&a.layout, &l, &r, a.json, a.svg.as_deref())
}

/// Prints the limit analysis `r` of the layout `l` (read from `layout`) as `drystone limit`
/// prints it: a table, or one JSON object with `json`; with `svg_path`, the mechanism drawn
/// there.
///
/// # Errors
/// The SVG file that could not be written.
pub fn report(layout: &Path, l: &Layout, r: &LimitResult, json: bool, svg_path: Option<&Path>) -> Result<ExitCode> {
    if let Some(path) = svg_path {
        drystone::files::replace_file(path, svg(l, r, layout).as_bytes())?;
        eprintln!("mechanism drawing: {}", path.display());
    }
    if json {
        out!("{}", serde_json::to_string_pretty(r)?);
    } else {
        print(layout, r);
    }
    Ok(ExitCode::SUCCESS)
}

/// The mechanism drawn on the layout: each block moved by its virtual velocity (the
/// figure magnifies the motion itself).
fn svg(l: &Layout, r: &LimitResult, path: &Path) -> String {
    let h = l.bounds().extent().z;
    let scale = 0.05 * h;
    let poses: Vec<(Vec3, nalgebra::UnitQuaternion<f64>)> = l
        .blocks
        .iter()
        .zip(&r.velocities)
        .map(|(b, v)| {
            let c = b.centroid();
            (c + v.translation * scale, nalgebra::UnitQuaternion::from_scaled_axis(v.rotation * scale))
        })
        .collect();
    let disp: Vec<f64> = r.velocities.iter().map(|v| v.translation.norm() * scale).collect();
    let moving: Vec<bool> = l.blocks.iter().map(|b| r.mechanism.blocks.contains(&b.id)).collect();
    let title = format!("limit analysis of {}", path.display());
    let subtitle = match r.collapse_angle_deg {
        Some(a) => format!("lambda = {:.4}, alpha_max = {a:.3} deg ({})", r.load_multiplier, flow_name(r.governing)),
        None => format!("lambda = {:.4} ({})", r.load_multiplier, flow_name(r.governing)),
    };
    mechanism_svg(&MechanismFigure {
        layout: l,
        poses: &poses,
        displacement_m: &disp,
        moving: &moving,
        joint: &r.mechanism.joint,
        title: &title,
        subtitle: &subtitle,
    })
}

fn flow_name(f: FlowRule) -> &'static str {
    match f {
        FlowRule::Associative => "associative",
        FlowRule::NonAssociative => "non-associative",
    }
}

fn print(layout: &Path, r: &LimitResult) {
    out!("layout            {}", layout.display());
    out!("load multiplier   {:.6} ({})", r.load_multiplier, flow_name(r.governing));
    if let Some(a) = r.collapse_angle_deg {
        out!("collapse angle    {a:.4} deg (atan of the multiplier)");
    }
    out!("associative       {:.6}", r.associative);
    if let Some(na) = &r.non_associative {
        out!(
            "non-associative   {:.6} ({} iterations, {})",
            na.load_multiplier,
            na.iterations,
            if na.converged { "converged" } else { "not converged: the associative value is an upper estimate" }
        );
    }
    out!(
        "mechanism         {:?} at joint {} ({} blocks moving)",
        r.mechanism.kind,
        r.mechanism.joint,
        r.mechanism.blocks.len()
    );
    for j in &r.joints {
        out!("  {:<24} {:?} at z {:.3} m (opening {:.3}, slip {:.3})", j.joint, j.mode, j.z_m, j.opening, j.slip);
    }
    out!(
        "program           {} blocks, {} contacts, {} contact points; {} ({} iterations); wall time {:.1} ms",
        r.blocks,
        r.contacts,
        r.contact_points,
        r.status,
        r.solver_iterations,
        r.wall_time_s * 1e3
    );
}
