//! Whether the baseline's misfit is systematic: a pattern that a spread alone cannot
//! explain. The scatter hypothesis ([`super::candidate::Candidate::scatter`]) widens the
//! baseline's predictive; it fits a misfit of any sign and size in each group by spread, so
//! a misfit of one sign in every group it is read in would be "explained" by a wider band
//! around the wrong level. Such a misfit is a bias, and the analysis does not name `scatter`
//! for it ([`systematic_misfit`], read by the ranking's eligibility in `stages`).

use super::fit::Data;
use super::observations::Family;
use super::predictive::Simulated;
use serde::Serialize;

/// A family of measures whose baseline residuals have one sign in every group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SystematicMisfit {
    /// The family.
    pub family: &'static str,
    /// Per group (in the order of the observations): its name and the mean standardized
    /// residual `z = (measured − predicted) / predictive σ` of its observations of the family.
    pub groups: Vec<(String, f64)>,
}

/// The smallest |mean z| of every group for a one-signed misfit to count as systematic: one
/// predictive σ. Under the baseline's own spread the chance that g groups all exceed it on
/// one side is `2 × 0.16^g` (5 % for two groups, under 1 % for three).
pub const SYSTEMATIC_Z: f64 = 1.0;

fn family_name(f: Family) -> &'static str {
    match f {
        Family::CollapseAngle => "collapse angles",
        Family::Displacement => "displacements",
        Family::PeakForce => "peak forces",
        Family::DriftAtPeak => "drifts at the peak",
        Family::InitialStiffness => "initial stiffnesses",
        Family::VerticalModulus => "vertical moduli",
        Family::PeakAsymmetry => "peak asymmetries",
    }
}

/// The first family (in [`Family::ALL`]'s order) whose observations, read in at least two
/// groups, have a mean standardized residual under the baseline `baseline` of one sign and
/// at least [`SYSTEMATIC_Z`] in every group; `None` when there is none.
pub fn systematic_misfit(data: Data<'_>, baseline: &[Simulated]) -> Option<SystematicMisfit> {
    Family::ALL.into_iter().find_map(|family| {
        let mut groups: Vec<(String, f64, usize)> = Vec::new();
        for (j, o) in data.obs.iter().enumerate() {
            if o.observable.family() != Some(family) {
                continue;
            }
            let p = data.predictive(baseline, j);
            if !(p.sd > 0.0 && p.mean.is_finite() && data.y[j].is_finite()) {
                continue;
            }
            let z = (data.y[j] - p.mean) / p.sd;
            match groups.iter_mut().find(|g| g.0 == o.group) {
                Some(g) => {
                    g.1 += z;
                    g.2 += 1;
                }
                None => groups.push((o.group.clone(), z, 1)),
            }
        }
        let groups: Vec<(String, f64)> = groups.into_iter().map(|(g, s, n)| (g, s / n as f64)).collect();
        let one_sign = groups.iter().all(|g| g.1 >= SYSTEMATIC_Z) || groups.iter().all(|g| g.1 <= -SYSTEMATIC_Z);
        (groups.len() >= 2 && one_sign).then(|| SystematicMisfit { family: family_name(family), groups })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::predictive::Heights;
    use crate::discrepancy::{InPlaneQuantity, Observable, Observation, Reading};

    fn obs(group: &str, quantity: InPlaneQuantity) -> Observation {
        Observation {
            specimen: format!("{group}-s"),
            group: group.into(),
            observable: Observable::InPlane { quantity },
            value: 0.0,
            sigma: 1.0,
        }
    }

    /// Peak forces 2 σ above the baseline in both groups (the predictive σ is
    /// `sqrt(sd² (1 + 1/n) + σ²)` = 1 here, the model's spread 0): systematic; one group
    /// above and one below, or one group only, or residuals within a σ: not.
    #[test]
    fn a_misfit_of_one_sign_in_every_group_is_systematic_and_a_mixed_one_is_not() {
        let o = vec![
            obs("a", InPlaneQuantity::PeakForce),
            obs("a", InPlaneQuantity::PeakForce),
            obs("b", InPlaneQuantity::PeakForce),
            obs("a", InPlaneQuantity::DriftAtPeak),
            obs("b", InPlaneQuantity::DriftAtPeak),
        ];
        let key = [0, 0, 1, 2, 3];
        let sim = |mean: f64| Simulated { mean, sd: 0.0, n: 4, err: 0.0, heights: Heights::NONE };
        let base = [sim(10.0), sim(20.0), sim(1.0), sim(1.0)];
        let weight = [1.0; 5];
        let read = |y: &[f64]| {
            let data = Data { obs: &o, y, key: &key, weight: &weight, reading: Reading::default(), bracket_deg: 0.0 };
            systematic_misfit(data, &base)
        };
        // Forces +2 σ in a and b, drifts as predicted.
        let m = read(&[12.0, 12.0, 22.0, 1.0, 1.0]).expect("systematic");
        assert_eq!(m.family, "peak forces");
        assert_eq!(m.groups.len(), 2);
        assert!(m.groups.iter().all(|(_, z)| (z - 2.0).abs() < 1e-9), "{m:?}");
        // +2 in a, −2 in b: a spread, not a bias.
        assert_eq!(read(&[12.0, 12.0, 18.0, 1.0, 1.0]), None);
        // Within a σ in one group.
        assert_eq!(read(&[12.0, 12.0, 20.5, 1.0, 1.0]), None);
        // Drifts −3 σ in both groups: systematic in drifts.
        assert_eq!(read(&[10.0, 10.0, 20.0, -2.0, -2.0]).map(|m| m.family), Some("drifts at the peak"));
    }
}
