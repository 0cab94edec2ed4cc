//! The compression study on a tiny wall (two courses of two blocks): it runs, resumes and
//! shards through the study core like any other protocol's (the merged shards and the
//! resumed run write the whole run's outputs bit for bit, the wall-clock column aside); its
//! keys are refused in another protocol's file and the in-plane test's in its own, each by
//! name.

use crate::common::{run_study_file, run_study_shard};
use drystone::ensemble::row::RealizationRow;
use drystone::ensemble::Shard;
use drystone::study::RunMode;
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

/// Two groups of one realization each on the tiny wall (0.5 and 0.25 MPa), two cycles.
fn study_text() -> String {
    "version = 1\nname = \"tiny\"\nseed = 7\nrealizations = 1\nprotocol = \"compression\"\n\n[compression]\n\
     sigma0_mpa = 0.5\ncycles = 2\n\n[[groups]]\nname = \"a\"\nwall = \"wall.toml\"\n\n[[groups]]\nname = \"b\"\n\
     wall = \"wall.toml\"\nsigma0_mpa = 0.25\n"
        .to_string()
}

/// A fresh folder with the tiny wall.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drystone-compression-study-{name}-{}", std::process::id()));
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

/// The text outputs of a run directory (but the journal and the manifest, which name the
/// run's own paths and times), `realizations.csv` without its wall-clock column and the
/// report without its run time.
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
                    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
                    let wall = header.iter().position(|h| *h == "wall_time_s").unwrap();
                    text.lines()
                        .map(|l| {
                            let mut f: Vec<&str> = l.split(',').collect();
                            f.remove(wall);
                            f.join(",") + "\n"
                        })
                        .collect()
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
        let (x, y) = (x.compression.as_deref().unwrap(), y.compression.as_deref().unwrap());
        let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(x.compression_modulus_mpa.to_bits(), y.compression_modulus_mpa.to_bits());
        assert_eq!(bits(&x.loading_secants_mpa), bits(&y.loading_secants_mpa));
        assert_eq!(bits(&x.residual_settlements_mm), bits(&y.residual_settlements_mm));
        assert_eq!(bits(&x.curve_shortening_mm), bits(&y.curve_shortening_mm));
        assert_eq!(x.strength_low_mpa.to_bits(), y.strength_low_mpa.to_bits(), "NaN kept");
    }
}

/// The whole run, a run killed after its first realization and resumed, and its two
/// shards merged write the same outputs; the summary holds the modulus's statistic and the
/// report its section.
#[test]
fn it_runs_resumes_and_shards_as_every_study() {
    let dir = folder("core");
    let study = write(&dir, "study.toml", &study_text());
    let whole = run_study_file(&study, &dir.join("whole")).unwrap();
    assert_eq!(whole.rows.len(), 2);
    for r in &whole.rows {
        let c = r.compression.as_deref().expect("the compression columns");
        assert!(r.status.is_ok() && c.compression_modulus_mpa > 0.0, "{r:?}");
        assert_eq!(c.loading_secants_mpa.len(), 2);
    }
    let summary = std::fs::read_to_string(dir.join("whole/summary.csv")).unwrap();
    assert!(summary.lines().next().unwrap().contains("vertical_modulus_mpa_mean"), "{summary}");
    let report = std::fs::read_to_string(dir.join("whole/report.md")).unwrap();
    assert!(report.contains("## The wall's vertical modulus"), "{report}");
    // Killed after one row: resumed, it runs the other.
    let journal = std::fs::read_to_string(dir.join("whole/journal.jsonl")).unwrap();
    let killed = dir.join("killed");
    std::fs::create_dir_all(&killed).unwrap();
    let kept: String = journal.lines().take(2).map(|l| format!("{l}\n")).collect();
    std::fs::write(killed.join("journal.jsonl"), kept).unwrap();
    let resumed = run_study_shard(&study, &killed, Shard::ALL, RunMode { resume: true, force: false }).unwrap();
    assert_eq!(resumed.resumed, 1);
    same_rows(&resumed.rows, &whole.rows);
    assert_eq!(outputs_of(&killed), outputs_of(&dir.join("whole")));
    // Shards 1/2 and 2/2, merged.
    let mut shards = Vec::new();
    for k in 0..2 {
        let d = dir.join(format!("shard{k}"));
        let r = run_study_shard(&study, &d, Shard { k, n: 2 }, RunMode::default()).unwrap();
        assert_eq!(r.rows.len(), 1);
        shards.push(d);
    }
    let merged = drystone::study::merge(&shards, &dir.join("merged")).unwrap();
    same_rows(&merged.rows, &whole.rows);
    assert_eq!(outputs_of(&dir.join("merged")), outputs_of(&dir.join("whole")));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `[compression]` in another protocol's file, the in-plane test's group keys and a method
/// that does not run the test in its own, and a key out of its range, each refused by name.
#[test]
fn foreign_and_bad_keys_are_refused_by_name() {
    let dir = folder("keys");
    let base = study_text();
    for (text, key) in [
        (base.replace("protocol = \"compression\"", "protocol = \"tilt\""), "compression"),
        (base.replace("sigma0_mpa = 0.25\n", "sigma0_mpa = 0.25\nhistory = \"cyclic\"\n"), "groups[b].history"),
        (base.replace("cycles = 2", "cycles = 0"), "compression.cycles"),
        (base.replace("sigma0_mpa = 0.25", "sigma0_mpa = -1.0"), "groups[b].sigma0_mpa"),
        (base.clone() + "\n[solver]\nkind = \"nscd\"\n", "solver.kind"),
    ] {
        let p = write(&dir, "bad.toml", &text);
        let e = drystone::study::Study::from_file(&p).unwrap_err().to_string();
        assert!(e.contains(key), "{key}: {e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
