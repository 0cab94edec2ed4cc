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
//! data ([`analyze`], in the stages of `stages.rs`).
//!
//! Every forward run uses the study's own loading protocol and its settings (the tilting
//! table's step and resolution, or the lateral load), so the predictive means are the
//! study's `run` means ([`Setup`]). Units: observations and predictions
//! are in the measured data's units (degrees for collapse angles, cm for displacements);
//! effect parameters in the units of their [`crate::effects::ParamDef`]s.

mod analysis;
mod candidate;
mod compare;
pub mod design;
mod findings;
mod fit;
mod held;
mod identify;
mod inplane;
mod null;
mod observations;
mod outcome;
mod predictive;
mod prepare;
mod progress;
mod rank;
mod refute;
mod report;
mod settings;
mod simulate;
mod stages;
mod store;
mod synthesize;
mod systematic;
mod weights;

/// The effects, as the discrepancy analysis uses them (see [`crate::effects`]).
pub use crate::effects;

pub use analysis::{
    Analysis, MeasuresCheck, Models, PredictiveCheck, Ranked, Reversal, TieCheck, Verdict, TIE_CHALLENGERS,
};
pub use candidate::Candidate;
pub use compare::{difference_se, per_specimen};
pub use findings::{bootstrap_gain, Design, FittedParameter, HeldRefit, Run};
pub use fit::Surface;
pub use held::{HeldReading, HeldReport};
pub use identify::{identifiability, Identifiability, KeySeparation, PairSeparation, INDISTINGUISHABLE};
pub use inplane::{InPlaneQuantity, IN_PLANE_MODES};
pub use null::Margins;
pub use observations::{
    measurement_sigma, mechanism_observations, observations, specimens, CategorySet, Family, Measure, MeasurementSigma,
    Observable, Observation, ObservationError, Scale, Share, MIN_SIGMA_DOF,
};
pub use predictive::{Heights, Predictive, Reading, Simulated, HEIGHT_BINS};
pub use prepare::{
    build_library, course_height, inert_effects, key_labels, null_seed, prepare, prepare_after, prepare_with, searched,
    GridRuns, InertEffect, Keys, Prepared,
};
pub use progress::{quiet, Progress};
pub use refute::{in_fit as refuted_in_fit, reading_of, Refutation, REFUTE_NATS, REFUTE_Z};
pub use report::{diagnosis, report_json, report_markdown, write_report, DiagnosisRow, WriteError};
pub use settings::Settings;
pub use simulate::{forward_runs, run_models, run_one, GroupSetup, Outcome, Outcomes, Setup, StageRuns};
pub use stages::{analyze, analyze_held, analyze_with};
pub use store::{RunStore, StoreError};
pub use synthesize::{
    master_seed as synthetic_master_seed, observables_of as synthetic_observables, synthesize,
    write as write_synthetic, Request as SynthesisRequest,
};
pub use systematic::{systematic_misfit, SystematicMisfit, SYSTEMATIC_Z};
pub use weights::{weights, ModelWeight, Weights, SHARED};

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
        "specimen {specimen}: displacement at {tilt_deg} deg is not a multiple of the study's tilt.step_deg = {step_deg}"
    )]
    Tilt {
        /// The specimen.
        specimen: String,
        /// Its tilt, degrees.
        tilt_deg: f64,
        /// The step, degrees.
        step_deg: f64,
    },
    /// A measured displacement of a lateral-load analysis at a tilt other than 0.
    #[error(
        "specimen {specimen}: displacement at {tilt_deg} deg; the lateral load gives the displacements under the load, at tilt 0 only"
    )]
    LateralTilt {
        /// The specimen.
        specimen: String,
        /// Its tilt, degrees.
        tilt_deg: f64,
    },
    /// A reading the fit does not hold ([`HeldReading`]) could not be made.
    #[error("the {reading}: {message}")]
    Held {
        /// The reading (`loops`).
        reading: String,
        /// What went wrong, naming the file or run.
        message: String,
    },
    /// An observable the setup's protocol does not give (a collapse angle or a mechanism
    /// under the lateral load).
    #[error("specimen {specimen}: observable {observable} is not given by protocol {protocol}")]
    Observable {
        /// The specimen.
        specimen: String,
        /// The observable.
        observable: String,
        /// The protocol's name.
        protocol: &'static str,
    },
    /// An observation outside the prepared design.
    #[error("specimen {specimen}: observable {observable} is not in the prepared design")]
    Design {
        /// The specimen.
        specimen: String,
        /// The observable.
        observable: String,
    },
    /// The setup's loading protocol has no observables the analysis can compare.
    #[error("protocol {protocol}: {reason}")]
    Protocol {
        /// The protocol's name.
        protocol: &'static str,
        /// Why it cannot be analysed.
        reason: &'static str,
    },
    /// A candidate effect named in `[discrepancy] effects` or `also_effects` that the
    /// setup's protocol does not read (the in-plane test and an out-of-plane effect,
    /// [`effects::EffectDef::not_read_in_plane`]).
    #[error("candidate effect {effect} (named in [discrepancy]): protocol {protocol} does not read it ({reason})")]
    NotRead {
        /// The effect.
        effect: String,
        /// The protocol's name.
        protocol: &'static str,
        /// Why it does not read it.
        reason: &'static str,
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
/// use drystone::discrepancy::{Observable, Observation};
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
    run_with(setup, obs, s, seed, library, &quiet)
}

/// [`run`], reporting each stage, model and candidate to `progress` (see [`Progress`]).
///
/// # Errors
/// As [`run`].
pub fn run_with(
    setup: &Setup,
    obs: Vec<Observation>,
    s: &Settings,
    seed: u64,
    library: &effects::Library,
    progress: Progress<'_>,
) -> Result<Run, DiscrepancyError> {
    let prepared = prepare_with(setup, &obs, s, library, progress)?;
    analyze_with(&prepared, obs, seed, progress)
}

/// [`run_with`] with a reading the fit does not hold ([`HeldReading`]: the in-plane test's
/// cyclic loops), asked of each candidate before it is confirmed or named; a candidate it
/// refutes is not named ([`Refutation`]).
///
/// # Errors
/// As [`run`], and the held reading's own ([`DiscrepancyError::Held`]).
pub fn run_held(
    setup: &Setup,
    obs: Vec<Observation>,
    s: &Settings,
    seed: u64,
    library: &effects::Library,
    held: Option<&dyn HeldReading>,
    progress: Progress<'_>,
) -> Result<Run, DiscrepancyError> {
    let prepared = prepare_with(setup, &obs, s, library, progress)?;
    analyze_held(&prepared, obs, seed, held, progress)
}
