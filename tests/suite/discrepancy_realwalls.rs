//! The discrepancy engine on measured data it did not make (`realwalls`: specimens
//! generated with unused seeds, edited as layout files by code that shares nothing with
//! `drystone::effects`, tilted at the study's settings, noise at a σ the engine is not told,
//! rounded to the readings' resolution). One data set of each class: null, a lean, rounded
//! edges, a softer base joint, a lean with rounded edges, spring end restraints. The power
//! table over many data sets per class is `examples/realwall_power.rs` (BENCHMARKS.md).
//!
//! With the specimens' failure mechanisms (read from each edited wall's own run, misread at
//! 10 %, written as the measured mechanism file and read back), one data set whose hidden
//! effect moves the failure; and with the readings of an observer whose rule shares no
//! code with the product's (`realwalls::Observer::Independent`), a rounding and a null
//! data set that must keep their verdicts: the slow cases, ignored by default (two
//! preparations, shared, and two or four analyses each: 131 s of wall time, 259 s of CPU,
//! on 2 idle cores for the first):
//!
//! ```sh
//! cargo test --release --test suite discrepancy_realwalls:: -- --ignored
//! ```

use crate::realwalls;

use drystone::discrepancy::{analyze, prepare, Prepared};
use drystone::loading::mechanism::{FailureKind, FailureStart};
use drystone::study::Study;
use realwalls::{
    classify, data_set, data_set_observed, mechanism_observations_via_file, mechanism_template, read_independently,
    Answer, Edit, LayoutBlock, MechanismNoise, Noise, Observer,
};
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

/// The preparation for data sets with mechanisms: the same template and every mechanism
/// key of both groups (`base_restraint` joins the search).
fn prepared_with_mechanisms() -> &'static Prepared {
    static P: OnceLock<Prepared> = OnceLock::new();
    P.get_or_init(|| {
        let st = &prepared().0;
        let s = st.discrepancy.clone();
        let mut template = data_set(st, DATA_SEED, 0, 2, Edit::None, NOISE, &TILTS, s.sigma);
        template.extend(mechanism_template(st, s.sigma));
        let setup = drystone::study::discrepancy::setup_of(st, s.most_realizations());
        prepare(&setup, &template, &s, &st.library).unwrap()
    })
}

/// One data set analysed without and with its mechanism file as `seen`'s observer reads
/// it (the same specimens, noise and analysis seed): (verdict, answer, the named cause is
/// the hidden effect, tied or not, what was named).
fn both_ways(e: Edit, first: u64, seen: (Observer, MechanismNoise)) -> [(String, Answer, bool, String); 2] {
    let st = &prepared().0;
    let sigma = st.discrepancy.sigma;
    let mut ds = data_set_observed(st, DATA_SEED, first, SPECIMENS, e, NOISE, &[seen], &TILTS, sigma);
    let dir =
        std::env::temp_dir().join(format!("discrepancy_realwalls-{}-{}-{first}", seen.0.name(), std::process::id()));
    let mut with = ds.obs.clone();
    with.extend(mechanism_observations_via_file(st, &dir, &ds.mechanisms.remove(0), sigma));
    let _ = std::fs::remove_dir_all(&dir);
    [(&prepared().1, ds.obs), (prepared_with_mechanisms(), with)].map(|(prep, obs)| {
        let run = analyze(prep, obs, first).unwrap();
        let a = &run.analysis;
        let cause = a.cause.as_ref().map(|c| c.name.clone());
        let verdict = a.verdict.name();
        let got = classify(e, verdict, cause.as_deref(), &a.tie);
        let named = cause.as_deref().is_some_and(|c| c.split('+').all(|m| realwalls::expected(e).contains(&m)));
        (verdict.to_string(), got, named, format!("{}: {verdict} {cause:?} tie {:?}", e.label(), a.tie))
    })
}

/// The analysis of one data set: its answer, what was named, and the margins' false alarms
/// on their own null data sets (alarms, sets, 95 % interval).
fn analysed(e: Edit, first: u64) -> (Answer, String, (usize, usize), (f64, f64)) {
    let (st, prep) = prepared();
    let obs = data_set(st, DATA_SEED, first, SPECIMENS, e, NOISE, &TILTS, st.discrepancy.sigma);
    let run = analyze(prep, obs, first).unwrap();
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| c.name.clone());
    let verdict = a.verdict.name();
    let got = classify(e, verdict, cause.as_deref(), &a.tie);
    (
        got,
        format!("{}: {verdict} {cause:?} tie {:?}", e.label(), a.tie),
        a.margins.false_alarms,
        a.margins.false_alarm_interval,
    )
}

fn answer(e: Edit, first: u64) -> (Answer, String) {
    let (got, what, _, _) = analysed(e, first);
    (got, what)
}

/// The independent observer's rule on a hand-made wall of 4 courses of 4 blocks (0.1 m
/// cubes, length 0.4 m, height 0.4 m): each block's (centroid displacement, rotation in
/// degrees) from `motion(course, column)`.
fn read_by_hand(held: bool, motion: impl Fn(usize, usize) -> (f64, f64)) -> Option<realwalls::IndependentReading> {
    let mut blocks = Vec::new();
    let mut motions = Vec::new();
    for c in 0..4 {
        for k in 0..4 {
            let (x, z) = (0.1 * k as f64, 0.1 * c as f64);
            let id = format!("b{c}{k}");
            let vertices = (0..8)
                .map(|v| [x + 0.1 * (v & 1) as f64, 0.1 * ((v >> 1) & 1) as f64, z + 0.1 * (v >> 2) as f64])
                .collect();
            blocks.push(LayoutBlock { id: id.clone(), vertices, course: Some(c) });
            let (d, r) = motion(c, k);
            motions.push((id, d, r, x + 0.05));
        }
    }
    read_independently(&blocks, &motions, held)
}

/// The independent observer: the moving part is every block that moved at least 0.2 of
/// the largest displacement; the height its lowest base; toppling above 2° of mean
/// rotation, else sliding; bending for a held wall moving in its middle fifth with its end
/// blocks resting; no start for a free wall.
#[test]
fn the_independent_observer_reads_by_its_own_rule() {
    // The top two courses overturn along the whole length (3°), the rest stays.
    let r = read_by_hand(false, |c, _| if c >= 2 { (0.01 * c as f64, 3.0) } else { (0.0, 0.0) }).unwrap();
    assert!((r.height_fraction - 0.5).abs() < 1e-12, "{r:?}");
    assert_eq!((r.kind, r.start, r.moving), (FailureKind::Toppling, None, 8));
    // The whole wall slides on the table (rotation 0.5°); blocks below 0.2 of the largest
    // motion are not part of it.
    let r = read_by_hand(true, |c, k| (if c == 0 && k == 0 { 0.001 } else { 0.01 }, 0.5)).unwrap();
    assert!((r.height_fraction - 0.0).abs() < 1e-12, "{r:?}");
    assert_eq!((r.kind, r.start, r.moving), (FailureKind::Sliding, Some(FailureStart::Centre), 15));
    // A held wall bulging in its two middle columns above the base course: bending from
    // the centre, whatever the rotation.
    let r = read_by_hand(true, |c, k| if c >= 1 && (k == 1 || k == 2) { (0.01, 5.0) } else { (0.0, 0.0) }).unwrap();
    assert!((r.height_fraction - 0.25).abs() < 1e-12, "{r:?}");
    assert_eq!((r.kind, r.start), (FailureKind::Bending, Some(FailureStart::Centre)));
    // The left end falls: an end start, toppling.
    let r = read_by_hand(true, |c, k| if c >= 2 && k == 0 { (0.02, 4.0) } else { (0.0, 0.0) }).unwrap();
    assert_eq!((r.kind, r.start), (FailureKind::Toppling, Some(FailureStart::End)));
    // Nothing moved: no reading.
    assert_eq!(read_by_hand(true, |_, _| (0.0, 0.0)), None);
}

#[test]
fn null_data_from_edited_files_raise_no_alarm() {
    let (got, what, (alarms, sets), interval) = analysed(Edit::None, 100);
    assert_eq!(got, Answer::NoEffect, "{what}");
    // The margins' own false-alarm rate on the null data sets (cross-fitted halves), with
    // every effect of the library searched: at most 5 % (the same analysis).
    eprintln!("false alarms {alarms} of {sets}, 95 % interval {interval:?}");
    assert!(sets > 0 && alarms as f64 <= 0.05 * sets as f64, "false alarms {alarms} of {sets}");
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

/// Edges rounded by 4 mm lower the held walls' failure and change its kind (the readings of
/// the reduced power run, 15 held specimens each: failure height 0.51 of the wall's height
/// on average against 0.72 on null data; sliding 5 and bending 6 against 13 and 1). On this
/// data set (rounding #1 of BENCHMARKS.md's reduced table) angles and displacements name
/// `base_stiffness` tied with `edge_rounding`; the mechanisms must keep the answer right
/// and name the rounding first (it stays tied with `base_stiffness`: the design of the
/// follow-up in docs/discrepancy.md is what separates them).
#[test]
#[ignore = "two preparations and two analyses: 131 s on 2 idle cores (see the module doc)"]
fn with_the_mechanisms_rounded_edges_are_named_first() {
    let product = (Observer::Product, MechanismNoise { misreading: 0.1 });
    let [without, with] = both_ways(Edit::Round(0.004), 201_100, product);
    assert_eq!(without.1, Answer::Right, "{}", without.3);
    assert_eq!(with.1, Answer::Right, "{} (without the mechanisms: {})", with.3, without.3);
    assert!(with.2, "the rounding is not named first: {} (without the mechanisms: {})", with.3, without.3);
}

/// Readings that never hurt, on readings the product did not make: the independent
/// observer calls most toppling free walls `sliding` and most held walls' centre failures
/// `bending`, categories no realization shows. The rounding data set #1 and the null data
/// set #0 of BENCHMARKS.md's reduced table keep their verdicts (`explained`, `no_effect`)
/// with those readings, where the absolute checks of fit once read the categories and
/// turned them `unexplained`.
#[test]
#[ignore = "two preparations and four analyses: 178 s on 2 cores (see the module doc)"]
fn the_independent_observers_readings_keep_the_verdicts() {
    // Read by a rule that shares no code with the product's, misread at 15 %.
    let independent = (Observer::Independent, MechanismNoise { misreading: 0.15 });
    let [without, with] = both_ways(Edit::Round(0.004), 201_100, independent);
    assert_eq!((without.0.as_str(), without.1), ("explained", Answer::Right), "{}", without.3);
    assert_eq!((with.0.as_str(), with.1), ("explained", Answer::Right), "{} (without: {})", with.3, without.3);
    let [without, with] = both_ways(Edit::None, 1_000, independent);
    assert_eq!(without.0, "no_effect", "{}", without.3);
    assert_eq!(with.0, "no_effect", "{} (without: {})", with.3, without.3);
}

/// A reading never hurts, on the lean class: a wall built out of plumb (1.5°, the power
/// table's class, on the data set `a_wall_built_out_of_plumb_is_named_a_lean` names a lean
/// from; and 1°, a lean a surveyor would miss), read from the angles and displacements alone
/// and with the mechanism readings added (the product's observer, misread at 10 %): a lean
/// named from the angles and displacements stays named with the mechanisms, and the
/// mechanisms never make the answer wrong. A change of the engine that turns the lean's
/// answer with the mechanisms to `no_effect` or to another cause fails here.
#[test]
#[ignore = "two preparations and four analyses: some 4 minutes on 2 cores (see the module doc)"]
fn a_lean_named_from_the_angles_stays_named_with_the_mechanisms() {
    let product = (Observer::Product, MechanismNoise { misreading: 0.1 });
    for (e, first) in [(Edit::Lean(1.5), 200), (Edit::Lean(1.0), 201_300)] {
        let [without, with] = both_ways(e, first, product);
        eprintln!("{} | {}", without.3, with.3);
        if first == 200 {
            assert_eq!(without.1, Answer::Right, "{}", without.3);
        }
        if without.1 == Answer::Right {
            assert_eq!(with.1, Answer::Right, "{} (without the mechanisms: {})", with.3, without.3);
        }
        assert_ne!(with.1, Answer::Wrong, "{} (without the mechanisms: {})", with.3, without.3);
    }
}
