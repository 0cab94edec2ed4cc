//! # drystone
//!
//! Probabilistic out-of-plane assessment of dry stone walls with a rigid-block Discrete
//! Element Method.
//!
//! ```text
//!  wall description ──generator──▶ layout (convex blocks) ──dem──▶ collapse angle,
//!   + seed, realization i          (JSON, strict)          loading   displacements,
//!                                                          protocol  mechanism
//!        ensemble: realizations in parallel ──▶ stats ──▶ tables, plots, reports
//!                                                   └──▶ discrepancy: measured data ──▶
//!                                                        named cause, extended model
//! ```
//!
//! * [`geometry`]: convex polyhedral blocks, mass properties, frames.
//! * [`layout`]: the layout file (materials, blocks, table, restraints).
//! * [`dem`]: the DEM engine (3DEC-style sub-contacts, Coulomb joints, central differences,
//!   local damping) and the non-smooth contact dynamics solver (`nscd`).
//! * [`loading`]: the protocols: the tilting table (quasi-static, at the rigid limit, or
//!   rolled by hand in kicks), the static lateral load and its pushover, and the shaking
//!   table under a ground motion ([`ground`]).
//! * [`limit`]: limit analysis (the rigid collapse load multiplier from statics alone, a
//!   second-order cone program over the DEM's contact polygons).
//! * [`protocol`]: the seam: a protocol with its parameters, run by the method the solver
//!   selects (the penalty DEM, non-smooth contact dynamics or limit analysis), as the one
//!   compatibility table (`protocol::methods`) allows.
//! * [`generator`]: seeded wall layouts; [`effects`]: named extensions of the model (the
//!   built-in library and the user's effect files) applied to a generated layout;
//!   [`ensemble`], [`stats`], [`study`]: ensembles, statistics, study files and reports.
//! * [`discrepancy`]: what the model gets wrong against measured data, the physical effect
//!   that explains it, the extended model and its held-out gain.
//! * [`verify`]: closed-form verification cases.
//!
//! ## Example
//!
//! Generate one realization of a wall description and tilt it to collapse
//! (`examples/tilt_a_wall.rs` prints more of the result):
//!
//! ```
//! use drystone::prelude::*;
//!
//! let file = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/discrepancy/walls/small_free.toml");
//! let wall = Wall::from_file(std::path::Path::new(file))?;
//! let layout = generate(&wall, 2021, 0)?.check()?; // master seed, realization
//! let again = generate(&wall, 2021, 0)?.check()?;
//! assert_eq!(layout.blocks.len(), again.blocks.len()); // the seed fixes the layout
//! let r = run_tilt(&layout, SolverParams::default(), &TiltParams::default())?;
//! assert!(r.collapse_angle_deg() > 5.0 && r.collapse_angle_deg() < 40.0);
//! assert!(r.first_unstable_deg.unwrap() > r.collapse_angle_deg());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Units
//!
//! SI inside (m, kg, s, N, Pa, rad). Degrees and centimetres only at the edges (files, CLI,
//! reports), converted in [`units`].
//!
//! ## Frames
//!
//! The table frame: x along the wall, y out of plane (positive is the side the wall falls
//! to), z up; the table is the plane z = 0. Tilting the table by α turns gravity into
//! `g (0, sin α, −cos α)` in this frame.
//!
//! ## Determinism contract
//!
//! A simulation is single-threaded and its force sums run in a fixed order: the same
//! layout and parameters give the same numbers bit for bit, run after run and whatever the
//! number of threads of the process. All randomness comes from [`rng::rng_for`].

#![warn(missing_docs)]

// The binary's `bench` and `verify` commands: not part of the library's API.
#[doc(hidden)]
pub mod benchmark;
pub mod closure;
pub mod dem;
pub mod discrepancy;
pub mod effects;
pub mod ensemble;
pub mod files;
pub mod generator;
pub mod geometry;
pub mod ground;
pub mod io;
pub mod layout;
pub mod limit;
pub mod loading;
pub mod math;
pub mod nscd;
pub mod protocol;
pub mod range;
pub mod rng;
pub mod stats;
pub mod study;
pub mod survey;
pub mod units;
#[doc(hidden)]
pub mod verify;

pub mod prelude {
    //! The entry points most programs need: `use drystone::prelude::*;`.
    //!
    //! Generate a layout ([`generate`] from a [`Wall`] description), tilt it ([`run_tilt`]
    //! with [`SolverParams`] and [`TiltParams`]) or load it laterally ([`run_lateral`]), run
    //! a study's ensemble ([`Study::from_file`], [`run_study`] over a [`Shard`]), and
    //! confront it with measured data ([`discrepancy::run`], or [`discrepancy::prepare`]
    //! once and [`discrepancy::analyze`] per data set).
    pub use crate::dem::SolverParams;
    pub use crate::discrepancy::{self, Settings as DiscrepancySettings};
    pub use crate::ensemble::Shard;
    pub use crate::generator::{generate, Wall};
    pub use crate::layout::{Layout, LayoutSpec};
    pub use crate::loading::lateral::LateralParams;
    pub use crate::loading::tilt::{TiltParams, TiltResult};
    pub use crate::protocol::{run_lateral, run_tilt};
    pub use crate::study::run_study;
    pub use crate::study::Study;
}

pub use math::{Mat3, Vec3};
