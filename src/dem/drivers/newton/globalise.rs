//! The bound of a Newton step by the joints' gaps (see the parent module).

use crate::dem::drivers::implicit::PoseIncrement;
use crate::dem::engine::Simulation;
use crate::math::Vec3;

/// The largest step length `s` along `d` (per body a translation, m, and a rotation
/// vector, rad, table frame) for which, to first order in the motion, no node of a contact
/// opens by more than its gap now plus `kappa` times the larger of its contact's largest
/// closure and the mean closure of the state's closed nodes (m; closure `u = (p_A − p_B)·n`
/// positive where the bodies overlap). A node's closure changes by `s n·(δp_A − δp_B)` with
/// `δp = d_x + d_θ × r` at its arm `r`. `f64::INFINITY` where no node opens along `d` or
/// `kappa` is infinite; 0 where the state has no closed node and a node opens (nothing to
/// measure the step by is no licence to throw).
pub(super) fn opening_bound(sim: &Simulation, d: &PoseIncrement, kappa: f64) -> f64 {
    if kappa == f64::INFINITY {
        return f64::INFINITY;
    }
    let st = &sim.state;
    // Per node: its contact, closure and the closure's rate along `d`.
    let mut nodes: Vec<(usize, f64, f64)> = Vec::new();
    let mut largest: Vec<f64> = Vec::with_capacity(st.contacts.len());
    let (mut sum, mut closed) = (0.0, 0usize);
    for (ci, c) in st.contacts.iter().enumerate() {
        let n = st.contact_normal(c);
        let rb_mat = &st.bodies[c.b].rot_mat;
        let mut umax = 0.0f64;
        for nd in &c.nodes {
            let (pa, pb) = st.node_points(c, nd);
            let u = (pa - pb).dot(&n);
            let vb = d.0[c.b] + d.1[c.b].cross(&(rb_mat * nd.on_b));
            let va = match c.a {
                Some(a) => d.0[a] + d.1[a].cross(&(st.bodies[a].rot_mat * nd.on_a)),
                None => Vec3::zeros(),
            };
            if u > 0.0 {
                sum += u;
                closed += 1;
            }
            umax = umax.max(u);
            nodes.push((ci, u, n.dot(&(va - vb))));
        }
        largest.push(umax);
    }
    let mean = if closed > 0 { sum / closed as f64 } else { 0.0 };
    nodes
        .iter()
        .filter(|(_, _, rate)| *rate < 0.0)
        .map(|&(ci, u, rate)| ((-u).max(0.0) + kappa * largest[ci].max(mean)) / -rate)
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::{RunToEquilibrium, SolverParams};
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    /// A block settled on the table closes its base by `W / (Kn A)` at every node; lifted
    /// by `h` (m) it may go `κ W / (Kn A) / h` of the way, and turned about an edge of its
    /// base by `θ` (rad) the opposite edge, at the base's width `b` from it, opens at
    /// `b θ` per unit step: the bound is `κ W / (Kn A) / (b θ)` to first order. Pushed down
    /// into the table, nothing opens: no bound.
    #[test]
    fn the_bound_is_the_closure_over_the_opening_rate() {
        let (kn, b, w) = (1e8, 0.3, 0.2);
        let l = layout_of(
            vec![box_vertices([0.0, -w / 2.0, 0.0], [b, w / 2.0, 0.1])],
            kn,
            kn / 2.0,
            35.0,
            BaseSliding::Free,
        );
        let mut sim = Simulation::new(&l, SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-9, 400_000).unwrap());
        let body = &sim.state.bodies[0];
        let closure = body.mass * sim.state.gravity_magnitude / (kn * b * w);
        let kappa = 1.5;
        let lift = (vec![Vec3::new(0.0, 0.0, 1e-3)], vec![Vec3::zeros()]);
        let s = opening_bound(&sim, &lift, kappa);
        assert!((s / (kappa * closure / 1e-3) - 1.0).abs() < 1e-3, "{s} against {}", kappa * closure / 1e-3);
        // A turn θ about the base's edge x = 0 (the y axis through the base's corner line):
        // the centroid moves by θ × (c − edge).
        let theta = 1e-4;
        let edge = Vec3::new(0.0, body.pos.y, 0.0);
        let rot = Vec3::new(0.0, -theta, 0.0);
        let turn = (vec![rot.cross(&(body.pos - edge))], vec![rot]);
        let s = opening_bound(&sim, &turn, kappa);
        let exact = kappa * closure / (b * theta);
        assert!((s / exact - 1.0).abs() < 1e-2, "{s} against {exact}");
        let push = (vec![Vec3::new(0.0, 0.0, -1e-3)], vec![Vec3::zeros()]);
        assert_eq!(opening_bound(&sim, &push, kappa), f64::INFINITY);
        assert_eq!(opening_bound(&sim, &lift, f64::INFINITY), f64::INFINITY);
    }
}
