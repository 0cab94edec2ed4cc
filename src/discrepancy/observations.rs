//! Observations: the measured data as one long table (specimen, group, observable, tilt,
//! value, measurement σ).
//!
//! The study's `[measured]` files are the input: collapse angles (the paper's Table 2,
//! degrees) and top displacements at given tilts (Table 3, cm). Measurement σ defaults
//! come from the paper: the tilt was read to 0.5° and the displacement instrument had a
//! precision of 5 mm (Santa-Cruz et al. 2021, Section 2); both are taken as one standard
//! deviation. A study may override them (`[discrepancy]`).

use crate::io::table::{MeasuredCollapse, MeasuredDisplacement};
use serde::Serialize;
use std::fmt;

pub use crate::ensemble::row::Measure;

/// What is observed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Observable {
    /// The collapse angle α_max, degrees.
    CollapseAngle,
    /// A top displacement measure at a tilt, cm.
    Displacement {
        /// The measure.
        measure: Measure,
        /// The tilt, degrees.
        tilt_deg: f64,
    },
}

impl Observable {
    /// Short label: `alpha_max`, `disp@5`.
    pub fn label(&self) -> String {
        match self {
            Observable::CollapseAngle => "alpha_max".into(),
            Observable::Displacement { tilt_deg, .. } => format!("disp@{tilt_deg}"),
        }
    }

    /// Unit of its values.
    pub fn unit(&self) -> &'static str {
        match self {
            Observable::CollapseAngle => "deg",
            Observable::Displacement { .. } => "cm",
        }
    }

    /// The same observable (same kind, measure and tilt).
    pub fn same(&self, other: &Observable) -> bool {
        match (self, other) {
            (Observable::CollapseAngle, Observable::CollapseAngle) => true,
            (
                Observable::Displacement { measure: a, tilt_deg: t },
                Observable::Displacement { measure: b, tilt_deg: u },
            ) => a == b && (t - u).abs() < 1e-9,
            _ => false,
        }
    }
}

impl fmt::Display for Observable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label())
    }
}

/// One measured value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Observation {
    /// Specimen, e.g. `SBL2`.
    pub specimen: String,
    /// Group of the study it belongs to, e.g. `SBL`.
    pub group: String,
    /// What was measured.
    pub observable: Observable,
    /// The value, in the observable's unit (degrees or cm).
    pub value: f64,
    /// Measurement standard deviation, same unit.
    pub sigma: f64,
}

/// Measurement standard deviations.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MeasurementSigma {
    /// Collapse angle, degrees \[0.5\] (angles read to 0.5°).
    pub angle_deg: f64,
    /// Displacement, cm \[0.5\] (instrument precision 5 mm).
    pub displacement_cm: f64,
}

impl Default for MeasurementSigma {
    fn default() -> Self {
        MeasurementSigma { angle_deg: 0.5, displacement_cm: 0.5 }
    }
}

/// Why the measured data cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ObservationError {
    /// No observation at all.
    #[error("the measured data hold no observation (files {files}): nothing to compare with")]
    Empty {
        /// The files.
        files: String,
    },
    /// A measured group that is not a group of the study.
    #[error(
        "measured data for group `{group}` (specimen {specimen}), which the study does not have (groups: {groups})"
    )]
    UnknownGroup {
        /// The group.
        group: String,
        /// The specimen.
        specimen: String,
        /// The study's measured groups.
        groups: String,
    },
    /// A displacement measure not known.
    #[error("specimen {specimen}: unknown displacement measure `{measure}` (known: mean_of_left_center_right, center_minus_mean_of_ends)")]
    UnknownMeasure {
        /// The specimen.
        specimen: String,
        /// The measure.
        measure: String,
    },
    /// A group with a single specimen: no specimen is left to score a fit held out.
    #[error("{file}: line {line}, column specimen: group {group} has a single specimen ({specimen}); a held-out score needs at least two specimens per group")]
    OneSpecimen {
        /// The file of the specimen's first row.
        file: String,
        /// Its line.
        line: usize,
        /// The measured group.
        group: String,
        /// The specimen.
        specimen: String,
    },
    /// A value that is not finite, or a σ not positive.
    #[error("specimen {specimen}: {what} = {value} is not a finite number (or not > 0)")]
    Invalid {
        /// The specimen.
        specimen: String,
        /// What.
        what: String,
        /// The value.
        value: f64,
    },
}

/// The observations of the measured data, for the study's measured group names `groups`
/// (measured group name → study group name), in file order: collapse angles, then
/// displacements.
///
/// # Errors
/// [`ObservationError`] naming the specimen, group or measure at fault.
pub fn observations(
    collapse: &[MeasuredCollapse],
    displacement: &[MeasuredDisplacement],
    groups: &[(String, String)],
    sigma: MeasurementSigma,
    files: &str,
) -> Result<Vec<Observation>, ObservationError> {
    for (what, v) in [("sigma angle_deg", sigma.angle_deg), ("sigma displacement_cm", sigma.displacement_cm)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(ObservationError::Invalid { specimen: "-".into(), what: what.into(), value: v });
        }
    }
    let group_of = |measured: &str, specimen: &str| {
        groups.iter().find(|(m, _)| m == measured).map(|(_, g)| g.clone()).ok_or_else(|| {
            ObservationError::UnknownGroup {
                group: measured.to_string(),
                specimen: specimen.to_string(),
                groups: groups.iter().map(|(m, _)| m.as_str()).collect::<Vec<_>>().join(", "),
            }
        })
    };
    let finite = |specimen: &str, what: &str, v: f64| {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(ObservationError::Invalid { specimen: specimen.into(), what: what.into(), value: v })
        }
    };
    let mut out = Vec::new();
    for c in collapse {
        out.push(Observation {
            specimen: c.specimen.clone(),
            group: group_of(&c.group, &c.specimen)?,
            observable: Observable::CollapseAngle,
            value: finite(&c.specimen, "collapse_angle_deg", c.collapse_angle_deg)?,
            sigma: sigma.angle_deg,
        });
    }
    for d in displacement {
        let measure = d.measure;
        out.push(Observation {
            specimen: d.specimen.clone(),
            group: group_of(&d.group, &d.specimen)?,
            observable: Observable::Displacement { measure, tilt_deg: finite(&d.specimen, "tilt_deg", d.tilt_deg)? },
            value: finite(&d.specimen, "displacement_cm", d.displacement_cm)?,
            sigma: sigma.displacement_cm,
        });
    }
    if out.is_empty() {
        return Err(ObservationError::Empty { files: files.to_string() });
    }
    let rows = collapse
        .iter()
        .map(|c| (&c.specimen, &c.group, &c.file, c.line))
        .chain(displacement.iter().map(|d| (&d.specimen, &d.group, &d.file, d.line)));
    let mut per_group: std::collections::BTreeMap<&String, Vec<(&String, &std::path::PathBuf, usize)>> =
        Default::default();
    for (specimen, group, file, line) in rows {
        let v = per_group.entry(group).or_default();
        if !v.iter().any(|(s, _, _)| *s == specimen) {
            v.push((specimen, file, line));
        }
    }
    if let Some((group, v)) = per_group.into_iter().find(|(_, v)| v.len() == 1) {
        let (specimen, file, line) = v[0];
        return Err(ObservationError::OneSpecimen {
            file: file.display().to_string(),
            line,
            group: group.clone(),
            specimen: specimen.clone(),
        });
    }
    Ok(out)
}

/// The specimens of the observations, in first-seen order.
pub fn specimens(obs: &[Observation]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for o in obs {
        if !out.contains(&o.specimen) {
            out.push(o.specimen.clone());
        }
    }
    out
}
