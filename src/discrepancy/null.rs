//! Null data and the margins: synthetic data sets drawn under a model from layouts the
//! fits never saw ([`draw_data`]), the measurement σ rule applied to them as to the data
//! ([`SigmaRule`]), and the gain and misfit margins calibrated on them together
//! ([`calibrate_margins`]) with their false-alarm rate measured by cross-fitting.
//!
//! Null data sets are drawn under the baseline from layouts the library never saw (a
//! master seed of their own): each null specimen is one such realization, centred on the
//! baseline with one draw of the baseline's own sampling error per data set, observed with
//! measurement noise, rounded to the readings' resolution, and given its σ by the same rule
//! as the data. Two alarms are calibrated together: the best candidate's gain over the
//! baseline (a cause named) and the baseline's score (a significant misfit), so that null
//! data raise either in at most 5 % of the data sets.

use super::compare::per_specimen;
use super::fit::Data;
use super::observations::{Family, Observable, Observation, Share, MEASURE_FAMILIES};
use super::predictive::{Reading, Simulated};
use super::rank::{rank, Models};
use super::simulate::Outcome;
use crate::rng::{rng_for, Purpose};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use serde::Serialize;

/// Margins calibrated on null data (per specimen, score units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Margins {
    /// Gain over the baseline a candidate needs.
    pub baseline: f64,
    /// The baseline's score per specimen above which its misfit is significant.
    pub misfit: f64,
    /// Null data sets drawn (all set the margins).
    pub replicates: usize,
    /// False alarms (either alarm) of margins set on one half of the null data sets,
    /// counted on the other half, both ways; and the data sets counted.
    pub false_alarms: (usize, usize),
    /// 95 % Clopper–Pearson interval of the false-alarm rate.
    pub false_alarm_interval: (f64, f64),
}

/// The `p` quantile of `v` (sorted here).
pub(super) fn quantile(mut v: Vec<f64>, p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    crate::stats::quantile(&v, p)
}

/// Where null data sets come from: realizations of a model on layouts the fits never saw,
/// `[group][realization]`, with the `(group, observable)` of every key. A group with fewer
/// than three realizations (a wall without random input) is drawn from its predictive.
#[derive(Debug, Clone, Copy)]
pub struct NullSource<'a> {
    /// The realizations.
    pub pool: &'a [Vec<Outcome>],
    /// The keys.
    pub keys: &'a [(usize, Observable)],
    /// The pool's own mean and spread per key.
    pub sims: &'a [Simulated],
    /// The model the null data stand for, per key: the data are centred on its mean, and
    /// its number of realizations sets the error of that mean that each data set draws.
    pub centre: &'a [Simulated],
    /// How the analysis sets the measurement σ from the data, applied again to every
    /// synthetic data set.
    pub sigma: SigmaRule<'a>,
}

/// How the analysis sets each observation's measurement σ: the stated σ, or the spread
/// the data show beyond the model's ([`super::observations::measurement_sigma`]) if
/// larger. Applied to the measured data and again to every synthetic data set, so that
/// the margins carry the uncertainty of a σ estimated from a few specimens (a parametric
/// bootstrap of the whole procedure; Efron & Tibshirani 1993, §6.5).
#[derive(Debug, Clone, Copy)]
pub struct SigmaRule<'a> {
    /// The stated σ of every observation (the file's, or the settings').
    pub stated: &'a [f64],
    /// The model's spread per key (the baseline's full run).
    pub model_sd: &'a [f64],
    /// The readings' resolutions.
    pub reading: Reading,
}

impl SigmaRule<'_> {
    /// Sets `obs[j].sigma` from the data (`obs[j].value`, keys `key`); returns the estimate
    /// of collapse angles and of displacements, each with its degrees of freedom.
    pub fn apply(&self, obs: &mut [Observation], key: &[usize]) -> [Option<(f64, usize)>; MEASURE_FAMILIES] {
        let est = Family::ALL.map(|family| {
            let r = self.reading.of_family(family);
            super::observations::measurement_sigma(obs, key, self.model_sd, r, family)
        });
        for (o, &stated) in obs.iter_mut().zip(self.stated) {
            // A mechanism observation keeps its stated σ.
            o.sigma = o.observable.family().and_then(|f| est[f.index()]).map_or(stated, |(sd, _)| stated.max(sd));
        }
        est
    }
}

/// One synthetic data set: values for every observation, each specimen one realization of
/// `source` (drawn with replacement), plus Gaussian noise of the observation's σ, rounded
/// to the reading resolution; and the observations with their σ set from these values as
/// the analysis sets them from the measured ones.
///
/// The values are centred on the model's mean, not on the pool's: a realization enters as
/// its deviation from the pool's mean, and every data set adds one draw of the error of
/// the model's mean (the mean of `R` realizations drawn from the pool, less the pool's
/// mean; `R` the model's realizations; one draw per group, so that a group's observables
/// err together). Under the null hypothesis the measured data differ from the model by
/// the specimens' spread and by the model's own sampling error; the synthetic data do by
/// the same two, whatever the pool's mean happens to be.
///
/// Mechanism readings are read by the likelihood's reading model
/// ([`super::predictive`]): a kind or a start misread at [`Reading::misreading`], a
/// failure height uniform over the wall at the same rate, else possibly a neighbouring
/// joint ([`Reading::neighbour_read`]). The replicates of the predictive check, the null
/// calibration and the tie check's reversal rates are thus read as the likelihood says
/// readings are, as the design's simulated campaigns are (`super::design`).
pub fn draw_data(
    data0: Data<'_>,
    specimens: &[String],
    source: NullSource<'_>,
    reading: Reading,
    rng: &mut ChaCha8Rng,
) -> (Vec<f64>, Vec<Observation>) {
    let obs = data0.obs;
    let groups = source.pool.len();
    let mut delta = vec![0.0f64; source.keys.len()];
    for g in 0..groups {
        let n = source.pool[g].len();
        if n < 3 {
            continue;
        }
        let r = (0..source.keys.len())
            .filter(|&k| source.keys[k].0 == g)
            .map(|k| source.centre[k].n)
            .max()
            .unwrap_or(0)
            .max(1);
        let picks: Vec<usize> = (0..r).map(|_| rng.random_range(0..n)).collect();
        for (k, (kg, o)) in source.keys.iter().enumerate() {
            if *kg != g {
                continue;
            }
            let v: Vec<f64> =
                picks.iter().filter_map(|&i| source.pool[g][i].value(o)).filter(|v| v.is_finite()).collect();
            if !v.is_empty() && source.sims[k].mean.is_finite() {
                delta[k] = crate::stats::mean(&v) - source.sims[k].mean;
            }
        }
    }
    let scale = spread_scale(data0, source, reading, rng);
    // The readings of the mechanism draw from a stream of their own (the same position,
    // another ChaCha stream; the measures' stream is not advanced by it), so that the
    // collapse angles and displacements of a replicate are the same with and without
    // readings (common random numbers: the tie check's test on the measures alone,
    // `TieCheck::on_measures`, then sees the replicates the analysis without readings saw).
    let mut readings_rng = {
        let mut r = rng.clone();
        r.set_stream(rng.get_stream() ^ 0x6d65_6368_616e_6973);
        r
    };
    let mut y: Vec<f64> = vec![0.0; obs.len()];
    for s in specimens {
        let idx: Vec<usize> = (0..obs.len()).filter(|&j| &obs[j].specimen == s).collect();
        let Some(&first) = idx.first() else { continue };
        let g = source.keys[data0.key[first]].0;
        let pick = (source.pool[g].len() >= 3).then(|| rng.random_range(0..source.pool[g].len()));
        let shared: f64 = StandardNormal.sample(rng);
        for j in idx {
            let rng: &mut ChaCha8Rng = if obs[j].observable.pins() { &mut *rng } else { &mut readings_rng };
            let z: f64 = StandardNormal.sample(rng);
            let k = data0.key[j];
            if let Some(category) = obs[j].observable.category() {
                // A category: the realization's own (or, without one, a draw from the
                // predictive), then misread.
                let seen = pick.and_then(|r| source.pool[g][r].value(&source.keys[k].1));
                let u: f64 = rng.random();
                y[j] = f64::from(u8::from(match seen {
                    Some(v) => misread(v >= 0.5, category, reading.misreading, u),
                    None => {
                        let q = reading.category_probability(&obs[j].observable, &source.centre[k]).unwrap_or(0.5);
                        u < q
                    }
                }));
                continue;
            }
            let p = data0.predictive(source.centre, j);
            let v = match pick {
                Some(r) => source.pool[g][r].value(&source.keys[k].1).map(|v| {
                    let (c, m) = (source.centre[k].mean, source.sims[k].mean);
                    let f = scale[kind_of(&obs[j].observable)];
                    if c.is_finite() && m.is_finite() {
                        c + delta[k] + f * ((v - m) + obs[j].sigma * z)
                    } else {
                        v + obs[j].sigma * z
                    }
                }),
                None => Some({
                    let f = scale[kind_of(&obs[j].observable)];
                    p.mean + f * p.sd * if obs[j].observable.share() == Share::Displacements { shared } else { z }
                }),
            };
            // A realization that fell before the tilt gives no displacement: the specimen
            // is read at its predictive mean there (rare; keeps the design balanced).
            let v = v.filter(|v| v.is_finite()).unwrap_or(if p.mean.is_finite() { p.mean } else { 0.0 });
            // A failure height is read as the likelihood's reading model has it
            // (`predictive::Heights::probability`): with probability ε it belongs to none
            // of the simulated failures (uniform over the height), else a neighbouring
            // joint may be named.
            let v = match obs[j].observable.place_width() {
                Some(width) => {
                    let (misread, anywhere, neighbour): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
                    if misread < reading.misreading {
                        anywhere
                    } else {
                        reading.neighbour_read(v, width, neighbour)
                    }
                }
                None => v,
            };
            y[j] = reading.round(&obs[j].observable, v);
        }
    }
    let mut o: Vec<Observation> = obs.to_vec();
    for (o, v) in o.iter_mut().zip(&y) {
        o.value = *v;
    }
    source.sigma.apply(&mut o, data0.key);
    (y, o)
}

/// A category seen (`seen`) or not, read with misreading probability `e` (`category` = `(m,
/// K)`: a category not seen is misread as this one with probability `e m / (K − 1)`), for
/// a uniform draw `u` in [0, 1).
fn misread(seen: bool, category: (usize, usize), e: f64, u: f64) -> bool {
    let (m, k) = (category.0 as f64, category.1 as f64);
    if seen {
        u >= e
    } else {
        u < e * m / (k - 1.0)
    }
}

/// Its family of measures ([`Observable::family`]), [`MEASURE_FAMILIES`] for a reading of
/// the mechanism.
fn kind_of(o: &Observable) -> usize {
    o.family().map_or(MEASURE_FAMILIES, Family::index)
}

/// The factor on a synthetic data set's deviations from the model's mean, per kind
/// (collapse angles, displacements), that gives them the spread of the measured data,
/// drawn with that spread's uncertainty: `f² = Σ_k ν_k (s_k² / v_k) / χ²_ν`, with `s_k²`
/// the data's variance at key `k` (specimens of one group and observable; a shift of a
/// group's mean does not enter it) less the readings' rounding `r²/12`, `v_k` the
/// variance the draws have there before the factor (the source's realizations about their
/// mean, which the draws resample, and the measurement σ; the predictive's where a group
/// is drawn from it), `ν_k = n_k − 1` and `ν = Σ ν_k`: the ratios are pooled, so a group
/// whose layouts barely scatter counts as much as one whose layouts scatter a lot. Under
/// the null hypothesis the data's spread is the walls' and the readings' together,
/// whatever the stated σ and whatever the few realizations of the source show; the null
/// distribution of the scores is then that of data as dispersed as the measured ones, and
/// a spread alone (no shift of a mean) is not evidence for a mechanism. 1 below
/// [`super::observations::MIN_SIGMA_DOF`] degrees of freedom.
fn spread_scale(
    data0: Data<'_>,
    source: NullSource<'_>,
    reading: Reading,
    rng: &mut ChaCha8Rng,
) -> [f64; MEASURE_FAMILIES + 1] {
    let obs = data0.obs;
    let mut acc = [(0.0f64, 0.0f64, 0usize); MEASURE_FAMILIES]; // (Σ ν_k s_k² / v_k, unused, ν)
    for (k, (g, o)) in source.keys.iter().enumerate() {
        let Some(family) = o.family() else {
            continue; // a reading of the mechanism: drawn as the realizations have them (factor 1)
        };
        let idx: Vec<usize> = (0..obs.len()).filter(|&j| data0.key[j] == k).collect();
        if idx.len() < 2 {
            continue;
        }
        let y: Vec<f64> = idx.iter().map(|&j| data0.y[j]).collect();
        let m = crate::stats::mean(&y);
        let ss = y.iter().map(|v| (v - m).powi(2)).sum::<f64>();
        let sigma2 = idx.iter().map(|&j| obs[j].sigma.powi(2)).sum::<f64>() / idx.len() as f64;
        let pool = &source.pool[*g];
        let v = if pool.len() >= 3 {
            let vals: Vec<f64> = pool.iter().filter_map(|r| r.value(o)).filter(|v| v.is_finite()).collect();
            if vals.len() < 2 {
                continue;
            }
            let pm = crate::stats::mean(&vals);
            vals.iter().map(|v| (v - pm).powi(2)).sum::<f64>() / vals.len() as f64 + sigma2
        } else {
            data0.predictive(source.centre, idx[0]).sd.powi(2)
        };
        if !(v > 0.0) {
            continue;
        }
        let kind = family.index();
        let r = reading.of_family(family);
        let dof = idx.len() - 1;
        let s2 = (ss / dof as f64 - r * r / 12.0).max(1e-3 * v);
        let a = &mut acc[kind];
        a.0 += dof as f64 * s2 / v;
        a.2 += dof;
    }
    let mut out = [1.0; MEASURE_FAMILIES + 1];
    for (family, (ratio, _, nu)) in Family::ALL.into_iter().zip(acc) {
        // One χ² draw for each of the tilting table's families whether used or not, and for
        // each in-plane family the design holds: the stream does not depend on the data.
        if !family.always_drawn() && !source.keys.iter().any(|(_, o)| o.family() == Some(family)) {
            continue;
        }
        let kind = family.index();
        let chi2: f64 = rand_distr::ChiSquared::new(nu.max(1) as f64).map_or(1.0, |c| c.sample(rng));
        if nu < super::observations::MIN_SIGMA_DOF {
            continue;
        }
        out[kind] = (ratio / chi2.max(1e-9)).sqrt();
    }
    out
}

/// The 95 % Clopper–Pearson interval of a binomial proportion `k / n`.
pub fn clopper_pearson(k: usize, n: usize) -> (f64, f64) {
    use statrs::distribution::{Beta, ContinuousCDF};
    if n == 0 {
        return (0.0, 1.0);
    }
    let (k, nf) = (k as f64, n as f64);
    let lo = if k == 0.0 { 0.0 } else { Beta::new(k, nf - k + 1.0).map_or(0.0, |b| b.inverse_cdf(0.025)) };
    let hi = if k == nf { 1.0 } else { Beta::new(k + 1.0, nf - k).map_or(1.0, |b| b.inverse_cdf(0.975)) };
    (lo, hi)
}

/// Calibrates the margins on `replicates` null data sets drawn from `source` (seeded by
/// `seed`, `Purpose::Discrepancy`, one stream per replicate): the gain and misfit margins
/// together (`joint_margins`).
pub fn calibrate_margins(
    lib: &Models,
    data0: Data<'_>,
    specimens: &[String],
    replicates: usize,
    seed: u64,
    source: NullSource<'_>,
) -> Margins {
    let n = specimens.len().max(1) as f64;
    let runs: Vec<(f64, f64)> = (0..replicates)
        .into_par_iter()
        .map(|b| {
            let mut rng = rng_for(seed, b as u64, Purpose::Discrepancy);
            let (y, o) = draw_data(data0, specimens, source, data0.reading, &mut rng);
            let data = Data { obs: &o, y: &y, ..data0 };
            let scores: Vec<f64> = (0..o.len()).map(|j| data.score(&lib.baseline, j)).collect();
            let base = per_specimen(&scores, data.obs, specimens);
            let base_he = base.iter().sum::<f64>() / n;
            let ranked = rank(&lib.candidates, data, specimens, &base);
            let best = ranked.first().map_or(base_he, |r| r.heldout_error);
            let misfit = per_specimen(&data.checked_scores(&scores), data.obs, specimens).iter().sum::<f64>() / n;
            (base_he - best, misfit)
        })
        .collect();
    let (baseline, misfit) = joint_margins(&runs);
    // The false-alarm rate of margins set this way, measured on data they were not set
    // on: margins from each half of the null data sets, alarms counted on the other half.
    let half = replicates / 2;
    let (a, b) = runs.split_at(half);
    let alarms_of = |set: &[(f64, f64)], on: &[(f64, f64)]| {
        let (g, m) = joint_margins(set);
        on.iter().filter(|r| r.0 > g || r.1 > m).count()
    };
    let alarms = if a.is_empty() || b.is_empty() { 0 } else { alarms_of(a, b) + alarms_of(b, a) };
    let tested = if a.is_empty() || b.is_empty() { 0 } else { replicates };
    Margins {
        baseline,
        misfit,
        replicates,
        false_alarms: (alarms, tested),
        false_alarm_interval: clopper_pearson(alarms, tested),
    }
}

/// The margin on the best candidate's gain and the threshold of the baseline's misfit,
/// set together so that a new null data set raises either alarm (a cause named, or a
/// significant misfit) with probability at most 5 %: both at the same upper quantile `q`
/// of their null distributions, the smallest `q` from 0.95 up whose `u` alarms (either
/// one) on the `n` runs (gain, baseline score) meet `(u + 2) / (n + 1) ≤ 5 %`.
///
/// A threshold that `u` of `n` exchangeable runs exceed is exceeded by a new one with
/// probability at most `(u + 1) / (n + 1)` (conformal calibration: Vovk, Gammerman &
/// Shafer 2005; Lei et al. 2018, JASA 113:1094); the two thresholds here add one each.
/// Margins from 100 runs then raise alarms on 4.4 % of new null sets, where `u / n ≤ 5 %`
/// gave 6.3 % and `(u + 1)/(n + 1) ≤ 5 %` 5.6 % (the unit test
/// `margins_from_a_hundred_null_sets_keep_new_null_sets_within_five_percent`).
fn joint_margins(runs: &[(f64, f64)]) -> (f64, f64) {
    let sorted = |f: fn(&(f64, f64)) -> f64| {
        let mut v: Vec<f64> = runs.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let (gains, base) = (sorted(|r| r.0), sorted(|r| r.1));
    let at = |q: f64| (crate::stats::quantile(&gains, q), crate::stats::quantile(&base, q));
    let n = runs.len() as f64;
    let mut q = 0.95;
    while q < 1.0 {
        let (g, m) = at(q);
        let union = runs.iter().filter(|r| r.0 > g || r.1 > m).count();
        if (union as f64 + 2.0) / (n + 1.0) <= 0.05 {
            return (g, m);
        }
        q += 0.0025;
    }
    at(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::Observed;

    fn angle_outcome(a: f64) -> Outcome {
        Outcome { observed: Observed { collapse_deg: Some(a), ..Observed::default() }, error: None }
    }

    /// One group, collapse angles only: a pool of 12 independent realizations whose mean is
    /// 5° above the model's, and 12 measured specimens whose spread is `k` times that of
    /// the pool's realizations with the measurement noise. The synthetic data must be
    /// centred on the model (not on the pool), and a data set's mean must scatter about it
    /// by the measured specimens' spread, drawn with its uncertainty (`E[ν/χ²_ν] = ν/(ν −
    /// 2)`), plus the sampling error of a model mean from `R` realizations:
    /// `var(ȳ) = k² v ν/(ν − 2) / n + s²/R`, `v = s² + σ²` (`s²` the pool's variance about
    /// its mean, as the draws resample it).
    #[test]
    fn null_data_are_centred_on_the_model_and_as_dispersed_as_the_data() {
        let pool_values: Vec<f64> = (0..12).map(|i| 25.0 + (i as f64 - 5.5) * 0.4).collect();
        let pool = vec![pool_values.iter().map(|&a| angle_outcome(a)).collect::<Vec<_>>()];
        let keys = vec![(0usize, Observable::CollapseAngle)];
        let pool_sims = vec![Simulated::from_values(&pool_values)];
        let r_model = 4usize;
        let centre = vec![Simulated {
            mean: 20.0,
            sd: pool_sims[0].sd,
            n: r_model,
            err: 0.0,
            heights: crate::discrepancy::predictive::Heights::NONE,
        }];
        let n = 12usize;
        let sigma = 0.3;
        let s2 = pool_values.iter().map(|x| (x - pool_sims[0].mean).powi(2)).sum::<f64>() / 12.0;
        let v = s2 + sigma * sigma;
        let k = 1.5;
        // Measured values with sample variance k² v exactly.
        let pattern: Vec<f64> = (0..n).map(|i| i as f64 - 5.5).collect();
        let ps = crate::stats::sd(&pattern);
        let y0: Vec<f64> = pattern.iter().map(|p| 18.0 + k * v.sqrt() * p / ps).collect();
        let obs: Vec<Observation> = y0
            .iter()
            .enumerate()
            .map(|(i, &value)| Observation {
                specimen: format!("S{i}"),
                group: "G".into(),
                observable: Observable::CollapseAngle,
                value,
                sigma,
            })
            .collect();
        let key = vec![0usize; n];
        let weight = vec![1.0; n];
        let reading = Reading {
            angle_deg: 1e-9,
            displacement_cm: 1e-9,
            misreading: 0.1,
            neighbour_joint: 0.0,
            ..Reading::default()
        };
        let data = Data { obs: &obs, y: &y0, key: &key, weight: &weight, reading, bracket_deg: 0.0 };
        let stated = vec![sigma; n];
        // A model spread larger than any data spread: the σ estimate never exceeds the
        // stated σ, so every data set keeps σ = 0.3.
        let model_sd = vec![10.0];
        let rule = SigmaRule { stated: &stated, model_sd: &model_sd, reading };
        let source = NullSource { pool: &pool, keys: &keys, sims: &pool_sims, centre: &centre, sigma: rule };
        let specimens: Vec<String> = obs.iter().map(|o| o.specimen.clone()).collect();
        let reps = 40_000u64;
        let means: Vec<f64> = (0..reps)
            .map(|b| {
                let mut rng = rng_for(11, b, Purpose::Discrepancy);
                let (y, o) = draw_data(data, &specimens, source, reading, &mut rng);
                assert!(o.iter().all(|o| o.sigma == sigma));
                y.iter().sum::<f64>() / n as f64
            })
            .collect();
        let m = crate::stats::mean(&means);
        let var = crate::stats::sd(&means).powi(2);
        let nu = (n - 1) as f64;
        let want = k * k * v * nu / (nu - 2.0) / n as f64 + s2 / r_model as f64;
        let se_mean = (want / reps as f64).sqrt();
        assert!((m - 20.0).abs() < 4.0 * se_mean, "mean {m}, want 20 ± {se_mean}");
        assert!((var / want - 1.0).abs() < 0.05, "var {var}, want {want}");
    }

    /// The absolute check of fit does not read the mechanism's kind (a reader's
    /// convention; it reads angles, displacements and failure heights): twelve
    /// specimens whose collapse angles are drawn like the model's realizations pass the
    /// posterior predictive check; the same specimens each read as having slid, where every
    /// realization toppled (a reader whose rule is not the model's), give the same score
    /// (bit for bit) and still pass, while the readings cost that model in a comparison
    /// (their score is large).
    #[test]
    fn mechanism_readings_the_model_never_shows_do_not_fail_the_predictive_check() {
        use crate::discrepancy::analysis::predictive_check;
        use crate::loading::mechanism::FailureKind;
        let values: Vec<f64> = (0..12).map(|i| 20.0 + (i as f64 - 5.5) * 0.3).collect();
        let pool = vec![values.iter().map(|&a| angle_outcome(a)).collect::<Vec<_>>()];
        let sliding = Observable::MechanismKind { kind: FailureKind::Sliding };
        let keys = vec![(0usize, Observable::CollapseAngle), (0usize, sliding)];
        // Every realization toppled: none shows sliding (indicator 0 in all 12).
        let sims = vec![Simulated::from_values(&values), Simulated::from_values(&[0.0; 12])];
        let angles: Vec<Observation> = (0..12)
            .map(|i| Observation {
                specimen: format!("S{i}"),
                group: "G".into(),
                observable: Observable::CollapseAngle,
                value: 20.0 + ((i * 7) % 12) as f64 * 0.25 - 1.4,
                sigma: 0.3,
            })
            .collect();
        let mut both = angles.clone();
        both.extend(angles.iter().map(|o| Observation { observable: sliding, value: 1.0, sigma: 1.0, ..o.clone() }));
        let reading = Reading {
            angle_deg: 0.25,
            displacement_cm: 0.1,
            misreading: 0.1,
            neighbour_joint: 0.25,
            ..Reading::default()
        };
        let check = |obs: &[Observation]| {
            let key: Vec<usize> = obs.iter().map(|o| usize::from(o.observable != Observable::CollapseAngle)).collect();
            let y: Vec<f64> = obs.iter().map(|o| o.value).collect();
            let weight = crate::discrepancy::compare::specimen_weights(obs);
            let data = Data { obs, y: &y, key: &key, weight: &weight, reading, bracket_deg: 0.25 };
            let stated: Vec<f64> = obs.iter().map(|o| o.sigma).collect();
            let model_sd = vec![10.0, 10.0];
            let rule = SigmaRule { stated: &stated, model_sd: &model_sd, reading };
            let source = NullSource { pool: &pool, keys: &keys, sims: &sims, centre: &sims, sigma: rule };
            let specimens: Vec<String> = (0..12).map(|i| format!("S{i}")).collect();
            let labels = vec!["G alpha_max".to_string(), "G kind=sliding".to_string()];
            let readings: f64 = (12..obs.len()).map(|j| data.score(&sims, j)).sum();
            (predictive_check(data, &sims, &specimens, source, 400, 7, &labels), readings)
        };
        let (alone, _) = check(&angles);
        let (with, cost) = check(&both);
        assert!(alone.passes() && with.passes(), "{alone:?} {with:?}");
        assert_eq!(alone.score.to_bits(), with.score.to_bits());
        assert!(cost > 12.0 * 2.0, "the readings cost {cost}");
        assert!(with.missed.iter().any(|(k, _)| k == "G kind=sliding"), "{:?}", with.missed);
    }

    /// The two alarms set together: on independent gains and misfit scores the union of
    /// alarms is within the bound, `(u + 2)/(n + 1) ≤ 5 %`, and each margin sits at or
    /// above its own 95th percentile.
    #[test]
    fn the_two_alarms_together_stay_within_five_percent() {
        let mut rng = rng_for(3, 0, Purpose::Discrepancy);
        let runs: Vec<(f64, f64)> = (0..2000)
            .map(|_| {
                let g: f64 = StandardNormal.sample(&mut rng);
                let m: f64 = StandardNormal.sample(&mut rng);
                (g, m)
            })
            .collect();
        let (g, m) = joint_margins(&runs);
        let union = runs.iter().filter(|r| r.0 > g || r.1 > m).count() as f64;
        assert!((union + 2.0) / 2001.0 <= 0.05, "{union}");
        let q = |v: Vec<f64>, p: f64| quantile(v, p);
        let gains: Vec<f64> = runs.iter().map(|r| r.0).collect();
        assert!(g >= q(gains.clone(), 0.95) && g <= q(gains, 0.98), "{g}");
        // Perfectly dependent alarms: one test's percentile is enough, at the level
        // (u + 2)/(n + 1) ≤ 5 %: 98 of 2000 above.
        let same: Vec<(f64, f64)> = runs.iter().map(|r| (r.0, r.0)).collect();
        let (g2, _) = joint_margins(&same);
        let above = same.iter().filter(|r| r.0 > g2).count();
        assert!((95..=98).contains(&above), "{above}");
    }

    /// The false-alarm rate of margins set on few null data sets, on data sets they were
    /// not set on: at most 5 % on average over calibrations, where margins at 5 % of their
    /// own runs give 6.3 % and `(u + 1)/(n + 1) ≤ 5 %` gives 5.6 % (measured with this
    /// test's draws). 400 calibrations of 100 runs, each checked on 1000 fresh runs.
    #[test]
    fn margins_from_a_hundred_null_sets_keep_new_null_sets_within_five_percent() {
        let mut rng = rng_for(11, 0, Purpose::Discrepancy);
        let mut draw = |k: usize| -> Vec<(f64, f64)> {
            (0..k)
                .map(|_| {
                    let g: f64 = StandardNormal.sample(&mut rng);
                    let e: f64 = StandardNormal.sample(&mut rng);
                    (g, 0.6 * g + 0.8 * e) // correlated alarms, as gains and misfits are
                })
                .collect()
        };
        let (mut alarms, mut tried) = (0usize, 0usize);
        for _ in 0..400 {
            let (g, m) = joint_margins(&draw(100));
            let fresh = draw(1000);
            alarms += fresh.iter().filter(|r| r.0 > g || r.1 > m).count();
            tried += fresh.len();
        }
        let rate = alarms as f64 / tried as f64;
        // The Monte Carlo error of the mean over 400 calibrations is about 0.1 %.
        assert!((0.035..=0.0505).contains(&rate), "{rate}");
    }
}
