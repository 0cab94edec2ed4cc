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

pub use super::spec::PaperStudy;

use super::summary::CellSummary;
use super::Study;
use crate::generator::Arrangement;
use crate::generator::Ends;
use crate::io::plot::{BandSeries, PlotError};
use crate::io::table::TableError;
use crate::io::FileError;
use std::path::Path;

/// Whether a wall's ends are held.
pub(crate) fn restrained(e: &Ends) -> bool {
    !matches!(e, Ends::Free)
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
    /// Replacing its plot file.
    #[error(transparent)]
    File(#[from] FileError),
}

/// Plots `series` (x–y curves with bands, [`crate::io::plot::bands`]) into `dir/file`,
/// replacing the file whole.
///
/// # Errors
/// [`PaperError`] naming the file.
fn plot_bands(dir: &Path, file: &str, title: &str, x: &str, y: &str, series: &[BandSeries]) -> Result<(), PaperError> {
    crate::io::replace_file_with(&dir.join(file), |p| -> Result<(), PaperError> {
        Ok(crate::io::plot::bands(p, title, x, y, series)?)
    })
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

/// A curve without a band (`lo` = `mid` = `hi`).
fn curve(label: String, x: Vec<f64>, y: Vec<f64>) -> BandSeries {
    BandSeries {
        label,
        x,
        mid: y.clone(),
        lo: y.clone(),
        hi: y,
        measured: vec![],
        points_label: None,
        specimens: vec![],
    }
}
