//! The tilting table rolled by hand (`loading::tilt_hand`) and its quasi-static equivalent
//! (the effect `table_kick`) against closed forms.
//!
//! * **A sliding block under the stops.** A flat block (0.2 m wide, 0.05 m high) on a
//!   frictional table (φ = 30°) whose axis is 1 m below the surface, rolled at 10°/s in 5°
//!   increments with starts and stops of 0.05 s: the block does not slide under the tilt
//!   alone below 30°, but every stop pushes it downhill by `α̈ L` (L the centroid's height
//!   above the axis) and from the 15° stop on the push beats the friction margin. The
//!   reference is the one-degree-of-freedom stick–slip of a rigid block in the rotating
//!   frame, integrated here at 1 µs from the table's motion written out anew (drive
//!   `g sin α − α̈ L`, friction `μ (g cos α − α̇² L)`; Coriolis left out as in the solver):
//!   the slip after each hold matches it.
//! * **A table rolled slowly is the quasi-static test.** With starts and stops of 0.5 s at
//!   1°/s the same block does not move at all below its friction angle.
//! * **The overshoot's closed form.** A rigid block b × h topples at `tan α = b / h`; with
//!   the table's overshoot Δ (`table_kick`) every 5° stop s loads it to s + Δ, so it
//!   topples at the 15° stop when 15° + Δ reaches `atan(b / h)` = 16.86°, and at its static
//!   angle when it does not, in both the penalty and the rigid test.
//! * **The dynamic kicks lie between the static angle and its peak-kick equivalent.** A
//!   slender block rolled by hand topples no later than the static `atan(b/h)` and no earlier
//!   than the angle the stops' peak push would give as a sustained inclination.

use drystone::dem::SolverParams;
use drystone::effects::{Effect, Library, Stage};
use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::loading::tilt_hand::{run_tilt_by_hand, HandTilt};
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::nscd::NscdParams;
use drystone::protocol::run_tilt;
use drystone::verify::{box_vertices, layout_of, RIGID_KN};

const G: f64 = 9.81;

fn block(b: f64, h: f64, friction_deg: f64) -> Layout {
    let blocks = vec![box_vertices([0.0, -b / 2.0, 0.0], [0.2, b / 2.0, h])];
    let mut l = layout_of(blocks, RIGID_KN, RIGID_KN / 2.0, friction_deg, BaseSliding::Free);
    l.gravity = G;
    l
}

/// The table's angle, speed and acceleration at time `t` of the whole test, written out
/// anew from the protocol's description (increments of `inc` degrees at `rate` deg/s,
/// ramps of `tau` s, holds of `hold` s).
fn table(t: f64, inc: f64, rate: f64, tau: f64, hold: f64) -> (f64, f64, f64) {
    let w = rate.to_radians();
    let a = w / tau;
    let roll = inc / rate + tau;
    let period = roll + hold;
    let k = (t / period).floor();
    let s = t - k * period;
    let base = (k * inc).to_radians();
    if s < tau {
        (base + a * s * s / 2.0, a * s, a)
    } else if s < roll - tau {
        (base + w * tau / 2.0 + w * (s - tau), w, 0.0)
    } else if s < roll {
        let r = roll - s;
        (base + inc.to_radians() - a * r * r / 2.0, a * r, -a)
    } else {
        (base + inc.to_radians(), 0.0, 0.0)
    }
}

/// Slip (m, downhill positive) of a rigid block at the end of each hold, by stick–slip of
/// one degree of freedom in the rotating frame (see the module doc).
fn reference_slips(mu: f64, lever: f64, hand: &HandTilt, increments: usize) -> Vec<f64> {
    let dt = 1e-6;
    let period = hand.increment_deg / hand.rate_deg_per_s + hand.ramp_s + hand.hold_s;
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let mut out = Vec::new();
    let steps = (period / dt).round() as usize;
    for _ in 0..increments {
        for n in 0..steps {
            let t = (out.len() * steps + n) as f64 * dt + dt / 2.0;
            let (al, w, acc) = table(t, hand.increment_deg, hand.rate_deg_per_s, hand.ramp_s, hand.hold_s);
            let drive = G * al.sin() - acc * lever;
            let cap = mu * (G * al.cos() - w * w * lever);
            if v == 0.0 {
                if drive.abs() > cap {
                    v += (drive - cap * drive.signum()) * dt;
                }
            } else {
                let nv = v + (drive - cap * v.signum()) * dt;
                v = if nv * v < 0.0 { 0.0 } else { nv };
            }
            x += v * dt;
        }
        out.push(x);
    }
    out
}

#[test]
fn a_sliding_block_slips_under_the_stops_as_the_rigid_stick_slip_gives() {
    let (b, h, phi) = (0.2, 0.05, 30.0f64);
    let layout = block(b, h, phi);
    let hand = HandTilt { increment_deg: 5.0, rate_deg_per_s: 10.0, ramp_s: 0.05, hold_s: 0.5, axis_depth_m: 1.0 };
    let tilt = TiltParams { max_angle_deg: 25.0, collapse_increment_fraction: 0.9, ..TiltParams::default() };
    let nscd = NscdParams { dt_s: 5e-4, ..NscdParams::default() };
    let r = run_tilt_by_hand(&layout, &nscd, &tilt, &hand).expect("runs");
    assert!(r.first_unstable_deg.is_none(), "the block slides but stays on the table: {r:?}");
    let reference = reference_slips(phi.to_radians().tan(), h / 2.0 + hand.axis_depth_m, &hand, 5);
    let readings: Vec<(f64, f64)> = r
        .increments
        .iter()
        .filter(|i| i.stable && i.alpha_deg > 0.0)
        .map(|i| (i.alpha_deg, i.displacement_m.iter().sum::<f64>() / i.displacement_m.len() as f64))
        .collect();
    assert_eq!(readings.len(), 5, "{readings:?}");
    // Below 15° the stops do not beat the friction margin; from the 15° stop on they do.
    assert!(reference[1] == 0.0 && reference[2] > 5e-4 && reference[4] > 1e-2, "{reference:?}");
    for ((alpha, slip), want) in readings.iter().zip(&reference) {
        assert!(
            (slip - want).abs() <= 0.05 * want.abs() + 2e-4,
            "at {alpha}°: slip {slip:.5} m, the rigid stick-slip {want:.5} m"
        );
    }
}

#[test]
fn a_table_rolled_slowly_does_not_move_a_block_below_its_friction_angle() {
    let layout = block(0.2, 0.05, 30.0);
    let hand = HandTilt { increment_deg: 5.0, rate_deg_per_s: 1.0, ramp_s: 0.5, hold_s: 0.2, axis_depth_m: 0.34 };
    let tilt = TiltParams { max_angle_deg: 25.0, ..TiltParams::default() };
    let r = run_tilt_by_hand(&layout, &NscdParams::default(), &tilt, &hand).expect("runs");
    assert!(r.first_unstable_deg.is_none());
    for inc in &r.increments {
        for d in &inc.displacement_m {
            assert!(d.abs() < 1e-5, "moved {d} m at {}°", inc.alpha_deg);
        }
    }
}

fn with_overshoot(layout: &Layout, overshoot_deg: f64) -> Layout {
    let lib = Library::builtin();
    let def = lib.get("table_kick").expect("a built-in");
    let e = Effect::new(def, vec![overshoot_deg], 0.05).expect("in range");
    let mut l = layout.clone();
    let mut rng = drystone::effects::effect_rng(1, 0, "g", "table_kick");
    for stage in [Stage::Layout, Stage::JointLaw, Stage::Restraints] {
        e.apply_stage(stage, &mut l, &[], &mut rng).expect("applies");
    }
    assert_eq!(l.table_overshoot_deg, overshoot_deg);
    l
}

#[test]
fn the_overshoot_topples_a_rigid_block_at_the_stop_within_it_of_its_static_angle() {
    let (b, h) = (0.1f64, 0.33f64);
    let exact = (b / h).atan().to_degrees();
    let layout = block(b, h, 60.0);
    // The static angle 16.86°. Δ = 1°: 15° + 1° < 16.86°, the block topples at its static
    // angle; Δ = 2.5°: 15° + 2.5° ≥ 16.86°, at the 15° stop (the last stable tilt just
    // below it, to the resolution).
    for (overshoot, want) in [(0.0, exact), (1.0, exact), (2.5, 15.0)] {
        let l = with_overshoot(&layout, overshoot);
        let params = TiltParams { resolution_deg: 0.05, ..TiltParams::default() };
        let rigid = run_tilt_nscd(&l, &NscdParams::default(), &params).expect("stands");
        let tol = if overshoot > exact - 15.0 { 0.06 } else { 0.1 };
        assert!(
            (rigid.collapse_angle_deg() - want).abs() <= tol,
            "nscd, overshoot {overshoot}: {} against {want}",
            rigid.collapse_angle_deg()
        );
        let penalty = run_tilt(&l, SolverParams::default(), &params).expect("stands");
        assert!(
            (penalty.collapse_angle_deg() - want).abs() <= 0.25,
            "penalty, overshoot {overshoot}: {} against {want}",
            penalty.collapse_angle_deg()
        );
    }
}

#[test]
fn kicks_topple_a_slender_block_between_its_static_angle_and_the_peak_kicks_equivalent() {
    let (b, h) = (0.1f64, 0.3f64);
    let exact = (b / h).atan().to_degrees();
    let layout = block(b, h, 60.0);
    let hand = HandTilt { increment_deg: 2.0, rate_deg_per_s: 4.0, ramp_s: 0.05, hold_s: 0.5, axis_depth_m: 0.34 };
    let tilt = TiltParams { max_angle_deg: 30.0, ..TiltParams::default() };
    let r = run_tilt_by_hand(&layout, &NscdParams::default(), &tilt, &hand).expect("runs");
    let alpha = r.collapse_angle_deg();
    assert!(r.first_unstable_deg.is_some(), "topples");
    // The stops' peak push at the centroid as a sustained inclination.
    let peak = (hand.peak_angular_acceleration() * (h / 2.0 + hand.axis_depth_m) / G).atan().to_degrees();
    assert!(peak > 1.0, "a kick worth testing: {peak}");
    assert!(alpha <= exact + 0.05, "{alpha} above the static {exact}");
    assert!(alpha >= exact - peak - 2.0, "{alpha} below the peak kick's {}", exact - peak);
}

/// `[tilt] by_hand` in a study runs the hand-rolled table on every realization: each row's
/// collapse angle is the one `drystone tilt --solver nscd --by-hand` gives on the same
/// generated layout (the command line's own path, run as a separate process).
#[test]
fn a_study_rolled_by_hand_gives_the_command_lines_angles() {
    use drystone::ensemble::Shard;
    use drystone::study::{run_study, Study};
    use std::process::Command;
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let study = Study::from_file(&root.join("tests/studies/good/mini_by_hand.toml")).expect("a valid study");
    let rows = run_study(&study, Shard::ALL);
    assert_eq!(rows.len(), 2);
    let dir = std::env::temp_dir().join(format!("drystone-by-hand-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bin = env!("CARGO_BIN_EXE_drystone");
    for r in &rows {
        let layout = dir.join(format!("r{}.json", r.realization));
        let wall = root.join("tests/studies/walls/tiny_running_bond.toml");
        let ok = Command::new(bin)
            .args(["generate", wall.to_str().unwrap(), "--seed", "7", "--realization", &r.realization.to_string()])
            .args(["--out", layout.to_str().unwrap()])
            .status()
            .unwrap();
        assert!(ok.success());
        let out = Command::new(bin)
            .args(["tilt", layout.to_str().unwrap(), "--json", "--solver", "nscd", "--by-hand"])
            .args([
                "--hand-increment-deg",
                "10",
                "--hand-rate-deg-s",
                "10",
                "--hand-hold-s",
                "0.1",
                "--resolution-deg",
                "0.25",
            ])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(r.collapse.collapse_angle_deg, v["collapse_angle_deg"].as_f64(), "realization {}", r.realization);
    }
    std::fs::remove_dir_all(&dir).ok();
    // A study that asks the penalty DEM to roll the table by hand is refused naming the key
    // (tests/studies/bad/by_hand_penalty.toml).
}

/// The last increment stops at the largest tilt: a block that stands to it is read there,
/// not one increment beyond.
#[test]
fn a_wall_that_stands_is_read_at_the_largest_tilt() {
    let layout = block(0.2, 0.05, 60.0);
    let hand = HandTilt { hold_s: 0.1, ..HandTilt::default() };
    let tilt = TiltParams { max_angle_deg: 12.0, ..TiltParams::default() };
    let r = run_tilt_by_hand(&layout, &NscdParams::default(), &tilt, &hand).expect("runs");
    assert!(r.first_unstable_deg.is_none());
    assert_eq!(r.last_stable_deg, 12.0);
    let stops: Vec<f64> = r.increments.iter().map(|i| i.alpha_deg).collect();
    assert_eq!(stops, vec![0.0, 5.0, 10.0, 12.0]);
}

/// A slender block (b/h = 1/15: it topples at atan(b/h) = 3.8°, inside the first 5°
/// increment) rolled by hand: the mechanism of a wall that fails in the first increment is
/// read like any other's, the block toppling about its toe on the table, not "none".
#[test]
fn a_block_that_topples_in_the_first_increment_has_its_mechanism() {
    use drystone::loading::tilt::MechanismKind;
    let (b, h) = (0.02f64, 0.3f64);
    let layout = block(b, h, 40.0);
    let r = run_tilt_by_hand(&layout, &NscdParams::default(), &TiltParams::default(), &HandTilt::default()).unwrap();
    assert!(r.collapse_angle_deg() < 5.0, "fails in the first increment: {}", r.collapse_angle_deg());
    assert_eq!(r.mechanism.kind, MechanismKind::Toppling, "{:?}", r.mechanism);
    assert_eq!(r.mechanism.joint, "table/b0");
    let reading = r.mechanism.reading.expect("a reading");
    assert_eq!(reading.failure_height_fraction, 0.0);
}

/// The library refuses a hand-rolled motion it cannot run as asked, before anything runs,
/// as the command line (`--hand-*`) and the study reader (`tilt.by_hand.*`) do: starts and
/// stops longer than the roll (the table would pass the increment), a roll or holds so
/// slow that the largest tilt is not reached within 2e7 steps, a stop shorter than 5 time
/// steps. Each is `TiltError::Parameter` naming the field of `HandTilt`, the error
/// `HandTilt::validate` or `HandTilt::check_run` gives the callers; `run_tilt`'s dispatch
/// gives the same.
#[test]
fn a_hand_rolled_motion_out_of_range_is_refused_by_the_library_naming_the_field() {
    use drystone::dem::SolverKind;
    use drystone::loading::tilt::TiltError;
    let layout = block(0.2, 0.05, 30.0);
    let nscd = NscdParams::default();
    let tilt = TiltParams::default();
    let d = HandTilt::default();
    let cases = [
        (HandTilt { ramp_s: 5.0, ..d }, "ramp_s", "within the roll", false),
        (HandTilt { rate_deg_per_s: 1e-6, ..d }, "rate_deg_per_s", "2e7", true),
        (HandTilt { increment_deg: 0.5, rate_deg_per_s: 0.5, hold_s: 600.0, ..d }, "hold_s", "2e7", true),
        (HandTilt { ramp_s: 2.0 * nscd.dt_s, ..d }, "ramp_s", "5 time steps", true),
    ];
    for (hand, key, words, by_run) in cases {
        // What the callers check.
        let theirs =
            if by_run { hand.check_run(nscd.dt_s, tilt.max_angle_deg) } else { hand.validate() }.expect_err(key);
        let solver = SolverParams { kind: SolverKind::Nscd, nscd, ..SolverParams::default() };
        for r in [
            run_tilt_by_hand(&layout, &nscd, &tilt, &hand),
            run_tilt(&layout, solver, &TiltParams { by_hand: Some(hand), ..tilt }),
        ] {
            match r {
                Err(TiltError::Parameter(p)) => {
                    assert_eq!(p.key, key, "{hand:?}");
                    assert!(p.allowed.contains(words), "{hand:?}: {p}");
                    assert_eq!(p, theirs);
                }
                other => panic!("{hand:?}: {other:?}"),
            }
        }
    }
}
