//! Loading protocols: the tilting table ([`tilt`]) and the static lateral load ([`lateral`]),
//! run through one seam ([`protocol::Protocol`]), with the monitor points and motion measures they share ([`monitors`]) and the reading of
//! the collapse mechanism ([`mechanism`]).

pub mod lateral;
pub mod mechanism;
pub mod monitors;
pub mod protocol;
pub mod settle;
pub mod tilt;
