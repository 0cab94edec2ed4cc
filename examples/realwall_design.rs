//! The designed follow-up on data it did not make: for every data set of the test bed
//! (`tests/discrepancy/study.toml`, data made by `tests/realwalls/mod.rs`: layouts edited as
//! files, noise at a σ the engine is not told, rounded readings) whose hidden cause is not
//! named alone, `drystone design`'s best follow-up is written as a study, the follow-up's
//! specimens are made the same independent way (the follow-up's walls generated with the
//! data's seed, edited as files with the same hidden edit, tilted, readings rounded; the
//! mechanism read from each edited wall's own run and misread at 10 % when the follow-up
//! reads it), and both campaigns are analysed together on the written study. Prints one
//! line per data set and the column "alone after the designed follow-up".
//!
//! ```sh
//! cargo run --release --example realwall_design -- [DATA_SETS_PER_CLASS] [FIRST_SET] [CLASSES]
//! ```
//!
//! `CLASSES`: indices into the classes (`0,2`), default all; `FIRST_SET`: the first data
//! set's index (data set `i` of class `c` uses the specimens `1000 c + 100 + 10 i ..`).

#[path = "../tests/realwalls/mod.rs"]
mod realwalls;

use drystone::discrepancy::design::{design, DesignSettings};
use drystone::discrepancy::{analyze, prepare, quiet};
use drystone::study::discrepancy::setup_of;
use drystone::study::followup::{menu, write_followup};
use drystone::study::Study;
use realwalls::{
    classify, data_set, data_set_with_mechanism, expected, mechanism_observations_via_file, Answer, Edit,
    MechanismNoise, Noise,
};
use std::path::PathBuf;

const NOISE: Noise =
    Noise { angle_deg: 0.4, displacement_cm: 0.01, angle_reading_deg: 0.25, displacement_reading_cm: 0.01 };
const TILTS: [f64; 2] = [5.0, 10.0];
const DATA_SEED: u64 = 0x5eed_da7a;
const SPECIMENS: u64 = 5;

fn classes() -> Vec<Edit> {
    vec![
        Edit::Lean(1.5),
        Edit::Round(0.004),
        Edit::Stiffness(0.3),
        Edit::SoftBase(5e6),
        Edit::Springs(150.0),
        Edit::LeanRound(1.5, 0.004),
    ]
}

/// The hidden cause named with no tie.
fn alone(e: Edit, cause: Option<&str>, tie: &[String]) -> bool {
    cause.is_some_and(|c| c.split('+').all(|m| expected(e).contains(&m))) && tie.len() <= 1
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(1);
    let first_set: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(0);
    let only: Option<Vec<usize>> = args.get(2).map(|a| a.split(',').filter_map(|x| x.parse().ok()).collect());
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let st = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
    let s = st.discrepancy.clone();
    let setup = setup_of(&st, s.most_realizations());
    let template = data_set(&st, DATA_SEED, 0, 2, Edit::None, NOISE, &TILTS, s.sigma);
    let prep = prepare(&setup, &template, &s, &st.library).unwrap();
    let ds = DesignSettings { specimens: SPECIMENS as usize, replicates: 100, ..DesignSettings::default() };
    let mut table: Vec<(String, usize, usize, usize)> = Vec::new();
    for (ci, e) in classes().into_iter().enumerate() {
        if only.as_ref().is_some_and(|o| !o.contains(&ci)) {
            continue;
        }
        let (mut sets, mut before, mut after) = (0, 0, 0);
        for i in first_set..first_set + n {
            let first = 1000 * ci as u64 + 100 + 10 * i as u64;
            let t0 = std::time::Instant::now();
            let obs = data_set(&st, DATA_SEED, first, SPECIMENS, e, NOISE, &TILTS, s.sigma);
            let mut run = analyze(&prep, obs.clone(), first).unwrap();
            let a = &run.analysis;
            let cause = a.cause.as_ref().map(|c| c.name.clone());
            let got = classify(e, a.verdict.name(), cause.as_deref(), &a.tie);
            let was = alone(e, cause.as_deref(), &a.tie);
            sets += 1;
            before += usize::from(was);
            let line0 = format!("{}: {} {cause:?} tie {:?}", a.verdict.name(), got_name(got), a.tie);
            if was || a.cause.is_none() {
                after += usize::from(was);
                println!("{} #{i}: {line0}; no follow-up ({:.0} s)", e.label(), t0.elapsed().as_secs_f64());
                continue;
            }
            let m = menu(&st, &setup, &run).unwrap();
            let plan = design(&run, &setup, m, &ds, first, &quiet).unwrap();
            let best = plan.best().unwrap().clone();
            run.followup = Some(plan.clone());
            let dir = std::env::temp_dir().join(format!("realwall_design-{}-{first}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            let files = write_followup(&st, &plan, &dir, SPECIMENS as usize, None).unwrap().unwrap();
            let fst = Study::from_file(&files.study).expect("the follow-up study reads");
            // The follow-up's specimens from the hidden truth walls: fresh realizations of the
            // follow-up's group, edited by the same hidden edit.
            let mut only_group = fst.clone();
            only_group.groups.retain(|g| g.name == best.followup.group);
            let reads_mechanism = best.followup.observables.iter().any(|o| o.is_mechanism());
            let seen = MechanismNoise { misreading: 0.1 };
            let more = data_set_with_mechanism(
                &only_group,
                DATA_SEED,
                first + 50_000,
                SPECIMENS,
                e,
                NOISE,
                seen,
                &TILTS,
                s.sigma,
            );
            let mut both = obs.clone();
            both.extend(more.obs);
            if reads_mechanism {
                both.extend(mechanism_observations_via_file(&only_group, &dir.join("mech"), &more.mechanism, s.sigma));
            }
            let fsetup = setup_of(&fst, fst.discrepancy.most_realizations());
            let fprep = prepare(&fsetup, &both, &fst.discrepancy, &fst.library).unwrap();
            let run2 = analyze(&fprep, both, first).unwrap();
            let b = &run2.analysis;
            let cause2 = b.cause.as_ref().map(|c| c.name.clone());
            let got2 = classify(e, b.verdict.name(), cause2.as_deref(), &b.tie);
            let now = alone(e, cause2.as_deref(), &b.tie);
            // The weights' own answer: the hidden cause alone holds 90 % of the weight.
            let by_weights = b.weights.shared.len() == 1 && alone(e, Some(&b.weights.shared[0]), &[]);
            after += usize::from(now);
            println!(
                "{} #{i}: {line0} -> follow-up {} (P alone {:.2}, by the weights {:.2}) -> {}: {} {cause2:?} tie {:?} \
                 shared {:?}; alone {} (by the weights {}) ({:.0} s)",
                e.label(),
                best.followup.name,
                best.at_budget.alone,
                best.at_budget.weights_alone,
                b.verdict.name(),
                got_name(got2),
                b.tie,
                b.weights.shared,
                now,
                by_weights,
                t0.elapsed().as_secs_f64()
            );
            let _ = std::fs::remove_dir_all(&dir);
        }
        table.push((e.label(), sets, before, after));
    }
    println!("\n| hidden in the walls | data sets | alone (first campaign) | alone after the designed follow-up |");
    println!("| --- | --- | --- | --- |");
    for (l, sets, b, a) in table {
        println!("| {l} | {sets} | {b} | {a} |");
    }
}

fn got_name(a: Answer) -> &'static str {
    match a {
        Answer::NoEffect => "no_effect",
        Answer::Unexplained => "unexplained",
        Answer::Right => "right",
        Answer::Wrong => "WRONG",
    }
}
