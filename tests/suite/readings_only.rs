//! Effects that act only on the readings (`jack_tilt`, `rig_friction`, `jack_incline`: the
//! in-plane rig's vertical load, a force the displacement-controlled beam carries on top of
//! the wall's shear; `series_compliance`, a displacement read on top of the beam's) make no run in the discrepancy analysis: the model with them is the run
//! without them read again. Here a realization run with such an effect and the same
//! realization's run without it read again give the same observables, bit for bit, on a
//! small granite wall (a monotonic push and a cyclic one, where the bearing's friction
//! changes sense), alone and beside an effect that moves the wall.

use drystone::dem::SolverParams;
use drystone::discrepancy::{forward_runs, run_models, run_one, GroupSetup, Outcome, Setup};
use drystone::effects::{Effect, Library};
use drystone::generator::Wall;
use drystone::loading::inplane::{History, InPlaneParams};
use drystone::protocol::{InPlane, Protocol};
use std::path::Path;

const WALL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/walls/granite_vasconcelos.toml");

pub(crate) fn setup() -> Setup {
    let wall = Wall::from_file(Path::new(WALL)).unwrap();
    let group = |name: &str, history: History| {
        let p = InPlaneParams {
            sigma0_mpa: 0.5,
            shear_span_m: Some(1.325),
            drift_pct: 0.4,
            history,
            cycles: 1,
            ..InPlaneParams::default()
        };
        GroupSetup {
            name: name.into(),
            course_m: drystone::effects::course_height_of(&wall),
            wall: wall.clone(),
            realizations: 1,
            restrained: false,
            deterministic: false,
            effects: vec![],
            protocol: Some(Protocol::InPlane(InPlane(p))),
        }
    };
    let groups = vec![group("monotonic", History::Monotonic), group("cyclic", History::Cyclic)];
    let protocol = groups[0].protocol.clone().expect("set");
    Setup { groups, seed: 5, solver: SolverParams::default(), protocol, store: None }
}

fn effect(name: &str, v: f64) -> Effect {
    let def = Library::builtin().get(name).unwrap();
    Effect::new(def, vec![v], drystone::effects::REFERENCE_COURSE_HEIGHT_M).unwrap()
}

/// The in-plane observables as bits (NaN compares equal to itself).
fn bits(o: &Outcome) -> Option<(u64, u64, u64, String)> {
    let m = o.observed.in_plane?;
    Some((
        m.peak_force_kn.to_bits(),
        m.drift_at_peak_pct.to_bits(),
        m.initial_stiffness_kn_per_mm.to_bits(),
        m.mode.name().to_string(),
    ))
}

#[test]
fn a_run_with_a_readings_only_effect_is_the_run_without_it_read_again() {
    let setup = setup();
    let base = run_models(&setup, &[vec![]], None).remove(0);
    let soft = effect("kn_scale", 0.5);
    let models = vec![
        vec![effect("jack_tilt", 0.3)],
        vec![effect("jack_tilt", 1.0)],
        vec![effect("rig_friction", 0.02)],
        vec![effect("jack_tilt", 0.6), effect("rig_friction", 0.05)],
        vec![soft.clone()],
        vec![effect("jack_tilt", 0.54), soft.clone()],
        vec![soft.clone(), effect("rig_friction", 0.01)],
        vec![effect("jack_incline", -0.013)],
        vec![effect("series_compliance", 0.05), effect("jack_tilt", 0.5)],
        vec![soft.clone(), effect("series_compliance", 0.03), effect("jack_incline", 0.02)],
    ];
    assert!(models.iter().flatten().filter(|e| e.name() != "kn_scale").all(|e| e.def.acts_on_readings_only()));
    assert!(!soft.def.acts_on_readings_only());
    // Only kn_scale's walls are run, once for the three models that share it.
    let per_model = setup.groups.iter().map(|g| g.realizations as usize).sum::<usize>();
    assert_eq!(forward_runs(&setup, &models, true), per_model);
    assert_eq!(forward_runs(&setup, &models[..4], true), 0);
    assert_eq!(forward_runs(&setup, &models[7..9], true), 0);
    assert_eq!(forward_runs(&setup, &models[..1], false), per_model, "nothing to read again: the baseline is run");
    let reread = run_models(&setup, &models, Some(&base));
    for (m, outs) in models.iter().zip(&reread) {
        for (g, group) in outs.iter().enumerate() {
            for (r, o) in group.iter().enumerate() {
                let own = run_one(&setup, g, r as u64, m);
                let label: Vec<String> = m.iter().map(Effect::label).collect();
                assert!(own.error.is_none() && bits(&own).is_some(), "{label:?}: {own:?}");
                assert_eq!(bits(o), bits(&own), "{label:?} group {g} realization {r}");
                assert_eq!(o, &own, "{label:?}: the whole outcome");
            }
        }
    }
    // The rig moved the readings: the leaning jack raises the peak.
    let peak = |o: &Outcome| o.observed.in_plane.map(|m| m.peak_force_kn).unwrap_or(f64::NAN);
    assert!(peak(&reread[1][0][0]) > peak(&base[0][0]), "{} vs {}", peak(&reread[1][0][0]), peak(&base[0][0]));
}

/// The surrogate library of an in-plane setup: an effect on the readings only has no grid
/// runs, and its pairs with every other searched effect (of one parameter, and of two:
/// `joint_closure`, a three-coordinate grid) stand on the partner's runs, equal at every
/// node to the partner's run read again.
#[test]
fn readings_only_effects_pair_with_every_effect_on_its_runs() {
    use drystone::discrepancy::{build_library, InPlaneQuantity, Keys, Observable, Observation, Settings};
    let setup = setup();
    let obs: Vec<Observation> = ["monotonic", "cyclic"]
        .iter()
        .flat_map(|g| {
            [InPlaneQuantity::PeakForce, InPlaneQuantity::DriftAtPeak].map(|quantity| Observation {
                specimen: format!("{g}-1"),
                group: g.to_string(),
                observable: Observable::InPlane { quantity },
                value: 1.0,
                sigma: 0.5,
            })
        })
        .collect();
    let keys = Keys::new(&setup, &obs);
    let mut s = Settings::default();
    (s.realizations, s.grid_points, s.grid_points_2d, s.scatter) = (1, 2, 2, false);
    let lib = Library::builtin();
    let defs: Vec<_> = ["kn_scale", "joint_closure", "jack_tilt", "rig_friction"].map(|n| lib.get(n).unwrap()).into();
    let base = run_models(&setup, &[vec![]], None).remove(0);
    let (models, runs, _) = build_library(&setup, &keys, &base, &s, &defs).unwrap();
    // kn_scale: 2 nodes off its neutral one; joint_closure: 2 × 2 nodes; 2 groups × 1
    // realization each; nothing for jack_tilt and rig_friction.
    assert_eq!(runs, (2 + 4) * 2);
    let names: Vec<String> = models.readings_pairs.iter().map(|c| c.name()).collect();
    assert_eq!(
        names,
        [
            "jack_tilt+kn_scale",
            "jack_tilt+joint_closure",
            "jack_tilt+rig_friction",
            "rig_friction+kn_scale",
            "rig_friction+joint_closure"
        ]
    );
    let dims: Vec<usize> = models.readings_pairs.iter().map(|c| c.surface.dims()).collect();
    assert_eq!(dims, [2, 3, 2, 2, 3]);
    let close = |a: f64, b: f64| (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-9 * b.abs().max(1.0);
    // At the readings' neutral point the pair is its partner.
    let single = |n: &str| models.candidates.iter().find(|c| c.name() == n).unwrap();
    let pair = &models.readings_pairs[1];
    for x in [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [0.0, 0.3, 0.7]] {
        let (a, b) = (pair.surface.at(&x), single("joint_closure").surface.at(&x[1..]));
        for (p, q) in a.iter().zip(&b) {
            assert!(close(p.mean, q.mean), "{x:?}: {p:?} vs {q:?}");
        }
    }
    // And with the partner at its neutral point, the single effect on the readings.
    let jack = &models.readings_pairs[0];
    let p = &single("kn_scale").params[0];
    let xn = (p.neutral / p.min).ln() / (p.max / p.min).ln();
    for r in [0.0, 0.5, 1.0] {
        let (a, b) = (jack.surface.at(&[r, xn]), single("jack_tilt").surface.at(&[r]));
        for (p, q) in a.iter().zip(&b) {
            assert!(close(p.mean, q.mean), "{r}: {p:?} vs {q:?}");
        }
    }
}
