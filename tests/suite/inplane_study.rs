//! The in-plane study on a tiny wall (two courses, a few blocks, a short monotonic history):
//! its `[solver]` table chooses the method as in every study, the groups' own keys are
//! refused in `[in_plane]`.

use crate::common::{in_plane, run_study_file, run_study_shard};
use drystone::dem::{SolverKind, SolverParams};
use drystone::ensemble::row::RealizationRow;
use drystone::loading::inplane::{History, InPlaneParams};
use std::path::{Path, PathBuf};

const WALL: &str = r#"version = 1
name = "tiny granite wall"
kind = "sawn_stone"
[geometry]
length_m = 0.4
height_m = 0.3
base_width_m = 0.2
top_width_m = 0.2
batter = "symmetric"
[arrangement]
kind = "discontinuous"
overlap = 0.5
[courses]
height_m = 0.15
[blocks]
length_m = 0.2
material = "granite"
[[materials]]
name = "granite"
density_kg_per_m3 = 2600.0
kn_pa_per_m = 2.0e10
ks_pa_per_m = 1.0e9
friction_deg = 32.2
cohesion_pa = 0.0
tensile_strength_pa = 0.0
[restraints]
base = "free"
ends = { kind = "free" }
"#;

/// Two groups (3 and 2 realizations) on the tiny wall; `extra` goes before `[in_plane]`,
/// `in_plane` into it.
fn study_text(extra: &str, in_plane: &str) -> String {
    format!(
        "version = 1\nname = \"tiny\"\nseed = 7\nrealizations = 3\nprotocol = \"in_plane\"\n{extra}\n[in_plane]\n\
         shear_span_m = 0.35\ndrift_pct = 0.4\n{in_plane}\n[[groups]]\nname = \"a\"\nwall = \"wall.toml\"\n\
         sigma0_mpa = 0.5\n\n[[groups]]\nname = \"b\"\nwall = \"wall.toml\"\nsigma0_mpa = 0.25\nrealizations = 2\n"
    )
}

/// A fresh folder with the tiny wall.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drystone-inplane-study-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("wall.toml"), WALL).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `[solver] kind = "nscd"` runs every realization by non-smooth contact dynamics: the row
/// is the one a direct nscd run of the same realization gives, bit for bit, and not the
/// penalty DEM's; limit analysis, which draws no curve, is refused at `solver.kind`.
#[test]
fn the_solver_table_chooses_the_method() {
    let dir = folder("solver");
    let nscd = write(&dir, "nscd.toml", &study_text("[solver]\nkind = \"nscd\"\n", ""));
    let penalty = write(&dir, "penalty.toml", &study_text("", ""));
    let spec = drystone::study::Study::from_file(&nscd).unwrap();
    assert_eq!(spec.solver.kind, SolverKind::Nscd);
    let by_nscd = run_study_file(&nscd, &dir.join("n")).unwrap();
    let by_penalty = run_study_file(&penalty, &dir.join("p")).unwrap();
    assert_eq!(by_nscd.rows.len(), 5);
    let wall = drystone::generator::Wall::from_file(&dir.join("wall.toml")).unwrap();
    for (g, sigma0_mpa, i) in [(0usize, 0.5, 0u64), (1, 0.25, 1)] {
        // The seed index of realization i of group g; group a has 3 realizations.
        let index = g as u64 * 10_000 + i;
        let row = &by_nscd.rows[[0, 3][g] + i as usize];
        assert_eq!((row.group.as_str(), row.realization), (["a", "b"][g], i));
        let (_, layout) = drystone::effects::realize(&wall, 7, index, &row.group, &[]).unwrap();
        let params = InPlaneParams {
            sigma0_mpa,
            history: History::Monotonic,
            shear_span_m: Some(0.35),
            drift_pct: 0.4,
            ..InPlaneParams::default()
        };
        let solver = SolverParams { kind: SolverKind::Nscd, ..SolverParams::default() };
        let run = drystone::protocol::run(&drystone::protocol::InPlane(params), &layout, solver, &mut ()).unwrap();
        let drystone::protocol::InPlaneRun::Nscd(Ok(direct)) = run else { panic!("{run:?}") };
        let d = direct.positive.unwrap();
        assert!(row.status.is_ok(), "{row:?}");
        let c = in_plane(row);
        assert_eq!(c.peak_pos_kn.to_bits(), d.peak_force_kn.to_bits());
        assert_eq!(c.stiffness_pos_kn_per_mm.to_bits(), d.initial_stiffness_kn_per_mm.to_bits());
        assert_eq!(c.in_plane_mechanism, direct.mechanism.kind.name());
        let p = &by_penalty.rows[row.index as usize];
        assert_ne!(in_plane(p).peak_pos_kn.to_bits(), c.peak_pos_kn.to_bits(), "the penalty DEM's row differs");
    }
    let report = std::fs::read_to_string(dir.join("n/report.md")).unwrap();
    assert!(report.contains("non-smooth contact dynamics"), "{report}");
    // A method that gives no curve, and a kind that is not one, refused by key.
    let limit = write(&dir, "limit.toml", &study_text("[solver]\nkind = \"limit\"\n", ""));
    let e = drystone::study::Study::from_file(&limit).unwrap_err().to_string();
    assert!(e.contains("solver.kind") && e.contains("limit"), "{e}");
    let bad = write(&dir, "bad.toml", &study_text("[solver]\nkind = \"rigid\"\n", ""));
    let e = drystone::study::Study::from_file(&bad).unwrap_err().to_string();
    assert!(e.contains("rigid") && e.contains("kind"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The groups' own keys given in `[in_plane]` (every group would overwrite them) are
/// refused, naming the key.
#[test]
fn the_groups_keys_are_refused_in_the_shared_table() {
    let dir = folder("keys");
    for key in ["sigma0_mpa = 0.5", "history = \"cyclic\""] {
        let p = write(&dir, "study.toml", &study_text("", key));
        let e = drystone::study::Study::from_file(&p).unwrap_err().to_string();
        let name = key.split(' ').next().unwrap();
        assert!(e.contains(&format!("in_plane.{name}")), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The outputs of a run folder that must be the same bit for bit: every file but the
/// journal and the manifest (which hold the run's own history) and `realizations.parquet`
/// (which holds the wall-clock column), the rows of `realizations.csv` without their
/// wall-clock column, the report without its run time.
fn outputs_of(dir: &Path) -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != "realizations.parquet"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read_to_string(&p).unwrap()))
        .filter(|(name, _)| name != "journal.jsonl" && name != "manifest.json")
        .map(|(name, text)| {
            let text = match name.as_str() {
                "realizations.csv" => {
                    text.lines().map(|l| l.rsplitn(3, ',').nth(2).unwrap_or_default().to_string() + "\n").collect()
                }
                "report.md" => text.lines().filter(|l| !l.contains("s of run time")).collect::<Vec<_>>().join("\n"),
                _ => text,
            };
            (name, text)
        })
        .collect();
    v.sort();
    v
}

fn same_rows(a: &[RealizationRow], b: &[RealizationRow]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert_eq!((x.index, &x.group, x.realization, x.status), (y.index, &y.group, y.realization, y.status));
        let (x, y) = (in_plane(x), in_plane(y));
        assert_eq!(x.peak_pos_kn.to_bits(), y.peak_pos_kn.to_bits());
        assert_eq!(x.limit_peak_kn.to_bits(), y.limit_peak_kn.to_bits());
        assert_eq!(x.damping_ratio.to_bits(), y.damping_ratio.to_bits(), "NaN kept");
        let bits = |c: &[(f64, f64)]| c.iter().map(|(d, f)| (d.to_bits(), f.to_bits())).collect::<Vec<_>>();
        assert_eq!(bits(&x.curve()), bits(&y.curve()));
        assert_eq!(x.curve().len(), x.curve_drift_pct.len());
    }
}

/// A run killed after two of its five realizations (its journal holds those two rows, as a
/// kill leaves it) continues with `resume`: it runs the three missing ones and writes the
/// outputs of the uninterrupted run, bit for bit; without `resume` the unfinished journal is
/// refused, and a journal of another run (another seed) is refused naming the seed.
#[test]
fn a_killed_run_resumes_to_the_uninterrupted_outputs() {
    use drystone::ensemble::Shard;
    use drystone::study::RunMode;
    let dir = folder("resume");
    let study = write(&dir, "study.toml", &study_text("", ""));
    let whole = run_study_file(&study, &dir.join("whole")).unwrap();
    assert_eq!(whole.rows.len(), 5);
    let manifest = std::fs::read_to_string(dir.join("whole/manifest.json")).unwrap();
    assert!(manifest.contains("\"shard\": \"1/1\"") && manifest.contains("wall.toml"), "{manifest}");
    let journal = std::fs::read_to_string(dir.join("whole/journal.jsonl")).unwrap();
    let killed = dir.join("killed");
    std::fs::create_dir_all(&killed).unwrap();
    let kept: String = journal.lines().take(3).map(|l| format!("{l}\n")).collect();
    std::fs::write(killed.join("journal.jsonl"), kept).unwrap();
    let e = run_study_file(&study, &killed).unwrap_err();
    assert!(e.contains("2 of 5") && e.contains("resume"), "{e}");
    let resume = RunMode { resume: true, force: false };
    let resumed = run_study_shard(&study, &killed, Shard::ALL, resume).unwrap();
    assert_eq!(resumed.resumed, 2);
    same_rows(&resumed.rows, &whole.rows);
    assert_eq!(outputs_of(&killed), outputs_of(&dir.join("whole")));
    let other = write(&dir, "other.toml", &study_text("", "").replace("seed = 7", "seed = 8"));
    let e = run_study_shard(&other, &killed, Shard::ALL, resume).unwrap_err();
    assert!(e.contains("seed") && e.contains('7') && e.contains('8'), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two shards of the study, merged by the study core (`drystone merge`), write the outputs
/// of the whole run bit for bit (`realizations.csv` among them); a shard given twice, the
/// other missing, is refused naming it.
#[test]
fn two_shards_merged_equal_the_whole() {
    use drystone::ensemble::Shard;
    use drystone::study::RunMode;
    let dir = folder("shards");
    // With a measured specimen (the database's table, its envelope and its curve, copied
    // beside the study): the merge rebuilds the study from the inputs its manifest stores.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/inplane_granite");
    for f in ["walls.csv", "envelopes/envelope_WS100_Vasconcelos2005.csv", "curves/FD_WS100_Vasconcelos2005.csv"] {
        std::fs::create_dir_all(dir.join("data").join(f).parent().unwrap()).unwrap();
        std::fs::copy(data.join(f), dir.join("data").join(f)).unwrap();
    }
    let text = study_text("", "").replace("sigma0_mpa = 0.5\n", "sigma0_mpa = 0.5\nspecimens = [\"WS.100\"]\n")
        + "[measured]\nwalls = \"data/walls.csv\"\nenvelopes = \"data/envelopes\"\ncurves = \"data/curves\"\n";
    let study = write(&dir, "study.toml", &text);
    let whole = run_study_file(&study, &dir.join("whole")).unwrap();
    let manifest = std::fs::read_to_string(dir.join("whole/manifest.json")).unwrap();
    assert!(manifest.contains("envelope_WS100_Vasconcelos2005.csv") && manifest.contains("FD_WS100"), "{manifest}");
    let mut shards = Vec::new();
    for k in 0..2 {
        let d = dir.join(format!("shard{k}"));
        let r = run_study_shard(&study, &d, Shard { k, n: 2 }, RunMode::default()).unwrap();
        assert_eq!(r.rows.len(), [3, 2][k]);
        assert!(!d.join("report.md").exists(), "a shard writes its rows alone");
        shards.push(d);
    }
    let merged = drystone::study::merge(&shards, &dir.join("merged")).unwrap();
    same_rows(&merged.rows, &whole.rows);
    assert_eq!(outputs_of(&dir.join("merged")), outputs_of(&dir.join("whole")));
    let csv = |d: &str, f: &str| std::fs::read_to_string(dir.join(d).join(f)).unwrap();
    assert_eq!(csv("merged", "realizations.csv").lines().count(), 6, "{}", csv("merged", "realizations.csv"));
    // The measured peak of WS.100 (the table's Vmax_pos_kN) and its envelope drawn.
    let comparison = csv("merged", "comparison.csv");
    assert!(comparison.contains("WS.100,peak_pos_kn,37,"), "{comparison}");
    assert!(csv("merged", "curves_a.svg").contains("WS.100 envelope (measured)"));
    let twice = [shards[0].clone(), shards[0].clone()];
    let e = drystone::study::merge(&twice, &dir.join("twice")).unwrap_err().to_string();
    assert!(e.contains("shard 2/2 missing"), "{e}");
    // The merged study written over one of its shards (it replaced that shard's manifest,
    // and the next merge failed): refused naming it, the shard untouched.
    let before = std::fs::read(shards[0].join("manifest.json")).unwrap();
    let e = drystone::study::merge(&shards, &shards[0]).unwrap_err().to_string();
    assert!(e.contains("is one of the shards to merge"), "{e}");
    assert_eq!(std::fs::read(shards[0].join("manifest.json")).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A parameter that only the wall's dimensions refuse (a shear span below the wall's top)
/// is a row of status `refused` with the refusal in its error column, not a blow-up; the
/// study goes on and writes every row.
#[test]
fn a_parameter_the_wall_refuses_is_a_refused_row_not_a_blow_up() {
    let dir = folder("refused");
    let text = study_text("", "").replace("shear_span_m = 0.35\n", "shear_span_m = 0.1\n");
    let p = write(&dir, "low.toml", &text);
    let run = run_study_file(&p, &dir.join("r")).unwrap();
    assert_eq!(run.rows.len(), 5);
    for r in &run.rows {
        assert_eq!(r.status, drystone::ensemble::row::Status::Refused, "{r:?}");
        assert!(r.error.contains("in_plane.shear_span_m = 0.1 m is below the wall's height"), "{}", r.error);
    }
    let table = std::fs::read_to_string(dir.join("r/realizations.csv")).unwrap();
    assert_eq!(table.matches(",refused,").count(), 5, "{table}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A study whose beam is held level (`beam_rotation = "fixed"`, double curvature) has no
/// shear span: its report says so rather than printing one.
#[test]
fn a_study_with_the_beam_held_level_reports_no_shear_span() {
    let dir = folder("fixed");
    let text = study_text("", "").replace("shear_span_m = 0.35\n", "beam_rotation = \"fixed\"\n");
    let p = write(&dir, "fixed.toml", &text);
    let run = run_study_file(&p, &dir.join("f")).unwrap();
    assert!(run.rows.iter().all(|r| r.status.is_ok()), "{:?}", run.rows);
    let report = std::fs::read_to_string(dir.join("f/report.md")).unwrap();
    assert!(report.contains("Beam held level: no shear span"), "{report}");
    assert!(!report.contains("Shear span"), "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The study core reads the in-plane study: `drystone run --realizations N` sets the count
/// of every group that does not fix its own, each row the one the whole study writes for
/// that realization (the wall-clock column aside); the test's keys are refused in another
/// protocol's file and the keys the test does not read in its own, each by name.
#[test]
fn the_study_core_reads_it_with_realizations_and_refuses_foreign_keys() {
    let dir = folder("core");
    let study = write(&dir, "study.toml", &study_text("", ""));
    let whole = run_study_file(&study, &dir.join("whole")).unwrap();
    let out = dir.join("one");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["run", study.to_str().unwrap(), "--realizations", "1", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Group a takes the command line's 1, group b keeps its own 2.
    let csv = std::fs::read_to_string(out.join("realizations.csv")).unwrap();
    let cells = |line: &str| line.rsplitn(3, ',').nth(2).unwrap_or_default().to_string();
    let rows: Vec<String> = csv.lines().skip(1).map(cells).collect();
    assert_eq!(rows.len(), 3, "{csv}");
    let all = std::fs::read_to_string(dir.join("whole/realizations.csv")).unwrap();
    for r in &rows {
        assert!(all.lines().any(|l| cells(l) == *r), "{r} is not a row of the whole study");
    }
    assert_eq!(whole.rows.len(), 5);
    let manifest = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    assert!(manifest.contains("\"realizations\": 1"), "{manifest}");
    // Another protocol's file with the test's keys, the test's file with a sweep.
    let tilt = study_text("", "").replace("protocol = \"in_plane\"", "protocol = \"tilt\"").replace("[in_plane]\n", "");
    let tilt = tilt.replace("shear_span_m = 0.35\ndrift_pct = 0.4\n", "");
    let p = write(&dir, "tilt.toml", &tilt);
    let e = drystone::study::Study::from_file(&p).unwrap_err().to_string();
    assert!(e.contains("groups[a].sigma0_mpa") && e.contains("in_plane"), "{e}");
    let p = write(&dir, "sweep.toml", &study_text("[sweep]\nfriction_deg = [30, 40]\n", ""));
    let e = drystone::study::Study::from_file(&p).unwrap_err().to_string();
    assert!(e.contains("sweep.friction_deg") && e.contains("does not read"), "{e}");
    let p = write(&dir, "missing.toml", &study_text("", "").replace("sigma0_mpa = 0.25\n", ""));
    let e = drystone::study::Study::from_file(&p).unwrap_err().to_string();
    assert!(e.contains("groups[b].sigma0_mpa") && e.contains("missing"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The discrepancy input of the bundled study, read through the study core: one group per
/// vertical stress (four), each pushed monotonically at its stress, and every specimen's
/// peak force the measured table's `Vmax_pos_kN` (read here from the CSV by hand).
#[test]
fn the_discrepancy_input_reads_the_groups_and_the_measured_peaks() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let study = drystone::study::Study::from_file(&root.join("studies/inplane_granite.toml")).unwrap();
    let input = (study.protocol.analysis().input)(&study, study.discrepancy.clone()).unwrap();
    let names: Vec<&str> = input.setup.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["0.2 MPa", "0.5 MPa", "0.875 MPa", "1.25 MPa"]);
    for g in &input.setup.groups {
        let Some(drystone::protocol::Protocol::InPlane(drystone::protocol::InPlane(p))) = &g.protocol else {
            panic!("{:?}", g.protocol)
        };
        assert_eq!((format!("{} MPa", p.sigma0_mpa), p.history), (g.name.clone(), History::Monotonic));
    }
    let table = std::fs::read_to_string(root.join("data/inplane_granite/walls.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|h| *h == "Vmax_pos_kN").unwrap();
    let mut peaks = 0;
    for o in input.obs.iter().filter(|o| {
        o.observable
            == drystone::discrepancy::Observable::InPlane {
                quantity: drystone::discrepancy::InPlaneQuantity::PeakForce,
            }
    }) {
        // The unit's row: its cells before any quoted one (the peak is before them).
        let row = table.lines().find(|l| l.split(',').next() == Some(o.specimen.as_str())).unwrap();
        let value: f64 = row.split(',').nth(column).unwrap().parse().unwrap();
        assert_eq!(o.value, value, "{}", o.specimen);
        peaks += 1;
    }
    assert_eq!(peaks, 14);
}

/// A shear span a thousand times too large (`shear_span_m = 1e9` in the bundled study, a
/// probable unit mistake) is refused when the study is read, naming the key, the file and
/// the wall, before any realization runs; the same file at the bundled 1.325 m reads.
#[test]
fn a_shear_span_far_above_the_wall_is_refused_before_any_run() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bundled = std::fs::read_to_string(root.join("studies/inplane_granite.toml")).unwrap();
    assert!(bundled.contains("\nshear_span_m = 1.325\n"), "the bundled study's shear span moved");
    let studies = root.join("studies");
    let here = bundled
        .replace("wall = \"walls/", &format!("wall = \"{}/walls/", studies.display()))
        .replace("\"../data/", &format!("\"{}/data/", root.display()));
    let dir = folder("shear-span");
    let good = write(&dir, "good.toml", &here);
    assert!(drystone::study::Study::from_file(&good).is_ok());
    let bad = write(&dir, "span.toml", &here.replace("\nshear_span_m = 1.325\n", "\nshear_span_m = 1e9\n"));
    let e = drystone::study::Study::from_file(&bad).unwrap_err().to_string();
    assert!(e.contains("span.toml") && e.contains("in_plane.shear_span_m") && e.contains("10 times"), "{e}");
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    for part in ["span.toml", "in_plane.shear_span_m", "1000000000 m", "granite_vasconcelos.toml", "millimetres"] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    let made: Vec<_> = std::fs::read_dir(&out).map(|d| d.flatten().map(|e| e.path()).collect()).unwrap_or_default();
    assert!(made.is_empty(), "the run wrote {made:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The bundled study with its paths made absolute, written in `dir` under `name` with
/// `edit` applied to its text.
fn bundled_study(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bundled = std::fs::read_to_string(root.join("studies/inplane_granite.toml")).unwrap();
    let here = bundled
        .replace("wall = \"walls/", &format!("wall = \"{}/walls/", root.join("studies").display()))
        .replace("\"../data/", &format!("\"{}/data/", root.display()));
    write(dir, name, &edit(here))
}

/// A group compared with a specimen tested at another vertical stress (WS.100, 0.5 MPa in
/// the table's `sigma0_applied_MPa`, named by the 0.875 MPa group) is refused naming the
/// group, the specimen and both stresses; it ran before, its report setting the walls at
/// one stress beside the specimen's readings at another. So is a monotonic specimen named
/// by a cyclic group of its own stress (WS.100 by the 0.5 MPa cyclic group). An envelopes
/// folder that does not
/// exist is refused naming `measured.envelopes` (before, every envelope reading of the
/// comparison came out empty without a word).
#[test]
fn a_specimen_of_another_stress_or_history_or_a_missing_envelopes_folder_is_refused() {
    let dir = folder("specimen-stress");
    let good = bundled_study(&dir, "good.toml", |t| t);
    assert!(drystone::study::Study::from_file(&good).is_ok());
    let swapped =
        bundled_study(&dir, "swapped.toml", |t| t.replacen("specimens = [\"WS.175\"]", "specimens = [\"WS.100\"]", 1));
    let e = drystone::study::Study::from_file(&swapped).unwrap_err().to_string();
    for part in ["swapped.toml", "groups[0.875 MPa monotonic].specimens", "WS.100 was tested at 0.5 MPa", "0.875 MPa"] {
        assert!(e.contains(part), "{part:?} not in {e}");
    }
    // A monotonic specimen in a cyclic group of its own stress: another history.
    let history = bundled_study(&dir, "history.toml", |t| {
        t.replacen("specimens = [\"WS1.100\", \"WS2.100\", \"WS3.100\", \"WS4.100\"]", "specimens = [\"WS.100\"]", 1)
    });
    let e = drystone::study::Study::from_file(&history).unwrap_err().to_string();
    for part in ["history.toml", "groups[0.5 MPa cyclic].specimens", "WS.100 was tested monotonic", "cyclic"] {
        assert!(e.contains(part), "{part:?} not in {e}");
    }
    let no_env =
        bundled_study(&dir, "no_env.toml", |t| t.replace("inplane_granite/envelopes\"", "inplane_granite/envelope\""));
    let e = drystone::study::Study::from_file(&no_env).unwrap_err().to_string();
    assert!(e.contains("no_env.toml") && e.contains("measured.envelopes") && e.contains("not a folder"), "{e}");
    // A crack maps folder that is not there (it ran, the report linking no crack map).
    let no_maps =
        bundled_study(&dir, "no_maps.toml", |t| t.replace("inplane_granite/crackmaps\"", "inplane_granite/crackmap\""));
    let e = drystone::study::Study::from_file(&no_maps).unwrap_err().to_string();
    assert!(e.contains("no_maps.toml") && e.contains("measured.crackmaps") && e.contains("not a folder"), "{e}");
    // Specimens named with no measured table at all: said so, not "not a unit of the
    // measured file".
    let no_measured = bundled_study(&dir, "no_measured.toml", |t| t[..t.find("[measured]").unwrap()].to_string());
    let e = drystone::study::Study::from_file(&no_measured).unwrap_err().to_string();
    assert!(e.contains("specimens") && e.contains("gives no measured file") && e.contains("[measured] walls"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A drift past the penalty DEM's reach (8.8 % at the default face-angle tolerance,
/// `loading::inplane::max_drift_pct`) is refused when the study is read, at
/// `in_plane.drift_pct`, not in every realization's row; nscd, which has no such reach,
/// reads the same file.
#[test]
fn a_drift_past_the_penalty_dems_reach_is_refused_on_read() {
    let dir = folder("reach");
    let text = study_text("", "").replace("drift_pct = 0.4\n", "drift_pct = 9\n");
    let p = write(&dir, "far.toml", &text);
    let e = drystone::study::Study::from_file(&p).unwrap_err().to_string();
    assert!(e.contains("in_plane.drift_pct") && e.contains("8.8"), "{e}");
    let nscd = write(&dir, "far_nscd.toml", &text.replace("\n[in_plane]", "[solver]\nkind = \"nscd\"\n\n[in_plane]"));
    drystone::study::Study::from_file(&nscd).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

/// `realizations.csv` carries the envelope's force at each reading drift of the JSON
/// (0.25, 0.5, 1 and 2 %), the same numbers as the run's own readings.
#[test]
fn the_rows_carry_the_force_at_every_reading_drift() {
    let dir = folder("readings");
    let text = study_text("", "").replace("drift_pct = 0.4\n", "drift_pct = 0.6\n");
    let p = write(&dir, "r.toml", &text);
    let run = run_study_file(&p, &dir.join("r")).unwrap();
    let table = std::fs::read_to_string(dir.join("r/realizations.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("{name}: {header:?}"));
    let (c25, c50) = (col("force_at_0_25_pos_kn"), col("force_at_0_5_pos_kn"));
    let first: Vec<&str> = table.lines().nth(1).unwrap().split(',').collect();
    let row = run.rows[0].in_plane.as_ref().unwrap();
    assert_eq!(first[c25].parse::<f64>().unwrap(), row.force_at_0_25_pos_kn);
    assert_eq!(first[c50].parse::<f64>().unwrap(), row.force_at_0_5_pos_kn);
    assert!(row.force_at_0_25_pos_kn > 0.0 && row.force_at_0_25_pos_kn <= row.peak_pos_kn, "{row:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
