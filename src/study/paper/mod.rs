//! The source paper's parametric studies (Santa-Cruz et al. 2021, §4 and §6), each set
//! beside the paper's numbers in the report of the study that reproduces it, one file per
//! table or figure:
//!
//! | [`PaperStudy`] | paper | file | what is compared |
//! | --- | --- | --- | --- |
//! | `joint_arrangement` | §4.1, Figure 10 | [`figure10`] | top displacement under the static trapezoidal load vs Kn for continuous, discontinuous and irregular joints: continuous ≈ 40 % below discontinuous, irregular mean ≈ 25 % below, irregular COV 21–25 % |
//! | `length_height` | §4.2, Figure 11 | [`figure11`] | drift vs L/H with and without end restraint: above L/H ≈ 4 the restraint stops mattering |
//! | `kn_phi` | §6, Tables 7 and 8 | [`table7`], [`table8`] | collapse angle of the free and the restrained 1:4 walls vs Kn and φ (Table 7); capacity ratio sin α_max restrained / free (Table 8: mean 1.38, min 1.14, max 1.70; tests 1.35) |
//!
//! The paper's Figures 10 and 11 are not tabulated in the paper (only their findings are
//! stated in the text), so those findings are what is checked; Table 7 is compared number by
//! number. Nothing is tuned to match: where drystone disagrees the report says so.

pub mod figure10;
pub mod figure11;
pub mod table7;
pub mod table8;

use super::summary::CellSummary;
use super::{ProtocolKind, Study, SweepKey};
use crate::generator::spec::{Arrangement, Ends};
use crate::io::plot::{BandSeries, PlotError};
use crate::io::table::TableError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Which of the paper's studies a study file reproduces (`paper = "…"` in the study file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PaperStudy {
    /// Figure 10: joint arrangement under the static lateral load, swept over Kn.
    JointArrangement,
    /// Figure 11: drift against L/H, restrained and free ends.
    LengthHeight,
    /// Tables 7 and 8: collapse angle against Kn and φ, free and restrained ends.
    KnPhi,
}

/// Errors of writing a paper study's table or figure.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PaperError {
    /// Writing its CSV.
    #[error(transparent)]
    Table(#[from] TableError),
    /// Writing its plot.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Checks that a study has what its paper comparison needs.
///
/// # Errors
/// A message naming what is missing.
pub fn check(p: PaperStudy, study: &Study) -> Result<(), String> {
    let has = |key: SweepKey| study.points[0].iter().any(|(k, _)| *k == key);
    let ends: Vec<bool> = study.groups.iter().map(|g| restrained(&g.walls[0].ends)).collect();
    match p {
        PaperStudy::JointArrangement => {
            if study.protocol != ProtocolKind::Lateral {
                return Err("joint_arrangement needs protocol = \"lateral\"".into());
            }
            if !has(SweepKey::KnPaPerM) {
                return Err("joint_arrangement needs a sweep over kn_pa_per_m".into());
            }
        }
        PaperStudy::LengthHeight => {
            if study.protocol != ProtocolKind::Lateral {
                return Err("length_height needs protocol = \"lateral\"".into());
            }
            if !has(SweepKey::LengthM) {
                return Err("length_height needs a sweep over length_m".into());
            }
            if !ends.iter().any(|&r| r) || ends.iter().all(|&r| r) {
                return Err("length_height needs groups with restrained and with free ends".into());
            }
        }
        PaperStudy::KnPhi => {
            if study.protocol != ProtocolKind::Tilt {
                return Err("kn_phi needs protocol = \"tilt\"".into());
            }
            if !has(SweepKey::KnPaPerM) || !has(SweepKey::FrictionDeg) {
                return Err("kn_phi needs a sweep over kn_pa_per_m and friction_deg".into());
            }
            if ends.iter().filter(|&&r| !r).count() != 1 || ends.iter().filter(|&&r| r).count() != 1 {
                return Err("kn_phi needs exactly one group with free ends and one with restrained ends".into());
            }
        }
    }
    Ok(())
}

/// The report section of a paper study (markdown), writing its CSV and SVG into `dir`.
///
/// # Errors
/// [`PaperError`] naming the file.
pub fn section(p: PaperStudy, study: &Study, cells: &[CellSummary], dir: &Path) -> Result<String, PaperError> {
    match p {
        PaperStudy::JointArrangement => figure10::section(study, cells, dir),
        PaperStudy::LengthHeight => figure11::section(study, cells, dir),
        PaperStudy::KnPhi => {
            let t7 = table7::Table7::collect(study, cells);
            let mut md = t7.section(study, cells);
            md.push_str(&table8::section(&t7));
            md.push_str(&t7.figure(dir)?);
            Ok(md)
        }
    }
}

/// The arrangement's name in the study files.
fn arrangement_name(a: &Arrangement) -> &'static str {
    match a {
        Arrangement::Continuous => "continuous",
        Arrangement::Discontinuous { .. } => "discontinuous",
        Arrangement::Irregular(_) => "irregular",
    }
}

/// Whether a wall's ends are held.
fn restrained(e: &Ends) -> bool {
    !matches!(e, Ends::Free)
}

/// A curve without a band (`lo` = `mid` = `hi`).
fn curve(label: String, x: Vec<f64>, y: Vec<f64>) -> BandSeries {
    BandSeries { label, x, mid: y.clone(), lo: y.clone(), hi: y, measured: vec![], points_label: None }
}
