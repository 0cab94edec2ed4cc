//! The model-discrepancy analysis of a study: its groups and measured data handed to
//! [`crate::discrepancy`] (`drystone discrepancy STUDY.toml`, `drystone synthesize`).
//!
//! `drystone discrepancy` and the Python package's `discrepancy` run every study the same
//! way, [`analyse`]: the study read by the core ([`Study::from_file`]), its protocol's
//! [`AnalysisWay`] ([`super::StudyProtocol::analysis`]) turning it into the analysis's
//! input ([`Analysis`]: groups, observations, settings, effect library) and, where the
//! protocol has one, a reading the fit does not hold
//! ([`crate::discrepancy::HeldReading`]), the analysis run
//! ([`crate::discrepancy::run_held`]); then its outputs written ([`write_analysis`]). What
//! differs between protocols is what the way declares: the tilting table's, the lateral
//! load's, the shaking table's and the compression test's is [`ENSEMBLE`] (the study's
//! groups at the first sweep point, [`setup_of`]; its `[measured]` files, [`observations_of`]),
//! the in-plane test's its own (`study::inplane_discrepancy`, `study::inplane_loops`).

use super::extend::ExtendError;
use super::inplane_error::InPlaneStudyError;
use super::outputs::{HeldDir, SetNames};
use super::Study;
use crate::discrepancy::{mechanism_observations, observations, write_report, DiscrepancyError, GroupSetup};
use crate::discrepancy::{run_held, HeldReading, HeldReport, Progress, Settings};
use crate::discrepancy::{MeasurementSigma, Observation, ObservationError, Run, Setup, WriteError};
use crate::io::FileError;
use std::path::PathBuf;

/// What the discrepancy analysis of a study runs on: its groups, its measured observations,
/// its settings and its effect library, analysed as any study's
/// ([`crate::discrepancy::run_held`]).
#[derive(Debug, Clone)]
pub struct Analysis {
    /// The study's name.
    pub name: String,
    /// Its master seed.
    pub seed: u64,
    /// The groups (each with the realizations the settings' runs take at most,
    /// [`Settings::most_realizations`], or a group's own fixed count where smaller), the
    /// solver and the protocol; no run store (the caller gives it).
    pub setup: Setup,
    /// The measured observations.
    pub obs: Vec<Observation>,
    /// The settings: the study's `[discrepancy]` (defaults where absent) with the
    /// command's options, and the notes of the σ a protocol sets from the data.
    pub settings: Settings,
    /// The effect library.
    pub library: crate::effects::Library,
}

/// An error of a study's discrepancy analysis, naming the file and key.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// The measured data refused (naming the file and line, or the study's `[measured]`),
    /// or the analysis's own (a setting, an effect, a baseline that fails entirely, the
    /// held reading's).
    #[error(transparent)]
    Analysis(#[from] DiscrepancyError),
    /// The in-plane study refused (naming the study file and key, or the measured file).
    #[error(transparent)]
    InPlane(#[from] InPlaneStudyError),
}

impl AnalysisError {
    /// The study file and its key at fault, where the error names a key of the study file
    /// (an in-plane study's groups and `[measured]`); `None` where it names a measured
    /// file's line or a setting in its message.
    pub fn file_key(&self) -> Option<(&std::path::Path, &str)> {
        match self {
            AnalysisError::InPlane(InPlaneStudyError::Invalid { path, key, .. }) => Some((path, key)),
            AnalysisError::InPlane(_) | AnalysisError::Analysis(_) => None,
        }
    }
}

/// Reads a study into its analysis's input ([`Analysis`]) with the settings `settings`
/// (the study's `[discrepancy]` with the command's options applied).
pub type InputFn = fn(&Study, Settings) -> Result<Analysis, AnalysisError>;

/// The reading of a study that its analysis's fit does not hold (the in-plane test's cyclic
/// loops), for the study and its analysis's input (with its run store): asked of each
/// candidate before it is named and reported after the analysis; `None` when the study has
/// nothing to read.
pub type HeldFn = fn(&Study, &Analysis) -> Result<Option<Box<dyn HeldReading>>, AnalysisError>;

/// How a protocol's studies are analysed by `drystone discrepancy`: what the protocol
/// declares ([`super::StudyProtocol::analysis`]); everything else is the command's one path.
#[derive(Debug, Clone, Copy)]
pub struct AnalysisWay {
    /// Where the study reads its measured data when it is not from the tilting table's
    /// files: `None` where `--measured DIR` and `--measured-sets DIR` replace the study's
    /// `[measured]` files by the tilting table's files of `DIR`
    /// (`tilting_table_collapse.csv`, …); otherwise the words of their refusal, after
    /// "--measured and --measured-sets read the tilting table's files; " (`an in-plane
    /// study reads its specimens from [measured] walls`).
    pub measured_elsewhere: Option<&'static str>,
    /// Reads the study into the analysis's input.
    pub input: InputFn,
    /// Its reading the fit does not hold ([`HeldFn`]), if it has one.
    pub held: Option<HeldFn>,
    /// Whether the cause the analysis names is written back as an extended study
    /// (`extended/`, [`super::extend::write_extended`]): the study's groups are the
    /// analysis's. `false` where the analysis's groups are not the study's (the in-plane
    /// test's stresses).
    pub extends: bool,
}

/// The way of the studies whose analysis's groups are the study's groups at its first
/// sweep point ([`setup_of`]) and whose observations are their `[measured]` files
/// ([`observations_of`], or the tilting table's files of `--measured`): the tilting table,
/// the lateral load, the shaking table and the compression test. No held reading; a named
/// cause is written as an extended study.
pub const ENSEMBLE: AnalysisWay =
    AnalysisWay { measured_elsewhere: None, input: ensemble_analysis, held: None, extends: true };

/// A study's discrepancy analysis, run ([`analyse`]): its input, the analysis and the
/// report of the reading its fit does not hold.
pub struct Analysed {
    /// The analysis's input (its setup with the run store it was given).
    pub input: Analysis,
    /// The analysis.
    pub run: Run,
    /// The held reading's report after the analysis (its section of `discrepancy.md`, its
    /// JSON, the lines the command prints); `None` without a held reading.
    pub held: Option<HeldReport>,
}

impl Analysed {
    /// The analysis as JSON (`drystone discrepancy --json`, the Python package's
    /// `discrepancy`): [`crate::discrepancy::report_json`] with the held reading's JSON
    /// under its key (`loops`).
    pub fn json(&self) -> serde_json::Value {
        let mut v = crate::discrepancy::report_json(&self.run);
        if let (Some(h), Some(o)) = (&self.held, v.as_object_mut()) {
            o.insert(h.key.into(), h.json.clone());
        }
        v
    }
}

/// The input of the discrepancy analysis of `study` with the settings `settings` (its
/// `[discrepancy]` with the caller's options, checked), read the way its protocol declares
/// ([`super::StudyProtocol::analysis`], [`AnalysisWay::input`]), without a run store.
///
/// # Errors
/// [`AnalysisError`]: the study's measured data or groups refused by its way, naming the
/// file and key.
pub fn input_of(study: &Study, settings: Settings) -> Result<Analysis, AnalysisError> {
    (study.protocol.analysis().input)(study, settings)
}

/// Runs the discrepancy analysis of `study` on its input `input` ([`input_of`], with the
/// run store its setup is given: `None`, every run made and none kept) the way its
/// protocol declares ([`super::StudyProtocol::analysis`]): the held reading, if the
/// protocol has one and the study something to read, asked of each candidate before it is
/// named ([`run_held`]) and reported after the analysis. In the current rayon pool (the
/// results do not depend on its threads); each stage reported to `progress`. The one path
/// of `drystone discrepancy` and of the Python package.
///
/// # Errors
/// [`AnalysisError`]: the held reading's study refused (naming the file and key); the
/// analysis's errors ([`crate::discrepancy::DiscrepancyError`]).
pub fn analyse(study: &Study, input: Analysis, progress: Progress<'_>) -> Result<Analysed, AnalysisError> {
    let way = study.protocol.analysis();
    let reading = match way.held {
        Some(f) => f(study, &input)?,
        None => None,
    };
    let run = run_held(
        &input.setup,
        input.obs.clone(),
        &input.settings,
        input.seed,
        &input.library,
        reading.as_deref(),
        progress,
    )?;
    let held = match &reading {
        Some(h) => h.report(&run, progress)?,
        None => None,
    };
    Ok(Analysed { input, run, held })
}

/// The analysis's input of a study of [`ENSEMBLE`]'s way: [`setup_of`] with the settings'
/// most realizations, [`observations_of`] with their σ, the study's effect library.
///
/// # Errors
/// [`AnalysisError::Analysis`] as [`observations_of`].
pub fn ensemble_analysis(study: &Study, settings: Settings) -> Result<Analysis, AnalysisError> {
    let obs = observations_of(study, settings.sigma)?;
    Ok(Analysis {
        name: study.name.clone(),
        seed: study.seed,
        setup: setup_of(study, settings.most_realizations()),
        obs,
        settings,
        library: study.library.clone(),
    })
}

/// The setup of a study for the discrepancy analysis: its groups at the first sweep point
/// with their effects (a group whose realizations 0 and 1 are the same layout is marked
/// deterministic), each with `realizations` (or the group's own fixed count, if smaller),
/// the study's seed, solver and loading protocol with its parameters as they are (the
/// analysis's predictive means are the study's `run` means).
pub fn setup_of(study: &Study, realizations: u64) -> Setup {
    let groups = study
        .groups
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let wall = g.walls[0].clone();
            let course_m = crate::effects::course_height_of(&wall);
            let layout = |r: u64| crate::generator::generate(&wall, study.seed, r).ok().and_then(|w| w.check().ok());
            let first = layout(0);
            let restrained = first.as_ref().is_some_and(|l| !l.end_restraints.is_empty());
            // Two realizations with the same blocks: the wall has no random input.
            let deterministic = first.is_some() && first == layout(1);
            GroupSetup {
                name: g.name.clone(),
                realizations: g.realizations.map_or(realizations, |r| r.min(realizations)),
                wall,
                restrained,
                deterministic,
                effects: g.effects.clone(),
                course_m,
                protocol: study.protocol.group_protocol(i),
            }
        })
        .collect();
    Setup { groups, seed: study.seed, solver: study.solver, protocol: study.protocol_at(0), store: None }
}

/// The observations of a study's measured data (`[measured]`), with the measured group
/// names mapped to the study's groups: collapse angles, displacements, then observed
/// mechanisms (none without a `mechanism` file: then angles and displacements only).
///
/// # Errors
/// [`DiscrepancyError::Observations`] naming the file and line of the row at fault (a
/// group the study does not have: the file it was read from, the study's `[measured]`
/// table or `--measured DIR`), else the study file.
pub fn observations_of(study: &Study, sigma: MeasurementSigma) -> Result<Vec<Observation>, DiscrepancyError> {
    let groups: Vec<(String, String)> =
        study.groups.iter().map(|g| (g.measured_group.clone(), g.name.clone())).collect();
    let file = format!("{} [measured]", study.path.display());
    let m = &study.measured;
    // The row a group error names: its own file and line.
    let located = |source: ObservationError| {
        let file = match &source {
            ObservationError::UnknownGroup { group, specimen, .. } => {
                let row = |s: &String, g: &String| s == specimen && g == group;
                m.collapse
                    .iter()
                    .filter(|c| row(&c.specimen, &c.group))
                    .map(|c| (&c.file, c.line))
                    .chain(m.displacement.iter().filter(|d| row(&d.specimen, &d.group)).map(|d| (&d.file, d.line)))
                    .chain(m.mechanism.iter().filter(|x| row(&x.specimen, &x.group)).map(|x| (&x.file, x.line)))
                    .next()
                    .map_or_else(|| file.clone(), |(f, line)| format!("{} line {line}", f.display()))
            }
            _ => file.clone(),
        };
        DiscrepancyError::Observations { file, source }
    };
    let mut obs = observations(&m.collapse, &m.displacement, &groups, sigma, &file).map_err(located)?;
    obs.extend(mechanism_observations(&m.mechanism, &groups, sigma).map_err(located)?);
    Ok(obs)
}

/// The staging directory and manifest of `drystone discrepancy`'s set in its output
/// directory (beside a run's, if the directory holds one).
pub const OUTPUT_SET: SetNames =
    SetNames { staging: ".drystone-staging-discrepancy", manifest: "discrepancy-manifest.json" };

/// Errors of writing a discrepancy analysis's outputs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DiscrepancyOutputError {
    /// The report could not be written.
    #[error(transparent)]
    Report(#[from] WriteError),
    /// A file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A held reading's JSON could not be written (naming the file).
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: serde_json::Error,
    },
    /// The extended study could not be written.
    #[error(transparent)]
    Extended(#[from] ExtendError),
}

/// Writes an analysis of `study` into the held directory `out`: the report
/// (`discrepancy.md`, `discrepancy.json`, `residuals.svg`, `displacement_<group>.svg`) as
/// one set ([`HeldDir::write_set`], manifest `discrepancy-manifest.json`), then, when a
/// mechanism was named, the extended study under `extended/` (still under the directory's
/// lock): [`write_analysis`] of an analysis without a held reading whose groups are the
/// study's (`drystone design`). Returns the extended study's file.
///
/// # Errors
/// [`DiscrepancyOutputError`] naming the file.
pub fn write_discrepancy(out: &HeldDir, study: &Study, run: &Run) -> Result<Option<PathBuf>, DiscrepancyOutputError> {
    write_outputs(out, study, run, None, true)
}

/// Writes the analysis `done` of `study` ([`analyse`]) into the held directory `out`: the
/// report (`discrepancy.md`, `discrepancy.json`, `residuals.svg`,
/// `displacement_<group>.svg`) with the held reading's report (its section appended to
/// `discrepancy.md`, its JSON `<key>.json`, `loops.json`) as one set
/// ([`HeldDir::write_set`], manifest `discrepancy-manifest.json`), then, where the
/// protocol's way writes one ([`AnalysisWay::extends`]) and a mechanism was named, the
/// extended study under `extended/` (still under the directory's lock). Returns the
/// extended study's file.
///
/// # Errors
/// [`DiscrepancyOutputError`] naming the file.
pub fn write_analysis(
    out: &HeldDir,
    study: &Study,
    done: &Analysed,
) -> Result<Option<PathBuf>, DiscrepancyOutputError> {
    write_outputs(out, study, &done.run, done.held.as_ref(), study.protocol.analysis().extends)
}

/// The outputs of [`write_analysis`] and [`write_discrepancy`]: the report with the held
/// reading's `held`, and the extended study when `extends`.
fn write_outputs(
    out: &HeldDir,
    study: &Study,
    run: &Run,
    held: Option<&HeldReport>,
    extends: bool,
) -> Result<Option<PathBuf>, DiscrepancyOutputError> {
    out.write_set(OUTPUT_SET, "discrepancy", &study.name, |staging| -> Result<(), DiscrepancyOutputError> {
        write_report(staging, run, &study.name)?;
        if let Some(h) = held {
            let md = staging.join("discrepancy.md");
            let mut text = std::fs::read_to_string(&md).map_err(FileError::at(&md))?;
            text.push('\n');
            text.push_str(&h.markdown);
            std::fs::write(&md, text).map_err(FileError::at(&md))?;
            let js = staging.join(format!("{}.json", h.key));
            let json = serde_json::to_string_pretty(&h.json)
                .map_err(|source| DiscrepancyOutputError::Json { path: js.clone(), source })?;
            std::fs::write(&js, json).map_err(FileError::at(&js))?;
        }
        Ok(())
    })?;
    Ok(match (&run.analysis.cause, &run.extended) {
        (Some(c), Some((effects, _))) if extends => {
            let note = format!(
                "{} named by `drystone discrepancy` ({}; {} specimens)",
                c.name,
                run.analysis.verdict.name(),
                run.specimens.len()
            );
            let ext = out.path().join("extended");
            Some(super::extend::write_extended(study, effects, &run.cause_interval, &note, &ext)?)
        }
        _ => None,
    })
}
