//! The `drystone` command line. Thin: parsing, printing, exit codes. `anyhow` lives here only.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use drystone::dem::SolverParams;
use drystone::layout::Layout;
use drystone::loading::tilt::{run_tilt, TiltParams};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "drystone", version, about = "Out-of-plane collapse of dry stone walls with a rigid-block DEM")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Tilting-table test of a layout to collapse.
    Tilt {
        /// Layout file (JSON).
        layout: PathBuf,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Tilt increment, degrees.
        #[arg(long, default_value_t = TiltParams::default().step_deg)]
        step_deg: f64,
        /// Width of the final collapse bracket, degrees.
        #[arg(long, default_value_t = TiltParams::default().resolution_deg)]
        resolution_deg: f64,
        /// Local damping coefficient.
        #[arg(long, default_value_t = SolverParams::default().damping)]
        damping: f64,
        /// Sub-contact subdivisions per fan-triangle edge.
        #[arg(long, default_value_t = SolverParams::default().subcontact_subdivisions)]
        subdivisions: u32,
        /// Unbalanced-force ratio of equilibrium.
        #[arg(long, default_value_t = TiltParams::default().tolerance)]
        tolerance: f64,
    },
    /// Closed-form verification cases; exit status 1 if any is out of tolerance.
    Verify {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Benchmarks.
    Bench {
        /// Which benchmark: `cube16` (the paper's Table 6 element-cost case).
        case: String,
        /// Steps to time.
        #[arg(long, default_value_t = 20_000)]
        steps: u64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run() -> Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Tilt { layout, json, step_deg, resolution_deg, damping, subdivisions, tolerance } => {
            let l = Layout::from_file(&layout)?;
            let solver = SolverParams { damping, subcontact_subdivisions: subdivisions, ..SolverParams::default() };
            let params = TiltParams { step_deg, resolution_deg, tolerance, ..TiltParams::default() };
            let r =
                run_tilt(&l, solver, &params).with_context(|| format!("tilting-table test of {}", layout.display()))?;
            if json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                println!("layout            {}", layout.display());
                println!(
                    "collapse angle    {:.2} deg (last stable), first unstable {}",
                    r.collapse_angle_deg,
                    r.first_unstable_deg.map_or("none".into(), |a| format!("{a:.2} deg"))
                );
                println!(
                    "mechanism         {:?} at joint {} ({} blocks moving)",
                    r.mechanism.kind,
                    r.mechanism.joint,
                    r.mechanism.blocks.len()
                );
                println!("steps             {}  (dt {:.3e} s, wall time {:.2} s)", r.steps, r.dt_s, r.wall_time_s);
                println!("out-of-plane displacement of the top points [cm]:");
                println!("  alpha_deg  {}", r.monitors.join("  "));
                for inc in r.increments.iter().filter(|i| i.stable) {
                    let d: Vec<String> = inc.displacement_m.iter().map(|d| format!("{:>9.3}", d * 100.0)).collect();
                    println!("  {:>9.2}  {}", inc.alpha_deg, d.join("  "));
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Verify { json } => {
            let rep = drystone::verify::run_all();
            if json {
                println!("{}", serde_json::to_string_pretty(&rep)?);
            } else {
                println!(
                    "{:<70} {:>9} {:>9} {:>8}  {:<4} {}",
                    "case", "expected", "simulated", "error", "ok", "mechanism"
                );
                for c in &rep.cases {
                    println!(
                        "{:<70} {:>9.3} {:>9.3} {:>+8.3}  {:<4} {}",
                        c.name,
                        c.expected_deg,
                        c.simulated_deg,
                        c.error_deg,
                        if c.ok { "ok" } else { "FAIL" },
                        c.detail
                    );
                }
                println!();
                println!("{:<50} {:>14} {:>14} {:>10} {:<4}", "check", "expected", "simulated", "rel.err", "ok");
                for c in &rep.checks {
                    println!(
                        "{:<50} {:>14.6e} {:>14.6e} {:>10.2e} {:<4} [{}]",
                        c.name,
                        c.expected,
                        c.simulated,
                        c.relative_error,
                        if c.ok { "ok" } else { "FAIL" },
                        c.unit
                    );
                }
            }
            Ok(if rep.all_ok() { ExitCode::SUCCESS } else { ExitCode::from(1) })
        }
        Command::Bench { case, steps, json } => {
            if case != "cube16" {
                bail!("unknown benchmark {case:?}; available: cube16");
            }
            let r = drystone::benchmark::run_cube16(steps, SolverParams::default());
            if json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                println!(
                    "cube16: {} bodies, {} contacts, {} sub-contacts, dt {:.3e} s",
                    r.bodies, r.contacts, r.sub_contacts, r.dt_s
                );
                println!("  {} steps at {:.0} steps/s (one thread)", r.steps, r.steps_per_s);
                println!(
                    "  equilibrium (unbalanced-force ratio < 1e-4) after {} steps, {:.3} s",
                    r.steps_to_equilibrium, r.equilibrium_wall_time_s
                );
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
