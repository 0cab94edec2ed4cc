//! Effects defined in TOML files: a user's hypothesis made of the library's primitives.
//!
//! ```toml
//! version = 1
//! name = "timber_base"
//! description = "the base course sits on a timber table, softer than the stone beds"
//! source = "our test rig"
//!
//! [[parameters]]
//! name = "factor"
//! unit = "-"
//! min = 0.05
//! max = 1.0
//! scale = "log"          # or "linear" (default)
//! neutral = 1.0
//!
//! [[steps]]
//! kind = "joint_factor"  # joint_factor | closure | dilatancy | lean | rounding | transverse_dip | restraint_spring
//! family = "base"        # base | bed | head | wedge; absent: every joint
//! property = "stiffness" # kn | ks | stiffness | friction | cohesion
//! parameter = "factor"
//! ```
//!
//! A parameter may carry narrower plausible ranges for walls of a declared kind (the wall
//! description's `kind`), each with its source; a kind without one takes `[min, max]`:
//!
//! ```toml
//! [[parameters.kinds]]
//! kind = "concrete_paver"  # concrete_paver | shaped_stone | sawn_stone | rubble_stone
//! min = 0.3
//! max = 1.0
//! source = "our plate-load tests of the pavers"
//! ```
//!
//! A kind's range contains a finite neutral value and ends at it where `[min, max]` does.
//!
//! A `closure` step takes `law = "hyperbolic" | "seating"` and a parameter in m; `lean` and
//! `transverse_dip` take degrees, `dilatancy` (a `family` or every joint) the asperity
//! angle in degrees (at or above 0), `rounding` m, `restraint_spring` N/m per block.

use super::{EffectDef, ParamDef, Scale, Step};
use crate::closure::Closure;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The only effect-file version this build reads.
pub const EFFECT_VERSION: u32 = 1;

/// Errors of an effect file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EffectFileError {
    /// The file could not be read.
    #[error("cannot read effect file {}: {message}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        message: String,
    },
    /// Not valid effect TOML (syntax, unknown key, wrong type).
    #[error("effect file {}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// toml's message, with the key and line.
        message: String,
    },
    /// A value is wrong.
    #[error("effect file {}: {key}: {reason}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The key.
        key: String,
        /// What is wrong.
        reason: String,
    },
}

/// The file's keys, [`EffectDef`]'s written out rather than flattened: a flattened struct is
/// read through an intermediate map, whose errors lose their position (every one was
/// reported at line 1, column 1).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EffectFile {
    version: u32,
    name: String,
    #[serde(default)]
    description: String,
    #[serde(default)]
    source: String,
    parameters: Vec<ParamDef>,
    steps: Vec<Step>,
}

impl EffectDef {
    /// Reads and checks an effect file.
    ///
    /// # Errors
    /// [`EffectFileError`] naming the file and the key.
    pub fn from_file(path: &Path) -> Result<EffectDef, EffectFileError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| EffectFileError::Io { path: path.to_owned(), message: e.to_string() })?;
        EffectDef::from_toml(&text, path)
    }

    /// Parses and checks effect TOML; `path` names the file in errors.
    ///
    /// # Errors
    /// [`EffectFileError`] naming the file and the key.
    pub fn from_toml(text: &str, path: &Path) -> Result<EffectDef, EffectFileError> {
        let f: EffectFile = toml::from_str(text)
            .map_err(|e| EffectFileError::Parse { path: path.to_owned(), message: e.to_string() })?;
        let bad = |key: String, reason: String| EffectFileError::Invalid { path: path.to_owned(), key, reason };
        if f.version != EFFECT_VERSION {
            return Err(bad("version".into(), format!("this drystone reads effect version {EFFECT_VERSION}")));
        }
        let d = EffectDef {
            name: f.name,
            description: f.description,
            source: f.source,
            parameters: f.parameters,
            steps: f.steps,
        };
        if d.name.is_empty() || !d.name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_') {
            return Err(bad("name".into(), format!("{:?} must be non-empty, of a-z, 0-9 and _", d.name)));
        }
        if !(1..=2).contains(&d.parameters.len()) {
            return Err(bad(
                "parameters".into(),
                format!("an effect has one or two parameters, {} given", d.parameters.len()),
            ));
        }
        for (i, p) in d.parameters.iter().enumerate() {
            let key = |k: &str| format!("parameters[{i}].{k}");
            if d.parameters[..i].iter().any(|q| q.name == p.name) {
                return Err(bad(key("name"), format!("parameter `{}` given twice", p.name)));
            }
            if !(p.min.is_finite() && p.max.is_finite() && p.min < p.max) {
                return Err(bad(key("min"), format!("needs finite min < max, got [{}, {}]", p.min, p.max)));
            }
            if p.scale == Scale::Log && p.min <= 0.0 {
                return Err(bad(key("min"), "a log scale needs min > 0".into()));
            }
            if p.neutral.is_nan() || (p.neutral.is_finite() && !(p.min..=p.max).contains(&p.neutral)) {
                return Err(bad(
                    key("neutral"),
                    format!("{} is outside [{}, {}] (infinite is allowed)", p.neutral, p.min, p.max),
                ));
            }
            p.check_kinds().map_err(|reason| bad(key("kinds"), reason))?;
        }
        if d.steps.is_empty() {
            return Err(bad("steps".into(), "an effect needs at least one step".into()));
        }
        for (i, s) in d.steps.iter().enumerate() {
            if !d.parameters.iter().any(|p| p.name == s.parameter()) {
                let names: Vec<&str> = d.parameters.iter().map(|p| p.name.as_str()).collect();
                return Err(bad(
                    format!("steps[{i}].parameter"),
                    format!("`{}` is not a parameter of the effect ({})", s.parameter(), names.join(", ")),
                ));
            }
            // The lowest value any range of the parameter (broad or of a kind) reaches.
            let p = d
                .parameters
                .iter()
                .find(|p| p.name == s.parameter())
                .map(|p| (p.kinds.iter().map(|k| k.min).fold(p.min, f64::min), p.max))
                .unwrap_or_default();
            let needs_positive = matches!(
                s,
                Step::JointFactor { .. }
                    | Step::RestraintSpring { .. }
                    | Step::RopeStiffness { .. }
                    | Step::Crushing { .. }
            );
            if needs_positive && p.0 <= 0.0 {
                return Err(bad(
                    format!("steps[{i}]"),
                    "a factor or a stiffness needs a parameter range above 0".into(),
                ));
            }
            if let Step::Closure { law, .. } = s {
                if Closure::with_length(law, 1e-3).is_none() {
                    return Err(bad(
                        format!("steps[{i}].law"),
                        format!(
                            "`{law}` is not a closure law with a length parameter ({})",
                            Closure::length_law_names().join(", ")
                        ),
                    ));
                }
            }
            if matches!(
                s,
                Step::JackTilt { .. }
                    | Step::RigFriction { .. }
                    | Step::SeriesCompliance { .. }
                    | Step::BeamRestraint { .. }
            ) && p.0 < 0.0
            {
                return Err(bad(
                    format!("steps[{i}]"),
                    "a rig's length, friction, compliance or stiffness needs a parameter range at or above 0".into(),
                ));
            }
            if matches!(s, Step::FixedLoad { .. }) && !(p.0 >= 0.0 && p.1 <= 1.0) {
                return Err(bad(
                    format!("steps[{i}]"),
                    "a share of the beam's displacement needs a parameter range in [0, 1]".into(),
                ));
            }
            if matches!(s, Step::RopePretension { .. }) && p.0 < 0.0 {
                return Err(bad(format!("steps[{i}]"), "a pretension needs a parameter range at or above 0".into()));
            }
            if matches!(s, Step::Closure { .. } | Step::Rounding { .. }) && p.0 < 0.0 {
                return Err(bad(format!("steps[{i}]"), "a length needs a parameter range at or above 0".into()));
            }
            if matches!(s, Step::Dilatancy { .. }) && !(p.0 >= 0.0 && p.1 < 90.0) {
                return Err(bad(
                    format!("steps[{i}]"),
                    "an asperity angle needs a parameter range in [0, 90) deg".into(),
                ));
            }
        }
        Ok(d)
    }
}
