//! The in-plane test's part of a study file (`protocol = "in_plane"`), read by the study
//! core ([`StudySpec::resolve`]) into [`StudyProtocol::InPlane`](super::StudyProtocol):
//! the shared `[in_plane]` table, each group's vertical stress, history and specimens, and
//! the measured specimens (`[measured] walls`, `envelopes`, `crackmaps`, `curves`). The
//! groups' walls, surveys, effects, realizations and the `[solver]` table are the core's,
//! read as in every study.
//!
//! The keys only the in-plane test reads are refused in the other protocols' files, and the
//! keys it does not read (a sweep, the tilting table's measured files, `paper`,
//! `calibrate`, the other protocols' tables) in its own, each naming its key.
//!
//! # The study file (docs/inplane.md)
//!
//! ```toml
//! version = 1
//! name = "inplane_granite"
//! seed = 20090301
//! realizations = 8
//! protocol = "in_plane"
//!
//! [in_plane]                 # every group's test (loading::inplane::InPlaneParams)
//! shear_span_m = 1.325
//! drift_pct = 3.25
//!
//! [[groups]]
//! name = "0.5 MPa monotonic"
//! wall = "walls/granite_vasconcelos.toml"
//! sigma0_mpa = 0.5
//! history = "monotonic"      # or "cyclic"
//! specimens = ["WS.100"]     # rows of the measured file compared with this group
//! realizations = 8           # optional: the study's by default
//! effects = { seating_gap = { max_gap_m = 4.2e-4 } }  # optional: on top of the study's
//!
//! [effects]                  # optional: every group's model extended (crate::effects)
//! jack_tilt = { inverse_length_per_m = 0.54 }
//!
//! [measured]
//! walls = "../data/inplane_granite/walls.csv"          # the database's columns
//! envelopes = "../data/inplane_granite/envelopes"      # envelope_<unit>_<source>.csv
//! crackmaps = "../data/inplane_granite/crackmaps"      # optional: linked in the report
//! curves = "../data/inplane_granite/curves"            # optional: the cyclic loops
//! ```
//!
//! The study's `[solver]` table chooses the method every realization's test runs by, as
//! in every study (any method of the protocol's `WAYS` that draws the curve: the penalty
//! DEM with any of its cascades, or nscd; the protocol's default without it); limit
//! analysis runs beside it whatever the kind (`limit_peak_kn`), by `[solver.limit]`.

use super::error::Invalid;
use super::inplane_measured::{file_stem, read_loops, read_specimens, Specimen};
use super::provenance::InputRole;
use super::spec::{EffectsSpec, GroupSpec, StudySpec};
use super::StudyError;
use crate::loading::inplane::{BeamRotation, History, InPlaneParams, MAX_HEIGHT_RATIO};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The in-plane test of a study: the parameters its groups share, each group's own and the
/// measured specimens.
#[derive(Debug, Clone)]
pub struct InPlaneStudy {
    /// The `[in_plane]` table (its `sigma0_mpa` and `history` not read: each group's).
    pub params: InPlaneParams,
    /// Each group's own values, in the order of the study's groups.
    pub groups: Vec<InPlaneGroup>,
    /// The measured specimens (none without `[measured] walls`).
    pub specimens: Vec<Specimen>,
    /// The folder of the measured crack maps (`[measured] crackmaps`, relative to the study
    /// file), linked in the report.
    pub crackmaps: Option<PathBuf>,
}

/// One group's values of the in-plane test.
#[derive(Debug, Clone)]
pub struct InPlaneGroup {
    /// The vertical stress applied, MPa.
    pub sigma0_mpa: f64,
    /// The loading history.
    pub history: History,
    /// The measured specimens compared with the group (units of the measured file).
    pub specimens: Vec<String>,
    /// Its wall description or survey as the study file names it.
    pub source: PathBuf,
    /// The effects of its model as stated ([`stated_effects`]): key, name and values.
    pub stated: Vec<(String, String, BTreeMap<String, f64>)>,
}

impl InPlaneStudy {
    /// The test's parameters of group `g`: the shared table with its vertical stress and
    /// history.
    pub fn params_of(&self, g: usize) -> InPlaneParams {
        let group = &self.groups[g];
        InPlaneParams { sigma0_mpa: group.sigma0_mpa, history: group.history, ..self.params.clone() }
    }

    /// Whether a group runs the cyclic history.
    pub fn any_cyclic(&self) -> bool {
        self.groups.iter().any(|g| g.history == History::Cyclic)
    }

    /// Refuses, before any run, a shear span (`in_plane.shear_span_m`, with the beam's
    /// rotation free) or a measuring height (`in_plane.measuring_height_m`) more than
    /// [`MAX_HEIGHT_RATIO`] times the height of a group's wall: a probable unit mistake
    /// (millimetres for metres) that the rig refuses in every realization
    /// ([`crate::loading::inplane::InPlaneError::TooHigh`], which stays for a direct
    /// `drystone in-plane` run). `walls` gives each group's name, its wall's height (m, the
    /// wall description's or the survey's; `None`: no wall to check) and its wall
    /// description or survey, in the order of the groups.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] naming the key, the group and its wall.
    pub(super) fn check_heights<'a>(
        &self,
        walls: impl IntoIterator<Item = (&'a str, Option<f64>, &'a Path)>,
        invalid: &Invalid,
    ) -> Result<(), StudyError> {
        for (g, (name, height_m, source)) in walls.into_iter().enumerate() {
            let Some(height_m) = height_m else { continue };
            let p = self.params_of(g);
            let span = match p.beam_rotation {
                BeamRotation::Free => p.shear_span_m,
                BeamRotation::Fixed => None,
            };
            for (key, value) in [("shear_span_m", span), ("measuring_height_m", p.measuring_height_m)] {
                let Some(v) = value else { continue };
                if v > MAX_HEIGHT_RATIO * height_m {
                    return Err(invalid.at(
                        &format!("in_plane.{key}"),
                        format!(
                            "{v} m is more than {MAX_HEIGHT_RATIO} times the height {height_m} m of the wall of group \
                             {name:?} ({}): a probable unit mistake (millimetres for metres?); it is a height on the \
                             loading beam, above the wall's top",
                            source.display()
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Refuses, on read, a drift the study's method cannot follow
    /// ([`crate::loading::inplane::check_drift_reach`]: the penalty DEM's reach is
    /// [`crate::loading::inplane::max_drift_pct`] of its face-angle tolerance), rather than
    /// failing every realization of the study with the same error.
    pub(super) fn check_reach(&self, solver: &crate::dem::SolverParams, invalid: &Invalid) -> Result<(), StudyError> {
        if !solver.kind.is_penalty() {
            return Ok(());
        }
        crate::loading::inplane::check_drift_reach(&self.params, solver.face_angle_tolerance_deg)
            .map_err(|e| invalid.at("in_plane.drift_pct", e.to_string()))
    }
}

/// The effects of group `g`'s model, each with the key that states it: the study's
/// `effects` the group does not restate, then the group's own.
pub fn stated_effects(study: &EffectsSpec, group: &GroupSpec) -> Vec<(String, String, BTreeMap<String, f64>)> {
    let mut v: Vec<(String, String, BTreeMap<String, f64>)> = study
        .iter()
        .filter(|(n, _)| !group.effects.contains_key(*n))
        .map(|(n, values)| (format!("effects.{n}"), n.clone(), values.clone()))
        .collect();
    v.extend(
        group
            .effects
            .iter()
            .map(|(n, values)| (format!("groups[{}].effects.{n}", group.name), n.clone(), values.clone())),
    );
    v
}

/// The first key of `[[groups]]` the in-plane test reads that group `g` gives and the
/// study's kind does not read (`reads`, its [`super::StudyKind::group_keys`]).
fn in_plane_group_keys(g: &GroupSpec, reads: &[&str]) -> Option<&'static str> {
    [("sigma0_mpa", g.sigma0_mpa.is_some()), ("history", g.history.is_some()), ("specimens", !g.specimens.is_empty())]
        .into_iter()
        .find_map(|(key, given)| (given && !reads.contains(&key)).then_some(key))
}

impl StudySpec {
    /// The in-plane test of an in-plane study, its measured files pushed into `files`;
    /// `None` for another protocol's study, whose file must state none of the in-plane
    /// test's keys.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] naming the key: a key of the in-plane test in another
    /// protocol's study, a key the in-plane test does not read in its own, a group's value
    /// out of range or missing, a specimen named twice or not in the measured file, an
    /// effect the test does not read, a method that draws no curve; a measured file that
    /// cannot be read.
    pub(super) fn resolve_in_plane(
        &self,
        dir: &Path,
        invalid: &Invalid,
        files: &mut Vec<(InputRole, PathBuf)>,
    ) -> Result<Option<InPlaneStudy>, StudyError> {
        let measured_in_plane = self.measured.as_ref().and_then(|m| {
            [("walls", &m.walls), ("envelopes", &m.envelopes), ("crackmaps", &m.crackmaps), ("curves", &m.curves)]
                .into_iter()
                .find_map(|(k, v)| v.is_some().then_some(k))
        });
        if !self.reads_table("in_plane") {
            let only = |key: String| {
                invalid.at(&key, "is read by the in-plane test only (protocol = \"in_plane\", docs/inplane.md)".into())
            };
            if self.in_plane.is_some() {
                return Err(only("in_plane".into()));
            }
            // The keys of the groups its own kind reads (the compression test's vertical
            // stress) are not refused.
            let reads = self.declared().group_keys;
            if let Some((g, k)) = self.groups.iter().find_map(|g| in_plane_group_keys(g, reads).map(|k| (g, k))) {
                return Err(only(format!("groups[{}].{k}", g.name)));
            }
            if let Some(k) = measured_in_plane {
                return Err(only(format!("measured.{k}")));
            }
            return Ok(None);
        }
        self.refuse_unread_by_in_plane(invalid)?;
        let params = self.in_plane.clone().unwrap_or_default();
        if !self.solver.kind.method().draws_curves() {
            return Err(invalid.at(
                "solver.kind",
                format!(
                    "{:?}: {} gives no force-displacement curve, which the study's rows read (it runs beside every \
                     realization, limit_peak_kn): give kind = \"penalty\" or \"nscd\"",
                    self.solver.kind.name(),
                    self.solver.kind.method().describe()
                ),
            ));
        }
        let mut groups = Vec::with_capacity(self.groups.len());
        for g in &self.groups {
            groups.push(self.in_plane_group(g, &params, invalid)?);
        }
        let any_cyclic = groups.iter().any(|g: &InPlaneGroup| g.history == History::Cyclic);
        if let Some((key, why)) = params.unread_key(any_cyclic) {
            return Err(invalid.at(&format!("in_plane.{key}"), why.into()));
        }
        // What holds the blocks out of the plane is the penalty DEM's setting (nscd's walls
        // are 3D), refused by name with another method as `--out-of-plane` is.
        if !self.solver.kind.is_penalty() && params.out_of_plane != InPlaneParams::default().out_of_plane {
            return Err(invalid.at(
                "in_plane.out_of_plane",
                format!(
                    "{:?} is read by the penalty DEM only (what holds its blocks out of the wall's plane); \
                     {} runs its walls in 3D: drop the key, or give [solver] kind = \"penalty\"",
                    params.out_of_plane.name(),
                    self.solver.kind.method().describe()
                ),
            ));
        }
        let specimens = read_measured_specimens(self, dir, invalid, files)?;
        for (spec, group) in self.groups.iter().zip(&groups) {
            if let Some(s) = group.specimens.iter().find(|s| !specimens.iter().any(|m| &m.unit == *s)) {
                let walls = self.measured.as_ref().and_then(|m| m.walls.as_ref());
                let why = match walls {
                    Some(w) => format!("{s} is not a unit of the measured file {}", w.display()),
                    None => format!(
                        "{s} names a measured specimen, but the study gives no measured file: add [measured] walls \
                         (the specimens' table, docs/inplane.md) or drop the key"
                    ),
                };
                return Err(invalid.at(&format!("groups[{}].specimens", spec.name), why));
            }
            // A specimen is compared with the walls of its own stress (the table's
            // `sigma0_applied_MPa`, where it gives one), as the discrepancy analysis pairs them.
            let tested = |name: &String| specimens.iter().find(|m| &m.unit == name).map_or(f64::NAN, |m| m.sigma0_mpa);
            if let Some(s) = group.specimens.iter().find(|s| (tested(s) - group.sigma0_mpa).abs() > 1e-9) {
                return Err(invalid.at(
                    &format!("groups[{}].specimens", spec.name),
                    format!(
                        "{s} was tested at {} MPa (the measured file's sigma0_applied_MPa), the group at sigma0_mpa = {} MPa: a specimen is compared with walls of its own stress",
                        tested(s),
                        group.sigma0_mpa
                    ),
                ));
            }
            // And with walls of its own history, where the file's `loading` names one.
            let measured = |name: &String| {
                specimens.iter().find(|m| &m.unit == name).and_then(|m| History::of_loading(&m.loading))
            };
            if let Some(s) = group.specimens.iter().find(|s| measured(s).is_some_and(|h| h != group.history)) {
                return Err(invalid.at(
                    &format!("groups[{}].specimens", spec.name),
                    format!(
                        "{s} was tested {} (the measured file's loading), the group's history is {}: a specimen is compared with walls of its own history",
                        measured(s).map_or("", History::name),
                        group.history.name()
                    ),
                ));
            }
        }
        let crackmaps = self.measured.as_ref().and_then(|m| m.crackmaps.clone());
        Ok(Some(InPlaneStudy { params, groups, specimens, crackmaps }))
    }

    /// The keys of an in-plane study file the in-plane test does not read, refused: a
    /// sweep, the tilting table's measured files, `paper`, `calibrate`, the other
    /// protocols' tables, the groups' `measured_group`.
    fn refuse_unread_by_in_plane(&self, invalid: &Invalid) -> Result<(), StudyError> {
        let not_read = |key: &str, why: &str| invalid.at(key, format!("the in-plane test does not read it ({why})"));
        if let Some(k) = self.sweep.keys().next() {
            return Err(not_read(&format!("sweep.{k}"), "an in-plane study has no sweep: give each case its group"));
        }
        if let Some(m) = &self.measured {
            for (k, v) in [
                ("collapse", &m.collapse),
                ("displacement", &m.displacement),
                ("mechanism", &m.mechanism),
                ("paper_dem", &m.paper_dem),
            ] {
                if v.is_some() {
                    return Err(not_read(&format!("measured.{k}"), "it compares with [measured] walls"));
                }
            }
        }
        let tables = [
            ("paper", self.paper.is_some()),
            ("calibrate", !self.calibrate.is_empty()),
            ("shake", self.shake.is_some()),
            ("tilt", self.tilt != crate::loading::tilt::TiltParams::default()),
            ("lateral", self.lateral != crate::loading::lateral::LateralParams::default()),
        ];
        if let Some((k, _)) = tables.iter().find(|(_, given)| *given) {
            return Err(not_read(k, "another protocol's key"));
        }
        if let Some(g) = self.groups.iter().find(|g| g.measured_group.is_some()) {
            return Err(not_read(
                &format!("groups[{}].measured_group", g.name),
                "a group is compared with the specimens it names, groups[].specimens",
            ));
        }
        Ok(())
    }

    /// Group `g`'s values of the in-plane test, checked with the shared table `params`.
    fn in_plane_group(
        &self,
        g: &GroupSpec,
        params: &InPlaneParams,
        invalid: &Invalid,
    ) -> Result<InPlaneGroup, StudyError> {
        let key = |k: &str| format!("groups[{}].{k}", g.name);
        let Some(sigma0_mpa) = g.sigma0_mpa else {
            return Err(
                invalid.at(&key("sigma0_mpa"), "missing: the vertical stress the group's walls bear, MPa".into())
            );
        };
        if let Some((k, s)) = g.specimens.iter().enumerate().find(|(k, s)| g.specimens[..*k].contains(s)) {
            return Err(invalid.at(
                &key(&format!("specimens[{k}]")),
                format!("{s} is named twice: a specimen is compared once with its group"),
            ));
        }
        let group = InPlaneGroup {
            sigma0_mpa,
            history: g.history.unwrap_or_default(),
            specimens: g.specimens.clone(),
            source: g.wall.clone().or_else(|| g.survey.clone()).unwrap_or_default(),
            stated: stated_effects(&self.effects, g),
        };
        let p = InPlaneParams { sigma0_mpa, history: group.history, ..params.clone() };
        p.validate().map_err(|e| invalid.at(&format!("groups[{}]: in_plane.{}", g.name, e.key), e.reason()))?;
        // The effects the test does not read, in the group's model.
        for (k, name, _) in &group.stated {
            refuse_out_of_plane(k, name, invalid)?;
        }
        if let Some(d) = &self.discrepancy {
            for (list, names) in [("effects", &d.effects), ("also_effects", &d.also_effects)] {
                for name in names {
                    refuse_out_of_plane(&format!("discrepancy.{list}"), name, invalid)?;
                }
            }
        }
        Ok(group)
    }
}

/// Refuses an effect the in-plane test does not read
/// ([`crate::effects::EffectDef::not_read_in_plane`]: `initial_lean`, `table_kick`,
/// `restraint_stiffness`, `end_rope`, `base_restraint`, `leaf_split`, `transverse_dip`),
/// stated at `key`: accepted, it would run the plain wall (or, for a lean or base stops, a
/// wall whose extent across its plane gives the rig another thickness) under the effect's
/// name. An unknown effect is left to the reader that resolves it.
fn refuse_out_of_plane(key: &str, name: &str, invalid: &Invalid) -> Result<(), StudyError> {
    let library = crate::effects::Library::builtin();
    match library.get(name).ok().and_then(|d| d.not_read_in_plane()) {
        Some(reason) => Err(invalid.at(key, format!("{name}: the in-plane test does not read it ({reason})"))),
        None => Ok(()),
    }
}

/// The measured specimens of an in-plane study (`[measured] walls`, with their envelopes
/// and loops); the table goes into `files`. None without `[measured]`.
fn read_measured_specimens(
    spec: &StudySpec,
    dir: &Path,
    invalid: &Invalid,
    files: &mut Vec<(InputRole, PathBuf)>,
) -> Result<Vec<Specimen>, StudyError> {
    let Some(m) = &spec.measured else { return Ok(Vec::new()) };
    let Some(walls) = &m.walls else {
        return Err(invalid.at("measured.walls", "missing: the measured specimens' table of an in-plane study".into()));
    };
    if let Some(e) = m.envelopes.as_ref().filter(|e| !dir.join(e).is_dir()) {
        return Err(invalid.at(
            "measured.envelopes",
            format!("{}: not a folder of the measured envelopes (envelope_<unit>_<author><year>.csv)", e.display()),
        ));
    }
    // The crack maps are only linked in the report, but a folder that is not there is a
    // typo the user would otherwise never see.
    if let Some(c) = m.crackmaps.as_ref().filter(|c| !dir.join(c).is_dir()) {
        return Err(invalid.at(
            "measured.crackmaps",
            format!("{}: not a folder of the measured crack maps (crackmap_<unit>_<author><year>.png)", c.display()),
        ));
    }
    let mut s = read_specimens(&dir.join(walls), m.envelopes.as_ref().map(|e| dir.join(e)).as_deref())
        .map_err(|e| invalid.at("measured.walls", e.to_string()))?;
    if let Some(c) = &m.curves {
        read_loops(&mut s, &dir.join(c)).map_err(|e| invalid.at("measured.curves", e.to_string()))?;
    }
    files.push((InputRole::Measured, dir.join(walls)));
    // The envelopes and curves read (the specimens' files that exist), stored with the run
    // so that `drystone merge` rebuilds the study from its manifest alone.
    let read = |folder: &Option<PathBuf>, name: fn(&Specimen) -> String| -> Vec<PathBuf> {
        folder
            .as_ref()
            .map_or_else(Vec::new, |f| s.iter().map(|x| dir.join(f).join(name(x))).filter(|p| p.is_file()).collect())
    };
    files.extend(
        read(&m.envelopes, |x| format!("envelope_{}.csv", file_stem(x))).into_iter().map(|p| (InputRole::Measured, p)),
    );
    files.extend(read(&m.curves, |x| format!("FD_{}.csv", file_stem(x))).into_iter().map(|p| (InputRole::Measured, p)));
    Ok(s)
}
