//! [`analyze`] in named stages, each a function with a typed result:
//!
//! ```text
//!  observations ─▶ design_keys ─▶ apply_sigma_rule (Sigmas) ─▶ calibrate_margins (Margins)
//!    ─▶ screen (Screening) ─▶ add_pairs ─▶ confirm (Confirmation runs) ─▶ name_cause
//!    ─▶ examine_cause: extended_model (ExtendedModel), predictive check, gain,
//!       tie_checks (Tie) → Findings ─▶ verdict ─▶ separating_design, fitted_parameters,
//!    weigh (Weights, Identifiability) ─▶ Run
//! ```
//!
//! The stages are those of the method ([`super::analysis`], [`super::null`]): the
//! measurement σ rule, the margins from null data on independent layouts, the screening of
//! the library's candidates on their surrogates, the pairs when the best single effect
//! leaves a significant misfit, the full runs of the two best candidates at their fitted
//! parameters, the cause named when it clears its margins, the extended model with its
//! posterior predictive check, the tie checks and the verdict; beside them, the models'
//! weights and what separates the leading ones.

use super::analysis::{pairs, predictive_check, rank, reversal_rates, sort, Analysis, Models, Ranked};
use super::analysis::{PredictiveCheck, Reversal, TieCheck, Verdict, TIE_CHALLENGERS};
use super::candidate::Candidate;
use super::compare::{self, specimen_weights};
use super::effects::Effect;
use super::findings::{bootstrap_gain, design, FittedParameter, Run};
use super::fit::{self, to_value, Data};
use super::held::HeldReading;
use super::null::{calibrate_margins, Margins, NullSource, SigmaRule};
use super::observations::{self, Observation};
use super::predictive::{Predictive, Reading, Simulated};
use super::prepare::{check, course_height, effects_of, key_labels, with_realizations, Keys, Prepared};
use super::progress::{quiet, Progress};
use super::simulate::{forward_runs, run_models, Outcome, Setup, StageRuns};
use super::DiscrepancyError;

/// Analyses one data set against prepared forward runs: the margins from null data on
/// independent layouts, the ranking, the full runs of the two best candidates, the verdict
/// with its predictive check, the extended model and the gain.
///
/// # Errors
/// [`DiscrepancyError`] for an observation outside the prepared design or a failed
/// effect.
pub fn analyze(prep: &Prepared, obs: Vec<Observation>, seed: u64) -> Result<Run, DiscrepancyError> {
    analyze_with(prep, obs, seed, &quiet)
}

/// [`analyze`], reporting each stage, model and candidate to `progress`.
///
/// # Errors
/// As [`analyze`].
pub fn analyze_with(
    prep: &Prepared,
    obs: Vec<Observation>,
    seed: u64,
    progress: Progress<'_>,
) -> Result<Run, DiscrepancyError> {
    analyze_held(prep, obs, seed, None, progress)
}

/// [`analyze_with`] with a reading the fit does not hold (`held`, [`HeldReading`]), asked
/// of each candidate that may be named before it is confirmed or named ([`Gate`]).
///
/// # Errors
/// As [`analyze`], and the held reading's ([`DiscrepancyError::Held`]).
pub fn analyze_held(
    prep: &Prepared,
    mut obs: Vec<Observation>,
    seed: u64,
    held: Option<&dyn HeldReading>,
    progress: Progress<'_>,
) -> Result<Run, DiscrepancyError> {
    let (setup, s, lib) = (&prep.setup, &prep.settings, &prep.library);
    check(setup, &obs, s)?;
    let keys = design_keys(prep, &obs)?;
    let sigmas = apply_sigma_rule(&mut obs, &keys.of, &lib.baseline, s.reading);
    let sigma_rule = sigmas.rule(s.reading);
    let labels = key_labels(setup, &keys);
    let specimens = observations::specimens(&obs);
    let full = with_realizations(setup, s.extension_realizations);
    let y: Vec<f64> = obs.iter().map(|o| o.value).collect();
    let weight = specimen_weights(&obs);
    let bracket_deg = setup.bracket_deg();
    let data = Data { obs: &obs, y: &y, key: &keys.of, weight: &weight, reading: s.reading, bracket_deg };
    let pool_sims = keys.simulated(&prep.null_pool);
    let null_source = NullSource {
        pool: &prep.null_pool,
        keys: &keys.keys,
        sims: &pool_sims,
        centre: &lib.baseline,
        sigma: sigma_rule,
    };
    let (margins, screening, mut pool, mut ranked) =
        screen_and_pair(lib, data, &specimens, seed, null_source, s, progress);
    let ctx = Ctx {
        data,
        specimens: &specimens,
        keys: &keys,
        labels: &labels,
        full: &full,
        course_m: course_height(setup),
        sigma: sigma_rule,
        seed,
        prep,
    };
    let gate = Gate::new(&screening, &margins, held, ctx.course_m);
    let runs =
        if s.confirm { confirm(&ctx, &screening.base_per, &mut pool, &mut ranked, &gate, progress)? } else { vec![] };
    let candidates: Vec<Ranked> = ranked;
    // A misfit of one sign in every group is a bias: a spread alone cannot explain it.
    let systematic = super::systematic::systematic_misfit(data, &lib.baseline);
    let eligible = |r: &Ranked| {
        if pool[r.index].is_scatter() {
            systematic.is_none()
        } else {
            r.confirmed || !s.confirm
        }
    };
    let refuted = |r: &Ranked| gate.refuted(r, &pool[r.index], data, progress).map(|f| f.is_some());
    let named = name_cause(&candidates, eligible, &screening, margins.baseline, refuted)?;
    let found = findings(
        &ctx,
        named.as_ref(),
        (&candidates, &pool),
        &runs,
        &screening.base_per,
        null_source,
        &refuted,
        progress,
    )?;
    let stage_runs = stage_runs(prep, &full, &runs, found.runs);
    let (passes, tie) = (found.passes, found.tie);
    let verdict = verdict(named.is_some(), passes, screening.base_misfit, margins.misfit);
    progress(&format!("verdict: {}", verdict.name()));
    let design = separating_design(&tie.members, &candidates, &pool, &obs, &keys, &labels);
    let cause_interval = named.as_ref().map_or(vec![], |b| fitted_parameters(b, &pool[b.index], data));
    let (weights, identifiability) =
        weigh(data, &specimens, &screening.base_scores, &candidates, &pool, &lib.baseline, &labels, s.bootstrap, seed);
    let refuted = gate.found.into_inner();
    let analysis = Analysis {
        verdict,
        cause: named,
        tie: tie.members,
        tie_checks: tie.checks,
        candidates,
        baseline_heldout_error: screening.base_he,
        screen_gain: screening.screen_gain,
        baseline_information_criterion: screening.base_ic,
        baseline_predictive: (0..obs.len()).map(|j| data.predictive(&lib.baseline, j)).collect(),
        baseline_scores: screening.base_scores,
        margins,
        check: Some(found.check),
        weights,
        identifiability,
        forward_runs: stage_runs,
        pool,
        systematic,
        refuted,
    };
    Ok(Run {
        obs,
        keys,
        specimens,
        library: lib.clone(),
        analysis,
        baseline: prep.baseline.clone(),
        grids: prep.grids.clone(),
        extended: found.extended,
        extended_predictive: found.extended_predictive,
        gain: found.gain,
        design,
        bracket_deg,
        cause_interval,
        sigma_estimate: sigmas.estimate,
        settings: s.clone(),
        inert: prep.inert.clone(),
        followup: None,
    })
}

/// The margins from null data ([`calibrate_margins`]), the screening of the library's
/// candidates on their surrogates ([`screen`]) and the pairs it admits ([`add_pairs`]):
/// the margins, the screening, and the pool of candidates with their ranking.
fn screen_and_pair(
    lib: &Models,
    data: Data<'_>,
    specimens: &[String],
    seed: u64,
    null_source: NullSource<'_>,
    s: &super::Settings,
    progress: Progress<'_>,
) -> (Margins, Screening, Vec<Candidate>, Vec<Ranked>) {
    progress(&format!("margins: {} null data sets on independent layouts", s.null_replicates));
    let margins = calibrate_margins(lib, data, specimens, s.null_replicates, seed, null_source);
    progress(&format!("screening: {} candidates on their surrogates", lib.candidates.len()));
    let screening = screen(lib, data, specimens);
    let mut pool = lib.candidates.clone();
    let mut ranked = screening.ranked.clone();
    let added = add_pairs(lib, data, specimens, &screening, &margins, &mut pool, &mut ranked);
    if added > 0 {
        progress(&format!("ranking: {added} pairs of effects added"));
    }
    (margins, screening, pool, ranked)
}

/// The forward runs by stage: the preparation's, the confirmation runs of `runs` on the
/// setup `full`, and the extended model's `extended`.
fn stage_runs(prep: &Prepared, full: &Setup, runs: &[Confirmation], extended: usize) -> Vec<StageRuns> {
    let mut stage_runs = prep.forward_runs.clone();
    let confirmation: usize = runs.iter().map(|r| forward_runs(full, std::slice::from_ref(&r.effects), true)).sum();
    stage_runs.push(StageRuns::new("confirmation", confirmation));
    stage_runs.push(StageRuns::new("extended model", extended));
    stage_runs
}

/// What the later stages share: the data, the specimens, the keys and their labels, the
/// setup of the full runs, the walls' mean course height, the σ rule, the seed of the null
/// data and the bootstrap, and the preparation.
struct Ctx<'a> {
    data: Data<'a>,
    specimens: &'a [String],
    keys: &'a Keys,
    labels: &'a [String],
    full: &'a Setup,
    course_m: f64,
    sigma: SigmaRule<'a>,
    seed: u64,
    prep: &'a Prepared,
}

/// What the analysis found after naming a cause, or not: the posterior predictive check
/// (of the extended model, else of the baseline) and whether it passes, the extended
/// model's run and predictive of every observation (the baseline's without a cause), the
/// gain with its bootstrap interval and the tie.
struct Findings {
    check: PredictiveCheck,
    passes: bool,
    extended: Option<(Vec<Effect>, Vec<Vec<Outcome>>)>,
    extended_predictive: Vec<Predictive>,
    gain: Option<(f64, f64, f64)>,
    tie: Tie,
    /// Forward runs of the extended model (its full run unless a confirmation run is
    /// reused, and its realizations on the independent layouts).
    runs: usize,
}

/// What the analysis finds of the named cause `named` (its extended model, check, gain and
/// tie, [`examine_cause`], the tie's members a reading refutes left out: that reading tells
/// them from the cause), or, with none named, the baseline's predictive check against
/// `null_source`. `ranking`: the ranked candidates and the pool they index.
#[allow(clippy::too_many_arguments)]
fn findings(
    ctx: &Ctx<'_>,
    named: Option<&Ranked>,
    (candidates, pool): (&[Ranked], &[Candidate]),
    runs: &[Confirmation],
    base_per: &[f64],
    null_source: NullSource<'_>,
    refuted: &dyn Fn(&Ranked) -> Result<bool, DiscrepancyError>,
    progress: Progress<'_>,
) -> Result<Findings, DiscrepancyError> {
    let (data, s, baseline) = (ctx.data, &ctx.prep.settings, &ctx.prep.library.baseline);
    let Some(b) = named else {
        return Ok(Findings {
            check: predictive_check(
                data,
                baseline,
                ctx.specimens,
                null_source,
                s.check_replicates,
                ctx.seed,
                ctx.labels,
            ),
            passes: false,
            extended: None,
            extended_predictive: (0..data.obs.len()).map(|j| data.predictive(baseline, j)).collect(),
            gain: None,
            tie: Tie::default(),
            runs: 0,
        });
    };
    let mut f = examine_cause(ctx, b, candidates, pool, runs, base_per, progress)?;
    let mut members = vec![];
    for m in std::mem::take(&mut f.tie.members) {
        let out = match candidates.iter().find(|r| r.name == m && m != b.name) {
            Some(r) => refuted(r)?,
            None => false,
        };
        if !out {
            members.push(m);
        }
    }
    f.tie.members = members;
    Ok(f)
}

/// Stages 7 and 8 for a named cause `b`: its extended model ([`extended_model`]) checked
/// on data drawn from its own independent realizations, the gain in held-out error per
/// specimen on the baseline (`base_per`) with its bootstrap interval, and the tie
/// ([`tie_checks`]).
///
/// # Errors
/// [`DiscrepancyError::Effect`] for an effect that cannot take its fitted values.
fn examine_cause(
    ctx: &Ctx<'_>,
    b: &Ranked,
    candidates: &[Ranked],
    pool: &[Candidate],
    runs: &[Confirmation],
    base_per: &[f64],
    progress: Progress<'_>,
) -> Result<Findings, DiscrepancyError> {
    let (data, s, seed) = (ctx.data, &ctx.prep.settings, ctx.seed);
    progress(&format!("extended model: {} ({} check data sets)", b.name, s.check_replicates));
    let model = extended_model(ctx, b, &pool[b.index], runs)?;
    let extended_predictive = (0..data.obs.len()).map(|j| data.predictive(&model.sims, j)).collect();
    let check_sims = ctx.keys.simulated(&model.check_pool);
    let src = NullSource {
        pool: &model.check_pool,
        keys: &ctx.keys.keys,
        sims: &check_sims,
        centre: &model.sims,
        sigma: ctx.sigma,
    };
    let check = predictive_check(data, &model.sims, ctx.specimens, src, s.check_replicates, seed, ctx.labels);
    let cause_per = compare::per_specimen(&b.scores, data.obs, ctx.specimens);
    let gain = Some(bootstrap_gain(base_per, &cause_per, s.bootstrap, seed));
    progress(&format!("tie checks: {} against its challengers", b.name));
    let tie = tie_checks(ctx, b, candidates, pool, src, s.check_replicates, seed);
    Ok(Findings {
        passes: check.passes(),
        check,
        extended: model.run,
        extended_predictive,
        gain,
        tie,
        runs: model.runs,
    })
}

/// Stage 1, the design: the key of every observation in the prepared design (its group
/// and observable).
///
/// # Errors
/// [`DiscrepancyError::Design`] naming the specimen and observable of an observation the
/// preparation did not provide for.
fn design_keys(prep: &Prepared, obs: &[Observation]) -> Result<Keys, DiscrepancyError> {
    let mut keys = prep.keys.clone();
    keys.of = obs
        .iter()
        .map(|o| {
            let g = prep.setup.groups.iter().position(|g| g.name == o.group).unwrap_or(0);
            keys.keys.iter().position(|(kg, ko)| *kg == g && ko.same(&o.observable)).ok_or_else(|| {
                DiscrepancyError::Design { specimen: o.specimen.clone(), observable: o.observable.label() }
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(keys)
}

/// The measurement σ of an analysis: the stated σ of every observation, the model's
/// spread per key (the baseline's full run) and the estimate the data give (collapse
/// angles in degrees, displacements in cm, each with its degrees of freedom).
#[derive(Debug, Clone, PartialEq)]
struct Sigmas {
    stated: Vec<f64>,
    model_sd: Vec<f64>,
    estimate: [Option<(f64, usize)>; super::observations::MEASURE_FAMILIES],
}

impl Sigmas {
    /// The rule, to apply again to every synthetic data set.
    fn rule(&self, reading: Reading) -> SigmaRule<'_> {
        SigmaRule { stated: &self.stated, model_sd: &self.model_sd, reading }
    }
}

/// Stage 2, the σ rule: every observation's σ becomes the larger of its stated σ and the
/// spread the data show beyond the model's ([`SigmaRule`]); `key[j]` is the key of
/// `obs[j]`, `baseline` the baseline's simulated values per key.
fn apply_sigma_rule(obs: &mut [Observation], key: &[usize], baseline: &[Simulated], reading: Reading) -> Sigmas {
    let mut sigmas = Sigmas {
        stated: obs.iter().map(|o| o.sigma).collect(),
        model_sd: baseline.iter().map(|x| x.sd).collect(),
        estimate: [None; super::observations::MEASURE_FAMILIES],
    };
    sigmas.estimate = sigmas.rule(reading).apply(obs, key);
    sigmas
}

/// The screening: the baseline's scores and the library's candidates ranked on their
/// surrogates.
#[derive(Debug, Clone)]
struct Screening {
    /// The baseline's score of every observation.
    base_scores: Vec<f64>,
    /// The baseline's score per specimen.
    base_per: Vec<f64>,
    /// The baseline's held-out error (its mean score per specimen; it has no parameter).
    base_he: f64,
    /// Its score per specimen on the observations the misfit margin reads
    /// ([`Data::fit_checked`]: angles, displacements and failure heights).
    base_misfit: f64,
    /// The baseline's AICc.
    base_ic: f64,
    /// The library's candidates, best held-out error first.
    ranked: Vec<Ranked>,
    /// The best candidate's gain on the baseline: the statistic the gain margin is
    /// calibrated on (0 without candidates).
    screen_gain: f64,
}

/// Stage 3, screening: the baseline scored and the library's candidates ranked by their
/// surrogates' held-out error, before pairs and confirmation runs.
fn screen(lib: &Models, data: Data<'_>, specimens: &[String]) -> Screening {
    let n = specimens.len().max(1) as f64;
    let base_scores: Vec<f64> = (0..data.obs.len()).map(|j| data.score(&lib.baseline, j)).collect();
    let base_per = compare::per_specimen(&base_scores, data.obs, specimens);
    let base_he = base_per.iter().sum::<f64>() / n;
    let base_misfit =
        compare::per_specimen(&data.checked_scores(&base_scores), data.obs, specimens).iter().sum::<f64>() / n;
    let base_ic = compare::aicc(base_scores.iter().sum(), 0, specimens.len());
    let ranked = rank(&lib.candidates, data, specimens, &base_per);
    let screen_gain = ranked.first().map_or(0.0, |r| base_he - r.heldout_error);
    Screening { base_scores, base_per, base_he, base_misfit, base_ic, ranked, screen_gain }
}

/// Whether pairs of effects are tried: the best single candidate (`best`) still misfits
/// significantly (`best_fit`, its mean score per specimen on the observations the misfit
/// margin reads, [`Data::fit_checked`], above the margin) and gains on the baseline by
/// more than the gain margin.
fn pairs_wanted(best: &Ranked, best_fit: f64, base_he: f64, margins: &Margins) -> bool {
    best_fit > margins.misfit && base_he - best.heldout_error > margins.baseline
}

/// The ranked pairs admitted beside the single effects: those whose held-out error is
/// below the best single's less the gain margin (`threshold`) and whose AICc is below the
/// best single's (`ic`); the whole ranking then sorted again (held-out error, then pool
/// order).
fn admit_pairs(ranked: &mut Vec<Ranked>, pairs: Vec<Ranked>, threshold: f64, ic: f64) {
    ranked.extend(pairs.into_iter().filter(|r| r.heldout_error < threshold && r.information_criterion < ic));
    sort(ranked);
}

/// Stage 4, ranking: pairs of the three best one-parameter mechanisms added to the pool
/// and ranked when [`pairs_wanted`], admitted by [`admit_pairs`]. Returns the pairs added
/// to the pool.
fn add_pairs(
    lib: &Models,
    data: Data<'_>,
    specimens: &[String],
    screening: &Screening,
    margins: &Margins,
    pool: &mut Vec<Candidate>,
    ranked: &mut Vec<Ranked>,
) -> usize {
    let n = specimens.len().max(1) as f64;
    let Some(best) = screening.ranked.first() else { return 0 };
    let best_fit = data.checked_scores(&best.scores).iter().sum::<f64>() / n;
    if !pairs_wanted(best, best_fit, screening.base_he, margins) {
        return 0;
    }
    let offset = pool.len();
    let extra = pairs(lib, &screening.ranked);
    let mut more = rank(&extra, data, specimens, &screening.base_per);
    for r in &mut more {
        r.index += offset;
    }
    let added = extra.len();
    pool.extend(extra);
    admit_pairs(ranked, more, best.heldout_error - margins.baseline, best.information_criterion);
    added
}

/// The extended model of a named cause.
#[derive(Debug, Clone)]
struct ExtendedModel {
    /// Its simulated values per key.
    sims: Vec<Simulated>,
    /// Its realizations on the independent layouts, `[group][realization]` (empty groups
    /// when it is not run: its data are then drawn from its own predictive).
    check_pool: Vec<Vec<Outcome>>,
    /// Its effects and full run, when it is run.
    run: Option<(Vec<Effect>, Vec<Vec<Outcome>>)>,
    /// Forward runs made for it.
    runs: usize,
}

/// Stage 7, the extended model: the scatter hypothesis, or any cause without confirmation
/// runs, is its surrogate at the fitted coordinates; a mechanism is run in full at its
/// fitted parameters (a confirmation run at the same coordinates is reused; one at other
/// coordinates, where the re-scored fit moved, is not) and on the independent layouts.
///
/// # Errors
/// [`DiscrepancyError::Effect`] for an effect that cannot take its fitted values.
fn extended_model(
    ctx: &Ctx<'_>,
    cause: &Ranked,
    c: &Candidate,
    runs: &[Confirmation],
) -> Result<ExtendedModel, DiscrepancyError> {
    let groups = ctx.prep.setup.groups.len();
    if c.is_scatter() || !ctx.prep.settings.confirm {
        return Ok(ExtendedModel {
            sims: c.surface.at(&cause.x),
            check_pool: vec![vec![]; groups],
            run: None,
            runs: 0,
        });
    }
    let x = &cause.x;
    let same = |y: &[f64]| y.len() == x.len() && y.iter().zip(x).all(|(p, q)| (p - q).abs() < 1e-9);
    let (effects, outs, full_runs) = match runs.iter().find(|r| r.candidate == cause.index && same(&r.x)) {
        Some(r) => (r.effects.clone(), r.outcomes.clone(), 0),
        None => {
            let e = effects_of(c, x, ctx.course_m)?;
            let o = run_models(ctx.full, std::slice::from_ref(&e), Some(&ctx.prep.baseline)).remove(0);
            let n = forward_runs(ctx.full, std::slice::from_ref(&e), true);
            (e, o, n)
        }
    };
    let sims = ctx.keys.simulated(&outs);
    let check_pool =
        run_models(&ctx.prep.null_setup, std::slice::from_ref(&effects), Some(&ctx.prep.null_pool)).remove(0);
    let runs = full_runs + forward_runs(&ctx.prep.null_setup, std::slice::from_ref(&effects), true);
    Ok(ExtendedModel { sims, check_pool, run: Some((effects, outs)), runs })
}

/// The tie of a named cause: its members (the cause first) and every challenger's check.
#[derive(Debug, Clone, Default, PartialEq)]
struct Tie {
    members: Vec<String>,
    checks: Vec<TieCheck>,
}

/// The tie of `cause` with `challengers` at their reversal rates ([`TieCheck::new`]).
fn tie_of(cause: &Ranked, challengers: &[&Ranked], rates: &[Reversal], data: Data<'_>, specimens: &[String]) -> Tie {
    let mut tie = Tie { members: vec![cause.name.clone()], checks: vec![] };
    for (r, &rate) in challengers.iter().zip(rates) {
        let t = TieCheck::new(cause, r, rate, data, specimens);
        if t.tied {
            tie.members.push(r.name.clone());
        }
        tie.checks.push(t);
    }
    tie
}

/// Stage 8, tie checks: the next [`TIE_CHALLENGERS`] candidates after the cause, and every
/// later one whose held-out difference to the cause is under the data test's bound
/// ([`TieCheck::STANDARD_ERRORS`] standard errors: a model the data cannot tell from the
/// cause is in the tie whatever its rank), each against the cause on data simulated from
/// the cause's own independent realizations (`src`, [`reversal_rates`]) and on the data,
/// [`tie_of`].
fn tie_checks(
    ctx: &Ctx<'_>,
    cause: &Ranked,
    candidates: &[Ranked],
    pool: &[Candidate],
    src: NullSource<'_>,
    replicates: usize,
    seed: u64,
) -> Tie {
    let none = Reversal { all: 0.0, measures: 0.0 };
    let within = |r: &Ranked| TieCheck::new(cause, r, none, ctx.data, ctx.specimens).tied;
    let challengers: Vec<&Ranked> = candidates
        .iter()
        .filter(|r| r.index != cause.index)
        .enumerate()
        .filter(|(k, r)| *k < TIE_CHALLENGERS || within(r))
        .map(|(_, r)| r)
        .collect();
    let rates = reversal_rates(
        &pool[cause.index],
        &challengers.iter().map(|r| &pool[r.index]).collect::<Vec<_>>(),
        ctx.data,
        ctx.specimens,
        src,
        replicates,
        seed,
    );
    tie_of(cause, &challengers, &rates, ctx.data, ctx.specimens)
}

/// Stage 9, the verdict: a named cause whose extended model passes its predictive check
/// explains the data, one that fails it is a partial explanation (`unexplained`); without
/// a cause, the baseline's score `base_he` on the observations the misfit margin reads
/// ([`Data::fit_checked`]) above the margin is
/// `unexplained`, else `no_effect`.
fn verdict(named: bool, passes: bool, base_he: f64, misfit: f64) -> Verdict {
    match (named, passes) {
        (true, true) => Verdict::Explained,
        (true, false) => Verdict::Unexplained,
        (false, _) if base_he > misfit => Verdict::Unexplained,
        (false, _) => Verdict::NoEffect,
    }
}

/// What would separate the first two members of a tie ([`super::findings::Design`]);
/// `None` without a tie. A new specimen is read with the largest σ of each key.
fn separating_design(
    tie: &[String],
    candidates: &[Ranked],
    pool: &[Candidate],
    obs: &[Observation],
    keys: &Keys,
    labels: &[String],
) -> Option<super::findings::Design> {
    if tie.len() < 2 {
        return None;
    }
    let mut key_sigma = vec![0.0f64; keys.keys.len()];
    for (o, &k) in obs.iter().zip(&keys.of) {
        key_sigma[k] = key_sigma[k].max(o.sigma);
    }
    let a = candidates.iter().find(|r| r.name == tie[0])?;
    let b = candidates.iter().find(|r| r.name == tie[1])?;
    design(
        &pool[a.index].surface.at(&a.x),
        &pool[b.index].surface.at(&b.x),
        &key_sigma,
        labels,
        (a.name.clone(), b.name.clone()),
    )
}

/// The models' weights ([`super::weights`]) from the held-out scores per specimen of the
/// baseline (`base_scores`, per observation) and every candidate, and the identifiability
/// of the models that share the weight ([`super::identify`]: at least the two heaviest, at
/// most [`super::identify::LEADING`]), each at its fitted parameters.
#[allow(clippy::too_many_arguments)]
fn weigh(
    data: Data<'_>,
    specimens: &[String],
    base_scores: &[f64],
    candidates: &[Ranked],
    pool: &[Candidate],
    baseline: &[Simulated],
    labels: &[String],
    draws: usize,
    seed: u64,
) -> (super::weights::Weights, super::identify::Identifiability) {
    let mut names = vec!["baseline".to_string()];
    let mut elpd =
        vec![compare::per_specimen(base_scores, data.obs, specimens).iter().map(|x| -x).collect::<Vec<f64>>()];
    for c in candidates {
        names.push(c.name.clone());
        elpd.push(compare::per_specimen(&c.scores, data.obs, specimens).iter().map(|x| -x).collect());
    }
    let w = super::weights::weights(&names, &elpd, draws, seed);
    let lead = w.shared.len().clamp(2, super::identify::LEADING).min(w.models.len());
    let models: Vec<(String, Vec<Simulated>)> = w.models[..lead]
        .iter()
        .filter_map(|m| {
            if m.name == "baseline" {
                return Some((m.name.clone(), baseline.to_vec()));
            }
            let c = candidates.iter().find(|c| c.name == m.name)?;
            Some((m.name.clone(), pool[c.index].surface.at(&c.x)))
        })
        .collect();
    let id = super::identify::identifiability(&models, data, labels);
    (w, id)
}

/// The cause's parameters with their 95 % profile intervals on the measures that pin them
/// ([`Data::pins`]), in the parameters' units.
fn fitted_parameters(cause: &Ranked, c: &Candidate, data: Data<'_>) -> Vec<FittedParameter> {
    let all: Vec<usize> = (0..data.obs.len()).collect();
    let iv = fit::profile_intervals(&c.surface, data, &data.pinning(&all), &cause.x);
    // Walls of one declared kind: the values in that kind's ranges, as the runs applied them.
    let kind = match c.kinds.as_slice() {
        [k] => Some(*k),
        _ => None,
    };
    cause
        .parameters
        .iter()
        .zip(c.params.iter().zip(iv))
        .zip(&cause.x)
        .map(|(((name, value), (p, (lo, hi))), &x)| match kind {
            Some(k) => FittedParameter {
                name: name.clone(),
                value: p.at_for(Some(k), x),
                interval: (p.at_for(Some(k), lo), p.at_for(Some(k), hi)),
            },
            None => FittedParameter { name: name.clone(), value: *value, interval: (to_value(p, lo), to_value(p, hi)) },
        })
        .collect()
}

mod naming;

use naming::{confirm, name_cause, Confirmation, Gate};

#[cfg(test)]
mod tests;
