//! The in-plane study's entry points for `drystone discrepancy` ([`STUDY`]): what it calls
//! to analyse a study file of `protocol = "in_plane"` ([`super::own`]). Its run, shards and
//! merge are the study core's (`drystone run`, `drystone merge`).

use super::inplane::InPlaneStudyError;
use super::inplane_discrepancy::analysis_of;
use super::own::{OwnAnalysis, OwnStudy, OwnStudyError};
use std::path::Path;

/// The in-plane test's discrepancy analysis, as `drystone discrepancy` runs it.
pub const STUDY: OwnStudy = OwnStudy {
    what: "an in-plane study",
    measured: "reads its specimens from [measured] walls",
    analysis: own_analysis,
    held: Some(own_held),
};

fn boxed(e: InPlaneStudyError) -> OwnStudyError {
    OwnStudyError(Box::new(e))
}

fn own_analysis(path: &Path) -> Result<OwnAnalysis, OwnStudyError> {
    analysis_of(path).map_err(boxed)
}

/// The cyclic loops, the reading the analysis's fit does not hold
/// ([`super::inplane_loops::LoopsReading`]).
fn own_held(
    path: &Path,
    input: &OwnAnalysis,
) -> Result<Option<Box<dyn crate::discrepancy::HeldReading>>, OwnStudyError> {
    let reading = super::inplane_loops::LoopsReading::of(path, input).map_err(boxed)?;
    Ok(reading.map(|r| Box::new(r) as Box<dyn crate::discrepancy::HeldReading>))
}
