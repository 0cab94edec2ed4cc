//! A cyclic in-plane history replayed point by point (`[in_plane] reversals_pct`,
//! `drystone in-plane --reversals-pct` / `--replay FILE`) and the turning points read from a
//! measured curve (`loading::inplane_loops::turning_points`).
//!
//! References, each independent of the code under test: histories written here by hand
//! and rounded as the curve files round their drifts; the ladder of
//! `InPlaneParams::amplitudes_pct`, the established history, which a replay of its own
//! points must reproduce bit for bit; and the bundled measured curves read here by a plain
//! fold of their drift column.

use drystone::dem::SolverParams;
use drystone::loading::inplane::{run_in_plane_penalty, History, InPlaneParams};
use drystone::loading::inplane_loops::{turning_points, TURNING_NOISE_PCT};
use drystone::verify::inplane::{inplane_block, inplane_params};
use std::path::PathBuf;
use std::process::Command;

fn curves() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/inplane_granite/curves")
}

/// The drift column of a curve file (four header lines; `mm, kN, %`), read here by hand.
fn drift_column(path: &std::path::Path) -> Vec<f64> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(4)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').nth(2).unwrap().trim().parse().unwrap())
        .collect()
}

/// A sawtooth written by hand, 0 → 0.1 → −0.1 → 0.2 → −0.2 → 0 % in readings every
/// 0.013 %, each with a jitter of ±0.005 % and rounded to 0.01 % as the files are: its
/// turning points are the sawtooth's, to the rounding, none from the jitter; the same
/// history pushed the other way first turns negative first.
#[test]
fn a_sawtooth_read_as_a_laboratory_reads_it_turns_where_it_was_turned() {
    let corners: [f64; 6] = [0.0, 0.1, -0.1, 0.2, -0.2, 0.0];
    let mut readings = Vec::new();
    let mut k = 0usize;
    for w in corners.windows(2) {
        let n = ((w[1] - w[0]).abs() / 0.013).ceil() as usize;
        for i in 1..=n {
            let exact = w[0] + (w[1] - w[0]) * i as f64 / n as f64;
            let jitter = if k % 3 == 0 {
                0.005
            } else if k % 3 == 1 {
                -0.005
            } else {
                0.0
            };
            k += 1;
            readings.push(((exact + jitter) * 100.0).round() / 100.0);
        }
    }
    let turns = turning_points(&readings, TURNING_NOISE_PCT);
    assert_eq!(turns.len(), 5, "{turns:?}");
    for (t, c) in turns.iter().zip(&corners[1..]) {
        assert!((t - c).abs() <= 0.0101, "{turns:?} against {:?}", &corners[1..]);
    }
    let mirrored: Vec<f64> = readings.iter().map(|v| -v).collect();
    let turns = turning_points(&mirrored, TURNING_NOISE_PCT);
    assert!(turns[0] < -0.09, "{turns:?}");
    assert!(turning_points(&[0.0, 0.01, -0.01, 0.0], TURNING_NOISE_PCT).is_empty());
}

/// The ladder's history written as its own points (returns to zero included) is the ladder,
/// increment for increment, and a cyclic run of the monolith on it gives the ladder's run
/// bit for bit.
#[test]
fn a_ladder_written_as_its_points_is_replayed_bit_for_bit() {
    let ladder = InPlaneParams {
        history: History::Cyclic,
        amplitudes_pct: Some(vec![0.1, 0.2]),
        cycles: 2,
        ..inplane_params(0.2)
    };
    let points = vec![0.1, -0.1, 0.0, 0.1, -0.1, 0.0, 0.2, -0.2, 0.0, 0.2, -0.2, 0.0];
    let replay = InPlaneParams { amplitudes_pct: None, reversals_pct: Some(points), ..ladder.clone() };
    replay.validate().unwrap();
    assert_eq!(replay.path(1.325), ladder.path(1.325));
    let wall = inplane_block(45.0, 1e10);
    let s = SolverParams::default();
    let a = run_in_plane_penalty(&wall, s, &ladder, &mut |_, _, _| {}).unwrap();
    let b = run_in_plane_penalty(&wall, s, &replay, &mut |_, _, _| {}).unwrap();
    assert_eq!(format!("{:?}", a.curve), format!("{:?}", b.curve));
    assert!(a.negative.is_some());
}

/// Every bundled cyclic curve: its turning points reach the file's largest drift each way,
/// the first turns the way the file's first reading past the band goes (WS2100 was pushed
/// negative first), and between two turning points every reading lies between them within
/// the band (each leg is one-way up to the readings' noise). Readings that are not numbers
/// (a file's gaps) are passed over, as the reader does.
#[test]
fn the_measured_histories_turn_where_their_files_do() {
    let mut cyclic = 0;
    let mut names: Vec<PathBuf> = std::fs::read_dir(curves()).unwrap().map(|e| e.unwrap().path()).collect();
    names.sort();
    for path in names {
        let d = drift_column(&path);
        if d.iter().all(|&v| v >= 0.0) {
            continue;
        }
        cyclic += 1;
        let turns = turning_points(&d, TURNING_NOISE_PCT);
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let hi = d.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
        let lo = d.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        assert_eq!(turns.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v)), hi, "{name}");
        assert_eq!(turns.iter().fold(f64::INFINITY, |m, &v| m.min(v)), lo, "{name}");
        let first = d.iter().find(|v| v.abs() > TURNING_NOISE_PCT).unwrap();
        assert_eq!(turns[0].signum(), first.signum(), "{name}: {turns:?}");
        if name.contains("WS2100") {
            assert!(turns[0] < 0.0, "{name}: {turns:?}");
        }
        // Walk the readings leg by leg.
        let mut leg = 0usize;
        let mut from = 0.0f64;
        for &v in d.iter().filter(|v| v.is_finite()) {
            let to = turns[leg];
            let (a, b) = (from.min(to), from.max(to));
            assert!(
                v >= a - TURNING_NOISE_PCT - 1e-12 && v <= b + TURNING_NOISE_PCT + 1e-12,
                "{name}: {v} outside the leg {from} → {to}"
            );
            if v == to && leg + 1 < turns.len() {
                from = to;
                leg += 1;
            }
        }
    }
    assert!(cyclic >= 10, "{cyclic} cyclic curves");
}

/// Bad histories are refused by key: a replay with a monotonic history or with
/// `amplitudes_pct`, a point past `drift_pct`, a point equal to the one before; on the
/// command line a file that does not exist and a file whose history goes past
/// `--drift-pct`, each named.
#[test]
fn bad_replayed_histories_are_refused_by_name() {
    let cyclic = InPlaneParams { history: History::Cyclic, ..inplane_params(1.0) };
    let with = |r: Vec<f64>| InPlaneParams { reversals_pct: Some(r), ..cyclic.clone() };
    let err = |p: InPlaneParams| p.validate().unwrap_err().to_string();
    assert!(err(InPlaneParams { history: History::Monotonic, ..with(vec![0.5]) }).contains("reversals_pct"));
    assert!(err(InPlaneParams { amplitudes_pct: Some(vec![0.5]), ..with(vec![0.5]) }).contains("amplitudes_pct"));
    assert!(err(with(vec![0.5, -1.5])).contains("reversals_pct = -1.5"));
    assert!(err(with(vec![0.5, 0.5])).contains("reversals_pct = 0.5"));
    assert!(err(with(vec![0.0])).contains("reversals_pct"));
    assert!(err(with(vec![])).contains("reversals_pct"));
    let layout = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/layouts/single_block.json");
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
            .args(["in-plane", layout.to_str().unwrap(), "--sigma0-mpa", "0.5", "--shear-span-m", "0.5"])
            .args(args)
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!e.contains("panicked"), "{e}");
        (o.status.code(), e)
    };
    let (code, e) = run(&["--replay", "/nonexistent/FD.csv"]);
    assert_ne!(code, Some(0));
    assert!(e.contains("/nonexistent/FD.csv"), "{e}");
    let ws = curves().join("FD_WS2100_Vasconcelos2009.csv");
    let (code, e) = run(&["--replay", ws.to_str().unwrap(), "--drift-pct", "1"]);
    assert_ne!(code, Some(0));
    assert!(e.contains("FD_WS2100") && e.contains("1.248"), "{e}");
    let (code, e) = run(&["--reversals-pct", "0.1", "--amplitudes-pct", "0.1", "--cyclic"]);
    assert_ne!(code, Some(0));
    assert!(e.contains("--amplitudes-pct") || e.contains("--reversals-pct"), "{e}");
}

/// A curve file whose reading is not a finite number, or whose header does not name the
/// columns, is refused naming the file, the line and the column, by the command line's
/// `--replay` and by the study's reader of its measured curves alike (both read it through
/// `study::inplane::read_envelope`'s reader); a line of `NaN` in every column (the
/// database's break between digitized segments, as the bundled WS1.100 has) is read.
/// Before, `inf`, `NaN` in one column and a header of other columns were read, and the
/// readings that were not finite passed over silently.
#[test]
fn a_curve_file_with_a_reading_that_is_not_finite_or_a_wrong_header_is_refused_by_line_and_column() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/inplane_granite");
    let name = "FD_WS1100_Vasconcelos2009.csv";
    let text = std::fs::read_to_string(curves().join(name)).unwrap();
    assert!(text.lines().any(|l| l == "NaN,NaN,NaN"));
    let dir = std::env::temp_dir().join(format!("drystone-replay-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Line `n` (1-based) replaced by `line`.
    let edited = |n: usize, line: &str| -> PathBuf {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        lines[n - 1] = line.to_string();
        let d = dir.join(format!("edit{n}"));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join(name), lines.join("\n")).unwrap();
        d.join(name)
    };
    let read = |p: &PathBuf| drystone::study::inplane::read_envelope(p).map(|_| ()).unwrap_err().to_string();
    for (n, line, needles) in [
        (10, "0.5,3.1,inf", vec!["line 10", "column drift", "not a finite"]),
        (11, "-inf,3.1,0.05", vec!["line 11", "column top_displacement", "not a finite"]),
        (12, "0.6,NaN,0.05", vec!["line 12", "column horizontal_force", "NaN beside numbers"]),
        (9, "1.2.3,3.0,0.04", vec!["line 9", "column top_displacement", "not a number"]),
        (9, "0.5,3.0,0.04,7", vec!["line 9", "not three numbers"]),
        (3, "drift,horizontal_force,top_displacement", vec!["line 3", "top_displacement,horizontal_force,drift"]),
        (4, "[m],[kN],[%]", vec!["line 4", "[mm],[kN],[%]"]),
    ] {
        let p = edited(n, line);
        let e = read(&p);
        assert!(e.contains(name), "{line}: {e}");
        for needle in &needles {
            assert!(e.contains(needle), "{line}: {e}");
        }
        // The study's reader of the measured curves: the same refusal, naming the file.
        let mut s = drystone::study::inplane::read_specimens(&root.join("walls.csv"), None).unwrap();
        let e = drystone::study::inplane::read_loops(&mut s, p.parent().unwrap()).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(needles[0]), "{line}: {e}");
    }
    // On the command line (the history is read before the layout).
    let p = edited(10, "0.5,3.1,inf");
    let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["in-plane", "/nonexistent/wall.json", "--sigma0-mpa", "0.5", "--shear-span-m", "1.325"])
        .args(["--drift-pct", "0.01", "--replay", p.to_str().unwrap()])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(0));
    assert!(!e.contains("panicked"), "{e}");
    assert!(e.contains(name) && e.contains("line 10") && e.contains("column drift"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A replayed history that never turns at a negative drift has no negative direction: the
/// unloading back to zero overshoots by the joints' elastic recovery alone, and reading it
/// as a push gave a negative peak of some 30 kN at a drift of 1e-5 % on the granite wall.
/// The same history turned through −0.2 % reads one. One block (Kn 1e10 Pa/m, φ 45°, the
/// table's φ 45°).
#[test]
fn a_history_never_pushed_negative_reads_no_negative_direction() {
    let layout = inplane_block(45.0, 1e10);
    let run = |r: Vec<f64>| {
        let p = InPlaneParams { history: History::Cyclic, reversals_pct: Some(r), ..inplane_params(0.3) };
        run_in_plane_penalty(&layout, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap()
    };
    let there_and_back = run(vec![0.2, 0.0]);
    assert!(there_and_back.positive.is_some());
    assert!(there_and_back.negative.is_none(), "{:?}", there_and_back.negative);
    let through = run(vec![0.2, -0.2, 0.0]);
    let neg = through.negative.expect("a negative direction");
    assert!(neg.peak_force_kn > 1.0, "{neg:?}");
}
