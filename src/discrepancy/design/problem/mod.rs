//! The preposterior problem of one follow-up: simulated follow-ups drawn from each
//! contender taken as the truth, every contender refit on both campaigns
//! ([`super::refit`]), and the answer the analysis would give.

mod bias;
mod space;
mod weights;

use super::plan::{Chance, Contender};
use super::refit::Refit;
use crate::discrepancy::compare::difference_se;
use crate::discrepancy::observations::Observable;
use crate::discrepancy::predictive::{Reading, Simulated};
use crate::discrepancy::TieCheck;
use crate::rng::{rng_for, Purpose};
use rand::RngExt;
use rayon::prelude::*;
use space::{NewScores, ScoreCache, Space};
use weights::{named, pseudo_bma_of};

/// The preposterior problem of one follow-up: the contenders, their predictions of each
/// key at their first-campaign fits (`sims[contender][key]`, what the simulated follow-ups
/// are drawn from), their refits (`refits[contender]`, `None` or an empty slice: scored at
/// `sims` with the first campaign's own held-out scores), the keys, each key's reading σ,
/// the readings' resolutions and the simulated angle's bracket (degrees).
#[derive(Debug, Clone, Copy)]
pub struct Problem<'a> {
    /// The contenders.
    pub contenders: &'a [Contender],
    /// `[contender][key]` at the first campaign's fit.
    pub sims: &'a [Vec<Simulated>],
    /// `[contender]`: the refit on both campaigns, or `None` (no parameters). Empty: no
    /// contender is refit.
    pub refits: &'a [Option<Refit<'a>>],
    /// How many contenders, the first ones, are taken as the truth (the others are
    /// challengers only; at most `contenders.len()`).
    pub truths: usize,
    /// `[contender]`: the model discrepancy the follow-up carries when drawn from it taken
    /// as the truth ([`super::Inadequacy`]: its own walls', plus what it carries to walls of
    /// a new kind on a follow-up of such walls), the variance of the bias per key in units
    /// of the key's predictive variance (0: none, the follow-up drawn from the model alone).
    /// Empty: none for every contender.
    pub inadequacy: &'a [f64],
    /// The follow-up builds walls of a kind the first campaign did not test: every key is
    /// unseen ([`Problem::unseen`]).
    pub unseen_walls: bool,
    /// `[key]`: a key the first campaign did not read on the follow-up's walls (the
    /// mechanism, the other top measure, a tilt not read). Empty: none beyond
    /// `unseen_walls`. Each truth's follow-ups carry, on an unseen measure, `transfer` and
    /// the contenders' disagreement there beside `inadequacy`
    /// ([`Problem::bias_variances`]); on an unseen mechanism reading, the mechanism of a
    /// model drawn from the truths by their priors ([`Problem::mechanism_source`]).
    pub unseen_keys: &'a [bool],
    /// `[contender]`: the discrepancy it carries to a key the first campaign did not read
    /// ([`super::Inadequacy::transfer`], same units as `inadequacy`). Empty: none.
    pub transfer: &'a [f64],
    /// The gain margin a pair contender ([`Contender::pair`]) must clear over the best
    /// single contender, in held-out error per specimen (nats), to be in the ranking of a
    /// simulated analysis of both campaigns ([`Problem::present`]; the analysis's
    /// `margins.baseline`). `None`: every contender is in every ranking.
    pub pair_margin: Option<f64>,
    /// The data sets the analysis's own reversal test draws (its `check_replicates`): the
    /// test is a Monte Carlo estimate, so whether it clears a challenger is itself random
    /// ([`clears`]).
    pub check_replicates: usize,
    /// The first campaign's design, to draw it anew from each truth for the reversal
    /// rates as the analysis's tie check draws them (both campaigns simulated). `None`:
    /// the reversal rates are read on the simulated follow-ups beside the first
    /// campaign's data.
    pub first: Option<FirstCampaign<'a>>,
    /// The keys read on each specimen (mechanism categories: one of them is seen).
    pub keys: &'a [Observable],
    /// The σ of each key's reading.
    pub sigma: &'a [f64],
    /// The readings' resolutions and misreading probability.
    pub reading: Reading,
    /// Width of a simulated collapse angle's bracket, degrees.
    pub bracket_deg: f64,
}

/// The first campaign as a design: its keys, each key's σ, the keys each specimen reads
/// (a mechanism's kind and start: every category of its group, one of them seen), and
/// every contender's predictions of them at its fit (`[contender][key]`, what a truth's
/// first campaign is drawn from) and, refit, at every scan point ([`Refit::first`]).
#[derive(Debug, Clone, Copy)]
pub struct FirstCampaign<'a> {
    /// The first campaign's keys.
    pub keys: &'a [Observable],
    /// The σ of each key's reading.
    pub sigma: &'a [f64],
    /// The keys each specimen reads.
    pub specimens: &'a [Vec<usize>],
    /// `[contender][key]` at the first campaign's fit.
    pub at_fit: &'a [Vec<Simulated>],
}

/// The random streams of one follow-up's simulated data: truth `t` draws from
/// `rng_for(seed, t, purpose)` ([`crate::rng::rng_for`]). The ranking draws on
/// [`Stream::select`] ([`Purpose::Discrepancy`]), the re-estimate of the chosen follow-up
/// on [`Stream::report`] ([`Purpose::DesignReport`]): same seed, disjoint ChaCha streams
/// (`t × 16 + 4` against `t × 16 + 8`), so no replicate that chose a follow-up scores it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stream {
    /// The master seed (the follow-up's, derived from the analysis's).
    pub seed: u64,
    /// The purpose that names the stream.
    pub purpose: Purpose,
}

impl Stream {
    /// The streams that rank the menu.
    pub fn select(seed: u64) -> Stream {
        Stream { seed, purpose: Purpose::Discrepancy }
    }

    /// The streams that re-estimate the chosen follow-up.
    pub fn report(seed: u64) -> Stream {
        Stream { seed, purpose: Purpose::DesignReport }
    }

    /// Truth `t`'s generator.
    pub fn rng(&self, t: usize) -> rand_chacha::ChaCha8Rng {
        rng_for(self.seed, t as u64, self.purpose)
    }

    /// Truth `t`'s generator of the reversal test's follow-up specimens (drawn from the
    /// truth without bias, as the analysis's reversal test draws them): a seed of its own,
    /// so the follow-up's own draws, the first campaign's and the weights' stay as
    /// [`Stream::rng`] gives them.
    pub fn reversal_rng(&self, t: usize) -> rand_chacha::ChaCha8Rng {
        rng_for(self.seed ^ Self::REVERSAL, t as u64, self.purpose)
    }

    /// Mixed into the seed of [`Stream::reversal_rng`].
    const REVERSAL: u64 = 0x7265_7665_7273_616c;
}

/// What one truth's replicates give, per ladder count.
struct Tally {
    /// `[ladder]`: replicates named alone by the weights.
    by_weights: Vec<usize>,
    /// `[ladder]`: replicates with the truth among the models that share the weight.
    right: Vec<usize>,
    /// `[ladder][replicate][other]`: whether `other` scores at least the truth in that
    /// replicate, on every observation and on the measures.
    reversed: Vec<Vec<Vec<(bool, bool)>>>,
    /// `[ladder][replicate][other]`: whether the data test separates `other` from the
    /// truth on every observation and on the measures, and whether `other` is absent from
    /// that replicate's ranking ([`Problem::present`]).
    seps: Vec<Vec<Vec<(bool, bool, bool)>>>,
}

impl Problem<'_> {
    fn space(&self) -> Space<'_> {
        Space { keys: self.keys, sigma: self.sigma, reading: self.reading, bracket_deg: self.bracket_deg }
    }

    /// One simulated specimen of the follow-up from contender `t` with the follow-up's
    /// biases `bias` (`[key]`, in units of each key's predictive standard deviation; empty:
    /// none): its observations (key index, value).
    #[cfg(test)]
    pub(super) fn draw_specimen(&self, t: usize, bias: &[f64], rng: &mut rand_chacha::ChaCha8Rng) -> Vec<(usize, f64)> {
        let all: Vec<usize> = (0..self.keys.len()).collect();
        self.space().draw(&self.sims[t], &all, bias, rng)
    }

    /// The rate at which contender `c` beats truth `t` in the reversal test of the tally
    /// (`(every observation, measures)`), at `n` follow-up specimens over `replicates`.
    #[cfg(test)]
    pub(super) fn reversal_rate(&self, t: usize, c: usize, n: usize, replicates: usize, seed: u64) -> (f64, f64) {
        let tally = self.tally(t, &[n], replicates, 10, Stream::select(seed));
        let count = |pick: fn(&(bool, bool)) -> bool| {
            tally.reversed[0].iter().filter(|r| pick(&r[c])).count() as f64 / replicates as f64
        };
        (count(|r| r.0), count(|r| r.1))
    }

    /// Whether key `k` is one the first campaign did not read on the follow-up's walls.
    pub fn unseen(&self, k: usize) -> bool {
        self.unseen_walls || self.unseen_keys.get(k).copied().unwrap_or(false)
    }

    fn refit(&self, c: usize) -> Option<&Refit<'_>> {
        self.refits.get(c).and_then(Option::as_ref)
    }

    /// Every contender's scores of the simulated follow-up `specimens`: at its
    /// first-campaign fit, or at every scan point when it is refit (`caches`, one per
    /// contender).
    fn new_scores(&self, specimens: &[Vec<(usize, f64)>], caches: &mut [ScoreCache]) -> Vec<NewScores> {
        let space = self.space();
        (0..self.contenders.len())
            .map(|c| space.scores(specimens, &self.sims[c], self.refit(c).map(|r| r.scan), &mut caches[c]))
            .collect()
    }

    /// Every contender's scores of a first campaign drawn anew from truth `t`.
    fn first_scores_drawn(
        &self,
        first: &FirstCampaign<'_>,
        t: usize,
        caches: &mut [ScoreCache],
        rng: &mut rand_chacha::ChaCha8Rng,
    ) -> Vec<NewScores> {
        let space =
            Space { keys: first.keys, sigma: first.sigma, reading: self.reading, bracket_deg: self.bracket_deg };
        let specimens: Vec<Vec<(usize, f64)>> =
            first.specimens.iter().map(|which| space.draw(&first.at_fit[t], which, &[], rng)).collect();
        (0..self.contenders.len())
            .map(|c| {
                let scan = self.refit(c).map(|r| r.first.scan.as_slice());
                space.scores(&specimens, &first.at_fit[c], scan, &mut caches[c])
            })
            .collect()
    }

    /// Every contender's scores of the first campaign's data, as [`NewScores`]: its
    /// held-out scores per specimen, or, refit, its tables at the scan points.
    fn first_campaign_scores(&self) -> Vec<NewScores> {
        let neg = |v: &[f64]| v.iter().map(|x| -x).collect();
        (0..self.contenders.len())
            .map(|c| match self.refit(c) {
                Some(r) => NewScores::Scan { pins: r.first.pins.clone(), all: r.first.all.clone() },
                None => {
                    let con = &self.contenders[c];
                    NewScores::Fixed { pins: neg(&con.elpd_measures), all: neg(&con.elpd) }
                }
            })
            .collect()
    }

    /// `[contender]`: whether contender `c` is in the ranking of a simulated analysis of
    /// both campaigns whose held-out log scores per specimen are `elpd[c]` (nats): every
    /// contender but a pair ([`Contender::pair`]), and a pair when its mean held-out score
    /// beats the best single contender's by more than [`Problem::pair_margin`], as the
    /// analysis admits the pairs it adds (`stages::admit_pairs`, held-out error below the
    /// best single's less the gain margin). The analysis's further conditions (the best
    /// single's misfit, the pair's AICc below the single's) only admit fewer pairs; the
    /// best single is taken among the contenders, not the whole library.
    fn present(&self, elpd: &[Vec<f64>]) -> Vec<bool> {
        let pair = |c: usize| self.contenders.get(c).is_some_and(|x| x.pair);
        let Some(margin) = self.pair_margin else { return vec![true; elpd.len()] };
        let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len().max(1) as f64;
        let best = (0..elpd.len()).filter(|&c| !pair(c)).map(|c| mean(&elpd[c])).fold(f64::NEG_INFINITY, f64::max);
        (0..elpd.len()).map(|c| !pair(c) || mean(&elpd[c]) - best > margin).collect()
    }

    /// One truth's replicates: for every ladder count, the weights' answer and the tie
    /// check's two tests against every other contender.
    fn tally(&self, t: usize, ladder: &[usize], replicates: usize, draws: usize, stream: Stream) -> Tally {
        let bound = TieCheck::STANDARD_ERRORS;
        let k = self.contenders.len();
        let nmax = ladder.iter().copied().max().unwrap_or(0);
        let mut tally = Tally {
            by_weights: vec![0; ladder.len()],
            right: vec![0; ladder.len()],
            reversed: vec![Vec::with_capacity(replicates); ladder.len()],
            seps: vec![Vec::with_capacity(replicates); ladder.len()],
        };
        let mut caches: Vec<ScoreCache> = (0..k).map(|_| ScoreCache::new()).collect();
        let mut first_caches: Vec<ScoreCache> = (0..k).map(|_| ScoreCache::new()).collect();
        let real = self.first_campaign_scores();
        let mut rng = stream.rng(t);
        let mut reversal_rng = stream.reversal_rng(t);
        let variances = self.bias_variances(t);
        for _ in 0..replicates {
            let bias = Self::draw_bias(&variances, &mut rng);
            let source = self.mechanism_source(&mut rng);
            let row = self.drawn_from(t, source);
            let all: Vec<usize> = (0..self.keys.len()).collect();
            let specimens: Vec<Vec<(usize, f64)>> =
                (0..nmax).map(|_| self.space().draw(&row, &all, &bias, &mut rng)).collect();
            let new = self.new_scores(&specimens, &mut caches);
            // Both campaigns drawn from the truth, for the reversal rates: as the
            // analysis's reversal test (`analysis::reversal_rates`) draws them, from the
            // cause's own predictions, without the follow-up's bias or another model's
            // mechanism.
            let drawn = self.first.as_ref().map(|f| {
                let first = self.first_scores_drawn(f, t, &mut first_caches, &mut rng);
                let own: Vec<Vec<(usize, f64)>> =
                    (0..nmax).map(|_| self.space().draw(&self.sims[t], &all, &[], &mut reversal_rng)).collect();
                (first, self.new_scores(&own, &mut caches))
            });
            for (li, &n) in ladder.iter().enumerate() {
                let mut reversed = vec![(false, false); k];
                if let Some((drawn, own)) = &drawn {
                    // The analysis's reversal: a challenger whose held-out score on data
                    // drawn from the cause beats the cause's (its held-out error lower).
                    let totals: Vec<(f64, f64)> = (0..k)
                        .map(|c| {
                            let (e, m) = heldout_both(&drawn[c], &own[c], n);
                            (e.iter().sum(), m.iter().sum())
                        })
                        .collect();
                    for c in 0..k {
                        reversed[c] = (c != t && totals[c].0 > totals[t].0, c != t && totals[c].1 > totals[t].1);
                    }
                }
                let (elpd, measures): (Vec<Vec<f64>>, Vec<Vec<f64>>) =
                    (0..k).map(|c| heldout_both(&real[c], &new[c], n)).unzip();
                let present = self.present(&elpd);
                let w = pseudo_bma_of(&elpd, &present, draws, &mut rng);
                let (a, r) = named(&w, t);
                let mut sep = Vec::with_capacity(k);
                for c in 0..k {
                    if c == t || !present[c] {
                        sep.push((true, true, !present[c]));
                        continue;
                    }
                    let diff = |e: &[Vec<f64>]| -> Vec<f64> { e[t].iter().zip(&e[c]).map(|(x, y)| x - y).collect() };
                    let (d, dm) = (diff(&elpd), diff(&measures));
                    let dr: Vec<f64> = d.iter().zip(&dm).map(|(x, y)| x - y).collect();
                    let (sum, sum_m, sum_r) = (d.iter().sum::<f64>(), dm.iter().sum::<f64>(), dr.iter().sum::<f64>());
                    if drawn.is_none() {
                        reversed[c] = (sum <= 0.0, sum_m <= 0.0);
                    }
                    let readings = dr.iter().any(|&x| x != 0.0);
                    // A difference of exactly zero (both models score every specimen alike,
                    // as two models at a common floor can on a simulated specimen) separates
                    // nothing, whatever its standard error.
                    sep.push((
                        sum > 0.0 && sum >= bound * difference_se(&d),
                        readings
                            && sum_m > 0.0
                            && sum_m >= bound * difference_se(&dm)
                            && sum_r >= -bound * difference_se(&dr),
                        false,
                    ));
                }
                tally.by_weights[li] += usize::from(a);
                tally.right[li] += usize::from(r);
                tally.seps[li].push(sep);
                tally.reversed[li].push(reversed);
            }
        }
        tally
    }

    /// Truth `t`'s probability of being named alone at ladder count `li` from its
    /// replicates `which` (indices into its tally, repeats allowed): the data test of each
    /// replicate against every other contender ranked there, times the probability that
    /// the analysis's reversal test clears it ([`clears`], from the reversals among
    /// `which`).
    fn alone_of(&self, tally: &Tally, t: usize, li: usize, which: &[usize]) -> f64 {
        let clear = self.clear_rates(tally, li, which);
        let n = which.len().max(1);
        let alone: f64 = which
            .iter()
            .map(|&r| &tally.seps[li][r])
            .filter(|sep| !sep[t].2)
            .map(|sep| (0..sep.len()).filter(|&c| c != t).map(|c| cleared(sep[c], clear[c])).product::<f64>())
            .sum();
        // `+ 0.0`: a sum of no replicate (a pair truth never ranked) is −0.0 in Rust's float
        // sum; a probability reads 0.
        alone / n as f64 + 0.0
    }

    /// What stops truth `t` being named alone at ladder count `li`, per contender, over all
    /// its replicates: `(blocked, by the data test)` ([`Chance::blocked_by`],
    /// [`Chance::data_blocked_by`]).
    fn blocked_of(&self, tally: &Tally, t: usize, li: usize) -> (Vec<f64>, Vec<f64>) {
        let which: Vec<usize> = (0..tally.seps[li].len()).collect();
        let clear = self.clear_rates(tally, li, &which);
        let n = which.len().max(1) as f64;
        let k = self.contenders.len();
        let (mut blocked, mut data) = (vec![0.0; k], vec![0.0; k]);
        for sep in tally.seps[li].iter().filter(|sep| !sep[t].2) {
            for c in (0..k).filter(|&c| c != t) {
                blocked[c] += 1.0 - cleared(sep[c], clear[c]);
                data[c] += f64::from(u8::from(!sep[c].2 && !sep[c].0 && !sep[c].1));
            }
        }
        (blocked.iter().map(|b| b / n).collect(), data.iter().map(|d| d / n).collect())
    }

    /// The probability that the analysis's reversal test clears each contender, on every
    /// observation and on the measures ([`clears`]), from the reversals among replicates
    /// `which` of a truth's tally at ladder count `li`.
    fn clear_rates(&self, tally: &Tally, li: usize, which: &[usize]) -> Vec<(f64, f64)> {
        let k = self.contenders.len();
        let n = which.len().max(1);
        let counts: Vec<(usize, usize)> = (0..k)
            .map(|c| {
                which.iter().fold((0, 0), |(a, m), &r| {
                    let f = tally.reversed[li][r][c];
                    (a + usize::from(f.0), m + usize::from(f.1))
                })
            })
            .collect();
        counts
            .iter()
            .map(|&(all, measures)| (clears(all, n, self.check_replicates), clears(measures, n, self.check_replicates)))
            .collect()
    }

    /// The probabilities at every specimen count of `ladder`, from `replicates` simulated
    /// follow-ups per contender taken as the truth (the first [`Problem::truths`]; the
    /// largest count drawn, the smaller counts its first specimens), weights from `draws`
    /// Bayesian-bootstrap draws. The truths run in parallel, each on its own random stream:
    /// the result does not depend on the number of threads.
    ///
    /// **Named alone** is the verdict's criterion, the analysis's tie check
    /// ([`TieCheck`]): the truth is named alone when both tests clear every other
    /// contender on both campaigns, the held-out difference per specimen at least
    /// [`TieCheck::STANDARD_ERRORS`] standard errors, and the reversal rate (the share of
    /// data sets drawn from the truth on both campaigns, [`Problem::first`] drawn anew
    /// beside each simulated follow-up, in which the other contender's held-out score
    /// beats the truth's; without [`Problem::first`], the share of the simulated
    /// follow-ups beside the first campaign's data in which it scores at least as well)
    /// under [`TieCheck::REVERSAL_RATE`] (a probability, [`clears`]: the analysis's test
    /// draws [`Problem::check_replicates`] data sets of its own); with readings of the
    /// mechanism, either on every observation or on the measures alone with the readings
    /// not favouring the other beyond the data bound, as the analysis clears a challenger.
    /// The weights' concentration (the truth alone holding [`crate::discrepancy::SHARED`]
    /// of the pseudo-BMA+ weight) is kept beside it ([`Chance::weights_alone`]).
    pub fn chances(&self, ladder: &[usize], replicates: usize, draws: usize, seed: u64) -> Vec<Chance> {
        self.chances_on(ladder, replicates, draws, Stream::select(seed))
    }

    /// [`Problem::chances`] on the random streams `stream`: truth `t`'s simulated
    /// follow-ups are drawn from `stream.rng(t)` alone, whatever the thread that runs it.
    pub fn chances_on(&self, ladder: &[usize], replicates: usize, draws: usize, stream: Stream) -> Vec<Chance> {
        let k = self.contenders.len();
        let truths = self.truths.clamp(1, k.max(1)).min(k);
        let tallies: Vec<Tally> =
            (0..truths).into_par_iter().map(|t| self.tally(t, ladder, replicates, draws, stream)).collect();
        let reps = replicates.max(1) as f64;
        let total: f64 = self.contenders[..truths].iter().map(|c| c.prior).sum();
        let prior = |t: usize| if total > 0.0 { self.contenders[t].prior / total } else { 1.0 / truths as f64 };
        ladder
            .iter()
            .enumerate()
            .map(|(li, &n)| {
                let all: Vec<usize> = (0..replicates).collect();
                let by: Vec<f64> =
                    tallies.iter().enumerate().map(|(t, tally)| self.alone_of(tally, t, li, &all)).collect();
                let (blocked_by, data_blocked_by): (Vec<Vec<f64>>, Vec<Vec<f64>>) =
                    tallies.iter().enumerate().map(|(t, tally)| self.blocked_of(tally, t, li)).unzip();
                // The Monte Carlo standard error of `alone`: the replicates of every truth
                // resampled (a bootstrap; the reversal counts, which every replicate of a
                // truth shares, resampled with them), on a generator of its own.
                let mut rng = rng_for(stream.seed ^ BOOTSTRAP_SEED, li as u64, stream.purpose);
                let boot: Vec<f64> = (0..BOOTSTRAP)
                    .map(|_| {
                        (0..truths)
                            .map(|t| {
                                let which: Vec<usize> =
                                    (0..replicates).map(|_| rng.random_range(0..replicates.max(1))).collect();
                                prior(t) * self.alone_of(&tallies[t], t, li, &which)
                            })
                            .sum()
                    })
                    .collect();
                let mean = |f: &dyn Fn(&Tally) -> f64| -> f64 {
                    tallies.iter().enumerate().map(|(t, tally)| prior(t) * f(tally)).sum()
                };
                Chance {
                    specimens: n,
                    alone: (0..truths).map(|t| prior(t) * by[t]).sum(),
                    alone_se: crate::stats::sd(&boot),
                    weights_alone: mean(&|tally| tally.by_weights[li] as f64 / reps),
                    right: mean(&|tally| tally.right[li] as f64 / reps),
                    alone_by_truth: by,
                    blocked_by,
                    data_blocked_by,
                }
            })
            .collect()
    }
}

/// The probability that the tie check clears one contender in one replicate: `sep` its
/// data tests and absence there (a [`Tally::seps`] entry), `clear` the probabilities that
/// the reversal test clears it (every observation, the measures). An absent contender is
/// cleared.
fn cleared(sep: (bool, bool, bool), clear: (f64, f64)) -> f64 {
    match (sep.2, sep.0, sep.1) {
        (true, _, _) => 1.0,
        // The two clears are of one model pair on the same data sets: taken as moving
        // together.
        (false, true, true) => clear.0.max(clear.1),
        (false, true, false) => clear.0,
        (false, false, true) => clear.1,
        (false, false, false) => 0.0,
    }
}

/// A contender's held-out log scores per specimen of both campaigns: the first campaign's
/// scores `first` (its data's or data drawn anew) and the first `n` specimens of a
/// simulated follow-up, `new`. Refit, each specimen is scored at the fit on the others'
/// measures ([`super::refit::heldout`]). Returns `(elpd, elpd_measures)`, nats.
fn heldout_both(first: &NewScores, new: &NewScores, n: usize) -> (Vec<f64>, Vec<f64>) {
    match (first, new) {
        (NewScores::Scan { pins: fp, all: fa }, NewScores::Scan { pins, all }) => {
            super::refit::heldout(fp, fa, pins, all, n)
        }
        (NewScores::Fixed { pins: fp, all: fa }, NewScores::Fixed { pins, all }) => {
            (fa.iter().chain(&all[..n]).map(|s| -s).collect(), fp.iter().chain(&pins[..n]).map(|s| -s).collect())
        }
        _ => unreachable!("a contender is refit on both campaigns or on neither"),
    }
}

/// Bootstrap resamples of the replicates behind [`Chance::alone_se`].
const BOOTSTRAP: usize = 200;

/// Mixed into the stream's seed for the bootstrap's generator (no simulated data set draws
/// from it).
const BOOTSTRAP_SEED: u64 = 0xb007_5a3d_0000_0001;

/// The probability that the analysis's reversal test clears a challenger
/// ([`TieCheck::REVERSAL_RATE`]: fewer than 5 % of its `check` data sets drawn from the
/// truth reversed) when `k` of the design's `n` simulated data sets reversed: the test's
/// count is binomial, `K ~ Bin(check, p)`, with the reversal probability `p` uncertain
/// after the design's own draws, `p ~ Beta(k + ½, n − k + ½)` (Jeffreys), so `K` is
/// beta-binomial and the probability is its distribution function at the last count that
/// clears. A rate the design estimates near 5 % clears about half the time, as the
/// analysis's estimate falls on either side of it; the design's own count thresholded at
/// 5 % would make the promise jump between 0 and 1 on one replicate.
pub fn clears(k: usize, n: usize, check: usize) -> f64 {
    use statrs::function::{beta::ln_beta, factorial::ln_binomial};
    let (a, b) = (k as f64 + 0.5, (n.max(k) - k) as f64 + 0.5);
    let r = check.max(1);
    let base = ln_beta(a, b);
    (0..=r)
        .take_while(|&j| (j as f64) / (r as f64) < TieCheck::REVERSAL_RATE)
        .map(|j| (ln_binomial(r as u64, j as u64) + ln_beta(j as f64 + a, (r - j) as f64 + b) - base).exp())
        .sum::<f64>()
        .min(1.0)
}
