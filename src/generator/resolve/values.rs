//! The checks of single values shared by every section of a wall file: numbers in range,
//! and distributions resolved by number or by name with their unit and support, each
//! error naming the file and the key.

use super::{describe, Resolver};
use crate::generator::distribution::{valid_name, Distribution, DistributionSpec, Law, Unit};
use crate::generator::spec::DistRef;
use crate::generator::GeneratorError;

/// Values and distributions.
impl Resolver<'_> {
    /// [`GeneratorError::Invalid`] for `key = value` in this file.
    pub(super) fn invalid(&self, key: &str, value: String, reason: impl Into<String>) -> GeneratorError {
        GeneratorError::Invalid { path: self.path.to_owned(), key: key.into(), value, reason: reason.into() }
    }

    /// A finite number > 0.
    pub(super) fn positive(&self, key: &str, v: f64) -> Result<f64, GeneratorError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v.to_string(), "must be a finite number > 0"))
        }
    }

    /// A finite number ≥ 0.
    pub(super) fn nonneg(&self, key: &str, v: f64) -> Result<f64, GeneratorError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v.to_string(), "must be a finite number >= 0"))
        }
    }

    /// A fraction in (0, 1), with 0 and 1 allowed as asked.
    pub(super) fn fraction(&self, key: &str, v: f64, zero_ok: bool, one_ok: bool) -> Result<f64, GeneratorError> {
        let ok =
            v.is_finite() && (if zero_ok { v >= 0.0 } else { v > 0.0 }) && (if one_ok { v <= 1.0 } else { v < 1.0 });
        if ok {
            Ok(v)
        } else {
            let (open, close) = (if zero_ok { "[" } else { "(" }, if one_ok { "]" } else { ")" });
            Err(self.invalid(key, v.to_string(), format!("must be in {open}0, 1{close}")))
        }
    }

    /// Resolves a number or a name to a distribution of the expected unit: inline
    /// distributions first, then the files of the distribution source.
    pub(super) fn dist(&self, r: &DistRef, key: &str, unit: Unit) -> Result<Distribution, GeneratorError> {
        let d = match r {
            DistRef::Value(v) => {
                if !v.is_finite() {
                    return Err(self.invalid(key, v.to_string(), "must be finite"));
                }
                return Ok(Distribution::fixed(*v, unit));
            }
            DistRef::Name(name) => {
                if !valid_name(name) {
                    return Err(self.invalid(key, format!("{name:?}"), "distribution names are [A-Za-z0-9_-]+"));
                }
                if let Some(inline) = self.spec.distributions.get(name) {
                    inline.resolve(name, self.path, &format!("distributions.{name}."))?
                } else if let Some(file) = self.source.find(name) {
                    DistributionSpec::from_file(&file)?.resolve(name, &file, "")?
                } else {
                    let mut available: Vec<String> = self.spec.distributions.keys().cloned().collect();
                    available.extend(self.source.available());
                    return Err(GeneratorError::UnknownDistribution {
                        path: self.path.to_owned(),
                        key: key.into(),
                        name: name.clone(),
                        searched: self.source.dirs.clone(),
                        available,
                    });
                }
            }
        };
        if d.unit != unit {
            return Err(self.invalid(
                key,
                format!("{:?}", d.name),
                format!("distribution {} has unit {}, this key needs {}", d.name, d.unit, unit),
            ));
        }
        Ok(d)
    }

    /// A block-size law in m: positive support, mean not larger than `limit` m (the wall
    /// dimension `limit_name`).
    pub(super) fn size_law(
        &self,
        r: &DistRef,
        key: &str,
        what: &str,
        limit_name: &str,
        limit: f64,
    ) -> Result<Distribution, GeneratorError> {
        let d = self.dist(r, key, Unit::M)?;
        self.positive_support(&d, key)?;
        if d.mean() > limit {
            return Err(self.invalid(
                key,
                describe(r, &d),
                format!("{what} (mean {}) larger than the {limit_name} = {limit} m", d.mean()),
            ));
        }
        Ok(d)
    }

    /// The law's support lies above 0 (a lognormal may start at 0).
    pub(super) fn positive_support(&self, d: &Distribution, key: &str) -> Result<(), GeneratorError> {
        let (lo, _) = d.support();
        if lo > 0.0 || (lo == 0.0 && matches!(d.law, Law::Lognormal { .. })) {
            Ok(())
        } else {
            let hint =
                if lo.is_finite() { "" } else { " (a normal law is unbounded; use truncated_normal or lognormal)" };
            Err(self.invalid(key, format!("{} ({:?})", d.name, d.law), format!("must be > 0{hint}")))
        }
    }
}
