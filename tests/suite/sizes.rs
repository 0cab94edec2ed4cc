//! Sizes: what would not fit is refused before anything is allocated, with an error naming
//! the key and the estimate; `--threads` is clamped; a study name cannot lead outside the
//! output directory.

use drystone::study::Study;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use crate::common;

const BIN: &str = env!("CARGO_BIN_EXE_drystone");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A study in `dir` of one group on a copy of the CBL wall with `wall_edit` applied
/// (`(from, to)` text replacements); `name`, `realizations` and extra TOML after the group.
fn study(dir: &Path, name: &str, realizations: &str, wall_edit: &[(&str, &str)], extra: &str) -> PathBuf {
    let mut wall = std::fs::read_to_string(root().join("studies/walls/cbl.toml")).unwrap();
    for (from, to) in wall_edit {
        assert!(wall.contains(from), "{from}");
        wall = wall.replace(from, to);
    }
    std::fs::write(dir.join("wall.toml"), wall).unwrap();
    let p = dir.join("study.toml");
    std::fs::write(
        &p,
        format!(
            "version = 1\nname = {name:?}\nseed = 1\nrealizations = {realizations}\n\
             [tilt]\nstep_deg = 4.0\nresolution_deg = 1.0\n\
             [[groups]]\nname = \"g\"\nwall = \"wall.toml\"\n{extra}"
        ),
    )
    .unwrap();
    p
}

fn refused(p: &Path) -> String {
    let t0 = Instant::now();
    let e = Study::from_file(p).err().unwrap_or_else(|| panic!("{} loaded", p.display())).to_string();
    assert!(t0.elapsed() < Duration::from_secs(10), "refusing took {:?}", t0.elapsed());
    e
}

fn run(args: &[&dyn AsRef<std::ffi::OsStr>], cwd: &Path) -> Output {
    Command::new(BIN).args(args).current_dir(cwd).output().expect("drystone runs")
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn too_many_items_are_refused_in_the_file_and_on_the_command_line() {
    let s = common::Scratch::created("sizes-items");
    let e = refused(&study(&s, "x", "1000000000", &[], ""));
    assert!(e.contains("study.toml: realizations: 1000000000 realizations × 1 group(s) × 1 sweep point(s) = 1000000000 work items (about 3.7 TiB"), "{e}");
    assert!(e.contains("the limit is 1000000 work items per study"), "{e}");
    let p = study(&s, "x", "2", &[], "");
    let o = run(&[&"run", &p, &"--realizations", &"1000000000", &"--out", &s.join("out")], &s);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--realizations 1000000000:") && text(&o).contains("work items"), "{}", text(&o));
    assert!(!s.join("out").exists(), "nothing written");
}

#[test]
fn walls_too_large_are_refused_naming_the_key_and_the_estimate() {
    let s = common::Scratch::created("sizes-walls");
    let cases: [(&[(&str, &str)], &str, &str); 4] = [
        (&[("length_m = 1.5", "length_m = 1e300")], "", "geometry.length_m = 1e300"),
        (&[("length_m = 1.5", "length_m = 10000.0")], "", "about 500020 blocks"),
        (&[("height_m = 0.040", "height_m = 1e-6")], "", "courses.height_m = 1e-6"),
        (&[], "[sweep]\nlength_m = [1.0, 1e300]\n", "groups[g] at sweep.length_m"),
    ];
    for (edit, extra, expect) in cases {
        let e = refused(&study(&s, "x", "1", edit, extra));
        assert!(e.contains(expect), "expected {expect:?} in {e}");
        assert!(e.contains("the limit is 100000 blocks per layout"), "{e}");
    }
}

#[test]
fn a_sweep_of_64000_points_is_refused_at_once() {
    let s = common::Scratch::created("sizes-sweep");
    let values: Vec<String> = (0..64_000).map(|i| format!("{}", 20.0 + i as f64 * 1e-4)).collect();
    let e = refused(&study(&s, "x", "1", &[], &format!("[sweep]\nfriction_deg = [{}]\n", values.join(","))));
    assert!(e.contains("sweep: friction_deg (64000 values) = 64000 sweep points; the limit is 10000"), "{e}");
}

#[test]
fn a_study_name_cannot_write_outside_the_output_directory() {
    let s = common::Scratch::created("sizes-name");
    let work = s.join("a/b");
    std::fs::create_dir_all(&work).unwrap();
    let p = study(&work, "../../x", "1", &[], "");
    // Without --out the default is out/<name>: refused before anything is written.
    let o = run(&[&"run", &p], &work);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("name: \"../../x\" contains '/'"), "{}", text(&o));
    assert!(!s.join("x").exists() && !work.join("out").exists());
}

#[test]
fn threads_are_clamped_and_zero_means_every_core() {
    let s = common::Scratch::created("sizes-threads");
    let p = study(&s, "t", "1", &[("length_m = 1.5", "length_m = 0.4")], "");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    for (threads, expect) in [("0", cores), ("1000000", cores)] {
        let o = run(&[&"run", &p, &"--threads", &threads, &"--out", &s.join(threads)], &s);
        assert!(o.status.success(), "{}", text(&o));
        assert!(text(&o).contains(&format!("on {expect} threads")), "{}", text(&o));
    }
}

#[test]
fn generate_shares_the_size_limits_of_run() {
    let s = common::Scratch::created("sizes-generate");
    for (edit, key) in [
        (("length_m = 1.5", "length_m = 1e300"), "geometry.length_m = 1e300"),
        (("length_m = 1.5", "length_m = 10000"), "geometry.length_m = 10000"),
        (("height_m = 0.040", "height_m = 1e-6"), "courses.height_m = 1e-6"),
    ] {
        study(&s, "g", "1", &[edit], "");
        let out = s.join("wall.json");
        let o = run(&[&"generate", &s.join("wall.toml"), &"--seed", &"1", &"--out", &out], &s);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(key) && err.contains("the limit is 100000 blocks per layout"), "{err}");
        assert!(err.contains("wall.toml"), "{err}");
        assert!(!out.exists());
    }
}
