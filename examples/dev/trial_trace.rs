//! Traces tilt trials: settles a layout, tilts it by 0.5° increments to equilibrium up to
//! `LAST_STABLE` degrees, then from that state runs one trial per given angle and prints,
//! every 64 steps (until the increment limit of 5 % of the wall width), the largest block motion since the start of the trial (centroid motion
//! plus rotation times radius, m), the kinetic energy (J) and the unbalanced-force ratio.
//!
//! `cargo run --release --example trial_trace -- LAYOUT.json LAST_STABLE ANGLE... > trace.csv`

mod common;

use drystone::dem::SolverParams;

fn main() {
    let args = common::args(3, "trial_trace LAYOUT.json LAST_STABLE ANGLE...");
    let layout = common::layout(&args[0]);
    let last: f64 = common::number(&args[1], "LAST_STABLE");
    let angles: Vec<f64> = args[2..].iter().map(|s| common::number(s, "ANGLE")).collect();
    // The wall width of the collapse criteria (as in `loading::tilt`).
    let width = layout.bounds().extent().y;
    let sim = common::settled_at(&layout, last, SolverParams::default());
    eprintln!("reached {last} deg after {} steps", sim.state.steps);
    println!("angle,step,moved_m,ke_j,ratio");
    for a in angles {
        let mut t = sim.clone();
        t.set_tilt(a.to_radians());
        let start: Vec<_> = t.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
        for s in 1..=40_000u64 {
            t.step().unwrap();
            if s > 10 && t.stats().unbalanced_ratio < 1e-4 {
                println!("{a},{s},stable,,");
                break;
            }
            if s % 64 == 0 {
                let moved = drystone::loading::monitors::largest_motion(&t, &start);
                println!("{a},{s},{moved:e},{:e},{:e}", t.stats().kinetic_energy, t.stats().unbalanced_ratio);
                if moved > 0.05 * width {
                    break;
                }
            }
        }
    }
}
