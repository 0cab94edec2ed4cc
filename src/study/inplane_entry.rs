//! The in-plane study's entry points ([`STUDY`]): what `drystone run` and `drystone
//! discrepancy` call to run and analyse a study file of `protocol = "in_plane"`
//! ([`super::own`]).

use super::inplane::{InPlaneStudyError, InPlaneStudyRun};
use super::inplane_discrepancy::analysis_of;
use super::inplane_run::{is_in_plane_shard, merge, run_study_into};
use super::own::{OwnAnalysis, OwnCheck, OwnStudy, OwnStudyError, OwnStudyRun};
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
    check: Some(own_check),
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

/// The cyclic loops of the baseline and the tie ([`super::inplane_loops::check_loops`]).
fn own_check(
    path: &Path,
    input: &OwnAnalysis,
    run: &crate::discrepancy::Run,
    progress: crate::discrepancy::Progress<'_>,
) -> Result<Option<OwnCheck>, OwnStudyError> {
    let Some(l) = super::inplane_loops::check_loops(path, input, run, progress).map_err(boxed)? else {
        return Ok(None);
    };
    let mut summary =
        vec!["the cyclic loops (a reading the fit did not use): the loops' damping ratio, χ² over the stresses"
            .to_string()];
    for m in &l.models {
        let read = m
            .friction_read
            .map(|f| format!("  μ_r read {:.4} [{:.4}, {:.4}], χ² {:.1}", f.friction, f.low, f.high, f.chi2))
            .unwrap_or_default();
        let peaks =
            m.peaks.as_ref().map(|p| format!("; held-out error with it {:.2}", p.heldout_error)).unwrap_or_default();
        summary.push(format!(
            "  {:<36} χ² {:>8.1}  p {:.2e}  {}{read}{peaks}",
            m.name,
            m.chi2,
            m.p_value,
            m.verdict.words()
        ));
    }
    if let Some((m, p)) = l.standing().first().and_then(|m| m.peaks.as_ref().map(|p| (m, p))) {
        summary.push(format!(
            "  both readings leave standing: {} with μ_r {:.4} held, held-out error {:.2} (baseline {:.2})",
            m.name,
            m.friction_read.map_or(f64::NAN, |f| f.friction),
            p.heldout_error,
            l.baseline_heldout_error
        ));
    }
    let json = serde_json::to_value(&l).map_err(|e| OwnStudyError(Box::new(e)))?;
    Ok(Some(OwnCheck { key: "loops", markdown: l.markdown(), json, summary }))
}
