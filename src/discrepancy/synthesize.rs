//! Synthetic measured data: specimens of the study's walls, built with seeds the study does
//! not use, with hidden effects applied, tilted to collapse, plus measurement noise rounded
//! to the readings' resolution; written in the format of the paper's data files. A power
//! analysis for planning tests: can a campaign of N specimens detect an effect of a given
//! strength? (Data made here share the effect code with the analysis: they check its
//! consistency, not its power on real walls.)

use super::observations::{Measure, MeasurementSigma, Observable, Observation};
use super::simulate::{run_models, Setup};
use crate::effects::Effect;
use crate::io::table::{MeasuredCollapse, MeasuredDisplacement};
use crate::io::FileError;
use crate::rng::{rng_for, Purpose};
use rand::RngExt;
use rand_distr::{Distribution, StandardNormal};
use std::path::Path;

/// What to synthesize.
#[derive(Debug, Clone)]
pub struct Request {
    /// The hidden effects (none: null data from the baseline model).
    pub effects: Vec<Effect>,
    /// The user's seed; the walls' master seed is derived from it and differs from the
    /// study's.
    pub seed: u64,
    /// Specimens per group.
    pub specimens: u64,
    /// Measurement noise.
    pub sigma: MeasurementSigma,
    /// Reading resolutions: every value is rounded to them, as real readings are.
    pub reading: super::predictive::Reading,
    /// Observables per group (group name, observables); a group missing here gets its
    /// collapse angle and the displacement at 5° and 10° (the centre minus the ends for
    /// restrained walls, the mean of the three top points otherwise).
    pub observables: Vec<(String, Vec<Observable>)>,
}

/// The master seed of the synthetic walls: drawn from the user's seed, never the study's.
pub fn master_seed(user_seed: u64, study_seed: u64) -> u64 {
    let m: u64 = rng_for(user_seed, 0, Purpose::Discrepancy).random();
    if m == study_seed {
        m ^ 1
    } else {
        m
    }
}

/// The observables of each group: those of `template` observations, or the default set.
pub fn observables_of(setup: &Setup, template: &[Observation]) -> Vec<(String, Vec<Observable>)> {
    setup
        .groups
        .iter()
        .map(|g| {
            let mut v: Vec<Observable> = Vec::new();
            for o in template.iter().filter(|o| o.group == g.name) {
                if !v.iter().any(|x| x.same(&o.observable)) {
                    v.push(o.observable);
                }
            }
            if v.is_empty() {
                let measure =
                    if g.restrained { Measure::CenterMinusMeanOfEnds } else { Measure::MeanOfLeftCenterRight };
                v = vec![
                    Observable::CollapseAngle,
                    Observable::Displacement { measure, tilt_deg: 5.0 },
                    Observable::Displacement { measure, tilt_deg: 10.0 },
                ];
            }
            (g.name.clone(), v)
        })
        .collect()
}

/// Synthesizes the measured data. Specimens whose run failed are left out; displacements
/// at tilts the specimen did not stand to are left out (as in the paper's Table 3).
pub fn synthesize(setup: &Setup, req: &Request) -> (Vec<MeasuredCollapse>, Vec<MeasuredDisplacement>) {
    let seed = master_seed(req.seed, setup.seed);
    let synth = Setup {
        seed,
        groups: setup
            .groups
            .iter()
            .map(|g| super::simulate::GroupSetup { realizations: req.specimens, deterministic: false, ..g.clone() })
            .collect(),
        ..setup.clone()
    };
    let outs = run_models(&synth, std::slice::from_ref(&req.effects), None).remove(0);
    let (mut collapse, mut disp) = (Vec::new(), Vec::new());
    for (gi, g) in synth.groups.iter().enumerate() {
        let wanted = req.observables.iter().find(|(n, _)| n == &g.name).map(|(_, v)| v.clone()).unwrap_or_default();
        for (k, o) in outs[gi].iter().enumerate() {
            if o.error.is_some() {
                continue;
            }
            let specimen = format!("{}-s{}", g.name, k + 1);
            let mut rng = rng_for(seed, (gi as u64) << 32 | k as u64, Purpose::Discrepancy);
            let mut noise = |s: f64| -> f64 {
                let z: f64 = StandardNormal.sample(&mut rng);
                s * z
            };
            for obs in &wanted {
                match *obs {
                    Observable::CollapseAngle => {
                        if let Some(a) = o.collapse_mid_deg() {
                            collapse.push(MeasuredCollapse {
                                specimen: specimen.clone(),
                                group: g.name.clone(),
                                collapse_angle_deg: req.reading.round(obs, a + noise(req.sigma.angle_deg)),
                                ..MeasuredCollapse::default()
                            });
                        }
                    }
                    Observable::Displacement { measure, tilt_deg }
                        if o.observed.tilt_deg.iter().any(|t| (t - tilt_deg).abs() < 1e-9) =>
                    {
                        if let Some(v) = o.value(obs) {
                            disp.push(MeasuredDisplacement {
                                specimen: specimen.clone(),
                                group: g.name.clone(),
                                measure,
                                tilt_deg,
                                displacement_cm: req.reading.round(obs, v + noise(req.sigma.displacement_cm)),
                                ..MeasuredDisplacement::default()
                            });
                        }
                    }
                    // A tilt the realization did not stand to gives no displacement; mechanisms
                    // are read by the test bed (`tests/realwalls`), not here; the in-plane
                    // test's data are its database's.
                    Observable::Displacement { .. }
                    | Observable::FailureHeight { .. }
                    | Observable::MechanismKind { .. }
                    | Observable::MechanismStart { .. }
                    | Observable::InPlane { .. }
                    | Observable::InPlaneMode { .. } => {}
                }
            }
        }
    }
    // A specimen's displacements stop at its (noisy) collapse angle, as a measured
    // specimen's do: the data must pass the check of measured data.
    disp.retain(|d| {
        collapse.iter().find(|c| c.specimen == d.specimen).is_none_or(|c| d.tilt_deg <= c.collapse_angle_deg)
    });
    (collapse, disp)
}

/// Writes `tilting_table_collapse.csv` and `tilting_table_displacement.csv` in `dir` (the
/// format of the paper's data files).
///
/// # Errors
/// [`FileError`]: the file system's error, with the file.
pub fn write(dir: &Path, collapse: &[MeasuredCollapse], disp: &[MeasuredDisplacement]) -> Result<(), FileError> {
    std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
    let mut c = String::from("specimen,group,block,joints,ends,collapse_angle_deg,load_factor_sin\n");
    for m in collapse {
        let sin = m.collapse_angle_deg.to_radians().sin();
        c += &format!(
            "{},{},synthetic,synthetic,synthetic,{:.4},{:.4}\n",
            m.specimen, m.group, m.collapse_angle_deg, sin
        );
    }
    let mut d = String::from("specimen,group,measure,tilt_deg,displacement_cm\n");
    for m in disp {
        d += &format!("{},{},{},{},{:.4}\n", m.specimen, m.group, m.measure.name(), m.tilt_deg, m.displacement_cm);
    }
    for (name, text) in [("tilting_table_collapse.csv", c), ("tilting_table_displacement.csv", d)] {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(FileError::at(&p))?;
    }
    Ok(())
}
