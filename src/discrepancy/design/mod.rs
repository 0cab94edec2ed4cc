//! The next experiment: which follow-up test would name the cause alone, by a
//! preposterior analysis of the candidates that share the weight.
//!
//! A discrepancy analysis ends with a tie (the candidates the data cannot tell apart) and
//! the models that share the pseudo-BMA+ weight ([`super::weights`]). For every follow-up
//! test of a menu the product can simulate (more specimens of a group; the failure
//! mechanism read; the top monitors read at both measures and more tilts; a wall of
//! another height, length or end restraint, as an extra group of the same study), the
//! analysis asks what the data of that test would do to the weights before it is run
//! (preposterior analysis, Raiffa & Schlaifer 1961, *Applied Statistical Decision Theory*;
//! the expected information of an experiment, Lindley 1956, Ann. Math. Stat. 27:986):
//!
//! 1. **The contenders**: the models that share the weight, and the members of the tie,
//!    at most [`MAX_CONTENDERS`], each at the parameters the analysis fitted to the first
//!    campaign, with its prior weight (its pseudo-BMA+ weight, renormalized over the
//!    contenders).
//! 2. **Their predictions of the follow-up**: on the keys the first campaign already has
//!    (more specimens of a group), the fitted surrogate of each contender, as the
//!    analysis scored it; on keys it does not have (a mechanism not read, a monitor not
//!    read, a new wall), a run of each contender at its fitted parameters on the follow-up's
//!    walls ([`Settings::extension_realizations`](super::Settings::extension_realizations)
//!    realizations, the analysis's layouts: common random numbers), with the scatter hypothesis on the baseline's run.
//! 3. **Simulated follow-ups**: for each contender taken as the truth, `replicates` data
//!    sets of the follow-up's specimens drawn from its own predictive (Student-t of each
//!    angle and displacement, the failure height from its distribution over the height
//!    with the misreading component, a kind and a start from their smoothed category
//!    probabilities), rounded to the readings' resolution.
//! 4. **Both campaigns together**: each contender's held-out log score per specimen of the
//!    first campaign (the analysis's) and its log predictive score of each simulated
//!    specimen (held out from its fit by construction: the parameters were fitted to the
//!    first campaign), pseudo-BMA+ weights over the contenders on all specimens (Yao,
//!    Vehtari, Simpson & Gelman 2018, Bayesian Analysis 13:917; the same Bayesian
//!    bootstrap as [`super::weights`]).
//! 5. **Named alone**: the truth alone holds [`super::SHARED`] (90 %) of the weight, and
//!    the two tests of the analysis's tie check clear every other contender on both
//!    campaigns (the held-out difference per specimen at least two standard errors; a
//!    reversal rate, the share of the truth's simulated follow-ups in which the other
//!    scores at least as well, under 5 %), on every observation or, with mechanism
//!    readings, on the angles and displacements alone with the readings not favouring the
//!    other (as [`super::TieCheck`] clears a challenger). The probability that the cause is then named
//!    alone is the average over the contenders as truth, weighted by their prior weights;
//!    the weights' criterion alone is reported beside it; "right" is the truth among the
//!    models that share the weight.
//!
//! The follow-ups are ranked by that probability at the same number of specimens
//! ([`DesignSettings::specimens`]), then by the fewest specimens that reach
//! [`DesignSettings::target`]. What this does not repeat: the full analysis of each
//! simulated data set (a refit of the parameters on both campaigns, the margins, the
//! confirmation runs, the tie checks); the parameters stay at the first campaign's fit,
//! so a refit that lets a contender absorb the follow-up's data is not foreseen.

mod menu;
mod plan;

pub use menu::{menu, GroupWall};
pub use plan::{Chance, Contender, DesignSettings, FollowUp, FollowUpKind, Plan, RankedFollowUp, WallEdit};

use super::compare::{per_specimen, specimen_weights};
use super::fit::Data;
use super::observations::{Observable, Observation};
use super::predictive::{Predictive, Reading, Simulated};
use super::simulate::{run_models, Outcome, Setup};
use super::{DiscrepancyError, Run};
use crate::loading::mechanism::{FailureKind, FailureStart};
use crate::rng::{rng_for, Purpose};
use rand::RngExt;
use rand_distr::{Distribution, Exp1, StandardNormal, StudentT};

/// The most contenders a design compares.
pub const MAX_CONTENDERS: usize = 5;

impl DesignSettings {
    /// Checks the ranges.
    ///
    /// # Errors
    /// [`DiscrepancyError::Setting`] naming `design.<key>`.
    pub fn validate(&self) -> Result<(), DiscrepancyError> {
        let bad = |key: &'static str, value: String, reason: &'static str| {
            Err(DiscrepancyError::Setting { key, value, reason })
        };
        if !(1..=MAX_SPECIMENS).contains(&self.specimens) {
            return bad("design.specimens", self.specimens.to_string(), "in [1, 64]");
        }
        if !(10..=100_000).contains(&self.replicates) {
            return bad("design.replicates", self.replicates.to_string(), "in [10, 100000]");
        }
        if !(10..=100_000).contains(&self.draws) {
            return bad("design.draws", self.draws.to_string(), "in [10, 100000]");
        }
        if !(self.target > 0.0 && self.target < 1.0) {
            return bad("design.target", self.target.to_string(), "in (0, 1)");
        }
        Ok(())
    }

    /// The specimen counts the probabilities are computed at: 1, 2, 3, 5, 8, 12, 16, 24,
    /// 32, 48, 64 up to four times the budget, and the budget.
    fn ladder(&self) -> Vec<usize> {
        let mut v: Vec<usize> =
            [1, 2, 3, 5, 8, 12, 16, 24, 32, 48, 64].into_iter().filter(|&n| n <= 4 * self.specimens).collect();
        v.push(self.specimens);
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// The most specimens of one follow-up.
pub const MAX_SPECIMENS: usize = 64;

/// The contenders of an analysis: the models that share the weight and the members of the
/// tie, heaviest first, at most [`MAX_CONTENDERS`], with their priors and held-out scores.
pub fn contenders(run: &Run) -> Vec<Contender> {
    let a = &run.analysis;
    let mut names: Vec<String> = a.weights.shared.clone();
    for t in &a.tie {
        if !names.contains(t) {
            names.push(t.clone());
        }
    }
    if names.len() < 2 {
        // One model holds the weight: the runner-up still shows what a follow-up keeps.
        for m in &a.weights.models {
            if !names.contains(&m.name) {
                names.push(m.name.clone());
                break;
            }
        }
    }
    names.sort_by(|x, y| a.weights.of(y).total_cmp(&a.weights.of(x)));
    names.truncate(MAX_CONTENDERS);
    let elpd_of = |name: &str| -> Option<(Vec<f64>, Vec<f64>)> {
        let scores = if name == "baseline" {
            a.baseline_scores.clone()
        } else {
            a.candidates.iter().find(|c| c.name == name)?.scores.clone()
        };
        let measures: Vec<f64> =
            scores.iter().enumerate().map(|(j, &s)| if run.obs[j].observable.pins() { s } else { 0.0 }).collect();
        let elpd = |s: &[f64]| per_specimen(s, &run.obs, &run.specimens).iter().map(|s| -s).collect();
        Some((elpd(&scores), elpd(&measures)))
    };
    let mut out: Vec<Contender> = names
        .iter()
        .filter_map(|n| {
            let (elpd, elpd_measures) = elpd_of(n)?;
            Some(Contender { name: n.clone(), prior: a.weights.of(n), elpd, elpd_measures })
        })
        .collect();
    let total: f64 = out.iter().map(|c| c.prior).sum();
    for c in &mut out {
        c.prior = if total > 0.0 { c.prior / total } else { 1.0 / names.len() as f64 };
    }
    out
}

/// The σ of a new reading of `o`: the largest σ the analysis used for an observation of
/// the same kind (after its σ rule), else the settings'.
fn sigma_of(run: &Run, o: &Observable) -> f64 {
    let same = |p: &Observable| std::mem::discriminant(p) == std::mem::discriminant(o);
    let used = run.obs.iter().filter(|x| same(&x.observable)).map(|x| x.sigma).fold(0.0, f64::max);
    if used > 0.0 {
        return used;
    }
    let s = run.settings.sigma;
    match o {
        Observable::CollapseAngle => s.angle_deg,
        Observable::Displacement { .. } => s.displacement_cm,
        Observable::FailureHeight { .. } => s.failure_height,
        _ => 1.0,
    }
}

/// The predictions of every contender for the keys of a follow-up: `[contender][key]`,
/// and the forward runs made for them.
///
/// # Errors
/// [`DiscrepancyError::Effect`] for a contender that cannot take its fitted values.
fn predictions(
    run: &Run,
    setup: &Setup,
    f: &FollowUp,
    cs: &[Contender],
    cache: &mut std::collections::BTreeMap<String, super::simulate::Outcomes>,
) -> Result<(Vec<Vec<Simulated>>, usize), DiscrepancyError> {
    let a = &run.analysis;
    let existing = setup.groups.iter().position(|g| g.name == f.group);
    // Keys the first campaign has for this group: the fitted surrogates answer.
    if let Some(g) = existing.filter(|_| f.new_group.is_none()) {
        let idx: Option<Vec<usize>> =
            f.observables.iter().map(|o| run.keys.keys.iter().position(|(kg, ko)| *kg == g && ko.same(o))).collect();
        if let Some(idx) = idx {
            let sims = cs
                .iter()
                .map(|c| {
                    let all = if c.name == "baseline" {
                        run.library.baseline.clone()
                    } else {
                        let r = a.candidates.iter().find(|r| r.name == c.name).expect("a contender is a candidate");
                        a.pool[r.index].surface.at(&r.x)
                    };
                    idx.iter().map(|&k| all[k]).collect()
                })
                .collect();
            return Ok((sims, 0));
        }
    }
    // Otherwise a run of every contender at its fitted parameters on the follow-up's group.
    let group = match (&f.new_group, existing) {
        (Some(g), _) => g.clone(),
        (None, Some(g)) => setup.groups[g].clone(),
        (None, None) => return Err(DiscrepancyError::Design { specimen: f.group.clone(), observable: f.name.clone() }),
    };
    let r = run.settings.extension_realizations.min(group.realizations.max(1)).max(1);
    let one = Setup { groups: vec![super::simulate::GroupSetup { realizations: r, ..group }], ..setup.clone() };
    let course_m = super::prepare::course_height(setup);
    let mut models = Vec::new();
    let mut which = Vec::new();
    for c in cs {
        let r = a.candidates.iter().find(|r| r.name == c.name);
        match r {
            Some(r) if !a.pool[r.index].is_scatter() => {
                which.push(Some(models.len()));
                models.push(super::prepare::effects_of(&a.pool[r.index], &r.x, course_m)?);
            }
            _ => which.push(None),
        }
    }
    let base_idx = models.len();
    models.push(vec![]);
    // The runs of an existing group serve every follow-up of it (the same contenders).
    let (outcomes, runs) = match cache.get(&f.group).filter(|_| f.new_group.is_none()) {
        Some(o) => (o.clone(), 0),
        None => {
            let o = run_models(&one, &models, None);
            let runs: usize = o.iter().map(|m| m[0].len()).sum();
            if f.new_group.is_none() {
                cache.insert(f.group.clone(), o.clone());
            }
            (o, runs)
        }
    };
    let sims_of =
        |outs: &[Outcome]| -> Vec<Simulated> { f.observables.iter().map(|o| Simulated::of(outs, o)).collect() };
    let base = sims_of(&outcomes[base_idx][0]);
    let sims = cs
        .iter()
        .zip(&which)
        .map(|(c, w)| match w {
            Some(m) => sims_of(&outcomes[*m][0]),
            None if c.name == super::candidate::SCATTER => {
                let r = a.candidates.iter().find(|r| r.name == c.name).expect("scatter is a candidate");
                let angle = f.observables.iter().map(|o| matches!(o, Observable::CollapseAngle)).collect();
                let mechanism = f.observables.iter().map(Observable::is_mechanism).collect();
                super::fit::Surface::Scatter { base: base.clone(), angle, mechanism }.at(&r.x)
            }
            None => base.clone(),
        })
        .collect();
    Ok((sims, runs))
}

/// Designs the next experiment for an analysed data set: every follow-up of `menu`
/// (see [`menu`]) ranked by the probability that the cause is named alone after it, at
/// the budget of `ds.specimens` specimens. `setup` is the analysis's; `seed` seeds the
/// simulated follow-ups (its own stream). Runs the contenders on the follow-ups' walls
/// where the fitted surrogates have no prediction (module documentation).
///
/// # Errors
/// [`DiscrepancyError::Setting`] for bad settings, [`DiscrepancyError::Effect`] for a
/// contender that cannot take its fitted values.
pub fn design(
    run: &Run,
    setup: &Setup,
    menu: Vec<FollowUp>,
    ds: &DesignSettings,
    seed: u64,
    progress: super::Progress<'_>,
) -> Result<Plan, DiscrepancyError> {
    ds.validate()?;
    let cs = contenders(run);
    let ladder = ds.ladder();
    let mut ranked = Vec::new();
    let mut total_runs = 0;
    let mut cache = std::collections::BTreeMap::new();
    for (i, f) in menu.into_iter().enumerate() {
        progress(&format!("follow-up {}: {}", i + 1, f.name));
        let (sims, runs) = predictions(run, setup, &f, &cs, &mut cache)?;
        total_runs += runs;
        let sigma: Vec<f64> = f.observables.iter().map(|o| sigma_of(run, o)).collect();
        let problem = Problem {
            contenders: &cs,
            sims: &sims,
            keys: &f.observables,
            sigma: &sigma,
            reading: run.settings.reading,
            bracket_deg: run.bracket_deg,
        };
        let chances = problem.chances(&ladder, ds.replicates, ds.draws, stream_seed(seed, i));
        let at_budget =
            chances.iter().find(|c| c.specimens == ds.specimens).cloned().expect("the budget is on the ladder");
        let to_target = chances.iter().find(|c| c.alone >= ds.target).map(|c| c.specimens);
        ranked.push(RankedFollowUp { followup: f, chances, at_budget, to_target, runs });
    }
    sort_ranked(&mut ranked);
    let alone_now =
        cs.first().is_some_and(|c| run.analysis.weights.shared.len() == 1 && run.analysis.weights.shared[0] == c.name);
    Ok(Plan { contenders: cs, alone_now, ranked, settings: *ds, runs: total_runs })
}

/// Best first: the probability of naming the cause alone at the budget, then the fewest
/// specimens to the target, then the weights' probability of naming it alone, then the
/// probability of a right answer, then the fewest runs, then menu order.
fn sort_ranked(v: &mut [RankedFollowUp]) {
    v.sort_by(|a, b| {
        b.at_budget
            .alone
            .total_cmp(&a.at_budget.alone)
            .then(a.to_target.unwrap_or(usize::MAX).cmp(&b.to_target.unwrap_or(usize::MAX)))
            .then(b.at_budget.weights_alone.total_cmp(&a.at_budget.weights_alone))
            .then(b.at_budget.right.total_cmp(&a.at_budget.right))
            .then(a.runs.cmp(&b.runs))
    });
}

/// The master seed of follow-up `i`'s simulated data: derived from the analysis's.
fn stream_seed(seed: u64, i: usize) -> u64 {
    (seed ^ 0x6465_7369_676e_0000).rotate_left(17).wrapping_add(i as u64)
}

/// The preposterior problem of one follow-up: the contenders, their predictions of each
/// key (`sims[contender][key]`), the keys, each key's reading σ, the readings'
/// resolutions and the simulated angle's bracket (degrees).
#[derive(Debug, Clone, Copy)]
pub struct Problem<'a> {
    /// The contenders.
    pub contenders: &'a [Contender],
    /// `[contender][key]`.
    pub sims: &'a [Vec<Simulated>],
    /// The keys read on each specimen (mechanism categories: one of them is seen).
    pub keys: &'a [Observable],
    /// The σ of each key's reading.
    pub sigma: &'a [f64],
    /// The readings' resolutions and misreading probability.
    pub reading: Reading,
    /// Width of a simulated collapse angle's bracket, degrees.
    pub bracket_deg: f64,
}

impl Problem<'_> {
    /// One simulated specimen from contender `t`: its observations (key index, value).
    fn draw_specimen(&self, t: usize, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<(usize, f64)> {
        let sims = &self.sims[t];
        let mut out = Vec::new();
        let mut kinds = Vec::new();
        let mut starts = Vec::new();
        for (k, o) in self.keys.iter().enumerate() {
            let sim = &sims[k];
            match o {
                Observable::MechanismKind { .. } => kinds.push(k),
                Observable::MechanismStart { .. } => starts.push(k),
                Observable::FailureHeight { width } => {
                    if sim.heights.is_empty() {
                        continue;
                    }
                    let v = if rng.random::<f64>() < self.reading.misreading {
                        rng.random::<f64>()
                    } else {
                        let u: f64 = rng.random();
                        let mut acc = 0.0;
                        let last = (sim.heights.0.len() - 1) as f64;
                        let mut c = 1.0;
                        for (i, m) in sim.heights.0.iter().enumerate() {
                            acc += m;
                            if u <= acc {
                                c = i as f64 / last;
                                break;
                            }
                        }
                        let z: f64 = StandardNormal.sample(rng);
                        (c + z * (self.sigma[k].powi(2) + sim.err.powi(2)).sqrt()).clamp(0.0, 1.0)
                    };
                    let v = self.reading.neighbour_read(v, *width, rng.random());
                    out.push((k, self.reading.round(&Observable::FailureHeight { width: *width }, v)));
                }
                _ => {
                    if !sim.mean.is_finite() {
                        continue;
                    }
                    let p = Predictive::new(sim, &self.template(k), self.bracket_deg);
                    let z: f64 = if p.dof < 1e4 {
                        StudentT::new(p.dof.max(1.0)).map_or(0.0, |d| d.sample(rng))
                    } else {
                        StandardNormal.sample(rng)
                    };
                    out.push((k, self.reading.round(o, p.mean + p.sd * z)));
                }
            }
        }
        for group in [kinds, starts] {
            if group.is_empty() {
                continue;
            }
            // The seen category, by the smoothed and misread probabilities.
            let q: Vec<f64> = group
                .iter()
                .map(|&k| self.reading.category_probability(&self.keys[k], &sims[k]).unwrap_or(0.0))
                .collect();
            let total: f64 = q.iter().sum();
            if !(total > 0.0) {
                continue;
            }
            let mut u = rng.random::<f64>() * total;
            let mut pick = group[group.len() - 1];
            for (&k, q) in group.iter().zip(&q) {
                if u < *q {
                    pick = k;
                    break;
                }
                u -= q;
            }
            out.push((pick, 1.0));
        }
        out
    }

    /// An observation of key `k` with its σ (its value set later).
    fn template(&self, k: usize) -> Observation {
        Observation {
            specimen: String::new(),
            group: String::new(),
            observable: self.keys[k],
            value: 0.0,
            sigma: self.sigma[k],
        }
    }

    /// The log predictive score of each of `specimens` (each its observations) under
    /// every contender, on every observation and on the measures alone
    /// ([`Observable::pins`]): two `[contender][specimen]`, nats.
    fn elpd(&self, specimens: &[Vec<(usize, f64)>]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let mut obs = Vec::new();
        let mut key = Vec::new();
        let mut y = Vec::new();
        let names: Vec<String> = (0..specimens.len()).map(|i| format!("s{i}")).collect();
        for (i, s) in specimens.iter().enumerate() {
            for &(k, v) in s {
                obs.push(Observation { specimen: names[i].clone(), value: v, ..self.template(k) });
                key.push(k);
                y.push(v);
            }
        }
        let weight = specimen_weights(&obs);
        let data =
            Data { obs: &obs, y: &y, key: &key, weight: &weight, reading: self.reading, bracket_deg: self.bracket_deg };
        let elpd = |scores: &[f64]| per_specimen(scores, &obs, &names).iter().map(|s| -s).collect();
        self.sims
            .iter()
            .map(|sims| {
                let scores: Vec<f64> = (0..obs.len()).map(|j| data.score(sims, j)).collect();
                (elpd(&scores), elpd(&data.split_scores(&scores).0))
            })
            .unzip()
    }

    /// The probabilities at every specimen count of `ladder`, from `replicates` simulated
    /// follow-ups per contender taken as the truth (the largest count drawn, the smaller
    /// counts its first specimens), weights from `draws` Bayesian-bootstrap draws.
    ///
    /// A simulated follow-up names the truth alone when the truth alone holds
    /// [`super::SHARED`] of the weight **and** the analysis's tie check
    /// ([`super::TieCheck`]) clears every other contender on both campaigns: the
    /// held-out difference per specimen at least [`TieCheck::STANDARD_ERRORS`] standard
    /// errors, and the reversal rate (the share of the truth's simulated follow-ups in
    /// which the other contender's total score is at least the truth's) under
    /// [`TieCheck::REVERSAL_RATE`]; with readings of the mechanism, either on every
    /// observation or on the measures alone with the readings not favouring the other
    /// beyond the data bound, as the analysis clears a challenger. The weights' criterion
    /// alone is kept beside it ([`Chance::weights_alone`]).
    ///
    /// [`TieCheck::STANDARD_ERRORS`]: super::TieCheck::STANDARD_ERRORS
    /// [`TieCheck::REVERSAL_RATE`]: super::TieCheck::REVERSAL_RATE
    pub fn chances(&self, ladder: &[usize], replicates: usize, draws: usize, seed: u64) -> Vec<Chance> {
        use super::TieCheck;
        let bound = TieCheck::STANDARD_ERRORS;
        let k = self.contenders.len();
        let nmax = ladder.iter().copied().max().unwrap_or(0);
        let mut by_weights = vec![vec![0usize; k]; ladder.len()];
        let mut right = vec![vec![0usize; k]; ladder.len()];
        // [ladder][truth][other]: replicates in which `other` scores at least the truth, on
        // every observation and on the measures.
        let mut reversed = vec![vec![vec![(0usize, 0usize); k]; k]; ladder.len()];
        // [ladder][truth]: per replicate named alone by the weights, and per other whether
        // the data test separates it on every observation and on the measures.
        let mut seps: Vec<Vec<Vec<(bool, Vec<(bool, bool)>)>>> = vec![vec![Vec::new(); k]; ladder.len()];
        let both =
            |first: &[f64], new: &[f64], n: usize| -> Vec<f64> { first.iter().chain(&new[..n]).copied().collect() };
        for t in 0..k {
            let mut rng = rng_for(seed, t as u64, Purpose::Discrepancy);
            for _ in 0..replicates {
                let specimens: Vec<Vec<(usize, f64)>> = (0..nmax).map(|_| self.draw_specimen(t, &mut rng)).collect();
                let (new, new_measures) = self.elpd(&specimens);
                for (li, &n) in ladder.iter().enumerate() {
                    let elpd: Vec<Vec<f64>> =
                        self.contenders.iter().zip(&new).map(|(c, e)| both(&c.elpd, e, n)).collect();
                    let measures: Vec<Vec<f64>> =
                        self.contenders.iter().zip(&new_measures).map(|(c, e)| both(&c.elpd_measures, e, n)).collect();
                    let w = pseudo_bma(&elpd, draws, &mut rng);
                    let (a, r) = named(&w, t);
                    let mut sep = Vec::with_capacity(k);
                    for c in 0..k {
                        if c == t {
                            sep.push((true, true));
                            continue;
                        }
                        let diff =
                            |e: &[Vec<f64>]| -> Vec<f64> { e[t].iter().zip(&e[c]).map(|(x, y)| x - y).collect() };
                        let (d, dm) = (diff(&elpd), diff(&measures));
                        let dr: Vec<f64> = d.iter().zip(&dm).map(|(x, y)| x - y).collect();
                        let (sum, sum_m, sum_r) =
                            (d.iter().sum::<f64>(), dm.iter().sum::<f64>(), dr.iter().sum::<f64>());
                        let se = super::compare::difference_se;
                        reversed[li][t][c].0 += usize::from(sum <= 0.0);
                        reversed[li][t][c].1 += usize::from(sum_m <= 0.0);
                        let readings = dr.iter().any(|&x| x != 0.0);
                        sep.push((
                            sum >= bound * se(&d),
                            readings && sum_m >= bound * se(&dm) && sum_r >= -bound * se(&dr),
                        ));
                    }
                    by_weights[li][t] += usize::from(a);
                    right[li][t] += usize::from(r);
                    seps[li][t].push((a, sep));
                }
            }
        }
        let reps = replicates.max(1) as f64;
        let prior = |t: usize| self.contenders[t].prior;
        ladder
            .iter()
            .enumerate()
            .map(|(li, &n)| {
                let by: Vec<f64> = (0..k)
                    .map(|t| {
                        let clear = |c: usize| {
                            let (all, measures) = reversed[li][t][c];
                            (
                                (all as f64 / reps) < TieCheck::REVERSAL_RATE,
                                (measures as f64 / reps) < TieCheck::REVERSAL_RATE,
                            )
                        };
                        let clear: Vec<(bool, bool)> = (0..k).map(clear).collect();
                        let alone = seps[li][t]
                            .iter()
                            .filter(|(a, sep)| {
                                *a && (0..k)
                                    .filter(|&c| c != t)
                                    .all(|c| (sep[c].0 && clear[c].0) || (sep[c].1 && clear[c].1))
                            })
                            .count();
                        alone as f64 / reps
                    })
                    .collect();
                Chance {
                    specimens: n,
                    alone: (0..k).map(|t| prior(t) * by[t]).sum(),
                    weights_alone: (0..k).map(|t| prior(t) * by_weights[li][t] as f64 / reps).sum(),
                    right: (0..k).map(|t| prior(t) * right[li][t] as f64 / reps).sum(),
                    alone_by_truth: by,
                }
            })
            .collect()
    }
}

/// Whether contender `t` alone holds [`super::SHARED`] of the weights `w` (alone), and
/// whether it is among the fewest heaviest that hold it (right).
fn named(w: &[f64], t: usize) -> (bool, bool) {
    let mut order: Vec<usize> = (0..w.len()).collect();
    order.sort_by(|&a, &b| w[b].total_cmp(&w[a]).then(a.cmp(&b)));
    let mut held = 0.0;
    let mut shared = Vec::new();
    for &m in &order {
        shared.push(m);
        held += w[m];
        if held >= super::SHARED - 1e-12 {
            break;
        }
    }
    (shared == [t], shared.contains(&t))
}

/// Pseudo-BMA+ weights of the models with log scores per specimen `elpd[k][i]`: `w_k ∝
/// exp(n Σ_i α_i elpd_ik)` averaged over `draws` Bayesian-bootstrap draws `α ~
/// Dirichlet(1, …, 1)` (as [`super::weights`]).
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

/// The section "The next experiment" of the discrepancy report (Markdown): the
/// contenders with their prior weights, and every follow-up with the probability that the
/// cause is named alone after it (at the budget and by the truth), the probability that it
/// stays among the models that share the weight, and the fewest specimens that reach the
/// target.
pub fn markdown(plan: &Plan) -> String {
    use std::fmt::Write;
    let mut md = String::new();
    let _ = writeln!(md, "\n## The next experiment\n");
    let names: Vec<String> = plan.contenders.iter().map(|c| format!("`{}` {:.2}", c.name, c.prior)).collect();
    let _ = writeln!(
        md,
        "Contenders (the models that share the weight and the tie, with their pseudo-BMA+ weights on the first campaign): {}. \
         Each follow-up: {} specimens, {} simulated data sets per contender taken as the truth, drawn from its predictive at \
         its fitted parameters and weighed with the first campaign's held-out scores (pseudo-BMA+, {} bootstrap draws). \
         *Alone*: the truth alone holds 90 % of the weight and the tie check's two tests (2 standard errors, reversal \
         rate under 5 %) clear every other contender; *weights alone*: the first condition only; *right*: the truth is \
         among the models that share the weight. {} forward runs.\n",
        names.join(", "),
        plan.settings.specimens,
        plan.settings.replicates,
        plan.settings.draws,
        plan.runs
    );
    let truths: Vec<String> = plan.contenders.iter().map(|c| format!("alone if `{}`", c.name)).collect();
    let _ = writeln!(
        md,
        "| follow-up | P(named alone) | P(weights alone) | P(right) | {} | specimens to {:.0} % | runs |",
        truths.join(" | "),
        100.0 * plan.settings.target
    );
    let _ = writeln!(md, "| --- | --- | --- | --- |{} --- | --- |", " --- |".repeat(truths.len()));
    for r in &plan.ranked {
        let by: Vec<String> = r.at_budget.alone_by_truth.iter().map(|p| format!("{p:.2}")).collect();
        let _ = writeln!(
            md,
            "| {} | {:.2} | {:.2} | {:.2} | {} | {} | {} |",
            r.followup.name,
            r.at_budget.alone,
            r.at_budget.weights_alone,
            r.at_budget.right,
            by.join(" | "),
            r.to_target.map_or(format!("> {}", 4 * plan.settings.specimens), |n| n.to_string()),
            r.runs
        );
    }
    if let Some(b) = plan.best() {
        let _ = writeln!(
            md,
            "\nBest: **{}**, {} specimens: the cause named alone with probability {:.2}. Written as a study with \
             empty measured-file templates in `design/followup/`.",
            b.followup.name, plan.settings.specimens, b.at_budget.alone
        );
    }
    md
}

/// The mechanism keys of a follow-up that reads the mechanism: the failure height read to
/// `width` of the wall's height, every kind and every simulated start.
pub fn mechanism_keys(width: f64) -> Vec<Observable> {
    let mut v = vec![Observable::FailureHeight { width }];
    v.extend(FailureKind::ALL.map(|kind| Observable::MechanismKind { kind }));
    v.extend(FailureStart::SIMULATED.map(|start| Observable::MechanismStart { start }));
    v
}

#[cfg(test)]
mod tests;
