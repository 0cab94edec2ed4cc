//! Contact points of the non-smooth solver, from drystone's own contact detection.
//!
//! The broad phase (`geometry::sweep`) and the narrow phase
//! (`dem::contact::geometry::{table_block, block_block}`: the separating-axis normal, the
//! contact features and their polygon) are the penalty engine's. Each contact polygon
//! gives one contact point per vertex (a face–face contact), its two ends (a segment:
//! edge–face or parallel edges) or its one point (vertex–face, crossing edges); the narrow
//! phase's widening of segments and points into thin polygons is merged back. A point is
//! stored as two material points, one on the surface of each body straight across the
//! contact plane, so that its gap (their separation along the normal, m, positive open)
//! follows the bodies; its normal is carried by both bodies as the penalty engine's is.
//!
//! Points come in a fixed order (the table's contacts first, then pairs (A, B) in index
//! order, each polygon's vertices in the narrow phase's order): every sweep of the
//! Gauss–Seidel loop visits them in that order, so a run is the same bit for bit.

use super::{NscdError, PolygonPoints};
use crate::dem::contact::geometry::{block_block, table_block, Patch, PatchKind, PatchParams};
use crate::dem::materials::JointTable;
use crate::dem::state::Body;
use crate::geometry::sweep::sweep_pairs;
use crate::math::Vec3;

/// Coulomb coefficient by which the step solvers hold a table joint against sliding
/// (`base_sliding = "held"`, the timber stops of the paper's held walls): a held point does
/// not slip while it presses unless its tangential impulse exceeds five times its normal
/// one (a friction angle of 79°, beyond the base shear of any tilt, lateral load or
/// shaking below 5 g that a standing wall carries), and is free once it lifts, as the
/// penalty DEM's held joint (an elastic tangential spring while closed, nothing once open)
/// and limit analysis's (no slip at a pressed point) are. Every step solver (the sweeps,
/// the gradient, the cone finisher), the natural-map residual and the rest certificate
/// ([`super::rest`], in its reduced cone `sin φ`) read this one Coulomb law.
///
/// Why a closed cone and why 5: the half-space `rₙ ≥ 0` (no slip at any μ) lets a lifted
/// point keep a tangential impulse with no normal one, which props a rocking heel; the
/// limit law (no slip while pressed, free once lifted) is not convex, so the gradient and
/// the cone programs do not solve it reliably. On the 13-box held wall under a 0.6 g, 0.3 s
/// one-sine pulse every step converges at μ = 1 to 5, while 27 of 2,350 steps stay
/// unconverged at 10 and 101 at 30 (De Saxcé's shift `μ ‖u_t‖` contracts less as μ
/// grows). On the SBL preset wall (195 blocks) under `data/motions/synthetic_10s.csv`, with
/// the rest certificate left as before, the wall overturned at 2.722 s at μ = 5 and at
/// 2.726 s under the limit law solved by a non-convex projection (with 74 steps
/// unconverged): μ = 5 is held for that wall (docs/shake.md).
pub const HELD_FRICTION: f64 = 5.0;

/// One contact point between body A (`None`: the table) and body B, with the impulse of
/// the last step (the warm start of the next).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Body A; `None` is the table.
    pub a: Option<usize>,
    /// Body B.
    pub b: usize,
    /// Point on A, A's body frame (the table frame for the table), m.
    pub on_a: Vec3,
    /// Point on B, B's body frame, m.
    pub on_b: Vec3,
    /// Unit normal A → B at detection, in A's body frame (table frame for the table).
    pub normal_a: Vec3,
    /// The same normal in B's body frame.
    pub normal_b: Vec3,
    /// Coulomb friction coefficient μ = tan φ of the joint ([`HELD_FRICTION`] for a table
    /// joint held against sliding).
    pub mu: f64,
    /// Impulse on B over the last step, local frame (n, t₁, t₂), N·s.
    pub impulse: Vec3,
}

impl ContactPoint {
    /// The pair key: the table first, then (A, B).
    pub fn key(&self) -> (usize, usize) {
        (self.a.map_or(0, |i| i + 1), self.b)
    }

    /// Table-frame positions of the point's two material points (on A, on B), m.
    pub fn world_points(&self, bodies: &[Body]) -> (Vec3, Vec3) {
        let pa = match self.a {
            None => self.on_a,
            Some(i) => bodies[i].to_world(&self.on_a),
        };
        (pa, bodies[self.b].to_world(&self.on_b))
    }

    /// Current unit normal (A → B, table frame): the mean of the detection normal carried
    /// by each body.
    pub fn normal(&self, bodies: &[Body]) -> Vec3 {
        let na = match self.a {
            None => self.normal_a,
            Some(i) => bodies[i].rot_mat * self.normal_a,
        };
        let n = na + bodies[self.b].rot_mat * self.normal_b;
        n / n.norm()
    }

    /// The joint's name, `table/ID` or `ID_A/ID_B`.
    pub fn joint_name(&self, bodies: &[Body]) -> String {
        match self.a {
            None => format!("table/{}", bodies[self.b].id),
            Some(i) => format!("{}/{}", bodies[i].id, bodies[self.b].id),
        }
    }
}

/// The (on A, on B) world points of a patch's contact points: its nodes for a polygon (at
/// most four with [`PolygonPoints::Quad`]), the two ends of a widened segment, the centre
/// of a widened point.
fn patch_points(p: &Patch, reduce: PolygonPoints) -> Vec<(Vec3, Vec3)> {
    let n = &p.nodes;
    let mean = |ids: &[usize]| {
        let k = ids.len() as f64;
        ids.iter().fold((Vec3::zeros(), Vec3::zeros()), |(a, b), &i| (a + n[i].on_a / k, b + n[i].on_b / k))
    };
    match p.kind {
        PatchKind::Face if reduce == PolygonPoints::Quad && n.len() > 4 => {
            largest_quad(&n.iter().map(|q| 0.5 * (q.on_a + q.on_b)).collect::<Vec<_>>(), &p.normal)
                .iter()
                .map(|&i| (n[i].on_a, n[i].on_b))
                .collect()
        }
        PatchKind::Face => n.iter().map(|q| (q.on_a, q.on_b)).collect(),
        // The rectangle [p − w, q − w, q + w, p + w] of the narrow phase.
        PatchKind::Edge if n.len() == 4 => vec![mean(&[0, 3]), mean(&[1, 2])],
        _ => vec![mean(&(0..n.len()).collect::<Vec<_>>())],
    }
}

/// The four vertices of a convex polygon (`v` in order around it, normal `n`) that span
/// the quadrilateral of largest area, in the polygon's order; the first such in
/// lexicographic order of the indices (deterministic).
fn largest_quad(v: &[Vec3], n: &Vec3) -> [usize; 4] {
    let area = |ids: [usize; 4]| {
        let (a, b, c, d) = (v[ids[0]], v[ids[1]], v[ids[2]], v[ids[3]]);
        0.5 * (c - a).cross(&(d - b)).dot(n).abs()
    };
    let m = v.len();
    let mut best = ([0, 1, 2, 3], -1.0);
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                for l in k + 1..m {
                    let a = area([i, j, k, l]);
                    if a > best.1 {
                        best = ([i, j, k, l], a);
                    }
                }
            }
        }
    }
    best.0
}

/// Detects the contact points of `bodies` at their current poses. The impulse of each new
/// point is taken from the old point of the same pair nearest to it on B (within
/// `carry_m`, m), else zero.
///
/// # Errors
/// [`NscdError::Cohesion`] for the first joint in contact with cohesion or tensile
/// strength.
pub(crate) fn detect(
    bodies: &[Body],
    joints: &JointTable,
    patch: &PatchParams,
    old: &[ContactPoint],
    carry_m: f64,
    reduce: PolygonPoints,
) -> Result<Vec<ContactPoint>, NscdError> {
    let boxes: Vec<_> = bodies
        .iter()
        .map(|b| {
            crate::geometry::Aabb::from_points(&b.shape.vertices.iter().map(|v| b.to_world(v)).collect::<Vec<_>>())
        })
        .collect();
    let mut pairs: Vec<(Option<usize>, usize)> = (0..bodies.len())
        .filter(|&j| !bodies[j].fixed() && boxes[j].min.z <= patch.contact_margin_m)
        .map(|j| (None, j))
        .collect();
    pairs.extend(
        sweep_pairs(&boxes, patch.contact_margin_m)
            .into_iter()
            .filter(|&(i, j)| !(bodies[i].fixed() && bodies[j].fixed()))
            .map(|(i, j)| (Some(i), j)),
    );
    let shapes: Vec<_> = bodies.iter().map(|b| b.world_shape()).collect();
    let mut out = Vec::new();
    for (a, b) in pairs {
        let found = match a {
            None => table_block(&shapes[b], patch),
            Some(i) => block_block(&shapes[i], &shapes[b], patch),
        };
        let Some(p) = found else { continue };
        let joint = joints.joint(a, b, &p.normal);
        let probe = ContactPoint {
            a,
            b,
            on_a: Vec3::zeros(),
            on_b: Vec3::zeros(),
            normal_a: Vec3::zeros(),
            normal_b: Vec3::zeros(),
            mu: 0.0,
            impulse: Vec3::zeros(),
        };
        if joint.has_strength() {
            return Err(NscdError::Cohesion {
                joint: probe.joint_name(bodies),
                cohesion_pa: joint.cohesion,
                tensile_strength_pa: joint.tension.strength(),
            });
        }
        let mu = if joint.can_slip { joint.tan_phi } else { HELD_FRICTION };
        let bb = &bodies[b];
        let normal_a = match a {
            None => p.normal,
            Some(i) => bodies[i].rot_mat.transpose() * p.normal,
        };
        let normal_b = bb.rot_mat.transpose() * p.normal;
        for (wa, wb) in patch_points(&p, reduce) {
            let on_a = match a {
                None => wa,
                Some(i) => bodies[i].to_body(&wa),
            };
            let on_b = bb.to_body(&wb);
            out.push(ContactPoint { on_a, on_b, normal_a, normal_b, mu, ..probe });
        }
    }
    // Warm start from the old points of the same pair (both lists are in pair order).
    let mut start = 0;
    for c in &mut out {
        while start < old.len() && old[start].key() < c.key() {
            start += 1;
        }
        let mut best = (carry_m, None);
        for o in old[start..].iter().take_while(|o| o.key() == c.key()) {
            let d = (o.on_b - c.on_b).norm();
            if d <= best.0 {
                best = (d, Some(o.impulse));
            }
        }
        if let Some(r) = best.1 {
            c.impulse = r;
        }
    }
    Ok(out)
}
