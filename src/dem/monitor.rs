//! What the engine reports after each step.

/// Statistics of one step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepStats {
    /// Unbalanced-force ratio: mean out-of-balance load of the free bodies divided by the
    /// mean magnitude of the resultant contact forces (YADE's `unbalancedForce()`),
    /// dimensionless. A body's out-of-balance load is `|F| + |T| / r`: the net force plus
    /// the net moment about its centroid over its radius r (YADE counts forces only, which
    /// misses a block rotating about an edge). Zero at exact equilibrium; `f64::INFINITY` while no contact carries
    /// force but bodies are loaded (free fall).
    pub unbalanced_ratio: f64,
    /// Mean out-of-balance load `|F| + |T|/r` of a free body, N.
    pub mean_unbalanced_force: f64,
    /// Mean resultant force of a loaded contact, N.
    pub mean_contact_force: f64,
    /// Translational kinetic energy at the half step, J.
    pub kinetic_energy: f64,
    /// Contacts carrying force.
    pub active_contacts: usize,
}

impl StepStats {
    /// Builds the statistics from the step's sums.
    pub fn new(
        mean_unbalanced_force: f64,
        mean_contact_force: f64,
        kinetic_energy: f64,
        active_contacts: usize,
    ) -> Self {
        let unbalanced_ratio = if mean_contact_force > 0.0 {
            mean_unbalanced_force / mean_contact_force
        } else if mean_unbalanced_force > 0.0 {
            f64::INFINITY
        } else {
            0.0
        };
        StepStats { unbalanced_ratio, mean_unbalanced_force, mean_contact_force, kinetic_energy, active_contacts }
    }
}
