//! A study group that names a survey instead of a wall description (`survey = "wall.svg"`
//! with its `[groups.import]` table): its realizations are the ensemble around the survey
//! ([`crate::survey::ensemble`]), run through the study's protocol as a generated wall's
//! are. A group of scanned stones (a folder, `.obj`, `.stl`) has no uncertainty drawn
//! around it: its realizations are the survey as scanned, the joints' properties as the
//! study states them (its materials, and its effects that do not reshape blocks).

use super::error::Invalid;
use super::spec::GroupSpec;
use super::sweep::{wall_label, SweepPoint};
use super::StudyError;
use crate::generator::Wall;
use crate::layout::MaterialSpec;
use crate::survey::ensemble::{surveyed_wall_with, Uncertainty};
use crate::survey::{ImportOptions, LengthUnit, Section, SurveyMaterials};
use std::path::Path;

/// The wall of a group naming the survey `survey` (the same at every sweep point: a sweep
/// over wall keys, or overrides, are refused naming the key).
pub(super) fn surveyed_wall(
    g: &GroupSpec,
    survey: &Path,
    dir: &Path,
    points: &[SweepPoint],
    invalid: &Invalid,
) -> Result<Wall, StudyError> {
    if let Some(k) = g.overrides.keys().next() {
        return Err(invalid.at(
            &format!("groups[{}].overrides.{k}", g.name),
            "a surveyed group's wall is its survey: it takes no wall overrides (state its materials in \
             [groups.import], its joints' properties as effects)"
                .into(),
        ));
    }
    if let Some((k, _)) =
        points.iter().find(|p| !wall_label(p).is_empty()).and_then(|p| p.iter().find(|(k, _)| !k.acts_on_protocol()))
    {
        return Err(invalid.at(
            &format!("sweep.{k}"),
            format!("sweeps a wall description's key; group {} is a survey, which has none", g.name),
        ));
    }
    let spec = g.import.clone().unwrap_or_default();
    wall_of_survey(&g.name, &spec, survey, dir, invalid.0).map_err(|(key, reason)| invalid.at(&key, reason))
}

/// The wall of the group `name` naming the survey `survey` (relative to the study file's
/// folder `dir`) with the import table `spec`, for the study file `file`: its layout as
/// `drystone import` makes it and the ensemble around it ([`surveyed_wall_with`]). The
/// core study's groups and the in-plane study's read their surveys through it.
///
/// # Errors
/// The key (`groups[NAME].import.KEY` or `groups[NAME].survey`) and the reason: a missing
/// thickness or material, a bad depth distribution, a survey that cannot be imported.
pub(super) fn wall_of_survey(
    name: &str,
    spec: &super::survey_spec::SurveyImportSpec,
    survey: &Path,
    dir: &Path,
    file: &Path,
) -> Result<Wall, (String, String)> {
    let key = |k: &str| format!("groups[{name}].import.{k}");
    let path = dir.join(survey);
    let format = if path.is_dir() {
        Some(crate::survey::SurveyFormat::Obj)
    } else {
        crate::survey::SurveyFormat::from_path(&path)
    };
    let Some(format) = format else {
        return Err((
            format!("groups[{name}].survey"),
            format!(
                "{}: unknown survey format: a traced elevation (.svg, .geojson, .dxf) or scanned stones (a folder, \
                 .obj, .stl)",
                path.display()
            ),
        ));
    };
    let scanned = !format.is_elevation();
    // The keys of the other kind of survey.
    let refused: &[(&str, bool)] = if scanned {
        &[
            ("scale_m_per_unit", spec.scale_m_per_unit.is_some()),
            ("thickness_m", spec.thickness_m.is_some()),
            ("top_thickness_m", spec.top_thickness_m.is_some()),
            ("hull_nonconvex", spec.hull_nonconvex),
            ("tolerance_m", spec.tolerance_m != 0.0),
            ("depth_m", spec.depth_m.is_some()),
        ]
    } else {
        &[
            ("unit", spec.unit.is_some()),
            ("y_up", spec.y_up),
            ("max_hull_vertices", spec.max_hull_vertices.is_some()),
            ("full_hull", spec.full_hull),
        ]
    };
    if let Some((k, _)) = refused.iter().find(|(_, given)| *given) {
        let reason = if scanned {
            "is for a traced elevation; scanned stones have their own shape, and no uncertainty is drawn around \
             them: their realizations are the survey as scanned"
        } else if matches!(*k, "unit" | "y_up") {
            "is for scanned stones; a traced elevation's unit is scale_m_per_unit"
        } else {
            "is for scanned stones; a traced stone's block is its outline"
        };
        return Err((key(k), reason.into()));
    }
    if let Some(n) = spec.max_hull_vertices {
        if n < 4 {
            return Err((key("max_hull_vertices"), format!("{n}: must be at least 4 (a tetrahedron)")));
        }
        if spec.full_hull {
            return Err((key("max_hull_vertices"), "and full_hull exclude each other".into()));
        }
    }
    if spec.materials.is_some() {
        let flags = [
            ("density", spec.density.is_some()),
            ("kn", spec.kn.is_some()),
            ("ks", spec.ks.is_some()),
            ("friction_deg", spec.friction_deg.is_some()),
            ("cohesion_pa", spec.cohesion_pa.is_some()),
        ];
        if let Some((k, _)) = flags.iter().find(|(_, given)| *given) {
            return Err((
                key(k),
                "is given beside materials = FILE: the stones' material is the file's, or the one these keys \
                 make (density, kn, ks, friction_deg and cohesion_pa), not both"
                    .into(),
            ));
        }
    }
    let section = if scanned {
        None
    } else {
        let Some(base) = spec.thickness_m else {
            return Err((key("thickness_m"), "a traced survey needs the wall's thickness, m".into()));
        };
        Some(Section { base_m: base, top_m: spec.top_thickness_m.unwrap_or(base), batter: spec.batter })
    };
    let unit = spec.unit.as_deref().map(str::parse::<LengthUnit>).transpose().map_err(|e| (key("unit"), e))?;
    let materials = materials_of(spec, dir, &key)?;
    let depth = match &spec.depth_m {
        None => None,
        Some(v) => Some(Uncertainty::depth_from_toml(v, file, &key("depth_m")).map_err(|e| (key("depth_m"), e))?),
    };
    let options = ImportOptions {
        format: None,
        scale_m_per_unit: spec.scale_m_per_unit,
        section,
        hull_nonconvex: spec.hull_nonconvex,
        unit,
        y_up: spec.y_up,
        materials,
        base_sliding: spec.base,
        name: Some(name.to_string()),
        max_hull_vertices: spec.max_hull_vertices,
        full_hull: spec.full_hull,
    };
    let u = Uncertainty { tolerance_m: spec.tolerance_m, depth };
    let named = |k: &str| match k {
        "thickness_m" | "top_thickness_m" | "scale_m_per_unit" | "tolerance_m" | "depth_m" | "unit" => key(k),
        other => other.to_string(),
    };
    surveyed_wall_with(&path, &options, &u, &named).map_err(|e| (format!("groups[{name}].survey"), e.to_string()))
}

/// The stones' materials of a surveyed group's import: the file `materials` names (read
/// beside the study, `dir`), or the one material its `density`, `kn`, `ks`, `friction_deg`
/// and `cohesion_pa` keys make.
///
/// # Errors
/// `(key, message)`: the materials file unreadable, or neither it nor every key of the one
/// material given (`key` makes the group's key of a name).
fn materials_of(
    spec: &super::survey_spec::SurveyImportSpec,
    dir: &Path,
    key: &dyn Fn(&str) -> String,
) -> Result<SurveyMaterials, (String, String)> {
    match &spec.materials {
        Some(p) => SurveyMaterials::from_file(&dir.join(p)).map_err(|e| (key("materials"), e.to_string())),
        None => match (spec.density, spec.kn, spec.ks, spec.friction_deg) {
            (Some(density), Some(kn), Some(ks), Some(friction_deg)) => Ok(SurveyMaterials::one(MaterialSpec {
                name: "stone".into(),
                density_kg_per_m3: density,
                kn_pa_per_m: kn,
                ks_pa_per_m: ks,
                friction_deg,
                cohesion_pa: spec.cohesion_pa.unwrap_or(0.0),
                tensile_strength_pa: 0.0,
                closure: Default::default(),
            })),
            _ => Err((
                key("materials"),
                "the stones' material: give materials = FILE, or all of density, kn, ks and friction_deg".into(),
            )),
        },
    }
}
