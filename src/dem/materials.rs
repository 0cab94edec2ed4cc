//! The joint law of a layout's joints: the layout's SI material values and joint families
//! as the [`JointParams`] of the contact law.

use super::contact::law::{JointParams, TensionCutoff};
use crate::layout::{BaseSliding, FamilyJoint, JointFamily, Layout, Material};
use crate::math::Vec3;

/// The joint law of a material's joints (the layout's SI values).
pub fn joint_of(m: &Material) -> JointParams {
    JointParams::coulomb(m.kn, m.ks, m.friction, m.cohesion, m.tensile_strength).with_closure(m.closure)
}

/// The joint between blocks of materials `m1` and `m2` of a layout: the material's own, or
/// the series combination of two half-joints (see [`JointParams::combine`]).
pub fn joint_between(layout: &Layout, m1: usize, m2: usize) -> JointParams {
    let j1 = joint_of(&layout.materials[m1]);
    if m1 == m2 {
        j1
    } else {
        j1.combine(&joint_of(&layout.materials[m2]))
    }
}

/// `rule` with a family's overrides.
fn with_family(rule: JointParams, f: &FamilyJoint) -> JointParams {
    let phi = f.friction.unwrap_or(rule.phi);
    JointParams {
        kn: f.kn.unwrap_or(rule.kn * f.kn_factor),
        ks: f.ks.unwrap_or(rule.ks * f.ks_factor),
        phi,
        tan_phi: phi.tan(),
        cohesion: f.cohesion.unwrap_or(rule.cohesion),
        tension: f.tensile_strength.map_or(rule.tension, TensionCutoff::from_strength),
        closure: f.closure.unwrap_or(rule.closure),
        can_slip: rule.can_slip,
    }
}

/// The joint law of every contact a layout can make: the material rule (the table
/// material's joint for the table; the material joint or the series combination between
/// blocks), with the layout's joint families on top, and a block's own bed law
/// ([`crate::layout::Block::bed_closure`]) on its bed. Built once per simulation; looked
/// up at every contact detection.
#[derive(Debug, Clone)]
pub struct JointTable {
    table: JointParams,
    pairs: Vec<Vec<JointParams>>,
    block_material: Vec<usize>,
    /// The layout itself when it has joint families or a block with its own bed law
    /// (classification needs its blocks).
    families: Option<Box<Layout>>,
    /// Each block's centroid height as built, m, when a block has its own bed law (which
    /// block of a bed joint without course indices is the upper one); empty otherwise.
    centroid_z: Vec<f64>,
}

impl JointTable {
    /// The table of a checked layout. A base course held against sliding
    /// ([`BaseSliding::Held`]) makes every table joint unable to slip, whatever its family.
    pub fn new(layout: &Layout) -> JointTable {
        let nm = layout.materials.len();
        let pairs = (0..nm).map(|i| (0..nm).map(|j| joint_between(layout, i, j)).collect()).collect();
        let mut table = joint_of(&layout.materials[layout.table_material]);
        if layout.base_sliding == BaseSliding::Held {
            table.can_slip = false;
        }
        let beds = layout.blocks.iter().any(|b| b.bed_closure.is_some());
        JointTable {
            table,
            pairs,
            block_material: layout.blocks.iter().map(|b| b.material).collect(),
            families: (!layout.joint_families.is_empty() || beds).then(|| Box::new(layout.clone())),
            centroid_z: if beds { layout.blocks.iter().map(|b| b.centroid().z).collect() } else { Vec::new() },
        }
    }

    /// The joint between body `a` (`None`: the table) and body `b` whose contact normal
    /// (table frame) is `normal`.
    pub fn joint(&self, a: Option<usize>, b: usize, normal: &Vec3) -> JointParams {
        let rule = match a {
            None => self.table,
            Some(i) => self.pairs[self.block_material[i]][self.block_material[b]],
        };
        let Some(layout) = &self.families else { return rule };
        let family: JointFamily = layout.joint_family(a, b, normal);
        let joint = match layout.joint_families.get(family) {
            Some(f) => with_family(rule, f),
            None => rule,
        };
        if self.centroid_z.is_empty() {
            return joint;
        }
        let bed = layout.bed_owner(a, b, family, |i| self.centroid_z[i]).and_then(|i| layout.blocks[i].bed_closure);
        match bed {
            Some(closure) => JointParams { closure, ..joint },
            None => joint,
        }
    }
}
