//! The designed follow-up calibrated on data it did not make: every data set of the test
//! bed (`tests/discrepancy/study.toml`, data made by `tests/realwalls/mod.rs`: layouts
//! edited as files, noise at a σ the engine is not told, rounded readings), nulls included,
//! is analysed; `drystone design` picks its best follow-up and states the probability that
//! the cause is then named alone (re-estimated on simulations independent of those that
//! picked it, column `p_alone`; the ranking's own estimate in `p_selected`, the
//! re-estimate's 95 % interval in `p_low`, `p_high`); the follow-up's specimens are made the same independent
//! way (the follow-up's walls generated with the data's seed, edited as files with the same
//! hidden edit, tilted, readings rounded; the mechanism read from each edited wall's own
//! run and misread at 10 % when the follow-up reads it), and both campaigns are analysed
//! together on the written study (prepared after the first campaign's analysis,
//! `prepare_after`, which reads the runs they share). Each data set is one row appended to a CSV file, so the
//! column runs in parts, resumed (a row already in the file is skipped) and merged; each
//! data set's design (`design.json`'s content: every follow-up's probabilities at every
//! specimen count and by truth) is kept in `OUT.plans/CLASS-SET.json`, so other readings of
//! the design can be scored without a rerun.
//!
//! ```sh
//! cargo run --release --example realwall_design -- run OUT.csv [SETS_PER_CLASS] [FIRST_SET] [CLASSES] [--without-mechanism]
//! cargo run --release --example realwall_design -- rescore FROM.csv OUT.csv
//! cargo run --release --example realwall_design -- summary OUT.csv [MORE.csv ...]
//! ```
//!
//! `--run-store=DIR` (with `run` or `rescore`): the forward runs are read from and kept in
//! the run store `DIR` ([`drystone::discrepancy::RunStore`]), so the parts of a column
//! run side by side, and data sets after the first, read the test bed's runs and the
//! follow-up walls' grids instead of making them again; the rows are the same bit for bit.
//!
//! `rescore` makes every data set of FROM.csv again with the current design: where the
//! design makes the same follow-up as FROM's row, the row's observed columns are kept (the
//! analysis of both campaigns depends on the data set and the follow-up made, nothing
//! else) and its predicted columns replaced, with no follow-up run; where it makes
//! another, the data set is run in full.
//!
//! `CLASSES`: indices into the classes (`0,2`; 0–5 the hidden effects, 6 null data),
//! default all; `--without-mechanism`: the best follow-up that does not read the failure
//! mechanism is made instead of the best one (the column without the mechanism; write it to
//! a file of its own). `FIRST_SET`: the first data set's index (data set `i` of class `c` uses the
//! specimens `1000 c + 100 + 10 i ..`). `summary` prints the reliability table of the
//! design's promise (the predicted probability of naming the cause alone, in bins, against
//! the observed frequency) and its Brier score, the same for the weights' criterion, the
//! alone-after-follow-up column per class, the false-alarm rate on null data, the same
//! split by whether the follow-up reads the mechanism and by whether it adds walls of a
//! new kind, and how often the design said that no follow-up reaches the target (column
//! `says_none`) while the cause was then named alone. Which figures are independent: the
//! observed columns (data made outside the engine, analysed by it); the predicted
//! probabilities are the design's own. The column measured is in
//! `docs/calibration/design_column.csv` (docs/discrepancy.md, "On data it did not make").

#[path = "../tests/realwalls/mod.rs"]
mod realwalls;

use drystone::discrepancy::design::{design, DesignSettings, Plan, RankedFollowUp};
use drystone::discrepancy::{analyze, prepare, prepare_after, quiet};
use drystone::study::discrepancy::setup_of;
use drystone::study::followup::{menu, write_followup};
use drystone::study::Study;
use realwalls::{
    data_set, data_set_with_mechanism, expected, mechanism_observations_via_file, Edit, MechanismNoise, Noise,
};
use std::io::Write;
use std::path::{Path, PathBuf};

const NOISE: Noise =
    Noise { angle_deg: 0.4, displacement_cm: 0.01, angle_reading_deg: 0.25, displacement_reading_cm: 0.01 };
const TILTS: [f64; 2] = [5.0, 10.0];
const DATA_SEED: u64 = 0x5eed_da7a;
const SPECIMENS: u64 = 5;
const HEADER: &str = "class,set,first_alone,followup,reads_mechanism,p_alone,p_weights,verdict,cause,tie,alone,weights_alone,alarm,seconds,first_tie,tie_members,weights_shared,discrepancy,says_none,p_selected,p_low,p_high";

fn classes() -> Vec<Edit> {
    vec![
        Edit::Lean(1.5),
        Edit::Round(0.004),
        Edit::Stiffness(0.3),
        Edit::SoftBase(5e6),
        Edit::Springs(150.0),
        Edit::LeanRound(1.5, 0.004),
        Edit::None,
    ]
}

/// The hidden cause named with no tie (the verdict's criterion, the design's "named alone").
fn alone(e: Edit, cause: Option<&str>, tie: &[String]) -> bool {
    e != Edit::None && cause.is_some_and(|c| c.split('+').all(|m| expected(e).contains(&m))) && tie.len() <= 1
}

fn main() {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let store = all
        .iter()
        .find_map(|a| a.strip_prefix("--run-store="))
        .map(|dir| std::sync::Arc::new(drystone::discrepancy::RunStore::open(dir).unwrap_or_else(|e| panic!("{e}"))));
    let args: Vec<String> = all.into_iter().filter(|a| !a.starts_with("--run-store=")).collect();
    match args.first().map(String::as_str) {
        Some("run") if args.len() >= 2 => run(&args[1..], store),
        Some("summary") if args.len() >= 2 => summary(&args[1..]),
        Some("rescore") if args.len() >= 3 => rescore(&args[1], &args[2], store),
        _ => {
            eprintln!(
                "usage: realwall_design run OUT.csv [SETS_PER_CLASS] [FIRST_SET] [CLASSES] [--without-mechanism] [--run-store=DIR] | rescore FROM.csv OUT.csv [--run-store=DIR] | summary FILE.csv ..."
            );
            std::process::exit(2);
        }
    }
}

/// What every data set of a column shares: the test bed's study, its setup, the prepared
/// forward runs and the design's settings.
struct Bed {
    st: Study,
    setup: drystone::discrepancy::Setup,
    prep: drystone::discrepancy::Prepared,
    ds: DesignSettings,
}

impl Bed {
    /// The test bed, its runs read from and kept in `store` when one is given.
    fn new(store: Option<std::sync::Arc<drystone::discrepancy::RunStore>>) -> Bed {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
        let st = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
        let s = st.discrepancy.clone();
        let mut setup = setup_of(&st, s.most_realizations());
        setup.store = store;
        let template = data_set(&st, DATA_SEED, 0, 2, Edit::None, NOISE, &TILTS, s.sigma);
        let prep = prepare(&setup, &template, &s, &st.library).unwrap();
        let ds = DesignSettings { specimens: SPECIMENS as usize, replicates: 100, ..DesignSettings::default() };
        Bed { st, setup, prep, ds }
    }
}

fn run(args: &[String], store: Option<std::sync::Arc<drystone::discrepancy::RunStore>>) {
    let without_mechanism = args.iter().any(|a| a == "--without-mechanism");
    let args: Vec<String> = args.iter().filter(|a| !a.starts_with("--")).cloned().collect();
    let out = PathBuf::from(&args[0]);
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    let first_set: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(0);
    let only: Option<Vec<usize>> = args.get(3).map(|a| a.split(',').filter_map(|x| x.parse().ok()).collect());
    let done: Vec<(String, usize)> =
        read_rows(&out).iter().map(|r| (r[0].clone(), r[1].parse().unwrap_or(0))).collect();
    if !out.exists() {
        std::fs::write(&out, format!("{HEADER}\n")).unwrap();
    }
    let bed = Bed::new(store);
    for (ci, e) in classes().into_iter().enumerate() {
        if only.as_ref().is_some_and(|o| !o.contains(&ci)) {
            continue;
        }
        for i in first_set..first_set + n {
            if done.contains(&(e.label(), i)) {
                continue;
            }
            one_set(&bed, ci, e, i, without_mechanism, None, &out);
        }
    }
}

/// Every row of `from` made again by the current design on the same data set: where the
/// design makes the same follow-up as the row, the row's observed columns (the analysis of
/// both campaigns, which depends on the follow-up made alone) are kept and its predicted
/// columns replaced; where it makes another, the data set is run in full. Rows already in
/// `out` are skipped.
fn rescore(from: &str, out: &str, store: Option<std::sync::Arc<drystone::discrepancy::RunStore>>) {
    let out = PathBuf::from(out);
    let done: Vec<(String, usize)> =
        read_rows(&out).iter().map(|r| (r[0].clone(), r[1].parse().unwrap_or(0))).collect();
    if !out.exists() {
        std::fs::write(&out, format!("{HEADER}\n")).unwrap();
    }
    let bed = Bed::new(store);
    let classes = classes();
    for row in read_rows(Path::new(from)) {
        let i: usize = row[1].parse().unwrap_or(0);
        let Some(ci) = classes.iter().position(|e| e.label() == row[0]) else { continue };
        if done.contains(&(row[0].clone(), i)) {
            continue;
        }
        one_set(&bed, ci, classes[ci], i, false, Some(&row), &out);
    }
}

/// One data set of class `e` (index `ci`), set `i`: the first campaign analysed, the design,
/// the follow-up made and both campaigns analysed; the row appended to `out`. With `old`,
/// a row of the same data set made by another design: if the follow-up made is the same,
/// its observed columns are kept (no follow-up run).
fn one_set(bed: &Bed, ci: usize, e: Edit, i: usize, without_mechanism: bool, old: Option<&[String]>, out: &Path) {
    let (st, setup, prep, ds) = (&bed.st, &bed.setup, &bed.prep, &bed.ds);
    let s = &st.discrepancy;
    let first = 1000 * ci as u64 + 100 + 10 * i as u64;
    let t0 = std::time::Instant::now();
    let obs = data_set(st, DATA_SEED, first, SPECIMENS, e, NOISE, &TILTS, s.sigma);
    let mut run = analyze(prep, obs.clone(), first).unwrap();
    let a = &run.analysis;
    let was = alone(e, a.cause.as_ref().map(|c| c.name.as_str()), &a.tie);
    let first_tie = a.tie.clone();
    let m = menu(st, setup, &run).unwrap();
    let mut plan = design(&run, setup, m, ds, first, &quiet).unwrap();
    if without_mechanism {
        // The best follow-up that does not read the mechanism, made as the best.
        let reads = |r: &RankedFollowUp| r.followup.observables.iter().any(|o| o.is_mechanism());
        let Some(k) = plan.ranked.iter().position(|r| !reads(r)) else {
            eprintln!("{} #{i}: no follow-up without the mechanism", e.label());
            return;
        };
        let chosen = plan.ranked.remove(k);
        plan.ranked.insert(0, chosen);
        if k > 0 {
            // The re-estimate is the design's best's: this column reports the
            // ranking's own estimate of the follow-up it makes instead.
            plan.reported = None;
        }
    }
    let best = plan.best().unwrap().clone();
    // The design says no follow-up of its menu reaches the target within its ladder.
    let says_none = plan.ranked.iter().all(|r| r.to_target.is_none());
    // The plan kept beside the CSV, to score other readings of it without a rerun.
    let plans = out.with_extension("plans");
    let _ = std::fs::create_dir_all(&plans);
    // The class's label made a file name ("table Kn 5.0e6 Pa/m" → "table_Kn_5.0e6_Pa_m").
    let stem: String = e.label().chars().map(|c| if c.is_alphanumeric() || c == '.' { c } else { '_' }).collect();
    let kept = plans.join(format!("{stem}-{i}.json"));
    if let Err(err) = std::fs::write(&kept, serde_json::to_string(&plan).unwrap_or_default()) {
        eprintln!("{}: {err} (the design is not kept)", kept.display());
    }
    if let Some(old) = old.filter(|o| o[3] == best.followup.name.replace('"', "'")) {
        // The same follow-up made: the observed columns are the row's.
        let mut row: Vec<String> = old.to_vec();
        predicted(&mut row, &plan, &best, says_none, t0.elapsed().as_secs_f64());
        append(out, &row);
        return;
    }
    run.followup = Some(plan.clone());
    let dir = std::env::temp_dir().join(format!("realwall_design-{}-{first}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let files = write_followup(st, &plan, &dir, SPECIMENS as usize, None).unwrap().unwrap();
    let fst = Study::from_file(&files.study).expect("the follow-up study reads");
    // The follow-up's specimens from the hidden truth walls: fresh realizations of the
    // follow-up's group, edited by the same hidden edit.
    let mut only_group = fst.clone();
    only_group.groups.retain(|g| g.name == best.followup.group);
    let reads_mechanism = best.followup.observables.iter().any(|o| o.is_mechanism());
    let seen = MechanismNoise { misreading: 0.1 };
    let more =
        data_set_with_mechanism(&only_group, DATA_SEED, first + 50_000, SPECIMENS, e, NOISE, seen, &TILTS, s.sigma);
    let mut both = obs.clone();
    both.extend(more.obs);
    if reads_mechanism {
        both.extend(mechanism_observations_via_file(&only_group, &dir.join("mech"), &more.mechanism, s.sigma));
    }
    let mut fsetup = setup_of(&fst, fst.discrepancy.most_realizations());
    fsetup.store = setup.store.clone();
    // The first campaign's runs, read where the follow-up's study runs them alike.
    let fprep = prepare_after(&fsetup, &both, &fst.discrepancy, &fst.library, Some(prep), &quiet).unwrap();
    let run2 = analyze(&fprep, both, first).unwrap();
    let b = &run2.analysis;
    let cause2 = b.cause.as_ref().map(|c| c.name.clone());
    let now = alone(e, cause2.as_deref(), &b.tie);
    let by_weights = b.weights.shared.len() == 1 && alone(e, Some(&b.weights.shared[0]), &[]);
    let alarm = e == Edit::None && b.verdict.name() != "no_effect";
    let mut row = vec![String::new(); HEADER.split(',').count()];
    row[0] = e.label();
    row[1] = i.to_string();
    row[2] = was.to_string();
    row[3] = best.followup.name.replace('"', "'");
    row[4] = reads_mechanism.to_string();
    row[7] = b.verdict.name().to_string();
    row[8] = cause2.as_deref().unwrap_or("-").to_string();
    row[9] = b.tie.len().to_string();
    row[10] = now.to_string();
    row[11] = by_weights.to_string();
    row[12] = alarm.to_string();
    row[14] = first_tie.join(";");
    row[15] = b.tie.join(";");
    row[16] = b.weights.shared.join(";");
    predicted(&mut row, &plan, &best, says_none, t0.elapsed().as_secs_f64());
    append(out, &row);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The design's columns of a row (HEADER's order): the promise, the weights' promise, the
/// discrepancy carried, whether it says no follow-up reaches the target, the ranking's own
/// estimate, the promise's interval; and the seconds the data set took.
fn predicted(row: &mut [String], plan: &Plan, best: &RankedFollowUp, says_none: bool, seconds: f64) {
    row[5] = format!("{:.4}", plan.promise().unwrap_or(best.at_budget.alone));
    row[6] = format!("{:.4}", plan.reported.as_ref().map_or(best.at_budget.weights_alone, |r| r.chance.weights_alone));
    row[13] = format!("{seconds:.0}");
    row[17] = plan.inadequacy.iter().map(|v| format!("{v:.2}")).collect::<Vec<_>>().join(";");
    row[18] = says_none.to_string();
    row[19] = format!("{:.4}", best.at_budget.alone);
    row[20] = format!("{:.4}", plan.reported.as_ref().map_or(f64::NAN, |r| r.interval.0));
    row[21] = format!("{:.4}", plan.reported.as_ref().map_or(f64::NAN, |r| r.interval.1));
}

/// Appends `row` to the CSV `out` and prints it (the follow-up's name and the two tie
/// lists quoted, as the column's files have them).
fn append(out: &Path, row: &[String]) {
    let row: Vec<String> = row
        .iter()
        .enumerate()
        .map(|(k, v)| if [3, 14, 15].contains(&k) { format!("\"{v}\"") } else { v.clone() })
        .collect();
    let row = row.join(",");
    println!("{row}");
    let mut f = std::fs::OpenOptions::new().append(true).open(out).unwrap();
    writeln!(f, "{row}").unwrap();
}

/// The rows of a CSV written by `run` (fields split on commas outside quotes).
fn read_rows(path: &Path) -> Vec<Vec<String>> {
    let Ok(text) = std::fs::read_to_string(path) else { return vec![] };
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let mut fields = vec![String::new()];
            let mut quoted = false;
            for ch in l.chars() {
                match ch {
                    '"' => quoted = !quoted,
                    ',' if !quoted => fields.push(String::new()),
                    c => fields.last_mut().unwrap().push(c),
                }
            }
            fields
        })
        .collect()
}

fn summary(files: &[String]) {
    let mut rows: Vec<Vec<String>> = Vec::new();
    for f in files {
        for r in read_rows(Path::new(f)) {
            if !rows.iter().any(|x| x[0] == r[0] && x[1] == r[1]) {
                rows.push(r);
            }
        }
    }
    let flag = |r: &Vec<String>, k: usize| r[k] == "true";
    let p = |r: &Vec<String>| r[5].parse::<f64>().unwrap_or(f64::NAN);
    let effect: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] != "null").collect();
    let nulls: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "null").collect();
    // The reliability table of the probabilities in column `pc` against the outcomes in `oc`.
    let table_of = |title: &str, set: &[&Vec<String>], pc: usize, oc: usize| {
        let p = |r: &Vec<String>| r[pc].parse::<f64>().unwrap_or(f64::NAN);
        println!("\n{title}: {} effect data sets\n", set.len());
        println!("| predicted P(named alone) | data sets | mean predicted | observed alone | |predicted − observed| |");
        println!("| --- | --- | --- | --- | --- |");
        for b in 0..5 {
            let (lo, hi) = (b as f64 * 0.2, (b + 1) as f64 * 0.2);
            let inb: Vec<&&Vec<String>> =
                set.iter().filter(|r| p(r) >= lo && (p(r) < hi || (b == 4 && p(r) <= 1.0))).collect();
            if inb.is_empty() {
                println!("| {lo:.1}–{hi:.1} | 0 | – | – | – |");
                continue;
            }
            let mp = inb.iter().map(|r| p(r)).sum::<f64>() / inb.len() as f64;
            let obs = inb.iter().filter(|r| flag(r, oc)).count() as f64 / inb.len() as f64;
            println!("| {lo:.1}–{hi:.1} | {} | {mp:.2} | {obs:.2} | {:.2} |", inb.len(), (mp - obs).abs());
        }
        let brier = set.iter().map(|r| (p(r) - f64::from(u8::from(flag(r, oc)))).powi(2)).sum::<f64>()
            / set.len().max(1) as f64;
        let promised: Vec<&&Vec<String>> = set.iter().filter(|r| p(r) >= 0.8).collect();
        let kept = promised.iter().filter(|r| flag(r, oc)).count();
        if set.is_empty() {
            return;
        }
        println!(
            "\nBrier score {brier:.3}; promised at least 0.8: {} data sets, named alone after {kept}.",
            promised.len()
        );
    };
    let table = |title: &str, set: &[&Vec<String>]| table_of(title, set, 5, 10);
    table("All follow-ups", &effect);
    // Rows that record the ranking's own estimate (column `p_selected`) beside the promise.
    let both: Vec<&Vec<String>> =
        effect.iter().copied().filter(|r| r.get(19).is_some_and(|v| v.parse::<f64>().is_ok())).collect();
    if !both.is_empty() {
        table_of(
            "The ranking's own estimate of the chosen follow-up (selecting replicates), same data sets",
            &both,
            19,
            10,
        );
        let covered = both
            .iter()
            .filter(|r| {
                let (lo, hi) = (r[20].parse::<f64>().unwrap_or(f64::NAN), r[21].parse::<f64>().unwrap_or(f64::NAN));
                let sel = r[19].parse::<f64>().unwrap_or(f64::NAN);
                sel >= lo && sel <= hi
            })
            .count();
        println!(
            "\nThe ranking's estimate inside the re-estimate's 95 % interval: {covered} of {} data sets.",
            both.len()
        );
    }
    table_of("By the weights' criterion (the truth alone holding 90 % of the weight), all follow-ups", &effect, 6, 11);
    let with: Vec<&Vec<String>> = effect.iter().copied().filter(|r| flag(r, 4)).collect();
    let without: Vec<&Vec<String>> = effect.iter().copied().filter(|r| !flag(r, 4)).collect();
    table("Follow-ups that read the mechanism", &with);
    table("Follow-ups that do not read the mechanism", &without);
    // A follow-up of walls of a new kind is named "<group> walls ..." by the menu; more
    // specimens of a first-campaign group are not.
    let new_walls = |r: &&Vec<String>| r[3].contains(" walls ");
    let same: Vec<&Vec<String>> = effect.iter().copied().filter(|r| !new_walls(r)).collect();
    let new: Vec<&Vec<String>> = effect.iter().copied().filter(new_walls).collect();
    table("Follow-ups on the first campaign's walls", &same);
    table("Follow-ups on walls of a new kind", &new);
    println!(
        "\n| hidden in the walls | data sets | alone (first campaign) | mean predicted | alone after the follow-up |"
    );
    println!("| --- | --- | --- | --- | --- |");
    let mut labels: Vec<&String> = Vec::new();
    for r in &effect {
        if !labels.contains(&&r[0]) {
            labels.push(&r[0]);
        }
    }
    for l in labels {
        let set: Vec<&&Vec<String>> = effect.iter().filter(|r| &r[0] == l).collect();
        let mp = set.iter().map(|r| p(r)).sum::<f64>() / set.len() as f64;
        let before = set.iter().filter(|r| flag(r, 2)).count();
        let after = set.iter().filter(|r| flag(r, 10)).count();
        println!("| {l} | {} | {before} | {mp:.2} | {after} |", set.len());
    }
    // Rows written before the column existed do not say.
    let said: Vec<&&Vec<String>> = effect.iter().filter(|r| r.get(18).is_some_and(|v| !v.is_empty())).collect();
    let none: Vec<&&Vec<String>> = said.iter().copied().filter(|r| flag(r, 18)).collect();
    println!(
        "\nThe design said no follow-up reaches the target: {} of {} effect data sets that record it; the cause then \
         named alone after {} of them (the statement holds when it is not).",
        none.len(),
        said.len(),
        none.iter().filter(|r| flag(r, 10)).count()
    );
    let alarms = nulls.iter().filter(|r| flag(r, 12)).count();
    println!("\nNull data: {} data sets, {alarms} false alarms after the follow-up.", nulls.len());
}
