//! The in-plane study's entry points ([`STUDY`]): what `drystone run` and `drystone
//! discrepancy` call to run and analyse a study file of `protocol = "in_plane"`
//! ([`super::own`]).

use super::inplane::{load, run, InPlaneStudyError};
use super::inplane_discrepancy::analysis_of;
use super::own::{OwnAnalysis, OwnStudy, OwnStudyError, OwnStudyRun};
use std::path::Path;

/// The in-plane test's study of its own, as `drystone run` and `drystone discrepancy` run
/// and analyse it.
pub const STUDY: OwnStudy = OwnStudy {
    kind: crate::protocol::ProtocolKind::InPlane,
    what: "an in-plane study",
    doc: "docs/inplane.md",
    measured: "reads its specimens from [measured] walls",
    name: own_name,
    run: own_run,
    analysis: own_analysis,
};

fn boxed(e: InPlaneStudyError) -> OwnStudyError {
    OwnStudyError(Box::new(e))
}

fn own_name(path: &Path) -> Result<String, OwnStudyError> {
    load(path).map(|s| s.name).map_err(boxed)
}

fn own_run(path: &Path, out: &Path) -> Result<OwnStudyRun, OwnStudyError> {
    let run = run(path, out).map_err(boxed)?;
    Ok(OwnStudyRun {
        realizations: run.rows.len(),
        failed: run.rows.iter().filter(|r| r.status != "ok").count(),
        wall_time_s: run.wall_time_s,
    })
}

fn own_analysis(path: &Path) -> Result<OwnAnalysis, OwnStudyError> {
    analysis_of(path).map_err(boxed)
}
