//! The one range-check helper of parameter structs (solver, tilt, lateral load): a leaf,
//! used by every module that checks numeric parameters.

/// A numeric parameter outside its allowed range: the key (as in the study file's tables and
/// the CLI flags), the value and the allowed range in words (every range also excludes NaN
/// and infinities).
#[derive(Debug, Clone, PartialEq)]
pub struct OutOfRange {
    /// The parameter.
    pub key: String,
    /// Its value.
    pub value: f64,
    /// The allowed range, e.g. `in [0, 1)`.
    pub allowed: &'static str,
}

impl OutOfRange {
    /// `key = value` is outside `allowed`.
    pub fn new(key: &str, value: f64, allowed: &'static str) -> Self {
        OutOfRange { key: key.to_string(), value, allowed }
    }

    /// What is wrong with the value, without the key: `-0.5 is out of range: must be in (0, 10]`.
    pub fn reason(&self) -> String {
        format!("{} is out of range: must be {}", self.value, self.allowed)
    }
}

impl std::fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} = {}", self.key, self.reason())
    }
}

/// Checks each `(key, value, ok, allowed)` in order; the first that is not `ok` or not finite
/// is the error.
pub(crate) fn check_ranges(checks: &[(&str, f64, bool, &'static str)]) -> Result<(), OutOfRange> {
    for &(k, v, ok, allowed) in checks {
        if !ok || !v.is_finite() {
            return Err(OutOfRange::new(k, v, allowed));
        }
    }
    Ok(())
}
