//! Verification against closed-form statics and dynamics (rigid-block limit analysis; Santa-Cruz et al. 2021, §5).
//!
//! Every case builds its layout here, runs the same code path as `drystone tilt`, and
//! compares with an independent closed form. `drystone verify` prints them; the test suite
//! asserts them.
//!
//! # Closed forms
//!
//! Rigid, cohesionless blocks on a table tilted by α (gravity `g (0, sin α, −cos α)`):
//!
//! * sliding: α = φ;
//! * rectangular block of width b (along y) and height h toppling: tan α = b/h;
//! * symmetric trapezoid monolith (base B, top T, height H): tan α = 3B(B+T) / (2H(B+2T))
//!   (moment of the section's weight about the downhill toe);
//! * stack: for each joint k, tan α_k = d_k / ȳ_k, the lever from the centroid of all blocks
//!   above to the downhill edge of the joint over the centroid's height above it; two
//!   identical blocks with the top one offset downhill by e: interface (b − 2e)/h, base
//!   (b − e)/(2h);
//! * sliding after onset: a = g (sin α − tan φ cos α).
//!
//! # Block on a no-tension Winkler joint (finite Kn)
//!
//! A rectangular block (width b, height h, density ρ) on a joint of normal stiffness Kn
//! (Pa/m) carrying no tension rotates by θ about its base; the weight's resultant on the base
//! then sits at eccentricity e = (h/2) tan β with β = α + θ (the block's own inclination to
//! gravity). Moment and force balance of the linear pressure distribution give (derived
//! here; the classical no-tension foundation, e.g. Timoshenko & Goodier's rigid footing on
//! a Winkler soil, or Housner's rocking block on a flexible base):
//!
//! * full contact (e ≤ b/6): θ = 6 ρ g h² sin β / (Kn b²);
//! * partial contact (e > b/6), contact length c = (3/2)(b − h tan β):
//!   θ = 8 ρ g b h cos β / (9 Kn (b − h tan β)²).
//!
//! The tilt α = β − θ(β) rises to a maximum and falls: that maximum is the collapse angle
//! under a quasi-static tilt. It tends to atan(b/h) as Kn → ∞ and is independent of the
//! block length and of Ks. The shear stiffness moves the block sideways but adds no moment
//! about the base.

pub mod inplane;

use crate::dem::{DensityScaling, RunToEquilibrium, SolverParams};
use crate::layout::{BaseSliding, BlockSpec, Layout, LayoutSpec, MaterialSpec, RestraintSpec, TableSpec};
use crate::loading::tilt::{MechanismKind, TiltParams, TiltResult};
use crate::protocol::run_tilt;

/// The tilt protocol of the verification cases: the defaults with the collapse bracket
/// bisected to 1/16° (the cases are single blocks and small stacks, cheap to refine).
fn verify_tilt() -> TiltParams {
    TiltParams { resolution_deg: 0.0625, ..TiltParams::default() }
}
use crate::units::{deg_to_rad, rad_to_deg};
use serde::Serialize;

/// Stiffness used for the rigid-limit cases, Pa/m. The collapse angles have converged to
/// within 0.01° of the rigid value at this stiffness (see the tests).
pub const RIGID_KN: f64 = 1e13;

/// Density of the verification blocks, kg/m³.
pub const DENSITY: f64 = 2200.0;

/// One angle case.
#[derive(Debug, Clone, Serialize)]
pub struct Case {
    /// Case name.
    pub name: String,
    /// Closed-form angle, degrees.
    pub expected_deg: f64,
    /// DEM angle, degrees.
    pub simulated_deg: f64,
    /// simulated − expected, degrees.
    pub error_deg: f64,
    /// Allowed |error|, degrees.
    pub tolerance_deg: f64,
    /// Mechanism and governing joint found, e.g. `toppling at table/b0`.
    pub detail: String,
    /// Within tolerance (and, where the case names one, the right joint and mechanism).
    pub ok: bool,
}

/// One non-angle check.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    /// Check name.
    pub name: String,
    /// Closed-form value.
    pub expected: f64,
    /// Simulated value.
    pub simulated: f64,
    /// Relative error |sim − exp| / scale (the scale is |exp| unless the check says otherwise).
    pub relative_error: f64,
    /// Allowed relative error.
    pub tolerance: f64,
    /// Unit of the values.
    pub unit: String,
    /// Within tolerance.
    pub ok: bool,
}

/// The verification report.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Angle cases.
    pub cases: Vec<Case>,
    /// Other checks.
    pub checks: Vec<Check>,
    /// The stiffness sweep ([`stiffness_sweep`]).
    pub sweep: Vec<Case>,
}

impl Report {
    /// True if every case and check passed.
    pub fn all_ok(&self) -> bool {
        self.cases.iter().chain(&self.sweep).all(|c| c.ok) && self.checks.iter().all(|c| c.ok)
    }
}

/// A box (m) as layout vertices.
pub fn box_vertices(min: [f64; 3], max: [f64; 3]) -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    for &z in &[min[2], max[2]] {
        for &y in &[min[1], max[1]] {
            for &x in &[min[0], max[0]] {
                v.push([x, y, z]);
            }
        }
    }
    v
}

/// A one-material layout of blocks given as vertex lists.
pub fn layout_of(blocks: Vec<Vec<[f64; 3]>>, kn: f64, ks: f64, phi_deg: f64, base: BaseSliding) -> Layout {
    let spec = LayoutSpec {
        version: 1,
        name: "verification".into(),
        gravity_m_per_s2: crate::units::STANDARD_GRAVITY,
        materials: vec![MaterialSpec {
            name: "m".into(),
            density_kg_per_m3: DENSITY,
            kn_pa_per_m: kn,
            ks_pa_per_m: ks,
            friction_deg: phi_deg,
            cohesion_pa: 0.0,
            tensile_strength_pa: 0.0,
            closure: Default::default(),
        }],
        table: TableSpec { material: "m".into() },
        blocks: blocks
            .into_iter()
            .enumerate()
            .map(|(i, vertices)| BlockSpec {
                id: format!("b{i}"),
                material: "m".into(),
                vertices,
                fixed: false,
                course: None,
                wedge: false,
                own_mass: None,
                bed_closure: None,
            })
            .collect(),
        restraints: RestraintSpec { base_sliding: base, ends: vec![], ropes: vec![] },
        monitors: vec![],
        joint_families: Default::default(),
    };
    spec.resolve().expect("verification layouts are valid")
}

/// A rectangular block of width `b` (y), height `h` (z) and length `l` (x) centred on y = 0.
pub fn rect_block(b: f64, h: f64, l: f64) -> Vec<[f64; 3]> {
    box_vertices([0.0, -b / 2.0, 0.0], [l, b / 2.0, h])
}

/// A symmetric trapezoidal prism 0.3 m long (x): base width `bb` and top width `tt` (y),
/// centred on y = 0, height `hh` (z), m.
///
/// # Panics
/// If a width or the height is not positive.
pub fn trapezoid_block(bb: f64, tt: f64, hh: f64) -> Vec<[f64; 3]> {
    let blk = crate::geometry::ConvexBlock::trapezoidal_prism(
        0.0,
        0.3,
        0.0,
        hh,
        (-bb / 2.0, bb / 2.0),
        (-tt / 2.0, tt / 2.0),
    )
    .expect("positive widths and height");
    blk.vertices.iter().map(|v| [v.x, v.y, v.z]).collect()
}

/// Closed-form collapse tilt (rad) of a rectangular block on a no-tension Winkler joint
/// (module doc): the maximum over β of α(β) = β − θ(β).
pub fn winkler_collapse_angle(b: f64, h: f64, rho: f64, g: f64, kn: f64) -> f64 {
    let theta = |beta: f64| {
        let tb = beta.tan();
        if tb <= b / (3.0 * h) {
            6.0 * rho * g * h * h * beta.sin() / (kn * b * b)
        } else {
            8.0 * rho * g * b * h * beta.cos() / (9.0 * kn * (b - h * tb).powi(2))
        }
    };
    let alpha = |beta: f64| beta - theta(beta);
    // α(β) is unimodal on (0, atan(b/h)): golden-section search for its maximum.
    let (mut lo, mut hi) = (0.0, (b / h).atan() * (1.0 - 1e-12));
    let gr = (5f64.sqrt() - 1.0) / 2.0;
    let mut x1 = hi - gr * (hi - lo);
    let mut x2 = lo + gr * (hi - lo);
    for _ in 0..200 {
        if alpha(x1) < alpha(x2) {
            lo = x1;
            x1 = x2;
            x2 = lo + gr * (hi - lo);
        } else {
            hi = x2;
            x2 = x1;
            x1 = hi - gr * (hi - lo);
        }
    }
    alpha(0.5 * (lo + hi))
}

fn case(name: &str, expected_deg: f64, r: &TiltResult, tol: f64, want: Option<(MechanismKind, &str)>) -> Case {
    let sim = r.collapse_angle_deg();
    let err = sim - expected_deg;
    let detail = format!("{:?} at {}", r.mechanism.kind, r.mechanism.joint).to_lowercase();
    let mech_ok = want.is_none_or(|(k, j)| r.mechanism.kind == k && r.mechanism.joint == j);
    Case {
        name: name.into(),
        expected_deg,
        simulated_deg: sim,
        error_deg: err,
        tolerance_deg: tol,
        detail,
        ok: err.abs() <= tol && mech_ok,
    }
}

/// Block sliding on the table at α = φ (rigid limit). Returns the tilt result.
pub fn sliding_block(phi_deg: f64) -> TiltResult {
    let l = layout_of(
        vec![box_vertices([0.0, -0.15, 0.0], [0.3, 0.15, 0.1])],
        RIGID_KN,
        RIGID_KN / 2.0,
        phi_deg,
        BaseSliding::Free,
    );
    run_tilt(&l, SolverParams::default(), &verify_tilt()).expect("stands at α = 0")
}

/// Rectangular block toppling (rigid limit, φ = 60°).
pub fn toppling_block(b: f64, h: f64) -> TiltResult {
    let l = layout_of(vec![rect_block(b, h, 0.3)], RIGID_KN, RIGID_KN / 2.0, 60.0, BaseSliding::Free);
    run_tilt(&l, SolverParams::default(), &verify_tilt()).expect("stands at α = 0")
}

/// The 1:4 section (B 0.150, T 0.077, H 0.375 m) as one trapezoidal block, 0.3 m long.
pub fn trapezoid_monolith() -> TiltResult {
    let l = layout_of(vec![trapezoid_block(0.150, 0.077, 0.375)], RIGID_KN, RIGID_KN / 2.0, 60.0, BaseSliding::Free);
    run_tilt(&l, SolverParams::default(), &verify_tilt()).expect("stands at α = 0")
}

/// Closed form of the symmetric trapezoid monolith, rad.
pub fn trapezoid_closed_form(bb: f64, tt: f64, hh: f64) -> f64 {
    (3.0 * bb * (bb + tt) / (2.0 * hh * (bb + 2.0 * tt))).atan()
}

/// `n` aligned blocks of width b and height h stacked on the table.
pub fn aligned_stack(n: usize, b: f64, h: f64) -> TiltResult {
    let blocks =
        (0..n).map(|k| box_vertices([0.0, -b / 2.0, k as f64 * h], [0.3, b / 2.0, (k + 1) as f64 * h])).collect();
    let l = layout_of(blocks, RIGID_KN, RIGID_KN / 2.0, 60.0, BaseSliding::Free);
    run_tilt(&l, SolverParams::default(), &verify_tilt()).expect("stands at α = 0")
}

/// Two identical blocks (b × h), the top one offset downhill (+y) by `e`.
pub fn offset_stack(b: f64, h: f64, e: f64) -> TiltResult {
    let blocks = vec![
        box_vertices([0.0, -b / 2.0, 0.0], [0.3, b / 2.0, h]),
        box_vertices([0.0, -b / 2.0 + e, h], [0.3, b / 2.0 + e, 2.0 * h]),
    ];
    let l = layout_of(blocks, RIGID_KN, RIGID_KN / 2.0, 60.0, BaseSliding::Free);
    run_tilt(&l, SolverParams::default(), &verify_tilt()).expect("stands at α = 0")
}

/// A block on the table at a fixed tilt α > φ without damping: the measured acceleration
/// along y, m/s² (least-squares slope of the velocity over 0.2 s after a 0.05 s transient).
pub fn slide_acceleration(alpha_deg: f64, phi_deg: f64) -> f64 {
    let l = layout_of(vec![box_vertices([0.0, -0.15, 0.0], [0.3, 0.15, 0.1])], 1e9, 5e8, phi_deg, BaseSliding::Free);
    let mut sim = crate::dem::Simulation::new(
        &l,
        SolverParams { density_scaling: DensityScaling::Off, ..SolverParams::default() },
    );
    sim.run_to_equilibrium(1e-6, 200_000).expect("finite");
    sim.set_damping(0.0);
    sim.set_tilt(deg_to_rad(alpha_deg));
    let run_for = |sim: &mut crate::dem::Simulation, t: f64| {
        let end = sim.state.time + t;
        while sim.state.time < end {
            sim.step().expect("finite");
        }
    };
    run_for(&mut sim, 0.05);
    // Least-squares slope of v_y(t) over 0.2 s: robust to the rocking the sudden tilt
    // excites in the undamped block (sampling v at two instants picks up its phase).
    let end = sim.state.time + 0.2;
    let (mut n, mut st, mut sv, mut stt, mut stv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    while sim.state.time < end {
        sim.step().expect("finite");
        let (t, v) = (sim.state.time, sim.state.bodies[0].vel.y);
        n += 1.0;
        st += t;
        sv += v;
        stt += t * t;
        stv += t * v;
    }
    (n * stv - st * sv) / (n * stt - st * st)
}

/// The closed-form sliding acceleration g (sin α − tan φ cos α), m/s².
pub fn slide_acceleration_closed_form(alpha_deg: f64, phi_deg: f64) -> f64 {
    let (a, p) = (deg_to_rad(alpha_deg), deg_to_rad(phi_deg));
    crate::units::STANDARD_GRAVITY * (a.sin() - p.tan() * a.cos())
}

/// Tilt test of a block (b × h) on a Winkler joint of stiffness `kn` with a given
/// sub-contact density (φ = 60°, Ks = Kn/2).
pub fn winkler_block(b: f64, h: f64, kn: f64, subdivisions: u32) -> TiltResult {
    let l = layout_of(vec![rect_block(b, h, 0.3)], kn, kn / 2.0, 60.0, BaseSliding::Free);
    let solver = SolverParams { subcontact_subdivisions: subdivisions, ..SolverParams::default() };
    run_tilt(&l, solver, &verify_tilt()).expect("stands at α = 0")
}

/// Free fall of a block 0.5 m above the table for 0.2 s: (simulated drop, exact drop), m.
pub fn free_fall() -> (f64, f64) {
    let l = layout_of(vec![box_vertices([0.0, 0.0, 0.5], [0.2, 0.2, 0.6])], 1e8, 5e7, 30.0, BaseSliding::Free);
    let mut sim = crate::dem::Simulation::new(
        &l,
        SolverParams { damping: 0.0, density_scaling: DensityScaling::Off, ..SolverParams::default() },
    );
    sim.set_time_step(1e-4);
    // Start the leapfrog from rest at t = 0: v(−Δt/2) = +g Δt/2 so that v(0) = 0.
    sim.state.bodies[0].vel = -sim.state.gravity * (0.5 * sim.dt());
    let z0 = sim.state.bodies[0].pos.z;
    for _ in 0..2000 {
        sim.step().expect("finite");
    }
    let t = sim.state.time;
    (z0 - sim.state.bodies[0].pos.z, 0.5 * crate::units::STANDARD_GRAVITY * t * t)
}

/// A block at rest on the table: (sum of table contact normal forces, weight), N.
pub fn weight_at_rest() -> (f64, f64) {
    let l = layout_of(vec![box_vertices([0.0, 0.0, 0.0], [0.2, 0.15, 0.1])], 5e7, 2.5e7, 30.0, BaseSliding::Free);
    let mut sim = crate::dem::Simulation::new(&l, SolverParams::default());
    sim.run_to_equilibrium(1e-8, 500_000).expect("finite");
    let fz: f64 = sim.state.contacts.iter().filter(|c| c.a.is_none()).map(|c| c.force.z).sum();
    (fz, sim.state.bodies[0].mass * crate::units::STANDARD_GRAVITY)
}

/// An undamped block dropped 5 mm onto the table: (total energy at release, total energy
/// at the apex of the first rebound, the drop's potential energy m g h), J. Energies
/// (kinetic + gravitational + elastic in the joints) relative to the release position. Both
/// ends are taken where the velocity is (nearly) zero, so the half-step offset of the
/// leapfrog velocities does not enter the balance. Time step: 0.1 of the critical step
/// (an undamped dynamic run; the quasi-static default is 0.5).
pub fn bounce_energy() -> (f64, f64, f64) {
    let l = layout_of(vec![box_vertices([0.0, 0.0, 0.005], [0.2, 0.15, 0.105])], 1e8, 5e7, 30.0, BaseSliding::Free);
    // A dynamic (undamped) run: time step at 0.1 of critical rather than the quasi-static 0.5.
    let params = SolverParams {
        damping: 0.0,
        contact_margin_m: 0.01,
        timestep_safety: 0.1,
        density_scaling: DensityScaling::Off,
        ..SolverParams::default()
    };
    let mut sim = crate::dem::Simulation::new(&l, params);
    sim.state.bodies[0].vel = -sim.state.gravity * (0.5 * sim.dt());
    let total = |s: &crate::dem::Simulation| {
        let (k, p, e) = s.state.energies();
        k + p + e
    };
    let e0 = total(&sim);
    let mut touched = false;
    let mut rising = false;
    for _ in 0..2_000_000 {
        sim.step().expect("finite");
        if sim.state.contacts.iter().any(|c| c.force.norm() > 0.0) {
            touched = true;
        } else if touched {
            if sim.state.bodies[0].vel.z > 0.0 {
                rising = true;
            } else if rising {
                break; // apex of the rebound
            }
        }
    }
    let mgh = sim.state.bodies[0].mass * crate::units::STANDARD_GRAVITY * 0.005;
    (e0, total(&sim), mgh)
}

/// Runs every case. Takes a few seconds in release mode.
pub fn run_all() -> Report {
    let mut cases = Vec::new();
    let tol = 0.3;
    for phi in [20.0, 30.0] {
        let r = sliding_block(phi);
        cases.push(case(
            &format!("block slides at phi = {phi} deg"),
            phi,
            &r,
            tol,
            Some((MechanismKind::Sliding, "table/b0")),
        ));
    }
    for (b, h) in [(0.1125, 0.375), (0.15, 0.3)] {
        let r = toppling_block(b, h);
        cases.push(case(
            &format!("block {b} x {h} m topples at atan(b/h)"),
            rad_to_deg((b / h).atan()),
            &r,
            tol,
            Some((MechanismKind::Toppling, "table/b0")),
        ));
    }
    let r = trapezoid_monolith();
    cases.push(case(
        "trapezoid monolith of the 1:4 section",
        rad_to_deg(trapezoid_closed_form(0.150, 0.077, 0.375)),
        &r,
        tol,
        Some((MechanismKind::Toppling, "table/b0")),
    ));
    let r = aligned_stack(5, 0.15, 0.075);
    cases.push(case(
        "stack of 5 aligned blocks (base joint)",
        rad_to_deg((0.15f64 / 0.375).atan()),
        &r,
        tol,
        Some((MechanismKind::Toppling, "table/b0")),
    ));
    let (b, h) = (0.15, 0.15);
    let e = 0.2 * b;
    let r = offset_stack(b, h, e);
    cases.push(case(
        "offset stack e = 0.2 b < b/3 (base joint)",
        rad_to_deg(((b - e) / (2.0 * h)).atan()),
        &r,
        tol,
        Some((MechanismKind::Toppling, "table/b0")),
    ));
    let e = 0.4 * b;
    let r = offset_stack(b, h, e);
    cases.push(case(
        "offset stack e = 0.4 b > b/3 (interface joint)",
        rad_to_deg(((b - 2.0 * e) / h).atan()),
        &r,
        tol,
        Some((MechanismKind::Toppling, "b0/b1")),
    ));
    // Sliding after onset, as the friction angle implied by the measured acceleration.
    let (alpha, phi) = (30.0, 20.0);
    let a = slide_acceleration(alpha, phi);
    let ar = deg_to_rad(alpha);
    let phi_app = rad_to_deg(((ar.sin() - a / crate::units::STANDARD_GRAVITY) / ar.cos()).atan());
    cases.push(Case {
        name: format!("slide acceleration at alpha = {alpha} deg, as implied phi (a = {a:.4} m/s2)"),
        expected_deg: phi,
        simulated_deg: phi_app,
        error_deg: phi_app - phi,
        tolerance_deg: tol,
        detail: format!("closed form a = {:.4} m/s2", slide_acceleration_closed_form(alpha, phi)),
        ok: (phi_app - phi).abs() <= tol,
    });
    // Finite stiffness: the paper's Kn on a no-tension Winkler joint, then stiffer joints
    // tending to the rigid angle atan(b/h) = 16.70°.
    let (b, h) = (0.1125, 0.375);
    for kn in [5e7, 1e9, 1e11] {
        let exp = rad_to_deg(winkler_collapse_angle(b, h, DENSITY, crate::units::STANDARD_GRAVITY, kn));
        let r = winkler_block(b, h, kn, SolverParams::default().subcontact_subdivisions);
        cases.push(case(
            &format!("block {b} x {h} m on a Winkler joint, Kn = {kn:.0e} Pa/m"),
            exp,
            &r,
            tol,
            Some((MechanismKind::Toppling, "table/b0")),
        ));
    }
    let sweep = stiffness_sweep();
    let mut checks = Vec::new();
    let (sim, exp) = free_fall();
    checks.push(check("free fall: drop after 0.2 s", exp, sim, exp, 1e-9, "m"));
    let (fz, w) = weight_at_rest();
    checks.push(check("block at rest: table reaction = weight", w, fz, w, 1e-3, "N"));
    let (e0, e1, scale) = bounce_energy();
    checks.push(check("undamped bounce: energy change / m g h_drop", e0, e1, scale, 1e-2, "J"));
    checks.extend(inplane::inplane_checks());
    Report { cases, checks, sweep }
}

/// Normal stiffnesses of the sweep of [`stiffness_sweep`], Pa/m: 1e7 to 1e11 by decades
/// (`tests/suite/stiffness_range.rs` covers 2.5e6 to 1e13 with its own reference).
pub const SWEEP_KN: [f64; 5] = [1e7, 1e8, 1e9, 1e10, 1e11];

/// The block 0.15 × 0.30 m (b × h) on a Winkler joint across [`SWEEP_KN`] (φ = 60°,
/// Ks = Kn/2), against [`winkler_collapse_angle`]: each case passes if the closed form lies
/// within 0.05° of the bracket (last stable, first unstable) and the bracket ends on a
/// collapse, not on a step budget (the detail gives the bracket, the reason, the steps and
/// the implicit iterations).
pub fn stiffness_sweep() -> Vec<Case> {
    let (b, h) = (0.15, 0.30);
    SWEEP_KN
        .iter()
        .map(|&kn| {
            let exp = rad_to_deg(winkler_collapse_angle(b, h, DENSITY, crate::units::STANDARD_GRAVITY, kn));
            let r = winkler_block(b, h, kn, SolverParams::default().subcontact_subdivisions);
            let up = r.first_unstable_deg.unwrap_or(f64::INFINITY);
            let decided = !matches!(r.collapse_reason, Some(crate::loading::tilt::CollapseReason::StepBudget) | None);
            let inside = r.last_stable_deg - 0.05 <= exp && exp <= up + 0.05;
            let mut c = case(
                &format!("stiffness sweep: block {b} x {h} m on a Winkler joint, Kn = {kn:.1e} Pa/m"),
                exp,
                &r,
                up - r.last_stable_deg + 0.05,
                Some((MechanismKind::Toppling, "table/b0")),
            );
            let reason = r
                .collapse_reason
                .and_then(|c| serde_json::to_string(&c).ok())
                .map_or("none".to_string(), |n| n.trim_matches('"').to_string());
            c.detail = format!(
                "{}; bracket [{:.4}, {:.4}] {reason}, {} steps, {} iterations",
                c.detail, r.last_stable_deg, up, r.steps, r.iterations
            );
            c.ok = c.ok && decided && inside;
            c
        })
        .collect()
}

fn check(name: &str, expected: f64, simulated: f64, scale: f64, tolerance: f64, unit: &str) -> Check {
    let relative_error = ((simulated - expected) / scale).abs();
    Check {
        name: name.into(),
        expected,
        simulated,
        relative_error,
        tolerance,
        unit: unit.into(),
        ok: relative_error <= tolerance,
    }
}
