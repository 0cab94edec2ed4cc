//! Named random models as data: `distributions/NAME.toml`.
//!
//! # File format (version 1, strict)
//!
//! ```toml
//! version = 1
//! description = "Dip of bed-joint segments, uniform in [-20°, +20°] (Santa-Cruz et al. 2021, §4.1)"
//! unit = "deg"
//! kind = "uniform"
//! min = -20.0
//! max = 20.0
//! ```
//!
//! | `kind` | keys | law |
//! | --- | --- | --- |
//! | `fixed` | `value` | always `value` |
//! | `uniform` | `min < max` | uniform on \[min, max) |
//! | `normal` | `mean`, `std > 0` | N(mean, std²) |
//! | `truncated_normal` | `mean`, `std > 0`, `min < max` | N(mean, std²) conditioned on \[min, max\], sampled by inverting the CDF (one uniform draw per sample) |
//! | `lognormal` | `mean > 0`, `cv > 0` | ln X ~ N(μ, σ²) with σ² = ln(1 + cv²), μ = ln(mean) − σ²/2 (so E\[X\] = mean, std/mean = cv) |
//!
//! `unit` says what the numbers are: `deg` (angles, degrees), `m` (lengths, metres), `1`
//! (dimensionless factors), `pa_per_m` (joint stiffness), `pa` (stress). A wall key that
//! takes a distribution checks its unit: a dip needs `deg`, a length `m`. Values stay in the
//! file's unit; the caller converts (degrees to radians once, in the generator).
//!
//! Any other key, a key the kind does not take, or a missing key is an error naming the file
//! and the key.
//!
//! # Names and lookup
//!
//! A distribution's name is its file stem (`distributions/dip_uniform_20.toml` is
//! `dip_uniform_20`); names are `[A-Za-z0-9_-]+`. A wall file may also define distributions
//! inline under `[distributions.NAME]` (same keys; `version` optional); inline definitions
//! are looked up first.
//!
//! # Sampling
//!
//! Every sample draws from the caller's `ChaCha8Rng` (from [`crate::rng::rng_for`]): uniform
//! via `rand::distr::Uniform`, normal and lognormal via `rand_distr`, truncated normal by the
//! inverse CDF of statrs' normal. A `fixed` distribution draws nothing.

use rand::Rng;
use rand_distr::Distribution as _;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, LogNormal as SLogNormal, Normal as SNormal};
use std::fmt;
use std::path::{Path, PathBuf};

use super::GeneratorError;

mod source;
pub use source::{valid_name, DistributionSource};

/// The only distribution file version this build reads.
pub const DISTRIBUTION_VERSION: u32 = 1;

/// Unit of a distribution's values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Unit {
    /// Degrees (angles).
    #[serde(rename = "deg")]
    Deg,
    /// Metres (lengths).
    #[serde(rename = "m")]
    M,
    /// Dimensionless (factors, fractions).
    #[serde(rename = "1")]
    One,
    /// Pa/m (joint stiffness).
    #[serde(rename = "pa_per_m")]
    PaPerM,
    /// Pa (stress).
    #[serde(rename = "pa")]
    Pa,
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Unit::Deg => "deg",
            Unit::M => "m",
            Unit::One => "1",
            Unit::PaPerM => "pa_per_m",
            Unit::Pa => "pa",
        })
    }
}

/// Kind of a distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A fixed value.
    Fixed,
    /// Uniform on \[min, max).
    Uniform,
    /// Normal.
    Normal,
    /// Normal truncated to \[min, max\].
    TruncatedNormal,
    /// Lognormal given by its mean and coefficient of variation.
    Lognormal,
}

/// Raw contents of a distribution file or inline table (see the module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DistributionSpec {
    /// Format version; required (= 1) in a file, optional inline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<u32>,
    /// Free text: what the distribution models and where it comes from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// Unit of every number in the file.
    pub unit: Unit,
    /// The law.
    pub kind: Kind,
    /// `fixed`: the value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// `uniform`, `truncated_normal`: lower bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// `uniform`, `truncated_normal`: upper bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// `normal`, `truncated_normal` (of the parent normal), `lognormal`: mean.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<f64>,
    /// `normal`, `truncated_normal` (of the parent normal): standard deviation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub std: Option<f64>,
    /// `lognormal`: coefficient of variation std/mean.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cv: Option<f64>,
}

/// The law of a checked distribution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// Always this value.
    Fixed(f64),
    /// Uniform on \[min, max).
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Normal.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (> 0).
        std: f64,
    },
    /// Normal(mean, std) conditioned on \[min, max\].
    TruncatedNormal {
        /// Mean of the parent normal.
        mean: f64,
        /// Standard deviation of the parent normal (> 0).
        std: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Lognormal with mean `mean` and std `cv × mean`.
    Lognormal {
        /// Mean (> 0).
        mean: f64,
        /// Coefficient of variation (> 0).
        cv: f64,
    },
}

/// A checked, named distribution: sample, CDF, mean, support.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution {
    /// Name (file stem, inline table name, or `<value>` for a plain number in a wall file).
    pub name: String,
    /// Where it was defined (file), for messages.
    pub source: PathBuf,
    /// Unit of the values.
    pub unit: Unit,
    /// The law.
    pub law: Law,
}

fn bad(path: &Path, key: &str, value: impl fmt::Display, reason: impl Into<String>) -> GeneratorError {
    GeneratorError::Invalid { path: path.to_owned(), key: key.into(), value: value.to_string(), reason: reason.into() }
}

/// Standard normal CDF and its lower/upper tails computed without cancellation.
fn std_normal() -> SNormal {
    SNormal::new(0.0, 1.0).expect("N(0,1) is valid")
}

impl DistributionSpec {
    /// Parses TOML text; `path` names the source in errors.
    ///
    /// # Errors
    /// [`GeneratorError::Parse`] naming the file (toml's message names the key and line).
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, GeneratorError> {
        toml::from_str(text).map_err(|e| GeneratorError::Parse { path: path.to_owned(), message: e.to_string() })
    }

    /// Reads `path`.
    ///
    /// # Errors
    /// [`GeneratorError::Io`] or [`GeneratorError::Parse`], naming the file.
    pub fn from_file(path: &Path) -> Result<Self, GeneratorError> {
        let text =
            std::fs::read_to_string(path).map_err(|source| GeneratorError::Io { path: path.to_owned(), source })?;
        let spec = Self::from_toml(&text, path)?;
        match spec.version {
            Some(DISTRIBUTION_VERSION) => Ok(spec),
            Some(v) => Err(bad(path, "version", v, "this drystone reads distribution version 1")),
            None => Err(bad(path, "version", "missing", "a distribution file needs `version = 1`")),
        }
    }

    /// Checks the keys for the kind and the values; `prefix` is prepended to key names in
    /// errors (e.g. `distributions.dip.` for an inline table).
    ///
    /// # Errors
    /// [`GeneratorError::Invalid`] naming `path` and the key.
    pub fn resolve(&self, name: &str, path: &Path, prefix: &str) -> Result<Distribution, GeneratorError> {
        let k = |s: &str| format!("{prefix}{s}");
        if let Some(v) = self.version {
            if v != DISTRIBUTION_VERSION {
                return Err(bad(path, &k("version"), v, "this drystone reads distribution version 1"));
            }
        }
        let given: [(&str, Option<f64>); 6] = [
            ("value", self.value),
            ("min", self.min),
            ("max", self.max),
            ("mean", self.mean),
            ("std", self.std),
            ("cv", self.cv),
        ];
        let takes: &[&str] = match self.kind {
            Kind::Fixed => &["value"],
            Kind::Uniform => &["min", "max"],
            Kind::Normal => &["mean", "std"],
            Kind::TruncatedNormal => &["mean", "std", "min", "max"],
            Kind::Lognormal => &["mean", "cv"],
        };
        let kind_name = format!("{:?}", self.kind);
        for (key, v) in given {
            match (takes.contains(&key), v) {
                (false, Some(v)) => {
                    return Err(bad(path, &k(key), v, format!("kind {kind_name} takes only {}", takes.join(", "))))
                }
                (true, None) => return Err(bad(path, &k(key), "missing", format!("kind {kind_name} needs it"))),
                (true, Some(v)) if !v.is_finite() => return Err(bad(path, &k(key), v, "must be finite")),
                _ => {}
            }
        }
        // Every value the kind takes is present and finite from here on.
        let g = |key: &str| given.iter().find(|(n, _)| *n == key).and_then(|(_, v)| *v).unwrap_or(f64::NAN);
        let law = match self.kind {
            Kind::Fixed => Law::Fixed(g("value")),
            Kind::Uniform => {
                let (min, max) = (g("min"), g("max"));
                if min >= max {
                    return Err(bad(
                        path,
                        &k("max"),
                        max,
                        format!("must be > min = {min} (use kind fixed for one value)"),
                    ));
                }
                Law::Uniform { min, max }
            }
            Kind::Normal => {
                let std = g("std");
                if std <= 0.0 {
                    return Err(bad(path, &k("std"), std, "must be > 0"));
                }
                Law::Normal { mean: g("mean"), std }
            }
            Kind::TruncatedNormal => {
                let (mean, std, min, max) = (g("mean"), g("std"), g("min"), g("max"));
                if std <= 0.0 {
                    return Err(bad(path, &k("std"), std, "must be > 0"));
                }
                if min >= max {
                    return Err(bad(path, &k("max"), max, format!("must be > min = {min}")));
                }
                let law = Law::TruncatedNormal { mean, std, min, max };
                if trunc_mass(mean, std, min, max) <= 1e-9 {
                    return Err(bad(
                        path,
                        &k("min"),
                        min,
                        format!("the interval [{min}, {max}] holds no probability of N({mean}, {std}²)"),
                    ));
                }
                law
            }
            Kind::Lognormal => {
                let (mean, cv) = (g("mean"), g("cv"));
                if mean <= 0.0 {
                    return Err(bad(path, &k("mean"), mean, "must be > 0"));
                }
                if cv <= 0.0 {
                    return Err(bad(path, &k("cv"), cv, "must be > 0 (use kind fixed for no scatter)"));
                }
                Law::Lognormal { mean, cv }
            }
        };
        Ok(Distribution { name: name.into(), source: path.to_owned(), unit: self.unit, law })
    }
}

/// Φ(b') − Φ(a') for the standardized bounds, computed in the tail that keeps precision.
fn trunc_mass(mean: f64, std: f64, min: f64, max: f64) -> f64 {
    let n = std_normal();
    let (a, b) = ((min - mean) / std, (max - mean) / std);
    if a > 0.0 {
        n.sf(a) - n.sf(b)
    } else {
        n.cdf(b) - n.cdf(a)
    }
}

fn lognormal_params(mean: f64, cv: f64) -> (f64, f64) {
    let s2 = (1.0 + cv * cv).ln();
    (mean.ln() - s2 / 2.0, s2.sqrt())
}

impl Distribution {
    /// A fixed value (a plain number in a wall file).
    pub fn fixed(value: f64, unit: Unit) -> Self {
        Distribution { name: format!("{value}"), source: PathBuf::new(), unit, law: Law::Fixed(value) }
    }

    /// Uniform on \[min, max) (built in, e.g. the default dip law).
    pub fn uniform(name: &str, min: f64, max: f64, unit: Unit) -> Self {
        Distribution { name: name.into(), source: PathBuf::new(), unit, law: Law::Uniform { min, max } }
    }

    /// True for a `fixed` law.
    pub fn is_fixed(&self) -> bool {
        matches!(self.law, Law::Fixed(_))
    }

    /// One sample, in the distribution's unit. Draws from `rng` (nothing for `fixed`).
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match self.law {
            Law::Fixed(v) => v,
            Law::Uniform { min, max } => {
                rand::distr::Uniform::new(min, max).expect("checked: min < max, finite").sample(rng)
            }
            Law::Normal { mean, std } => rand_distr::Normal::new(mean, std).expect("checked: std > 0").sample(rng),
            Law::TruncatedNormal { mean, std, min, max } => {
                let n = std_normal();
                let (a, b) = ((min - mean) / std, (max - mean) / std);
                let u: f64 = rand::distr::Uniform::new(0.0, 1.0).expect("valid").sample(rng);
                // Invert in the tail that keeps precision: upper-tail intervals by symmetry.
                let z = if a > 0.0 {
                    let (pa, pb) = (n.sf(a), n.sf(b));
                    let p = (pa - u * (pa - pb)).clamp(0.0, 1.0);
                    -n.inverse_cdf(p)
                } else {
                    let (pa, pb) = (n.cdf(a), n.cdf(b));
                    let p = (pa + u * (pb - pa)).clamp(0.0, 1.0);
                    n.inverse_cdf(p)
                };
                (mean + std * z).clamp(min, max)
            }
            Law::Lognormal { mean, cv } => {
                let (mu, sigma) = lognormal_params(mean, cv);
                rand_distr::LogNormal::new(mu, sigma).expect("checked: sigma > 0").sample(rng)
            }
        }
    }

    /// Cumulative distribution function at `x` (for goodness-of-fit tests). A `fixed` law
    /// is a step at its value.
    pub fn cdf(&self, x: f64) -> f64 {
        match self.law {
            Law::Fixed(v) => {
                if x < v {
                    0.0
                } else {
                    1.0
                }
            }
            Law::Uniform { min, max } => ((x - min) / (max - min)).clamp(0.0, 1.0),
            Law::Normal { mean, std } => std_normal().cdf((x - mean) / std),
            Law::TruncatedNormal { mean, std, min, max } => {
                if x <= min {
                    return 0.0;
                }
                if x >= max {
                    return 1.0;
                }
                let n = std_normal();
                let (a, b, z) = ((min - mean) / std, (max - mean) / std, (x - mean) / std);
                if a > 0.0 {
                    ((n.sf(a) - n.sf(z)) / (n.sf(a) - n.sf(b))).clamp(0.0, 1.0)
                } else {
                    ((n.cdf(z) - n.cdf(a)) / (n.cdf(b) - n.cdf(a))).clamp(0.0, 1.0)
                }
            }
            Law::Lognormal { mean, cv } => {
                if x <= 0.0 {
                    return 0.0;
                }
                let (mu, sigma) = lognormal_params(mean, cv);
                SLogNormal::new(mu, sigma).expect("sigma > 0").cdf(x)
            }
        }
    }

    /// Quantile (inverse CDF) at probability `p` in (0, 1).
    pub fn quantile(&self, p: f64) -> f64 {
        let p = p.clamp(1e-15, 1.0 - 1e-15);
        match self.law {
            Law::Fixed(v) => v,
            Law::Uniform { min, max } => min + p * (max - min),
            Law::Normal { mean, std } => mean + std * std_normal().inverse_cdf(p),
            Law::TruncatedNormal { mean, std, min, max } => {
                let n = std_normal();
                let (a, b) = ((min - mean) / std, (max - mean) / std);
                let z = if a > 0.0 {
                    let (pa, pb) = (n.sf(a), n.sf(b));
                    -n.inverse_cdf((pa - p * (pa - pb)).clamp(0.0, 1.0))
                } else {
                    let (pa, pb) = (n.cdf(a), n.cdf(b));
                    n.inverse_cdf((pa + p * (pb - pa)).clamp(0.0, 1.0))
                };
                (mean + std * z).clamp(min, max)
            }
            Law::Lognormal { mean, cv } => {
                let (mu, sigma) = lognormal_params(mean, cv);
                (mu + sigma * std_normal().inverse_cdf(p)).exp()
            }
        }
    }

    /// Mean of the law.
    pub fn mean(&self) -> f64 {
        match self.law {
            Law::Fixed(v) => v,
            Law::Uniform { min, max } => 0.5 * (min + max),
            Law::Normal { mean, .. } | Law::Lognormal { mean, .. } => mean,
            Law::TruncatedNormal { mean, std, min, max } => {
                let (a, b) = ((min - mean) / std, (max - mean) / std);
                let pdf = |z: f64| (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
                let m = mean + std * (pdf(a) - pdf(b)) / trunc_mass(mean, std, min, max).max(f64::MIN_POSITIVE);
                m.clamp(min, max)
            }
        }
    }

    /// Smallest and largest possible values (±∞ where unbounded; 0 is the lower bound of a
    /// lognormal).
    pub fn support(&self) -> (f64, f64) {
        match self.law {
            Law::Fixed(v) => (v, v),
            Law::Uniform { min, max } | Law::TruncatedNormal { min, max, .. } => (min, max),
            Law::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Law::Lognormal { .. } => (0.0, f64::INFINITY),
        }
    }

    /// A practical upper bound: the support's upper end if finite, else the 0.999 quantile.
    pub fn practical_max(&self) -> f64 {
        let (_, hi) = self.support();
        if hi.is_finite() {
            hi
        } else {
            self.quantile(0.999)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{rng_for, Purpose};

    fn spec(text: &str) -> Result<Distribution, GeneratorError> {
        let p = Path::new("test.toml");
        DistributionSpec::from_toml(text, p)?.resolve("t", p, "")
    }

    #[test]
    fn uniform_samples_lie_in_range_and_match_the_mean() {
        let d = spec("unit = \"deg\"\nkind = \"uniform\"\nmin = -20\nmax = 20").unwrap();
        let mut rng = rng_for(1, 0, Purpose::Layout);
        let xs: Vec<f64> = (0..20000).map(|_| d.sample(&mut rng)).collect();
        assert!(xs.iter().all(|x| (-20.0..20.0).contains(x)));
        let m = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!(m.abs() < 0.3, "{m}");
    }

    #[test]
    fn truncated_normal_respects_bounds_mean_and_cdf() {
        for (mean, std, min, max) in [(0.2, 0.03, 0.15, 0.25), (0.0, 1.0, 2.0, 4.0), (0.0, 1.0, -4.0, -2.5)] {
            let d = Distribution {
                name: "t".into(),
                source: PathBuf::new(),
                unit: Unit::M,
                law: Law::TruncatedNormal { mean, std, min, max },
            };
            let mut rng = rng_for(3, 0, Purpose::Layout);
            let n = 40000;
            let xs: Vec<f64> = (0..n).map(|_| d.sample(&mut rng)).collect();
            assert!(xs.iter().all(|x| (min..=max).contains(x)));
            let m = xs.iter().sum::<f64>() / n as f64;
            assert!((m - d.mean()).abs() < 0.02 * (max - min), "{m} vs {}", d.mean());
            let q = d.quantile(0.3);
            assert!((d.cdf(q) - 0.3).abs() < 1e-9);
        }
    }

    #[test]
    fn lognormal_has_the_stated_mean_and_cv() {
        let d = spec("unit = \"m\"\nkind = \"lognormal\"\nmean = 0.5\ncv = 0.2").unwrap();
        let mut rng = rng_for(5, 0, Purpose::Layout);
        let n = 50000;
        let xs: Vec<f64> = (0..n).map(|_| d.sample(&mut rng)).collect();
        let m = xs.iter().sum::<f64>() / n as f64;
        let s = (xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n as f64).sqrt();
        assert!((m - 0.5).abs() < 0.005, "{m}");
        assert!((s / m - 0.2).abs() < 0.005, "{}", s / m);
        assert!((d.cdf(d.quantile(0.9)) - 0.9).abs() < 1e-9);
    }

    #[test]
    fn wrong_keys_are_named() {
        let e = spec("unit = \"deg\"\nkind = \"uniform\"\nmin = -20\nmax = 20\nstd = 3").unwrap_err().to_string();
        assert!(e.contains("test.toml") && e.contains("std"), "{e}");
        let e = spec("unit = \"deg\"\nkind = \"uniform\"\nmin = -20").unwrap_err().to_string();
        assert!(e.contains("max") && e.contains("missing"), "{e}");
        let e = spec("unit = \"deg\"\nkind = \"uniform\"\nmin = -20\nmax = 20\nmaxx = 3").unwrap_err().to_string();
        assert!(e.contains("maxx"), "{e}");
        let e = spec("unit = \"deg\"\nkind = \"uniform\"\nmin = 20\nmax = -20").unwrap_err().to_string();
        assert!(e.contains("max"), "{e}");
        let e = spec("unit = \"furlong\"\nkind = \"fixed\"\nvalue = 1").unwrap_err().to_string();
        assert!(e.contains("furlong"), "{e}");
    }
}
