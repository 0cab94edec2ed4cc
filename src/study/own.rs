//! Protocols whose discrepancy analysis is their own ([`OwnStudy`]): `drystone discrepancy`
//! analyses their study files through the entry points their study module gives here
//! (their run, rows, shards, merge and report are the study core's, `drystone run`). The
//! command line hands their files over by their `protocol` key ([`super::own_study_of`]),
//! and the kind's entry is its arm of [`super::protocol::own_study`] (the compiler points
//! to it at a new kind).

use super::spec::ProtocolKind;
use crate::discrepancy::{Observation, Settings, Setup};
use std::path::Path;

/// An error of a study of its own, as its module words it (naming its file and key).
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct OwnStudyError(#[from] pub Box<dyn std::error::Error + Send + Sync>);

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

/// A protocol's discrepancy analysis of its own: what `drystone discrepancy` needs to
/// analyse its study files.
#[derive(Debug, Clone, Copy)]
pub struct OwnStudy {
    /// Its study in a phrase, for messages (`an in-plane study`).
    pub what: &'static str,
    /// Where it reads its measured data, for the refusal of the tilting table's
    /// `--measured` (`reads its specimens from [measured] walls`).
    pub measured: &'static str,
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
