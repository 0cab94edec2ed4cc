//! Sweep keys: the parameters a study varies (in `[sweep]`) or fixes per group (in
//! `overrides`), each acting on a wall description through [`SweepKey::apply`]; and the
//! two keys of a shaking study, `motion` and `pga_g`, which act on the protocol instead
//! (set from the study's `[shake]` table, never written in `[sweep]`): each motion at each
//! PGA level is a sweep point, so that work items, journal, shards and merge treat the
//! incremental dynamic analysis as any sweep.

use crate::generator::spec::{ArrangementKind, EndKind, EndsSpec, WallSpec};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use thiserror::Error;

/// End zone given to a wall made `rigid` by the `ends` key when it has none, m: the
/// paper's SBR ropes sat 0.05 m from each end (Santa-Cruz et al. 2021).
pub const DEFAULT_END_ZONE_M: f64 = 0.05;

/// A key of `[sweep]` or of a group's `overrides`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepKey {
    /// `kn_pa_per_m`: Kn of every material, Pa/m (> 0); Ks follows at the material's own
    /// Ks/Kn.
    KnPaPerM,
    /// `ks_over_kn`: Ks = ratio × Kn for every material (> 0).
    KsOverKn,
    /// `friction_deg`: φ of every material, degrees.
    FrictionDeg,
    /// `cohesion_pa`: cohesion of every material, Pa.
    CohesionPa,
    /// `length_m`: the wall length L, m.
    LengthM,
    /// `arrangement`: `continuous`, `discontinuous` or `irregular`.
    Arrangement,
    /// `ends`: `free`, or `rigid` (every block within the wall's end zone, or
    /// [`DEFAULT_END_ZONE_M`] if it has none, held in y).
    Ends,
    /// `motion`: the name of a ground motion of the study's `[shake]` table (acts on the
    /// protocol; set by `[shake]`).
    Motion,
    /// `pga_g`: the PGA the motion is scaled to, g (acts on the protocol; set by
    /// `[shake] pga_g`).
    PgaG,
}

impl SweepKey {
    /// Every key, in the order the error messages list them.
    pub const ALL: [SweepKey; 9] = [
        SweepKey::KnPaPerM,
        SweepKey::KsOverKn,
        SweepKey::FrictionDeg,
        SweepKey::CohesionPa,
        SweepKey::LengthM,
        SweepKey::Arrangement,
        SweepKey::Ends,
        SweepKey::Motion,
        SweepKey::PgaG,
    ];

    /// The key as written in a study file.
    pub fn as_str(self) -> &'static str {
        match self {
            SweepKey::KnPaPerM => "kn_pa_per_m",
            SweepKey::KsOverKn => "ks_over_kn",
            SweepKey::FrictionDeg => "friction_deg",
            SweepKey::CohesionPa => "cohesion_pa",
            SweepKey::LengthM => "length_m",
            SweepKey::Arrangement => "arrangement",
            SweepKey::Ends => "ends",
            SweepKey::Motion => "motion",
            SweepKey::PgaG => "pga_g",
        }
    }

    /// Whether the key acts on the loading protocol (`motion`, `pga_g`) rather than on the
    /// wall: the study's `[shake]` table sets it, and the wall is the same at every value.
    pub fn acts_on_protocol(self) -> bool {
        matches!(self, SweepKey::Motion | SweepKey::PgaG)
    }

    /// Parses [`SweepKey::as_str`].
    ///
    /// # Errors
    /// [`SweepError::UnknownKey`], which lists the known keys.
    pub fn parse(text: &str) -> Result<SweepKey, SweepError> {
        SweepKey::ALL.into_iter().find(|k| k.as_str() == text).ok_or_else(|| {
            let known: Vec<&str> = SweepKey::ALL.iter().map(|k| k.as_str()).collect();
            SweepError::UnknownKey { known: known.join(", ") }
        })
    }

    /// Applies the key with `value` to a wall description.
    ///
    /// # Errors
    /// [`SweepError`] saying what the key expects.
    pub fn apply(self, spec: &mut WallSpec, value: &SweepValue) -> Result<(), SweepError> {
        let num = || match value {
            SweepValue::Number(v) if v.is_finite() => Ok(*v),
            other => Err(SweepError::Expected { expected: "a finite number", got: other.to_string() }),
        };
        let positive = || match num()? {
            v if v <= 0.0 => Err(SweepError::NotPositive { got: v }),
            v => Ok(v),
        };
        match self {
            SweepKey::KnPaPerM => {
                let kn = positive()?;
                for m in &mut spec.materials {
                    let ratio = m.ks_pa_per_m / m.kn_pa_per_m;
                    m.kn_pa_per_m = kn;
                    m.ks_pa_per_m = kn * ratio;
                }
            }
            SweepKey::KsOverKn => {
                let r = positive()?;
                for m in &mut spec.materials {
                    m.ks_pa_per_m = m.kn_pa_per_m * r;
                }
            }
            SweepKey::FrictionDeg => {
                let p = num()?;
                spec.materials.iter_mut().for_each(|m| m.friction_deg = p);
            }
            SweepKey::CohesionPa => {
                let c = num()?;
                spec.materials.iter_mut().for_each(|m| m.cohesion_pa = c);
            }
            SweepKey::LengthM => spec.geometry.length_m = num()?,
            SweepKey::Ends => apply_ends(spec, value)?,
            SweepKey::Arrangement => spec.arrangement.kind = arrangement(value)?,
            // The protocol's keys leave the wall as it is (`Study::protocol_at` reads them).
            SweepKey::Motion | SweepKey::PgaG => {}
        }
        Ok(())
    }
}

fn apply_ends(spec: &mut WallSpec, value: &SweepValue) -> Result<(), SweepError> {
    match value {
        SweepValue::Text(s) if s == "free" => spec.restraints.ends = EndsSpec::default(),
        SweepValue::Text(s) if s == "rigid" => {
            let e = &mut spec.restraints.ends;
            e.kind = EndKind::Rigid;
            e.zone_m = Some(e.zone_m.unwrap_or(DEFAULT_END_ZONE_M));
            e.stiffness_n_per_m = None;
        }
        other => return Err(SweepError::Expected { expected: "free or rigid", got: other.to_string() }),
    }
    Ok(())
}

fn arrangement(value: &SweepValue) -> Result<ArrangementKind, SweepError> {
    match value {
        SweepValue::Text(s) if s == "continuous" => Ok(ArrangementKind::Continuous),
        SweepValue::Text(s) if s == "discontinuous" => Ok(ArrangementKind::Discontinuous),
        SweepValue::Text(s) if s == "irregular" => Ok(ArrangementKind::Irregular),
        other => {
            Err(SweepError::Expected { expected: "continuous, discontinuous or irregular", got: other.to_string() })
        }
    }
}

impl std::fmt::Display for SweepKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A sweep value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SweepValue {
    /// A number.
    Number(f64),
    /// Text (e.g. an arrangement).
    Text(String),
}

impl SweepValue {
    /// The value of a TOML number or string; `None` for any other TOML type.
    pub fn from_toml(v: &toml::Value) -> Option<SweepValue> {
        match v {
            toml::Value::Integer(i) => Some(SweepValue::Number(*i as f64)),
            toml::Value::Float(f) => Some(SweepValue::Number(*f)),
            toml::Value::String(s) => Some(SweepValue::Text(s.clone())),
            _ => None,
        }
    }

    /// The number, if this is one.
    pub fn number(&self) -> Option<f64> {
        match self {
            SweepValue::Number(x) => Some(*x),
            SweepValue::Text(_) => None,
        }
    }
}

impl std::fmt::Display for SweepValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SweepValue::Number(v) => write!(f, "{v}"),
            SweepValue::Text(s) => write!(f, "{s}"),
        }
    }
}

/// A point of the sweep: (key, value) in the order of the keys' names.
pub type SweepPoint = Vec<(SweepKey, SweepValue)>;

/// Label of the wall of a point: the label of its keys that act on the wall (points that
/// differ only in `motion` and `pga_g` share their wall).
pub fn wall_label(p: &[(SweepKey, SweepValue)]) -> String {
    p.iter().filter(|(k, _)| !k.acts_on_protocol()).map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(";")
}

/// Label of a point: `key=value;key=value` (empty without a sweep).
pub fn point_label(p: &[(SweepKey, SweepValue)]) -> String {
    p.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(";")
}

/// Why a sweep key or value cannot be used (the key itself is named by the caller: the
/// study file's `sweep.KEY` or `groups[i].overrides.KEY`).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SweepError {
    /// Not a key of [`SweepKey::ALL`].
    #[error("unknown key; known keys: {known}")]
    UnknownKey {
        /// The known keys, comma-separated.
        known: String,
    },
    /// A key without values in `[sweep]`.
    #[error("needs at least one value")]
    NoValues,
    /// A TOML value that is neither a number nor text.
    #[error("{value} is not a number or text")]
    NotNumberOrText {
        /// The value as written.
        value: String,
    },
    /// A value of the wrong kind for its key.
    #[error("expects {expected}, got {got}")]
    Expected {
        /// What the key takes.
        expected: &'static str,
        /// The value given.
        got: String,
    },
    /// A value that must be positive.
    #[error("must be > 0, got {got}")]
    NotPositive {
        /// The value given.
        got: f64,
    },
}

/// A sweep entry that cannot be used: the key as written and what is wrong.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("sweep.{key}: {reason}")]
pub struct SweepEntryError {
    /// The key as written in the file.
    pub key: String,
    /// What is wrong.
    #[source]
    pub reason: SweepError,
}

/// The points of a `[sweep]` table: the cartesian product of its values, keys in the order
/// of their names, the last varying fastest; one empty point without a sweep.
///
/// # Errors
/// The first key that is unknown, has no values, or has a value that is not a number or
/// text. Values are checked against their key by [`SweepKey::apply`].
pub fn grid(sweep: &BTreeMap<String, Vec<toml::Value>>) -> Result<Vec<SweepPoint>, SweepEntryError> {
    let mut points: Vec<SweepPoint> = vec![Vec::new()];
    for (name, values) in sweep {
        let error = |reason: SweepError| SweepEntryError { key: name.clone(), reason };
        if values.is_empty() {
            return Err(error(SweepError::NoValues));
        }
        let key = SweepKey::parse(name).map_err(error)?;
        let values = values
            .iter()
            .map(|v| {
                SweepValue::from_toml(v).ok_or_else(|| error(SweepError::NotNumberOrText { value: v.to_string() }))
            })
            .collect::<Result<Vec<_>, _>>()?;
        points = points
            .iter()
            .flat_map(|p| {
                values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push((key, v.clone()));
                    q
                })
            })
            .collect();
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_parses_from_its_name() {
        for k in SweepKey::ALL {
            assert_eq!(SweepKey::parse(k.as_str()), Ok(k));
            let json = serde_json::to_string(&k).unwrap();
            assert_eq!(json, format!("\"{}\"", k.as_str()));
        }
        let err = SweepKey::parse("youngs_modulus").unwrap_err().to_string();
        assert!(err.starts_with("unknown key; known keys: kn_pa_per_m, ks_over_kn"), "{err}");
    }

    #[test]
    fn grid_is_the_cartesian_product_with_the_last_key_fastest() {
        let mut sweep = BTreeMap::new();
        sweep.insert("length_m".to_string(), vec![toml::Value::Float(1.0), toml::Value::Integer(2)]);
        sweep.insert("friction_deg".to_string(), vec![toml::Value::Integer(30), toml::Value::Integer(40)]);
        let labels: Vec<String> = grid(&sweep).unwrap().iter().map(|p| point_label(p)).collect();
        assert_eq!(
            labels,
            [
                "friction_deg=30;length_m=1",
                "friction_deg=30;length_m=2",
                "friction_deg=40;length_m=1",
                "friction_deg=40;length_m=2"
            ]
        );
        assert_eq!(grid(&BTreeMap::new()).unwrap(), vec![Vec::new()]);
    }
}
