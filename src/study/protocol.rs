//! A study's protocol with its parameters ([`StudyProtocol`]): the kind the file names and
//! its table together. What a kind declares of its own is data, one [`StudyKind`] constant
//! a kind here (its name, seed index, realizations table, whether its groups differ, what its
//! summary counts, how `drystone discrepancy` analyses it, its table's name, its groups'
//! keys, whether it steps ground motions, its table's former keys and its row of the
//! compatibility table), read through [`StudyProtocol::declared`] or, for a study file not
//! yet resolved, [`StudyKind::of`]. What its table does is the table's own
//! ([`ProtocolTable`], [`StudyProtocol::table`]: the protocol of each sweep point and group,
//! the table written back, the report and its sections, the VTK series, its warnings). The
//! other matches on it here are the table read from the file ([`StudyProtocol::from_spec`]),
//! the row its run fills (a match on [`crate::protocol::ProtocolRun`]; the row functions of
//! [`super::run`], [`super::inplane`] and [`super::compression`]) and the accessors of the
//! tables only one protocol has ([`StudyProtocol::tilt`], [`StudyProtocol::shake`],
//! [`StudyProtocol::in_plane`]): the checks of `[tilt]`, `[shake]` and the sweep keys
//! (`checks.rs`, `resolve.rs`), the paper's comparison and the calibration (which compare
//! collapse angles), the measured data's tilt step. The compiler points to each at a new
//! protocol.

use super::compression::{compression_row, CompressionStudy};
use super::discrepancy::{AnalysisWay, ENSEMBLE};
use super::error::Invalid;
use super::inplane::{in_plane_row, write_rows};
use super::inplane_spec::InPlaneStudy;
use super::motions::ShakeStudy;
use super::protocol_table::ProtocolTable;
use super::report_error::ReportError;
use super::run::{
    failed_row, lateral_row, limit_lateral_row, limit_tilt_row, nscd_pushover_row, pushover_row, shake_row, tilt_row,
};
use super::shards::OutputError;
use super::spec::{ProtocolKind, StudySpec};
use super::summary::{CellSummary, Comparison};
use super::sweep::{SweepKey, SweepValue};
use super::{Study, StudyError};
use crate::ensemble::row::{RealizationRow, Status};
use crate::ensemble::Item;
use crate::io::series::SeriesError;
use crate::layout::Layout;
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;
use crate::protocol::{CompressionRun, LateralRun, Loading, Protocol, ProtocolRun, PushoverRun, RunOutcome, TiltRun};
use std::path::{Path, PathBuf};

/// A study's protocol with its parameters: the kind and its table together, so that every
/// consumer matches on one value (a new protocol is pointed to by the compiler at each).
#[derive(Debug, Clone)]
pub enum StudyProtocol {
    /// The tilting table (`protocol = "tilt"`, its `[tilt]` table).
    Tilt(TiltParams),
    /// The static lateral load, or its pushover (`protocol = "lateral"`, `[lateral]`).
    Lateral(LateralParams),
    /// The shaking table (`protocol = "shake"`, `[shake]`): its parameters, motions and
    /// levels.
    Shake(ShakeStudy),
    /// The in-plane shear–compression test (`protocol = "in_plane"`, `[in_plane]` and each
    /// group's `sigma0_mpa`, `history`, `specimens`): its parameters and measured specimens.
    InPlane(InPlaneStudy),
    /// The vertical compression test (`protocol = "compression"`, `[compression]` and each
    /// group's `sigma0_mpa`).
    Compression(CompressionStudy),
}

impl StudyProtocol {
    /// The protocol a study file names, with its table (`shake`: the `[shake]` table already
    /// resolved, [`StudySpec::resolve_shake`]; `in_plane`: the in-plane test already resolved,
    /// [`StudySpec::resolve_in_plane`]), without the table's former keys of the penalty
    /// settings (the resolved study's solver holds them).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] naming the table a protocol needs and the file lacks.
    pub(super) fn from_spec(
        spec: &StudySpec,
        shake: Option<ShakeStudy>,
        in_plane: Option<InPlaneStudy>,
        compression: Option<CompressionStudy>,
        invalid: &Invalid,
    ) -> Result<StudyProtocol, StudyError> {
        match (spec.protocol, shake) {
            (ProtocolKind::Tilt, _) => Ok(StudyProtocol::Tilt(spec.tilt.without_moved())),
            (ProtocolKind::Lateral, _) => Ok(StudyProtocol::Lateral(spec.lateral.without_moved())),
            (ProtocolKind::Shake, Some(mut shake)) => {
                shake.params = shake.params.without_moved();
                Ok(StudyProtocol::Shake(shake))
            }
            (ProtocolKind::Shake, None) => {
                Err(invalid.at("shake", "protocol = \"shake\" needs a [shake] table".into()))
            }
            (ProtocolKind::InPlane, _) => in_plane.map(StudyProtocol::InPlane).ok_or_else(|| {
                invalid.at("protocol", "protocol = \"in_plane\": the in-plane test was not resolved".into())
            }),
            (ProtocolKind::Compression, _) => compression.map(StudyProtocol::Compression).ok_or_else(|| {
                invalid.at("protocol", "protocol = \"compression\": the compression test was not resolved".into())
            }),
        }
    }

    /// Its table written back into a study file (`drystone discrepancy`'s extended study):
    /// the kind and the tilting table's or the lateral load's parameters, or the in-plane
    /// test's with each group's values (`spec.groups` in the study's order). A shaking
    /// study's motions are not written (the analysis refuses the shaking table).
    pub(super) fn write_into(&self, spec: &mut StudySpec) {
        spec.protocol = self.kind();
        self.table().write_into(spec);
    }

    /// Its table ([`ProtocolTable`]: the kind's parameters as the study resolved them), the
    /// one match on the kind for the questions whose answer is its table's.
    pub fn table(&self) -> &dyn ProtocolTable {
        match self {
            StudyProtocol::Tilt(t) => t,
            StudyProtocol::Lateral(l) => l,
            StudyProtocol::Shake(s) => s,
            StudyProtocol::InPlane(p) => p,
            StudyProtocol::Compression(c) => c,
        }
    }

    /// What its kind declares of its own ([`StudyKind`]): the one match on the kind for
    /// the questions whose answer is the kind's alone, not its table's.
    pub fn declared(&self) -> &'static StudyKind {
        match self {
            StudyProtocol::Tilt(_) => &TILT,
            StudyProtocol::Lateral(_) => &LATERAL,
            StudyProtocol::Shake(_) => &SHAKE,
            StudyProtocol::InPlane(_) => &IN_PLANE,
            StudyProtocol::Compression(_) => &COMPRESSION,
        }
    }

    /// Its kind, as the study file names it ([`StudyKind::kind`]).
    pub fn kind(&self) -> ProtocolKind {
        self.declared().kind
    }

    /// Its name in study files (`protocol = "..."`), as the protocol seam names it
    /// ([`Protocol::name`]).
    pub fn name(&self) -> &'static str {
        self.at(&[]).name()
    }

    /// Its row of the compatibility table ([`crate::protocol::methods`]), with the variant
    /// its table chooses (`tilt.by_hand`, `lateral.pushover`): its protocol's
    /// ([`Protocol::loading`]).
    pub fn loading(&self) -> Loading {
        self.at(&[]).loading()
    }

    /// The protocol group `group` runs at a sweep point with the values `point`: the
    /// protocol at the point ([`StudyProtocol::at`]), with the in-plane test's group values
    /// (its vertical stress and history).
    pub fn of_group(&self, group: usize, point: &[(SweepKey, SweepValue)]) -> Protocol {
        self.table().of_group(group, point)
    }

    /// The protocol run at a sweep point with the values `point`: the tilting table or the
    /// lateral load with the study's parameters, or the shaking table under the point's
    /// motion scaled to its PGA level (sweep keys `motion` and `pga_g`), or the in-plane test
    /// with its first group's values ([`StudyProtocol::of_group`] gives each group's). A
    /// shaking point whose motion is missing (a study not made by [`StudySpec::resolve`])
    /// gets an empty motion, which the protocol refuses with an error row.
    pub fn at(&self, point: &[(SweepKey, SweepValue)]) -> Protocol {
        self.table().at(point)
    }

    /// A realization's row (`row`: its identification and block count) filled with what its
    /// run of item `item` on `layout` gave: one row function per kind of run
    /// ([`super::run`]; the in-plane test's [`super::inplane::in_plane_row`], with limit
    /// analysis of `layout` beside it), an error as a status row.
    pub(super) fn row(
        &self,
        study: &Study,
        item: &Item,
        layout: &Layout,
        row: RealizationRow,
        run: ProtocolRun,
    ) -> RealizationRow {
        let failure = Status::of_failure(run.does_not_stand(), run.refused());
        let error = run.error().unwrap_or_default();
        match run {
            ProtocolRun::Tilt(TiltRun::Penalty(Ok(t)) | TiltRun::Nscd(Ok(t))) | ProtocolRun::TiltByHand(Ok(t)) => {
                tilt_row(row, t)
            }
            ProtocolRun::Tilt(TiltRun::Limit(Ok(r))) => limit_tilt_row(row, r),
            ProtocolRun::Lateral(LateralRun::Limit(Ok(r))) => limit_lateral_row(row, r, false),
            ProtocolRun::Pushover(PushoverRun::Limit(Ok(r))) => limit_lateral_row(row, r, true),
            ProtocolRun::Lateral(LateralRun::Penalty(Ok(r))) => lateral_row(row, r),
            ProtocolRun::Pushover(PushoverRun::Penalty { service: Ok(r), collapse }) => {
                pushover_row(lateral_row(row, r), collapse.map(|c| *c))
            }
            ProtocolRun::Pushover(PushoverRun::Nscd(Ok(r))) => nscd_pushover_row(row, r),
            ProtocolRun::Compression(CompressionRun::Penalty(Ok(r))) => compression_row(row, r),
            ProtocolRun::Shake(Ok(r)) => shake_row(row, r, study.sweep_number(item.point, SweepKey::PgaG)),
            ProtocolRun::InPlane(r) => match self.in_plane() {
                Some(test) => in_plane_row(row, r, failure, layout, &test.params_of(item.group), study.solver),
                None => failed_row(row, Status::BlewUp, &"an in-plane run of a study of another protocol"),
            },
            ProtocolRun::Tilt(TiltRun::Penalty(Err(_)) | TiltRun::Nscd(Err(_)) | TiltRun::Limit(Err(_)))
            | ProtocolRun::TiltByHand(Err(_))
            | ProtocolRun::Lateral(LateralRun::Penalty(Err(_)) | LateralRun::Limit(Err(_)))
            | ProtocolRun::Pushover(
                PushoverRun::Penalty { service: Err(_), .. } | PushoverRun::Nscd(Err(_)) | PushoverRun::Limit(Err(_)),
            )
            | ProtocolRun::Shake(Err(_))
            | ProtocolRun::Compression(CompressionRun::Penalty(Err(_)))
            | ProtocolRun::Unsupported(_) => failed_row(row, failure, &error),
        }
    }

    /// The seed index of item `item`: the index its layout is generated with
    /// ([`crate::effects::realize`], with the study's seed). The realization's index in its
    /// group, but for the in-plane test's `g · 10000 + i` (group g, realization i), the
    /// index its studies have always used.
    pub fn seed_index(&self, item: &Item) -> u64 {
        (self.declared().seed_index)(item)
    }

    /// Writes the realizations table of `rows` into `dir`: `realizations.parquet` with every
    /// column (what `drystone merge` reads back) and `realizations.csv`, the core's columns
    /// ([`crate::io::table::write_realizations`]) or the in-plane test's
    /// ([`super::inplane::write_rows`]).
    ///
    /// # Errors
    /// [`OutputError`] naming the file.
    pub(super) fn write_rows(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<(), OutputError> {
        (self.declared().write_rows)(study, rows, dir)
    }

    /// Writes the report of a whole study's `rows` into `dir` and returns what `drystone
    /// run` prints of it: the ensemble's (`summary.csv` of its cells, [`report_sections`],
    /// [`super::report::ensemble_report`]), or the in-plane test's (`summary.csv` per
    /// observable, `comparison.csv` with the measured specimens, its figures,
    /// [`super::inplane_report::report`]).
    ///
    /// [`report_sections`]: StudyProtocol::report_sections
    ///
    /// # Errors
    /// [`ReportError`] naming the file.
    pub(super) fn write_report(
        &self,
        study: &Study,
        rows: &[RealizationRow],
        dir: &Path,
    ) -> Result<String, ReportError> {
        self.table().write_report(study, rows, dir)
    }

    /// Its sections of the report (`report.md`, with their plots in `dir`); returns what
    /// `drystone run` prints of them.
    ///
    /// # Errors
    /// [`ReportError`] naming the file.
    pub(super) fn report_sections(
        &self,
        study: &Study,
        rows: &[RealizationRow],
        dir: &Path,
        cells: &[CellSummary],
        cmp: &[Comparison],
        md: &mut String,
    ) -> Result<String, ReportError> {
        self.table().report_sections(study, rows, dir, cells, cmp, md)
    }

    /// The ParaView time series of one realization (`layout`, at sweep point `point`), run
    /// again with the recording on, into `out`; `None` if the run fails.
    ///
    /// # Errors
    /// [`SeriesError`] naming the file that could not be written.
    pub(super) fn write_series(
        &self,
        study: &Study,
        point: usize,
        layout: &Layout,
        out: &Path,
    ) -> Result<Option<PathBuf>, SeriesError> {
        self.table().write_series(study, point, layout, out)
    }

    /// What the study warns of before it runs and in its report (a shaking study's motions
    /// that cannot reach its levels).
    pub fn warnings(&self) -> Vec<String> {
        self.table().warnings()
    }

    /// Whether its summary counts the walls that collapsed under the load (the lateral
    /// load: a collapse is an outcome of the service load, not a collapse angle).
    pub fn counts_collapses_under_load(&self) -> bool {
        self.declared().counts_collapses_under_load
    }

    /// The tilting table's parameters, for a tilting-table study.
    pub fn tilt(&self) -> Option<&TiltParams> {
        self.table().tilt()
    }

    /// The shaking table's parameters, motions and levels, for a shaking study.
    pub fn shake(&self) -> Option<&ShakeStudy> {
        self.table().shake()
    }

    /// The protocol of group `group` where the groups' protocols differ (the in-plane test:
    /// each group's vertical stress and history), for the discrepancy analysis's groups
    /// ([`crate::discrepancy::GroupSetup::protocol`]); `None` where every group runs the
    /// study's.
    pub fn group_protocol(&self, group: usize) -> Option<Protocol> {
        self.declared().groups_differ.then(|| self.of_group(group, &[]))
    }

    /// How `drystone discrepancy` analyses a study of this protocol ([`AnalysisWay`]: its
    /// study read into the analysis's groups, observations, settings and library, where it
    /// reads its measured data, its reading the fit does not hold, whether a named cause is
    /// written as an extended study; [`StudyKind::analysis`]): the ensemble's
    /// ([`ENSEMBLE`]), or the in-plane test's. The command's one path runs it
    /// ([`super::discrepancy`]).
    pub fn analysis(&self) -> AnalysisWay {
        self.declared().analysis
    }

    /// The in-plane test's parameters, groups and measured specimens, for an in-plane study.
    pub fn in_plane(&self) -> Option<&InPlaneStudy> {
        self.table().in_plane()
    }
}

/// What a protocol's study declares of its own, as data: one constant a kind (`TILT`,
/// `LATERAL`, `SHAKE`, `IN_PLANE`, `COMPRESSION` in `study/protocol.rs`), read through
/// [`StudyProtocol::declared`]. A new kind states each answer once (the compiler asks for
/// every field), and no caller matches on the kind to ask it.
#[derive(Debug, Clone, Copy)]
pub struct StudyKind {
    /// The kind, as the study file names it (`protocol = "..."`).
    pub kind: ProtocolKind,
    /// The seed index of a work item ([`StudyProtocol::seed_index`]): the realization's
    /// index in its group, or the in-plane test's `g · 10000 + i`.
    pub seed_index: fn(&Item) -> u64,
    /// Writes the realizations table of the rows into the directory: the core's columns
    /// (`realizations.parquet` and `realizations.csv`), or the in-plane test's own
    /// `realizations.csv` beside the parquet table.
    ///
    /// # Errors
    /// [`OutputError`] naming the file.
    pub write_rows: fn(&Study, &[RealizationRow], &Path) -> Result<(), OutputError>,
    /// Whether its groups run protocols of their own (the in-plane test's and the
    /// compression test's vertical stress a group), which the discrepancy analysis's
    /// groups carry ([`StudyProtocol::group_protocol`]).
    pub groups_differ: bool,
    /// Whether its summary counts the walls that collapsed under the load
    /// ([`StudyProtocol::counts_collapses_under_load`]): the lateral load's.
    pub counts_collapses_under_load: bool,
    /// How `drystone discrepancy` analyses its studies ([`StudyProtocol::analysis`]).
    pub analysis: AnalysisWay,
    /// Its parameters table in a study file (`tilt` for `[tilt]`): a study of another kind
    /// refuses it, or warns that it is not read (`StudySpec::reads_table`).
    pub table: &'static str,
    /// The keys of its own it reads in a study file's groups (`[[groups]] sigma0_mpa`):
    /// a study of a kind that does not list one refuses it in a group.
    pub group_keys: &'static [&'static str],
    /// Whether its runs step ground motions (the shaking table): nscd's steps of motion
    /// (`solver.nscd.rest`, `step_solver`, `natural_tolerance`, `apgd_after_solves`) and
    /// `solver.nscd.dt_s`, at which its pulses are sampled whatever the method, are read.
    pub ground_motions: bool,
    /// The penalty settings its table writes under their former keys (deprecated;
    /// [`crate::dem::MovedKey`]; `StudySpec::moved_keys`).
    pub moved: fn(&StudySpec) -> Vec<crate::dem::MovedKey>,
    /// Its row of the compatibility table with the variant its table chooses
    /// (`tilt.by_hand`, `lateral.pushover`; [`StudySpec::loading`]).
    pub loading: fn(&StudySpec) -> Loading,
}

impl StudyKind {
    /// What kind `kind` declares: the one match on the kind for a study file not yet
    /// resolved ([`StudySpec::declared`]).
    pub fn of(kind: ProtocolKind) -> &'static StudyKind {
        match kind {
            ProtocolKind::Tilt => &TILT,
            ProtocolKind::Lateral => &LATERAL,
            ProtocolKind::Shake => &SHAKE,
            ProtocolKind::InPlane => &IN_PLANE,
            ProtocolKind::Compression => &COMPRESSION,
        }
    }
}

/// The tilting table's study (`protocol = "tilt"`).
const TILT: StudyKind = StudyKind {
    kind: ProtocolKind::Tilt,
    seed_index: realization_index,
    write_rows: core_rows,
    groups_differ: false,
    counts_collapses_under_load: false,
    analysis: ENSEMBLE,
    table: "tilt",
    group_keys: &[],
    ground_motions: false,
    moved: |spec| spec.tilt.moved(),
    loading: |spec| Protocol::tilting(spec.tilt).loading(),
};

/// The lateral load's study (`protocol = "lateral"`, or its pushover): its summary counts
/// the walls that collapsed under the service load.
const LATERAL: StudyKind = StudyKind {
    kind: ProtocolKind::Lateral,
    seed_index: realization_index,
    write_rows: core_rows,
    groups_differ: false,
    counts_collapses_under_load: true,
    analysis: ENSEMBLE,
    table: "lateral",
    group_keys: &[],
    ground_motions: false,
    moved: |spec| spec.lateral.moved(),
    loading: |spec| Protocol::lateral(spec.lateral).loading(),
};

/// The shaking table's study (`protocol = "shake"`).
const SHAKE: StudyKind = StudyKind {
    kind: ProtocolKind::Shake,
    seed_index: realization_index,
    write_rows: core_rows,
    groups_differ: false,
    counts_collapses_under_load: false,
    analysis: ENSEMBLE,
    table: "shake",
    group_keys: &[],
    ground_motions: true,
    moved: |spec| spec.shake.as_ref().map(|s| s.params().moved()).unwrap_or_default(),
    loading: |_| Loading::Shake,
};

/// The in-plane test's study (`protocol = "in_plane"`): its seed index, its own
/// `realizations.csv`, a protocol a group, its own analysis (`IN_PLANE_ANALYSIS`).
const IN_PLANE: StudyKind = StudyKind {
    kind: ProtocolKind::InPlane,
    seed_index: group_stride_index,
    write_rows: in_plane_rows,
    groups_differ: true,
    counts_collapses_under_load: false,
    analysis: IN_PLANE_ANALYSIS,
    table: "in_plane",
    group_keys: &["sigma0_mpa", "history", "specimens"],
    ground_motions: false,
    moved: |_| Vec::new(),
    loading: |_| Loading::InPlane,
};

/// The compression test's study (`protocol = "compression"`): a protocol a group (its
/// vertical stress).
const COMPRESSION: StudyKind = StudyKind {
    kind: ProtocolKind::Compression,
    seed_index: realization_index,
    write_rows: core_rows,
    groups_differ: true,
    counts_collapses_under_load: false,
    analysis: ENSEMBLE,
    table: "compression",
    group_keys: &["sigma0_mpa"],
    ground_motions: false,
    moved: |_| Vec::new(),
    loading: |_| Loading::Compression,
};

/// The seed index of an item: its realization's index in its group.
fn realization_index(item: &Item) -> u64 {
    item.realization
}

/// The in-plane test's seed index of an item, `g · 10000 + i` (group g, realization i), the
/// index its studies have always used.
fn group_stride_index(item: &Item) -> u64 {
    item.group as u64 * 10_000 + item.realization
}

/// Writes the realizations table of `rows` into `dir` with the core's columns
/// ([`crate::io::table::write_realizations`]: `realizations.parquet` and
/// `realizations.csv`).
///
/// # Errors
/// [`OutputError`] naming the file.
fn core_rows(_study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<(), OutputError> {
    Ok(crate::io::table::write_realizations(rows, dir)?)
}

/// Writes the in-plane test's realizations table of `rows` into `dir`:
/// `realizations.parquet` with every column and its own `realizations.csv`
/// ([`super::inplane::write_rows`]).
///
/// # Errors
/// [`OutputError`] naming the file.
fn in_plane_rows(study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<(), OutputError> {
    crate::io::table::write_realizations_parquet(rows, dir)?;
    Ok(write_rows(study, rows, dir)?)
}

/// The in-plane test's analysis ([`StudyProtocol::analysis`]): its stresses as the
/// analysis's groups and its specimens as observations
/// ([`super::inplane_discrepancy::analysis_of`]), its cyclic loops as the reading the fit
/// does not hold ([`super::inplane_loops::LoopsReading::held`]); its measured data the
/// `[measured] walls` table (the tilting table's files of `--measured` refused), no extended
/// study (its analysis's groups are stresses, not the study's groups).
const IN_PLANE_ANALYSIS: AnalysisWay = AnalysisWay {
    measured_elsewhere: Some("an in-plane study reads its specimens from [measured] walls"),
    input: super::inplane_discrepancy::analysis_of,
    held: Some(super::inplane_loops::LoopsReading::held),
    extends: false,
};

impl StudySpec {
    /// What the study's kind declares ([`StudyKind::of`]).
    pub fn declared(&self) -> &'static StudyKind {
        StudyKind::of(self.protocol)
    }

    /// Whether the study's kind reads the parameters table `table` (`"tilt"` for `[tilt]`):
    /// it is its own ([`StudyKind::table`]).
    pub(super) fn reads_table(&self, table: &str) -> bool {
        self.declared().table == table
    }

    /// The penalty settings the study's protocol table writes under their former keys
    /// (deprecated; [`crate::dem::MovedKey`]), with the table's name. Only the table of
    /// the study's protocol is read.
    pub(super) fn moved_keys(&self) -> (&'static str, Vec<crate::dem::MovedKey>) {
        let kind = self.declared();
        (kind.table, (kind.moved)(self))
    }

    /// The study's row of the compatibility table ([`crate::protocol::methods`]): its
    /// protocol with the variant its tables choose (`tilt.by_hand`, `lateral.pushover`).
    pub fn loading(&self) -> Loading {
        (self.declared().loading)(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each kind's constant names its own kind, every kind has one, and the answers each
    /// states are the protocol's: the in-plane test's seed index `g · 10000 + i`, the lateral
    /// load's count of collapses under the load, the
    /// in-plane and compression tests' protocol a group, the in-plane test's own analysis
    /// (refusing the tilting table's files, no extended study), every other kind's the
    /// ensemble's.
    #[test]
    fn each_kind_states_its_own_answers_once() {
        let kinds = [&TILT, &LATERAL, &SHAKE, &IN_PLANE, &COMPRESSION];
        assert_eq!(kinds.map(|k| k.kind), ProtocolKind::ALL);
        let item = Item { group: 3, point: 0, realization: 5, index: 0 };
        for k in kinds {
            let in_plane = k.kind == ProtocolKind::InPlane;
            assert_eq!((k.seed_index)(&item), if in_plane { 30_005 } else { 5 }, "{:?}", k.kind);
            assert_eq!(k.counts_collapses_under_load, k.kind == ProtocolKind::Lateral, "{:?}", k.kind);
            let per_group = matches!(k.kind, ProtocolKind::InPlane | ProtocolKind::Compression);
            assert_eq!(k.groups_differ, per_group, "{:?}", k.kind);
            assert_eq!(k.analysis.measured_elsewhere.is_some(), in_plane, "{:?}", k.kind);
            assert_eq!(k.analysis.held.is_some(), in_plane, "{:?}", k.kind);
            assert_eq!(k.analysis.extends, !in_plane, "{:?}", k.kind);
            assert!(std::ptr::eq(StudyKind::of(k.kind), k), "{:?}", k.kind);
            // Each kind's table is named as the kind; only the shaking table steps motions.
            assert_eq!(k.table, k.kind.name());
            assert_eq!(k.ground_motions, k.kind == ProtocolKind::Shake, "{:?}", k.kind);
            let sigma0 = k.group_keys.contains(&"sigma0_mpa");
            assert_eq!(sigma0, per_group, "{:?}", k.kind);
            assert_eq!(k.group_keys.contains(&"history"), in_plane, "{:?}", k.kind);
            assert_eq!(k.group_keys.contains(&"specimens"), in_plane, "{:?}", k.kind);
        }
    }

    /// A study file of each kind, as written: its row of the compatibility table is its
    /// kind's first, or the one its table chooses (`[tilt] by_hand`, `[lateral] pushover`);
    /// its former keys are read from its own table only.
    #[test]
    fn each_kind_reads_its_row_and_former_keys_from_its_own_table() {
        let file = |kind: &str, tables: &str| -> StudySpec {
            toml::from_str(&format!(
                "version = 1\nname = \"x\"\nseed = 1\nrealizations = 1\nprotocol = \"{kind}\"\n{tables}\n\
                 [[groups]]\nname = \"g\"\nwall = \"w.toml\"\n"
            ))
            .unwrap()
        };
        for kind in ProtocolKind::ALL {
            let spec = file(kind.name(), "");
            assert_eq!(spec.loading(), kind.loadings()[0], "{kind}");
            assert_eq!(spec.moved_keys(), (kind.name(), vec![]), "{kind}");
            // The tilting table's former key is read by the tilting table alone.
            let moved = file(kind.name(), "[tilt]\nmax_steps_per_increment = 100");
            assert_eq!(moved.moved_keys().1.is_empty(), kind != ProtocolKind::Tilt, "{kind}");
        }
        assert_eq!(file("tilt", "[tilt.by_hand]").loading(), Loading::TiltByHand);
        assert_eq!(file("lateral", "[lateral]\npushover = true").loading(), Loading::Pushover);
        assert_eq!(file("shake", "[lateral]\npushover = true").loading(), Loading::Shake);
    }
}
