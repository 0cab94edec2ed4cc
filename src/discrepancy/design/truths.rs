//! The design's prior over truths ([`contenders`]): the models the first campaign weighs,
//! and beside them truths it does not, so that "none of these" is part of the promise.
//!
//! The analysis's pseudo-BMA+ weights are over the library it searched (an M-open
//! weighting, Yao, Vehtari, Simpson & Gelman 2018, *Bayesian Analysis* 13, 917–1007): they
//! say which of those models predicts best, not the probability that the walls are one of
//! them. A design that takes them as its prior over truths promises as if the cause were
//! among the contenders. Here the prior also holds, with the weight [`OUTSIDE_PRIOR`]:
//!
//! - **the pair of the two best single effects**, wherever the joint analysis of both
//!   campaigns could admit a pair ([`pairs_possible`]): the analysis adds pairs of its best
//!   one-parameter effects when the best single still misfits (`stages::add_pairs`), which
//!   a follow-up can bring about. Its first-campaign fit is the scan point of least
//!   summed score of its additive surrogate about the baseline (as `analysis::pairs`
//!   builds it), its held-out scores those of the leave-one-specimen-out refit
//!   ([`super::heldout`]); on new walls it is predicted from its singles' grids, so it needs
//!   no run of its own. It is refit and scored on every simulated follow-up as a
//!   challenger too.
//! - **the best single effect the first campaign did not rank among the contenders**.

use super::plan::{Contender, Made};
use super::refit::{heldout, scan_table, FirstValues};
use crate::discrepancy::candidate::{Candidate, SCATTER};
use crate::discrepancy::compare::per_specimen;
use crate::discrepancy::fit::Surface;
use crate::discrepancy::Run;
use std::sync::Arc;

/// The prior weight of the truths beyond the analysis's contenders (the pair of the best
/// singles, an effect not ranked among the contenders), shared equally among them; the
/// analysis's contenders share the rest in proportion to their weights. One part in five:
/// the weights are over the searched library, not probabilities that the walls are one of
/// its models (module documentation), and on the independent test bed every broken
/// promise was a tie with a model the design had not taken as a truth. The value is
/// stated, not fitted: no data set of the test bed chose it, so the calibration column
/// scores it on data it did not choose.
pub const OUTSIDE_PRIOR: f64 = 0.2;

/// The contenders of an analysis, the truths first, with their priors and held-out scores,
/// and how many of them, the first, are taken as the truth.
///
/// The truths: the models that share the weight and the members of the tie, at most
/// [`super::MAX_CONTENDERS`] (with one model holding the weight, the runner-up too), their
/// priors the pseudo-BMA+ weights renormalized over them to `1 − OUTSIDE_PRIOR`; then the
/// truths outside the analysis's (module documentation) sharing [`OUTSIDE_PRIOR`]
/// (`Contender::outside`). Beside them, up to [`super::MAX_CHALLENGERS`] in all, the models
/// the user's analysis of both campaigns will check for a tie: the rest of the tie and the
/// [`TIE_CHALLENGERS`](crate::discrepancy::TIE_CHALLENGERS) candidates ranked next to the
/// cause. Every contender is refit and scored on every simulated follow-up.
pub fn contenders(run: &Run) -> (Vec<Contender>, usize) {
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
    let mut extra: Vec<String> = names.split_off(names.len().min(super::MAX_CONTENDERS));
    let inside = names.len();
    // The truths outside the analysis's contenders.
    let pair = pairs_possible(run).then(|| best_pair(run)).flatten();
    let mut outside: Vec<Contender> = Vec::new();
    if let Some(p) = pair.filter(|p| !names.contains(&p.name)) {
        extra.retain(|n| *n != p.name);
        outside.push(p);
    }
    let unranked = a.candidates.iter().find(|r| {
        let c = &a.pool[r.index];
        c.effects.len() == 1 && !names.contains(&r.name) && !outside.iter().any(|o| o.name == r.name)
    });
    if let Some(r) = unranked {
        extra.retain(|n| *n != r.name);
        outside.extend(of_analysis(run, &r.name));
    }
    for r in a.candidates.iter().take(1 + crate::discrepancy::TIE_CHALLENGERS) {
        if !extra.contains(&r.name) {
            extra.push(r.name.clone());
        }
    }
    extra.retain(|n| !names.contains(n) && !outside.iter().any(|o| o.name == *n));
    extra.sort_by(|x, y| a.weights.of(y).total_cmp(&a.weights.of(x)));
    let mut out: Vec<Contender> = names.iter().filter_map(|n| of_analysis(run, n)).collect();
    let inside = inside.min(out.len());
    let total: f64 = out[..inside].iter().map(|c| c.prior).sum();
    let share = if outside.is_empty() { 1.0 } else { 1.0 - OUTSIDE_PRIOR };
    for c in &mut out {
        c.prior = share * if total > 0.0 { c.prior / total } else { 1.0 / inside.max(1) as f64 };
    }
    let n_out = outside.len();
    for mut c in outside {
        c.prior = OUTSIDE_PRIOR / n_out as f64;
        c.outside = true;
        out.push(c);
    }
    let truths = out.len();
    let room = super::MAX_CHALLENGERS.saturating_sub(truths);
    out.extend(extra.iter().filter_map(|n| of_analysis(run, n)).take(room).map(|mut c| {
        c.prior = if total > 0.0 { share * c.prior / total } else { 0.0 };
        c
    }));
    (out, truths)
}

/// A contender of the analysis's (`baseline`, a candidate or `scatter`): its weight as its
/// prior (renormalized by [`contenders`]) and its held-out scores per specimen.
fn of_analysis(run: &Run, name: &str) -> Option<Contender> {
    let a = &run.analysis;
    let scores = if name == "baseline" {
        a.baseline_scores.clone()
    } else {
        a.candidates.iter().find(|c| c.name == name)?.scores.clone()
    };
    let measures: Vec<f64> =
        scores.iter().enumerate().map(|(j, &s)| if run.obs[j].observable.pins() { s } else { 0.0 }).collect();
    let elpd = |s: &[f64]| per_specimen(s, &run.obs, &run.specimens).iter().map(|s| -s).collect();
    Some(Contender {
        name: name.to_string(),
        prior: a.weights.of(name),
        elpd: elpd(&scores),
        elpd_measures: elpd(&measures),
        outside: false,
        pair: a.candidates.iter().find(|c| c.name == name).is_some_and(|r| a.pool[r.index].surface.is_pair()),
        made: None,
    })
}

/// The analysis's one-parameter single effects, best held-out error first (the effects
/// `analysis::pairs` pairs).
fn singles(run: &Run) -> Vec<&Candidate> {
    let a = &run.analysis;
    a.candidates
        .iter()
        .map(|r| &a.pool[r.index])
        .filter(|c| c.effects.len() == 1 && c.surface.dims() == 1 && c.name() != SCATTER)
        .collect()
}

/// Whether the joint analysis of both campaigns could admit a pair: the library has two
/// one-parameter single effects to pair and the best candidate gains on the baseline (the
/// analysis adds pairs only then, when the best single still misfits: a follow-up can
/// make it misfit).
pub fn pairs_possible(run: &Run) -> bool {
    let a = &run.analysis;
    singles(run).len() >= 2 && a.candidates.first().is_some_and(|c| c.heldout_error < a.baseline_heldout_error)
}

/// The pair of the two best single effects as a contender: the analysis's own where it
/// ranked it, else built here ([`Made`]) and fitted on the first campaign (module
/// documentation).
fn best_pair(run: &Run) -> Option<Contender> {
    let s = singles(run);
    let (p, q) = (s.first()?, s.get(1)?);
    let candidate = Candidate {
        effects: vec![p.effects[0].clone(), q.effects[0].clone()],
        params: p.params.iter().chain(&q.params).cloned().collect(),
        kinds: p.kinds.clone(),
        surface: Surface::Pair {
            a: Box::new(p.surface.clone()),
            b: Box::new(q.surface.clone()),
            base: run.library.baseline.clone(),
        },
    };
    let name = candidate.name();
    let swapped = format!("{}+{}", q.effects[0].name, p.effects[0].name);
    // The analysis's own pair, whichever order it named it in.
    if let Some(r) = run.analysis.candidates.iter().find(|r| r.name == name || r.name == swapped) {
        return of_analysis(run, &r.name);
    }
    let values = FirstValues::of(run);
    let (table, points) = scan_table(run, &values.data(run), &candidate);
    let best = (0..table.all.len())
        .map(|i| (i, table.all[i].iter().sum::<f64>()))
        .fold((0, f64::INFINITY), |b, (i, v)| if v < b.1 { (i, v) } else { b });
    let (elpd, elpd_measures) = heldout(&table.pins, &table.all, &[], &[], 0);
    Some(Contender {
        name,
        prior: 0.0,
        elpd,
        elpd_measures,
        outside: true,
        pair: true,
        made: Some(Arc::new(Made { x: points[best.0].clone(), candidate })),
    })
}
