//! At the stiff end of the penalty solver (Kn ≥ 1e11 Pa/m) dynamic relaxation may not
//! settle the light sub-contacts of a knife-edge joint within an increment's step budget:
//! such an increment is undecided (`step_budget`), and the tilt result
//! must say that its `[last_stable, first_unstable]` is not a bracket. The single block of
//! `data/layouts/rigid/single_block.json` (0.15 m wide, 0.30 m tall, 2500 kg/m³, Kn 1e13
//! Pa/m) collapses, on its Winkler joint, 0.09° below the rigid limit atan(1/2) = 26.565°
//! (`common/winkler_exact.rs`); on a budget of 20 000 steps the penalty protocol stops on
//! undecided increments half a degree below that.

use crate::winkler_exact;

use drystone::dem::{PenaltyParams, SolverParams};
use drystone::layout::Layout;
use drystone::loading::tilt::{CollapseReason, TiltParams};
use drystone::protocol::run_tilt;
use drystone::units::STANDARD_GRAVITY as G;
use std::path::Path;
use std::process::Command;
use winkler_exact::{Block, Interface};

const LAYOUT: &str = "data/layouts/rigid/single_block.json";
const BUDGET: u64 = 20_000;

fn layout() -> Layout {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(LAYOUT);
    Layout::from_file(&path).expect("the layout loads")
}

/// The exact collapse tilt of the block on its joint, degrees.
fn exact() -> f64 {
    winkler_exact::collapse(&Block::new(0.15, 0.30, 2500.0, G, 1e13), Interface::WINKLER).alpha_deg
}

#[test]
fn a_step_budget_at_kn_1e13_is_not_reported_as_a_bracket() {
    let l = layout();
    assert_eq!(l.materials[0].kn, 1e13);
    let p = TiltParams { resolution_deg: 0.0625, ..TiltParams::default() };
    let s = SolverParams {
        penalty: PenaltyParams { max_steps: BUDGET, ..PenaltyParams::default() },
        ..SolverParams::default()
    };
    let r = run_tilt(&l, s, &p).expect("stands");
    let up = r.first_unstable_deg.expect("an unstable trial");
    assert_eq!(r.collapse_reason, Some(CollapseReason::StepBudget));
    assert!(!r.bracket_reliable, "a step budget read as a bracket: [{}, {up}]", r.last_stable_deg);
    // Read as a bracket it would be wrong: the exact collapse lies above it.
    let exact = exact();
    assert!(up < exact - 0.25, "[{}, {up}] against the exact {exact}", r.last_stable_deg);
    // The same block on joints a decade and more softer settles within the budget: a
    // bracket, reliable, holding its exact collapse.
    let mut soft = layout();
    soft.materials[0].kn = 1e9;
    soft.materials[0].ks = 5e8;
    let r = run_tilt(&soft, s, &p).expect("stands");
    let up = r.first_unstable_deg.expect("topples");
    assert_ne!(r.collapse_reason, Some(CollapseReason::StepBudget));
    assert!(r.bracket_reliable);
    let blk = Block::new(0.15, 0.30, 2500.0, G, 1e9);
    let (lo, hi) = (
        winkler_exact::collapse(&blk, Interface::WINKLER).alpha_deg,
        winkler_exact::collapse(&blk, Interface::MID_PLANE).alpha_deg,
    );
    assert!(up >= lo - 0.01 && r.last_stable_deg <= hi + 0.01, "[{}, {up}] against [{lo}, {hi}]", r.last_stable_deg);
}

/// `drystone tilt` prints it, in the table and in the JSON.
#[test]
fn the_command_line_says_the_bracket_is_not_reliable() {
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join(LAYOUT);
    let run = |json: bool| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_drystone"));
        c.arg("tilt").arg(&layout).args(["--resolution-deg", "0.0625", "--max-steps", &BUDGET.to_string()]);
        if json {
            c.arg("--json");
        }
        let out = c.output().expect("drystone runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).expect("utf-8")
    };
    let v: serde_json::Value = serde_json::from_str(&run(true)).expect("one JSON object");
    assert_eq!(v["bracket_reliable"], serde_json::Value::Bool(false), "{v}");
    assert_eq!(v["collapse_reason"], "step_budget");
    let text = run(false);
    assert!(text.contains("NOT RELIABLE"), "{text}");
}
