//! The discrepancy engine on measured data it did not make (`realwalls`: specimens
//! generated with unused seeds, edited as layout files by code that shares nothing with
//! `drystone::effects`, tilted at the study's settings, noise at a σ the engine is not told,
//! rounded to the readings' resolution). One data set of each class: null, a lean, rounded
//! edges, a softer base joint, a lean with rounded edges, spring end restraints. The power
//! table over many data sets per class is `examples/realwall_power.rs` (BENCHMARKS.md).

mod realwalls;

use drystone::discrepancy::{analyze, prepare, Prepared};
use drystone::study::Study;
use realwalls::{classify, data_set, Answer, Edit, Noise};
use std::path::PathBuf;
use std::sync::OnceLock;

/// The data's own noise: 1.6 × the engine's assumed σ for angles, 2 × for displacements,
/// rounded to the test bed's readings.
const NOISE: Noise =
    Noise { angle_deg: 0.4, displacement_cm: 0.01, angle_reading_deg: 0.25, displacement_reading_cm: 0.01 };
const SPECIMENS: u64 = 5;
const TILTS: [f64; 2] = [5.0, 10.0];
/// Master seed of the specimens: neither the study's (7) nor its null layouts'.
const DATA_SEED: u64 = 0x5eed_da7a;

fn study() -> Study {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap()
}

fn prepared() -> &'static (Study, Prepared) {
    static P: OnceLock<(Study, Prepared)> = OnceLock::new();
    P.get_or_init(|| {
        let st = study();
        let s = st.discrepancy.clone();
        let template = data_set(&st, DATA_SEED, 0, 2, Edit::None, NOISE, &TILTS, s.sigma);
        let setup = drystone::study::discrepancy::setup_of(&st, s.most_realizations());
        let prep = prepare(&setup, &template, &s, &st.library).unwrap();
        (st, prep)
    })
}

fn answer(e: Edit, first: u64) -> (Answer, String) {
    let (st, prep) = prepared();
    let obs = data_set(st, DATA_SEED, first, SPECIMENS, e, NOISE, &TILTS, st.discrepancy.sigma);
    let run = analyze(prep, obs, first).unwrap();
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| c.name.clone());
    let verdict = a.verdict.name();
    let got = classify(e, verdict, cause.as_deref(), &a.tie);
    (got, format!("{}: {verdict} {cause:?} tie {:?}", e.label(), a.tie))
}

#[test]
fn null_data_from_edited_files_raise_no_alarm() {
    let (got, what) = answer(Edit::None, 100);
    assert_eq!(got, Answer::NoEffect, "{what}");
}

#[test]
fn a_wall_built_out_of_plumb_is_named_a_lean() {
    let (got, what) = answer(Edit::Lean(1.5), 200);
    assert_eq!(got, Answer::Right, "{what}");
}

#[test]
fn rounded_edges_are_named_edge_rounding() {
    let (got, what) = answer(Edit::Round(0.004), 300);
    assert_eq!(got, Answer::Right, "{what}");
}

#[test]
fn a_softer_base_joint_is_never_a_geometric_or_restraint_effect() {
    let (got, what) = answer(Edit::SoftBase(5e6), 400);
    assert_ne!(got, Answer::Wrong, "{what}");
}

#[test]
fn a_lean_with_rounded_edges_names_the_pair_or_a_member() {
    let (got, what) = answer(Edit::LeanRound(1.5, 0.004), 500);
    assert_eq!(got, Answer::Right, "{what}");
}

#[test]
fn spring_end_restraints_are_named_restraint_stiffness() {
    let (got, what) = answer(Edit::Springs(150.0), 600);
    assert_eq!(got, Answer::Right, "{what}");
}
