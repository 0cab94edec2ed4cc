//! Shared by the diagnostic examples (not an example itself).

use drystone::dem::{RunToEquilibrium, Simulation, SolverParams};
use drystone::layout::Layout;

/// Settles `layout` at α = 0, then tilts it by 0.5° increments to equilibrium up to `last`
/// degrees (unbalanced-force ratio 1e-4, solver `params`). Panics if an increment has no
/// equilibrium: the diagnostics start from a stable state.
#[allow(dead_code)] // not every example settles a layout
pub fn settled_at(layout: &Layout, last: f64, params: SolverParams) -> Simulation {
    let mut sim = Simulation::new(layout, params);
    assert!(sim.run_to_equilibrium(1e-4, 400_000).unwrap(), "no equilibrium at 0 deg");
    let mut k = 1;
    while k as f64 * 0.5 <= last + 1e-9 {
        sim.set_tilt((k as f64 * 0.5f64).to_radians());
        assert!(sim.run_to_equilibrium(1e-4, 400_000).unwrap(), "unstable at {}", k as f64 * 0.5);
        k += 1;
    }
    sim
}

/// The command-line arguments after the program name; exits with `usage` (status 2) if
/// there are fewer than `min`.
#[allow(dead_code)] // not every example takes arguments
pub fn args(min: usize, usage: &str) -> Vec<String> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    if a.len() < min {
        eprintln!("usage: {usage}");
        std::process::exit(2);
    }
    a
}

/// The layout file `path`; exits with the error (status 2) if it cannot be read.
#[allow(dead_code)]
pub fn layout(path: &str) -> Layout {
    Layout::from_file(std::path::Path::new(path)).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2);
    })
}

/// `s` as a number for the argument `name`; exits with a message (status 2) if it is not.
#[allow(dead_code)]
pub fn number<T: std::str::FromStr>(s: &str, name: &str) -> T {
    s.parse().unwrap_or_else(|_| {
        eprintln!("error: {name} must be a number, got {s:?}");
        std::process::exit(2);
    })
}
