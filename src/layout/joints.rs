//! Joint families: the joints of a wall grouped by where they are, each with its own joint
//! properties, and the normal closure law as written in files.
//!
//! # How a joint is classified
//!
//! A contact between the table and a block is a **`base`** joint. Otherwise, a contact
//! touching a block flagged `wedge` is a **`wedge`** joint. Otherwise, when both blocks
//! carry a `course` index (every generated layout does), blocks of the same course meet at
//! a **`head`** joint and blocks of different courses at a **`bed`** joint. Blocks without a
//! course index are classified by the contact normal at detection, in the table frame: a
//! normal within 45° of the vertical is a `bed` joint, a steeper joint plane a `head` joint.
//!
//! # Properties of a family
//!
//! Each family takes any of `kn_pa_per_m`, `ks_pa_per_m` (or `kn_factor`, `ks_factor`: a
//! factor on the stiffness the family would otherwise have), `friction_deg`, `cohesion_pa`,
//! `tensile_strength_pa` and `closure`; a key not given keeps the value of the default
//! rule (the table material's joint for `base`; the material joint, or the series
//! combination of two materials, for the others). A layout without `joint_families` is the
//! default rule throughout.

use super::{invalid, Closure, Layout, LayoutError, STIFFNESS_RANGE_PA_PER_M};
use crate::math::Vec3;
use serde::{Deserialize, Serialize};

/// Range of a stiffness factor of a joint family, dimensionless.
pub const FACTOR_RANGE: (f64, f64) = (1e-3, 1e3);

/// Where a joint is in the wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointFamily {
    /// Between the table and a block (the first course's bed).
    Base,
    /// Between blocks of different courses (bed joints).
    Bed,
    /// Between blocks of the same course (vertical or steep head joints).
    Head,
    /// Touching a wedge stone.
    Wedge,
}

impl JointFamily {
    /// Every family, in the order of [`JointFamilies`].
    pub const ALL: [JointFamily; 4] = [JointFamily::Base, JointFamily::Bed, JointFamily::Head, JointFamily::Wedge];

    /// The name as written in files (`base`, `bed`, `head`, `wedge`).
    pub fn name(self) -> &'static str {
        match self {
            JointFamily::Base => "base",
            JointFamily::Bed => "bed",
            JointFamily::Head => "head",
            JointFamily::Wedge => "wedge",
        }
    }

    /// The family of a name.
    pub fn from_name(name: &str) -> Option<JointFamily> {
        JointFamily::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// The joint properties of one family as written (every key optional).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Normal stiffness Kn, Pa/m, in [1e5, 1e15].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn_pa_per_m: Option<f64>,
    /// Shear stiffness Ks, Pa/m, in [1e5, 1e15].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ks_pa_per_m: Option<f64>,
    /// Factor on the Kn of the default rule, in [1e-3, 1e3] (not with `kn_pa_per_m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn_factor: Option<f64>,
    /// Factor on the Ks of the default rule, in [1e-3, 1e3] (not with `ks_pa_per_m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ks_factor: Option<f64>,
    /// Friction angle φ, degrees, in [0, 90).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_deg: Option<f64>,
    /// Cohesion c, Pa (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion_pa: Option<f64>,
    /// Tensile strength, Pa (≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensile_strength_pa: Option<f64>,
    /// Normal closure law.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closure: Option<Closure>,
}

/// `joint_families` of a layout (or `[joints]` of a wall): the families given their own
/// properties. Unknown family names are refused.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFamiliesSpec {
    /// Table–block joints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<JointSpec>,
    /// Bed joints between courses.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bed: Option<JointSpec>,
    /// Head joints within a course.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub head: Option<JointSpec>,
    /// Joints touching a wedge stone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wedge: Option<JointSpec>,
}

impl JointFamiliesSpec {
    /// No family given.
    pub fn is_empty(&self) -> bool {
        self.base.is_none() && self.bed.is_none() && self.head.is_none() && self.wedge.is_none()
    }

    /// The spec of a family, if given.
    pub fn get(&self, f: JointFamily) -> Option<&JointSpec> {
        match f {
            JointFamily::Base => self.base.as_ref(),
            JointFamily::Bed => self.bed.as_ref(),
            JointFamily::Head => self.head.as_ref(),
            JointFamily::Wedge => self.wedge.as_ref(),
        }
    }

    /// The spec of a family, created empty if absent.
    pub fn get_mut(&mut self, f: JointFamily) -> &mut JointSpec {
        let slot = match f {
            JointFamily::Base => &mut self.base,
            JointFamily::Bed => &mut self.bed,
            JointFamily::Head => &mut self.head,
            JointFamily::Wedge => &mut self.wedge,
        };
        slot.get_or_insert_with(JointSpec::default)
    }

    /// Checks every family; keys are named `{prefix}.{family}.{key}`.
    ///
    /// # Errors
    /// [`LayoutError::Invalid`] naming the key.
    pub fn resolve(&self, prefix: &str) -> Result<JointFamilies, LayoutError> {
        let mut out = JointFamilies::default();
        for f in JointFamily::ALL {
            if let Some(s) = self.get(f) {
                out.0[f as usize] = Some(s.resolve(&format!("{prefix}.{}", f.name()))?);
            }
        }
        Ok(out)
    }
}

/// A family's checked overrides (SI; `None` keeps the default rule's value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FamilyJoint {
    /// Kn, Pa/m.
    pub kn: Option<f64>,
    /// Ks, Pa/m.
    pub ks: Option<f64>,
    /// Factor on the default rule's Kn (1 when not given).
    pub kn_factor: f64,
    /// Factor on the default rule's Ks (1 when not given).
    pub ks_factor: f64,
    /// Friction angle φ, rad.
    pub friction: Option<f64>,
    /// Cohesion, Pa.
    pub cohesion: Option<f64>,
    /// Tensile strength, Pa.
    pub tensile_strength: Option<f64>,
    /// Normal closure law.
    pub closure: Option<Closure>,
}

/// The checked families, indexed by [`JointFamily`] (`None`: the default rule).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JointFamilies(pub [Option<FamilyJoint>; 4]);

impl JointFamilies {
    /// No family has its own properties.
    pub fn is_empty(&self) -> bool {
        self.0.iter().all(Option::is_none)
    }

    /// The overrides of a family.
    pub fn get(&self, f: JointFamily) -> Option<&FamilyJoint> {
        self.0[f as usize].as_ref()
    }
}

fn check_in(key: String, v: f64, (lo, hi): (f64, f64)) -> Result<f64, LayoutError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(invalid(key, format!("{v:e}"), &format!("must be in [{lo:e}, {hi:e}]")))
    }
}

/// A closure law's range error as the layout's error.
pub(super) fn closure_error(e: crate::closure::ClosureRangeError) -> LayoutError {
    let (lo, hi) = e.range;
    invalid(e.key, format!("{:e}", e.value), &format!("must be in [{lo:e}, {hi:e}]"))
}

impl JointSpec {
    /// Checks the values; keys are named `{prefix}.{key}`.
    ///
    /// # Errors
    /// [`LayoutError::Invalid`] naming the key.
    pub fn resolve(&self, prefix: &str) -> Result<FamilyJoint, LayoutError> {
        let k = |f: &str| format!("{prefix}.{f}");
        let both = |a: &str, b: &str| invalid(k(b), "given", &format!("give {a} or {b}, not both"));
        if self.kn_pa_per_m.is_some() && self.kn_factor.is_some() {
            return Err(both("kn_pa_per_m", "kn_factor"));
        }
        if self.ks_pa_per_m.is_some() && self.ks_factor.is_some() {
            return Err(both("ks_pa_per_m", "ks_factor"));
        }
        let stiff = |key: &str, v: Option<f64>| v.map(|v| check_in(k(key), v, STIFFNESS_RANGE_PA_PER_M)).transpose();
        let factor = |key: &str, v: Option<f64>| v.map_or(Ok(1.0), |v| check_in(k(key), v, FACTOR_RANGE));
        let non_negative = |key: &str, v: Option<f64>| {
            v.map(|v| {
                if v.is_finite() && v >= 0.0 {
                    Ok(v)
                } else {
                    Err(invalid(k(key), v, "must be a finite number >= 0"))
                }
            })
            .transpose()
        };
        let friction = match self.friction_deg {
            Some(phi) if !(phi.is_finite() && (0.0..90.0).contains(&phi)) => {
                return Err(invalid(k("friction_deg"), phi, "must be in [0, 90) degrees"))
            }
            other => other.map(f64::to_radians),
        };
        Ok(FamilyJoint {
            kn: stiff("kn_pa_per_m", self.kn_pa_per_m)?,
            ks: stiff("ks_pa_per_m", self.ks_pa_per_m)?,
            kn_factor: factor("kn_factor", self.kn_factor)?,
            ks_factor: factor("ks_factor", self.ks_factor)?,
            friction,
            cohesion: non_negative("cohesion_pa", self.cohesion_pa)?,
            tensile_strength: non_negative("tensile_strength_pa", self.tensile_strength_pa)?,
            closure: self.closure.map(|c| c.check(&k("closure"))).transpose().map_err(closure_error)?,
        })
    }
}

/// Cosine of the steepest joint plane still classified `bed` by its normal (45°).
const BED_NORMAL_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

impl Layout {
    /// The family of the joint between block `a` (`None`: the table) and block `b`, whose
    /// contact normal (table frame, either sense) is `normal` (see the module doc).
    pub fn joint_family(&self, a: Option<usize>, b: usize, normal: &Vec3) -> JointFamily {
        let Some(a) = a else { return JointFamily::Base };
        let (ba, bb) = (&self.blocks[a], &self.blocks[b]);
        if ba.wedge || bb.wedge {
            return JointFamily::Wedge;
        }
        match (ba.course, bb.course) {
            (Some(ca), Some(cb)) if ca == cb => JointFamily::Head,
            (Some(_), Some(_)) => JointFamily::Bed,
            _ if normal.z.abs() >= BED_NORMAL_COS * normal.norm() => JointFamily::Bed,
            _ => JointFamily::Head,
        }
    }

    /// Checks that every family given its own properties has joints in the layout (as far
    /// as the blocks' `course` and `wedge` flags tell).
    ///
    /// # Errors
    /// [`LayoutError::Invalid`] naming `{prefix}.{family}`.
    pub(super) fn check_families_present(&self, prefix: &str) -> Result<(), LayoutError> {
        let f = &self.joint_families;
        let none = |fam: JointFamily, why: &str| Err(invalid(format!("{prefix}.{}", fam.name()), "given", why));
        if f.get(JointFamily::Wedge).is_some() && !self.blocks.iter().any(|b| b.wedge) {
            return none(JointFamily::Wedge, "the layout has no wedge stone (no block with \"wedge\": true)");
        }
        let courses: Option<Vec<usize>> = self.blocks.iter().filter(|b| !b.wedge).map(|b| b.course).collect();
        if let Some(c) = courses {
            let mut distinct = c.clone();
            distinct.sort_unstable();
            distinct.dedup();
            if f.get(JointFamily::Bed).is_some() && distinct.len() < 2 {
                return none(JointFamily::Bed, "the layout has one course only: it has no bed joint");
            }
            if f.get(JointFamily::Head).is_some() && distinct.len() == c.len() {
                return none(JointFamily::Head, "every course is one block: the layout has no head joint");
            }
        }
        Ok(())
    }

    /// The first joint rule whose faces crush ([`Closure::Crushing`], what the effect
    /// `toe_crushing` sets): named as the layout file names it, `material NAME` or `joint
    /// family NAME`, with its strength fc (Pa); `None` when no joint crushes. The rigid
    /// methods (limit analysis, nscd) have no crushing law and refuse a layout with one
    /// rather than analyse the wall without it.
    pub fn crushing_joint(&self) -> Option<(String, f64)> {
        let material = self.materials.iter().enumerate().find_map(|(i, m)| match m.closure {
            Closure::Crushing(c) => {
                let name = self.material_names.get(i).map_or_else(|| format!("#{i}"), Clone::clone);
                Some((format!("material {name}"), c.strength_pa))
            }
            _ => None,
        });
        material
            .or_else(|| {
                JointFamily::ALL.into_iter().find_map(|f| match self.joint_families.get(f).and_then(|j| j.closure) {
                    Some(Closure::Crushing(c)) => Some((format!("joint family {}", f.name()), c.strength_pa)),
                    _ => None,
                })
            })
            .or_else(|| {
                self.blocks.iter().find_map(|b| match b.bed_closure {
                    Some(Closure::Crushing(c)) => Some((format!("the bed of block {}", b.id), c.strength_pa)),
                    _ => None,
                })
            })
    }

    /// Every normal closure law of the layout with the stiffness it goes with (Pa/m): the
    /// materials' and the families' (a family with no stiffness of its own is taken with
    /// the smallest material stiffness times its factor), and the blocks' own beds' (with
    /// the smallest stiffness of the block's material and the families').
    pub fn closure_laws(&self) -> Vec<(f64, Closure)> {
        let mut out: Vec<(f64, Closure)> = self.materials.iter().map(|m| (m.kn, m.closure)).collect();
        let kn_min = self.materials.iter().map(|m| m.kn).fold(f64::INFINITY, f64::min);
        for fj in self.joint_families.0.iter().flatten() {
            let kn = fj.kn.unwrap_or(kn_min * fj.kn_factor);
            match fj.closure {
                Some(c) => out.push((kn, c)),
                None => out.extend(self.materials.iter().map(|m| (kn, m.closure))),
            }
        }
        for b in &self.blocks {
            if let Some(c) = b.bed_closure {
                let kn = self.joint_families.0.iter().flatten().fold(self.materials[b.material].kn, |k, fj| {
                    k.min(fj.kn.unwrap_or(self.materials[b.material].kn * fj.kn_factor))
                });
                out.push((kn, c));
            }
        }
        out
    }

    /// The block whose bed the joint between block `a` (`None`: the table) and block `b`
    /// of family `family` is, if it is one ([`crate::layout::Block::bed_closure`]): `b` on
    /// the table; of a `bed` joint, the block of the higher course, or without course
    /// indices the one whose centroid (as built) is higher, `centroid_z(i)` giving block
    /// `i`'s (m); none for the other families.
    pub fn bed_owner(
        &self,
        a: Option<usize>,
        b: usize,
        family: JointFamily,
        centroid_z: impl Fn(usize) -> f64,
    ) -> Option<usize> {
        match (family, a) {
            (JointFamily::Base, _) | (_, None) => Some(b),
            (JointFamily::Bed, Some(a)) => {
                let (ba, bb) = (&self.blocks[a], &self.blocks[b]);
                Some(match (ba.course, bb.course) {
                    (Some(ca), Some(cb)) if ca != cb => {
                        if ca > cb {
                            a
                        } else {
                            b
                        }
                    }
                    _ => {
                        if centroid_z(a) > centroid_z(b) {
                            a
                        } else {
                            b
                        }
                    }
                })
            }
            _ => None,
        }
    }
}
