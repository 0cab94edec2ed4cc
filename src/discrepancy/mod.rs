//! Model discrepancy: what the simulation gets wrong against measured data, which physical
//! effect causes it, and what the extended model gains on data it did not fit.
//!
//! ```text
//!  measured data ─▶ observations ─┐
//!  study ─▶ baseline ensemble ─────┼─▶ diagnosis (standardized residuals by group,
//!          (common random numbers) │    observable, tilt; spread against specimens)
//!  effect library ─▶ ensembles on ─┴─▶ surrogates (with their own error) ─▶ fits,
//!   (crate::effects)  parameter grids     held-out error, AICc ─▶ margins from null data
//!                                         on independent layouts ─▶ the two best re-run
//!                                         in full and re-scored ─▶ posterior predictive
//!                                         check ─▶ verdict, extended model, gain
//! ```
//!
//! The reference formulation is Kennedy & O'Hagan (2001, J. R. Stat. Soc. B 63:425), a
//! statistical discrepancy term added after calibration; Brynjarsdóttir & O'Hagan (2014,
//! Inverse Problems 30:114007) show that such a term, without physics, confounds the
//! parameters. drystone instead searches a library of named physical mechanisms
//! ([`crate::effects`]), each entering the model where it acts, beside a `scatter`
//! hypothesis (specimens scatter more than the model's layouts: workmanship), and names
//! one only when it predicts held-out specimens better than the baseline by a margin
//! calibrated on data the baseline explains, after a full run at its fitted parameters,
//! and when the extended model then fits the data as well as it fits its own simulated
//! data ([`analysis`]).
//!
//! Every forward run uses the study's own tilting-table settings (step and resolution), so
//! the predictive means are the study's `run` means. Units: observations and predictions
//! are in the measured data's units (degrees for collapse angles, cm for displacements);
//! effect parameters in the units of their [`crate::effects::ParamDef`]s.

pub(crate) mod analysis;
pub mod fit;
pub mod observations;
pub mod predictive;
pub mod report;
pub mod simulate;
pub mod synthesize;

/// The effects, as the discrepancy analysis uses them (see [`crate::effects`]).
pub use crate::effects;

use analysis::{calibrate_margins, predictive_check, rank, sort, Library, NullSource};
pub use analysis::{Analysis, Margins, PredictiveCheck, Ranked, TieCheck, Verdict};
use effects::{Effect, EffectDef};
use fit::{specimen_weights, to_value, to_x, Candidate, Data, Surface};
use observations::{Observable, Observation};
use predictive::{Predictive, Reading, Simulated};
use serde::{Deserialize, Serialize};
use simulate::{run_models, Outcome, Setup};
use std::sync::Arc;

/// Settings of a discrepancy analysis. Defaults in brackets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Realizations per group at every node of the surrogates' grids \[2\]: the models
    /// share their layouts (common random numbers), so the nodes differ by the effect and
    /// not by the sampling; the predictive carries the few realizations (Student-t), and
    /// the two best candidates are re-run and scored with `extension_realizations`.
    pub realizations: u64,
    /// Realizations per group of the baseline's and of a confirmed candidate's full run
    /// \[9\] (the first `realizations` of the baseline are the grids' neutral node).
    pub extension_realizations: u64,
    /// Realizations per group on independent layouts (a master seed of their own) for the
    /// null data and the posterior predictive check \[9\].
    pub null_realizations: u64,
    /// Grid intervals per parameter axis of a one-parameter effect \[4\]: nodes at
    /// `x = 0, 1/G, …, 1`, the node nearest the neutral value taken from the baseline.
    pub grid_points: usize,
    /// Nodes per axis of a two-parameter effect \[3\], corners included.
    pub grid_points_2d: usize,
    /// Null data sets of the margin calibration \[200\] (all set the margins; the
    /// false-alarm rate is measured by cross-fitting their two halves).
    pub null_replicates: usize,
    /// Data sets of the posterior predictive check \[200\].
    pub check_replicates: usize,
    /// Bootstrap resamples of the specimens for the gain's interval \[2000\].
    pub bootstrap: usize,
    /// The effects searched, by name \[every built-in and every effect file of the
    /// study\].
    pub effects: Vec<String>,
    /// Rank the specimen-scatter hypothesis beside the mechanisms \[true\].
    pub scatter: bool,
    /// Re-run the two best candidates as full ensembles at their fitted parameters and
    /// score them by those runs \[true\]; off, the surrogate's scores stand (for power
    /// studies; the report says so).
    pub confirm: bool,
    /// Measurement standard deviations.
    pub sigma: observations::MeasurementSigma,
    /// Reading resolutions of the measured values.
    pub reading: Reading,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            realizations: 2,
            extension_realizations: 9,
            null_realizations: 9,
            grid_points: 4,
            grid_points_2d: 3,
            null_replicates: 200,
            check_replicates: 200,
            bootstrap: 2000,
            effects: vec![],
            scatter: true,
            confirm: true,
            sigma: observations::MeasurementSigma::default(),
            reading: Reading::default(),
        }
    }
}

/// A fitted parameter of the named cause: `effect.param`, its value and its interval (in
/// the parameter's unit; see [`crate::effects::ParamDef`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FittedParameter {
    /// `effect.param`.
    pub name: String,
    /// The fitted value.
    pub value: f64,
    /// The interval (lower, upper).
    pub interval: (f64, f64),
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
    /// An observation outside the prepared design.
    #[error("specimen {specimen}: observable {observable} is not in the prepared design")]
    Design {
        /// The specimen.
        specimen: String,
        /// The observable.
        observable: String,
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
    /// The settings of `drystone discrepancy --thorough`: twice the realizations of the
    /// grids, of the full runs and of the independent layouts, and finer grids (at least 6
    /// intervals per axis, 4 nodes per axis of a two-parameter effect). About three times
    /// the cost.
    pub fn thorough(&mut self) {
        self.realizations *= 2;
        self.extension_realizations *= 2;
        self.null_realizations *= 2;
        self.grid_points = self.grid_points.max(6);
        self.grid_points_2d = self.grid_points_2d.max(4);
    }

    /// The most realizations any of its runs takes per group (grids, full runs, independent
    /// layouts): what a [`simulate::Setup`] for the analysis must allow.
    pub fn most_realizations(&self) -> u64 {
        self.realizations.max(self.extension_realizations).max(self.null_realizations)
    }

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
        if !(1..=10_000).contains(&self.null_realizations) {
            return bad("null_realizations", self.null_realizations.to_string(), "must be in [1, 10000]");
        }
        if !(20..=100_000).contains(&self.check_replicates) {
            return bad("check_replicates", self.check_replicates.to_string(), "must be in [20, 100000]");
        }
        if !(self.reading.misreading.is_finite() && (0.0..0.5).contains(&self.reading.misreading)) {
            return bad("reading.misreading", self.reading.misreading.to_string(), "must be in [0, 0.5)");
        }
        for (key, v) in
            [("reading.angle_deg", self.reading.angle_deg), ("reading.displacement_cm", self.reading.displacement_cm)]
        {
            if !(v.is_finite() && (0.0..=10.0).contains(&v)) {
                return bad(key, v.to_string(), "must be in [0, 10] (0: exact readings)");
            }
        }
        let mut seen = std::collections::BTreeSet::new();
        for e in &self.effects {
            if !seen.insert(e) {
                return bad("effects", e.clone(), "an effect is listed twice");
            }
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

/// The grid of one effect: node coordinates and their effects (`None` marks the node
/// taken from the baseline).
#[derive(Debug, Clone)]
struct Plan {
    def: Arc<EffectDef>,
    params: Vec<effects::ParamDef>,
    nodes: Vec<(Vec<f64>, Option<Effect>)>,
}

fn effect_at(
    def: &Arc<EffectDef>,
    params: &[effects::ParamDef],
    x: &[f64],
    course_m: f64,
) -> Result<Effect, DiscrepancyError> {
    let values = params.iter().zip(x).map(|(p, &xi)| to_value(p, xi)).collect();
    Ok(Effect::new(def.clone(), values, course_m)?)
}

fn plan(def: Arc<EffectDef>, s: &Settings, course_m: f64) -> Result<Plan, DiscrepancyError> {
    let params = def.params_for(course_m);
    let mut nodes = Vec::new();
    if params.len() == 1 {
        let xn = to_x(&params[0], params[0].neutral).clamp(0.0, 1.0);
        let g = s.grid_points;
        let half = 0.5 / g as f64;
        for k in 0..=g {
            let x = k as f64 / g as f64;
            if (x - xn).abs() >= half {
                nodes.push((vec![x], Some(effect_at(&def, &params, &[x], course_m)?)));
            }
        }
        nodes.push((vec![xn], None));
        nodes.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    } else {
        let g = s.grid_points_2d;
        let axis: Vec<f64> = (0..g).map(|k| k as f64 / (g - 1) as f64).collect();
        for &a in &axis {
            for &b in &axis {
                nodes.push((vec![a, b], Some(effect_at(&def, &params, &[a, b], course_m)?)));
            }
        }
    }
    Ok(Plan { def, params, nodes })
}

/// The effects a run searches: the settings' names, or every effect of `library`, less
/// the built-ins whose signature is the failure mechanism
/// ([`effects::MECHANISM_EFFECTS`]) when the data hold no mechanism observation
/// (`mechanism` false): an analysis of angles and displacements alone searches what it
/// searched before those effects existed. Named in the settings, they are searched
/// always.
///
/// # Errors
/// [`DiscrepancyError::Effect`] for an unknown name.
pub fn searched(
    s: &Settings,
    library: &effects::Library,
    mechanism: bool,
) -> Result<Vec<Arc<EffectDef>>, DiscrepancyError> {
    if s.effects.is_empty() {
        return Ok(library
            .all()
            .into_iter()
            .filter(|d| mechanism || !effects::MECHANISM_EFFECTS.contains(&d.name.as_str()))
            .collect());
    }
    Ok(s.effects.iter().map(|n| library.get(n)).collect::<Result<_, _>>()?)
}

/// Mean course height of the analysed walls, m (the effects' length ranges scale with it).
pub fn course_height(setup: &Setup) -> f64 {
    let v: Vec<f64> = setup.groups.iter().map(|g| g.course_m).collect();
    if v.is_empty() {
        effects::REFERENCE_COURSE_HEIGHT_M
    } else {
        crate::stats::mean(&v)
    }
}

/// Builds the surrogate library: the baseline (every realization of `baseline`, the full
/// run), every effect's grid (the first `realizations` layouts of each group, common random
/// numbers) re-centred on the full baseline at the effect's neutral point
/// ([`Surface::Corrected`]), and the scatter hypothesis. The baseline and every candidate
/// are thereby scored with the same number of realizations: a candidate does not gain on
/// the baseline by being estimated from more layouts.
pub fn build_library(
    setup: &Setup,
    keys: &Keys,
    baseline: &[Vec<Outcome>],
    s: &Settings,
    defs: &[Arc<EffectDef>],
) -> Result<Library, DiscrepancyError> {
    let course_m = course_height(setup);
    let plans: Vec<Plan> = defs.iter().map(|d| plan(d.clone(), s, course_m)).collect::<Result<_, _>>()?;
    let models: Vec<Vec<Effect>> =
        plans.iter().flat_map(|p| p.nodes.iter().filter_map(|(_, e)| e.clone().map(|e| vec![e]))).collect();
    let grid_setup = with_realizations(setup, s.realizations);
    let base_grid: Vec<Vec<Outcome>> = baseline
        .iter()
        .zip(&grid_setup.groups)
        .map(|(o, g)| o[..(g.realizations as usize).min(o.len())].to_vec())
        .collect();
    let outcomes = run_models(&grid_setup, &models, Some(&base_grid));
    let base_sims = keys.simulated(&base_grid);
    let full_sims = keys.simulated(baseline);
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
        let surface = if p.params.len() == 1 {
            Surface::axis(sims.iter().map(|(x, _)| x[0]).collect(), sims.into_iter().map(|(_, s)| s).collect())
        } else {
            let mut x1: Vec<f64> = sims.iter().map(|(x, _)| x[0]).collect();
            x1.dedup();
            let mut x2: Vec<f64> = sims.iter().map(|(x, _)| x[1]).collect();
            x2.sort_by(f64::total_cmp);
            x2.dedup();
            Surface::Grid { x1, x2, sims: sims.into_iter().map(|(_, s)| s).collect() }
        };
        let x0: Vec<f64> = p.params.iter().map(|q| to_x(q, q.neutral).clamp(0.0, 1.0)).collect();
        let surface = Surface::Corrected { inner: Box::new(surface), x0, full: full_sims.clone() };
        candidates.push(Candidate { effects: vec![p.def.clone()], params: p.params.clone(), surface });
    }
    if s.scatter {
        let angle = keys.keys.iter().map(|(_, o)| matches!(o, Observable::CollapseAngle)).collect();
        let mechanism = keys.keys.iter().map(|(_, o)| o.is_mechanism()).collect();
        candidates.push(Candidate::scatter(full_sims.clone(), angle, mechanism));
    }
    Ok(Library { baseline: full_sims, candidates })
}

/// The setup with every group's realizations capped at `n`.
fn with_realizations(setup: &Setup, n: u64) -> Setup {
    Setup {
        groups: setup
            .groups
            .iter()
            .map(|g| simulate::GroupSetup { realizations: g.realizations.min(n), ..g.clone() })
            .collect(),
        ..setup.clone()
    }
}

/// The master seed of the independent layouts (null data, predictive checks): derived from
/// the study's, never equal to it.
pub fn null_seed(seed: u64) -> u64 {
    let s = seed.rotate_left(29) ^ 0x6a09_e667_f3bc_c909;
    if s == seed {
        s ^ 1
    } else {
        s
    }
}

/// The effects of a candidate at its fitted coordinates.
fn effects_of(c: &Candidate, x: &[f64], course_m: f64) -> Result<Vec<Effect>, DiscrepancyError> {
    let mut out = Vec::new();
    let mut offset = 0;
    for def in &c.effects {
        let n = def.parameters.len();
        out.push(effect_at(def, &c.params[offset..offset + n], &x[offset..offset + n], course_m)?);
        offset += n;
    }
    Ok(out)
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
    /// ([`observations::measurement_sigma`]). The analysis uses the larger of it and the
    /// setting: data that scatter more than the model and the stated σ together are not
    /// evidence for a mechanism.
    pub sigma_estimate: [Option<(f64, usize)>; 2],
    /// The settings.
    pub settings: Settings,
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
fn design(
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

/// The key labels, `GROUP observable`.
pub fn key_labels(setup: &Setup, keys: &Keys) -> Vec<String> {
    keys.keys.iter().map(|(g, o)| format!("{} {}", setup.groups[*g].name, o.label())).collect()
}

/// The data-independent part of an analysis: the baseline's full run, the surrogate
/// library, and the baseline on independent layouts (the null pool), for the observable
/// keys of a design. Many data sets of the same design are analysed against one
/// [`Prepared`] ([`analyze`]).
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The setup.
    pub setup: Setup,
    /// The observable keys of the design.
    pub keys: Keys,
    /// The baseline's full run.
    pub baseline: Vec<Vec<Outcome>>,
    /// The surrogate library.
    pub library: Library,
    /// The baseline on independent layouts, `[group][realization]`.
    pub null_pool: Vec<Vec<Outcome>>,
    /// The setup of the independent layouts.
    pub null_setup: Setup,
    /// The settings.
    pub settings: Settings,
}

/// Checks the settings and the observations' tilts against the study's step.
fn check(setup: &Setup, obs: &[Observation], s: &Settings) -> Result<(), DiscrepancyError> {
    s.validate()?;
    for o in obs {
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
    Ok(())
}

/// Runs the forward models of a design whose observations are `template` (any data set of
/// it, or the union of several): the baseline, the library's grids and the null pool.
///
/// # Errors
/// [`DiscrepancyError`] for bad settings, an unknown effect or a baseline that fails
/// entirely.
pub fn prepare(
    setup: &Setup,
    template: &[Observation],
    s: &Settings,
    library: &effects::Library,
) -> Result<Prepared, DiscrepancyError> {
    check(setup, template, s)?;
    let defs = searched(s, library, template.iter().any(|o| o.observable.is_mechanism()))?;
    let keys = Keys::new(setup, template);
    let full = with_realizations(setup, s.extension_realizations);
    let baseline = run_models(&full, &[vec![]], None).remove(0);
    for (g, outs) in full.groups.iter().zip(&baseline) {
        if outs.iter().all(|o| o.error.is_some()) {
            let error = outs.first().and_then(|o| o.error.clone()).unwrap_or_default();
            return Err(DiscrepancyError::Baseline { group: g.name.clone(), error });
        }
    }
    let lib = build_library(setup, &keys, &baseline, s, &defs)?;
    let null_setup = Setup { seed: null_seed(setup.seed), ..with_realizations(setup, s.null_realizations) };
    let null_pool = run_models(&null_setup, &[vec![]], None).remove(0);
    Ok(Prepared { setup: setup.clone(), keys, baseline, library: lib, null_pool, null_setup, settings: s.clone() })
}

/// Runs the whole analysis of one data set: [`prepare`], then [`analyze`]. `seed` seeds the
/// null data and the bootstrap; `library` holds the effects by name.
///
/// ```no_run
/// use drystone::study::{discrepancy::{observations_of, setup_of}, Study};
///
/// // The paper's tilting-table tests against their measured collapse angles and
/// // displacements (about 8 minutes on 2 cores: `drystone discrepancy` does the same and
/// // writes the report).
/// let study = Study::from_file(std::path::Path::new("studies/tilting_table.toml"))?;
/// let s = study.discrepancy.clone();
/// let setup = setup_of(&study, s.most_realizations());
/// let obs = observations_of(&study, s.sigma)?;
/// let run = drystone::discrepancy::run(&setup, obs, &s, study.seed, &study.library)?;
/// let a = &run.analysis;
/// println!("{}: {:?}, tied with {:?}", a.verdict.name(), a.cause.as_ref().map(|c| &c.name), a.tie);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// A small analysis that runs in seconds: the test bed's two small walls, four collapse
/// angles read to 0.25° per group, one candidate effect and small ensembles (too small
/// for a verdict to mean much; the defaults are in [`Settings`]):
///
/// ```
/// use drystone::discrepancy::observations::{Observable, Observation};
/// use drystone::study::{discrepancy::setup_of, Study};
///
/// let file = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/discrepancy/study.toml");
/// let study = Study::from_file(std::path::Path::new(file))?;
/// let mut s = study.discrepancy.clone();
/// (s.realizations, s.extension_realizations, s.null_realizations) = (2, 3, 3);
/// (s.grid_points, s.null_replicates, s.check_replicates, s.bootstrap) = (2, 20, 20, 100);
/// s.effects = vec!["initial_lean".into()];
/// (s.scatter, s.confirm) = (false, false);
/// let reading = |group: &str, i: usize, deg: f64| Observation {
///     specimen: format!("{group}{i}"),
///     group: group.into(),
///     observable: Observable::CollapseAngle,
///     value: deg,
///     sigma: s.sigma.angle_deg,
/// };
/// let mut obs = Vec::new();
/// for (i, (free, held)) in [(26.0, 33.5), (25.75, 34.0), (26.25, 33.0), (25.5, 34.5)].into_iter().enumerate() {
///     obs.push(reading("FREE", i, free));
///     obs.push(reading("HELD", i, held));
/// }
/// let setup = setup_of(&study, s.most_realizations());
/// let run = drystone::discrepancy::run(&setup, obs, &s, study.seed, &study.library)?;
/// let a = &run.analysis;
/// assert!(["explained", "no_effect", "unexplained"].contains(&a.verdict.name()));
/// assert_eq!(run.baseline[0].len(), 3); // the baseline's full run: 3 realizations per group
/// assert!(a.baseline_heldout_error.is_finite());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`DiscrepancyError`] for bad settings, an unknown effect or a baseline that fails
/// entirely.
pub fn run(
    setup: &Setup,
    obs: Vec<Observation>,
    s: &Settings,
    seed: u64,
    library: &effects::Library,
) -> Result<Run, DiscrepancyError> {
    let prepared = prepare(setup, &obs, s, library)?;
    analyze(&prepared, obs, seed)
}

/// Analyses one data set against prepared forward runs: the margins from null data on
/// independent layouts, the ranking, the full runs of the two best candidates, the verdict
/// with its predictive check, the extended model and the gain.
///
/// # Errors
/// [`DiscrepancyError`] for an observation outside the prepared design or a failed
/// effect.
pub fn analyze(prep: &Prepared, mut obs: Vec<Observation>, seed: u64) -> Result<Run, DiscrepancyError> {
    let (setup, s, lib) = (&prep.setup, &prep.settings, &prep.library);
    check(setup, &obs, s)?;
    let mut keys = prep.keys.clone();
    keys.of = obs
        .iter()
        .map(|o| {
            let g = setup.groups.iter().position(|g| g.name == o.group).unwrap_or(0);
            keys.keys.iter().position(|(kg, ko)| *kg == g && ko.same(&o.observable)).ok_or_else(|| {
                DiscrepancyError::Design { specimen: o.specimen.clone(), observable: o.observable.label() }
            })
        })
        .collect::<Result<_, _>>()?;
    // The measurement σ: the stated one, or the spread the data show beyond the model's,
    // if larger (again on every synthetic data set).
    // The baseline's full run, as the library scores it.
    let full_base = &lib.baseline;
    let model_sd: Vec<f64> = full_base.iter().map(|x| x.sd).collect();
    let stated: Vec<f64> = obs.iter().map(|o| o.sigma).collect();
    let sigma_rule = analysis::SigmaRule { stated: &stated, model_sd: &model_sd, reading: s.reading };
    let sigma_estimate = sigma_rule.apply(&mut obs, &keys.of);
    let labels = key_labels(setup, &keys);
    let specimens = observations::specimens(&obs);
    let course_m = course_height(setup);
    let full = with_realizations(setup, s.extension_realizations);
    let (baseline, null_pool, null_setup) = (&prep.baseline, &prep.null_pool, &prep.null_setup);
    let y: Vec<f64> = obs.iter().map(|o| o.value).collect();
    let weight = specimen_weights(&obs);
    let bracket_deg = setup.tilt.resolution_deg;
    let data = Data { obs: &obs, y: &y, key: &keys.of, weight: &weight, reading: s.reading, bracket_deg };
    let pool_sims = keys.simulated(null_pool);
    let source =
        NullSource { pool: null_pool, keys: &keys.keys, sims: &pool_sims, centre: full_base, sigma: sigma_rule };
    let margins = calibrate_margins(lib, data, &specimens, s.null_replicates, seed, source);

    let n = specimens.len().max(1) as f64;
    let base_scores: Vec<f64> = (0..obs.len()).map(|j| data.score(&lib.baseline, j)).collect();
    let base_per = fit::per_specimen(&base_scores, &obs, &specimens);
    let base_he = base_per.iter().sum::<f64>() / n;
    let base_ic = fit::aicc(base_scores.iter().sum(), 0, specimens.len());
    let mut pool = lib.candidates.clone();
    let mut ranked = rank(&pool, data, &specimens, &base_per);
    // The statistic the margins are calibrated on: the best gain of the library's
    // candidates on their surrogates, before pairs and confirmation runs.
    let screen_gain = ranked.first().map_or(0.0, |r| base_he - r.heldout_error);
    // Pairs, when the best single effect leaves a significant misfit.
    if let Some(best) = ranked.first() {
        let best_fit = best.scores.iter().sum::<f64>() / n;
        if best_fit > margins.misfit && base_he - best.heldout_error > margins.baseline {
            let offset = pool.len();
            let extra = analysis::pairs(lib, &ranked);
            let mut more = rank(&extra, data, &specimens, &base_per);
            for r in &mut more {
                r.index += offset;
            }
            pool.extend(extra);
            let (threshold, ic) = (best.heldout_error - margins.baseline, best.information_criterion);
            ranked.extend(more.into_iter().filter(|r| r.heldout_error < threshold && r.information_criterion < ic));
            sort(&mut ranked);
        }
    }
    // Full runs of the best candidates at their fitted parameters, re-scored.
    // (candidate, coordinates of the run, its effects, its outcomes)
    let mut runs: Vec<(usize, Vec<f64>, Vec<Effect>, Vec<Vec<Outcome>>)> = Vec::new();
    if s.confirm {
        for _round in 0..3 {
            let todo: Vec<usize> = ranked
                .iter()
                .take(2)
                .filter(|r| !r.confirmed && !pool[r.index].is_scatter())
                .map(|r| r.index)
                .collect();
            if todo.is_empty() {
                break;
            }
            for idx in todo {
                let pos = ranked.iter().position(|r| r.index == idx).unwrap_or(0);
                let x = ranked[pos].x.clone();
                let effects = effects_of(&pool[idx], &x, course_m)?;
                let outs = run_models(&full, std::slice::from_ref(&effects), Some(baseline)).remove(0);
                let corrected = Candidate {
                    surface: Surface::Corrected {
                        inner: Box::new(pool[idx].surface.clone()),
                        x0: x.clone(),
                        full: keys.simulated(&outs),
                    },
                    ..pool[idx].clone()
                };
                let mut r = analysis::score(&corrected, data, &specimens, idx, &base_per);
                r.confirmed = true;
                pool[idx] = corrected;
                ranked[pos] = r;
                runs.push((idx, x, effects, outs));
            }
            sort(&mut ranked);
        }
    }
    let candidates: Vec<Ranked> = ranked.clone();
    let eligible = |r: &&Ranked| r.confirmed || pool[r.index].is_scatter() || !s.confirm;
    let best = candidates.iter().find(eligible).cloned();
    // A cause is named when the calibrated statistic clears its margin and the confirmed
    // winner still does: re-scoring the best few by full runs and keeping the best is a
    // selection the null calibration does not repeat, so it may veto an alarm, never
    // raise one.
    let named = best.clone().filter(|b| {
        screen_gain > margins.baseline
            && base_he - b.heldout_error > margins.baseline
            && b.information_criterion < base_ic
    });

    let mut extended = None;
    let mut extended_predictive: Vec<Predictive> = (0..obs.len()).map(|j| data.predictive(full_base, j)).collect();
    let mut gain = None;
    let check;
    let mut tie_checks: Vec<analysis::TieCheck> = Vec::new();
    let (verdict, cause, tie) = match named {
        Some(b) => {
            let c = &pool[b.index];
            let (sims, check_pool): (Vec<Simulated>, Vec<Vec<Outcome>>) = if c.is_scatter() || !s.confirm {
                // No full run: the surrogate's values, checked against draws from its own
                // predictive.
                (c.surface.at(&b.x), vec![vec![]; setup.groups.len()])
            } else {
                // The extended model is run at the fitted parameters: a confirmation run
                // at other coordinates (the re-scored fit moved) is not reused.
                let same = |x: &[f64]| x.len() == b.x.len() && x.iter().zip(&b.x).all(|(p, q)| (p - q).abs() < 1e-9);
                let (effects, outs) = match runs.iter().find(|r| r.0 == b.index && same(&r.1)) {
                    Some((_, _, e, o)) => (e.clone(), o.clone()),
                    None => {
                        let e = effects_of(c, &b.x, course_m)?;
                        let o = run_models(&full, std::slice::from_ref(&e), Some(baseline)).remove(0);
                        (e, o)
                    }
                };
                let sims = keys.simulated(&outs);
                let ppc = run_models(null_setup, std::slice::from_ref(&effects), Some(null_pool)).remove(0);
                extended = Some((effects, outs));
                (sims, ppc)
            };
            extended_predictive = (0..obs.len()).map(|j| data.predictive(&sims, j)).collect();
            let check_sims = keys.simulated(&check_pool);
            let src =
                NullSource { pool: &check_pool, keys: &keys.keys, sims: &check_sims, centre: &sims, sigma: sigma_rule };
            let ppc = predictive_check(data, &sims, &specimens, src, s.check_replicates, seed, &labels);
            let passes = ppc.passes();
            check = Some(ppc);
            gain = Some(bootstrap_gain(&base_per, &fit::per_specimen(&b.scores, &obs, &specimens), s.bootstrap, seed));
            // The tie: the challengers that the design (data simulated from the cause's own
            // independent realizations) or the data (the held-out difference in standard
            // errors) cannot separate from the cause.
            let challengers: Vec<&Ranked> =
                candidates.iter().filter(|r| r.index != b.index).take(analysis::TIE_CHALLENGERS).collect();
            let rates = analysis::reversal_rates(
                &pool[b.index],
                &challengers.iter().map(|r| &pool[r.index]).collect::<Vec<_>>(),
                data,
                &specimens,
                src,
                s.check_replicates,
                seed,
            );
            let mut tie = vec![b.name.clone()];
            for (r, &rate) in challengers.iter().zip(&rates) {
                let t = analysis::TieCheck::new(&b, r, rate, &obs, &specimens);
                if t.tied {
                    tie.push(r.name.clone());
                }
                tie_checks.push(t);
            }
            (if passes { Verdict::Explained } else { Verdict::Unexplained }, Some(b), tie)
        }
        None => {
            let src = NullSource {
                pool: null_pool,
                keys: &keys.keys,
                sims: &pool_sims,
                centre: full_base,
                sigma: sigma_rule,
            };
            check = Some(predictive_check(data, full_base, &specimens, src, s.check_replicates, seed, &labels));
            if base_he > margins.misfit {
                (Verdict::Unexplained, None, vec![])
            } else {
                (Verdict::NoEffect, None, vec![])
            }
        }
    };
    let mut key_sigma = vec![0.0f64; keys.keys.len()];
    for (o, &k) in obs.iter().zip(&keys.of) {
        key_sigma[k] = key_sigma[k].max(o.sigma);
    }
    let design = (tie.len() > 1)
        .then(|| {
            let a = candidates.iter().find(|r| r.name == tie[0])?;
            let b = candidates.iter().find(|r| r.name == tie[1])?;
            design(
                &pool[a.index].surface.at(&a.x),
                &pool[b.index].surface.at(&b.x),
                &key_sigma,
                &labels,
                (a.name.clone(), b.name.clone()),
            )
        })
        .flatten();
    let cause_interval = match &cause {
        Some(b) => {
            let all: Vec<usize> = (0..obs.len()).collect();
            let c = &pool[b.index];
            let iv = fit::profile_intervals(&c.surface, data, &all, &b.x);
            b.parameters
                .iter()
                .zip(c.params.iter().zip(iv))
                .map(|((name, value), (p, (lo, hi)))| FittedParameter {
                    name: name.clone(),
                    value: *value,
                    interval: (to_value(p, lo), to_value(p, hi)),
                })
                .collect()
        }
        None => vec![],
    };
    let analysis = Analysis {
        verdict,
        cause,
        tie,
        tie_checks,
        candidates,
        baseline_heldout_error: base_he,
        screen_gain,
        baseline_information_criterion: base_ic,
        baseline_predictive: (0..obs.len()).map(|j| data.predictive(&lib.baseline, j)).collect(),
        baseline_scores: base_scores,
        margins,
        check,
        pool,
    };
    Ok(Run {
        obs,
        keys,
        specimens,
        library: lib.clone(),
        analysis,
        baseline: baseline.clone(),
        extended,
        extended_predictive,
        gain,
        design,
        bracket_deg,
        cause_interval,
        sigma_estimate,
        settings: s.clone(),
    })
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
