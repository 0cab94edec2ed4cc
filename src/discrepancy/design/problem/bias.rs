//! The follow-up's departures from the model it is drawn from: the contenders'
//! disagreement on its keys, the variance of the bias each truth's follow-ups carry, the
//! bias of one simulated follow-up, and the model whose mechanism a follow-up reads where
//! the first campaign did not read it.

use super::Problem;
use crate::discrepancy::predictive::{Predictive, Simulated};
use rand::RngExt;
use rand_distr::{Distribution, StandardNormal};

impl Problem<'_> {
    /// Whether key `k` of a follow-up drawn from contender `t` carries a bias: an angle or a
    /// displacement `t` predicts (not the mechanism's readings, nor the failure height,
    /// which are drawn from their categories).
    fn biased(&self, t: usize, k: usize) -> bool {
        let o = &self.keys[k];
        !o.is_mechanism() && self.sims[t][k].mean.is_finite()
    }

    /// The contenders' disagreement on the follow-up's keys (`[key]`, in units of the key's
    /// predictive variance under contender `t`): the between-model variance of the model
    /// average over the truths `B = Σ_c w_c (m_c − m̄)²` (`w_c`: their first-campaign
    /// weights, `m_c`: their predicted means of the key, `m̄ = Σ_c w_c m_c`). 0 for the
    /// mechanism's readings and failure heights (not biased) and a key `t` does not predict.
    ///
    /// A floor: the same variance over every contender the follow-up refits (the truths and
    /// the challengers, the library's plausible models, equally weighted), so that a truth
    /// that holds nearly all the weight, or the only truth, still carries the spread of the
    /// models that fit the first campaign on keys none of them was fitted on.
    pub fn disagreement(&self, t: usize) -> Vec<f64> {
        let space = self.space();
        let n = self.contenders.len().min(self.sims.len());
        let truths = self.truths.min(n);
        let between = |k: usize, of: &dyn Fn(usize) -> f64, upto: usize| -> f64 {
            let (mut w, mut m, mut m2) = (0.0, 0.0, 0.0);
            for c in 0..upto {
                let (p, x) = (of(c), self.sims[c][k].mean);
                if p > 0.0 && x.is_finite() {
                    w += p;
                    m += p * x;
                    m2 += p * x * x;
                }
            }
            if w > 0.0 {
                (m2 / w - (m / w).powi(2)).max(0.0)
            } else {
                0.0
            }
        };
        (0..self.keys.len())
            .map(|k| {
                let sim = &self.sims[t][k];
                if !self.biased(t, k) {
                    return 0.0;
                }
                let sd = Predictive::new(sim, &space.template(k), self.bracket_deg).sd;
                let weighted = between(k, &|c| self.contenders[c].prior, truths);
                let floor = between(k, &|_| 1.0, n);
                if sd > 0.0 {
                    weighted.max(floor) / (sd * sd)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The variance of the bias per key (`[key]`, in units of the key's predictive variance
    /// under contender `t`) that a follow-up drawn from `t` carries: `inadequacy[t]`, and on
    /// walls of a new kind ([`Problem::unseen_walls`]) the contenders' disagreement there
    /// ([`Problem::disagreement`]). Every truth fits the first campaign comparably, so on
    /// walls it did not test any of them, the cause's model included, may be off by as much
    /// as they disagree (the between-model part of a Bayesian model average's predictive
    /// variance; Hoeting et al. 1999, *Statist. Sci.* 14, 382–417). 0 for the mechanism's
    /// readings and failure heights (not biased). Empty when every key is 0, so nothing is
    /// drawn.
    ///
    /// Per key: a key the first campaign did not read ([`Problem::unseen`]: walls of a new
    /// kind, the other top measure, a tilt not read) carries `transfer[t]` and the
    /// disagreement there beside `inadequacy[t]`; a key it read carries `inadequacy[t]`.
    pub fn bias_variances(&self, t: usize) -> Vec<f64> {
        let own = self.inadequacy.get(t).copied().unwrap_or(0.0).max(0.0);
        let carried = self.transfer.get(t).copied().unwrap_or(0.0).max(0.0);
        let any = (0..self.keys.len()).any(|k| self.unseen(k));
        let between = if any { self.disagreement(t) } else { vec![0.0; self.keys.len()] };
        let v: Vec<f64> = (0..self.keys.len())
            .map(|k| match (self.biased(t, k), self.unseen(k)) {
                (false, _) => 0.0,
                (true, false) => own,
                (true, true) => own + carried + between[k],
            })
            .collect();
        if v.iter().all(|x| !(*x > 0.0)) {
            Vec::new()
        } else {
            v
        }
    }

    /// The biases of one simulated follow-up (`[key]`, in units of each key's predictive
    /// standard deviation): `N(0, variances[key])` per key ([`Problem::bias_variances`]),
    /// shared by every specimen of the follow-up, as the walls of a campaign share the way
    /// they differ from the model. Empty, drawing nothing, when `variances` is empty.
    pub(in crate::discrepancy::design) fn draw_bias(variances: &[f64], rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
        variances
            .iter()
            .map(|v| {
                let z: f64 = StandardNormal.sample(rng);
                v.sqrt() * z
            })
            .collect()
    }

    /// Whether key `k` is a mechanism reading (a kind, a start, a failure height) the
    /// first campaign did not read.
    fn unseen_mechanism(&self, k: usize) -> bool {
        self.keys[k].is_mechanism() && self.unseen(k)
    }

    /// The model whose mechanism one simulated follow-up drawn from a truth reads, where
    /// the first campaign did not read it: a truth drawn by the priors (the truth itself
    /// included). No model was checked against a failure no one watched, so the truth's
    /// mechanism there is as uncertain as the models that fit the first campaign disagree
    /// about it (the model average's draw, Hoeting et al. 1999, *Statist. Sci.* 14,
    /// 382–417), shared by the follow-up's specimens as a wall kind's mechanism is.
    /// `None`, drawing nothing, when the follow-up reads no unseen mechanism key.
    pub fn mechanism_source(&self, rng: &mut rand_chacha::ChaCha8Rng) -> Option<usize> {
        if !(0..self.keys.len()).any(|k| self.unseen_mechanism(k)) {
            return None;
        }
        let truths = self.truths.clamp(1, self.contenders.len().max(1)).min(self.contenders.len());
        let total: f64 = self.contenders[..truths].iter().map(|c| c.prior.max(0.0)).sum();
        let mut u = rng.random::<f64>() * total;
        for (c, con) in self.contenders[..truths].iter().enumerate() {
            if u < con.prior.max(0.0) {
                return Some(c);
            }
            u -= con.prior.max(0.0);
        }
        Some(truths.saturating_sub(1))
    }

    /// The predictions a follow-up drawn from truth `t` is drawn from: `t`'s, with its
    /// unseen mechanism keys read from `source` ([`Problem::mechanism_source`]).
    pub(super) fn drawn_from(&self, t: usize, source: Option<usize>) -> Vec<Simulated> {
        let mut row = self.sims[t].clone();
        if let Some(c) = source {
            for (k, x) in row.iter_mut().enumerate() {
                if self.unseen_mechanism(k) {
                    *x = self.sims[c][k];
                }
            }
        }
        row
    }
}
