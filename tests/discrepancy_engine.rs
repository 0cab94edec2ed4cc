//! The discrepancy engine's forward runs are the study's: its baseline predictive means
//! are the means of `drystone run` on the same study (collapse angles as the middles of
//! their brackets, displacements at every observed tilt), realization by realization.

use drystone::discrepancy::{run_models, Measure, Observable, Simulated};
use drystone::ensemble::Shard;
use drystone::study::discrepancy::setup_of;
use drystone::study::{run::run_study, Study};
use std::path::PathBuf;

#[test]
fn the_baseline_predictive_means_are_the_study_run_means() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let study = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
    let n = 3;
    let study = Study { realizations: n, ..study };
    let rows = run_study(&study, Shard::ALL);
    let setup = setup_of(&study, n);
    assert_eq!((setup.tilt.step_deg, setup.tilt.resolution_deg), (study.tilt.step_deg, study.tilt.resolution_deg));
    let outs = run_models(&setup, &[vec![]], None).remove(0);
    for (g, group) in study.groups.iter().enumerate() {
        let mine: Vec<_> = rows.iter().filter(|r| r.group == group.name).collect();
        let mid: Vec<f64> = mine
            .iter()
            .map(|r| {
                let a = r.collapse_angle_deg.unwrap();
                r.first_unstable_deg.map_or(a, |b| 0.5 * (a + b))
            })
            .collect();
        let sim = Simulated::of(&outs[g], &Observable::CollapseAngle);
        assert_eq!(sim.n, n as usize);
        assert!((sim.mean - drystone::stats::mean(&mid)).abs() < 1e-12, "{}: {} vs {:?}", group.name, sim.mean, mid);
        // The displacement at the first tilt step, mean of the three top points.
        let t = study.tilt.step_deg;
        let ob = Observable::Displacement { measure: Measure::MeanOfLeftCenterRight, tilt_deg: t };
        let sim = Simulated::of(&outs[g], &ob);
        let run: Vec<f64> = mine
            .iter()
            .map(|r| {
                let i = r.tilt_deg.iter().position(|&x| (x - t).abs() < 1e-9).unwrap();
                (r.disp_top_left_cm[i] + r.disp_top_centre_cm[i] + r.disp_top_right_cm[i]) / 3.0
            })
            .collect();
        assert!((sim.mean - drystone::stats::mean(&run)).abs() < 1e-12, "{}: {} vs {:?}", group.name, sim.mean, run);
    }
}
