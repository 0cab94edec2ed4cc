//! The model-discrepancy analysis of an in-plane study (`drystone discrepancy` on a study
//! with `protocol = "in_plane"`): its vertical-stress levels as the analysis's groups, its
//! measured specimens as observations (peak force, drift at the peak, initial stiffness
//! and mode of the first direction loaded), the test pushed monotonically as the forward
//! model ([`crate::protocol::InPlane`]'s `compared`).
//!
//! # Groups
//!
//! One group per vertical stress of the study (its groups of one stress share the wall and
//! the test; a monotonic and a cyclic group of one stress become one group). Realization
//! `r` of the group is the layout `effects::realize` makes for the group's name, as in
//! every discrepancy analysis; the study's own run numbers its layouts `g · 10000 + i`.
//!
//! # Observations
//!
//! Per specimen the direction the database calls positive (+x, its `pos` columns): the peak
//! force (kN), the drift at the peak (%), the initial stiffness (kN/mm), each with the
//! measurement σ of `[discrepancy.sigma]`; the group's vertical modulus (MPa, one reading a
//! stress); per cyclic specimen the ± asymmetry of its peaks (`Vmax_neg − Vmax_pos`, kN,
//! against the model's push read both ways by its mirror image,
//! [`crate::protocol::InPlaneReading::negative_peak_kn`]); and the mode (`InPlaneMode`,
//! value 1): failure
//! type 1 read as rocking, 0.5 as mixed; a failure type 0 (sliding or diagonal, which the
//! database does not tell apart) gives no mode reading. Which direction a cyclic specimen
//! was pushed first is not assumed: its two peaks enter as the positive one and their
//! difference.

use super::discrepancy::{Analysis, AnalysisError};
use super::inplane::InPlaneStudyError;
use super::inplane_run::Prepared;
use super::Study;
use crate::discrepancy::{GroupSetup, InPlaneQuantity, Observable, Observation, Settings, Setup};
use crate::loading::inplane::{History, InPlaneParams, MechanismKind};
use crate::protocol::{InPlane, Protocol};
use std::path::Path;

/// The name of the analysis's group of vertical stress `sigma0` (MPa): `0.5 MPa`.
pub fn stress_group(sigma0_mpa: f64) -> String {
    format!("{sigma0_mpa} MPa")
}

/// The in-plane study `study` as its discrepancy analysis reads it (module documentation),
/// with the settings `settings` (its `[discrepancy]` with the command's options): each
/// group's realizations the settings' most ([`Settings::most_realizations`]), the σ of the
/// measures the study does not state set from the data ([`sigma_from_data`],
/// [`asymmetry_sigma_from_data`], their notes in the settings), the built-in effects.
/// `drystone discrepancy` reads an in-plane study by it (the protocol's
/// [`super::discrepancy::AnalysisWay`]).
///
/// # Errors
/// [`AnalysisError::InPlane`]: a study of another protocol, a study without measured
/// specimens, a specimen whose stress is not its group's, groups of one stress with
/// different walls or effects, naming the file and the key.
pub fn analysis_of(study: &Study, settings: Settings) -> Result<Analysis, AnalysisError> {
    Ok(analysis(study, settings)?)
}

fn analysis(study: &Study, settings: Settings) -> Result<Analysis, InPlaneStudyError> {
    let Prepared { study, test } = Prepared::of(study)?;
    let path = study.path.as_path();
    let bad = |key: String, message: String| InPlaneStudyError::Invalid { path: path.to_owned(), key, message };
    if !study.inputs.iter().any(|f| f.role == super::provenance::InputRole::Measured) {
        return Err(bad("measured".into(), "the analysis needs the measured specimens ([measured] walls)".into()));
    }
    let specimens = &test.specimens;
    let realizations = settings.most_realizations();
    let mut groups: Vec<GroupSetup> = Vec::new();
    let mut walls_of: Vec<std::path::PathBuf> = Vec::new();
    let mut effects_of: Vec<usize> = Vec::new();
    let mut obs = Vec::new();
    for (g, (core, group)) in study.groups.iter().zip(&test.groups).enumerate() {
        let name = stress_group(group.sigma0_mpa);
        match groups.iter().position(|x| x.name == name) {
            Some(k) if walls_of[k] != group.source => {
                return Err(bad(
                    format!("groups[{}].{}", core.name, if core.spec.is_none() { "survey" } else { "wall" }),
                    format!(
                        "{}: the groups of {name} must share one wall for the analysis ({} is the first's)",
                        group.source.display(),
                        walls_of[k].display()
                    ),
                ))
            }
            Some(k) if test.groups[effects_of[k]].stated != group.stated => {
                return Err(bad(
                    format!("groups[{}].effects", core.name),
                    format!(
                        "the groups of {name} must share one model for the analysis (groups[{}]'s effects)",
                        study.groups[effects_of[k]].name
                    ),
                ))
            }
            Some(_) => {}
            None => {
                let (wall, effects) = (core.walls[0].clone(), core.effects.clone());
                let layout =
                    |r: u64| crate::effects::realize(&wall, study.seed, r, &name, &effects).ok().map(|(_, l)| l);
                let first = layout(0);
                let deterministic = first.is_some() && first == layout(1);
                let params = InPlaneParams { history: History::Monotonic, ..test.params_of(g) };
                groups.push(GroupSetup {
                    name: name.clone(),
                    course_m: crate::effects::course_height_of(&wall),
                    wall,
                    realizations,
                    restrained: false,
                    deterministic,
                    effects,
                    protocol: Some(Protocol::InPlane(InPlane(params))),
                });
                walls_of.push(group.source.clone());
                effects_of.push(g);
            }
        }
        for unit in &group.specimens {
            let Some(s) = specimens.iter().find(|s| &s.unit == unit) else {
                return Err(bad(
                    format!("groups[{}].specimens", core.name),
                    format!("{unit} is not a unit of the measured file"),
                ));
            };
            if (s.sigma0_mpa - group.sigma0_mpa).abs() > 1e-9 {
                return Err(bad(
                    format!("groups[{}].specimens", core.name),
                    format!("{unit} was tested at {} MPa, the group at {} MPa", s.sigma0_mpa, group.sigma0_mpa),
                ));
            }
            specimen_observations(unit, s, &name, settings.sigma, &mut obs);
        }
    }
    if obs.is_empty() {
        return Err(bad("groups[].specimens".into(), "no group names a measured specimen: nothing to compare".into()));
    }
    let mut settings = settings;
    let stated = stated_sigma_keys(path);
    settings.sigma_notes = sigma_from_data(&mut obs, &stated);
    settings.sigma_notes.extend(asymmetry_sigma_from_data(&mut obs, &stated, settings.sigma.asymmetry_kn));
    let protocol = groups[0].protocol.clone().unwrap_or_else(|| Protocol::InPlane(InPlane(test.params.clone())));
    let setup = Setup { groups, seed: study.seed, solver: study.solver, protocol, store: None };
    Ok(Analysis {
        name: study.name.clone(),
        seed: study.seed,
        setup,
        obs,
        settings,
        library: crate::effects::Library::builtin(),
    })
}

/// The observations of the measured specimen `s` (unit `unit`) of the analysis's group
/// `name`, each with its σ of `sigma`, pushed onto `obs` (module documentation): the peak
/// force, the drift at the peak, the initial stiffness, the vertical modulus (once a group),
/// the peaks' asymmetry, and the mode where the failure type tells it.
fn specimen_observations(
    unit: &str,
    s: &super::inplane::Specimen,
    name: &str,
    sigma: crate::discrepancy::MeasurementSigma,
    obs: &mut Vec<Observation>,
) {
    for (quantity, value, sd) in [
        (InPlaneQuantity::PeakForce, s.vmax_pos_kn, sigma.force_kn),
        (InPlaneQuantity::DriftAtPeak, s.dmax_pos_pct, sigma.drift_pct),
        (InPlaneQuantity::InitialStiffness, s.kel_pos, sigma.stiffness_kn_per_mm),
        (InPlaneQuantity::VerticalModulus, s.epc_mpa, sigma.modulus_mpa),
        // A cyclic specimen's two directions' peaks (each a magnitude in the
        // database's columns): the rig's asymmetry. NaN for a monotonic specimen.
        (InPlaneQuantity::PeakAsymmetry, s.vmax_neg_kn.abs() - s.vmax_pos_kn, sigma.asymmetry_kn),
    ] {
        // The database gives one vertical modulus per stress level of a campaign
        // (the same number in every specimen's row): one reading of the group, not
        // one per specimen.
        let repeated = quantity == InPlaneQuantity::VerticalModulus
            && obs.iter().any(|o: &Observation| {
                o.group == name && o.observable == Observable::InPlane { quantity } && o.value == value
            });
        if value.is_finite() && !repeated {
            obs.push(Observation {
                specimen: unit.to_string(),
                group: name.to_string(),
                observable: Observable::InPlane { quantity },
                value,
                sigma: sd,
            });
        }
    }
    let mode = if s.failure_type == 1.0 {
        Some(MechanismKind::Rocking)
    } else if s.failure_type == 0.5 {
        Some(MechanismKind::Mixed)
    } else {
        None
    };
    if let Some(mode) = mode {
        obs.push(Observation {
            specimen: unit.to_string(),
            group: name.to_string(),
            observable: Observable::InPlaneMode { mode },
            value: 1.0,
            sigma: 0.0,
        });
    }
}

/// The typical scatter between nominally equal specimens of a shear–compression test, as a
/// coefficient of variation, for the measures whose σ a study does not state: the prior of
/// [`sigma_from_data`]. Estimates (reasoning: repeated in-plane tests of nominally equal
/// masonry walls scatter by 5–10 % in their peak force, by a quarter to a third in the drift
/// at the peak and the initial stiffness, which depend on the seating of the first
/// increments (the Stone Masonry Database's repeated specimens, Vanin et al. 2017, Bull.
/// Earthquake Eng. 15:5435; the granite walls' four repeats at 0.5 MPa, Vasconcelos &
/// Lourenço 2009, show 0.03 and 9.2–35.6 kN/mm); not checked against a survey of
/// campaigns).
pub const PRIOR_COV: [(InPlaneQuantity, &str, &str, f64); 3] = [
    (InPlaneQuantity::PeakForce, "force_kn", "peak forces", 0.08),
    (InPlaneQuantity::DriftAtPeak, "drift_pct", "drifts at the peak", 0.30),
    (InPlaneQuantity::InitialStiffness, "stiffness_kn_per_mm", "initial stiffnesses", 0.35),
];

/// The weight of [`PRIOR_COV`] in degrees of freedom: two, a group of three repeats.
pub const PRIOR_DOF: f64 = 2.0;

/// The keys of `[discrepancy.sigma]` the study file states (empty when it cannot be read
/// again: its errors were reported by the first read).
fn stated_sigma_keys(path: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return vec![];
    };
    let Ok(table) = text.parse::<toml::Table>() else {
        return vec![];
    };
    table
        .get("discrepancy")
        .and_then(|d| d.get("sigma"))
        .and_then(|s| s.as_table())
        .map(|t| t.keys().cloned().collect())
        .unwrap_or_default()
}

/// Sets the σ of the in-plane measures whose `[discrepancy.sigma]` key the study does not
/// state (`stated`) from the data: the coefficient of variation of the repeats, pooled over
/// the groups (each group's squared deviations from its mean, relative to it, `n − 1`
/// degrees of freedom) with the prior [`PRIOR_COV`] of weight [`PRIOR_DOF`],
/// `cov² = (ν0 c0² + Σ Σ ((x − x̄) / x̄)²) / (ν0 + Σ (n − 1))`; each observation's σ becomes
/// the larger of its setting (the instrument's) and `cov × |x̄|` of its group. Returns one
/// sentence per family so set, saying how (the report prints them).
pub fn sigma_from_data(obs: &mut [Observation], stated: &[String]) -> Vec<String> {
    let mut notes = Vec::new();
    for (quantity, key, what, prior) in PRIOR_COV {
        if stated.iter().any(|k| k == key) {
            continue;
        }
        let of = |o: &Observation| o.observable == Observable::InPlane { quantity } && o.value.is_finite();
        let groups = readings_by_group(obs, quantity);
        if groups.is_empty() {
            continue;
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let (mut ss, mut dof, mut repeated) = (0.0, 0usize, 0usize);
        for (_, v) in groups.iter().filter(|g| g.1.len() >= 2) {
            let m = mean(v);
            if m != 0.0 {
                ss += v.iter().map(|x| ((x - m) / m).powi(2)).sum::<f64>();
                dof += v.len() - 1;
                repeated += 1;
            }
        }
        let cov = ((PRIOR_DOF * prior * prior + ss) / (PRIOR_DOF + dof as f64)).sqrt();
        for o in obs.iter_mut().filter(|o| of(o)) {
            let m = groups.iter().find(|g| g.0 == o.group).map_or(o.value, |g| mean(&g.1));
            o.sigma = o.sigma.max(cov * m.abs());
        }
        notes.push(if dof == 0 {
            format!(
                "{what}: σ = {cov:.3} × the group's mean (no group has repeats: the typical scatter of the test, COV {prior}), the larger of it and the setting"
            )
        } else {
            format!(
                "{what}: σ = {cov:.3} × the group's mean, the repeats' COV pooled over {repeated} groups ({dof} degrees of freedom) with the test's typical COV {prior} (weight {PRIOR_DOF}), the larger of it and the setting"
            )
        });
    }
    notes
}

/// The finite readings of `quantity` in `obs`, per group, in the order the groups first
/// appear.
fn readings_by_group(obs: &[Observation], quantity: InPlaneQuantity) -> Vec<(String, Vec<f64>)> {
    let mut groups: Vec<(String, Vec<f64>)> = Vec::new();
    for o in obs.iter().filter(|o| o.observable == Observable::InPlane { quantity } && o.value.is_finite()) {
        match groups.iter_mut().find(|g| g.0 == o.group) {
            Some(g) => g.1.push(o.value),
            None => groups.push((o.group.clone(), vec![o.value])),
        }
    }
    groups
}

/// Sets the σ of the peaks' ± asymmetries ([`InPlaneQuantity::PeakAsymmetry`]) from the
/// data when `[discrepancy.sigma] asymmetry_kn` is not stated: the repeats' spread pooled
/// over the groups in kN (a difference that can be 0 has no coefficient of variation),
/// `σ² = (ν0 σ0² + Σ Σ (x − x̄)²) / (ν0 + Σ (n − 1))`, the setting `setting` (kN) as the
/// prior `σ0` of weight [`PRIOR_DOF`]; each observation's σ becomes the larger of it and
/// the setting. Returns the sentence the report prints, or nothing.
pub fn asymmetry_sigma_from_data(obs: &mut [Observation], stated: &[String], setting: f64) -> Option<String> {
    if stated.iter().any(|k| k == "asymmetry_kn") {
        return None;
    }
    let quantity = InPlaneQuantity::PeakAsymmetry;
    let of = |o: &Observation| o.observable == Observable::InPlane { quantity } && o.value.is_finite();
    let groups = readings_by_group(obs, quantity);
    if groups.is_empty() {
        return None;
    }
    let (mut ss, mut dof) = (0.0, 0usize);
    for (_, v) in groups.iter().filter(|g| g.1.len() >= 2) {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        ss += v.iter().map(|x| (x - m).powi(2)).sum::<f64>();
        dof += v.len() - 1;
    }
    let sd = ((PRIOR_DOF * setting * setting + ss) / (PRIOR_DOF + dof as f64)).sqrt();
    for o in obs.iter_mut().filter(|o| of(o)) {
        o.sigma = o.sigma.max(sd);
    }
    Some(format!(
        "peaks' ± asymmetries: σ = {sd:.3} kN, the repeats' spread pooled over the groups ({dof} degrees of freedom) with the setting {setting} kN as the prior (weight {PRIOR_DOF}), the larger of it and the setting"
    ))
}

/// A measured group of the check: the index of the analysis's group, its vertical stress
/// (MPa), its specimens' readings `(unit, ξ_eq)`, and the turning points of each one's
/// measured history (drift %, [`InPlaneParams::reversals_pct`]; in the readings' order). A
/// group whose histories are all empty (none given, or `vec![]`) is run by the study's
/// history on [`super::inplane_loops::LOOP_REALIZATIONS`] layouts; otherwise each specimen with a history is run
/// on it, on the layout of its index in the group, and a specimen without one is not run.
pub type MeasuredLoops = (usize, f64, Vec<(String, f64)>, Vec<Vec<f64>>);

/// The measured loops of the in-plane study `study` analysed as `input`: per analysis group
/// with cyclic specimens whose curves are read (`[measured] curves`), its index, stress and
/// readings; and the cyclic test of a stress (the study's history). `None` when the study
/// reads no curve or no cyclic specimen has one.
///
/// # Errors
/// [`InPlaneStudyError::Invalid`] at `protocol` for a study of another protocol.
#[allow(clippy::type_complexity)]
pub fn measured_loops(
    study: &Study,
    input: &Analysis,
) -> Result<Option<(Vec<MeasuredLoops>, InPlaneParams)>, InPlaneStudyError> {
    let Prepared { test, .. } = Prepared::of(study)?;
    // The loops are read only with `[measured] curves` (their damping ratio NaN without).
    if !test.specimens.iter().any(|s| s.damping_ratio.is_finite()) {
        return Ok(None);
    }
    let specimens = &test.specimens;
    let mut groups: Vec<MeasuredLoops> = Vec::new();
    for g in test.groups.iter().filter(|g| g.history == History::Cyclic) {
        let name = stress_group(g.sigma0_mpa);
        let Some(k) = input.setup.groups.iter().position(|x| x.name == name) else {
            continue;
        };
        let of: Vec<&crate::study::inplane::Specimen> = g
            .specimens
            .iter()
            .filter_map(|u| specimens.iter().find(|s| &s.unit == u))
            .filter(|s| s.damping_ratio.is_finite())
            .collect();
        if of.is_empty() {
            continue;
        }
        let read: Vec<(String, f64)> = of.iter().map(|s| (s.unit.clone(), s.damping_ratio)).collect();
        let histories: Vec<Vec<f64>> = of.iter().map(|s| s.reversals_pct.clone()).collect();
        match groups.iter_mut().find(|(j, _, _, _)| *j == k) {
            Some((_, _, r, h)) => {
                r.extend(read);
                h.extend(histories);
            }
            None => groups.push((k, g.sigma0_mpa, read, histories)),
        }
    }
    let cyclic = InPlaneParams { history: History::Cyclic, ..test.params.clone() };
    Ok((!groups.is_empty()).then_some((groups, cyclic)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(group: &str, quantity: InPlaneQuantity, value: f64, sigma: f64) -> Observation {
        Observation {
            specimen: format!("{group}{value}"),
            group: group.into(),
            observable: Observable::InPlane { quantity },
            value,
            sigma,
        }
    }

    fn force(group: &str, value: f64) -> Observation {
        reading(group, InPlaneQuantity::PeakForce, value, 0.5)
    }

    fn asymmetry(group: &str, value: f64) -> Observation {
        reading(group, InPlaneQuantity::PeakAsymmetry, value, 0.7)
    }

    /// By hand: group a reads 3 and 5 kN (mean 4, squared deviations 2, one degree of
    /// freedom), b reads 7 alone; with the setting 0.7 kN as the prior of weight 2,
    /// σ² = (2 × 0.49 + 2) / 3, in kN for every specimen (not relative to the mean: an
    /// asymmetry can be 0). A peak force beside them keeps its σ; a stated key keeps the
    /// setting.
    #[test]
    fn the_sigma_of_the_asymmetry_is_the_repeats_spread_pooled_in_kn_with_the_setting_as_prior() {
        let mut obs = vec![asymmetry("a", 3.0), asymmetry("a", 5.0), asymmetry("b", 7.0), force("a", 10.0)];
        let note = asymmetry_sigma_from_data(&mut obs, &[], 0.7).expect("a note");
        let sd = ((2.0 * 0.49 + 2.0) / 3.0f64).sqrt();
        for o in &obs[..3] {
            assert!((o.sigma - sd).abs() < 1e-12, "{} vs {sd}", o.sigma);
        }
        assert_eq!(obs[3].sigma, 0.5);
        assert!(note.contains("1 degrees of freedom"), "{note}");
        let mut obs = vec![asymmetry("a", 3.0), asymmetry("a", 5.0)];
        assert!(asymmetry_sigma_from_data(&mut obs, &["asymmetry_kn".to_string()], 0.7).is_none());
        assert!(obs.iter().all(|o| o.sigma == 0.7));
        // Repeats that agree to the digit leave the setting.
        let mut obs = vec![asymmetry("a", 4.0), asymmetry("a", 4.0)];
        let _ = asymmetry_sigma_from_data(&mut obs, &[], 0.7);
        assert!(obs.iter().all(|o| o.sigma == 0.7), "{:?}", obs.iter().map(|o| o.sigma).collect::<Vec<_>>());
    }

    /// By hand: group a reads 10 and 12 (mean 11, relative deviations ±1/11, one degree of
    /// freedom), b reads 20 alone; with the prior COV 0.08 of weight 2,
    /// cov² = (2 × 0.0064 + 2/121) / 3; a's σ is cov × 11, b's cov × 20. A stated key keeps
    /// the setting's σ.
    #[test]
    fn the_sigma_of_an_unstated_measure_is_the_repeats_cov_pooled_with_the_tests_prior() {
        let mut obs = vec![force("a", 10.0), force("a", 12.0), force("b", 20.0)];
        let notes = sigma_from_data(&mut obs, &[]);
        let cov = ((2.0 * 0.0064 + 2.0 / 121.0) / 3.0f64).sqrt();
        assert!((obs[0].sigma - cov * 11.0).abs() < 1e-12, "{}", obs[0].sigma);
        assert!((obs[1].sigma - cov * 11.0).abs() < 1e-12);
        assert!((obs[2].sigma - cov * 20.0).abs() < 1e-12);
        assert_eq!(notes.len(), 1);
        assert!(notes[0].contains("1 degrees of freedom") && notes[0].contains("peak forces"), "{notes:?}");
        let mut obs = vec![force("a", 10.0), force("a", 12.0)];
        assert!(sigma_from_data(&mut obs, &["force_kn".to_string()]).is_empty());
        assert!(obs.iter().all(|o| o.sigma == 0.5));
        // No repeats: the prior alone.
        let mut obs = vec![force("a", 10.0), force("b", 20.0)];
        let notes = sigma_from_data(&mut obs, &[]);
        assert!((obs[1].sigma - 0.08 * 20.0).abs() < 1e-12);
        assert!(notes[0].contains("no group has repeats"), "{notes:?}");
    }
}
