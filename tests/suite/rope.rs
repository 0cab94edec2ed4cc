//! The rope restraint (`restraints.ropes`, `drystone::dem::rope`) against closed forms:
//!
//! * the force on a block pushed into two ropes against the taut string
//!   `F = 2 T δ / √(s² + δ²)`, `T = T₀ + EA (ℓ − ℓ_ref)/ℓ_ref`, its small-deflection form
//!   `2 T₀ δ / s + EA δ³ / s³`, and the derivative of the rope's stored energy
//!   `U = T₀ Δℓ + EA Δℓ² / (2 ℓ_ref)` (the force is conservative);
//! * tension only: a block pulled away from the rope, or a rope gone slack, feels nothing;
//! * the tilting table: a rigid block held by two ropes that press its face (wrap depth d)
//!   overturns about its toe at the angle where the moments about the toe balance,
//!   `W R sin(α − α₀ + θ) = 2 F(θ) z_c cos θ`, maximized over the rotation θ along the
//!   path (solved here by a scan, not by the code under test), by the penalty engine and by
//!   non-smooth contact dynamics.

use drystone::dem::rope::RopeLoad;
use drystone::dem::{RunToEquilibrium, SolverParams, WallState};
use drystone::effects::{effect_rng, Library, Stage};
use drystone::layout::{BaseSliding, Layout, LayoutSpec, Rope};
use drystone::loading::tilt::TiltParams;
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::math::Vec3;
use drystone::nscd::NscdParams;
use drystone::protocol::run_tilt;
use drystone::verify::{layout_of, rect_block, DENSITY, RIGID_KN};

/// A block b × h × l (y, z, x) on the table with two ropes at x = l/6 and 5 l/6 over its
/// whole height.
fn block_with_ropes(b: f64, h: f64, l: f64, t0: f64, ea: f64, s: f64, d: f64) -> Layout {
    let mut layout = layout_of(vec![rect_block(b, h, l)], RIGID_KN, RIGID_KN / 2.0, 30.0, BaseSliding::Free);
    for x in [l / 6.0, 5.0 * l / 6.0] {
        layout.ropes.push(Rope { x, z_lo: 0.0, z_hi: h, pretension: t0, axial_stiffness: ea, span: s, wrap_depth: d });
    }
    layout
}

/// The y force (N) and the moment about x (N·m, about the centroid) of the ropes on the
/// block moved by `dy` in y.
fn rope_load(layout: &Layout, dy: f64) -> (f64, f64) {
    let mut st = WallState::new(layout);
    st.bodies[0].pos.y += dy;
    let (mut f, mut t) = (vec![Vec3::zeros()], vec![Vec3::zeros()]);
    for r in &st.ropes {
        r.add_forces(&st.bodies, &mut f, &mut t);
    }
    (f[0].y, t[0].x)
}

#[test]
fn a_block_pushed_into_two_ropes_feels_the_taut_string_force() {
    let (t0, ea, s) = (300.0, 6e4, 0.1);
    let layout = block_with_ropes(0.1, 0.3, 0.3, t0, ea, s, 0.0);
    let l_ref = 2.0 * s;
    let energy = |d: f64| {
        let dl = 2.0 * (s * s + d * d).sqrt() - l_ref;
        t0 * dl + ea * dl * dl / (2.0 * l_ref)
    };
    for delta in [1e-4, 1e-3, 5e-3, 0.02, 0.05] {
        let (fy, mx) = rope_load(&layout, delta);
        let l = (s * s + delta * delta).sqrt();
        let t = t0 + ea * (2.0 * l - l_ref) / l_ref;
        let want = 2.0 * 2.0 * t * delta / l;
        assert!((-fy - want).abs() <= 1e-9 * want, "δ {delta}: {} against the taut string {want}", -fy);
        // The stored energy's derivative (central differences), two ropes.
        let h = delta * 1e-4;
        let de = 2.0 * (energy(delta + h) - energy(delta - h)) / (2.0 * h);
        assert!((-fy - de).abs() <= 1e-5 * de, "δ {delta}: {} against dU/dδ {de}", -fy);
        // The ropes bear at the centroid's height: no moment about x.
        assert!(mx.abs() <= 1e-9 * want, "moment {mx}");
        if delta <= 5e-3 {
            let small = 2.0 * (2.0 * t0 * delta / s + ea * delta.powi(3) / s.powi(3));
            assert!((-fy - small).abs() <= 2e-3 * small, "δ {delta}: {} against the small form {small}", -fy);
        }
    }
}

#[test]
fn a_rope_pulls_nothing_when_the_block_moves_away_or_it_goes_slack() {
    let layout = block_with_ropes(0.1, 0.3, 0.3, 300.0, 6e4, 0.1, 0.0);
    for dy in [-1e-4, -0.01, -0.05] {
        assert_eq!(rope_load(&layout, dy), (0.0, 0.0), "moved away by {dy}");
    }
    // Pressed by the face as built (d = 10 mm, T₀ = 10 N, EA = 1e5 N): pulled back by 5 mm
    // the rope still touches the face, but it has shortened by more than its pretension
    // stretched it: T₀ + EA (ℓ − ℓ_ref)/ℓ_ref < 0, slack.
    let (s, d, t0, ea) = (0.1, 0.01, 10.0, 1e5);
    let layout = block_with_ropes(0.1, 0.3, 0.3, t0, ea, s, d);
    let (l, l_ref) = ((s * s + 0.005f64.powi(2)).sqrt(), (s * s + d * d).sqrt());
    assert!(t0 + ea * (l - l_ref) / l_ref < 0.0, "the case is slack");
    assert_eq!(rope_load(&layout, -0.005).0, 0.0, "slack rope");
    // As built it presses with 2 T₀ d / √(s² + d²) per rope.
    let want = 2.0 * 2.0 * t0 * d / l_ref;
    assert!((-rope_load(&layout, 0.0).0 - want).abs() < 1e-9 * want);
}

#[test]
fn a_block_held_by_ropes_on_the_tilting_table_overturns_where_the_moments_balance() {
    let (b, h, l) = (0.1, 0.3, 0.3);
    let (t0, ea, s, d) = (20.0, 1.0, 0.1, 0.04);
    let layout = block_with_ropes(b, h, l, t0, ea, s, d);
    // Statics of the rigid block rotated by θ about its downhill toe.
    let w = DENSITY * b * h * l * layout.gravity;
    let r = (b * b + h * h).sqrt() / 2.0;
    let a0 = (b / h).atan();
    let zc = h / 2.0;
    let rope = |theta: f64| {
        let delta = zc * theta.sin() + d;
        let ll = (s * s + delta * delta).sqrt();
        let t = (t0 + ea * (ll - (s * s + d * d).sqrt()) / (s * s + d * d).sqrt()).max(0.0);
        2.0 * t * delta / ll
    };
    let alpha = |theta: f64| a0 - theta + (2.0 * rope(theta) * zc * theta.cos() / (w * r)).asin();
    // Along the path the tilt rises with θ up to its first maximum: the collapse angle.
    let mut best = alpha(0.0);
    let mut theta = 0.0;
    while theta < 0.5 {
        theta += 1e-5;
        let a = alpha(theta);
        if a < best {
            break;
        }
        best = a;
    }
    let want = best.to_degrees();
    let free = a0.to_degrees();
    let run =
        run_tilt(&layout, SolverParams::default(), &TiltParams { resolution_deg: 0.0625, ..TiltParams::default() })
            .expect("stands at 0");
    let got = run.collapse_angle_deg();
    eprintln!("held by ropes: simulated {got:.4} deg, statics {want:.4} deg (free block {free:.4} deg)");
    assert!(want > free + 5.0, "the ropes matter in this case");
    assert!((got - want).abs() < 0.25, "{got} against statics {want}");
    // The same with non-smooth contact dynamics (the rope a smooth force).
    let nscd =
        run_tilt_nscd(&layout, &NscdParams::default(), &TiltParams { resolution_deg: 0.0625, ..TiltParams::default() })
            .expect("stands at 0")
            .collapse_angle_deg();
    eprintln!("held by ropes, nscd: {nscd:.4} deg");
    assert!((nscd - want).abs() < 0.25, "nscd {nscd} against statics {want}");
}

#[test]
fn a_layout_file_s_rope_is_checked_by_name() {
    let text = |rope: &str| {
        format!(
            r#"{{"version": 1, "materials": [{{"name": "m", "density_kg_per_m3": 2200, "kn_pa_per_m": 1e8,
            "ks_pa_per_m": 5e7, "friction_deg": 30}}], "table": {{"material": "m"}},
            "blocks": [{{"id": "b0", "material": "m", "vertices": [[0,0,0],[0.3,0,0],[0.3,0.1,0],[0,0.1,0],
            [0,0,0.3],[0.3,0,0.3],[0.3,0.1,0.3],[0,0.1,0.3]]}}],
            "restraints": {{"ropes": [{rope}]}}}}"#
        )
    };
    let ok = r#"{"x_m": 0.05, "band_m": [0.0, 0.3], "pretension_n": 300, "axial_stiffness_n": 6e4, "span_m": 0.1}"#;
    let l = LayoutSpec::from_json(&text(ok)).unwrap().resolve().unwrap();
    assert_eq!(l.ropes.len(), 1);
    assert_eq!(RopeLoad::of_layout(&l, &WallState::new(&l).bodies)[0].bearers.len(), 1);
    for (rope, key) in [
        (ok.replace("0.05", "0.5"), "restraints.ropes[0].x_m"),
        (ok.replace("[0.0, 0.3]", "[0.3, 0.1]"), "restraints.ropes[0].band_m"),
        (ok.replace("300", "-1"), "restraints.ropes[0].pretension_n"),
        (ok.replace("6e4", "0"), "restraints.ropes[0].axial_stiffness_n"),
        (ok.replace("0.1}", "0}"), "restraints.ropes[0].span_m"),
        (ok.replace("}", r#", "wrap_depth_m": 0.2}"#), "restraints.ropes[0].wrap_depth_m"),
    ] {
        let e = LayoutSpec::from_json(&text(&rope)).unwrap().resolve().unwrap_err().to_string();
        assert!(e.contains(key), "{rope}: {e}");
    }
}

/// A block on the table, end-restrained as the layout file gives it.
fn held_block(restrained: bool) -> Layout {
    let ends = if restrained { r#"[{"blocks":["b0"],"kind":"rigid"}]"# } else { "[]" };
    LayoutSpec::from_json(&format!(
        r#"{{"version":1,"name":"held block","materials":[{{"name":"m","density_kg_per_m3":2400,"kn_pa_per_m":1e9,
        "ks_pa_per_m":5e8,"friction_deg":0}}],"table":{{"material":"m"}},
        "blocks":[{{"id":"b0","material":"m","vertices":[[0,-0.1,0],[0.2,-0.1,0],[0.2,0.1,0],[0,0.1,0],[0,-0.1,0.05],[0.2,-0.1,0.05],[0.2,0.1,0.05],[0,0.1,0.05]]}}],
        "restraints":{{"ends":{ends}}}}}"#
    ))
    .unwrap()
    .resolve()
    .unwrap()
}

fn apply(layout: &mut Layout, e: &str) {
    let mut rng = effect_rng(0, 0, "test", "e");
    let e = Library::builtin().parse(e, drystone::effects::REFERENCE_COURSE_HEIGHT_M).unwrap();
    for stage in [Stage::Layout, Stage::JointLaw, Stage::Restraints] {
        e.apply_stage(stage, layout, &[], &mut rng).unwrap();
    }
}

/// `end_rope` on an end-restrained block on a frictionless table tilted to α: the rigid
/// restraint becomes two ropes 0.05 m in from the ends, which hold the block where their
/// taut-string force balances the downhill weight, `W sin α = 2 · 2 T δ / √(s² + δ²)`
/// (δ solved here by bisection); a wall without end restraints is left as it is.
#[test]
fn end_rope_holds_a_block_on_a_frictionless_table_by_the_taut_string() {
    let (t0, ea) = (50.0, 1e4);
    let mut l = held_block(true);
    apply(&mut l, &format!("end_rope={t0}:{ea}"));
    assert!(l.end_restraints.is_empty(), "the ropes replace the rigid restraint");
    let xs: Vec<f64> = l.ropes.iter().map(|r| r.x).collect();
    assert_eq!(xs.len(), 2);
    assert!((xs[0] - 0.05).abs() < 1e-12 && (xs[1] - 0.15).abs() < 1e-12, "{xs:?}");
    let s = l.ropes[0].span;
    let mut sim = drystone::dem::Simulation::new(&l, SolverParams::default());
    sim.run_to_equilibrium(1e-9, 2_000_000).unwrap();
    let y0 = sim.state.bodies[0].pos.y;
    let alpha = 10f64.to_radians();
    sim.set_tilt(alpha);
    sim.run_to_equilibrium(1e-9, 4_000_000).unwrap();
    let load = sim.state.bodies[0].mass * drystone::units::STANDARD_GRAVITY * alpha.sin();
    let force = |d: f64| {
        let ll = (s * s + d * d).sqrt();
        4.0 * (t0 + ea * (ll - s) / s) * d / ll
    };
    let (mut lo, mut hi) = (0.0, s);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if force(mid) < load {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let dy = sim.state.bodies[0].pos.y - y0;
    eprintln!("held by end ropes: moved {dy:e} m, taut string {lo:e} m");
    assert!((dy - lo).abs() < 2e-3 * lo, "{dy:e} against {lo:e}");

    let free = held_block(false);
    let mut l = free.clone();
    apply(&mut l, "end_rope=300:6e4");
    assert_eq!(l, free, "a wall without end restraints is left alone");
}

/// A generated wall with `end_rope` tilts to the same numbers, bit for bit, run after run
/// and inside rayon pools of 1 and 2 threads (the rope pass is serial, in bearer order).
#[test]
fn a_wall_held_by_end_ropes_tilts_bit_for_bit_on_1_and_2_threads() {
    use rayon::prelude::*;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let wall =
        drystone::generator::Wall::from_file(&root.join("tests/discrepancy/walls/small_restrained.toml")).unwrap();
    let mut l = drystone::generator::generate(&wall, 7, 0).unwrap().check().unwrap();
    apply(&mut l, "end_rope=300:6e4");
    assert_eq!(l.ropes.len(), 2);
    let params = TiltParams { step_deg: 2.0, resolution_deg: 0.5, ..TiltParams::default() };
    let print = || {
        let r = run_tilt(&l, SolverParams::default(), &params).unwrap();
        let mut bits = vec![r.collapse_angle_deg().to_bits()];
        for inc in &r.increments {
            bits.extend(inc.displacement_m.iter().map(|d| d.to_bits()));
        }
        bits
    };
    let reference = print();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let prints: Vec<Vec<u64>> = pool.install(|| (0..2).into_par_iter().map(|_| print()).collect());
        for p in prints {
            assert_eq!(p, reference, "{threads} threads");
        }
    }
}

/// A held block b × h × l with one stiff rope (EA 1e6 N, inside the documented range) over
/// its whole +y face under a sustained −1 g (the d'Alembert force pushes it into the rope)
/// for 2 s and a 3 s tail, by nscd: the rope's explicit force must not make the motion
/// unstable, the default step (1e-3 s) agrees with the fine one (2e-4 s: 2.71°, 3.05° at
/// the default). Before the rope's force was taken at the step's advanced poses the
/// default step rocked it with a growing amplitude to 8.5°.
#[test]
fn a_stiff_rope_keeps_the_nscd_shake_stable_at_the_default_step() {
    use drystone::ground::Motion;
    use drystone::loading::shake::{run_shake_nscd, ShakeParams};
    let (b, h, l) = (0.1125, 0.375, 0.3);
    let mut layout = layout_of(vec![rect_block(b, h, l)], RIGID_KN, RIGID_KN / 2.0, 30.0, BaseSliding::Held);
    layout.ropes.push(Rope {
        x: l / 2.0,
        z_lo: 0.0,
        z_hi: h,
        pretension: 300.0,
        axial_stiffness: 1e6,
        span: 0.1,
        wrap_depth: 0.0,
    });
    let motion = Motion { name: "sustained".into(), dt_s: 0.01, horizontal_g: vec![-1.0; 201], vertical_g: None };
    let params = ShakeParams { tail_s: 3.0, ..ShakeParams::default() };
    let run = |dt: f64| {
        let mut solver = SolverParams::default();
        if dt > 0.0 {
            solver.nscd.dt_s = dt;
        }
        let r = run_shake_nscd(&layout, solver, &motion, &params, &mut |_, _| {}).expect("shake");
        eprintln!(
            "stiff rope, nscd at {:e} s: max rotation {:.4} deg, max drift {:.4e}, overturned {}",
            r.dt_s, r.max_rotation_deg, r.max_drift, r.overturned
        );
        assert!(!r.overturned, "overturned: {r:?}");
        r.max_rotation_deg
    };
    let (coarse, fine) = (run(0.0), run(2e-4));
    assert!(coarse < 4.0 && (coarse - fine).abs() < 0.5, "default step {coarse} deg, fine step {fine} deg");
}
