//! Units: SI inside (m, kg, s, N, Pa, rad); degrees and centimetres only at the edges
//! (files, CLI, reports), converted here and nowhere else.

/// Standard gravity, m/s² (the default of every layout).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Degrees to radians.
#[inline]
pub fn deg_to_rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// Radians to degrees.
#[inline]
pub fn rad_to_deg(rad: f64) -> f64 {
    rad.to_degrees()
}

/// Metres to centimetres (reports of displacement use cm, as the source paper does).
#[inline]
pub fn m_to_cm(m: f64) -> f64 {
    m * 100.0
}
