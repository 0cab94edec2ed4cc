//! The run store (`--run-store`, `drystone::discrepancy::RunStore`): a run read from it is
//! the run made again, bit for bit, on the tilting table and on the in-plane test (whose
//! rig reading is read again under another vertical-load system); a run is read only under
//! everything it read (a key differs when any input differs by one bit, not when the wall
//! was read from another file); a run that would not read back exactly is not kept, and a
//! damaged record is a miss. The reference of each check is the engine run without a store.

use crate::common::Scratch;
use drystone::discrepancy::{run_models, Outcome, RunStore, Setup};
use drystone::effects::{Effect, Library};
use drystone::study::discrepancy::setup_of;
use drystone::study::Study;
use std::path::Path;
use std::sync::Arc;

const STUDY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/discrepancy/study.toml");

/// The test bed's free wall, two realizations.
fn tilt_setup() -> Setup {
    let st = Study::from_file(Path::new(STUDY)).unwrap();
    let mut s = setup_of(&st, 2);
    s.groups.truncate(1);
    s
}

fn effect(name: &str, v: f64, course_m: f64) -> Effect {
    Effect::new(Library::builtin().get(name).unwrap(), vec![v], course_m).unwrap()
}

/// Outcomes as text: `Debug` prints every float as the shortest text that reads back to its
/// bits, so equal texts are equal bits (NaN included).
fn text(o: &[Vec<Vec<Outcome>>]) -> String {
    format!("{o:?}")
}

fn with_store(setup: &Setup, dir: &Path) -> (Setup, Arc<RunStore>) {
    let store = Arc::new(RunStore::open(dir).unwrap());
    (Setup { store: Some(store.clone()), ..setup.clone() }, store)
}

#[test]
fn runs_read_from_the_store_are_the_runs_made_again_bit_for_bit() {
    let dir = Scratch::new("run-store-tilt");
    let plain = tilt_setup();
    let c = plain.groups[0].course_m;
    let models = vec![vec![], vec![effect("kn_scale", 0.5, c)], vec![effect("initial_lean", 0.5, c)]];
    let made = run_models(&plain, &models, None);
    // First command: every run made and kept.
    let (first, s1) = with_store(&plain, &dir);
    let kept = run_models(&first, &models, None);
    assert_eq!(text(&kept), text(&made));
    assert_eq!((s1.reads(), s1.writes()), (0, 6));
    // A second command on the same directory (another process's store): every run read.
    let (second, s2) = with_store(&plain, &dir);
    let read = run_models(&second, &models, None);
    assert_eq!(text(&read), text(&made));
    assert_eq!((s2.reads(), s2.writes()), (6, 0));
    // Another seed reads nothing and runs everything.
    let (other, s3) = with_store(&Setup { seed: plain.seed + 1, ..plain.clone() }, &dir);
    let _ = run_models(&other, &models[..1], None);
    assert_eq!((s3.reads(), s3.writes()), (0, 2));
}

/// The in-plane test's runs carry the rig reading they are read again from: a baseline read
/// from the store and read again under the bearing's friction gives what the run made
/// with the friction gives.
#[test]
fn an_in_plane_run_read_from_the_store_is_read_again_as_the_run_made() {
    let dir = Scratch::new("run-store-inplane");
    let plain = crate::readings_only::setup();
    let plain = Setup { groups: plain.groups[..1].to_vec(), ..plain };
    let c = plain.groups[0].course_m;
    let models = vec![vec![], vec![effect("rig_friction", 0.05, c)]];
    let made = run_models(&plain, &models, None);
    assert!(made[0][0][0].observed.rig_reading.is_some(), "the in-plane run keeps its rig reading");
    let (first, _) = with_store(&plain, &dir);
    let _ = run_models(&first, &models[..1], None);
    let (second, s2) = with_store(&plain, &dir);
    let read = run_models(&second, &models, None);
    assert_eq!(s2.reads(), 1);
    assert_eq!(text(&read), text(&made));
}

#[test]
fn a_run_is_read_only_under_everything_it_read() {
    let s = tilt_setup();
    let c = s.groups[0].course_m;
    let e = |v: f64| vec![effect("kn_scale", v, c)];
    let key = |s: &Setup, r: u64, m: &[Effect]| s.run_key(0, r, m);
    let k0 = key(&s, 0, &e(0.5));
    assert_eq!(k0.len(), 64);
    assert_eq!(k0, key(&s.clone(), 0, &e(0.5)));
    let up = |x: f64| f64::from_bits(x.to_bits() + 1);
    assert_ne!(k0, key(&s, 1, &e(0.5)), "realization");
    assert_ne!(k0, key(&s, 0, &e(up(0.5))), "an effect's parameter by one ulp");
    assert_ne!(k0, key(&s, 0, &[]), "the baseline");
    assert_ne!(k0, key(&Setup { seed: s.seed ^ 1, ..s.clone() }, 0, &e(0.5)), "seed");
    let mut g = s.clone();
    g.groups[0].wall.height = up(g.groups[0].wall.height);
    assert_ne!(k0, key(&g, 0, &e(0.5)), "the wall's height by one ulp");
    let mut g = s.clone();
    g.groups[0].course_m = up(c);
    assert_ne!(k0, key(&g, 0, &e(0.5)), "the course height by one ulp");
    let mut g = s.clone();
    g.groups[0].name.push('x');
    assert_ne!(k0, key(&g, 0, &e(0.5)), "the group's name");
    let mut g = s.clone();
    g.solver.damping = up(g.solver.damping);
    assert_ne!(k0, key(&g, 0, &e(0.5)), "the solver's damping by one ulp");
    let mut g = s.clone();
    g.groups[0].restrained = !g.groups[0].restrained;
    assert_ne!(k0, key(&g, 0, &e(0.5)), "the end restraints");
    // The same walls read from another file are the same runs.
    let mut g = s.clone();
    g.groups[0].wall.source = "elsewhere/copy.toml".into();
    assert_eq!(k0, key(&g, 0, &e(0.5)));
}

#[test]
fn a_run_that_would_not_read_back_exactly_is_not_kept_and_a_damaged_record_is_a_miss() {
    let dir = Scratch::new("run-store-exact");
    let store = RunStore::open(&*dir).unwrap();
    let key = "ab".repeat(32);
    let mut o = Outcome { observed: Default::default(), error: None };
    o.observed.collapse_deg = Some(17.125);
    o.observed.tilt_deg = vec![0.0, 1.0];
    o.observed.top_cm = vec![[0.0, -0.0, 1e-300], [0.1 + 0.2, f64::MIN_POSITIVE, 3.0]];
    assert!(store.put(&key, &o));
    assert_eq!(format!("{:?}", store.get(&key).unwrap()), format!("{o:?}"));
    // NaN and infinity do not survive JSON: not kept.
    let other = "cd".repeat(32);
    for bad in [f64::NAN, f64::INFINITY] {
        let mut n = o.clone();
        n.observed.top_cm[1][1] = bad;
        assert!(!store.put(&other, &n));
        assert!(store.get(&other).is_none());
    }
    // A record cut short reads as a miss.
    let path = dir.join(&key[..2]).join(format!("{key}.json"));
    let whole = std::fs::read(&path).unwrap();
    std::fs::write(&path, &whole[..whole.len() / 2]).unwrap();
    assert!(store.get(&key).is_none());
    assert_eq!(store.reads(), 1);
    // A directory that cannot be made is an error naming it.
    let file = dir.join("a_file");
    std::fs::write(&file, "x").unwrap();
    let err = RunStore::open(file.join("store")).unwrap_err().to_string();
    assert!(err.contains("a_file"), "{err}");
}

/// A stored outcome whose collapse angle tells it apart.
fn outcome_of(collapse_deg: f64) -> Outcome {
    let mut o = Outcome { observed: Default::default(), error: None };
    o.observed.collapse_deg = Some(collapse_deg);
    o
}

/// Each record is read only under the key stored in it: two records whose files were
/// swapped are both misses (their runs made again), and a record without its key (as
/// written before records carried it) is a miss.
#[test]
fn records_swapped_between_files_and_records_without_their_key_are_misses() {
    let dir = Scratch::new("run-store-swap");
    let store = RunStore::open(&*dir).unwrap();
    let (k1, k2) = ("ab".repeat(32), "cd".repeat(32));
    assert!(store.put(&k1, &outcome_of(11.0)));
    assert!(store.put(&k2, &outcome_of(22.0)));
    assert_eq!(store.get(&k1).unwrap().observed.collapse_deg, Some(11.0));
    assert_eq!(store.get(&k2).unwrap().observed.collapse_deg, Some(22.0));
    assert_eq!(store.reads(), 2);
    let file = |k: &str| dir.join(&k[..2]).join(format!("{k}.json"));
    let (t1, t2) = (std::fs::read(file(&k1)).unwrap(), std::fs::read(file(&k2)).unwrap());
    std::fs::write(file(&k1), &t2).unwrap();
    std::fs::write(file(&k2), &t1).unwrap();
    assert!(store.get(&k1).is_none(), "the record of {k2} read under {k1}");
    assert!(store.get(&k2).is_none(), "the record of {k1} read under {k2}");
    assert_eq!(store.reads(), 2);
    // The record of k1 without the key it carries: a miss.
    let mut old: serde_json::Value = serde_json::from_slice(&t1).unwrap();
    assert_eq!(old["key"], serde_json::Value::String(k1.clone()));
    old.as_object_mut().unwrap().remove("key");
    std::fs::write(file(&k1), serde_json::to_vec(&old).unwrap()).unwrap();
    assert!(store.get(&k1).is_none(), "a record without its key read");
    // Written again, it reads.
    assert!(store.put(&k1, &outcome_of(11.0)));
    assert_eq!(store.get(&k1).unwrap().observed.collapse_deg, Some(11.0));
}

/// A store whose directory cannot be written keeps nothing and says so, naming the
/// directory and the error, instead of a silent "0 kept".
#[test]
fn a_store_that_cannot_be_written_warns_naming_its_directory() {
    let dir = Scratch::new("run-store-unwritable");
    let store = RunStore::open(&*dir).unwrap();
    assert!(store.write_failures().is_none());
    assert!(!store.summary().contains("warning"), "{}", store.summary());
    // The directory replaced by a file (a permission check would not hold for root).
    std::fs::remove_dir_all(&*dir).unwrap();
    std::fs::write(&*dir, "not a directory").unwrap();
    for k in ["ab", "cd"] {
        assert!(!store.put(&k.repeat(32), &outcome_of(1.0)));
    }
    let (n, error) = store.write_failures().expect("the failed writes counted");
    assert_eq!(n, 2);
    assert!(error.contains(&*dir.to_string_lossy()), "{error}");
    let summary = store.summary();
    assert_eq!(store.writes(), 0);
    assert!(
        summary.contains(&format!("warning: run store {}: nothing could be kept, 2 run(s) not written", dir.display())),
        "{summary}"
    );
    std::fs::remove_file(&*dir).unwrap();
}

/// The run store is on by default, beside the output directory (`NAME-runs`): a second
/// cold `drystone discrepancy` of the same study into another output directory reads every
/// run the first made and writes the same report, byte for byte; `--no-run-store` makes
/// every run and keeps none, and writes the same report again. The reference is the first
/// command, which made every run itself.
#[test]
fn the_default_run_store_lets_cold_commands_on_one_study_read_each_others_runs() {
    let dir = Scratch::created("run-store-default");
    let text = std::fs::read_to_string(STUDY).unwrap();
    let walls = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/discrepancy/walls");
    let mut rows = String::from("specimen,group,collapse_angle_deg\n");
    for (i, (free, held)) in [(26.0, 33.5), (25.5, 34.0), (26.5, 33.0)].into_iter().enumerate() {
        rows += &format!("F{i},FREE,{free}\nH{i},HELD,{held}\n");
    }
    std::fs::write(dir.join("collapse.csv"), rows).unwrap();
    let study = text.replace("walls/", &format!("{}/", walls.display())).replacen(
        "[discrepancy]\n",
        "[discrepancy]\neffects = [\"kn_scale\"]\n",
        1,
    ) + "\n[measured]\ncollapse = \"collapse.csv\"\n";
    std::fs::write(dir.join("s.toml"), study).unwrap();
    let run = |out: &str, extra: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
            .args(["discrepancy", "s.toml", "--out", out, "--threads", "2", "--realizations", "1", "--no-confirm"])
            .args(extra)
            .current_dir(&*dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned() + &String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{err}");
        (err, std::fs::read_to_string(dir.join(out).join("discrepancy.md")).unwrap())
    };
    let store_line = |log: &str| log.lines().find(|l| l.starts_with("run store ")).map(str::to_owned);
    let (first, report) = run("out/first", &[]);
    let line = store_line(&first).expect("a store line");
    assert!(
        line.starts_with("run store out/small_walls-runs: 0 run(s) read, ") && !line.ends_with(" 0 kept"),
        "{line}"
    );
    let kept: usize = line.rsplit(", ").next().unwrap().trim_end_matches(" kept").parse().unwrap();
    assert!(dir.join("out/small_walls-runs").is_dir());
    let (second, again) = run("out/second", &[]);
    assert_eq!(store_line(&second).unwrap(), format!("run store out/small_walls-runs: {kept} run(s) read, 0 kept"));
    assert_eq!(again, report);
    let (none, made) = run("out/third", &["--no-run-store"]);
    assert_eq!(store_line(&none), None, "{none}");
    assert_eq!(made, report);
}
