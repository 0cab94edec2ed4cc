//! The effect library: named physical mechanisms that the baseline model leaves out, each
//! with one or two parameters (unit, plausible range), its source in the literature, a
//! deterministic form and, where it makes sense, a random per-realization form, and the
//! place where it enters the model (the generated layout, the joint law or the
//! restraints).
//!
//! | effect | parameters | enters | random form |
//! | --- | --- | --- | --- |
//! | `kn_scale` | s (–) | joint law: Kn, Ks × s | – |
//! | `joint_closure` | Kni/Kn (–), Vm (m) | joint law: hyperbolic closure | – |
//! | `seating_gap` | g₀ (m) | joint law: seating closure | g₀ᵢ ~ U(0, 2 g₀) per realization |
//! | `initial_lean` | ψ (deg) | layout: sheared out of plumb | ψᵢ ~ U(0, 2 ψ) per realization |
//! | `edge_rounding` | r (m) | layout: pivot edges chamfered | – |
//! | `restraint_stiffness` | k (N/m per block) | restraints: rigid → spring | – |
//! | `transverse_dip` | δ (deg) | layout: bed joints dipping across the thickness | always: δⱼ ~ U(−δ, δ) per bed joint |
//!
//! An effect at its *neutral* value reproduces the baseline exactly (s = 1, g₀ = 0, ψ = 0,
//! r = 0, k → rigid, δ = 0; `joint_closure` reaches the linear law only in the limit Vm → ∞
//! with Kni = Kn).

mod geometry;

use crate::layout::{Closure, EndRestraint, Layout};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::fmt;

pub use geometry::{chamfer_pivot_edges, shear_out_of_plumb, tilt_beds_across};

/// Where an effect enters the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// The generated block layout.
    Layout,
    /// The joint law.
    JointLaw,
    /// The end restraints.
    Restraints,
}

/// How the parameter is searched: on a linear or a logarithmic axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// Linear.
    Linear,
    /// Logarithmic (positive values).
    Log,
}

/// One parameter of an effect.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ParamInfo {
    /// Name, e.g. `max_gap_m`.
    pub name: &'static str,
    /// Unit as printed.
    pub unit: &'static str,
    /// Plausible range: lower bound.
    pub min: f64,
    /// Plausible range: upper bound.
    pub max: f64,
    /// Search axis.
    pub scale: Scale,
    /// The value that reproduces the baseline (or its limit).
    pub neutral: f64,
}

const fn p(name: &'static str, unit: &'static str, min: f64, max: f64, scale: Scale, neutral: f64) -> ParamInfo {
    ParamInfo { name, unit, min, max, scale, neutral }
}
const KN_SCALE: [ParamInfo; 1] = [p("factor", "-", 0.05, 2.0, Scale::Log, 1.0)];
const JOINT_CLOSURE: [ParamInfo; 2] = [
    p("initial_stiffness_ratio", "-", 0.02, 1.0, Scale::Log, 1.0),
    p("max_closure_m", "m", 1e-4, 5e-3, Scale::Log, f64::INFINITY),
];
const SEATING_GAP: [ParamInfo; 1] = [p("max_gap_m", "m", 0.0, 3e-3, Scale::Linear, 0.0)];
const INITIAL_LEAN: [ParamInfo; 1] = [p("lean_deg", "deg", 0.0, 3.0, Scale::Linear, 0.0)];
const EDGE_ROUNDING: [ParamInfo; 1] = [p("radius_m", "m", 0.0, 0.015, Scale::Linear, 0.0)];
const RESTRAINT_STIFFNESS: [ParamInfo; 1] =
    [p("stiffness_n_per_m", "N/m per block", 10.0, 1e6, Scale::Log, f64::INFINITY)];
const TRANSVERSE_DIP: [ParamInfo; 1] = [p("max_dip_deg", "deg", 0.0, 15.0, Scale::Linear, 0.0)];

/// The effects of the library.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// Plain recalibration of Kn (and Ks with it): the control a user tries first.
    KnScale,
    /// Hyperbolic normal closure of rough joints (Bandis, Lumsden & Barton 1983).
    JointClosure,
    /// Seating of uneven beds: initial gaps up to g₀ that close under load.
    SeatingGap,
    /// The wall built out of plumb by ψ towards the side it falls to.
    InitialLean,
    /// Rounded or crushed block edges of size r: every out-of-plane pivot moves inwards.
    EdgeRounding,
    /// End restraints as springs instead of rigid.
    RestraintStiffness,
    /// Bed joints dipping across the wall's thickness, randomly per joint up to δ.
    TransverseDip,
}

impl EffectKind {
    /// Every effect, in library order.
    pub const ALL: [EffectKind; 7] = [
        EffectKind::KnScale,
        EffectKind::JointClosure,
        EffectKind::SeatingGap,
        EffectKind::InitialLean,
        EffectKind::EdgeRounding,
        EffectKind::RestraintStiffness,
        EffectKind::TransverseDip,
    ];

    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::KnScale => "kn_scale",
            EffectKind::JointClosure => "joint_closure",
            EffectKind::SeatingGap => "seating_gap",
            EffectKind::InitialLean => "initial_lean",
            EffectKind::EdgeRounding => "edge_rounding",
            EffectKind::RestraintStiffness => "restraint_stiffness",
            EffectKind::TransverseDip => "transverse_dip",
        }
    }

    /// The effect of a name.
    pub fn from_name(name: &str) -> Option<EffectKind> {
        EffectKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Its parameters.
    pub fn params(self) -> &'static [ParamInfo] {
        match self {
            EffectKind::KnScale => &KN_SCALE,
            EffectKind::JointClosure => &JOINT_CLOSURE,
            EffectKind::SeatingGap => &SEATING_GAP,
            EffectKind::InitialLean => &INITIAL_LEAN,
            EffectKind::EdgeRounding => &EDGE_ROUNDING,
            EffectKind::RestraintStiffness => &RESTRAINT_STIFFNESS,
            EffectKind::TransverseDip => &TRANSVERSE_DIP,
        }
    }

    /// Where it enters the model.
    pub fn stage(self) -> Stage {
        match self {
            EffectKind::KnScale | EffectKind::JointClosure | EffectKind::SeatingGap => Stage::JointLaw,
            EffectKind::InitialLean | EffectKind::EdgeRounding | EffectKind::TransverseDip => Stage::Layout,
            EffectKind::RestraintStiffness => Stage::Restraints,
        }
    }

    /// Its source in the literature.
    pub fn source(self) -> &'static str {
        match self {
            EffectKind::KnScale => "recalibration of the joint stiffness (Santa-Cruz et al. 2021, Table 9 procedure)",
            EffectKind::JointClosure => {
                "Bandis, Lumsden & Barton (1983), Int. J. Rock Mech. Min. Sci. 20:249; Goodman (1976)"
            }
            EffectKind::SeatingGap => {
                "uneven beds of hand-placed stones; uniform asperity heights (Greenwood & Williamson 1966)"
            }
            EffectKind::InitialLean => {
                "construction tolerance: walls out of plumb (de Felice 2011, Int. J. Archit. Herit. 5:466)"
            }
            EffectKind::EdgeRounding => "rounded and crushed block edges (Mehrotra & DeJong 2018, Earthq. Eng. Struct. Dyn. 47:2661)",
            EffectKind::RestraintStiffness => "finite stiffness of rope end restraints (Santa-Cruz et al. 2021, SBR set-up)",
            EffectKind::TransverseDip => {
                "stones not cut to the section: bed joints dipping across the thickness (the 'slightly irregular' stones of Santa-Cruz et al. 2021)"
            }
        }
    }

    /// What the random per-realization form is, if the effect has one.
    pub fn random_form(self) -> Option<&'static str> {
        match self {
            EffectKind::SeatingGap => Some("g0 per realization uniform in [0, 2 g0]"),
            EffectKind::InitialLean => Some("psi per realization uniform in [0, 2 psi]"),
            EffectKind::TransverseDip => Some("dip of every bed joint uniform in [-delta, delta] (always random)"),
            _ => None,
        }
    }

    /// Whether the effect changes a layout with these properties (`restrained`: it has
    /// end restraints). An effect that cannot act is skipped for that group.
    pub fn acts_on(self, restrained: bool) -> bool {
        !matches!(self, EffectKind::RestraintStiffness) || restrained
    }
}

impl fmt::Display for EffectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Errors of the effect library.
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
    /// Wrong number of parameter values.
    #[error("effect `{effect}` takes {expected} parameter(s) ({names}), {given} given")]
    Arity {
        /// The effect.
        effect: &'static str,
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
        effect: &'static str,
        /// The parameter.
        param: &'static str,
        /// The value.
        value: f64,
        /// Range.
        min: f64,
        /// Range.
        max: f64,
        /// Unit.
        unit: &'static str,
    },
    /// The effect made a block that is not a valid convex polyhedron.
    #[error("effect `{effect}`: block {block}: {reason}")]
    Geometry {
        /// The effect.
        effect: &'static str,
        /// The block id.
        block: String,
        /// What failed.
        reason: crate::geometry::GeometryError,
    },
}

/// An effect with its parameter values (in the units of [`EffectKind::params`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Effect {
    /// Which effect.
    pub kind: EffectKind,
    /// Parameter values, one per [`EffectKind::params`] entry.
    pub values: Vec<f64>,
    /// Use the random per-realization form (where the effect has one; `transverse_dip` is
    /// always random).
    pub random: bool,
}

impl Effect {
    /// A checked effect.
    ///
    /// # Errors
    /// [`EffectError::Arity`] or [`EffectError::OutOfRange`].
    pub fn new(kind: EffectKind, values: Vec<f64>, random: bool) -> Result<Effect, EffectError> {
        let ps = kind.params();
        if values.len() != ps.len() {
            return Err(EffectError::Arity {
                effect: kind.name(),
                expected: ps.len(),
                given: values.len(),
                names: ps.iter().map(|p| p.name).collect::<Vec<_>>().join(", "),
            });
        }
        for (p, &v) in ps.iter().zip(&values) {
            if !(v.is_finite() && v >= p.min && v <= p.max) {
                return Err(EffectError::OutOfRange {
                    effect: kind.name(),
                    param: p.name,
                    value: v,
                    min: p.min,
                    max: p.max,
                    unit: p.unit,
                });
            }
        }
        Ok(Effect { kind, values, random })
    }

    /// Parses `NAME=V` or `NAME=V1:V2` (two-parameter effects), as on the command line.
    ///
    /// # Errors
    /// [`EffectError`] naming the effect or the parameter.
    pub fn parse(text: &str) -> Result<Effect, EffectError> {
        let unknown = |name: &str| EffectError::Unknown {
            name: name.to_string(),
            known: EffectKind::ALL.iter().map(|k| k.name()).collect::<Vec<_>>().join(", "),
        };
        let (name, vals) = text.split_once('=').ok_or_else(|| unknown(text))?;
        let kind = EffectKind::from_name(name.trim()).ok_or_else(|| unknown(name.trim()))?;
        let values: Vec<f64> = vals.split(':').map(|v| v.trim().parse::<f64>().unwrap_or(f64::NAN)).collect();
        Effect::new(kind, values, kind.random_form().is_some())
    }

    /// `name=v` or `name=v1:v2`.
    pub fn label(&self) -> String {
        let v: Vec<String> = self.values.iter().map(|x| format!("{x:.4e}")).collect();
        format!("{}={}", self.kind.name(), v.join(":"))
    }

    /// Applies the effect to the layout of one realization. `course_tops_m` are the nominal
    /// course tops of the generated wall (m; used by `transverse_dip`), `rng` is that
    /// realization's effect stream (`rng_for(seed, realization, Purpose::Effect)`), used by
    /// the random forms only, so that every candidate sees the same layouts (common random
    /// numbers).
    ///
    /// # Errors
    /// [`EffectError::Geometry`] if a transformed block is not a valid convex block.
    pub fn apply(&self, layout: &mut Layout, course_tops_m: &[f64], rng: &mut ChaCha8Rng) -> Result<(), EffectError> {
        let v = &self.values;
        match self.kind {
            EffectKind::KnScale => {
                for m in &mut layout.materials {
                    m.kn *= v[0];
                    m.ks *= v[0];
                }
            }
            EffectKind::JointClosure => {
                for m in &mut layout.materials {
                    m.kn *= v[0];
                    m.closure = Closure::Hyperbolic { max_closure_m: v[1] };
                }
            }
            EffectKind::SeatingGap => {
                let g = if self.random { rng.random_range(0.0..=2.0) * v[0] } else { v[0] };
                if g > 0.0 {
                    for m in &mut layout.materials {
                        m.closure = Closure::Seating { max_gap_m: g };
                    }
                }
            }
            EffectKind::InitialLean => {
                let psi = if self.random { rng.random_range(0.0..=2.0) * v[0] } else { v[0] };
                shear_out_of_plumb(layout, psi.to_radians()).map_err(|(block, reason)| EffectError::Geometry {
                    effect: self.kind.name(),
                    block,
                    reason,
                })?;
            }
            EffectKind::EdgeRounding => {
                chamfer_pivot_edges(layout, v[0]).map_err(|(block, reason)| EffectError::Geometry {
                    effect: self.kind.name(),
                    block,
                    reason,
                })?;
            }
            EffectKind::RestraintStiffness => {
                for (_, r) in &mut layout.end_restraints {
                    *r = EndRestraint::Spring(v[0]);
                }
            }
            EffectKind::TransverseDip => {
                tilt_beds_across(layout, v[0].to_radians(), course_tops_m, rng)
                    .map_err(|(block, reason)| EffectError::Geometry { effect: self.kind.name(), block, reason })?;
            }
        }
        Ok(())
    }
}
