//! The tilting table's and the lateral load's tables in a study ([`ProtocolTable`] for
//! [`TiltParams`], `[tilt]`, and [`LateralParams`], `[lateral]`): the protocol their table
//! chooses (`tilt.by_hand`, `lateral.pushover`; the same at every sweep point and in every
//! group), the ensemble's report with their sections (`study/report.rs`) and their ParaView
//! series (`study/figures.rs`).

use super::figures::{lateral_series, tilt_series};
use super::protocol_table::ProtocolTable;
use super::report::{ensemble_report, lateral_sections, tilt_sections};
use super::report_error::ReportError;
use super::spec::StudySpec;
use super::summary::{CellSummary, Comparison};
use super::sweep::{SweepKey, SweepValue};
use super::Study;
use crate::ensemble::row::RealizationRow;
use crate::io::series::SeriesError;
use crate::layout::Layout;
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;
use crate::protocol::Protocol;
use std::path::{Path, PathBuf};

impl ProtocolTable for TiltParams {
    fn write_into(&self, spec: &mut StudySpec) {
        spec.tilt = *self;
    }

    fn at(&self, _point: &[(SweepKey, SweepValue)]) -> Protocol {
        Protocol::tilting(*self)
    }

    fn of_group(&self, _group: usize, point: &[(SweepKey, SweepValue)]) -> Protocol {
        self.at(point)
    }

    fn write_report(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
        ensemble_report(study, rows, dir)
    }

    fn report_sections(
        &self,
        study: &Study,
        rows: &[RealizationRow],
        dir: &Path,
        cells: &[CellSummary],
        cmp: &[Comparison],
        md: &mut String,
    ) -> Result<String, ReportError> {
        tilt_sections(study, self, rows, dir, cells, cmp, md).map(|()| String::new())
    }

    fn write_series(
        &self,
        study: &Study,
        _point: usize,
        layout: &Layout,
        out: &Path,
    ) -> Result<Option<PathBuf>, SeriesError> {
        tilt_series(study, self, layout, out)
    }

    fn warnings(&self) -> Vec<String> {
        vec![]
    }

    fn tilt(&self) -> Option<&TiltParams> {
        Some(self)
    }
}

impl ProtocolTable for LateralParams {
    fn write_into(&self, spec: &mut StudySpec) {
        spec.lateral = *self;
    }

    fn at(&self, _point: &[(SweepKey, SweepValue)]) -> Protocol {
        Protocol::lateral(*self)
    }

    fn of_group(&self, _group: usize, point: &[(SweepKey, SweepValue)]) -> Protocol {
        self.at(point)
    }

    fn write_report(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
        ensemble_report(study, rows, dir)
    }

    fn report_sections(
        &self,
        study: &Study,
        _rows: &[RealizationRow],
        _dir: &Path,
        cells: &[CellSummary],
        _cmp: &[Comparison],
        md: &mut String,
    ) -> Result<String, ReportError> {
        lateral_sections(study, self, cells, md);
        Ok(String::new())
    }

    fn write_series(
        &self,
        study: &Study,
        _point: usize,
        layout: &Layout,
        out: &Path,
    ) -> Result<Option<PathBuf>, SeriesError> {
        lateral_series(study, self, layout, out)
    }

    fn warnings(&self) -> Vec<String> {
        vec![]
    }
}
