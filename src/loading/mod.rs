//! Loading protocols: the tilting table ([`tilt`]) and the static lateral load ([`lateral`]).

pub mod lateral;
pub mod tilt;
