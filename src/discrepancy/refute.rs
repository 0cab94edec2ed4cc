//! Readings that refute a candidate: a cause is not named when one of the readings the
//! data hold says its mechanism is wrong, however much it gains on the others.
//!
//! Two kinds of reading are asked, in the ranking's order, before a candidate is confirmed
//! by a full run and before it is named ([`super::stages`]):
//!
//! * **A reading of the fit** (every observation of one reading, [`reading_of`]: the peak
//!   forces, the walls' vertical modulus, the ± asymmetry, the mode, the collapse angles,
//!   the displacements, …). The candidate's held-out scores on that reading's
//!   observations are set against the baseline's ([`in_fit`]): the reading refutes the
//!   candidate when the candidate predicts it worse than the baseline by more than
//!   [`REFUTE_NATS`] of log predictive density summed over the reading, and by more than
//!   [`REFUTE_Z`] standard errors of that sum over the specimens (a paired test, as the
//!   tie check's data test: a candidate that gains 50 nats on the peaks cannot buy a
//!   vertical modulus it contradicts; a reading held by one specimen alone is judged by
//!   the threshold in nats alone). A reading the candidate fails no worse than the
//!   baseline does not refute it: it is a misfit the candidate leaves, which its
//!   predictive check reports.
//! * **A held reading** ([`super::HeldReading`]): one the fit does not hold because it needs runs
//!   of another kind (the in-plane test's cyclic loops: each specimen run on its own
//!   history). The protocol runs the candidate at its fitted parameters and judges it by
//!   the same rule, its statistic against the baseline's.
//!
//! The threshold is "strong" evidence on Kass & Raftery's scale (1995, J. Am. Stat. Assoc.
//! 90:773, `2 ln B > 6`): a likelihood ratio of 20 against the candidate on that reading.

use super::fit::Data;
use super::observations::Observable;
use super::rank::Ranked;
use serde::Serialize;

/// The evidence, in nats of log predictive density summed over one reading, by which a
/// candidate must predict the reading worse than the baseline for the reading to refute it:
/// 3 nats, a likelihood ratio of 20 ("strong", Kass & Raftery 1995). A held reading read
/// as a χ² refutes at a χ² larger than the baseline's by twice this (the Gaussian
/// likelihood's `Δχ² = 2 Δ ln L`).
pub const REFUTE_NATS: f64 = 3.0;

/// Standard errors of the summed difference over specimens (one-sided 1 %) by which the
/// candidate's loss on a reading must also exceed 0: the loss is not one specimen's luck.
pub const REFUTE_Z: f64 = 2.326;

/// A reading's refutation of a candidate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Refutation {
    /// The candidate (`a`, `a+b`).
    pub candidate: String,
    /// The reading (`wall_vertical_modulus_mpa`, `loops`).
    pub reading: String,
    /// How much worse than the baseline the candidate predicts it, nats (a held reading's
    /// `Δχ² / 2`).
    pub nats: f64,
    /// What the reading says, for the report (`held-out log density 7.2 nats below the
    /// baseline's over 3 observations`).
    pub words: String,
}

/// The reading an observable belongs to: a measure's family or quantity (`alpha_max`,
/// `displacement`, `peak_force_kn`, `wall_vertical_modulus_mpa`), a category's reading
/// (`failure_kind`, `failure_start`, `mode`), `failure_height`.
pub fn reading_of(o: &Observable) -> String {
    match o {
        Observable::CollapseAngle => "alpha_max".into(),
        Observable::Displacement { .. } => "displacement".into(),
        Observable::FailureHeight { .. } => "failure_height".into(),
        Observable::MechanismKind { .. } => "failure_kind".into(),
        Observable::MechanismStart { .. } => "failure_start".into(),
        Observable::InPlane { quantity } => quantity.name().into(),
        Observable::InPlaneMode { .. } => "mode".into(),
    }
}

/// The reading of the fit that refutes `r` (module documentation), the one of largest loss
/// when several do; `base_scores` the baseline's score of every observation of `data`.
/// Observations whose score is not finite on either side are left out.
pub fn in_fit(r: &Ranked, base_scores: &[f64], data: Data<'_>) -> Option<Refutation> {
    let mut readings: Vec<String> = data.obs.iter().map(|o| reading_of(&o.observable)).collect();
    let of_obs = readings.clone();
    readings.sort();
    readings.dedup();
    let mut worst: Option<Refutation> = None;
    for reading in readings {
        // Per specimen, the candidate's loss on this reading's observations.
        let mut per: Vec<(&str, f64)> = Vec::new();
        let mut count = 0usize;
        for (j, o) in data.obs.iter().enumerate() {
            let (Some(&c), Some(&b)) = (r.scores.get(j), base_scores.get(j)) else { continue };
            if of_obs[j] != reading || !c.is_finite() || !b.is_finite() {
                continue;
            }
            count += 1;
            match per.iter_mut().find(|(s, _)| *s == o.specimen) {
                Some(p) => p.1 += c - b,
                None => per.push((&o.specimen, c - b)),
            }
        }
        let loss: f64 = per.iter().map(|p| p.1).sum();
        let d: Vec<f64> = per.iter().map(|p| p.1).collect();
        // One specimen has no spread to test against: the threshold alone decides.
        let se = if d.len() < 2 { 0.0 } else { super::compare::difference_se(&d) };
        if loss > REFUTE_NATS && loss > REFUTE_Z * se && worst.as_ref().is_none_or(|w| loss > w.nats) {
            worst = Some(Refutation {
                candidate: r.name.clone(),
                reading: reading.clone(),
                nats: loss,
                words: format!(
                    "its held-out log density of {reading} is {loss:.1} nats below the baseline's (± {se:.1}) over {count} observations of {} specimens",
                    per.len()
                ),
            });
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::Observation;
    use crate::discrepancy::InPlaneQuantity;

    fn ranked(scores: Vec<f64>) -> Ranked {
        Ranked::with_scores("c", scores)
    }

    /// Four specimens, each with a peak force and a vertical modulus.
    fn obs() -> Vec<Observation> {
        (0..8)
            .map(|j| Observation {
                specimen: format!("S{}", j / 2),
                group: "G".into(),
                observable: Observable::InPlane {
                    quantity: if j % 2 == 0 { InPlaneQuantity::PeakForce } else { InPlaneQuantity::VerticalModulus },
                },
                value: 0.0,
                sigma: 1.0,
            })
            .collect()
    }

    fn data<'a>(obs: &'a [Observation], zeros: &'a [f64], keys: &'a [usize]) -> Data<'a> {
        Data { obs, y: zeros, key: keys, weight: zeros, reading: Default::default(), bracket_deg: 0.5 }
    }

    #[test]
    fn a_reading_the_candidate_predicts_much_worse_than_the_baseline_refutes_it() {
        let o = obs();
        let (zeros, keys) = (vec![0.0; 8], vec![0usize; 8]);
        let base = vec![1.0; 8];
        // Gains 10 nats a specimen on the peaks, loses 2 a specimen on the modulus.
        let c: Vec<f64> = (0..8).map(|j| if j % 2 == 0 { -9.0 } else { 3.0 }).collect();
        let r = in_fit(&ranked(c), &base, data(&o, &zeros, &keys)).expect("refuted");
        assert_eq!(r.reading, "wall_vertical_modulus_mpa");
        assert!((r.nats - 8.0).abs() < 1e-12);
    }

    #[test]
    fn a_reading_no_worse_than_the_baseline_or_lost_by_one_specimen_does_not_refute() {
        let o = obs();
        let (zeros, keys) = (vec![0.0; 8], vec![0usize; 8]);
        let base = vec![1.0; 8];
        // Below the threshold: 0.5 nats a specimen, 2 in all.
        let c: Vec<f64> = (0..8).map(|j| if j % 2 == 0 { -9.0 } else { 1.5 }).collect();
        assert_eq!(in_fit(&ranked(c), &base, data(&o, &zeros, &keys)), None);
        // 4 nats in all, but one specimen's: not beyond its standard error.
        let c: Vec<f64> = (0..8)
            .map(|j| {
                if j == 1 {
                    5.0
                } else if j % 2 == 0 {
                    -9.0
                } else {
                    1.0
                }
            })
            .collect();
        assert_eq!(in_fit(&ranked(c), &base, data(&o, &zeros, &keys)), None);
    }
}
