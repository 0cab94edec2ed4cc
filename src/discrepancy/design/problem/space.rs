//! A space of keys: drawing a simulated specimen of the follow-up (or of a first campaign
//! drawn anew) from a contender's predictions, and scoring simulated specimens under a
//! contender at its fit or at every scan point of its refit.

use crate::discrepancy::compare::{per_specimen, specimen_weights};
use crate::discrepancy::fit::Data;
use crate::discrepancy::observations::{CategorySet, Observable, Observation, Scale};
use crate::discrepancy::predictive::{Predictive, Reading, Simulated};
use rand::RngExt;
use rand_distr::{Distribution, StandardNormal, StudentT};
use std::collections::HashMap;

/// A space of keys: what a simulated specimen is drawn on and scored on.
#[derive(Debug, Clone, Copy)]
pub(super) struct Space<'a> {
    pub(super) keys: &'a [Observable],
    pub(super) sigma: &'a [f64],
    pub(super) reading: Reading,
    pub(super) bracket_deg: f64,
}

/// One contender's scores of a simulated follow-up's specimens: per specimen, the measures'
/// and every observation's summed score (nats, lower is better); refit, one row per scan
/// point.
pub(super) enum NewScores {
    Fixed { pins: Vec<f64>, all: Vec<f64> },
    Scan { pins: Vec<Vec<f64>>, all: Vec<Vec<f64>> },
}

/// The score of one reading (key, value bits) at every scan point of one contender,
/// computed once (the readings are rounded, so values repeat across replicates).
pub(super) type ScoreCache = HashMap<(usize, u64), Vec<f64>>;

impl Space<'_> {
    /// One simulated specimen from the predictions `sims` (`[key]`) reading the keys
    /// `which`, each measure shifted by its bias `bias[key]` predictive standard deviations
    /// (empty: none; the mechanism's readings are not biased): its observations (key index,
    /// value).
    pub(super) fn draw(
        &self,
        sims: &[Simulated],
        which: &[usize],
        bias: &[f64],
        rng: &mut rand_chacha::ChaCha8Rng,
    ) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        // The keys of each set of categories ([`CategorySet::ALL`]'s order), drawn as one.
        let mut sets: [Vec<usize>; CategorySet::ALL.len()] = Default::default();
        for &k in which {
            let (o, sim) = (&self.keys[k], &sims[k]);
            match o.scale() {
                Scale::Category { set, .. } => sets[set.index()].push(k),
                Scale::Place { width } => {
                    if sim.heights.is_empty() {
                        continue;
                    }
                    let v = if rng.random::<f64>() < self.reading.misreading {
                        rng.random::<f64>()
                    } else {
                        let u: f64 = rng.random();
                        let mut acc = 0.0;
                        let last = (sim.heights.0.len() - 1) as f64;
                        let mut c = 1.0;
                        for (i, m) in sim.heights.0.iter().enumerate() {
                            acc += m;
                            if u <= acc {
                                c = i as f64 / last;
                                break;
                            }
                        }
                        let z: f64 = StandardNormal.sample(rng);
                        (c + z * (self.sigma[k].powi(2) + sim.err.powi(2)).sqrt()).clamp(0.0, 1.0)
                    };
                    let v = self.reading.neighbour_read(v, width, rng.random());
                    out.push((k, self.reading.round(o, v)));
                }
                Scale::Measure(_) => {
                    if !sim.mean.is_finite() {
                        continue;
                    }
                    let p = Predictive::new(sim, &self.template(k), self.bracket_deg);
                    let z: f64 = if p.dof < 1e4 {
                        StudentT::new(p.dof.max(1.0)).map_or(0.0, |d| d.sample(rng))
                    } else {
                        StandardNormal.sample(rng)
                    };
                    let b = bias.get(k).copied().unwrap_or(0.0);
                    out.push((k, self.reading.round(o, p.mean + p.sd * (z + b))));
                }
            }
        }
        for group in sets {
            if group.is_empty() {
                continue;
            }
            // The seen category, by the smoothed and misread probabilities.
            let q: Vec<f64> = group
                .iter()
                .map(|&k| self.reading.category_probability(&self.keys[k], &sims[k]).unwrap_or(0.0))
                .collect();
            let total: f64 = q.iter().sum();
            if !(total > 0.0) {
                continue;
            }
            let mut u = rng.random::<f64>() * total;
            let mut pick = group[group.len() - 1];
            for (&k, q) in group.iter().zip(&q) {
                if u < *q {
                    pick = k;
                    break;
                }
                u -= q;
            }
            out.push((pick, 1.0));
        }
        out
    }

    /// An observation of key `k` with its σ (its value set later).
    pub(super) fn template(&self, k: usize) -> Observation {
        Observation {
            specimen: String::new(),
            group: String::new(),
            observable: self.keys[k],
            value: 0.0,
            sigma: self.sigma[k],
        }
    }

    /// The scores of the simulated `specimens` (each its observations) under one
    /// contender: at `fixed`, or at every scan point of `scan` (`cache` keeps each
    /// reading's row of scores).
    pub(super) fn scores(
        &self,
        specimens: &[Vec<(usize, f64)>],
        fixed: &[Simulated],
        scan: Option<&[Vec<Simulated>]>,
        cache: &mut ScoreCache,
    ) -> NewScores {
        let mut obs = Vec::new();
        let mut key = Vec::new();
        let mut y = Vec::new();
        let names: Vec<String> = (0..specimens.len()).map(|i| format!("s{i}")).collect();
        let mut of = Vec::new();
        for (i, s) in specimens.iter().enumerate() {
            for &(k, v) in s {
                obs.push(Observation { specimen: names[i].clone(), value: v, ..self.template(k) });
                key.push(k);
                y.push(v);
                of.push(i);
            }
        }
        let weight = specimen_weights(&obs);
        let data =
            Data { obs: &obs, y: &y, key: &key, weight: &weight, reading: self.reading, bracket_deg: self.bracket_deg };
        let Some(scan) = scan else {
            let scores: Vec<f64> = (0..obs.len()).map(|j| data.score(fixed, j)).collect();
            return NewScores::Fixed {
                all: per_specimen(&scores, &obs, &names),
                pins: per_specimen(&data.split_scores(&scores).0, &obs, &names),
            };
        };
        let points = scan.len();
        let mut pins_t = vec![vec![0.0; specimens.len()]; points];
        let mut all_t = vec![vec![0.0; specimens.len()]; points];
        let unit = vec![1.0; obs.len()];
        let unweighted = Data { weight: &unit, ..data };
        for j in 0..obs.len() {
            let pins = data.pins(j);
            let row = cache
                .entry((key[j], y[j].to_bits()))
                .or_insert_with(|| scan.iter().map(|sims| unweighted.score(sims, j)).collect());
            for p in 0..points {
                let s = weight[j] * row[p];
                all_t[p][of[j]] += s;
                if pins {
                    pins_t[p][of[j]] += s;
                }
            }
        }
        NewScores::Scan { pins: pins_t, all: all_t }
    }
}
