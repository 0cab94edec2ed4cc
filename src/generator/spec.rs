//! The wall description as written: a TOML file (`version = 1`, strict, unknown keys
//! rejected) read into a raw [`WallSpec`]. Nothing here is checked beyond its type;
//! [`WallSpec::resolve`] checks every value into a [`Wall`](super::Wall).
//! See the [module doc](super) for the format and every default.

use super::distribution::DistributionSpec;
use super::GeneratorError;
use crate::layout::{BaseSliding, JointFamiliesSpec, MaterialSpec};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The only wall-description version this build reads.
pub const WALL_VERSION: u32 = 1;

/// Default minimum thickness of a stone, fraction of its course's nominal height.
pub const DEFAULT_MIN_THICKNESS_FRACTION: f64 = 0.4;
/// Default shortest end piece of a course, fraction of the mean block length.
pub const DEFAULT_MIN_END_FRACTION: f64 = 0.25;
/// Default running-bond overlap, fraction of the block length.
pub const DEFAULT_OVERLAP: f64 = 0.5;
/// Default dip law of the irregular arrangement: uniform on [−20°, +20°] (the source paper's
/// full-scale study, §4.1).
pub const DEFAULT_DIP_DEG: (f64, f64) = (-20.0, 20.0);
/// Default thinnest wedge kept, fraction of the mean course height (thinner gaps stay open).
pub const DEFAULT_MIN_WEDGE_THICKNESS_FRACTION: f64 = 0.01;
/// Default narrowest wedge kept (along x), fraction of the mean block length.
pub const DEFAULT_MIN_WEDGE_LENGTH_FRACTION: f64 = 0.05;

/// A value given either as a plain number (a fixed value, in the key's unit) or as the name
/// of a distribution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged, expecting = "a number or the name of a distribution (a string)")]
pub enum DistRef {
    /// A fixed value.
    Value(f64),
    /// A distribution name.
    Name(String),
}

/// How the two faces lean.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Batter {
    /// Both faces lean in by (B − b)/2 over the height (default).
    #[default]
    Symmetric,
    /// The −y face is vertical (y = −B/2); the +y face takes the whole batter.
    VerticalNegativeY,
    /// The +y face is vertical (y = +B/2); the −y face takes the whole batter.
    VerticalPositiveY,
}

/// The joint arrangement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ArrangementKind {
    /// Horizontal bed joints, head joints aligned through all courses.
    Continuous,
    /// Running bond: horizontal bed joints, head joints staggered course to course.
    Discontinuous,
    /// Tilted bed-joint segments, random lengths and heights, wedge stones.
    Irregular,
}

impl ArrangementKind {
    /// The name as written in the wall file (`continuous`, `discontinuous`, `irregular`).
    pub fn name(self) -> &'static str {
        match self {
            ArrangementKind::Continuous => "continuous",
            ArrangementKind::Discontinuous => "discontinuous",
            ArrangementKind::Irregular => "irregular",
        }
    }
}

/// `[geometry]`: the wall envelope, metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometrySpec {
    /// Length L along x, m (> 0).
    pub length_m: f64,
    /// Height H, m (> 0).
    pub height_m: f64,
    /// Base width B (y extent at z = 0), m (> 0).
    pub base_width_m: f64,
    /// Top width b (y extent at z = H), m (0 < b ≤ B).
    pub top_width_m: f64,
    /// Which faces lean. Default `symmetric`.
    #[serde(default)]
    pub batter: Batter,
}

/// `[arrangement]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArrangementSpec {
    /// `continuous`, `discontinuous` or `irregular`.
    pub kind: ArrangementKind,
    /// `discontinuous` only: head-joint offset of every other course, fraction of the block
    /// length, in (0, 1). Default 0.5 (half a block).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overlap: Option<f64>,
    /// `irregular` only: dip of each bed-joint segment, degrees (number or distribution of
    /// unit `deg`, support inside (−90°, 90°)). Default uniform on [−20°, 20°].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dip_deg: Option<DistRef>,
    /// `irregular` only: gaps thinner than this stay open instead of getting a wedge, m.
    /// Default 0.01 × mean course height (which keeps the open gaps under 1 % of the volume).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_wedge_thickness_m: Option<f64>,
    /// `irregular` only: gap pieces shorter than this (along x) stay open, m. Default
    /// 0.05 × mean block length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_wedge_length_m: Option<f64>,
    /// `irregular` only: a gap longer than a drawn wedge length is filled by several wedges
    /// of (about) that length, m (number or distribution of unit `m`). Default: one wedge
    /// per gap piece.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wedge_length_m: Option<DistRef>,
    /// `irregular` only: wedge frequency, the probability that a gap (thick and long enough
    /// for a wedge) gets its wedge(s), in [0, 1]. Default 1: every such gap. Gaps left
    /// empty add to the void the generator reports (not to the stated void fraction).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wedge_fill: Option<f64>,
}

/// `[courses]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoursesSpec {
    /// Course height, m (number or distribution of unit `m`, positive support, mean ≤ H).
    pub height_m: DistRef,
    /// Thinnest stone, fraction of its course's nominal height, in (0, 1). Default 0.4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_thickness_fraction: Option<f64>,
}

/// `[blocks]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlocksSpec {
    /// Block length along x, m (number or distribution of unit `m`, positive support,
    /// mean ≤ L). `continuous` and `discontinuous` need a fixed value.
    pub length_m: DistRef,
    /// Shortest end piece of a course, fraction of the mean block length, in (0, 1].
    /// Shorter end pieces are merged into their neighbour. Default 0.25.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_end_fraction: Option<f64>,
    /// Material of the stones. Default: the first material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Material of the wedges. Default: the stones' material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wedge_material: Option<String>,
}

/// `[head_joints]`: open head joints (micro-gaps). At most one key.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeadJointsSpec {
    /// Every interior head joint open by this width, m (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub micro_gap_m: Option<f64>,
    /// Fraction of the section volume left open, in [0, 0.5): each course's interior head
    /// joints share an open width of `void_fraction × L`. In irregular walls the wedges fill
    /// under an open joint down to the course below, so the joint leaves only its own width
    /// open and the realized void is f plus the thin gaps left open (the generator reports
    /// it, `GeneratedWall::void_fraction`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub void_fraction: Option<f64>,
}

/// Kind of end restraint.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EndKind {
    /// No end restraint (default).
    #[default]
    Free,
    /// The y translation of each end block held at zero.
    Rigid,
    /// A linear spring in y on each end block.
    Spring,
}

/// `[restraints.ends]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EndsSpec {
    /// `free` (default), `rigid` or `spring`.
    #[serde(default)]
    pub kind: EndKind,
    /// Blocks (stones and wedges) reaching within this distance of either end (x < zone or
    /// x > L − zone) are restrained, m, in (0, L/2). Needed for `rigid` and `spring`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zone_m: Option<f64>,
    /// `spring` only: stiffness per restrained block, N/m (> 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_n_per_m: Option<f64>,
}

/// `[restraints]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RestraintsSpec {
    /// Base course on the table: `free` (default) or `held` (no sliding, as by timber stops).
    #[serde(default)]
    pub base: BaseSliding,
    /// Material of the table joint. Default: the stones' material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table_material: Option<String>,
    /// End restraints. Default free.
    #[serde(default)]
    pub ends: EndsSpec,
}

/// `[scatter]`: what differs between nominally equal walls, drawn per realization. The
/// material property scatter per block (`kn_factor`, `friction_offset_deg`: each block gets
/// its own material; the joint between two blocks combines them as the layout file says:
/// series stiffness, the smaller friction angle), drawn from the `Material` stream of the
/// realization, so the geometry does not change when scatter is switched on; and the
/// seating of each block's bed (`bed_seating_gap_m`), drawn from a stream of its own
/// (`Seating`), so that switching it on or off changes no other drawn number.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScatterSpec {
    /// Factor on Kn and Ks of a block's material (ratio kept), dimensionless (distribution
    /// of unit `1`, support > 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn_factor: Option<DistRef>,
    /// Added to a block's friction angle, degrees (distribution of unit `deg`; the result
    /// must stay in [0°, 90°)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_offset_deg: Option<DistRef>,
    /// The largest initial gap g₀ of each block's bed, m (number or distribution of unit
    /// `m`, support in [0, 0.05]): one draw per block, in layout order, gives the block's bed
    /// (its joints with the table or the course below) the seating law
    /// ([`crate::closure::Seating`]: initial gaps uniform in [0, g₀] that close under load,
    /// Greenwood & Williamson 1966) over its material's law (layout key `bed_closure`); a
    /// draw below 1e-6 m (the closure laws' range, [`crate::closure::CLOSURE_RANGE_M`]) is a
    /// bed seated flat, the material's law. The uneven seating of nominally equal stones,
    /// which makes nominally equal walls differ in stiffness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bed_seating_gap_m: Option<DistRef>,
}

/// What a wall is built of, as far as the plausible ranges of the model's effects depend
/// on it (the `kind` key of a wall description): the finish of its units' faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallKind {
    /// Prismatic blocks cast to size (concrete pavers, cobblestones, bricks): flat, mated
    /// faces, sharp arrises, courses of one height.
    ConcretePaver,
    /// Shaped, hammer-dressed natural stone: faces dressed by hand, beds that seat on
    /// their asperities, irregular edges.
    ShapedStone,
    /// Natural stone sawn to size (ashlar): faces flat to tenths of a millimetre, sharp
    /// arrises; the joints close and slip by tenths of a millimetre, not millimetres.
    SawnStone,
    /// Rubble: undressed field stone, beds that seat on a few points, edges as found.
    RubbleStone,
}

impl WallKind {
    /// Every kind, in order.
    pub const ALL: [WallKind; 4] =
        [WallKind::ConcretePaver, WallKind::ShapedStone, WallKind::SawnStone, WallKind::RubbleStone];

    /// The name as in files.
    pub fn name(self) -> &'static str {
        match self {
            WallKind::ConcretePaver => "concrete_paver",
            WallKind::ShapedStone => "shaped_stone",
            WallKind::SawnStone => "sawn_stone",
            WallKind::RubbleStone => "rubble_stone",
        }
    }
}

/// `[section]`: how the section is built across its thickness. Absent: one leaf of through
/// stones (every block spans the whole section).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    /// Number of leaves: 1 (every block a through stone) or 2 (double-faced: two leaves of
    /// face stones, hearting between them when `leaf_width_m` is given).
    pub leaves: u32,
    /// `leaves = 2` only: width of each leaf, m, measured horizontally (y) from its own
    /// face and parallel to it (each leaf follows its face's batter); the hearting fills the
    /// rest of the section (B − 2w at the base, b − 2w at the top, so 2w < b). Default: no
    /// hearting, the two leaves meet at the section's centre line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub leaf_width_m: Option<f64>,
    /// With `leaf_width_m`: the hearting (fill between the leaves) is cut along x into
    /// pieces of equal length at most this long, m (> 0). Default: one hearting piece per
    /// face stone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hearting_stone_m: Option<f64>,
    /// `leaves = 2` only: spacing of the through stones along a course, m (> 0): in a
    /// course with through stones, the stone over each point `(j + ½) s` (shifted by `s/2`
    /// in every other such course) spans the whole section. Default: no through stones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub through_stone_spacing_m: Option<f64>,
    /// With `through_stone_spacing_m`: through stones in every n-th course, from the base
    /// course (n ≥ 1). Default 1 (every course).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub through_stone_every_courses: Option<u32>,
}

/// Raw wall description (see the module doc of [`super`] for the format).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Format version; must be [`WALL_VERSION`].
    pub version: u32,
    /// Free-text name; the layout is named after it.
    #[serde(default)]
    pub name: String,
    /// Free text: what the wall models and where its numbers come from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// What the wall is built of (`kind = "concrete_paver" | "shaped_stone"`): selects the
    /// plausible ranges the discrepancy analysis searches the effects' parameters within
    /// ([`crate::effects::ParamDef::range_for`]). Default none: the broad ranges.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<WallKind>,
    /// Gravity, m/s². Default 9.81.
    #[serde(default = "default_gravity")]
    pub gravity_m_per_s2: f64,
    /// Envelope.
    pub geometry: GeometrySpec,
    /// Joint arrangement.
    pub arrangement: ArrangementSpec,
    /// Courses.
    pub courses: CoursesSpec,
    /// Blocks.
    pub blocks: BlocksSpec,
    /// Open head joints. Default closed.
    #[serde(default)]
    pub head_joints: HeadJointsSpec,
    /// How the section is built across its thickness. Default: one leaf of through stones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<SectionSpec>,
    /// Materials (the layout file's material fields).
    pub materials: Vec<MaterialSpec>,
    /// Base and end restraints.
    #[serde(default)]
    pub restraints: RestraintsSpec,
    /// Joint families with their own properties (`[joints.base]`, `[joints.bed]`,
    /// `[joints.head]`, `[joints.wedge]`; the keys of a layout's `joint_families`). Default
    /// none: the material rule.
    #[serde(default, skip_serializing_if = "JointFamiliesSpec::is_empty")]
    pub joints: JointFamiliesSpec,
    /// Material scatter. Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scatter: Option<ScatterSpec>,
    /// Inline distributions by name (looked up before `distributions/`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub distributions: BTreeMap<String, DistributionSpec>,
}

fn default_gravity() -> f64 {
    crate::units::STANDARD_GRAVITY
}

impl WallSpec {
    /// Parses TOML; `path` names the file in errors.
    ///
    /// # Errors
    /// [`GeneratorError::Parse`] with toml's message (key, line and column).
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, GeneratorError> {
        toml::from_str(text).map_err(|e| GeneratorError::Parse { path: path.to_owned(), message: e.to_string() })
    }

    /// Serializes to TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }
}
