//! Loading protocols: the tilting table ([`tilt`]; at the rigid limit by non-smooth
//! contact dynamics, [`tilt_nscd`]) and the static lateral load ([`lateral`]; its rigid pushover, [`lateral_nscd`]),
//! with the monitor points and motion measures they share ([`monitors`]) and the reading of
//! the collapse mechanism ([`mechanism`]).

pub mod lateral;
pub mod lateral_nscd;
pub mod mechanism;
pub mod monitors;
pub mod settle;
pub mod tilt;
pub mod tilt_nscd;
