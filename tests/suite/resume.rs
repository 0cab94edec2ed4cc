//! Crash safety of `drystone run`: a run killed with SIGKILL in the middle of its ensemble
//! keeps every finished realization in its journal, and `--resume` finishes it with outputs
//! byte-identical to an uninterrupted run (except the wall-time column). Also: an
//! unwritable `--out` is refused before anything runs, and the exit status when every
//! realization failed.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common;

const BIN: &str = env!("CARGO_BIN_EXE_drystone");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The small study of the tests: 2 groups × 2 sweep points × 4 realizations = 16 items of
/// short walls, a few seconds in all.
fn study() -> PathBuf {
    root().join("tests/studies/good/mini_sweep.toml")
}

const ITEMS: usize = 16;

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(root()).output().expect("drystone runs")
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The finished rows in a journal (lines after the header).
fn journal_rows(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("journal.jsonl")).map_or(0, |t| t.lines().count().saturating_sub(1))
}

/// A CSV file with the `wall_time_s` column removed.
fn without_wall_time(p: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let rows: Vec<Vec<String>> = text.lines().map(split_csv).collect();
    let i = rows[0].iter().position(|c| c == "wall_time_s").expect("a wall_time_s column");
    rows.into_iter()
        .map(|mut r| {
            r.remove(i);
            r
        })
        .collect()
}

/// Splits a CSV line (quoted cells may hold commas).
fn split_csv(line: &str) -> Vec<String> {
    let (mut cells, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => cells.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    cells.push(cur);
    cells
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn a_killed_run_resumes_to_the_outputs_of_an_uninterrupted_one() {
    let whole = common::Scratch::new("resume-whole");
    let killed = common::Scratch::new("resume-killed");
    let s = study();
    let s = s.to_str().unwrap();
    let o = run(&["run", s, "--realizations", "4", "--threads", "2", "--out", whole.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));

    // Started, killed with SIGKILL (Child::kill on Unix) once some but not all items are in
    // the journal.
    let mut child = Command::new(BIN)
        .args(["run", s, "--realizations", "4", "--threads", "1", "--out", killed.to_str().unwrap()])
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("drystone starts");
    let t0 = Instant::now();
    while journal_rows(&killed) < 1 {
        assert!(t0.elapsed() < Duration::from_secs(60), "no item finished within 60 s");
        assert!(child.try_wait().unwrap().is_none(), "the run ended before it could be killed");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().expect("SIGKILL");
    child.wait().unwrap();
    let finished = journal_rows(&killed);
    assert!((1..ITEMS).contains(&finished), "{finished} of {ITEMS} items in the journal");
    assert!(!killed.join("summary.csv").exists() && !killed.join("realizations.csv").exists());

    // A plain rerun would throw the finished items away: refused.
    let o = run(&["run", s, "--realizations", "4", "--out", killed.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("journal.jsonl: holds") && text(&o).contains("--resume"), "{}", text(&o));

    // Resumed on another number of threads.
    let o = run(&["run", s, "--realizations", "4", "--threads", "2", "--resume", "--out", killed.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let resumed: usize = text(&o)
        .split("failed, ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count of resumed items in {}", text(&o)));
    assert!((finished..ITEMS).contains(&resumed), "{resumed} resumed, {finished} were in the journal");
    assert_eq!(journal_rows(&killed), ITEMS, "every item once in the journal");

    for f in ["summary.csv", "report.md", "collapse_angle_histograms.svg", "fragility.svg", "displacement_vs_tilt.svg"]
    {
        assert_eq!(read(&whole.join(f)), read(&killed.join(f)), "{f} differs");
    }
    assert_eq!(without_wall_time(&whole.join("realizations.csv")), without_wall_time(&killed.join("realizations.csv")));
    let zero = |p: PathBuf| {
        let mut rows = drystone::io::table::read_realizations(&p).unwrap();
        rows.iter_mut().for_each(|r| r.wall_time_s = 0.0);
        rows
    };
    assert_eq!(zero(whole.join("realizations.parquet")), zero(killed.join("realizations.parquet")));

    // Resuming a finished run computes nothing and writes the same outputs.
    let t0 = Instant::now();
    let o = run(&["run", s, "--realizations", "4", "--resume", "--out", killed.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains(&format!("{ITEMS} from the journal")), "{}", text(&o));
    assert!(t0.elapsed() < Duration::from_secs(20));
    assert_eq!(read(&whole.join("summary.csv")), read(&killed.join("summary.csv")));
}

#[test]
fn an_unwritable_out_is_refused_before_anything_runs() {
    let scratch = common::Scratch::created("resume-unwritable");
    let file = scratch.join("a_file");
    std::fs::write(&file, b"not a directory").unwrap();
    let out = file.join("out");
    let s = study();
    let t0 = Instant::now();
    // 400000 items would run for days: the refusal must come first.
    let o = run(&["run", s.to_str().unwrap(), "--realizations", "100000", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains(&*file.to_string_lossy()), "the message names the path: {}", text(&o));
    assert!(t0.elapsed() < Duration::from_secs(20), "took {:?}", t0.elapsed());
}

#[test]
fn every_realization_failing_is_exit_status_3_and_the_outputs_are_written() {
    let scratch = common::Scratch::created("resume-all-failed");
    // No equilibrium at alpha = 0 within 5 steps: every realization fails.
    let text_of =
        std::fs::read_to_string(study()).unwrap().replace("[tilt]\n", "[tilt]\nmax_steps_per_increment = 5\n");
    let text_of = text_of.replace("../../../", &format!("{}/", root().display()));
    let s = scratch.join("failing.toml");
    std::fs::write(&s, text_of).unwrap();
    let out = scratch.join("out");
    let o = run(&["run", s.to_str().unwrap(), "--realizations", "1", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o));
    assert!(text(&o).contains("every realization (4) failed"), "{}", text(&o));
    let csv = std::fs::read_to_string(out.join("realizations.csv")).unwrap();
    assert_eq!(csv.matches("no_initial_equilibrium").count(), 4, "{csv}");
    assert!(out.join("report.md").exists());
}

/// A copy of the small study in `dir` (its relative paths made absolute) with `extra`
/// appended to its text (a comment changes its hash, hence the run's identity, and nothing
/// else). Returns its path.
fn study_copy(dir: &Path, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(study()).unwrap().replace("../../../", &format!("{}/", root().display()));
    let p = dir.join(format!("study{}.toml", extra.len()));
    std::fs::write(&p, text + extra).unwrap();
    p
}

/// The lines of a journal.
fn journal_lines(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join("journal.jsonl")).unwrap().lines().map(str::to_string).collect()
}

fn write_journal(dir: &Path, lines: &[String]) {
    std::fs::write(dir.join("journal.jsonl"), lines.join("\n") + "\n").unwrap();
}

/// Runs `study` with 1 realization (4 items) into `out` and returns the journal lines.
fn journal_of(study: &Path, out: &Path) -> Vec<String> {
    let (s, o) = (study.to_str().unwrap(), out.to_str().unwrap());
    let run = run(&["run", s, "--realizations", "1", "--threads", "1", "--out", o]);
    assert!(run.status.success(), "{}", text(&run));
    journal_lines(out)
}

#[test]
fn foreign_altered_or_mismatched_journal_lines_are_refused_before_anything_runs() {
    let scratch = common::Scratch::created("resume-foreign");
    let (a, b) = (study_copy(&scratch, ""), study_copy(&scratch, "# an edited copy\n"));
    let (da, db) = (scratch.join("a"), scratch.join("b"));
    let ja = journal_of(&a, &da);
    let jb = journal_of(&b, &db);
    assert_eq!(jb.len(), 5);
    let resume = |journal: &[String]| {
        write_journal(&db, journal);
        for f in ["realizations.csv", "summary.csv", "report.md"] {
            let _ = std::fs::remove_file(db.join(f));
        }
        let o = run(&["run", b.to_str().unwrap(), "--realizations", "1", "--resume", "--out", db.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert_eq!(journal_lines(&db), journal, "the journal is left as it was");
        assert!(!db.join("realizations.csv").exists(), "nothing was run or written");
        text(&o)
    };
    let journal = db.join("journal.jsonl");
    let at = |line: usize, field: &str| format!("{}: line {line}: {field}: ", journal.display());
    // The row of item 2 of the other study (same seed, group, point and realization; every
    // field but the run identity the same) in place of this run's row on line 3.
    let index = |l: &str| l.split("\"index\":").nth(1).and_then(|r| r.split(',').next()).unwrap().to_string();
    let foreign = ja.iter().skip(1).find(|l| index(l) == index(&jb[2])).unwrap().clone();
    let mut mixed = jb[..2].to_vec();
    mixed.push(foreign.clone());
    let msg = resume(&mixed);
    assert!(msg.contains(&format!("{}a row of another run", at(3, "run"))), "{msg}");
    // A flipped digit and an edited status in a row.
    let blocks = jb[2].split("\"blocks\":").nth(1).and_then(|r| r.split(',').next()).unwrap().to_string();
    let mut flipped = jb.clone();
    flipped[2] = jb[2].replacen(&format!("\"blocks\":{blocks},"), &format!("\"blocks\":{}1,", blocks), 1);
    let msg = resume(&flipped);
    assert!(msg.contains(&format!("{}the line was altered", at(3, "sum"))), "{msg}");
    let mut edited = jb.clone();
    edited[4] = jb[4].replacen("\"status\":\"", "\"status\":\"x", 1);
    assert!(resume(&edited).contains(&at(5, "sum")));
    // The journal of the other study as a whole: refused naming the differing input.
    let msg = resume(&ja);
    assert!(
        msg.contains("was written by another run (the study file ")
            && msg.contains("study0.toml is an input of the journal but not of this run"),
        "{msg}"
    );
    // A torn last line is still dropped and recomputed.
    let mut torn = jb[..3].to_vec();
    torn.push(jb[3][..jb[3].len() / 2].to_string());
    std::fs::write(&journal, torn.join("\n")).unwrap();
    let o = run(&["run", b.to_str().unwrap(), "--realizations", "1", "--resume", "--out", db.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("2 from the journal"), "{}", text(&o));
    assert_eq!(journal_lines(&db).len(), 5);
}

#[test]
fn a_plain_rerun_never_throws_finished_work_away() {
    let scratch = common::Scratch::created("resume-plain");
    let s = study_copy(&scratch, "");
    let out = scratch.join("out");
    let full = journal_of(&s, &out);
    // 2 of 4 items finished; a rerun with another --realizations, without --resume.
    write_journal(&out, &full[..3]);
    let (st, o) = (s.to_str().unwrap(), out.to_str().unwrap());
    let r = run(&["run", st, "--realizations", "3", "--out", o]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    assert!(
        text(&r).contains("was written by another run (realizations: 1 in the journal, 3 in this run)"),
        "{}",
        text(&r)
    );
    assert_eq!(journal_lines(&out), full[..3], "the journal is kept");
    // The same run without --resume: refused too.
    let r = run(&["run", st, "--realizations", "1", "--out", o]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    assert!(text(&r).contains("holds 2 of 4 finished realization(s) of this run; continue it with --resume"));
    // A damaged line is refused without --force too.
    let mut damaged = full[..3].to_vec();
    damaged[1] = damaged[1].replacen("\"seed\":7", "\"seed\":8", 1);
    write_journal(&out, &damaged);
    let r = run(&["run", st, "--realizations", "1", "--out", o]);
    assert_eq!(r.status.code(), Some(2), "{}", text(&r));
    assert!(text(&r).contains("journal.jsonl: line 2: sum: the line was altered"), "{}", text(&r));
    assert!(text(&r).contains("give --force to start again"), "{}", text(&r));
    // A finished journal of this run is started again.
    write_journal(&out, &full);
    let r = run(&["run", st, "--realizations", "1", "--out", o]);
    assert!(r.status.success(), "{}", text(&r));
    // --force replaces the journal of another run.
    write_journal(&out, &full[..3]);
    let r = run(&["run", st, "--realizations", "2", "--force", "--out", o]);
    assert!(r.status.success(), "{}", text(&r));
    assert_eq!(journal_lines(&out).len(), 9);
}

#[test]
fn one_writer_per_output_directory_and_the_lock_dies_with_its_holder() {
    let scratch = common::Scratch::created("resume-lock");
    let s = study();
    let s = s.to_str().unwrap();
    let out = scratch.join("out");
    let o = out.to_str().unwrap();
    let mut first = Command::new(BIN)
        .args(["run", s, "--realizations", "4", "--threads", "1", "--out", o])
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("drystone starts");
    let t0 = Instant::now();
    while !out.join("journal.jsonl").exists() {
        assert!(t0.elapsed() < Duration::from_secs(60), "no journal within 60 s");
        assert!(first.try_wait().unwrap().is_none(), "the run ended before the test could race it");
        std::thread::sleep(Duration::from_millis(5));
    }
    let holder = format!("{}: in use by another drystone process (pid {}: ", out.display(), first.id());
    let before = journal_lines(&out).len();
    for args in [
        vec!["run", s, "--realizations", "4", "--out", o],
        vec!["run", s, "--realizations", "4", "--resume", "--out", o],
        vec!["run", s, "--realizations", "2", "--force", "--out", o],
        vec!["merge", "--out", o, o],
    ] {
        let r = run(&args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", text(&r));
        assert!(text(&r).contains(&holder), "{args:?}: {}", text(&r));
    }
    assert!(journal_lines(&out).len() >= before, "the journal was not cut");
    first.kill().expect("SIGKILL");
    first.wait().unwrap();
    // The operating system released the lock with the process.
    let r = run(&["run", s, "--realizations", "4", "--threads", "2", "--resume", "--out", o]);
    assert!(r.status.success(), "{}", text(&r));
    assert_eq!(journal_rows(&out), ITEMS);
}
