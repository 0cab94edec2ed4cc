//! The `end_rope` primitive: a wall's end restraints replaced by a tensioned rope at each
//! end ([`crate::layout::Rope`], the force law in [`crate::dem::rope`]; docs/rope.md).
//!
//! Geometry (the source paper gives only "a rope manually tensioned at the specimen ends"
//! with 1.4 m between the ropes on the 1.5 m wall, Santa-Cruz et al. 2021, §2.1): one rope
//! [`END_ROPE_OFFSET_M`] in from each end of the wall, bearing on the wall's whole height,
//! its legs of free length [`END_ROPE_SPAN_M`] to their anchors, just touching the face as
//! built (wrap depth 0).

use crate::layout::{Layout, Rope};

/// Distance of each end rope from its end of the wall, m: the paper's ropes are 1.4 m apart
/// on the 1.5 m wall (Santa-Cruz et al. 2021, §2.1).
pub const END_ROPE_OFFSET_M: f64 = 0.05;

/// Free length of each leg of an end rope, from the face to its anchor, m (an assumption:
/// the rope led over the 0.05 m of wall beyond it to an anchor on the 1.6 m platform's
/// edge, 0.05 m beyond the wall's end; the paper does not give the anchors).
pub const END_ROPE_SPAN_M: f64 = 0.1;

/// Pretension an end rope gets when an effect sets only its stiffness, N (the middle of the
/// built-in `end_rope` range, an estimate).
pub const END_ROPE_DEFAULT_PRETENSION_N: f64 = 300.0;

/// Axial stiffness an end rope gets when an effect sets only its pretension, N (a 6 mm
/// polypropylene rope, an estimate: docs/rope.md).
pub const END_ROPE_DEFAULT_AXIAL_STIFFNESS_N: f64 = 6e4;

/// Which property of the end ropes a step sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RopeProperty {
    /// Pretension T₀, N.
    Pretension,
    /// Axial stiffness EA, N.
    AxialStiffness,
}

/// Sets `property` of the end ropes of `layout` to `v`, first replacing the wall's end
/// restraints by one rope at each end if it has none. A wall without end restraints or
/// ropes is left as it is (nothing holds its ends); so is every wall for an infinite `v`
/// (the rigid ends: the neutral value).
pub(super) fn set_end_rope(layout: &mut Layout, property: RopeProperty, v: f64) {
    if !v.is_finite() || (layout.ropes.is_empty() && layout.end_restraints.is_empty()) {
        return;
    }
    if layout.ropes.is_empty() {
        let bb = layout.bounds();
        for x in [bb.min.x + END_ROPE_OFFSET_M, bb.max.x - END_ROPE_OFFSET_M] {
            layout.ropes.push(Rope {
                x,
                z_lo: 0.0,
                z_hi: bb.max.z,
                pretension: END_ROPE_DEFAULT_PRETENSION_N,
                axial_stiffness: END_ROPE_DEFAULT_AXIAL_STIFFNESS_N,
                span: END_ROPE_SPAN_M,
                wrap_depth: 0.0,
            });
        }
        layout.end_restraints.clear();
    }
    for r in &mut layout.ropes {
        match property {
            RopeProperty::Pretension => r.pretension = v,
            RopeProperty::AxialStiffness => r.axial_stiffness = v,
        }
    }
}
