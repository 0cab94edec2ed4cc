//! The model-discrepancy analysis of a study: its groups and measured data handed to
//! [`crate::discrepancy`] (`drystone discrepancy STUDY.toml`, `drystone synthesize`).

use super::extend::ExtendError;
use super::outputs::{HeldDir, SetNames};
use super::Study;
use crate::discrepancy::{mechanism_observations, observations, write_report, DiscrepancyError, GroupSetup};
use crate::discrepancy::{MeasurementSigma, Observation, ObservationError, Run, Setup, WriteError};
use crate::io::FileError;
use std::path::PathBuf;

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
    /// The extended study could not be written.
    #[error(transparent)]
    Extended(#[from] ExtendError),
}

/// Writes an analysis of `study` into the held directory `out`: the report
/// (`discrepancy.md`, `discrepancy.json`, `residuals.svg`, `displacement_<group>.svg`) as
/// one set ([`HeldDir::write_set`], manifest `discrepancy-manifest.json`), then, when a
/// mechanism was named, the extended study under `extended/` (still under the
/// directory's lock). Returns the extended study's file.
///
/// # Errors
/// [`DiscrepancyOutputError`] naming the file.
pub fn write_discrepancy(out: &HeldDir, study: &Study, run: &Run) -> Result<Option<PathBuf>, DiscrepancyOutputError> {
    out.write_set(OUTPUT_SET, "discrepancy", &study.name, |staging| -> Result<(), DiscrepancyOutputError> {
        Ok(write_report(staging, run, &study.name)?)
    })?;
    Ok(match (&run.analysis.cause, &run.extended) {
        (Some(c), Some((effects, _))) => {
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
