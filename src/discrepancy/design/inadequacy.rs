//! The model discrepancy a first campaign shows beside each contender, carried into the
//! simulated follow-ups ([`inadequacy`]).
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

use super::refit::{FirstDesign, FirstValues};
use crate::discrepancy::fit::Data;
use crate::discrepancy::predictive::Simulated;
use crate::discrepancy::Run;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The level of the check that declares a discrepancy: the weighted sum of the measures'
/// squared standardized residuals at the contender's first-campaign fit is compared with
/// this quantile of χ² on their weighted count.
pub const CHECK_LEVEL: f64 = 0.95;

/// `[contender]`: the variance of a follow-up's bias per key, in units of the key's
/// predictive variance, that the first campaign shows beside each contender of `first`
/// (its predictions at its fit, `first.at_fit`).
///
/// For one contender, with `z_j` the standardized residual of measure `j` (a collapse
/// angle or a displacement; not the mechanism's readings) at the contender's fit
/// ([`Data::predictive`]) and `w_j` its weight (a specimen's displacements share one),
/// `S = Σ w_j z_j²` on `n = Σ w_j`: when `S` exceeds the [`CHECK_LEVEL`] quantile of χ²
/// on `n` degrees of freedom, the discrepancy is `S / n − 1`; else 0 (the first campaign
/// does not tell it from the reading σ). A fit on the same data makes `S` small, so the
/// check errs toward no discrepancy.
pub fn inadequacy(run: &Run, first: &FirstDesign) -> Vec<f64> {
    let values = FirstValues::of(run);
    let data = values.data(run);
    first.at_fit.iter().map(|sims| excess(&data, sims)).collect()
}

/// The discrepancy of the predictions `sims` (`[key]`) on `data` ([`inadequacy`]).
fn excess(data: &Data<'_>, sims: &[Simulated]) -> f64 {
    let (mut s, mut n) = (0.0, 0.0);
    for (j, o) in data.obs.iter().enumerate() {
        if o.observable.is_mechanism() || !sims[data.key[j]].mean.is_finite() {
            continue;
        }
        let z = data.predictive(sims, j).z(data.y[j]);
        if z.is_finite() {
            s += data.weight[j] * z * z;
            n += data.weight[j];
        }
    }
    discrepancy_of(s, n)
}

/// The discrepancy of a weighted sum of squared standardized residuals `s` on the weighted
/// count `n` ([`inadequacy`]).
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
}
