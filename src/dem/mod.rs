//! The rigid-block Discrete Element Method (3DEC-style): state, contact geometry, types
//! and law, integrator, time step, engine, monitor. See [`engine`] for the step order.

pub mod accelerate;
pub mod contact;
pub mod dispatch;
pub mod engine;
pub mod implicit;
pub mod integrator;
pub mod materials;
pub mod monitor;
pub mod params;
pub mod relax;
pub mod state;
pub mod timestep;

pub use engine::{Contact, DemError, Isa, Simulation};
pub use params::{DensityScaling, SolverParams};
pub use relax::RunToEquilibrium;
