//! The ensemble around a survey: a traced elevation made a wall the generator draws
//! ([`crate::generator::traced`]), its tracing tolerance and its stones' unknown depths
//! drawn per realization. `drystone import … --seed N --realization R` writes one such
//! realization; a study group naming a `survey` runs its realizations through every
//! protocol. See docs/survey.md, "The ensemble around a survey".

use super::{elevation, import, ImportOptions, SurveyError, SurveyFormat};
use crate::generator::distribution::{Distribution, DistributionSpec, Kind, Unit};
use crate::generator::{TraceSetting, Traced, TracedStone, Wall};
use std::path::Path;

/// The largest tracing tolerance accepted, m: a larger one is a probable unit mistake.
pub const MAX_TOLERANCE_M: f64 = 0.1;

/// The survey's uncertainty, drawn per realization.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Uncertainty {
    /// The tracing tolerance, m (default 0): every traced corner moves by at most this
    /// (docs/survey.md; [`crate::generator::trace_draw`]).
    pub tolerance_m: f64,
    /// Each stone's depth into the wall from the traced (−y) face, m, unit `m`, its support
    /// within (0, the base thickness]; `None` (default): through stones.
    pub depth: Option<Distribution>,
}

impl Uncertainty {
    /// Refuses a tolerance that is negative, not finite or above [`MAX_TOLERANCE_M`], and a
    /// depth law whose unit is not `m` or whose support is not within (0, `thickness_m`].
    /// `key` names an option in the errors (`tolerance_m` → `--tolerance-m` on the command
    /// line, `groups[G].import.tolerance_m` in a study).
    ///
    /// # Errors
    /// [`SurveyError::Option`] naming the option.
    pub fn check(&self, thickness_m: f64, key: &dyn Fn(&str) -> String) -> Result<(), SurveyError> {
        let t = self.tolerance_m;
        if !(t.is_finite() && (0.0..=MAX_TOLERANCE_M).contains(&t)) {
            return Err(SurveyError::Option {
                option: key("tolerance_m"),
                value: t.to_string(),
                reason: format!("the tracing tolerance must be a number of metres in [0, {MAX_TOLERANCE_M}]"),
            });
        }
        if let Some(d) = &self.depth {
            let (lo, hi) = d.support();
            let bad = |reason: String| SurveyError::Option { option: key("depth_m"), value: d.name.clone(), reason };
            if d.unit != Unit::M {
                return Err(bad(format!("a depth is in metres (unit \"m\"), not {}", d.unit)));
            }
            if !(lo > 0.0 && hi <= thickness_m) {
                return Err(bad(format!(
                    "a stone's depth must lie within (0, {thickness_m}] m, the wall's thickness at its base; this law \
                     ranges over [{lo}, {hi}] (a normal or lognormal law is unbounded: use truncated_normal or uniform)"
                )));
            }
        }
        Ok(())
    }

    /// A depth law from its command-line text: `D` (fixed, m) or `A..B` (uniform on [A, B),
    /// m).
    ///
    /// # Errors
    /// A message naming the text.
    pub fn depth_from_text(text: &str) -> Result<Distribution, String> {
        let number =
            |s: &str| s.trim().parse::<f64>().map_err(|_| format!("--depth-m {text}: {s:?} is not a number of metres"));
        match text.split_once("..") {
            None => Ok(Distribution::fixed(number(text)?, Unit::M)),
            Some((a, b)) => {
                let (a, b) = (number(a)?, number(b)?);
                if !(a.is_finite() && b.is_finite() && a < b) {
                    return Err(format!("--depth-m {text}: a range A..B needs A < B"));
                }
                Ok(Distribution::uniform("depth_m", a, b, Unit::M))
            }
        }
    }

    /// A depth law from a study's value: a number (fixed, m) or an inline distribution table
    /// (the keys of a distribution file, `unit` optional and `m`). `path` and `key` name the
    /// study file and the key in errors.
    ///
    /// # Errors
    /// A message naming the key.
    pub fn depth_from_toml(value: &toml::Value, path: &Path, key: &str) -> Result<Distribution, String> {
        match value {
            toml::Value::Float(_) | toml::Value::Integer(_) => {
                let v = value.as_float().or_else(|| value.as_integer().map(|i| i as f64)).unwrap_or(f64::NAN);
                Ok(Distribution::fixed(v, Unit::M))
            }
            toml::Value::Table(t) => {
                let mut t = t.clone();
                t.entry("unit").or_insert_with(|| toml::Value::String("m".into()));
                let spec: DistributionSpec =
                    toml::Value::Table(t).try_into().map_err(|e: toml::de::Error| format!("{key}: {e}"))?;
                if spec.kind == Kind::Fixed && spec.value.is_none() {
                    return Err(format!("{key}: a fixed law needs `value`"));
                }
                spec.resolve(key, path, &format!("{key}.")).map_err(|e| e.to_string())
            }
            other => Err(format!("{key} = {other}: a number of metres or a distribution table")),
        }
    }
}

/// The surveyed wall of the traced elevation at `path` with the uncertainty `u`: a
/// [`Wall`] whose realizations ([`crate::generator::generate`]) draw the uncertainty around
/// the trace. The survey is first imported as traced ([`import`], every check of an import).
/// Scanned stones at `path` make a wall whose every realization is the survey as scanned
/// ([`Wall::from_scanned`]), `u` at its default.
///
/// # Errors
/// The errors of [`import`]; [`SurveyError::Option`] for a tolerance or depth law on
/// scanned stones (whose every realization is the survey as scanned,
/// [`Wall::from_scanned`]) and for an uncertainty out of range ([`Uncertainty::check`],
/// options named as on the command line).
pub fn surveyed_wall(path: &Path, options: &ImportOptions, u: &Uncertainty) -> Result<Wall, SurveyError> {
    surveyed_wall_with(path, options, u, &|k| format!("--{}", k.replace('_', "-")))
}

/// [`surveyed_wall`] with the options named by `key` in errors.
///
/// # Errors
/// As [`surveyed_wall`].
pub fn surveyed_wall_with(
    path: &Path,
    options: &ImportOptions,
    u: &Uncertainty,
    key: &dyn Fn(&str) -> String,
) -> Result<Wall, SurveyError> {
    let traced = import(path, options)?;
    if !traced.format.is_elevation() {
        // No uncertainty is defined for meshes: every realization is the survey as scanned.
        for (k, given) in [("tolerance_m", u.tolerance_m != 0.0), ("depth_m", u.depth.is_some())] {
            if given {
                return Err(SurveyError::Option {
                    option: key(k),
                    value: traced.format.name().into(),
                    reason: "is for a traced elevation: no uncertainty is drawn around scanned stones, whose \
                             realizations are the survey as scanned"
                        .into(),
                });
            }
        }
        return Ok(Wall::from_scanned(traced.layout, path.to_owned()));
    }
    let section = options.section.expect("checked by the import: a traced elevation has a section");
    u.check(section.base_m, key)?;
    let format = traced.format;
    let trace = elevation::trace(path, format, options)?;
    let stone = options.materials.stone();
    let stones = trace
        .stones
        .iter()
        .zip(trace.polygons())
        .map(|(s, polygon)| TracedStone {
            id: s.id.clone(),
            material: s.material.clone().unwrap_or_else(|| stone.clone()),
            polygon,
            depth_m: s.depth_m,
        })
        .collect();
    let setting = TraceSetting {
        name: traced.layout.name.clone(),
        source: path.to_owned(),
        gravity: traced.layout.gravity_m_per_s2,
        base_width: section.base_m,
        top_width: section.top_m,
        batter: section.batter,
        materials: traced.layout.materials.clone(),
        table_material: traced.layout.table.material.clone(),
        base: traced.layout.restraints.base_sliding,
    };
    debug_assert!(matches!(format, SurveyFormat::Svg | SurveyFormat::Geojson | SurveyFormat::Dxf));
    Ok(Wall::from_trace(setting, Traced { stones, tolerance_m: u.tolerance_m, depth: u.depth.clone(), scanned: None }))
}
