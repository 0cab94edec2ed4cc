//! Generate a wall, tilt it to collapse and print the result, through the library API.
//!
//! ```sh
//! cargo run --release --example tilt_a_wall [-- WALL.toml [SEED [REALIZATION]]]
//! ```
//!
//! By default: the small irregular test wall of `tests/discrepancy/walls/small_free.toml`
//! (34 blocks, under a second).

use drystone::dem::SolverParams;
use drystone::generator::{generate, Wall};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let wall_file =
        args.first().map_or_else(|| PathBuf::from("tests/discrepancy/walls/small_free.toml"), PathBuf::from);
    let seed: u64 = args.get(1).map_or(Ok(2021), |s| s.parse())?;
    let realization: u64 = args.get(2).map_or(Ok(0), |s| s.parse())?;

    // A wall description (TOML) -> one seeded realization -> a checked layout.
    let wall = Wall::from_file(&wall_file)?;
    let layout = generate(&wall, seed, realization)?.check()?;
    println!("{}: {} blocks (seed {seed}, realization {realization})", wall_file.display(), layout.blocks.len());

    // The tilting-table test to collapse, default solver and protocol parameters.
    let result = run_tilt(&layout, SolverParams::default(), &TiltParams::default())?;
    println!(
        "collapse angle α_max = {:.3}° (next trial {:?}°), {:?} at joint {} ({} blocks moved)",
        result.collapse_angle_deg(),
        result.first_unstable_deg,
        result.mechanism.kind,
        result.mechanism.joint,
        result.mechanism.blocks.len()
    );
    println!("load multiplier λ = tan α_max = {:.3}", result.collapse_angle_deg().to_radians().tan());
    println!("{:>8} {}", "tilt", result.monitors.iter().map(|m| format!("{m:>12}")).collect::<String>());
    for inc in result.increments.iter().filter(|i| i.stable && (i.alpha_deg % 5.0).abs() < 1e-9) {
        let d: String = inc.displacement_m.iter().map(|d| format!("{:>10.3} mm", d * 1e3)).collect();
        println!("{:>7.1}° {d}", inc.alpha_deg);
    }
    println!(
        "{} implicit iterations and {} steps of dynamic relaxation (time step {:.2e} s), {:.2} s",
        result.iterations, result.steps, result.dt_s, result.wall_time_s
    );
    Ok(())
}
