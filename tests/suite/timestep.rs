//! The time step comes from the largest eigenvalue of the assembled, density-scaled
//! stiffness (`dem::timestep::Stiffness::max_eigenvalue`, Lanczos). Checked against an
//! independent reference: the dense eigen-solution of the same matrix assembled spring by
//! spring (normal `Kn·A/3` and two shear `Ks·A/3` per sub-contact node) in this test, on the
//! SBL wall (195 blocks, 1,170 degrees of freedom) as generated and after it settled, with
//! scalar and with block density scaling.

use drystone::dem::integrator::{advance, YConstraint};
use drystone::dem::state::Body;
use drystone::dem::timestep::Stiffness;
use drystone::dem::RunToEquilibrium;
use drystone::dem::{DensityScaling, Simulation, SolverParams};
use drystone::generator::{generate, Wall};
use drystone::geometry::ConvexBlock;
use drystone::math::inv_sqrt;
use drystone::Vec3;
use nalgebra::DMatrix;
use std::path::PathBuf;

use crate::common;

/// `λ_max(M^{-1/2} K M^{-1/2})` by dense assembly, one spring at a time.
fn dense_max_eigenvalue(sim: &Simulation) -> f64 {
    let n = sim.state.bodies.len();
    let mut k = DMatrix::<f64>::zeros(6 * n, 6 * n);
    for c in &sim.state.contacts {
        let nrm = sim.state.contact_normal(c);
        let (t1, t2) = drystone::geometry::polygon::plane_basis(&nrm);
        for s in &c.subs {
            for &i in &s.nodes {
                let nd = &c.nodes[i as usize];
                let w = s.area / 3.0;
                for (kk, d) in [(c.joint.kn * w, nrm), (c.joint.ks * w, t1), (c.joint.ks * w, t2)] {
                    let mut g: Vec<(usize, [f64; 6])> = Vec::new();
                    let b = &sim.state.bodies[c.b];
                    if !b.fixed() {
                        let m = (b.rot_mat * nd.on_b).cross(&d);
                        g.push((c.b, [d.x, d.y, d.z, m.x, m.y, m.z]));
                    }
                    if let Some(ia) = c.a.filter(|&ia| !sim.state.bodies[ia].fixed()) {
                        let m = (sim.state.bodies[ia].rot_mat * nd.on_a).cross(&d);
                        g.push((ia, [-d.x, -d.y, -d.z, -m.x, -m.y, -m.z]));
                    }
                    for (p, gp) in &g {
                        for (q, gq) in &g {
                            for i in 0..6 {
                                for j in 0..6 {
                                    k[(6 * p + i, 6 * q + j)] += kk * gp[i] * gq[j];
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    let s = mass_root(sim);
    (&s * k * &s).symmetric_eigenvalues().iter().cloned().fold(0.0, f64::max)
}

/// `M^{-1/2}` of the inertial masses the integrator uses (block masses where set, else the
/// density-scaled mass and inertia), dense, 6 per body; zero rows for fixed bodies.
fn mass_root(sim: &Simulation) -> DMatrix<f64> {
    let n = sim.state.bodies.len();
    let mut s = DMatrix::<f64>::zeros(6 * n, 6 * n);
    for (i, b) in sim.state.bodies.iter().enumerate() {
        if b.fixed() {
            continue;
        }
        if let Some(bm) = &b.block_mass {
            let r = bm.q * nalgebra::Matrix6::from_diagonal(&bm.inv_lambda.map(f64::sqrt)) * bm.q.transpose();
            s.view_mut((6 * i, 6 * i), (6, 6)).copy_from(&r);
            continue;
        }
        let scale = 1.0 / b.inertia_scale_inv;
        for d in 0..3 {
            s[(6 * i + d, 6 * i + d)] = 1.0 / (scale * b.mass).sqrt();
        }
        let r = inv_sqrt(&(b.rot_mat * b.inertia * b.rot_mat.transpose() * scale));
        for p in 0..3 {
            for q in 0..3 {
                s[(6 * i + 3 + p, 6 * i + 3 + q)] = r[(p, q)];
            }
        }
    }
    s
}

#[test]
fn the_lanczos_step_bounds_the_dense_top_eigenvalue_closely() {
    let wall = Wall::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/walls/sbl.toml")).unwrap();
    let layout = generate(&wall, 20210917, 0).unwrap().check().unwrap();
    // Scalar density scaling, then block scaling.
    for params in
        [SolverParams { density_scaling: DensityScaling::Scalar, ..SolverParams::default() }, SolverParams::default()]
    {
        let mut sim = Simulation::new(&layout, params);
        assert_eq!(
            sim.state.bodies.iter().any(|b| b.block_mass.is_some()),
            matches!(params.density_scaling, DensityScaling::Block { .. })
        );
        for settled in [false, true] {
            if settled {
                assert!(sim.run_to_equilibrium(1e-4, 100_000).unwrap());
            }
            let stiffness = Stiffness::new(&sim.state.bodies, &sim.state.contacts);
            let lanczos = stiffness.max_eigenvalue(&sim.state.bodies);
            let dense = dense_max_eigenvalue(&sim);
            // An over-estimate (the residual bound), by under 1 %.
            assert!(lanczos >= dense * (1.0 - 1e-9) && lanczos <= dense * 1.01, "{lanczos:e} vs dense {dense:e}");
            if !settled {
                // The engine's step is the one of this eigenvalue under local damping α:
                // safety × 2 / (ω_max √(1 + α)).
                let want = params.timestep_safety * 2.0 / (lanczos.sqrt() * (1.0 + params.damping).sqrt());
                assert_eq!(sim.dt(), want);
            }
        }
        // Scalar scaling: below the classical bound 2 max λ_body (every body has the same
        // scaled λ_body), which the assembled matrix does not reach.
        if !matches!(params.density_scaling, DensityScaling::Block { .. }) {
            let stiffness = Stiffness::new(&sim.state.bodies, &sim.state.contacts);
            let bound = 2.0
                * stiffness
                    .body_eigenvalues()
                    .iter()
                    .zip(&sim.state.bodies)
                    .map(|(l, b)| l * b.inertia_scale_inv)
                    .fold(0.0, f64::max);
            let dense = dense_max_eigenvalue(&sim);
            assert!(dense < 0.9 * bound, "{dense:e} vs bound {bound:e}");
        }
    }
}

/// The reason for the factor √(1 + α): one body on a linear spring (force −k x along z,
/// ω² = k/m), integrated by the engine's `advance` with local damping α = 0.8, settles at
/// ω Δt = 1.45 and diverges at ω Δt = 1.55, either side of 2/√1.8 = 1.491 (the undamped
/// scheme is stable up to 2).
#[test]
fn local_damping_lowers_the_stable_step_by_the_square_root_of_one_plus_alpha() {
    let cube: Vec<Vec3> = drystone::verify::box_vertices([0.0; 3], [0.1; 3]).iter().map(|v| Vec3::from(*v)).collect();
    let shape = ConvexBlock::from_vertices(&cube).unwrap();
    let run = |omega_dt: f64, damping: f64| -> f64 {
        let mut b = Body::new("b".into(), &shape, 2500.0, 0, false);
        let k = 1e6;
        let dt = omega_dt / (k / b.mass).sqrt();
        let z0 = b.pos.z;
        b.pos.z += 1e-3;
        let mut largest: f64 = 0.0;
        for _ in 0..2000 {
            let f = Vec3::new(0.0, 0.0, -k * (b.pos.z - z0));
            advance(&mut b, f, Vec3::zeros(), dt, damping, YConstraint::Free);
            largest = largest.max((b.pos.z - z0).abs());
        }
        (b.pos.z - z0).abs().max(if largest.is_finite() { 0.0 } else { f64::INFINITY })
    };
    let limit = 2.0 / 1.8f64.sqrt();
    assert!(run(0.97 * limit, 0.8) < 1e-12, "settles below the damped limit");
    assert!(run(1.04 * limit, 0.8) > 1.0, "diverges above it");
    assert!(run(1.04 * limit, 0.0) < 2e-3, "stable without damping");
}

/// Block density scaling changes the path to each equilibrium, not the equilibria: on the
/// 24-block running-bond wall it gives the same collapse bracket and, up to 80 % of the
/// collapse angle, the same displacements (within 2 % of the largest; both are equilibria to
/// the same tolerance), in fewer steps than scalar scaling.
#[test]
fn block_scaling_reaches_the_same_equilibria_in_fewer_steps() {
    use drystone::layout::Layout;
    use drystone::loading::tilt::{TiltParams, TiltResult};
    use drystone::protocol::run_tilt;
    let l = Layout::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/layouts/running_bond_wall.json"))
        .unwrap();
    // Density scaling acts on dynamic relaxation: without the implicit relaxation.
    let tilt = TiltParams { implicit: false, ..TiltParams::default() };
    let block = run_tilt(&l, SolverParams::default(), &tilt).unwrap();
    let scalar =
        run_tilt(&l, SolverParams { density_scaling: DensityScaling::Scalar, ..SolverParams::default() }, &tilt)
            .unwrap();
    assert_eq!(block.collapse_angle_deg(), scalar.collapse_angle_deg());
    assert_eq!(block.first_unstable_deg, scalar.first_unstable_deg);
    let limit = 0.8 * scalar.collapse_angle_deg();
    let linear = |r: &TiltResult| -> Vec<(f64, Vec<f64>, u64)> {
        r.increments
            .iter()
            .filter(|i| i.stable && i.alpha_deg > 0.0 && i.alpha_deg <= limit)
            .map(|i| (i.alpha_deg, i.displacement_m.clone(), i.steps))
            .collect()
    };
    let (a, b) = (linear(&block), linear(&scalar));
    assert_eq!(a.len(), b.len());
    let largest = b.iter().flat_map(|(_, d, _)| d.iter().map(|v| v.abs())).fold(0.0, f64::max);
    for ((alpha, da, _), (beta, db, _)) in a.iter().zip(&b) {
        assert_eq!(alpha, beta);
        for (x, y) in da.iter().zip(db) {
            assert!((x - y).abs() <= 0.02 * largest, "at {alpha}°: {x} vs {y} m");
        }
    }
    let steps = |v: &[(f64, Vec<f64>, u64)]| v.iter().map(|x| x.2).sum::<u64>() as f64;
    assert!(steps(&a) < 0.9 * steps(&b), "{} steps with block scaling, {} with scalar", steps(&a), steps(&b));
}

/// A tilt whose block-scaled dynamics blow up is repeated with scalar scaling and the run
/// goes on: a block (0.1125 × 0.375 m) on the paper's soft joint (Kn 5e7 Pa/m) tilted in 10°
/// steps topples at 11.9° (Winkler closed form 11.72°); the first failing increment, a
/// jump from 10° to 20°, throws the light soft directions of its block mass into
/// re-closing contacts and blows up. The run records the fallback and ends with the
/// collapse bracket and mechanism of a run with scalar scaling throughout.
#[test]
fn a_blown_up_block_scaled_increment_is_repeated_with_scalar_scaling() {
    use drystone::layout::BaseSliding;
    use drystone::loading::tilt::TiltParams;
    use drystone::protocol::run_tilt;
    use drystone::verify::{layout_of, rect_block};
    let l = layout_of(vec![rect_block(0.1125, 0.375, 0.3)], 5e7, 2.5e7, 60.0, BaseSliding::Free);
    let tilt = TiltParams { step_deg: 10.0, implicit: false, ..TiltParams::default() };
    let block = run_tilt(&l, SolverParams::default(), &tilt).unwrap();
    let scalar =
        run_tilt(&l, SolverParams { density_scaling: DensityScaling::Scalar, ..SolverParams::default() }, &tilt)
            .unwrap();
    assert_eq!(block.scalar_fallbacks_deg, vec![20.0]);
    assert!(scalar.scalar_fallbacks_deg.is_empty());
    assert_eq!(block.collapse_angle_deg(), scalar.collapse_angle_deg());
    assert_eq!(block.first_unstable_deg, scalar.first_unstable_deg);
    assert_eq!(block.mechanism, scalar.mechanism);
    let closed_form = drystone::verify::winkler_collapse_angle(0.1125, 0.375, drystone::verify::DENSITY, 9.81, 5e7);
    assert!((block.collapse_angle_deg() - closed_form.to_degrees()).abs() < 0.3, "{}", block.collapse_angle_deg());
}

/// The CLI names a fallback: `drystone tilt --no-implicit` on the soft-jointed block of the
/// test above, tilted in 10° steps, prints the tilt at which block scaling blew up.
#[test]
fn the_tilt_command_reports_a_scalar_fallback() {
    let vertices = drystone::verify::rect_block(0.1125, 0.375, 0.3);
    let layout = serde_json::json!({
        "version": 1,
        "materials": [{"name": "m", "density_kg_per_m3": drystone::verify::DENSITY, "kn_pa_per_m": 5e7,
                       "ks_pa_per_m": 2.5e7, "friction_deg": 60.0}],
        "table": {"material": "m"},
        "blocks": [{"id": "b0", "material": "m", "vertices": vertices}]
    });
    let dir = common::Scratch::created("timestep-fallback");
    let path = dir.join("block.json");
    std::fs::write(&path, layout.to_string()).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["tilt", path.to_str().unwrap(), "--step-deg", "10", "--no-implicit"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("blew up at 20.000 deg; repeated with scalar scaling"), "{text}");
}
