//! Model discrepancy: what the simulation gets wrong against measured data, which physical
//! effect causes it, and what the extended model gains on data it did not fit.
//!
//! ```text
//!  measured data ─▶ observations ─┐
//!  study ─▶ baseline ensemble ─────┼─▶ diagnosis (standardized residuals by group,
//!          (common random numbers) │    observable, tilt; spread against specimens)
//!  effect library ─▶ ensembles on ─┴─▶ surrogates ─▶ fits, held-out error, AICc
//!   (effects/)      parameter grids        ─▶ margins from null data ─▶ verdict
//!                                          ─▶ extended model: full ensemble, gain
//! ```
//!
//! The reference formulation is Kennedy & O'Hagan (2001, J. R. Stat. Soc. B 63:425), a
//! statistical discrepancy term added after calibration; Brynjarsdóttir & O'Hagan (2014,
//! Inverse Problems 30:114007) show that such a term, without physics, confounds the
//! parameters. drystone instead searches a library of named physical mechanisms
//! ([`effects`]), each entering the model where it acts, and names one only when it
//! predicts held-out specimens better than the baseline by a margin calibrated on data
//! the baseline explains ([`analysis`]).
//!
//! Units: observations and predictions are in the measured data's units (degrees for
//! collapse angles, cm for displacements); effect parameters in the units of
//! [`effects::EffectKind::params`].

pub mod analysis;
pub mod effects;
pub mod fit;
pub mod observations;
pub mod predictive;
pub mod report;
pub mod simulate;
pub mod synthesize;

use analysis::{analyze, calibrate_margins, Analysis, Library};
use effects::{Effect, EffectKind};
use fit::{to_value, to_x, Candidate, Data, Surface};
use observations::{Observable, Observation};
use predictive::{Predictive, Simulated};
use serde::{Deserialize, Serialize};
use simulate::{run_models, Outcome, Outcomes, Setup};

/// Settings of a discrepancy analysis. Defaults in brackets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Realizations per group of every model on the fitting grids \[3\].
    pub realizations: u64,
    /// Realizations per group of the baseline and of the extended model's full run \[9\];
    /// the baseline's realizations beyond `realizations` make the null data of the margin
    /// calibration (with fewer than 3 the null data are drawn from the predictive
    /// distributions).
    pub extension_realizations: u64,
    /// Grid intervals per parameter axis of a one-parameter effect \[2\]: nodes at
    /// `x = 0, 1/G, …, 1`, the node nearest the neutral value taken from the baseline.
    pub grid_points: usize,
    /// Nodes per axis of a two-parameter effect \[2\], at the cell centres.
    pub grid_points_2d: usize,
    /// Null data sets of the margin calibration \[200\].
    pub null_replicates: usize,
    /// Bootstrap resamples of the specimens for the gain's interval \[2000\].
    pub bootstrap: usize,
    /// Tilt increment of the analysis's tilting-table runs, degrees \[1\]; every measured
    /// displacement's tilt must be a multiple of it.
    pub step_deg: f64,
    /// Collapse-angle resolution of those runs, degrees \[0.5\] (the reading precision of
    /// the measured angles).
    pub resolution_deg: f64,
    /// The effects searched \[all\].
    pub effects: Vec<EffectKind>,
    /// Measurement standard deviations.
    pub sigma: observations::MeasurementSigma,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            realizations: 3,
            extension_realizations: 9,
            grid_points: 2,
            grid_points_2d: 2,
            null_replicates: 200,
            bootstrap: 2000,
            step_deg: 1.0,
            resolution_deg: 0.5,
            effects: EffectKind::ALL.to_vec(),
            sigma: observations::MeasurementSigma::default(),
        }
    }
}

/// Errors of a discrepancy analysis.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DiscrepancyError {
    /// The measured data cannot be used.
    #[error("{file}: {source}")]
    Observations {
        /// The file(s).
        file: String,
        /// The cause.
        source: observations::ObservationError,
    },
    /// An effect specification is wrong.
    #[error(transparent)]
    Effect(#[from] effects::EffectError),
    /// A setting is out of range.
    #[error("discrepancy.{key} = {value}: {reason}")]
    Setting {
        /// The key.
        key: &'static str,
        /// The value.
        value: String,
        /// The range.
        reason: &'static str,
    },
    /// A measured displacement at a tilt the analysis's tilt steps do not reach.
    #[error(
        "specimen {specimen}: displacement at {tilt_deg} deg is not a multiple of discrepancy.step_deg = {step_deg}"
    )]
    Tilt {
        /// The specimen.
        specimen: String,
        /// Its tilt, degrees.
        tilt_deg: f64,
        /// The step, degrees.
        step_deg: f64,
    },
    /// Every realization of the baseline failed for a group.
    #[error("group {group}: every baseline realization failed ({error})")]
    Baseline {
        /// The group.
        group: String,
        /// The first error.
        error: String,
    },
}

impl Settings {
    /// Checks ranges.
    ///
    /// # Errors
    /// [`DiscrepancyError::Setting`] naming the key.
    pub fn validate(&self) -> Result<(), DiscrepancyError> {
        let bad = |key, value: String, reason| Err(DiscrepancyError::Setting { key, value, reason });
        if !(1..=10_000).contains(&self.realizations) {
            return bad("realizations", self.realizations.to_string(), "must be in [1, 10000]");
        }
        if !(1..=10_000).contains(&self.extension_realizations) {
            return bad("extension_realizations", self.extension_realizations.to_string(), "must be in [1, 10000]");
        }
        if !(1..=20).contains(&self.grid_points) {
            return bad("grid_points", self.grid_points.to_string(), "must be in [1, 20]");
        }
        if !(2..=10).contains(&self.grid_points_2d) {
            return bad("grid_points_2d", self.grid_points_2d.to_string(), "must be in [2, 10]");
        }
        if !(20..=100_000).contains(&self.null_replicates) {
            return bad("null_replicates", self.null_replicates.to_string(), "must be in [20, 100000]");
        }
        if !(100..=1_000_000).contains(&self.bootstrap) {
            return bad("bootstrap", self.bootstrap.to_string(), "must be in [100, 1000000]");
        }
        if !(self.step_deg > 0.0 && self.step_deg <= 5.0) {
            return bad("step_deg", self.step_deg.to_string(), "must be in (0, 5]");
        }
        if !(self.resolution_deg > 0.0 && self.resolution_deg <= self.step_deg) {
            return bad("resolution_deg", self.resolution_deg.to_string(), "must be in (0, step_deg]");
        }
        if self.effects.is_empty() {
            return bad("effects", "[]".into(), "needs at least one effect");
        }
        Ok(())
    }
}

/// The observable keys of the observations: `(group, observable)` pairs, and each
/// observation's key.
#[derive(Debug, Clone)]
pub struct Keys {
    /// Group index into the setup and observable of each key.
    pub keys: Vec<(usize, Observable)>,
    /// Key of each observation.
    pub of: Vec<usize>,
}

impl Keys {
    /// The keys of `obs` for the setup's groups (observations of a group the setup does not
    /// have are an error of the caller, caught by [`observations::observations`]).
    pub fn new(setup: &Setup, obs: &[Observation]) -> Keys {
        let mut keys: Vec<(usize, Observable)> = Vec::new();
        let mut of = Vec::with_capacity(obs.len());
        for o in obs {
            let g = setup.groups.iter().position(|g| g.name == o.group).unwrap_or(0);
            let k = match keys.iter().position(|(kg, ko)| *kg == g && ko.same(&o.observable)) {
                Some(k) => k,
                None => {
                    keys.push((g, o.observable));
                    keys.len() - 1
                }
            };
            of.push(k);
        }
        Keys { keys, of }
    }

    /// The simulated values of every key from one model's outcomes (`[group][realization]`).
    pub fn simulated(&self, outcomes: &[Vec<Outcome>]) -> Vec<Simulated> {
        self.keys.iter().map(|(g, o)| Simulated::of(&outcomes[*g], o)).collect()
    }
}

/// The models run for one effect: its grid nodes (search coordinates) and their effects.
#[derive(Debug, Clone)]
struct Plan {
    kind: EffectKind,
    /// Node coordinates; `None` marks the node taken from the baseline.
    nodes: Vec<(Vec<f64>, Option<Effect>)>,
}

fn effect_at(kind: EffectKind, x: &[f64]) -> Result<Effect, DiscrepancyError> {
    let values = kind.params().iter().zip(x).map(|(p, &xi)| to_value(p, xi)).collect();
    Ok(Effect::new(kind, values, kind.random_form().is_some())?)
}

fn plan(kind: EffectKind, s: &Settings) -> Result<Plan, DiscrepancyError> {
    let ps = kind.params();
    let mut nodes = Vec::new();
    if ps.len() == 1 {
        let xn = to_x(&ps[0], ps[0].neutral).clamp(0.0, 1.0);
        let g = s.grid_points;
        for k in 0..=g {
            let x = k as f64 / g as f64;
            if (x - xn).abs() >= 0.15 {
                nodes.push((vec![x], Some(effect_at(kind, &[x])?)));
            }
        }
        nodes.push((vec![xn], None));
        nodes.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    } else {
        let g = s.grid_points_2d;
        let axis: Vec<f64> = (0..g).map(|k| (k as f64 + 0.5) / g as f64).collect();
        for &a in &axis {
            for &b in &axis {
                nodes.push((vec![a, b], Some(effect_at(kind, &[a, b])?)));
            }
        }
    }
    Ok(Plan { kind, nodes })
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
    pub library: Library,
    /// The analysis.
    pub analysis: Analysis,
    /// The baseline's full run, `[group][realization]`.
    pub baseline: Vec<Vec<Outcome>>,
    /// The extended model's effects at the fitted parameters and its full run, when a
    /// cause was named.
    pub extended: Option<(Vec<Effect>, Vec<Vec<Outcome>>)>,
    /// Predictive of every observation under the extended model's full run.
    pub extended_predictive: Vec<Predictive>,
    /// Gain in held-out error (baseline − extended, per observation) and its 95 %
    /// bootstrap interval over specimens.
    pub gain: Option<(f64, f64, f64)>,
    /// Tilt resolution used.
    pub resolution_deg: f64,
    /// The settings.
    pub settings: Settings,
}

/// Builds the surrogate library: the baseline (from `baseline`, the first `realizations`
/// of each group) and every effect's grid, run with common random numbers.
pub fn build_library(
    setup: &Setup,
    keys: &Keys,
    baseline: &[Vec<Outcome>],
    s: &Settings,
) -> Result<Library, DiscrepancyError> {
    let plans: Vec<Plan> = s.effects.iter().map(|&k| plan(k, s)).collect::<Result<_, _>>()?;
    let models: Vec<Vec<Effect>> =
        plans.iter().flat_map(|p| p.nodes.iter().filter_map(|(_, e)| e.clone().map(|e| vec![e]))).collect();
    let grid_setup = Setup {
        groups: setup
            .groups
            .iter()
            .map(|g| simulate::GroupSetup { realizations: g.realizations.min(s.realizations), ..g.clone() })
            .collect(),
        ..setup.clone()
    };
    let base_grid: Vec<Vec<Outcome>> = baseline
        .iter()
        .zip(&grid_setup.groups)
        .map(|(o, g)| o[..(g.realizations as usize).min(o.len())].to_vec())
        .collect();
    let outcomes: Outcomes = run_models(&grid_setup, &models, Some(&base_grid));
    let base_sims = keys.simulated(&base_grid);
    let mut next = outcomes.iter();
    let mut candidates = Vec::new();
    for p in &plans {
        let sims: Vec<(Vec<f64>, Vec<Simulated>)> = p
            .nodes
            .iter()
            .map(|(x, e)| {
                let sims = match e {
                    Some(_) => keys.simulated(next.next().map(|v| v.as_slice()).unwrap_or(&[])),
                    None => base_sims.clone(),
                };
                (x.clone(), sims)
            })
            .collect();
        let surface = if p.kind.params().len() == 1 {
            Surface::Axis {
                xs: sims.iter().map(|(x, _)| x[0]).collect(),
                sims: sims.into_iter().map(|(_, s)| s).collect(),
            }
        } else {
            let mut x1: Vec<f64> = sims.iter().map(|(x, _)| x[0]).collect();
            x1.dedup();
            let mut x2: Vec<f64> = sims.iter().map(|(x, _)| x[1]).collect();
            x2.sort_by(f64::total_cmp);
            x2.dedup();
            Surface::Grid { x1, x2, sims: sims.into_iter().map(|(_, s)| s).collect() }
        };
        candidates.push(Candidate { effects: vec![p.kind], surface });
    }
    let base_sims = keys.simulated(&base_grid);
    Ok(Library { baseline: base_sims, candidates })
}

/// Runs the whole analysis: the baseline ensemble, the library, the margins, the ranking,
/// the extended model's full run and the gain. `seed` seeds the null data and the
/// bootstrap.
///
/// # Errors
/// [`DiscrepancyError`] for bad settings or a baseline that fails entirely.
pub fn run(setup: &Setup, obs: Vec<Observation>, s: &Settings, seed: u64) -> Result<Run, DiscrepancyError> {
    s.validate()?;
    for o in &obs {
        if let Observable::Displacement { tilt_deg, .. } = o.observable {
            let k = (tilt_deg / setup.tilt.step_deg).round();
            if (k * setup.tilt.step_deg - tilt_deg).abs() > 1e-9 {
                return Err(DiscrepancyError::Tilt {
                    specimen: o.specimen.clone(),
                    tilt_deg,
                    step_deg: setup.tilt.step_deg,
                });
            }
        }
    }
    let keys = Keys::new(setup, &obs);
    let specimens = observations::specimens(&obs);
    let full = Setup {
        groups: setup
            .groups
            .iter()
            .map(|g| simulate::GroupSetup { realizations: g.realizations.min(s.extension_realizations), ..g.clone() })
            .collect(),
        ..setup.clone()
    };
    let baseline = run_models(&full, &[vec![]], None).remove(0);
    for (g, outs) in full.groups.iter().zip(&baseline) {
        if outs.iter().all(|o| o.error.is_some()) {
            let error = outs.first().and_then(|o| o.error.clone()).unwrap_or_default();
            return Err(DiscrepancyError::Baseline { group: g.name.clone(), error });
        }
    }
    let library = build_library(setup, &keys, &baseline, s)?;
    // The diagnosis uses the full baseline run; the ranking compares like with like on the
    // grid's realizations (the library's baseline).
    let y: Vec<f64> = obs.iter().map(|o| o.value).collect();
    let data = Data { obs: &obs, y: &y, key: &keys.of, resolution_deg: s.resolution_deg };
    let pool: Vec<Vec<Outcome>> =
        baseline.iter().map(|o| o.get(s.realizations as usize..).map(|v| v.to_vec()).unwrap_or_default()).collect();
    let source = if pool.iter().any(|p| p.len() >= 3) {
        analysis::NullSource::Pool(&pool, &keys.keys)
    } else {
        analysis::NullSource::Predictive
    };
    let margins =
        calibrate_margins(&library, &obs, &keys.of, &specimens, s.resolution_deg, s.null_replicates, seed, source);
    let analysis = analyze(&library, data, &specimens, margins);
    let full_base = keys.simulated(&baseline);
    let mut extended = None;
    let mut extended_predictive: Vec<Predictive> = (0..obs.len()).map(|j| data.predictive(&full_base, j)).collect();
    let mut gain = None;
    if let Some(cause) = &analysis.cause {
        let c = &analysis.pool[cause.index];
        let mut effects = Vec::new();
        let mut offset = 0;
        for &k in &c.effects {
            let n = k.params().len();
            effects.push(effect_at(k, &cause.x[offset..offset + n])?);
            offset += n;
        }
        let outs = run_models(&full, &[effects.clone()], Some(&baseline)).remove(0);
        let sims = keys.simulated(&outs);
        extended_predictive = (0..obs.len()).map(|j| data.predictive(&sims, j)).collect();
        extended = Some((effects, outs));
        gain = Some(bootstrap_gain(&analysis, &obs, &specimens, s.bootstrap, seed));
    }
    Ok(Run {
        obs,
        keys,
        specimens,
        library,
        analysis,
        baseline,
        extended,
        extended_predictive,
        gain,
        resolution_deg: s.resolution_deg,
        settings: s.clone(),
    })
}

/// The mean held-out gain per observation (baseline − best) and its 95 % percentile
/// bootstrap interval, resampling specimens with replacement.
pub fn bootstrap_gain(
    a: &Analysis,
    obs: &[Observation],
    specimens: &[String],
    resamples: usize,
    seed: u64,
) -> (f64, f64, f64) {
    use rand::RngExt;
    let per: Vec<(f64, usize)> = specimens
        .iter()
        .map(|s| {
            let idx: Vec<usize> = (0..obs.len()).filter(|&j| &obs[j].specimen == s).collect();
            (idx.iter().map(|&j| a.baseline_scores[j] - a.best_scores[j]).sum::<f64>(), idx.len())
        })
        .collect();
    let total: f64 = per.iter().map(|p| p.0).sum();
    let count: usize = per.iter().map(|p| p.1).sum();
    let mut rng = crate::rng::rng_for(seed, u64::MAX >> 8, crate::rng::Purpose::Bootstrap);
    let mut means: Vec<f64> = (0..resamples)
        .map(|_| {
            let (mut t, mut c) = (0.0, 0usize);
            for _ in 0..per.len() {
                let p = per[rng.random_range(0..per.len())];
                t += p.0;
                c += p.1;
            }
            t / c.max(1) as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    (total / count.max(1) as f64, crate::stats::quantile(&means, 0.025), crate::stats::quantile(&means, 0.975))
}
