//! Loading protocols: the in-plane shear–compression test ([`inplane`]), the vertical compression test ([`compression`]), the tilting table ([`tilt`]; at the rigid limit by non-smooth
//! contact dynamics, [`tilt_nscd`]; rolled by hand in kicks, [`tilt_hand`]), the static lateral load ([`lateral`]; its pushover to
//! collapse by the penalty DEM, [`lateral_pushover`], and at the rigid limit,
//! [`lateral_nscd`]) and the shaking table ([`shake`]), with the monitor points and motion measures they share
//! ([`monitors`]) and the reading of
//! the collapse mechanism ([`mechanism`]).

pub mod compression;
pub mod excursion;
pub mod inplane;
pub mod inplane_loops;
pub mod inplane_nscd;
pub mod lateral;
pub mod lateral_nscd;
pub mod lateral_pushover;
pub mod mechanism;
pub mod monitors;
pub mod settle;
pub mod shake;
pub mod tilt;
pub mod tilt_hand;
pub mod tilt_nscd;

pub use monitors::TopMonitor;
