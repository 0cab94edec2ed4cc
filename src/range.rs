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
    /// The key has no single value to show (it is missing, or a list): the message says what
    /// it must be, not a value (`value` is NaN).
    pub no_value: bool,
}

impl OutOfRange {
    /// `key = value` is outside `allowed`.
    pub fn new(key: &str, value: f64, allowed: &'static str) -> Self {
        OutOfRange { key: key.to_string(), value, allowed, no_value: false }
    }

    /// `key` has no single value to show (missing, or a list that breaks the rule) and must
    /// be `allowed`.
    pub fn without_value(key: &str, allowed: &'static str) -> Self {
        OutOfRange { key: key.to_string(), value: f64::NAN, allowed, no_value: true }
    }

    /// What is wrong with the value, without the key: `-0.5 is out of range: must be in (0, 10]`
    /// (for a key without a value: `must be given: …`).
    pub fn reason(&self) -> String {
        if self.no_value {
            format!("must be {}", self.allowed)
        } else {
            format!("{} is out of range: must be {}", self.value, self.allowed)
        }
    }
}

impl std::fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.no_value {
            write!(f, "{}: {}", self.key, self.reason())
        } else {
            write!(f, "{} = {}", self.key, self.reason())
        }
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
