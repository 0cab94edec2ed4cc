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
//! 1. **The contenders**: taken as the truth, the models that share the weight and the
//!    members of the tie, at most [`MAX_CONTENDERS`], each with its prior weight (its
//!    pseudo-BMA+ weight, renormalized over them), and the truths outside them; beside them, up to [`MAX_CHALLENGERS`]
//!    in all, the rest of the tie and the candidates ranked next to the cause, which the
//!    user's tie check of both campaigns will examine ([`contenders`]).
//! 2. **Their predictions of the follow-up over their whole range** (`refit`): on the
//!    keys the first campaign already has (more specimens of a group), each contender's
//!    own surrogate; on keys it does not have (a mechanism not read, a monitor not read, a
//!    new wall), a grid of runs on the follow-up's walls built as the analysis builds its
//!    library (the analysis's layouts: common random numbers), one per effect and wall,
//!    shared by every follow-up of that wall and every simulated data set.
//! 3. **Simulated follow-ups**: for each contender taken as the truth, `replicates` data
//!    sets of the follow-up's specimens drawn from its own predictive at its first-campaign
//!    fit (Student-t of each angle and displacement, the failure height from its
//!    distribution over the height with the misreading component, a kind and a start from
//!    their smoothed category probabilities), rounded to the readings' resolution.
//! 4. **Both campaigns analysed as the user will**: on each simulated data set every
//!    contender is refit on the measures of both campaigns, leave one specimen out, and
//!    each specimen of either campaign scored at the fit without it; pseudo-BMA+ weights
//!    over the contenders on all specimens (Yao, Vehtari, Simpson & Gelman 2018, Bayesian
//!    Analysis 13:917; the same Bayesian bootstrap as [`super::weights`]).
//! 5. **Named alone**, the verdict's criterion ([`super::Analysis::named_alone`]): the two
//!    tests of the analysis's tie check clear every other contender on both campaigns (the
//!    held-out difference per specimen at least two standard errors; a reversal rate, the
//!    share of data sets drawn from the truth on both campaigns, the first campaign's
//!    design drawn anew as the analysis draws it, in which the other's held-out score
//!    beats the truth's, under 5 %: the analysis estimates that rate on data sets of its
//!    own, so the test clears with a probability, [`problem::clears`]), on every observation or, with mechanism readings, on the angles and
//!    displacements alone with the readings not favouring the other (as
//!    [`super::TieCheck`] clears a challenger). A pair of single effects is a challenger
//!    (and a truth that can be named) only in the simulated data sets where the analysis
//!    would rank it: where its held-out error is below the best single's by the gain
//!    margin, as the analysis admits the pairs it adds ([`Problem::pair_margin`]); a pair
//!    that nests the truth can never be separated from it, and the analysis does not
//!    rank it unless it beats the truth. The probability that the cause is then
//!    named alone is the average over the truths, weighted by their prior weights. Beside
//!    it: the truth alone holding [`super::SHARED`] (90 %) of the weight, and "right", the
//!    truth among the models that share the weight.
//!
//! The follow-ups are ranked by that probability at the same number of specimens
//! ([`DesignSettings::specimens`]), then by the fewest specimens that reach
//! [`DesignSettings::target`]. The best one is then **re-estimated** at the budget on
//! fresh simulated follow-ups, drawn on random streams disjoint from those that ranked the
//! menu ([`Stream`]), since the best of many estimates runs high even when each is unbiased
//! (the optimizer's curse, Smith & Winkler 2006, *Management Science* 52, 311–322): that
//! estimate, with its Wilson interval, is the promise ([`Plan::reported`]).
//!
//! The truths are wider than the analysis's contenders ([`contenders`]): the pair of the
//! two best singles wherever both campaigns could admit a pair, and an effect the first
//! campaign did not rank among them, sharing [`OUTSIDE_PRIOR`]. Keys the first campaign did
//! not read carry model discrepancy per key ([`Problem::bias_variances`],
//! [`Problem::mechanism_source`]).
//!
//! What this does not repeat of the user's analysis: the margins from null data, the
//! pairs of the third-best single the ranking may add, and the full runs that confirm the
//! two best candidates at their fitted points; the refit keeps the scan's point without
//! the analysis's polish (`refit`).

mod inadequacy;
mod menu;
mod plan;
mod problem;
mod refit;
mod truths;

pub use inadequacy::{inadequacy, Inadequacy, CHECK_LEVEL};
pub use menu::{menu, GroupWall};
pub use plan::{
    Chance, Contender, DesignSettings, FollowUp, FollowUpKind, Made, Plan, RankedFollowUp, Reported, WallEdit,
};
pub use problem::{clears, FirstCampaign, Problem, Stream};
pub use refit::{first_design, first_scores, heldout, FirstDesign, FirstScores, Refit};
pub use truths::{contenders, pairs_possible, OUTSIDE_PRIOR};

use super::observations::{Observable, Scale};
use super::simulate::Setup;
use super::{DiscrepancyError, Run};
use crate::loading::mechanism::{FailureKind, FailureStart};
use statrs::distribution::ContinuousCDF;

/// The most contenders a design takes as the truth.
pub const MAX_CONTENDERS: usize = 5;
/// The most contenders a design refits and scores on every simulated follow-up (the
/// truths and the models the user's tie check will examine).
pub const MAX_CHALLENGERS: usize = 12;

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

/// The σ of a new reading of `o`: the largest σ the analysis used for an observation of
/// the same kind (after its σ rule), else the settings'.
fn sigma_of(run: &Run, o: &Observable) -> f64 {
    let same = |p: &Observable| std::mem::discriminant(p) == std::mem::discriminant(o);
    let used = run.obs.iter().filter(|x| same(&x.observable)).map(|x| x.sigma).fold(0.0, f64::max);
    if used > 0.0 {
        return used;
    }
    let s = run.settings.sigma;
    match o.scale() {
        Scale::Measure(family) => s.of_family(family),
        Scale::Place { .. } => s.failure_height,
        // A category's indicator is scored by its misreading, not by a σ.
        Scale::Category { .. } => 1.0,
    }
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
    let (cs, truths) = contenders(run);
    let first = refit::first_scores(run, &cs);
    let first_design = refit::first_design(run, &cs);
    let Inadequacy { own: inadequacy, transfer } = inadequacy::inadequacy(run, &first, &first_design);
    let shared = Shared {
        run,
        cs: &cs,
        truths,
        first: &first,
        first_design: &first_design,
        inadequacy: &inadequacy,
        transfer: &transfer,
    };
    let ladder = ds.ladder();
    let mut ranked = Vec::new();
    let mut total_runs = 0;
    let mut cache = refit::RunCache::new();
    for (i, f) in menu.into_iter().enumerate() {
        progress(&format!("follow-up {}: {}", i + 1, f.name));
        let pred = refit::predictions(run, setup, &f, &cs, &mut cache)?;
        total_runs += pred.runs;
        let (chances, disagreement) = shared.with_problem(&f, &pred, |problem| {
            let unseen = (0..problem.keys.len()).any(|k| problem.unseen(k));
            let disagreement: Vec<Vec<f64>> =
                if unseen { (0..truths).map(|t| problem.disagreement(t)).collect() } else { Vec::new() };
            (problem.chances_on(&ladder, ds.replicates, ds.draws, Stream::select(stream_seed(seed, i))), disagreement)
        });
        let at_budget =
            chances.iter().find(|c| c.specimens == ds.specimens).cloned().expect("the budget is on the ladder");
        let to_target = chances.iter().find(|c| c.alone >= ds.target).map(|c| c.specimens);
        ranked.push(RankedFollowUp {
            followup: f,
            chances,
            at_budget,
            to_target,
            runs: pred.runs,
            disagreement,
            menu_index: i,
        });
    }
    sort_ranked(&mut ranked);
    let reported = match ranked.first() {
        Some(best) => {
            progress(&format!("re-estimating the chosen follow-up: {}", best.followup.name));
            // The best follow-up's walls are in the cache: no forward run is made again.
            let pred = refit::predictions(run, setup, &best.followup, &cs, &mut cache)?;
            let stream = Stream::report(stream_seed(seed, best.menu_index));
            let chance = shared.with_problem(&best.followup, &pred, |problem| {
                problem.chances_on(&[ds.specimens], ds.replicates, ds.draws, stream)
            });
            Some(reported(&cs[..truths.min(cs.len())], chance[0].clone(), ds.replicates, best.at_budget.alone))
        }
        None => None,
    };
    let alone_now = run.analysis.named_alone().is_some();
    Ok(Plan {
        contenders: cs.clone(),
        truths,
        inadequacy: inadequacy.clone(),
        transfer: transfer.clone(),
        alone_now,
        ranked,
        settings: *ds,
        runs: total_runs,
        reported,
    })
}

/// The re-estimate of the chosen follow-up ([`Reported`]) from its probabilities on fresh
/// replicates `chance` (`replicates` per truth), the truths `truths` (their priors weigh
/// the mean), and the ranking's own estimate `selected`.
pub fn reported(truths: &[Contender], chance: Chance, replicates: usize, selected: f64) -> Reported {
    let total: f64 = truths.iter().map(|c| c.prior).sum();
    let squares: f64 = if total > 0.0 {
        truths.iter().map(|c| (c.prior / total).powi(2)).sum()
    } else {
        1.0 / truths.len().max(1) as f64
    };
    let kish = replicates as f64 / squares.max(f64::MIN_POSITIVE);
    let (p, se) = (chance.alone, chance.alone_se);
    let effective_replicates =
        if se > 0.0 && p > 0.0 && p < 1.0 { (p * (1.0 - p) / (se * se)).min(kish) } else { kish };
    // The two-sided normal quantile of `Reported::LEVEL`.
    let z = statrs::distribution::Normal::standard().inverse_cdf(0.5 + Reported::LEVEL / 2.0);
    let interval = crate::stats::wilson(chance.alone, effective_replicates, z);
    let misleads = 1.0 - chance.right > chance.alone;
    Reported { specimens: chance.specimens, replicates, chance, interval, effective_replicates, selected, misleads }
}

/// What every follow-up's problem shares: the analysis, the contenders, their first
/// campaign and the discrepancy they carry.
struct Shared<'a> {
    run: &'a Run,
    cs: &'a [Contender],
    truths: usize,
    first: &'a [Option<FirstScores>],
    first_design: &'a FirstDesign,
    inadequacy: &'a [f64],
    transfer: &'a [f64],
}

impl Shared<'_> {
    /// Builds the problem of follow-up `f` from its predictions `pred` and hands it to `go`.
    fn with_problem<R>(&self, f: &FollowUp, pred: &refit::Predictions, go: impl FnOnce(&Problem<'_>) -> R) -> R {
        let run = self.run;
        let refits: Vec<Option<Refit<'_>>> = pred
            .scan
            .iter()
            .zip(self.first)
            .map(|(scan, first)| Some(Refit { scan: scan.as_deref()?, first: first.as_ref()? }))
            .collect();
        let sigma: Vec<f64> = f.observables.iter().map(|o| sigma_of(run, o)).collect();
        let fd = self.first_design;
        // The first campaign's group of the follow-up's walls (none on new walls), and the
        // follow-up's keys it did not read there.
        let group = run
            .obs
            .iter()
            .zip(&run.keys.of)
            .find(|(o, _)| f.new_group.is_none() && o.group == f.group)
            .map(|(_, &k)| run.keys.keys[k].0);
        let unseen: Vec<bool> = f
            .observables
            .iter()
            .map(|o| group.is_none_or(|g| !run.keys.keys.iter().any(|(kg, ko)| *kg == g && ko.same(o))))
            .collect();
        let problem = Problem {
            contenders: self.cs,
            sims: &pred.at_fit,
            refits: &refits,
            truths: self.truths,
            inadequacy: self.inadequacy,
            unseen_walls: f.new_group.is_some(),
            unseen_keys: &unseen,
            transfer: self.transfer,
            pair_margin: Some(run.analysis.margins.baseline),
            check_replicates: run.settings.check_replicates,
            first: Some(FirstCampaign {
                keys: &fd.keys,
                sigma: &fd.sigma,
                specimens: &fd.specimens,
                at_fit: &fd.at_fit,
            }),
            keys: &f.observables,
            sigma: &sigma,
            reading: run.settings.reading,
            bracket_deg: run.bracket_deg,
        };
        go(&problem)
    }
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

/// The section "The next experiment" of the discrepancy report (Markdown): the
/// contenders with their prior weights, and every follow-up with the probability that the
/// cause is named alone after it (at the budget and by the truth), the probability that it
/// stays among the models that share the weight, and the fewest specimens that reach the
/// target.
pub fn markdown(plan: &Plan) -> String {
    use std::fmt::Write;
    let mut md = String::new();
    let _ = writeln!(md, "\n## The next experiment\n");
    let truths = &plan.contenders[..plan.truths.min(plan.contenders.len())];
    let names: Vec<String> = truths
        .iter()
        .map(|c| {
            format!(
                "`{}` {:.2}{}",
                c.name,
                c.prior,
                if c.outside { " (outside the analysis's contenders)" } else { "" }
            )
        })
        .collect();
    let carried = |v: &[f64], extra: &[f64]| -> Vec<String> {
        truths
            .iter()
            .enumerate()
            .map(|(t, c)| (c, v.get(t).copied().unwrap_or(0.0) + extra.get(t).copied().unwrap_or(0.0)))
            .filter(|(_, v)| *v > 0.0)
            .map(|(c, v)| format!("`{}` ×{:.2}", c.name, (1.0 + v).sqrt()))
            .collect()
    };
    let (own, new_walls) = (carried(&plan.inadequacy, &[]), carried(&plan.inadequacy, &plan.transfer));
    let list = |v: &[String]| if v.is_empty() { "none".to_string() } else { v.join(", ") };
    let biased = format!(
        " Model discrepancy carried by the follow-ups drawn from a truth (a bias per key shared by their specimens, as \
         the root of the predictive variance it multiplies): on the first campaign's walls, where the truth misses \
         them beyond its predictive spread ({:.0} % χ² check), {}; on walls of a new kind, beside that, as far as it \
         misses a group of the first campaign when refit on the others, {}, and for every truth the contenders' \
         disagreement on those walls (the variance of their predictions there about their weighted mean).",
        100.0 * CHECK_LEVEL,
        list(&own),
        list(&new_walls)
    );
    let others: Vec<String> = plan.contenders[truths.len()..].iter().map(|c| format!("`{}`", c.name)).collect();
    let others = if others.is_empty() { String::new() } else { format!(" Refit beside them: {}.", others.join(", ")) };
    let _ = writeln!(
        md,
        "Contenders taken as the truth (the models that share the weight and the tie, with their pseudo-BMA+ weights \
         on the first campaign scaled to {:.2}; beside them, sharing {:.2}, the pair of the two best single effects \
         where the analysis of both campaigns could admit a pair, and the best effect the first campaign did not rank \
         among the contenders, so that none of the analysis's contenders is part of the promise): {}.{} Each follow-up: {} specimens, {} simulated data sets per truth, drawn from its \
         predictive at its fitted parameters; on each, every contender is refit on both campaigns over its range (leave \
         one specimen out, on the follow-up's walls from a grid run there) and scored as the analysis scores it. \
         *Named alone*: the tie check's two tests (2 standard errors, reversal rate under 5 %) clear every other \
         contender, the verdict's criterion; *90 % weight*: the truth alone holds 90 % of the pseudo-BMA+ weight ({} \
         bootstrap draws); *right*: the truth is among the models that share the weight.{} {} forward runs.\n",
        1.0 - OUTSIDE_PRIOR,
        OUTSIDE_PRIOR,
        names.join(", "),
        others,
        plan.settings.specimens,
        plan.settings.replicates,
        plan.settings.draws,
        biased,
        plan.runs
    );
    let truths: Vec<String> = truths.iter().map(|c| format!("alone if `{}`", c.name)).collect();
    // The most specimens the ladder tries (`DesignSettings::ladder`).
    let most = plan.settings.ladder().last().copied().unwrap_or(plan.settings.specimens);
    let _ = writeln!(
        md,
        "| follow-up | P(named alone) | P(90 % weight) | P(right) | {} | specimens to {:.0} % | runs |",
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
            r.to_target.map_or(format!("> {most}"), |n| n.to_string()),
            r.runs
        );
    }
    if let Some(b) = plan.best() {
        best_markdown(&mut md, plan, b, most);
    }
    md
}

/// The markdown of the best follow-up `b` of `plan`: whether any follow-up reaches the
/// target within `most` specimens, the promise re-estimated on fresh draws, what most
/// often stops each truth being named alone, and what the probabilities assume.
fn best_markdown(md: &mut String, plan: &Plan, b: &RankedFollowUp, most: usize) {
    use std::fmt::Write;
    if plan.ranked.iter().all(|r| r.to_target.is_none()) {
        let _ = writeln!(
            md,
            "\nNo follow-up of the menu names the cause alone with probability {:.2} within {} specimens: the \
             contenders are not told apart by these tests at an affordable size.",
            plan.settings.target, most
        );
    }
    let _ = writeln!(
        md,
        "\nBest: **{}**, {} specimens. Written as a study with empty measured-file templates in \
         `design/followup/`.",
        b.followup.name, plan.settings.specimens
    );
    if let Some(r) = &plan.reported {
        let _ = writeln!(
            md,
            "\nThe cause named alone after it with probability **{:.2}** ({:.0} % Monte Carlo interval {:.2}–{:.2}, \
             Wilson on {:.0} effective replicates): re-estimated on {} fresh simulated follow-ups per truth, drawn \
             on random streams disjoint from those that ranked the menu, since the best of many estimates runs \
             high even when each is unbiased (the optimizer's curse, Smith & Winkler 2006). The ranking's own \
             estimate was {:.2}; weights' criterion {:.2}, right {:.2}.",
            r.chance.alone,
            100.0 * Reported::LEVEL,
            r.interval.0,
            r.interval.1,
            r.effective_replicates,
            r.replicates,
            r.selected,
            r.chance.weights_alone,
            r.chance.right
        );
        if r.misleads {
            let _ = writeln!(md, "\n**{}**", misleading_words(r));
        }
    }
    let chance = plan.reported.as_ref().map_or(&b.at_budget, |r| &r.chance);
    let stops: Vec<String> = chance
        .blocked_by
        .iter()
        .zip(&chance.data_blocked_by)
        .enumerate()
        .filter_map(|(t, (row, data))| {
            let (c, share) =
                row.iter().copied().enumerate().max_by(|a, b| a.1.total_cmp(&b.1)).filter(|&(_, s)| s >= 0.005)?;
            Some(format!(
                "`{}` by `{}` ({:.2}, the data test {:.2})",
                plan.contenders.get(t)?.name,
                plan.contenders.get(c)?.name,
                share,
                data[c]
            ))
        })
        .collect();
    if !stops.is_empty() {
        let _ = writeln!(
            md,
            "\nWhat most often stops each truth being named alone after it (the contender the tie check fails to \
             clear, the share of the simulated follow-ups, and the share in which the data test does not separate \
             it): {}.",
            stops.join("; ")
        );
    }
    let _ = writeln!(
        md,
        "\nThese probabilities take the truth to be one of the truths above (the analysis's contenders and, \
         sharing {:.2} of the prior, the truths outside them), off by the discrepancy the first campaign shows \
         and, on what it did not read, by as much as the models disagree there. Real walls can differ from every \
         one of them in ways the first campaign does not show (docs/discrepancy.md, \"On data it did not make\", \
         scores the promise on walls the engine did not make).",
        OUTSIDE_PRIOR
    );
}

/// The caution of a follow-up that is likelier to mislead than to help
/// ([`Reported::misleads`]), one sentence.
pub fn misleading_words(r: &Reported) -> String {
    format!(
        "Likelier to mislead than to help: after this follow-up the true cause leaves the models that share the \
         weight with probability {:.2}, more than the {:.2} with which it is named alone; more data of this kind \
         would more often move the answer away from the truth than settle on it. Read the tie as it stands.",
        1.0 - r.chance.right,
        r.chance.alone
    )
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
