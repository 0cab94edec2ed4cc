//! The tilting-table test at the rigid limit, by non-smooth contact dynamics
//! (`nscd`): a static bisection of trials released from rest.
//!
//! Every joint is rigid (the layout's Kn and Ks are not used); friction is the layout's.
//! The result is the same [`TiltResult`] as the penalty solver's [`super::tilt::run_tilt_penalty`]
//! (the same JSON and CSV fields).
//!
//! # A trial
//!
//! The wall in its reference configuration (as built: rigid blocks do not settle), at rest,
//! gravity tilted by α, is released and stepped by the Moreau–Jean scheme:
//!
//! * **stable** at once when the largest speed of any block point (`|v| + |ω| R`) stays
//!   below the rest velocity `rest_velocity_ratio × g h` for `rest_steps` steps running:
//!   an equilibrium exists (a statically admissible set of contact forces holds the wall
//!   still; rigid blocks released from rest then never move);
//! * **unstable** ([`CollapseReason::IncrementDisplacement`]) as soon as a block has moved
//!   (centroid motion plus rotation times its radius) more than the per-increment collapse
//!   displacement, [`TiltParams::collapse_increment_fraction`] × the wall width;
//! * otherwise, after `trial_steps` steps, **unstable** ([`CollapseReason::NoEquilibrium`])
//!   if the mean largest point speed of the second half of the steps exceeds
//!   `growth_ratio` times that of the first half and the rest velocity: the mechanism
//!   keeps accelerating under the constant tilt (its kinetic energy grows), and
//!   **stable** if not: the motion settles, or is the noise of the Gauss–Seidel iterate
//!   about an equilibrium (large walls of small wedges converge to a few 1e-4 g h, not to
//!   the rest velocity).
//!
//! Just above the rigid limit the mechanism accelerates at about `g δ` (δ the tilt excess
//! in rad), so its speed after n steps is about `n δ g h`: at δ = 0.01° it passes the rest
//! velocity `10⁻⁵ g h` at the first step and reaches 7e-3 g h in 40 steps, far above the
//! Gauss–Seidel noise of a converged equilibrium (below 1e-6 g h on the 13-box wall; a
//! few 1e-4 g h on the SBL wall).
//!
//! # A wall held by ropes
//!
//! A rope ([`crate::dem::rope`]) is compliant: its force develops only as the wall moves
//! into it, so a rope-held wall's equilibrium is displaced from the reference and depends
//! on the path, and a block released from rest first accelerates as if free, for about a
//! quarter period of the rope's mode, before the rope catches it. The rigid trial's window
//! (`trial_steps`, 40 steps) would call that motion a mechanism. A layout with ropes
//! (`TrialLimits::of`) therefore follows the penalty path's increments:
//!
//! * α grows by [`TiltParams::step_deg`], each trial starting at rest from the last stable
//!   trial's state (the equilibrium of the tilt before), and the first unstable increment
//!   is bisected from that state to [`TiltParams::resolution_deg`];
//! * a trial's window is [`ROPE_PERIODS`] periods `2π/√λ` of the slowest rope-held block
//!   (λ its largest eigenvalue of the ropes' stiffness against its mass), at least
//!   `trial_steps` and at most [`ROPE_TRIAL_MAX_STEPS`]; a rope with no stiffness as built
//!   (no pretension, just touching the face) is taken at its stiffness over the deflections
//!   a trial reaches, its elongation's ([`TrialLimits::of`]);
//! * the motion is kinetically damped (Cundall's kinetic damping of dynamic relaxation):
//!   when the kinetic energy passes a peak, the wall is passing its equilibrium and every
//!   block is stopped there, so that the release converges on the equilibrium instead of
//!   oscillating about it;
//! * a trial is unstable, as an increment of the penalty path, once a block has moved more
//!   than the per-increment collapse displacement since the trial's start, or more than
//!   [`TiltParams::collapse_displacement_fraction`] × the width since the reference
//!   ([`CollapseReason::TotalDisplacement`]), or by the growth test at the end of the
//!   window; stable at rest as a rigid trial.
//!
//! The wall then stands where the taut-string statics of docs/rope.md balance it, and
//! fails at the first maximum of the tilt along its path (a snap to a distant branch is a
//! per-increment collapse, as on the penalty path). A soft rope that lets the rigid wall tip
//! at its free limit before it catches it gives that limit (docs/rope.md: the penalty DEM's
//! elastic joints lean into the rope first, and its answer there depends on their stiffness).
//!
//! # The bisection
//!
//! A trial at α = 0 (the layout must stand as given), then bisection of
//! `[0, max_angle_deg]` to [`TiltParams::resolution_deg`] (the largest tilt itself is tried
//! only if every trial below it stood). Rigid trials do not depend on the loading path
//! (each starts from the reference state at rest), so the increments of the penalty path
//! ([`TiltParams::step_deg`]) are not needed: about 12 trials instead of one per
//! increment. The bracket `[last_stable_deg, first_unstable_deg]`
//! contains the rigid-limit tilt (the largest tilt at which an equilibrium exists, found
//! dynamically: with non-associated friction an equilibrium the release from rest does not
//! find counts as none, as in LMGC90's bisections). Each trial warm-starts its impulses
//! from the last stable trial.
//!
//! # The mechanism
//!
//! Read as the penalty path reads it ([`mechanism`]) between the reference state, whose
//! load-carrying joints are those with an impulse in the last stable trial, and the first
//! unstable trial's final state carried along its velocity until a block has moved the
//! per-increment collapse displacement.

use super::mechanism::{mechanism, Mechanism};
use super::monitors::{body_motion, monitor_points, BodyPose, MonitorPoint};
use super::settle::SettleError;
use super::tilt::after_snap;
use super::tilt::hand::effective_tilt_deg;
use super::tilt::params::TiltParams;
use super::tilt::result::{CollapseReason, Increment, TiltError, TiltResult};
use crate::dem::rope::{stiffness_bound, RopeLoad};
use crate::dem::timestep::Stiffness;
use crate::dem::{DemError, Simulation, SolverParams};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::nscd::{NscdError, NscdParams, NscdSimulation};
use crate::units::deg_to_rad;
use std::time::Instant;

/// The outcome of one trial.
pub(crate) struct Trial {
    pub(crate) sim: NscdSimulation,
    /// `None`: stable.
    pub(crate) reason: Option<CollapseReason>,
    pub(crate) steps: u64,
    pub(crate) iterations: u64,
}

pub(crate) fn tilt_error(e: NscdError) -> TiltError {
    match e {
        NscdError::Parameter(p) => TiltError::Parameter(p),
        NscdError::NonFinite { id, step, dt_s } => TiltError::Dem(DemError::NonFinite { id, step, dt_s }),
        other => TiltError::Nscd(other),
    }
}

pub(crate) fn poses(sim: &NscdSimulation) -> Vec<BodyPose> {
    sim.bodies().iter().map(|b| (b.pos, b.rot)).collect()
}

/// The largest motion of a free block since `start`, m.
pub(crate) fn largest_motion(sim: &NscdSimulation, start: &[BodyPose]) -> f64 {
    sim.bodies()
        .iter()
        .zip(start)
        .filter(|(b, _)| !b.fixed())
        .map(|(b, s)| body_motion(s, &(b.pos, b.rot), b.radius))
        .fold(0.0, f64::max)
}

/// The first half of the rigid check that a wall stands as given: every free block of
/// `base` (the reference state) has a contact point.
///
/// # Errors
/// [`TiltError::DoesNotStand`] ([`SettleError::Untouched`]) naming the first free block,
/// in layout order, that touches nothing within `params.contact_margin_m`.
pub(crate) fn touches_something(base: &NscdSimulation, params: &NscdParams) -> Result<(), TiltError> {
    for (k, b) in base.bodies().iter().enumerate() {
        if !b.fixed() && !base.contact_points().iter().any(|c| c.b == k || c.a == Some(k)) {
            return Err(TiltError::DoesNotStand(SettleError::Untouched {
                block: b.id.clone(),
                margin_m: params.contact_margin_m,
            }));
        }
    }
    Ok(())
}

/// The second half of the rigid check: the trial `first` released from `base` under
/// gravity alone (α = 0) came to rest.
///
/// # Errors
/// [`TiltError::DoesNotStand`] ([`SettleError::Moved`]) naming the block that moved most
/// and how far (m; the rigid tolerance is 0), if the trial did not come to rest.
pub(crate) fn stood(base: &NscdSimulation, first: &Trial) -> Result<(), TiltError> {
    if first.reason.is_none() {
        return Ok(());
    }
    let start = poses(base);
    let (block, moved_m) = first
        .sim
        .bodies()
        .iter()
        .zip(&start)
        .map(|(b, s)| (b.id.clone(), body_motion(s, &(b.pos, b.rot), b.radius)))
        .fold((String::new(), -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
    Err(TiltError::DoesNotStand(SettleError::Moved { block, moved_m, tolerance_m: 0.0 }))
}

/// The rigid check that `layout` stands as given, the tilting table's at α = 0: every
/// free block touches something, and the wall released from rest under gravity alone
/// comes to rest without a block moving more than the per-increment collapse
/// displacement (a fraction [`TiltParams::collapse_increment_fraction`], default 0.05,
/// of the wall's width). Changes nothing; the protocols that load a rigid wall run it
/// before loading.
///
/// # Errors
/// [`TiltError::DoesNotStand`] naming the block (and how far it moved),
/// [`TiltError::Parameter`] or [`TiltError::Nscd`] for a solver setting the rigid solver
/// refuses.
pub fn check_stands_rigid(layout: &Layout, params: &NscdParams) -> Result<(), TiltError> {
    let base = NscdSimulation::new(layout, &params.for_trials()).map_err(tilt_error)?;
    touches_something(&base, params)?;
    let d = TiltParams::default();
    let width = layout.bounds().extent().y;
    let limits =
        TrialLimits::of(layout, &base, d.collapse_increment_fraction * width, d.collapse_displacement_fraction * width);
    let first = trial(&base, &base, 0.0, &limits).map_err(tilt_error)?;
    stood(&base, &first)
}

/// Runs one trial at `alpha_deg` from `base` (the reference state at rest), warm-started
/// from `warm`.
fn trial(
    base: &NscdSimulation,
    warm: &NscdSimulation,
    alpha_deg: f64,
    limits: &TrialLimits,
) -> Result<Trial, NscdError> {
    released(base, warm, limits, |sim| sim.set_tilt(deg_to_rad(alpha_deg)))
}

/// Periods of the slowest rope mode a trial of a wall held by ropes runs at most
/// (module doc, "A wall held by ropes").
pub const ROPE_PERIODS: f64 = 8.0;

/// The most steps of one trial of a wall held by ropes, whatever its ropes' periods.
pub const ROPE_TRIAL_MAX_STEPS: u32 = 50_000;

/// What ends a trial (module doc).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TrialLimits {
    /// A rigid trial is unstable once a block has moved this far since its start, m (the
    /// per-increment collapse displacement).
    pub(crate) increment_m: f64,
    /// `Some` for a wall held by ropes.
    pub(crate) rope: Option<RopeTrial>,
}

/// A trial of a wall held by ropes (module doc, "A wall held by ropes").
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RopeTrial {
    /// Steps of the trial: [`ROPE_PERIODS`] periods of the slowest rope mode, at least the
    /// rigid trial's `trial_steps`, at most [`ROPE_TRIAL_MAX_STEPS`].
    pub(crate) steps: u32,
    /// Unstable once a block has moved this far since the reference state, m: the
    /// quasi-static tests' total collapse displacement.
    pub(crate) total_m: f64,
    /// The reference state's poses (as built).
    pub(crate) reference: Vec<BodyPose>,
}

impl TrialLimits {
    /// The limits of the trials of `layout` from `base` (its reference state): the
    /// per-increment collapse displacement `increment_m` (m) and, if the layout has ropes
    /// bearing on a free block, the rope trial with the total collapse displacement
    /// `total_m` (m) and a window of [`ROPE_PERIODS`] periods `2π/√λ` of the slowest
    /// rope-held block, `λ` its largest eigenvalue of the ropes' stiffness at the
    /// deflection as built ([`crate::dem::timestep::Stiffness::add_restraints`]) against its
    /// mass (rad²/s²).
    ///
    /// A rope without pretension that just touches the face as built (`T₀ = 0`, `d = 0`)
    /// has no stiffness there: its force `EA δ̄³ / s³` is all elongation and grows only as
    /// the wall moves into it. The ropes' stiffness is then bounded over the deflections a
    /// stable trial reaches, up to `increment_m` ([`crate::dem::rope::stiffness_bound`]:
    /// the elongation's `2 EA δ̄² / (L² L_ref)` in it), so that the window lasts while the
    /// rope catches the wall instead of the rigid trial's `trial_steps`.
    pub(crate) fn of(layout: &Layout, base: &NscdSimulation, increment_m: f64, total_m: f64) -> TrialLimits {
        let bodies = base.bodies();
        let ropes = RopeLoad::of_layout(layout, bodies);
        let rope = if ropes.iter().any(|r| !r.bearers.is_empty()) {
            let slack = ropes.iter().any(|r| {
                let d = r.deflection(bodies);
                !r.bearers.is_empty() && !(stiffness_bound(&r.rope, d, d) > 0.0)
            });
            let reach = if slack { increment_m } else { 0.0 };
            let mut k = Stiffness::new(bodies, &[]);
            k.add_restraints(bodies, &vec![None; bodies.len()], &ropes, reach);
            let lambda = k.body_eigenvalues().iter().copied().filter(|l| *l > 0.0).fold(f64::INFINITY, f64::min);
            let dt = base.params().dt_s;
            let p = base.params().trial_steps;
            let steps = if lambda.is_finite() {
                let n = (ROPE_PERIODS * std::f64::consts::TAU / lambda.sqrt() / dt).ceil();
                n.clamp(f64::from(p), f64::from(ROPE_TRIAL_MAX_STEPS.max(p))) as u32
            } else {
                p
            };
            Some(RopeTrial { steps, total_m, reference: poses(base) })
        } else {
            None
        };
        TrialLimits { increment_m, rope }
    }
}

/// Runs one trial (see the module doc) from `base` (the reference state at rest) loaded by
/// `load`, warm-started from `warm`, with the limits `limits` (a wall held by ropes: the
/// module doc's "A wall held by ropes").
pub(crate) fn released(
    base: &NscdSimulation,
    warm: &NscdSimulation,
    limits: &TrialLimits,
    load: impl FnOnce(&mut NscdSimulation),
) -> Result<Trial, NscdError> {
    let p = *base.params();
    let mut sim = base.clone();
    sim.warm_start_from(warm);
    load(&mut sim);
    let start = poses(&sim);
    let (steps0, it0) = (sim.steps(), sim.iterations());
    let v_rest = p.rest_velocity_ratio * sim.gravity_magnitude() * p.dt_s;
    let n = limits.rope.as_ref().map_or(p.trial_steps, |r| r.steps) as usize;
    let mut speeds = Vec::with_capacity(n);
    let mut at_rest = 0u32;
    let mut reason = None;
    let mut energy = 0.0;
    for _ in 0..n {
        sim.step(|_| Vec3::zeros())?;
        if largest_motion(&sim, &start) > limits.increment_m {
            reason = Some(CollapseReason::IncrementDisplacement);
            break;
        }
        if let Some(r) = &limits.rope {
            if largest_motion(&sim, &r.reference) > r.total_m {
                reason = Some(CollapseReason::TotalDisplacement);
                break;
            }
        }
        let speed = sim.max_point_speed();
        speeds.push(speed);
        if limits.rope.is_some() {
            // Kinetic damping: the ropes' force develops as the wall moves into them; at a
            // peak of the kinetic energy the wall passes its equilibrium, stopped there.
            let e = sim.kinetic_energy();
            if e < energy {
                sim.stop();
                energy = 0.0;
            } else {
                energy = e;
            }
        }
        at_rest = if speed < v_rest { at_rest + 1 } else { 0 };
        if at_rest >= p.rest_steps {
            break;
        }
    }
    if reason.is_none() && speeds.len() == n {
        let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len() as f64;
        let (first, second) = (mean(&speeds[..n / 2]), mean(&speeds[n / 2..]));
        if second > p.growth_ratio * first && second > v_rest {
            reason = Some(CollapseReason::NoEquilibrium);
        }
    }
    let (steps, iterations) = (sim.steps() - steps0, sim.iterations() - it0);
    Ok(Trial { sim, reason, steps, iterations })
}

/// Runs the tilting-table test of a layout at the rigid limit by non-smooth contact
/// dynamics (see the module doc). `tilt` gives the increment, the resolution, the largest
/// tilt and the per-increment collapse displacement; its relaxation settings (tolerance,
/// step budget, predictor, acceleration, implicit) do not apply. The result's
/// `elastic_scale_m` is 0 (rigid joints), `steps` counts time steps, `iterations` NSGS
/// sweeps, `dt_s` is the time step, and each increment's `unbalanced_ratio` is the last
/// NSGS residual over `g h`.
///
/// # Errors
/// [`TiltError::Parameter`] for a tilt or nscd parameter out of range (its key),
/// [`TiltError::Nscd`] for a joint with cohesion or tensile strength,
/// [`TiltError::DoesNotStand`] if a free block touches nothing or the wall is not stable
/// at α = 0, [`TiltError::Dem`] if the state blows up.
pub fn run_tilt_nscd(layout: &Layout, params: &NscdParams, tilt: &TiltParams) -> Result<TiltResult, TiltError> {
    let mut first = run_tilt_nscd_once(layout, params, tilt)?;
    first.after_snap = after_snap(layout, tilt, &first, |lifted| run_tilt_nscd_once(layout, params, lifted))?;
    Ok(first)
}

/// [`run_tilt_nscd`] without the fall past a caught snap.
fn run_tilt_nscd_once(layout: &Layout, params: &NscdParams, tilt: &TiltParams) -> Result<TiltResult, TiltError> {
    tilt.validate().map_err(TiltError::Parameter)?;
    let t0 = Instant::now();
    let base = NscdSimulation::new(layout, &params.for_trials()).map_err(tilt_error)?;
    touches_something(&base, params)?;
    // The penalty engine's view of the same layout, for the monitors and the mechanism.
    let reader = Simulation::new(layout, SolverParams::default());
    let monitors = monitor_points(layout, &reader);
    let reference: Vec<Vec3> = monitors.iter().map(|m| base.bodies()[m.body].to_world(&m.local)).collect();
    let width = layout.bounds().extent().y;
    let inc_limit = tilt.collapse_increment_fraction * width;
    let limits = TrialLimits::of(layout, &base, inc_limit, tilt.collapse_displacement_fraction * width);
    let g_h = base.gravity_magnitude() * params.dt_s;
    // The table's overshoot (`Layout::table_overshoot_deg`, 0 as built), added as the
    // penalty path adds it.
    let overshoot = layout.table_overshoot_deg;

    let mut increments = Vec::new();
    let (mut total_steps, mut total_iterations, mut detections) = (0u64, 0u64, 0u64);
    let mut record = |alpha: f64, t: &Trial, increments: &mut Vec<Increment>| {
        total_steps += t.steps;
        total_iterations += t.iterations;
        detections += t.sim.detections();
        increments.push(Increment {
            alpha_deg: alpha,
            stable: t.reason.is_none(),
            steps: t.steps,
            iterations: u32::try_from(t.iterations).unwrap_or(u32::MAX),
            displacement_m: displacements(&t.sim, &monitors, &reference),
            unbalanced_ratio: t.sim.last_step().residual_m_per_s / g_h,
            newton_handed_over: false,
        });
    };

    let first = trial(&base, &base, 0.0, &limits).map_err(tilt_error)?;
    record(0.0, &first, &mut increments);
    stood(&base, &first)?;
    let mut stable = first.sim;
    let mut last_stable = 0.0;
    let mut unstable: Option<(f64, CollapseReason, NscdSimulation)> = None;
    // The state the collapsing trial started from (the reference for rigid trials).
    let mut from = base.clone();
    if limits.rope.is_some() {
        // A compliant wall follows the path (module doc, "A wall held by ropes").
        stable.stop();
        let mut up: Option<f64> = None;
        loop {
            let next = match up {
                None => (last_stable + tilt.step_deg).min(tilt.max_angle_deg),
                Some(u) if u - last_stable > tilt.resolution_deg + 1e-12 => 0.5 * (u + last_stable),
                Some(_) => break,
            };
            if up.is_none() && next <= last_stable {
                break;
            }
            let t = trial(&stable, &stable, effective_tilt_deg(next, overshoot), &limits).map_err(tilt_error)?;
            record(next, &t, &mut increments);
            match t.reason {
                None => {
                    last_stable = next;
                    stable = t.sim;
                    stable.stop();
                }
                Some(r) => {
                    up = Some(next);
                    from = stable.clone();
                    unstable = Some((next, r, t.sim));
                }
            }
        }
    }
    // Rigid trials do not depend on the path (each starts from the reference state):
    // bisection of [0, max_angle_deg], the largest tilt itself tried only if every trial
    // below it stood.
    let top = tilt.max_angle_deg;
    let mut up = if limits.rope.is_some() { last_stable } else { top };
    while up - last_stable > tilt.resolution_deg + 1e-12 {
        let mid = 0.5 * (up + last_stable);
        let t = trial(&base, &stable, effective_tilt_deg(mid, overshoot), &limits).map_err(tilt_error)?;
        record(mid, &t, &mut increments);
        match t.reason {
            None => {
                last_stable = mid;
                stable = t.sim;
            }
            Some(r) => {
                up = mid;
                unstable = Some((mid, r, t.sim));
            }
        }
    }
    if unstable.is_none() && limits.rope.is_none() {
        let t = trial(&base, &stable, effective_tilt_deg(top, overshoot), &limits).map_err(tilt_error)?;
        record(top, &t, &mut increments);
        match t.reason {
            None => {
                last_stable = top;
                stable = t.sim;
            }
            Some(r) => unstable = Some((top, r, t.sim)),
        }
    }
    increments.sort_by(|a, b| (!a.stable).cmp(&!b.stable).then(a.alpha_deg.total_cmp(&b.alpha_deg)));
    // The bracket's upper end, why it failed and the mechanism read from it (none if the
    // wall stood to the largest tilt).
    let (first_unstable_deg, collapse_reason, mechanism) = match unstable {
        Some((up, reason, failed)) => {
            (Some(up), Some(reason), read_mechanism(&reader, &from, &stable, &failed, inc_limit))
        }
        None => (None, None, Mechanism::none()),
    };
    let bracket = Bracket { last_stable_deg: last_stable, first_unstable_deg, collapse_reason, mechanism };
    let work = RigidWork { steps: total_steps, iterations: total_iterations, detections, dt_s: params.dt_s, t0 };
    Ok(rigid_result(bracket, &monitors, increments, work, width))
}

/// The bracket of a rigid tilt: the last stable and first unstable tilts (degrees), why the
/// upper end failed and the mechanism read there.
pub(crate) struct Bracket {
    pub last_stable_deg: f64,
    pub first_unstable_deg: Option<f64>,
    pub collapse_reason: Option<CollapseReason>,
    pub mechanism: Mechanism,
}

/// The work of a rigid tilt: its steps, solver iterations, contact detections, time step
/// (s) and start.
pub(crate) struct RigidWork {
    pub steps: u64,
    pub iterations: u64,
    pub detections: u64,
    pub dt_s: f64,
    pub t0: Instant,
}

/// The result of a tilt of rigid blocks (by nscd, quasi-statically or rolled by hand): no
/// elastic scale, no density scaling, a bracket always reliable (its trials are motions).
pub(crate) fn rigid_result(
    bracket: Bracket,
    monitors: &[MonitorPoint],
    increments: Vec<Increment>,
    work: RigidWork,
    width_m: f64,
) -> TiltResult {
    TiltResult {
        last_stable_deg: bracket.last_stable_deg,
        first_unstable_deg: bracket.first_unstable_deg,
        collapse_reason: bracket.collapse_reason,
        mechanism: bracket.mechanism,
        monitors: monitors.iter().map(|m| m.name.clone()).collect(),
        increments,
        steps: work.steps,
        iterations: work.iterations,
        dt_s: work.dt_s,
        wall_time_s: work.t0.elapsed().as_secs_f64(),
        wall_width_m: width_m,
        elastic_scale_m: 0.0,
        detections: work.detections,
        max_density_scale: 1.0,
        scalar_fallbacks_deg: Vec::new(),
        bracket_reliable: true,
        after_snap: None,
    }
}

/// Out-of-plane (y) displacement of each monitor point from its reference, m.
pub(crate) fn displacements(sim: &NscdSimulation, monitors: &[MonitorPoint], reference: &[Vec3]) -> Vec<f64> {
    monitors.iter().zip(reference).map(|(m, r)| (sim.bodies()[m.body].to_world(&m.local) - r).y).collect()
}

/// The mechanism (see the module doc) through the penalty path's reading: `reader` (the
/// penalty engine's contacts of the layout at its reference configuration) with the
/// contact forces of the last stable trial, against the first unstable trial carried along
/// its velocity to a block motion of `limit` (m).
pub(crate) fn read_mechanism(
    reader: &Simulation,
    base: &NscdSimulation,
    stable: &NscdSimulation,
    failed: &NscdSimulation,
    limit: f64,
) -> Mechanism {
    let mut at_rest = reader.clone();
    let forces = stable.point_forces();
    for c in &mut at_rest.state.contacts {
        c.force = stable
            .contact_points()
            .iter()
            .zip(&forces)
            .filter(|(p, _)| p.a == c.a && p.b == c.b)
            .fold(Vec3::zeros(), |s, (_, f)| s + f);
    }
    let start = poses(base);
    let speed = failed.max_point_speed();
    let extra = if speed > 0.0 { (limit - largest_motion(failed, &start)).max(0.0) / speed } else { 0.0 };
    let mut moved = at_rest.clone();
    for (b, f) in moved.state.bodies.iter_mut().zip(failed.bodies()) {
        b.pos = f.pos + f.vel * extra;
        b.rot = crate::dem::state::rotation_increment(f.angvel * extra) * f.rot;
        b.rot_mat = *b.rot.to_rotation_matrix().matrix();
    }
    mechanism(&at_rest, &moved)
}
