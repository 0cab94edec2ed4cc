//! The stages on small hand-made inputs whose answer is stated independently.

use super::naming::to_confirm;
use super::*;
use crate::discrepancy::fit::Surface;
use crate::discrepancy::observations::{Measure, Observable};

fn ranked(name: &str, index: usize, heldout_error: f64, information_criterion: f64) -> Ranked {
    Ranked {
        name: name.into(),
        parameters: vec![],
        heldout_error,
        difference_se: 0.0,
        information_criterion,
        confirmed: false,
        x: vec![],
        index,
        scores: vec![],
        predictive: vec![],
    }
}

fn angle(specimen: &str, group: &str, value: f64, sigma: f64) -> Observation {
    Observation { specimen: specimen.into(), group: group.into(), observable: Observable::CollapseAngle, value, sigma }
}

fn screening(base_he: f64, base_ic: f64, screen_gain: f64) -> Screening {
    Screening {
        base_scores: vec![],
        base_per: vec![],
        base_he,
        base_misfit: base_he,
        base_ic,
        ranked: vec![],
        screen_gain,
    }
}

fn margins(baseline: f64, misfit: f64) -> Margins {
    Margins { baseline, misfit, replicates: 0, false_alarms: (0, 0), false_alarm_interval: (0.0, 1.0) }
}

const EXACT: Reading = Reading {
    angle_deg: 0.0,
    displacement_cm: 0.0,
    misreading: 0.0,
    neighbour_joint: 0.0,
    force_kn: 0.0,
    drift_pct: 0.0,
    stiffness_kn_per_mm: 0.0,
    modulus_mpa: 0.0,
    asymmetry_kn: 0.0,
};

/// Five collapse angles 10, 12, 14, 16, 18° of one group: sample variance 40/4 = 10 deg²;
/// the model's spread there 1° (variance 1) and exact readings: the data show
/// σ² = 10 − 1 = 9, σ = 3° on 4 degrees of freedom. A stated σ of 0.5° becomes 3°; one of
/// 5° stays. The displacements of two specimens at two keys give one degree of freedom,
/// below the four an estimate needs: they keep their stated σ.
#[test]
fn the_sigma_rule_takes_the_spread_the_data_show_beyond_the_model() {
    let mut obs: Vec<Observation> =
        [10.0, 12.0, 14.0, 16.0, 18.0].iter().enumerate().map(|(i, &v)| angle(&format!("S{i}"), "G", v, 0.5)).collect();
    obs[4].sigma = 5.0;
    let disp = Observable::Displacement { measure: Measure::MeanOfLeftCenterRight, tilt_deg: 5.0 };
    obs.push(Observation { specimen: "S0".into(), group: "G".into(), observable: disp, value: 1.0, sigma: 0.01 });
    obs.push(Observation { specimen: "S1".into(), group: "G".into(), observable: disp, value: 3.0, sigma: 0.01 });
    let key = vec![0, 0, 0, 0, 0, 1, 1];
    let baseline = [
        Simulated { mean: 14.0, sd: 1.0, n: 9, err: 0.0, heights: crate::discrepancy::predictive::Heights::NONE },
        Simulated { mean: 2.0, sd: 0.1, n: 9, err: 0.0, heights: crate::discrepancy::predictive::Heights::NONE },
    ];
    let s = apply_sigma_rule(&mut obs, &key, &baseline, EXACT);
    let (sd, dof) = s.estimate[0].unwrap();
    assert!((sd - 3.0).abs() < 1e-12 && dof == 4, "{:?}", s.estimate);
    assert_eq!(s.estimate[1], None);
    assert_eq!(s.stated, vec![0.5, 0.5, 0.5, 0.5, 5.0, 0.01, 0.01]);
    assert_eq!(s.model_sd, vec![1.0, 0.1]);
    let got: Vec<f64> = obs.iter().map(|o| o.sigma).collect();
    assert!(got[..4].iter().all(|g| (g - 3.0).abs() < 1e-12), "{got:?}");
    assert_eq!(&got[4..], &[5.0, 0.01, 0.01]);
    // The rule is the same on a synthetic data set: applied again, nothing moves.
    let mut again = obs.clone();
    s.rule(EXACT).apply(&mut again, &key);
    assert_eq!(again, obs);
}

/// Pairs are tried only when the best single both misfits (mean score per specimen on
/// the checked observations above the misfit margin) and gains (held-out error below the
/// baseline's by more than the gain margin): a fit of 3 per specimen.
#[test]
fn pairs_are_tried_when_the_best_single_gains_and_still_misfits() {
    let best = ranked("a", 0, 2.0, 10.0);
    assert!(pairs_wanted(&best, 3.0, 2.6, &margins(0.5, 2.9)));
    assert!(!pairs_wanted(&best, 3.0, 2.6, &margins(0.5, 3.0)), "fits within the misfit margin");
    assert!(!pairs_wanted(&best, 3.0, 2.5, &margins(0.5, 2.9)), "gains no more than the margin");
}

/// Three single candidates with held-out errors 1.2, 0.9 and 0.9 rank b (pool index 1),
/// c (2), a (0): equal errors keep pool order. Of two pairs, the one below the best single
/// less the margin (0.9 − 0.1 = 0.8) with a lower AICc is admitted and ranks first; the
/// one at 0.85 is not.
#[test]
fn ranking_orders_by_heldout_error_then_pool_order_and_admits_pairs_that_beat_the_best() {
    let mut r = vec![ranked("a", 0, 1.2, 5.0), ranked("b", 1, 0.9, 4.0), ranked("c", 2, 0.9, 3.0)];
    sort(&mut r);
    let names = |r: &[Ranked]| r.iter().map(|r| r.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&r), ["b", "c", "a"]);
    let pairs = vec![ranked("a+b", 3, 0.85, 1.0), ranked("b+c", 4, 0.7, 3.9), ranked("a+c", 5, 0.5, 4.5)];
    admit_pairs(&mut r, pairs, 0.9 - 0.1, 4.0);
    assert_eq!(names(&r), ["b+c", "b", "c", "a"]);
}

/// A confirmation round runs the two best that are neither confirmed nor the scatter
/// hypothesis; the third is never run, however close.
#[test]
fn a_confirmation_round_runs_the_two_best_unconfirmed_mechanisms() {
    let mut r = vec![ranked("a", 4, 0.5, 0.0), ranked("scatter", 7, 0.6, 0.0), ranked("c", 2, 0.7, 0.0)];
    assert_eq!(to_confirm(&r, |i| i == 7, |_| Ok::<bool, ()>(false)).unwrap(), vec![4]);
    r[0].confirmed = true;
    assert_eq!(to_confirm(&r, |i| i == 7, |_| Ok::<bool, ()>(false)).unwrap(), Vec::<usize>::new());
    assert_eq!(to_confirm(&r, |_| false, |_| Ok::<bool, ()>(false)).unwrap(), vec![7]);
}

/// With a gain margin of 0.3 and the baseline at held-out error 2.0, AICc 50: the best
/// eligible candidate (the unconfirmed one ranked first is skipped) is named when the
/// screening gain (0.5) and its own gain (2.0 − 1.6 = 0.4) exceed 0.3 and its AICc (40)
/// is below 50; with a screening gain of 0.25, or an AICc of 55, nothing is named.
#[test]
fn a_cause_is_named_only_when_both_gains_clear_the_margin_and_its_aicc_the_baseline() {
    let mut first = ranked("unconfirmed", 0, 1.0, 10.0);
    first.confirmed = false;
    let mut second = ranked("confirmed", 1, 1.6, 40.0);
    second.confirmed = true;
    let r = vec![first, second];
    let eligible = |r: &Ranked| r.confirmed;
    let named = name_cause(&r, eligible, &screening(2.0, 50.0, 0.5), 0.3, |_| Ok::<bool, ()>(false)).unwrap();
    assert_eq!(named.map(|n| n.name), Some("confirmed".to_string()));
    assert!(name_cause(&r, eligible, &screening(2.0, 50.0, 0.25), 0.3, |_| Ok::<bool, ()>(false)).unwrap().is_none());
    assert!(name_cause(&r, eligible, &screening(2.0, 50.0, 0.5), 0.45, |_| Ok::<bool, ()>(false)).unwrap().is_none());
    let mut high_ic = r.clone();
    high_ic[1].information_criterion = 55.0;
    assert!(name_cause(&high_ic, eligible, &screening(2.0, 50.0, 0.5), 0.3, |_| Ok::<bool, ()>(false))
        .unwrap()
        .is_none());
    assert!(name_cause(&r, |_| false, &screening(2.0, 50.0, 0.5), 0.3, |_| Ok::<bool, ()>(false)).unwrap().is_none());
}

/// A candidate a reading refutes is passed over: the next eligible one is named, and a
/// confirmation round runs the two best that no reading refutes.
#[test]
fn a_refuted_candidate_is_neither_confirmed_nor_named() {
    let mut a = ranked("a", 0, 1.0, 10.0);
    a.confirmed = true;
    let mut b = ranked("b", 1, 1.2, 20.0);
    b.confirmed = true;
    let r = vec![a, b, ranked("c", 2, 1.4, 30.0), ranked("d", 3, 1.5, 30.0)];
    let refutes_a = |x: &Ranked| Ok::<bool, ()>(x.name == "a");
    let named = name_cause(&r, |r: &Ranked| r.confirmed, &screening(2.0, 50.0, 0.5), 0.3, refutes_a).unwrap();
    assert_eq!(named.map(|n| n.name), Some("b".to_string()));
    // Only the refuted one eligible: nothing is named.
    let refutes_ab = |x: &Ranked| Ok::<bool, ()>(x.name == "a" || x.name == "b");
    assert!(name_cause(&r, |r: &Ranked| r.confirmed, &screening(2.0, 50.0, 0.5), 0.3, refutes_ab).unwrap().is_none());
    // The two best not refuted are b (confirmed) and c.
    assert_eq!(to_confirm(&r, |_| false, refutes_a).unwrap(), vec![2]);
    assert_eq!(to_confirm(&r, |_| false, refutes_ab).unwrap(), vec![2, 3]);
}

/// The tie of a cause with two challengers over four specimens (two observations each):
/// challenger b differs by 1, 3, 1, 3 per specimen (sum 8, standard error
/// √4 · sd = 2 · 2/√3 = 2.31: separated by the data) and c by −2, 5, −3, 8 (sum 8,
/// standard error 2 · 5.48 = 10.95: tied by the data). At reversal rates 0 and 0, only c
/// is tied; at 0.05 for b, b is tied by the design too.
#[test]
fn the_tie_holds_the_challengers_the_design_or_the_data_cannot_separate() {
    let obs: Vec<Observation> = (0..8).map(|j| angle(&format!("S{}", j / 2), "G", 0.0, 1.0)).collect();
    let specimens = observations::specimens(&obs);
    let mut cause = ranked("a", 0, 0.0, 0.0);
    cause.scores = vec![0.0; 8];
    let mut b = ranked("b", 1, 0.0, 0.0);
    b.scores = vec![0.5, 0.5, 1.0, 2.0, 0.0, 1.0, 3.0, 0.0];
    let mut c = ranked("c", 2, 0.0, 0.0);
    c.scores = vec![-2.0, 0.0, 5.0, 0.0, -3.0, 0.0, 8.0, 0.0];
    let (zeros, keys) = (vec![0.0; 8], vec![0; 8]);
    let data = Data { obs: &obs, y: &zeros, key: &keys, weight: &zeros, reading: EXACT, bracket_deg: 0.5 };
    let rates = |b: f64| [Reversal { all: b, measures: b }, Reversal { all: 0.0, measures: 0.0 }];
    let tie = tie_of(&cause, &[&b, &c], &rates(0.0), data, &specimens);
    assert_eq!(tie.members, ["a", "c"]);
    assert_eq!(tie.checks.len(), 2);
    assert!((tie.checks[0].difference_se - 4.0 / 3.0f64.sqrt()).abs() < 1e-12, "{:?}", tie.checks[0]);
    let sd_c = {
        let d = [-2.0f64, 5.0, -3.0, 8.0];
        let m = 2.0;
        (d.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 3.0).sqrt()
    };
    assert!((tie.checks[1].difference_se - 2.0 * sd_c).abs() < 1e-12, "{:?}", tie.checks[1]);
    let tie = tie_of(&cause, &[&b, &c], &rates(0.05), data, &specimens);
    assert_eq!(tie.members, ["a", "b", "c"]);
}

/// The verdict's table: a named cause explains the data when its extended model passes
/// its check, else it is a partial explanation; without one, a baseline whose held-out
/// error exceeds the misfit margin is unexplained, else there is no effect.
#[test]
fn the_verdict_follows_the_cause_its_check_and_the_misfit_margin() {
    assert_eq!(verdict(true, true, 0.0, 1.0), Verdict::Explained);
    assert_eq!(verdict(true, false, 0.0, 1.0), Verdict::Unexplained);
    assert_eq!(verdict(false, false, 1.5, 1.0), Verdict::Unexplained);
    assert_eq!(verdict(false, true, 1.0, 1.0), Verdict::NoEffect);
    assert_eq!(verdict(false, false, 0.5, 1.0), Verdict::NoEffect);
}

/// Screening on five collapse angles 21, 21.5, 22, 21.25, 21.75° (σ = 0.5°, exact
/// readings) against a baseline at 20° from one realization (a Gaussian predictive of
/// sd σ): each specimen scores ln σ + ½ ln 2π + ½ ((y − 20)/σ)². A candidate whose surface
/// is the baseline everywhere gains nothing and pays the AICc of one parameter,
/// 2 + 2·1·2/(5 − 1 − 1); one whose mean runs linearly from 20° to 22° over its axis fits
/// any mean, so leaving specimen i out it predicts the mean of the other four, missing by
/// (5/4)(yᵢ − ȳ): it ranks first, and its gain is the screening's statistic.
#[test]
fn screening_scores_the_baseline_and_ranks_the_candidates_by_their_heldout_error() {
    let ys = [21.0, 21.5, 22.0, 21.25, 21.75];
    let sigma = 0.5;
    let obs: Vec<Observation> = ys.iter().enumerate().map(|(i, &y)| angle(&format!("S{i}"), "G", y, sigma)).collect();
    let y: Vec<f64> = ys.to_vec();
    let key = vec![0usize; 5];
    let weight = vec![1.0; 5];
    let data = Data { obs: &obs, y: &y, key: &key, weight: &weight, reading: EXACT, bracket_deg: 0.0 };
    let specimens = observations::specimens(&obs);
    let at = |mean: f64| {
        vec![Simulated { mean, sd: 0.0, n: 1, err: 0.0, heights: crate::discrepancy::predictive::Heights::NONE }]
    };
    let defs = crate::effects::Library::builtin();
    let candidate = |name: &str, means: [f64; 3]| {
        let def = defs.get(name).unwrap();
        Candidate {
            params: def.params_for(0.2),
            effects: vec![def],
            kinds: vec![],
            surface: Surface::axis(vec![0.0, 0.5, 1.0], means.iter().map(|&m| at(m)).collect()),
        }
    };
    let lib = Models {
        baseline: at(20.0),
        candidates: vec![candidate("kn_scale", [20.0; 3]), candidate("initial_lean", [20.0, 21.0, 22.0])],
        readings_pairs: vec![],
        readings_triples: vec![],
    };
    let s = screen(&lib, data, &specimens);
    let c = sigma.ln() + 0.5 * (2.0 * std::f64::consts::PI).ln();
    let base: Vec<f64> = ys.iter().map(|y| c + 0.5 * ((y - 20.0) / sigma).powi(2)).collect();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9 * b.abs().max(1.0);
    assert!(s.base_scores.iter().zip(&base).all(|(a, b)| close(*a, *b)), "{:?}", s.base_scores);
    let base_he = base.iter().sum::<f64>() / 5.0;
    assert!(close(s.base_he, base_he) && close(s.base_ic, 2.0 * base.iter().sum::<f64>()), "{s:?}");
    let mean = ys.iter().sum::<f64>() / 5.0;
    let loso: f64 = ys.iter().map(|y| c + 0.5 * (1.25 * (y - mean) / sigma).powi(2)).sum::<f64>() / 5.0;
    assert_eq!(s.ranked.iter().map(|r| r.name.as_str()).collect::<Vec<_>>(), ["initial_lean", "kn_scale"]);
    let (best, flat) = (&s.ranked[0], &s.ranked[1]);
    assert!((best.heldout_error - loso).abs() < 1e-6, "{} vs {loso}", best.heldout_error);
    assert!((s.screen_gain - (base_he - loso)).abs() < 1e-6, "{}", s.screen_gain);
    assert!(close(flat.heldout_error, base_he), "{} vs {base_he}", flat.heldout_error);
    assert!(close(flat.information_criterion, s.base_ic + 2.0 + 4.0 / 3.0), "{}", flat.information_criterion);
}
