//! The in-plane study's entry points ([`STUDY`]): what `drystone run` and `drystone
//! discrepancy` call to run and analyse a study file of `protocol = "in_plane"`
//! ([`super::own`]).

use super::inplane::{InPlaneStudyError, InPlaneStudyRun};
use super::inplane_discrepancy::analysis_of;
use super::inplane_run::{is_in_plane_shard, merge, run_study_into};
use super::own::{OwnAnalysis, OwnStudy, OwnStudyError, OwnStudyRun};
use std::path::Path;

/// The in-plane test's study of its own, as `drystone run` and `drystone discrepancy` run
/// and analyse it.
pub const STUDY: OwnStudy = OwnStudy {
    kind: crate::protocol::ProtocolKind::InPlane,
    what: "an in-plane study",
    doc: "docs/inplane.md",
    measured: "reads its specimens from [measured] walls",
    run: own_run,
    merge: own_merge,
    is_shard: is_in_plane_shard,
    analysis: own_analysis,
    held: Some(own_held),
};

fn boxed(e: InPlaneStudyError) -> OwnStudyError {
    OwnStudyError(Box::new(e))
}

fn own_run(
    study: &super::Study,
    out: &Path,
    shard: crate::ensemble::Shard,
    mode: super::RunMode,
) -> Result<OwnStudyRun, OwnStudyError> {
    run_study_into(study, out, shard, mode).map(|r| counts(&r)).map_err(boxed)
}

fn own_merge(dirs: &[std::path::PathBuf], out: &Path) -> Result<OwnStudyRun, OwnStudyError> {
    merge(dirs, out).map(|r| counts(&r)).map_err(boxed)
}

fn counts(run: &InPlaneStudyRun) -> OwnStudyRun {
    OwnStudyRun {
        realizations: run.rows.len(),
        failed: run.rows.iter().filter(|r| r.status != "ok").count(),
        wall_time_s: run.wall_time_s,
        resumed: run.resumed,
    }
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
