//! The discrepancy engine's power and false-alarm rate on measured data it did not make:
//! data sets of the test bed (`tests/discrepancy/study.toml`) made by
//! `tests/realwalls/mod.rs` (layouts edited as files, noise at a σ the engine is not told,
//! rounded readings), analysed against one prepared set of forward runs.
//!
//! ```sh
//! cargo run --release --example realwall_power -- [DATA_SETS_PER_EFFECT] [NULL_DATA_SETS] [SPECIMENS_PER_GROUP] [FIRST_NULL | LIST] [CLASSES] [FIRST_SET] [without | with | both]
//! cargo run --release --example realwall_power -- effects     # the edits' effect on the specimens
//! ```
//!
//! Prints, per class, how often the answer is right (the effect, or a tie containing it),
//! and of those how often the named cause is itself the effect (or one of the effects a class
//! accepts) and how often it is named with no tie, `unexplained`, `no_effect`, or a wrong cause, with the Clopper–Pearson interval of the
//! rate that matters.
//!
//! The last argument says whether the data sets carry the specimens' failure mechanisms
//! (`without`, the default: angles and displacements only; `with`: also the mechanism file
//! of each data set, each mechanism read from the specimen's own run and misread at
//! [`MISREADING`]; `both`: every data set analysed both ways, the same specimens, noise
//! and analysis seed: common random numbers). Each way has its own preparation (with
//! mechanism data, the mechanism keys and `base_restraint` join the search). `both` ends
//! with a table of how often the named cause is the hidden effect alone, without and
//! with the mechanisms.

#[path = "../tests/realwalls/mod.rs"]
mod realwalls;

use drystone::discrepancy::{analyze, prepare};
use drystone::study::Study;
use rayon::prelude::*;
use realwalls::{
    classify, data_set, data_set_with_mechanism, mechanism_observations_via_file, mechanism_template, specimen, Answer,
    Edit, MechanismNoise, Noise,
};
use statrs::distribution::{Beta, ContinuousCDF};
use std::path::PathBuf;

const NOISE: Noise =
    Noise { angle_deg: 0.4, displacement_cm: 0.01, angle_reading_deg: 0.25, displacement_reading_cm: 0.01 };
const TILTS: [f64; 2] = [5.0, 10.0];
const DATA_SEED: u64 = 0x5eed_da7a;
/// The observers' misreading probability of a kind, and of a start (the engine's stated
/// `reading.misreading` is also 0.1).
const MISREADING: f64 = 0.1;

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

/// One analysis: the edit, with mechanisms, the answer, (the named cause itself is the
/// hidden effect or one of its members, named with no tie), the line printed, and (the
/// pseudo-BMA+ weight of the truth, whether the truth is among the models that share the
/// weight).
type Row = (Edit, bool, Answer, (bool, bool), String, (f64, bool));

fn clopper_pearson(k: usize, n: usize) -> (f64, f64) {
    let lo = if k == 0 { 0.0 } else { Beta::new(k as f64, (n - k + 1) as f64).unwrap().inverse_cdf(0.025) };
    let hi = if k == n { 1.0 } else { Beta::new((k + 1) as f64, (n - k) as f64).unwrap().inverse_cdf(0.975) };
    (lo, hi)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let st = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
    if args.first().map(String::as_str) == Some("effects") {
        // The mean shift of each edit on the first specimens, against the unedited walls.
        let n = 6u64;
        let only: Option<usize> = args.get(1).and_then(|a| a.parse().ok());
        for (ci, e) in std::iter::once(Edit::None).chain(classes()).enumerate() {
            if only.is_some_and(|o| o != ci) {
                continue;
            }
            for g in &st.groups {
                let t0 = std::time::Instant::now();
                let rows: Vec<_> = (0..n)
                    .into_par_iter()
                    .filter_map(|k| specimen(&st, &g.walls[0], DATA_SEED, 10_000 + k, e))
                    .collect();
                let a: Vec<f64> = rows.iter().map(|s| 0.5 * (s.bracket.0 + s.bracket.1)).collect();
                let mut seen = std::collections::BTreeMap::new();
                for r in rows.iter().filter_map(|s| s.mechanism) {
                    let h = (r.failure_height_fraction * 100.0).round() / 100.0;
                    *seen.entry(format!("{h} {} {}", r.kind.name(), r.start.name())).or_insert(0usize) += 1;
                }
                let d5: Vec<f64> = rows
                    .iter()
                    .filter_map(|s| s.top_cm.iter().find(|(t, _)| (*t - 5.0).abs() < 1e-9).map(|(_, v)| v[1]))
                    .collect();
                println!(
                    "{:<32} {:<5} alpha mean {:6.2} sd {:5.2} | centre disp at 5 deg {:.4} cm (n {}) {:.1} s | mechanisms {:?}",
                    e.label(),
                    g.name,
                    drystone::stats::mean(&a),
                    drystone::stats::sd(&a),
                    drystone::stats::mean(&d5),
                    rows.len(),
                    t0.elapsed().as_secs_f64(),
                    seen
                );
            }
        }
        return;
    }
    let per: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(20);
    let nulls: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(80);
    let specimens: u64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(5);
    // The null data sets: FIRST_NULL.. (a number), or a list `12,13,22`.
    let null_ids: Vec<usize> = match args.get(3) {
        Some(a) if a.contains(',') => a.split(',').filter_map(|x| x.trim().parse().ok()).collect(),
        a => {
            let first: usize = a.and_then(|a| a.parse().ok()).unwrap_or(0);
            (first..first + nulls).collect()
        }
    };
    // The effect classes to run (1-based, as in the table: `2` or `1,2,6`), all by default, and
    // the index of each class's first data set.
    let only: Option<Vec<usize>> =
        args.get(4).filter(|a| *a != "all").map(|a| a.split(',').filter_map(|x| x.trim().parse().ok()).collect());
    let first_set: usize = args.get(5).and_then(|a| a.parse().ok()).unwrap_or(0);
    let mode = args.get(6).map_or("without", String::as_str);
    let ways: Vec<bool> = match mode {
        "without" => vec![false],
        "with" => vec![true],
        "both" => vec![false, true],
        other => {
            eprintln!("the seventh argument is `without`, `with` or `both`, not `{other}`");
            std::process::exit(2);
        }
    };
    let s = st.discrepancy.clone();
    let t0 = std::time::Instant::now();
    let template = data_set(&st, DATA_SEED, 0, 2, Edit::None, NOISE, &TILTS, s.sigma);
    let setup = drystone::study::discrepancy::setup_of(&st, s.most_realizations());
    // One preparation per way: with mechanism data the template holds every mechanism key.
    let preps: Vec<_> = ways
        .iter()
        .map(|&with| {
            let mut t = template.clone();
            if with {
                t.extend(mechanism_template(&st, s.sigma));
            }
            let p = prepare(&setup, &t, &s, &st.library).unwrap();
            eprintln!(
                "prepared ({}) in {:.0} s",
                if with { "with mechanisms" } else { "without" },
                t0.elapsed().as_secs_f64()
            );
            p
        })
        .collect();
    let files = std::env::temp_dir().join(format!("realwall_power-{}", std::process::id()));
    // (edit, its class, data set index): a data set's specimens depend on its class and
    // index only, not on how many data sets the run has.
    let mut jobs: Vec<(Edit, usize, usize)> = null_ids.iter().map(|&i| (Edit::None, 0, i)).collect();
    for (c, e) in classes().into_iter().enumerate() {
        if only.as_ref().is_some_and(|o| !o.contains(&(c + 1))) {
            continue;
        }
        jobs.extend((first_set..first_set + per).map(|i| (e, c + 1, i)));
    }
    // (edit, with mechanisms, answer, (the named cause itself is the hidden effect or one
    // of its members, named with no tie), line)
    let answers: Vec<Row> = jobs
        .iter()
        .flat_map(|&(e, c, i)| {
            let first = 1_000 + 100 * i as u64 + 100_000 * c as u64;
            let seen = MechanismNoise { misreading: MISREADING };
            let ds = data_set_with_mechanism(&st, DATA_SEED, first, specimens, e, NOISE, seen, &TILTS, s.sigma);
            let mut out = Vec::new();
            for (&with, prep) in ways.iter().zip(&preps) {
                let mut obs = ds.obs.clone();
                if with {
                    let dir = files.join(format!("{c}-{i}"));
                    obs.extend(mechanism_observations_via_file(&st, &dir, &ds.mechanism, s.sigma));
                }
                out.push(one(prep, obs, e, with, i, first));
            }
            out
        })
        .collect();
    let _ = std::fs::remove_dir_all(&files);
    for &with in &ways {
        println!();
        println!("{}", if with { "With the mechanisms:" } else { "Without the mechanisms:" });
        println!();
        table(&answers, with);
    }
    println!();
    println!("The weights: the pseudo-BMA+ weight of the truth (the baseline on null data; else the models made of the class's effects, summed), its mean and range over the data sets, and in how many data sets the truth is among the models that share 90 % of the weight:");
    println!();
    println!(
        "| data | mechanisms | sets | weight of the truth, mean | min – max | truth among the models sharing 90 % |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for &with in &ways {
        for e in std::iter::once(Edit::None).chain(classes()) {
            let w: Vec<&(f64, bool)> =
                answers.iter().filter(|(x, m, ..)| *x == e && *m == with).map(|r| &r.5).collect();
            if w.is_empty() {
                continue;
            }
            let v: Vec<f64> = w.iter().map(|x| x.0).collect();
            println!(
                "| {} | {} | {} | {:.3} | {:.3} – {:.3} | {} of {} |",
                e.label(),
                if with { "with" } else { "without" },
                w.len(),
                drystone::stats::mean(&v),
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                w.iter().filter(|x| x.1).count(),
                w.len()
            );
        }
    }
    if ways.len() == 2 {
        println!();
        println!("| data | sets | named cause is the hidden effect alone, without mechanisms | with mechanisms | false alarms or wrong cause, without | with |");
        println!("| --- | --- | --- | --- | --- | --- |");
        for e in std::iter::once(Edit::None).chain(classes()) {
            let count = |with: bool, f: &dyn Fn(&Answer, &(bool, bool)) -> bool| {
                answers.iter().filter(|(x, w, a, b, ..)| *x == e && *w == with && f(a, b)).count()
            };
            let n = count(false, &|_, _| true);
            if n == 0 {
                continue;
            }
            let alone = |a: &Answer, f: &(bool, bool)| *a == Answer::Right && f.1;
            let bad = |a: &Answer, _: &(bool, bool)| {
                if e == Edit::None {
                    *a != Answer::NoEffect
                } else {
                    *a == Answer::Wrong
                }
            };
            let dash = |k: usize| if e == Edit::None { "–".to_string() } else { k.to_string() };
            println!(
                "| {} | {n} | {} | {} | {} | {} |",
                e.label(),
                dash(count(false, &alone)),
                dash(count(true, &alone)),
                count(false, &bad),
                count(true, &bad)
            );
        }
    }
    eprintln!("total {:.0} s", t0.elapsed().as_secs_f64());
}

/// Analyses one data set's observations and classifies the answer.
fn one(
    prep: &drystone::discrepancy::Prepared,
    obs: Vec<drystone::discrepancy::Observation>,
    e: Edit,
    with: bool,
    i: usize,
    first: u64,
) -> Row {
    let run = analyze(prep, obs, first).unwrap();
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| c.name.clone());
    let got = classify(e, a.verdict.name(), cause.as_deref(), &a.tie);
    let named = cause.as_deref().is_some_and(|c| c.split('+').all(|m| realwalls::expected(e).contains(&m)));
    let m = &a.margins;
    let gain = a.candidates.first().map_or(0.0, |b| a.baseline_heldout_error - b.heldout_error);
    let missed = a.check.as_ref().map(|c| c.missed.clone()).unwrap_or_default();
    let what = format!(
        "{} #{i}{}: {} {:?} tie {:?} | base {:.2} (misfit margin {:.2}) best gain {:.2}, on the surrogates {:.2} (margin {:.2}) sigma {:?} missed {:?}",
        e.label(),
        if with { " (with mechanisms)" } else { "" },
        a.verdict.name(),
        cause,
        a.tie,
        a.baseline_heldout_error,
        m.misfit,
        gain,
        a.screen_gain,
        m.baseline,
        run.sigma_estimate,
        missed
    );
    // The truth: the baseline on null data, else every model made of the class's effects.
    let truth = |name: &str| {
        if e == Edit::None {
            name == "baseline"
        } else {
            name != "baseline" && name != "scatter" && name.split('+').all(|m| realwalls::expected(e).contains(&m))
        }
    };
    let w = &a.weights;
    let truth_weight: f64 = w.models.iter().filter(|m| truth(&m.name)).map(|m| m.pseudo_bma).sum();
    let truth_shared = w.shared.iter().any(|n| truth(n));
    let what = format!("{what} | weight of the truth {truth_weight:.3}, shared by {:?}", w.shared);
    eprintln!("{what} -> {got:?}");
    if std::env::var_os("REALWALL_VERBOSE").is_some() {
        let top = &a.candidates[0];
        let ps = |sc: &[f64]| drystone::discrepancy::per_specimen(sc, &run.obs, &run.specimens);
        for c in &a.candidates {
            let d: Vec<f64> = ps(&c.scores).iter().zip(ps(&top.scores)).map(|(x, y)| x - y).collect();
            eprintln!(
                "    vs top: D {:8.3} se {:8.3} per-specimen {:?}",
                d.iter().sum::<f64>(),
                drystone::discrepancy::difference_se(&d),
                d.iter().map(|x| (x * 100.0).round() / 100.0).collect::<Vec<_>>()
            );
            eprintln!(
                "    {:<28} held-out {:8.3} ± {:.3}  AICc {:9.2}  confirmed {}  {:?}",
                c.name, c.heldout_error, c.difference_se, c.information_criterion, c.confirmed, c.parameters
            );
        }
        let mut seen = std::collections::BTreeMap::new();
        for (o, (pb, pe)) in run.obs.iter().zip(a.baseline_predictive.iter().zip(&run.extended_predictive)) {
            let k = format!("{} {}", o.group, o.observable.label());
            seen.entry(k).or_insert_with(Vec::new).push((o.value, pb.mean, pb.sd, pe.mean, pe.sd));
        }
        for (k, v) in seen {
            let d: Vec<f64> = v.iter().map(|x| x.0).collect();
            eprintln!(
                "    {:<22} data {:8.4} (sd {:.4}) | base {:8.4} ± {:.4} | extended {:8.4} ± {:.4}",
                k,
                drystone::stats::mean(&d),
                drystone::stats::sd(&d),
                v[0].1,
                v[0].2,
                v[0].3,
                v[0].4
            );
        }
    }
    (e, with, got, (named, named && a.tie.len() <= 1), what, (truth_weight, truth_shared))
}

/// The power table of the analyses `with` (or without) mechanisms.
fn table(answers: &[Row], with: bool) {
    println!("| data | sets | right (alone or in a tie) | of which the named cause itself | of which with no tie | unexplained | no_effect | wrong cause | rate that matters, 95 % CI |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for e in std::iter::once(Edit::None).chain(classes()) {
        let mine = || answers.iter().filter(|(x, w, ..)| *x == e && *w == with);
        let v: Vec<&Answer> = mine().map(|(_, _, a, ..)| a).collect();
        let first = mine().filter(|(_, _, a, f, ..)| *a == Answer::Right && f.0).count();
        let alone = mine().filter(|(_, _, a, f, ..)| *a == Answer::Right && f.1).count();
        let dash = |k: usize| if e == Edit::None { "–".to_string() } else { k.to_string() };
        let c = |a: Answer| v.iter().filter(|x| ***x == a).count();
        let n = v.len();
        let (k, what) =
            if e == Edit::None { (n - c(Answer::NoEffect), "false alarms") } else { (c(Answer::Right), "named") };
        let (lo, hi) = clopper_pearson(k, n);
        println!(
            "| {} | {n} | {} | {} | {} | {} | {} | {} | {what} {:.0} % [{:.0}, {:.0}] |",
            e.label(),
            c(Answer::Right),
            dash(first),
            dash(alone),
            c(Answer::Unexplained),
            c(Answer::NoEffect),
            c(Answer::Wrong),
            100.0 * k as f64 / n.max(1) as f64,
            100.0 * lo,
            100.0 * hi
        );
    }
}
