//! Each contender's predictions of a follow-up over its whole parameter range, so that a
//! simulated follow-up is analysed as the user's analysis of both campaigns will analyse
//! it: every contender refit on both campaigns, leave one specimen out.
//!
//! **Where the predictions come from.** On the keys the first campaign already has (more
//! specimens of a group read as before), a contender's own first-campaign surrogate. On
//! keys it does not have (the mechanism or a monitor not read, walls of another height,
//! length or end restraint), a grid of runs on the follow-up's walls built as the
//! analysis builds its library ([`crate::discrepancy::Settings::grid_points`] nodes per
//! axis at [`crate::discrepancy::Settings::realizations`] layouts, the baseline at
//! [`crate::discrepancy::Settings::extension_realizations`], each grid re-centred on it at
//! the effect's neutral value; a pair additive about that baseline; the scatter hypothesis
//! on it). One grid per effect and wall serves every contender, every follow-up of that
//! wall and every simulated replicate (common random numbers: the analysis's layouts).
//!
//! **The refit.** The summed score of every observation at every scan point of a
//! contender's parameters (101 on one axis, 21 × 21 on two, the points
//! [`crate::discrepancy::Surface`]'s fits scan) is tabulated once for the first campaign
//! and once per simulated follow-up; each leave-one-specimen-out fold, on the measures
//! ([`Observable::pins`]) of both campaigns, is then a sum over that table and its
//! minimum. The analysis polishes the scan's best point with Brent's method; the design
//! keeps the scan's point (0.01 of the range on one axis, 0.05 on two), which moves a
//! held-out score by far less than a specimen's own.
//!
//! What the design still does not repeat of the user's analysis: the full runs that
//! confirm the two best candidates at their fitted points (on the follow-up's walls the
//! contenders are scored on their grids), the margins and the pairs the ranking may add.

use super::plan::{Contender, FollowUp};
use crate::discrepancy::candidate::{Candidate, SCATTER};
use crate::discrepancy::compare::{per_specimen, specimen_weights};
use crate::discrepancy::fit::{scan_points, Data, Surface};
use crate::discrepancy::observations::Observable;
use crate::discrepancy::predictive::Simulated;
use crate::discrepancy::prepare::{course_height, plan, same_nodes, with_realizations};
use crate::discrepancy::simulate::{run_models, GroupSetup, Outcome, Setup};
use crate::discrepancy::{DiscrepancyError, Run};
use std::collections::BTreeMap;

/// A contender's first-campaign scores at every scan point of its parameters: per scan
/// point and specimen (the analysis's specimen order), the summed score of the specimen's
/// measures ([`Observable::pins`]) and of all its observations, nats.
#[derive(Debug, Clone)]
pub struct FirstScores {
    /// `[point][specimen]`, the measures.
    pub pins: Vec<Vec<f64>>,
    /// `[point][specimen]`, every observation.
    pub all: Vec<Vec<f64>>,
    /// `[point][key]`: the contender's predictions of the first campaign's keys there.
    pub scan: Vec<Vec<Simulated>>,
}

/// A contender refit on both campaigns: its predictions of the follow-up's keys at every
/// scan point (`[point][key]`) and its first campaign's scores there.
#[derive(Debug, Clone, Copy)]
pub struct Refit<'a> {
    /// `[point][key]` on the follow-up's keys.
    pub scan: &'a [Vec<Simulated>],
    /// The first campaign's scores at the same points.
    pub first: &'a FirstScores,
}

/// The candidate of a contender, with its fit on the first campaign (`None`: the
/// baseline).
fn candidate_of<'r>(run: &'r Run, c: &'r Contender) -> Option<(&'r Candidate, &'r [f64])> {
    if let Some(m) = &c.made {
        return Some((&m.candidate, &m.x));
    }
    let a = &run.analysis;
    let r = a.candidates.iter().find(|r| r.name == c.name)?;
    Some((&a.pool[r.index], &r.x))
}

/// The first campaign's readings and their weights (a specimen's displacements share one),
/// owned, for a [`Data`] view of the analysis's observations.
pub(super) struct FirstValues {
    y: Vec<f64>,
    weight: Vec<f64>,
}

impl FirstValues {
    /// The readings and weights of `run`'s observations.
    pub(super) fn of(run: &Run) -> FirstValues {
        FirstValues { y: run.obs.iter().map(|o| o.value).collect(), weight: specimen_weights(&run.obs) }
    }

    /// The analysis's data: `run`'s observations with these readings and weights.
    pub(super) fn data<'a>(&'a self, run: &'a Run) -> Data<'a> {
        Data {
            obs: &run.obs,
            y: &self.y,
            key: &run.keys.of,
            weight: &self.weight,
            reading: run.settings.reading,
            bracket_deg: run.bracket_deg,
        }
    }
}

/// The first campaign's scores of every contender with parameters, tabulated at its scan
/// points (`None`: the baseline, which has none).
pub fn first_scores(run: &Run, cs: &[Contender]) -> Vec<Option<FirstScores>> {
    let values = FirstValues::of(run);
    let data = values.data(run);
    cs.iter().map(|c| Some(scan_table(run, &data, candidate_of(run, c)?.0).0)).collect()
}

/// One candidate's first-campaign scores at every scan point of its parameters
/// ([`FirstScores`]) and the scan points (search coordinates).
pub(super) fn scan_table(run: &Run, data: &Data<'_>, cand: &Candidate) -> (FirstScores, Vec<Vec<f64>>) {
    let (mut pins, mut all, mut scan) = (Vec::new(), Vec::new(), Vec::new());
    let points = scan_points(&cand.surface);
    for x in &points {
        let sims = cand.surface.at(x);
        let scores: Vec<f64> = (0..run.obs.len()).map(|j| data.score(&sims, j)).collect();
        scan.push(sims);
        all.push(per_specimen(&scores, &run.obs, &run.specimens));
        pins.push(per_specimen(&data.split_scores(&scores).0, &run.obs, &run.specimens));
    }
    (FirstScores { pins, all, scan }, points)
}

/// A contender's held-out log scores per specimen of both campaigns, refit leave one
/// specimen out on the measures: the first campaign's specimens, whose summed scores per
/// scan point and specimen are `first_pins` (measures) and `first_all` (every
/// observation), `[point][specimen]`, then the first `n` of a follow-up's, `new_pins` and
/// `new_all` (unread when `n` is 0). Each specimen is scored at the scan point of least
/// summed score of the others' measures (the first of equals). Returns `(elpd,
/// elpd_measures)`, nats, one per specimen.
pub fn heldout(
    first_pins: &[Vec<f64>],
    first_all: &[Vec<f64>],
    new_pins: &[Vec<f64>],
    new_all: &[Vec<f64>],
    n: usize,
) -> (Vec<f64>, Vec<f64>) {
    let s1 = first_pins.first().map_or(0, Vec::len);
    let new_sum = |p: usize| if n == 0 { 0.0 } else { new_pins[p][..n].iter().sum::<f64>() };
    let total: Vec<f64> = (0..first_pins.len()).map(|p| first_pins[p].iter().sum::<f64>() + new_sum(p)).collect();
    let at = |t: &[Vec<f64>], u: &[Vec<f64>], p: usize, s: usize| if s < s1 { t[p][s] } else { u[p][s - s1] };
    let mut elpd = Vec::with_capacity(s1 + n);
    let mut measures = Vec::with_capacity(s1 + n);
    for s in 0..s1 + n {
        let mut best = (0, f64::INFINITY);
        for (p, tot) in total.iter().enumerate() {
            let v = tot - at(first_pins, new_pins, p, s);
            if v < best.1 {
                best = (p, v);
            }
        }
        elpd.push(-at(first_all, new_all, best.0, s));
        measures.push(-at(first_pins, new_pins, best.0, s));
    }
    (elpd, measures)
}

/// The first campaign as a design ([`super::problem::FirstCampaign`], owned): its keys,
/// each key's σ (the largest the analysis used for it), the keys each specimen reads (a
/// mechanism's kind and start: every category of its group), and every contender's
/// predictions of the keys at its fit.
#[derive(Debug, Clone)]
pub struct FirstDesign {
    /// The keys.
    pub keys: Vec<Observable>,
    /// The σ of each key.
    pub sigma: Vec<f64>,
    /// The keys each specimen reads, in the analysis's specimen order.
    pub specimens: Vec<Vec<usize>>,
    /// `[contender][key]` at the first campaign's fit.
    pub at_fit: Vec<Vec<Simulated>>,
}

/// The first campaign's design for the contenders `cs` of `run`.
pub fn first_design(run: &Run, cs: &[Contender]) -> FirstDesign {
    let keys: Vec<Observable> = run.keys.keys.iter().map(|(_, o)| *o).collect();
    let mut sigma = vec![0.0f64; keys.len()];
    for (o, &k) in run.obs.iter().zip(&run.keys.of) {
        sigma[k] = sigma[k].max(o.sigma);
    }
    // A specimen's categories are read as one of their set (every key of the set: its
    // kind, its start); a number alone.
    let family = |o: &Observable| o.category_set().map_or(0, |s| s.index() + 1);
    let specimens = run
        .specimens
        .iter()
        .map(|name| {
            let mut which: Vec<usize> = Vec::new();
            for (o, &k) in run.obs.iter().zip(&run.keys.of) {
                if &o.specimen != name {
                    continue;
                }
                let f = family(&o.observable);
                if f == 0 {
                    which.push(k);
                } else {
                    let g = run.keys.keys[k].0;
                    which.extend(
                        run.keys
                            .keys
                            .iter()
                            .enumerate()
                            .filter(|(_, (kg, ko))| *kg == g && family(ko) == f)
                            .map(|(i, _)| i),
                    );
                }
            }
            which.sort_unstable();
            which.dedup();
            which
        })
        .collect();
    let at_fit = cs
        .iter()
        .map(|c| match candidate_of(run, c) {
            Some((cand, x)) => cand.surface.at(x),
            None => run.library.baseline.clone(),
        })
        .collect();
    FirstDesign { keys, sigma, specimens, at_fit }
}

/// Every contender's predictions of one follow-up: at its first-campaign fit
/// (`at_fit[contender][key]`, what a simulated follow-up is drawn from) and at every scan
/// point of its parameters (`scan[contender]`, `None` for the baseline), with the forward
/// runs made for them.
#[derive(Debug, Clone)]
pub struct Predictions {
    /// `[contender][key]` at the first campaign's fit.
    pub at_fit: Vec<Vec<Simulated>>,
    /// `[contender][point][key]`.
    pub scan: Vec<Option<Vec<Vec<Simulated>>>>,
    /// Forward runs made for this follow-up (0: its wall's grids were run before, or the
    /// first campaign's surrogates answer).
    pub runs: usize,
}

/// The runs of one wall: the baseline's (the full run) and every effect's grid nodes
/// (`None`: the node of the neutral value, the baseline's first layouts).
#[derive(Debug, Clone, Default)]
pub struct WallRuns {
    base: Vec<Outcome>,
    grid_realizations: usize,
    nodes: BTreeMap<String, Vec<(Vec<f64>, Option<Vec<Outcome>>)>>,
}

/// The runs of the follow-ups' walls, by group name (shared by every follow-up of a wall).
pub type RunCache = BTreeMap<String, WallRuns>;

/// The predictions of every contender for the keys of follow-up `f` (module
/// documentation). `setup` is the analysis's.
///
/// # Errors
/// [`DiscrepancyError::Effect`] for an effect that cannot take a node's values,
/// [`DiscrepancyError::Design`] for a follow-up of an unknown group.
pub fn predictions(
    run: &Run,
    setup: &Setup,
    f: &FollowUp,
    cs: &[Contender],
    cache: &mut RunCache,
) -> Result<Predictions, DiscrepancyError> {
    let existing = setup.groups.iter().position(|g| g.name == f.group);
    // Keys the first campaign has for this group: the fitted surrogates answer.
    if let Some(g) = existing.filter(|_| f.new_group.is_none()) {
        let idx: Option<Vec<usize>> =
            f.observables.iter().map(|o| run.keys.keys.iter().position(|(kg, ko)| *kg == g && ko.same(o))).collect();
        if let Some(idx) = idx {
            let pick = |all: Vec<Simulated>| -> Vec<Simulated> { idx.iter().map(|&k| all[k]).collect() };
            let mut at_fit = Vec::new();
            let mut scan = Vec::new();
            for c in cs {
                match candidate_of(run, c) {
                    Some((cand, x)) => {
                        at_fit.push(pick(cand.surface.at(x)));
                        scan.push(Some(scan_points(&cand.surface).iter().map(|p| pick(cand.surface.at(p))).collect()));
                    }
                    None => {
                        at_fit.push(pick(run.library.baseline.clone()));
                        scan.push(None);
                    }
                }
            }
            return Ok(Predictions { at_fit, scan, runs: 0 });
        }
    }
    let group = match (&f.new_group, existing) {
        (Some(g), _) => g.clone(),
        (None, Some(g)) => setup.groups[g].clone(),
        (None, None) => return Err(DiscrepancyError::Design { specimen: f.group.clone(), observable: f.name.clone() }),
    };
    let runs = wall_runs(run, setup, &group, cs, cache)?;
    let wall = &cache[&group.name];
    let sims_of =
        |outs: &[Outcome]| -> Vec<Simulated> { f.observables.iter().map(|o| Simulated::of(outs, o)).collect() };
    let full = sims_of(&wall.base);
    let base_grid = sims_of(&wall.base[..wall.grid_realizations.min(wall.base.len())]);
    let course_m = course_height(setup);
    // One effect's surface on the follow-up's keys: its grid re-centred on the baseline.
    let single = |def: &std::sync::Arc<crate::effects::EffectDef>| -> Result<Surface, DiscrepancyError> {
        let p = plan(def.clone(), &run.settings, course_m)?;
        let nodes = &wall.nodes[&def.name];
        let sims: Vec<(Vec<f64>, Vec<Simulated>)> =
            nodes.iter().map(|(x, o)| (x.clone(), o.as_deref().map_or_else(|| base_grid.clone(), sims_of))).collect();
        Ok(Surface::Corrected { inner: Box::new(p.surface(sims)), x0: p.neutral(), full: full.clone() })
    };
    let mut at_fit = Vec::new();
    let mut scan = Vec::new();
    for c in cs {
        let Some((cand, x)) = candidate_of(run, c) else {
            at_fit.push(full.clone());
            scan.push(None);
            continue;
        };
        let surface = match cand.effects.as_slice() {
            [] => {
                debug_assert_eq!(c.name, SCATTER);
                let angle = f.observables.iter().map(Observable::is_angle).collect();
                let mechanism = f.observables.iter().map(Observable::is_mechanism).collect();
                Surface::Scatter { base: full.clone(), angle, mechanism }
            }
            [a] => single(a)?,
            [a, b] => Surface::Pair { a: Box::new(single(a)?), b: Box::new(single(b)?), base: full.clone() },
            _ => return Err(DiscrepancyError::Design { specimen: f.group.clone(), observable: c.name.clone() }),
        };
        at_fit.push(surface.at(x));
        scan.push(Some(scan_points(&surface).iter().map(|p| surface.at(p)).collect()));
    }
    Ok(Predictions { at_fit, scan, runs })
}

/// Runs, once per wall, the baseline and the grid of every effect of the contenders on
/// `group`'s walls, into `cache`; returns the runs made now. On a group of the analysis's
/// own setup (a follow-up of its walls that reads another key), the baseline and the grid
/// of every effect the analysis searched are the analysis's runs ([`Run::baseline`],
/// [`Run::grids`]): the same layouts, effects, grid nodes and protocol, so the outcomes a
/// new run would give, bit for bit, without a run.
fn wall_runs(
    run: &Run,
    setup: &Setup,
    group: &GroupSetup,
    cs: &[Contender],
    cache: &mut RunCache,
) -> Result<usize, DiscrepancyError> {
    let s = &run.settings;
    let course_m = course_height(setup);
    let mut defs = Vec::new();
    for c in cs {
        if let Some((cand, _)) = candidate_of(run, c) {
            for d in &cand.effects {
                if !defs.iter().any(|x: &std::sync::Arc<crate::effects::EffectDef>| x.name == d.name) {
                    defs.push(d.clone());
                }
            }
        }
    }
    let mut made = 0;
    let one = Setup { groups: vec![group.clone()], ..setup.clone() };
    let full = with_realizations(&one, s.extension_realizations.max(1));
    let grid = with_realizations(&one, s.realizations.max(1));
    // The analysis's own group, as the analysis ran it.
    let own = setup.groups.iter().position(|g| g.name == group.name).filter(|&g| {
        setup.groups[g].runs_alike(group)
            && run.baseline.get(g).is_some_and(|b| b.len() == full.groups[0].realizations as usize)
    });
    let wall = cache.entry(group.name.clone()).or_default();
    if wall.base.is_empty() {
        match own {
            Some(g) => wall.base = run.baseline[g].clone(),
            None => {
                let o = run_models(&full, &[vec![]], None);
                wall.base = o[0][0].clone();
                made += wall.base.len();
            }
        }
    }
    wall.grid_realizations = grid.groups[0].realizations as usize;
    let base_grid = vec![wall.base[..wall.grid_realizations.min(wall.base.len())].to_vec()];
    if let Some(g) = own {
        for d in &defs {
            if wall.nodes.contains_key(&d.name) {
                continue;
            }
            // The same nodes with the same effects (an effect's length parameters scale
            // with the setup's course height).
            if let Some(nodes) = same_nodes(&run.grids, &plan(d.clone(), s, course_m)?) {
                let nodes = nodes.iter().map(|(x, o)| (x.clone(), o.as_ref().map(|(_, o)| o[g].clone()))).collect();
                wall.nodes.insert(d.name.clone(), nodes);
            }
        }
    }
    let todo: Vec<_> = defs.into_iter().filter(|d| !wall.nodes.contains_key(&d.name)).collect();
    let plans = todo.iter().map(|d| plan(d.clone(), s, course_m)).collect::<Result<Vec<_>, _>>()?;
    let models: Vec<Vec<crate::effects::Effect>> =
        plans.iter().flat_map(|p| p.nodes.iter().filter_map(|(_, e)| e.clone().map(|e| vec![e]))).collect();
    if models.is_empty() {
        return Ok(made);
    }
    let outcomes = run_models(&grid, &models, Some(&base_grid));
    let mut next = outcomes.into_iter();
    for p in &plans {
        // An effect that cannot act on these walls reuses the baseline's runs: none made.
        let acts = p.def.acts_on(group.restrained);
        let mut nodes = Vec::new();
        for (x, e) in &p.nodes {
            let o = e.as_ref().map(|_| next.next().map(|mut m| m.swap_remove(0)).unwrap_or_default());
            made += o.as_ref().filter(|_| acts).map_or(0, Vec::len);
            nodes.push((x.clone(), o));
        }
        wall.nodes.insert(p.def.name.clone(), nodes);
    }
    Ok(made)
}
