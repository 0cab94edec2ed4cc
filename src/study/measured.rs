//! The measured data of a study checked against the study itself
//! ([`crate::io::measured::check_against_study`]): displacement tilts on the study's tilt
//! grid, displacements within the height of the group's wall, none beyond the specimen's
//! collapse angle, one group per specimen; observed mechanisms of the study's groups and of
//! specimens the other files know.

use super::Study;
use crate::io::measured::{check_against_study, check_mechanism_against_study, StudyContext};
use crate::io::table::TableError;

impl Study {
    /// What the measured data are checked against: each group's measured-group name with
    /// the height of its tallest wall over the sweep (m), and the tilt step of a
    /// tilting-table study.
    pub fn measured_context(&self) -> StudyContext {
        StudyContext {
            groups: self
                .groups
                .iter()
                .map(|g| (g.measured_group.clone(), g.walls.iter().map(|w| w.height).fold(0.0, f64::max)))
                .collect(),
            step_deg: self.protocol.tilt().map(|t| t.step_deg),
        }
    }

    /// Checks the study's measured data against the study (see
    /// [`crate::io::measured`]); run when the study is resolved and when `discrepancy
    /// --measured` replaces the data.
    ///
    /// # Errors
    /// [`TableError::Value`] naming the file, the line and the column.
    pub fn check_measured(&self) -> Result<(), TableError> {
        let (c, d) = (&self.measured.collapse, &self.measured.displacement);
        check_against_study(c, d, &self.measured_context())?;
        check_mechanism_against_study(&self.measured.mechanism, c, d, &self.measured_context())
    }
}
