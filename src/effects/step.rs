//! The primitives of the model an effect drives ([`Step`]) and the joint properties a
//! factor multiplies ([`Property`]).

use super::Stage;
use crate::layout::JointFamily;
use serde::{Deserialize, Serialize};

/// A joint property a [`Step::JointFactor`] multiplies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Property {
    /// Kn.
    Kn,
    /// Ks.
    Ks,
    /// Kn and Ks (their ratio kept).
    Stiffness,
    /// The friction coefficient tan φ.
    Friction,
    /// The cohesion c.
    Cohesion,
}

/// One primitive of the model, driven by a parameter of the effect (named in files by
/// `parameter`; held as its index once checked).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Step {
    /// A factor on a joint property of one family (or of every joint when `family` is
    /// absent).
    JointFactor {
        /// The family; absent: every joint (the materials and every family).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        family: Option<JointFamily>,
        /// The property.
        property: Property,
        /// The parameter giving the factor.
        parameter: String,
    },
    /// A normal closure law on one family (or every joint).
    Closure {
        /// The family; absent: every joint.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        family: Option<JointFamily>,
        /// The law, by its name in files (`hyperbolic`, `seating`: a law of
        /// [`crate::closure::Closure::with_length`]).
        law: String,
        /// The parameter giving Vm or g₀, m.
        parameter: String,
    },
    /// The faces of one family (or of every joint) crushing at the compressive strength
    /// fc (MPa): the closure law [`crate::closure::Crushing`], `q = min(Kn u, fc)`; an
    /// infinite fc is the linear joint.
    Crushing {
        /// The family; absent: every joint.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        family: Option<JointFamily>,
        /// The parameter giving fc, MPa.
        parameter: String,
    },
    /// The wall sheared out of plumb by ψ (deg) towards +y.
    Lean {
        /// The parameter giving ψ, degrees.
        parameter: String,
    },
    /// Every edge of every block rounded by r (m).
    Rounding {
        /// The parameter giving r, m.
        parameter: String,
    },
    /// Bed joints dipping across the thickness, uniform in [−δ, δ] (deg) per joint.
    TransverseDip {
        /// The parameter giving δ, degrees.
        parameter: String,
    },
    /// End restraints as springs of stiffness k (N/m per block).
    RestraintSpring {
        /// The parameter giving k, N/m.
        parameter: String,
    },
    /// The end restraints replaced by a tensioned rope at each end ([`super::rope`]), with
    /// pretension T₀ (N).
    RopePretension {
        /// The parameter giving T₀, N.
        parameter: String,
    },
    /// The end restraints replaced by a tensioned rope at each end ([`super::rope`]), with axial
    /// stiffness EA (N).
    RopeStiffness {
        /// The parameter giving EA, N.
        parameter: String,
    },
    /// Dilatant (rough, interlocking) joints of one family (or of every joint): the
    /// friction angle raised by the asperity angle i (deg), φ → φ + i, capped at
    /// [`super::MAX_FRICTION_DEG`] (Patton 1966: the apparent friction of a joint whose asperities
    /// ride up at i).
    Dilatancy {
        /// The family; absent: every joint.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        family: Option<JointFamily>,
        /// The parameter giving i, degrees.
        parameter: String,
    },
    /// Fixed stops of height h_s (m) bearing on the downhill face of every block on the
    /// table ([`super::geometry::add_base_stops`]).
    BaseStop {
        /// The parameter giving h_s, m.
        parameter: String,
        /// Friction angle of the stops' joints, degrees; absent: the table's material (the
        /// joint with a block is then that material's series combination with the block's,
        /// as between any two materials).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        friction_deg: Option<f64>,
    },
    /// The table rolled by hand overshoots each stop by Δ (deg): the quasi-static tilting
    /// tests load the wall to the stop plus Δ at every 5° stop
    /// (`Layout::table_overshoot_deg`, [`crate::loading::tilt_hand::effective_tilt_deg`]).
    TableOvershoot {
        /// The parameter giving Δ, degrees.
        parameter: String,
    },
    /// The in-plane rig's vertical load applied by a jack (or tie rods) hinged `L` from the
    /// beam: the actuator carries `N u / L` more (`Layout::vertical_load_rig`).
    JackTilt {
        /// The parameter giving `1/L`, 1/m.
        parameter: String,
    },
    /// The in-plane rig's vertical load bearing on the beam through rollers or a sliding
    /// bearing of friction `μ_r`: the actuator carries `μ_r N` more, against the beam's
    /// motion (`Layout::vertical_load_rig`).
    RigFriction {
        /// The parameter giving `μ_r`.
        parameter: String,
    },
    /// The in-plane rig's vertical load leaning by β in the wall's plane: the actuator
    /// carries `N tan β` more towards +x and as much less towards −x
    /// (`Layout::vertical_load_rig`).
    JackIncline {
        /// The parameter giving `tan β` (signed).
        parameter: String,
    },
    /// A compliance in series with the in-plane test's wall: the displacement read is the
    /// beam's own plus `c V` (`Layout::vertical_load_rig`).
    SeriesCompliance {
        /// The parameter giving `c`, mm/kN (≥ 0).
        parameter: String,
    },
    /// The in-plane rig's vertical load applied `e0` along x from the beam's centroid: a
    /// moment `e0 P` on the beam (`Layout::vertical_load_rig`).
    LoadEccentricity {
        /// The parameter giving `e0`, m (signed).
        parameter: String,
    },
    /// The in-plane rig's vertical load whose point lags the beam by the share κ of its
    /// displacement (1: fixed in space): a moment `−κ P u` on the beam
    /// (`Layout::vertical_load_rig`).
    FixedLoad {
        /// The parameter giving κ, in [0, 1].
        parameter: String,
    },
    /// The in-plane test's loading beam restrained against rotation in the wall's plane by
    /// a spring `K_θ` (`Layout::vertical_load_rig`).
    BeamRestraint {
        /// The parameter giving `K_θ`, MN·m/rad (≥ 0).
        parameter: String,
    },
    /// The section split into two leaves: every block cut so that the +y leaf takes the
    /// share f (the parameter, in [0, 1)) of the section's width ([`super::geometry::split_leaves`]).
    LeafSplit {
        /// The parameter giving f, the loose (+y) leaf's share of the width.
        parameter: String,
        /// A through stone (left whole) every n stones along each course (staggered course
        /// to course); absent: none, the leaves are tied by friction only.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        through_stone_every: Option<u32>,
    },
}

impl Step {
    /// The parameter's name.
    pub fn parameter(&self) -> &str {
        match self {
            Step::JointFactor { parameter, .. }
            | Step::Closure { parameter, .. }
            | Step::Crushing { parameter, .. }
            | Step::Lean { parameter }
            | Step::Rounding { parameter }
            | Step::TransverseDip { parameter }
            | Step::RestraintSpring { parameter }
            | Step::RopePretension { parameter }
            | Step::RopeStiffness { parameter }
            | Step::BaseStop { parameter, .. }
            | Step::TableOvershoot { parameter }
            | Step::JackTilt { parameter }
            | Step::RigFriction { parameter }
            | Step::JackIncline { parameter }
            | Step::SeriesCompliance { parameter }
            | Step::LoadEccentricity { parameter }
            | Step::FixedLoad { parameter }
            | Step::BeamRestraint { parameter }
            | Step::LeafSplit { parameter, .. } => parameter,
            Step::Dilatancy { parameter, .. } => parameter,
        }
    }

    /// Whether the step acts only on the readings of a run, not on the wall's motion: the
    /// in-plane rig's terms that the readings carry (`JackTilt`, `RigFriction`,
    /// `JackIncline`: a force the displacement-controlled beam carries on top of the wall's
    /// shear; `SeriesCompliance`: a displacement read on top of the beam's). A run with
    /// such a step is a run without it read again ([`crate::protocol::Observed::reread`]).
    pub fn acts_on_readings_only(&self) -> bool {
        matches!(
            self,
            Step::JackTilt { .. } | Step::RigFriction { .. } | Step::JackIncline { .. } | Step::SeriesCompliance { .. }
        )
    }

    /// Whether the step sets one of the in-plane rig's own terms
    /// (`Layout::vertical_load_rig`, [`Step::set_rig`]): read only by the protocols that
    /// load a beam.
    pub fn on_rig(&self) -> bool {
        self.acts_on_readings_only()
            || matches!(self, Step::LoadEccentricity { .. } | Step::FixedLoad { .. } | Step::BeamRestraint { .. })
    }

    /// Why the in-plane shear–compression test does not read this step, or `None` when it
    /// does: the out-of-plane set-up's primitives (a lean across the wall, the tilting
    /// table's overshoot, end restraints and ropes, base stops, a leaf split, beds dipping
    /// across the thickness) have nothing to act on in a wall loaded in its own plane, and
    /// those that change the layout's extent across the wall would change the thickness the
    /// rig takes from it (`loading::inplane::Rig::build`), hence its vertical force.
    pub fn not_read_in_plane(&self) -> Option<&'static str> {
        match self {
            Step::Lean { .. } => Some(
                "a lean out of plumb across the wall: the test loads the wall in its own plane, and the lean would \
                 widen the layout's extent across it, from which the rig takes the wall's thickness and its vertical \
                 force",
            ),
            Step::TableOvershoot { .. } => {
                Some("the tilting table's overshoot at its stops: the test has no tilting table")
            }
            Step::RestraintSpring { .. } | Step::RopePretension { .. } | Step::RopeStiffness { .. } => {
                Some("the wall's end restraints across its plane: the in-plane rig has none")
            }
            Step::BaseStop { .. } => Some(
                "stops on the downhill face of the first course: the test's table does not tilt, and the stops would \
                 widen the layout's extent across the wall, from which the rig takes its thickness",
            ),
            Step::LeafSplit { .. } => Some(
                "a section split into leaves across its thickness: the test loads the wall in its own plane, where \
                 the leaves move together",
            ),
            Step::TransverseDip { .. } => Some(
                "bed joints dipping across the thickness: a slope across the wall, which the test, loading the wall \
                 in its own plane, does not load",
            ),
            _ => None,
        }
    }

    /// Sets the rig's term this step gives to `v` (the step's parameter value, in its
    /// unit: mm/kN for the compliance, MN·m/rad for the restraint); nothing for a step that
    /// is not one of its terms ([`Step::on_rig`]). The one place these steps enter a layout.
    pub fn set_rig(&self, rig: &mut crate::layout::VerticalLoadRig, v: f64) {
        match self {
            Step::JackTilt { .. } => rig.inverse_jack_length_per_m = v,
            Step::RigFriction { .. } => rig.friction = v,
            Step::JackIncline { .. } => rig.incline = v,
            Step::SeriesCompliance { .. } => rig.series_compliance_m_per_n = v * 1e-6,
            Step::LoadEccentricity { .. } => rig.eccentricity_m = v,
            Step::FixedLoad { .. } => rig.fixed_share = v,
            Step::BeamRestraint { .. } => rig.rotational_stiffness_nm_per_rad = v * 1e6,
            _ => {}
        }
    }

    /// Where the step enters the model.
    pub fn stage(&self) -> Stage {
        match self {
            Step::Lean { .. }
            | Step::Rounding { .. }
            | Step::TransverseDip { .. }
            | Step::BaseStop { .. }
            | Step::LeafSplit { .. } => Stage::Layout,
            Step::JointFactor { .. } | Step::Closure { .. } | Step::Crushing { .. } => Stage::JointLaw,
            Step::RestraintSpring { .. }
            | Step::RopePretension { .. }
            | Step::RopeStiffness { .. }
            | Step::TableOvershoot { .. }
            | Step::JackTilt { .. }
            | Step::RigFriction { .. }
            | Step::JackIncline { .. }
            | Step::SeriesCompliance { .. }
            | Step::LoadEccentricity { .. }
            | Step::FixedLoad { .. }
            | Step::BeamRestraint { .. } => Stage::Restraints,
            Step::Dilatancy { .. } => Stage::JointLaw,
        }
    }

    /// The family the step acts on, if it is a joint-law step on one family.
    pub fn family(&self) -> Option<JointFamily> {
        match self {
            Step::JointFactor { family, .. } | Step::Closure { family, .. } | Step::Crushing { family, .. } => *family,
            Step::Dilatancy { family, .. } => *family,
            _ => None,
        }
    }
}
