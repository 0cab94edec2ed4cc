//! The tilting-table protocol (Santa-Cruz et al. 2021, §2.2 and §5.3).
//!
//! 1. Gravity only (α = 0): the layout settles to equilibrium (unbalanced-force ratio below
//!    [`TiltParams::tolerance`]); this is the reference state of every displacement.
//! 2. α grows by [`TiltParams::step_deg`]; after each increment the model is solved to
//!    equilibrium (starting from the secant prediction of that equilibrium:
//!    [`TiltParams::predictor`]; slow creep near collapse accelerated by secant steps along
//!    the motion: [`TiltParams::accelerate`]), or declared unstable when the wall has no
//!    equilibrium near the increment's path: the stiffness along a persistent motion turns
//!    negative while the out-of-balance force along it grows (the stability indicator of
//!    `dem::drivers::accelerate`) *and* that force keeps pushing the state along the motion over the
//!    whole collapse displacement ahead (the probe of the path); or, during the
//!    increment, a block moves more than the collapse displacement, or a top point moves
//!    from the reference more than the total collapse displacement. Both displacements
//!    are the larger of a fraction of the wall width
//!    ([`TiltParams::collapse_increment_fraction`],
//!    [`TiltParams::collapse_displacement_fraction`]) and the elastic displacement scale
//!    of the layout's joints ([`elastic_scale`]), so that the elastic rotation of soft
//!    joints is never taken for a mechanism. An increment that reaches neither an
//!    equilibrium nor a collapse within [`TiltParams::max_steps_per_increment`] steps is
//!    reported as such ([`CollapseReason::StepBudget`]): it bounds the bracket from above
//!    (nothing above it is known to be stable) without being a collapse.
//! 3. The bracket (last stable, first unstable) is bisected from the last stable state
//!    until it is narrower than [`TiltParams::resolution_deg`]. The collapse angle α_max is
//!    the last stable angle; the critical tilt lies in the bracket (unless its upper end
//!    is a [`CollapseReason::StepBudget`]).
//! 4. The mechanism is read from the motion between the last stable and the collapsed
//!    state ([`mechanism`]): the joints that failed (large relative motion), the groups of
//!    blocks they cut loose from the table, the joints between moving and resting bodies,
//!    and for each whether it slid (relative tangential motion dominates) or opened
//!    (toppling).
//!
//! The *wall width* is the y extent of the whole layout (the base width B of a wall).

pub use super::mechanism::{mechanism, Mechanism, MechanismKind};
use super::monitors::{body_motion, largest_motion, monitor_displacements, monitor_points, BodyPose, MonitorPoint};
use super::settle::{settle, SettleError};
use crate::dem::drivers::accelerate::{largest_body_motion, SecantAcceleration};
use crate::dem::drivers::implicit::{self, ImplicitSolve};
use crate::dem::{
    solve_static, Cascade, DemError, DensityScaling, End, Simulation, SolverKind, SolverParams, StaticSolve,
};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::range::{check_ranges, OutOfRange};
use crate::units::deg_to_rad;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Tilting-table parameters. Defaults in brackets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TiltParams {
    /// Tilt increment, degrees \[0.5\] (the paper's DEM used 0.5°).
    pub step_deg: f64,
    /// Width of the final collapse bracket, degrees \[0.125\]: three bisections of the
    /// 0.5° step. The trial nearest α_max is the slowest of a test (the wall creeps for tens
    /// of thousands of steps before it settles or fails), so each further halving costs
    /// about 30 % more steps; the last-stable α_max is then on average 1/16° below the
    /// critical tilt, with a spread (σ 0.036°) well under the realization-to-realization σ.
    pub resolution_deg: f64,
    /// Largest tilt tried, degrees \[80\].
    pub max_angle_deg: f64,
    /// Equilibrium when the unbalanced-force ratio is below this \[1e-4\].
    pub tolerance: f64,
    /// Step budget of one increment (and of the initial settling) \[400000\].
    pub max_steps_per_increment: u64,
    /// Start each increment from the secant prediction of its equilibrium \[true\]: the
    /// motion between the last two stable states, scaled to the new tilt increment, applied
    /// as one jump before relaxing (see `Simulation::predict`). Off: each increment starts
    /// from the last stable state at rest.
    pub predictor: bool,
    /// Collapse when a top point has moved (in y) since α = 0 more than this fraction of the
    /// wall width, or the elastic displacement scale of the joints ([`elastic_scale`]) if
    /// that is larger \[0.5\].
    pub collapse_displacement_fraction: f64,
    /// Collapse when, within one increment, a block moves (centroid motion plus rotation
    /// times its radius) more than this fraction of the wall width, or the elastic
    /// displacement scale of the joints ([`elastic_scale`]) if that is larger \[0.05\]. Also
    /// the reach of the probe that confirms the stability indicator.
    pub collapse_increment_fraction: f64,
    /// Deprecated: choose the solver instead (`[solver] kind = "relaxation"`, `--solver
    /// relaxation`). `false` turns the secant acceleration of slow creep and its stability
    /// indicator off in whichever penalty solver runs ([`TiltParams::cascade`]) \[true\].
    pub accelerate: bool,
    /// Settings of that acceleration.
    pub acceleration: SecantAcceleration,
    /// Deprecated: choose the solver instead (`[solver] kind = "accelerated"`, `--solver
    /// accelerated`). `false` turns the implicit iteration of each increment off in
    /// whichever penalty solver runs ([`TiltParams::cascade`]) \[true\].
    pub implicit: bool,
    /// Settings of the implicit iteration.
    pub implicit_solve: ImplicitSolve,
}

impl Default for TiltParams {
    fn default() -> Self {
        TiltParams {
            step_deg: 0.5,
            resolution_deg: 0.125,
            max_angle_deg: 80.0,
            tolerance: 1e-4,
            max_steps_per_increment: 400_000,
            predictor: true,
            collapse_displacement_fraction: 0.5,
            collapse_increment_fraction: 0.05,
            accelerate: true,
            acceleration: SecantAcceleration::default(),
            implicit: true,
            implicit_solve: ImplicitSolve::default(),
        }
    }
}

impl TiltParams {
    /// The stages of the static solve of every increment and trial with the solver `kind`:
    /// the tilting table's default is every stage ([`Cascade::FULL`]: the implicit
    /// iteration, its stall probe, accelerated and probed dynamic relaxation); the
    /// deprecated [`TiltParams::implicit`] and [`TiltParams::accelerate`] switch stages off.
    /// `Cascade::RELAXATION` for a solver that is not a penalty method (which does not run
    /// this protocol).
    pub fn cascade(&self, kind: SolverKind) -> Cascade {
        let c = kind.cascade(Cascade::FULL).unwrap_or(Cascade::RELAXATION);
        Cascade { implicit: c.implicit && self.implicit, accelerate: c.accelerate && self.accelerate }
    }

    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("step_deg", self.step_deg, self.step_deg > 0.0 && self.step_deg <= 10.0, "in (0, 10]"),
            (
                "resolution_deg",
                self.resolution_deg,
                self.resolution_deg > 0.0 && self.resolution_deg <= self.step_deg,
                "in (0, step_deg]",
            ),
            ("max_angle_deg", self.max_angle_deg, self.max_angle_deg > 0.0 && self.max_angle_deg < 90.0, "in (0, 90)"),
            ("tolerance", self.tolerance, self.tolerance > 0.0 && self.tolerance < 1.0, "in (0, 1)"),
            (
                "collapse_displacement_fraction",
                self.collapse_displacement_fraction,
                self.collapse_displacement_fraction > 0.0,
                "> 0",
            ),
            (
                "collapse_increment_fraction",
                self.collapse_increment_fraction,
                self.collapse_increment_fraction > 0.0,
                "> 0",
            ),
            ("max_steps_per_increment", self.max_steps_per_increment as f64, self.max_steps_per_increment > 0, ">= 1"),
        ])?;
        self.acceleration.validate()?;
        self.implicit_solve.validate()
    }
}

/// Why an increment was declared unstable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CollapseReason {
    /// A block moved too much within one increment.
    IncrementDisplacement,
    /// A top point moved too far from its reference.
    TotalDisplacement,
    /// No equilibrium: the name the static lateral load gives a load it cannot carry.
    NoEquilibrium,
    /// Negative stiffness along a persistent motion during relaxation (the secant
    /// acceleration's stability indicator, `dem::drivers::accelerate`), and no equilibrium on the
    /// path ahead up to the collapse displacement (the indicator's probe).
    NegativeStiffness,
    /// The step budget of the increment ([`TiltParams::max_steps_per_increment`]) ran out
    /// before an equilibrium or a collapse was established: not a collapse, an undecided
    /// increment (the critical tilt may lie above it).
    StepBudget,
}

impl CollapseReason {
    /// Every collapse reason.
    pub const ALL: [CollapseReason; 5] = [
        CollapseReason::IncrementDisplacement,
        CollapseReason::TotalDisplacement,
        CollapseReason::NoEquilibrium,
        CollapseReason::NegativeStiffness,
        CollapseReason::StepBudget,
    ];

    /// The name of the reason in the `collapse_reason` column of both protocols: its serde
    /// name, as `drystone tilt --json` prints it.
    pub fn name(self) -> &'static str {
        match self {
            CollapseReason::IncrementDisplacement => "increment_displacement",
            CollapseReason::TotalDisplacement => "total_displacement",
            CollapseReason::NoEquilibrium => "no_equilibrium",
            CollapseReason::NegativeStiffness => "negative_stiffness",
            CollapseReason::StepBudget => "step_budget",
        }
    }

    /// The reason of a name of the `collapse_reason` column.
    pub fn from_name(name: &str) -> Option<CollapseReason> {
        CollapseReason::ALL.into_iter().find(|r| r.name() == name)
    }
}

/// One tilt increment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Increment {
    /// Tilt, degrees.
    pub alpha_deg: f64,
    /// Equilibrium reached.
    pub stable: bool,
    /// Dynamic-relaxation steps taken in this increment.
    pub steps: u64,
    /// Iterations of the implicit relaxation in this increment (0 without it).
    #[serde(default)]
    pub iterations: u32,
    /// Out-of-plane (y) displacement of each monitor point since α = 0, m, in the order of
    /// [`TiltResult::monitors`].
    pub displacement_m: Vec<f64>,
    /// Unbalanced-force ratio at the end of the increment.
    pub unbalanced_ratio: f64,
}

/// Outcome of a tilting-table run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TiltResult {
    /// Last stable tilt, degrees: the collapse angle α_max
    /// ([`TiltResult::collapse_angle_deg`]; `max_angle_deg` if the wall stood).
    pub last_stable_deg: f64,
    /// First unstable tilt, degrees (`None` if the wall stood up to `max_angle_deg`).
    pub first_unstable_deg: Option<f64>,
    /// Why the first unstable tilt was unstable.
    pub collapse_reason: Option<CollapseReason>,
    /// Mechanism of collapse.
    pub mechanism: Mechanism,
    /// Monitor point names (`top_left`, `top_centre`, `top_right` unless the layout names its
    /// own).
    pub monitors: Vec<String>,
    /// Accepted (stable) increments in increasing α, then the unstable trials.
    pub increments: Vec<Increment>,
    /// Dynamic-relaxation steps in all.
    pub steps: u64,
    /// Iterations of the implicit relaxation in all.
    #[serde(default)]
    pub iterations: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s (not part of the deterministic output).
    pub wall_time_s: f64,
    /// Wall width used by the collapse criteria, m.
    pub wall_width_m: f64,
    /// Elastic displacement scale of the joints ([`elastic_scale`]), m: the collapse
    /// displacements are never below it.
    #[serde(default)]
    pub elastic_scale_m: f64,
    /// Contact detections (broad + narrow phase over the model) in the accepted path.
    pub detections: u64,
    /// Largest density-scaling factor applied (1: none; see `SolverParams::density_scaling`).
    pub max_density_scale: f64,
    /// The tilts (degrees, in the order tried) of the increments and trials whose scaled
    /// dynamics blew up and were repeated with a weaker density scaling (block, then
    /// scalar, then true masses; see `DensityScaling::Block`); empty if none did.
    #[serde(default)]
    pub scalar_fallbacks_deg: Vec<f64>,
}

/// Pose of every body, in body order.
type Pose = Vec<BodyPose>;

/// A predicted increment: translation (m) and rotation vector (rad) per body.
type Prediction = implicit::PoseIncrement;

fn pose(sim: &Simulation) -> Pose {
    sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect()
}

/// The last four stable states (tilt in degrees, pose), oldest first.
#[derive(Default)]
struct Secant {
    states: Vec<(f64, Pose)>,
}

/// The predictor extrapolates only a nearly linear or a steadily accelerating response.
/// With `r` the largest body motion per degree of an increment (last `r₂`, then `r₁`,
/// `r₀`), it is used if `r₂ ≤ LINEAR_RESPONSE_RATIO r₁`, or if the motion has been
/// accelerating for two increments (`r₁ ≥ STEADY_GROWTH r₀`) and `r₂ ≤
/// ACCELERATING_RESPONSE_RATIO r₁` (a wall approaching its limit point). A sudden jump of
/// the rate after a steady one is a local slip event (an end stone sliding): a linear jump
/// would impose that slip again at every increment, and friction would keep it, so the
/// increment relaxes from rest.
const LINEAR_RESPONSE_RATIO: f64 = 1.2;
/// See [`LINEAR_RESPONSE_RATIO`].
const STEADY_GROWTH: f64 = 1.05;
/// See [`LINEAR_RESPONSE_RATIO`].
const ACCELERATING_RESPONSE_RATIO: f64 = 2.5;

impl Secant {
    fn push(&mut self, alpha: f64, sim: &Simulation) {
        self.states.push((alpha, pose(sim)));
        if self.states.len() > 4 {
            self.states.remove(0);
        }
    }

    /// Largest body motion ([`body_motion`] with a radius of 1 m) per degree of tilt between
    /// two stable states.
    fn rate(a: &(f64, Pose), b: &(f64, Pose)) -> f64 {
        let m = a.1.iter().zip(&b.1).map(|(from, to)| body_motion(from, to, 1.0)).fold(0.0, f64::max);
        m / (b.0 - a.0).abs()
    }

    /// Whether the response is smooth enough to extrapolate ([`LINEAR_RESPONSE_RATIO`]).
    fn smooth(&self) -> bool {
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
    fn predict(&self, alpha: f64) -> Option<Prediction> {
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

enum Stage {
    Stable,
    Collapsed(CollapseReason),
}

/// What one increment or trial came to: its stage, the dynamic-relaxation steps and the
/// implicit iterations it took.
struct Trial {
    stage: Stage,
    steps: u64,
    iterations: u32,
}

struct Ctx<'a> {
    params: &'a TiltParams,
    /// The static solve of every increment and trial (its reach set per trial).
    solve: StaticSolve,
    monitors: &'a [MonitorPoint],
    reference: Vec<Vec3>,
    width: f64,
    /// [`elastic_scale`], m.
    elastic: f64,
}

impl Ctx<'_> {
    fn displacements(&self, sim: &Simulation) -> Vec<f64> {
        monitor_displacements(sim, self.monitors, &self.reference)
    }

    /// Relaxes `sim` at its tilt from `prediction` (applied as one jump) through the solver
    /// seam ([`solve_static`]), with this protocol's collapse criteria as the stop check.
    fn run_stage(&self, sim: &mut Simulation, prediction: Option<Prediction>) -> Result<Trial, DemError> {
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
            End::Equilibrium => Stage::Stable,
            End::Stopped(reason) => Stage::Collapsed(reason),
            End::Budget => Stage::Collapsed(CollapseReason::StepBudget),
            End::Unstable((dpos, drot)) => {
                extrapolate_collapse(sim, &start, &dpos, &drot, inc_limit);
                Stage::Collapsed(CollapseReason::NegativeStiffness)
            }
        };
        Ok(Trial { stage, steps: out.steps, iterations: out.iterations })
    }

    /// The per-increment collapse displacement, m: the larger of
    /// [`TiltParams::collapse_increment_fraction`] of the wall width and the elastic scale.
    fn inc_limit(&self) -> f64 {
        (self.params.collapse_increment_fraction * self.width).max(self.elastic)
    }

    /// One increment or bisection trial: `from` (a stable state) tilted to `alpha_deg` and
    /// relaxed ([`Ctx::run_stage`]). If the scaled dynamics blow up (a collapse can throw
    /// light soft directions of a block mass into re-closing contacts, and a soft joint's
    /// collapse displacement carries a body far with a scaled time step), the trial again
    /// from `from` with the next weaker density scaling (block, then scalar, then true
    /// masses), which the returned state keeps. Returns the state, the stage, the steps
    /// taken (those of blown-up attempts included) and the implicit iterations of the
    /// attempt kept; `fallbacks` gets `alpha_deg` if the trial fell back.
    fn run_from(
        &self,
        from: &Simulation,
        alpha_deg: f64,
        prediction: Option<Prediction>,
        fallbacks: &mut Vec<f64>,
    ) -> Result<(Simulation, Trial), DemError> {
        let mut wasted = 0;
        let mut scaling = from.params().density_scaling;
        loop {
            let mut sim = from.clone();
            sim.set_density_scaling(scaling);
            sim.set_tilt(deg_to_rad(alpha_deg));
            let before = sim.state.steps;
            match self.run_stage(&mut sim, prediction.clone()) {
                Ok(trial) => return Ok((sim, Trial { steps: trial.steps + wasted, ..trial })),
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
struct StablePath {
    sim: Simulation,
    last_stable: f64,
    secant: Secant,
    predictor: bool,
    total_steps: u64,
    total_iterations: u64,
    fallbacks: Vec<f64>,
}

impl StablePath {
    fn new(settled: Simulation, predictor: bool) -> StablePath {
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
    fn try_at(
        &mut self,
        ctx: &Ctx<'_>,
        alpha_deg: f64,
        increments: &mut Vec<Increment>,
        observe: &mut dyn FnMut(f64, bool, &Simulation),
    ) -> Result<Option<(CollapseReason, Simulation)>, DemError> {
        let prediction = if self.predictor { self.secant.predict(alpha_deg) } else { None };
        let (next, Trial { stage, steps, iterations }) =
            ctx.run_from(&self.sim, alpha_deg, prediction, &mut self.fallbacks)?;
        self.total_steps += steps;
        self.total_iterations += u64::from(iterations);
        increments.push(Increment {
            alpha_deg,
            stable: matches!(stage, Stage::Stable),
            steps,
            iterations,
            displacement_m: ctx.displacements(&next),
            unbalanced_ratio: next.stats().unbalanced_ratio,
        });
        observe(alpha_deg, matches!(stage, Stage::Stable), &next);
        Ok(match stage {
            Stage::Stable => {
                self.last_stable = alpha_deg;
                self.secant.push(alpha_deg, &next);
                self.sim = next;
                None
            }
            Stage::Collapsed(reason) => Some((reason, next)),
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
fn extrapolate_collapse(sim: &mut Simulation, start: &[BodyPose], dpos: &[Vec3], drot: &[Vec3], limit: f64) {
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
    let weight: f64 = sim.state.bodies.iter().filter(|b| !b.fixed).map(|b| b.mass).sum::<f64>() * layout.gravity;
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

/// Errors of the tilting-table protocol.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum TiltError {
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
    /// The layout does not stand as given under gravity alone (see [`super::settle`]).
    #[error(transparent)]
    DoesNotStand(SettleError),
    /// A tilt or solver parameter is out of range.
    #[error("parameter {0}")]
    Parameter(OutOfRange),
    /// The solver chosen cannot run this protocol.
    #[error("solver {0} cannot run the tilting-table test (limit analysis: `drystone limit LAYOUT.json`, or [solver] kind = \"limit\" in a study)")]
    Unsupported(SolverKind),
    /// The non-smooth solver refused the layout (a joint with cohesion or tensile
    /// strength; `loading::tilt_nscd`).
    #[error(transparent)]
    Nscd(crate::dem::drivers::nscd::NscdError),
}

impl TiltError {
    fn from_settle(e: SettleError) -> TiltError {
        match e {
            SettleError::Dem(e) => TiltError::Dem(e),
            other => TiltError::DoesNotStand(other),
        }
    }
}

impl TiltResult {
    /// The collapse angle α_max, degrees: the last stable tilt, which the bracket
    /// `[last_stable_deg, first_unstable_deg]` holds to the protocol's resolution (the
    /// convention of the source paper's tilting-table readings: the last angle at which the
    /// wall stood).
    pub fn collapse_angle_deg(&self) -> f64 {
        self.last_stable_deg
    }
}

/// Runs the tilting-table test of a layout to collapse.
///
/// The returned bracket `[last_stable_deg, first_unstable_deg]` contains the collapse
/// angle α_max to `params.resolution_deg`.
///
/// ```
/// use drystone::dem::SolverParams;
/// use drystone::layout::BaseSliding;
/// use drystone::loading::tilt::{run_tilt, TiltParams};
/// use drystone::verify::{box_vertices, layout_of};
///
/// // A block 0.1125 m deep (y) and 0.375 m tall on stiff joints (Kn 1e11 Pa/m, φ 60°)
/// // topples near the rigid limit tan α = b / h = 0.3 (16.70°), below it by the elastic
/// // rotation of its base joint (the no-tension Winkler solution: 16.31°, `drystone verify`).
/// let block = box_vertices([0.0, -0.05625, 0.0], [0.3, 0.05625, 0.375]);
/// let layout = layout_of(vec![block], 1e11, 5e10, 60.0, BaseSliding::Free);
/// let params = TiltParams { resolution_deg: 0.0625, ..TiltParams::default() };
/// let r = run_tilt(&layout, SolverParams::default(), &params)?;
/// let up = r.first_unstable_deg.unwrap();
/// assert!(r.last_stable_deg <= 16.31 + 0.02 && up >= 16.31 - 0.02, "{} {up}", r.last_stable_deg);
/// // The load multiplier at collapse, λ = tan α_max, against the rigid limit b / h.
/// assert!((r.collapse_angle_deg().to_radians().tan() - 0.3).abs() < 0.01);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`TiltError::DoesNotStand`] if the layout does not stand as given at α = 0 (a block
/// touching nothing, no equilibrium, or a block that moved while settling),
/// [`TiltError::Dem`] if the state blows up, [`TiltError::Parameter`] for bad parameters.
pub fn run_tilt(layout: &Layout, solver: SolverParams, params: &TiltParams) -> Result<TiltResult, TiltError> {
    run_tilt_observed(layout, solver, params, &mut |_, _, _| {})
}

/// As [`run_tilt`], handing every state of the test to `observe(alpha_deg, stable, state)`
/// as it is reached: the settled state at α = 0, then every increment and bisection trial
/// in the order tried (the unstable ones in the state their mechanism is read from). The
/// last unstable state handed over at `first_unstable_deg` is the first unstable state of
/// the result. Observing changes nothing in the test.
///
/// # Errors
/// As [`run_tilt`].
pub fn run_tilt_observed(
    layout: &Layout,
    solver: SolverParams,
    params: &TiltParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<TiltResult, TiltError> {
    params.validate().map_err(TiltError::Parameter)?;
    match solver.kind {
        SolverKind::Nscd => return super::tilt_nscd::run_tilt_nscd(layout, &solver.nscd, params),
        kind if !kind.is_penalty() => return Err(TiltError::Unsupported(kind)),
        _ => {}
    }
    solver.validate_static().map_err(TiltError::Parameter)?;
    let t0 = Instant::now();
    let mut sim = Simulation::new(layout, solver);
    let monitors = monitor_points(layout, &sim);
    let width = layout.bounds().extent().y;
    sim.set_tilt(0.0);
    let elastic = elastic_scale(layout, &sim);
    let solve = StaticSolve {
        cascade: params.cascade(solver.kind),
        tolerance: params.tolerance,
        max_steps: params.max_steps_per_increment,
        acceleration: params.acceleration,
        implicit: params.implicit_solve,
        reach: None,
    };
    let mut ctx = Ctx { params, solve, monitors: &monitors, reference: Vec::new(), width, elastic };
    ctx.solve.reach = Some(ctx.inc_limit());
    settle(&mut sim, layout, params.tolerance, params.max_steps_per_increment).map_err(TiltError::from_settle)?;
    ctx.reference = monitors.iter().map(|m| sim.state.bodies[m.body].to_world(&m.local)).collect();
    let mut increments = vec![Increment {
        alpha_deg: 0.0,
        stable: true,
        steps: sim.state.steps,
        iterations: 0,
        displacement_m: vec![0.0; monitors.len()],
        unbalanced_ratio: sim.stats().unbalanced_ratio,
    }];
    observe(0.0, true, &sim);
    let mut path = StablePath::new(sim, params.predictor);
    let mut first_unstable: Option<(f64, CollapseReason, Simulation)> = None;
    let mut k = 1;
    loop {
        let alpha = k as f64 * params.step_deg;
        if alpha > params.max_angle_deg + 1e-9 {
            break;
        }
        if let Some((reason, next)) = path.try_at(&ctx, alpha, &mut increments, observe)? {
            first_unstable = Some((alpha, reason, next));
            break;
        }
        k += 1;
    }
    let Some((mut unstable, mut reason, mut failed)) = first_unstable else {
        let last_stable = path.last_stable;
        return Ok(TiltResult {
            last_stable_deg: last_stable,
            first_unstable_deg: None,
            collapse_reason: None,
            mechanism: Mechanism::none(),
            monitors: monitors.iter().map(|m| m.name.clone()).collect(),
            increments,
            steps: path.total_steps,
            iterations: path.total_iterations,
            dt_s: path.sim.dt(),
            wall_time_s: t0.elapsed().as_secs_f64(),
            wall_width_m: width,
            elastic_scale_m: elastic,
            detections: path.sim.detections(),
            max_density_scale: path.sim.max_density_scale(),
            scalar_fallbacks_deg: path.fallbacks,
        });
    };
    // Time step of the first failing increment (bisection trials may replace `failed`).
    let dt_s = failed.dt();
    // Bisection of the bracket from the last stable state.
    while unstable - path.last_stable > params.resolution_deg + 1e-12 {
        let mid = 0.5 * (unstable + path.last_stable);
        if let Some((r, trial)) = path.try_at(&ctx, mid, &mut increments, observe)? {
            unstable = mid;
            reason = r;
            failed = trial;
        }
    }
    let (last_stable, stable_sim, total_steps, total_iterations, fallbacks) =
        (path.last_stable, path.sim, path.total_steps, path.total_iterations, path.fallbacks);
    // Stable increments first, sorted by α, then unstable trials by α.
    increments.sort_by(|a, b| (!a.stable).cmp(&!b.stable).then(a.alpha_deg.total_cmp(&b.alpha_deg)));
    let mechanism = mechanism(&stable_sim, &failed);
    Ok(TiltResult {
        last_stable_deg: last_stable,
        first_unstable_deg: Some(unstable),
        collapse_reason: Some(reason),
        mechanism,
        monitors: monitors.iter().map(|m| m.name.clone()).collect(),
        increments,
        steps: total_steps,
        iterations: total_iterations,
        dt_s: failed.dt().min(dt_s),
        wall_time_s: t0.elapsed().as_secs_f64(),
        wall_width_m: width,
        elastic_scale_m: elastic,
        detections: failed.detections(),
        max_density_scale: failed.max_density_scale().max(stable_sim.max_density_scale()),
        scalar_fallbacks_deg: fallbacks,
    })
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
