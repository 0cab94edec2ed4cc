//! The rigid-limit table: the collapse tilt of rigid-block layouts by non-smooth contact
//! dynamics (`run_tilt_nscd`, a static bisection to 0.05°) beside the exact rigid limit and
//! LMGC90's bisection of the same layout (`data/lmgc90_rigid_limits.csv`), with the time
//! of each.
//!
//! ```sh
//! cargo run --release --example rigid_limits            # every case
//! cargo run --release --example rigid_limits -- running_bond_13   # the cases named
//! cargo run --release --example rigid_limits -- wall.json          # any layout file
//! cargo run --release --example rigid_limits -- --cost a.json b.json  # cost of one trial
//! ```
//!
//! `NSCD='{"norm":"quad","tolerance":1e-5}'` before the command sets solver parameters
//! (a JSON object of `NscdParams` keys over the defaults).
//!
//! `--cost` runs one tilt trial's worth of steps (40, at 10°, released from rest) on each
//! layout and prints the blocks, contact points, time per step and sweeps per step: the
//! cost against wall size.

use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::nscd::NscdParams;
use drystone::verify::{box_vertices, layout_of, trapezoid_block};
use std::path::Path;

/// (case, layout, exact rigid limit in degrees).
fn cases() -> Vec<(String, Layout, f64)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = |p: &str| Layout::from_file(&root.join(p)).expect("layout");
    let mut out = vec![
        ("single_block".to_string(), file("data/layouts/rigid/single_block.json"), 0.5f64.atan().to_degrees()),
        ("offset_stack".into(), file("data/layouts/rigid/offset_stack.json"), (0.03f64 / 0.075).atan().to_degrees()),
        ("running_bond_13".into(), file("data/layouts/rigid/running_bond_13.json"), (1.0f64 / 3.0).atan().to_degrees()),
    ];
    // Boxes b (y) × h (z), 0.3 m long, friction 60°: toppling at tan α = b / h.
    for (b, h) in [(0.05, 0.15), (0.1, 0.25), (0.25, 0.5), (0.5, 1.0), (1.0, 1.25)] {
        let l =
            layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [0.3, b / 2.0, h])], 1e13, 5e12, 60.0, BaseSliding::Free);
        out.push((format!("box_{b}x{h}"), l, (b / h).atan().to_degrees()));
    }
    // A squat box sliding at tan α = tan φ.
    for phi in [20.0, 30.0] {
        let l = layout_of(vec![box_vertices([0.0, -0.15, 0.0], [0.3, 0.15, 0.1])], 1e13, 5e12, phi, BaseSliding::Free);
        out.push((format!("sliding_phi{phi}"), l, phi));
    }
    // Symmetric trapezoids (base B, top T, height H): tan α = 3B(B + T) / (2H(B + 2T)).
    for (bb, tt, hh) in [(0.15, 0.077, 0.375), (0.6, 0.3, 1.0)] {
        let l = layout_of(vec![trapezoid_block(bb, tt, hh)], 1e13, 5e12, 60.0, BaseSliding::Free);
        let exact = (3.0 * bb * (bb + tt) / (2.0 * hh * (bb + 2.0 * tt))).atan().to_degrees();
        out.push((format!("trapezoid_{bb}_{tt}_{hh}"), l, exact));
    }
    out
}

/// LMGC90's (last stable, first unstable, seconds) of a case, if the table has it.
fn lmgc90(case: &str) -> Option<(f64, f64, f64)> {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lmgc90_rigid_limits.csv")).ok()?;
    let row: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect())
        .find(|r: &Vec<&str>| r[0] == case)?;
    Some((row[2].parse().ok()?, row[3].parse().ok()?, row[6].parse().ok()?))
}

/// The solver's parameters: the defaults, or the keys of the JSON object in the
/// environment variable `NSCD` over them (e.g. `NSCD='{"norm":"quad","tolerance":1e-5}'`).
fn nscd_params() -> NscdParams {
    match std::env::var("NSCD") {
        Ok(s) => serde_json::from_str(&s).expect("NSCD: a JSON object of NscdParams keys"),
        Err(_) => NscdParams::default(),
    }
}

/// One trial's steps at 10° on each layout: blocks, points, seconds and sweeps per step.
fn cost(files: &[String]) {
    use drystone::nscd::NscdSimulation;
    println!("| layout | blocks | contact points | s per step | sweeps per step | s per trial (40 steps) |");
    println!("| --- | --- | --- | --- | --- | --- |");
    for f in files {
        let l = Layout::from_file(Path::new(f)).expect("layout");
        let params = nscd_params();
        let t0 = std::time::Instant::now();
        let mut sim = NscdSimulation::new(&l, &params).expect("simulation");
        sim.set_tilt(10f64.to_radians());
        let n = params.trial_steps;
        for _ in 0..n {
            sim.step(|_| drystone::Vec3::zeros()).expect("step");
        }
        let s = t0.elapsed().as_secs_f64();
        println!(
            "| {f} | {} | {} | {:.4} | {:.0} | {s:.2} |",
            l.blocks.len(),
            sim.contact_points().len(),
            s / f64::from(n),
            sim.iterations() as f64 / f64::from(n)
        );
    }
}

fn main() {
    let only: Vec<String> = std::env::args().skip(1).collect();
    if only.first().is_some_and(|a| a == "--cost") {
        return cost(&only[1..]);
    }
    let params = nscd_params();
    let tilt = TiltParams { resolution_deg: 0.05, ..TiltParams::default() };
    println!(
        "| case | exact (°) | nscd bracket (°) | contains exact | LMGC90 (°) | nscd time (s) | LMGC90 time (s) | trials | steps | mechanism |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut all = cases();
    for f in only.iter().filter(|a| a.ends_with(".json")) {
        all.push((f.clone(), Layout::from_file(Path::new(f)).expect("layout"), f64::NAN));
    }
    for (name, layout, exact) in all {
        if !only.is_empty() && !only.contains(&name) {
            continue;
        }
        let r = run_tilt_nscd(&layout, &params, &tilt).expect("tilt");
        let up = r.first_unstable_deg.unwrap_or(f64::NAN);
        if std::env::var_os("RIGID_LIMITS_TRACE").is_some() {
            for i in &r.increments {
                eprintln!("{name} {:.4} stable {} steps {} sweeps {}", i.alpha_deg, i.stable, i.steps, i.iterations);
            }
        }
        let (lm, lt) = match lmgc90(&name) {
            Some((lo, hi, s)) => (format!("[{lo:.4}, {hi:.4}]"), format!("{s:.1}")),
            None => ("".into(), "".into()),
        };
        println!(
            "| {name} | {exact:.4} | [{:.4}, {up:.4}] | {} | {lm} | {:.3} | {lt} | {} | {} | {:?} {} |",
            r.last_stable_deg,
            r.last_stable_deg <= exact && exact <= up,
            r.wall_time_s,
            r.increments.len(),
            r.steps,
            r.mechanism.kind,
            r.mechanism.joint,
        );
    }
}
