//! A surveyed group's `[groups.import]` table: the options of `drystone import` and the
//! survey's uncertainty (read by [`super::survey`]).

use crate::generator::spec::Batter;
use crate::layout::BaseSliding;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A surveyed group's `[groups.import]` table: the options of `drystone import` by their
/// flag names (`--thickness-m` is `thickness_m`), and the survey's uncertainty. Paths are
/// relative to the study file.
///
/// ```toml
/// [[groups]]
/// name = "gable"
/// survey = "surveys/gable.svg"
/// [groups.import]
/// scale_m_per_unit = 0.001      # SVG without a scale line; DXF without $INSUNITS
/// thickness_m = 0.5             # required
/// top_thickness_m = 0.4         # default: thickness_m
/// batter = "symmetric"          # or vertical_negative_y, vertical_positive_y
/// hull_nonconvex = false
/// materials = "granite.toml"    # or density, kn, ks, friction_deg (cohesion_pa)
/// base = "free"                 # or held
/// tolerance_m = 0.005           # the tracing tolerance, m (default 0)
/// depth_m = { kind = "uniform", min = 0.25, max = 0.5 }   # or a number; default: through stones
/// ```
///
/// A group of scanned stones (`survey` a folder, `.obj` or `.stl`) takes `unit`, `y_up`,
/// `max_hull_vertices` and `full_hull` instead of the keys of a traced elevation (`scale_m_per_unit`, `thickness_m`,
/// `top_thickness_m`, `hull_nonconvex`, `tolerance_m`, `depth_m`, which it refuses): its
/// realizations are the survey as scanned.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurveyImportSpec {
    /// Metres per drawing unit (`--scale-m-per-unit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale_m_per_unit: Option<f64>,
    /// The wall's thickness at its base, m (`--thickness-m`; required).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness_m: Option<f64>,
    /// The wall's thickness at its top, m (`--top-thickness-m`; default `thickness_m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top_thickness_m: Option<f64>,
    /// Which faces lean (`--batter`; default symmetric).
    #[serde(default)]
    pub batter: Batter,
    /// Take a non-convex outline's convex hull (`--hull-nonconvex`; default false).
    #[serde(default)]
    pub hull_nonconvex: bool,
    /// A materials file (`--materials`), relative to the study file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub materials: Option<PathBuf>,
    /// Without `materials`: stone density, kg/m³ (`--density`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Joint normal stiffness, Pa/m (`--kn`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn: Option<f64>,
    /// Joint shear stiffness, Pa/m (`--ks`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ks: Option<f64>,
    /// Joint friction angle, degrees (`--friction-deg`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_deg: Option<f64>,
    /// Joint cohesion, Pa (`--cohesion-pa`; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion_pa: Option<f64>,
    /// The base course on the table (`--base`; default free).
    #[serde(default)]
    pub base: BaseSliding,
    /// The tracing tolerance, m (`--tolerance-m`; default 0).
    #[serde(default)]
    pub tolerance_m: f64,
    /// Each stone's depth from the traced face, m: a number or an inline distribution
    /// (`--depth-m`; default through stones).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_m: Option<toml::Value>,
    /// Scanned stones: the unit of the meshes' coordinates, `m`, `cm` or `mm` (`--unit`;
    /// default `m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// Scanned stones: the meshes are y-up (`--y-up`; default false: z up).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub y_up: bool,
    /// Scanned stones: the most vertices a stone's hull keeps, at least 4
    /// (`--max-hull-vertices`; default [`crate::survey::DEFAULT_MAX_HULL_VERTICES`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_hull_vertices: Option<usize>,
    /// Scanned stones: keep every stone's full hull (`--full-hull`; default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub full_hull: bool,
}
