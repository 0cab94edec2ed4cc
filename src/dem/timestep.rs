//! Critical time step of the explicit scheme.
//!
//! For each free body, the translational and rotational stiffness of all its sub-contacts
//! (open or closed) bound its highest frequency (Gershgorin's theorem on the assembled
//! stiffness: `ω² ≤ 2 Σk / m`, `ω² ≤ 2 Σ k |r|² / I_min`); the step is
//! `Δt = safety × 2 / ω_max` (central difference is stable for `Δt < 2/ω_max`). The
//! safety factor (default 0.5) covers translation–rotation coupling.

use super::engine::Contact;
use super::state::Body;

/// The stable time step, s, for the current contacts, or `None` if no body touches
/// anything (then any step is stable for the contact forces; the caller keeps its own).
pub fn critical_timestep(bodies: &[Body], contacts: &[Contact], safety: f64) -> Option<f64> {
    let n = bodies.len();
    let mut kt = vec![0.0; n];
    let mut kr = vec![0.0; n];
    for c in contacts {
        let k = c.joint.kn.max(c.joint.ks);
        for s in &c.subs {
            let ks = k * s.area / 3.0;
            for &i in &s.nodes {
                let nd = &c.nodes[i as usize];
                if let Some(a) = c.a {
                    kt[a] += ks;
                    kr[a] += ks * nd.on_a.norm_squared();
                }
                kt[c.b] += ks;
                kr[c.b] += ks * nd.on_b.norm_squared();
            }
        }
    }
    let mut w2max: f64 = 0.0;
    for (i, b) in bodies.iter().enumerate() {
        if b.fixed {
            continue;
        }
        w2max = w2max.max(2.0 * kt[i] / b.mass).max(2.0 * kr[i] / b.min_inertia);
    }
    (w2max > 0.0).then(|| safety * 2.0 / w2max.sqrt())
}
