//! The data-independent part of an analysis: the observable keys of a design, the
//! effects searched and their parameter grids, the baseline's full run, the surrogate
//! library ([`build_library`]) and the baseline on independent layouts (the null pool),
//! gathered in a [`Prepared`] by [`prepare`].

use super::analysis::Models;
use super::candidate::Candidate;
use super::effects::{self, Effect, EffectDef};
use super::fit::{to_x, Surface};
use super::observations::{Observable, Observation};
use super::predictive::Simulated;
use super::simulate::{forward_runs, reread_outcomes, rereads, run_models, GroupSetup, Outcome, Setup, StageRuns};
use super::{DiscrepancyError, Settings};
use std::sync::Arc;

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
    /// have are an error of the caller, caught by [`observations::observations`](super::observations::observations)).
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
pub(super) struct Plan {
    pub(super) def: Arc<EffectDef>,
    pub(super) params: Vec<effects::ParamDef>,
    /// The grid's nodes: search coordinates, and the effect there (`None`: the node of
    /// the neutral value, the baseline's run).
    pub(super) nodes: Vec<(Vec<f64>, Option<Effect>)>,
}

/// The effect at search coordinates `x` (its values in the broad ranges; a wall of a
/// declared kind takes them in its own, [`Effect::for_kind`]).
fn effect_at(def: &Arc<EffectDef>, x: &[f64], course_m: f64) -> Result<Effect, DiscrepancyError> {
    Ok(Effect::at_search(def.clone(), x, course_m)?)
}

/// The surrogate grid of one effect: its nodes ([`Settings::grid_points`] intervals on one
/// axis, the node nearest the neutral value the baseline's; [`Settings::grid_points_2d`]
/// nodes per axis on two).
pub(super) fn plan(def: Arc<EffectDef>, s: &Settings, course_m: f64) -> Result<Plan, DiscrepancyError> {
    let params = def.params_for(course_m);
    let mut nodes = Vec::new();
    if params.len() == 1 {
        let xn = to_x(&params[0], params[0].neutral).clamp(0.0, 1.0);
        let g = s.grid_points;
        let half = 0.5 / g as f64;
        for k in 0..=g {
            let x = k as f64 / g as f64;
            if (x - xn).abs() >= half {
                nodes.push((vec![x], Some(effect_at(&def, &[x], course_m)?)));
            }
        }
        nodes.push((vec![xn], None));
        nodes.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    } else {
        let g = s.grid_points_2d;
        let axis: Vec<f64> = (0..g).map(|k| k as f64 / (g - 1) as f64).collect();
        for &a in &axis {
            for &b in &axis {
                nodes.push((vec![a, b], Some(effect_at(&def, &[a, b], course_m)?)));
            }
        }
    }
    Ok(Plan { def, params, nodes })
}

/// The effects a run searches: the settings' names, or every effect of `library`, less
/// the built-ins whose signature is the failure mechanism
/// ([`effects::MECHANISM_EFFECTS`]) when the data hold no mechanism observation
/// (`mechanism` false): an analysis of angles and displacements alone searches what it
/// searched before those effects existed, and less the built-ins searched only by name
/// ([`effects::NAMED_ONLY_EFFECTS`]), plus the settings' `also_effects`. Named in the
/// settings, they are searched always.
///
/// # Errors
/// [`DiscrepancyError::Effect`] for an unknown name.
pub fn searched(
    s: &Settings,
    library: &effects::Library,
    mechanism: bool,
) -> Result<Vec<Arc<EffectDef>>, DiscrepancyError> {
    if s.effects.is_empty() {
        let mut v: Vec<Arc<EffectDef>> = library
            .all()
            .into_iter()
            .filter(|d| mechanism || !effects::MECHANISM_EFFECTS.contains(&d.name.as_str()))
            .filter(|d| !effects::NAMED_ONLY_EFFECTS.contains(&d.name.as_str()))
            .collect();
        for name in &s.also_effects {
            let d = library.get(name)?;
            if !v.iter().any(|e| e.name == d.name) {
                v.push(d);
            }
        }
        return Ok(v);
    }
    Ok(s.effects.iter().map(|n| library.get(n)).collect::<Result<_, _>>()?)
}

/// The searched `defs` the setup's protocol reads: on a protocol that loads the wall in its
/// own plane ([`crate::protocol::Loading::loads_in_plane`]: the in-plane test), the default
/// search leaves out the effects it does not read
/// ([`effects::EffectDef::not_read_in_plane`]), and one named in `[discrepancy] effects`
/// or `also_effects` is refused by name; other protocols read every effect.
///
/// # Errors
/// [`DiscrepancyError::NotRead`] naming the first such effect named.
fn read_by_protocol(
    setup: &Setup,
    s: &Settings,
    defs: Vec<Arc<EffectDef>>,
) -> Result<Vec<Arc<EffectDef>>, DiscrepancyError> {
    if !setup.protocol.loading().loads_in_plane() {
        return Ok(defs);
    }
    let named = |n: &str| s.effects.iter().chain(&s.also_effects).any(|e| e == n);
    let mut out = Vec::with_capacity(defs.len());
    for d in defs {
        match d.not_read_in_plane() {
            None => out.push(d),
            Some(reason) if named(&d.name) => {
                return Err(DiscrepancyError::NotRead {
                    effect: d.name.clone(),
                    protocol: setup.protocol.name(),
                    reason,
                })
            }
            Some(_) => {}
        }
    }
    Ok(out)
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

impl Plan {
    /// The surrogate on the node values `sims` (`(coordinates, values per key)` in the
    /// nodes' order): an axis on one parameter, a tensor grid on two.
    pub(super) fn surface(&self, sims: Vec<(Vec<f64>, Vec<Simulated>)>) -> Surface {
        if self.params.len() == 1 {
            Surface::axis(sims.iter().map(|(x, _)| x[0]).collect(), sims.into_iter().map(|(_, s)| s).collect())
        } else {
            let mut x1: Vec<f64> = sims.iter().map(|(x, _)| x[0]).collect();
            x1.dedup();
            let mut x2: Vec<f64> = sims.iter().map(|(x, _)| x[1]).collect();
            x2.sort_by(f64::total_cmp);
            x2.dedup();
            Surface::Grid { x1, x2, sims: sims.into_iter().map(|(_, s)| s).collect() }
        }
    }

    /// The search coordinates of the effect's neutral values (where its grid is re-centred
    /// on the baseline's full run).
    pub(super) fn neutral(&self) -> Vec<f64> {
        self.params.iter().map(|q| to_x(q, q.neutral).clamp(0.0, 1.0)).collect()
    }
}

/// The raw outcomes of the surrogate grids, by effect name: every node's search
/// coordinates, and its effect with its outcomes `[group][realization]` (`None`: the node
/// of the neutral value, the baseline's first `realizations` layouts). The effect at a
/// node depends on the setup's walls (its length parameters scale with their mean course
/// height), so a node is read again only where its effect is the same. A follow-up that reads, on the analysis's
/// own walls, a key the analysis did not score (the mechanism, the other top measure)
/// reads it from these runs (`design::refit`): the same layouts, effects and protocol, so
/// the same outcomes a new run would give, bit for bit.
pub type GridRuns = std::collections::BTreeMap<String, Vec<(Vec<f64>, Option<(Effect, Vec<Vec<Outcome>>)>)>>;

/// The nodes of `grids` for plan `p`'s effect, if they are `p`'s nodes: the same search
/// coordinates and the same effect at each (an effect carries the setup's course height).
pub(super) fn same_nodes<'g>(
    grids: &'g GridRuns,
    p: &Plan,
) -> Option<&'g [(Vec<f64>, Option<(Effect, Vec<Vec<Outcome>>)>)]> {
    let nodes = grids.get(&p.def.name)?;
    let same = nodes.len() == p.nodes.len()
        && nodes.iter().zip(&p.nodes).all(|((y, o), (x, e))| y == x && o.as_ref().map(|(f, _)| f) == e.as_ref());
    same.then_some(nodes.as_slice())
}

/// The distinct declared kinds of the setup's walls, in order.
pub fn kinds(setup: &Setup) -> Vec<effects::WallKind> {
    let mut k: Vec<effects::WallKind> = setup.groups.iter().filter_map(|g| g.wall.kind).collect();
    k.sort_unstable();
    k.dedup();
    k
}

/// The setup with every group's realizations capped at `n`.
pub(super) fn with_realizations(setup: &Setup, n: u64) -> Setup {
    Setup {
        groups: setup.groups.iter().map(|g| GroupSetup { realizations: g.realizations.min(n), ..g.clone() }).collect(),
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
pub(super) fn effects_of(c: &Candidate, x: &[f64], course_m: f64) -> Result<Vec<Effect>, DiscrepancyError> {
    let mut out = Vec::new();
    let mut offset = 0;
    for def in &c.effects {
        let n = def.parameters.len();
        out.push(effect_at(def, &x[offset..offset + n], course_m)?);
        offset += n;
    }
    Ok(out)
}

/// The key labels, `GROUP observable`.
pub fn key_labels(setup: &Setup, keys: &Keys) -> Vec<String> {
    keys.keys.iter().map(|(g, o)| format!("{} {}", setup.groups[*g].name, o.label())).collect()
}

/// The data-independent part of an analysis: the baseline's full run, the surrogate
/// library, and the baseline on independent layouts (the null pool), for the observable
/// keys of a design. Many data sets of the same design are analysed against one
/// [`Prepared`] ([`analyze`](super::analyze)).
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The setup.
    pub setup: Setup,
    /// The observable keys of the design.
    pub keys: Keys,
    /// The baseline's full run.
    pub baseline: Vec<Vec<Outcome>>,
    /// The surrogate library.
    pub library: Models,
    /// The grids' outcomes the library was built from.
    pub grids: Arc<GridRuns>,
    /// The baseline on independent layouts, `[group][realization]`.
    pub null_pool: Vec<Vec<Outcome>>,
    /// The setup of the independent layouts.
    pub null_setup: Setup,
    /// The settings.
    pub settings: Settings,
    /// The effects that change nothing in a group (the group's own or a candidate): the
    /// analysis reuses the baseline's outcomes for a candidate there.
    pub inert: Vec<InertEffect>,
    /// The forward runs made, by stage: the baseline's full run, the surrogate grids and
    /// the null pool.
    pub forward_runs: Vec<StageRuns>,
}

/// Checks the settings, the setup's protocol ([`Setup::check_protocol`]) and the
/// observations against it: displacements at tilts the tilting table's steps reach (at
/// tilt 0 under the lateral load), and under the lateral load no collapse angle or
/// mechanism.
pub(super) fn check(setup: &Setup, obs: &[Observation], s: &Settings) -> Result<(), DiscrepancyError> {
    s.validate()?;
    setup.check_protocol()?;
    let gives = setup.protocol.observables();
    for o in obs {
        if !gives.gives(o.observable.output()) {
            return Err(DiscrepancyError::Observable {
                specimen: o.specimen.clone(),
                observable: o.observable.label(),
                protocol: setup.protocol.name(),
            });
        }
        if let Some(tilt_deg) = o.observable.tilt_deg() {
            if !gives.reaches_tilt(tilt_deg) {
                return Err(match gives.state_step_deg {
                    Some(step_deg) => DiscrepancyError::Tilt { specimen: o.specimen.clone(), tilt_deg, step_deg },
                    None => DiscrepancyError::LateralTilt { specimen: o.specimen.clone(), tilt_deg },
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
    prepare_with(setup, template, s, library, &super::quiet)
}

/// [`prepare`], reporting each stage and model to `progress` (see
/// [`super::Progress`]), and each effect that changes nothing in a group (a line
/// starting `warning:`; also in [`Prepared::inert`]).
///
/// # Errors
/// As [`prepare`].
pub fn prepare_with(
    setup: &Setup,
    template: &[Observation],
    s: &Settings,
    library: &effects::Library,
    progress: super::Progress<'_>,
) -> Result<Prepared, DiscrepancyError> {
    prepare_after(setup, template, s, library, None, progress)
}

/// [`prepare_with`] for a campaign analysed after `earlier` (the first campaign's
/// preparation, when the follow-up's study is analysed with it): every run of a group that
/// `earlier` ran the same way (the same walls, effects, realizations, protocol, solver and
/// master seed; the same grid nodes for an effect) is read from `earlier` instead of run
/// again, the same outcomes bit for bit; the rest is run. `None`: everything is run.
///
/// # Errors
/// As [`prepare`].
pub fn prepare_after(
    setup: &Setup,
    template: &[Observation],
    s: &Settings,
    library: &effects::Library,
    earlier: Option<&Prepared>,
    progress: super::Progress<'_>,
) -> Result<Prepared, DiscrepancyError> {
    check(setup, template, s)?;
    let defs = searched(s, library, template.iter().any(|o| o.observable.is_mechanism()))?;
    let defs = read_by_protocol(setup, s, defs)?;
    let inert = inert_effects(setup, &defs);
    for i in &inert {
        progress(&format!("warning: {i}"));
    }
    let keys = Keys::new(setup, template);
    let full = with_realizations(setup, s.extension_realizations);
    progress(&format!("baseline: full run of {} ({})", setup.protocol.name(), realizations_of(&full)));
    let earlier_full = earlier.map(|e| Earlier::new(e, &e.setup, &full, &e.baseline));
    let (baseline, baseline_runs) = baseline_of(&full, earlier_full.as_ref());
    for (g, outs) in full.groups.iter().zip(&baseline) {
        if outs.iter().all(|o| o.error.is_some()) {
            let error = outs.first().and_then(|o| o.error.clone()).unwrap_or_default();
            return Err(DiscrepancyError::Baseline { group: g.name.clone(), error });
        }
    }
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    progress(&format!(
        "surrogates: grids of {} effect(s) [{}] ({} per node)",
        defs.len(),
        names.join(", "),
        realizations_of(&with_realizations(setup, s.realizations))
    ));
    let earlier_grid = earlier.map(|e| Earlier::new(e, &e.setup, &with_realizations(setup, s.realizations), &[]));
    let (lib, grid_runs, grids) = build_library_from(setup, &keys, &baseline, s, &defs, earlier_grid.as_ref())?;
    let null_setup = Setup { seed: null_seed(setup.seed), ..with_realizations(setup, s.null_realizations) };
    progress(&format!("null pool: the baseline on independent layouts ({})", realizations_of(&null_setup)));
    let earlier_null = earlier.map(|e| Earlier::new(e, &e.null_setup, &null_setup, &e.null_pool));
    let (null_pool, null_runs) = baseline_of(&null_setup, earlier_null.as_ref());
    let forward_runs = vec![
        StageRuns::new("baseline", baseline_runs),
        StageRuns::new("surrogate grids", grid_runs),
        StageRuns::new("null pool", null_runs),
    ];
    Ok(Prepared {
        forward_runs,
        setup: setup.clone(),
        keys,
        baseline,
        library: lib,
        grids: Arc::new(grids),
        null_pool,
        null_setup,
        settings: s.clone(),
        inert,
    })
}

/// What an earlier preparation ran that a new one can read: for each group of the new
/// setup `setup`, the index of the same group in the earlier one's setup (the same
/// [`GroupSetup`], master seed, solver and protocol), with the earlier outcomes of one
/// model (`[group][realization]`) and its grids.
struct Earlier<'a> {
    /// `[group of the new setup]`: the earlier group's index.
    same: Vec<Option<usize>>,
    /// The earlier outcomes of the model in question (the baseline's full run, the null
    /// pool; empty for the grids).
    outcomes: &'a [Vec<Outcome>],
    grids: &'a GridRuns,
}

impl<'a> Earlier<'a> {
    /// `earlier`'s groups that are `setup`'s, run as `setup` runs them; `old` the setup the
    /// earlier preparation ran `outcomes`, the earlier outcomes of the model to read, with.
    fn new(earlier: &'a Prepared, old: &Setup, setup: &Setup, outcomes: &'a [Vec<Outcome>]) -> Earlier<'a> {
        let alike = old.seed == setup.seed && old.solver == setup.solver && old.protocol == setup.protocol;
        let same = setup
            .groups
            .iter()
            .map(|g| {
                let k = old.groups.iter().position(|o| o.name == g.name)?;
                (alike && old.groups[k].runs_alike(g)).then_some(k)
            })
            .collect();
        Earlier { same, outcomes, grids: &earlier.grids }
    }

    /// The earlier outcomes of group `g` of the new setup, if it was run alike with at
    /// least `n` realizations (the first `n`: the realizations are the same layouts).
    fn outcomes_of(&self, g: usize, n: usize) -> Option<Vec<Outcome>> {
        let k = self.same.get(g).copied().flatten()?;
        let o = self.outcomes.get(k)?;
        (o.len() >= n).then(|| o[..n].to_vec())
    }

    /// The earlier grids' outcomes for every node of `plans`, `[node of the models, in
    /// plan order][group]` (`None` for a model or group to run), where the earlier analysis
    /// ran the effect's grid on the same nodes; `None` when nothing can be read.
    fn grids(&self, plans: &[Plan], grid_setup: &Setup) -> Option<Vec<Vec<Option<Vec<Outcome>>>>> {
        let mut known = Vec::new();
        let mut any = false;
        for p in plans {
            let earlier = same_nodes(self.grids, p);
            for (k, (_, e)) in p.nodes.iter().enumerate() {
                let Some(e) = e else { continue };
                let row: Vec<Option<Vec<Outcome>>> = (0..grid_setup.groups.len())
                    .map(|g| {
                        let old = self.same.get(g).copied().flatten()?;
                        let (_, outs) = earlier?[k].1.as_ref()?;
                        let outs = outs.get(old)?;
                        let n = runs_of(grid_setup, g, std::slice::from_ref(e));
                        (outs.len() >= n).then(|| outs[..n].to_vec())
                    })
                    .collect();
                any |= row.iter().any(Option::is_some);
                known.push(row);
            }
        }
        any.then_some(known)
    }
}

/// The baseline's outcomes on `setup` (`[group][realization]`) and the runs made: every
/// group run, or read from `earlier` where it ran the group alike.
fn baseline_of(setup: &Setup, earlier: Option<&Earlier<'_>>) -> (Vec<Vec<Outcome>>, usize) {
    let known: Vec<Option<Vec<Outcome>>> =
        (0..setup.groups.len()).map(|g| earlier?.outcomes_of(g, runs_of(setup, g, &[]))).collect();
    let (outs, runs) = run_models_knowing(setup, &[vec![]], &[], &[known]);
    (outs.into_iter().next().unwrap_or_default(), runs)
}

/// The realizations a model (its effects `model`) runs on group `g` of `setup`: the
/// group's, or one for a deterministic wall without random input ([`forward_runs`]).
fn runs_of(setup: &Setup, g: usize, model: &[Effect]) -> usize {
    forward_runs(&Setup { groups: vec![setup.groups[g].clone()], ..setup.clone() }, &[model.to_vec()], false)
}

/// [`run_models`] with some outcomes known: `known[model][group]`, `Some` where the
/// model's outcomes on that group are read instead of run; `base` the outcomes to reuse
/// where a model does not act (empty: none, every group run). Returns the outcomes,
/// `[model][group][realization]`, and the runs made.
fn run_models_knowing(
    setup: &Setup,
    models: &[Vec<Effect>],
    base: &[Vec<Outcome>],
    known: &[Vec<Option<Vec<Outcome>>>],
) -> (super::simulate::Outcomes, usize) {
    let reuse = (!base.is_empty()).then_some(base);
    if known.iter().all(|k| k.iter().all(Option::is_none)) {
        return (run_models(setup, models, reuse), forward_runs(setup, models, reuse.is_some()));
    }
    let mut out: super::simulate::Outcomes = vec![vec![Vec::new(); setup.groups.len()]; models.len()];
    let mut runs = 0;
    for g in 0..setup.groups.len() {
        let todo: Vec<usize> =
            (0..models.len()).filter(|&m| known.get(m).and_then(|k| k[g].as_ref()).is_none()).collect();
        for m in 0..models.len() {
            if let Some(o) = known.get(m).and_then(|k| k[g].clone()) {
                out[m][g] = o;
            }
        }
        if todo.is_empty() {
            continue;
        }
        let one = Setup { groups: vec![setup.groups[g].clone()], ..setup.clone() };
        let ms: Vec<Vec<Effect>> = todo.iter().map(|&m| models[m].clone()).collect();
        let one_base = reuse.map(|b| vec![b[g].clone()]);
        runs += forward_runs(&one, &ms, one_base.is_some());
        let ran = run_models(&one, &ms, one_base.as_deref());
        for (&m, mut o) in todo.iter().zip(ran) {
            out[m][g] = o.swap_remove(0);
        }
    }
    (out, runs)
}

/// `GROUP × N realizations, …` of a setup.
fn realizations_of(setup: &Setup) -> String {
    let v: Vec<String> = setup.groups.iter().map(|g| format!("{} × {}", g.name, g.realizations)).collect();
    v.join(", ")
}

/// An effect that changes nothing in a group: an effect made only of restraint steps
/// (e.g. `restraint_stiffness`) on a wall without end restraints. The analysis reuses the
/// baseline's outcomes for it there, and says so.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct InertEffect {
    /// The effect's name.
    pub effect: String,
    /// The group.
    pub group: String,
    /// The group's own effect (the study's `effects`), not a searched candidate.
    pub own: bool,
}

impl std::fmt::Display for InertEffect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = if self.own { "the study's effect" } else { "candidate effect" };
        write!(
            f,
            "{what} {} changes nothing in group {} (its wall has no end restraints){}",
            self.effect,
            self.group,
            if self.own { "" } else { "; the baseline's outcomes stand for it there" }
        )
    }
}

/// The effects of `setup`'s groups and the searched `defs` that cannot act on a group
/// ([`effects::EffectDef::acts_on`]), group by group.
pub fn inert_effects(setup: &Setup, defs: &[Arc<EffectDef>]) -> Vec<InertEffect> {
    let mut out = Vec::new();
    for g in &setup.groups {
        for e in g.effects.iter().filter(|e| !e.def.acts_on(g.restrained)) {
            out.push(InertEffect { effect: e.def.name.clone(), group: g.name.clone(), own: true });
        }
        for d in defs.iter().filter(|d| !d.acts_on(g.restrained)) {
            out.push(InertEffect { effect: d.name.clone(), group: g.name.clone(), own: false });
        }
    }
    out
}

mod library;

pub use library::build_library;
use library::build_library_from;

#[cfg(test)]
mod tests;
