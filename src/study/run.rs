//! Running a study: one realization per work item, in parallel, into rows.
//!
//! The items are scheduled longest first, by the block count estimated from their wall
//! description ([`super::size::estimated_blocks`]); each item generates its layout once,
//! when it runs, and drops it with its result. Memory thus holds the layouts of the items
//! running, not those of the whole ensemble.
//!
//! [`run_study_with`] hands each finished row to a sink (the journal of the run) as soon as
//! it is computed, and takes the rows of items already finished (read back from the
//! journal), which it does not run again. Every row being a pure function of the study and
//! its item, the rows are the same whichever items were done before.

use super::{point_label, Study, SweepKey};
use crate::ensemble::row::{CollapseColumns, RealizationRow, ShakeColumns, Status};
use crate::ensemble::{self, Item, Shard};
use crate::layout::Layout;
use crate::loading::lateral::LateralResult;
use crate::loading::monitors::TopMonitor;
use crate::loading::shake::ShakeResult;
use crate::loading::tilt::{CollapseReason, Mechanism, MechanismKind, TiltResult};
use crate::units::m_to_cm;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Scheduling cost of an item: the block count estimated from its wall description (the
/// DEM run grows with it), without generating the layout; 0 where no finite estimate exists.
fn cost(study: &Study, item: &Item) -> f64 {
    let n = super::size::estimated_blocks(&study.groups[item.group].walls[item.point]);
    if n.is_finite() {
        n
    } else {
        0.0
    }
}

/// Runs one realization of a study: generate the layout of its group and sweep point from
/// `(seed, realization)`, apply the group's effects, run the protocol, and record the
/// outcome. Never panics on a bad
/// realization: failures become rows with their [`Status`]. The wall time includes the
/// generation of the layout.
pub fn run_item(study: &Study, item: &Item) -> RealizationRow {
    let t0 = Instant::now();
    let base = empty_row(study, item);
    let row = match realize_item(study, item) {
        Err(e) => RealizationRow::failed(base, Status::LayoutFailed, e.to_string()),
        Ok(layout) => {
            let row = RealizationRow { blocks: layout.blocks.len() as u64, ..base };
            let run = study.protocol_of(item.group, item.point).run(&layout, study.solver);
            study.protocol.row(study, item, &layout, row, run)
        }
    };
    finish(row, t0)
}

/// The layout of an item: its group's wall at its sweep point generated with the master
/// seed `study.seed` and the item's seed index ([`super::StudyProtocol::seed_index`]: its
/// realization, or the in-plane test's `g · 10000 + i`), with the group's effects applied
/// ([`crate::effects::realize`]). The one layout every run of the item is made of: its row
/// ([`run_item`]), its mechanism figure and its ParaView series (`study::figures`).
///
/// # Errors
/// Why the layout cannot be generated, checked or given its effects.
pub(super) fn realize_item(study: &Study, item: &Item) -> Result<Layout, crate::effects::EffectError> {
    let group = &study.groups[item.group];
    let wall = &group.walls[item.point];
    let index = study.protocol.seed_index(item);
    crate::effects::realize(wall, study.seed, index, &group.name, &group.effects).map(|(_, layout)| layout)
}

/// The row with its wall time since `t0`.
fn finish(mut row: RealizationRow, t0: Instant) -> RealizationRow {
    row.wall_time_s = t0.elapsed().as_secs_f64();
    row
}

/// A realization of the tilting table by limit analysis (`[solver] kind = "limit"`): the
/// collapse angle α_max = atan λ (its bracket of zero width, reason `no_equilibrium`: no
/// statically admissible state exists above it), the mechanism columns from the dual. A
/// wall that does not stand (λ ≤ 0, [`crate::limit::LimitError::DoesNotStand`]) is a
/// `no_initial_equilibrium` row with the message ([`failed_row`]), as the tilting table's
/// rows are.
pub(super) fn limit_tilt_row(mut row: RealizationRow, r: crate::limit::LimitResult) -> RealizationRow {
    mechanism_columns(&mut row.collapse, &r.mechanism);
    row.iterations = u64::from(r.solver_iterations);
    row.status = Status::Collapsed;
    row.collapse.collapse_angle_deg = r.collapse_angle_deg;
    row.collapse.first_unstable_deg = r.collapse_angle_deg;
    row.collapse.collapse_reason = CollapseReason::NoEquilibrium.name().to_string();
    row
}

/// A realization of the lateral load by limit analysis: whether the wall carries the
/// pressure (λ ≥ 1: stood; rigid blocks have no displacements) or not (collapsed, with λ
/// in the error column), and λ in `load_multiplier_limit` for a `pushover`; the mechanism
/// columns from the dual. A wall that does not stand is a failed row as in
/// [`limit_tilt_row`].
pub(super) fn limit_lateral_row(
    mut row: RealizationRow,
    r: crate::limit::LimitResult,
    pushover: bool,
) -> RealizationRow {
    mechanism_columns(&mut row.collapse, &r.mechanism);
    row.iterations = u64::from(r.solver_iterations);
    if pushover {
        row.pushover.load_multiplier_limit = Some(r.load_multiplier);
    }
    if r.load_multiplier >= 1.0 {
        row.status = Status::Stood;
    } else {
        row.status = Status::Collapsed;
        row.collapse.collapse_reason = CollapseReason::NoEquilibrium.name().to_string();
        row.error =
            format!("the pressure is {:.3} times the rigid collapse load (load multiplier λ)", 1.0 / r.load_multiplier);
    }
    row
}

/// The pushover's load multipliers into a row already holding its service load: λ of the
/// penalty DEM (stable, first unstable, the reason and mechanism of its collapse) and λ of
/// limit analysis; an error of either is appended to the error column.
pub(super) fn pushover_row(
    mut row: RealizationRow,
    collapse: Option<(
        Result<crate::loading::lateral_pushover::LateralPushover, crate::loading::lateral::LateralError>,
        Result<crate::limit::LimitResult, crate::limit::LimitError>,
    )>,
) -> RealizationRow {
    let Some((dem, limit)) = collapse else { return row };
    let mut errors = Vec::new();
    match dem {
        Ok(p) => {
            row.pushover.load_multiplier_dem = Some(p.lambda_stable);
            row.pushover.load_multiplier_dem_unstable = p.lambda_unstable;
            row.collapse.collapse_reason = p.collapse_reason.map(CollapseReason::name).unwrap_or_default().to_string();
            if let Some(m) = &p.mechanism {
                mechanism_columns(&mut row.collapse, m);
            }
        }
        Err(e) => errors.push(format!("DEM pushover: {e}")),
    }
    match limit {
        Ok(r) => row.pushover.load_multiplier_limit = Some(r.load_multiplier),
        Err(e) => errors.push(format!("limit analysis: {e}")),
    }
    if !errors.is_empty() {
        let sep = if row.error.is_empty() { "" } else { "; " };
        row.error = format!("{}{sep}{}", row.error, errors.join("; "));
    }
    row
}

/// The rigid pushover (nscd) into a row: λ stable and first unstable in the DEM
/// pushover's columns (a non-smooth DEM of rigid blocks), the mechanism, and the status of
/// the service load: stood if λ ≥ 1 (rigid blocks have no displacements), else collapsed.
pub(super) fn nscd_pushover_row(
    mut row: RealizationRow,
    r: crate::loading::lateral_nscd::LateralLimit,
) -> RealizationRow {
    row.pushover.load_multiplier_dem = Some(r.lambda_stable);
    row.pushover.load_multiplier_dem_unstable = r.lambda_unstable;
    if let Some(m) = &r.mechanism {
        mechanism_columns(&mut row.collapse, m);
    }
    row.steps = r.steps;
    if r.lambda_stable >= 1.0 {
        row.status = Status::Stood;
    } else {
        row.status = Status::Collapsed;
        row.collapse.collapse_reason = CollapseReason::NoEquilibrium.name().to_string();
        row.error = format!(
            "the pressure is above the rigid collapse load: load multiplier λ {:.4} (by nscd)",
            r.lambda_stable
        );
    }
    row
}

/// Runs the items of a shard of a study in parallel on the current rayon pool; rows in item
/// order.
///
/// Items are scheduled longest first, by the estimated number of blocks of their layout, so
/// that the expensive walls do not run last on one thread while the others idle.
///
/// ```
/// use drystone::ensemble::Shard;
/// use drystone::study::{run_study, Study};
///
/// // Three realizations of the source paper's CBL wall on the tilting table.
/// let walls = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls");
/// let dir = std::env::temp_dir().join(format!("drystone-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let text = format!(
///     "version = 1\nname = \"cbl3\"\nseed = 1\nrealizations = 3\nprotocol = \"tilt\"\n\
///      [[groups]]\nname = \"CBL\"\nwall = {:?}\n",
///     walls.join("cbl.toml")
/// );
/// std::fs::write(dir.join("cbl3.toml"), text)?;
/// let study = Study::from_file(&dir.join("cbl3.toml"))?;
/// let rows = run_study(&study, Shard::ALL);
/// assert_eq!(rows.len(), 3);
/// for r in &rows {
///     // Every realization collapses below the overturning of the section as one rigid
///     // monolith about its toe: tan α = (B/2) / z_c = 0.075 / 0.1674, 24.1° (the paper
///     // measured 18.5–19°).
///     let a = r.collapse.collapse_angle_deg.expect("collapsed");
///     assert!(a > 10.0 && a < 24.1, "{a}");
/// }
/// // The same rows bit for bit on another run (any thread count; `tests/suite/determinism.rs`).
/// let again = run_study(&study, Shard::ALL);
/// assert!(rows.iter().zip(&again).all(|(a, b)| a.collapse.collapse_angle_deg == b.collapse.collapse_angle_deg));
/// # std::fs::remove_dir_all(&dir).ok();
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_study(study: &Study, shard: Shard) -> Vec<RealizationRow> {
    let never = |_: &RealizationRow| Ok::<(), std::convert::Infallible>(());
    match run_study_with(study, shard, Vec::new(), never) {
        Ok(rows) => rows,
        Err(e) => match e {},
    }
}

/// As [`run_study`], with the rows of the items already finished (`done`, any order; they
/// are not run again) and a `sink` that receives every new row as soon as it is computed,
/// from the worker thread that computed it. Returns every row of the shard in item order.
///
/// # Errors
/// The first error of the sink (in item order); no item starts after the sink failed.
pub fn run_study_with<E: Send>(
    study: &Study,
    shard: Shard,
    done: Vec<RealizationRow>,
    sink: impl Fn(&RealizationRow) -> Result<(), E> + Sync,
) -> Result<Vec<RealizationRow>, E> {
    let finished: std::collections::BTreeSet<u64> = done.iter().map(|r| r.index).collect();
    let items: Vec<Item> =
        shard.select(&study.items()).into_iter().filter(|it| !finished.contains(&(it.index as u64))).collect();
    let costs: Vec<f64> = items.iter().map(|it| cost(study, it)).collect();
    let failed = AtomicBool::new(false);
    let results = ensemble::run_scheduled(&items, &costs, &study.name, |it| {
        if failed.load(Ordering::SeqCst) {
            return None;
        }
        let row = run_item(study, it);
        match sink(&row) {
            Ok(()) => Some(Ok(row)),
            Err(e) => {
                failed.store(true, Ordering::SeqCst);
                Some(Err(e))
            }
        }
    });
    let mut rows = done;
    for r in results.into_iter().flatten() {
        rows.push(r?);
    }
    rows.sort_by_key(|r| r.index);
    Ok(rows)
}

/// The row of an item before its run: identification, no results.
fn empty_row(study: &Study, item: &Item) -> RealizationRow {
    let group = &study.groups[item.group];
    RealizationRow {
        index: item.index as u64,
        study: study.name.clone(),
        group: group.name.clone(),
        point: item.point as u64,
        sweep: point_label(&study.points[item.point]),
        seed: study.seed,
        realization: item.realization,
        shake: ShakeColumns {
            motion: study.points[item.point]
                .iter()
                .find(|(k, _)| *k == SweepKey::Motion)
                .map(|(_, v)| v.to_string())
                .unwrap_or_default(),
            pga_g: study.sweep_number(item.point, SweepKey::PgaG),
            ..ShakeColumns::default()
        },
        ..RealizationRow::default()
    }
}

/// The name of a mechanism in the `mechanism` column.
fn mechanism_name(k: MechanismKind) -> &'static str {
    match k {
        MechanismKind::Sliding => "sliding",
        MechanismKind::Toppling => "toppling",
        MechanismKind::Mixed => "mixed",
        MechanismKind::None => "none",
    }
}

/// A collapse mechanism (the tilting table's or the limit analysis's) into the collapse
/// columns: its kind, governing joint, moving blocks and, where read, how a person would
/// describe it.
fn mechanism_columns(c: &mut CollapseColumns, m: &Mechanism) {
    c.mechanism = mechanism_name(m.kind).to_string();
    c.joint = m.joint.clone();
    c.moving_blocks = m.blocks.len() as u64;
    if let Some(r) = &m.reading {
        (c.failure_height_fraction, c.mechanism_extent) = (Some(r.failure_height_fraction), Some(r.extent_fraction));
        (c.mechanism_kind, c.mechanism_start) = (r.kind.name().to_string(), r.start.name().to_string());
    }
}

/// The row of a protocol that failed, its status `status` ([`Status::of_failure`]: the
/// layout did not stand as given, the protocol refused its parameters, or the run blew up),
/// with the message.
pub(super) fn failed_row(mut row: RealizationRow, status: Status, e: &dyn std::fmt::Display) -> RealizationRow {
    row.status = status;
    row.error = e.to_string();
    row
}

/// A tilting-table outcome into the row.
pub(super) fn tilt_row(mut row: RealizationRow, t: TiltResult) -> RealizationRow {
    row.status = if t.first_unstable_deg.is_some() { Status::Collapsed } else { Status::Stood };
    row.collapse.collapse_angle_deg = t.first_unstable_deg.map(|_| t.collapse_angle_deg());
    row.collapse.first_unstable_deg = t.first_unstable_deg;
    row.collapse.collapse_reason = t.collapse_reason.map(CollapseReason::name).unwrap_or_default().to_string();
    mechanism_columns(&mut row.collapse, &t.mechanism);
    let [il, ic, ir] = TopMonitor::ALL.map(|m| m.index_in(&t.monitors));
    for inc in t.increments.iter().filter(|i| i.stable) {
        row.tilt.tilt_deg.push(inc.alpha_deg);
        let get = |i: Option<usize>| i.map_or(f64::NAN, |i| m_to_cm(inc.displacement_m[i]));
        row.tilt.disp_top_left_cm.push(get(il));
        row.tilt.disp_top_centre_cm.push(get(ic));
        row.tilt.disp_top_right_cm.push(get(ir));
    }
    row.steps = t.steps;
    row.iterations = t.iterations;
    row.dt_s = t.dt_s;
    row
}

/// A shaking-table outcome into the row: `collapsed` if a block fell, else `stood`; the
/// motion's name and its PGA level (`level`, the point's `pga_g` exactly; the motion's own
/// PGA otherwise), the collapse time, the largest rocking rotation, the drifts and the
/// fallen blocks.
pub(super) fn shake_row(mut row: RealizationRow, r: ShakeResult, level: Option<f64>) -> RealizationRow {
    row.status = if r.overturned { Status::Collapsed } else { Status::Stood };
    // The non-smooth solver's count of steps above its natural-map tolerance; the penalty
    // DEM's explicit steps have none to count.
    let nscd = r.solver.method().solves_steps_to_a_tolerance();
    row.shake = ShakeColumns {
        motion: r.motion,
        pga_g: Some(level.unwrap_or(r.pga_g)),
        collapse_time_s: r.collapse_time_s,
        max_rotation_deg: Some(r.max_rotation_deg),
        max_drift: Some(r.max_drift),
        residual_drift: Some(r.residual_drift),
        blocks_fallen: Some(r.blocks_fallen as u64),
        unconverged_steps: nscd.then_some(r.unconverged_steps),
        max_natural_residual: nscd.then_some(r.max_natural_residual),
    };
    row.steps = r.steps;
    row.iterations = r.iterations;
    row.dt_s = r.dt_s;
    row
}

/// A static lateral load outcome into the row.
pub(super) fn lateral_row(mut row: RealizationRow, r: LateralResult) -> RealizationRow {
    row.steps = r.steps;
    row.dt_s = r.dt_s;
    match &r.collapse_reason {
        None => {
            row.status = Status::Stood;
            let [l, c, rt] = TopMonitor::ALL.map(|m| m.index_in(&r.monitors).map(|i| m_to_cm(r.displacement_m[i])));
            (row.lateral.lateral_disp_left_cm, row.lateral.lateral_disp_centre_cm, row.lateral.lateral_disp_right_cm) =
                (l, c, rt);
            row.lateral.lateral_disp_max_cm = Some(m_to_cm(r.max_displacement_m));
            row.lateral.lateral_drift = Some(r.drift);
        }
        Some(why) => {
            row.status = Status::Collapsed;
            // The lateral load names its reasons with the same vocabulary.
            row.collapse.collapse_reason =
                CollapseReason::from_name(why).map_or_else(|| why.clone(), |r| r.name().to_string());
            row.error = format!(
                "collapsed under the lateral load ({why}): top displacement {:.2} cm when stopped",
                m_to_cm(r.max_displacement_m)
            );
        }
    }
    row
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collapse_reasons_have_one_spelling_in_every_table_and_in_tilt_json() {
        for r in CollapseReason::ALL {
            assert_eq!(serde_json::to_string(&r).unwrap(), format!("\"{}\"", r.name()));
            assert_eq!(CollapseReason::from_name(r.name()), Some(r));
        }
        // The names the lateral load gives.
        for why in ["total_displacement", "no_equilibrium", "step_budget"] {
            assert!(CollapseReason::from_name(why).is_some(), "{why}");
        }
    }
}
