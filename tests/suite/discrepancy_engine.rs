//! The discrepancy engine's forward runs are the study's: its baseline predictive means
//! are the means of `drystone run` on the same study (collapse angles as the middles of
//! their brackets, displacements at every observed tilt), realization by realization; the
//! lateral load goes through the same protocol seam, and an analysis of its displacements
//! finds a joint stiffness by the elastic 1/Kn scaling.

use drystone::discrepancy::{analyze, analyze_held, prepare, quiet, run_models, DiscrepancyError, HeldReading};
use drystone::discrepancy::{Measure, Observable, Observation, Refutation};
use drystone::discrepancy::{Reading, Settings, Simulated, Verdict};
use drystone::ensemble::Shard;
use drystone::study::discrepancy::setup_of;
use drystone::study::{run_study, Study};
use std::path::PathBuf;

#[test]
fn the_baseline_predictive_means_are_the_study_run_means() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let study = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
    let n = 3;
    let study = Study { realizations: n, ..study };
    let rows = run_study(&study, Shard::ALL);
    let setup = setup_of(&study, n);
    let tilt = setup.tilt().expect("a tilting-table study");
    assert_eq!((tilt.step_deg, tilt.resolution_deg), {
        let t = study.protocol.tilt().unwrap();
        (t.step_deg, t.resolution_deg)
    });
    let outs = run_models(&setup, &[vec![]], None).remove(0);
    for (g, group) in study.groups.iter().enumerate() {
        let mine: Vec<_> = rows.iter().filter(|r| r.group == group.name).collect();
        let mid: Vec<f64> = mine
            .iter()
            .map(|r| {
                let a = r.collapse.collapse_angle_deg.unwrap();
                r.collapse.first_unstable_deg.map_or(a, |b| 0.5 * (a + b))
            })
            .collect();
        let sim = Simulated::of(&outs[g], &Observable::CollapseAngle);
        assert_eq!(sim.n, n as usize);
        assert!((sim.mean - drystone::stats::mean(&mid)).abs() < 1e-12, "{}: {} vs {:?}", group.name, sim.mean, mid);
        // The displacement at the first tilt step, mean of the three top points.
        let t = study.protocol.tilt().unwrap().step_deg;
        let ob = Observable::Displacement { measure: Measure::MeanOfLeftCenterRight, tilt_deg: t };
        let sim = Simulated::of(&outs[g], &ob);
        let run: Vec<f64> = mine
            .iter()
            .map(|r| {
                let i = r.tilt.tilt_deg.iter().position(|&x| (x - t).abs() < 1e-9).unwrap();
                (r.tilt.disp_top_left_cm[i] + r.tilt.disp_top_centre_cm[i] + r.tilt.disp_top_right_cm[i]) / 3.0
            })
            .collect();
        assert!((sim.mean - drystone::stats::mean(&run)).abs() < 1e-12, "{}: {} vs {:?}", group.name, sim.mean, run);
    }
}

fn lateral_study() -> Study {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    Study::from_file(&root.join("tests/studies/good/mini_lateral.toml")).unwrap()
}

/// The settings of the lateral-load analyses below (one realization, a grid of 4
/// intervals, `kn_scale` alone), their setup, and the specimens of the `free` group at
/// `scale` times the model's own displacement under the load (three specimens at 0.99, 1
/// and 1.01 of it, σ 1 % of it): data made by scaling the baseline's reading by hand.
fn lateral_analysis(study: &Study) -> (Settings, drystone::discrepancy::Setup, impl Fn(f64) -> Vec<Observation>) {
    let s = Settings {
        realizations: 1,
        extension_realizations: 1,
        null_realizations: 1,
        grid_points: 4,
        null_replicates: 40,
        check_replicates: 40,
        bootstrap: 100,
        effects: vec!["kn_scale".into()],
        scatter: false,
        reading: Reading {
            angle_deg: 0.5,
            displacement_cm: 0.0,
            misreading: 0.0,
            neighbour_joint: 0.0,
            ..Reading::default()
        },
        ..Settings::default()
    };
    let setup = setup_of(study, s.most_realizations());
    let model = run_models(&setup, &[vec![]], None).remove(0);
    let ob = Observable::Displacement { measure: Measure::MeanOfLeftCenterRight, tilt_deg: 0.0 };
    let free = study.groups.iter().position(|g| g.name == "free").unwrap();
    let at_model = model[free][0].value(&ob).unwrap();
    assert!(at_model > 0.01, "{at_model} cm");
    let data = move |scale: f64| -> Vec<Observation> {
        [0.99, 1.0, 1.01]
            .iter()
            .enumerate()
            .map(|(i, f)| Observation {
                specimen: format!("free{i}"),
                group: "free".into(),
                observable: ob,
                value: scale * at_model * f,
                sigma: 0.01 * at_model,
            })
            .collect()
    };
    (s, setup, data)
}

/// A reading the fit does not hold, made by hand: it refutes the candidates it is told to
/// and records every candidate it is asked of, with its fitted parameters.
struct HandReading {
    refutes: &'static [&'static str],
    asked: std::sync::Mutex<Vec<(String, Vec<(String, f64)>, usize)>>,
}

impl HeldReading for HandReading {
    fn name(&self) -> &str {
        "hand"
    }
    fn judge(
        &self,
        name: &str,
        parameters: &[(String, f64)],
        effects: &[drystone::effects::Effect],
        _: drystone::discrepancy::Progress<'_>,
    ) -> Result<Option<Refutation>, DiscrepancyError> {
        self.asked.lock().unwrap().push((name.into(), parameters.to_vec(), effects.len()));
        Ok(self.refutes.contains(&name).then(|| Refutation {
            candidate: name.into(),
            reading: "hand".into(),
            nats: 10.0,
            words: "refuted by hand".into(),
        }))
    }
    fn report(
        &self,
        _: &drystone::discrepancy::Run,
        _: drystone::discrepancy::Progress<'_>,
    ) -> Result<Option<drystone::discrepancy::HeldReport>, DiscrepancyError> {
        Ok(None)
    }
}

/// A cause that a reading refutes is not named: on displacements three times the model's
/// (where `kn_scale` near 1/3 is named, the test above), a held reading that refutes
/// `kn_scale` leaves the baseline's misfit unexplained, with `kn_scale` listed as refuted
/// and out of every confirmation; one that refutes nothing changes nothing. The reading is
/// asked of the candidate at its fitted parameters, with its effects.
#[test]
fn a_cause_that_a_held_reading_refutes_is_not_named() {
    let study = lateral_study();
    let (s, setup, data) = lateral_analysis(&study);
    let prep = prepare(&setup, &data(3.0), &s, &study.library).unwrap();
    let plain = analyze(&prep, data(3.0), study.seed).unwrap();
    let none = HandReading { refutes: &[], asked: Default::default() };
    let held = analyze_held(&prep, data(3.0), study.seed, Some(&none), &quiet).unwrap();
    assert_eq!(held.analysis.cause.as_ref().map(|c| &c.name), plain.analysis.cause.as_ref().map(|c| &c.name));
    assert_eq!(held.analysis.verdict, plain.analysis.verdict);
    assert!(held.analysis.refuted.is_empty());
    let asked = none.asked.lock().unwrap().clone();
    let cause = plain.analysis.cause.as_ref().expect("kn_scale named without the reading");
    assert!(
        asked.iter().any(|(n, p, e)| n == "kn_scale" && *p == cause.parameters && *e == 1),
        "asked {asked:?}, fitted {:?}",
        cause.parameters
    );

    // The models whose wall is the baseline's (a held reading of them reads the baseline's
    // runs): the scatter hypothesis, and a candidate whose every fitted value is its
    // parameter's neutral value, read from the library's definitions, not from the search
    // coordinates the product compares.
    for r in &plain.analysis.candidates {
        let neutral = r.name != "scatter"
            && r.parameters.iter().all(|(key, v)| {
                let (effect, name) = key.split_once('.').expect("effect.param");
                let def = study.library.get(effect).expect("a library effect");
                let n = def.parameters.iter().find(|q| q.name == name).expect("its parameter").neutral;
                (v - n).abs() <= 1e-12 * n.abs().max(1.0)
            });
        assert_eq!(plain.is_baseline_model(&r.name), r.name == "scatter" || neutral, "{}: {:?}", r.name, r.parameters);
    }
    assert!(!plain.is_baseline_model("kn_scale"), "kn_scale is fitted away from its neutral factor");
    assert!(!plain.is_baseline_model("no_such_effect"));

    let kn = HandReading { refutes: &["kn_scale"], asked: Default::default() };
    let run = analyze_held(&prep, data(3.0), study.seed, Some(&kn), &quiet).unwrap();
    let a = &run.analysis;
    assert_eq!(a.cause, None, "named {:?}", a.cause.as_ref().map(|c| &c.name));
    assert_eq!(a.verdict, Verdict::Unexplained);
    assert_eq!(a.refuted.len(), 1, "{:?}", a.refuted);
    assert_eq!((a.refuted[0].candidate.as_str(), a.refuted[0].reading.as_str()), ("kn_scale", "hand"));
    assert!(a.candidates.iter().all(|c| !c.confirmed), "a refuted candidate is not confirmed");
}

/// The lateral load through the protocol seam: every group's outcome is one state at
/// tilt 0 holding the top monitors' out-of-plane displacements under the load, the columns
/// `lateral_disp_{left,centre,right}_cm` of `drystone run` on the same study (first sweep
/// point), and no collapse angle.
#[test]
fn the_lateral_load_gives_the_study_run_displacements_under_the_load() {
    let study = lateral_study();
    let rows = run_study(&study, Shard::ALL);
    let setup = setup_of(&study, 1);
    assert!(setup.tilt().is_none() && setup.bracket_deg() == 0.0);
    let outs = run_models(&setup, &[vec![]], None).remove(0);
    let ob = Observable::Displacement { measure: Measure::MeanOfLeftCenterRight, tilt_deg: 0.0 };
    for (g, group) in study.groups.iter().enumerate() {
        let row = rows.iter().find(|r| r.group == group.name && r.point == 0).unwrap();
        let want =
            [row.lateral.lateral_disp_left_cm, row.lateral.lateral_disp_centre_cm, row.lateral.lateral_disp_right_cm]
                .map(Option::unwrap);
        let o = &outs[g][0];
        assert_eq!(o.observed.tilt_deg, [0.0], "{}", group.name);
        assert_eq!(o.observed.top_cm, [want], "{}", group.name);
        assert_eq!((o.observed.collapse_deg, o.value(&Observable::CollapseAngle)), (None, None));
        let sim = Simulated::of(&outs[g], &ob);
        assert!((sim.mean - (want[0] + want[1] + want[2]) / 3.0).abs() < 1e-15, "{}: {sim:?}", group.name);
    }
    // The free wall moves towards +y, the side the pressure pushes it to.
    assert!(outs[1][0].observed.top_cm[0][1] > 0.0, "{:?}", outs[1][0]);
}

/// Measured displacements of the free wall under the lateral load three times the model's
/// (three specimens, ±1 %): with joints elastic and fully compressed the displacement
/// scales as 1/Kn (Kn and Ks together), so the analysis names `kn_scale` with a factor
/// near 1/3; the same specimens at the model's own displacement are explained by no
/// effect. A collapse angle, or a displacement at a tilt, is not an observable of the
/// lateral load and is refused before anything runs.
#[test]
fn an_analysis_of_lateral_displacements_finds_the_joint_stiffness_by_its_scaling() {
    let study = lateral_study();
    let (s, setup, data) = lateral_analysis(&study);
    let prep = prepare(&setup, &data(3.0), &s, &study.library).unwrap();
    let run = analyze(&prep, data(3.0), study.seed).unwrap();
    let a = &run.analysis;
    // The forward runs by stage, counted by hand: one realization of each group for the
    // baseline and the null pool; kn_scale's grid of 4 intervals on its log range has its
    // neutral factor 1 at the middle node, which the baseline gives: 4 nodes run on every
    // group; a confirmation run of every confirmed candidate on every group; the extended
    // model at its re-scored fit (which moved from the coordinates confirmed) runs anew on
    // every group and on the independent layouts.
    let groups = setup.groups.len();
    let confirmed = a.candidates.iter().filter(|c| c.confirmed).count();
    let runs: Vec<(&str, usize)> = a.forward_runs.iter().map(|r| (r.stage.as_str(), r.runs)).collect();
    assert_eq!(
        runs,
        [
            ("baseline", groups),
            ("surrogate grids", 4 * groups),
            ("null pool", groups),
            ("confirmation", confirmed * groups),
            ("extended model", 2 * groups)
        ],
        "{groups} groups, {confirmed} confirmed"
    );
    let cause = a.cause.as_ref().expect("a cause named");
    assert_eq!(cause.name, "kn_scale");
    assert_ne!(a.verdict, Verdict::NoEffect);
    let factor = cause.parameters[0].1;
    assert!((factor * 3.0 - 1.0).abs() < 0.15, "kn_scale.factor = {factor}, want about 1/3");
    // The weights: the displacements three times the model's leave the baseline none; the
    // hidden cause holds the weight alone, and the displacement separates it from the
    // baseline.
    let w = &a.weights;
    assert_eq!(w.models.len(), 2, "{w:?}");
    let total: f64 = w.models.iter().map(|m| m.pseudo_bma).sum();
    assert!((total - 1.0).abs() < 1e-9 && w.of("kn_scale") > 0.99 && w.shared == ["kn_scale"], "{w:?}");
    let sep = &a.identifiability.pairs[0];
    assert!(!sep.indistinguishable && sep.keys[0].observable.starts_with("free"), "{sep:?}");
    let run = analyze(&prep, data(1.0), study.seed).unwrap();
    assert_eq!((run.analysis.verdict, run.analysis.cause.as_ref().map(|c| c.name.clone())), (Verdict::NoEffect, None));
    // At the model's own displacements the baseline shares the weight (`kn_scale` at a
    // factor near 1 predicts as well, so it may share it too).
    assert!(run.analysis.weights.shared.iter().any(|n| n == "baseline"), "{:?}", run.analysis.weights);
    // Observables the lateral load does not give.
    let mut angle = data(1.0);
    angle[0].observable = Observable::CollapseAngle;
    let e = prepare(&setup, &angle, &s, &study.library).unwrap_err();
    assert!(matches!(e, DiscrepancyError::Observable { protocol: "lateral", .. }), "{e}");
    let mut tilted = data(1.0);
    tilted[1].observable = Observable::Displacement { measure: Measure::MeanOfLeftCenterRight, tilt_deg: 5.0 };
    let e = prepare(&setup, &tilted, &s, &study.library).unwrap_err();
    assert_eq!(
        e.to_string(),
        "specimen free1: displacement at 5 deg; the lateral load gives the displacements under the load, at tilt 0 only"
    );
}
