//! The `drystone` command line: the top-level parser, the list of subcommands and the
//! dispatch; each subcommand's options (clap) and work live in its file of [`cli`]
//! (`cli/<subcommand>.rs`, the shared solver flags in `cli/solver.rs`); errors end the program with status 2 (and `run` or `merge` with
//! status 3 when every realization failed). `anyhow` lives in the command line only.

mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// The exit statuses of `run` and `merge`.
const EXIT_STATUS: &str = "Exit status: 0 when the outputs are written and at least one realization succeeded \
(if some failed, a warning on stderr gives their count; their rows carry the status and the error); \
2 on an error (bad input, a file that cannot be read or written, a journal or shard of another run); \
3 when every realization failed (the outputs are written all the same).";

#[derive(Parser)]
#[command(name = "drystone", version = drystone::study::BUILD, about = "How dry stone walls fail, out of plane (tilting table, lateral load, shaking) and in plane (the shear-compression test), by a rigid-block DEM, non-smooth contact dynamics and limit analysis")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Tilting-table test of a layout to collapse.
    #[command(allow_negative_numbers = true)]
    Tilt(cli::tilt::TiltArgs),
    /// Static lateral load: a trapezoidal pressure on the wall face (pushing towards +y),
    /// solved to equilibrium; prints the top displacements and the drift.
    #[command(allow_negative_numbers = true)]
    Lateral(cli::lateral::LateralArgs),
    /// In-plane shear–compression test: a loading beam on the top course under a constant
    /// vertical stress, its horizontal displacement imposed (monotonic or in growing
    /// cycles); prints the peak force, the drift at the peak, the initial stiffness and the
    /// mechanism (`--solver limit`: the peak force by limit analysis).
    #[command(name = "in-plane", allow_negative_numbers = true)]
    InPlane(cli::inplane::InPlaneArgs),
    /// Vertical compression test: the loading beam's vertical force cycled between σ0 and
    /// the beam's own weight (and optionally raised); prints the wall's vertical modulus
    /// (the secant of the first loading branch, the database's Epc), each cycle's secant and
    /// residual settlement, and the force–shortening curve.
    #[command(allow_negative_numbers = true)]
    Compression(cli::compression::CompressionArgs),
    /// Shaking table: the layout on a base that moves with a recorded or a built-in
    /// acceleration along y (out of plane), by non-smooth contact dynamics (rigid blocks;
    /// `--solver penalty`: the penalty DEM in explicit dynamics); prints whether it overturned, the largest rocking rotation and the drifts.
    #[command(allow_negative_numbers = true)]
    Shake(cli::shake::ShakeArgs),
    /// Limit analysis: the rigid collapse load multiplier of a layout from statics alone (a
    /// second-order cone program over the contact polygons; tilting table: λ = tan α_max).
    #[command(allow_negative_numbers = true)]
    Limit(cli::limit::LimitArgs),
    /// Runs a study (ensembles of realizations) and writes tables, plots and a report.
    ///
    /// Every finished realization goes at once to DIR/journal.jsonl (synced); after a crash
    /// or a kill, the same command with --resume runs only what is missing and writes
    /// outputs identical to an uninterrupted run (except the wall_time_s column).
    #[command(after_help = EXIT_STATUS)]
    Run(cli::study::RunArgs),
    /// Calibrates joint parameters (Kn, φ) of a study's walls against the measured collapse
    /// angles, step by step as its [[calibrate]] table says (Brent root finding, argmin).
    Calibrate(cli::study::CalibrateArgs),
    /// Merges shard directories of one study run into what an unsharded run writes.
    ///
    /// The shards must agree on the drystone version, the master seed, the realizations,
    /// the number of shards and every input file (by SHA-256); the first difference is
    /// named with both values. The study is rebuilt from the input files stored in the
    /// manifests, so the study file need not be unchanged or where it was.
    #[command(after_help = EXIT_STATUS)]
    Merge(cli::study::MergeArgs),
    /// Closed-form verification cases; exit status 1 if any is out of tolerance.
    Verify(cli::verify::VerifyArgs),
    /// Generates a wall layout from a wall description (TOML), a seed and a realization index.
    Generate(cli::generate::GenerateArgs),
    /// Imports a surveyed wall (a traced elevation: SVG, GeoJSON, DXF; scanned stones: OBJ, STL)
    /// as a layout (docs/survey.md).
    Import(cli::import::ImportArgs),
    /// Model discrepancy: what the simulation gets wrong against the study's measured data,
    /// the physical effect that explains it (from a library of candidate effects, ranked by
    /// held-out error with margins calibrated on null data), the extended model and its gain.
    Discrepancy(cli::discrepancy::DiscrepancyArgs),
    /// Synthetic measured data: the study's walls built with seeds the study does not use,
    /// hidden effects applied, tilted to collapse, with measurement noise; written in the
    /// format of the paper's data files (a power analysis for planning tests).
    Synthesize(cli::discrepancy::SynthesizeArgs),
    /// The next experiment: runs the discrepancy analysis, then ranks follow-up tests on the
    /// tilting table (more specimens, the mechanism read, both monitors, walls of another
    /// height, length or restraint) by the probability that the cause is then named alone,
    /// and writes the best as a study with empty measured-file templates.
    Design(cli::design::DesignArgs),
    /// Benchmarks: `cube16` (the paper's Table 6 element-cost case: `--steps` engine steps of
    /// 16 boxes) or `tilt` (tilting-table tests to collapse of a generated wall, one after
    /// the other on one thread: by default the SBL preset, seed 20210917, realization 0;
    /// `--realizations N` runs realizations 0..N and gives the totals).
    Bench(cli::bench::BenchArgs),
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes joined by `: `, each cause left out when the message before it
/// already ends with it (most errors here print their cause themselves).
fn message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.ends_with(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

/// Parses the command line and runs the subcommand.
fn run() -> anyhow::Result<ExitCode> {
    match Cli::parse().command {
        Command::Tilt(a) => cli::tilt::command(a),
        Command::Lateral(a) => cli::lateral::command(a),
        Command::InPlane(a) => cli::inplane::command(a),
        Command::Compression(a) => cli::compression::command(a),
        Command::Shake(a) => cli::shake::command(a),
        Command::Limit(a) => cli::limit::run(&a),
        Command::Run(a) => cli::study::run(a),
        Command::Calibrate(a) => cli::study::calibrate(a),
        Command::Merge(a) => cli::study::merge(a),
        Command::Verify(a) => cli::verify::command(a),
        Command::Generate(a) => cli::generate::command(a),
        Command::Import(a) => cli::import::command(a),
        Command::Discrepancy(a) => cli::discrepancy::discrepancy(a).map(|()| ExitCode::SUCCESS),
        Command::Synthesize(a) => cli::discrepancy::synthesize_command(a).map(|()| ExitCode::SUCCESS),
        Command::Design(a) => cli::design::command(a).map(|()| ExitCode::SUCCESS),
        Command::Bench(a) => cli::bench::command(a),
    }
}
