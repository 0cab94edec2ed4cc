//! Non-smooth contact dynamics (NSCD) of rigid blocks: the Moreau–Jean time stepping with
//! hard unilateral contacts and Coulomb friction, solved by non-linear Gauss–Seidel
//! (Moreau 1988; Jean 1999, Comput. Methods Appl. Mech. Eng. 177:235; Acary & Brogliato
//! 2008, *Numerical Methods for Nonsmooth Dynamical Systems*, ch. 10 and 12). LMGC90 and
//! Siconos are the reference codes of the method; this is drystone's own implementation.
//!
//! Every joint is rigid: the layout's Kn, Ks and elastic closure law are not used; its friction
//! angle φ (material rule and joint families, as the penalty engine reads them) is.
//! Cohesion and tensile strength are refused ([`NscdError::Cohesion`], naming the joint), and
//! so is a crushing law ([`NscdError::Crushing`], naming the material or joint family): its
//! rigid joints crush at no stress.
//!
//! # The parts
//!
//! * [`contacts`]: contact points and their local frames from drystone's own detection
//!   (sweep and prune, the separating-axis narrow phase and its contact polygon,
//!   `dem::contact::geometry`): one point per vertex of each contact polygon (a segment
//!   contact: its two ends; a point contact: the point). With hard contacts the vertices
//!   of the polygon carry every admissible pressure resultant inside it, so the reduced
//!   set carries the same forces and moments as the polygon (as LMGC90's polyhedra do).
//! * [`delassus`]: the blocks of the Delassus operator `W = H M⁻¹ Hᵀ` of the rigid
//!   bodies (the diagonal 3 × 3 block of each contact point, and the rows `H` that map
//!   the bodies' velocities to the point's relative velocity).
//! * [`held`]: the mobility of a body whose degrees of freedom are constrained (held
//!   translations at an anchor, an imposed displacement, held rotations): its held
//!   directions eliminated from the velocity unknowns, its imposed velocity a known term.
//! * [`local`]: the local 3D Coulomb problem of one contact point (separation, stick or
//!   slip, exact; De Saxcé's projection as a fallback).
//! * [`nsgs`]: the Gauss–Seidel sweeps of one step (their order, [`nsgs::SweepPlan`];
//!   the visit of a contact polygon; the stopping rule).
//! * [`apgd`]: the accelerated projected gradient of a step of motion (Nesterov's method
//!   with De Saxcé's shift), stopped by the natural-map residual
//!   ([`nsgs::natural_residual`]).
//! * [`cone`]: the finisher of the steps the gradient leaves at its limit: the step as
//!   one cone program per value of De Saxcé's shift (an interior point, Clarabel), the
//!   shift updated by Anderson's acceleration.
//! * [`rest`]: the rest certificate of a wall at rest (statics in the reduced cones).
//! * [`stepper`]: [`NscdSimulation`], the θ-scheme step with a prescribed base
//!   acceleration and its NSGS loop.
//!
//! # Frames and signs
//!
//! The table frame (x along the wall, y out of plane, z up). At each contact point the
//! local frame is (n, t₁, t₂), `n` the unit normal from body A (the table, or the lower
//! index) to body B and (t₁, t₂) = `geometry::polygon::plane_basis(n)`. `u` is the
//! velocity of B relative to A at the point in that frame (m/s), `r` the impulse on B over
//! the step in that frame (N·s; A gets −r). Signorini: `uₙ + b ≥ 0, rₙ ≥ 0, (uₙ + b) rₙ = 0`
//! with `b` the gap and restitution term of [`stepper`]; Coulomb: `‖r_t‖ ≤ μ rₙ`, and
//! `r_t = −μ rₙ u_t/‖u_t‖` when `u_t ≠ 0`.

pub mod apgd;
pub mod cone;
pub mod contacts;
pub mod delassus;
pub mod held;
pub mod local;
pub mod nsgs;
pub mod rest;
pub mod stepper;

pub use contacts::ContactPoint;
pub use stepper::{NscdSimulation, NscdStep};

pub use crate::dem::nscd_params::{NscdParams, NsgsNorm, PolygonPoints, RestRule, StepSolver, SweepOrder};

use crate::range::OutOfRange;

/// Errors of the non-smooth solver.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum NscdError {
    /// A parameter is out of range.
    #[error("nscd parameter {0}")]
    Parameter(OutOfRange),
    /// A joint has cohesion or tensile strength: the solver's joints are cohesionless
    /// Coulomb contacts.
    #[error(
        "joint {joint} has cohesion {cohesion_pa} Pa and tensile strength {tensile_strength_pa} Pa: the nscd solver \
         models rigid cohesionless Coulomb joints; set both to 0 for this joint's material or family, or use the \
         penalty solver"
    )]
    Cohesion {
        /// The joint, `table/ID` or `ID_A/ID_B`.
        joint: String,
        /// Its cohesion, Pa.
        cohesion_pa: f64,
        /// Its tensile strength, Pa.
        tensile_strength_pa: f64,
    },
    /// A joint's faces crush ([`crate::layout::Layout::crushing_joint`]): the solver's
    /// joints are rigid, with no crushing law, and would run the wall without it.
    #[error(
        "the nscd solver has no crushing law: the faces' crushing of {joint} (closure crushing, strength {:.4} MPa; \
         the effect toe_crushing sets it) is not modelled; use the penalty DEM",
        strength_pa * 1e-6
    )]
    Crushing {
        /// The joint rule, `material NAME` or `joint family NAME`.
        joint: String,
        /// Its crushing strength fc, Pa.
        strength_pa: f64,
    },
    /// A body's state became NaN or infinite.
    #[error("block {id} has a non-finite state at step {step} (time step {dt_s:e} s): the run blew up")]
    NonFinite {
        /// Block id.
        id: String,
        /// Step number.
        step: u64,
        /// Time step, s.
        dt_s: f64,
    },
}
