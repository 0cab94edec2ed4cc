//! An in-plane study as its discrepancy analysis reads it ([`Prepared`]): the study read by
//! the core ([`Study::from_file`]) with its in-plane test. Its run, journal, resume, shards,
//! merge and manifest are the study core's ([`super::run_into`], [`super::merge`]), its rows
//! [`super::inplane`]'s and its report [`super::inplane_report`]'s.

use super::inplane::InPlaneStudyError;
use super::inplane_spec::InPlaneStudy;
use super::Study;

/// An in-plane study: the study (read by the core, [`Study::from_file`]) and its in-plane
/// test.
pub(super) struct Prepared<'a> {
    /// The study: its groups' walls and effects, seed, realizations, solver and inputs.
    pub study: &'a Study,
    /// Its in-plane test: the parameters, each group's values, the measured specimens.
    pub test: &'a InPlaneStudy,
}

impl<'a> Prepared<'a> {
    /// The in-plane study `study`.
    ///
    /// # Errors
    /// [`InPlaneStudyError::Invalid`] at `protocol` for a study of another protocol.
    pub fn of(study: &'a Study) -> Result<Prepared<'a>, InPlaneStudyError> {
        let test = study.protocol.in_plane().ok_or_else(|| InPlaneStudyError::Invalid {
            path: study.path.clone(),
            key: "protocol".into(),
            message: format!("{:?}: this run is the in-plane test's (protocol = \"in_plane\")", study.protocol.name()),
        })?;
        Ok(Prepared { study, test })
    }
}
