//! The in-plane shear–compression test of a wall (the masonry laboratory's most common wall
//! test; Vasconcelos & Lourenço 2009, J. Struct. Eng. 135(10):1269; Vanin et al. 2017, Bull.
//! Earthquake Eng. 15:5435 for the database's definitions of its outputs).
//!
//! # The rig
//!
//! The wall stands on the table (the fixed foundation; its base course's joint is the table
//! joint of the layout, with the bed joints' law). A rigid **loading beam** is laid on the
//! top course ([`Rig::build`]): a block `loading_beam` over the wall's whole length and
//! thickness, of the top course's material (so the beam–wall joint has the bed joints' law),
//! as deep as twice the distance from the wall's top to the shear span (at most a quarter of
//! the wall's height, at least a twentieth). Its degrees of freedom
//! ([`crate::dem::constraint`]):
//!
//! * **vertical**: free, under a constant force `N = σ0 · L · t` (the applied stress times the
//!   wall's plan area), the beam's own weight included in it; the wall's self-weight comes on
//!   top, so the axial force at the base is `N_total = N + W_wall`;
//! * **horizontal (x)**: held at the actuator's point, the *shear span* `H0` above the base
//!   (the anchor), and moved by the imposed displacement, quasi-statically: one static solve
//!   ([`CASCADE`]: the implicit iteration, dynamic relaxation where it hands over, to the
//!   penalty tolerance) per increment. The actuator's force `V`
//!   is the reaction of that hold;
//! * **rotation in the plane (about y)**: free (cantilever: the horizontal force acts at
//!   `H0`, where the moment is zero, the tests' case) or held (double-fixed, no shear span);
//! * **out of plane** (y, and the rotations about x and z): held by the rig's guides.
//!
//! # The history
//!
//! Monotonic to a drift ([`InPlaneParams::drift_pct`]), or cycles of growing amplitude
//! ([`History::Cyclic`]: each amplitude [`InPlaneParams::cycles`] times, 0 → +a → −a → 0).
//! The displacement is read on the beam at the *measuring point*
//! ([`InPlaneParams::measuring_height_m`]; unset, the actuator's height: the shear span `H0`
//! with the beam's rotation free, the wall's top with it held), and the drift is that
//! displacement over the measuring point's height. This is the Stone Masonry Database's
//! reading (Vanin et al. 2017): where a test reports no measuring height (`HLVDT_mm`
//! empty), the displacement is taken at the actuator's height, and every curve and
//! envelope file gives `drift_% = displacement_mm / H0 × 100`. The initial stiffness
//! (kN/mm) is read on the same displacement.
//!
//! # The outputs (the database's definitions, Vanin et al. 2017)
//!
//! The curve (top displacement mm, drift %, force kN). Per direction: the peak force and the
//! drift where it was reached; the ultimate drift, where the force on the envelope (the
//! points at a new largest drift of the direction) first falls below 80 % of the peak past
//! it, or the largest drift run; the initial stiffness, the secant at 15 % of the peak
//! (kN/mm). The mechanism ([`InPlaneMechanism`], read from the blocks' motion): rocking
//! about a toe, sliding of a bed joint, a stepped diagonal (shear) crack, or mixed.
//!
//! # Closed forms
//!
//! A monolithic wall rocking about its toe carries `V = N_total · L / (2 H0)`; a wall whose
//! joints slide before it rocks carries `V = μ N_total` (μ of the sliding joint); a one-block
//! wall on a linear joint of normal and shear stiffness Kn, Ks has the elastic stiffness
//! [`one_block_stiffness`] (`drystone verify`, `tests/suite/inplane.rs`).
//!
//! # The parts
//!
//! * `params`: the parameters ([`InPlaneParams`], [`History`], [`BeamRotation`], [`OutOfPlane`]), their
//!   validation, amplitudes and path, and the bounds they are checked against;
//! * `error`: the errors ([`InPlaneError`]) and the checks of a layout against the penalty
//!   DEM's reach ([`check_cyclic_slip_range`], [`check_joint_closure`], [`check_drift_reach`]);
//! * `rig`: the rig ([`Rig`]: the beam, its constraint, the rig's forces, [`add_rig_force`],
//!   [`read_curve`]), the mirror reading ([`Mirror`]) and [`one_block_stiffness`];
//! * `readings`: the curve ([`CurvePoint`]) and its per-direction readings ([`direction`],
//!   [`DirectionResult`], [`envelope_readings`]);
//! * `wall_mechanism`: the mechanism ([`MechanismKind`], [`InPlaneMechanism`],
//!   [`read_mechanism`] over the joints of [`mechanism_joints`]) and the half-cycle it is
//!   read over;
//! * `driver`: the penalty DEM's driver ([`run_in_plane_penalty`]): the wall under the
//!   vertical force, then the imposed path;
//! * `vertical`: the vertical phase every test on the rig starts with
//!   ([`stand_under_vertical_force`]: the wall under the vertical force, and its vertical
//!   modulus read on that first loading branch, [`VerticalPhase`]);
//! * `increments`: the driver's increments along the path, their size, predictor and
//!   restarts;
//! * `result`: the outcome ([`InPlaneResult`]) and how a driver's run makes it.

mod driver;
mod error;
mod increments;
mod params;
mod readings;
mod result;
mod rig;
mod vertical;
mod wall_mechanism;

pub use driver::{run_in_plane_penalty, BLOCK_IMBALANCE_SHARE};
pub use error::{
    check_cyclic_slip_range, check_drift_reach, check_joint_closure, max_drift_pct, InPlaneError, MAX_CLOSURE_SHARE,
    MIN_CYCLIC_SLIP_RANGE_M,
};
pub use params::{
    BeamRotation, History, InPlaneParams, OutOfPlane, MAX_CYCLES, MAX_HEIGHT_RATIO, MAX_INCREMENTS,
    MAX_QUARTER_INCREMENTS,
};
pub use readings::{
    direction, envelope_readings, CurvePoint, DirectionResult, READING_DRIFTS_PCT, STIFFNESS_SHARE, ULTIMATE_DROP,
};
pub use result::InPlaneResult;
pub(crate) use result::{result_of, Excursion, Work};
pub use rig::{
    add_rig_force, level_tolerance_m, one_block_stiffness, read_curve, Mirror, Rig, BEAM_ID, BEARING_SHARE,
    LEVEL_TOLERANCE_FLOOR_M, LEVEL_TOLERANCE_FRACTION,
};
pub use vertical::{stand_under_vertical_force, VerticalPhase, CASCADE, LOCAL_TOLERANCE};
pub use wall_mechanism::{
    mechanism_joints, read_mechanism, InPlaneMechanism, MechanismJoint, MechanismKind, ACTIVE_JOINT_SHARE,
};
pub(crate) use wall_mechanism::{HalfCycle, Poses};
