//! The errors of an import ([`SurveyError`]): each names the survey file and, for its
//! contents, the element, feature, object or line at fault.

use super::{MAX_STONE_M, MIN_STONE_M};
use crate::layout::LayoutError;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The errors of an import. Each names the survey file and, for its contents, the
/// element, feature, object or line at fault.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SurveyError {
    /// The file could not be read.
    #[error("cannot read survey {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file as a whole is wrong (not XML or JSON, no stone, no scale, unknown format).
    #[error("{}: {reason}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// One element, feature, object or line of the file is wrong. A file of one mesh is
    /// its own element: its name is not given twice.
    #[error("{}{}: {reason}", path.display(), element_in(path, element))]
    Element {
        /// The file.
        path: PathBuf,
        /// The element (`<path id="s3"> at line 12`), feature (`feature 2 (id "s3")`), or
        /// line (`line 40`).
        element: String,
        /// What is wrong.
        reason: String,
    },
    /// A traced stone whose outline is not convex (without `hull_nonconvex`).
    #[error(
        "{}: stone {stone} ({element}) is not convex: its convex hull adds {added_m2:.4e} m² ({:.2} % of its \
         area {area_m2:.4e} m²; reflex corner at x = {:.4} m, z = {:.4} m); a block is a convex polyhedron: trace \
         the stone as convex pieces, or import with --hull-nonconvex to take its convex hull",
        path.display(), 100.0 * added_m2 / area_m2, corner[0], corner[1]
    )]
    NonConvex {
        /// The file.
        path: PathBuf,
        /// The stone's id.
        stone: String,
        /// Its element or feature.
        element: String,
        /// The outline's area, m².
        area_m2: f64,
        /// The area its convex hull adds, m² (the convexity deficit).
        added_m2: f64,
        /// A reflex corner (x, z) in the table frame, m.
        corner: [f64; 2],
    },
    /// Two stones overlap by more than the layout's tolerance.
    #[error(
        "{}: stones {a} and {b} overlap by {depth_m:.3e} m (tolerance {:e} m)",
        path.display(), crate::layout::OVERLAP_TOLERANCE_M
    )]
    Overlap {
        /// The file.
        path: PathBuf,
        /// The first stone: its id and element, `s3 (<path id="s3"> at line 12)`.
        a: String,
        /// The second stone, as `a`.
        b: String,
        /// The penetration depth, m.
        depth_m: f64,
    },
    /// A stone whose size after the unit conversion is implausible.
    #[error(
        "{}: stone {stone} ({element}) is {extent_m:.4e} m long after conversion ({unit}): a stone between {MIN_STONE_M} \
         and {MAX_STONE_M} m is expected; probable unit mistake",
        path.display()
    )]
    Size {
        /// The file.
        path: PathBuf,
        /// The stone's id.
        stone: String,
        /// Its element.
        element: String,
        /// Its longest extent, m.
        extent_m: f64,
        /// The conversion used (`--unit mm`, `--scale-m-per-unit 0.001`).
        unit: String,
    },
    /// An option out of range or not for this format.
    #[error("{option} = {value}: {reason}")]
    Option {
        /// The option, e.g. `--thickness-m`.
        option: String,
        /// Its value.
        value: String,
        /// What is wrong.
        reason: String,
    },
    /// The layout made from the survey fails the layout checks.
    #[error("{}: the imported layout is invalid: {source}", path.display())]
    Layout {
        /// The survey file.
        path: PathBuf,
        /// The cause.
        source: LayoutError,
    },
}

/// `": element"`, or nothing where the element is the file itself (a file of one mesh).
fn element_in(path: &Path, element: &str) -> String {
    if path.file_name().is_some_and(|f| f.to_string_lossy() == element) {
        String::new()
    } else {
        format!(": {element}")
    }
}
