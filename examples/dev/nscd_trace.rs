//! Traces the non-smooth solver's steps: a layout released from rest at a tilt, with the
//! NSGS sweeps, the last residual (over g h) and the largest block-point speed (over g h)
//! of each step, and the number of contact points per contact polygon.
//!
//! `NSCD='{"tolerance":1e-5}' cargo run --release --example nscd_trace -- LAYOUT.json TILT_DEG [STEPS]`
//! (`NSCD`: a JSON object of `NscdParams` keys overriding the defaults).

mod common;

use drystone::nscd::{NscdParams, NscdSimulation};
use std::collections::BTreeMap;

fn main() {
    let args = common::args(2, "nscd_trace LAYOUT.json TILT_DEG [STEPS]");
    // `box:B:H`: a box b (y) × h (z), 0.3 m long, friction 60°, on the table.
    let layout = match args[0].strip_prefix("box:") {
        Some(dims) => {
            let d: Vec<f64> = dims.split(':').map(|x| common::number(x, "box:B:H")).collect();
            drystone::verify::layout_of(
                vec![drystone::verify::box_vertices([0.0, -d[0] / 2.0, 0.0], [0.3, d[0] / 2.0, d[1]])],
                1e13,
                5e12,
                60.0,
                drystone::layout::BaseSliding::Free,
            )
        }
        None => common::layout(&args[0]),
    };
    let tilt: f64 = common::number(&args[1], "TILT_DEG");
    let steps: u64 = args.get(2).map_or(40, |s| common::number(s, "STEPS"));
    let params: NscdParams = match std::env::var("NSCD") {
        Ok(s) => serde_json::from_str(&s).expect("NSCD: NscdParams as JSON"),
        Err(_) => NscdParams::default(),
    };
    let t0 = std::time::Instant::now();
    let mut sim = NscdSimulation::new(&layout, &params).expect("simulation");
    let mut per_pair: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for c in sim.contact_points() {
        *per_pair.entry(c.key()).or_default() += 1;
    }
    let mut hist: BTreeMap<usize, usize> = BTreeMap::new();
    for n in per_pair.values() {
        *hist.entry(*n).or_default() += 1;
    }
    eprintln!(
        "blocks {} contacts {} points {} points per contact {hist:?}",
        sim.bodies().len(),
        per_pair.len(),
        sim.contact_points().len()
    );
    sim.set_tilt(tilt.to_radians());
    let gh = sim.gravity_magnitude() * params.dt_s;
    println!("step,sweeps,converged,residual_gh,quad,speed_gh,active,power_gh,drop_gh2");
    let start: Vec<drystone::Vec3> = sim.bodies().iter().map(|b| b.pos).collect();
    let gdir = drystone::Vec3::new(0.0, tilt.to_radians().sin(), -tilt.to_radians().cos());
    let mass: f64 = sim.bodies().iter().filter(|b| !b.fixed()).map(|b| b.mass).sum();
    for k in 1..=steps {
        let s = sim.step(|_| drystone::Vec3::zeros()).expect("step");
        let power: f64 =
            sim.bodies().iter().filter(|b| !b.fixed()).map(|b| b.mass * b.vel.dot(&gdir)).sum::<f64>() / mass / gh;
        let drop: f64 = sim
            .bodies()
            .iter()
            .zip(&start)
            .filter(|(b, _)| !b.fixed())
            .map(|(b, s)| b.mass * (b.pos - s).dot(&gdir))
            .sum::<f64>()
            / mass
            / (gh * params.dt_s);
        println!(
            "{k},{},{},{:.3e},{:.3e},{:.3e},{},{power:.3e},{drop:.3e}",
            s.iterations,
            s.converged,
            s.residual_m_per_s / gh,
            s.quad_residual,
            sim.max_point_speed() / gh,
            s.active
        );
    }
    eprintln!("{:.3} s, {} sweeps", t0.elapsed().as_secs_f64(), sim.iterations());
    // The fastest blocks at the end: id, mass (kg), speed over g h, contact points.
    let mut speeds: Vec<(f64, usize)> = sim
        .bodies()
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.fixed())
        .map(|(k, b)| ((b.vel.norm() + b.angvel.norm() * b.radius) / gh, k))
        .collect();
    speeds.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (v, k) in speeds.iter().take(8) {
        let b = &sim.bodies()[*k];
        let pts = sim.contact_points().iter().filter(|c| c.b == *k || c.a == Some(*k)).count();
        let carrying =
            sim.contact_points().iter().filter(|c| (c.b == *k || c.a == Some(*k)) && c.impulse.x > 0.0).count();
        eprintln!("  {} mass {:.3} kg speed {v:.3e} g h, points {pts} ({carrying} carrying)", b.id, b.mass);
    }
}
