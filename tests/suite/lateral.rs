//! The static lateral load protocol against closed-form statics.

use drystone::dem::{PenaltyParams, Simulation, SolverParams};
use drystone::generator::{generate, Wall};
use drystone::layout::BaseSliding;
use drystone::loading::lateral::{pressure_loads, LateralParams};
use drystone::protocol::run_lateral;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of, DENSITY};
use std::path::Path;

/// A block L × B × h on a Winkler joint under a uniform face pressure p: the base joint
/// shears by u_s = F / (Ks L B) and rotates by θ = M / (Kn I − W h/2) (I = L B³ / 12 about
/// the base centroid, M = F h / 2, the W h/2 term the P-delta of the weight), so the top
/// moves u_s + θ h, as long as the base stays fully compressed (M < W B / 6).
#[test]
fn block_under_uniform_pressure_moves_as_the_winkler_closed_form() {
    let (l, b, h) = (0.5, 0.3, 0.6);
    let (kn, ks) = (1e8, 5e7);
    let p = 500.0;
    let layout = layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [l, b / 2.0, h])], kn, ks, 40.0, BaseSliding::Free);
    let params = LateralParams { pressure_base_pa: p, pressure_top_pa: p, ..LateralParams::default() };
    let solver = SolverParams {
        penalty: PenaltyParams { tolerance: 1e-7, ..PenaltyParams::default() },
        ..SolverParams::default()
    };
    let r = run_lateral(&layout, solver, &params).expect("stands");
    assert!(r.equilibrium, "{r:?}");
    let f = p * l * h;
    let w = DENSITY * G * l * b * h;
    assert!((r.resultant_n.y - f).abs() < 1e-9 * f, "resultant {} vs {f}", r.resultant_n.y);
    assert!((r.weight_n - w).abs() < 1e-9 * w);
    let m = f * h / 2.0;
    assert!(m < w * b / 6.0, "the closed form needs a fully compressed base");
    let u_s = f / (ks * l * b);
    let theta = m / (kn * l * b.powi(3) / 12.0 - w * h / 2.0);
    let expected = u_s + theta * h;
    let d = &r.displacement_m;
    assert_eq!(r.monitors, ["top_left", "top_centre", "top_right"]);
    // The centre, and the mean of the two ends (a twist about z cancels in it).
    for (what, v) in [("top_centre", d[1]), ("mean of top_left and top_right", 0.5 * (d[0] + d[2]))] {
        let err = (v - expected) / expected;
        assert!(err.abs() < 0.005, "{what}: {v:.4e} m vs closed form {expected:.4e} m ({:+.2} %)", 100.0 * err);
    }
    // Hardly any twist about z: the elastic shear of the two triangles of the base acts
    // near their area centroids (it twisted by 4.8 % of the displacement when the shear
    // acted at the pressure centroid; what is left, ≈ 0.5 %, is the 8 % of the strength
    // mobilised moving the point towards the pressure centroid).
    assert!((d[0] - d[2]).abs() < 1e-2 * d[1], "left {:.4e} vs right {:.4e}", d[0], d[2]);
    assert!((r.drift - r.max_displacement_m / h).abs() < 1e-15);
}

/// A trapezoidal pressure p(z) = p0 + (p1 − p0) z / H on a wall face: the y resultant is
/// L H (p0 + p1) / 2 whatever the batter (the face's y projection is its elevation), and its
/// moment about the base line is L H² (p0 / 2 + (p1 − p0) / 3).
#[test]
fn trapezoidal_pressure_on_a_generated_wall_integrates_to_the_closed_form() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls/full_scale_continuous.toml");
    let wall = Wall::from_file(&path).expect("preset");
    let layout = generate(&wall, 1, 0).and_then(|g| g.check()).expect("layout");
    let sim = Simulation::new(&layout, SolverParams::default());
    let (l, hgt) = (wall.length, wall.height);
    let (p0, p1) = (1000.0, 500.0);
    let (loads, faces) = pressure_loads(&sim, 0.0, hgt, p0, p1);
    // Through stones: one loaded face per block, on the −y face only.
    assert_eq!(faces, layout.blocks.len());
    let fy: f64 = loads.iter().map(|(f, _)| f.y).sum();
    let expected = l * hgt * (p0 + p1) / 2.0;
    assert!((fy - expected).abs() < 1e-9 * expected, "resultant {fy} vs {expected}");
    // Moment of the y forces about the x axis through the base line (z = 0): Σ (c × F + T)
    // takes the x component; for the y force alone, −∫ z dF_y.
    let mut mx_y = 0.0;
    for (b, (f, t)) in sim.state.bodies.iter().zip(&loads) {
        let total = b.pos.cross(f) + t;
        // Remove the part of the moment due to the z force (batter), y lever.
        mx_y += total.x;
    }
    let fz: Vec<f64> = loads.iter().map(|(f, _)| f.z).collect();
    assert!(fz.iter().all(|&z| z <= 0.0), "the battered face is pushed down, never up");
    let expected_m = l * hgt * hgt * (p0 / 2.0 + (p1 - p0) / 3.0);
    // The x moment of the pressure: −∫ z dF_y + ∫ y dF_z; the second term is the batter's.
    // On the symmetric batter the face is at y = −B(z)/2, and dF_z = −p tanβ dA_proj, so
    // ∫ y dF_z = ∫ p(z) tanβ B(z)/2 L dz.
    let beta = ((wall.base_width - wall.top_width) / 2.0 / hgt).atan();
    let n = 2000;
    let mut batter = 0.0;
    for k in 0..n {
        let z = (k as f64 + 0.5) * hgt / n as f64;
        let bz = wall.base_width + (wall.top_width - wall.base_width) * z / hgt;
        batter += (p0 + (p1 - p0) * z / hgt) * beta.tan() * bz / 2.0 * l * hgt / n as f64;
    }
    let m_expected = -expected_m + batter;
    assert!((mx_y - m_expected).abs() < 1e-6 * expected_m, "moment {mx_y} vs {m_expected}");
}

/// Only exposed faces are loaded: of two blocks back to back in y, the front one (facing
/// −y) carries the pressure and the hidden face of the back one nothing.
#[test]
fn hidden_faces_carry_no_pressure() {
    let (l, b, h) = (0.4, 0.2, 0.3);
    let layout = layout_of(
        vec![box_vertices([0.0, -b, 0.0], [l, 0.0, h]), box_vertices([0.0, 0.0, 0.0], [l, b, h])],
        1e8,
        5e7,
        35.0,
        BaseSliding::Free,
    );
    let sim = Simulation::new(&layout, SolverParams::default());
    let (loads, faces) = pressure_loads(&sim, 0.0, h, 800.0, 800.0);
    assert_eq!(faces, 1);
    assert!((loads[0].0.y - 800.0 * l * h).abs() < 1e-9);
    assert_eq!(loads[1].0, drystone::Vec3::zeros());
}

/// A pressure far above the overturning load collapses the wall: reported as a result
/// (no equilibrium), not an error.
#[test]
fn overturning_pressure_is_reported_as_collapse() {
    let (l, b, h) = (0.5, 0.2, 0.6);
    let layout =
        layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [l, b / 2.0, h])], 1e8, 5e7, 40.0, BaseSliding::Free);
    // Overturning about the toe: p L h · h/2 > W b/2  ⇔  p > ρ g b² / h.
    let p_over = DENSITY * G * b * b / h;
    let params =
        LateralParams { pressure_base_pa: 2.0 * p_over, pressure_top_pa: 2.0 * p_over, ..LateralParams::default() };
    let r = run_lateral(&layout, SolverParams::default(), &params).expect("runs");
    assert!(!r.equilibrium);
    assert_eq!(r.collapse_reason.as_deref(), Some("total_displacement"));
    let params =
        LateralParams { pressure_base_pa: 0.5 * p_over, pressure_top_pa: 0.5 * p_over, ..LateralParams::default() };
    let r = run_lateral(&layout, SolverParams::default(), &params).expect("runs");
    assert!(r.equilibrium, "half the overturning pressure stands: {r:?}");
}
