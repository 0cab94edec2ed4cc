//! The penalty DEM's solve settings are the method's (`[solver.penalty]`,
//! `drystone::dem::PenaltyParams`); the protocols' former keys (`[tilt] tolerance`,
//! `max_steps_per_increment`, `predictor`, `acceleration`, `implicit_solve`, `[lateral]
//! tolerance`, `max_steps`, `[shake] contact_restitution`, `penalty_step_fraction`) keep
//! working with a deprecation warning. Each former key must give the run the new key gives,
//! bit for bit, and a different run from the default (so that the key is read at all).

use drystone::dem::{PenaltyParams, SolverKind, SolverParams};
use drystone::ground::Pulse;
use drystone::layout::BaseSliding;
use drystone::loading::lateral::LateralParams;
use drystone::loading::shake::ShakeParams;
use drystone::loading::tilt::TiltParams;
use drystone::protocol::{run_lateral, run_shake, run_tilt};
use drystone::study::Study;
use drystone::verify::{box_vertices, layout_of};
use std::path::Path;

/// A result as JSON without its wall-clock time.
fn timeless<T: serde::Serialize>(r: &T) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    v.as_object_mut().unwrap().remove("wall_time_s");
    v
}

fn block() -> drystone::layout::Layout {
    layout_of(vec![box_vertices([0.0, -0.075, 0.0], [0.3, 0.075, 0.3])], 1e8, 5e7, 40.0, BaseSliding::Free)
}

fn with(penalty: PenaltyParams) -> SolverParams {
    SolverParams { penalty, ..SolverParams::default() }
}

#[test]
fn the_tilting_tables_former_keys_run_as_the_methods_settings() {
    let l = block();
    let table = TiltParams { step_deg: 2.0, resolution_deg: 0.5, ..TiltParams::default() };
    let former =
        TiltParams { tolerance: Some(1e-6), max_steps_per_increment: Some(200_000), predictor: Some(false), ..table };
    let new = PenaltyParams { tolerance: 1e-6, max_steps: 200_000, predictor: false, ..PenaltyParams::default() };
    let a = run_tilt(&l, SolverParams::default(), &former).unwrap();
    let b = run_tilt(&l, with(new), &table).unwrap();
    let d = run_tilt(&l, SolverParams::default(), &table).unwrap();
    assert_eq!(timeless(&a), timeless(&b));
    assert_ne!(a.steps, d.steps, "the former keys were not read");
}

#[test]
fn the_lateral_loads_former_keys_run_as_the_methods_settings() {
    let l = block();
    let load = LateralParams { pressure_base_pa: 300.0, pressure_top_pa: 300.0, ..LateralParams::default() };
    let former = LateralParams { tolerance: Some(1e-7), ..load };
    let a = run_lateral(&l, SolverParams::default(), &former).unwrap();
    let b = run_lateral(&l, with(PenaltyParams { tolerance: 1e-7, ..PenaltyParams::default() }), &load).unwrap();
    let d = run_lateral(&l, SolverParams::default(), &load).unwrap();
    assert_eq!(timeless(&a), timeless(&b));
    assert_ne!(a.steps, d.steps, "the former key was not read");
}

#[test]
fn the_shaking_tables_former_keys_run_as_the_methods_settings() {
    let l = layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.3, 0.05, 0.4])], 1e9, 5e8, 40.0, BaseSliding::Free);
    let pulse = Pulse::OneSine { amplitude_g: 0.3, period_s: 0.2 }.sampled(0.001, 0.2);
    let shake = ShakeParams { tail_s: 0.1, ..ShakeParams::default() };
    let former = ShakeParams { contact_restitution: Some(0.4), penalty_step_fraction: Some(0.2), ..shake };
    let penalty = SolverParams { kind: SolverKind::Penalty, ..SolverParams::default() };
    let new = PenaltyParams { contact_restitution: 0.4, step_fraction: 0.2, ..PenaltyParams::default() };
    let a = run_shake(&l, penalty, &pulse, &former).unwrap();
    let b = run_shake(&l, SolverParams { penalty: new, ..penalty }, &pulse, &shake).unwrap();
    let d = run_shake(&l, penalty, &pulse, &shake).unwrap();
    assert_eq!(timeless(&a), timeless(&b));
    assert_ne!(a.dt_s, d.dt_s, "the former keys were not read");
}

/// A study written with the former keys resolves to the method's settings and warns once a
/// key, naming the new key; the new table does not warn; either out of range is refused
/// under the key as written.
#[test]
fn a_study_with_the_former_keys_warns_and_sets_the_methods_settings() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("tests/studies/good/mini_sweep.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("drystone-moved-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fix = |t: String| t.replace("../../../", &format!("{}/", root.display()));
    let load = |body: &str| {
        let p = dir.join("study.toml");
        std::fs::write(&p, fix(body.to_string())).unwrap();
        Study::from_file(&p)
    };
    let former = text.replace("[tilt]\n", "[tilt]\ntolerance = 5e-5\npredictor = false\n");
    let s = load(&former).unwrap();
    assert_eq!((s.solver.penalty.tolerance, s.solver.penalty.predictor), (5e-5, false));
    // The table keeps its own knobs only: what the study writes back has no former key.
    let drystone::study::StudyProtocol::Tilt(t) = &s.protocol else { panic!("a tilting-table study") };
    assert!(t.moved().is_empty(), "{t:?}");
    let w = s.warnings();
    for key in ["tilt.tolerance", "tilt.predictor"] {
        assert!(w.iter().any(|l| l.contains(key) && l.contains("deprecated") && l.contains("solver.penalty")), "{w:?}");
    }
    let new = format!("{text}\n[solver.penalty]\ntolerance = 5e-5\npredictor = false\n");
    let n = load(&new).unwrap();
    assert_eq!(n.solver, s.solver);
    assert!(!n.warnings().iter().any(|l| l.contains("deprecated")), "{:?}", n.warnings());
    // The cascade's switches turned off are the solver's stages: a warning naming the kind.
    let off = load(&text.replace("[tilt]\n", "[tilt]\nimplicit = false\n")).unwrap();
    assert!(
        off.warnings().iter().any(|l| l.contains("tilt.implicit = false is deprecated") && l.contains("accelerated")),
        "{:?}",
        off.warnings()
    );
    let bad = load(&text.replace("[tilt]\n", "[tilt]\ntolerance = 2.0\n")).unwrap_err().to_string();
    assert!(bad.contains("tilt.tolerance"), "{bad}");
    let bad = load(&format!("{text}\n[solver.penalty]\ntolerance = 2.0\n")).unwrap_err().to_string();
    assert!(bad.contains("solver.penalty.tolerance"), "{bad}");
    let _ = std::fs::remove_dir_all(&dir);
}
