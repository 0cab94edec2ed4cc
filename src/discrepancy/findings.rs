//! What an analysis found, beyond the ranking: the [`Run`] with every part of it, the
//! design that would separate two tied candidates, the fitted parameters of the cause and
//! the bootstrap interval of the gain.

use super::analysis::Analysis;
use super::analysis::Models;
use super::effects::Effect;
use super::observations::Observation;
use super::predictive::{Predictive, Simulated};
use super::prepare::Keys;
use super::simulate::Outcome;
use super::Settings;
use serde::Serialize;

/// A fitted parameter of the named cause: `effect.param`, its value and its interval (in
/// the parameter's unit; see [`crate::effects::ParamDef`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FittedParameter {
    /// `effect.param`.
    pub name: String,
    /// The fitted value: in the range of the analysed walls' kind when they all declare
    /// the same one (the value the runs applied, [`crate::effects::ParamDef::at_for`]), in
    /// the broad range otherwise (the report gives the values per kind).
    pub value: f64,
    /// The interval (lower, upper), in the same range.
    pub interval: (f64, f64),
}

/// A model refit with one parameter held at a value another reading gives
/// ([`Run::refit_held`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldRefit {
    /// The model's name as a candidate's (`jack_tilt+rig_friction+bed_stiffness`).
    pub name: String,
    /// Its parameters fitted to all the data, the held one among them at its value,
    /// `effect.param` → value.
    pub parameters: Vec<(String, f64)>,
    /// Its held-out error (mean held-out score per specimen, leave one specimen out, the
    /// held parameter held in every fold), comparable with the ranked candidates'.
    pub heldout_error: f64,
    /// The standard error of its summed held-out difference to the baseline, per specimen.
    pub difference_se: f64,
}

/// Everything a discrepancy run computed.
#[derive(Debug, Clone)]
pub struct Run {
    /// The observations.
    pub obs: Vec<Observation>,
    /// Their keys.
    pub keys: Keys,
    /// The specimens, in first-seen order.
    pub specimens: Vec<String>,
    /// The surrogate library.
    pub library: Models,
    /// The analysis.
    pub analysis: Analysis,
    /// The baseline's full run, `[group][realization]`.
    pub baseline: Vec<Vec<Outcome>>,
    /// The surrogate grids' outcomes ([`super::Prepared::grids`]).
    pub grids: std::sync::Arc<super::prepare::GridRuns>,
    /// The extended model's effects at the fitted parameters and its full run, when a
    /// mechanism was named (also as a partial explanation).
    pub extended: Option<(Vec<Effect>, Vec<Vec<Outcome>>)>,
    /// Predictive of every observation under the extended model (the baseline's when no
    /// cause was named).
    pub extended_predictive: Vec<Predictive>,
    /// Gain in held-out error (baseline − extended, per specimen) and its 95 % bootstrap
    /// interval over specimens.
    pub gain: Option<(f64, f64, f64)>,
    /// What would separate tied candidates: an observable, the difference of the two
    /// models there in predictive standard deviations, and the specimens of its group a
    /// test would need to tell them apart (two-sided 5 %, power 80 %).
    pub design: Option<Design>,
    /// Width of a simulated collapse angle's bracket, degrees (the study's resolution).
    pub bracket_deg: f64,
    /// The cause's parameters: `effect.param`, fitted value and 95 % profile interval.
    pub cause_interval: Vec<FittedParameter>,
    /// The measurement σ the data show (collapse angles in degrees, displacements in cm),
    /// each with its degrees of freedom, where the data allow an estimate
    /// ([`super::measurement_sigma`]). The analysis uses the larger of it and the
    /// setting: data that scatter more than the model and the stated σ together are not
    /// evidence for a mechanism.
    pub sigma_estimate: [Option<(f64, usize)>; super::observations::MEASURE_FAMILIES],
    /// The settings.
    pub settings: Settings,
    /// The effects that change nothing in a group ([`super::Prepared::inert`]).
    pub inert: Vec<super::InertEffect>,
    /// The next experiment, when one was designed ([`super::design::design`]; `drystone
    /// design`): the report then has its section and the JSON its `followup`. `None` from
    /// an analysis alone.
    pub followup: Option<super::design::Plan>,
}

impl Run {
    /// The effects of the candidate `name` (a ranked candidate's name, `a+b` for a pair) at
    /// its parameters fitted to all the data, for a group of course height `course_m` (m;
    /// the length scale of its effects' parameters, `effects::course_height_of`); `None` for
    /// a name the analysis did not rank (the baseline included: it has no effect).
    ///
    /// # Errors
    /// A parameter the effect refuses (it does not happen for a fit within the ranges).
    pub fn fitted_effects(&self, name: &str, course_m: f64) -> Result<Option<Vec<Effect>>, super::DiscrepancyError> {
        let Some(r) = self.analysis.candidates.iter().find(|r| r.name == name) else {
            return Ok(None);
        };
        let Some(c) = self.analysis.pool.get(r.index) else {
            return Ok(None);
        };
        super::prepare::effects_of(c, &r.x, course_m).map(Some)
    }

    /// Whether the ranked candidate `name`'s model at its fitted parameters is the
    /// baseline's ([`super::Candidate::is_baseline_at`]): a run of it is a run of the
    /// baseline. `false` for a name the analysis did not rank.
    pub fn is_baseline_model(&self, name: &str) -> bool {
        let Some(r) = self.analysis.candidates.iter().find(|r| r.name == name) else {
            return false;
        };
        let Some(c) = self.analysis.pool.get(r.index) else {
            return false;
        };
        c.is_baseline_at(&r.x)
    }
}

impl Run {
    /// The model of the effects `effects` with the effect `held` (one parameter) refit to
    /// the data with `held`'s parameter at `value` (in its unit): the candidate of exactly
    /// those effects (the analysis's pool first, its confirmed surfaces among them, then the
    /// library's singles, readings pairs and readings triples), its surface sliced at
    /// `held`'s coordinate ([`super::Surface::Slice`]) and scored as the ranking scores
    /// ([`super::fit::loso`]). `None` when no candidate has those effects, `held` has
    /// another number of parameters than one, or `value` is outside its range. No run.
    pub fn refit_held(&self, effects: &[&str], held: &str, value: f64) -> Option<HeldRefit> {
        use super::compare::{difference_se, per_specimen, specimen_weights};
        use super::fit::{loso, to_x, Data, Surface};
        let mut want: Vec<&str> = effects.iter().copied().filter(|e| *e != held).chain([held]).collect();
        want.sort_unstable();
        let lib = &self.library;
        let c = self
            .analysis
            .pool
            .iter()
            .chain(&lib.candidates)
            .chain(&lib.readings_pairs)
            .chain(&lib.readings_triples)
            .find(|c| {
                let mut names: Vec<&str> = c.effects.iter().map(|e| e.name.as_str()).collect();
                names.sort_unstable();
                names == want
            })?;
        let mut axis = 0;
        for e in &c.effects {
            if e.name == held {
                break;
            }
            axis += e.parameters.len();
        }
        let p = c.params.get(axis).filter(|_| c.effects.iter().any(|e| e.name == held && e.parameters.len() == 1))?;
        let lo = p.min.min(p.max);
        let hi = p.min.max(p.max);
        if !(lo..=hi).contains(&value) {
            return None;
        }
        let xv = to_x(p, value).clamp(0.0, 1.0);
        let surface = Surface::Slice { inner: Box::new(c.surface.clone()), axis, value: xv };
        let y: Vec<f64> = self.obs.iter().map(|o| o.value).collect();
        let weight = specimen_weights(&self.obs);
        let data = Data {
            obs: &self.obs,
            y: &y,
            key: &self.keys.of,
            weight: &weight,
            reading: self.settings.reading,
            bracket_deg: self.bracket_deg,
        };
        let (scores, _, (x, _)) = loso(&surface, data, &self.specimens);
        let mut full = x;
        full.insert(axis.min(full.len()), xv);
        let per = per_specimen(&scores, &self.obs, &self.specimens);
        let base = per_specimen(&self.analysis.baseline_scores, &self.obs, &self.specimens);
        let d: Vec<f64> = base.iter().zip(&per).map(|(b, c)| b - c).collect();
        let n = self.specimens.len().max(1) as f64;
        Some(HeldRefit {
            name: c.name(),
            parameters: c.values(&full),
            heldout_error: per.iter().sum::<f64>() / n,
            difference_se: difference_se(&d) / n,
        })
    }
}

/// What would separate two tied candidates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Design {
    /// The two candidates.
    pub candidates: (String, String),
    /// The group and observable that separates them best.
    pub observable: String,
    /// Their difference there, in standard deviations of a new specimen (the models' spread,
    /// their surrogates' error and the measurement σ).
    pub effect_size: f64,
    /// Specimens of that group needed (two-sided 5 %, power 80 %).
    pub specimens: usize,
}

/// `sigma[k]`: the measurement σ of key `k` (a new specimen is read with it).
pub(super) fn design(
    a: &[Simulated],
    b: &[Simulated],
    sigma: &[f64],
    labels: &[String],
    names: (String, String),
) -> Option<Design> {
    let mut best: Option<(usize, f64)> = None;
    for k in 0..a.len() {
        let sd =
            (0.5 * (a[k].sd.powi(2) + b[k].sd.powi(2)) + a[k].err.powi(2) + b[k].err.powi(2) + sigma[k].powi(2)).sqrt();
        let d = (a[k].mean - b[k].mean).abs() / sd.max(1e-12);
        if d.is_finite() && best.is_none_or(|(_, bd)| d > bd) {
            best = Some((k, d));
        }
    }
    let (k, d) = best?;
    let n = ((1.96 + 0.84) / d.max(1e-6)).powi(2).ceil().min(1e6) as usize;
    Some(Design { candidates: names, observable: labels[k].clone(), effect_size: d, specimens: n.max(2) })
}

/// The mean held-out gain per specimen (baseline − extended) and its 95 % percentile
/// bootstrap interval, resampling specimens with replacement.
pub fn bootstrap_gain(base: &[f64], ext: &[f64], resamples: usize, seed: u64) -> (f64, f64, f64) {
    use rand::RngExt;
    let d: Vec<f64> = base.iter().zip(ext).map(|(b, e)| b - e).collect();
    if d.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let mut rng = crate::rng::rng_for(seed, u64::MAX >> 8, crate::rng::Purpose::Bootstrap);
    let mut means: Vec<f64> = (0..resamples)
        .map(|_| (0..d.len()).map(|_| d[rng.random_range(0..d.len())]).sum::<f64>() / d.len() as f64)
        .collect();
    means.sort_by(f64::total_cmp);
    (crate::stats::mean(&d), crate::stats::quantile(&means, 0.025), crate::stats::quantile(&means, 0.975))
}
