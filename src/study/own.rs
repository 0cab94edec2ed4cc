//! Protocols whose study is their own ([`OwnStudy`]): their own study file, rows,
//! statistics, figures and report, run by `drystone run` and analysed by `drystone
//! discrepancy` through the entry points their study module gives here. The ensemble study
//! ([`super::Study`]) refuses their files; the command line hands them over by their
//! `protocol` key ([`super::own_study_of`]), and the kind's entry is its arm of
//! [`super::protocol::own_study`] (the compiler points to it at a new kind).

use super::spec::ProtocolKind;
use crate::discrepancy::{Observation, Settings, Setup};
use std::path::Path;

/// An error of a study of its own, as its module words it (naming its file and key).
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct OwnStudyError(#[from] pub Box<dyn std::error::Error + Send + Sync>);

/// What a run of a study of its own gave, as the command line reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OwnStudyRun {
    /// Its realizations (rows written).
    pub realizations: usize,
    /// Those that failed (their rows carry the error).
    pub failed: usize,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// How many rows came from the journal of an earlier run (`--resume`).
    pub resumed: usize,
}

/// What the discrepancy analysis of a study of its own runs on: its groups, its measured
/// observations and its settings, analysed as any study's ([`crate::discrepancy::run_with`]).
#[derive(Debug, Clone)]
pub struct OwnAnalysis {
    /// The study's name.
    pub name: String,
    /// Its master seed.
    pub seed: u64,
    /// The groups, the solver and the protocol.
    pub setup: Setup,
    /// The measured observations.
    pub obs: Vec<Observation>,
    /// The study's `[discrepancy]` settings (defaults where absent).
    pub settings: Settings,
    /// The effect library.
    pub library: crate::effects::Library,
}

/// The reading of a study of its own that its fit does not hold (the in-plane test's cyclic
/// loops), for the study file and its analysis input: asked of each candidate before it is
/// named and reported after the analysis ([`crate::discrepancy::HeldReading`]); `None` when
/// the study has nothing to read.
pub type HeldFn = fn(&Path, &OwnAnalysis) -> Result<Option<Box<dyn crate::discrepancy::HeldReading>>, OwnStudyError>;

/// A protocol's study of its own: what the command line needs to run and analyse it.
#[derive(Debug, Clone, Copy)]
pub struct OwnStudy {
    /// Its kind (`protocol = "..."` of its study files).
    pub kind: ProtocolKind,
    /// Its study in a phrase, for messages (`an in-plane study`).
    pub what: &'static str,
    /// Where its study files are documented (`docs/<name>.md`).
    pub doc: &'static str,
    /// Where it reads its measured data, for the refusal of the tilting table's
    /// `--measured` (`reads its specimens from [measured] walls`).
    pub measured: &'static str,
    /// Runs a shard of a study (read by the study core, [`super::Study::from_file`]) into a
    /// folder, its journal treated as `RunMode` says: its outputs written there.
    pub run: fn(&super::Study, &Path, crate::ensemble::Shard, super::RunMode) -> Result<OwnStudyRun, OwnStudyError>,
    /// Merges shard folders into a folder: the outputs of the whole study.
    pub merge: fn(&[std::path::PathBuf], &Path) -> Result<OwnStudyRun, OwnStudyError>,
    /// Whether a folder holds a shard of one of its studies.
    pub is_shard: fn(&Path) -> bool,
    /// Reads the study of a file for its discrepancy analysis.
    pub analysis: fn(&Path) -> Result<OwnAnalysis, OwnStudyError>,
    /// Its reading the fit does not hold ([`HeldFn`]), if it has one.
    pub held: Option<HeldFn>,
}

/// The kind a study file names (`protocol = "..."`); `None` for a file that cannot be read,
/// names none or names an unknown one.
pub fn kind_of(path: &Path) -> Option<ProtocolKind> {
    let text = std::fs::read_to_string(path).ok()?;
    let table = text.parse::<toml::Table>().ok()?;
    table.get("protocol")?.as_str().and_then(ProtocolKind::from_name)
}
