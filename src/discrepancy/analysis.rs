//! Cause finding: the candidates ranked by held-out error and AICc, margins calibrated on
//! null data from independent layouts, and the verdict.
//!
//! * **Hold-out.** Leave one specimen out: every specimen's observations are predicted by
//!   the candidate fitted to the other specimens only ([`super::fit::loso`]). The held-out
//!   error is the mean held-out score per specimen. The baseline has no parameter: its
//!   held-out error is its plain score. Differences carry their standard error over
//!   specimens ([`super::compare::difference_se`]).
//! * **Information criterion.** AICc at the full-data fit, n = specimens.
//! * **Null calibration.** Null data sets are drawn under the baseline from layouts the
//!   library never saw (a master seed of their own): each null specimen is one such
//!   realization, centred on the baseline with one draw of the baseline's own sampling
//!   error per data set, observed with measurement noise, rounded to the readings'
//!   resolution, and given its σ by the same rule as the data ([`super::null::draw_data`]). Two alarms
//!   are calibrated together ([`super::null::calibrate_margins`]): the best candidate's gain over the
//!   baseline (a cause named) and the baseline's score (a significant misfit), so that
//!   null data raise either in at most 5 % of the data sets. The false-alarm rate of
//!   margins set this way is measured by cross-fitting (margins from one half of the null
//!   data sets, alarms on the other) and reported with its Clopper–Pearson interval.
//! * **Ties.** Each of the next four candidates after a named cause, and every later
//!   candidate within the data test's bound, is in the tie when the
//!   design cannot separate it from the cause (it beats the cause on 5 % or more of data
//!   simulated from the cause's own independent realizations, [`reversal_rates`]) or the
//!   data cannot (its held-out difference to the cause is under two standard errors),
//!   [`TieCheck`].
//! * **Ranking.** Candidates are ranked by their surrogate's held-out error; the two best
//!   are then run as full ensembles at their fitted parameters and re-scored with their
//!   surrogates re-centred on those runs ([`super::fit::Surface::Corrected`]); the ranking,
//!   the gain and the verdict use those scores.

use super::candidate::Candidate;
use super::compare::{difference_se, per_specimen};
use super::fit::{Data, Surface};
use super::null::{draw_data, quantile, Margins, NullSource};
use super::observations::Observation;
use super::predictive::{Predictive, Simulated};
pub use super::rank::{rank, score, sort, Models, Ranked};
use crate::rng::{rng_for, Purpose};
use rayon::prelude::*;
use serde::Serialize;

/// The verdict of an analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// A candidate explains the misfit, and the extended model passes its posterior
    /// predictive check.
    Explained,
    /// The baseline fits: nothing to explain.
    NoEffect,
    /// The baseline misfits and no candidate explains it (the best may be a partial
    /// explanation).
    Unexplained,
}

impl Verdict {
    /// `explained`, `no_effect`, `unexplained`.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Explained => "explained",
            Verdict::NoEffect => "no_effect",
            Verdict::Unexplained => "unexplained",
        }
    }
}

/// Challengers always checked against a named cause for a tie, the best after it
/// ([`TieCheck`]); a later candidate is checked too when the data cannot tell it from the
/// cause (its held-out difference under [`TieCheck::STANDARD_ERRORS`] standard errors), so
/// that a model the data tie to the cause is never left out for its rank.
pub const TIE_CHALLENGERS: usize = 4;

/// One challenger checked against the named cause for a tie. It is in the tie when either
/// test fails to separate the two:
///
/// * **the design**: it beats the cause (lower held-out error) on 5 % or more of data
///   simulated from the cause's own independent realizations (the reversal rate); this
///   assumes the cause's model is exactly right;
/// * **the data**: its summed held-out difference to the cause, over specimens, is less
///   than two standard errors of that difference, `sqrt(n · var(dᵢ))` over the
///   per-specimen differences (Vehtari, Gelman & Gabry 2017; ArviZ `compare`'s `dse`).
///   This needs no model to be right: when the data lie between two models, or off both,
///   the per-specimen differences scatter more than either model's own data would make
///   them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TieCheck {
    /// The challenger's name.
    pub name: String,
    /// Rate at which it beats the cause on data simulated from the cause, in [0, 1].
    pub reversal_rate: f64,
    /// Its summed held-out score minus the cause's, over specimens (≥ 0: the cause ranks
    /// first).
    pub difference: f64,
    /// Standard error of that difference.
    pub difference_se: f64,
    /// In the tie.
    pub tied: bool,
}

impl TieCheck {
    /// Reversal rate at or above which the design cannot separate two candidates.
    pub const REVERSAL_RATE: f64 = 0.05;
    /// Standard errors of the held-out difference below which the data cannot.
    pub const STANDARD_ERRORS: f64 = 2.0;

    /// The check of `challenger` against `cause` (held-out scores per observation of
    /// `obs`, summed per specimen) at reversal rate `reversal_rate`.
    pub fn new(
        cause: &Ranked,
        challenger: &Ranked,
        reversal_rate: f64,
        obs: &[Observation],
        specimens: &[String],
    ) -> TieCheck {
        let a = per_specimen(&challenger.scores, obs, specimens);
        let b = per_specimen(&cause.scores, obs, specimens);
        let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
        let difference: f64 = d.iter().sum();
        let difference_se = difference_se(&d);
        let tied = reversal_rate >= Self::REVERSAL_RATE || difference < Self::STANDARD_ERRORS * difference_se;
        TieCheck { name: challenger.name.clone(), reversal_rate, difference, difference_se, tied }
    }
}

/// Rate at which a challenger ranks above a model (lower held-out error) on data simulated
/// from that model: `replicates` data sets drawn from `source` (the model's own
/// independent realizations) and read as the data are. A challenger that beats the true
/// model on 5 % or more of its data cannot be told from it by this design: the two are a
/// tie (a Monte Carlo version of the reversal probability of Vehtari, Gelman & Gabry 2017,
/// §5, for the design at hand).
pub fn reversal_rates(
    winner: &Candidate,
    challengers: &[&Candidate],
    data0: Data<'_>,
    specimens: &[String],
    source: NullSource<'_>,
    replicates: usize,
    seed: u64,
) -> Vec<f64> {
    if challengers.is_empty() || replicates == 0 {
        return vec![0.0; challengers.len()];
    }
    let zero = vec![0.0; specimens.len()];
    let wins: Vec<Vec<bool>> = (0..replicates)
        .into_par_iter()
        .map(|b| {
            let mut rng = rng_for(seed ^ 0x71e5_71e5_0000_0001, b as u64, Purpose::Discrepancy);
            let (y, o) = draw_data(data0, specimens, source, data0.reading, &mut rng);
            let data = Data { obs: &o, y: &y, ..data0 };
            let w = score(winner, data, specimens, 0, &zero).heldout_error;
            challengers.iter().map(|c| score(c, data, specimens, 0, &zero).heldout_error < w).collect()
        })
        .collect();
    (0..challengers.len()).map(|k| wins.iter().filter(|w| w[k]).count() as f64 / replicates as f64).collect()
}

/// Pairs of the three best one-parameter mechanisms, with the additive surrogate.
pub fn pairs(lib: &Models, ranked: &[Ranked]) -> Vec<Candidate> {
    let top: Vec<&Candidate> = ranked
        .iter()
        .map(|r| &lib.candidates[r.index])
        .filter(|c| c.effects.len() == 1 && c.surface.dims() == 1)
        .take(3)
        .collect();
    let mut out = Vec::new();
    for i in 0..top.len() {
        for j in i + 1..top.len() {
            let (a, b) = (top[i], top[j]);
            out.push(Candidate {
                effects: vec![a.effects[0].clone(), b.effects[0].clone()],
                params: a.params.iter().chain(&b.params).cloned().collect(),
                kinds: a.kinds.clone(),
                surface: Surface::Pair {
                    a: Box::new(a.surface.clone()),
                    b: Box::new(b.surface.clone()),
                    base: lib.baseline.clone(),
                },
            });
        }
    }
    out
}

/// The posterior predictive check of a model on the data: its score per specimen (at its
/// full-data fit) on the collapse angles, displacements and failure heights
/// ([`Data::fit_checked`]: not the mechanism's kind and start, which a person classifies
/// by a convention of their own) against the 95th
/// percentile of the same score on `replicates` data sets drawn from the model's own
/// independent realizations; the observables it misses are listed over every key, the
/// kinds and starts included.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictiveCheck {
    /// The data's score per specimen.
    pub score: f64,
    /// The 95th percentile of the score per specimen on the model's own data.
    pub envelope: f64,
    /// Data sets drawn.
    pub replicates: usize,
    /// Observables the model misses (|mean standardized residual| > 2/√n), with that
    /// residual.
    pub missed: Vec<(String, f64)>,
}

impl PredictiveCheck {
    /// The model fits its data as well as it fits its own.
    pub fn passes(&self) -> bool {
        self.score <= self.envelope
    }
}

/// Runs the check: `sims` the model's simulated values per key, `source` its independent
/// realizations, `labels` the key labels (`GROUP alpha_max`, …).
pub fn predictive_check(
    data: Data<'_>,
    sims: &[Simulated],
    specimens: &[String],
    source: NullSource<'_>,
    replicates: usize,
    seed: u64,
    labels: &[String],
) -> PredictiveCheck {
    let n = specimens.len().max(1) as f64;
    let all: Vec<usize> = (0..data.obs.len()).collect();
    let checked: Vec<usize> = all.iter().copied().filter(|&j| data.fit_checked(j)).collect();
    let score = data.nlpd(sims, &checked) / n;
    let null: Vec<f64> = (0..replicates)
        .into_par_iter()
        .map(|b| {
            let mut rng = rng_for(seed ^ 0x9e37_79b9_7f4a_7c15, b as u64, Purpose::Discrepancy);
            let (y, o) = draw_data(data, specimens, source, data.reading, &mut rng);
            Data { obs: &o, y: &y, ..data }.nlpd(sims, &checked) / n
        })
        .collect();
    let mut missed = Vec::new();
    for (k, label) in labels.iter().enumerate() {
        let z: Vec<f64> =
            all.iter().filter(|&&j| data.key[j] == k).map(|&j| data.predictive(sims, j).z(data.y[j])).collect();
        if z.is_empty() {
            continue;
        }
        let zbar = crate::stats::mean(&z);
        if zbar.abs() > 2.0 / (z.len() as f64).sqrt() {
            missed.push((label.clone(), zbar));
        }
    }
    PredictiveCheck { score, envelope: quantile(null, 0.95), replicates, missed }
}

/// The outcome of an analysis.
#[derive(Debug, Clone, Serialize)]
pub struct Analysis {
    /// The verdict.
    pub verdict: Verdict,
    /// The named cause (`explained`), or the best candidate as a partial explanation
    /// (`unexplained` after a failed predictive check).
    pub cause: Option<Ranked>,
    /// Candidates indistinguishable from the cause, the cause first; one entry when the
    /// cause is unique. A challenger is in the tie when the design cannot separate it from
    /// the cause or the data cannot ([`TieCheck`]).
    pub tie: Vec<String>,
    /// The challengers checked for the tie (the [`TIE_CHALLENGERS`] next best candidates,
    /// and every later one within the data test's bound), each with both tests.
    pub tie_checks: Vec<TieCheck>,
    /// All candidates, best first.
    pub candidates: Vec<Ranked>,
    /// The baseline's held-out error (its score per specimen).
    pub baseline_heldout_error: f64,
    /// The baseline's AICc.
    pub baseline_information_criterion: f64,
    /// Predictive of each observation under the baseline.
    pub baseline_predictive: Vec<Predictive>,
    /// Score of each observation under the baseline.
    pub baseline_scores: Vec<f64>,
    /// The best gain in held-out error of the library's candidates on their surrogates
    /// alone, before pairs and confirmation runs: the statistic the gain margin is
    /// calibrated on. A cause is named only when it and the confirmed winner's gain both
    /// clear the margin.
    pub screen_gain: f64,
    /// The margins used.
    pub margins: Margins,
    /// The posterior predictive check of the extended model (of the baseline when no cause
    /// is named).
    pub check: Option<PredictiveCheck>,
    /// The weight of the baseline and of every candidate (`scatter` and pairs included):
    /// pseudo-BMA+ and stacking on the held-out scores per specimen, with their bootstrap
    /// intervals, and the models that share the weight ([`super::weights()`]).
    pub weights: super::weights::Weights,
    /// Which observables of the design separate the models that share the weight, and the
    /// pairs none separates ([`super::identifiability`]).
    pub identifiability: super::identify::Identifiability,
    /// The candidates analysed, pairs included.
    #[serde(skip)]
    pub pool: Vec<Candidate>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::Observable;

    fn ranked(name: &str, scores: Vec<f64>) -> Ranked {
        Ranked {
            name: name.into(),
            parameters: vec![],
            heldout_error: 0.0,
            difference_se: 0.0,
            information_criterion: 0.0,
            confirmed: false,
            x: vec![],
            index: 0,
            scores,
            predictive: vec![],
        }
    }

    /// The tie check's data test is the summed difference against two of its standard
    /// errors, `sqrt(n · var(dᵢ))` over specimens (two observations per specimen here,
    /// summed first); its design test is the reversal rate against 5 %.
    #[test]
    fn a_challenger_is_tied_when_the_design_or_the_data_cannot_separate_it() {
        let obs: Vec<Observation> = (0..8)
            .map(|j| Observation {
                specimen: format!("S{}", j / 2),
                group: "G".into(),
                observable: Observable::CollapseAngle,
                value: 0.0,
                sigma: 1.0,
            })
            .collect();
        let specimens = crate::discrepancy::observations::specimens(&obs);
        assert_eq!(specimens.len(), 4);
        let cause = ranked("a", vec![0.0; 8]);
        // Per-specimen differences 1, 3, 1, 3: sum 8, sd 2/√3, se = √4 · sd = 2.309.
        let close = ranked("b", vec![0.5, 0.5, 1.0, 2.0, 0.0, 1.0, 3.0, 0.0]);
        let t = TieCheck::new(&cause, &close, 0.0, &obs, &specimens);
        let se = 2.0 * (4.0f64 / 3.0).sqrt();
        assert!((t.difference - 8.0).abs() < 1e-12 && (t.difference_se - se).abs() < 1e-12, "{t:?}");
        assert!(!t.tied, "8 > 2 × {se}: separated by the data, and the design (rate 0)");
        // The same mean difference with a wide spread: 8 < 2 se.
        let wide = ranked("c", vec![-2.0, 0.0, 5.0, 0.0, -3.0, 0.0, 8.0, 0.0]);
        let t = TieCheck::new(&cause, &wide, 0.0, &obs, &specimens);
        assert!((t.difference - 8.0).abs() < 1e-12 && t.difference < 2.0 * t.difference_se && t.tied, "{t:?}");
        // Separated by the data, not by the design.
        let t = TieCheck::new(&cause, &close, 0.05, &obs, &specimens);
        assert!(t.tied);
        let t = TieCheck::new(&cause, &close, 0.049, &obs, &specimens);
        assert!(!t.tied);
    }
}
