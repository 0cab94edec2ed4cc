//! The rope restraint's force on the blocks it bears on (the layout's
//! [`crate::layout::Rope`]; docs/rope.md).
//!
//! # The law
//!
//! A rope crosses the downhill (+y) face of the wall in the section `x = x_r`, lying on the
//! face as built over its band `[z_lo, z_hi]`; its two legs, each of free length `s`, run to
//! anchors fixed to the table, so that the rope is a taut string loaded at its middle. Each
//! block `b` it bears on (a free block reaching the section whose height overlaps the band
//! by `h_b`) presses it at a material point `p_b`: the block's reference point
//! `(x_r, y_max, z_c)` (its largest y as built, at the mid-height `z_c` of its overlap with
//! the band), carried with the block. The block's penetration into the rope's straight line
//! between its anchors is
//!
//! ```text
//! δ_b = (y(p_b) − y₀(p_b)) + d          (m; d the wrap depth, y₀ the point's y as built)
//! ```
//!
//! and the rope's deflection is the band's mean penetration over the blocks' heights,
//! `δ̄ = Σ h_b max(δ_b, 0) / Σ h_b` (a block behind the rope's line does not touch it). One
//! tension for the whole rope (it slides freely over the face):
//!
//! ```text
//! L = √(s² + δ̄²),  ℓ = 2L,  ℓ_ref = 2√(s² + d²)
//! T = max(0, T₀ + EA (ℓ − ℓ_ref) / ℓ_ref)       (N; tension only: a slack rope carries nothing)
//! F = 2 T δ̄ / L                                  (N, towards −y: the legs' pull on the wall)
//! ```
//!
//! and block `b` receives `F_b = F h_b max(δ_b, 0) / Σ_c h_c max(δ_c, 0)` in −y at `p_b`
//! (with its moment about the centroid). Small deflections with `d = 0`:
//! `F ≈ 2 T₀ δ̄ / s + EA δ̄³ / s³` (the taut string's geometric stiffness and the
//! stretch term). Units: N, m; frame: the table frame (x along the wall, y out of plane
//! towards the side the tilted wall falls to, z up).
//!
//! The bearers and their points are computed once when the state is built; the force pass
//! ([`RopeLoad::add_forces`]) allocates nothing.

use super::state::Body;
use crate::layout::{Layout, Rope};
use crate::math::Vec3;

/// One block bearing on a rope.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RopeBearer {
    /// The body's index.
    pub body: usize,
    /// The bearing point in the body frame, m.
    pub point: Vec3,
    /// The bearing point's y as built, table frame, m.
    pub y0: f64,
    /// The height of the band the block covers, m.
    pub height: f64,
}

/// A rope with the blocks it bears on: what the force pass reads.
#[derive(Debug, Clone, PartialEq)]
pub struct RopeLoad {
    /// The rope's parameters.
    pub rope: Rope,
    /// The blocks it bears on, in body order.
    pub bearers: Vec<RopeBearer>,
    /// Σ h_b over the bearers, m.
    pub covered: f64,
}

/// The rope's tension T (N) and its force F on the wall (N, towards −y) at the deflection
/// `delta` (m, the band's mean penetration δ̄ ≥ 0) (module doc).
pub fn rope_law(rope: &Rope, delta: f64) -> (f64, f64) {
    let s = rope.span;
    let l = (s * s + delta * delta).sqrt();
    let l_ref = (s * s + rope.wrap_depth * rope.wrap_depth).sqrt();
    let t = (rope.pretension + rope.axial_stiffness * (l - l_ref) / l_ref).max(0.0);
    (t, 2.0 * t * delta / l)
}

/// An upper bound (N/m) of the rope's tangent stiffness `dF/dδ̄` over the deflections
/// `[lo, hi]` (m, `0 ≤ lo ≤ hi`), and of its secant stiffness `F/δ̄` there:
///
/// ```text
/// dF/dδ̄ = 2 T s² / L³ + 2 EA δ̄² / (L² L_ref)     (T > 0; 0 where the rope is slack)
///       ≤ max(2 T/L at lo, at hi) + 2 EA hi² / (L(hi)² L_ref)
/// ```
///
/// (`2 T / L` is monotone in δ̄, its derivative has the sign of `EA − T₀`; `δ̄² / L²`
/// increases). At `δ̄ = 0` with `d = 0` it is the taut string's geometric stiffness
/// `2 T₀ / s`; the second term is the axial one, up to `2 EA / L_ref` for deflections
/// comparable with the span.
pub fn stiffness_bound(rope: &Rope, lo: f64, hi: f64) -> f64 {
    let s = rope.span;
    let l_ref = (s * s + rope.wrap_depth * rope.wrap_depth).sqrt();
    let geometric = |d: f64| {
        let l = (s * s + d * d).sqrt();
        2.0 * (rope.pretension + rope.axial_stiffness * (l - l_ref) / l_ref).max(0.0) / l
    };
    let axial = 2.0 * rope.axial_stiffness * hi * hi / ((s * s + hi * hi) * l_ref);
    geometric(lo).max(geometric(hi)) + axial
}

impl RopeLoad {
    /// The ropes of `layout` with their bearers among `bodies` (at their poses as built).
    pub fn of_layout(layout: &Layout, bodies: &[Body]) -> Vec<RopeLoad> {
        layout
            .ropes
            .iter()
            .map(|rope| {
                let bearers: Vec<RopeBearer> = layout
                    .blocks
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| !bodies[*k].fixed())
                    .filter_map(|(k, b)| {
                        let h = rope.bearing_height(b);
                        (h > 0.0).then(|| {
                            let bb = b.shape.aabb();
                            let zc = 0.5 * (bb.min.z.max(rope.z_lo) + bb.max.z.min(rope.z_hi));
                            let p = Vec3::new(rope.x, bb.max.y, zc);
                            RopeBearer { body: k, point: bodies[k].to_body(&p), y0: p.y, height: h }
                        })
                    })
                    .collect();
                let covered = bearers.iter().map(|b| b.height).sum();
                RopeLoad { rope: *rope, bearers, covered }
            })
            .collect()
    }

    /// Penetration δ_b (m) of a bearer at the bodies' current poses.
    #[inline]
    fn penetration(&self, b: &RopeBearer, bodies: &[Body]) -> (f64, Vec3) {
        let p = bodies[b.body].to_world(&b.point);
        (p.y - b.y0 + self.rope.wrap_depth, p)
    }

    /// The rope's deflection δ̄ (m) at the bodies' current poses (module doc); 0 for a rope
    /// that bears on no block.
    pub fn deflection(&self, bodies: &[Body]) -> f64 {
        if self.covered <= 0.0 {
            return 0.0;
        }
        let mut sum = 0.0;
        for b in &self.bearers {
            sum += b.height * self.penetration(b, bodies).0.max(0.0);
        }
        sum / self.covered
    }

    /// The bearer's point (m, table frame) at the bodies' current poses, relative to the
    /// bearing body's centroid.
    pub fn arm(&self, b: &RopeBearer, bodies: &[Body]) -> Vec3 {
        bodies[b.body].to_world(&b.point) - bodies[b.body].pos
    }

    /// Adds the rope's force on each block it presses, and its moment about the block's
    /// centroid, to `force` (N) and `torque` (N·m), table frame, indexed by body; returns
    /// the rope's tension T (N). Allocates nothing.
    pub fn add_forces(&self, bodies: &[Body], force: &mut [Vec3], torque: &mut [Vec3]) -> f64 {
        let mut weight = 0.0;
        for b in &self.bearers {
            weight += b.height * self.penetration(b, bodies).0.max(0.0);
        }
        if self.covered <= 0.0 {
            return self.rope.pretension;
        }
        let (t, f) = rope_law(&self.rope, weight / self.covered);
        if !(f > 0.0 && weight > 0.0) {
            return t;
        }
        for b in &self.bearers {
            let (d, p) = self.penetration(b, bodies);
            if d <= 0.0 {
                continue;
            }
            let fb = Vec3::new(0.0, -f * b.height * d / weight, 0.0);
            force[b.body] += fb;
            torque[b.body] += (p - bodies[b.body].pos).cross(&fb);
        }
        t
    }
}
