//! The wall description: a TOML file (`version = 1`, strict) read into a raw [`WallSpec`]
//! and checked into a [`Wall`] by [`WallSpec::resolve`]. Every error names the file and the
//! key. See the [module doc](super) for the format and every default.

use super::distribution::{valid_name, Distribution, DistributionSource, DistributionSpec, Unit};
use super::GeneratorError;
use crate::layout::{BaseSliding, MaterialSpec};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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

/// `[scatter]`: material property scatter per block (each block gets its own material; the
/// joint between two blocks combines them as the layout file says: series stiffness, the
/// smaller friction angle). Drawn from the `Material` stream of the realization, so the
/// geometry does not change when scatter is switched on.
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
    /// Materials (the layout file's material fields).
    pub materials: Vec<MaterialSpec>,
    /// Base and end restraints.
    #[serde(default)]
    pub restraints: RestraintsSpec,
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

/// The checked arrangement.
#[derive(Debug, Clone, PartialEq)]
pub enum Arrangement {
    /// Head joints aligned through all courses.
    Continuous,
    /// Running bond.
    Discontinuous {
        /// Offset of every other course, fraction of the block length.
        overlap: f64,
    },
    /// Irregular.
    Irregular(Box<Irregular>),
}

/// The checked irregular-arrangement parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Irregular {
    /// Dip of the bed-joint segments, degrees (unit `deg`).
    pub dip: Distribution,
    /// Thinnest wedge kept, m.
    pub min_wedge_thickness: f64,
    /// Narrowest wedge kept (x), m.
    pub min_wedge_length: f64,
    /// Wedge length law (unit `m`), if gaps are split into several wedges.
    pub wedge_length: Option<Distribution>,
    /// Probability that a gap gets its wedge(s), in [0, 1].
    pub wedge_fill: f64,
}

/// Open head joints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HeadGap {
    /// Closed head joints (blocks touching).
    Closed,
    /// Every interior head joint open by this width, m.
    Width(f64),
    /// Each course's interior head joints share `fraction × L` of open width.
    VoidFraction(f64),
}

/// A checked end restraint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ends {
    /// None.
    Free,
    /// Rigid (y held) on blocks within `zone` m of either end.
    Rigid {
        /// m.
        zone: f64,
    },
    /// Spring of `stiffness` N/m per block within `zone` m of either end.
    Spring {
        /// m.
        zone: f64,
        /// N/m per block.
        stiffness: f64,
    },
}

/// Checked material scatter.
#[derive(Debug, Clone, PartialEq)]
pub struct Scatter {
    /// Factor on Kn and Ks (unit `1`).
    pub kn_factor: Option<Distribution>,
    /// Offset on φ, degrees.
    pub friction_offset: Option<Distribution>,
}

/// A checked wall description: SI units (m), dips in degrees inside their distribution.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    /// Name.
    pub name: String,
    /// The file it came from (for messages).
    pub source: PathBuf,
    /// Gravity, m/s².
    pub gravity: f64,
    /// L, m.
    pub length: f64,
    /// H, m.
    pub height: f64,
    /// B, m.
    pub base_width: f64,
    /// b, m.
    pub top_width: f64,
    /// Batter.
    pub batter: Batter,
    /// Arrangement.
    pub arrangement: Arrangement,
    /// Course height law, m.
    pub course_height: Distribution,
    /// Thinnest stone, fraction of the course's nominal height.
    pub min_thickness_fraction: f64,
    /// Block length law, m.
    pub block_length: Distribution,
    /// Shortest end piece, fraction of the mean block length.
    pub min_end_fraction: f64,
    /// Open head joints.
    pub head_gap: HeadGap,
    /// Materials (checked), in file order.
    pub materials: Vec<MaterialSpec>,
    /// Stone material name.
    pub block_material: String,
    /// Wedge material name.
    pub wedge_material: String,
    /// Table material name.
    pub table_material: String,
    /// Base course restraint.
    pub base: BaseSliding,
    /// End restraints.
    pub ends: Ends,
    /// Material scatter.
    pub scatter: Option<Scatter>,
}

impl Wall {
    /// Reads and checks a wall file, finding named distributions with
    /// [`DistributionSource::default_for`].
    ///
    /// # Errors
    /// Any [`GeneratorError`], naming the file and key.
    pub fn from_file(path: &Path) -> Result<Wall, GeneratorError> {
        Self::from_file_with(path, &DistributionSource::default_for(path))
    }

    /// Reads and checks a wall file with an explicit distribution source.
    ///
    /// # Errors
    /// Any [`GeneratorError`], naming the file and key.
    pub fn from_file_with(path: &Path, source: &DistributionSource) -> Result<Wall, GeneratorError> {
        let text =
            std::fs::read_to_string(path).map_err(|e| GeneratorError::Io { path: path.to_owned(), source: e })?;
        WallSpec::from_toml(&text, path)?.resolve(path, source)
    }

    /// y of the −y and +y faces at height z (m), table frame.
    pub fn faces_at(&self, z: f64) -> (f64, f64) {
        let (bb, tb, h) = (self.base_width, self.top_width, self.height);
        let s = z / h;
        match self.batter {
            Batter::Symmetric => {
                let half = 0.5 * bb - 0.5 * (bb - tb) * s;
                (-half, half)
            }
            Batter::VerticalNegativeY => (-0.5 * bb, 0.5 * bb - (bb - tb) * s),
            Batter::VerticalPositiveY => (-0.5 * bb + (bb - tb) * s, 0.5 * bb),
        }
    }

    /// Width of the section at height z, m: `B − (B − b) z / H`.
    pub fn width_at(&self, z: f64) -> f64 {
        self.base_width - (self.base_width - self.top_width) * z / self.height
    }

    /// Area of the cross-section, m²: `(B + b) H / 2`.
    pub fn section_area(&self) -> f64 {
        0.5 * (self.base_width + self.top_width) * self.height
    }

    /// Volume of the envelope, m³: section area × L.
    pub fn envelope_volume(&self) -> f64 {
        self.section_area() * self.length
    }

    /// The stated void fraction: `void_fraction` if given, else 0 (micro-gaps of a given
    /// width leave a void the generator reports but the description does not state).
    pub fn stated_void_fraction(&self) -> f64 {
        match self.head_gap {
            HeadGap::VoidFraction(f) => f,
            _ => 0.0,
        }
    }
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

    /// Checks every value and builds the [`Wall`]. `path` names the file in errors;
    /// `source` finds named distributions.
    ///
    /// # Errors
    /// The first problem found, as [`GeneratorError::Invalid`] or
    /// [`GeneratorError::UnknownDistribution`] naming `path` and the key.
    pub fn resolve(&self, path: &Path, source: &DistributionSource) -> Result<Wall, GeneratorError> {
        let inv = |key: &str, value: String, reason: String| GeneratorError::Invalid {
            path: path.to_owned(),
            key: key.into(),
            value,
            reason,
        };
        if self.version != WALL_VERSION {
            return Err(inv("version", self.version.to_string(), "this drystone reads wall version 1".into()));
        }
        let pos = |key: &str, v: f64| -> Result<f64, GeneratorError> {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(inv(key, v.to_string(), "must be a finite number > 0".into()))
            }
        };
        let gravity = pos("gravity_m_per_s2", self.gravity_m_per_s2)?;
        let g = &self.geometry;
        let length = pos("geometry.length_m", g.length_m)?;
        let height = pos("geometry.height_m", g.height_m)?;
        let base_width = pos("geometry.base_width_m", g.base_width_m)?;
        let top_width = pos("geometry.top_width_m", g.top_width_m)?;
        if top_width > base_width {
            return Err(inv(
                "geometry.top_width_m",
                top_width.to_string(),
                format!("must not exceed geometry.base_width_m = {base_width} (b ≤ B)"),
            ));
        }

        let resolver = Resolver { spec: self, path, source };

        // Courses.
        let course_height =
            resolver.size_law(&self.courses.height_m, "courses.height_m", "course height", "wall height H", height)?;
        let min_thickness_fraction = fraction(
            path,
            "courses.min_thickness_fraction",
            self.courses.min_thickness_fraction.unwrap_or(DEFAULT_MIN_THICKNESS_FRACTION),
            false,
            false,
        )?;

        // Blocks.
        let block_length =
            resolver.size_law(&self.blocks.length_m, "blocks.length_m", "block length", "wall length L", length)?;
        let min_end_fraction = fraction(
            path,
            "blocks.min_end_fraction",
            self.blocks.min_end_fraction.unwrap_or(DEFAULT_MIN_END_FRACTION),
            false,
            true,
        )?;

        // Arrangement.
        let a = &self.arrangement;
        let kind_name = format!("{:?}", a.kind).to_lowercase();
        let only = |key: &str, given: bool, for_kind: &str| -> Result<(), GeneratorError> {
            if given {
                Err(inv(
                    &format!("arrangement.{key}"),
                    "(given)".into(),
                    format!("only for kind = \"{for_kind}\", not \"{kind_name}\""),
                ))
            } else {
                Ok(())
            }
        };
        let arrangement = match a.kind {
            ArrangementKind::Continuous | ArrangementKind::Discontinuous => {
                only("dip_deg", a.dip_deg.is_some(), "irregular")?;
                only("min_wedge_thickness_m", a.min_wedge_thickness_m.is_some(), "irregular")?;
                only("min_wedge_length_m", a.min_wedge_length_m.is_some(), "irregular")?;
                only("wedge_length_m", a.wedge_length_m.is_some(), "irregular")?;
                only("wedge_fill", a.wedge_fill.is_some(), "irregular")?;
                if !block_length.is_fixed() {
                    return Err(inv(
                        "blocks.length_m",
                        describe(&self.blocks.length_m, &block_length),
                        format!("the {kind_name} arrangement needs a fixed block length (a number)"),
                    ));
                }
                if a.kind == ArrangementKind::Continuous {
                    only("overlap", a.overlap.is_some(), "discontinuous")?;
                    Arrangement::Continuous
                } else {
                    let overlap =
                        fraction(path, "arrangement.overlap", a.overlap.unwrap_or(DEFAULT_OVERLAP), false, false)?;
                    Arrangement::Discontinuous { overlap }
                }
            }
            ArrangementKind::Irregular => {
                only("overlap", a.overlap.is_some(), "discontinuous")?;
                let dip = match &a.dip_deg {
                    Some(r) => resolver.dist(r, "arrangement.dip_deg", Unit::Deg)?,
                    None => Distribution::uniform("default_dip", DEFAULT_DIP_DEG.0, DEFAULT_DIP_DEG.1, Unit::Deg),
                };
                let (lo, hi) = dip.support();
                if !(lo > -90.0 && hi < 90.0) {
                    return Err(inv(
                        "arrangement.dip_deg",
                        describe(a.dip_deg.as_ref().unwrap_or(&DistRef::Value(lo)), &dip),
                        format!(
                            "dips range over [{lo}, {hi}] degrees; they must lie inside (-90, 90) \
                             (use a bounded law: uniform, truncated_normal or fixed)"
                        ),
                    ));
                }
                let h_mean = course_height.mean();
                let l_mean = block_length.mean();
                let min_wedge_thickness = match a.min_wedge_thickness_m {
                    Some(v) => nonneg(path, "arrangement.min_wedge_thickness_m", v)?,
                    None => DEFAULT_MIN_WEDGE_THICKNESS_FRACTION * h_mean,
                };
                let min_wedge_length = match a.min_wedge_length_m {
                    Some(v) => nonneg(path, "arrangement.min_wedge_length_m", v)?,
                    None => DEFAULT_MIN_WEDGE_LENGTH_FRACTION * l_mean,
                };
                let wedge_length = match &a.wedge_length_m {
                    Some(r) => {
                        let d = resolver.dist(r, "arrangement.wedge_length_m", Unit::M)?;
                        resolver.positive_support(&d, "arrangement.wedge_length_m")?;
                        Some(d)
                    }
                    None => None,
                };
                let wedge_fill = fraction(path, "arrangement.wedge_fill", a.wedge_fill.unwrap_or(1.0), true, true)?;
                Arrangement::Irregular(Box::new(Irregular {
                    dip,
                    min_wedge_thickness,
                    min_wedge_length,
                    wedge_length,
                    wedge_fill,
                }))
            }
        };

        // Head joints.
        let head_gap = match (self.head_joints.micro_gap_m, self.head_joints.void_fraction) {
            (Some(_), Some(_)) => {
                return Err(inv(
                    "head_joints.void_fraction",
                    "(given)".into(),
                    "give either head_joints.micro_gap_m or head_joints.void_fraction, not both".into(),
                ))
            }
            (Some(w), None) => {
                let w = nonneg(path, "head_joints.micro_gap_m", w)?;
                let (lmin, _) = block_length.support();
                let shortest = (min_end_fraction * block_length.mean()).min(lmin.max(0.0).max(1e-300));
                if w >= 0.5 * shortest {
                    return Err(inv(
                        "head_joints.micro_gap_m",
                        w.to_string(),
                        format!("must be smaller than half the shortest block piece ({shortest} m)"),
                    ));
                }
                if w == 0.0 {
                    HeadGap::Closed
                } else {
                    HeadGap::Width(w)
                }
            }
            (None, Some(f)) => {
                if !(f.is_finite() && (0.0..0.5).contains(&f)) {
                    return Err(inv("head_joints.void_fraction", f.to_string(), "must be in [0, 0.5)".into()));
                }
                if f == 0.0 {
                    HeadGap::Closed
                } else {
                    HeadGap::VoidFraction(f)
                }
            }
            (None, None) => HeadGap::Closed,
        };

        // Materials.
        if self.materials.is_empty() {
            return Err(inv("materials", "[]".into(), "at least one material is needed".into()));
        }
        let mut names = BTreeMap::new();
        for m in &self.materials {
            if names.insert(m.name.clone(), ()).is_some() {
                return Err(inv(
                    &format!("materials[{}].name", m.name),
                    m.name.clone(),
                    "duplicate material name".into(),
                ));
            }
            if m.name.contains('~') {
                return Err(inv(
                    &format!("materials[{}].name", m.name),
                    m.name.clone(),
                    "'~' is reserved for scattered materials".into(),
                ));
            }
            m.resolve().map_err(|e| match e {
                crate::layout::LayoutError::Invalid { key, value, reason } => {
                    GeneratorError::Invalid { path: path.to_owned(), key, value, reason }
                }
                other => GeneratorError::Invalid {
                    path: path.to_owned(),
                    key: format!("materials[{}]", m.name),
                    value: String::new(),
                    reason: other.to_string(),
                },
            })?;
        }
        let mat = |key: &str, v: &Option<String>, default: &str| -> Result<String, GeneratorError> {
            let n = v.clone().unwrap_or_else(|| default.to_string());
            if names.contains_key(&n) {
                Ok(n)
            } else {
                Err(inv(
                    key,
                    n,
                    format!("no such material (have: {})", names.keys().cloned().collect::<Vec<_>>().join(", ")),
                ))
            }
        };
        let block_material = mat("blocks.material", &self.blocks.material, &self.materials[0].name)?;
        let wedge_material = mat("blocks.wedge_material", &self.blocks.wedge_material, &block_material)?;
        let table_material = mat("restraints.table_material", &self.restraints.table_material, &block_material)?;

        // Ends.
        let e = &self.restraints.ends;
        let zone = |z: Option<f64>| -> Result<f64, GeneratorError> {
            match z {
                None => Err(inv(
                    "restraints.ends.zone_m",
                    "missing".into(),
                    "rigid and spring ends need a zone in m".into(),
                )),
                Some(z) if z.is_finite() && z > 0.0 && z < 0.5 * length => Ok(z),
                Some(z) => {
                    Err(inv("restraints.ends.zone_m", z.to_string(), format!("must be in (0, L/2 = {})", 0.5 * length)))
                }
            }
        };
        let ends = match e.kind {
            EndKind::Free => {
                if e.zone_m.is_some() || e.stiffness_n_per_m.is_some() {
                    return Err(inv(
                        "restraints.ends.kind",
                        "free".into(),
                        "free ends take no zone_m or stiffness_n_per_m".into(),
                    ));
                }
                Ends::Free
            }
            EndKind::Rigid => {
                if let Some(s) = e.stiffness_n_per_m {
                    return Err(inv(
                        "restraints.ends.stiffness_n_per_m",
                        s.to_string(),
                        "a rigid restraint takes no stiffness".into(),
                    ));
                }
                Ends::Rigid { zone: zone(e.zone_m)? }
            }
            EndKind::Spring => {
                let stiffness = match e.stiffness_n_per_m {
                    Some(s) => pos("restraints.ends.stiffness_n_per_m", s)?,
                    None => {
                        return Err(inv(
                            "restraints.ends.stiffness_n_per_m",
                            "missing".into(),
                            "a spring needs a stiffness in N/m".into(),
                        ))
                    }
                };
                Ends::Spring { zone: zone(e.zone_m)?, stiffness }
            }
        };

        // Scatter.
        let scatter = match &self.scatter {
            None => None,
            Some(s) => {
                let kn_factor = match &s.kn_factor {
                    Some(r) => {
                        let d = resolver.dist(r, "scatter.kn_factor", Unit::One)?;
                        resolver.positive_support(&d, "scatter.kn_factor")?;
                        Some(d)
                    }
                    None => None,
                };
                let friction_offset = match &s.friction_offset_deg {
                    Some(r) => {
                        let d = resolver.dist(r, "scatter.friction_offset_deg", Unit::Deg)?;
                        let (lo, hi) = d.support();
                        for m in &self.materials {
                            if !(m.friction_deg + lo >= 0.0 && m.friction_deg + hi < 90.0) {
                                return Err(inv(
                                    "scatter.friction_offset_deg",
                                    describe(r, &d),
                                    format!(
                                        "offsets in [{lo}, {hi}] take materials[{}].friction_deg = {} outside [0, 90)",
                                        m.name, m.friction_deg
                                    ),
                                ));
                            }
                        }
                        Some(d)
                    }
                    None => None,
                };
                Some(Scatter { kn_factor, friction_offset })
            }
        };

        // Inline distributions that are never used are still checked.
        for (n, d) in &self.distributions {
            if !valid_name(n) {
                return Err(inv(&format!("distributions.{n}"), n.clone(), "names are [A-Za-z0-9_-]+".into()));
            }
            d.resolve(n, path, &format!("distributions.{n}."))?;
        }

        Ok(Wall {
            name: if self.name.is_empty() {
                path.file_stem().and_then(|s| s.to_str()).unwrap_or("wall").to_string()
            } else {
                self.name.clone()
            },
            source: path.to_owned(),
            gravity,
            length,
            height,
            base_width,
            top_width,
            batter: g.batter,
            arrangement,
            course_height,
            min_thickness_fraction,
            block_length,
            min_end_fraction,
            head_gap,
            materials: self.materials.clone(),
            block_material,
            wedge_material,
            table_material,
            base: self.restraints.base,
            ends,
            scatter,
        })
    }
}

fn describe(r: &DistRef, d: &Distribution) -> String {
    match r {
        DistRef::Value(v) => v.to_string(),
        DistRef::Name(n) => format!("{n:?} ({:?})", d.law),
    }
}

fn fraction(path: &Path, key: &str, v: f64, zero_ok: bool, one_ok: bool) -> Result<f64, GeneratorError> {
    let ok = v.is_finite() && (if zero_ok { v >= 0.0 } else { v > 0.0 }) && (if one_ok { v <= 1.0 } else { v < 1.0 });
    if ok {
        Ok(v)
    } else {
        Err(GeneratorError::Invalid {
            path: path.to_owned(),
            key: key.into(),
            value: v.to_string(),
            reason: format!("must be in {}0, 1{}", if zero_ok { "[" } else { "(" }, if one_ok { "]" } else { ")" }),
        })
    }
}

fn nonneg(path: &Path, key: &str, v: f64) -> Result<f64, GeneratorError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(GeneratorError::Invalid {
            path: path.to_owned(),
            key: key.into(),
            value: v.to_string(),
            reason: "must be a finite number >= 0".into(),
        })
    }
}

struct Resolver<'a> {
    spec: &'a WallSpec,
    path: &'a Path,
    source: &'a DistributionSource,
}

impl Resolver<'_> {
    /// Resolves a number or a name to a distribution of the expected unit.
    fn dist(&self, r: &DistRef, key: &str, unit: Unit) -> Result<Distribution, GeneratorError> {
        let d = match r {
            DistRef::Value(v) => {
                if !v.is_finite() {
                    return Err(GeneratorError::Invalid {
                        path: self.path.to_owned(),
                        key: key.into(),
                        value: v.to_string(),
                        reason: "must be finite".into(),
                    });
                }
                return Ok(Distribution::fixed(*v, unit));
            }
            DistRef::Name(name) => {
                if !valid_name(name) {
                    return Err(GeneratorError::Invalid {
                        path: self.path.to_owned(),
                        key: key.into(),
                        value: format!("{name:?}"),
                        reason: "distribution names are [A-Za-z0-9_-]+".into(),
                    });
                }
                if let Some(inline) = self.spec.distributions.get(name) {
                    inline.resolve(name, self.path, &format!("distributions.{name}."))?
                } else if let Some(file) = self.source.find(name) {
                    DistributionSpec::from_file(&file)?.resolve(name, &file, "")?
                } else {
                    let mut available: Vec<String> = self.spec.distributions.keys().cloned().collect();
                    available.extend(self.source.available());
                    return Err(GeneratorError::UnknownDistribution {
                        path: self.path.to_owned(),
                        key: key.into(),
                        name: name.clone(),
                        searched: self.source.dirs.clone(),
                        available,
                    });
                }
            }
        };
        if d.unit != unit {
            return Err(GeneratorError::Invalid {
                path: self.path.to_owned(),
                key: key.into(),
                value: format!("{:?}", d.name),
                reason: format!("distribution {} has unit {}, this key needs {}", d.name, d.unit, unit),
            });
        }
        Ok(d)
    }

    /// A block-size law in m: positive support, mean not larger than `limit` m (the wall
    /// dimension `limit_name`).
    fn size_law(
        &self,
        r: &DistRef,
        key: &str,
        what: &str,
        limit_name: &str,
        limit: f64,
    ) -> Result<Distribution, GeneratorError> {
        let d = self.dist(r, key, Unit::M)?;
        self.positive_support(&d, key)?;
        if d.mean() > limit {
            return Err(GeneratorError::Invalid {
                path: self.path.to_owned(),
                key: key.into(),
                value: describe(r, &d),
                reason: format!("{what} (mean {}) larger than the {limit_name} = {limit} m", d.mean()),
            });
        }
        Ok(d)
    }

    fn positive_support(&self, d: &Distribution, key: &str) -> Result<(), GeneratorError> {
        let (lo, _) = d.support();
        if lo > 0.0 || (lo == 0.0 && matches!(d.law, super::distribution::Law::Lognormal { .. })) {
            Ok(())
        } else {
            Err(GeneratorError::Invalid {
                path: self.path.to_owned(),
                key: key.into(),
                value: format!("{} ({:?})", d.name, d.law),
                reason: format!(
                    "must be > 0{}",
                    if lo.is_finite() {
                        String::new()
                    } else {
                        " (a normal law is unbounded; use truncated_normal or lognormal)".into()
                    }
                ),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(batter: &str) -> Wall {
        let text = format!(
            "version = 1\n[geometry]\nlength_m = 2.0\nheight_m = 1.0\nbase_width_m = 0.5\ntop_width_m = 0.2\n\
             batter = \"{batter}\"\n[arrangement]\nkind = \"continuous\"\n[courses]\nheight_m = 0.25\n\
             [blocks]\nlength_m = 0.5\n[[materials]]\nname = \"m\"\ndensity_kg_per_m3 = 2000\n\
             kn_pa_per_m = 1e8\nks_pa_per_m = 5e7\nfriction_deg = 30\n"
        );
        let p = Path::new("t.toml");
        WallSpec::from_toml(&text, p).unwrap().resolve(p, &DistributionSource::default()).unwrap()
    }

    #[test]
    fn faces_follow_the_batter() {
        let w = wall("symmetric");
        assert_eq!(w.faces_at(0.0), (-0.25, 0.25));
        let (a, b) = w.faces_at(1.0);
        assert!((a + 0.1).abs() < 1e-15 && (b - 0.1).abs() < 1e-15);
        let w = wall("vertical_negative_y");
        for z in [0.0, 0.3, 1.0] {
            let (a, b) = w.faces_at(z);
            assert_eq!(a, -0.25);
            assert!((b - a - w.width_at(z)).abs() < 1e-15);
        }
        let w = wall("vertical_positive_y");
        for z in [0.0, 0.3, 1.0] {
            let (a, b) = w.faces_at(z);
            assert_eq!(b, 0.25);
            assert!((b - a - w.width_at(z)).abs() < 1e-15);
        }
        assert!((w.section_area() - 0.35).abs() < 1e-15);
        assert!((w.envelope_volume() - 0.7).abs() < 1e-15);
    }
}
