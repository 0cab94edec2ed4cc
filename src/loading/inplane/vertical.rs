//! The vertical phase of a test on the rig ([`stand_under_vertical_force`]): the wall
//! settled under gravity with the loading beam on it, then solved under the vertical force,
//! and its vertical modulus read on that first loading branch ([`VerticalPhase`]). The
//! in-plane test (`driver`) and the vertical compression test
//! ([`crate::loading::compression`]) both start with it, so that the compression test's
//! first loading branch and the in-plane test's vertical phase are one computation.

use super::{BeamRotation, InPlaneError, Rig};
use crate::dem::motion::{poses, BodyPose};
use crate::dem::{solve_static, Cascade, End, Hold, Simulation, SolverParams, StaticSolve};
use crate::loading::settle::{settle, SettleError};
use crate::math::Vec3;

/// The local unbalanced-force ratio of equilibrium of every static solve of the rig's tests
/// \[0.01\] ([`crate::dem::Simulation::largest_local_ratio`]; with the solver's global
/// tolerance): each block balanced to a hundredth of the load it carries. The global ratio
/// is a mean over a wall whose blocks carry hundreds of times their weight, so a block the
/// beam has lifted off (an end half-stone of the top course rocking back onto its bed) can
/// still be moving at the global tolerance; a solve stopped there leaves it to the next
/// increment, which reads it out of balance (on the granite wall at 1.25 MPa, 69 of the 216
/// increments of a monotonic run had a block out of balance by a fifth of its load).
pub const LOCAL_TOLERANCE: f64 = 0.01;

/// The static solve of the rig's tests by the penalty DEM's default method (`--solver
/// penalty`): the implicit iteration (`dem::drivers::implicit`: the factorized stiffness of
/// the sub-contacts, the rig's holds read through [`crate::dem::Hold`]), and dynamic
/// relaxation with local damping where it hands over (an iteration that stalls, or an
/// equilibrium that leaves a block out of balance by [`LOCAL_TOLERANCE`]), to the same
/// tolerances. Without the relaxation's acceleration: the rig's increments start from a
/// predicted motion, and an accelerated relaxation that overshoots it throws the loose
/// blocks of a rocking wall's heel. The same equilibria as dynamic relaxation alone within
/// the tolerance (on the bundled granite wall the monotonic peaks at 0.2–1.25 MPa within
/// 0.04 % of relaxation's and 0.02 % of runs at 1e-6, linear or hyperbolic joints;
/// BENCHMARKS.md, "In-plane shear–compression test"),
/// for a half (linear joints) to a tenth (the hyperbolic closure law, whose stiffening
/// tangent slows the relaxation's time step) of the CPU. `--solver relaxation` gives the
/// relaxation alone, `--solver implicit` the implicit iteration over the accelerated
/// relaxation.
pub const CASCADE: Cascade = Cascade { newton: false, implicit: true, accelerate: false };

/// The wall standing under the vertical force ([`stand_under_vertical_force`]).
#[derive(Debug, Clone)]
pub struct VerticalPhase {
    /// The rig's simulation in equilibrium under the vertical force `N = σ0 L t`
    /// ([`Rig::vertical_force_n`]; the beam's weight part of it).
    pub sim: Simulation,
    /// The static solve the phase used (the solver's cascade over dynamic relaxation), for
    /// the protocol's own solves after it.
    pub relax: StaticSolve,
    /// The bodies' poses before the vertical force (settled under gravity, the beam's
    /// weight alone on the wall), layout order with the beam last.
    pub start: Vec<BodyPose>,
    /// The beam's settlement under the force the actuator added, m (its centroid's, `start`
    /// to `sim`; positive down).
    pub settlement_m: f64,
    /// The wall's vertical modulus, MPa, as the laboratory reads it from the vertical
    /// loading phase (the database's `Epc`, Vanin et al. 2017, Bull. Earthquake Eng.
    /// 15:5435): the secant of the first loading branch, the stress the actuator added,
    /// `(N − W_beam) / (L t)`, over the wall's shortening (`settlement_m` over the wall's
    /// height `H`).
    pub vertical_modulus_mpa: f64,
}

/// The rig's simulation with the beam held ([`Rig::constraint`] with `rotation`), settled
/// under gravity, then solved under the vertical force and the rig's moment on the beam,
/// and checked to stand (no block moved by more than the joints' closure under the vertical
/// stress `sigma0_mpa`, MPa, explains); with the static solve used, the poses before the
/// vertical force and the vertical modulus read on the way ([`VerticalPhase`]).
/// `settled` sees the state settled under gravity, before the vertical force (the
/// compression test reads its first loading branch's points from it).
///
/// The solver's settings are used as given (the drivers drop the density scaling's block
/// option and check the static settings before).
///
/// # Errors
/// [`InPlaneError::Crushes`] where the mean stress at the base reaches a crushing joint's
/// strength ([`check_crushing`]), [`InPlaneError::DoesNotStand`] (under gravity),
/// [`InPlaneError::UnderVerticalForce`] naming the block that moved most,
/// [`InPlaneError::Dem`] for a blow-up.
pub fn stand_under_vertical_force(
    rig: &Rig,
    solver: SolverParams,
    rotation: BeamRotation,
    sigma0_mpa: f64,
    settled: &mut dyn FnMut(&Simulation),
) -> Result<VerticalPhase, InPlaneError> {
    check_crushing(rig)?;
    let mut sim = Simulation::new(&rig.layout, solver);
    let (tol, budget) = (solver.penalty.tolerance, solver.penalty.max_steps);
    let bi = rig.beam;
    sim.state.bodies[bi].hold = Hold::Dof(rig.constraint(&sim, rotation));
    // The plane model: each block held out of the wall's plane (`OutOfPlane`).
    for k in 0..sim.state.bodies.len() {
        let b = &sim.state.bodies[k];
        if k != bi && !b.fixed() {
            if let Some(c) = rig.block_constraint_of(b) {
                sim.state.bodies[k].hold = Hold::Dof(c);
            }
        }
    }
    settle(&mut sim, &rig.layout, tol, budget).map_err(|e| match e {
        SettleError::Dem(e) => InPlaneError::Dem(e),
        other => InPlaneError::DoesNotStand(other),
    })?;
    settled(&sim);
    // The vertical force, the beam's weight part of it.
    let start = poses(&sim);
    sim.state.external_force[bi] = Vec3::new(0.0, 0.0, -(rig.vertical_force_n - rig.beam_weight_n));
    // The rig's terms that move the wall: a moment on the beam from its pose now.
    let moment = rig.beam_moment(&sim.state.bodies[bi]);
    if let Some(c) = sim.state.bodies[bi].hold.dof_mut() {
        c.moment = moment;
    }
    // The static solves: the solver's stages, the protocol's own ([`CASCADE`]) by default.
    let relax = StaticSolve {
        local_tolerance: Some(LOCAL_TOLERANCE),
        ..StaticSolve::of(&solver.penalty, solver.kind.cascade(CASCADE).unwrap_or(CASCADE), None)
    };
    let out = solve_static(&mut sim, &relax, &start, |_| None::<()>)?;
    check_under_vertical_force(&sim, rig, sigma0_mpa, &start, &out.end)?;
    // The vertical modulus: the stress the actuator added over the wall's shortening.
    let settlement_m = start[bi].0.z - sim.state.bodies[bi].pos.z;
    let added_stress = (rig.vertical_force_n - rig.beam_weight_n) / (rig.length_m * rig.thickness_m);
    let vertical_modulus_mpa = added_stress * rig.height_m / settlement_m * 1e-6;
    Ok(VerticalPhase { sim, relax, start, settlement_m, vertical_modulus_mpa })
}

/// Refuses a vertical force the wall's base joint crushes under: where every block on the
/// table meets it with a crushing law (`q = min(Kn u, fc)`,
/// [`crate::closure::Closure::Crushing`]: a material's, the base family's or a block's
/// own bed law, as the engine's joint table resolves them), the base joint carries at most
/// the largest of their fc over an area of at most the plan area `L t`, and a mean stress
/// `(N + W) / (L t)` reaching it leaves the joint closing without end (the wall crushes),
/// which the static solve would report as a block moved kilometres. A base that any block
/// bears on without a crushing law, or crushing joints higher up, are left to that solve.
///
/// # Errors
/// [`InPlaneError::Crushes`], naming the layout's crushing rule and both stresses.
pub fn check_crushing(rig: &Rig) -> Result<(), InPlaneError> {
    let Some((joint, _)) = rig.layout.crushing_joint() else { return Ok(()) };
    let table = crate::dem::materials::JointTable::new(&rig.layout);
    let up = Vec3::new(0.0, 0.0, 1.0);
    let mut strength_pa = f64::NEG_INFINITY;
    for (k, b) in rig.layout.blocks.iter().enumerate() {
        if b.shape.aabb().min.z > crate::loading::excursion::TOUCH_TOLERANCE_M {
            continue;
        }
        match table.joint(None, k, &up).closure {
            crate::closure::Closure::Crushing(c) => strength_pa = strength_pa.max(c.strength_pa),
            _ => return Ok(()),
        }
    }
    let stress_pa = rig.n_total_n() / (rig.length_m * rig.thickness_m);
    if strength_pa.is_finite() && stress_pa >= strength_pa {
        return Err(InPlaneError::Crushes {
            joint,
            strength_mpa: strength_pa * 1e-6,
            stress_mpa: stress_pa * 1e-6,
            force_kn: rig.vertical_force_n * 1e-3,
        });
    }
    Ok(())
}

/// Checks that the wall stands under the vertical force: its solve from the poses `start`
/// ended in equilibrium (`end`), and no block moved by more than the joints' closure under
/// the vertical stress `sigma0_mpa` (MPa) explains.
///
/// # Errors
/// [`InPlaneError::UnderVerticalForce`], naming the block that moved most.
fn check_under_vertical_force(
    sim: &Simulation,
    rig: &Rig,
    sigma0_mpa: f64,
    start: &[BodyPose],
    end: &End<()>,
) -> Result<(), InPlaneError> {
    // What the joints' closure under the vertical stress explains, twice, on top of the
    // settling's tolerance: a stack of H / h_min joints each closing σ0 / Kn.
    let h_min = rig.layout.blocks.iter().map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
    let kn_min = rig.layout.materials.iter().map(|m| m.kn).fold(f64::INFINITY, f64::min);
    let allowed = crate::loading::settle::settle_tolerance(&rig.layout)
        + 2.0 * (rig.height_m / h_min).ceil() * sigma0_mpa * 1e6 / kn_min;
    let worst = sim
        .state
        .bodies
        .iter()
        .zip(start)
        .map(|(b, (x0, _))| (b.id.clone(), (b.pos - x0).norm()))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((block, moved)) = worst {
        if *end != End::Equilibrium || moved > allowed {
            return Err(InPlaneError::UnderVerticalForce {
                block,
                moved_mm: moved * 1e3,
                allowed_mm: allowed * 1e3,
                force_kn: rig.vertical_force_n * 1e-3,
                equilibrium: *end == End::Equilibrium,
            });
        }
    }
    Ok(())
}
