//! The drivers that run the engine to equilibrium: dynamic relaxation ([`relax`]), the
//! secant acceleration of slow creep and its stability indicator ([`accelerate`]), and the
//! implicit iteration of static increments ([`implicit`]), the semi-smooth Newton method
//! of a static increment ([`newton`]): the penalty DEM's static
//! methods (the non-smooth contact dynamics of rigid blocks is a method of its own,
//! `crate::nscd`, beside `crate::limit`). They use the engine through the
//! public methods of [`super::Simulation`] and read its state; the engine imports none of
//! them. Each returns a typed outcome with its cause ([`relax::Relaxed`],
//! [`implicit::Solved`]).

pub mod accelerate;
pub mod implicit;
pub mod newton;
pub mod relax;
