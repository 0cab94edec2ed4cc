//! The offset 2-block stack of `verify` (b = h = 0.15 m, e = 0.2 b, rigid joints; closed
//! form 21.80°) tilted with scalar and with block density scaling, with and without the
//! secant predictor: prints the steps, α_max and every increment above 20° as
//! `alpha:S|U:steps` (S stable, U no equilibrium or collapse); then, for both scalings
//! relaxed to 21.5° by 0.5° increments, the forces locked into each joint.
//!
//! `cargo run --release --example knife_edge`

mod common;

use drystone::dem::{DensityScaling, PenaltyParams, SolverParams};
use drystone::layout::BaseSliding;
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::verify::{box_vertices, layout_of, RIGID_KN};
fn main() {
    let (b, h) = (0.15, 0.15);
    let e = 0.2 * b;
    let blocks = vec![
        box_vertices([0.0, -b / 2.0, 0.0], [0.3, b / 2.0, h]),
        box_vertices([0.0, -b / 2.0 + e, h], [0.3, b / 2.0 + e, 2.0 * h]),
    ];
    let l = layout_of(blocks, RIGID_KN, RIGID_KN / 2.0, 60.0, BaseSliding::Free);
    for (block, pred) in [(false, true), (true, true), (false, false), (true, false)] {
        let s = SolverParams {
            density_scaling: if block { SolverParams::default().density_scaling } else { DensityScaling::Scalar },
            penalty: PenaltyParams { predictor: pred, ..PenaltyParams::default() },
            ..SolverParams::default()
        };
        let t = TiltParams { resolution_deg: 0.0625, ..TiltParams::default() };
        let r = run_tilt(&l, s, &t).unwrap();
        let inc: Vec<String> = r
            .increments
            .iter()
            .filter(|i| i.alpha_deg > 20.0)
            .map(|i| format!("{}:{}:{}", i.alpha_deg, if i.stable { "S" } else { "U" }, i.steps))
            .collect();
        println!("block {block} predictor {pred}: {} steps, alpha {} {:?}", r.steps, r.collapse_angle_deg(), inc);
    }
    locked_in_shear(&l);
}

/// After the tilt runs: both scalings relaxed by 0.5° increments (no predictor) to 21.5°,
/// and per contact the normal force, the shear force and the mobilised friction
/// |Fs| / (Fn tan φ) of the sub-contact sums, to compare the locked-in shear of the two paths.
fn locked_in_shear(l: &drystone::layout::Layout) {
    for block in [false, true] {
        let sim = common::settled_at(
            l,
            21.5,
            SolverParams {
                density_scaling: if block { SolverParams::default().density_scaling } else { DensityScaling::Scalar },
                ..SolverParams::default()
            },
        );
        for c in &sim.state.contacts {
            let n = sim.state.contact_normal(c);
            let fnorm: f64 = c.subs.iter().map(|s| s.state.normal).sum();
            let fs: drystone::Vec3 = c.subs.iter().map(|s| s.state.shear).sum();
            let fsn = (fs - n * n.dot(&fs)).norm();
            println!(
                "block {block}: {} Fn {:.3} N, |Fs| {:.3} N, mobilised {:.4}, top rotation {:.3e} rad",
                sim.state.joint_name(c),
                fnorm,
                fsn,
                fsn / (fnorm * c.joint.tan_phi),
                sim.state.bodies[1].rot.angle()
            );
        }
    }
}
