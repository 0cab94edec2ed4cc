//! The model discrepancy a first campaign shows beside each contender, carried into the
//! simulated follow-ups ([`inadequacy`], [`Inadequacy`]).
//!
//! A follow-up drawn from a contender's model alone assumes that the walls the laboratory
//! will build behave as that model predicts, to the reading σ. Real walls differ from every
//! model (their stones are not the generator's, an edited layout is not an effect's), and a
//! follow-up that separates two models on model-made data can leave them tied on a real
//! campaign. Where the first campaign already shows that a contender misses its data by
//! more than its own predictive spread allows, the simulated follow-ups drawn from it carry
//! a model discrepancy of that size: a bias per key, shared by every specimen of the
//! follow-up (the walls of one campaign share how they differ from the model), in the
//! manner of the discrepancy term of Kennedy and O'Hagan (2001, *J. R. Stat. Soc. B* 63,
//! 425–464).

use super::refit::{FirstDesign, FirstScores, FirstValues};
use crate::discrepancy::fit::Data;
use crate::discrepancy::predictive::Simulated;
use crate::discrepancy::Run;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The level of the check that declares a discrepancy: the weighted sum of the measures'
/// squared standardized residuals at the contender's first-campaign fit is compared with
/// this quantile of χ² on their weighted count.
pub const CHECK_LEVEL: f64 = 0.95;

/// The model discrepancy each contender shows on the first campaign, in units of a key's
/// predictive variance: the variance of the bias per key a follow-up drawn from it carries.
#[derive(Debug, Clone, PartialEq)]
pub struct Inadequacy {
    /// `[contender]`: on the first campaign's walls. With `z_j` the standardized residual
    /// of measure `j` (a collapse angle or a displacement; not the mechanism's readings) at
    /// the contender's fit (`Data::predictive`) and `w_j` its weight (a specimen's
    /// displacements share one), `S = Σ w_j z_j²` on `n = Σ w_j`: when `S` exceeds the
    /// [`CHECK_LEVEL`] quantile of χ² on `n` degrees of freedom, `S / n − 1`; else 0 (the
    /// first campaign does not tell it from the reading σ). A fit on the same data makes
    /// `S` small, so the check errs toward no discrepancy.
    pub own: Vec<f64>,
    /// `[contender]`: added on walls of a kind the first campaign did not test, from how
    /// the contender carries to a kind of wall it was not fitted on (leave one group out).
    /// For each group `g`, the contender is refit on the measures of the other groups'
    /// specimens (the scan point of least summed score, [`FirstScores::pins`], the first of
    /// equals) and its predictions there ([`FirstScores::scan`]) score `g`'s measures: `S'`
    /// over every group on the same `n`. The excess `S'/n − S/n`, where positive, is the
    /// share of the predictive variance that moving to an unseen kind of wall adds. 0 for a
    /// contender without parameters (the baseline) or a campaign of one group.
    pub transfer: Vec<f64>,
}

/// The discrepancy of every contender (`first`: its scores at its scan points, `None` for
/// the baseline; `design`: its predictions at its fit), [`Inadequacy`].
pub fn inadequacy(run: &Run, first: &[Option<FirstScores>], design: &FirstDesign) -> Inadequacy {
    let values = FirstValues::of(run);
    let data = values.data(run);
    let mut names: Vec<&str> = run.obs.iter().map(|o| o.group.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    let index = |g: &str| names.iter().position(|n| *n == g).unwrap_or(0);
    let obs_group: Vec<usize> = run.obs.iter().map(|o| index(&o.group)).collect();
    let specimen_group: Vec<usize> = run
        .specimens
        .iter()
        .map(|name| run.obs.iter().find(|o| &o.specimen == name).map_or(0, |o| index(&o.group)))
        .collect();
    let (mut own, mut transfer) = (Vec::new(), Vec::new());
    for (scores, at_fit) in first.iter().zip(&design.at_fit) {
        let fit = squares(&data, at_fit, |_| true);
        own.push(discrepancy_of(fit.0, fit.1));
        transfer
            .push(scores.as_ref().map_or(0.0, |fs| carried(&data, fs, fit, &specimen_group, &obs_group, names.len())));
    }
    Inadequacy { own, transfer }
}

/// `(S, n)` of the predictions `sims` (`[key]`) on the observations `j` of `data` that
/// `keep` keeps ([`Inadequacy::own`]).
fn squares(data: &Data<'_>, sims: &[Simulated], keep: impl Fn(usize) -> bool) -> (f64, f64) {
    let (mut s, mut n) = (0.0, 0.0);
    for (j, o) in data.obs.iter().enumerate() {
        if !keep(j) || o.observable.is_mechanism() || !sims[data.key[j]].mean.is_finite() {
            continue;
        }
        let z = data.predictive(sims, j).z(data.y[j]);
        if z.is_finite() {
            s += data.weight[j] * z * z;
            n += data.weight[j];
        }
    }
    (s, n)
}

/// The discrepancy one contender carries to an unseen kind of wall
/// ([`Inadequacy::transfer`]): its scores and scan predictions `fs`, `(S, n)` at its fit on
/// every group `fit`, the group of each specimen and of each observation of `data`
/// (indices below `groups`).
fn carried(
    data: &Data<'_>,
    fs: &FirstScores,
    fit: (f64, f64),
    specimen_group: &[usize],
    obs_group: &[usize],
    groups: usize,
) -> f64 {
    if groups < 2 || fs.pins.is_empty() {
        return 0.0;
    }
    let (mut s_out, mut n_out) = (0.0, 0.0);
    for g in 0..groups {
        let others: Vec<usize> = (0..specimen_group.len()).filter(|&i| specimen_group[i] != g).collect();
        let best = (0..fs.pins.len())
            .map(|p| (p, others.iter().map(|&i| fs.pins[p][i]).sum::<f64>()))
            .fold((0, f64::INFINITY), |b, (p, v)| if v < b.1 { (p, v) } else { b });
        let (s, n) = squares(data, &fs.scan[best.0], |j| obs_group[j] == g);
        s_out += s;
        n_out += n;
    }
    let (s_in, n_in) = fit;
    if n_in > 0.0 && n_out > 0.0 {
        (s_out / n_out - s_in / n_in).max(0.0)
    } else {
        0.0
    }
}

/// The discrepancy of a weighted sum of squared standardized residuals `s` on the weighted
/// count `n` ([`Inadequacy::own`]).
pub fn discrepancy_of(s: f64, n: f64) -> f64 {
    if !(n >= 1.0) {
        return 0.0;
    }
    let bound = ChiSquared::new(n).map_or(f64::INFINITY, |d| d.inverse_cdf(CHECK_LEVEL));
    if s > bound {
        s / n - 1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::{Observable, Observation};
    use crate::discrepancy::predictive::Heights;
    use crate::discrepancy::Reading;

    /// The gate is χ²'s 95th percentile (closed form for 2 degrees of freedom:
    /// `−2 ln 0.05 = 5.991`), and above it the discrepancy is the excess of the mean
    /// square over 1.
    #[test]
    fn a_discrepancy_is_declared_beyond_the_chi_square_bound() {
        let bound = -2.0 * (0.05f64).ln();
        assert_eq!(discrepancy_of(bound - 1e-6, 2.0), 0.0);
        assert!((discrepancy_of(bound + 1e-6, 2.0) - (bound / 2.0 - 1.0)).abs() < 1e-6);
        assert_eq!(discrepancy_of(100.0, 0.5), 0.0);
        assert_eq!(discrepancy_of(f64::NAN, 10.0), 0.0);
    }

    fn obs(specimen: &str, group: &str, value: f64) -> Observation {
        Observation {
            specimen: specimen.into(),
            group: group.into(),
            observable: Observable::CollapseAngle,
            value,
            sigma: 0.5,
        }
    }

    fn at(mean: f64) -> Simulated {
        Simulated { mean, sd: 0.0, n: 1, err: 0.0, heights: Heights::NONE }
    }

    /// Two groups of two specimens each, one key a group (predictive σ exactly 0.5: one
    /// realization, no bracket, exact readings). Group A reads 20°, group B 24°. A contender
    /// whose two scan points predict (20°, 22°) and (22°, 24°) fits either group at one point
    /// and misses the other there by 2° (4 σ): refit on B it predicts A at 22°, refit on A it
    /// predicts B at 22°, so every held-out group's residual is 4 σ (`S'/n = 16`) where the fit
    /// on both, (20°, 24°), leaves none: it carries 16 predictive variances to an unseen wall.
    /// A contender whose scan points both fit both groups carries none; one group alone
    /// cannot tell.
    #[test]
    fn a_contender_that_misses_a_group_it_was_not_fitted_on_carries_the_miss_to_new_walls() {
        let o = [obs("A1", "A", 20.0), obs("A2", "A", 20.0), obs("B1", "B", 24.0), obs("B2", "B", 24.0)];
        let y: Vec<f64> = o.iter().map(|x| x.value).collect();
        let (key, weight) = ([0, 0, 1, 1], [1.0; 4]);
        let exact = Reading {
            angle_deg: 0.0,
            displacement_cm: 0.0,
            misreading: 0.0,
            neighbour_joint: 0.0,
            ..Reading::default()
        };
        let data = Data { obs: &o, y: &y, key: &key, weight: &weight, reading: exact, bracket_deg: 0.0 };
        let scan = vec![vec![at(20.0), at(22.0)], vec![at(22.0), at(24.0)]];
        // Scores of the measures per scan point and specimen: lower where the group fits.
        let pins = vec![vec![0.0, 0.0, 8.0, 8.0], vec![8.0, 8.0, 0.0, 0.0]];
        let fs = FirstScores { pins: pins.clone(), all: pins, scan };
        let fit = [at(20.0), at(24.0)];
        let at_fit = squares(&data, &fit, |_| true);
        assert_eq!(at_fit, (0.0, 4.0));
        let v = carried(&data, &fs, at_fit, &[0, 0, 1, 1], &[0, 0, 1, 1], 2);
        assert!((v - 16.0).abs() < 1e-9, "{v}");
        let flat = FirstScores { scan: vec![fit.to_vec(), fit.to_vec()], ..fs.clone() };
        assert_eq!(carried(&data, &flat, at_fit, &[0, 0, 1, 1], &[0, 0, 1, 1], 2), 0.0);
        assert_eq!(carried(&data, &fs, at_fit, &[0, 0, 0, 0], &[0, 0, 0, 0], 1), 0.0);
    }
}
