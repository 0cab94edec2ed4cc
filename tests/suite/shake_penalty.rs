//! The shaking table by the penalty DEM in explicit dynamics (`--solver penalty`: true
//! masses, no local damping, normal contact dashpots set by a coefficient of restitution
//! e), against references computed here, independently of the solver under test:
//!
//! * a block dropped flat on the table leaves it at e times its impact speed (the linear
//!   spring–dashpot contact, Tsuji et al. 1992);
//! * free rocking of a block released from a tilt: the half-cycle amplitudes follow
//!   Housner's (1963) energy balance between impacts, `cos(α − θₖ₊₁) − cos α =
//!   r² (cos(α − θₖ) − cos α)`, `r = 1 − 1.5 sin²α`. A penalty contact is not Housner's
//!   rigid impact: the landing edge sinks into its springs and the dashpots absorb what
//!   the restitution says. What is checked: at a stiff Kn (1e10 Pa/m) and the default
//!   e = 0.05 (chosen as the value that brings the penalty impact to Housner's loss), for
//!   slenderness 9.5° to 26.6°, the first three amplitudes within 10 % of the release tilt
//!   of Housner's and decreasing; and the restitution sets the loss: e = 0 loses more than
//!   Housner's impact, e = 0.5 far less;
//! * a block on a base accelerated by a rectangular pulse above μ g slides as Newmark's
//!   (1965) rigid block: relative displacement `(A − μg) t₁² / 2 + v₁² / (2 μ g)`, within
//!   3 % (the shear springs' elastic slip and the step);
//! * a block under a one-sine pulse (Zhang & Makris 2001) overturns or survives as
//!   Housner's rocking equation with its impact rule says (RK4 here), at 0.85 and 1.15 times
//!   the equation's smallest overturning amplitude, for ω_p/p = 2 and 4.
//!
//! Frames: the table frame (y out of plane); the base accelerates along +y. θ > 0 is a
//! rotation towards +y about the +y bottom edge (the rotation vector's −x).

use drystone::dem::damping::ContactDamping;
use drystone::dem::{DensityScaling, PenaltyParams, SolverKind, SolverParams};
use drystone::ground::{Motion, Pulse, G as G_RECORD};
use drystone::layout::{BaseSliding, Layout};
use drystone::loading::shake::ShakeParams;
use drystone::protocol::run_shake;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of};
use drystone::Vec3;

const KN: f64 = 1e10;

/// A block 0.2 m long (x), `b` wide (y), `h` high (z) on the table, friction `phi_deg`,
/// bottom at `z0`.
fn block_at(b: f64, h: f64, phi_deg: f64, z0: f64) -> Layout {
    layout_of(vec![box_vertices([0.0, -b / 2.0, z0], [0.2, b / 2.0, z0 + h])], KN, KN / 2.0, phi_deg, BaseSliding::Free)
}

fn penalty() -> SolverParams {
    SolverParams { kind: SolverKind::Penalty, ..SolverParams::default() }
}

/// The engine as the shaking table runs it: true masses, no local damping, dashpots of
/// restitution `e`.
fn dynamics(layout: &Layout, e: f64) -> drystone::dem::Simulation {
    let d = SolverParams::default();
    let p = SolverParams {
        damping: 0.0,
        density_scaling: DensityScaling::Off,
        timestep_safety: d.timestep_safety * PenaltyParams::default().step_fraction,
        ..d
    };
    let mut sim = drystone::dem::Simulation::new(layout, p);
    sim.set_contact_damping(Some(ContactDamping::from_restitution(e).unwrap()));
    sim
}

#[test]
fn a_block_dropped_flat_leaves_the_table_at_e_times_its_impact_speed() {
    for e in [0.8, 0.5, 0.3, 0.05] {
        // Dropped from 0.05 m: 0.99 m/s at impact; the contact lasts about a millisecond,
        // in which gravity changes the speed by 1 %: the ratio is read from the velocities
        // just before the first contact and just after the last, corrected for gravity over
        // the contact's duration.
        let mut sim = dynamics(&block_at(0.3, 0.1, 30.0, 0.05), e);
        let (mut before, mut after) = (None, None);
        let mut t_in = 0.0;
        let mut touching = false;
        while sim.state.time < 0.5 && after.is_none() {
            let v = sim.state.bodies[0].vel.z;
            sim.step().unwrap();
            let force = sim.state.contacts.iter().any(|c| c.force.norm() > 0.0);
            if force && !touching {
                before = Some(v);
                t_in = sim.state.time;
                touching = true;
            } else if !force && touching {
                let dur = sim.state.time - t_in;
                after = Some((sim.state.bodies[0].vel.z, dur));
            }
        }
        let (vb, (va, dur)) = (before.unwrap(), after.unwrap());
        // Gravity's share over the contact: g·dur slows the rebound.
        let ratio = (va + G * dur) / -vb;
        eprintln!("e {e}: rebound ratio {ratio:.4} (contact {dur:.2e} s, step {:.2e} s)", sim.dt());
        assert!((ratio - e).abs() < 0.03, "e {e}: rebound ratio {ratio:.4} (contact {dur:.2e} s)");
        assert!(sim.state.bodies[0].rot.angle() < 1e-9, "a flat drop does not turn the block");
    }
}

/// Housner's θ of body 0 (its orientation is relative to the upright layout).
fn theta_of(sim: &drystone::dem::Simulation) -> f64 {
    -sim.state.bodies[0].rot.scaled_axis().x
}

/// Free rocking by the penalty DEM from `theta0` (rad) for `impacts` impacts: the largest
/// |θ| of each half-cycle.
fn rock_penalty(b: f64, h: f64, theta0: f64, e: f64, impacts: usize) -> Vec<f64> {
    let mut sim = dynamics(&block_at(b, h, 80.0, 0.0), e);
    // Turn the block by θ₀ towards +y about its +y bottom edge (rotation vector −θ₀ x).
    {
        let body = &mut sim.state.bodies[0];
        let pivot = Vec3::new(body.pos.x, b / 2.0, 0.0);
        let turn = nalgebra::UnitQuaternion::from_scaled_axis(Vec3::new(-theta0, 0.0, 0.0));
        body.pos = pivot + turn * (body.pos - pivot);
        body.rotate(Vec3::new(-theta0, 0.0, 0.0));
    }
    let mut peaks = vec![theta0];
    // The side of the current half-cycle: a new one starts when θ is past 1e-4 rad on the
    // other side (the landing edge sinks into its springs by microradians).
    let mut side = 1.0;
    while peaks.len() < impacts + 2 && sim.state.time < 10.0 {
        sim.step().unwrap();
        let th = theta_of(&sim);
        if th * side < -1e-4 {
            side = -side;
            peaks.push(0.0);
        }
        let last = peaks.last_mut().unwrap();
        *last = last.max(th * side);
    }
    peaks.truncate(impacts + 1);
    peaks
}

/// Housner's amplitudes of free rocking from `theta0`: energy between impacts, the angular
/// velocity times r at each.
fn housner_peaks(b: f64, h: f64, theta0: f64, impacts: usize) -> Vec<f64> {
    let alpha = (b / h).atan();
    let r = 1.0 - 1.5 * alpha.sin().powi(2);
    let mut peaks = vec![theta0];
    for _ in 0..impacts {
        let th = *peaks.last().unwrap();
        let c = alpha.cos() + r * r * ((alpha - th).cos() - alpha.cos());
        peaks.push(alpha - c.acos());
    }
    peaks
}

#[test]
fn free_rocking_loses_housners_share_per_impact_with_the_default_restitution() {
    let e = PenaltyParams::default().contact_restitution;
    for (b, h) in [(0.1, 0.6), (0.15, 0.6), (0.2, 0.55), (0.15, 0.3)] {
        let alpha = f64::atan(b / h);
        let theta0 = 0.6 * alpha;
        let want = housner_peaks(b, h, theta0, 3);
        let got = rock_penalty(b, h, theta0, e, 3);
        eprintln!("α {:.1}°: penalty {got:.4?}, Housner {want:.4?}", alpha.to_degrees());
        assert_eq!(got.len(), 4, "three impacts within 10 s: {got:?}");
        for (k, (g, w)) in got.iter().zip(&want).enumerate().skip(1) {
            assert!(
                (g - w).abs() < 0.1 * theta0,
                "α {:.1}°, half-cycle {k}: {g:.4} rad against Housner's {w:.4}",
                alpha.to_degrees()
            );
            assert!(g < &got[k - 1], "amplitudes decrease: {got:?}");
        }
    }
    // The restitution sets the loss: a plastic dashpot (e = 0) loses more than Housner's
    // rigid impact at the first impact, a light one (e = 0.5) far less.
    let (b, h): (f64, f64) = (0.15, 0.6);
    let theta0 = 0.6 * (b / h).atan();
    let want = housner_peaks(b, h, theta0, 1)[1];
    let plastic = rock_penalty(b, h, theta0, 0.0, 1)[1];
    let light = rock_penalty(b, h, theta0, 0.5, 1)[1];
    assert!(
        plastic < want - 0.05 * theta0 && light > want + 0.1 * theta0,
        "e 0: {plastic}, e 0.5: {light}, Housner {want}"
    );
}

#[test]
fn a_block_slides_on_an_accelerated_base_as_newmarks_block() {
    // A flat block (tan α = 4: no rocking below 4 g), φ = 20°, under A = 0.6 g for 0.3 s.
    let (b, h, phi): (f64, f64, f64) = (0.4, 0.1, 20.0);
    let mu = phi.to_radians().tan();
    let (a_g, t1): (f64, f64) = (0.6, 0.3);
    let dt: f64 = 1e-3;
    let n = (t1 / dt).round() as usize;
    let mut horizontal_g = vec![a_g; n + 1];
    horizontal_g.push(0.0);
    let motion = Motion { name: "step".into(), dt_s: dt, horizontal_g, vertical_g: None };
    let params = ShakeParams { tail_s: 0.6, ..ShakeParams::default() };
    let r = run_shake(&block_at(b, h, phi, 0.0), penalty(), &motion, &params).unwrap();
    // Newmark: the base's acceleration in the block's (the layout's g) units.
    let a = a_g * G_RECORD;
    let g = G;
    // The motion ramps from A to 0 over its last interval (linear interpolation): A for
    // t₁ + dt/2 on average.
    let t_on = t1 + 0.5 * dt;
    let v1 = (a - mu * g) * t_on;
    let d = 0.5 * (a - mu * g) * t_on * t_on + v1 * v1 / (2.0 * mu * g);
    let slid = r.residual_drift * r.height_m;
    assert!((slid - d).abs() < 0.03 * d, "slid {slid:.5} m against Newmark's {d:.5} m");
    assert!(!r.overturned && r.max_rotation_deg < 0.5, "{r:?}");
    assert_eq!(r.solver, drystone::dem::SolverKind::Penalty);
}

/// Housner's rocking equation by RK4 at 1e-4 s with the impact rule `θ̇ ← r θ̇` when θ
/// crosses 0: whether |θ| exceeds 1.5 α within `t_end` (the block has passed its
/// overturning angle and falls).
fn overturns(b: f64, h: f64, pulse: &Pulse, t_end: f64) -> bool {
    let alpha = (b / h).atan();
    let p2 = 3.0 * G / (2.0 * (b * b + h * h).sqrt());
    let r = 1.0 - 1.5 * alpha.sin().powi(2);
    let dt = 1e-4;
    let (mut th, mut om, mut t) = (0.0_f64, 0.0_f64, 0.0_f64);
    let ag = |t: f64| pulse.at(t) * G_RECORD / G;
    while t < t_end {
        if th == 0.0 && om == 0.0 && ag(t).abs() <= alpha.tan() {
            t += dt;
            continue;
        }
        let side = if th != 0.0 {
            th.signum()
        } else if om != 0.0 {
            om.signum()
        } else {
            -ag(t).signum()
        };
        let f = |th: f64, om: f64, t: f64| {
            let s = alpha * side - th;
            (om, -p2 * (s.sin() + ag(t) * s.cos()))
        };
        let (k1t, k1o) = f(th, om, t);
        let (k2t, k2o) = f(th + 0.5 * dt * k1t, om + 0.5 * dt * k1o, t + 0.5 * dt);
        let (k3t, k3o) = f(th + 0.5 * dt * k2t, om + 0.5 * dt * k2o, t + 0.5 * dt);
        let (k4t, k4o) = f(th + dt * k3t, om + dt * k3o, t + dt);
        let nth = th + dt / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
        let nom = om + dt / 6.0 * (k1o + 2.0 * k2o + 2.0 * k3o + k4o);
        t += dt;
        if th != 0.0 && nth * th < 0.0 {
            th = 0.0;
            om = if (nom * r).abs() < 1e-6 { 0.0 } else { nom * r };
            continue;
        }
        (th, om) = (nth, nom);
        if th.abs() > 1.5 * alpha {
            return true;
        }
    }
    false
}

/// The smallest one-sine amplitude (g) that overturns the block by the rocking equation:
/// a scan up from the uplift threshold in 2 % steps, then bisection of the first bracket.
fn overturning_amplitude(b: f64, h: f64, period: f64) -> f64 {
    let mk = |a: f64| Pulse::OneSine { amplitude_g: a, period_s: period };
    let (mut lo, mut hi) = (b / h * 1.0001, 20.0 * b / h);
    let mut a = lo;
    while a < hi {
        if overturns(b, h, &mk(a), period + 4.0) {
            hi = a;
            break;
        }
        lo = a;
        a *= 1.02;
    }
    for _ in 0..25 {
        let mid = 0.5 * (lo + hi);
        if overturns(b, h, &mk(mid), period + 4.0) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

#[test]
fn a_block_under_a_one_sine_pulse_overturns_as_the_rocking_equation_says() {
    let (b, h): (f64, f64) = (0.15, 0.6);
    let p = (3.0 * G / (2.0 * (b * b + h * h).sqrt())).sqrt();
    for ratio in [2.0, 4.0] {
        let period = 2.0 * std::f64::consts::PI / (ratio * p);
        let ac = overturning_amplitude(b, h, period);
        for (factor, expect) in [(0.85, false), (1.15, true)] {
            let pulse = Pulse::OneSine { amplitude_g: factor * ac, period_s: period };
            assert_eq!(overturns(b, h, &pulse, period + 4.0), expect, "reference at {factor} × {ac:.3} g");
            let motion = pulse.sampled(1e-4, period);
            let params = ShakeParams { tail_s: 3.0, ..ShakeParams::default() };
            let r = run_shake(&block_at(b, h, 80.0, 0.0), penalty(), &motion, &params).unwrap();
            assert_eq!(
                r.overturned, expect,
                "ω_p/p {ratio}, A = {factor} × {ac:.3} g: max rotation {:.2}°",
                r.max_rotation_deg
            );
        }
    }
}

/// The static methods and limit analysis do not run the shaking table, and say so; the
/// restitution is checked.
#[test]
fn the_shaking_table_refuses_static_methods_and_a_bad_restitution() {
    let pulse = Pulse::OneSine { amplitude_g: 0.1, period_s: 0.3 }.sampled(0.001, 0.3);
    let l = block_at(0.15, 0.6, 80.0, 0.0);
    for kind in [SolverKind::Relaxation, SolverKind::Implicit, SolverKind::Limit] {
        let s = SolverParams { kind, ..SolverParams::default() };
        let e = run_shake(&l, s, &pulse, &ShakeParams::default()).unwrap_err();
        assert!(e.to_string().contains("penalty (explicit dynamics") && e.to_string().contains("nscd ("), "{e}");
    }
    // Out of range in the method's settings, and under the table's former key.
    let mut bad = penalty();
    bad.penalty.contact_restitution = 1.5;
    let e = run_shake(&l, bad, &pulse, &ShakeParams::default()).unwrap_err();
    assert!(e.to_string().contains("penalty.contact_restitution"), "{e}");
    let bad = ShakeParams { contact_restitution: Some(1.5), ..ShakeParams::default() };
    let e = run_shake(&l, penalty(), &pulse, &bad).unwrap_err();
    assert!(e.to_string().contains("contact_restitution"), "{e}");
}

/// `drystone shake --solver penalty`: the JSON names the solver and the restitution it
/// used (the default, or `--restitution`), a block below its uplift threshold stands, and
/// a restitution out of range is refused naming the key.
#[test]
fn the_command_line_runs_the_penalty_solver_with_its_restitution() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "shake",
            "data/layouts/single_block.json",
            "--pulse",
            "one-sine",
            "--amplitude-g",
            "0.2",
            "--period-s",
            "0.3",
            "--tail-s",
            "0.5",
            "--solver",
            "penalty",
            "--json",
        ];
        args.extend_from_slice(extra);
        std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
            .args(&args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("drystone")
    };
    for (extra, e) in [(vec![], 0.05), (vec!["--restitution", "0.3"], 0.3)] {
        let out = run(&extra);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
        assert_eq!(v["solver"], "penalty");
        assert_eq!(v["contact_restitution"].as_f64(), Some(e));
        // tan α = 0.1125 / 0.375 = 0.3 > 0.2: the block does not rock over.
        assert_eq!(v["overturned"], false);
        assert!(v["iterations"] == 0 && v["steps"].as_u64().unwrap() > 1000, "{v}");
    }
    let out = run(&["--restitution", "2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("contact_restitution"), "{err}");
}
