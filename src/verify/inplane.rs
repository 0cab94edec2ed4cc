//! The in-plane shear–compression test's verification cases: one block on the table under
//! the loading beam, its rocking and sliding peaks and its elastic stiffness against their
//! closed forms (`loading::inplane`), by limit analysis and by the penalty DEM.

use super::{box_vertices, check, Check, DENSITY, RIGID_KN};
use crate::dem::SolverParams;
use crate::layout::{BlockSpec, Layout, LayoutSpec, MaterialSpec, RestraintSpec, TableSpec};

/// The in-plane verification wall: one block `L × t × H` = 1.0 × 0.2 × 1.2 m (the granite
/// specimens' size) of a material with friction 45° on a table whose joint has friction
/// `table_phi_deg`, both joints of normal and shear stiffness `kn`, `kn / 2.5` (Pa/m).
pub fn inplane_block(table_phi_deg: f64, kn: f64) -> Layout {
    let material = |name: &str, phi: f64| MaterialSpec {
        name: name.into(),
        density_kg_per_m3: DENSITY,
        kn_pa_per_m: kn,
        ks_pa_per_m: kn / 2.5,
        friction_deg: phi,
        cohesion_pa: 0.0,
        tensile_strength_pa: 0.0,
        closure: Default::default(),
    };
    LayoutSpec {
        version: 1,
        name: "in-plane verification block".into(),
        gravity_m_per_s2: crate::units::STANDARD_GRAVITY,
        materials: vec![material("stone", 45.0), material("foundation", table_phi_deg)],
        table: TableSpec { material: "foundation".into() },
        blocks: vec![BlockSpec {
            id: "wall".into(),
            material: "stone".into(),
            vertices: box_vertices([0.0, -0.1, 0.0], [1.0, 0.1, 1.2]),
            fixed: false,
            course: None,
            wedge: false,
            own_mass: None,
            bed_closure: None,
        }],
        restraints: RestraintSpec::default(),
        monitors: vec![],
        joint_families: Default::default(),
    }
    .resolve()
    .expect("verification layouts are valid")
}

/// The in-plane test's parameters of the verification cases: σ0 = 0.5 MPa, H0 = 1.325 m,
/// monotonic to `drift_pct`.
pub fn inplane_params(drift_pct: f64) -> crate::loading::inplane::InPlaneParams {
    crate::loading::inplane::InPlaneParams {
        sigma0_mpa: 0.5,
        shear_span_m: Some(1.325),
        drift_pct,
        ..Default::default()
    }
}

/// The axial force at the base of [`inplane_block`] under [`inplane_params`], N:
/// `σ0 L t + ρ g L t H`.
pub fn inplane_n_total() -> f64 {
    0.5e6 * 1.0 * 0.2 + DENSITY * crate::units::STANDARD_GRAVITY * 1.0 * 0.2 * 1.2
}

/// The in-plane closed forms (`loading::inplane`): the monolith rocking about its toe at
/// `V = N_total L / (2 H0)` (table friction 45°) and sliding on its base at
/// `V = μ N_total` (table friction atan 0.2: μ = 0.2 < L / (2 H0) = 0.377), by limit
/// analysis (1e-6 relative) and by the penalty DEM's peak (2 %, rigid joints Kn = 1e13
/// Pa/m, where the toe's elastic contact zone and the P–Δ of the peak's rotation are
/// under 1 %); and the elastic stiffness of the block on joints of Kn = 1e9 Pa/m against
/// [`crate::loading::inplane::one_block_stiffness`] with its first-order P–Δ (1 %).
pub fn inplane_checks() -> Vec<Check> {
    use crate::limit::inplane::limit_in_plane;
    use crate::loading::inplane::{one_block_stiffness, run_in_plane_penalty};
    let solver = SolverParams::default();
    let n_total = inplane_n_total();
    let mut checks = Vec::new();
    let cases = [
        ("rocking about the toe: V = N_total L / (2 H0)", 45.0, n_total * 1.0 / (2.0 * 1.325)),
        ("sliding on the base: V = mu N_total", 0.2_f64.atan().to_degrees(), 0.2 * n_total),
    ];
    for (name, phi, v) in cases {
        let wall = inplane_block(phi, RIGID_KN);
        let p = inplane_params(1.0);
        let la = limit_in_plane(&wall, &solver, &p, &solver.limit).map_or(f64::NAN, |r| r.peak_force_kn * 1e3);
        checks.push(check(&format!("in-plane, limit analysis: {name}"), v, la, v, 1e-6, "N"));
        let dem = run_in_plane_penalty(&wall, solver, &inplane_params(0.5), &mut |_, _, _| {})
            .ok()
            .and_then(|r| r.positive)
            .map_or(f64::NAN, |d| d.peak_force_kn * 1e3);
        checks.push(check(&format!("in-plane, penalty DEM peak: {name}"), v, dem, v, 2e-2, "N"));
    }
    let kn = 1e9;
    let w = DENSITY * crate::units::STANDARD_GRAVITY * 1.0 * 0.2 * 1.2;
    let k = one_block_stiffness(1.0, 0.2, 1.2, 1.325, 1.325, kn, kn / 2.5, 0.5e6 * 0.2, w);
    let run = run_in_plane_penalty(&inplane_block(45.0, kn), solver, &inplane_params(0.05), &mut |_, _, _| {}).ok();
    let dem = run.as_ref().and_then(|r| r.positive).map_or(f64::NAN, |d| d.initial_stiffness_kn_per_mm * 1e6);
    checks.push(check("in-plane, penalty DEM: elastic stiffness of one block (read at H0)", k, dem, k, 1e-2, "N/m"));
    // The vertical loading phase: the block between the table and the beam, each on a
    // linear joint of Kn, shortens by 2 Δσ / Kn under the stress Δσ the actuator adds, so
    // the wall's vertical modulus is Kn H / 2.
    let e = kn * 1.2 / 2.0 * 1e-6;
    let dem = run.as_ref().map_or(f64::NAN, |r| r.wall_vertical_modulus_mpa);
    checks.push(check("in-plane, penalty DEM: vertical modulus of one block, Kn H / 2", e, dem, e, 1e-3, "MPa"));
    checks
}
