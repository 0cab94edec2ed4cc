//! The `base_restraint` effect against statics: a rigid block of width b and height h on
//! the tilting table, held at its downhill toe by a smooth fixed stop of height h_s, can no
//! longer overturn about its toe; it overturns about the stop's top edge with its toe
//! sliding uphill on the table (friction μ = tan φ). Moments about that edge, the toe
//! carrying the weight's normal component W cos α and the friction μ W cos α at lever h_s:
//! `(h/2 − h_s) sin α = (b/2 + μ h_s) cos α`, i.e. `tan α = (b + 2 μ h_s) / (h − 2 h_s)`.
//! Without the stop, `tan α = b/h` (the rigid block of the verification cases).

use drystone::dem::SolverParams;
use drystone::effects::{Effect, EffectDef, ParamDef, Scale, Stage, Step};
use drystone::layout::BaseSliding;
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::verify::{layout_of, rect_block, RIGID_KN};
use std::sync::Arc;

/// The collapse angle (deg) of the block with a smooth stop of height `h_s` (m).
fn collapse_with_stop(b: f64, h: f64, phi_deg: f64, h_s: f64) -> (f64, usize) {
    let mut layout = layout_of(vec![rect_block(b, h, 0.3)], RIGID_KN, RIGID_KN / 2.0, phi_deg, BaseSliding::Free);
    let def = EffectDef {
        name: "smooth_stop".into(),
        description: "a frictionless stop".into(),
        source: "test".into(),
        parameters: vec![ParamDef {
            name: "h_s".into(),
            unit: "m".into(),
            min: 0.0,
            max: 0.1,
            scale: Scale::Linear,
            neutral: 0.0,
            range_per_course_height: false,
            source: String::new(),
            kinds: vec![],
        }],
        steps: vec![Step::BaseStop { parameter: "h_s".into(), friction_deg: Some(0.0) }],
    };
    let e = Effect::new(Arc::new(def), vec![h_s], 0.05).unwrap();
    let mut rng = drystone::effects::effect_rng(1, 0, "g", "smooth_stop");
    e.apply_stage(Stage::Layout, &mut layout, &[], &mut rng).unwrap();
    let n = layout.blocks.len();
    let t = run_tilt(&layout, SolverParams::default(), &TiltParams { resolution_deg: 0.0625, ..TiltParams::default() })
        .expect("stands at 0");
    assert!(t.first_unstable_deg.is_some(), "collapses");
    (t.collapse_angle_deg(), n)
}

#[test]
fn a_block_held_by_a_stop_tips_about_the_stop_s_edge_as_statics_says() {
    let (b, h, phi) = (0.1, 0.3, 30f64);
    let mu = phi.to_radians().tan();
    let (free, n) = collapse_with_stop(b, h, phi, 0.0);
    assert_eq!(n, 1, "h_s = 0 adds no stop");
    let want = (b / h).atan().to_degrees();
    assert!((free - want).abs() < 0.25, "no stop: {free} against {want}");
    for h_s in [0.015, 0.03] {
        let (held, n) = collapse_with_stop(b, h, phi, h_s);
        assert_eq!(n, 2, "one stop");
        let want = ((b + 2.0 * mu * h_s) / (h - 2.0 * h_s)).atan().to_degrees();
        eprintln!("h_s {h_s} m: simulated {held:.4} deg, statics {want:.4} deg");
        assert!((held - want).abs() < 0.25, "h_s {h_s}: {held} against statics {want}");
    }
}
