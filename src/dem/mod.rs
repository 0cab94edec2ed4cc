//! The rigid-block Discrete Element Method (3DEC-style): the model state ([`model`],
//! [`state`]), contact geometry, types and law, integrator, time step, the engine and its
//! workspace ([`Simulation`], whose `step` gives the step order), the monitor, and the drivers that
//! run the engine to equilibrium ([`drivers`]).

pub mod constraint;
pub mod contact;
pub mod damping;
pub(crate) mod dispatch;
pub mod drivers;
pub(crate) mod engine;
mod error;
pub mod hold;
pub mod integrator;
pub(crate) mod materials;
pub mod method;
pub mod model;
pub(crate) mod monitor;
pub mod motion;
pub mod nscd_params;
pub(crate) mod params;
pub mod penalty;
pub mod rope;
pub mod solve;
pub mod state;
pub mod timestep;
mod workspace;

pub use constraint::{DofConstraint, Hold, RigMoment};
pub use engine::{Contact, DemError, Isa, Redetection, Simulation};
pub use method::{Cascade, Method, SolverKind};
pub use model::WallState;
pub use monitor::StepStats;
pub use params::{with_moved, DensityScaling, LimitParams, SolverParams};
pub use penalty::{MovedKey, MovedValue, PenaltyParams};
pub use solve::{solve_static, End, RunToEquilibrium, SolveOutcome, SolveStage, StaticSolve};
