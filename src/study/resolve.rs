//! From the raw study file to a checked [`Study`]: every value range checked, every wall
//! generated from its description with the group's overrides and each sweep point applied,
//! every measured file read, before anything runs.

use super::checks::{check_calibration, check_name, check_paper};
use super::error::Invalid;
use super::motions::protocol_sweep;
pub use super::motions::ShakeStudy;

use super::protocol::StudyProtocol;
use super::provenance::{self, InputRole};
use super::size;
use super::spec::{GroupSpec, MeasuredSpec, StudySpec};
use super::sweep::{self, SweepKey, SweepPoint, SweepValue};
use super::{Study, StudyError};
use crate::generator::distribution::DistributionSource;
use crate::generator::spec::WallSpec;
use crate::generator::Wall;
use crate::io::table::{self, MeasuredCollapse, MeasuredDisplacement};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A checked group.
#[derive(Debug, Clone)]
pub struct Group {
    /// Name.
    pub name: String,
    /// Group name in the measured data.
    pub measured_group: String,
    /// The wall description file, or the survey of a surveyed group.
    pub wall_path: PathBuf,
    /// The resolved wall at each sweep point.
    pub walls: Vec<Wall>,
    /// Own number of realizations per sweep point, if the group fixes it.
    pub realizations: Option<u64>,
    /// The group's wall description with its overrides applied (before any sweep point);
    /// `None` for a group naming a survey (its wall is [`crate::survey::surveyed_wall`]'s).
    pub spec: Option<WallSpec>,
    /// The effects of the group's model (the study's, then the group's own), applied to
    /// every realization ([`crate::effects::realize`]).
    pub effects: Vec<crate::effects::Effect>,
    /// A surveyed group's materials file (`[groups.import] materials`), an input of the run.
    pub materials_path: Option<PathBuf>,
}

/// Measured data of a study.
#[derive(Debug, Clone, Default)]
pub struct Measured {
    /// Collapse angles.
    pub collapse: Vec<MeasuredCollapse>,
    /// Displacements.
    pub displacement: Vec<MeasuredDisplacement>,
    /// Failure mechanisms as seen.
    pub mechanism: Vec<table::MeasuredMechanism>,
    /// The paper's DEM collapse angles (Table 7).
    pub paper_dem: Vec<table::PaperDemAngle>,
}

/// A penalty shaking study's step count, before the run: the penalty step of each group's
/// realization 0 (its masses and joint stiffnesses,
/// [`crate::loading::shake::penalty_step`]) over every motion, within
/// [`crate::loading::shake::MAX_SHAKE_STEPS`]. A realization that cannot be generated is
/// left to its row.
fn check_penalty_steps(study: &Study, invalid: &Invalid) -> Result<(), StudyError> {
    let Some(shake) = study.protocol.shake() else {
        return Ok(());
    };
    // nscd's step is the study's own, checked against every motion as they are read
    // (`StudySpec::resolve_shake`); a solver that does not shake is refused by
    // `check_scalars` (`protocol::check`).
    if !crate::protocol::shake::step_rule(&study.solver).is_some_and(|r| r.from_walls) {
        return Ok(());
    }
    for g in &study.groups {
        let Some(wall) = g.walls.first() else { continue };
        let Ok((_, layout)) = crate::effects::realize(wall, study.seed, 0, &g.name, &g.effects) else { continue };
        let dt = crate::loading::shake::penalty_step(&layout, study.solver, &shake.params)
            .map_err(|e| invalid.at("solver", e.to_string()))?;
        for m in &shake.motions {
            crate::loading::shake::check_steps(m, &shake.params, dt).map_err(|e| {
                invalid.at(
                    "shake",
                    format!(
                        "motion {} on group {} by the penalty solver (its step {dt:.3e} s, from the masses and \
                         joint stiffnesses of realization 0): {e}",
                        m.name, g.name
                    ),
                )
            })?;
        }
    }
    Ok(())
}

impl StudySpec {
    /// Checks the study and resolves every wall and measured file.
    ///
    /// # Errors
    /// The first problem found, naming the file and key.
    pub fn resolve(&self, path: &Path) -> Result<Study, StudyError> {
        let invalid = Invalid(path);
        self.check_scalars(&invalid)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut files = vec![(InputRole::Study, path.to_owned())];
        let shake = self.resolve_shake(dir, &invalid, &mut files)?;
        let in_plane = self.resolve_in_plane(dir, &invalid, &mut files)?;
        let compression = self.resolve_compression(&invalid)?;
        let sweep = protocol_sweep(&self.sweep, shake.as_ref());
        self.check_counts(&sweep, &invalid)?;
        let points = sweep::grid(&sweep).map_err(|e| invalid.at(&format!("sweep.{}", e.key), e.reason.to_string()))?;
        let mut library = crate::effects::Library::builtin();
        for (i, f) in self.effect_files.iter().enumerate() {
            let p = dir.join(f);
            let def = crate::effects::EffectDef::from_file(&p)
                .map_err(|e| invalid.at(&format!("effect_files[{i}]"), e.to_string()))?;
            library.add(def).map_err(|e| invalid.at(&format!("effect_files[{i}]"), e.to_string()))?;
            files.push((InputRole::Effect, p));
        }
        let mut names = std::collections::BTreeSet::new();
        let mut groups = Vec::new();
        let mut read_warnings = self.ignored_settings();
        let (table, moved) = self.moved_keys();
        read_warnings.extend(moved.iter().map(|m| m.warning(table)));
        if self.reads_table("tilt") {
            read_warnings.extend(self.tilt.cascade_warnings("tilt"));
        }
        let solver = crate::dem::with_moved(self.solver, &moved);
        if let Some(ip) = &in_plane {
            ip.check_reach(&solver, &invalid)?;
        }
        for g in &self.groups {
            if !names.insert(g.name.clone()) {
                return Err(invalid.at(&format!("groups[{}].name", g.name), "duplicate group name".into()));
            }
            let mut group = resolve_group(g, dir, &points, &invalid)?;
            group.effects = group_effects(&self.effects, g, &group, &library, &invalid)?;
            self.check_realized(g, &group, &invalid)?;
            read_warnings.extend(self.idle_end_rope(g, &group));
            if let (Some(hand), Some(wall)) = (&self.tilt.by_hand, group.walls.first()) {
                let keys = "tilt.by_hand.rate_deg_per_s, ramp_s, axis_depth_m";
                let g0 = crate::units::STANDARD_GRAVITY;
                read_warnings
                    .extend(hand.plausibility_warning(wall.height, g0, keys).map(|w| format!("group {}: {w}", g.name)));
            }
            groups.push(group);
        }
        if let Some(ip) = &in_plane {
            let walls = groups.iter().map(|g| (g.name.as_str(), g.walls.first().map(|w| w.height), &*g.wall_path));
            ip.check_heights(walls, &invalid)?;
        }
        files.extend(groups.iter().flat_map(group_files));
        let measured = match &self.measured {
            Some(m) => read_measured(m, dir, path, &mut files)?,
            None => Measured::default(),
        };
        let inputs = provenance::record(&files)
            .map_err(|(p, e)| invalid.at("inputs", format!("cannot read {}: {e}", p.display())))?;
        let protocol = StudyProtocol::from_spec(self, shake, in_plane, compression, &invalid)?;
        let study = Study {
            name: self.name.clone(),
            description: self.description.clone(),
            path: path.to_owned(),
            seed: self.seed,
            realizations: self.realizations,
            protocol,
            solver,
            groups,
            points,
            measured,
            paper: self.paper,
            calibrate: self.calibrate.clone(),
            discrepancy: self.discrepancy.clone().unwrap_or_default(),
            inputs,
            library,
            read_warnings,
        };
        // Each name under the list that gives it.
        for (list, names) in
            [("effects", &study.discrepancy.effects), ("also_effects", &study.discrepancy.also_effects)]
        {
            for (i, n) in names.iter().enumerate() {
                study.library.get(n).map_err(|e| invalid.at(&format!("discrepancy.{list}[{i}]"), e.to_string()))?;
            }
        }
        crate::discrepancy::searched(&study.discrepancy, &study.library, true)
            .map_err(|e| invalid.at("discrepancy.effects", e.to_string()))?;
        study.check_measured().map_err(|source| StudyError::Measured { path: path.to_owned(), source })?;
        study.discrepancy.validate().map_err(|e| invalid.at("discrepancy", e.to_string()))?;
        for (i, c) in study.calibrate.iter().enumerate() {
            check_calibration(c, &study).map_err(|r| invalid.at(&format!("calibrate[{i}]"), r.to_string()))?;
        }
        if let Some(p) = study.paper {
            check_paper(p, &study).map_err(|r| invalid.at("paper", r.to_string()))?;
        }
        check_penalty_steps(&study, &invalid)?;
        Ok(study)
    }

    /// The version, the counts and the parameter tables.
    fn check_scalars(&self, invalid: &Invalid) -> Result<(), StudyError> {
        if self.version != 1 {
            return Err(invalid.at("version", format!("this drystone reads study version 1, got {}", self.version)));
        }
        check_name(&self.name).map_err(|r| invalid.at("name", r.to_string()))?;
        if self.realizations == 0 {
            return Err(invalid.at("realizations", "must be at least 1".into()));
        }
        if self.groups.is_empty() {
            return Err(invalid.at("groups", "at least one group is needed".into()));
        }
        let range = |table: &'static str| {
            move |e: crate::range::OutOfRange| invalid.at(&format!("{table}.{}", e.key), e.reason())
        };
        self.tilt.validate().map_err(range("tilt"))?;
        self.lateral.validate().map_err(range("lateral"))?;
        // `[lateral] pushover` chooses the pushover within the lateral load only.
        if self.lateral.pushover && !self.reads_table("lateral") {
            return Err(invalid.at(
                "lateral.pushover",
                format!("pushes the lateral load over: it needs protocol = \"lateral\" (got {:?})", self.protocol),
            ));
        }
        self.solver.validate_static().map_err(range("solver"))?;
        if let Some(name) = self.sweep.keys().find(|k| SweepKey::parse(k).is_ok_and(SweepKey::acts_on_protocol)) {
            return Err(invalid.at(
                &format!("sweep.{name}"),
                "is set by the [shake] table (its motions and pga_g levels), not in [sweep]".into(),
            ));
        }
        for g in &self.groups {
            if let Some(k) = g.overrides.keys().find(|k| SweepKey::parse(k).is_ok_and(SweepKey::acts_on_protocol)) {
                return Err(invalid.at(
                    &format!("groups[{}].overrides.{k}", g.name),
                    "is set by the [shake] table for every group, not per group".into(),
                ));
            }
        }
        // Limit analysis runs beside the other methods too (the shaking study's static
        // capacity), so its table is checked whatever the kind.
        super::solver::check_method(self.loading(), &self.solver).map_err(|(key, why)| invalid.at(&key, why))?;
        if let Some(hand) = &self.tilt.by_hand {
            // What `drystone tilt --by-hand` refuses before it runs, refused before any
            // realization does.
            hand.check_run(self.solver.nscd.dt_s, self.tilt.max_angle_deg).map_err(range("tilt.by_hand"))?;
        }
        Ok(())
    }

    /// Whether the study rolls the tilting table by hand (protocol `tilt` with
    /// `[tilt] by_hand`).
    pub(super) fn rolled_by_hand(&self) -> bool {
        self.reads_table("tilt") && self.tilt.by_hand.is_some()
    }

    /// What the protocol's run would refuse or drop on the group's realization 0,
    /// refused here before any realization runs:
    ///
    /// * ropes under `[solver] kind = "limit"` (`LimitError::Ropes`, as `drystone tilt
    ///   --solver limit` refuses them): limit analysis has no displacement for a rope;
    /// * an effect on a rig's own terms (`jack_tilt`, `rig_friction`, …: [`crate::effects::Step::on_rig`]) in a study of a
    ///   protocol that does not read it
    ///   ([`crate::protocol::LoadingProtocol::READS_VERTICAL_LOAD_RIG`]);
    /// * a table overshoot (`table_kick`) with `[tilt] by_hand`: the hand-rolled table runs
    ///   the kicks of its stops, of which `table_kick` is the quasi-static equivalent; both
    ///   would count them twice, and the hand-rolled run does not read it.
    ///
    /// Each is named by the effect that sets it (the group's own, then the study's), or
    /// else the group's effects.
    fn check_realized(&self, g: &GroupSpec, group: &Group, invalid: &Invalid) -> Result<(), StudyError> {
        let refuses_ropes = !self.solver.kind.method().runs_ropes();
        let by_hand = self.rolled_by_hand();
        let reads_rig = self.loading().reads_vertical_load_rig();
        if group.effects.is_empty() {
            return Ok(());
        }
        if !reads_rig {
            if let Some(e) = group.effects.iter().find(|e| e.def.steps.iter().any(crate::effects::Step::on_rig)) {
                let name = &e.def.name;
                let at = if g.effects.contains_key(name) {
                    format!("groups[{}].effects.{name}", g.name)
                } else {
                    format!("effects.{name}")
                };
                let readers: Vec<crate::protocol::Loading> =
                    crate::protocol::Loading::ALL.into_iter().filter(|l| l.reads_vertical_load_rig()).collect();
                let what: Vec<&str> = readers.iter().map(|l| l.describe()).collect();
                let kinds: Vec<String> =
                    readers.iter().map(|l| format!("protocol = \"{}\"", l.kind().name())).collect();
                return Err(invalid.at(
                    &at,
                    format!(
                        "acts on the vertical load of {} (the force its horizontal actuator reads); {} does not read it (drop the effect, or run the study with {})",
                        what.join(" or "),
                        self.loading().describe(),
                        kinds.join(" or ")
                    ),
                ));
            }
        }
        if !(refuses_ropes || by_hand) {
            return Ok(());
        }
        let Some(wall) = group.walls.first() else { return Ok(()) };
        let Ok((_, layout)) = crate::effects::realize(wall, 0, 0, &g.name, &group.effects) else { return Ok(()) };
        let key = |effect: &str| {
            if g.effects.contains_key(effect) {
                format!("groups[{}].effects.{effect}", g.name)
            } else if self.effects.contains_key(effect) {
                format!("effects.{effect}")
            } else {
                format!("groups[{}].effects", g.name)
            }
        };
        if refuses_ropes && !layout.ropes.is_empty() {
            let e = crate::limit::LimitError::Ropes { count: layout.ropes.len() };
            return Err(invalid.at(&key("end_rope"), e.to_string()));
        }
        if by_hand && layout.table_overshoot_deg != 0.0 {
            return Err(invalid.at(
                &key("table_kick"),
                format!(
                    "sets a table overshoot of {} degrees, the quasi-static equivalent of the kicks of a table \
                     rolled by hand; [tilt] by_hand runs those kicks themselves and does not read it (drop the \
                     effect, or drop by_hand to test the kicks quasi-statically)",
                    layout.table_overshoot_deg
                ),
            ));
        }
        Ok(())
    }

    /// The number of sweep points and work items against the limits of [`size`], before
    /// the grid is built or a wall resolved (`sweep`: the file's `[sweep]` with the
    /// protocol's keys of a shaking study).
    fn check_counts(&self, sweep: &BTreeMap<String, Vec<toml::Value>>, invalid: &Invalid) -> Result<(), StudyError> {
        let points = size::sweep_points(sweep);
        if points > size::MAX_SWEEP_POINTS as f64 {
            let counts: Vec<String> = sweep.iter().map(|(k, v)| format!("{k} ({} values)", v.len())).collect();
            return Err(invalid.at(
                "sweep",
                format!(
                    "{} = {} sweep points; the limit is {} (each point is a wall resolved, a row of summary.csv and a panel of the report)",
                    counts.join(" × "),
                    size::count(points),
                    size::MAX_SWEEP_POINTS
                ),
            ));
        }
        if self.groups.iter().any(|g| g.realizations == Some(0)) {
            return Ok(()); // resolve_group names the group
        }
        let counts: Vec<u64> = self.groups.iter().map(|g| g.realizations.unwrap_or(self.realizations)).collect();
        size::check_items(&counts, points).map_err(|reason| {
            let largest = self.groups.iter().max_by_key(|g| g.realizations.unwrap_or(self.realizations));
            let key = match largest.and_then(|g| g.realizations.map(|_| &g.name)) {
                Some(name) => format!("groups[{name}].realizations"),
                None => "realizations".to_string(),
            };
            invalid.at(&key, reason.to_string())
        })
    }
}

/// The input files of a group: its wall description (or its survey's files) and the
/// distribution files its walls use (at every sweep point).
fn group_files(g: &Group) -> Vec<(InputRole, PathBuf)> {
    // A folder of scanned stones is its mesh files.
    let mut files: Vec<(InputRole, PathBuf)> =
        crate::survey::survey_files(&g.wall_path).into_iter().map(|p| (InputRole::Wall, p)).collect();
    files.extend(g.materials_path.iter().map(|p| (InputRole::Materials, p.clone())));
    for w in &g.walls {
        for d in w.distributions() {
            if !d.source.as_os_str().is_empty() && d.source != g.wall_path {
                files.push((InputRole::Distribution, d.source.clone()));
            }
        }
    }
    files
}

/// One group: its wall description read, its overrides applied, its wall resolved at every
/// sweep point.
fn resolve_group(g: &GroupSpec, dir: &Path, points: &[SweepPoint], invalid: &Invalid) -> Result<Group, StudyError> {
    if g.realizations == Some(0) {
        return Err(invalid.at(&format!("groups[{}].realizations", g.name), "must be at least 1".into()));
    }
    let wall = match (&g.wall, &g.survey) {
        (Some(w), None) => w,
        (None, Some(survey)) => {
            let wall = super::survey::surveyed_wall(g, survey, dir, points, invalid)?;
            return Ok(Group {
                name: g.name.clone(),
                measured_group: g.measured_group.clone().unwrap_or_else(|| g.name.clone()),
                wall_path: dir.join(survey),
                walls: vec![wall; points.len()],
                realizations: g.realizations,
                spec: None,
                effects: vec![],
                materials_path: g.import.as_ref().and_then(|i| i.materials.as_ref()).map(|m| dir.join(m)),
            });
        }
        (Some(_), Some(_)) => {
            return Err(invalid.at(
                &format!("groups[{}]", g.name),
                "names both a wall and a survey: a group is one wall description (wall) or one survey (survey)".into(),
            ))
        }
        (None, None) => {
            return Err(invalid.at(
                &format!("groups[{}]", g.name),
                "names no wall: give wall = a wall description, or survey = a traced elevation".into(),
            ))
        }
    };
    if g.import.is_some() {
        return Err(invalid.at(
            &format!("groups[{}].import", g.name),
            "is for a group naming a survey; this group names a wall description".into(),
        ));
    }
    let wall_path = dir.join(wall);
    let text = std::fs::read_to_string(&wall_path).map_err(|source| {
        invalid.at(&format!("groups[{}].wall", g.name), format!("cannot read {}: {source}", wall_path.display()))
    })?;
    let mut gspec = WallSpec::from_toml(&text, &wall_path).map_err(|e| invalid.wall(&g.name, e))?;
    for (k, v) in &g.overrides {
        let key = format!("groups[{}].overrides.{k}", g.name);
        let value = SweepValue::from_toml(v).ok_or_else(|| invalid.at(&key, format!("{v} is not a number or text")))?;
        SweepKey::parse(k).and_then(|sk| sk.apply(&mut gspec, &value)).map_err(|r| invalid.at(&key, r.to_string()))?;
    }
    let source = DistributionSource::default_for(&wall_path);
    let mut walls: Vec<Wall> = Vec::with_capacity(points.len());
    let mut resolved: BTreeMap<String, usize> = BTreeMap::new();
    for p in points {
        // Points that differ only in the protocol's keys (a shaking study's motion and
        // level) share their wall.
        let label = sweep::wall_label(p);
        if let Some(&j) = resolved.get(&label) {
            walls.push(walls[j].clone());
            continue;
        }
        resolved.insert(label, walls.len());
        let mut spec = gspec.clone();
        for (k, v) in p {
            k.apply(&mut spec, v).map_err(|r| invalid.at(&format!("sweep.{k}"), r.to_string()))?;
        }
        let wall = spec.resolve(&wall_path, &source).map_err(|e| invalid.wall(&g.name, e))?;
        size::check_blocks(&wall).map_err(|reason| invalid.at(&size_key(g, p), reason.to_string()))?;
        walls.push(wall);
    }
    Ok(Group {
        name: g.name.clone(),
        measured_group: g.measured_group.clone().unwrap_or_else(|| g.name.clone()),
        wall_path,
        walls,
        realizations: g.realizations,
        spec: Some(gspec),
        effects: vec![],
        materials_path: None,
    })
}

/// The effects of a group: the study's `effects`, then the group's own (which replace the
/// study's values of the same effect), each checked against the effect's ranges for the
/// group's wall, and applied once to its first layout so that an effect that cannot act
/// on the wall (a joint family it does not have, a rounding that breaks a block) is an
/// error here rather than in every realization.
fn group_effects(
    study: &super::spec::EffectsSpec,
    g: &GroupSpec,
    group: &Group,
    library: &crate::effects::Library,
    invalid: &Invalid,
) -> Result<Vec<crate::effects::Effect>, StudyError> {
    let mut merged: Vec<(String, String, &std::collections::BTreeMap<String, f64>)> = study
        .iter()
        .filter(|(n, _)| !g.effects.contains_key(*n))
        .map(|(n, v)| (format!("effects.{n}"), n.clone(), v))
        .collect();
    merged.extend(g.effects.iter().map(|(n, v)| (format!("groups[{}].effects.{n}", g.name), n.clone(), v)));
    let Some(wall) = group.walls.first() else { return Ok(vec![]) };
    let course_m = crate::effects::course_height_of(wall);
    let mut out = Vec::new();
    for (key, name, values) in &merged {
        out.push(library.from_values(name, values, course_m).map_err(|e| invalid.at(key, e.to_string()))?);
    }
    if !out.is_empty() {
        // Realization 0 of the first sweep point: the effects must be able to act on it.
        if let Err(e) = crate::effects::realize(wall, 0, 0, &g.name, &out) {
            if !matches!(e, crate::effects::EffectError::Generator(_)) {
                let key = merged.first().map_or("effects".to_string(), |m| m.0.clone());
                return Err(invalid.at(&key, e.to_string()));
            }
        }
    }
    Ok(out)
}

/// The key a wall too large for [`size::MAX_BLOCKS`] is blamed on: the sweep's or the
/// group's `length_m` if either sets it, else the group's wall file.
fn size_key(g: &GroupSpec, point: &SweepPoint) -> String {
    let label = super::point_label(point);
    let wall = g.wall.as_deref().unwrap_or(Path::new(""));
    if point.iter().any(|(k, _)| *k == SweepKey::LengthM) {
        format!("groups[{}] at sweep.length_m", g.name)
    } else if g.overrides.contains_key(SweepKey::LengthM.as_str()) {
        format!("groups[{}].overrides.length_m", g.name)
    } else if label.is_empty() {
        format!("groups[{}].wall ({})", g.name, wall.display())
    } else {
        format!("groups[{}].wall ({}) at sweep point {label}", g.name, wall.display())
    }
}

/// Reads the measured data; their files go into `files`.
fn read_measured(
    m: &MeasuredSpec,
    dir: &Path,
    path: &Path,
    files: &mut Vec<(InputRole, PathBuf)>,
) -> Result<Measured, StudyError> {
    Ok(Measured {
        collapse: read_measured_file(&m.collapse, dir, path, files, table::read_measured_collapse)?,
        displacement: read_measured_file(&m.displacement, dir, path, files, table::read_measured_displacement)?,
        mechanism: read_measured_file(&m.mechanism, dir, path, files, table::read_measured_mechanism)?,
        paper_dem: read_measured_file(&m.paper_dem, dir, path, files, table::read_paper_dem)?,
    })
}

/// The rows of the measured file `name` of the study file `path` (relative to `dir`; none:
/// no rows) as `read` reads them; the file goes into `files`.
fn read_measured_file<T>(
    name: &Option<PathBuf>,
    dir: &Path,
    path: &Path,
    files: &mut Vec<(InputRole, PathBuf)>,
    read: fn(&Path) -> Result<Vec<T>, table::TableError>,
) -> Result<Vec<T>, StudyError> {
    let Some(name) = name else { return Ok(Vec::new()) };
    let rows = read(&dir.join(name)).map_err(|source| StudyError::Measured { path: path.to_owned(), source })?;
    files.push((InputRole::Measured, dir.join(name)));
    Ok(rows)
}

impl Study {
    /// What the study warns of before it runs and in its report's "Warnings": the
    /// protocol's (a shaking study's motions that cannot reach its levels), then the inputs
    /// it accepts but does not use ([`Study::read_warnings`]).
    pub fn warnings(&self) -> Vec<String> {
        let mut w = self.protocol.warnings();
        w.extend(self.read_warnings.iter().cloned());
        w
    }

    /// The protocol with its parameters that sweep point `point` runs, as the seam runs it
    /// ([`StudyProtocol::at`] with the point's values; point 0 without a sweep).
    pub fn protocol_at(&self, point: usize) -> crate::protocol::Protocol {
        self.protocol.at(self.points.get(point).map_or(&[], Vec::as_slice))
    }

    /// Reads and resolves a study file.
    ///
    /// # Errors
    /// Any [`StudyError`].
    pub fn from_file(path: &Path) -> Result<Study, StudyError> {
        StudySpec::from_file(path)?.resolve(path)
    }

    /// The protocol with its parameters that group `group` runs at sweep point `point`
    /// ([`StudyProtocol::of_group`]: the in-plane test with the group's vertical stress and
    /// history).
    pub fn protocol_of(&self, group: usize, point: usize) -> crate::protocol::Protocol {
        self.protocol.of_group(group, self.points.get(point).map_or(&[], Vec::as_slice))
    }

    /// All work items of the study.
    pub fn items(&self) -> Vec<crate::ensemble::Item> {
        let counts: Vec<u64> = (0..self.groups.len()).map(|g| self.group_realizations(g)).collect();
        crate::ensemble::items_per_group(&counts, self.points.len())
    }

    /// The wall of group `g` with its overrides and then `values` applied, resolved and
    /// checked.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] for a bad value, [`StudyError::Wall`] if the wall no longer
    /// checks.
    pub fn wall_with(&self, g: usize, values: &[(SweepKey, SweepValue)]) -> Result<Wall, StudyError> {
        let group = &self.groups[g];
        let Some(mut spec) = group.spec.clone() else {
            return Err(StudyError::Invalid {
                path: self.path.clone(),
                key: format!("groups[{}].survey", group.name),
                reason: "a surveyed group's wall has no wall description keys to set".into(),
            });
        };
        for (k, v) in values {
            k.apply(&mut spec, v).map_err(|reason| StudyError::Invalid {
                path: self.path.clone(),
                key: k.as_str().into(),
                reason: reason.to_string(),
            })?;
        }
        let source = DistributionSource::default_for(&group.wall_path);
        spec.resolve(&group.wall_path, &source).map_err(|source| StudyError::Wall {
            path: self.path.clone(),
            group: group.name.clone(),
            source: Box::new(source),
        })
    }

    /// Realizations per sweep point of group `g`: its own count, or the study's.
    pub fn group_realizations(&self, g: usize) -> u64 {
        self.groups[g].realizations.unwrap_or(self.realizations)
    }

    /// The number that sweep key `key` takes at point `point`, if the sweep has it.
    pub fn sweep_number(&self, point: usize, key: SweepKey) -> Option<f64> {
        self.points[point].iter().find(|(k, _)| *k == key).and_then(|(_, v)| v.number())
    }
}
