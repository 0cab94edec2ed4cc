//! Provenance of a run: the manifest records the drystone version, the master seed and the
//! SHA-256 of every input file; `drystone merge` refuses shards that disagree on any of
//! them, naming the field and both values, and needs neither the study file nor its walls
//! where they were; `--resume` refuses a journal of another run; the report prints the seed
//! of its rows.

use drystone::study::sha256_hex;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;

const BIN: &str = env!("CARGO_BIN_EXE_drystone");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A self-contained copy of a small study in `dir`: the study file, its wall and its
/// measured data. Returns the study path.
fn copy_study(dir: &Path, seed: u64, description: &str) -> PathBuf {
    for (from, to) in
        [("studies/walls/cbl.toml", "walls/cbl.toml"), ("data/paper/tilting_table_collapse.csv", "data/collapse.csv")]
    {
        let to = dir.join(to);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(root().join(from), &to).unwrap();
    }
    let study = format!(
        "version = 1\nname = \"prov\"\ndescription = \"{description}\"\nseed = {seed}\nrealizations = 2\n\
         [tilt]\nstep_deg = 2.0\nresolution_deg = 0.5\n\
         [[groups]]\nname = \"CBL\"\nwall = \"walls/cbl.toml\"\noverrides = {{ length_m = 0.4 }}\n\
         [sweep]\nkn_pa_per_m = [1.75e8, 3.5e8]\n\
         [measured]\ncollapse = \"data/collapse.csv\"\n"
    );
    let p = dir.join("study.toml");
    std::fs::write(&p, study).unwrap();
    p
}

fn drystone(args: &[&dyn AsRef<std::ffi::OsStr>], cwd: &Path) -> Output {
    Command::new(BIN).args(args).current_dir(cwd).output().expect("drystone runs")
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", text(&o));
    o
}

fn shard(study: &Path, k: &str, out: &Path) -> Output {
    ok(drystone(&[&"run", &study, &"--shard", &k, &"--out", &out], study.parent().unwrap()))
}

fn manifest(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap()
}

#[test]
fn the_manifest_records_version_seed_and_input_hashes() {
    let s = common::Scratch::created("prov-manifest");
    let study = copy_study(&s, 7, "a");
    let out = s.join("out");
    ok(drystone(&[&"run", &study, &"--out", &out], &s));
    let m = manifest(&out);
    assert_eq!(m["drystone_version"], env!("CARGO_PKG_VERSION"));
    // The exact build: the version and a digest of the sources, also in the journal.
    let build = m["build"].as_str().unwrap();
    assert_eq!(build, drystone::study::BUILD);
    let digest = build.strip_prefix(&format!("{}+src.", env!("CARGO_PKG_VERSION"))).unwrap();
    assert!(digest.len() == 16 && digest.bytes().all(|b| b.is_ascii_hexdigit()), "{build}");
    let journal = std::fs::read_to_string(out.join("journal.jsonl")).unwrap();
    assert!(journal.lines().next().unwrap().contains(&format!("\"build\":\"{build}\"")), "{journal}");
    let v = drystone(&[&"--version"], &s);
    assert_eq!(String::from_utf8_lossy(&v.stdout).trim(), format!("drystone {build}"));
    assert_eq!(m["seed"], 7);
    let inputs = m["inputs"].as_array().unwrap();
    let find = |path: &str| inputs.iter().find(|f| f["path"] == path).unwrap_or_else(|| panic!("{path} in {inputs:?}"));
    for (path, role) in [("study.toml", "study"), ("walls/cbl.toml", "wall"), ("data/collapse.csv", "measured")] {
        let f = find(path);
        assert_eq!(f["role"], role);
        assert_eq!(f["sha256"], sha256_hex(&std::fs::read(s.join(path)).unwrap()), "{path}");
    }
    // A shipped study records its named distribution files too.
    let st = drystone::study::Study::from_file(&root().join("studies/tilting_table.toml")).unwrap();
    let dists: Vec<&str> = st
        .inputs
        .iter()
        .filter(|f| f.role == drystone::study::InputRole::Distribution)
        .map(|f| f.path.as_str())
        .collect();
    assert!(dists.contains(&"distributions/course_height_sbl.toml"), "{dists:?}");
    // The report prints the seed that produced its rows.
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("Master seed 7;"), "{report}");
}

#[test]
fn merge_refuses_shards_of_different_seeds_or_edited_inputs_naming_the_difference() {
    let s = common::Scratch::created("prov-refuse");
    let study = copy_study(&s, 7, "a");
    let (a, b) = (s.join("a"), s.join("b"));
    shard(&study, "1/2", &a);
    // Another seed.
    copy_study(&s, 8, "a");
    shard(&study, "2/2", &b);
    let o = drystone(&[&"merge", &"--out", &s.join("m1"), &a, &b], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let msg = text(&o);
    assert!(msg.contains("seed: 7 in") && msg.contains(", 8 in"), "{msg}");
    // The same seed, an edited study file.
    copy_study(&s, 7, "edited");
    let c = s.join("c");
    shard(&study, "2/2", &c);
    let o = drystone(&[&"merge", &"--out", &s.join("m2"), &a, &c], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let msg = text(&o);
    let (old, new) = (manifest(&a)["inputs"][0]["sha256"].clone(), manifest(&c)["inputs"][0]["sha256"].clone());
    assert_ne!(old, new);
    assert!(msg.contains("the study file study.toml differs: sha256"), "{msg}");
    assert!(msg.contains(old.as_str().unwrap()) && msg.contains(new.as_str().unwrap()), "{msg}");
    // An edited wall file.
    copy_study(&s, 7, "a");
    let wall = s.join("walls/cbl.toml");
    let edited = std::fs::read_to_string(&wall).unwrap().replace("friction_deg = 32.0", "friction_deg = 33.0");
    std::fs::write(&wall, edited).unwrap();
    let d = s.join("d");
    shard(&study, "2/2", &d);
    let o = drystone(&[&"merge", &"--out", &s.join("m3"), &a, &d], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("the wall file walls/cbl.toml differs: sha256"), "{}", text(&o));
}

#[test]
fn merge_needs_neither_the_study_file_nor_its_walls() {
    let s = common::Scratch::created("prov-moved");
    let study = copy_study(&s, 7, "a");
    let (a, b, whole) = (s.join("a"), s.join("b"), s.join("whole"));
    shard(&study, "1/2", &a);
    shard(&study, "2/2", &b);
    ok(drystone(&[&"run", &study, &"--out", &whole], &s));
    // The study, its wall and its data are gone; merge from another directory.
    for f in ["study.toml", "walls/cbl.toml", "data/collapse.csv"] {
        std::fs::remove_file(s.join(f)).unwrap();
    }
    let merged = s.join("merged");
    let o = ok(drystone(&[&"merge", &"--out", &merged, &a, &b], &root()));
    assert!(text(&o).contains("(seed 7)"), "{}", text(&o));
    for f in ["report.md", "summary.csv", "realizations.csv"] {
        let strip = |p: PathBuf| {
            let t = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            // realizations.csv: drop the last column (wall time).
            t.lines()
                .map(|l| if f == "realizations.csv" { l.rsplit_once(',').unwrap().0 } else { l })
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(strip(whole.join(f)), strip(merged.join(f)), "{f} differs");
    }
    assert!(!merged.join(".inputs").exists(), "the rebuilt inputs are removed");
    let (mw, mm) = (manifest(&whole), manifest(&merged));
    assert_eq!(mw["inputs"], mm["inputs"]);
}

#[test]
fn resume_refuses_the_journal_of_another_run() {
    let s = common::Scratch::created("prov-resume");
    let study = copy_study(&s, 7, "a");
    let out = s.join("out");
    ok(drystone(&[&"run", &study, &"--out", &out], &s));
    copy_study(&s, 8, "a");
    let o = drystone(&[&"run", &study, &"--out", &out, &"--resume"], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let msg = text(&o);
    assert!(msg.contains("journal.jsonl: was written by another run (seed: 7 in the journal, 8 in this run)"), "{msg}");
}

#[test]
fn the_manifest_lists_every_output_with_its_digest_and_no_staging_is_left() {
    let s = common::Scratch::created("prov-outputs");
    let study = copy_study(&s, 7, "a");
    let out = s.join("out");
    ok(drystone(&[&"run", &study, &"--out", &out], &s));
    let m = manifest(&out);
    let outputs = m["outputs"].as_array().unwrap();
    let names: Vec<&str> = outputs.iter().map(|o| o["path"].as_str().unwrap()).collect();
    for f in ["realizations.parquet", "realizations.csv", "summary.csv", "report.md", "fragility.svg"] {
        assert!(names.contains(&f), "{f} not in {names:?}");
    }
    for o in outputs {
        let p = out.join(o["path"].as_str().unwrap());
        assert_eq!(o["sha256"], sha256_hex(&std::fs::read(&p).unwrap()), "{}", p.display());
    }
    assert!(!names.iter().any(|n| n.starts_with('.') || *n == "journal.jsonl" || *n == "manifest.json"), "{names:?}");
    assert!(!out.join(".drystone-staging").exists());
}

#[test]
fn merge_checks_every_row_and_the_table_digests_and_keeps_the_shards_version() {
    let s = common::Scratch::created("prov-rows");
    let study = copy_study(&s, 7, "a");
    let (a, b) = (s.join("a"), s.join("b"));
    shard(&study, "1/2", &a);
    shard(&study, "2/2", &b);
    // The same study under another name: its shard 1/2 has the same seed, groups and count.
    let other_dir = s.join("other");
    std::fs::create_dir_all(&other_dir).unwrap();
    let other = copy_study(&other_dir, 7, "a");
    std::fs::write(&other, std::fs::read_to_string(&other).unwrap().replace("name = \"prov\"", "name = \"other\""))
        .unwrap();
    let o1 = s.join("o1");
    shard(&other, "1/2", &o1);
    let table = |d: &Path| d.join("realizations.parquet");
    let original = std::fs::read(table(&a)).unwrap();
    std::fs::copy(table(&o1), table(&a)).unwrap();
    let o = drystone(&[&"merge", &"--out", &s.join("m1"), &a, &b], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let msg = text(&o);
    assert!(
        msg.contains("realizations.parquet: sha256") && msg.contains("the file is not the one its run wrote"),
        "{msg}"
    );
    // With the manifest's digest forged to match, the rows themselves are refused.
    let mut m = manifest(&a);
    for f in m["outputs"].as_array_mut().unwrap() {
        if f["path"] == "realizations.parquet" {
            f["sha256"] = sha256_hex(&std::fs::read(table(&a)).unwrap()).into();
        }
    }
    std::fs::write(a.join("manifest.json"), serde_json::to_string_pretty(&m).unwrap()).unwrap();
    let o = drystone(&[&"merge", &"--out", &s.join("m2"), &a, &b], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let msg = text(&o);
    assert!(msg.contains("realizations.parquet: row of item 0: study: other in the shard, prov in this run"), "{msg}");
    // The merged manifest keeps the version and build of the shards.
    std::fs::write(table(&a), original).unwrap();
    for d in [&a, &b] {
        let mut m = manifest(d);
        m["drystone_version"] = "0.1.9".into();
        m["build"] = "0.1.9+src.0123456789abcdef".into();
        if d == &a {
            for f in m["outputs"].as_array_mut().unwrap() {
                if f["path"] == "realizations.parquet" {
                    f["sha256"] = sha256_hex(&std::fs::read(table(&a)).unwrap()).into();
                }
            }
        }
        std::fs::write(d.join("manifest.json"), serde_json::to_string_pretty(&m).unwrap()).unwrap();
    }
    let merged = s.join("m3");
    ok(drystone(&[&"merge", &"--out", &merged, &a, &b], &s));
    let m = manifest(&merged);
    assert_eq!(
        (m["drystone_version"].as_str(), m["build"].as_str()),
        (Some("0.1.9"), Some("0.1.9+src.0123456789abcdef"))
    );
}

#[test]
fn shards_with_distributions_from_the_working_directory_merge_from_anywhere() {
    let s = common::Scratch::created("prov-cwd");
    let (proj, cwd, elsewhere) = (s.join("proj"), s.join("cwd"), s.join("elsewhere"));
    for d in [proj.join("walls"), cwd.join("distributions"), elsewhere.clone()] {
        std::fs::create_dir_all(d).unwrap();
    }
    std::fs::copy(root().join("studies/walls/sbl.toml"), proj.join("walls/sbl.toml")).unwrap();
    for name in ["dip_uniform_10", "course_height_sbl", "block_length_sbl"] {
        let f = format!("distributions/{name}.toml");
        std::fs::copy(root().join(&f), cwd.join(&f)).unwrap();
    }
    let study = proj.join("study.toml");
    std::fs::write(
        &study,
        "version = 1\nname = \"cwd\"\nseed = 3\nrealizations = 2\n[tilt]\nstep_deg = 2.5\nresolution_deg = 0.5\n\
         [[groups]]\nname = \"SBL\"\nwall = \"walls/sbl.toml\"\noverrides = { length_m = 0.4 }\n",
    )
    .unwrap();
    let (a, b, whole) = (s.join("a"), s.join("b"), s.join("whole"));
    for (k, d) in [("1/2", &a), ("2/2", &b)] {
        ok(drystone(&[&"run", &study, &"--shard", &k, &"--out", d], &cwd));
    }
    ok(drystone(&[&"run", &study, &"--out", &whole], &cwd));
    let dists = manifest(&a)["inputs"].as_array().unwrap().iter().filter(|f| f["role"] == "distribution").count();
    assert_eq!(dists, 3, "the distributions found in the working directory are inputs");
    let merged = s.join("merged");
    ok(drystone(&[&"merge", &"--out", &merged, &a, &b], &elsewhere));
    assert_eq!(std::fs::read(whole.join("summary.csv")).unwrap(), std::fs::read(merged.join("summary.csv")).unwrap());
    assert_eq!(manifest(&whole)["inputs"], manifest(&merged)["inputs"]);
}

/// A study whose wall and measured folders are links to another place merges: the manifest
/// records each input where the study file's relative paths reach it, not where the links
/// point, so the study rebuilt from the stored texts finds every file (before, the stored
/// tree held the links' targets and the rebuilt study could not read its wall).
#[cfg(unix)]
#[test]
fn shards_of_a_study_reaching_its_files_through_links_merge() {
    let s = common::Scratch::created("prov-linked");
    let elsewhere = s.join("elsewhere");
    copy_study(&elsewhere, 7, "a");
    let study_dir = s.join("study");
    std::fs::create_dir_all(&study_dir).unwrap();
    for d in ["walls", "data"] {
        std::os::unix::fs::symlink(elsewhere.join(d), study_dir.join(d)).unwrap();
    }
    let study = study_dir.join("study.toml");
    std::fs::copy(elsewhere.join("study.toml"), &study).unwrap();
    let (a, b) = (s.join("a"), s.join("b"));
    shard(&study, "1/2", &a);
    shard(&study, "2/2", &b);
    let paths: Vec<String> =
        manifest(&a)["inputs"].as_array().unwrap().iter().map(|f| f["path"].as_str().unwrap().to_string()).collect();
    assert_eq!(paths, ["study.toml", "walls/cbl.toml", "data/collapse.csv"], "recorded where the study names them");
    let merged = s.join("merged");
    ok(drystone(&[&"merge", &"--out", &merged, &a, &b], &s));
    let whole = s.join("whole");
    ok(drystone(&[&"run", &study, &"--out", &whole], &study_dir));
    assert_eq!(std::fs::read(whole.join("summary.csv")).unwrap(), std::fs::read(merged.join("summary.csv")).unwrap());
}
