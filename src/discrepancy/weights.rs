//! Posterior probabilities over the causes: a weight for the baseline, every candidate and
//! `scatter`, from the per-specimen held-out log scores the ranking already has.
//!
//! Two weights per model, both from the held-out (leave-one-specimen-out) log predictive
//! density `elpd_ik = −score_ik` of specimen `i` under model `k` (a specimen's readings
//! summed with their weights, [`super::compare::specimen_weights`]):
//!
//! * **pseudo-BMA+** (Yao, Vehtari, Simpson & Gelman 2018, Bayesian Analysis 13:917, §3.4):
//!   `w_k ∝ exp(n Σ_i α_i elpd_ik)` averaged over Bayesian-bootstrap draws `α ~
//!   Dirichlet(1, …, 1)` over the `n` specimens (Rubin 1981), which discounts a model whose
//!   advantage rests on few specimens. Read as "how much the data favour it" among the
//!   models compared; its 95 % interval is that of the draws' weights.
//! * **stacking** (ibid., §3.2): the weights on the simplex maximising `Σ_i ln Σ_k w_k
//!   exp(elpd_ik)`, the mixture of predictive distributions that predicts held-out
//!   specimens best; a concave problem, solved by the EM fixed point for mixture weights
//!   `w_k ← w_k (1/n) Σ_i p_ik / Σ_l w_l p_il` (monotone ascent; Dempster, Laird & Rubin
//!   1977). Its interval: the same problem on Bayesian-bootstrap weights of the specimens.
//!   Stacking splits the weight among models that predict alike (it asks which mixture
//!   predicts best, not which model is true).
//!
//! **The candidates that share the weight** are the fewest models, heaviest first, whose
//! pseudo-BMA+ weights add up to [`SHARED`] (90 %). They stand beside the tie
//! ([`super::analysis::TieCheck`]), which the verdict keeps.
//!
//! The draws come from `rng::rng_for(seed, 0, Purpose::Weights)`, one sequential stream:
//! the weights are the same on any number of threads.

use crate::rng::{rng_for, Purpose};
use rand_distr::{Distribution, Exp1};
use serde::Serialize;

/// The share of the pseudo-BMA+ weight the models that share the weight hold together.
pub const SHARED: f64 = 0.9;

/// Iterations of the stacking fixed point (point estimate; a bootstrap draw uses a fifth).
const STACKING_ITERATIONS: usize = 2000;

/// Bootstrap draws of the stacking weights at most (each solves the problem again).
const STACKING_DRAWS: usize = 400;

/// The weights of one model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelWeight {
    /// The model: `baseline`, a candidate's name (`a`, `a+b`) or `scatter`.
    pub name: String,
    /// Pseudo-BMA+ weight, in [0, 1]; the models' weights sum to 1.
    pub pseudo_bma: f64,
    /// Its 95 % Bayesian-bootstrap interval.
    pub pseudo_bma_interval: (f64, f64),
    /// Stacking weight, in [0, 1]; the models' weights sum to 1.
    pub stacking: f64,
    /// Its 95 % Bayesian-bootstrap interval.
    pub stacking_interval: (f64, f64),
}

/// The weights of every model compared.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Weights {
    /// Every model, heaviest pseudo-BMA+ weight first.
    pub models: Vec<ModelWeight>,
    /// The fewest models, heaviest first, holding [`Weights::shared_share`] of the
    /// pseudo-BMA+ weight.
    pub shared: Vec<String>,
    /// The share the models in [`Weights::shared`] hold at least ([`SHARED`]).
    pub shared_share: f64,
    /// Bayesian-bootstrap draws of the pseudo-BMA+ weights (of the stacking weights at most
    /// `STACKING_DRAWS`).
    pub draws: usize,
}

impl Weights {
    /// The pseudo-BMA+ weight of `name` (0 if not compared).
    pub fn of(&self, name: &str) -> f64 {
        self.models.iter().find(|m| m.name == name).map_or(0.0, |m| m.pseudo_bma)
    }
}

/// `exp(v − max v)` normalised (a softmax); uniform if nothing is finite.
fn softmax(v: &[f64]) -> Vec<f64> {
    let m = v.iter().copied().filter(|x| x.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    if !m.is_finite() {
        return vec![1.0 / v.len().max(1) as f64; v.len()];
    }
    let e: Vec<f64> = v.iter().map(|x| if x.is_finite() { (x - m).exp() } else { 0.0 }).collect();
    let s: f64 = e.iter().sum();
    e.iter().map(|x| x / s).collect()
}

/// Stacking weights for the scaled densities `p[i][k]` (each row divided by its largest
/// entry) and specimen weights `alpha` (summing to 1), by `iterations` EM steps from the
/// uniform weights.
fn stack(p: &[Vec<f64>], alpha: &[f64], k: usize, iterations: usize) -> Vec<f64> {
    let mut w = vec![1.0 / k as f64; k];
    let mut next = vec![0.0; k];
    for _ in 0..iterations {
        next.iter_mut().for_each(|x| *x = 0.0);
        for (row, a) in p.iter().zip(alpha) {
            let d: f64 = row.iter().zip(&w).map(|(p, w)| p * w).sum();
            if d > 0.0 {
                for ((n, p), w) in next.iter_mut().zip(row).zip(&w) {
                    *n += a * p * w / d;
                }
            }
        }
        let s: f64 = next.iter().sum();
        if !(s > 0.0) {
            break;
        }
        let change = next.iter().zip(&w).map(|(n, w)| (n / s - w).abs()).fold(0.0, f64::max);
        w.iter_mut().zip(&next).for_each(|(w, n)| *w = n / s);
        if change < 1e-12 {
            break;
        }
    }
    w
}

/// The 2.5 % and 97.5 % quantiles of `v`.
fn interval(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    (crate::stats::quantile(&v, 0.025), crate::stats::quantile(&v, 0.975))
}

/// The weights of the models `names` from their held-out log predictive densities per
/// specimen, `elpd[k][i]` (model `k`, specimen `i`; nats, higher better), with `draws`
/// Bayesian-bootstrap draws seeded by `seed` (`Purpose::Weights`). Empty for no model;
/// with no specimen every weight is uniform.
pub fn weights(names: &[String], elpd: &[Vec<f64>], draws: usize, seed: u64) -> Weights {
    let k = names.len();
    if k == 0 {
        return Weights { shared_share: SHARED, ..Weights::default() };
    }
    let n = elpd.first().map_or(0, Vec::len);
    let mut rng = rng_for(seed, 0, Purpose::Weights);
    let mut dirichlet = || -> Vec<f64> {
        let g: Vec<f64> = (0..n).map(|_| Exp1.sample(&mut rng)).collect();
        let s: f64 = g.iter().sum();
        g.iter().map(|x| x / s).collect()
    };
    // Pseudo-BMA+.
    let mut bma_draws: Vec<Vec<f64>> = Vec::with_capacity(draws);
    let mut alphas: Vec<Vec<f64>> = Vec::new();
    for b in 0..draws {
        let a = dirichlet();
        let z: Vec<f64> = elpd.iter().map(|e| n as f64 * e.iter().zip(&a).map(|(x, a)| x * a).sum::<f64>()).collect();
        bma_draws.push(softmax(&z));
        if b < STACKING_DRAWS {
            alphas.push(a);
        }
    }
    let pseudo: Vec<f64> = if bma_draws.is_empty() {
        softmax(&elpd.iter().map(|e| e.iter().sum::<f64>()).collect::<Vec<_>>())
    } else {
        (0..k).map(|m| bma_draws.iter().map(|w| w[m]).sum::<f64>() / bma_draws.len() as f64).collect()
    };
    // Stacking on the densities scaled per specimen (the maximiser does not change).
    let p: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let row: Vec<f64> = elpd.iter().map(|e| e[i]).collect();
            let m = row.iter().copied().filter(|x| x.is_finite()).fold(f64::NEG_INFINITY, f64::max);
            row.iter().map(|x| if x.is_finite() && m.is_finite() { (x - m).exp() } else { 0.0 }).collect()
        })
        .collect();
    let uniform = vec![1.0 / n.max(1) as f64; n];
    let stacking = if n == 0 { vec![1.0 / k as f64; k] } else { stack(&p, &uniform, k, STACKING_ITERATIONS) };
    let stack_draws: Vec<Vec<f64>> = alphas.iter().map(|a| stack(&p, a, k, STACKING_ITERATIONS / 5)).collect();
    let column = |d: &[Vec<f64>], m: usize, point: f64| {
        if d.is_empty() {
            (point, point)
        } else {
            interval(d.iter().map(|w| w[m]).collect())
        }
    };
    let mut models: Vec<ModelWeight> = (0..k)
        .map(|m| ModelWeight {
            name: names[m].clone(),
            pseudo_bma: pseudo[m],
            pseudo_bma_interval: column(&bma_draws, m, pseudo[m]),
            stacking: stacking[m],
            stacking_interval: column(&stack_draws, m, stacking[m]),
        })
        .collect();
    // Heaviest first; equal weights in the given order.
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by(|&a, &b| models[b].pseudo_bma.total_cmp(&models[a].pseudo_bma).then(a.cmp(&b)));
    models = order.iter().map(|&m| models[m].clone()).collect();
    let mut shared = Vec::new();
    let mut held = 0.0;
    for m in &models {
        shared.push(m.name.clone());
        held += m.pseudo_bma;
        if held >= SHARED - 1e-12 {
            break;
        }
    }
    Weights { models, shared, shared_share: SHARED, draws }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two models and closed forms. Model A predicts every specimen `d` nats better than
    /// B: stacking puts all the weight on A (the EM fixed point of a dominated model is
    /// 0), and pseudo-BMA+ with a constant difference has no bootstrap spread, `w_A =
    /// 1/(1 + exp(−n d))`.
    #[test]
    fn a_model_better_on_every_specimen_takes_the_weight() {
        let names = vec!["A".to_string(), "B".to_string()];
        let n = 6;
        let d = 0.2;
        let elpd = vec![vec![-1.0; n], vec![-1.0 - d; n]];
        let w = weights(&names, &elpd, 500, 1);
        let want = 1.0 / (1.0 + (-(n as f64) * d).exp());
        assert!((w.of("A") - want).abs() < 1e-12, "{w:?}");
        let a = &w.models[0];
        assert_eq!(a.name, "A");
        assert!((a.pseudo_bma_interval.0 - want).abs() < 1e-12 && (a.pseudo_bma_interval.1 - want).abs() < 1e-12);
        assert!(a.stacking > 0.99, "{a:?}");
        // 0.769 of the weight: the two share it.
        assert_eq!(w.shared, vec!["A".to_string(), "B".to_string()]);
    }

    /// Stacking of two models each right on half the specimens: with densities p_A = (1,
    /// r) and p_B = (r, 1), r = e⁻², on the two halves, the optimum of `ln(w + (1−w) r) + ln(w r +
    /// 1 − w)` is `w = 1/2` by symmetry, where pseudo-BMA+ (equal summed scores) also
    /// gives 1/2 on average but with a wide interval. A third model, worse everywhere,
    /// gets no stacking weight.
    #[test]
    fn stacking_mixes_models_that_are_each_right_somewhere() {
        let names: Vec<String> = ["A", "B", "C"].iter().map(|s| s.to_string()).collect();
        let elpd = vec![vec![0.0, 0.0, 0.0, -2.0, -2.0, -2.0], vec![-2.0, -2.0, -2.0, 0.0, 0.0, 0.0], vec![-3.0; 6]];
        let w = weights(&names, &elpd, 1000, 3);
        let get = |n: &str| w.models.iter().find(|m| m.name == n).unwrap().clone();
        assert!((get("A").stacking - 0.5).abs() < 1e-6 && (get("B").stacking - 0.5).abs() < 1e-6, "{w:?}");
        assert!(get("C").stacking < 1e-6);
        assert!((get("A").pseudo_bma - 0.5).abs() < 0.05, "{:?}", get("A"));
        let (lo, hi) = get("A").pseudo_bma_interval;
        assert!(lo < 0.01 && hi > 0.99, "{lo} {hi}");
        // The same draws on a second call: a seeded stream.
        assert_eq!(weights(&names, &elpd, 1000, 3), w);
    }
}
