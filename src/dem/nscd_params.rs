//! The non-smooth contact-dynamics solver's settings ([`NscdParams`], a study's
//! `[solver.nscd]` table) and their choices (the rest rule, the step solver, the sweeps'
//! norm and order, the points of a contact polygon): plain data beside the other methods'
//! settings in [`super::SolverParams`], read by the solver (`crate::nscd`).

use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};

/// Parameters of the non-smooth contact-dynamics solver. Defaults in brackets; serde
/// keys as the field names (a study's `[solver]` table), unknown keys refused.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NscdParams {
    /// Time step h, s \[1e-3\] (LMGC90's step in `scripts/lmgc90/rigid_limits.py`).
    pub dt_s: f64,
    /// θ of the Moreau–Jean scheme, in \[0.5, 1\] \[0.5\]: the positions advance by
    /// `h (θ v⁺ + (1 − θ) v⁻)` and the smooth forces act at `t + θ h`. 0.5 (LMGC90's
    /// choice) conserves the energy of free flight; the impulse law is on the end-of-step
    /// velocity `v⁺` for every θ, so Housner's impact ratio does not depend on it
    /// (`tests/suite/nscd_motion.rs` checks 0.5 and 1).
    pub theta: f64,
    /// Newton's coefficient of restitution e, in \[0, 1\] \[0\]: `uₙ⁺ ≥ −e uₙ⁻` at an impact
    /// (0: no bounce, the rocking block's impact of Housner 1963).
    pub restitution: f64,
    /// What a step of a wall at rest does \[`certify`\] (see [`RestRule`]).
    pub rest: RestRule,
    /// NSGS convergence tolerance \[1e-7\], read by [`Self::norm`] (with the default
    /// [`NsgsNorm::Adaptive`]: the tolerance of its velocity norm, over g h).
    pub tolerance: f64,
    /// The convergence norm of the NSGS sweeps \[`adaptive`\] (see [`NsgsNorm`]).
    pub norm: NsgsNorm,
    /// The quadratic norm's tolerance of [`NsgsNorm::Adaptive`], dimensionless \[1e-4\]
    /// (LMGC90's usual `Quad` tolerance).
    pub quad_tolerance: f64,
    /// The work of a step, in local solves (contact points × sweeps), after which
    /// [`NsgsNorm::Adaptive`] also accepts the quadratic norm \[1.5e5\]: a step over P
    /// contact points accepts it after `ceil(quad_after_solves / P)` sweeps. 1.5e5 is 1,250
    /// sweeps of the 13-box wall (120 points; it meets the velocity norm before that in
    /// every step of its tilt, whose result is the velocity norm's; at 500 sweeps or
    /// fewer its bracket misses t/H by 0.003°, from 750 it holds it), 62 of the SBL preset
    /// wall of seed 20210917 (195 blocks, 2,424 points) and 53 of that of seed 2021 (227
    /// blocks, 2,854 points). Measured on the 227-block wall (BENCHMARKS.md): 2.5e5 costs
    /// 18 % more CPU for a bracket 0.08° lower, 1e6 2.4 times as much for one 0.04° lower.
    pub quad_after_solves: f64,
    /// The order of the NSGS sweeps \[`forward`\] (see [`SweepOrder`]).
    pub sweep: SweepOrder,
    /// Relaxation ω of the NSGS update, in (0, 2) \[1\]: a point's impulse becomes
    /// `ω r_loc + (1 − ω) r_old`, projected on its Coulomb cone (`r_loc` the exact local
    /// solution; 1 is plain Gauss–Seidel, as LMGC90's default `RELAX 1.0`).
    pub relaxation: f64,
    /// Passes over the points of one contact polygon at each visit of a sweep, ≥ 1 \[1\]:
    /// more than one is an inexact block Gauss–Seidel over the polygon (its points share
    /// two bodies and are strongly coupled), stopped early when a pass changes no impulse
    /// by more than [`Self::tolerance`] of its velocity response.
    pub polygon_passes: u32,
    /// The method of a step of motion \[`apgd`\] (see [`StepSolver`]). The release trials
    /// of the tilting table, the table rolled by hand and the pushover always use
    /// [`StepSolver::Nsgs`] ([`Self::for_trials`]).
    pub step_solver: StepSolver,
    /// The natural-map residual a step of motion must meet with [`StepSolver::Apgd`],
    /// dimensionless, in \[1e-12, 1) \[1e-4\] ([`crate::nscd::nsgs::natural_residual`]: LMGC90's usual tolerance, here on
    /// the residual of the Coulomb problem itself rather than on the change over a sweep).
    pub natural_tolerance: f64,
    /// The work of a step, in local solves (contact points × sweeps), that
    /// [`StepSolver::Apgd`] gives the NSGS sweeps before it takes over \[1.5e4\]: a small
    /// wall meets the sweeps' own norm within it and is solved exactly as by
    /// [`StepSolver::Nsgs`] (a block: 3,750 sweeps of 4 points; the 13-box wall: 125); the
    /// SBL preset wall (2,424 points) gets 7 sweeps.
    pub apgd_after_solves: f64,
    /// Largest number of NSGS sweeps and gradient iterations per step \[2000\]. With
    /// [`StepSolver::Apgd`] a step that reaches it is finished by cone programs
    /// ([`crate::nscd::cone::solve`]) and counts as unconverged ([`crate::nscd::NscdStep::converged`]) only if they
    /// too leave the natural-map residual above [`Self::natural_tolerance`]; with
    /// [`StepSolver::Nsgs`] it keeps its last iterate and counts as unconverged.
    pub max_iterations: u32,
    /// The contact points of a face contact polygon \[`vertices`\] (see [`PolygonPoints`]).
    pub polygon_points: PolygonPoints,
    /// Pairs closer than this get contact points, m \[1e-3\].
    pub contact_margin_m: f64,
    /// Vertices within this distance of the support plane form an edge or vertex feature,
    /// m \[5e-4\].
    pub feature_tolerance_m: f64,
    /// Faces within this angle of the contact normal form a face feature, degrees \[10\]:
    /// a block rocking on an edge gets the points of its whole face back when it turns
    /// within this angle of its seat, before the impact.
    pub face_angle_tolerance_deg: f64,
    /// Contacts are re-detected when a body has moved this fraction of the margin since
    /// the last detection (translation plus rotation times its radius) \[0.5\].
    pub redetect_fraction: f64,
    /// Steps of one trial released from rest \[40\] (see `loading::tilt_nscd`): the
    /// window over which the growth of the motion is judged. This and the next three are
    /// the method's test of a static state, read by every protocol it runs statically (the
    /// tilting table's trials, the rigid pushover's), as the tolerance and step budget of
    /// [`crate::dem::PenaltyParams`] are the penalty DEM's.
    pub trial_steps: u32,
    /// A trial is at rest, and stable at once, when the largest speed of any block point
    /// (`|v| + |ω| R`) is below `rest_velocity_ratio × g h` \[1e-5\] for
    /// [`Self::rest_steps`] steps running.
    pub rest_velocity_ratio: f64,
    /// Steps at rest that end a trial as stable \[10\].
    pub rest_steps: u32,
    /// A trial is unstable when the mean largest point speed over the second half of its
    /// steps exceeds this many times its mean over the first half (and the rest
    /// velocity): the mechanism keeps accelerating under a constant tilt \[2\] (a speed
    /// growing linearly from rest gives 3, an exponential toppling more, a settling or the
    /// noise of an unconverged solution about 1 or less).
    pub growth_ratio: f64,
}

/// The natural-map tolerance below which the steps of motion are not expected to meet it
/// \[1e-8\]: rounding leaves about that residual (the 13-box wall under a Ricker pulse of
/// 0.5 g: at 1e-8, 11 of 1,150 steps above it, the largest 2.8e-8; at 1e-10 to 1e-12 the
/// same 246 steps at the iteration limit and 30 s instead of 2.4 s), so that every step
/// runs to [`NscdParams::max_iterations`] and the cone programs.
pub const NATURAL_TOLERANCE_FLOOR: f64 = 1e-8;

/// The iteration limit of [`StepSolver::Apgd`] below which a capped step costs more than
/// the iterations save \[1000\]: a step that reaches it is finished by cone programs (the
/// 13-box wall under a one-sine pulse of 0.6 g and 0.3 s: 1.4 s at the default 2000, 15.6 s
/// at 200, 36 s at 20).
pub const APGD_MIN_USEFUL_ITERATIONS: u32 = 1000;

impl NscdParams {
    /// The settings of a step of motion that cost more than they save, each with its key
    /// and why: a [`Self::natural_tolerance`] below [`NATURAL_TOLERANCE_FLOOR`], and with
    /// [`StepSolver::Apgd`] a [`Self::max_iterations`] below
    /// [`APGD_MIN_USEFUL_ITERATIONS`]. The command line and a shaking study warn of them.
    pub fn motion_cost_warnings(&self) -> Vec<(&'static str, String)> {
        let mut out = Vec::new();
        if self.step_solver == StepSolver::Apgd && self.natural_tolerance < NATURAL_TOLERANCE_FLOOR {
            out.push((
                "natural_tolerance",
                format!(
                    "= {:e} is below what a step reaches in double precision (about {NATURAL_TOLERANCE_FLOOR:e}): \
                     most steps run to max_iterations and the cone programs, and count as unconverged",
                    self.natural_tolerance
                ),
            ));
        }
        if self.step_solver == StepSolver::Apgd && self.max_iterations < APGD_MIN_USEFUL_ITERATIONS {
            out.push((
                "max_iterations",
                format!(
                    "= {} with step_solver apgd: a step that reaches it is finished by cone programs, which cost \
                     more than the iterations saved (at least {APGD_MIN_USEFUL_ITERATIONS}; the default is 2000)",
                    self.max_iterations
                ),
            ));
        }
        out
    }
}

impl Default for NscdParams {
    fn default() -> Self {
        NscdParams {
            dt_s: 1e-3,
            theta: 0.5,
            restitution: 0.0,
            rest: RestRule::Certify,
            tolerance: 1e-7,
            norm: NsgsNorm::Adaptive,
            quad_tolerance: 1e-4,
            quad_after_solves: 1.5e5,
            sweep: SweepOrder::Forward,
            relaxation: 1.0,
            polygon_passes: 1,
            step_solver: StepSolver::Apgd,
            natural_tolerance: 1e-4,
            apgd_after_solves: 1.5e4,
            max_iterations: 2000,
            polygon_points: PolygonPoints::Vertices,
            contact_margin_m: 1e-3,
            feature_tolerance_m: 5e-4,
            face_angle_tolerance_deg: 10.0,
            redetect_fraction: 0.5,
            trial_steps: 40,
            rest_velocity_ratio: 1e-5,
            rest_steps: 10,
            growth_ratio: 2.0,
        }
    }
}

impl NscdParams {
    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, named by its key, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("dt_s", self.dt_s, self.dt_s > 0.0 && self.dt_s <= 0.1, "in (0, 0.1]"),
            ("theta", self.theta, (0.5..=1.0).contains(&self.theta), "in [0.5, 1]"),
            ("restitution", self.restitution, (0.0..=1.0).contains(&self.restitution), "in [0, 1]"),
            ("tolerance", self.tolerance, self.tolerance > 0.0 && self.tolerance < 1.0, "in (0, 1)"),
            (
                "quad_tolerance",
                self.quad_tolerance,
                self.quad_tolerance > 0.0 && self.quad_tolerance < 1.0,
                "in (0, 1)",
            ),
            (
                "quad_after_solves",
                self.quad_after_solves,
                self.quad_after_solves >= 1.0 && self.quad_after_solves.is_finite(),
                ">= 1",
            ),
            ("relaxation", self.relaxation, self.relaxation > 0.0 && self.relaxation < 2.0, "in (0, 2)"),
            ("polygon_passes", self.polygon_passes as f64, self.polygon_passes >= 1, ">= 1"),
            ("max_iterations", self.max_iterations as f64, self.max_iterations >= 1, ">= 1"),
            (
                "natural_tolerance",
                self.natural_tolerance,
                (1e-12..1.0).contains(&self.natural_tolerance),
                "in [1e-12, 1) (a relative residual in f64 is not met below about 1e-12: every step would run to max_iterations)",
            ),
            (
                "apgd_after_solves",
                self.apgd_after_solves,
                self.apgd_after_solves >= 0.0 && !self.apgd_after_solves.is_nan(),
                ">= 0",
            ),
        ])?;
        check_ranges(&crate::dem::contact::geometry::detection_ranges(
            self.contact_margin_m,
            self.feature_tolerance_m,
            self.face_angle_tolerance_deg,
            self.redetect_fraction,
        ))?;
        check_ranges(&[
            ("trial_steps", self.trial_steps as f64, self.trial_steps >= 4, ">= 4"),
            (
                "rest_velocity_ratio",
                self.rest_velocity_ratio,
                self.rest_velocity_ratio > 0.0 && self.rest_velocity_ratio < 1.0,
                "in (0, 1)",
            ),
            ("rest_steps", self.rest_steps as f64, self.rest_steps >= 1, ">= 1"),
            ("growth_ratio", self.growth_ratio, self.growth_ratio > 1.0, "> 1"),
        ])
    }

    /// The narrow phase's share: drystone's detection with one point per polygon vertex
    /// (no subdivision, fanned from a vertex) and a negligible widening of segment and
    /// point contacts (their points are merged back, `nscd::contacts`).
    pub fn patch(&self) -> crate::dem::contact::geometry::PatchParams {
        crate::dem::contact::geometry::PatchParams {
            contact_margin_m: self.contact_margin_m,
            feature_tolerance_m: self.feature_tolerance_m,
            face_angle_tolerance_rad: self.face_angle_tolerance_deg.to_radians(),
            degenerate_width_fraction: 1e-4,
            subcontact_subdivisions: 1,
            fan: crate::dem::contact::geometry::Fan::Vertex,
        }
    }
}

/// What a step does when every block is at rest (slower than
/// [`NscdParams::rest_velocity_ratio`] `× g h`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestRule {
    /// Certify the rest by statics where the contacts carry the step's load inside the
    /// reduced Coulomb cones (the step is then solved exactly, without sweeps; `nscd::rest`),
    /// and sweep otherwise. The default. The tilting table's and the pushover's release
    /// trials never certify (their verdict is the dynamics' own, [`NscdParams::for_trials`]).
    Certify,
    /// Always sweep.
    Solve,
}

impl NscdParams {
    /// These parameters for a release trial of the tilting table, the table rolled by hand
    /// or the pushover: [`RestRule::Solve`] (a trial asks whether the released wall moves,
    /// which the sweeps answer; statics would answer another question, the limit
    /// analysis's).
    pub fn for_trials(&self) -> NscdParams {
        NscdParams { rest: RestRule::Solve, step_solver: StepSolver::Nsgs, ..*self }
    }
}

/// The method of a step of motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StepSolver {
    /// The NSGS sweeps alone, stopped by [`NscdParams::norm`] or at
    /// [`NscdParams::max_iterations`] sweeps.
    Nsgs,
    /// The NSGS sweeps for [`NscdParams::apgd_after_solves`] local solves (stopped by their
    /// norm), then the accelerated projected gradient (`nscd::apgd`) until the natural-map
    /// residual is at most [`NscdParams::natural_tolerance`]; at most
    /// [`NscdParams::max_iterations`] sweeps and iterations in all. The default for motion.
    Apgd,
}

/// The convergence norm of the NSGS sweeps (the iteration stops at the first sweep whose
/// norm is at most [`NscdParams::tolerance`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NsgsNorm {
    /// The largest change of a block point's velocity over a sweep, over `g h` (g h the
    /// velocity gravity adds in one step): `max_k (‖Δv_k‖ + ‖Δω_k‖ R_k) / (g h)`, R_k the
    /// block's radius. An absolute norm on the bodies: strict on a large wall, whose
    /// impulses a sweep moves among nearly equivalent solutions.
    Velocity,
    /// The quadratic norm of the change over a sweep of the contact points' own velocity
    /// responses, relative to their quadratic mean: `sqrt(Σ_α ‖W_αα Δr_α‖²) / sqrt(Σ_α
    /// ‖W_αα r_α‖²)` (dimensionless; W_αα the point's Delassus block, r_α its impulse,
    /// Δr_α the change over the sweep). After LMGC90's `Quad` check of its NLGS (the
    /// quadratic mean of the velocity corrections against that of `W r`), whose usual
    /// tolerances are 1e-4 to 1e-5: the norm of the impulse change weighted by what it
    /// does to the contact, relative to the mean impulse, not to a fixed velocity.
    Quad,
    /// The velocity norm to [`NscdParams::tolerance`], and, once a step has done
    /// [`NscdParams::quad_after_solves`] local solves, the quadratic norm to
    /// [`NscdParams::quad_tolerance`] as well (whichever is met first). The default.
    ///
    /// Why both: the velocity norm is the one a tilt trial needs (an absolute bound on the
    /// velocity the iterate leaves, far below the acceleration of a mechanism a few
    /// thousandths of a degree past its limit), and on a small wall Gauss–Seidel reaches
    /// it in tens to hundreds of sweeps; on a wall of hundreds of blocks it does not reach
    /// it in 2,000 (a correction travels one contact per sweep), and the iterate's noise
    /// then depends on where the sweeps stopped. The quadratic norm is met in a number of
    /// sweeps that does not grow with the wall, but it is relative to the mean impulse:
    /// alone at 1e-4 it leaves the 13-box wall a velocity of a few 1e-3 g h (the wall is
    /// then called stable 0.003° past its limit) and a single box a noise that grows
    /// from step to step. The work budget decides which applies: a small wall always meets
    /// the velocity norm within its budget, a large wall gets a fixed amount of work per
    /// step towards it and then the quadratic norm.
    Adaptive,
}

/// The contact points of a face contact polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PolygonPoints {
    /// One point per vertex: with hard contacts the vertices carry every pressure
    /// resultant inside the polygon, so the points carry its forces and moments exactly.
    Vertices,
    /// At most four points: a polygon of more than four vertices keeps the four that span
    /// the quadrilateral of largest area (LMGC90's polyhedra likewise reduce a face–face
    /// contact to at most four points). The moments the points can carry are those of that
    /// quadrilateral, a subset of the polygon's: the rigid limit can only go down, by the
    /// share of the polygon's lever arm the dropped corners held.
    Quad,
}

/// The order in which the NSGS sweeps visit the contact points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepOrder {
    /// Every sweep in the points' fixed order (the table's contacts first, then pairs in
    /// block order: from the base up in a generated wall, whose blocks are numbered course
    /// by course).
    Forward,
    /// Odd sweeps forward, even sweeps backward (symmetric Gauss–Seidel): a correction
    /// travels up the wall in one sweep and down it in the next.
    Symmetric,
}
