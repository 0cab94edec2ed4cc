//! Model extensions: named physical effects that change a wall model where they act (its
//! layout geometry, its joint law or its restraints), each with one or two parameters.
//!
//! An effect is data, an [`EffectDef`]: its parameters (name, unit, plausible range, search
//! scale, neutral value) and a list of [`Step`]s, each a primitive of the model driven by one
//! parameter. The built-in library ([`builtin`]) is a set of such definitions, and a user
//! adds a hypothesis the same way in a TOML file ([`EffectDef::from_file`]); both are run by
//! the same code, in a study (`effects = { NAME = { PARAM = VALUE } }`), in `drystone
//! discrepancy` and in `drystone synthesize`.
//!
//! | built-in | parameters | steps (where it enters) |
//! | --- | --- | --- |
//! | `kn_scale` | factor (–) | joint law: Kn and Ks of every joint × factor |
//! | `base_stiffness` | factor (–) | joint law: Kn and Ks of the `base` joints × factor |
//! | `bed_stiffness` | factor (–) | joint law: Kn and Ks of the `bed` joints × factor |
//! | `head_stiffness` | factor (–) | joint law: Kn and Ks of the `head` joints × factor |
//! | `joint_closure` | Kni/Kn (–), Vm (m) | joint law: Kn × ratio, hyperbolic closure Vm |
//! | `seating_gap` | g₀ (m) | joint law: seating closure with gaps up to g₀ |
//! | `initial_lean` | ψ (deg) | layout: sheared out of plumb towards +y |
//! | `edge_rounding` | r (m) | layout: every edge of every block rounded by r |
//! | `restraint_stiffness` | k (N/m per block) | restraints: rigid ends → springs |
//! | `end_rope` | T₀ (N), EA (N) | restraints: rigid ends → a tensioned rope at each end |
//! | `transverse_dip` | δ (deg) | layout: bed joints dipping across the thickness, U(−δ, δ) per joint |
//! | `base_restraint` | h_s (m) | layout: fixed stops of height h_s on the downhill face of the first course |
//! | `leaf_split` | f (–) | layout: every block cut into two leaves, the loose +y leaf taking the share f of the width |
//! | `shear_stiffness` | factor (–) | joint law: Ks of every joint × factor (Kn kept) |
//! | `dilatant_joints` | i (deg) | joint law: friction angle of the `bed` joints φ → φ + i (Patton 1966) |
//! | `toe_crushing` | fc (MPa) | joint law: faces crushing at fc, `q = min(Kn u, fc)` |
//! | `table_kick` | Δ (deg) | the tilting table: each 5° stop loads the wall to the stop plus Δ |
//! | `jack_tilt` | 1/L (1/m) | the in-plane rig: the actuator carries `N u / L` more |
//! | `rig_friction` | μ_r (–) | the in-plane rig: the actuator carries `μ_r N` more, against the motion |
//!
//! Every parameter carries a broad plausible range with its source and narrower ranges for
//! the kinds of wall ([`WallKind`], the wall description's `kind`), each with its source
//! ([`ParamDef::kinds`]). A user states values within the broad range; the discrepancy
//! analysis searches each wall within the range of its kind ([`Effect::at_search`],
//! [`Effect::for_kind`]).
//!
//! Every form is deterministic (the same value in every realization) except
//! `transverse_dip`, whose dips are drawn per bed joint. Length ranges marked
//! `range_per_course_height` scale with the wall: they are written for a course height of
//! 0.05 m (the source paper's 1:4 walls) and multiplied by the wall's mean course height /
//! 0.05 m. An effect at its neutral value reproduces the model unchanged (factor 1, g₀ = 0,
//! ψ = 0, r = 0, δ = 0, h_s = 0, i = 0, f = 0; `joint_closure`, `restraint_stiffness` and `end_rope`
//! reach it only in the limit Vm → ∞, k → ∞, T₀ → ∞).
//!
//! Random draws come from [`effect_rng`]: one stream per (master seed, realization, group,
//! effect), so that a study with an effect and the discrepancy analysis that named it draw
//! the same numbers, and no group or effect shifts another's draws.

mod apply;
mod builtin;
mod file;
pub mod geometry;
pub mod rope;
mod step;

pub use apply::{apply_all, effect_rng};
pub use builtin::builtin;
pub use file::EffectFileError;
pub use step::{Property, Step};

use crate::closure::Closure;
pub use crate::generator::WallKind;
use crate::generator::{generate, GeneratedWall, Wall};
use crate::layout::Layout;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Course height the built-in length ranges are written for, m (the 1:4 walls of
/// Santa-Cruz et al. 2021).
pub const REFERENCE_COURSE_HEIGHT_M: f64 = 0.05;

/// The built-in effects whose signature is the failure mechanism (where the moving part
/// starts) more than the angles: the discrepancy analysis searches them by default only
/// when the data hold mechanism observations ([`crate::discrepancy::searched`]).
pub const MECHANISM_EFFECTS: [&str; 2] = ["base_restraint", "leaf_split"];

/// The built-in effects searched only when a study names them in `[discrepancy] effects`
/// ([`crate::discrepancy::searched`]): `table_kick` belongs to a table rolled by hand and
/// moves only the tilting table's angles, as a lean does; a study of such a table names it.
/// `toe_crushing` acts only where joints bear stresses of MPa (the in-plane test's toe
/// under its vertical force), not under a wall's own weight; a study of such a test names
/// it. The in-plane rig's own terms (`jack_tilt`, `rig_friction`, `jack_incline`,
/// `series_compliance`, `load_eccentricity`, `fixed_vertical_load`, `beam_restraint`)
/// belong to a rig that loads a beam; a study of such a test names them.
pub const NAMED_ONLY_EFFECTS: [&str; 9] = [
    "table_kick",
    "toe_crushing",
    "jack_tilt",
    "rig_friction",
    "jack_incline",
    "series_compliance",
    "load_eccentricity",
    "fixed_vertical_load",
    "beam_restraint",
];

/// The largest friction angle a [`Step::Dilatancy`] raises a joint to, degrees.
pub const MAX_FRICTION_DEG: f64 = 85.0;

/// Where an effect enters the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// The generated block layout (applied first).
    Layout,
    /// The joint law.
    JointLaw,
    /// The end restraints (applied last).
    Restraints,
}

/// How a parameter is searched: on a linear or a logarithmic axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// Linear.
    Linear,
    /// Logarithmic (positive values).
    Log,
}

/// One parameter of an effect.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamDef {
    /// Name, e.g. `max_gap_m`.
    pub name: String,
    /// Unit as printed.
    pub unit: String,
    /// Plausible range: lower bound.
    pub min: f64,
    /// Plausible range: upper bound.
    pub max: f64,
    /// Search axis. Default linear.
    #[serde(default = "linear")]
    pub scale: Scale,
    /// The value that leaves the model unchanged (or its limit; may be infinite).
    pub neutral: f64,
    /// The range (and a finite neutral value) is written for a course height of
    /// [`REFERENCE_COURSE_HEIGHT_M`] and scales with the wall's mean course height.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub range_per_course_height: bool,
    /// Where the broad range `[min, max]` (the range of a wall that declares no kind) comes
    /// from. Default empty.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub source: String,
    /// Narrower plausible ranges for walls of a declared kind ([`WallKind`]), each with its
    /// source. A kind without an entry takes the broad range. Each contains the neutral
    /// value when it is finite, and ends at it where the broad range does (so that the
    /// neutral point of a search is the unchanged model for every kind). Default none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub kinds: Vec<KindRange>,
}

/// The plausible range of a parameter for walls of one kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KindRange {
    /// The kind of wall.
    pub kind: WallKind,
    /// Lower bound, in the parameter's unit (scaled like the broad range when the parameter
    /// is `range_per_course_height`, unless the range is [`KindRange::as_built`]).
    pub min: f64,
    /// Upper bound.
    pub max: f64,
    /// Where the range comes from: a measurement, a standard, the paper's text or geometry,
    /// or `estimate (reasoning: ...)`.
    #[serde(default)]
    pub source: String,
    /// The range is stated for walls of this kind as they are built, in absolute units, and
    /// does not scale with the course height even when the parameter does: a saw's
    /// flatness or the asperities of a split face do not grow with the block (the
    /// `sawn_stone` and `rubble_stone` finishes). Default `false`: the range scales like the
    /// broad one (written for [`REFERENCE_COURSE_HEIGHT_M`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub as_built: bool,
}

fn linear() -> Scale {
    Scale::Linear
}

impl ParamDef {
    /// The parameter with its range scaled to a wall of mean course height `course_m` (m):
    /// the broad range, a finite neutral value and every kind's range but those stated
    /// [`KindRange::as_built`] are multiplied by `course_m / REFERENCE_COURSE_HEIGHT_M`.
    pub fn for_course_height(&self, course_m: f64) -> ParamDef {
        if !self.range_per_course_height {
            return self.clone();
        }
        let f = course_m / REFERENCE_COURSE_HEIGHT_M;
        ParamDef {
            min: self.min * f,
            max: self.max * f,
            neutral: if self.neutral.is_finite() { self.neutral * f } else { self.neutral },
            range_per_course_height: false,
            kinds: self
                .kinds
                .iter()
                .map(|k| if k.as_built { k.clone() } else { KindRange { min: k.min * f, max: k.max * f, ..k.clone() } })
                .collect(),
            ..self.clone()
        }
    }

    /// The values a user may state, `(min, max)`: the broad range, widened to hold every
    /// [`KindRange::as_built`] range (so that any value a kind's search can reach can be
    /// stated on a wall of any course height).
    pub fn statable(&self) -> (f64, f64) {
        let built = self.kinds.iter().filter(|k| k.as_built);
        built.fold((self.min, self.max), |(lo, hi), k| (lo.min(k.min), hi.max(k.max)))
    }

    /// The plausible range `(min, max)` and its source for a wall of `kind` (`None`, or a
    /// kind without its own range: the broad range).
    pub fn range_for(&self, kind: Option<WallKind>) -> (f64, f64, &str) {
        match kind.and_then(|k| self.kinds.iter().find(|r| r.kind == k)) {
            Some(r) => (r.min, r.max, &r.source),
            None => (self.min, self.max, &self.source),
        }
    }

    /// Whether the parameter has a range of its own for `kind`.
    pub fn has_kind(&self, kind: WallKind) -> bool {
        self.kinds.iter().any(|r| r.kind == kind)
    }

    /// The value at search coordinate `x` ∈ [0, 1] of the broad range: `min + x (max − min)`
    /// on a linear axis, `min (max/min)^x` on a logarithmic one.
    pub fn at(&self, x: f64) -> f64 {
        interpolate(self.scale, self.min, self.max, x)
    }

    /// The search coordinate of a value in the broad range (the inverse of [`ParamDef::at`];
    /// not clamped).
    pub fn position(&self, v: f64) -> f64 {
        match self.scale {
            Scale::Linear => (v - self.min) / (self.max - self.min),
            Scale::Log => (v / self.min).ln() / (self.max / self.min).ln(),
        }
    }

    /// The value at search coordinate `x` ∈ [0, 1] for a wall of `kind`: the coordinate
    /// runs over the kind's range piecewise, so that 0 and 1 are the kind's bounds and the
    /// coordinate of the neutral value in the broad range is the neutral value for every
    /// kind (the search's unchanged model). A kind without its own range, or `None`:
    /// [`ParamDef::at`].
    pub fn at_for(&self, kind: Option<WallKind>, x: f64) -> f64 {
        let Some(r) = kind.and_then(|k| self.kinds.iter().find(|r| r.kind == k)) else {
            return self.at(x);
        };
        if !self.neutral.is_finite() {
            return interpolate(self.scale, r.min, r.max, x);
        }
        let xn = self.position(self.neutral).clamp(0.0, 1.0);
        if x <= xn {
            if xn <= 0.0 {
                self.neutral
            } else {
                interpolate(self.scale, r.min, self.neutral, x / xn)
            }
        } else if xn >= 1.0 {
            self.neutral
        } else {
            interpolate(self.scale, self.neutral, r.max, (x - xn) / (1.0 - xn))
        }
    }

    /// Checks the kinds' ranges: finite, `min < max`, positive on a log axis, within the
    /// broad range unless [`KindRange::as_built`], containing a finite neutral value and
    /// ending at it where the broad range does.
    ///
    /// # Errors
    /// What is wrong, naming the kind.
    pub fn check_kinds(&self) -> Result<(), String> {
        for r in &self.kinds {
            let k = r.kind.name();
            if !(r.min.is_finite() && r.max.is_finite() && r.min < r.max) {
                return Err(format!("kind {k}: needs finite min < max, got [{}, {}]", r.min, r.max));
            }
            if self.scale == Scale::Log && r.min <= 0.0 {
                return Err(format!("kind {k}: a log-scale range needs min > 0, got {}", r.min));
            }
            // A range that scales with the broad one narrows it: a value its search
            // reaches can be stated ([`ParamDef::statable`]). An as-built range is stated
            // apart and widens what can be stated.
            let tol = 1e-9 * (self.max - self.min).abs();
            if !r.as_built && (r.min < self.min - tol || r.max > self.max + tol) {
                return Err(format!(
                    "kind {k}: [{}, {}] must lie within the broad range [{}, {}] (or be stated `as_built = true`)",
                    r.min, r.max, self.min, self.max
                ));
            }
            if self.neutral.is_finite() {
                if !(r.min..=r.max).contains(&self.neutral) {
                    return Err(format!(
                        "kind {k}: [{}, {}] must contain the neutral value {}",
                        r.min, r.max, self.neutral
                    ));
                }
                if (self.neutral == self.min && r.min != self.neutral)
                    || (self.neutral == self.max && r.max != self.neutral)
                {
                    return Err(format!(
                        "kind {k}: [{}, {}] must end at the neutral value {} where the broad range [{}, {}] does",
                        r.min, r.max, self.neutral, self.min, self.max
                    ));
                }
            }
            if self.kinds.iter().filter(|o| o.kind == r.kind).count() > 1 {
                return Err(format!("kind {k} is given twice"));
            }
        }
        Ok(())
    }
}

/// `a + t (b − a)` on a linear axis, `a (b/a)^t` on a logarithmic one.
fn interpolate(scale: Scale, a: f64, b: f64, t: f64) -> f64 {
    match scale {
        Scale::Linear => a + t * (b - a),
        Scale::Log => a * (b / a).powf(t),
    }
}

/// A named effect: parameters and the steps they drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectDef {
    /// Name, as in files and on the command line (`[a-z0-9_]`).
    pub name: String,
    /// What the effect is, in a sentence.
    #[serde(default)]
    pub description: String,
    /// Its source in the literature (or the user's reason).
    #[serde(default)]
    pub source: String,
    /// Its parameters (one or two).
    pub parameters: Vec<ParamDef>,
    /// Its steps, applied in stage order (layout, joint law, restraints), file order within
    /// a stage.
    pub steps: Vec<Step>,
}

/// Errors of effects.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EffectError {
    /// Unknown effect name.
    #[error("unknown effect `{name}` (known: {known})")]
    Unknown {
        /// The name given.
        name: String,
        /// The known names.
        known: String,
    },
    /// Unknown parameter of an effect.
    #[error("effect `{effect}` has no parameter `{param}` (its parameters: {names})")]
    UnknownParameter {
        /// The effect.
        effect: String,
        /// The name given.
        param: String,
        /// Its parameters.
        names: String,
    },
    /// Wrong number of parameter values.
    #[error("effect `{effect}` takes {expected} parameter(s) ({names}), {given} given")]
    Arity {
        /// The effect.
        effect: String,
        /// Expected count.
        expected: usize,
        /// Given count.
        given: usize,
        /// Parameter names.
        names: String,
    },
    /// A parameter outside its plausible range (or not a number).
    #[error("effect `{effect}`: {param} = {value} is outside its range [{min}, {max}] {unit}")]
    OutOfRange {
        /// The effect.
        effect: String,
        /// The parameter.
        param: String,
        /// The value.
        value: f64,
        /// Range.
        min: f64,
        /// Range.
        max: f64,
        /// Unit.
        unit: String,
    },
    /// The same effect given twice.
    #[error("effect `{effect}` is given twice")]
    Duplicate {
        /// The effect.
        effect: String,
    },
    /// The effect made a block that is not a valid convex polyhedron.
    #[error("effect `{effect}`: block {block}: {reason}")]
    Geometry {
        /// The effect.
        effect: String,
        /// The block id.
        block: String,
        /// What failed.
        reason: crate::geometry::GeometryError,
    },
    /// The effect reshapes blocks and a block's mass is its own (a scanned stone's mesh,
    /// the layout's `own_mass`), which no reshaping can follow.
    #[error(
        "effect `{effect}` reshapes the blocks, but block {block} has its own mass properties (a scanned stone's \
         mesh), which a reshaped block would no longer have: leave the effect out for scanned stones"
    )]
    OwnMass {
        /// The effect.
        effect: String,
        /// The block id.
        block: String,
    },
    /// A `closure` step names a law that is not a closure law of one length parameter.
    #[error("effect `{effect}`: `{law}` is not a closure law with a length parameter (known: {known})")]
    UnknownLaw {
        /// The effect.
        effect: String,
        /// The name given.
        law: String,
        /// The known names.
        known: String,
    },
    /// The effect acts on a joint family the wall does not have.
    #[error("effect `{effect}` acts on the {family} joints, which this wall does not have")]
    NoFamily {
        /// The effect.
        effect: String,
        /// The family.
        family: &'static str,
    },
    /// Generating or checking the wall failed (the generator's message).
    #[error("{0}")]
    Generator(String),
}

/// An effect with its parameter values (in the units of its [`ParamDef`]s).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Effect {
    /// The definition (serialized as its name).
    #[serde(rename = "effect", serialize_with = "def_name")]
    pub def: Arc<EffectDef>,
    /// Parameter values, one per parameter.
    pub values: Vec<f64>,
    /// Set when the effect was made at a search coordinate of the discrepancy analysis
    /// ([`Effect::at_search`]): the coordinate and the course height its ranges were scaled
    /// for. A wall of a declared kind then takes the values at that coordinate in its own
    /// ranges ([`Effect::for_kind`]); `None` (an effect with stated values, as in a study):
    /// the values as they are for every wall.
    #[serde(skip)]
    pub search: Option<SearchPoint>,
}

/// The search coordinate an effect was made at ([`Effect::search`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SearchPoint {
    /// Coordinates in [0, 1], one per parameter.
    pub x: Vec<f64>,
    /// Course height the ranges were scaled for, m.
    pub course_m: f64,
}

fn def_name<S: serde::Serializer>(d: &Arc<EffectDef>, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&d.name)
}

/// The known effects by name: the built-ins and the user's definitions.
#[derive(Debug, Clone, PartialEq)]
pub struct Library {
    defs: BTreeMap<String, Arc<EffectDef>>,
    order: Vec<String>,
}

impl Default for Library {
    fn default() -> Self {
        Library::builtin()
    }
}

impl Library {
    /// The built-in library.
    pub fn builtin() -> Library {
        let mut l = Library { defs: BTreeMap::new(), order: Vec::new() };
        for d in builtin() {
            l.order.push(d.name.clone());
            l.defs.insert(d.name.clone(), Arc::new(d));
        }
        l
    }

    /// Adds a user definition.
    ///
    /// # Errors
    /// [`EffectError::Duplicate`] if the name is taken.
    pub fn add(&mut self, def: EffectDef) -> Result<(), EffectError> {
        if self.defs.contains_key(&def.name) {
            return Err(EffectError::Duplicate { effect: def.name });
        }
        self.order.push(def.name.clone());
        self.defs.insert(def.name.clone(), Arc::new(def));
        Ok(())
    }

    /// Every definition, built-ins first, then the user's in the order added.
    pub fn all(&self) -> Vec<Arc<EffectDef>> {
        self.order.iter().map(|n| self.defs[n].clone()).collect()
    }

    /// The definition of a name.
    ///
    /// # Errors
    /// [`EffectError::Unknown`] listing the known names.
    pub fn get(&self, name: &str) -> Result<Arc<EffectDef>, EffectError> {
        self.defs
            .get(name)
            .cloned()
            .ok_or_else(|| EffectError::Unknown { name: name.to_string(), known: self.order.join(", ") })
    }

    /// Parses `NAME=V` or `NAME=V1:V2` (as on the command line), values checked against the
    /// ranges scaled to a wall of mean course height `course_m` (m).
    ///
    /// # Errors
    /// [`EffectError`] naming the effect or the parameter.
    pub fn parse(&self, text: &str, course_m: f64) -> Result<Effect, EffectError> {
        let (name, vals) = text.split_once('=').unwrap_or((text, ""));
        let def = self.get(name.trim())?;
        let values: Vec<f64> = vals.split(':').map(|v| v.trim().parse::<f64>().unwrap_or(f64::NAN)).collect();
        Effect::new(def, values, course_m)
    }

    /// An effect from named values (`{ PARAM = VALUE }` of a study file).
    ///
    /// # Errors
    /// [`EffectError`] naming the effect or the parameter.
    pub fn from_values(
        &self,
        name: &str,
        values: &BTreeMap<String, f64>,
        course_m: f64,
    ) -> Result<Effect, EffectError> {
        let def = self.get(name)?;
        let names = || def.parameters.iter().map(|p| p.name.clone()).collect::<Vec<_>>().join(", ");
        if let Some(k) = values.keys().find(|k| !def.parameters.iter().any(|p| &p.name == *k)) {
            return Err(EffectError::UnknownParameter { effect: def.name.clone(), param: k.clone(), names: names() });
        }
        let mut v = Vec::new();
        for p in &def.parameters {
            v.push(*values.get(&p.name).ok_or_else(|| EffectError::Arity {
                effect: def.name.clone(),
                expected: def.parameters.len(),
                given: values.len(),
                names: names(),
            })?);
        }
        Effect::new(def, v, course_m)
    }
}

impl EffectDef {
    /// Its parameters with their ranges for a wall of mean course height `course_m` (m).
    pub fn params_for(&self, course_m: f64) -> Vec<ParamDef> {
        self.parameters.iter().map(|p| p.for_course_height(course_m)).collect()
    }

    /// The earliest stage its steps enter.
    pub fn stage(&self) -> Stage {
        self.steps.iter().map(Step::stage).min().unwrap_or(Stage::JointLaw)
    }

    /// Whether the effect can change a wall with these properties (`restrained`: it has end
    /// restraints): an effect made only of end-restraint steps (springs, ropes) cannot act
    /// on a free wall; the table's overshoot acts on every wall.
    pub fn acts_on(&self, restrained: bool) -> bool {
        restrained
            || self
                .steps
                .iter()
                .any(|s| s.stage() != Stage::Restraints || matches!(s, Step::TableOvershoot { .. }) || s.on_rig())
    }

    /// Whether it acts only on the readings of a run, not on the wall's motion: every step
    /// is one of the in-plane rig's terms that the readings carry
    /// ([`Step::acts_on_readings_only`]: `jack_tilt`, `rig_friction`, `jack_incline`,
    /// `series_compliance`, or an effect of a file made of such steps). Derived
    /// from the steps, so a file's effect has it by what it does. The discrepancy analysis
    /// makes no run for such an effect: the model with it is the model without it, its
    /// runs read again ([`crate::protocol::Observed::reread`]).
    pub fn acts_on_readings_only(&self) -> bool {
        !self.steps.is_empty() && self.steps.iter().all(Step::acts_on_readings_only)
    }

    /// Why the in-plane shear–compression test does not read the effect, or `None` when it
    /// reads every step ([`Step::not_read_in_plane`]: `initial_lean`, `table_kick`,
    /// `restraint_stiffness`, `end_rope`, `base_restraint`, `leaf_split`,
    /// `transverse_dip`, or an effect of a file with such a step). Derived from the steps,
    /// so a file's effect has it by what it does; an in-plane study and its discrepancy
    /// analysis refuse such an effect by name.
    pub fn not_read_in_plane(&self) -> Option<&'static str> {
        self.steps.iter().find_map(Step::not_read_in_plane)
    }

    /// Whether it draws random numbers (a `transverse_dip` step).
    pub fn is_random(&self) -> bool {
        self.steps.iter().any(|s| matches!(s, Step::TransverseDip { .. }))
    }
}

/// The checked layout of realization `realization` of `wall` (master seed `seed`) in group
/// `group`, with `effects` applied ([`apply_all`]), and the generated wall it came from.
/// Effects made at a search coordinate take their values in the ranges of the wall's kind
/// ([`Effect::for_kind`]).
///
/// # Errors
/// [`EffectError::Generator`] if the wall cannot be generated or checked; the errors of
/// [`apply_all`].
pub fn realize(
    wall: &Wall,
    seed: u64,
    realization: u64,
    group: &str,
    effects: &[Effect],
) -> Result<(GeneratedWall, Layout), EffectError> {
    let generated = generate(wall, seed, realization).map_err(|e| EffectError::Generator(e.to_string()))?;
    let mut layout = generated.check().map_err(|e| EffectError::Generator(e.to_string()))?;
    if wall.kind.is_some() && effects.iter().any(|e| e.search.is_some()) {
        let mapped: Vec<Effect> = effects.iter().map(|e| e.for_kind(wall.kind)).collect();
        apply_all(&mut layout, &generated, group, &mapped)?;
        return Ok((generated, layout));
    }
    apply_all(&mut layout, &generated, group, effects)?;
    Ok((generated, layout))
}

/// Mean course height of a wall, m (the scale of the length ranges).
pub fn course_height_of(wall: &Wall) -> f64 {
    let m = wall.course_height.mean();
    if m.is_finite() && m > 0.0 {
        m
    } else {
        REFERENCE_COURSE_HEIGHT_M
    }
}
