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
///
/// With readings of the failure mechanism (failure height, kind, start) the same two tests
/// are also made on the measures alone (collapse angles and displacements,
/// [`super::Observable::pins`]), and the challenger is out of the tie when they separate it there and
/// the readings' own difference does not favour it beyond the data bound (it is at least
/// −[`TieCheck::STANDARD_ERRORS`] of its standard errors): readings that cannot tell the
/// two models apart add the scatter of a person's reading to every specimen's difference
/// and would otherwise undo a separation the angles made. Readings that point to the
/// challenger keep it in; readings that clear it where the angles cannot, clear it. With
/// the same cause, a model the measures separate from it is in the tie with the readings
/// only when the readings favour it (the synthetic data's measures are those drawn without
/// readings: the readings of a synthetic data set draw from a random stream of their own).
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
    /// With readings of the mechanism: the tests on the measures alone and the readings'
    /// own difference (`None` on angles and displacements alone).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub on_measures: Option<MeasuresCheck>,
    /// In the tie.
    pub tied: bool,
}

/// The tie check of one challenger on the measures alone, beside the readings that were
/// left out of it ([`TieCheck`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuresCheck {
    /// Rate at which it beats the cause on the measures of data simulated from the cause,
    /// in [0, 1].
    pub reversal_rate: f64,
    /// Its summed held-out score minus the cause's on the measures.
    pub difference: f64,
    /// Standard error of that difference.
    pub difference_se: f64,
    /// The same difference on the readings of the mechanism (< 0: they favour the
    /// challenger).
    pub readings_difference: f64,
    /// Standard error of the readings' difference.
    pub readings_difference_se: f64,
}

/// Reversal rates of a challenger against the cause (`reversal_rates`): on every
/// observation, and on the measures alone ([`super::Observable::pins`]; the same where every
/// observation is a measure).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reversal {
    /// On every observation.
    pub all: f64,
    /// On the measures alone.
    pub measures: f64,
}

impl TieCheck {
    /// Reversal rate at or above which the design cannot separate two candidates.
    pub const REVERSAL_RATE: f64 = 0.05;
    /// Standard errors of the held-out difference below which the data cannot.
    pub const STANDARD_ERRORS: f64 = 2.0;

    /// The check of `challenger` against `cause` (held-out scores per observation of
    /// `data`, summed per specimen) at reversal rates `reversal`.
    pub fn new(
        cause: &Ranked,
        challenger: &Ranked,
        reversal: Reversal,
        data: Data<'_>,
        specimens: &[String],
    ) -> TieCheck {
        // The summed per-specimen difference of two score vectors and its standard error.
        let compare = |ours: &[f64], theirs: &[f64]| -> (f64, f64) {
            let a = per_specimen(ours, data.obs, specimens);
            let b = per_specimen(theirs, data.obs, specimens);
            let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
            (d.iter().sum(), difference_se(&d))
        };
        let (difference, difference_se) = compare(&challenger.scores, &cause.scores);
        let separated = reversal.all < Self::REVERSAL_RATE && difference >= Self::STANDARD_ERRORS * difference_se;
        let on_measures = (0..data.obs.len()).any(|j| !data.pins(j)).then(|| {
            let (ours_m, ours_r) = data.split_scores(&challenger.scores);
            let (theirs_m, theirs_r) = data.split_scores(&cause.scores);
            let (difference, difference_se) = compare(&ours_m, &theirs_m);
            let (readings_difference, readings_difference_se) = compare(&ours_r, &theirs_r);
            MeasuresCheck {
                reversal_rate: reversal.measures,
                difference,
                difference_se,
                readings_difference,
                readings_difference_se,
            }
        });
        let separated_on_measures = on_measures.as_ref().is_some_and(|m| {
            m.reversal_rate < Self::REVERSAL_RATE
                && m.difference >= Self::STANDARD_ERRORS * m.difference_se
                && m.readings_difference >= -Self::STANDARD_ERRORS * m.readings_difference_se
        });
        TieCheck {
            name: challenger.name.clone(),
            reversal_rate: reversal.all,
            difference,
            difference_se,
            on_measures,
            tied: !(separated || separated_on_measures),
        }
    }
}

/// Rate at which a challenger ranks above a model (lower held-out error) on data simulated
/// from that model: `replicates` data sets drawn from `source` (the model's own
/// independent realizations) and read as the data are. A challenger that beats the true
/// model on 5 % or more of its data cannot be told from it by this design: the two are a
/// tie (a Monte Carlo version of the reversal probability of Vehtari, Gelman & Gabry 2017,
/// §5, for the design at hand). The rate on the measures alone ([`super::Observable::pins`]) compares
/// the held-out scores of the collapse angles and displacements of the same data sets.
pub fn reversal_rates(
    winner: &Candidate,
    challengers: &[&Candidate],
    data0: Data<'_>,
    specimens: &[String],
    source: NullSource<'_>,
    replicates: usize,
    seed: u64,
) -> Vec<Reversal> {
    if challengers.is_empty() || replicates == 0 {
        return vec![Reversal { all: 0.0, measures: 0.0 }; challengers.len()];
    }
    let zero = vec![0.0; specimens.len()];
    let wins: Vec<Vec<(bool, bool)>> = (0..replicates)
        .into_par_iter()
        .map(|b| {
            let mut rng = rng_for(seed ^ 0x71e5_71e5_0000_0001, b as u64, Purpose::Discrepancy);
            let (y, o) = draw_data(data0, specimens, source, data0.reading, &mut rng);
            let data = Data { obs: &o, y: &y, ..data0 };
            let on_measures = |r: &Ranked| -> f64 { data.split_scores(&r.scores).0.iter().sum() };
            let w = score(winner, data, specimens, 0, &zero);
            let wm = on_measures(&w);
            challengers
                .iter()
                .map(|c| {
                    let r = score(c, data, specimens, 0, &zero);
                    (r.heldout_error < w.heldout_error, on_measures(&r) < wm)
                })
                .collect()
        })
        .collect();
    let rate = |k: usize, pick: fn(&(bool, bool)) -> bool| {
        wins.iter().filter(|w| pick(&w[k])).count() as f64 / replicates as f64
    };
    (0..challengers.len()).map(|k| Reversal { all: rate(k, |w| w.0), measures: rate(k, |w| w.1) }).collect()
}

/// Pairs of the three best one-parameter mechanisms that move the wall, with the additive
/// surrogate, then every pair of an effect on the readings only with another searched
/// effect, on its partner's runs read again ([`Models::readings_pairs`]).
pub fn pairs(lib: &Models, ranked: &[Ranked]) -> Vec<Candidate> {
    // An effect on the readings only pairs with every effect on its partner's runs
    // (`Models::readings_pairs`): it takes no place among the three.
    let paired = |c: &Candidate| c.effects[0].acts_on_readings_only() && !lib.readings_pairs.is_empty();
    let top: Vec<&Candidate> = ranked
        .iter()
        .map(|r| &lib.candidates[r.index])
        .filter(|c| c.effects.len() == 1 && c.surface.dims() == 1 && !paired(c))
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
    out.extend(lib.readings_pairs.iter().cloned());
    out
}

/// The posterior predictive check of a model on the data: its score per specimen (at its
/// full-data fit) on the collapse angles, displacements and failure heights
/// (`Data::fit_checked`: not the mechanism's kind and start, which a person classifies
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
    /// The forward runs made, by stage (those of the preparation included, which many
    /// analyses of one design share).
    pub forward_runs: Vec<super::simulate::StageRuns>,
    /// The baseline's misfit of one sign in every group, if any
    /// ([`super::systematic_misfit`]): the scatter hypothesis is then not named.
    pub systematic: Option<super::SystematicMisfit>,
    /// The candidates a reading refutes at their latest fit, in the order they were asked
    /// ([`super::refute`]): none of them is named, confirmed or in the tie.
    pub refuted: Vec<super::Refutation>,
    /// The candidates analysed, pairs included.
    #[serde(skip)]
    pub pool: Vec<Candidate>,
}

impl Analysis {
    /// The cause named alone, the one meaning of "named alone" across the product (the
    /// report, `drystone design`'s probabilities and its follow-up's promise): the verdict
    /// is `explained` (a cause is named and the extended model passes its check) and the
    /// tie check clears every challenger ([`Analysis::tie`] holds the cause only). The
    /// partial explanation an `unexplained` verdict carries in [`Analysis::cause`] is not
    /// named, alone or not. The pseudo-BMA+ weights are reported beside it; a model holding
    /// [`super::SHARED`] of the weight is not by itself named alone.
    pub fn named_alone(&self) -> Option<&str> {
        self.cause
            .as_ref()
            .filter(|_| self.verdict == Verdict::Explained && self.tie.len() <= 1)
            .map(|c| c.name.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::{Observable, Observation};

    fn ranked(name: &str, scores: Vec<f64>) -> Ranked {
        Ranked::with_scores(name, scores)
    }

    fn observations(kinds: &[Observable]) -> Vec<Observation> {
        (0..4 * kinds.len())
            .map(|j| Observation {
                specimen: format!("S{}", j / kinds.len()),
                group: "G".into(),
                observable: kinds[j % kinds.len()],
                value: 0.0,
                sigma: 1.0,
            })
            .collect()
    }

    fn data<'a>(obs: &'a [Observation], zeros: &'a [f64], keys: &'a [usize]) -> Data<'a> {
        let reading = crate::discrepancy::predictive::Reading {
            angle_deg: 0.5,
            displacement_cm: 0.1,
            misreading: 0.1,
            neighbour_joint: 0.25,
            ..Default::default()
        };
        Data { obs, y: zeros, key: keys, weight: zeros, reading, bracket_deg: 0.5 }
    }

    /// An analysis with the verdict `verdict`, the cause `cause` and a tie of it alone.
    fn analysis(verdict: Verdict, cause: Option<&str>) -> Analysis {
        Analysis {
            verdict,
            cause: cause.map(|c| ranked(c, vec![])),
            tie: cause.map(str::to_string).into_iter().collect(),
            tie_checks: vec![],
            candidates: vec![],
            baseline_heldout_error: 0.0,
            baseline_information_criterion: 0.0,
            baseline_predictive: vec![],
            baseline_scores: vec![],
            screen_gain: 0.0,
            margins: Margins {
                baseline: 0.0,
                misfit: 0.0,
                replicates: 0,
                false_alarms: (0, 0),
                false_alarm_interval: (0.0, 0.0),
            },
            check: None,
            weights: Default::default(),
            identifiability: Default::default(),
            forward_runs: vec![],
            pool: vec![],
            systematic: None,
            refuted: vec![],
        }
    }

    /// Named alone is the verdict's: an `explained` verdict with a tie of one names its
    /// cause alone; the best candidate an `unexplained` verdict carries as a partial
    /// explanation (its extended model fails the predictive check) is not named at all, tie
    /// of one or not; `no_effect` names nothing.
    #[test]
    fn only_an_explained_verdict_names_a_cause_alone() {
        assert_eq!(analysis(Verdict::Explained, Some("a")).named_alone(), Some("a"));
        assert_eq!(analysis(Verdict::Unexplained, Some("a")).named_alone(), None);
        assert_eq!(analysis(Verdict::Unexplained, None).named_alone(), None);
        assert_eq!(analysis(Verdict::NoEffect, None).named_alone(), None);
    }

    fn rate(all: f64) -> Reversal {
        Reversal { all, measures: all }
    }

    /// The tie check's data test is the summed difference against two of its standard
    /// errors, `sqrt(n · var(dᵢ))` over specimens (two observations per specimen here,
    /// summed first); its design test is the reversal rate against 5 %.
    #[test]
    fn a_challenger_is_tied_when_the_design_or_the_data_cannot_separate_it() {
        let obs = observations(&[Observable::CollapseAngle, Observable::CollapseAngle]);
        let (zeros, keys) = (vec![0.0; 8], vec![0; 8]);
        let data = data(&obs, &zeros, &keys);
        let specimens = crate::discrepancy::observations::specimens(&obs);
        assert_eq!(specimens.len(), 4);
        let cause = ranked("a", vec![0.0; 8]);
        // Per-specimen differences 1, 3, 1, 3: sum 8, sd 2/√3, se = √4 · sd = 2.309.
        let close = ranked("b", vec![0.5, 0.5, 1.0, 2.0, 0.0, 1.0, 3.0, 0.0]);
        let t = TieCheck::new(&cause, &close, rate(0.0), data, &specimens);
        let se = 2.0 * (4.0f64 / 3.0).sqrt();
        assert!((t.difference - 8.0).abs() < 1e-12 && (t.difference_se - se).abs() < 1e-12, "{t:?}");
        assert!(!t.tied && t.on_measures.is_none(), "8 > 2 × {se}: separated by the data, and the design (rate 0)");
        // The same mean difference with a wide spread: 8 < 2 se.
        let wide = ranked("c", vec![-2.0, 0.0, 5.0, 0.0, -3.0, 0.0, 8.0, 0.0]);
        let t = TieCheck::new(&cause, &wide, rate(0.0), data, &specimens);
        assert!((t.difference - 8.0).abs() < 1e-12 && t.difference < 2.0 * t.difference_se && t.tied, "{t:?}");
        // Separated by the data, not by the design.
        let t = TieCheck::new(&cause, &close, rate(0.05), data, &specimens);
        assert!(t.tied);
        let t = TieCheck::new(&cause, &close, rate(0.049), data, &specimens);
        assert!(!t.tied);
    }

    /// With a reading of the mechanism per specimen: readings that scatter without favouring
    /// either model do not undo the angles' separation, readings that favour the challenger
    /// beyond two standard errors keep it in the tie, and the design test on the measures
    /// still holds.
    #[test]
    fn readings_that_cannot_tell_two_models_apart_do_not_undo_the_angles_separation() {
        let obs = observations(&[Observable::CollapseAngle, Observable::FailureHeight { width: 0.1 }]);
        let (zeros, keys) = (vec![0.0; 8], vec![0; 8]);
        let data = data(&obs, &zeros, &keys);
        let specimens = crate::discrepancy::observations::specimens(&obs);
        let cause = ranked("a", vec![0.0; 8]);
        // Angles: 2, 3, 2, 3 (sum 10, se = 2 · sd = 2 · 0.577 = 1.155): separated.
        // Readings: +4, −4, +4, −4 (sum 0, se = 2 · 4.619 = 9.24): no side taken.
        // Together: 6, −1, 6, −1 (sum 10, se = 2 · 4.041 = 8.08): 10 < 16.2, tied.
        let noisy = ranked("b", vec![2.0, 4.0, 3.0, -4.0, 2.0, 4.0, 3.0, -4.0]);
        let t = TieCheck::new(&cause, &noisy, rate(0.0), data, &specimens);
        assert!(t.difference < 2.0 * t.difference_se, "{t:?}");
        let m = t.on_measures.clone().expect("readings present");
        assert!((m.difference - 10.0).abs() < 1e-12 && (m.readings_difference).abs() < 1e-12, "{m:?}");
        assert!(!t.tied, "{t:?}");
        // The same angles, readings that favour the challenger by 3 on every specimen but
        // one (−3, −3, −3, −2: sum −11, se = 2 · 0.5 = 1): in the tie.
        let favoured = ranked("c", vec![2.0, -3.0, 3.0, -3.0, 2.0, -3.0, 3.0, -2.0]);
        let t = TieCheck::new(&cause, &favoured, rate(0.0), data, &specimens);
        assert!(t.tied, "{t:?}");
        // The noisy readings again, the design unable to separate on the measures.
        let t = TieCheck::new(&cause, &noisy, Reversal { all: 0.0, measures: 0.05 }, data, &specimens);
        assert!(t.tied, "{t:?}");
    }
}
