//! The settings a study file states but its run does not read, one warning each naming
//! its key ([`Study::read_warnings`](super::Study::read_warnings)): the tilting table's
//! keys the hand-rolled table does not read, `[solver.nscd]` keys by the penalty DEM and
//! `[solver.penalty]` keys by nscd, the lateral load's keys in a shaking study, an end
//! rope on a wall that does not reach it.

use super::resolve::Group;
use super::spec::{GroupSpec, StudySpec};
use crate::dem::Method;

impl StudySpec {
    /// Settings the study accepts but does not read: `[tilt] step_deg` and
    /// `resolution_deg` with `[tilt] by_hand` (the hand's increments are the path), and
    /// `discrepancy.also_effects` beside `discrepancy.effects` (which names every
    /// candidate), `[solver.nscd]` keys by the penalty DEM and `[solver.penalty]` keys by
    /// nscd. One message per setting, naming its key.
    pub(super) fn ignored_settings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let d = crate::loading::tilt::TiltParams::default();
        if self.rolled_by_hand() {
            for (key, v, default) in [
                ("tilt.step_deg", self.tilt.step_deg, d.step_deg),
                ("tilt.resolution_deg", self.tilt.resolution_deg, d.resolution_deg),
            ] {
                if v != default {
                    out.push(format!(
                        "{key} = {v} is not read with [tilt] by_hand: the table rolled by hand tilts by its \
                         increment_deg and reads the collapse from the motion"
                    ));
                }
            }
        }
        let motions = self.declared().ground_motions;
        if motions {
            out.extend(self.ignored_by_shaking());
            if self.solver.kind.method().solves_steps_to_a_tolerance() {
                out.extend(
                    self.solver
                        .nscd
                        .motion_cost_warnings()
                        .into_iter()
                        .map(|(k, why)| format!("solver.nscd.{k} {why}")),
                );
            }
        }
        // The settings of each method the chosen one does not read (its declared list).
        for &unread in self.solver.kind.method().does_not_read() {
            match unread {
                Method::Nscd => out.extend(self.nscd_not_read(motions)),
                Method::Penalty => out.extend(self.penalty_not_read(motions)),
                // Limit analysis runs beside the other methods (the shaking study's static
                // capacity): its settings are read whatever the method.
                Method::Limit => {}
            }
        }
        if let Some(dis) = &self.discrepancy {
            let hand = self.rolled_by_hand();
            if hand && dis.effects.iter().chain(&dis.also_effects).any(|e| e == "table_kick") {
                out.push(
                    "discrepancy: table_kick is the quasi-static equivalent of the kicks [tilt] by_hand already runs; \
                     the hand-rolled realizations do not read it (its candidate changes nothing)"
                        .to_string(),
                );
            }
            if !dis.effects.is_empty() && !dis.also_effects.is_empty() {
                out.push(format!(
                    "discrepancy.also_effects = {:?} is not read: discrepancy.effects names every candidate \
                     (add them there)",
                    dis.also_effects
                ));
            }
        }
        out
    }

    /// `[solver.nscd]` keys set away from their defaults with a penalty solver, which runs
    /// no non-smooth solver (the command line refuses `--nscd-*` without `--solver nscd`):
    /// one message a key, but `dt_s` in a study that steps ground motions (`motions`), whose
    /// pulses are sampled at it whatever the method.
    fn nscd_not_read(&self, motions: bool) -> Vec<String> {
        let read = |k: &str| motions && k == "dt_s";
        changed_keys(&self.solver.nscd, &crate::dem::nscd_params::NscdParams::default())
            .into_iter()
            .filter(|key| !read(key))
            .map(|key| {
                format!(
                    "solver.nscd.{key} is not read with solver.kind = \"{}\": the penalty DEM does not run the \
                     non-smooth solver (give kind = \"nscd\", or drop the key)",
                    self.solver.kind.name()
                )
            })
            .collect()
    }

    /// With nscd, which runs none of the penalty DEM's static solves or its motion (the
    /// command line's penalty options are refused or warned of with `--solver nscd`): the
    /// `[solver.nscd]` keys of a step of motion in a study that steps no ground motion
    /// (`motions` false: the tilting table's, the hand's and the pushover's release trials
    /// take the sweeps alone and never certify rest, `NscdParams::for_trials`, as `drystone
    /// tilt` refuses these options), then the `[solver.penalty]` keys set; one message a key.
    fn penalty_not_read(&self, motions: bool) -> Vec<String> {
        let mut out = Vec::new();
        if !motions {
            let motion = ["rest", "step_solver", "natural_tolerance", "apgd_after_solves"];
            let nscd = crate::dem::nscd_params::NscdParams::default();
            for key in changed_keys(&self.solver.nscd, &nscd).into_iter().filter(|k| motion.contains(&k.as_str())) {
                out.push(format!(
                    "solver.nscd.{key} is not read by protocol = \"{}\": it sets a step of motion of a shaking \
                     study, and this protocol's release trials take the NSGS sweeps alone and never certify rest",
                    self.protocol.name()
                ));
            }
        }
        for key in changed_keys(&self.solver.penalty, &crate::dem::PenaltyParams::default()) {
            out.push(format!(
                "solver.penalty.{key} is not read with solver.kind = \"{}\": non-smooth contact dynamics does \
                 not run the penalty DEM (give kind = \"penalty\", or drop the key)",
                self.solver.kind.name()
            ));
        }
        out
    }

    /// What a shaking study (protocol `shake`) accepts and does not read, one message per
    /// key: `[tilt] by_hand`, the keys of `[lateral]` set away from their defaults,
    /// `[measured]` (a shaking study has no measured data to compare) and the effect
    /// `table_kick` (a tilting table's overshoot) in the study's or a group's effects.
    fn ignored_by_shaking(&self) -> Vec<String> {
        let mut out = Vec::new();
        let not_read =
            |key: &str, why: &str| format!("{key} is not read by a shaking study (protocol = \"shake\"): {why}");
        if self.tilt.by_hand.is_some() {
            out.push(not_read("tilt.by_hand", "the table rolled by hand is a tilting-table protocol"));
        }
        for key in changed_keys(&self.lateral, &crate::loading::lateral::LateralParams::default()) {
            out.push(not_read(&format!("lateral.{key}"), "the lateral load is another protocol"));
        }
        if self.measured.is_some() {
            out.push(not_read("measured", "a shaking study has no measured data to compare (no row reads it)"));
        }
        let kicks = std::iter::once(("effects".to_string(), &self.effects))
            .chain(self.groups.iter().map(|g| (format!("groups[{}].effects", g.name), &g.effects)));
        for (key, effects) in kicks {
            if effects.contains_key("table_kick") {
                out.push(not_read(
                    &format!("{key}.table_kick"),
                    "it sets the tilting table's overshoot, which the shaking table does not have",
                ));
            }
        }
        out
    }

    /// A warning when the group's `end_rope` (the group's own or the study's) acts on a
    /// wall without end restraints, where it changes nothing (docs/rope.md).
    pub(super) fn idle_end_rope(&self, g: &GroupSpec, group: &Group) -> Option<String> {
        let key = if g.effects.contains_key("end_rope") {
            format!("groups[{}].effects.end_rope", g.name)
        } else if self.effects.contains_key("end_rope") {
            "effects.end_rope".to_string()
        } else {
            return None;
        };
        let wall = group.walls.first()?;
        let (_, layout) = crate::effects::realize(wall, 0, 0, &g.name, &group.effects).ok()?;
        layout.ropes.is_empty().then(|| {
            format!(
                "{key} changes nothing on group {}: its wall has no end restraints for the ropes to replace",
                g.name
            )
        })
    }
}

/// The keys of `value` whose values differ from `default`'s, in their serde spelling (a
/// settings table of a study file against its defaults).
fn changed_keys<T: serde::Serialize>(value: &T, default: &T) -> Vec<String> {
    let (Ok(toml::Value::Table(v)), Ok(toml::Value::Table(d))) =
        (toml::Value::try_from(value), toml::Value::try_from(default))
    else {
        return Vec::new();
    };
    v.iter().filter(|(k, x)| d.get(*k) != Some(*x)).map(|(k, _)| k.clone()).collect()
}
