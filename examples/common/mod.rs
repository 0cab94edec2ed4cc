//! Shared by the diagnostic examples (not an example itself).

use drystone::dem::{Simulation, SolverParams};
use drystone::layout::Layout;

/// Settles `layout` at α = 0, then tilts it by 0.5° increments to equilibrium up to `last`
/// degrees (unbalanced-force ratio 1e-4, default solver). Panics if an increment has no
/// equilibrium: the diagnostics start from a stable state.
pub fn settled_at(layout: &Layout, last: f64) -> Simulation {
    let mut sim = Simulation::new(layout, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-4, 400_000).unwrap(), "no equilibrium at 0 deg");
    let mut k = 1;
    while k as f64 * 0.5 <= last + 1e-9 {
        sim.set_tilt((k as f64 * 0.5f64).to_radians());
        assert!(sim.run_to_equilibrium(1e-4, 400_000).unwrap(), "unstable at {}", k as f64 * 0.5);
        k += 1;
    }
    sim
}
