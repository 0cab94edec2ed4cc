//! What a tilting-table test returns ([`TiltResult`]) and why it can fail ([`TiltError`]).

use crate::dem::DemError;
use crate::loading::mechanism::Mechanism;
use crate::loading::settle::SettleError;
use crate::range::OutOfRange;
use serde::{Deserialize, Serialize};

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
    /// The step budget of the increment
    /// ([`PenaltyParams::max_steps`](crate::dem::PenaltyParams::max_steps)) ran out before an
    /// equilibrium or a collapse was established: not a collapse, an undecided
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
    /// The semi-smooth Newton solve (`--solver newton`) found no equilibrium here and
    /// handed the increment to the protocol's own static methods (false without a Newton
    /// stage; not written when false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub newton_handed_over: bool,
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
    /// Elastic displacement scale of the joints ([`elastic_scale`](super::elastic_scale)), m: the collapse
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
    /// Whether `[last_stable_deg, first_unstable_deg]` is a bracket of the collapse tilt
    /// \[true\]: false when the first unstable tilt is an increment or trial whose step
    /// budget ran out ([`CollapseReason::StepBudget`]: neither an equilibrium nor a collapse
    /// established; at Kn ≥ 1e11 Pa/m dynamic relaxation may not settle the light
    /// sub-contacts of a knife-edge joint within it). Nothing above `last_stable_deg` is
    /// then known to be stable, but the critical tilt may lie above `first_unstable_deg`:
    /// read the result as a lower bound, or raise `[solver.penalty] max_steps`, or run the
    /// non-smooth solver (`--solver nscd`). `drystone tilt` prints it, `--json` carries it.
    #[serde(default = "reliable")]
    pub bracket_reliable: bool,
    /// A wall held by ropes whose first instability is a jump its ropes catch: where it
    /// falls ([`RopeCatch`]). The bracket above is then the **snap**, the tilt at which
    /// the wall jumps (a block moved more than the per-increment collapse displacement);
    /// `None` when the layout has no rope, when the first instability is not such a jump,
    /// or when the wall, the jump let run, fails there too (the snap is the fall).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub after_snap: Option<RopeCatch>,
}

/// Where a wall held by ropes falls once its first jump is caught (see
/// [`TiltResult::after_snap`]): the same test with the per-increment collapse displacement
/// raised to the total one ([`TiltParams::collapse_displacement_fraction`] of the width:
/// a jump is a collapse only if it carries a monitor point that far), so that a jump the
/// ropes catch within it is a stable increment. Tilts in degrees, as the bracket's.
///
/// [`TiltParams::collapse_displacement_fraction`]: super::TiltParams::collapse_displacement_fraction
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RopeCatch {
    /// The last stable tilt with the jump let run, degrees: the collapse angle of the fall
    /// (`max_angle_deg` if the wall stood to it).
    pub falls_last_stable_deg: f64,
    /// The first unstable tilt of the fall, degrees (`None`: the wall stood to
    /// `max_angle_deg`).
    pub falls_first_unstable_deg: Option<f64>,
    /// Why the fall's first unstable tilt was unstable.
    pub falls_reason: Option<CollapseReason>,
    /// The largest out-of-plane displacement of a monitor point at the first tilt past the
    /// snap with the jump let run, m: how far the ropes let the wall go before catching it.
    pub caught_displacement_m: f64,
}

fn reliable() -> bool {
    true
}

/// Errors of the tilting-table protocol.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum TiltError {
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
    /// The layout does not stand as given under gravity alone (see [`crate::loading::settle`]).
    #[error(transparent)]
    DoesNotStand(SettleError),
    /// A tilt or solver parameter is out of range.
    #[error("parameter {0}")]
    Parameter(OutOfRange),
    /// The solver chosen does not give the tilting table's path (`protocol::run_tilt`): the
    /// protocol seam's refusal (`protocol::Unsupported`), or limit analysis, which gives the
    /// collapse load multiplier instead (`protocol::Protocol::run`); the reason as text.
    #[error("{0}")]
    Unsupported(String),
    /// The non-smooth solver refused the layout (a joint with cohesion or tensile
    /// strength; `loading::tilt_nscd`).
    #[error(transparent)]
    Nscd(crate::nscd::NscdError),
    /// The rigid pushover's pressure resolves to no force on the wall
    /// ([`crate::loading::lateral::check_pushover_force`]).
    #[error(transparent)]
    NoLoad(NoLoad),
}

impl TiltError {
    pub(super) fn from_settle(e: SettleError) -> TiltError {
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

/// A pushover's pressure that resolves to no force on the wall ([`crate::loading::lateral::check_pushover_force`]).
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[error("the lateral pressure (pressure_base_pa = {pressure_base_pa}, pressure_top_pa = {pressure_top_pa}) resolves to no force on the wall: {loaded_faces} loaded faces, resultant {force_n:.3e} N (the pressure acts on exposed faces whose outward normal is within 60° of −y); a pushover multiplies the load, and there is none")]
pub struct NoLoad {
    /// Pressure at the base, Pa.
    pub pressure_base_pa: f64,
    /// Pressure at the top, Pa.
    pub pressure_top_pa: f64,
    /// Faces the pressure loads.
    pub loaded_faces: usize,
    /// Norm of the resultant force, N.
    pub force_n: f64,
}
