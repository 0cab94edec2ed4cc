//! A study group that names a survey instead of a wall description (`survey = "wall.svg"`
//! with its `[groups.import]` table): its realizations are the ensemble around the survey
//! ([`crate::survey::ensemble`]), run through the study's protocol as a generated wall's
//! are.

use super::error::Invalid;
use super::resolve::Group;
use super::spec::GroupSpec;
use super::sweep::{wall_label, SweepPoint};
use super::StudyError;
use crate::generator::spec::Batter;
use crate::layout::{BaseSliding, MaterialSpec};
use crate::survey::ensemble::{surveyed_wall_with, Uncertainty};
use crate::survey::{ImportOptions, Section, SurveyMaterials};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

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
}

/// A group naming the survey `survey`: its wall (the same at every sweep point: a sweep
/// over wall keys, or overrides, are refused naming the key).
pub(super) fn resolve_group(
    g: &GroupSpec,
    survey: &Path,
    dir: &Path,
    points: &[SweepPoint],
    invalid: &Invalid,
) -> Result<Group, StudyError> {
    let key = |k: &str| format!("groups[{}].import.{k}", g.name);
    if let Some(k) = g.overrides.keys().next() {
        return Err(invalid.at(
            &format!("groups[{}].overrides.{k}", g.name),
            "a surveyed group's wall is its survey: it takes no wall overrides (state its materials in \
             [groups.import], its joints' properties as effects)"
                .into(),
        ));
    }
    if let Some((k, _)) = points.iter().find(|p| !wall_label(p).is_empty()).and_then(|p| p.iter().find(|(k, _)| !k.acts_on_protocol())) {
        return Err(invalid.at(
            &format!("sweep.{k}"),
            format!("sweeps a wall description's key; group {} is a survey, which has none", g.name),
        ));
    }
    let spec = g.import.clone().unwrap_or_default();
    let Some(base) = spec.thickness_m else {
        return Err(invalid.at(&key("thickness_m"), "a traced survey needs the wall's thickness, m".into()));
    };
    let materials = match &spec.materials {
        Some(p) => SurveyMaterials::from_file(&dir.join(p)).map_err(|e| invalid.at(&key("materials"), e.to_string()))?,
        None => match (spec.density, spec.kn, spec.ks, spec.friction_deg) {
            (Some(density), Some(kn), Some(ks), Some(friction_deg)) => SurveyMaterials::one(MaterialSpec {
                name: "stone".into(),
                density_kg_per_m3: density,
                kn_pa_per_m: kn,
                ks_pa_per_m: ks,
                friction_deg,
                cohesion_pa: spec.cohesion_pa.unwrap_or(0.0),
                tensile_strength_pa: 0.0,
                closure: Default::default(),
            }),
            _ => {
                return Err(invalid.at(
                    &key("materials"),
                    "the stones' material: give materials = FILE, or all of density, kn, ks and friction_deg".into(),
                ))
            }
        },
    };
    let depth = match &spec.depth_m {
        None => None,
        Some(v) => Some(Uncertainty::depth_from_toml(v, invalid.0, &key("depth_m")).map_err(|e| invalid.at(&key("depth_m"), e))?),
    };
    let options = ImportOptions {
        format: None,
        scale_m_per_unit: spec.scale_m_per_unit,
        section: Some(Section { base_m: base, top_m: spec.top_thickness_m.unwrap_or(base), batter: spec.batter }),
        hull_nonconvex: spec.hull_nonconvex,
        unit: None,
        y_up: false,
        materials,
        base_sliding: spec.base,
        name: Some(g.name.clone()),
    };
    let path = dir.join(survey);
    let u = Uncertainty { tolerance_m: spec.tolerance_m, depth };
    let named = |k: &str| match k {
        "thickness_m" | "top_thickness_m" | "scale_m_per_unit" | "tolerance_m" | "depth_m" => key(k),
        other => other.to_string(),
    };
    let wall = surveyed_wall_with(&path, &options, &u, &named)
        .map_err(|e| invalid.at(&format!("groups[{}].survey", g.name), e.to_string()))?;
    Ok(Group {
        name: g.name.clone(),
        measured_group: g.measured_group.clone().unwrap_or_else(|| g.name.clone()),
        wall_path: path,
        walls: vec![wall; points.len()],
        realizations: g.realizations,
        spec: None,
        effects: vec![],
    })
}
