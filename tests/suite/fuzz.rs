//! Fuzzing of every input parser (property tests, a fixed budget of cases per run): the
//! layout JSON, the wall and distribution TOML, the study TOML, the measured-data CSV
//! files, run journals and manifests, each fed arbitrary text and the bundled valid files
//! with their numbers replaced by hostile values (NaN, ±inf, 0, negative, huge, tiny,
//! random), and every wall that parses generated and its layout checked. The property is
//! that nothing panics: every input is either accepted or refused with an error. Beyond
//! that, measured data accepted are in range, and a journal altered anywhere gives back
//! exactly the rows written (a cut-off last line dropped) or is refused.

use drystone::ensemble::journal::Journal;
use drystone::ensemble::row::{CollapseColumns, LateralColumns, RealizationRow, Status, TiltColumns};
use drystone::generator::{generate, DistributionSource, DistributionSpec, WallSpec};
use drystone::io::table::{read_measured_collapse, read_measured_displacement};
use drystone::layout::LayoutSpec;
use drystone::study::Manifest;
use drystone::study::Study;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).unwrap()
}

/// Byte ranges of the numbers of `text` (a digit run with its sign, point and exponent).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if starts {
            let s = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'e' | b'E' | b'_' | b'+' | b'-')) {
                if matches!(b[j], b'+' | b'-') && !matches!(b[j - 1], b'e' | b'E') {
                    break;
                }
                j += 1;
            }
            out.push((s, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// A hostile replacement for a number, as text in the syntax of `json` or TOML.
fn hostile(json: bool) -> impl Strategy<Value = String> {
    let special = prop_oneof![
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e300".to_string()),
        Just("-1e300".to_string()),
        Just("1e-300".to_string()),
        Just("4294967296".to_string()),
        Just("18446744073709551615".to_string()),
        Just(if json { "1e999" } else { "inf" }.to_string()),
        Just(if json { "-1e999" } else { "-inf" }.to_string()),
        Just(if json { "null" } else { "nan" }.to_string()),
        Just("\"x\"".to_string()),
    ];
    prop_oneof![
        special,
        any::<f64>().prop_map(|v| if v.is_finite() { format!("{v:e}") } else { "0".into() }),
        (0u32..100_000).prop_map(|v| v.to_string())
    ]
}

/// `text` with up to three of its numbers replaced: by a hostile value, or (half of the
/// edits) by the number itself scaled by a factor in [0.5, 2], which mostly stays valid and
/// so exercises the generation of random valid walls.
fn mutated(text: String, json: bool) -> impl Strategy<Value = String> {
    let spans = numbers(&text);
    let n = spans.len().max(1);
    let edit = prop_oneof![hostile(json).prop_map(Err), (0.5f64..2.0).prop_map(Ok)];
    proptest::collection::vec((0..n, edit), 1..4).prop_map(move |edits| {
        let mut t = text.clone();
        let mut edits: Vec<_> = edits.into_iter().filter(|(k, _)| *k < spans.len()).collect();
        edits.sort_by_key(|(k, _)| std::cmp::Reverse(*k));
        edits.dedup_by_key(|(k, _)| *k);
        for (k, v) in edits {
            let (a, b) = spans[k];
            let original = &text[a..b];
            let new = match v {
                Err(hostile) => hostile,
                Ok(f) => match original.replace('_', "").parse::<f64>() {
                    Ok(x) if original.contains(['.', 'e', 'E']) => format!("{:?}", x * f),
                    Ok(x) => format!("{}", (x * f).round() as i64),
                    Err(_) => original.to_string(),
                },
            };
            t.replace_range(a..b, &new);
        }
        t
    })
}

/// Parses a wall description and, if it resolves to a wall of a sane size, generates two
/// realizations and checks their layouts: no panic anywhere.
fn wall_pipeline(text: &str, dir: &Path) -> bool {
    let path = dir.join("fuzz_wall.toml");
    let Ok(spec) = WallSpec::from_toml(text, &path) else { return false };
    let Ok(wall) = spec.resolve(&path, &DistributionSource::default_for(&root().join("studies/walls/x.toml"))) else {
        return false;
    };
    if drystone::study::check_blocks(&wall).is_err() || drystone::study::estimated_blocks(&wall) > 3000.0 {
        return false;
    }
    let mut generated = false;
    for r in 0..2 {
        if let Ok(g) = generate(&wall, 7, r) {
            generated |= g.check().is_ok();
        }
    }
    generated
}

#[test]
fn the_wall_fuzzing_reaches_the_generator() {
    // Scaled numbers alone: most walls stay valid and generate.
    let text = read("studies/walls/sbl.toml");
    let spans = numbers(&text);
    assert!(spans.len() > 10, "{} numbers found", spans.len());
    let mut ok = 0;
    for k in 0..spans.len() {
        let (a, b) = spans[k];
        let mut t = text.clone();
        let original = &text[a..b];
        let Ok(x) = original.replace('_', "").parse::<f64>() else { continue };
        let new = if original.contains(['.', 'e', 'E']) { format!("{:?}", x * 1.1) } else { original.to_string() };
        t.replace_range(a..b, &new);
        ok += wall_pipeline(&t, &std::env::temp_dir()) as u32;
    }
    assert!(ok as usize > spans.len() / 2, "{ok} of {} scaled walls generated", spans.len());
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        rng_seed: crate::common::proptest_seed(),
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn layout_json_never_panics(text in mutated(read("data/layouts/single_block.json"), true)) {
        if let Ok(spec) = LayoutSpec::from_json(&text) {
            let _ = spec.resolve();
        }
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
        let _ = LayoutSpec::from_json(&text);
        let _ = WallSpec::from_toml(&text, Path::new("x.toml"));
        let _ = DistributionSpec::from_toml(&text, Path::new("x.toml"));
    }

    #[test]
    fn distribution_toml_never_panics(
        text in prop_oneof![
            mutated(read("distributions/dip_truncated_normal_8.toml"), false),
            mutated(read("distributions/block_length_sbl.toml"), false),
            mutated(read("distributions/kn_factor_lognormal_cv20.toml"), false),
        ]
    ) {
        if let Ok(spec) = DistributionSpec::from_toml(&text, Path::new("x.toml")) {
            let _ = spec.resolve("x", Path::new("x.toml"), "");
        }
    }
}

proptest! {
    #![proptest_config(config(120))]

    #[test]
    fn wall_toml_and_generation_never_panic(
        text in prop_oneof![
            mutated(read("studies/walls/sbl.toml"), false),
            mutated(read("studies/walls/cbl.toml"), false),
            mutated(read("studies/walls/full_scale.toml"), false),
        ]
    ) {
        wall_pipeline(&text, &std::env::temp_dir());
    }

    #[test]
    fn study_toml_never_panics(text in mutated(read("studies/tilting_table.toml"), false)) {
        // Beside the bundled study so that its wall paths resolve; a name of its own per case.
        let path = root().join("studies").join(format!(".fuzz_study_{}.toml", std::process::id()));
        std::fs::write(&path, &text).unwrap();
        let study = Study::from_file(&path);
        let _ = std::fs::remove_file(&path);
        if let Ok(study) = study {
            let _ = study.items();
        }
    }
}

/// A row of a journal (any values: the journal does not look into them).
fn row(index: u64) -> RealizationRow {
    RealizationRow {
        index,
        study: "s".into(),
        group: "g".into(),
        point: 0,
        sweep: String::new(),
        seed: 1,
        realization: index,
        status: Status::Collapsed,
        error: String::new(),
        blocks: 12,
        collapse: CollapseColumns {
            collapse_angle_deg: Some(17.25),
            first_unstable_deg: Some(17.5),
            collapse_reason: "negative_stiffness".into(),
            mechanism: "toppling".into(),
            joint: "table/b0".into(),
            moving_blocks: 3,
            failure_height_fraction: None,
            mechanism_kind: String::new(),
            mechanism_start: String::new(),
            mechanism_extent: None,
        },
        tilt: TiltColumns {
            tilt_deg: vec![0.5, 1.0],
            disp_top_left_cm: vec![0.01, 0.02],
            disp_top_centre_cm: vec![0.011, 0.021],
            disp_top_right_cm: vec![0.012, 0.022],
        },
        lateral: LateralColumns {
            lateral_disp_left_cm: None,
            lateral_disp_centre_cm: None,
            lateral_disp_right_cm: None,
            lateral_disp_max_cm: None,
            lateral_drift: None,
        },
        shake: Default::default(),
        pushover: Default::default(),
        in_plane: None,
        compression: None,
        steps: 140,
        iterations: 30,
        dt_s: 1.5e-5,
        wall_time_s: 0.25,
    }
}

/// The text of a journal of three rows, and its rows as JSON.
fn journal_text() -> (String, Vec<String>) {
    let dir = std::env::temp_dir().join(format!("drystone-fuzz-journal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("journal.jsonl");
    let j = Journal::create(&p, "run-a", &"header".to_string()).unwrap();
    let rows = [row(3), row(0), row(7)];
    for r in &rows {
        j.append(r).unwrap();
    }
    drop(j);
    let text = std::fs::read_to_string(&p).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (text, rows.iter().map(|r| serde_json::to_string(r).unwrap()).collect())
}

/// `text` with one character replaced (any position, any printable character).
fn flipped(text: String) -> impl Strategy<Value = String> {
    let n = text.len();
    (0..n, proptest::char::range(' ', '~')).prop_map(move |(i, c)| {
        let mut b = text.clone().into_bytes();
        b[i] = c as u8;
        String::from_utf8_lossy(&b).into_owned()
    })
}

/// Writes `text` to a scratch file named `name` for one case; returns its path.
fn scratch_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drystone-fuzz-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn an_altered_journal_gives_back_its_rows_or_is_refused(
        text in prop_oneof![mutated(journal_text().0, true), flipped(journal_text().0)]
    ) {
        let (_, rows) = journal_text();
        let p = scratch_file("journal.jsonl", &text);
        if let Ok(Some(c)) = Journal::read::<String>(&p) {
            let back: Vec<String> = c.rows.iter().map(|r| serde_json::to_string(r).unwrap()).collect();
            // Only a cut-off last line may be missing.
            prop_assert!(back.len() + 1 >= rows.len() && back[..] == rows[..back.len()], "{back:?}");
            prop_assert_eq!(c.run.as_str(), "run-a");
        }
    }

    #[test]
    fn measured_csv_accepted_is_in_range(
        collapse in mutated(read("data/paper/tilting_table_collapse.csv"), false),
        displacement in mutated(read("data/paper/tilting_table_displacement.csv"), false),
        arbitrary in "\\PC{0,200}",
    ) {
        for text in [&collapse, &arbitrary] {
            if let Ok(rows) = read_measured_collapse(&scratch_file("collapse.csv", text)) {
                prop_assert!(rows.iter().all(|r| r.collapse_angle_deg > 0.0 && r.collapse_angle_deg < 90.0));
            }
        }
        for text in [&displacement, &arbitrary] {
            if let Ok(rows) = read_measured_displacement(&scratch_file("displacement.csv", text)) {
                prop_assert!(rows.iter().all(|r| (0.0..90.0).contains(&r.tilt_deg) && r.displacement_cm.abs() <= 1000.0));
            }
        }
    }

    #[test]
    fn manifests_never_panic(text in mutated(read("tests/fuzz/manifest.json"), true)) {
        if let Ok(m) = serde_json::from_str::<Manifest>(&text) {
            let _ = m.identity();
            let _ = m.difference(&m, "a", "b");
            let _ = drystone::study::verify_outputs(Path::new("/nonexistent"), &m.outputs);
        }
    }
}
