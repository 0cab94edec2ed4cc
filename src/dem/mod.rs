//! The rigid-block Discrete Element Method (3DEC-style): the model state ([`model`],
//! [`state`]), contact geometry, types and law, integrator, time step, the engine and its
//! workspace ([`engine`], which gives the step order), the monitor, and the drivers that
//! run the engine to equilibrium ([`drivers`]).

pub mod contact;
pub mod dispatch;
pub mod drivers;
pub mod engine;
pub mod integrator;
pub mod materials;
pub mod model;
pub mod monitor;
pub mod params;
pub mod state;
pub mod timestep;

pub use drivers::relax::RunToEquilibrium;
pub use engine::{Contact, DemError, Isa, Redetection, Simulation};
pub use model::WallState;
pub use params::{DensityScaling, SolverParams};
