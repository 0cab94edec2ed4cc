//! What a protocol's table does in a study, behind one trait ([`ProtocolTable`]): each
//! kind's table (the tilting table's and the lateral load's parameters,
//! `study/static_tables.rs`; the shaking table's motions and levels, `study/shaking.rs`;
//! the in-plane test's groups and specimens, `study/inplane.rs`; the compression test's
//! stresses, `study/compression.rs`) answers for itself, and
//! [`super::StudyProtocol::table`] is the one match that hands a study's table over.
//! A method has no default, but the accessors of the tables only one kind has
//! ([`ProtocolTable::tilt`], [`ProtocolTable::shake`], [`ProtocolTable::in_plane`], `None`
//! unless the kind's own): a new kind's table states every answer (the compiler asks for
//! each).

use super::inplane_spec::InPlaneStudy;
use super::motions::ShakeStudy;
use super::report_error::ReportError;
use super::spec::StudySpec;
use super::summary::{CellSummary, Comparison};
use super::sweep::{SweepKey, SweepValue};
use super::Study;
use crate::ensemble::row::RealizationRow;
use crate::io::series::SeriesError;
use crate::layout::Layout;
use crate::loading::tilt::TiltParams;
use crate::protocol::Protocol;
use std::path::{Path, PathBuf};

/// A study's protocol table (the kind's parameters as the study file gives them, resolved):
/// what the study asks of it, whichever kind it is.
pub trait ProtocolTable {
    /// Writes the table back into `spec` (`drystone discrepancy`'s extended study): its
    /// parameters table, and each group's values where it has some (`spec.groups` in the
    /// study's order). The kind (`protocol = "..."`) is written by the caller.
    fn write_into(&self, spec: &mut StudySpec);

    /// The protocol run at a sweep point with the values `point` (its keys and values, as
    /// [`super::Study::protocol_at`] gives them).
    fn at(&self, point: &[(SweepKey, SweepValue)]) -> Protocol;

    /// The protocol group `group` (its index in the study's groups) runs at a sweep point
    /// with the values `point`: [`ProtocolTable::at`], with the group's own values where
    /// its groups differ (a vertical stress).
    fn of_group(&self, group: usize, point: &[(SweepKey, SweepValue)]) -> Protocol;

    /// Writes the report of a whole study's `rows` into `dir` (`summary.csv`, `report.md`
    /// and their figures) and returns what `drystone run` prints of it.
    ///
    /// # Errors
    /// [`ReportError`] naming the file.
    fn write_report(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError>;

    /// Appends its sections of the ensemble's report to `md` (their plots written into
    /// `dir`; `cells` the summary's cells, `cmp` the comparison with the measured data) and
    /// returns what `drystone run` prints of them.
    ///
    /// # Errors
    /// [`ReportError`] naming the file.
    fn report_sections(
        &self,
        study: &Study,
        rows: &[RealizationRow],
        dir: &Path,
        cells: &[CellSummary],
        cmp: &[Comparison],
        md: &mut String,
    ) -> Result<String, ReportError>;

    /// The ParaView time series of one realization (`layout`, at sweep point index `point`),
    /// run again with the recording on, into `out`; `None` if the run fails or the protocol
    /// records none.
    ///
    /// # Errors
    /// [`SeriesError`] naming the file that could not be written.
    fn write_series(
        &self,
        study: &Study,
        point: usize,
        layout: &Layout,
        out: &Path,
    ) -> Result<Option<PathBuf>, SeriesError>;

    /// What the study warns of before it runs and in its report (a shaking study's motions
    /// that cannot reach its levels); empty for none.
    fn warnings(&self) -> Vec<String>;

    /// The tilting table's parameters, for a tilting-table study (`None` for another).
    fn tilt(&self) -> Option<&TiltParams> {
        None
    }

    /// The shaking table's parameters, motions and levels, for a shaking study (`None` for
    /// another).
    fn shake(&self) -> Option<&ShakeStudy> {
        None
    }

    /// The in-plane test's parameters, groups and measured specimens, for an in-plane study
    /// (`None` for another).
    fn in_plane(&self) -> Option<&InPlaneStudy> {
        None
    }
}
