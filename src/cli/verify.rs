//! `drystone verify`: the closed-form verification cases.

use anyhow::Result;
use drystone::verify::{self, Report};
use std::process::ExitCode;

/// Options of `drystone verify`.
#[derive(clap::Args)]
pub struct VerifyArgs {
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// `drystone verify`: [`run`].
///
/// # Errors
/// Those of [`run`].
pub fn command(a: VerifyArgs) -> Result<ExitCode> {
    run(a.json)
}

/// Runs every case and prints two tables, or JSON with `json`; status 1 if any case is out
/// of tolerance.
pub fn run(json: bool) -> Result<ExitCode> {
    let rep = verify::run_all();
    if json {
        out!("{}", serde_json::to_string_pretty(&rep)?);
    } else {
        print(&rep);
    }
    Ok(if rep.all_ok() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

fn print(rep: &Report) {
    let ok = |b: bool| if b { "ok" } else { "FAIL" };
    out!("{:<70} {:>9} {:>9} {:>8}  {:<4} {}", "case", "expected", "simulated", "error", "ok", "mechanism");
    for c in rep.cases.iter().chain(&rep.sweep) {
        out!(
            "{:<70} {:>9.3} {:>9.3} {:>+8.3}  {:<4} {}",
            c.name,
            c.expected_deg,
            c.simulated_deg,
            c.error_deg,
            ok(c.ok),
            c.detail
        );
    }
    out!();
    out!("{:<50} {:>14} {:>14} {:>10} {:<4}", "check", "expected", "simulated", "rel.err", "ok");
    for c in &rep.checks {
        out!(
            "{:<50} {:>14.6e} {:>14.6e} {:>10.2e} {:<4} [{}]",
            c.name,
            c.expected,
            c.simulated,
            c.relative_error,
            ok(c.ok),
            c.unit
        );
    }
}
