//! Files at the edges of the pipeline. Generated walls: VTK for ParaView ([`vtk`]) and SVG
//! drawings (`svg`).
//!
//! # Writing files
//!
//! Result files are replaced whole ([`replace_file`], [`replace_file_with`], re-exported
//! from [`crate::files`], which describes how).

mod error;
pub mod inplane;
pub mod measured;
pub mod mechanism;
pub(crate) mod plot;
pub mod series;
pub(crate) mod svg;
pub mod table;
pub mod vtk;

use crate::generator::{GeneratedWall, GeneratorError, PieceKind, Wall};

pub use crate::files::{replace_file, replace_file_with, sync_dir, temporary_name, FileError};
pub use plot::PlotError;

/// Output formats of `drystone generate`, chosen by the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.json`: the layout file that `drystone tilt` reads.
    Json,
    /// `.vtk`: legacy VTK polydata for ParaView ([`render`]).
    Vtk,
    /// `.svg`: front elevation and cross-section ([`render`]).
    Svg,
}

impl OutputFormat {
    /// The format of a file name by its extension (case-insensitive), if known.
    pub fn from_path(path: &std::path::Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "json" => Some(OutputFormat::Json),
            "vtk" => Some(OutputFormat::Vtk),
            "svg" => Some(OutputFormat::Svg),
            _ => None,
        }
    }
}

/// A generated wall as the contents of a file in `format`: the layout JSON (the format
/// `drystone tilt` reads), VTK polydata with the course, wedge and restraint of every block,
/// or an SVG drawing (front elevation and cross-section; `wall` gives the batter).
///
/// # Errors
/// [`GeneratorError::Layout`] if the layout does not resolve (VTK needs the block faces).
pub fn render(g: &GeneratedWall, wall: &Wall, format: OutputFormat) -> Result<String, GeneratorError> {
    Ok(match format {
        OutputFormat::Json => g.layout.to_json(),
        OutputFormat::Vtk => {
            let layout = g.check()?;
            let fields = [
                ("course", g.pieces.iter().map(|p| p.course as i64).collect()),
                ("wedge", g.pieces.iter().map(|p| i64::from(p.kind == PieceKind::Wedge)).collect()),
                ("restrained", g.pieces.iter().map(|p| i64::from(p.restrained)).collect()),
            ];
            vtk::layout_to_vtk(&layout, &fields)
        }
        OutputFormat::Svg => svg::wall_to_svg(g, |z| wall.faces_at(z), &wall.name),
    })
}
