//! Cause finding: the baseline's misfit, the candidates ranked by held-out error and AICc,
//! margins calibrated on null data, and the verdict.
//!
//! * **Hold-out.** Leave one specimen out: every specimen's observations are predicted by
//!   the candidate fitted to the other specimens only ([`super::fit::loso`]). The held-out
//!   error is the mean held-out NLPD per observation. The baseline has no parameter: its
//!   held-out error is its plain NLPD.
//! * **Information criterion.** AICc at the full-data fit (Hurvich & Tsai 1989).
//! * **Null calibration.** Null data sets are drawn under the baseline (the model is
//!   right, only realization spread and measurement error vary) and analysed exactly as
//!   the data: each null specimen is a baseline realization kept out of the library,
//!   observed with measurement noise ([`NullSource::Pool`]), or, without such a pool, a
//!   draw from the baseline's predictive distributions ([`NullSource::Predictive`]).
//!   The margin a candidate must beat the baseline by is the 95th percentile of the best
//!   candidate's gain on null data, so that a cause is named on at most 5 % of data sets
//!   the baseline explains; the margin over the runner-up is the 95th percentile of the
//!   gap between the best two candidates on null data; the baseline's misfit is
//!   significant when its NLPD exceeds the 95th percentile of its NLPD on null data.
//! * **Verdict.** `explained` when the best candidate beats the baseline by the margin and
//!   has the lower AICc (candidates within the runner-up margin of it are reported as a
//!   tie); otherwise `unexplained` when the baseline's misfit is significant, `no_effect`
//!   when it is not. When the best single effect leaves a significant misfit, pairs of the
//!   three best single effects are screened with the additive surrogate; a pair replaces
//!   the best single effect only if it beats it by the margin and has the lower AICc.

use super::fit::{aicc, fit, loso, Candidate, Data, Surface};
use super::observations::{Observable, Observation};
use super::predictive::{Predictive, Simulated};
use super::simulate::Outcome;
use crate::rng::{rng_for, Purpose};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use serde::Serialize;

/// The verdict of an analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// A candidate explains the misfit.
    Explained,
    /// The baseline fits: nothing to explain.
    NoEffect,
    /// The baseline misfits and no candidate explains it.
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

/// The models' simulated values, ready for analysis: the baseline per key and one
/// candidate per effect.
#[derive(Debug, Clone)]
pub struct Library {
    /// The baseline's simulated values, per key.
    pub baseline: Vec<Simulated>,
    /// The single-effect candidates.
    pub candidates: Vec<Candidate>,
}

/// Margins calibrated on null data (per observation, NLPD units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Margins {
    /// Gain over the baseline a candidate needs.
    pub baseline: f64,
    /// Lead over the runner-up needed to name one effect rather than a tie.
    pub runner_up: f64,
    /// The baseline's NLPD per observation above which its misfit is significant.
    pub misfit: f64,
    /// Null data sets drawn.
    pub replicates: usize,
}

/// A ranked candidate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ranked {
    /// Effect names.
    pub effects: Vec<String>,
    /// Fitted parameters on all data, `effect.param` → value.
    pub parameters: Vec<(String, f64)>,
    /// Mean held-out NLPD per observation.
    pub heldout_error: f64,
    /// AICc at the full-data fit.
    pub information_criterion: f64,
    /// Search coordinates of the full-data fit.
    #[serde(skip)]
    pub x: Vec<f64>,
    /// Index into the analysis's candidate list.
    #[serde(skip)]
    pub index: usize,
}

/// The outcome of an analysis.
#[derive(Debug, Clone, Serialize)]
pub struct Analysis {
    /// The verdict.
    pub verdict: Verdict,
    /// The named cause: the best candidate when the verdict is `explained`.
    pub cause: Option<Ranked>,
    /// Candidates indistinguishable from the cause (within the runner-up margin), the cause
    /// first; one entry when the cause is unique.
    pub tie: Vec<String>,
    /// All candidates, best first.
    pub candidates: Vec<Ranked>,
    /// The baseline's held-out error (its NLPD per observation) and AICc.
    pub baseline_heldout_error: f64,
    /// The baseline's AICc.
    pub baseline_information_criterion: f64,
    /// Held-out predictive of each observation under the baseline.
    pub baseline_predictive: Vec<Predictive>,
    /// Held-out NLPD of each observation under the baseline.
    pub baseline_scores: Vec<f64>,
    /// Held-out predictive of each observation under the cause (or the best candidate).
    pub best_predictive: Vec<Predictive>,
    /// Held-out NLPD of each observation under the cause (or the best candidate).
    pub best_scores: Vec<f64>,
    /// The margins used.
    pub margins: Margins,
    /// The candidates analysed, pairs included.
    #[serde(skip)]
    pub pool: Vec<Candidate>,
}

/// Held-out error and full-data fit of one candidate.
fn score(c: &Candidate, data: Data<'_>, specimens: &[String], index: usize) -> (Ranked, Vec<f64>, Vec<Predictive>) {
    let all: Vec<usize> = (0..data.obs.len()).collect();
    let (x, nlpd) = fit(&c.surface, data, &all);
    let (scores, pred) = loso(&c.surface, data, specimens);
    let n = data.obs.len();
    let ranked = Ranked {
        effects: c.effects.iter().map(|e| e.name().to_string()).collect(),
        parameters: c.values(&x),
        heldout_error: scores.iter().sum::<f64>() / n as f64,
        information_criterion: aicc(nlpd, c.surface.dims(), n),
        x,
        index,
    };
    (ranked, scores, pred)
}

/// Ranks the candidates on `data`: best held-out error first.
fn rank(pool: &[Candidate], data: Data<'_>, specimens: &[String]) -> Vec<(Ranked, Vec<f64>, Vec<Predictive>)> {
    let mut r: Vec<_> = pool.iter().enumerate().map(|(i, c)| score(c, data, specimens, i)).collect();
    r.sort_by(|a, b| a.0.heldout_error.total_cmp(&b.0.heldout_error).then(a.0.index.cmp(&b.0.index)));
    r
}

fn quantile95(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    crate::stats::quantile(&v, 0.95)
}

/// Where null data sets come from.
#[derive(Debug, Clone, Copy)]
pub enum NullSource<'a> {
    /// The baseline's Gaussian predictive distributions (parametric bootstrap).
    Predictive,
    /// Baseline realizations kept out of the library, `[group][realization]`: each null
    /// specimen is one of them, drawn with replacement, observed with measurement noise.
    /// This carries the model's true (non-Gaussian, correlated) spread into the null data.
    Pool(&'a [Vec<Outcome>], &'a [(usize, Observable)]),
}

/// One null data set: values for every observation.
fn null_values(
    lib: &Library,
    data0: Data<'_>,
    specimens: &[String],
    source: NullSource<'_>,
    rng: &mut ChaCha8Rng,
) -> Vec<f64> {
    let obs = data0.obs;
    let mut y: Vec<f64> = vec![0.0; obs.len()];
    match source {
        NullSource::Pool(pool, keys) => {
            for s in specimens {
                let idx: Vec<usize> = (0..obs.len()).filter(|&j| &obs[j].specimen == s).collect();
                let g = keys[data0.key[idx[0]]].0;
                // A group with fewer than three pooled realizations (e.g. a wall without
                // random input, run once) is drawn from its predictive distributions.
                let pick = (pool[g].len() >= 3).then(|| rng.random_range(0..pool[g].len()));
                for j in idx {
                    let z: f64 = StandardNormal.sample(rng);
                    let p = data0.predictive(&lib.baseline, j);
                    let v = match pick {
                        Some(r) => pool[g][r].value(&keys[data0.key[j]].1).map(|v| v + obs[j].sigma * z),
                        None => Some(p.mean + p.sd * z),
                    };
                    y[j] = v.filter(|v| v.is_finite()).unwrap_or(0.0);
                }
            }
        }
        NullSource::Predictive => {
            for (j, yj) in y.iter_mut().enumerate() {
                let p = data0.predictive(&lib.baseline, j);
                let z: f64 = StandardNormal.sample(rng);
                *yj = if p.mean.is_finite() { p.mean + p.sd * z } else { 0.0 };
            }
        }
    }
    y
}

/// Calibrates the margins on `replicates` null data sets of the observations `obs`, drawn
/// from `source` (seeded by `seed`, `Purpose::Discrepancy`, one stream per replicate).
#[allow(clippy::too_many_arguments)]
pub fn calibrate_margins(
    lib: &Library,
    obs: &[Observation],
    key: &[usize],
    specimens: &[String],
    resolution_deg: f64,
    replicates: usize,
    seed: u64,
    source: NullSource<'_>,
) -> Margins {
    let n = obs.len();
    let runs: Vec<(f64, f64, f64)> = (0..replicates)
        .into_par_iter()
        .map(|b| {
            let mut rng = rng_for(seed, b as u64, Purpose::Discrepancy);
            let zero = vec![0.0; n];
            let d0 = Data { obs, y: &zero, key, resolution_deg };
            let y = null_values(lib, d0, specimens, source, &mut rng);
            let data = Data { obs, y: &y, key, resolution_deg };
            let all: Vec<usize> = (0..n).collect();
            let base = data.nlpd(&lib.baseline, &all) / n as f64;
            let ranked = rank(&lib.candidates, data, specimens);
            let best = ranked.first().map_or(base, |r| r.0.heldout_error);
            let second = ranked.get(1).map_or(best, |r| r.0.heldout_error);
            (base - best, second - best, base)
        })
        .collect();
    Margins {
        baseline: quantile95(runs.iter().map(|r| r.0).collect()),
        runner_up: quantile95(runs.iter().map(|r| r.1).collect()),
        misfit: quantile95(runs.iter().map(|r| r.2).collect()),
        replicates,
    }
}

/// Pairs of the three best one-parameter effects, with the additive surrogate.
fn pairs(lib: &Library, ranked: &[(Ranked, Vec<f64>, Vec<Predictive>)]) -> Vec<Candidate> {
    let top: Vec<&Candidate> = ranked
        .iter()
        .map(|r| &lib.candidates[r.0.index])
        .filter(|c| c.effects.len() == 1 && c.surface.dims() == 1)
        .take(3)
        .collect();
    let mut out = Vec::new();
    for i in 0..top.len() {
        for j in i + 1..top.len() {
            let (a, b) = (top[i], top[j]);
            out.push(Candidate {
                effects: vec![a.effects[0], b.effects[0]],
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

/// Analyses the data `y` of the observations `obs` against the library with the
/// calibrated margins.
pub fn analyze(lib: &Library, data: Data<'_>, specimens: &[String], margins: Margins) -> Analysis {
    let n = data.obs.len();
    let all: Vec<usize> = (0..n).collect();
    let base_scores: Vec<f64> = all.iter().map(|&j| data.predictive(&lib.baseline, j).nlpd(data.y[j])).collect();
    let base_pred: Vec<Predictive> = all.iter().map(|&j| data.predictive(&lib.baseline, j)).collect();
    let base_he = base_scores.iter().sum::<f64>() / n as f64;
    let base_ic = aicc(base_he * n as f64, 0, n);
    let mut ranked = rank(&lib.candidates, data, specimens);
    let mut pool = lib.candidates.clone();
    // Pairs, when the best single effect leaves a significant misfit.
    if !ranked.is_empty() {
        let best_nlpd = ranked[0].1.iter().sum::<f64>() / n as f64;
        if best_nlpd > margins.misfit && base_he - ranked[0].0.heldout_error > margins.baseline {
            let offset = pool.len();
            let extra = pairs(lib, &ranked);
            let mut more = rank(&extra, data, specimens);
            for r in &mut more {
                r.0.index += offset;
            }
            pool.extend(extra);
            let (threshold, ic) = (ranked[0].0.heldout_error - margins.baseline, ranked[0].0.information_criterion);
            ranked.extend(more.into_iter().filter(|r| r.0.heldout_error < threshold && r.0.information_criterion < ic));
            ranked.sort_by(|a, b| a.0.heldout_error.total_cmp(&b.0.heldout_error).then(a.0.index.cmp(&b.0.index)));
        }
    }
    let (best_pred, best_scores) =
        ranked.first().map_or((base_pred.clone(), base_scores.clone()), |r| (r.2.clone(), r.1.clone()));
    let candidates: Vec<Ranked> = ranked.iter().map(|r| r.0.clone()).collect();
    let named = candidates
        .first()
        .filter(|b| base_he - b.heldout_error > margins.baseline && b.information_criterion < base_ic);
    let (verdict, cause, tie) = match named {
        Some(b) => {
            let tie: Vec<String> = candidates
                .iter()
                .filter(|c| c.heldout_error - b.heldout_error <= margins.runner_up)
                .map(|c| c.effects.join("+"))
                .collect();
            (Verdict::Explained, Some(b.clone()), tie)
        }
        None if base_he > margins.misfit => (Verdict::Unexplained, None, vec![]),
        None => (Verdict::NoEffect, None, vec![]),
    };
    Analysis {
        verdict,
        cause,
        tie,
        candidates,
        baseline_heldout_error: base_he,
        baseline_information_criterion: base_ic,
        baseline_predictive: base_pred,
        baseline_scores: base_scores,
        best_predictive: best_pred,
        best_scores,
        margins,
        pool,
    }
}
