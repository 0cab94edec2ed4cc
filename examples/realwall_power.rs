//! The discrepancy engine's power and false-alarm rate on measured data it did not make:
//! data sets of the test bed (`tests/discrepancy/study.toml`) made by
//! `tests/realwalls/mod.rs` (layouts edited as files, noise at a σ the engine is not told,
//! rounded readings), analysed against one prepared set of forward runs.
//!
//! ```sh
//! cargo run --release --example realwall_power -- [DATA_SETS_PER_EFFECT] [NULL_DATA_SETS] [SPECIMENS_PER_GROUP] [FIRST_NULL | LIST] [CLASSES] [FIRST_SET] [without | with | both] [product | independent | both]
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
//!
//! The eighth argument (or `REALWALL_OBSERVER`; the argument wins) says who reads the
//! mechanisms: `product` (the default: each specimen's own `TiltResult::mechanism`
//! reading, misread at [`MISREADING`]), `independent` (the test bed's independent
//! observer, which shares no code with the product's reading, misread at
//! [`INDEPENDENT_MISREADING`], its height too), or `both`: every data set with mechanisms
//! analysed once per observer (the same specimens, noise and analysis seed; one
//! preparation serves both). With `both` and `both`, each data set is analysed three
//! ways, and every data set whose answer with an observer's readings differs from its
//! answer without mechanisms gets a diagnosis: the held-out scores of the truth and of
//! the named cause (or the best candidate) summed per kind of observable, the margins, the
//! tie checks and the predictive check of each way, and which of them turned the answer.

#[path = "../tests/realwalls/mod.rs"]
mod realwalls;

use drystone::discrepancy::{analyze, prepare};
use drystone::study::Study;
use rayon::prelude::*;
use realwalls::{
    classify, data_set, data_set_observed, mechanism_observations_via_file, mechanism_template, specimen, Answer, Edit,
    MechanismNoise, Noise, Observer,
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
/// The independent observer's misreading probability of a height (one course up or down),
/// of a kind and of a start.
const INDEPENDENT_MISREADING: f64 = 0.15;

/// How a data set is analysed: angles and displacements only, or with the mechanisms as
/// an observer read them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Way {
    Without,
    With(Observer),
}

impl Way {
    fn label(self) -> &'static str {
        match self {
            Way::Without => "without",
            Way::With(Observer::Product) => "with (product observer)",
            Way::With(Observer::Independent) => "with (independent observer)",
        }
    }

    fn short(self) -> &'static str {
        match self {
            Way::Without => "without",
            Way::With(o) => o.name(),
        }
    }

    fn with(self) -> bool {
        self != Way::Without
    }
}

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

/// One analysis: the edit, the way, the answer, (the named cause itself is the hidden
/// effect or one of its members, named with no tie), the line printed, and (the
/// pseudo-BMA+ weight of the truth, whether the truth is among the models that share the
/// weight).
type Row = (Edit, Way, Answer, (bool, bool), String, (f64, bool));

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
                let mut independent = std::collections::BTreeMap::new();
                for r in rows.iter().filter_map(|s| s.independent) {
                    let h = (r.height_fraction * 100.0).round() / 100.0;
                    let start = r.start.map_or("-", |s| s.name());
                    *independent.entry(format!("{h} {} {start}", r.kind.name())).or_insert(0usize) += 1;
                }
                let d5: Vec<f64> = rows
                    .iter()
                    .filter_map(|s| s.top_cm.iter().find(|(t, _)| (*t - 5.0).abs() < 1e-9).map(|(_, v)| v[1]))
                    .collect();
                let rot: Vec<f64> = rows.iter().filter_map(|s| s.independent.map(|r| r.rotation_deg)).collect();
                let moving: Vec<f64> = rows.iter().filter_map(|s| s.independent.map(|r| r.moving as f64)).collect();
                println!(
                    "{:<32} {:<5} alpha mean {:6.2} sd {:5.2} | centre disp at 5 deg {:.4} cm (n {}) {:.1} s | mechanisms {:?} | independent observer {:?}, mean rotation {:.2} deg (max {:.2}), moving blocks {:.1}",
                    e.label(),
                    g.name,
                    drystone::stats::mean(&a),
                    drystone::stats::sd(&a),
                    drystone::stats::mean(&d5),
                    rows.len(),
                    t0.elapsed().as_secs_f64(),
                    seen,
                    independent,
                    drystone::stats::mean(&rot),
                    rot.iter().copied().fold(0.0, f64::max),
                    drystone::stats::mean(&moving)
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
    let who = args.get(7).cloned().or_else(|| std::env::var("REALWALL_OBSERVER").ok()).unwrap_or("product".into());
    let observers: Vec<Observer> = match who.as_str() {
        "product" => vec![Observer::Product],
        "independent" => vec![Observer::Independent],
        "both" => vec![Observer::Product, Observer::Independent],
        other => {
            eprintln!("the observer (eighth argument, or REALWALL_OBSERVER) is `product`, `independent` or `both`, not `{other}`");
            std::process::exit(2);
        }
    };
    let with_ways = observers.iter().map(|&o| Way::With(o));
    let ways: Vec<Way> = match mode {
        "without" => vec![Way::Without],
        "with" => with_ways.collect(),
        "both" => std::iter::once(Way::Without).chain(with_ways).collect(),
        other => {
            eprintln!("the seventh argument is `without`, `with` or `both`, not `{other}`");
            std::process::exit(2);
        }
    };
    let s = st.discrepancy.clone();
    let t0 = std::time::Instant::now();
    let template = data_set(&st, DATA_SEED, 0, 2, Edit::None, NOISE, &TILTS, s.sigma);
    let setup = drystone::study::discrepancy::setup_of(&st, s.most_realizations());
    // One preparation without and one with mechanism data (the template then holds every
    // mechanism key; every observer's data sets share it).
    let kinds: Vec<bool> = [false, true].into_iter().filter(|&w| ways.iter().any(|x| x.with() == w)).collect();
    let preps: Vec<(bool, drystone::discrepancy::Prepared)> = kinds
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
            (with, p)
        })
        .collect();
    let prep_of = |w: Way| &preps.iter().find(|p| p.0 == w.with()).expect("a preparation").1;
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
    let seen: Vec<(Observer, MechanismNoise)> = observers
        .iter()
        .map(|&o| {
            let m = if o == Observer::Product { MISREADING } else { INDEPENDENT_MISREADING };
            (o, MechanismNoise { misreading: m })
        })
        .collect();
    let mut answers: Vec<Row> = Vec::new();
    let mut diagnoses: Vec<String> = Vec::new();
    // (edit, observer, the rows as read) for the table of readings.
    let mut readings: Vec<(Edit, Observer, Vec<drystone::io::measured::MeasuredMechanism>)> = Vec::new();
    for &(e, c, i) in &jobs {
        let first = 1_000 + 100 * i as u64 + 100_000 * c as u64;
        let ds = data_set_observed(&st, DATA_SEED, first, specimens, e, NOISE, &seen, &TILTS, s.sigma);
        for ((o, _), rows) in seen.iter().zip(&ds.mechanisms) {
            readings.push((e, *o, rows.clone()));
        }
        let mut done: Vec<(Way, Row, Diag)> = Vec::new();
        for &way in &ways {
            let mut obs = ds.obs.clone();
            if let Way::With(o) = way {
                let k = seen.iter().position(|x| x.0 == o).expect("an observer's rows");
                let dir = files.join(format!("{c}-{i}-{}", o.name()));
                obs.extend(mechanism_observations_via_file(&st, &dir, &ds.mechanisms[k], s.sigma));
            }
            let (row, diag) = one(prep_of(way), obs, e, way, i, first);
            done.push((way, row, diag));
        }
        if let Some((_, base, d0)) = done.iter().find(|d| d.0 == Way::Without) {
            for (way, row, d) in done.iter().filter(|d| d.0.with()) {
                if row.2 != base.2 || d.verdict != d0.verdict || d.cause != d0.cause || row.3 != base.3 {
                    let text = diagnose(e, i, *way, (base, d0), (row, d));
                    eprintln!("{text}");
                    diagnoses.push(text);
                }
            }
        }
        answers.extend(done.into_iter().map(|d| d.1));
    }
    let _ = std::fs::remove_dir_all(&files);
    for &way in &ways {
        println!();
        println!("{}:", way.label());
        println!();
        table(&answers, way);
    }
    if ways.len() > 1 {
        println!();
        println!("Every way side by side (right / of which the named cause itself / of which with no tie / of which a partial explanation (verdict `unexplained`, the predictive check failed) / unexplained / no_effect / wrong cause):");
        println!();
        let head: Vec<&str> = ways.iter().map(|w| w.short()).collect();
        println!("| data | sets | {} |", head.join(" | "));
        println!("|{}", " --- |".repeat(2 + ways.len()));
        for e in std::iter::once(Edit::None).chain(classes()) {
            let cells: Vec<String> = ways
                .iter()
                .map(|&w| {
                    let mine: Vec<&Row> = answers.iter().filter(|r| r.0 == e && r.1 == w).collect();
                    let c = |a: Answer| mine.iter().filter(|r| r.2 == a).count();
                    let itself = mine.iter().filter(|r| r.2 == Answer::Right && r.3 .0).count();
                    let alone = mine.iter().filter(|r| r.2 == Answer::Right && r.3 .1).count();
                    let partial =
                        mine.iter().filter(|r| r.2 == Answer::Right && r.4.contains("): unexplained")).count();
                    format!(
                        "{} / {itself} / {alone} / {partial} / {} / {} / {}",
                        c(Answer::Right),
                        c(Answer::Unexplained),
                        c(Answer::NoEffect),
                        c(Answer::Wrong)
                    )
                })
                .collect();
            let n = answers.iter().filter(|r| r.0 == e && r.1 == ways[0]).count();
            if n > 0 {
                println!("| {} | {n} | {} |", e.label(), cells.join(" | "));
            }
        }
    }
    if observers.len() > 1 || ways.iter().any(|w| w.with()) {
        println!();
        println!("The mechanisms as each observer read them (after misreadings; failure height as a fraction of the wall's height):");
        println!();
        println!("| data | observer | free: mean height, at the table joint | free: kinds | held: mean height, at the table joint | held: kinds | held: starts |");
        println!("| --- | --- | --- | --- | --- | --- | --- |");
        for e in std::iter::once(Edit::None).chain(classes()) {
            for &o in &observers {
                let rows: Vec<&drystone::io::measured::MeasuredMechanism> =
                    readings.iter().filter(|r| r.0 == e && r.1 == o).flat_map(|r| r.2.iter()).collect();
                if rows.is_empty() {
                    continue;
                }
                let part = |held: bool| {
                    let mine: Vec<_> = rows.iter().filter(|r| (r.group == "HELD") == held).collect();
                    let h: Vec<f64> = mine.iter().filter_map(|r| r.failure_height.map(|x| x.0)).collect();
                    let count = |names: Vec<&str>| {
                        let mut m = std::collections::BTreeMap::new();
                        for n in names {
                            *m.entry(n).or_insert(0usize) += 1;
                        }
                        let mut v: Vec<(&str, usize)> = m.into_iter().collect();
                        v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
                        v.iter().map(|(n, k)| format!("{n} {k}")).collect::<Vec<_>>().join(", ")
                    };
                    (
                        format!("{:.2}, {}", drystone::stats::mean(&h), h.iter().filter(|x| **x == 0.0).count()),
                        count(mine.iter().filter_map(|r| r.kind.map(|k| k.name())).collect()),
                        count(mine.iter().filter_map(|r| r.start.map(|k| k.name())).collect()),
                    )
                };
                let (free, held) = (part(false), part(true));
                println!(
                    "| {} | {} | {} | {} | {} | {} | {} |",
                    e.label(),
                    o.name(),
                    free.0,
                    free.1,
                    held.0,
                    held.1,
                    held.2
                );
            }
        }
    }
    println!();
    println!("The weights: the pseudo-BMA+ weight of the truth (the baseline on null data; else the models made of the class's effects, summed), its mean and range over the data sets, and in how many data sets the truth is among the models that share 90 % of the weight:");
    println!();
    println!(
        "| data | mechanisms | sets | weight of the truth, mean | min – max | truth among the models sharing 90 % |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for &way in &ways {
        for e in std::iter::once(Edit::None).chain(classes()) {
            let w: Vec<&(f64, bool)> = answers.iter().filter(|(x, m, ..)| *x == e && *m == way).map(|r| &r.5).collect();
            if w.is_empty() {
                continue;
            }
            let v: Vec<f64> = w.iter().map(|x| x.0).collect();
            println!(
                "| {} | {} | {} | {:.3} | {:.3} – {:.3} | {} of {} |",
                e.label(),
                way.short(),
                w.len(),
                drystone::stats::mean(&v),
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                w.iter().filter(|x| x.1).count(),
                w.len()
            );
        }
    }
    if ways.len() > 1 && ways[0] == Way::Without {
        println!();
        let others: Vec<Way> = ways[1..].to_vec();
        let head: Vec<String> = others.iter().map(|w| format!("alone, {}", w.short())).collect();
        let bad: Vec<String> = others.iter().map(|w| format!("bad, {}", w.short())).collect();
        println!("The named cause is the hidden effect alone, and false alarms or wrong causes (bad), per way:");
        println!();
        println!("| data | sets | alone, without | {} | bad, without | {} |", head.join(" | "), bad.join(" | "));
        println!("|{}", " --- |".repeat(4 + 2 * others.len()));
        for e in std::iter::once(Edit::None).chain(classes()) {
            let count = |way: Way, f: &dyn Fn(&Answer, &(bool, bool)) -> bool| {
                answers.iter().filter(|(x, w, a, b, ..)| *x == e && *w == way && f(a, b)).count()
            };
            let n = count(Way::Without, &|_, _| true);
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
            let alones: Vec<String> = ways.iter().map(|&w| dash(count(w, &alone))).collect();
            let bads: Vec<String> = ways.iter().map(|&w| count(w, &bad).to_string()).collect();
            println!("| {} | {n} | {} | {} |", e.label(), alones.join(" | "), bads.join(" | "));
        }
    }
    if !diagnoses.is_empty() {
        println!();
        println!("Data sets whose answer with an observer's mechanisms differs from the answer without (answer class, named cause or its tie):");
        for d in &diagnoses {
            println!();
            println!("{d}");
        }
    }
    eprintln!("total {:.0} s", t0.elapsed().as_secs_f64());
}

/// The kinds of observable the diagnosis splits scores by.
const KINDS: [&str; 5] = ["angle", "displacements", "failure height", "kind", "start"];

fn kind_of(o: &drystone::discrepancy::Observable) -> usize {
    use drystone::discrepancy::Observable as O;
    match o {
        O::CollapseAngle => 0,
        O::Displacement { .. } => 1,
        O::FailureHeight { .. } => 2,
        O::MechanismKind { .. } => 3,
        O::MechanismStart { .. } => 4,
        O::InPlane { .. } | O::InPlaneMode { .. } => {
            unreachable!("the test bed's walls are tilted, not pushed in plane")
        }
    }
}

/// Scores summed per kind of observable.
fn split(scores: &[f64], obs: &[drystone::discrepancy::Observation]) -> [f64; 5] {
    let mut out = [0.0; 5];
    for (s, o) in scores.iter().zip(obs) {
        out[kind_of(&o.observable)] += s;
    }
    out
}

fn fmt_split(v: &[f64; 5]) -> String {
    KINDS.iter().zip(v).filter(|(_, x)| **x != 0.0).map(|(k, x)| format!("{k} {x:.2}")).collect::<Vec<_>>().join(", ")
}

fn fmt_split3(v: &[f64; 5]) -> String {
    KINDS
        .iter()
        .zip(v)
        .filter(|(_, x)| x.abs() > 5e-4)
        .map(|(k, x)| format!("{k} {x:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// What the diagnosis needs of one analysis.
struct Diag {
    verdict: String,
    cause: Option<String>,
    tie: Vec<String>,
    /// The baseline's scores summed per kind; its held-out error and AICc.
    baseline: ([f64; 5], f64, f64),
    /// The truth (best-ranked model of the class's effects; the baseline on null data):
    /// name, rank (0: first), held-out error, scores per kind.
    truth: Option<(String, usize, f64, [f64; 5])>,
    /// The named cause, or the best candidate: name, held-out error, AICc, scores per kind.
    top: Option<(String, f64, f64, [f64; 5])>,
    /// Gain margin, misfit margin, the screening gain.
    margins: (f64, f64, f64),
    tie_checks: Vec<drystone::discrepancy::TieCheck>,
    check: Option<drystone::discrepancy::PredictiveCheck>,
    /// The checked model's score per specimen split by kind of observable (angles and
    /// displacements from their predictive, kinds and starts from their probability, the
    /// failure height the rest of the check's score).
    check_split: Option<[f64; 5]>,
    specimens: usize,
}

/// The predictive check's score per specimen split by kind of observable: the extended
/// model's predictive of each observation (angles and displacements scored as the
/// analysis scores them, a displacement weighted 1/k for k per specimen; a kind or a start
/// `−ln q` with q its predictive mean), the failure heights the remainder of the check's
/// score (zero without mechanism data, up to rounding: a test of the split).
fn check_split(run: &drystone::discrepancy::Run) -> Option<[f64; 5]> {
    let c = run.analysis.check.as_ref()?;
    let n = run.specimens.len().max(1) as f64;
    let reading = run.settings.reading;
    let mut out = [0.0; 5];
    for (o, p) in run.obs.iter().zip(&run.extended_predictive) {
        let k = kind_of(&o.observable);
        let v = match k {
            0 => p.score(o.value, reading.of(&o.observable)),
            1 => {
                let per =
                    run.obs.iter().filter(|x| x.specimen == o.specimen && kind_of(&x.observable) == 1).count().max(1)
                        as f64;
                p.score(o.value, reading.of(&o.observable)) / per
            }
            3 | 4 => {
                let q = p.mean.clamp(1e-12, 1.0 - 1e-12);
                if o.value >= 0.5 {
                    -q.ln()
                } else {
                    -(1.0 - q).ln()
                }
            }
            _ => 0.0,
        };
        out[k] += v / n;
    }
    out[2] = c.score - (out[0] + out[1] + out[3] + out[4]);
    Some(out)
}

/// Analyses one data set's observations and classifies the answer.
fn one(
    prep: &drystone::discrepancy::Prepared,
    obs: Vec<drystone::discrepancy::Observation>,
    e: Edit,
    way: Way,
    i: usize,
    first: u64,
) -> (Row, Diag) {
    let run = analyze(prep, obs, first).unwrap();
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| c.name.clone());
    let got = classify(e, a.verdict.name(), cause.as_deref(), &a.tie);
    let named = cause.as_deref().is_some_and(|c| c.split('+').all(|m| realwalls::expected(e).contains(&m)));
    let m = &a.margins;
    let gain = a.candidates.first().map_or(0.0, |b| a.baseline_heldout_error - b.heldout_error);
    let missed = a.check.as_ref().map(|c| c.missed.clone()).unwrap_or_default();
    let what = format!(
        "{} #{i} ({}): {} {:?} tie {:?} | base {:.2} (misfit margin {:.2}) best gain {:.2}, on the surrogates {:.2} (margin {:.2}) sigma {:?} missed {:?}",
        e.label(),
        way.short(),
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
    let baseline = (split(&a.baseline_scores, &run.obs), a.baseline_heldout_error, a.baseline_information_criterion);
    let diag = Diag {
        verdict: a.verdict.name().to_string(),
        cause: cause.clone(),
        tie: a.tie.clone(),
        baseline,
        truth: if e == Edit::None {
            Some(("baseline".into(), usize::MAX, a.baseline_heldout_error, baseline.0))
        } else {
            a.candidates
                .iter()
                .enumerate()
                .find(|(_, c)| truth(&c.name))
                .map(|(k, c)| (c.name.clone(), k, c.heldout_error, split(&c.scores, &run.obs)))
        },
        top: a
            .cause
            .as_ref()
            .or(a.candidates.first())
            .map(|c| (c.name.clone(), c.heldout_error, c.information_criterion, split(&c.scores, &run.obs))),
        margins: (m.baseline, m.misfit, a.screen_gain),
        tie_checks: a.tie_checks.clone(),
        check: a.check.clone(),
        check_split: check_split(&run),
        specimens: run.specimens.len(),
    };
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
    ((e, way, got, (named, named && a.tie.len() <= 1), what, (truth_weight, truth_shared)), diag)
}

/// One way's state in a diagnosis: the verdict, the scores per kind, the margins, the tie
/// checks and the predictive check.
fn describe(way: Way, row: &Row, d: &Diag) -> String {
    let n = d.specimens.max(1) as f64;
    let mut t = format!("  {}: {:?}, {} {:?} tie {:?}\n", way.label(), row.2, d.verdict, d.cause, d.tie);
    t += &format!(
        "    baseline: held-out {:.3} per specimen (sum {:.2}: {}), AICc {:.2}\n",
        d.baseline.1,
        d.baseline.1 * n,
        fmt_split(&d.baseline.0),
        d.baseline.2
    );
    if let Some((name, rank, he, sp)) = &d.truth {
        let rank = if *rank == usize::MAX { "-".to_string() } else { (rank + 1).to_string() };
        t += &format!("    truth {name} (rank {rank}): held-out {he:.3} (sum {:.2}: {})\n", he * n, fmt_split(sp));
    } else {
        t += "    truth: no model of the class's effects among the candidates\n";
    }
    if let Some((name, he, ic, sp)) = &d.top {
        let named = if d.cause.is_some() { "named" } else { "best candidate" };
        t += &format!("    {named} {name}: held-out {he:.3} (sum {:.2}: {}), AICc {ic:.2}\n", he * n, fmt_split(sp));
        if let Some((tn, _, _, tsp)) = &d.truth {
            if tn != name {
                let diff: [f64; 5] = std::array::from_fn(|k| tsp[k] - sp[k]);
                t += &format!(
                    "    truth minus {name} per kind (> 0: {name} scores better): {} (total {:.2})\n",
                    fmt_split(&diff),
                    diff.iter().sum::<f64>()
                );
            }
        }
        t += &format!(
            "    margins: gain {:.3} (gain margin {:.3}), screening gain {:.3}; baseline {:.3} (misfit margin {:.3}); AICc {} the baseline's\n",
            d.baseline.1 - he,
            d.margins.0,
            d.margins.2,
            d.baseline.1,
            d.margins.1,
            if *ic < d.baseline.2 { "below" } else { "not below" }
        );
    }
    for c in &d.tie_checks {
        t += &format!(
            "    tie check {}: reversal {:.2}, difference {:.2} ± {:.2}{} -> {}\n",
            c.name,
            c.reversal_rate,
            c.difference,
            c.difference_se,
            c.on_measures.as_ref().map_or(String::new(), |m| format!(
                "; measures: reversal {:.2}, difference {:.2} ± {:.2}, readings {:.2} ± {:.2}",
                m.reversal_rate, m.difference, m.difference_se, m.readings_difference, m.readings_difference_se
            )),
            if c.tied { "tied" } else { "separated" }
        );
    }
    if let Some(c) = &d.check {
        t += &format!(
            "    predictive check: score {:.3} vs envelope {:.3} ({}), per specimen by kind {}, missed {:?}\n",
            c.score,
            c.envelope,
            if c.passes() { "passes" } else { "fails" },
            d.check_split.as_ref().map_or(String::new(), |v| format!("[{}]", fmt_split3(v))),
            c.missed
        );
    }
    t
}

/// Why the answer with mechanisms (`b`) differs from the answer without (`a`).
fn turned_by(a: &Diag, b: &Diag) -> Vec<String> {
    let mut why = Vec::new();
    let gain_ok = |d: &Diag| {
        d.top
            .as_ref()
            .is_some_and(|t| d.margins.2 > d.margins.0 && d.baseline.1 - t.1 > d.margins.0 && t.2 < d.baseline.2)
    };
    match (&a.cause, &b.cause) {
        (Some(_), None) | (None, Some(_)) => why.push(format!(
            "margins: a cause named {} the mechanisms and not {} (gain clears its margin without: {}, with: {})",
            if a.cause.is_some() { "without" } else { "with" },
            if a.cause.is_some() { "with" } else { "without" },
            gain_ok(a),
            gain_ok(b)
        )),
        (Some(x), Some(y)) if x != y => why.push(format!("likelihood: the ranking puts {y} first instead of {x}")),
        _ => {}
    }
    if a.cause.is_none() && b.cause.is_none() && a.verdict != b.verdict {
        why.push(format!(
            "misfit margin: baseline {:.3} vs margin {:.3} without, {:.3} vs {:.3} with",
            a.baseline.1, a.margins.1, b.baseline.1, b.margins.1
        ));
    }
    let tie_changed = (a.cause == b.cause && a.tie != b.tie) || a.tie.len() != b.tie.len();
    if a.cause.is_some() && b.cause.is_some() && tie_changed {
        why.push(format!("tie checks: tie {:?} without, {:?} with", a.tie, b.tie));
    }
    let passes = |d: &Diag| d.check.as_ref().map(|c| c.passes());
    if a.cause.is_some() && b.cause.is_some() && passes(a) != passes(b) {
        why.push(format!(
            "predictive check: {} without, {} with",
            passes(a).map_or("none", |p| if p { "passes" } else { "fails" }),
            passes(b).map_or("none", |p| if p { "passes" } else { "fails" })
        ));
    }
    if why.is_empty() {
        why.push("nothing but the answer's class (the same cause, tie and check)".into());
    }
    why
}

/// The diagnosis of one data set whose answer with `way`'s mechanisms differs from its
/// answer without.
fn diagnose(e: Edit, i: usize, way: Way, without: (&Row, &Diag), with: (&Row, &Diag)) -> String {
    let mut t = format!("{} #{i}: {:?} without, {:?} {}\n", e.label(), without.0 .2, with.0 .2, way.label());
    t += &describe(Way::Without, without.0, without.1);
    t += &describe(way, with.0, with.1);
    t += &format!("  turned by: {}", turned_by(without.1, with.1).join("; "));
    t
}

/// The power table of the analyses made one way.
fn table(answers: &[Row], way: Way) {
    println!("| data | sets | right (alone or in a tie) | of which the named cause itself | of which with no tie | unexplained | no_effect | wrong cause | rate that matters, 95 % CI |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for e in std::iter::once(Edit::None).chain(classes()) {
        let mine = || answers.iter().filter(|(x, w, ..)| *x == e && *w == way);
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
