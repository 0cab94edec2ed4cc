//! Identifiability: which observables of the design separate the leading models, and by
//! how much.
//!
//! For two models `a` and `b` at their fitted parameters, the expected log predictive
//! difference of one observation of key `k` when `a` is true is the Kullback–Leibler
//! divergence of their predictives there, `D_k(a‖b) = E_a[ln p_a(y) − ln p_b(y)]` (nats,
//! ≥ 0), times the observation's weight in the score ([`super::compare::specimen_weights`]):
//! the evidence for `a` one such reading adds on average (Lindley 1956, Ann. Math. Stat.
//! 27:986; the design criterion of Box & Hill 1967, Technometrics 9:57, for telling models
//! apart). Per key:
//!
//! * a collapse angle or a displacement: the predictives' Gaussian approximation (their
//!   location and scale; a Student-t's heavier tails are left out), `ln(s_b/s_a) + (s_a² +
//!   (m_a − m_b)²) / (2 s_b²) − ½`;
//! * a mechanism's kind or start: the two Bernoulli probabilities of the reading;
//! * a failure height: the two distributions over reading intervals of the reading's
//!   width tiling the height ([`super::predictive::Heights::probability`]).
//!
//! A specimen of a group adds the sum over its keys. Two models whose divergence per
//! replicate of the design (one specimen of every group), in the direction where it is
//! smaller, is below [`INDISTINGUISHABLE`] nats are named indistinguishable under this
//! design: more than a hundred replicates would give one nat of evidence on average.

use super::fit::Data;
use super::predictive::{height_score, Simulated};
use serde::Serialize;

/// Expected nats per replicate of the design below which two models are indistinguishable.
pub const INDISTINGUISHABLE: f64 = 0.01;

/// Leading models examined at most.
pub const LEADING: usize = 4;

/// How one key separates two models.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KeySeparation {
    /// The key (`GROUP alpha_max`, …).
    pub observable: String,
    /// Expected log predictive difference per observation when the first model is true,
    /// nats (weighted as in the score).
    pub first_true: f64,
    /// The same when the second is true.
    pub second_true: f64,
}

/// How the design separates two models.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairSeparation {
    /// The two models.
    pub models: (String, String),
    /// Every key, the best separating first (largest `first_true + second_true`).
    pub keys: Vec<KeySeparation>,
    /// Expected nats per replicate of the design (one specimen of every group), when the
    /// first model is true and when the second is.
    pub per_replicate: (f64, f64),
    /// The smaller of the two is below [`INDISTINGUISHABLE`].
    pub indistinguishable: bool,
}

/// The separations of the leading models, pair by pair.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Identifiability {
    /// The models examined (the models that share the weight, at least two and at most
    /// `LEADING`).
    pub leading: Vec<String>,
    /// Every pair of them.
    pub pairs: Vec<PairSeparation>,
    /// The threshold of [`PairSeparation::indistinguishable`], nats per replicate.
    pub threshold: f64,
}

impl Identifiability {
    /// The pairs no observation of the design separates.
    pub fn indistinguishable(&self) -> Vec<&(String, String)> {
        self.pairs.iter().filter(|p| p.indistinguishable).map(|p| &p.models).collect()
    }
}

fn gaussian_kl(ma: f64, sa: f64, mb: f64, sb: f64) -> f64 {
    if !(ma.is_finite() && mb.is_finite() && sa > 0.0 && sb > 0.0) {
        return 0.0;
    }
    (sb / sa).ln() + (sa * sa + (ma - mb).powi(2)) / (2.0 * sb * sb) - 0.5
}

fn discrete_kl(p: &[f64], q: &[f64]) -> f64 {
    let (sp, sq): (f64, f64) = (p.iter().sum(), q.iter().sum());
    if !(sp > 0.0 && sq > 0.0) {
        return 0.0;
    }
    p.iter().zip(q).filter(|(p, _)| **p > 0.0).map(|(p, q)| (p / sp) * ((p / sp) / (q / sq).max(1e-300)).ln()).sum()
}

/// `D(a‖b)` of observation `j`'s key (unweighted).
fn divergence(data: Data<'_>, a: &[Simulated], b: &[Simulated], j: usize) -> f64 {
    let o = &data.obs[j];
    let k = data.key[j];
    if let (Some(qa), Some(qb)) = (
        data.reading.category_probability(&o.observable, &a[k]),
        data.reading.category_probability(&o.observable, &b[k]),
    ) {
        return discrete_kl(&[qa, 1.0 - qa], &[qb, 1.0 - qb]);
    }
    if let Some(width) = o.observable.place_width() {
        let w = if width > 0.0 { width } else { 0.05 };
        let bins = (1.0 / w).ceil() as usize;
        let prob = |s: &Simulated| -> Vec<f64> {
            (0..bins)
                .map(|i| {
                    let y = ((i as f64 + 0.5) * w).min(1.0);
                    // The score is −ln q + ln(width of the clipped interval).
                    let (lo, hi) = ((y - 0.5 * w).max(0.0), (y + 0.5 * w).min(1.0));
                    (-(height_score(s, y, w, o.sigma, &data.reading) - (hi - lo).ln())).exp()
                })
                .collect()
        };
        return discrete_kl(&prob(&a[k]), &prob(&b[k]));
    }
    let (pa, pb) = (data.predictive(a, j), data.predictive(b, j));
    gaussian_kl(pa.mean, pa.sd, pb.mean, pb.sd)
}

/// The separations of `models` (name and simulated values per key at its fitted
/// parameters), pair by pair, on the design of `data` (`labels[k]`: each key's label; one
/// observation of each key stands for it).
pub fn identifiability(models: &[(String, Vec<Simulated>)], data: Data<'_>, labels: &[String]) -> Identifiability {
    let keys = labels.len();
    // The first observation of every key.
    let rep: Vec<Option<usize>> = (0..keys).map(|k| data.key.iter().position(|&x| x == k)).collect();
    let mut pairs = Vec::new();
    for i in 0..models.len() {
        for j in i + 1..models.len() {
            let (a, b) = (&models[i].1, &models[j].1);
            let mut ks: Vec<KeySeparation> = Vec::new();
            let (mut ra, mut rb) = (0.0, 0.0);
            // A replicate: every key of every group once, weighted as one specimen's.
            for (k, r) in rep.iter().enumerate() {
                let Some(r) = *r else { continue };
                let w = data.weight[r];
                let (x, y) = (w * divergence(data, a, b, r), w * divergence(data, b, a, r));
                ra += x;
                rb += y;
                ks.push(KeySeparation { observable: labels[k].clone(), first_true: x, second_true: y });
            }
            ks.sort_by(|p, q| (q.first_true + q.second_true).total_cmp(&(p.first_true + p.second_true)));
            pairs.push(PairSeparation {
                models: (models[i].0.clone(), models[j].0.clone()),
                keys: ks,
                per_replicate: (ra, rb),
                indistinguishable: ra.min(rb) < INDISTINGUISHABLE,
            });
        }
    }
    Identifiability { leading: models.iter().map(|m| m.0.clone()).collect(), pairs, threshold: INDISTINGUISHABLE }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::{Observable, Observation};
    use crate::discrepancy::predictive::{Heights, Reading};

    fn sim(mean: f64, sd: f64) -> Simulated {
        Simulated { mean, sd, n: 1_000_000, err: 0.0, heights: Heights::NONE }
    }

    /// Two keys: collapse angles 2° apart (a separating observable) and a displacement
    /// the two models predict alike. The angle's divergence against the closed form of
    /// two Gaussians (the predictive's scale: model spread and measurement σ); the
    /// displacement's is 0, and a model compared with itself is indistinguishable.
    #[test]
    fn the_separating_observable_is_found_with_its_divergence() {
        let obs = vec![
            Observation {
                specimen: "S".into(),
                group: "G".into(),
                observable: Observable::CollapseAngle,
                value: 0.0,
                sigma: 0.5,
            },
            Observation {
                specimen: "S".into(),
                group: "G".into(),
                observable: Observable::Displacement {
                    measure: crate::discrepancy::Measure::MeanOfLeftCenterRight,
                    tilt_deg: 5.0,
                },
                value: 0.0,
                sigma: 0.1,
            },
        ];
        let y = [0.0, 0.0];
        let key = [0usize, 1];
        let weight = [1.0, 1.0];
        let data = Data { obs: &obs, y: &y, key: &key, weight: &weight, reading: Reading::default(), bracket_deg: 0.0 };
        let a = vec![sim(20.0, 1.0), sim(1.0, 0.2)];
        let b = vec![sim(22.0, 1.0), sim(1.0, 0.2)];
        let labels = vec!["G alpha_max".to_string(), "G disp".to_string()];
        let id = identifiability(&[("a".into(), a.clone()), ("b".into(), b), ("a2".into(), a)], data, &labels);
        let ab = &id.pairs[0];
        assert_eq!(ab.keys[0].observable, "G alpha_max");
        // Scale² = 1 (1 + 1e-6) + 0.25.
        let s2 = 1.0 + 1e-6 + 0.25;
        assert!((ab.keys[0].first_true - 4.0 / (2.0 * s2)).abs() < 1e-9, "{ab:?}");
        assert!(ab.keys[1].first_true.abs() < 1e-12 && !ab.indistinguishable);
        let aa = &id.pairs[1];
        assert_eq!(aa.models, ("a".to_string(), "a2".to_string()));
        assert!(aa.indistinguishable && id.indistinguishable().len() == 1);
    }
}
