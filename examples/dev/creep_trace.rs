//! Which bodies move during a slow near-collapse increment: settles a layout, tilts it by
//! 0.5° increments to equilibrium up to `LAST_STABLE` degrees, then tilts it to `TRIAL` and
//! prints every 2,000 steps the unbalanced-force ratio, the mean body speed (m/s, centroid
//! speed plus angular speed times radius) and the six fastest bodies with their speed and
//! their motion since the start of the trial (m), until equilibrium or 60,000 steps.
//!
//! `cargo run --release --example creep_trace -- LAYOUT.json LAST_STABLE TRIAL`

mod common;

use drystone::dem::SolverParams;

fn main() {
    let args = common::args(3, "creep_trace LAYOUT.json LAST_STABLE TRIAL");
    let layout = common::layout(&args[0]);
    let last: f64 = common::number(&args[1], "LAST_STABLE");
    let trial: f64 = common::number(&args[2], "TRIAL");
    let mut sim = common::settled_at(&layout, last, SolverParams::default());
    sim.set_tilt(trial.to_radians());
    let start: Vec<_> = sim.state.bodies.iter().map(|b| b.pos).collect();
    for s in 1..=60_000u64 {
        sim.step().unwrap();
        if s > 10 && sim.stats().unbalanced_ratio < 1e-4 {
            println!("stable at {s}");
            break;
        }
        if s % 2000 == 0 {
            let mut v: Vec<(f64, usize)> = sim
                .state
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| (b.vel.norm() + b.angvel.norm() * b.radius, i))
                .collect();
            v.sort_by(|a, b| b.0.total_cmp(&a.0));
            let mean: f64 = v.iter().map(|x| x.0).sum::<f64>() / v.len() as f64;
            let top: Vec<String> = v
                .iter()
                .take(6)
                .map(|(sp, i)| {
                    format!(
                        "{}:{:.1e}/{:.1e}m",
                        sim.state.bodies[*i].id,
                        sp,
                        (sim.state.bodies[*i].pos - start[*i]).norm()
                    )
                })
                .collect();
            println!("{s} ratio {:.2e} mean speed {:.1e} top {}", sim.stats().unbalanced_ratio, mean, top.join(" "));
        }
    }
}
