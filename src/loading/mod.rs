//! Loading protocols: the tilting table ([`tilt`]; at the rigid limit by non-smooth
//! contact dynamics, [`tilt_nscd`]) and the static lateral load ([`lateral`]), run through
//! one seam ([`protocol::Protocol`]), with the monitor points and motion measures they share ([`monitors`]) and the reading of
//! the collapse mechanism ([`mechanism`]).

pub mod lateral;
pub mod mechanism;
pub mod monitors;
pub mod protocol;
pub mod settle;
pub mod shake;
pub mod tilt;
pub mod tilt_nscd;
