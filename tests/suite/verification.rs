//! Analytic scenario tests: the DEM against closed-form statics and dynamics.
//! Each test is named for what it proves.

use drystone::dem::contact::law::Quadrature;
use drystone::dem::SolverParams;
use drystone::layout::BaseSliding;
use drystone::loading::tilt::{MechanismKind, TiltParams, TiltResult};
use drystone::protocol::run_tilt;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::*;

const TOL_DEG: f64 = 0.3;

fn assert_angle(r: &TiltResult, expected_deg: f64, kind: MechanismKind, joint: &str) {
    let err = r.collapse_angle_deg() - expected_deg;
    assert!(
        err.abs() <= TOL_DEG,
        "collapse {:.3}° vs closed form {:.3}° (error {:+.3}°)",
        r.collapse_angle_deg(),
        expected_deg,
        err
    );
    assert_eq!(r.mechanism.kind, kind, "{:?}", r.mechanism);
    assert_eq!(r.mechanism.joint, joint, "{:?}", r.mechanism);
    // The bracket is resolved to the stated resolution.
    let up = r.first_unstable_deg.expect("collapsed");
    assert!(up > r.last_stable_deg && up - r.last_stable_deg <= TiltParams::default().resolution_deg + 1e-9);
}

#[test]
fn block_on_table_slides_at_phi() {
    for phi in [20.0, 30.0] {
        assert_angle(&sliding_block(phi), phi, MechanismKind::Sliding, "table/b0");
    }
}

#[test]
fn rectangular_block_topples_at_atan_b_over_h() {
    for (b, h) in [(0.1125f64, 0.375f64), (0.15, 0.3)] {
        assert_angle(&toppling_block(b, h), (b / h).atan().to_degrees(), MechanismKind::Toppling, "table/b0");
    }
}

#[test]
fn trapezoid_monolith_of_the_1_4_section_topples_at_24_2_deg() {
    let exp = trapezoid_closed_form(0.150, 0.077, 0.375).to_degrees();
    assert!((exp - 24.13).abs() < 0.01, "closed form {exp}");
    assert_angle(&trapezoid_monolith(), exp, MechanismKind::Toppling, "table/b0");
}

#[test]
fn aligned_stack_of_five_fails_at_the_base_joint() {
    let r = aligned_stack(5, 0.15, 0.075);
    assert_angle(&r, (0.15f64 / 0.375).atan().to_degrees(), MechanismKind::Toppling, "table/b0");
    assert_eq!(r.mechanism.blocks.len(), 5, "the whole stack rotates: {:?}", r.mechanism);
}

#[test]
fn offset_stack_fails_at_the_base_when_e_below_b_over_3() {
    let (b, h, e) = (0.15, 0.15, 0.03);
    let r = offset_stack(b, h, e);
    assert_angle(&r, ((b - e) / (2.0 * h)).atan().to_degrees(), MechanismKind::Toppling, "table/b0");
}

#[test]
fn offset_stack_fails_at_the_interface_when_e_above_b_over_3() {
    let (b, h, e) = (0.15, 0.15, 0.06);
    let r = offset_stack(b, h, e);
    assert_angle(&r, ((b - 2.0 * e) / h).atan().to_degrees(), MechanismKind::Toppling, "b0/b1");
    assert_eq!(r.mechanism.blocks, vec!["b1".to_string()], "only the top block moves");
}

#[test]
fn slide_acceleration_after_onset_is_g_sin_minus_tan_phi_cos() {
    for (alpha, phi) in [(30.0, 20.0), (40.0, 30.0)] {
        let a = slide_acceleration(alpha, phi);
        let exp = slide_acceleration_closed_form(alpha, phi);
        assert!(((a - exp) / exp).abs() < 0.01, "a = {a} vs {exp} m/s²");
    }
}

#[test]
fn winkler_block_at_the_paper_stiffness_tips_at_the_closed_form_angle() {
    let (b, h, kn) = (0.1125f64, 0.375f64, 5e7);
    let exp = winkler_collapse_angle(b, h, DENSITY, G, kn).to_degrees();
    // Several degrees before the rigid angle.
    assert!((b / h).atan().to_degrees() - exp > 4.0, "closed form {exp}");
    let r = winkler_block(b, h, kn, 1);
    assert_angle(&r, exp, MechanismKind::Toppling, "table/b0");
}

fn winkler_error(kn: f64, n: u32, quad: Quadrature) -> f64 {
    let (b, h) = (0.1125, 0.375);
    let l = layout_of(vec![rect_block(b, h, 0.3)], kn, kn / 2.0, 60.0, BaseSliding::Free);
    let solver = SolverParams { subcontact_subdivisions: n, quadrature: quad, ..SolverParams::default() };
    let p = TiltParams { resolution_deg: 0.02, ..TiltParams::default() };
    let r = run_tilt(&l, solver, &p).unwrap();
    r.collapse_angle_deg() - winkler_collapse_angle(b, h, DENSITY, G, kn).to_degrees()
}

#[test]
fn vertex_subcontacts_converge_to_the_winkler_closed_form_as_density_grows() {
    let errs: Vec<f64> = [1, 2, 4, 8].iter().map(|&n| winkler_error(5e7, n, Quadrature::Vertex)).collect();
    for w in errs.windows(2) {
        assert!(w[1].abs() < w[0].abs(), "errors must shrink with the sub-contact density: {errs:?}");
    }
    assert!(errs[0] > 2.0, "one vertex sub-contact per corner overestimates: {errs:?}");
    assert!(errs[3].abs() < TOL_DEG, "{errs:?}");
}

#[test]
fn exact_subcontacts_match_the_winkler_closed_form_at_every_density() {
    for n in [1, 2, 4] {
        let e = winkler_error(5e7, n, Quadrature::Exact);
        assert!(e.abs() < 0.05, "n = {n}: error {e}");
    }
}

#[test]
fn winkler_collapse_tends_to_atan_b_over_h_as_kn_grows() {
    let (b, h) = (0.1125f64, 0.375f64);
    let rigid = (b / h).atan().to_degrees();
    let mut last_gap = f64::INFINITY;
    for kn in [1e8, 1e10, 1e12] {
        let cf = winkler_collapse_angle(b, h, DENSITY, G, kn).to_degrees();
        let e = winkler_error(kn, 1, Quadrature::Exact);
        assert!(e.abs() < 0.05, "Kn = {kn:e}: DEM − closed form = {e}");
        let gap = rigid - cf;
        assert!(gap > 0.0 && gap < last_gap, "closed form approaches the rigid angle");
        last_gap = gap;
    }
    assert!(last_gap < 0.2);
}

#[test]
fn free_fall_matches_half_g_t_squared() {
    let (sim, exp) = free_fall();
    assert!(((sim - exp) / exp).abs() < 1e-9, "{sim} vs {exp}");
}

#[test]
fn block_at_rest_carries_its_weight() {
    let (fz, w) = weight_at_rest();
    assert!(((fz - w) / w).abs() < 1e-3, "{fz} vs {w}");
}

#[test]
fn undamped_bounce_closes_its_energy_balance() {
    let (e0, e1, mgh) = bounce_energy();
    assert!(((e1 - e0) / mgh).abs() < 0.01, "ΔE = {} J of m g h = {mgh} J", e1 - e0);
}

#[test]
fn verify_report_passes() {
    let rep = run_all();
    assert!(rep.all_ok(), "{rep:#?}");
    assert_eq!(rep.cases.len(), 12);
}

/// A block on joints of the hyperbolic closure law (Kni 1e8 Pa/m, Vm 1 mm), dropped
/// undamped: the time step follows the tangent within its windows (not the law's cap,
/// `25 Kni`) and shrinks as the impact closes the joint, and the energy balance closes as
/// the linear joint's does (conservation: kinetic + gravitational + the law's stored
/// energy). `safety` is the time step's fraction of the critical step. Returns (ΔE over
/// m g h, the step at release, the smallest step, the step of the law's cap), s.
fn hyperbolic_bounce(safety: f64, bounces: usize) -> (f64, f64, f64, f64) {
    use drystone::closure::{Closure, Hyperbolic};
    use drystone::dem::{DensityScaling, Simulation};
    let mut l = layout_of(vec![box_vertices([0.0, 0.0, 0.005], [0.2, 0.15, 0.105])], 1e8, 5e7, 30.0, BaseSliding::Free);
    l.materials[0].closure = Closure::Hyperbolic(Hyperbolic { max_closure_m: 1e-3 });
    let params = SolverParams {
        damping: 0.0,
        contact_margin_m: 0.01,
        timestep_safety: safety,
        density_scaling: DensityScaling::Off,
        ..SolverParams::default()
    };
    let mut sim = Simulation::new(&l, params);
    let dt0 = sim.dt();
    // The step of a joint at the law's bound, 25 Kni: √25 = 5 times shorter than Kni's.
    let dt_cap = dt0 / 5.0;
    sim.state.bodies[0].vel = -sim.state.gravity * (0.5 * sim.dt());
    let total = |s: &Simulation| {
        let (k, p, e) = s.state.energies();
        k + p + e
    };
    let e0 = total(&sim);
    let (mut touched, mut rising, mut apexes) = (false, false, 0);
    let mut dt_min = dt0;
    for _ in 0..20_000_000 {
        sim.step().expect("finite");
        dt_min = dt_min.min(sim.dt());
        if sim.state.contacts.iter().any(|c| c.force.norm() > 0.0) {
            touched = true;
        } else if touched {
            if sim.state.bodies[0].vel.z > 0.0 {
                rising = true;
            } else if rising {
                apexes += 1; // apex of a rebound
                if apexes == bounces {
                    break;
                }
                (touched, rising) = (false, false);
            }
        }
    }
    assert_eq!(apexes, bounces, "the block rebounds {bounces} times");
    let mgh = sim.state.bodies[0].mass * G * 0.005;
    ((total(&sim) - e0) / mgh, dt0, dt_min, dt_cap)
}

#[test]
fn a_hyperbolic_joints_step_follows_its_tangent_and_its_bounce_closes_the_energy_balance() {
    // At a tenth of the critical step, one bounce. The step changes as the joint closes,
    // and the leapfrog's half-step velocity is not re-centred on a change of step: the
    // balance's error is of first order in the step, and closes as the step shrinks.
    let (de, dt0, dt_min, dt_cap) = hyperbolic_bounce(0.1, 1);
    let (de_half, ..) = hyperbolic_bounce(0.05, 1);
    assert!(de.abs() < 0.02, "ΔE = {de} m g h");
    assert!(de_half.abs() < 0.6 * de.abs(), "ΔE = {de} then {de_half} m g h at half the step");
    // The impact closes the joint to about half its maximum closure (tangent ≈ 4 Kni): the
    // step shrank from Kni's, and stayed well above the cap's.
    assert!(dt_min < 0.8 * dt0, "the step did not follow the closure: {dt_min:e} s from {dt0:e} s");
    assert!(dt_min > 1.5 * dt_cap, "the step fell to the cap's: {dt_min:e} s, the cap's {dt_cap:e} s");
    // At the quasi-static runs' default safety (0.95 of the critical step), ten bounces: a
    // step too long for the tangent would be unstable and the energy grow without bound.
    let (de, ..) = hyperbolic_bounce(SolverParams::default().timestep_safety, 10);
    // (The step's phase error at that safety moves the energy by tenths of m g h over the
    // bounces either way; an unstable step multiplies it at every bounce.)
    assert!(de < 0.5, "ΔE = {de} m g h over ten bounces at the default step");
}
