//! The penalty DEM's solve settings ([`PenaltyParams`], a study's `[solver.penalty]`
//! table): the tolerance and step budget of every static solve, the secant predictor, the
//! settings of the secant acceleration ([`SecantAcceleration`]) and of the implicit
//! iteration ([`ImplicitSolve`]), and the contact dashpots and step of motion. The former
//! keys of these settings in the protocols' tables ([`MovedKey`]) keep working with a
//! deprecation warning. Plain data: the drivers (`dem::drivers`, `dem::solve`) read it.

use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};

/// Parameters of the penalty DEM's solves (`kind = "penalty"`, `newton`, `implicit`, `accelerated`,
/// `relaxation`; a `[solver.penalty]` table in a study, the `penalty` key of a Python
/// solver dict, `--tolerance`, `--max-steps`, `--no-predictor` and `--restitution` on the
/// command line). Defaults in brackets. The method's other settings (local damping, the
/// time-step safety, contact detection and density scaling) are the top-level keys of
/// [`SolverParams`](crate::dem::SolverParams); the protocols hold only their own knobs (increments, loads,
/// collapse criteria, durations).
///
/// Every static solve of every protocol reads the same tolerance and step budget: the
/// settling under gravity, each increment and trial of the tilting table, the static
/// lateral load and its pushover (`dem::solve::solve_static`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PenaltyParams {
    /// A static solve has reached equilibrium when the unbalanced-force ratio (the largest
    /// out-of-balance force over the mean gravity force, 3DEC's ratio) is below this, in
    /// (0, 1) \[1e-4\].
    pub tolerance: f64,
    /// Step budget of one static solve (the settling, one increment or trial, the loaded
    /// lateral solve), ≥ 1 \[400000\]. A solve that spends it ends as a step-budget row,
    /// never as a collapse.
    pub max_steps: u64,
    /// Start each increment of the tilting table and of the pushover from the secant
    /// prediction of its equilibrium \[true\]: the motion between the last two stable
    /// states, scaled to the new increment, applied as one jump before relaxing
    /// (`Simulation::predict`). Off: each increment starts from the last stable state.
    pub predictor: bool,
    /// Settings of the secant acceleration of slow creep (the `accelerated` stage).
    pub acceleration: SecantAcceleration,
    /// Settings of the implicit iteration (the `implicit` stage).
    pub implicit_solve: ImplicitSolve,
    /// Coefficient of restitution `e` of the normal contact dashpots of motion (the
    /// shaking table; `crate::dem::damping`), in \[0, 1\] \[0.05\]: the value whose rocking
    /// impacts lose Housner's share (`r = 1 − 1.5 sin²α`) for blocks of slenderness 10° to
    /// 27° on joints of Kn 1e10 to 1e11 Pa/m (docs/shake.md), as nscd's restitution 0 does
    /// for rigid blocks.
    pub contact_restitution: f64,
    /// Fraction of the stable step used in motion (on top of `timestep_safety`), in (0, 1]
    /// \[0.1\]: the critical step resolves a contact's impact in two or three steps, too few
    /// for the dashpot's restitution (a dropped block rebounds at 0.87 for e = 0.8 at the
    /// critical step); a tenth resolves it in about thirty.
    pub step_fraction: f64,
}

impl Default for PenaltyParams {
    fn default() -> Self {
        PenaltyParams {
            tolerance: 1e-4,
            max_steps: 400_000,
            predictor: true,
            acceleration: SecantAcceleration::default(),
            implicit_solve: ImplicitSolve::default(),
            contact_restitution: 0.05,
            step_fraction: 0.1,
        }
    }
}

impl PenaltyParams {
    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("tolerance", self.tolerance, self.tolerance > 0.0 && self.tolerance < 1.0, "in (0, 1)"),
            ("max_steps", self.max_steps as f64, self.max_steps > 0, ">= 1"),
            (
                "contact_restitution",
                self.contact_restitution,
                (0.0..=1.0).contains(&self.contact_restitution),
                "in [0, 1]",
            ),
            ("step_fraction", self.step_fraction, self.step_fraction > 0.0 && self.step_fraction <= 1.0, "in (0, 1]"),
        ])?;
        self.acceleration.validate()?;
        self.implicit_solve.validate()
    }
}

/// The value of a penalty setting written under a protocol's former key (deprecated: the
/// setting is the method's, [`PenaltyParams`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MovedValue {
    /// [`PenaltyParams::tolerance`].
    Tolerance(f64),
    /// [`PenaltyParams::max_steps`].
    MaxSteps(u64),
    /// [`PenaltyParams::predictor`].
    Predictor(bool),
    /// [`PenaltyParams::acceleration`].
    Acceleration(SecantAcceleration),
    /// [`PenaltyParams::implicit_solve`].
    ImplicitSolve(ImplicitSolve),
    /// [`PenaltyParams::contact_restitution`].
    ContactRestitution(f64),
    /// [`PenaltyParams::step_fraction`].
    StepFraction(f64),
}

impl MovedValue {
    /// Its key in `[solver.penalty]`.
    pub fn key(&self) -> &'static str {
        match self {
            MovedValue::Tolerance(_) => "tolerance",
            MovedValue::MaxSteps(_) => "max_steps",
            MovedValue::Predictor(_) => "predictor",
            MovedValue::Acceleration(_) => "acceleration",
            MovedValue::ImplicitSolve(_) => "implicit_solve",
            MovedValue::ContactRestitution(_) => "contact_restitution",
            MovedValue::StepFraction(_) => "step_fraction",
        }
    }

    /// Sets its field of `p`.
    pub fn apply(&self, p: &mut PenaltyParams) {
        match *self {
            MovedValue::Tolerance(v) => p.tolerance = v,
            MovedValue::MaxSteps(v) => p.max_steps = v,
            MovedValue::Predictor(v) => p.predictor = v,
            MovedValue::Acceleration(v) => p.acceleration = v,
            MovedValue::ImplicitSolve(v) => p.implicit_solve = v,
            MovedValue::ContactRestitution(v) => p.contact_restitution = v,
            MovedValue::StepFraction(v) => p.step_fraction = v,
        }
    }
}

/// A penalty setting a protocol's table still accepts under its former key, which keeps
/// working with a deprecation warning ([`MovedKey::warning`]): the study reader, the
/// command line and Python apply it to [`SolverParams::penalty`](crate::dem::SolverParams::penalty), and so does each
/// penalty driver, so that a caller of the library who sets it gets the same run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovedKey {
    /// The former key in the protocol's table (`tolerance` of `[tilt]`).
    pub key: &'static str,
    /// Its value.
    pub value: MovedValue,
}

impl MovedKey {
    /// The former key `key` with `value`.
    pub fn new(key: &'static str, value: MovedValue) -> MovedKey {
        MovedKey { key, value }
    }

    /// The deprecation line (without `warning: `) for the former key in the table `table`
    /// (`tilt`).
    pub fn warning(&self, table: &str) -> String {
        format!(
            "{table}.{} is deprecated: it is the penalty DEM's setting solver.penalty.{} (a [solver.penalty] table in a study), which it still sets",
            self.key,
            self.value.key()
        )
    }

    /// Checks its range as [`PenaltyParams::validate`] does, naming the former key.
    ///
    /// # Errors
    /// The value out of its range, under the former key.
    pub fn check(&self) -> Result<(), OutOfRange> {
        let mut p = PenaltyParams::default();
        self.value.apply(&mut p);
        p.validate().map_err(|e| {
            let key = match e.key.strip_prefix(self.value.key()) {
                Some(rest) => format!("{}{rest}", self.key),
                None => e.key.clone(),
            };
            OutOfRange { key, ..e }
        })
    }
}

/// Settings of the secant acceleration. Defaults in brackets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SecantAcceleration {
    /// Steps before the first window \[256\].
    pub warmup: u64,
    /// Steps per window \[128\].
    pub window: u64,
    /// Largest jump, in windows of motion \[32\].
    pub max_scale: f64,
    /// Least cosine between the motions of two successive windows for them to count as
    /// moving the same way \[0.9\].
    pub min_alignment: f64,
    /// Successive windows of negative stiffness, each with a larger out-of-balance force
    /// along the motion than the window before, that make the state unstable \[3\].
    pub negative_windows: u32,
}

impl Default for SecantAcceleration {
    fn default() -> Self {
        SecantAcceleration { warmup: 256, window: 128, max_scale: 32.0, min_alignment: 0.9, negative_windows: 3 }
    }
}

impl SecantAcceleration {
    /// Checks ranges.
    ///
    /// # Errors
    /// The first setting out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("acceleration.warmup", self.warmup as f64, true, ">= 0"),
            ("acceleration.window", self.window as f64, self.window >= 1, ">= 1"),
            ("acceleration.max_scale", self.max_scale, self.max_scale >= 1.0, ">= 1"),
            (
                "acceleration.min_alignment",
                self.min_alignment,
                self.min_alignment > -1.0 && self.min_alignment <= 1.0,
                "in (-1, 1]",
            ),
            ("acceleration.negative_windows", self.negative_windows as f64, self.negative_windows >= 1, ">= 1"),
        ])
    }
}

/// Settings of the implicit iteration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImplicitSolve {
    /// Iterations at most before dynamic relaxation takes over (default 1000).
    pub max_iterations: u32,
    /// Differences kept by the Anderson mixing, m (default 4; 0: the plain preconditioned
    /// iteration `Δx = K⁻¹ R`).
    pub anderson_depth: u32,
    /// Iterations between two factorizations of the stiffness when no contact is
    /// re-detected (default 32).
    pub refactor_every: u32,
    /// Iterations without progress after which the iteration gives up and dynamic
    /// relaxation takes over (default 100; see [`Unsolved::Stalled`](crate::dem::drivers::implicit::Unsolved::Stalled)). Progress is an
    /// unbalanced-force ratio below [`STALL_PROGRESS`](crate::dem::drivers::implicit::STALL_PROGRESS) times the lowest one reached so far.
    pub stall_window: u32,
}

impl Default for ImplicitSolve {
    fn default() -> Self {
        ImplicitSolve { max_iterations: 1000, anderson_depth: 4, refactor_every: 32, stall_window: 100 }
    }
}

impl ImplicitSolve {
    /// Checks the settings.
    ///
    /// # Errors
    /// The first key out of range, by name.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            (
                "implicit_solve.max_iterations",
                self.max_iterations as f64,
                (1..=1_000_000).contains(&self.max_iterations),
                "in [1, 1000000]",
            ),
            ("implicit_solve.anderson_depth", self.anderson_depth as f64, self.anderson_depth <= 50, "in [0, 50]"),
            ("implicit_solve.refactor_every", self.refactor_every as f64, self.refactor_every >= 1, ">= 1"),
            ("implicit_solve.stall_window", self.stall_window as f64, self.stall_window >= 1, ">= 1"),
        ])
    }
}
