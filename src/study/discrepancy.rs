//! The model-discrepancy analysis of a study: its groups and measured data handed to
//! [`crate::discrepancy`] (`drystone discrepancy STUDY.toml`, `drystone synthesize`).

use super::Study;
use crate::discrepancy::observations::{mechanism_observations, observations, MeasurementSigma, Observation};
use crate::discrepancy::simulate::{GroupSetup, Setup};
use crate::discrepancy::DiscrepancyError;

/// The setup of a study for the discrepancy analysis: its groups at the first sweep point
/// with their effects (a group whose realizations 0 and 1 are the same layout is marked
/// deterministic), each with `realizations` (or the group's own fixed count, if smaller),
/// the study's seed, solver and tilting-table parameters as they are (the analysis's
/// predictive means are the study's `run` means).
pub fn setup_of(study: &Study, realizations: u64) -> Setup {
    let groups = study
        .groups
        .iter()
        .map(|g| {
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
            }
        })
        .collect();
    Setup { groups, seed: study.seed, solver: study.solver, tilt: study.tilt }
}

/// The observations of a study's measured data (`[measured]`), with the measured group
/// names mapped to the study's groups: collapse angles, displacements, then observed
/// mechanisms (none without a `mechanism` file: the observations are then as before).
///
/// # Errors
/// [`DiscrepancyError::Observations`] naming the study file.
pub fn observations_of(study: &Study, sigma: MeasurementSigma) -> Result<Vec<Observation>, DiscrepancyError> {
    let groups: Vec<(String, String)> =
        study.groups.iter().map(|g| (g.measured_group.clone(), g.name.clone())).collect();
    let file = format!("{} [measured]", study.path.display());
    let mut obs = observations(&study.measured.collapse, &study.measured.displacement, &groups, sigma, &file)
        .map_err(|source| DiscrepancyError::Observations { file: file.clone(), source })?;
    obs.extend(
        mechanism_observations(&study.measured.mechanism, &groups, sigma)
            .map_err(|source| DiscrepancyError::Observations { file, source })?,
    );
    Ok(obs)
}
