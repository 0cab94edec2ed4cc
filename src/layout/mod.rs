//! The layout file: materials, blocks, the table and the restraints of one wall model.
//!
//! A layout is JSON, strict (unknown keys are errors), versioned (`"version": 1`). It is
//! read into a raw [`LayoutSpec`] (serde) and checked into a [`Layout`] by
//! [`LayoutSpec::resolve`]: every value finite and in range, ids unique, blocks convex, no
//! block overlapping another or the table beyond [`OVERLAP_TOLERANCE_M`].
//!
//! ```json
//! {
//!   "version": 1,
//!   "name": "one block",
//!   "gravity_m_per_s2": 9.81,
//!   "materials": [
//!     {"name": "shale", "density_kg_per_m3": 2200, "kn_pa_per_m": 5e7, "ks_pa_per_m": 2.5e7,
//!      "friction_deg": 35, "cohesion_pa": 0, "tensile_strength_pa": 0}
//!   ],
//!   "table": {"material": "shale"},
//!   "blocks": [
//!     {"id": "b0", "material": "shale",
//!      "vertices": [[0,0,0],[0.3,0,0],[0.3,0.1,0],[0,0.1,0],
//!                   [0,0,0.3],[0.3,0,0.3],[0.3,0.1,0.3],[0,0.1,0.3]]}
//!   ],
//!   "restraints": {"base_sliding": "free", "ends": []}
//! }
//! ```
//!
//! Units: lengths m, density kg/m³, joint stiffness Pa/m (force per unit area per unit
//! relative displacement), stresses Pa, angles degrees (converted to radians on resolve).
//! Frame: the table frame of [`crate::geometry`] (x along the wall, y out of plane, z up; the
//! table is the plane z = 0).
//!
//! Joint properties between two blocks of different materials: normal and shear stiffness
//! are the series combination of two half-joints, `2 k₁ k₂ / (k₁ + k₂)`; friction angle,
//! cohesion and tensile strength are the smaller of the two. Between a block and the table,
//! the table material's joint properties are used as they are. The optional
//! `joint_families` give the `base`, `bed`, `head` and `wedge` joints their own properties
//! on top of that rule (see [`joints`](JointFamily) for how a joint is classified); blocks
//! may carry their `course` index and a `wedge` flag, which the generator writes.
//!
//! `restraints.ropes` holds tensioned ropes bearing on the +y face of one section
//! ([`RopeSpec`]: a tension-only taut string with a pretension; docs/rope.md).
//!
//! A material or a family may give a normal closure law:
//! `"closure": "linear"` (default), `{"hyperbolic": {"max_closure_m": 1e-3}}` (Bandis et
//! al. 1983) or `{"seating": {"max_gap_m": 1e-3}}` (uneven beds), with the parameter in
//! [`CLOSURE_RANGE_M`]. A block may give its own bed's law, `"bed_closure"` (same forms;
//! [`Block::bed_closure`]): the law of its joints with the table and the course below.

mod check;
mod joints;
mod resolve;
mod rope;

pub use crate::closure::{Closure, CLOSURE_RANGE_M};
pub use joints::{FamilyJoint, JointFamilies, JointFamiliesSpec, JointFamily, JointSpec, FACTOR_RANGE};
pub use resolve::too_soft;
pub use rope::{Rope, RopeSpec, ROPE_AXIAL_STIFFNESS_RANGE_N, ROPE_PRETENSION_RANGE_N};

use crate::geometry::{ConvexBlock, GeometryError, MassProperties};
use crate::math::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Two blocks (or a block and the table) may interpenetrate by at most this much, m.
pub const OVERLAP_TOLERANCE_M: f64 = 1e-5;

/// The fraction of a block's `own_mass` volume its convex hull may leave out (1 %): a
/// scanned stone's hull simplified to a vertex budget lies inside the stone's full hull and
/// may leave out up to this fraction of the full hull's volume, hence of the stone's (which
/// the full hull holds), so the stone's solid may stick out of its block by as much
/// (`drystone import` refuses a simplification that leaves out more,
/// `survey::HULL_VOLUME_TOLERANCE`, the same figure). See [`OwnMassSpec`].
pub const SIMPLIFIED_HULL_VOLUME_TOLERANCE: f64 = 0.01;

/// Range of a material's density, kg/m³ (from cork-light fills to the densest metals; dry
/// stone is 1,500–3,000).
pub const DENSITY_RANGE_KG_PER_M3: (f64, f64) = (100.0, 30_000.0);

/// Range of a joint's normal and shear stiffness, Pa/m (the paper's joints are 2.5e7–1.75e8;
/// rigid-limit checks use up to 1e13).
pub const STIFFNESS_RANGE_PA_PER_M: (f64, f64) = (1e5, 1e15);

/// Range of the gravitational acceleration, m/s².
pub const GRAVITY_RANGE_M_PER_S2: (f64, f64) = (0.1, 100.0);

/// Largest elastic closure of a joint under the wall's own weight, as a fraction of the
/// wall's height: `ρ g H / Kn ≤ MAX_CLOSURE_RATIO H`, i.e. `ρ g / Kn ≤ 0.01` for every
/// material (the paper's shale joints: 4e-4). Softer joints sink blocks into each other by
/// more than the rigid-block model can represent.
pub const MAX_CLOSURE_RATIO: f64 = 0.01;

/// How far a monitor point may lie outside the bounding box of its block, as a fraction of
/// the block's bounding-box diagonal.
pub const MONITOR_TOLERANCE_FRACTION: f64 = 0.05;

/// The only layout format version this build reads and writes.
pub const LAYOUT_VERSION: u32 = 1;

/// Errors in reading or checking a layout.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum LayoutError {
    /// The file could not be read.
    #[error("cannot read layout file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is not valid layout JSON (syntax, unknown key, wrong type, missing key).
    #[error("layout file {path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// serde's message, with the key and line.
        message: String,
    },
    /// A value is out of range.
    #[error("layout: {key} = {value}: {reason}")]
    Invalid {
        /// The key at fault, e.g. `materials[shale].kn_pa_per_m`.
        key: String,
        /// The value as given.
        value: String,
        /// What is wrong.
        reason: String,
    },
    /// A block's geometry is invalid.
    #[error("layout: block {id}: {source}")]
    Block {
        /// Block id.
        id: String,
        /// The cause.
        source: GeometryError,
    },
    /// A block's vertices are not those of a convex polyhedron.
    #[error(
        "layout: block {id} is not convex: vertex {index} {vertex:?} is not a vertex of the convex hull of the block's \
         vertices (drystone's blocks are convex polyhedra given by their corners; split a non-convex stone into \
         convex blocks)"
    )]
    NotConvex {
        /// Block id.
        id: String,
        /// Index of the vertex in the block's list.
        index: usize,
        /// The vertex, m.
        vertex: [f64; 3],
    },
    /// Two blocks overlap beyond the tolerance.
    #[error("layout: blocks {a} and {b} overlap by {depth_m:.3e} m (tolerance {OVERLAP_TOLERANCE_M:e} m)")]
    Overlap {
        /// First block id.
        a: String,
        /// Second block id (or `table`).
        b: String,
        /// Penetration depth, m.
        depth_m: f64,
    },
}

/// Raw layout file contents (see the module doc for the format).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LayoutSpec {
    /// Format version; must be [`LAYOUT_VERSION`].
    pub version: u32,
    /// Free-text name.
    #[serde(default)]
    pub name: String,
    /// Gravitational acceleration, m/s². Default 9.81.
    #[serde(default = "default_gravity")]
    pub gravity_m_per_s2: f64,
    /// Materials by name.
    pub materials: Vec<MaterialSpec>,
    /// The table (the plane z = 0) and the material of its joint with the blocks.
    pub table: TableSpec,
    /// The blocks.
    pub blocks: Vec<BlockSpec>,
    /// Base and end restraints. Default: base free, no end restraint.
    #[serde(default)]
    pub restraints: RestraintSpec,
    /// Points whose displacement is recorded. Default: none named; protocols add the wall's
    /// left, centre and right top points automatically.
    #[serde(default)]
    pub monitors: Vec<MonitorSpec>,
    /// Joint families with their own properties. Default: none (the material rule).
    #[serde(default, skip_serializing_if = "JointFamiliesSpec::is_empty")]
    pub joint_families: JointFamiliesSpec,
}

fn default_gravity() -> f64 {
    crate::units::STANDARD_GRAVITY
}

/// One material: block density and joint properties.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Unique name.
    pub name: String,
    /// Block density, kg/m³ (> 0). For porous walls, the effective density of the block
    /// volume modelled.
    pub density_kg_per_m3: f64,
    /// Joint normal stiffness Kn, Pa/m (> 0).
    pub kn_pa_per_m: f64,
    /// Joint shear stiffness Ks, Pa/m (> 0).
    pub ks_pa_per_m: f64,
    /// Joint friction angle φ, degrees, in [0, 90).
    pub friction_deg: f64,
    /// Joint cohesion c, Pa (≥ 0). Default 0.
    #[serde(default)]
    pub cohesion_pa: f64,
    /// Joint tensile strength, Pa (≥ 0). Default 0: no tension.
    #[serde(default)]
    pub tensile_strength_pa: f64,
    /// Normal closure law of the material's joints. Default `linear`.
    #[serde(default, skip_serializing_if = "Closure::is_linear")]
    pub closure: Closure,
}

/// The table.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// Name of the material whose joint properties the table–block joints use.
    pub material: String,
}

/// One block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// Unique id.
    pub id: String,
    /// Material name.
    pub material: String,
    /// Vertices in the table frame, m; at least 4, not coplanar, all on the convex hull.
    pub vertices: Vec<[f64; 3]>,
    /// A fixed block never moves. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fixed: bool,
    /// Course index, 0 at the base (classifies its joints as `bed` or `head`). Optional.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub course: Option<usize>,
    /// A wedge stone (its joints are `wedge` joints). Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub wedge: bool,
    /// The stone's own mass properties, when its block (the convex hull of `vertices`) is
    /// not the stone: a scanned stone's closed mesh ([`crate::geometry::mesh_mass_properties`]).
    /// Absent (the default, and not written): the block's mass properties are its hull's.
    /// See [`OwnMassSpec`] for the keys and the checks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub own_mass: Option<OwnMassSpec>,
    /// The normal closure law of the block's own bed: its joints with the table and with
    /// the blocks of a lower course (see [`Block::bed_closure`]), over the law its material
    /// and joint family give. Absent (the default, and not written): theirs. The generator
    /// writes it for a wall whose `[scatter]` draws each block's bed seating
    /// (`{"seating": {"max_gap_m": G}}`, G the block's drawn largest initial gap).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bed_closure: Option<Closure>,
}

/// A block's own mass properties per unit density (key `own_mass` of a block): the solid
/// the stone is, while its block, the contact geometry, is the convex hull of its vertices.
/// The mass is `density × volume_m3`, the inertia `density × inertia_m5`, with the
/// density of the block's material.
///
/// ```json
/// "own_mass": {"volume_m3": 4.2e-4, "centroid_m": [0.11, 0.0, 0.05],
///              "inertia_m5": [[2.1e-7, 0, 0], [0, 2.4e-7, 0], [0, 0, 1.9e-7]]}
/// ```
///
/// Checked on resolve ([`LayoutError::Invalid`] naming `blocks[ID].own_mass.KEY`): every
/// value finite; the volume positive and larger than the hull's by no more than
/// [`SIMPLIFIED_HULL_VOLUME_TOLERANCE`] of itself (a solid lies inside its convex hull, up
/// to what a hull simplified to a vertex budget may leave out; a relative 1e-9 more for
/// round-off); the centroid inside the hull;
/// the inertia symmetric with positive principal moments that satisfy the triangle
/// inequality (each at most the sum of the other two, as every solid's do).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OwnMassSpec {
    /// The stone's volume, m³.
    pub volume_m3: f64,
    /// The stone's centroid in the table frame, m.
    pub centroid_m: [f64; 3],
    /// The stone's inertia tensor about its centroid, table-frame axes, per unit density
    /// (kg·m² per kg/m³ = m⁵): `∫ (|r|² 1 − r rᵀ) dV`, r from the centroid. Rows in order
    /// x, y, z.
    pub inertia_m5: [[f64; 3]; 3],
}

impl OwnMassSpec {
    /// The spec of mass properties computed at unit density (`mass` = `volume`).
    pub fn of(mp: &MassProperties) -> Self {
        let i = &mp.inertia;
        OwnMassSpec {
            volume_m3: mp.volume,
            centroid_m: [mp.centroid.x, mp.centroid.y, mp.centroid.z],
            inertia_m5: [0, 1, 2].map(|r| [0, 1, 2].map(|c| i[(r, c)])),
        }
    }

    /// The mass properties at unit density (`mass` = `volume`, kg at 1 kg/m³).
    pub fn unit_density(&self) -> MassProperties {
        let i = &self.inertia_m5;
        MassProperties {
            volume: self.volume_m3,
            mass: self.volume_m3,
            centroid: Vec3::new(self.centroid_m[0], self.centroid_m[1], self.centroid_m[2]),
            inertia: nalgebra::Matrix3::from_fn(|r, c| i[r][c]),
        }
    }
}

/// How the base course is held on the table.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BaseSliding {
    /// Table joints follow the Coulomb law like any other joint.
    #[default]
    Free,
    /// Table joints never slip (their shear spring stays elastic): the base course is held
    /// against sliding, as by the timber stops of the source tests, but can still lift and
    /// rotate about its edges.
    Held,
}

/// Restraints.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RestraintSpec {
    /// Base course restraint. Default `free`.
    #[serde(default)]
    pub base_sliding: BaseSliding,
    /// End restraints acting in y (out of plane) on named blocks.
    #[serde(default)]
    pub ends: Vec<EndRestraintSpec>,
    /// Rope restraints: tension-only members bearing on the +y face of one section over a
    /// height band ([`RopeSpec`]). Default none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ropes: Vec<RopeSpec>,
}

/// An out-of-plane (y) restraint on a set of blocks, acting at each block's centroid.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EndRestraintSpec {
    /// Block ids restrained.
    pub blocks: Vec<String>,
    /// Rigid or spring.
    pub kind: EndRestraintKind,
    /// Spring stiffness, N/m per block (> 0), for `kind = "spring"`; absent for `rigid`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_n_per_m: Option<f64>,
}

/// Kind of end restraint.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EndRestraintKind {
    /// The block centroid cannot move in y (rotations and x, z motion free).
    Rigid,
    /// A linear spring in y between the block centroid and its initial position
    /// (a tensioned rope: bilateral, as the paper's partially restrained ends).
    Spring,
}

/// A named point fixed to a block whose displacement is recorded.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MonitorSpec {
    /// Name, e.g. `top_centre`.
    pub name: String,
    /// Block id.
    pub block: String,
    /// Point in the table frame at the reference configuration, m.
    pub point: [f64; 3],
}

/// A checked material, SI values (the DEM builds its joint law from them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Block density, kg/m³.
    pub density: f64,
    /// Joint normal stiffness Kn, Pa/m.
    pub kn: f64,
    /// Joint shear stiffness Ks, Pa/m.
    pub ks: f64,
    /// Joint friction angle φ, rad.
    pub friction: f64,
    /// Joint cohesion c, Pa.
    pub cohesion: f64,
    /// Joint tensile strength, Pa (0: no tension).
    pub tensile_strength: f64,
    /// Normal closure law. Default linear.
    pub closure: Closure,
}

/// A checked block.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Id as in the file.
    pub id: String,
    /// Index into [`Layout::materials`].
    pub material: usize,
    /// Geometry in the table frame.
    pub shape: ConvexBlock,
    /// Fixed block.
    pub fixed: bool,
    /// Course index, if the layout gives it.
    pub course: Option<usize>,
    /// A wedge stone.
    pub wedge: bool,
    /// The stone's own mass properties at unit density (volume m³, centroid m, inertia m⁵),
    /// when they are not its shape's (a scanned stone's closed mesh; [`OwnMassSpec`]);
    /// `None`: its shape's. Read them through [`Block::mass_properties`].
    pub own_mass: Option<MassProperties>,
    /// The normal closure law of the block's own bed, checked (`None`: the law of its
    /// material and joint family). The bed is every joint of the block classified `base`
    /// (the block on the table) or `bed` where the block is the upper one: the higher
    /// course index when both blocks carry one, else the higher centroid (as built). The
    /// joints of the block's top, its head joints and its wedge joints keep their law; a
    /// bed law overrides the joint family's `closure` (the bed is the block's own).
    pub bed_closure: Option<Closure>,
}

impl Block {
    /// The block's mass properties at `density` (kg/m³, its material's): volume (m³), mass
    /// (kg), centroid (m, table frame) and inertia tensor about the centroid (kg·m²,
    /// table-frame axes). Those of the stone itself when the layout gives them
    /// ([`Block::own_mass`]: a scanned stone whose block is its convex hull), else its
    /// shape's ([`ConvexBlock::mass_properties`]). Every mass, weight, inertia and centroid
    /// of a block is read through this function; the contact geometry is `shape`.
    pub fn mass_properties(&self, density: f64) -> MassProperties {
        match &self.own_mass {
            None => self.shape.mass_properties(density),
            Some(m) => MassProperties {
                volume: m.volume,
                mass: m.volume * density,
                centroid: m.centroid,
                inertia: m.inertia * density,
            },
        }
    }

    /// The block's centroid (m, table frame): that of [`Block::mass_properties`], the
    /// origin of its body frame.
    pub fn centroid(&self) -> Vec3 {
        self.mass_properties(1.0).centroid
    }
}

/// A checked end restraint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EndRestraint {
    /// y-translation of the block held at zero.
    Rigid,
    /// Linear spring in y, N/m.
    Spring(f64),
}

/// A checked monitor point.
#[derive(Debug, Clone, PartialEq)]
pub struct Monitor {
    /// Name.
    pub name: String,
    /// Block index.
    pub block: usize,
    /// Point in the table frame, m.
    pub point: Vec3,
}

/// A checked layout: what the DEM loads.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Name.
    pub name: String,
    /// Gravity magnitude, m/s².
    pub gravity: f64,
    /// Material names, in file order.
    pub material_names: Vec<String>,
    /// Materials, in file order.
    pub materials: Vec<Material>,
    /// Index of the table's material.
    pub table_material: usize,
    /// Blocks, in file order.
    pub blocks: Vec<Block>,
    /// Base restraint.
    pub base_sliding: BaseSliding,
    /// End restraints per block index (at most one per block).
    pub end_restraints: Vec<(usize, EndRestraint)>,
    /// Rope restraints, in file order.
    pub ropes: Vec<Rope>,
    /// The overshoot of each stop of a table rolled by hand, degrees (≥ 0; 0 as built from
    /// a file): the quasi-static tilting tests load the wall to the stop plus this much at
    /// every 5° stop (`loading::tilt_hand::effective_tilt_deg`). Set by the effect
    /// `table_kick`; the other protocols do not read it.
    pub table_overshoot_deg: f64,
    /// The vertical-load system of a loading beam's rig as the horizontal actuator feels it
    /// (zero as built from a file: an ideal rig). Set by the effects of the in-plane rig
    /// (`jack_tilt`, `rig_friction`, `jack_incline`, `series_compliance`,
    /// `load_eccentricity`, `fixed_vertical_load`, `beam_restraint`); read by the drivers of the protocols that load a beam (those that
    /// state `LoadingProtocol::READS_VERTICAL_LOAD_RIG`), the other protocols do not read it.
    pub vertical_load_rig: VerticalLoadRig,
    /// Monitor points.
    pub monitors: Vec<Monitor>,
    /// Joint families with their own properties.
    pub joint_families: JointFamilies,
}

/// A loading beam rig's own terms: how its vertical-load system, its bearings and its
/// measurement depart from an ideal vertical force on a beam read at the wall. All zero (as
/// built from a file): the ideal rig. `N = σ0 L t` is the applied vertical force (the
/// loading beam's weight part of it, as the rig applies it), `P = N − W_beam` the part the
/// rig's jacks apply, `u` the beam's horizontal displacement at the measuring point and
/// `u̇` the sense of its last increment.
///
/// **Terms the readings carry** (the beam's horizontal motion is imposed, so these leave
/// the wall's state as it is and move only what is read: [`VerticalLoadRig::reads_only`]):
///
/// * `inverse_jack_length_per_m` (`1/L`, 1/m, ≥ 0): a jack, or tie rods, hinged at a
///   distance `L` from the beam leans by `u / L` as the beam moves, and its force then pulls
///   the beam back by `N u / L` (the pendulum of a vertical load applied between hinges);
/// * `friction` (`μ_r`, ≥ 0): a vertical load that bears on the beam through rollers or a
///   sliding bearing resists the beam's motion by `μ_r N`;
/// * `incline` (`tan β`, signed): a vertical load whose line of action leans by β from the
///   vertical in the wall's plane pushes the beam along −x by `N tan β` (β > 0), which the
///   actuator carries in both senses: the force read is `N tan β` more towards +x and as
///   much less towards −x (an asymmetry of the two directions' peaks of `2 N tan β`);
/// * `series_compliance_m_per_n` (`c`, m/N, ≥ 0): a compliance in series with the wall
///   between the measuring point and the wall (the bedding of the base and of the beam,
///   slack in the actuator's pins, a reference frame that deflects): the displacement read
///   is the beam's own plus `c V`, V the force read.
///
/// So the force read is `V = V_wall + N (u / L + μ_r sgn(u̇) + tan β)` and the displacement
/// read `u + c V` ([`crate::loading::inplane::add_rig_force`]).
///
/// **Terms that move the wall** (the beam's drivers apply them as a moment on the beam
/// about y, `dem::RigMoment` in the DEM; with the beam's rotation held they act on the rig,
/// not on the wall):
///
/// * `eccentricity_m` (`e0`, m, signed along x): the vertical load applied `e0` from the
///   beam's centroid, a moment `e0 P` about y;
/// * `fixed_share` (`κ`, in \[0, 1\]): the vertical load's point lags the beam by the share
///   κ of its displacement (0: it follows the beam, a load through rods hinged on it or dead
///   weights; 1: it stays where it was, a jack fixed to the reaction frame bearing on the
///   beam through rollers), a moment `−κ P u_c` (u_c the centroid's displacement);
/// * `rotational_stiffness_nm_per_rad` (`K_θ`, N·m/rad, ≥ 0): the beam's rotation in the
///   wall's plane partly restrained (two jacks that do not share one pressure, guides), a
///   moment `−K_θ θ`.
///
/// Limit analysis, which has no displacement, reads the friction, the incline and the
/// eccentricity.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct VerticalLoadRig {
    /// `1/L`, 1/m: the jack's hinges `L` apart (0: no lean).
    pub inverse_jack_length_per_m: f64,
    /// `μ_r`, the bearing's friction coefficient (0: none).
    pub friction: f64,
    /// `tan β`, the vertical load's inclination in the wall's plane (0: vertical; > 0: it
    /// pushes the beam towards −x).
    #[serde(default)]
    pub incline: f64,
    /// `c`, m/N: the compliance in series with the wall (0: none).
    #[serde(default)]
    pub series_compliance_m_per_n: f64,
    /// `e0`, m: the vertical load's point along x from the beam's centroid (0: centred).
    #[serde(default)]
    pub eccentricity_m: f64,
    /// `κ`: the share of the beam's displacement by which the vertical load's point lags it
    /// (0: it follows the beam).
    #[serde(default)]
    pub fixed_share: f64,
    /// `K_θ`, N·m/rad: the beam's rotational restraint in the wall's plane (0: free).
    #[serde(default)]
    pub rotational_stiffness_nm_per_rad: f64,
}

impl VerticalLoadRig {
    /// The rig's terms that the readings carry, if any (the others zero), or `None` when
    /// they are all zero.
    pub fn reads_only(&self) -> Option<VerticalLoadRig> {
        let r = VerticalLoadRig {
            inverse_jack_length_per_m: self.inverse_jack_length_per_m,
            friction: self.friction,
            incline: self.incline,
            series_compliance_m_per_n: self.series_compliance_m_per_n,
            ..VerticalLoadRig::default()
        };
        (r != VerticalLoadRig::default()).then_some(r)
    }

    /// The rig seen in a mirror across the wall's mid-length plane (x → −x): the
    /// inclination `tan β` and the eccentricity `e0` change sign, the terms that follow the
    /// push's sense or act about the beam's own pose (the jack's lean, the bearing's
    /// friction, the series compliance, the load's lag, the restraint) do not. A push
    /// towards −x under this rig is the mirror image of a push towards +x under the
    /// mirrored one.
    pub fn mirrored(&self) -> VerticalLoadRig {
        VerticalLoadRig { incline: -self.incline, eccentricity_m: -self.eccentricity_m, ..*self }
    }

    /// Whether a term that moves the wall is set (the eccentricity, the load's lag or the
    /// rotational restraint).
    pub fn moves_wall(&self) -> bool {
        self.eccentricity_m != 0.0 || self.fixed_share != 0.0 || self.rotational_stiffness_nm_per_rad != 0.0
    }

    /// The horizontal force the actuator carries for the rig, N (along +x, the sense of the
    /// actuator's push) under the vertical force `n_n` (N): `n_n (u_m / L + μ_r sense +
    /// tan β)`, `sense` the sign of the beam's last increment (−1, 0 or +1).
    pub fn actuator_force_n(&self, n_n: f64, u_m: f64, sense: f64) -> f64 {
        n_n * (u_m * self.inverse_jack_length_per_m + self.friction * sense + self.incline)
    }
}

impl LayoutSpec {
    /// Reads a layout file (JSON).
    ///
    /// # Errors
    /// [`LayoutError::Io`] or [`LayoutError::Parse`] naming the file.
    pub fn from_file(path: &Path) -> Result<Self, LayoutError> {
        let text = std::fs::read_to_string(path).map_err(|source| LayoutError::Io { path: path.to_owned(), source })?;
        Self::from_json(&text).map_err(|e| match e {
            LayoutError::Parse { message, .. } => LayoutError::Parse { path: path.to_owned(), message },
            other => other,
        })
    }

    /// Parses layout JSON.
    ///
    /// # Errors
    /// [`LayoutError::Parse`] with serde's message (key, line and column).
    pub fn from_json(text: &str) -> Result<Self, LayoutError> {
        serde_json::from_str(text)
            .map_err(|e| LayoutError::Parse { path: PathBuf::from("<json>"), message: e.to_string() })
    }

    /// Serializes to pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

impl Layout {
    /// Reads and checks a layout file.
    ///
    /// # Errors
    /// Any [`LayoutError`], naming the file, key or block.
    pub fn from_file(path: &Path) -> Result<Self, LayoutError> {
        LayoutSpec::from_file(path)?.resolve()
    }

    /// Bounding box of all blocks as built (table frame, m): its y extent is the wall width
    /// B, its z extent the wall height H, used by the loading protocols.
    pub fn bounds(&self) -> crate::geometry::Aabb {
        crate::geometry::Aabb::from_points(self.blocks.iter().flat_map(|b| b.shape.vertices.iter()))
    }
}

/// A [`LayoutError::Invalid`] for `key` with its `value` and the `reason`.
fn invalid(key: impl Into<String>, value: impl std::fmt::Display, reason: &str) -> LayoutError {
    LayoutError::Invalid { key: key.into(), value: value.to_string(), reason: reason.into() }
}

#[cfg(test)]
mod tests;
