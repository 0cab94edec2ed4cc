//! The checked wall description: every value in range, SI units (m), named distributions
//! resolved, defaults filled in. Built by [`WallSpec::resolve`](super::WallSpec::resolve);
//! the build stages read only this.

use super::distribution::Distribution;
use super::spec::Batter;
use crate::layout::{BaseSliding, MaterialSpec};
use std::path::PathBuf;

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

/// The checked section: how the blocks are laid across the thickness.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Section {
    /// One leaf: every block spans the whole section (default).
    #[default]
    Single,
    /// Two leaves of face stones, with hearting between them if `leaf_width` is given.
    Double {
        /// Width of each leaf from its face, m (horizontal); None: the leaves meet at the
        /// section's centre line.
        leaf_width: Option<f64>,
        /// Longest hearting piece along x, m (None: one per face stone).
        hearting_stone: Option<f64>,
        /// Through stones: spacing along a course (m) and every how many courses.
        through: Option<(f64, usize)>,
    },
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
    /// Largest initial gap of each block's bed, m (support in [0, 0.05]).
    pub bed_seating_gap: Option<Distribution>,
}

impl Scatter {
    /// Whether each block gets a material of its own (a Kn factor or a friction offset is
    /// drawn, or neither key nor a bed seating is given: an empty `[scatter]` table names
    /// one material per block, as it always has).
    pub fn per_block_materials(&self) -> bool {
        self.kn_factor.is_some() || self.friction_offset.is_some() || self.bed_seating_gap.is_none()
    }
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
    /// Joint families with their own properties (checked), written into every layout.
    pub joints: crate::layout::JointFamiliesSpec,
    /// What the wall is built of (the plausible ranges of the effects); `None`: the broad
    /// ranges.
    pub kind: Option<super::WallKind>,
    /// The section across the thickness.
    pub section: Section,
    /// A surveyed wall's trace: when set, [`generate`](super::generate) draws the wall from
    /// it ([`super::traced`]) and the course, block, arrangement and section fields above
    /// describe nothing but its scale. `None` for a wall description.
    pub traced: Option<Box<super::trace::Traced>>,
}

impl Wall {
    /// Whether `other` describes the same walls: equal in every field but the files the two
    /// were read from (`source`, the wall's and its distributions'), which only name them in
    /// messages. Two such descriptions generate the same layouts for every seed and
    /// realization (a follow-up's study, which copies the walls' files, reads the first
    /// campaign's walls so).
    pub fn same_walls(&self, other: &Wall) -> bool {
        self.without_sources() == other.without_sources()
    }

    /// A copy with every `source` path emptied.
    pub(crate) fn without_sources(&self) -> Wall {
        let mut w = self.clone();
        let clear = |d: &mut Distribution| d.source = std::path::PathBuf::new();
        w.source = std::path::PathBuf::new();
        clear(&mut w.course_height);
        clear(&mut w.block_length);
        if let Arrangement::Irregular(i) = &mut w.arrangement {
            clear(&mut i.dip);
            i.wedge_length.iter_mut().for_each(clear);
        }
        if let Some(sc) = &mut w.scatter {
            sc.kn_factor.iter_mut().for_each(clear);
            sc.friction_offset.iter_mut().for_each(clear);
            sc.bed_seating_gap.iter_mut().for_each(clear);
        }
        if let Some(t) = &mut w.traced {
            t.depth.iter_mut().for_each(clear);
        }
        w
    }

    /// y of the −y and +y faces at height z (m), table frame.
    pub fn faces_at(&self, z: f64) -> (f64, f64) {
        faces_at(self.batter, self.base_width, self.top_width, self.height, z)
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

/// y of the −y and +y faces at height z (m, table frame) of a section of width `bb` at
/// z = 0 and `tb` at z = `h`, with the `batter` (the symmetric section is centred on y = 0;
/// a vertical face is at y = ∓bb/2). Both faces are affine in z.
pub(crate) fn faces_at(batter: Batter, bb: f64, tb: f64, h: f64, z: f64) -> (f64, f64) {
    let s = z / h;
    match batter {
        Batter::Symmetric => {
            let half = 0.5 * bb - 0.5 * (bb - tb) * s;
            (-half, half)
        }
        Batter::VerticalNegativeY => (-0.5 * bb, 0.5 * bb - (bb - tb) * s),
        Batter::VerticalPositiveY => (-0.5 * bb + (bb - tb) * s, 0.5 * bb),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(batter: &str) -> Wall {
        crate::generator::test_wall(&format!(
            "version = 1\n[geometry]\nlength_m = 2.0\nheight_m = 1.0\nbase_width_m = 0.5\ntop_width_m = 0.2\n\
             batter = \"{batter}\"\n[arrangement]\nkind = \"continuous\"\n[courses]\nheight_m = 0.25\n\
             [blocks]\nlength_m = 0.5\n"
        ))
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
