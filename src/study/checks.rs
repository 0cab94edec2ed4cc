//! The checks of a study's names and of what its extensions need, each naming the key at
//! fault: a name usable as a directory, a calibration step's parameter, interval and
//! groups, and the paper comparison's protocol, sweeps and groups. Run by
//! [`super::resolve`] when a study is read, and again by calibration and suites.

use super::error::{CalibrationSpecError, NameError, PaperSpecError};
use super::paper::restrained;
use super::spec::{CalibrateSpec, PaperStudy, ProtocolKind};
use super::sweep::SweepKey;
use super::Study;

/// A study (or suite) name is used as a directory name (the default output `out/<name>`,
/// a suite's `DIR/<name>`): it must be one plain path component, so a name such as
/// `../../x` is refused rather than written outside the output directory.
///
/// # Errors
/// [`NameError`]: what is wrong with it.
pub fn check_name(name: &str) -> Result<(), NameError> {
    let bad = name.chars().find(|c| matches!(c, '/' | '\\') || c.is_control());
    if name.trim().is_empty() {
        Err(NameError::Empty)
    } else if name == "." || name == ".." {
        Err(NameError::Reserved { name: name.into() })
    } else if let Some(character) = bad {
        Err(NameError::Character { name: name.into(), character })
    } else {
        Ok(())
    }
}

/// Checks a calibration step against a study.
///
/// # Errors
/// [`CalibrationSpecError`] naming the bad key.
pub fn check_calibration(c: &CalibrateSpec, study: &Study) -> Result<(), CalibrationSpecError> {
    if !matches!(c.parameter.as_str(), "kn_pa_per_m" | "friction_deg") {
        return Err(CalibrationSpecError::Parameter(c.parameter.clone()));
    }
    if !(c.lower.is_finite() && c.upper.is_finite() && c.lower < c.upper) {
        return Err(CalibrationSpecError::Interval { lower: c.lower, upper: c.upper });
    }
    if c.is_kn() && c.lower <= 0.0 {
        return Err(CalibrationSpecError::KnLower(c.lower));
    }
    if !c.is_kn() && (c.lower <= 0.0 || c.upper >= 90.0) {
        return Err(CalibrationSpecError::FrictionInterval { lower: c.lower, upper: c.upper });
    }
    if c.tolerance.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
        return Err(CalibrationSpecError::Tolerance);
    }
    for g in std::iter::once(&c.group).chain(&c.carry_to) {
        if !study.groups.iter().any(|x| &x.name == g) {
            return Err(CalibrationSpecError::UnknownGroup(g.clone()));
        }
    }
    let mg = &study.groups.iter().find(|x| x.name == c.group).map(|x| x.measured_group.clone()).unwrap_or_default();
    if !study.measured.collapse.iter().any(|m| &m.group == mg) {
        return Err(CalibrationSpecError::NoMeasurement { group: c.group.clone(), measured: mg.clone() });
    }
    Ok(())
}

/// Checks that a study has what its paper comparison needs.
///
/// # Errors
/// [`PaperSpecError`] naming what is missing.
pub fn check_paper(p: PaperStudy, study: &Study) -> Result<(), PaperSpecError> {
    let has = |key: SweepKey| study.points[0].iter().any(|(k, _)| *k == key);
    let ends: Vec<bool> = study.groups.iter().map(|g| restrained(&g.walls[0].ends)).collect();
    // The protocol each comparison is made under, as the paper study states it.
    let (paper, under, need) = match p {
        PaperStudy::JointArrangement => ("joint_arrangement", ProtocolKind::Lateral, "protocol = \"lateral\""),
        PaperStudy::LengthHeight => ("length_height", ProtocolKind::Lateral, "protocol = \"lateral\""),
        PaperStudy::KnPhi => ("kn_phi", ProtocolKind::Tilt, "protocol = \"tilt\""),
    };
    if study.protocol.kind() != under {
        return Err(PaperSpecError { paper, need });
    }
    match p {
        PaperStudy::JointArrangement => {
            if !has(SweepKey::KnPaPerM) {
                return Err(PaperSpecError { paper: "joint_arrangement", need: "a sweep over kn_pa_per_m" });
            }
        }
        PaperStudy::LengthHeight => {
            if !has(SweepKey::LengthM) {
                return Err(PaperSpecError { paper: "length_height", need: "a sweep over length_m" });
            }
            if !ends.iter().any(|&r| r) || ends.iter().all(|&r| r) {
                return Err(PaperSpecError {
                    paper: "length_height",
                    need: "groups with restrained and with free ends",
                });
            }
        }
        PaperStudy::KnPhi => {
            if !has(SweepKey::KnPaPerM) || !has(SweepKey::FrictionDeg) {
                return Err(PaperSpecError { paper: "kn_phi", need: "a sweep over kn_pa_per_m and friction_deg" });
            }
            if ends.iter().filter(|&&r| !r).count() != 1 || ends.iter().filter(|&&r| r).count() != 1 {
                return Err(PaperSpecError {
                    paper: "kn_phi",
                    need: "exactly one group with free ends and one with restrained ends",
                });
            }
        }
    }
    Ok(())
}
