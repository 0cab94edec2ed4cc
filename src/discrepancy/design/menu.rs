//! The menu of follow-up tests on the tilting table: for every group of the study, more
//! specimens of it; its failure mechanism read; its top monitors read at both measures
//! and more tilts; and walls of another height, length or end restraint as an extra
//! group of the same study (analysed together with the first campaign).

use super::mechanism_keys;
use super::plan::{FollowUp, FollowUpKind, WallEdit};
use crate::discrepancy::observations::{Measure, Observable};
use crate::discrepancy::simulate::{GroupSetup, Setup};
use crate::discrepancy::{DiscrepancyError, Run};
use crate::generator::spec::{EndKind, EndsSpec, WallSpec};
use crate::generator::DistributionSource;
use std::path::Path;

/// The tilts a monitor follow-up reads: those of the first campaign's displacements, else
/// 5° and 10° (where the table's steps reach them).
fn monitor_tilts(run: &Run, setup: &Setup) -> Vec<f64> {
    let mut t: Vec<f64> = run.obs.iter().filter_map(|o| o.observable.tilt_deg()).collect();
    if t.is_empty() {
        t = vec![5.0, 10.0];
    }
    t.sort_by(f64::total_cmp);
    t.dedup();
    t.retain(|&x| setup.reaches_tilt(x));
    t
}

/// A follow-up on the group's own walls (`group`): more specimens, or other readings of
/// them.
fn on_own_walls(group: &str, name: String, kind: FollowUpKind, observables: Vec<Observable>) -> FollowUp {
    FollowUp {
        name,
        kind,
        group: group.to_string(),
        from_group: group.to_string(),
        observables,
        new_group: None,
        new_spec: None,
        edit: WallEdit::default(),
    }
}

/// A group's wall as the study describes it: its name, its wall description (overrides
/// applied) and the file it came from (for its named distributions).
#[derive(Debug, Clone, Copy)]
pub struct GroupWall<'a> {
    /// The group's name.
    pub name: &'a str,
    /// Its wall description, with the group's overrides applied.
    pub spec: &'a WallSpec,
    /// The wall description file.
    pub wall_path: &'a Path,
}

/// The menu of tilting-table follow-ups of an analysed study (see the module
/// documentation): per group, more specimens; the mechanism read (unless its specimens
/// were read for height, kind and start already); both monitors at the campaign's tilts
/// (unless read already); walls 1.5 × taller; walls half as long (twice as long when
/// shorter than 1 m); the other end restraint (unless another group is that wall).
///
/// # Errors
/// [`DiscrepancyError::Protocol`] for a protocol other than the tilting table;
/// [`DiscrepancyError::Design`] for a wall edit the generator refuses.
pub fn menu(walls: &[GroupWall<'_>], setup: &Setup, run: &Run) -> Result<Vec<FollowUp>, DiscrepancyError> {
    if setup.tilt().is_none() {
        return Err(DiscrepancyError::Protocol {
            protocol: setup.protocol.name(),
            reason: "`drystone design` plans tilting-table follow-ups; this study's protocol is not the tilting table",
        });
    }
    let tilts = monitor_tilts(run, setup);
    let mut out = Vec::new();
    for (gi, g) in setup.groups.iter().enumerate() {
        let Some(sg) = walls.iter().find(|s| s.name == g.name) else { continue };
        let read: Vec<Observable> = run.keys.keys.iter().filter(|(kg, _)| *kg == gi).map(|(_, o)| *o).collect();
        if read.is_empty() {
            continue;
        }
        let width = (g.course_m / g.wall.height).clamp(0.01, 1.0);
        let angle_and_disp: Vec<Observable> = read.iter().copied().filter(|o| !o.is_mechanism()).collect();
        let has_mech = read.iter().filter(|o| o.is_mechanism()).count();
        out.push(on_own_walls(
            &g.name,
            format!("more {} specimens", g.name),
            FollowUpKind::MoreSpecimens,
            read.clone(),
        ));
        let mech = mechanism_keys(width);
        if has_mech < mech.len() {
            let mut obs = angle_and_disp.clone();
            obs.extend(mech.iter().copied());
            out.push(on_own_walls(
                &g.name,
                format!("{} specimens with the failure mechanism read", g.name),
                FollowUpKind::Mechanism,
                obs,
            ));
        }
        let monitors: Vec<Observable> = tilts
            .iter()
            .flat_map(|&t| Measure::ALL.map(|measure| Observable::Displacement { measure, tilt_deg: t }))
            .collect();
        if monitors.iter().any(|m| !read.iter().any(|o| o.same(m))) {
            let mut obs: Vec<Observable> = read.iter().copied().filter(Observable::is_angle).collect();
            obs.extend(monitors);
            out.push(on_own_walls(
                &g.name,
                format!("{} specimens with both top measures read at {:?} deg", g.name, tilts),
                FollowUpKind::Monitors,
                obs,
            ));
        }
        // Walls of another kind, as extra groups: the first campaign's readings, and the
        // mechanism.
        let mut new_read = angle_and_disp.clone();
        new_read.extend(mech.iter().copied());
        let length_factor = if g.wall.length < 1.0 { 2.0 } else { 0.5 };
        let edits = [
            (FollowUpKind::Height, "tall", WallEdit { height_factor: Some(1.5), ..WallEdit::default() }),
            (
                FollowUpKind::Length,
                if length_factor > 1.0 { "long" } else { "short" },
                WallEdit { length_factor: Some(length_factor), ..WallEdit::default() },
            ),
            (
                FollowUpKind::Restraint,
                if g.restrained { "free" } else { "held" },
                WallEdit { rigid_ends: Some(!g.restrained), ..WallEdit::default() },
            ),
        ];
        for (kind, suffix, edit) in edits {
            let spec = edited(sg.spec, &edit);
            if kind == FollowUpKind::Restraint && walls.iter().any(|o| o.name != g.name && same_wall(o.spec, &spec)) {
                continue;
            }
            let name = format!("{}_{suffix}", g.name);
            let wall = spec.resolve(sg.wall_path, &DistributionSource::default_for(sg.wall_path)).map_err(|e| {
                DiscrepancyError::Design { specimen: name.clone(), observable: format!("wall edit refused: {e}") }
            })?;
            let first = crate::generator::generate(&wall, setup.seed, 0).ok().and_then(|w| w.check().ok());
            let restrained = first.as_ref().is_some_and(|l| !l.end_restraints.is_empty());
            let what = match kind {
                FollowUpKind::Height => format!("{} walls 1.5 × taller", g.name),
                FollowUpKind::Length => format!("{} walls {} × as long", g.name, length_factor),
                _ => format!("{} walls with {} ends", g.name, if restrained { "held" } else { "free" }),
            };
            out.push(FollowUp {
                name: format!("{what} ({name}), the mechanism read"),
                kind,
                group: name.clone(),
                from_group: g.name.clone(),
                observables: new_read.clone(),
                new_group: Some(GroupSetup {
                    name,
                    course_m: crate::effects::course_height_of(&wall),
                    wall,
                    realizations: g.realizations,
                    restrained,
                    deterministic: g.deterministic,
                    effects: g.effects.clone(),
                    protocol: g.protocol.clone(),
                }),
                new_spec: Some(spec),
                edit,
            });
        }
    }
    Ok(out)
}

/// The group's wall description with `edit` applied.
fn edited(spec: &WallSpec, edit: &WallEdit) -> WallSpec {
    let mut s = spec.clone();
    if let Some(f) = edit.height_factor {
        s.geometry.height_m *= f;
        s.name = format!("{} (height × {f})", s.name);
    }
    if let Some(f) = edit.length_factor {
        s.geometry.length_m *= f;
        s.name = format!("{} (length × {f})", s.name);
    }
    if let Some(rigid) = edit.rigid_ends {
        s.restraints.ends = if rigid {
            EndsSpec { kind: EndKind::Rigid, zone_m: Some(0.05), stiffness_n_per_m: None }
        } else {
            EndsSpec::default()
        };
        s.name = format!("{} ({} ends)", s.name, if rigid { "held" } else { "free" });
    }
    s
}

/// Two wall descriptions that differ at most in name and description.
fn same_wall(a: &WallSpec, b: &WallSpec) -> bool {
    let strip = |w: &WallSpec| WallSpec { name: String::new(), description: String::new(), ..w.clone() };
    strip(a) == strip(b)
}
