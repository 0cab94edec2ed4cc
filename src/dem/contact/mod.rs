//! Contacts: narrow-phase geometry, the contact types and the joint law.

pub(crate) mod forces;
pub mod geometry;
pub mod law;
pub mod types;
