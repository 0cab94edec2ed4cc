//! Pictures of single realizations of a study, made by running a realization again with its
//! states recorded (`io::series::Recorder`); a realization is a pure function of the study
//! and its item, and its layout is made as its row's (`study::run::realize_item`: the
//! group's effects applied), so the run gives the same result as its row.
//!
//! * [`mechanism_figures`]: per group, the collapse mechanism of one representative
//!   realization at its first unstable state (`mechanism_GROUP.svg`, `io::mechanism`), for
//!   the report.
//! * [`write_vtk_realizations`]: the ParaView time series of chosen realizations
//!   (`drystone run --vtk-realizations 0,3`), into `DIR/vtk/GROUP[_pP]_rR/`.

use super::Study;
use crate::ensemble::row::{RealizationRow, Status};
use crate::ensemble::{Item, Shard};
use crate::io::mechanism::{mechanism_svg, MechanismFigure};
use crate::io::series::{
    block_motion, lateral_frames, motion_frames, tilt_frames, write_series, Recorder, SeriesError,
};
use crate::io::{replace_file, FileError};
use crate::layout::Layout;
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::{MechanismKind, TiltParams, TiltResult};
use crate::protocol::{run_lateral_observed, run_tilt_observed, RunOutcome};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// A name safe as one path component: ASCII letters, digits, `-` and `_`; anything else `_`.
pub fn file_stem(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect()
}

/// The layout of an item, with its group's effects as its row's run has them
/// ([`super::run::realize_item`]), and its tilt run with every state recorded; `None` if the
/// layout cannot be made or the run fails (the row says why).
fn record_tilt(study: &Study, item: &Item) -> Option<(Layout, Recorder, TiltResult)> {
    let layout = super::run::realize_item(study, item).ok()?;
    let mut rec = Recorder::default();
    let tilt = study.protocol.tilt()?;
    let r = run_tilt_observed(&layout, study.solver, tilt, &mut |a, s, sim| rec.observe(a, s, sim)).ok()?;
    Some((layout, rec, r))
}

/// The realization of group `g` at sweep point 0 whose collapse angle is the (lower) median
/// of the group's collapsed realizations there, the lowest realization among equals.
fn representative<'a>(rows: &'a [RealizationRow], group: &str) -> Option<&'a RealizationRow> {
    let mut collapsed: Vec<&RealizationRow> = rows
        .iter()
        .filter(|r| {
            r.group == group && r.point == 0 && r.status == Status::Collapsed && r.collapse.collapse_angle_deg.is_some()
        })
        .collect();
    collapsed.sort_by(|a, b| {
        a.collapse
            .collapse_angle_deg
            .unwrap_or(0.0)
            .total_cmp(&b.collapse.collapse_angle_deg.unwrap_or(0.0))
            .then(a.realization.cmp(&b.realization))
    });
    let median = collapsed.get(collapsed.len().checked_sub(1)? / 2)?.collapse.collapse_angle_deg;
    collapsed.into_iter().filter(|r| r.collapse.collapse_angle_deg == median).min_by_key(|r| r.realization)
}

fn kind_name(k: MechanismKind) -> &'static str {
    match k {
        MechanismKind::Sliding => "sliding",
        MechanismKind::Toppling => "toppling",
        MechanismKind::Mixed => "mixed",
        MechanismKind::None => "none",
    }
}

/// The mechanism drawing of a recorded tilt at its first unstable state (the last frame of
/// its series); `None` if it did not collapse.
pub fn tilt_mechanism_svg(
    layout: &Layout,
    rec: &Recorder,
    r: &TiltResult,
    title: &str,
    subtitle: &str,
) -> Option<String> {
    let unstable = r.first_unstable_deg?;
    let (series, _) = tilt_frames(rec, r);
    let last = series.last()?;
    let state = &rec.states[last.state];
    let motion = block_motion(&rec.states.first()?.poses, &state.poses);
    let disp: Vec<f64> = motion.iter().map(|m| m.0.norm()).collect();
    let subtitle = format!(
        "{subtitle}α_max {:.2}°, first unstable {unstable:.2}°: {} at {}",
        r.collapse_angle_deg(),
        kind_name(r.mechanism.kind),
        r.mechanism.joint
    );
    Some(mechanism_svg(&MechanismFigure {
        layout,
        poses: &state.poses,
        displacement_m: &disp,
        moving: &last.moving,
        joint: &r.mechanism.joint,
        title,
        subtitle: &subtitle,
    }))
}

/// For each group of a tilt study, the mechanism of its representative realization at sweep
/// point 0 (the median collapse angle, see the module documentation), written to
/// `dir/mechanism_GROUP.svg`. Returns `(group, file name)` of every drawing written (groups
/// without a collapsed realization have none).
///
/// # Errors
/// [`FileError`] naming the drawing that could not be written.
pub fn mechanism_figures(
    study: &Study,
    rows: &[RealizationRow],
    dir: &Path,
) -> Result<Vec<(String, String)>, FileError> {
    if study.protocol.tilt().is_none() {
        return Ok(vec![]);
    }
    let picks: Vec<(usize, &RealizationRow)> = study
        .groups
        .iter()
        .enumerate()
        .filter_map(|(g, group)| representative(rows, &group.name).map(|r| (g, r)))
        .collect();
    let drawn: Vec<Option<(String, String, String)>> = picks
        .par_iter()
        .map(|&(g, row)| {
            let item = Item { index: row.index as usize, group: g, point: 0, realization: row.realization };
            let (layout, rec, r) = record_tilt(study, &item)?;
            let name = &study.groups[g].name;
            let title = format!("{} {name}: collapse mechanism at the first unstable tilt", study.name);
            let subtitle =
                format!("realization {} (seed {}, the group's median collapse angle); ", row.realization, study.seed);
            let svg = tilt_mechanism_svg(&layout, &rec, &r, &title, &subtitle)?;
            Some((name.clone(), format!("mechanism_{}.svg", file_stem(name)), svg))
        })
        .collect();
    let mut files = Vec::new();
    for (group, file, svg) in drawn.into_iter().flatten() {
        replace_file(&dir.join(&file), svg.as_bytes())?;
        files.push((group, file));
    }
    Ok(files)
}

/// Writes the ParaView time series (`io::series`) of the items of `shard` whose realization
/// is in `realizations`, each into `dir/vtk/GROUP[_pP]_rR/` (`_pP` with a sweep), running
/// them again with the recording on. Returns the `.pvd` files written, in item order.
///
/// # Errors
/// [`SeriesError`] naming the file that could not be written.
pub fn write_vtk_realizations(
    study: &Study,
    shard: Shard,
    dir: &Path,
    realizations: &[u64],
) -> Result<Vec<PathBuf>, SeriesError> {
    let items: Vec<Item> =
        shard.select(&study.items()).into_iter().filter(|it| realizations.contains(&it.realization)).collect();
    let written: Vec<Result<Option<PathBuf>, SeriesError>> = items
        .par_iter()
        .map(|it| {
            let group = file_stem(&study.groups[it.group].name);
            let point = if study.points.len() > 1 { format!("_p{}", it.point) } else { String::new() };
            let out = dir.join("vtk").join(format!("{group}{point}_r{}", it.realization));
            // (A shaking study's points are its motions and levels: `_pP` names them.)
            let Ok(layout) = super::run::realize_item(study, it) else {
                return Ok(None);
            };
            study.protocol.write_series(study, it.point, &layout, &out)
        })
        .collect();
    let mut files = Vec::new();
    for w in written {
        files.extend(w?);
    }
    Ok(files)
}

/// The tilting table's time series of one realization, run again with every state
/// recorded: the stable path (`tilt`) and the unstable trials (`unstable_trials`) into `out`;
/// `None` if the run fails.
pub(super) fn tilt_series(
    study: &Study,
    tilt: &TiltParams,
    layout: &Layout,
    out: &Path,
) -> Result<Option<PathBuf>, SeriesError> {
    let mut rec = Recorder::default();
    let mut observe = |a: f64, s: bool, sim: &crate::dem::Simulation| rec.observe(a, s, sim);
    let Ok(r) = run_tilt_observed(layout, study.solver, tilt, &mut observe) else {
        return Ok(None);
    };
    let (series, others) = tilt_frames(&rec, &r);
    write_series(out, "unstable_trials", &rec, &others)?;
    write_series(out, "tilt", &rec, &series).map(Some)
}

/// The lateral load's time series of one realization (`lateral`) into `out`; `None` if
/// the run fails.
pub(super) fn lateral_series(
    study: &Study,
    lateral: &LateralParams,
    layout: &Layout,
    out: &Path,
) -> Result<Option<PathBuf>, SeriesError> {
    let mut rec = Recorder::default();
    let mut observe = |a: f64, s: bool, sim: &crate::dem::Simulation| rec.observe(a, s, sim);
    if run_lateral_observed(layout, study.solver, lateral, &mut observe).is_err() {
        return Ok(None);
    }
    write_series(out, "lateral", &rec, &lateral_frames(&rec)).map(Some)
}

/// The shaking table's time series of one realization at sweep point `point` (its motion
/// and level, `shake`) into `out`; `None` if the run fails.
pub(super) fn shake_series(
    study: &Study,
    point: usize,
    layout: &Layout,
    out: &Path,
) -> Result<Option<PathBuf>, SeriesError> {
    let protocol = study.protocol_at(point);
    if protocol.shaking().is_none() {
        return Ok(None);
    }
    let mut rec = Recorder::default();
    if protocol.run_observed(layout, study.solver, &mut rec).error().is_some() {
        return Ok(None);
    }
    write_series(out, "shake", &rec, &motion_frames(&rec)).map(Some)
}
