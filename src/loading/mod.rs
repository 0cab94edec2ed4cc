//! Loading protocols: the tilting table (and, later, static lateral loads).

pub mod tilt;
