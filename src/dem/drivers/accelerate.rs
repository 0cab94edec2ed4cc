//! Secant acceleration of slow creep in dynamic relaxation, and the stability indicator it
//! reads on the way.
//!
//! Near a limit point (a wall close to collapse) the lowest stiffness mode of the assembly
//! goes to zero and dynamic relaxation creeps: the fast modes have died out, and the state
//! moves, a little per step, along one slow mode towards equilibrium (or away from it, if
//! there is none). Every [`SecantAcceleration::window`] steps, once
//! [`SecantAcceleration::warmup`] steps have been taken, the motion over the last window
//! `Δx` (centroid translations and rotation vectors of every free body) and the change of
//! the out-of-balance forces and moments `Δg` give the secant stiffness along the motion,
//! `k = −Δx·Δg / Δx·Δx`, and the out-of-balance force along it, `Δx·g`: the work-conjugate
//! pairs of a generalized coordinate, so no metric between translations and rotations is
//! assumed. Then:
//!
//! - `k > 0` and two successive windows moving the same way (cosine of their motions at
//!   least [`SecantAcceleration::min_alignment`]): the out-of-balance force along the
//!   motion is modelled as `φ(t) = Δx·g − c₁ t − c₂ t²` in the travel `t` (windows of
//!   motion ahead), its stiffness extrapolated linearly from the secant stiffnesses of the
//!   last two windows. The state jumps to the first root, `t Δx` with
//!   `t = 2 Δx·g / (c₁ + √(c₁² + 4 c₂ Δx·g))` capped at [`SecantAcceleration::max_scale`],
//!   through [`Simulation::predict`] (the joints follow the jump as a straight path), and
//!   relaxation goes on from rest there. Where the softening stiffness reaches zero before
//!   the force does (no root ahead: the limit point comes first), the state does not jump,
//!   so a jump never carries a stable state past its limit point.
//! - `k ≤ 0` while the out-of-balance force pushes along the motion and grows from window
//!   to window, in [`SecantAcceleration::negative_windows`] successive windows moving the
//!   same way: the second-order work along the motion is negative (Hill's stability
//!   criterion) and the state accelerates away from any equilibrium along a softening path;
//!   the indicator fires. A dynamic overshoot past a limit point with an equilibrium before
//!   it does not count: there the force opposes the motion.
//! - When the indicator fires, the path ahead is probed ([`Accelerator::probe`]): the state
//!   is moved along the motion of the last window, at rest, by travels growing geometrically
//!   up to a given reach (the protocol's collapse displacement), and the out-of-balance
//!   force along the motion is read at each. If it turns against the motion somewhere, an
//!   equilibrium lies on the path (the window softened locally: a knife-edge joint whose
//!   closed length shrinks past a quadrature point, the creep of a stiff joint seen through
//!   its fast modes) and the relaxation goes on from the last probe that still pushed along
//!   the motion. Only if it pushes the state along the whole way is there no equilibrium
//!   near the path: [`Creep::Unstable`].
//!
//! This is the 1-D secant (quasi-Newton) step of path-following solvers applied to the
//! slow mode that dynamic relaxation isolates (Underwood 1983, "Dynamic relaxation", in
//! Computational Methods for Transient Analysis, ch. 5, on the slow mode; Hill 1958 and
//! Darve's second-order work for the indicator).
//!
//! Both leave short relaxations (fewer than `warmup + 2 window` steps) untouched.

use crate::dem::engine::Simulation;
use crate::math::Vec3;
use nalgebra::UnitQuaternion;

pub use crate::dem::penalty::SecantAcceleration;

/// What the accelerator did at a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Creep {
    /// Nothing (not a window boundary, or no reason to act).
    Continue,
    /// The state jumped along the slow mode.
    Jumped,
    /// Negative stiffness along a persistent motion: the stability indicator fired (see
    /// [`Accelerator::probe`] for whether an equilibrium lies ahead).
    Unstable,
}

/// What the probe of the path ahead found ([`Accelerator::probe`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Ahead {
    /// The out-of-balance force pushes the state along the motion over the whole reach: no
    /// equilibrium near the path.
    NoEquilibrium,
    /// The force turns against the motion within the reach: an equilibrium lies ahead. The
    /// pose increment (per body: translation, m; rotation vector, rad) to the last probe
    /// that still pushed along the motion (zero if the first did not).
    Equilibrium(Vec<Vec3>, Vec<Vec3>),
}

/// Probe points of [`Accelerator::probe`]: travels `reach · 2^-k` for `k` from this down to
/// 0.
const PROBE_HALVINGS: i32 = 12;

/// Bisections of [`Accelerator::probe`] between the last probe that pushed the state along
/// the motion and the first that did not.
const PROBE_BISECTIONS: u32 = 10;

/// The largest motion of a free body of `sim` under the pose increment `(dpos, drot)` (per
/// body: translation, m; rotation vector, rad): centroid translation plus rotation times
/// the body's radius, m.
pub fn largest_body_motion(sim: &Simulation, dpos: &[Vec3], drot: &[Vec3]) -> f64 {
    sim.state
        .bodies
        .iter()
        .zip(dpos.iter().zip(drot))
        .filter(|(b, _)| !b.fixed())
        .map(|(b, (d, r))| d.norm() + r.norm() * b.radius)
        .fold(0.0, f64::max)
}

/// [`Accelerator::probe`] along a given motion `(dpos, drot)` (per body: translation, m;
/// rotation vector, rad; table frame) instead of the last window's: travels `t` of it whose
/// largest body motion is `reach · 2^-k` (m), `t` at most `max_windows`. Leaves `sim`
/// unchanged.
pub fn probe_along(sim: &Simulation, dpos: &[Vec3], drot: &[Vec3], reach: f64, max_windows: f64) -> Ahead {
    let per_unit = largest_body_motion(sim, dpos, drot);
    if !(per_unit > 0.0 && reach > 0.0) {
        return Ahead::NoEquilibrium;
    }
    let scaled = |v: &[Vec3], t: f64| v.iter().map(|x| x * t).collect::<Vec<_>>();
    let pushes = |t: f64| {
        let mut trial = sim.clone();
        trial.predict(&scaled(dpos, t), &scaled(drot, t));
        trial.assess_predicted();
        let along: f64 = (0..trial.state.bodies.len())
            .map(|i| {
                let (f, m) = trial.unbalanced(i);
                f.dot(&dpos[i]) + m.dot(&drot[i])
            })
            .sum();
        along > 0.0
    };
    let mut last_pushing = 0.0;
    let t_max = (reach / per_unit).min(max_windows);
    for k in (0..=PROBE_HALVINGS).rev() {
        let t = t_max * 0.5f64.powi(k);
        if !pushes(t) {
            // The equilibrium lies between the last probe that pushed and this one:
            // narrow it down to an eighth of a percent of the interval.
            let mut hi = t;
            for _ in 0..PROBE_BISECTIONS {
                let mid = 0.5 * (last_pushing + hi);
                if pushes(mid) {
                    last_pushing = mid;
                } else {
                    hi = mid;
                }
            }
            return Ahead::Equilibrium(scaled(dpos, last_pushing), scaled(drot, last_pushing));
        }
        last_pushing = t;
    }
    Ahead::NoEquilibrium
}

/// The accelerator's memory within one relaxation.
#[derive(Debug, Clone)]
pub struct Accelerator {
    settings: SecantAcceleration,
    /// Pose and generalized force at the last window boundary.
    last: Option<(Vec<(Vec3, UnitQuaternion<f64>)>, Vec<f64>)>,
    /// Motion of the last window.
    last_dx: Option<Vec<f64>>,
    negative: u32,
    /// Stiffness per unit motion squared and force along the motion of the last window.
    last_window: Option<(f64, f64)>,
    /// Whether the last window moved the way of the one before, pushed by the
    /// out-of-balance force along its motion (a creep the probe can follow).
    creeping: bool,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Accelerator {
    /// A fresh accelerator.
    pub fn new(settings: SecantAcceleration) -> Accelerator {
        Accelerator { settings, last: None, last_dx: None, negative: 0, last_window: None, creeping: false }
    }

    /// Probes the path ahead of a state on which the indicator fired: moves a copy of `sim`
    /// along the motion of the last window, at rest ([`Simulation::predict`], the joints
    /// following a straight path from the state), by travels whose largest body motion
    /// (centroid translation plus rotation times the body's radius) is `reach · 2^-k`, `k`
    /// = `PROBE_HALVINGS` … 0, and reads the out-of-balance force and moment along the
    /// motion (`Δx·g`, the work-conjugate pairs) at each. `reach` in m, and at most
    /// `max_windows` windows of motion. Leaves `sim` unchanged.
    pub fn probe(&self, sim: &Simulation, reach: f64, max_windows: f64) -> Ahead {
        let Some((dpos, drot)) = self.last_motion() else { return Ahead::NoEquilibrium };
        probe_along(sim, &dpos, &drot, reach, max_windows)
    }

    /// Whether the last window moved the way of the one before, pushed by the
    /// out-of-balance force along its motion: a creep [`Accelerator::probe`] can follow
    /// to its equilibrium.
    pub fn creeping(&self) -> bool {
        self.creeping
    }

    /// Forgets the windows seen so far (after the state was moved).
    pub fn reset(&mut self) {
        self.creeping = false;
        self.last = None;
        self.last_dx = None;
        self.negative = 0;
        self.last_window = None;
    }

    /// The motion of the last window: per body, in body order, the centroid translation (m)
    /// and the rotation vector (rad), table frame; `None` before the first window.
    pub fn last_motion(&self) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
        let dx = self.last_dx.as_ref()?;
        Some(dx.chunks_exact(6).map(|c| (Vec3::new(c[0], c[1], c[2]), Vec3::new(c[3], c[4], c[5]))).unzip())
    }

    /// Called after step number `steps` (1-based) of a relaxation.
    pub fn observe(&mut self, sim: &mut Simulation, steps: u64) -> Creep {
        let s = self.settings;
        if steps < s.warmup || (steps - s.warmup) % s.window != 0 {
            return Creep::Continue;
        }
        let pose: Vec<(Vec3, UnitQuaternion<f64>)> = sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
        let mut g = Vec::with_capacity(6 * pose.len());
        for k in 0..pose.len() {
            let (f, t) = sim.unbalanced(k);
            g.extend_from_slice(&[f.x, f.y, f.z, t.x, t.y, t.z]);
        }
        let Some((pose0, g0)) = self.last.replace((pose.clone(), g.clone())) else { return Creep::Continue };
        let mut dx = Vec::with_capacity(g.len());
        for (k, ((x1, q1), (x0, q0))) in pose.iter().zip(&pose0).enumerate() {
            if sim.state.bodies[k].fixed() {
                dx.extend_from_slice(&[0.0; 6]);
                continue;
            }
            let d = x1 - x0;
            let r = (q1 * q0.inverse()).scaled_axis();
            dx.extend_from_slice(&[d.x, d.y, d.z, r.x, r.y, r.z]);
        }
        let dg: Vec<f64> = g.iter().zip(&g0).map(|(a, b)| a - b).collect();
        let work = dot(&dx, &g);
        let stiff = -dot(&dx, &dg);
        let dxx = dot(&dx, &dx);
        let align = match &self.last_dx {
            Some(p) => dot(p, &dx) / (dot(p, p) * dxx).sqrt(),
            None => f64::NAN,
        };
        self.last_dx = Some(dx.clone());
        let (kappa1, force1) = self.last_window.replace((stiff / dxx, work / dxx.sqrt())).unzip();
        let aligned = align >= s.min_alignment;
        self.creeping = aligned && work > 0.0;
        if stiff <= 0.0 && work > 0.0 && aligned && force1.is_some_and(|f| work / dxx.sqrt() > f) {
            self.negative += 1;
            if self.negative >= s.negative_windows {
                return Creep::Unstable;
            }
            return Creep::Continue;
        }
        self.negative = 0;
        let Some(kappa1) = kappa1 else { return Creep::Continue };
        if !(aligned && stiff > 0.0 && work > 0.0) {
            return Creep::Continue;
        }
        // Travel t (in windows of motion) to the root of the out-of-balance force along the
        // motion, its stiffness extrapolated linearly from the last two windows (centred at
        // t = -1/2 and -3/2): phi(t) = work - c1 t - c2 t^2.
        let k1 = kappa1 * dxx;
        let c2 = 0.5 * (stiff - k1);
        let c1 = stiff + c2;
        if c1 <= 0.0 {
            return Creep::Continue;
        }
        let disc = c1 * c1 + 4.0 * c2 * work;
        if disc < 0.0 {
            return Creep::Continue; // the peak comes first: no root ahead along this line
        }
        let t = 2.0 * work / (c1 + disc.sqrt());
        if !(t > 1.0) {
            return Creep::Continue;
        }
        let scale = t.min(s.max_scale);
        let (dpos, drot): (Vec<Vec3>, Vec<Vec3>) = dx
            .chunks_exact(6)
            .map(|c| (Vec3::new(c[0], c[1], c[2]) * scale, Vec3::new(c[3], c[4], c[5]) * scale))
            .unzip();
        sim.predict(&dpos, &drot);
        self.reset();
        Creep::Jumped
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::{RunToEquilibrium, SolverParams};
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    /// A block 0.3 × 0.2 × 0.1 m (φ 35°) settled on the table, then tilted by `deg`.
    fn block_tilted(deg: f64) -> Simulation {
        let l = layout_of(vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])], 1e8, 5e7, 35.0, BaseSliding::Free);
        let mut sim = Simulation::new(&l, SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-9, 400_000).unwrap());
        sim.set_tilt(deg.to_radians());
        sim
    }

    /// At least `steps` steps of dynamic relaxation observed by an accelerator with windows
    /// of 16 steps, ending on a window with a motion; the accelerator and what it said at
    /// each window.
    fn observe_steps(sim: &mut Simulation, steps: u64) -> (Accelerator, Vec<Creep>) {
        let settings = SecantAcceleration { warmup: 16, window: 16, ..SecantAcceleration::default() };
        let mut acc = Accelerator::new(settings);
        let mut said = Vec::new();
        // Until a window boundary that did not jump (a jump forgets the motion).
        for k in 1..=steps + 160 {
            sim.step().unwrap();
            let c = acc.observe(sim, k);
            if k >= 16 && (k - 16) % 16 == 0 {
                said.push(c);
                if k >= steps && acc.last_motion().is_some() {
                    break;
                }
            }
        }
        (acc, said)
    }

    /// Past its friction angle (40° against 35°) the block slides: once the joint's shear
    /// has reached its Coulomb limit, the probe finds the out-of-balance force pushing it
    /// along its motion over the whole reach, so no equilibrium lies near the path, and
    /// the indicator does not fire (the force along the motion does not grow: a slide at
    /// constant friction, not a softening mechanism).
    #[test]
    fn a_sliding_block_has_no_equilibrium_ahead() {
        let mut sim = block_tilted(40.0);
        let (acc, said) = observe_steps(&mut sim, 480);
        assert!(!said.contains(&Creep::Unstable), "{said:?}");
        let (dpos, _) = acc.last_motion().unwrap();
        assert!(dpos[0].y > 0.0, "the block slides down the table (+y): {:?}", dpos[0]);
        assert_eq!(acc.probe(&sim, 0.01, 1e6), Ahead::NoEquilibrium);
    }

    /// Below its friction and toppling limits (20°) the block, released from its state at
    /// 0°, moves elastically towards its new equilibrium: the probe along that motion finds
    /// the force turning against it within the elastic shear of the joint (Ks = 5e7 Pa/m,
    /// under 0.1 mm), not after the 10 mm reach.
    #[test]
    fn a_stable_block_has_an_equilibrium_ahead() {
        let mut sim = block_tilted(20.0);
        let (acc, said) = observe_steps(&mut sim, 48);
        assert!(!said.contains(&Creep::Unstable), "{said:?}");
        let Ahead::Equilibrium(dpos, drot) = acc.probe(&sim, 0.01, 1e6) else { panic!("no equilibrium ahead") };
        assert!(dpos[0].norm() + drot[0].norm() * sim.state.bodies[0].radius < 1e-4, "{:?}", dpos[0]);
    }
}
