//! Contacts: narrow-phase geometry and the joint law.

pub mod geometry;
pub mod law;
