//! The observations of measured files: the collapse angles, the displacements and the
//! mechanisms of the study's measured groups, each value checked and each fault named.

use super::{MeasurementSigma, Observable, Observation};
use crate::io::table::{MeasuredCollapse, MeasuredDisplacement, MeasuredMechanism};

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

/// The observations of observed failure mechanisms for the study's measured group names
/// `groups` (measured group name → study group name), in file order, per specimen: the
/// failure height (value the middle of its reading interval, the interval's width in the
/// observable, σ `sigma.failure_height`), the kind, the start (value 1: seen), each where
/// given. The extent is not an observation.
///
/// # Errors
/// [`ObservationError::UnknownGroup`] or [`ObservationError::Invalid`] (a σ not > 0).
pub fn mechanism_observations(
    mechanism: &[MeasuredMechanism],
    groups: &[(String, String)],
    sigma: MeasurementSigma,
) -> Result<Vec<Observation>, ObservationError> {
    if !(sigma.failure_height.is_finite() && sigma.failure_height > 0.0) {
        return Err(ObservationError::Invalid {
            specimen: "-".into(),
            what: "sigma failure_height".into(),
            value: sigma.failure_height,
        });
    }
    let mut out = Vec::new();
    for m in mechanism {
        let group = groups.iter().find(|(g, _)| g == &m.group).map(|(_, g)| g.clone()).ok_or_else(|| {
            ObservationError::UnknownGroup {
                group: m.group.clone(),
                specimen: m.specimen.clone(),
                groups: groups.iter().map(|(g, _)| g.as_str()).collect::<Vec<_>>().join(", "),
            }
        })?;
        let one = |observable: Observable, value: f64, sigma: f64| Observation {
            specimen: m.specimen.clone(),
            group: group.clone(),
            observable,
            value,
            sigma,
        };
        if let Some((_, lo, hi)) = m.failure_height {
            out.push(one(Observable::FailureHeight { width: hi - lo }, 0.5 * (lo + hi), sigma.failure_height));
        }
        if let Some(kind) = m.kind {
            out.push(one(Observable::MechanismKind { kind }, 1.0, 1.0));
        }
        if let Some(start) = m.start {
            out.push(one(Observable::MechanismStart { start }, 1.0, 1.0));
        }
    }
    Ok(out)
}
