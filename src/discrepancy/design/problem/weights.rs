//! The pseudo-BMA+ weights of a simulated analysis of both campaigns, and whether they
//! name the truth alone.

use rand_distr::{Distribution, Exp1};

/// [`pseudo_bma`] over the contenders `present` in the ranking, 0 for the others (the
/// same random draws whatever the contenders present).
pub(super) fn pseudo_bma_of(
    elpd: &[Vec<f64>],
    present: &[bool],
    draws: usize,
    rng: &mut rand_chacha::ChaCha8Rng,
) -> Vec<f64> {
    if present.iter().all(|&p| p) {
        return pseudo_bma(elpd, draws, rng);
    }
    let kept: Vec<Vec<f64>> = elpd.iter().zip(present).filter(|(_, &p)| p).map(|(e, _)| e.clone()).collect();
    let mut w = pseudo_bma(&kept, draws, rng).into_iter();
    present.iter().map(|&p| if p { w.next().unwrap_or(0.0) } else { 0.0 }).collect()
}

/// Whether contender `t` alone holds [`crate::discrepancy::SHARED`] of the weights `w` (alone), and
/// whether it is among the fewest heaviest that hold it (right).
pub(super) fn named(w: &[f64], t: usize) -> (bool, bool) {
    let mut order: Vec<usize> = (0..w.len()).collect();
    order.sort_by(|&a, &b| w[b].total_cmp(&w[a]).then(a.cmp(&b)));
    let mut held = 0.0;
    let mut shared = Vec::new();
    for &m in &order {
        shared.push(m);
        held += w[m];
        if held >= crate::discrepancy::SHARED - 1e-12 {
            break;
        }
    }
    (shared == [t], shared.contains(&t))
}

/// Pseudo-BMA+ weights of the models with log scores per specimen `elpd[k][i]`: `w_k ∝
/// exp(n Σ_i α_i elpd_ik)` averaged over `draws` Bayesian-bootstrap draws `α ~
/// Dirichlet(1, …, 1)` (as [`crate::discrepancy::weights`]).
fn pseudo_bma(elpd: &[Vec<f64>], draws: usize, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
    let k = elpd.len();
    let n = elpd.first().map_or(0, Vec::len);
    let mut w = vec![0.0; k];
    let mut z = vec![0.0; k];
    let mut a = vec![0.0; n];
    for _ in 0..draws.max(1) {
        for x in a.iter_mut() {
            *x = Exp1.sample(rng);
        }
        let s: f64 = a.iter().sum();
        for (zk, e) in z.iter_mut().zip(elpd) {
            *zk = n as f64 * e.iter().zip(&a).map(|(x, a)| x * a).sum::<f64>() / s;
        }
        let m = z.iter().copied().filter(|x| x.is_finite()).fold(f64::NEG_INFINITY, f64::max);
        let e: Vec<f64> = z.iter().map(|x| if x.is_finite() { (x - m).exp() } else { 0.0 }).collect();
        let total: f64 = e.iter().sum();
        for (wk, ek) in w.iter_mut().zip(&e) {
            *wk += ek / total / draws.max(1) as f64;
        }
    }
    w
}
