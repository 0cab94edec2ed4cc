//! Shaking studies (`protocol = "shake"`) end to end: a rigid block under built-in pulses
//! collapses at each PGA level as Housner's rocking equation, integrated here, says, and
//! its fitted fragility and static capacity sit where statics and the counts put them;
//! the rows are the same on 1 and 2 threads and sharded then merged; bad inputs are refused
//! naming the file, line or key.

use drystone::ensemble::row::{RealizationRow, Status};
use drystone::ensemble::Shard;
use drystone::ground::{Pulse, G};
use drystone::study::run_study;
use drystone::study::{fragilities, Study, StudyError};
use drystone::study::{merge, run_into, RunMode};
use std::path::{Path, PathBuf};

/// The block: 0.2 m along x, b = 0.1 m out of plane (y), h = 0.5 m tall; tan α = b/h = 0.2.
const B: f64 = 0.1;
const H: f64 = 0.5;

/// A wall description of one block on the table (one course, one stone), friction 60°
/// (μ 1.7 against b/h 0.2: it rocks, it does not slide).
const BLOCK: &str = r#"
version = 1
name = "block"
[geometry]
length_m = 0.2
height_m = 0.5
base_width_m = 0.1
top_width_m = 0.1
batter = "symmetric"
[arrangement]
kind = "continuous"
[courses]
height_m = 0.5
[blocks]
length_m = 0.2
material = "stone"
[[materials]]
name = "stone"
density_kg_per_m3 = 2000.0
kn_pa_per_m = 1.0e9
ks_pa_per_m = 5.0e8
friction_deg = 60.0
cohesion_pa = 0.0
tensile_strength_pa = 0.0
[restraints]
base = "free"
ends = { kind = "free" }
"#;

/// The periods of the pulses: long (ω_p/p ≈ 2), medium (≈ 4), short (≈ 8), with
/// p = √(3g / 4R) = 5.37 rad/s.
const PERIODS: [f64; 3] = [0.6, 0.3, 0.15];
/// The PGA levels, g: the first below the uplift threshold tan α = 0.2, the others at
/// least 10 % away from the overturning boundary of each pulse (about 0.25 g for T 0.6 s,
/// 0.34 g for 0.3 s, 1.6 g for 0.15 s by the rocking equation; the test checks it).
const LEVELS: [f64; 5] = [0.1, 0.29, 0.6, 1.2, 2.0];
/// Free motion after the pulse, s.
const TAIL_S: f64 = 1.5;

/// A scratch directory of this test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("drystone-shake-study-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A shaking study of the block in `dir` with the given `[shake]` lines and solver kind.
///
/// The solver's step is 2.5e-4 s: 600 steps over the shortest pulse (0.15 s, ω_p/p ≈ 8),
/// whose overturning a coarser step misses near the boundary (`tests/suite/shake.rs`).
fn block_study(dir: &Path, shake: &str, solver: &str) -> PathBuf {
    std::fs::write(dir.join("block.toml"), BLOCK).unwrap();
    let text = format!(
        "version = 1\nname = \"block_shake\"\nseed = 5\nrealizations = 1\nprotocol = \"shake\"\n\
         [solver]\nkind = \"{solver}\"\n[solver.nscd]\ndt_s = 2.5e-4\n[shake]\n{shake}\n[[groups]]\nname = \"block\"\nwall = \"block.toml\"\n"
    );
    let path = dir.join("study.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn pulses_table() -> String {
    let levels: Vec<String> = LEVELS.iter().map(|l| l.to_string()).collect();
    let pulses: Vec<String> =
        PERIODS.iter().map(|t| format!("{{ kind = \"one-sine\", amplitude_g = 1.0, period_s = {t} }}")).collect();
    format!("pga_g = [{}]\npulses = [{}]\ntail_s = {TAIL_S}", levels.join(", "), pulses.join(", "))
}

/// Housner's rocking equation (Housner 1963), integrated here by RK4 at 1e-4 s, with the
/// impact rule θ̇ ← r θ̇, r = 1 − 1.5 sin²α, at θ = 0 and uplift only when |a_g| > g tan α:
/// whether the block turns past 45° (the protocol's fall rotation) within `t_end`.
fn housner_falls(pulse: &Pulse, t_end: f64) -> bool {
    let g = drystone::units::STANDARD_GRAVITY;
    let alpha = (B / H).atan();
    let p2 = 3.0 * g / (4.0 * 0.5 * (B * B + H * H).sqrt());
    let r = 1.0 - 1.5 * alpha.sin().powi(2);
    let a = |t: f64| pulse.at(t) * G / g;
    let dt = 1e-4;
    let (mut th, mut om, mut t) = (0.0_f64, 0.0_f64, 0.0_f64);
    while t < t_end {
        if th == 0.0 && om == 0.0 && a(t).abs() <= alpha.tan() {
            t += dt;
            continue;
        }
        let side = if th != 0.0 {
            th.signum()
        } else if om != 0.0 {
            om.signum()
        } else {
            -a(t).signum()
        };
        let f = |th: f64, t: f64| -p2 * ((alpha * side - th).sin() + a(t) * (alpha * side - th).cos());
        let (k1t, k1o) = (om, f(th, t));
        let (k2t, k2o) = (om + 0.5 * dt * k1o, f(th + 0.5 * dt * k1t, t + 0.5 * dt));
        let (k3t, k3o) = (om + 0.5 * dt * k2o, f(th + 0.5 * dt * k2t, t + 0.5 * dt));
        let (k4t, k4o) = (om + dt * k3o, f(th + dt * k3t, t + dt));
        let nth = th + dt / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
        let nom = om + dt / 6.0 * (k1o + 2.0 * k2o + 2.0 * k3o + k4o);
        t += dt;
        if th != 0.0 && nth * th < 0.0 {
            th = 0.0;
            om = if (nom * r).abs() < 1e-6 { 0.0 } else { nom * r };
            continue;
        }
        (th, om) = (nth, nom);
        if th.abs() > 45f64.to_radians() {
            return true;
        }
    }
    false
}

/// The rows by (motion period, level).
fn verdict(rows: &[RealizationRow], period: f64, level: f64) -> &RealizationRow {
    let name = format!("one-sine_1g_{period}s");
    rows.iter().find(|r| r.shake.motion == name && r.shake.pga_g == Some(level)).expect("a row per motion and level")
}

/// Every (pulse, level) of the block collapses or stands as the rocking equation says (at
/// levels where the equation gives the same verdict 10 % below and above: away from the
/// overturning boundary), below the uplift threshold nothing moves; the fitted median lies
/// between the highest level with no collapse and the lowest where every motion
/// overturns; the static capacity by limit analysis is tan α = b/h.
#[test]
fn a_rigid_block_collapses_at_each_level_as_the_rocking_equation_says() {
    let dir = scratch("block");
    let study = Study::from_file(&block_study(&dir, &pulses_table(), "nscd")).unwrap();
    assert_eq!(study.points.len(), PERIODS.len() * LEVELS.len());
    let rows = run_study(&study, Shard::ALL);
    let mut collapses = vec![0u64; LEVELS.len()];
    for &t in &PERIODS {
        for (k, &level) in LEVELS.iter().enumerate() {
            let pulse = |f: f64| Pulse::OneSine { amplitude_g: f * level, period_s: t };
            let expect = housner_falls(&pulse(1.0), t + TAIL_S);
            assert!(
                housner_falls(&pulse(0.9), t + TAIL_S) == expect && housner_falls(&pulse(1.1), t + TAIL_S) == expect,
                "T {t} s at {level} g is within 10 % of the overturning boundary: choose another level"
            );
            let r = verdict(&rows, t, level);
            assert!(r.status.is_ok(), "{}", r.error);
            assert_eq!(r.status == Status::Collapsed, expect, "T {t} s at {level} g: {:?}", r.shake);
            assert_eq!(r.shake.collapse_time_s.is_some(), expect);
            assert_eq!(r.shake.blocks_fallen, Some(u64::from(expect)));
            collapses[k] += u64::from(expect);
            if level < B / H {
                assert!(r.shake.max_rotation_deg.unwrap() < 1e-3, "below g tan α: {:?}", r.shake);
            }
        }
    }
    // The counts overlap (a fit exists) and bracket the median.
    assert_eq!(collapses[0], 0);
    assert!(collapses.iter().any(|&c| c > 0 && c < PERIODS.len() as u64), "{collapses:?}");
    let frag = fragilities(&study, &rows);
    let f = &frag[0];
    assert_eq!(f.levels.iter().map(|l| l.collapses).collect::<Vec<_>>(), collapses);
    let band = f.band.as_ref().expect("overlapping counts have a fit");
    let quiet = LEVELS.iter().zip(&collapses).filter(|(_, &c)| c == 0).map(|(l, _)| *l).fold(0.0, f64::max);
    let all = LEVELS.iter().zip(&collapses).filter(|(_, &c)| c == PERIODS.len() as u64).map(|(l, _)| *l);
    let all = all.fold(f64::INFINITY, f64::min).min(2.0 * LEVELS[LEVELS.len() - 1]);
    assert!(quiet < band.fit.median && band.fit.median < all, "θ {} not in ({quiet}, {all})", band.fit.median);
    // Limit analysis of the block on the tilting table: λ = tan α = b/h.
    assert_eq!(f.capacity.len(), 1);
    assert!((f.capacity[0] - B / H).abs() < 1e-4, "λ {} vs b/h {}", f.capacity[0], B / H);
    // The report has its table and plot.
    let out = dir.join("out");
    run_into(&study, &dir.join("study.toml"), Shard::ALL, &out, RunMode::default()).unwrap();
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Fragility against PGA") && report.contains("shaking.svg"), "{report}");
    assert!(report.contains("; solver `nscd`: non-smooth contact dynamics, time step "), "{report}");
    assert!(out.join("shaking.svg").exists() && out.join("fragility.csv").exists());
    let csv = std::fs::read_to_string(out.join("realizations.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for c in ["motion", "pga_g", "collapse_time_s", "max_rotation_deg", "max_drift", "residual_drift", "blocks_fallen"]
    {
        assert!(header.split(',').any(|h| h == c), "{c} in {header}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `[solver] kind = "penalty"`: the same block by the penalty DEM in explicit dynamics (Kn
/// 1e9 Pa/m, contact dashpots of the default restitution) collapses as the rocking
/// equation says at every period and every level below μ g (μ = tan 60° = 1.73): at 2 g the
/// base slides under the block, which the rocking equation does not know.
#[test]
fn a_penalty_shaking_study_collapses_as_the_rocking_equation_says() {
    let dir = scratch("penalty");
    let study = Study::from_file(&block_study(&dir, &pulses_table(), "penalty")).unwrap();
    let rows = run_study(&study, Shard::ALL);
    for &t in &PERIODS {
        for &level in LEVELS.iter().filter(|&&l| l < 60f64.to_radians().tan()) {
            let expect = housner_falls(&Pulse::OneSine { amplitude_g: level, period_s: t }, t + TAIL_S);
            let r = verdict(&rows, t, level);
            assert!(r.status.is_ok(), "{}", r.error);
            assert_eq!(r.status == Status::Collapsed, expect, "T {t} s at {level} g: {:?}", r.shake);
            if level < B / H {
                // Below g tan α the block does not rock: it only turns on its elastic bed
                // joint (the heel lifts at b/3h = 0.067 g in the no-tension Winkler joint),
                // far less than α = 11.3°.
                let rot = r.shake.max_rotation_deg.unwrap();
                assert!(rot < 0.1, "below g tan α: {rot}°: {:?}", r.shake);
            }
        }
    }
    // The report names the method that ran, not nscd's settings.
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    drystone::study::write_report(&study, &rows, &out).unwrap();
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("; solver `penalty`: the penalty DEM, explicit dynamics with contact dashpots"),
        "{report}"
    );
    assert!(!report.contains("NSGS"), "{report}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The rows without their wall times.
fn rows_of(rows: &[RealizationRow]) -> Vec<RealizationRow> {
    rows.iter().map(|r| RealizationRow { wall_time_s: 0.0, ..r.clone() }).collect()
}

/// A study with every kind of motion (a CSV record beside the study file, a generated
/// motion, a pulse) gives the same rows on 1 and 2 threads, and in two shards merged
/// (the merge rebuilds the study from the stored inputs, the record among them).
#[test]
fn rows_are_the_same_on_any_thread_count_and_sharded_then_merged() {
    let dir = scratch("determinism");
    std::fs::create_dir_all(dir.join("records")).unwrap();
    let mut record = String::from("# a one-sine pulse of 0.4 s, 0.5 g\ntime_s,accel_g\n");
    for k in 0..=400 {
        let t = k as f64 * 0.001;
        let _ = std::fmt::Write::write_fmt(
            &mut record,
            format_args!("{t},{}\n", 0.5 * (std::f64::consts::TAU * t / 0.4).sin()),
        );
    }
    std::fs::write(dir.join("records/pulse04.csv"), record).unwrap();
    let shake = "pga_g = [0.15, 0.4, 0.9]\nrecords = [\"records/pulse04.csv\"]\n\
                 stochastic = { count = 1, duration_s = 1.0, envelope_peak_s = 0.4 }\n\
                 pulses = [{ kind = \"ricker\", amplitude_g = 1.0, period_s = 0.3 }]\ntail_s = 0.5";
    let path = block_study(&dir, shake, "nscd");
    let study = Study::from_file(&path).unwrap();
    assert_eq!(study.items().len(), 9);
    let on = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap();
        rows_of(&pool.install(|| run_study(&study, Shard::ALL)))
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert!(one.iter().all(|r| r.status.is_ok()), "{one:?}");
    assert!(one.iter().any(|r| r.status == Status::Collapsed) && one.iter().any(|r| r.status == Status::Stood));
    let shards: Vec<PathBuf> = (1..=2).map(|k| dir.join(format!("shard{k}"))).collect();
    for (k, d) in shards.iter().enumerate() {
        run_into(&study, &path, Shard::parse(&format!("{}/2", k + 1)).unwrap(), d, RunMode::default()).unwrap();
    }
    let merged = merge(&shards, &dir.join("merged")).unwrap();
    assert_eq!(rows_of(&merged.rows), one);
    std::fs::remove_dir_all(&dir).ok();
}

/// Bad shaking inputs are refused before anything runs, naming the file and line or the
/// key.
#[test]
fn bad_shaking_inputs_are_refused_naming_file_and_key() {
    let dir = scratch("bad");
    let err =
        |shake: &str, solver: &str| -> StudyError { Study::from_file(&block_study(&dir, shake, solver)).unwrap_err() };
    // A record file that is not there.
    let e = err("pga_g = [0.2]\nrecords = [\"missing.AT2\"]", "nscd");
    assert!(matches!(e, StudyError::Record { .. }), "{e}");
    let text = e.to_string();
    assert!(text.contains("shake.records[0]") && text.contains("missing.AT2"), "{text}");
    // A record with a NaN on line 6.
    std::fs::write(
        dir.join("nan.AT2"),
        "PEER NGA\nevent\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT=   .0100 SEC\n0.0 0.1\nNaN 0.0\n",
    )
    .unwrap();
    let text = err("pga_g = [0.2]\nrecords = [\"nan.AT2\"]", "nscd").to_string();
    assert!(text.contains("nan.AT2") && text.contains("line 6"), "{text}");
    // A static method of the penalty DEM.
    let table = "pga_g = [0.2]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }]";
    let text = err(table, "relaxation").to_string();
    assert!(text.contains("solver.kind") && text.contains("nscd") && text.contains("penalty"), "{text}");
    let text = err(&format!("{table}\ncontact_restitution = 1.2"), "penalty").to_string();
    assert!(text.contains("shake.contact_restitution"), "{text}");
    // Levels, motions, generated motions.
    let text = err("pga_g = [0.3, 0.2]\npulses = [{ kind = \"ricker\", amplitude_g = 1.0, period_s = 0.5 }]", "nscd");
    assert!(text.to_string().contains("shake.pga_g"), "{text}");
    let text = err("pga_g = [0.2]", "nscd").to_string();
    assert!(text.contains("shake") && text.contains("no motions"), "{text}");
    let text = err("pga_g = [0.2]\nstochastic = { count = 2, ground_frequency_hz = -1.0 }", "nscd").to_string();
    assert!(text.contains("shake.stochastic.ground_frequency_hz"), "{text}");
    let text = err("pga_g = [0.2]\nstochastic = { count = 0 }", "nscd").to_string();
    assert!(text.contains("shake.stochastic.count"), "{text}");
    let text = err("pga_g = [0.2]\nstochastic = { count = 1, duration = 3.0 }", "nscd").to_string();
    assert!(text.contains("shake.stochastic") && text.contains("duration"), "{text}");
    // `motion` and `pga_g` belong to [shake], not to [sweep]; [shake] needs protocol shake.
    let path = block_study(&dir, table, "nscd");
    let with_sweep = std::fs::read_to_string(&path).unwrap() + "[sweep]\npga_g = [0.1, 0.2]\n";
    std::fs::write(&path, with_sweep).unwrap();
    let text = Study::from_file(&path).unwrap_err().to_string();
    assert!(text.contains("sweep.pga_g") && text.contains("[shake]"), "{text}");
    let tilt = std::fs::read_to_string(block_study(&dir, table, "nscd")).unwrap().replace("\"shake\"\n", "\"tilt\"\n");
    std::fs::write(&path, tilt).unwrap();
    let text = Study::from_file(&path).unwrap_err().to_string();
    assert!(text.contains("shake") && text.contains("protocol = \"shake\""), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A shaking study without `[solver] kind` shakes by the non-smooth solver, as `drystone
/// shake` does; a tilting study without it keeps the penalty DEM; a shaking study that
/// names the penalty DEM keeps it.
#[test]
fn a_shaking_study_shakes_by_nscd_unless_it_names_another_solver() {
    let dir = scratch("default-solver");
    std::fs::write(dir.join("block.toml"), BLOCK).unwrap();
    let write = |name: &str, body: &str| {
        let path = dir.join(name);
        std::fs::write(
            &path,
            format!(
                "version = 1\nname = \"block_shake\"\nseed = 5\nrealizations = 1\n{body}\n[[groups]]\nname = \
                 \"block\"\nwall = \"block.toml\"\n"
            ),
        )
        .unwrap();
        path
    };
    let table = "[shake]\npga_g = [0.2]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }]";
    let shake = Study::from_file(&write("shake.toml", &format!("protocol = \"shake\"\n{table}"))).unwrap();
    assert_eq!(shake.solver.kind, drystone::dem::SolverKind::Nscd);
    let penalty = write("penalty.toml", &format!("protocol = \"shake\"\n[solver]\nkind = \"penalty\"\n{table}"));
    assert_eq!(Study::from_file(&penalty).unwrap().solver.kind, drystone::dem::SolverKind::Penalty);
    let tilt = Study::from_file(&write("tilt.toml", "")).unwrap();
    assert_eq!(tilt.solver.kind, drystone::dem::SolverKind::Penalty);
}

/// A shaking study by `nscd` says how many steps missed the natural-map tolerance, as
/// `drystone shake` does: `realizations.csv` has the columns `unconverged_steps` and
/// `max_natural_residual`, and the report a line with their sum over the runs. The sweeps
/// cut at one per step (`step_solver = "nsgs"`, `max_iterations = 1`) cannot solve the
/// block's rocking impacts, so the count is positive; by its definition it is at most the
/// steps taken, and it is zero exactly when the largest residual meets the tolerance.
#[test]
fn a_shaking_study_counts_its_unconverged_steps_in_its_rows_and_report() {
    let dir = scratch("unconverged");
    std::fs::write(dir.join("block.toml"), BLOCK).unwrap();
    let text = "version = 1\nname = \"block_shake\"\nseed = 5\nrealizations = 1\nprotocol = \"shake\"\n\
                [solver]\nkind = \"nscd\"\n[solver.nscd]\nstep_solver = \"nsgs\"\nmax_iterations = 1\n\
                [shake]\npga_g = [0.6]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.3 }]\n\
                tail_s = 0.5\n[[groups]]\nname = \"block\"\nwall = \"block.toml\"\n";
    let path = dir.join("study.toml");
    std::fs::write(&path, text).unwrap();
    let study = Study::from_file(&path).unwrap();
    let out = dir.join("out");
    run_into(&study, &path, Shard::ALL, &out, RunMode::default()).unwrap();
    let csv = std::fs::read_to_string(out.join("realizations.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let cell =
        |name: &str| row[header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("{name} in {header:?}"))];
    let unconverged: u64 = cell("unconverged_steps").parse().unwrap();
    let steps: u64 = cell("steps").parse().unwrap();
    let worst: f64 = cell("max_natural_residual").parse().unwrap();
    assert!(unconverged > 0 && unconverged <= steps, "{unconverged} of {steps} steps unconverged");
    assert!(worst > study.solver.nscd.natural_tolerance, "largest residual {worst:e} with {unconverged} unconverged");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains(&format!("{unconverged} of {steps} steps, in 1 of 1 run(s)")),
        "no count of unconverged steps in the report: {report}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A shaking study names by key every setting it accepts and does not read, as `drystone
/// run`, `discrepancy` and `design` print them: `[tilt] by_hand`, a `[lateral]` key,
/// `[measured]`, the tilting table's `table_kick` effect, and, by the penalty DEM, a
/// `[solver.nscd]` key other than the pulses' sampling step `dt_s` (the command line
/// refuses `--nscd-*` without `--solver nscd`); the same study without them warns of none.
#[test]
fn a_shaking_study_warns_of_the_keys_it_does_not_read() {
    let dir = scratch("ignored-keys");
    std::fs::write(dir.join("block.toml"), BLOCK).unwrap();
    let body = |solver: &str, extra: &str| {
        format!(
            "version = 1\nname = \"block_shake\"\nseed = 5\nrealizations = 1\nprotocol = \"shake\"\n{extra}\n\
             [solver]\nkind = \"{solver}\"\n[solver.nscd]\ndt_s = 5e-4\nnatural_tolerance = 1e-5\n\
             [shake]\npga_g = [0.2]\npulses = [{{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }}]\n\
             [[groups]]\nname = \"block\"\nwall = \"block.toml\"\n"
        )
    };
    let warnings = |text: String| {
        let path = dir.join("study.toml");
        std::fs::write(&path, text).unwrap();
        Study::from_file(&path).unwrap().warnings()
    };
    let extra = "[effects]\ntable_kick = { overshoot_deg = 1.0 }\n[tilt]\nby_hand = { increment_deg = 5.0 }\n\
                 [lateral]\npressure_base_pa = 2000.0\n[measured]\n";
    let w = warnings(body("nscd", extra));
    for key in ["tilt.by_hand", "lateral.pressure_base_pa", "measured", "effects.table_kick"] {
        assert!(w.iter().any(|m| m.starts_with(&format!("{key} is not read"))), "{key} not warned of: {w:?}");
    }
    assert!(!w.iter().any(|m| m.contains("solver.nscd")), "nscd reads its table: {w:?}");
    let w = warnings(body("penalty", ""));
    assert!(w.iter().any(|m| m.starts_with("solver.nscd.natural_tolerance is not read")), "{w:?}");
    assert!(!w.iter().any(|m| m.contains("solver.nscd.dt_s")), "the pulses are sampled at dt_s: {w:?}");
    assert!(warnings(body("nscd", "")).is_empty());
    // Settings that cost more than they save: a natural-map tolerance below what rounding
    // leaves, an iteration cap that sends the capped steps to the cone programs.
    let costly = body("nscd", "").replace("natural_tolerance = 1e-5", "natural_tolerance = 1e-12\nmax_iterations = 20");
    let w = warnings(costly);
    for key in ["solver.nscd.natural_tolerance = 1e-12", "solver.nscd.max_iterations = 20"] {
        assert!(w.iter().any(|m| m.starts_with(key)), "{key} not warned of: {w:?}");
    }
    // `drystone discrepancy` and `design` print them too (before they refuse a study with
    // no measured data).
    let path = dir.join("study.toml");
    std::fs::write(&path, body("nscd", extra)).unwrap();
    for command in ["discrepancy", "design"] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_drystone")).arg(command).arg(&path).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("warning: tilt.by_hand is not read"), "{command}: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
