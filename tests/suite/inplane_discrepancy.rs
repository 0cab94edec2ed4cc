//! The discrepancy analysis on in-plane data (`study::inplane_discrepancy`,
//! `Observable::InPlane`): a hidden effect found in data made by an independent path.
//!
//! The "measured" walls are the granite wall with its joints' Kn and Ks scaled by 0.3 in the
//! wall description itself (the material's numbers edited, as a real wall's softer beds
//! differ from the calibration; not the `kn_scale` effect's code), generated on a seed of
//! their own, pushed by the penalty DEM, and read as the database reads a test: peak force
//! to 0.1 kN, drift to 0.01 %, stiffness to 0.1 kN/mm. The model is the wall as described;
//! the analysis searches `kn_scale` and `toe_crushing` and must name the first, with its
//! factor's interval holding 0.3.
//!
//! A second hidden cause is the rig's, not the wall's: a vertical load applied by a jack
//! hinged 2.5 m from the beam (1/L = 0.4 per m). The "measured" curves are the plain wall's,
//! pushed by the penalty DEM, with `N u / L` added here to each point's force (the statics
//! of the leaning jack, written in this file, not through the effect's code), then read as
//! the database reads a test (the peak of the envelope and the drift where it is reached,
//! to its digits). The analysis searches `rig_friction` (which raises the peak without
//! moving it) and `jack_tilt`, and must name the second with 1/L's interval holding 0.4.
//! The in-plane study's command on the bundled walls is
//! tested for its refusals (its full run is the README's and docs/inplane.md's).

use drystone::dem::SolverParams;
use drystone::discrepancy::{GroupSetup, InPlaneQuantity, Observable, Observation, Settings, Setup};
use drystone::effects::Library;
use drystone::generator::{generate, Wall};
use drystone::loading::inplane::{run_in_plane_penalty, InPlaneParams};
use drystone::protocol::{InPlane, Protocol};
use std::path::Path;

const WALL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/walls/granite_vasconcelos.toml");
/// The hidden factor on Kn and Ks.
const HIDDEN: f64 = 0.3;

fn params(sigma0_mpa: f64) -> InPlaneParams {
    InPlaneParams { sigma0_mpa, shear_span_m: Some(1.325), drift_pct: 0.6, ..InPlaneParams::default() }
}

fn round(v: f64, r: f64) -> f64 {
    (v / r).round() * r
}

#[test]
fn a_softer_joint_hidden_in_in_plane_data_is_named() {
    let wall = Wall::from_file(Path::new(WALL)).unwrap();
    let mut soft = wall.clone();
    for m in &mut soft.materials {
        m.kn_pa_per_m *= HIDDEN;
        m.ks_pa_per_m *= HIDDEN;
    }
    let solver = SolverParams::default();
    let mut obs = Vec::new();
    let mut groups = Vec::new();
    for sigma in [0.5, 1.0] {
        let name = format!("{sigma} MPa");
        for i in 0..3 {
            let layout = generate(&soft, 4242, i).unwrap().check().unwrap();
            let r = run_in_plane_penalty(&layout, solver, &params(sigma), &mut |_, _, _| {}).unwrap();
            let d = r.positive.unwrap();
            for (quantity, v, res, sd) in [
                (InPlaneQuantity::PeakForce, d.peak_force_kn, 0.1, 0.5),
                (InPlaneQuantity::InitialStiffness, d.initial_stiffness_kn_per_mm, 0.1, 2.0),
            ] {
                obs.push(Observation {
                    specimen: format!("S{sigma}-{i}"),
                    group: name.clone(),
                    observable: Observable::InPlane { quantity },
                    value: round(v, res),
                    sigma: sd,
                });
            }
        }
        groups.push(GroupSetup {
            name,
            course_m: drystone::effects::course_height_of(&wall),
            wall: wall.clone(),
            realizations: 4,
            restrained: false,
            deterministic: false,
            effects: vec![],
            protocol: Some(Protocol::InPlane(InPlane(params(sigma)))),
        });
    }
    let setup = Setup { groups, seed: 7, solver, protocol: Protocol::InPlane(InPlane(params(0.5))) };
    let mut s = Settings::default();
    (s.realizations, s.extension_realizations, s.null_realizations) = (2, 3, 3);
    (s.grid_points, s.null_replicates, s.check_replicates, s.bootstrap) = (4, 40, 40, 200);
    s.effects = vec!["kn_scale".into(), "toe_crushing".into()];
    let run = drystone::discrepancy::run(&setup, obs, &s, 11, &Library::builtin()).unwrap();
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| c.name.clone());
    assert!(
        cause.as_deref().is_some_and(|c| c.starts_with("kn_scale")),
        "named {cause:?}, verdict {}",
        a.verdict.name()
    );
    let factor = run.cause_interval.iter().find(|p| p.name == "kn_scale.factor").expect("the factor's interval");
    assert!(
        factor.interval.0 <= HIDDEN && HIDDEN <= factor.interval.1,
        "kn_scale.factor {} {:?} does not hold the hidden {HIDDEN}",
        factor.value,
        factor.interval
    );
}

/// The hidden 1/L of the leaning jack, per m.
const HIDDEN_INVERSE_LENGTH: f64 = 0.4;

#[test]
fn a_leaning_jack_hidden_in_in_plane_data_is_named() {
    let wall = Wall::from_file(Path::new(WALL)).unwrap();
    let solver = SolverParams::default();
    let push = |sigma0_mpa: f64| InPlaneParams { drift_pct: 2.0, ..params(sigma0_mpa) };
    let mut obs = Vec::new();
    let mut groups = Vec::new();
    for sigma in [0.5, 0.875] {
        let name = format!("{sigma} MPa");
        for i in 0..3 {
            let layout = generate(&wall, 4343, i).unwrap().check().unwrap();
            let r = run_in_plane_penalty(&layout, solver, &push(sigma), &mut |_, _, _| {}).unwrap();
            // The jack: N = σ0 L t of the wall's plan, pulling the beam back by N u / L.
            let n_kn = sigma * 1e3 * r.length_m * r.thickness_m;
            let (peak, drift) = r
                .curve
                .iter()
                .map(|p| (p.force_kn + n_kn * p.top_mm * 1e-3 * HIDDEN_INVERSE_LENGTH, p.drift_pct))
                .fold((f64::NEG_INFINITY, 0.0), |best, p| if p.0 > best.0 { p } else { best });
            for (quantity, v, res, sd) in
                [(InPlaneQuantity::PeakForce, peak, 0.1, 0.5), (InPlaneQuantity::DriftAtPeak, drift, 0.01, 0.15)]
            {
                obs.push(Observation {
                    specimen: format!("S{sigma}-{i}"),
                    group: name.clone(),
                    observable: Observable::InPlane { quantity },
                    value: round(v, res),
                    sigma: sd,
                });
            }
        }
        groups.push(GroupSetup {
            name,
            course_m: drystone::effects::course_height_of(&wall),
            wall: wall.clone(),
            realizations: 4,
            restrained: false,
            deterministic: false,
            effects: vec![],
            protocol: Some(Protocol::InPlane(InPlane(push(sigma)))),
        });
    }
    let setup = Setup { groups, seed: 7, solver, protocol: Protocol::InPlane(InPlane(push(0.5))) };
    let mut s = Settings::default();
    (s.realizations, s.extension_realizations, s.null_realizations) = (2, 3, 3);
    (s.grid_points, s.null_replicates, s.check_replicates, s.bootstrap) = (4, 40, 40, 200);
    s.effects = vec!["rig_friction".into(), "jack_tilt".into()];
    let run = drystone::discrepancy::run(&setup, obs, &s, 11, &Library::builtin()).unwrap();
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| c.name.clone());
    assert!(
        cause.as_deref().is_some_and(|c| c.starts_with("jack_tilt")),
        "named {cause:?}, verdict {}",
        a.verdict.name()
    );
    let p = run.cause_interval.iter().find(|p| p.name == "jack_tilt.inverse_length_per_m").expect("1/L's interval");
    assert!(
        p.interval.0 <= HIDDEN_INVERSE_LENGTH && HIDDEN_INVERSE_LENGTH <= p.interval.1,
        "jack_tilt 1/L {} {:?} does not hold the hidden {HIDDEN_INVERSE_LENGTH}",
        p.value,
        p.interval
    );
}
