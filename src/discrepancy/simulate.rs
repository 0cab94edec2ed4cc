//! Running the model, baseline or extended by effects, as an ensemble with common random
//! numbers: realization `i` of a group uses the same generated layout (`Purpose::Layout`)
//! and the same effect draws ([`crate::effects::effect_rng`]) in every model, so that the
//! differences between models are the effects' and not the sampling's. The layouts are
//! made by [`crate::effects::realize`], as a study's run makes them: a study with the same
//! effects gives the same numbers.
//!
//! Every realization is loaded by the setup's protocol through the protocol seam, which
//! also says what each protocol gives to compare ([`Protocol::observed`],
//! [`crate::protocol::ProtocolRun::observed`]): the tilting table (the path the paper's data
//! take: collapse angle, displacements at every stable tilt, the failure mechanism) or the
//! static lateral load (the monitors' out-of-plane displacements under the load, as one
//! state at tilt 0°). The shaking table has no observable here and is refused
//! ([`Setup::check_protocol`]).

pub use super::outcome::Outcome;
use super::store::RunStore;
use crate::dem::SolverParams;
use crate::effects::Effect;
use crate::ensemble::{run_scheduled, Item};
use crate::generator::Wall;
use crate::loading::tilt::TiltParams;
use crate::protocol::{Protocol, RunOutcome};
use std::sync::Arc;

/// One group of walls the model is run for.
#[derive(Debug, Clone)]
pub struct GroupSetup {
    /// Group name (as in the observations).
    pub name: String,
    /// The wall description.
    pub wall: Wall,
    /// Realizations run for this group.
    pub realizations: u64,
    /// The walls have end restraints.
    pub restrained: bool,
    /// Every realization of the wall is the same layout (a wall without random input):
    /// a model without random effects then runs it once.
    pub deterministic: bool,
    /// The effects of the user's model for this group (the study's `effects`): the
    /// baseline of the analysis; candidates are added to them.
    pub effects: Vec<Effect>,
    /// Mean course height of the wall, m (scales the effects' length ranges).
    pub course_m: f64,
    /// The group's own loading protocol, of the setup's kind with this group's parameters;
    /// `None`: the setup's.
    pub protocol: Option<Protocol>,
}

impl GroupSetup {
    /// Whether `other` runs as this group does, but for the number of realizations: the
    /// same name (it seeds the effects' draws), walls ([`Wall::same_walls`]: the files
    /// they were read from aside), end restraints, effects, course height and protocol.
    /// Realization `i` of either is then the same run.
    pub fn runs_alike(&self, other: &GroupSetup) -> bool {
        self.name == other.name
            && self.wall.same_walls(&other.wall)
            && (self.restrained, self.deterministic) == (other.restrained, other.deterministic)
            && self.effects == other.effects
            && self.course_m == other.course_m
            && self.protocol == other.protocol
    }
}

/// What the model is run with: groups, master seed, solver and loading protocol.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Groups.
    pub groups: Vec<GroupSetup>,
    /// Master seed of the layouts and of the effects' random forms.
    pub seed: u64,
    /// Solver parameters.
    pub solver: SolverParams,
    /// The loading protocol with its parameters (the study's): [`Protocol::Tilt`] or
    /// [`Protocol::Lateral`].
    pub protocol: Protocol,
    /// Where runs are read from and kept ([`RunStore`]); `None`: every run is made.
    /// A run read is the same bit for bit as the run made again.
    pub store: Option<Arc<RunStore>>,
}

impl Setup {
    /// The run store's key of realization `realization` of group `group` extended by
    /// `effects` ([`RunStore`]): 64 hex digits, the SHA-256 of everything [`run_one`]
    /// reads, each written out by its `Debug` form (whose floats are the shortest text that
    /// reads back to the same bits): the build (`drystone --version`, so a run of another
    /// build is never read), the group's name (it seeds the effects' draws), its walls as
    /// [`Wall::same_walls`] compares them (the files they were read from aside), end
    /// restraints, course height, own effects and protocol, the setup's seed, solver and
    /// protocol, the realization and `effects`.
    pub fn run_key(&self, group: usize, realization: u64, effects: &[Effect]) -> String {
        let g = &self.groups[group];
        let text = format!(
            "{}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{}\noutcome",
            env!("DRYSTONE_BUILD"),
            g.name,
            g.wall.without_sources(),
            (g.restrained, g.deterministic),
            g.course_m.to_bits(),
            g.effects,
            g.protocol,
            self.seed,
            self.solver,
            self.protocol,
            effects,
            realization,
        );
        crate::files::sha256_hex(text.as_bytes())
    }

    /// The tilting table's parameters, for a tilting-table setup ([`Protocol::tilt`]).
    pub fn tilt(&self) -> Option<&TiltParams> {
        self.protocol.tilt()
    }

    /// Width of a simulated collapse angle's bracket, degrees (the protocol's
    /// [`crate::protocol::Observables`]: the tilting table's resolution); 0 for a protocol
    /// with no collapse angle.
    pub fn bracket_deg(&self) -> f64 {
        self.protocol.observables().collapse_bracket_deg.unwrap_or(0.0)
    }

    /// Whether the protocol gives displacements at tilt `tilt_deg`, degrees (the tilting
    /// table: multiples of its step; the lateral load: its one state at tilt 0).
    pub fn reaches_tilt(&self, tilt_deg: f64) -> bool {
        self.protocol.observables().reaches_tilt(tilt_deg)
    }

    /// Refuses a protocol the analysis cannot compare with measured data (the shaking
    /// table: no collapse angle, no displacement at a tilt).
    ///
    /// # Errors
    /// [`super::DiscrepancyError::Protocol`] naming it.
    pub fn check_protocol(&self) -> Result<(), super::DiscrepancyError> {
        match self.protocol.observed() {
            Ok(_) => Ok(()),
            Err(reason) => Err(super::DiscrepancyError::Protocol { protocol: self.protocol.name(), reason }),
        }
    }
}

/// Runs one realization of one group with `effects` applied to its layout.
pub fn run_one(setup: &Setup, group: usize, realization: u64, effects: &[Effect]) -> Outcome {
    let g = &setup.groups[group];
    let all: Vec<Effect> = g.effects.iter().chain(effects).cloned().collect();
    let layout = match crate::effects::realize(&g.wall, setup.seed, realization, &g.name, &all) {
        Ok((_, l)) => l,
        Err(e) => return Outcome::failed(e.to_string()),
    };
    // The observables of the protocol's run ([`Protocol::observed`], refused by
    // `Setup::check_protocol` when it has none); a run without them or with an error is a
    // failed outcome.
    let own = g.protocol.as_ref().unwrap_or(&setup.protocol);
    let protocol = own.observed().unwrap_or_else(|_| own.clone());
    let run = protocol.run(&layout, setup.solver);
    match run.observed() {
        Some(observed) => Outcome { observed, error: None },
        None => Outcome::failed(
            run.error().unwrap_or_else(|| format!("protocol {}: no observables", setup.protocol.name())),
        ),
    }
}

/// [`run_one`], read from the setup's run store where it holds the run, and kept there
/// when made ([`Setup::store`]).
fn run_stored(setup: &Setup, group: usize, realization: u64, effects: &[Effect]) -> Outcome {
    let Some(store) = &setup.store else { return run_one(setup, group, realization, effects) };
    let key = setup.run_key(group, realization, effects);
    if let Some(o) = store.get(&key) {
        return o;
    }
    let o = run_one(setup, group, realization, effects);
    let _ = store.put(&key, &o);
    o
}

/// Whether a model acts on a group: the baseline (no effect) always, a model when one of
/// its effects acts on the group's ends (`EffectDef::acts_on`).
fn acts(m: &[Effect], g: &GroupSetup) -> bool {
    m.is_empty() || m.iter().any(|e| e.def.acts_on(g.restrained))
}

/// Whether the setup's runs can be read again under another vertical-load system
/// ([`crate::protocol::Observed::reread`]): its protocol's drivers read the layout's
/// ([`crate::protocol::LoadingProtocol::READS_VERTICAL_LOAD_RIG`]).
pub(super) fn rereads(setup: &Setup) -> bool {
    setup.protocol.loading().reads_vertical_load_rig()
}

/// Where a model's outcomes come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// Its own runs: entry `k` of the models run.
    Run(usize),
    /// Entry `k` of the models run, read again with the model's effects that act on the
    /// readings only ([`crate::effects::EffectDef::acts_on_readings_only`]).
    Reread(usize),
    /// The outcomes to reuse (the baseline's), read again with those effects.
    Reused,
}

/// The schedule of [`run_models`]: the models run (each model's effects that move the wall,
/// in first-seen order, without repeats) and where each model's outcomes come from. On the
/// in-plane test a model's effects that act on the readings only make no run: the model is
/// the run of its other effects (the baseline's, when they are none and the baseline's
/// outcomes are given) read again. Elsewhere every model is run as it is.
fn schedule(setup: &Setup, models: &[Vec<Effect>], reused: bool) -> (Vec<Vec<Effect>>, Vec<Source>) {
    let split = rereads(setup);
    let mut run: Vec<Vec<Effect>> = Vec::new();
    let mut sources = Vec::with_capacity(models.len());
    for m in models {
        let reads = split && m.iter().any(|e| e.def.acts_on_readings_only());
        let wall: Vec<Effect> =
            if reads { m.iter().filter(|e| !e.def.acts_on_readings_only()).cloned().collect() } else { m.clone() };
        if reads && wall.is_empty() && reused {
            sources.push(Source::Reused);
            continue;
        }
        let k = match run.iter().position(|r| *r == wall) {
            Some(k) if reads => k,
            _ => {
                run.push(wall);
                run.len() - 1
            }
        };
        sources.push(if reads { Source::Reread(k) } else { Source::Run(k) });
    }
    (run, sources)
}

/// The forward runs [`run_models`] makes, `(model run, group, realization)` in its order,
/// for the models run of its [`schedule`]: every realization of every group a model acts
/// on (every group when nothing is `reused`), one realization of a deterministic group
/// whose effects draw nothing.
fn tasks(setup: &Setup, models: &[Vec<Effect>], reused: bool) -> Vec<(usize, usize, u64)> {
    let mut tasks = Vec::new();
    for (mi, m) in models.iter().enumerate() {
        for (gi, g) in setup.groups.iter().enumerate() {
            if reused && !acts(m, g) {
                continue;
            }
            let random = m.iter().chain(&g.effects).any(|e| e.def.is_random());
            let n = if g.deterministic && !random { g.realizations.min(1) } else { g.realizations };
            for r in 0..n {
                tasks.push((mi, gi, r));
            }
        }
    }
    tasks
}

/// The forward runs of one stage of an analysis: protocol runs of one wall, each a
/// realization of a group under a model (`drystone discrepancy`'s report lists them).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct StageRuns {
    /// The stage: `baseline`, `surrogate grids`, `null pool`, `confirmation`, `extended model`.
    pub stage: String,
    /// Forward runs made.
    pub runs: usize,
}

impl StageRuns {
    /// `runs` forward runs of `stage`.
    pub fn new(stage: &str, runs: usize) -> StageRuns {
        StageRuns { stage: stage.to_string(), runs }
    }
}

/// The number of forward runs (protocol runs of one wall) [`run_models`] makes for these
/// arguments (`reused`: an outcome to reuse is given), without running them.
pub fn forward_runs(setup: &Setup, models: &[Vec<Effect>], reused: bool) -> usize {
    let (run, _) = schedule(setup, models, reused);
    tasks(setup, &run, reused).len()
}

/// The outcomes of several models: `[model][group][realization]`.
pub type Outcomes = Vec<Vec<Vec<Outcome>>>;

/// One outcome read again with `reads`, the effects of a model that act on the readings
/// only, on top of the vertical-load system it was run with, for a wall of declared kind
/// `kind`: what a run with them gives, bit for bit ([`crate::protocol::Observed::reread`]). A failed run
/// stays failed; a run read again without a +x branch fails as a run would.
fn reread(o: &Outcome, reads: &[Effect], kind: Option<crate::effects::WallKind>, protocol: &str) -> Outcome {
    let Some(r) = o.observed.rig_reading.as_ref().filter(|_| o.error.is_none()) else {
        return o.clone();
    };
    let rig = reads.iter().fold(r.rig, |rig, e| e.on_rig(rig, kind));
    match o.observed.reread(rig) {
        Some(Some(observed)) => Outcome { observed, error: None },
        Some(None) => Outcome::failed(format!("protocol {protocol}: no observables")),
        None => o.clone(),
    }
}

/// Runs every model on every group and realization, in parallel on the current rayon pool;
/// the result does not depend on the number of threads. A model whose effects cannot act on
/// a group (e.g. `restraint_stiffness` on free walls) reuses `reuse`'s outcomes for it
/// (`reuse[group]`, the baseline's), when given. On the in-plane test a model's effects
/// that act on the readings only (`jack_tilt`, `rig_friction`) make no run: its outcomes
/// are those of its other effects (run once for all the models that share them, or
/// `reuse`'s when there are none) read again ([`schedule`]), the same numbers as its own
/// runs would give.
pub fn run_models(setup: &Setup, models: &[Vec<Effect>], reuse: Option<&[Vec<Outcome>]>) -> Outcomes {
    let (run, sources) = schedule(setup, models, reuse.is_some());
    let tasks = tasks(setup, &run, reuse.is_some());
    // Restrained walls creep longest near collapse: schedule them first.
    let items: Vec<Item> = tasks
        .iter()
        .enumerate()
        .map(|(index, &(mi, gi, r))| Item { index, group: gi, point: mi, realization: r })
        .collect();
    let cost: Vec<f64> = tasks.iter().map(|&(_, gi, _)| if setup.groups[gi].restrained { 2.0 } else { 1.0 }).collect();
    let results: Vec<Outcome> =
        run_scheduled(&items, &cost, "discrepancy", |it| run_stored(setup, it.group, it.realization, &run[it.point]));
    let mut ran: Outcomes = run.iter().map(|_| setup.groups.iter().map(|_| Vec::new()).collect()).collect();
    for ((mi, gi, _), o) in tasks.into_iter().zip(results) {
        ran[mi][gi].push(o);
    }
    if let Some(base) = reuse {
        for (mi, m) in run.iter().enumerate() {
            for (gi, g) in setup.groups.iter().enumerate() {
                if !acts(m, g) {
                    ran[mi][gi] = base[gi].clone();
                }
            }
        }
    }
    let empty: Vec<Vec<Outcome>> = setup.groups.iter().map(|_| Vec::new()).collect();
    models
        .iter()
        .zip(&sources)
        .map(|(m, src)| {
            let from = match *src {
                Source::Run(k) => return ran[k].clone(),
                Source::Reread(k) => &ran[k],
                Source::Reused => reuse.unwrap_or(&empty),
            };
            let reads: Vec<Effect> = m.iter().filter(|e| e.def.acts_on_readings_only()).cloned().collect();
            reread_outcomes(setup, from, &reads)
        })
        .collect()
}

/// One model's outcomes (`[group][realization]`) read again with `reads`, effects that act
/// on the readings only: what runs of the model with them give, bit for bit, on the
/// in-plane test ([`rereads`]); a run of another protocol, or a failed run, as it is.
pub(super) fn reread_outcomes(setup: &Setup, outcomes: &[Vec<Outcome>], reads: &[Effect]) -> Vec<Vec<Outcome>> {
    outcomes
        .iter()
        .zip(&setup.groups)
        .map(|(outs, g)| outs.iter().map(|o| reread(o, reads, g.wall.kind, setup.protocol.name())).collect())
        .collect()
}
