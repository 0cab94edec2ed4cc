//! Step 3 of the engine for one contact: the node gaps and mid-points from the two bodies'
//! poses, the joint law on every sub-contact, and the resultant force and moments.

use super::law::{self, Kinematics, Quadrature};
use super::types::Contact;
use crate::dem::state::Body;
use crate::math::Vec3;

/// Per-node values of the contact loop: the table-frame mid-point of the node's two
/// material points (m) and the normal gap between them (m).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct NodeScratch {
    x: Vec3,
    gap: f64,
}

/// `v / |v|` with one division (the contact normal of every step).
#[inline(always)]
pub(crate) fn unit(v: Vec3) -> Vec3 {
    v * (1.0 / v.norm())
}

/// Step 3 for one contact: evaluates the law on every sub-contact and returns the resultant
/// force on B, the moment on A about A's centroid and the moment on B about B's centroid
/// (N, N·m, table frame). `PAIR` is false for a table contact (A is the table: fixed, at the
/// origin, identity rotation; `a` is then ignored and no moment on A is returned), which
/// skips the transformations and products by the identity and zero (the results are those
/// of the general expressions, up to the sign of zero). Sets `left_window` when a
/// sub-contact's closure has passed the window its time step was taken over
/// ([`super::types::SubContact::window_cap_m`]).
#[inline(always)]
pub(crate) fn contact_forces<const PAIR: bool>(
    c: &mut Contact,
    a: &Body,
    bb: &Body,
    dt: f64,
    quad: Quadrature,
    scratch: &mut Vec<NodeScratch>,
    left_window: &mut bool,
) -> (Vec3, Vec3, Vec3) {
    let (xb, rb, vb, wb) = (&bb.pos, &bb.rot_mat, &bb.vel, &bb.angvel);
    let (xa, ra, va, wa) = (&a.pos, &a.rot_mat, &a.vel, &a.angvel);
    let n = unit(if PAIR { ra * c.normal_a + rb * c.normal_b } else { c.normal_a + rb * c.normal_b });
    if scratch.len() < c.nodes.len() {
        scratch.resize(c.nodes.len(), NodeScratch::default());
    }
    for (nd, sc) in c.nodes.iter().zip(scratch.iter_mut()) {
        let pa = if PAIR { xa + ra * nd.on_a } else { nd.on_a };
        let pb = xb + rb * nd.on_b;
        *sc = NodeScratch { x: 0.5 * (pa + pb), gap: (pb - pa).dot(&n) };
    }
    let scratch = &scratch[..c.nodes.len()];
    let mut fsum = Vec3::zeros();
    // Moment of the sub-contact forces about the table origin; shifted to the centroids once.
    let mut moment = Vec3::zeros();
    for s in &mut c.subs {
        let [s0, s1, s2] = s.nodes.map(|k| &scratch[k as usize]);
        let gaps = [s0.gap, s1.gap, s2.gap];
        if gaps[0] >= 0.0 && gaps[1] >= 0.0 && gaps[2] >= 0.0 && !s.state.bonded && s.state.normal == 0.0 {
            continue; // open everywhere, no history: no force
        }
        if -gaps[0].min(gaps[1]).min(gaps[2]) > s.window_cap_m {
            *left_window = true;
        }
        let (x0, x1, x2) = (s0.x, s1.x, s2.x);
        let xc = (x0 + x1 + x2) * (1.0 / 3.0);
        let vrel = if PAIR { vb + wb.cross(&(xc - xb)) - va - wa.cross(&(xc - xa)) } else { vb + wb.cross(&(xc - xb)) };
        let du = (vrel - n * n.dot(&vrel)) * dt;
        let out =
            law::evaluate(&c.joint, quad, &mut s.state, &Kinematics { normal: n, gaps, du_shear: du, area: s.area });
        let f = out.force;
        let x = x0 * out.at[0] + x1 * out.at[1] + x2 * out.at[2];
        let xs = x0 * out.at_shear[0] + x1 * out.at_shear[1] + x2 * out.at_shear[2];
        fsum += f;
        moment += x.cross(&(f - out.shear)) + xs.cross(&out.shear);
    }
    let tb = moment - xb.cross(&fsum);
    let ta = if PAIR { xa.cross(&fsum) - moment } else { Vec3::zeros() };
    (fsum, ta, tb)
}

/// The mass of a contact's pair as one degree of freedom, kg: `m_a m_b / (m_a + m_b)`, the
/// free body's mass where the other is the table or fixed (`None` where both are fixed).
#[inline(always)]
pub(crate) fn effective_mass(a: Option<&Body>, b: &Body) -> Option<f64> {
    match (a.filter(|a| !a.fixed()), b.fixed()) {
        (Some(a), false) => Some(a.mass * b.mass / (a.mass + b.mass)),
        (Some(a), true) => Some(a.mass),
        (None, false) => Some(b.mass),
        (None, true) => None,
    }
}

/// Normal contact damping of one contact (the dashpot of the linear spring–dashpot
/// contact, Cundall & Strack 1979; Tsuji, Tanaka & Ishida 1992, Powder Technol. 71:239),
/// evaluated after [`contact_forces`] at the same pose (its per-node `scratch`): the
/// dashpot pressure `c_p` (N·s/m³) acts on every node of the sub-contact mesh that is in
/// overlap (gap < 0), lumped over a third of the area of each triangle the node belongs to,
/// against the node's relative normal velocity (B relative to A, the bodies' velocities of
/// the step): `f = −c_p A_node (n · v_rel) n` on B. Returns the resultant force on B and
/// the moments on A and B about their centroids (N, N·m, table frame), as
/// [`contact_forces`]. When every node is in overlap and the pair translates along n, the
/// total is the single dashpot `c = c_p A` of the contact (its area `A`).
#[inline(always)]
pub(crate) fn contact_dashpot<const PAIR: bool>(
    c: &Contact,
    a: &Body,
    bb: &Body,
    c_p: f64,
    scratch: &[NodeScratch],
    node_area: &mut Vec<f64>,
) -> (Vec3, Vec3, Vec3) {
    let (xb, rb, vb, wb) = (&bb.pos, &bb.rot_mat, &bb.vel, &bb.angvel);
    let (xa, ra, va, wa) = (&a.pos, &a.rot_mat, &a.vel, &a.angvel);
    let n = unit(if PAIR { ra * c.normal_a + rb * c.normal_b } else { c.normal_a + rb * c.normal_b });
    node_area.clear();
    node_area.resize(c.nodes.len(), 0.0);
    for s in &c.subs {
        for k in s.nodes {
            node_area[k as usize] += s.area / 3.0;
        }
    }
    let mut fsum = Vec3::zeros();
    let mut moment = Vec3::zeros();
    for (sc, &area) in scratch[..c.nodes.len()].iter().zip(node_area.iter()) {
        if sc.gap >= 0.0 || area == 0.0 {
            continue;
        }
        let x = sc.x;
        let vrel = if PAIR { vb + wb.cross(&(x - xb)) - va - wa.cross(&(x - xa)) } else { vb + wb.cross(&(x - xb)) };
        let f = n * (-c_p * area * n.dot(&vrel));
        fsum += f;
        moment += x.cross(&f);
    }
    let tb = moment - xb.cross(&fsum);
    let ta = if PAIR { xa.cross(&fsum) - moment } else { Vec3::zeros() };
    (fsum, ta, tb)
}
