//! The one relaxation loop of every static solution (the settling under gravity, each
//! tilting-table increment and bisection trial, the static lateral load): dynamic
//! relaxation with local damping until the unbalanced-force ratio drops below a tolerance
//! (Cundall 1988; 3DEC's `solve ratio`), a protocol's stop check fires, or the step budget
//! runs out.

use super::accelerate::{Accelerator, Ahead, Creep, SecantAcceleration};
use crate::dem::engine::{DemError, Simulation};
use crate::math::Vec3;

/// Steps between two calls of the stop check (it measures displacements, which costs more
/// than a step's bookkeeping).
pub const CHECK_EVERY: u64 = 64;

/// Steps of a relaxation after which a slow creep is followed along its motion to the
/// equilibrium ahead ([`Accelerator::probe`]) every [`FOLLOW_CREEP_EVERY`] steps: the
/// creep of stiff joints near a limit point, where the secant stiffness of a window is
/// lost in the fast modes (the knife-edge contact of a block on joints of Kn ≥ 1e11 Pa/m
/// creeps for hundreds of thousands of steps). Relaxations shorter than that are left as
/// they are.
pub const FOLLOW_CREEP_AFTER: u64 = 8192;

/// See [`FOLLOW_CREEP_AFTER`].
pub const FOLLOW_CREEP_EVERY: u64 = 1024;

/// When a relaxation has reached equilibrium: the unbalanced-force ratio below `global`
/// and, where `local` is given, the largest local ratio below it
/// ([`Simulation::largest_local_ratio`]: every block balanced against the load it carries,
/// not only the wall on average). A bare `f64` is the global tolerance alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// The unbalanced-force ratio of equilibrium, –.
    pub global: f64,
    /// The local unbalanced-force ratio of equilibrium, –; `None`: not checked.
    pub local: Option<f64>,
}

impl From<f64> for Tolerance {
    fn from(global: f64) -> Tolerance {
        Tolerance { global, local: None }
    }
}

impl Tolerance {
    /// Whether `sim`, after its last step, is in equilibrium by this tolerance (the local
    /// ratio read only once the global one holds).
    pub fn holds(&self, sim: &Simulation) -> bool {
        sim.stats().unbalanced_ratio < self.global && self.local.is_none_or(|l| sim.largest_local_ratio().0 < l)
    }
}

/// How a relaxation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Relaxed<R> {
    /// The unbalanced-force ratio fell below the tolerance after this many steps.
    Equilibrium(u64),
    /// The stop check returned its reason after this many steps.
    Stopped(R, u64),
    /// The step budget ran out (neither equilibrium nor a collapse established).
    Budget(u64),
    /// The secant acceleration found negative stiffness along a persistent motion and no
    /// equilibrium on the path ahead up to the probe's reach (see [`super::accelerate`])
    /// after this many steps; with the motion of its last window (per body: translation,
    /// m, and rotation vector, rad), the direction of collapse.
    Unstable(u64, (Vec<Vec3>, Vec<Vec3>)),
}

/// Steps `sim` until equilibrium (by `tol`, [`Tolerance`]: the unbalanced-force ratio below
/// it, and every block's local ratio where it says so; after at least 11
/// steps so that the first forces have propagated), until `check` (called every
/// [`CHECK_EVERY`] steps) returns a reason to stop, or for `max_steps` steps; with the
/// secant acceleration if `accelerate` is given, whose stability indicator then ends the
/// relaxation as soon as it fires (no probe of the path ahead: see [`dynamic_relaxation_probed`]).
///
/// # Errors
/// [`DemError::NonFinite`] when a body's state blows up.
pub fn dynamic_relaxation<R>(
    sim: &mut Simulation,
    tol: impl Into<Tolerance>,
    max_steps: u64,
    accelerate: Option<SecantAcceleration>,
    check: impl FnMut(&Simulation) -> Option<R>,
) -> Result<Relaxed<R>, DemError> {
    relax_impl(sim, tol.into(), max_steps, accelerate.map(|a| (a, None)), check)
}

/// [`dynamic_relaxation`] with the secant acceleration and probes of the path ahead, `reach` (m) the
/// largest body motion a probe goes: where the stability indicator fires, the state is
/// unstable only if no equilibrium lies within that reach along the collapse direction
/// ([`Accelerator::probe`]), otherwise the relaxation goes on from the last probe point
/// that still pushed along the motion; and a long creep is followed to the equilibrium
/// ahead ([`FOLLOW_CREEP_AFTER`]).
///
/// # Errors
/// [`DemError::NonFinite`] when a body's state blows up.
pub fn dynamic_relaxation_probed<R>(
    sim: &mut Simulation,
    tol: impl Into<Tolerance>,
    max_steps: u64,
    accelerate: SecantAcceleration,
    reach: f64,
    check: impl FnMut(&Simulation) -> Option<R>,
) -> Result<Relaxed<R>, DemError> {
    relax_impl(sim, tol.into(), max_steps, Some((accelerate, Some(reach))), check)
}

fn relax_impl<R>(
    sim: &mut Simulation,
    tol: Tolerance,
    max_steps: u64,
    accelerate: Option<(SecantAcceleration, Option<f64>)>,
    mut check: impl FnMut(&Simulation) -> Option<R>,
) -> Result<Relaxed<R>, DemError> {
    let mut steps = 0;
    let reach = accelerate.and_then(|a| a.1);
    let max_scale = accelerate.map_or(0.0, |a| a.0.max_scale);
    let mut acc = accelerate.map(|a| Accelerator::new(a.0));
    while steps < max_steps {
        sim.step()?;
        steps += 1;
        if steps > 10 && tol.holds(sim) {
            return Ok(Relaxed::Equilibrium(steps));
        }
        if let Some(acc) = acc.as_mut() {
            let creep = acc.observe(sim, steps);
            let follow = steps >= FOLLOW_CREEP_AFTER && steps % FOLLOW_CREEP_EVERY == 0;
            if let (Creep::Continue, true, Some(reach)) = (creep, follow && acc.creeping(), reach) {
                if let Ahead::Equilibrium(dpos, drot) = acc.probe(sim, reach, max_scale) {
                    sim.predict(&dpos, &drot);
                    acc.reset();
                }
            }
            if creep == Creep::Unstable {
                let ahead = reach.map_or(Ahead::NoEquilibrium, |r| acc.probe(sim, r, f64::INFINITY));
                match ahead {
                    Ahead::NoEquilibrium => {
                        let motion = acc.last_motion().unwrap_or_default();
                        return Ok(Relaxed::Unstable(steps, motion));
                    }
                    Ahead::Equilibrium(dpos, drot) => {
                        sim.predict(&dpos, &drot);
                        acc.reset();
                    }
                }
            }
        }
        if steps % CHECK_EVERY == 0 {
            if let Some(r) = check(sim) {
                return Ok(Relaxed::Stopped(r, steps));
            }
        }
    }
    Ok(Relaxed::Budget(steps))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::SolverParams;
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    fn block() -> Simulation {
        let l = layout_of(vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])], 1e8, 5e7, 35.0, BaseSliding::Free);
        Simulation::new(&l, SolverParams::default())
    }

    /// The local ratio sees a light block the global one hides: a 1 m granite cube at rest
    /// on the table and a 1 cm cube held 1 mm above it. The global ratio (a mean over the
    /// bodies) is about 1e-6 while the small cube falls, so a relaxation to 1e-4 alone
    /// stops with it in the air; with a local tolerance of 0.01 the relaxation goes on
    /// until the cube rests on the table: its bottom within its joint's closure under its
    /// weight of z = 0 (the reference: the free fall lands it, the Winkler joint holds it
    /// at `W / (Kn A)`).
    #[test]
    fn the_local_ratio_holds_a_relaxation_until_every_block_rests() {
        let boxes = vec![
            box_vertices([0.0, -0.5, 0.0], [1.0, 0.5, 1.0]),
            box_vertices([2.0, -0.005, 0.001], [2.01, 0.005, 0.011]),
        ];
        let l = layout_of(boxes, 1e9, 5e8, 35.0, BaseSliding::Free);
        let none = |_: &Simulation| None::<()>;
        let settled = {
            let mut sim = Simulation::new(&l, SolverParams::default());
            let Relaxed::Equilibrium(_) = dynamic_relaxation(&mut sim, 1e-4, 1_000_000, None, none).unwrap() else {
                panic!()
            };
            sim
        };
        let bottom = |sim: &Simulation| sim.state.bodies[1].pos.z - 0.005;
        assert!(bottom(&settled) > 1e-4, "the global ratio alone stopped with the cube landed: {}", bottom(&settled));
        assert!(settled.largest_local_ratio().0 > 0.5, "{:?}", settled.largest_local_ratio());
        let mut sim = Simulation::new(&l, SolverParams::default());
        let tol = Tolerance { global: 1e-4, local: Some(0.01) };
        let Relaxed::Equilibrium(_) = dynamic_relaxation(&mut sim, tol, 1_000_000, None, none).unwrap() else {
            panic!()
        };
        let w = sim.state.bodies[1].mass * 9.81;
        let closure = w / (1e9 * 1e-4);
        assert!(bottom(&sim).abs() < 3.0 * closure + 1e-9, "bottom at {} m, closure {closure} m", bottom(&sim));
        assert!(sim.largest_local_ratio().0 < 0.01);
    }

    /// The loop's stopping rules, each on its own: equilibrium (never before step 11), the
    /// step budget, and the protocol's check (called every [`CHECK_EVERY`] steps).
    #[test]
    fn relaxation_stops_at_equilibrium_at_the_budget_or_at_the_check() {
        let none = |_: &Simulation| None::<()>;
        let mut sim = block();
        let Relaxed::Equilibrium(n) = dynamic_relaxation(&mut sim, 1e-6, 100_000, None, none).unwrap() else {
            panic!()
        };
        assert!(n > 10 && sim.stats().unbalanced_ratio < 1e-6, "{n} steps");
        // Already in equilibrium: still at least 11 steps, so that the first forces
        // propagate.
        let Relaxed::Equilibrium(again) = dynamic_relaxation(&mut sim, 1e-6, 100_000, None, none).unwrap() else {
            panic!()
        };
        assert!((11..n).contains(&again), "{again} steps, {n} from rest");
        let mut sim = block();
        assert_eq!(dynamic_relaxation(&mut sim, 1e-12, 5, None, none).unwrap(), Relaxed::Budget(5));
        assert_eq!(sim.state.steps, 5);
        let mut sim = block();
        let mut calls = 0;
        let out = dynamic_relaxation(&mut sim, 1e-12, 100_000, None, |_| {
            calls += 1;
            (calls == 2).then_some("stop")
        })
        .unwrap();
        assert_eq!(out, Relaxed::Stopped("stop", 2 * CHECK_EVERY));
    }
}
