//! The candidates scored and ranked: each candidate's held-out error (leave one specimen
//! out, [`super::fit::loso`]), its standard error against the baseline and its AICc at the
//! full-data fit, used by the analysis and by every null data set of its calibration.

use super::candidate::Candidate;
use super::compare::{aicc, difference_se, per_specimen};
use super::fit::{loso, Data};
use super::predictive::{Predictive, Simulated};
use serde::Serialize;

/// The models' simulated values, ready for analysis: the baseline per key and the
/// candidates.
#[derive(Debug, Clone)]
pub struct Models {
    /// The baseline's simulated values, per key.
    pub baseline: Vec<Simulated>,
    /// The candidates (single effects and the scatter hypothesis).
    pub candidates: Vec<Candidate>,
    /// The pairs of every effect that acts on the readings only with every other searched
    /// effect (`jack_tilt+joint_closure`, …), each on its partner's grid read again at the
    /// readings' nodes (no run of their own, [`super::fit::Surface::Grid`] or
    /// [`super::fit::Surface::Grid3`]); tried beside the additive pairs when pairs are
    /// tried. Empty on protocols other than the in-plane test.
    pub readings_pairs: Vec<Candidate>,
    /// The triples of both effects on the readings only with every one-parameter effect
    /// that moves the wall (`jack_tilt+rig_friction+bed_stiffness`, …), on the partner's
    /// grid read again ([`super::fit::Surface::Grid3`]). Not ranked: refit with one of the
    /// rig's forces held where another reading fixes it ([`super::Run::refit_held`]). Empty
    /// on protocols other than the in-plane test.
    pub readings_triples: Vec<Candidate>,
}

/// A ranked candidate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ranked {
    /// Candidate name (`a`, `a+b`, `scatter`).
    pub name: String,
    /// Fitted parameters on all data, `effect.param` → value.
    pub parameters: Vec<(String, f64)>,
    /// Mean held-out score per specimen.
    pub heldout_error: f64,
    /// Standard error of the summed held-out difference to the baseline.
    pub difference_se: f64,
    /// AICc at the full-data fit.
    pub information_criterion: f64,
    /// Scored by a full run at its fitted parameters (not the surrogate alone).
    pub confirmed: bool,
    /// Search coordinates of the full-data fit.
    #[serde(skip)]
    pub x: Vec<f64>,
    /// Index into the analysis's candidate pool.
    #[serde(skip)]
    pub index: usize,
    /// Held-out score of every observation.
    #[serde(skip)]
    pub scores: Vec<f64>,
    /// Held-out predictive of every observation.
    #[serde(skip)]
    pub predictive: Vec<Predictive>,
}

#[cfg(test)]
impl Ranked {
    /// A candidate `name` with the held-out scores `scores` and nothing else, for tests.
    pub(crate) fn with_scores(name: &str, scores: Vec<f64>) -> Ranked {
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
}

/// Held-out error and full-data fit of one candidate.
pub fn score(c: &Candidate, data: Data<'_>, specimens: &[String], index: usize, base: &[f64]) -> Ranked {
    // The full-data fit and the held-out fits share one scan of the surface.
    let (scores, predictive, (x, nlpd)) = loso(&c.surface, data, specimens);
    let per = per_specimen(&scores, data.obs, specimens);
    let d: Vec<f64> = base.iter().zip(&per).map(|(b, c)| b - c).collect();
    let n = specimens.len().max(1);
    Ranked {
        name: c.name(),
        parameters: c.values(&x),
        heldout_error: per.iter().sum::<f64>() / n as f64,
        difference_se: difference_se(&d) / n as f64,
        information_criterion: aicc(nlpd, c.surface.dims(), n),
        confirmed: false,
        x,
        index,
        scores,
        predictive,
    }
}

/// Ranks the candidates on `data`: best held-out error first (ties by pool order).
pub fn rank(pool: &[Candidate], data: Data<'_>, specimens: &[String], base: &[f64]) -> Vec<Ranked> {
    let mut r: Vec<Ranked> = pool.iter().enumerate().map(|(i, c)| score(c, data, specimens, i, base)).collect();
    sort(&mut r);
    r
}

/// Sorts by held-out error, then pool order.
pub fn sort(r: &mut [Ranked]) {
    r.sort_by(|a, b| a.heldout_error.total_cmp(&b.heldout_error).then(a.index.cmp(&b.index)));
}
