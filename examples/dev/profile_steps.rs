//! Profiling harness: settles a layout at α = 0, tilts it and takes a fixed number of
//! steps, then prints a checksum of the state (bit-level, to check that an optimization
//! leaves the results unchanged) and the contact counts.
//!
//! `cargo run --release --example profile_steps -- LAYOUT.json [STEPS] [TILT_DEG]`

mod common;

use drystone::dem::RunToEquilibrium;
use drystone::dem::{Simulation, SolverParams};
use std::time::Instant;

fn main() {
    let args = common::args(1, "profile_steps LAYOUT.json [STEPS] [TILT_DEG]");
    let layout = common::layout(&args[0]);
    let steps: u64 = args.get(1).map_or(2000, |s| common::number(s, "STEPS"));
    let tilt: f64 = args.get(2).map_or(10.0, |s| common::number(s, "TILT_DEG"));
    let mut sim = Simulation::new(&layout, SolverParams::default());
    let t0 = Instant::now();
    let settled = sim.run_to_equilibrium(1e-4, 400_000).unwrap();
    let settle_steps = sim.state.steps;
    sim.set_tilt(tilt.to_radians());
    let t1 = Instant::now();
    for _ in 0..steps {
        sim.step().unwrap();
    }
    let el = t1.elapsed().as_secs_f64();
    let mut h: u64 = 0xcbf29ce484222325;
    let mut mix = |v: f64| {
        h ^= v.to_bits();
        h = h.wrapping_mul(0x100000001b3);
    };
    for b in &sim.state.bodies {
        b.pos.iter().chain(b.vel.iter()).chain(b.angvel.iter()).chain(b.rot.coords.iter()).for_each(|&v| mix(v));
    }
    for c in &sim.state.contacts {
        c.force.iter().for_each(|&v| mix(v));
        for s in &c.subs {
            s.state.shear.iter().for_each(|&v| mix(v));
            mix(s.state.normal);
        }
    }
    mix(sim.stats().unbalanced_ratio);
    let subs: usize = sim.state.contacts.iter().map(|c| c.subs.len()).sum();
    let loaded: usize = sim.state.contacts.iter().flat_map(|c| &c.subs).filter(|s| s.state.normal != 0.0).count();
    let nodes: usize = sim.state.contacts.iter().map(|c| c.nodes.len()).sum();
    println!(
        "settled {settled} in {settle_steps} steps ({:.2} s); {steps} steps at {tilt} deg in {el:.3} s ({:.1} us/step)",
        (t1 - t0).as_secs_f64(),
        1e6 * el / steps as f64
    );
    println!(
        "bodies {} contacts {} subs {subs} loaded subs {loaded} nodes {nodes} detections {} dt {:e}",
        sim.state.bodies.len(),
        sim.state.contacts.len(),
        sim.detections(),
        sim.dt()
    );
    println!("ratio {:e} checksum {h:016x}", sim.stats().unbalanced_ratio);
}
