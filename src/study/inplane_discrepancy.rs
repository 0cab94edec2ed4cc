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
//! Per specimen the first direction loaded (+x, the database's `pos` columns): the peak
//! force (kN), the drift at the peak (%), the initial stiffness (kN/mm), each with the
//! measurement σ of `[discrepancy.sigma]`, and the mode (`InPlaneMode`, value 1): failure
//! type 1 read as rocking, 0.5 as mixed; a failure type 0 (sliding or diagonal, which the
//! database does not tell apart) gives no mode reading. The reverse direction of a cyclic
//! specimen is loaded after the damage of the first and is left to the study's cyclic runs.

use super::inplane::{load, read_specimens, refuse_out_of_plane, InPlaneStudyError};
use super::own::OwnAnalysis;
use crate::discrepancy::{GroupSetup, InPlaneQuantity, Observable, Observation, Setup};
use crate::generator::{DistributionSource, Wall};
use crate::loading::inplane::{History, InPlaneParams, MechanismKind};
use crate::protocol::{InPlane, Protocol};
use std::path::Path;

/// The name of the analysis's group of vertical stress `sigma0` (MPa): `0.5 MPa`.
pub fn stress_group(sigma0_mpa: f64) -> String {
    format!("{sigma0_mpa} MPa")
}

/// Reads an in-plane study for its discrepancy analysis (module documentation).
///
/// # Errors
/// A bad study, wall or measured file, or a specimen whose stress is not its group's,
/// naming the file and the key; an effect the test does not read
/// ([`refuse_out_of_plane`]).
pub fn analysis_of(path: &Path) -> Result<OwnAnalysis, InPlaneStudyError> {
    let spec = load(path)?;
    refuse_out_of_plane(&spec, path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let bad = |key: String, message: String| InPlaneStudyError::Invalid { path: path.to_owned(), key, message };
    let settings = spec.discrepancy.clone().unwrap_or_default();
    settings.validate().map_err(|e| bad("discrepancy".into(), e.to_string()))?;
    let Some(measured) = &spec.measured else {
        return Err(bad("measured".into(), "the analysis needs the measured specimens ([measured] walls)".into()));
    };
    let specimens = read_specimens(&base.join(&measured.walls), None)?;
    let realizations = settings.most_realizations();
    let mut groups: Vec<GroupSetup> = Vec::new();
    let mut walls_of: Vec<std::path::PathBuf> = Vec::new();
    let mut effects_of: Vec<usize> = Vec::new();
    let mut obs = Vec::new();
    for (g, group) in spec.groups.iter().enumerate() {
        let name = stress_group(group.sigma0_mpa);
        match groups.iter().position(|x| x.name == name) {
            Some(k) if walls_of[k] != group.wall => {
                return Err(bad(
                    format!("groups[{g}].wall"),
                    format!(
                        "{}: the groups of {name} must share one wall for the analysis ({} is the first's)",
                        group.wall.display(),
                        walls_of[k].display()
                    ),
                ))
            }
            Some(k)
                if super::inplane::stated_effects(&spec, effects_of[k]) != super::inplane::stated_effects(&spec, g) =>
            {
                return Err(bad(
                    format!("groups[{g}].effects"),
                    format!(
                        "the groups of {name} must share one model for the analysis (groups[{}]'s effects)",
                        effects_of[k]
                    ),
                ))
            }
            Some(_) => {}
            None => {
                let p = base.join(&group.wall);
                let wall = Wall::from_file_with(&p, &DistributionSource::default_for(&p))
                    .map_err(|e| InPlaneStudyError::File { path: p.clone(), message: e.to_string() })?;
                let effects = super::inplane::group_effects(&spec, path, g, &wall)?;
                let layout =
                    |r: u64| crate::effects::realize(&wall, spec.seed, r, &name, &effects).ok().map(|(_, l)| l);
                let first = layout(0);
                let deterministic = first.is_some() && first == layout(1);
                let params = InPlaneParams {
                    sigma0_mpa: group.sigma0_mpa,
                    history: History::Monotonic,
                    ..spec.in_plane.clone()
                };
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
                walls_of.push(group.wall.clone());
                effects_of.push(g);
            }
        }
        for unit in &group.specimens {
            let Some(s) = specimens.iter().find(|s| &s.unit == unit) else {
                return Err(bad(
                    format!("groups[{g}].specimens"),
                    format!("{unit} is not a unit of the measured file"),
                ));
            };
            if (s.sigma0_mpa - group.sigma0_mpa).abs() > 1e-9 {
                return Err(bad(
                    format!("groups[{g}].specimens"),
                    format!("{unit} was tested at {} MPa, the group at {} MPa", s.sigma0_mpa, group.sigma0_mpa),
                ));
            }
            let sigma = settings.sigma;
            for (quantity, value, sd) in [
                (InPlaneQuantity::PeakForce, s.vmax_pos_kn, sigma.force_kn),
                (InPlaneQuantity::DriftAtPeak, s.dmax_pos_pct, sigma.drift_pct),
                (InPlaneQuantity::InitialStiffness, s.kel_pos, sigma.stiffness_kn_per_mm),
                (InPlaneQuantity::VerticalModulus, s.epc_mpa, sigma.modulus_mpa),
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
                        specimen: unit.clone(),
                        group: name.clone(),
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
                    specimen: unit.clone(),
                    group: name.clone(),
                    observable: Observable::InPlaneMode { mode },
                    value: 1.0,
                    sigma: 0.0,
                });
            }
        }
    }
    if obs.is_empty() {
        return Err(bad("groups[].specimens".into(), "no group names a measured specimen: nothing to compare".into()));
    }
    let protocol = groups[0].protocol.clone().unwrap_or_else(|| Protocol::InPlane(InPlane(spec.in_plane.clone())));
    let setup = Setup { groups, seed: spec.seed, solver: crate::dem::SolverParams::default(), protocol, store: None };
    Ok(OwnAnalysis {
        name: spec.name,
        seed: spec.seed,
        setup,
        obs,
        settings,
        library: crate::effects::Library::builtin(),
    })
}
