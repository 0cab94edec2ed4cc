//! The stable path of a tilting-table test: the secant predictor of the next equilibrium,
//! one increment's solve and its collapse checks, the bisection's trials, and the elastic
//! displacement scale of the joints. The lateral pushover (`loading::lateral_pushover`)
//! walks the same path in its load multiplier ([`Ctx::load`]).

use super::*;
use crate::dem::drivers::accelerate::largest_body_motion;
use crate::dem::drivers::implicit::{self};
use crate::dem::{solve_static, DemError, DensityScaling, End, Simulation, StaticSolve};
use crate::layout::Layout;
use crate::loading::monitors::{body_motion, largest_motion, monitor_displacements, BodyPose, MonitorPoint};
use crate::math::Vec3;

/// Pose of every body, in body order.
pub(super) type Pose = Vec<BodyPose>;

/// A predicted increment: translation (m) and rotation vector (rad) per body.
pub(super) type Prediction = implicit::PoseIncrement;

pub(super) fn pose(sim: &Simulation) -> Pose {
    sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect()
}

/// The last four stable states (tilt in degrees, pose), oldest first.
#[derive(Default)]
pub(super) struct Secant {
    pub(super) states: Vec<(f64, Pose)>,
}

/// The predictor extrapolates only a nearly linear or a steadily accelerating response.
/// With `r` the largest body motion per degree of an increment (last `r₂`, then `r₁`,
/// `r₀`), it is used if `r₂ ≤ LINEAR_RESPONSE_RATIO r₁`, or if the motion has been
/// accelerating for two increments (`r₁ ≥ STEADY_GROWTH r₀`) and `r₂ ≤
/// ACCELERATING_RESPONSE_RATIO r₁` (a wall approaching its limit point). A sudden jump of
/// the rate after a steady one is a local slip event (an end stone sliding): a linear jump
/// would impose that slip again at every increment, and friction would keep it, so the
/// increment relaxes from rest.
pub(super) const LINEAR_RESPONSE_RATIO: f64 = 1.2;
/// See [`LINEAR_RESPONSE_RATIO`].
pub(super) const STEADY_GROWTH: f64 = 1.05;
/// See [`LINEAR_RESPONSE_RATIO`].
pub(super) const ACCELERATING_RESPONSE_RATIO: f64 = 2.5;

impl Secant {
    pub(super) fn push(&mut self, alpha: f64, sim: &Simulation) {
        self.states.push((alpha, pose(sim)));
        if self.states.len() > 4 {
            self.states.remove(0);
        }
    }

    /// Largest body motion ([`body_motion`] with a radius of 1 m) per degree of tilt between
    /// two stable states.
    pub(super) fn rate(a: &(f64, Pose), b: &(f64, Pose)) -> f64 {
        let m = a.1.iter().zip(&b.1).map(|(from, to)| body_motion(from, to, 1.0)).fold(0.0, f64::max);
        m / (b.0 - a.0).abs()
    }

    /// Whether the response is smooth enough to extrapolate ([`LINEAR_RESPONSE_RATIO`]).
    pub(super) fn smooth(&self) -> bool {
        let n = self.states.len();
        if n < 3 {
            return false;
        }
        let s = &self.states;
        let (r1, r2) = (Self::rate(&s[n - 3], &s[n - 2]), Self::rate(&s[n - 2], &s[n - 1]));
        if r2 <= LINEAR_RESPONSE_RATIO * r1 {
            return true;
        }
        n == 4 && r1 >= STEADY_GROWTH * Self::rate(&s[0], &s[1]) && r2 <= ACCELERATING_RESPONSE_RATIO * r1
    }

    /// The motion from the second-last to the last stable state, scaled linearly in tilt to
    /// an increment from the last state to `alpha` (degrees); `None` until three stable
    /// states are known or where the response is not smooth ([`LINEAR_RESPONSE_RATIO`]; a
    /// NaN rate, from a degenerate increment, is not smooth either).
    pub(super) fn predict(&self, alpha: f64) -> Option<Prediction> {
        if !self.smooth() {
            return None;
        }
        let n = self.states.len();
        let ((a1, p1), (a2, p2)) = (&self.states[n - 2], &self.states[n - 1]);
        let scale = (alpha - a2) / (a2 - a1);
        if !scale.is_finite() {
            return None;
        }
        Some(
            p1.iter()
                .zip(p2)
                .map(|((x0, q0), (x1, q1))| ((x1 - x0) * scale, (q1 * q0.inverse()).scaled_axis() * scale))
                .unzip(),
        )
    }
}

/// How an increment or trial ended: the wall stood, or it collapsed and why.
pub(super) enum StageEnd {
    Stable,
    Collapsed(CollapseReason),
}

/// What one increment or trial came to: its stage, the dynamic-relaxation steps and the
/// implicit iterations it took.
pub(super) struct StageRun {
    pub(super) stage: StageEnd,
    pub(super) steps: u64,
    pub(super) iterations: u32,
    /// The Newton stage handed the solve over ([`crate::dem::SolveOutcome::newton_unsolved`]).
    pub(super) newton_handed_over: bool,
}

pub(crate) struct Ctx<'a> {
    pub(crate) params: &'a TiltParams,
    /// Sets the load of a trial on a state: the tilt α (degrees) of the tilting table, the
    /// load multiplier λ of the lateral pushover (`loading::lateral_pushover`).
    pub(crate) load: &'a dyn Fn(&mut Simulation, f64),
    /// The static solve of every increment and trial (its reach set per trial).
    pub(crate) solve: StaticSolve,
    pub(crate) monitors: &'a [MonitorPoint],
    pub(crate) reference: Vec<Vec3>,
    pub(crate) width: f64,
    /// [`elastic_scale`], m.
    pub(crate) elastic: f64,
}

impl Ctx<'_> {
    pub(super) fn displacements(&self, sim: &Simulation) -> Vec<f64> {
        monitor_displacements(sim, self.monitors, &self.reference)
    }

    /// Relaxes `sim` at its tilt from `prediction` (applied as one jump) through the solver
    /// seam ([`solve_static`]), with this protocol's collapse criteria as the stop check.
    pub(super) fn run_stage(&self, sim: &mut Simulation, prediction: Option<Prediction>) -> Result<StageRun, DemError> {
        let start = pose(sim);
        let inc_limit = self.inc_limit();
        let tot_limit = (self.params.collapse_displacement_fraction * self.width).max(self.elastic);
        let check = |sim: &Simulation| {
            if largest_motion(sim, &start) > inc_limit {
                Some(CollapseReason::IncrementDisplacement)
            } else if self.displacements(sim).iter().any(|d| d.abs() > tot_limit) {
                Some(CollapseReason::TotalDisplacement)
            } else {
                None
            }
        };
        if let Some((dpos, drot)) = prediction {
            sim.predict(&dpos, &drot);
        }
        let out = solve_static(sim, &self.solve, &start, check)?;
        let stage = match out.end {
            End::Equilibrium => StageEnd::Stable,
            End::Stopped(reason) => StageEnd::Collapsed(reason),
            End::Budget => StageEnd::Collapsed(CollapseReason::StepBudget),
            End::Unstable((dpos, drot)) => {
                extrapolate_collapse(sim, &start, &dpos, &drot, inc_limit);
                StageEnd::Collapsed(CollapseReason::NegativeStiffness)
            }
        };
        Ok(StageRun {
            stage,
            steps: out.steps,
            iterations: out.iterations,
            newton_handed_over: out.newton_unsolved.is_some(),
        })
    }

    /// The per-increment collapse displacement, m: the larger of
    /// [`TiltParams::collapse_increment_fraction`] of the wall width and the elastic scale.
    pub(crate) fn inc_limit(&self) -> f64 {
        (self.params.collapse_increment_fraction * self.width).max(self.elastic)
    }

    /// One increment or bisection trial: `from` (a stable state) loaded to `alpha_deg` (by
    /// [`Ctx::load`]: the tilt in degrees, or the load multiplier of the pushover) and
    /// relaxed ([`Ctx::run_stage`]). If the scaled dynamics blow up (a collapse can throw
    /// light soft directions of a block mass into re-closing contacts, and a soft joint's
    /// collapse displacement carries a body far with a scaled time step), the trial again
    /// from `from` with the next weaker density scaling (block, then scalar, then true
    /// masses), which the returned state keeps. Returns the state, the stage, the steps
    /// taken (those of blown-up attempts included) and the implicit iterations of the
    /// attempt kept; `fallbacks` gets `alpha_deg` if the trial fell back.
    pub(super) fn run_from(
        &self,
        from: &Simulation,
        alpha_deg: f64,
        prediction: Option<Prediction>,
        fallbacks: &mut Vec<f64>,
    ) -> Result<(Simulation, StageRun), DemError> {
        let mut wasted = 0;
        let mut scaling = from.params().density_scaling;
        loop {
            let mut sim = from.clone();
            sim.set_density_scaling(scaling);
            (self.load)(&mut sim, alpha_deg);
            let before = sim.state.steps;
            match self.run_stage(&mut sim, prediction.clone()) {
                Ok(trial) => return Ok((sim, StageRun { steps: trial.steps + wasted, ..trial })),
                Err(DemError::NonFinite { .. }) if scaling.is_on() => {
                    wasted += sim.state.steps - before;
                    if fallbacks.last() != Some(&alpha_deg) {
                        fallbacks.push(alpha_deg);
                    }
                    scaling = match scaling {
                        DensityScaling::Block { .. } => DensityScaling::Scalar,
                        _ => DensityScaling::Off,
                    };
                }
                Err(e) => return Err(e),
            }
        }
    }
}

/// The stable path of a test: the last stable state (every increment and trial starts
/// from it), its tilt, the secant predictor's states, and the counts.
pub(crate) struct StablePath {
    pub(crate) sim: Simulation,
    pub(crate) last_stable: f64,
    pub(super) secant: Secant,
    pub(super) predictor: bool,
    pub(crate) total_steps: u64,
    pub(super) total_iterations: u64,
    pub(super) fallbacks: Vec<f64>,
}

impl StablePath {
    pub(crate) fn new(settled: Simulation, predictor: bool) -> StablePath {
        let mut secant = Secant::default();
        secant.push(0.0, &settled);
        let total_steps = settled.state.steps;
        StablePath {
            sim: settled,
            last_stable: 0.0,
            secant,
            predictor,
            total_steps,
            total_iterations: 0,
            fallbacks: Vec::new(),
        }
    }

    /// Runs the increment or trial at `alpha_deg` from the last stable state and records it
    /// in `increments`; a stable state becomes the new end of the path (`None`), an
    /// unstable one is returned with its reason.
    pub(crate) fn try_at(
        &mut self,
        ctx: &Ctx<'_>,
        alpha_deg: f64,
        increments: &mut Vec<Increment>,
        observe: &mut dyn FnMut(f64, bool, &Simulation),
    ) -> Result<Option<(CollapseReason, Simulation)>, DemError> {
        let prediction = if self.predictor { self.secant.predict(alpha_deg) } else { None };
        let (next, StageRun { stage, steps, iterations, newton_handed_over }) =
            ctx.run_from(&self.sim, alpha_deg, prediction, &mut self.fallbacks)?;
        self.total_steps += steps;
        self.total_iterations += u64::from(iterations);
        increments.push(Increment {
            alpha_deg,
            stable: matches!(stage, StageEnd::Stable),
            steps,
            iterations,
            displacement_m: ctx.displacements(&next),
            unbalanced_ratio: next.stats().unbalanced_ratio,
            newton_handed_over,
        });
        observe(alpha_deg, matches!(stage, StageEnd::Stable), &next);
        Ok(match stage {
            StageEnd::Stable => {
                self.last_stable = alpha_deg;
                self.secant.push(alpha_deg, &next);
                self.sim = next;
                None
            }
            StageEnd::Collapsed(reason) => Some((reason, next)),
        })
    }
}

/// Carries a state found unstable by the stability indicator along its direction of
/// collapse, `(dpos, drot)` (the motion of the indicator's last window), until the largest
/// block motion since `start` reaches `limit` (m), the per-increment collapse criterion:
/// the state from which the collapse mechanism is read, as if the collapse had been
/// followed by relaxation to that criterion (the motion of a collapsing state keeps its
/// direction; the early motion of a trial still holds the elastic shear of the joints,
/// which would read as sliding).
pub(super) fn extrapolate_collapse(sim: &mut Simulation, start: &[BodyPose], dpos: &[Vec3], drot: &[Vec3], limit: f64) {
    let now = largest_motion(sim, start);
    let per_unit = largest_body_motion(sim, dpos, drot);
    let scale = (limit - now).max(0.0) / per_unit;
    if dpos.len() != sim.state.bodies.len() || !(scale.is_finite() && scale > 0.0) {
        return;
    }
    let scaled = |v: &[Vec3]| v.iter().map(|x| x * scale).collect::<Vec<_>>();
    sim.predict(&scaled(dpos), &scaled(drot));
}

/// The elastic displacement scale of a layout's joints, m: how far the wall can move on
/// its joints' elastic closure alone before it collapses, an upper estimate.
///
/// With W the weight of the free blocks, A the plan area of the layout (its x extent times
/// its width B), H its height and Kn the smallest normal stiffness of its joints, the
/// closure of the base under the whole weight is `p = W / (Kn A)`; a no-tension Winkler
/// joint with the resultant at the edge of its middle third rotates by `6 p / B` (the
/// full-contact rotation `6 ρ g h² sin β / (Kn b²)` of a block at its rigid limit
/// `tan β = b/h`), which moves the top by `6 p H / B`. The scale is `p + 6 p H / B`. At
/// the stiffnesses of the source study (Kn ≥ 2.5e7 Pa/m, the 1:4 walls) it is a few
/// millimetres, below the fixed fractions of the wall width; at Kn of the order of 1e6
/// Pa/m it is centimetres, the rotation of the joints before collapse.
pub fn elastic_scale(layout: &Layout, sim: &Simulation) -> f64 {
    let weight: f64 = sim.state.bodies.iter().filter(|b| !b.fixed()).map(|b| b.mass).sum::<f64>() * layout.gravity;
    let ext = layout.bounds().extent();
    let area = ext.x * ext.y;
    let kn = sim
        .state
        .contacts
        .iter()
        .map(|c| c.joint.kn)
        .chain(layout.materials.iter().map(|m| m.kn))
        .fold(f64::INFINITY, f64::min);
    let p = weight / (kn * area);
    let scale = p + 6.0 * p * ext.z / ext.y;
    if scale.is_finite() {
        scale
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    /// A secant path of one body moving `rate(k)` m per degree (along y) and turning by a
    /// tenth of that in rad per degree about x, at the tilts of `alphas`.
    fn path(alphas: &[f64], rate: impl Fn(usize) -> f64) -> Secant {
        let mut s = Secant::default();
        let (mut y, mut turn) = (0.0, 0.0);
        for (k, &a) in alphas.iter().enumerate() {
            if k > 0 {
                let d = rate(k) * (a - alphas[k - 1]);
                y += d;
                turn += 0.1 * d;
            }
            let pose = (Vec3::new(0.0, y, 0.0), UnitQuaternion::from_scaled_axis(Vec3::new(turn, 0.0, 0.0)));
            s.states.push((a, vec![pose]));
        }
        s
    }

    /// A linear response is extrapolated linearly: the last increment's motion scaled to
    /// the new step, translation and rotation alike; fewer than three states give nothing.
    #[test]
    fn the_predictor_extrapolates_a_linear_response() {
        assert!(path(&[0.0, 0.5], |_| 1e-4).predict(1.0).is_none());
        let (dpos, drot) = path(&[0.0, 0.5, 1.0], |_| 1e-4).predict(1.25).unwrap();
        assert!((dpos[0] - Vec3::new(0.0, 0.25e-4, 0.0)).norm() < 1e-15, "{:?}", dpos[0]);
        assert!((drot[0] - Vec3::new(0.25e-5, 0.0, 0.0)).norm() < 1e-15, "{:?}", drot[0]);
    }

    /// A steadily accelerating response (a wall approaching its limit point) is
    /// extrapolated; a sudden jump of the rate after a steady one (a local slip) is not,
    /// nor is a jump beyond the accelerating ratio.
    #[test]
    fn the_predictor_refuses_a_sudden_jump_of_the_rate() {
        let alphas = [0.0, 0.5, 1.0, 1.5];
        let accelerating = path(&alphas, |k| 1e-4 * 2f64.powi(k as i32));
        assert!(accelerating.predict(2.0).is_some());
        let slip = path(&alphas, |k| if k == 3 { 3e-4 } else { 1e-4 });
        assert!(slip.predict(2.0).is_none());
        let runaway = path(&alphas, |k| if k == 3 { 1e-3 } else { 1e-4 * 1.1f64.powi(k as i32) });
        assert!(runaway.predict(2.0).is_none());
    }
}
