//! The joint law of a layout's materials: the layout's SI material values as the
//! [`JointParams`] of the contact law.

use super::contact::law::{JointParams, NormalClosure};
use crate::layout::{Closure, Layout, Material};

/// The joint law of a material's joints (the layout's SI values).
pub fn joint_of(m: &Material) -> JointParams {
    let closure = match m.closure {
        Closure::Linear => NormalClosure::Linear,
        Closure::Hyperbolic { max_closure_m } => NormalClosure::Hyperbolic { max_closure: max_closure_m },
        Closure::Seating { max_gap_m } => NormalClosure::Seating { max_gap: max_gap_m },
    };
    JointParams::coulomb(m.kn, m.ks, m.friction, m.cohesion, m.tensile_strength).with_closure(closure)
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
