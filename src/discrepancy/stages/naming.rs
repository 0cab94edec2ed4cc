//! The confirmation runs and the naming: which candidates are run in full at their fitted
//! parameters, the gate that asks the readings before a candidate is confirmed or named
//! ([`crate::discrepancy::refute`]), and the cause named when it clears its margins.

use super::{Ctx, Screening};
use crate::discrepancy::analysis::{score, sort, Ranked};
use crate::discrepancy::candidate::Candidate;
use crate::discrepancy::effects::Effect;
use crate::discrepancy::fit::{Data, Surface};
use crate::discrepancy::held::HeldReading;
use crate::discrepancy::null::Margins;
use crate::discrepancy::prepare::effects_of;
use crate::discrepancy::progress::Progress;
use crate::discrepancy::refute::{self, Refutation};
use crate::discrepancy::simulate::{run_models, Outcome};
use crate::discrepancy::DiscrepancyError;

/// A full run of a candidate at its fitted parameters.
#[derive(Debug, Clone)]
pub(super) struct Confirmation {
    /// The candidate's index in the pool.
    pub(super) candidate: usize,
    /// The search coordinates of the run.
    pub(super) x: Vec<f64>,
    /// The effects at those coordinates.
    pub(super) effects: Vec<Effect>,
    /// The outcomes, `[group][realization]`.
    pub(super) outcomes: Vec<Vec<Outcome>>,
}

/// The candidates a confirmation round runs: of the two best that no reading refutes
/// (`refuted`, asked in the ranking's order until two are found), those not yet confirmed
/// and not the scatter hypothesis (which has no model to run), by pool index.
///
/// # Errors
/// Those of `refuted`.
pub(super) fn to_confirm<E>(
    ranked: &[Ranked],
    is_scatter: impl Fn(usize) -> bool,
    mut refuted: impl FnMut(&Ranked) -> Result<bool, E>,
) -> Result<Vec<usize>, E> {
    let mut best = Vec::with_capacity(2);
    for r in ranked {
        if best.len() == 2 {
            break;
        }
        if !refuted(r)? {
            best.push(r);
        }
    }
    Ok(best.into_iter().filter(|r| !r.confirmed && !is_scatter(r.index)).map(|r| r.index).collect())
}

/// The readings asked of a candidate before it is confirmed by a full run and before it is
/// named ([`crate::discrepancy::refute`]): the readings of the fit (the candidate's held-out scores
/// against the baseline's, [`refute::in_fit`]) and, for a candidate that may be
/// named (its held-out error below `can_name`: the baseline's less the gain margin), the
/// protocol's held reading at its fitted parameters, judged once per fit.
pub(super) struct Gate<'a> {
    /// The baseline's score of every observation.
    pub(super) base_scores: &'a [f64],
    /// The held-out error below which a candidate may be named.
    pub(super) can_name: f64,
    /// The protocol's reading the fit does not hold.
    pub(super) held: Option<&'a dyn HeldReading>,
    /// The walls' mean course height, m (the effects' parameters in courses).
    pub(super) course_m: f64,
    /// The held reading's judgements: the candidate's name, its coordinates' bits and what
    /// the reading said.
    pub(super) judged: std::cell::RefCell<Vec<(String, Vec<u64>, Option<Refutation>)>>,
    /// The refutations of the candidates at their latest fit, in the order found.
    pub(super) found: std::cell::RefCell<Vec<Refutation>>,
}

impl<'a> Gate<'a> {
    /// The gate of an analysis: a candidate may be named below the baseline's held-out
    /// error less the gain margin; `held` the protocol's held reading, if any.
    pub(super) fn new(
        screening: &'a Screening,
        margins: &Margins,
        held: Option<&'a dyn HeldReading>,
        course_m: f64,
    ) -> Gate<'a> {
        Gate {
            base_scores: &screening.base_scores,
            can_name: screening.base_he - margins.baseline,
            held,
            course_m,
            judged: std::cell::RefCell::new(vec![]),
            found: std::cell::RefCell::new(vec![]),
        }
    }
}

impl Gate<'_> {
    /// The reading that refutes `r` (the candidate `c` of the pool) at its current fit, if
    /// one does; recorded in [`Gate::found`].
    ///
    /// # Errors
    /// [`DiscrepancyError::Effect`] for effects that cannot take the fitted values, and the
    /// held reading's.
    pub(super) fn refuted(
        &self,
        r: &Ranked,
        c: &Candidate,
        data: Data<'_>,
        progress: Progress<'_>,
    ) -> Result<Option<Refutation>, DiscrepancyError> {
        let found = match refute::in_fit(r, self.base_scores, data) {
            Some(f) => Some(f),
            None => self.held_judgement(r, c, progress)?,
        };
        let mut all = self.found.borrow_mut();
        all.retain(|f| f.candidate != r.name);
        all.extend(found.clone());
        Ok(found)
    }

    /// The held reading's judgement of `r` at its fitted coordinates (`None` without a held
    /// reading, for the scatter hypothesis, which has no model to run, and for a candidate
    /// that cannot be named).
    pub(super) fn held_judgement(
        &self,
        r: &Ranked,
        c: &Candidate,
        progress: Progress<'_>,
    ) -> Result<Option<Refutation>, DiscrepancyError> {
        let Some(held) = self.held else { return Ok(None) };
        if c.is_scatter() || r.heldout_error >= self.can_name {
            return Ok(None);
        }
        let bits: Vec<u64> = r.x.iter().map(|v| v.to_bits()).collect();
        if let Some((_, _, j)) = self.judged.borrow().iter().find(|(n, b, _)| *n == r.name && *b == bits) {
            return Ok(j.clone());
        }
        let effects = effects_of(c, &r.x, self.course_m)?;
        let j = held.judge(&r.name, &r.parameters, &effects, progress)?;
        self.judged.borrow_mut().push((r.name.clone(), bits, j.clone()));
        Ok(j)
    }
}

/// Stage 5, confirmation runs: up to three rounds in which the two best candidates not
/// yet confirmed ([`to_confirm`]) are run as full ensembles at their fitted parameters
/// and re-scored with their surrogates re-centred on those runs
/// ([`Surface::Corrected`]); the ranking is sorted again after each round.
///
/// # Errors
/// [`DiscrepancyError::Effect`] for an effect that cannot take its fitted values.
pub(super) fn confirm(
    ctx: &Ctx<'_>,
    base_per: &[f64],
    pool: &mut [Candidate],
    ranked: &mut [Ranked],
    gate: &Gate<'_>,
    progress: Progress<'_>,
) -> Result<Vec<Confirmation>, DiscrepancyError> {
    let mut runs = Vec::new();
    for _round in 0..3 {
        let todo = to_confirm(
            ranked,
            |i| pool[i].is_scatter(),
            |r| gate.refuted(r, &pool[r.index], ctx.data, progress).map(|f| f.is_some()),
        )?;
        if todo.is_empty() {
            break;
        }
        for idx in todo {
            let pos = ranked.iter().position(|r| r.index == idx).unwrap_or(0);
            let x = ranked[pos].x.clone();
            progress(&format!("confirming {} by a full run at its fitted parameters", ranked[pos].name));
            let effects = effects_of(&pool[idx], &x, ctx.course_m)?;
            let outcomes = run_models(ctx.full, std::slice::from_ref(&effects), Some(&ctx.prep.baseline)).remove(0);
            let corrected = Candidate {
                surface: Surface::Corrected {
                    inner: Box::new(pool[idx].surface.clone()),
                    x0: x.clone(),
                    full: ctx.keys.simulated(&outcomes),
                },
                ..pool[idx].clone()
            };
            let mut r = score(&corrected, ctx.data, ctx.specimens, idx, base_per);
            r.confirmed = true;
            pool[idx] = corrected;
            ranked[pos] = r;
            runs.push(Confirmation { candidate: idx, x, effects, outcomes });
        }
        sort(ranked);
    }
    Ok(runs)
}

/// Stage 6, the cause: the best candidate that may be named (`eligible`: confirmed by a
/// full run, the scatter hypothesis, or any without confirmation runs) and that no reading
/// refutes (`refuted`, asked in the ranking's order), named when the screening's gain and
/// its own gain on the baseline both exceed the gain margin and its AICc is below the
/// baseline's. Re-scoring the best few by full runs and keeping the best is a selection the
/// null calibration does not repeat, so it may veto an alarm, never raise one.
///
/// # Errors
/// Those of `refuted`.
pub(super) fn name_cause<E>(
    ranked: &[Ranked],
    eligible: impl Fn(&Ranked) -> bool,
    screening: &Screening,
    gain_margin: f64,
    mut refuted: impl FnMut(&Ranked) -> Result<bool, E>,
) -> Result<Option<Ranked>, E> {
    let mut best = None;
    for r in ranked.iter().filter(|r| eligible(r)) {
        if !refuted(r)? {
            best = Some(r.clone());
            break;
        }
    }
    Ok(best.filter(|b| {
        screening.screen_gain > gain_margin
            && screening.base_he - b.heldout_error > gain_margin
            && b.information_criterion < screening.base_ic
    }))
}
