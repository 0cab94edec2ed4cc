//! The in-plane rig's own terms (`Layout::vertical_load_rig`: the effects `jack_incline`,
//! `series_compliance`, `load_eccentricity`, `fixed_vertical_load`, `beam_restraint`)
//! against the statics of a monolithic wall worked by hand here (L × t × H = 1.0 × 0.2 ×
//! 1.2 m under σ0 = 0.5 MPa, the force at H0 = 1.325 m, the beam's centroid there too):
//!
//! * an eccentric vertical load `e0` moves the rocking capacity about the pushed toe to
//!   `(N_total L / 2 − e0 P) / H0` (P the force the jacks apply, `N − W_beam`), by limit
//!   analysis exactly and by the penalty DEM and nscd within their closed-form tolerances;
//! * a load fixed in space (κ = 1) holds its arm `L / 2` while the wall rocks: at the same
//!   displacement `u` of the beam's centroid the force exceeds a following load's by
//!   `P u / H0`, and the envelope keeps its peak where the following load's falls;
//! * a rotational spring `K_θ` on the beam adds `K_θ θ / H0`, θ = u / H0 of rigid rocking;
//! * an inclined load adds `N tan β` to both senses' readings of a sliding monolith (so the
//!   peaks differ by `2 N tan β`), and a compliance `c` in series gives the stiffness read
//!   `1 / (1 / K + c)` and moves every point by `c V`, leaving the force as it was.

use drystone::dem::SolverParams;
use drystone::layout::{Layout, VerticalLoadRig};
use drystone::limit::inplane::limit_in_plane;
use drystone::loading::inplane::{run_in_plane_penalty, History, InPlaneParams, InPlaneResult, MechanismKind, Rig};
use drystone::loading::inplane_nscd::run_in_plane_nscd;
use drystone::verify::inplane::inplane_block;
use drystone::verify::{DENSITY, RIGID_KN};

const G: f64 = drystone::units::STANDARD_GRAVITY;
const L: f64 = 1.0;
const T: f64 = 0.2;
const H: f64 = 1.2;
const H0: f64 = 1.325;
const SIGMA0: f64 = 0.5e6;

fn params(drift_pct: f64) -> InPlaneParams {
    InPlaneParams { sigma0_mpa: SIGMA0 * 1e-6, shear_span_m: Some(H0), drift_pct, ..InPlaneParams::default() }
}

/// N, W (the wall's weight) and P = N − W_beam, N; the beam is L × t × 2 (H0 − H).
fn forces() -> (f64, f64, f64) {
    let n = SIGMA0 * L * T;
    let w_beam = DENSITY * G * L * T * 2.0 * (H0 - H);
    (n, DENSITY * G * L * T * H, n - w_beam)
}

fn with(rig: VerticalLoadRig, kn: f64, phi_deg: f64) -> Layout {
    let mut wall = inplane_block(phi_deg, kn);
    wall.vertical_load_rig = rig;
    wall
}

fn penalty(wall: &Layout, p: &InPlaneParams) -> InPlaneResult {
    run_in_plane_penalty(wall, SolverParams::default(), p, &mut |_, _, _| {}).unwrap()
}

#[test]
fn the_beams_weight_is_the_one_worked_by_hand() {
    let (n, _, p) = forces();
    let rig = Rig::build(&inplane_block(45.0, 1e11), &params(1.0)).unwrap();
    assert!((rig.beam_weight_n - (n - p)).abs() < 1e-9 * n, "{} N vs {} N", rig.beam_weight_n, n - p);
    assert!((rig.beam_z_m - H0).abs() < 1e-12);
}

#[test]
fn an_eccentric_vertical_load_moves_the_rocking_capacity_by_its_moment() {
    let (n, w, p) = forces();
    let s = SolverParams::default();
    // On the granite walls' order of joint stiffness the peak at 0.5 % drift is not yet the
    // rigid capacity (the joints' rotation): the eccentricity moves it by its moment alone.
    let centred = penalty(&inplane_block(45.0, 1e11), &params(0.5)).positive.unwrap().peak_force_kn * 1e3;
    for e0 in [0.03, -0.03] {
        let v = ((n + w) * L / 2.0 - e0 * p) / H0;
        let rig = VerticalLoadRig { eccentricity_m: e0, ..VerticalLoadRig::default() };
        let la = limit_in_plane(&with(rig, RIGID_KN, 45.0), &s, &params(1.0), &s.limit).unwrap();
        assert!(
            (la.peak_force_kn * 1e3 / v - 1.0).abs() < 1e-6,
            "e0 {e0}: limit analysis {} kN vs {v} N",
            la.peak_force_kn
        );
        let dem = penalty(&with(rig, RIGID_KN, 45.0), &params(0.5));
        let peak = dem.positive.unwrap().peak_force_kn * 1e3;
        assert!((peak / v - 1.0).abs() < 0.02, "e0 {e0}: DEM peak {peak} N vs {v} N");
        assert_eq!(dem.unconverged, 0);
        let dem = penalty(&with(rig, 1e11, 45.0), &params(0.5));
        let shift = dem.positive.unwrap().peak_force_kn * 1e3 - centred;
        assert!((shift / (-e0 * p / H0) - 1.0).abs() < 0.02, "e0 {e0}: DEM shift {shift} N vs −e0 P / H0");
        assert_eq!(dem.mechanism.kind, MechanismKind::Rocking);
    }
    // nscd, the rigid monolith (its closed-form tolerance: 1 %).
    let e0 = 0.03;
    let v = ((n + w) * L / 2.0 - e0 * p) / H0;
    let rig = VerticalLoadRig { eccentricity_m: e0, ..VerticalLoadRig::default() };
    let r = run_in_plane_nscd(&with(rig, RIGID_KN, 45.0), &SolverParams::default().nscd, &params(0.2)).unwrap();
    let peak = r.positive.unwrap().peak_force_kn * 1e3;
    assert!((peak / v - 1.0).abs() < 0.01, "nscd peak {peak} N vs {v} N");
}

#[test]
fn a_vertical_load_fixed_in_space_keeps_its_arm_as_the_wall_rocks() {
    let (_, _, p) = forces();
    let follows = penalty(&with(VerticalLoadRig::default(), 1e11, 45.0), &params(3.0));
    let fixed =
        penalty(&with(VerticalLoadRig { fixed_share: 1.0, ..VerticalLoadRig::default() }, 1e11, 45.0), &params(3.0));
    assert_eq!(fixed.unconverged, 0);
    let (a, b) = (follows.curve.last().unwrap(), fixed.curve.last().unwrap());
    assert!((a.top_mm - b.top_mm).abs() < 1e-6 * b.top_mm, "the same imposed displacement");
    // The beam's centroid is the measuring point (at H0): it moved by u.
    let dv = (b.force_kn - a.force_kn) * 1e3;
    let want = p * b.top_mm * 1e-3 / H0;
    assert!((dv / want - 1.0).abs() < 0.05, "ΔV {dv} N vs P u / H0 {want} N at {} mm", b.top_mm);
    // The fixed load's envelope holds its peak; the following load's sways off it.
    let (pf, pa) = (fixed.positive.unwrap().peak_force_kn, follows.positive.unwrap().peak_force_kn);
    assert!(b.force_kn > 0.99 * pf, "fixed: {} kN at 3 % of a {pf} kN peak", b.force_kn);
    assert!(a.force_kn < 0.95 * pa, "following: {} kN at 3 % of a {pa} kN peak", a.force_kn);
}

#[test]
fn a_rotational_restraint_of_the_beam_adds_its_springs_moment_over_the_shear_span() {
    let k = 2e6;
    let free = penalty(&with(VerticalLoadRig::default(), 1e11, 45.0), &params(1.0));
    let held = penalty(
        &with(VerticalLoadRig { rotational_stiffness_nm_per_rad: k, ..VerticalLoadRig::default() }, 1e11, 45.0),
        &params(1.0),
    );
    assert_eq!(held.unconverged, 0);
    let (a, b) = (free.curve.last().unwrap(), held.curve.last().unwrap());
    let theta = b.top_mm * 1e-3 / H0;
    let want = k * theta / H0;
    let dv = (b.force_kn - a.force_kn) * 1e3;
    assert!((dv / want - 1.0).abs() < 0.03, "ΔV {dv} N vs K θ / H0 {want} N");
}

#[test]
fn an_inclined_load_and_a_series_compliance_move_the_readings_by_their_statics() {
    let (n, w, _) = forces();
    let mu: f64 = 0.2;
    let phi = mu.atan().to_degrees();
    let p = InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.5]), ..params(0.5) };
    let tan_b = -0.013;
    let r = penalty(&with(VerticalLoadRig { incline: tan_b, ..VerticalLoadRig::default() }, 1e10, phi), &p);
    let (pos, neg) = (r.positive.unwrap().peak_force_kn * 1e3, r.negative.unwrap().peak_force_kn * 1e3);
    let (vp, vn) = (mu * (n + w) + n * tan_b, mu * (n + w) - n * tan_b);
    assert!((pos / vp - 1.0).abs() < 0.01, "+x: {pos} N vs {vp} N");
    assert!((neg / vn - 1.0).abs() < 0.01, "−x: {neg} N vs {vn} N");
    assert!(((neg - pos) / (-2.0 * n * tan_b) - 1.0).abs() < 0.02, "asymmetry {} N", neg - pos);
    // The series compliance: every point moved by c V, the force as it was.
    let c = 0.05e-6;
    let plain = penalty(&with(VerticalLoadRig::default(), 1e10, phi), &params(0.5));
    let soft = penalty(
        &with(VerticalLoadRig { series_compliance_m_per_n: c, ..VerticalLoadRig::default() }, 1e10, phi),
        &params(0.5),
    );
    assert_eq!(plain.curve.len(), soft.curve.len());
    for (a, b) in plain.curve.iter().zip(&soft.curve) {
        assert_eq!(a.force_kn, b.force_kn);
        let moved = (b.top_mm - a.top_mm) * 1e-3;
        assert!((moved - c * a.force_kn * 1e3).abs() < 1e-12, "{moved} m at {} kN", a.force_kn);
        let drift = 100.0 * moved / H0;
        assert!((b.drift_pct - a.drift_pct - drift).abs() < 1e-9);
    }
    let (k0, k1) =
        (plain.positive.unwrap().initial_stiffness_kn_per_mm, soft.positive.unwrap().initial_stiffness_kn_per_mm);
    // kN/mm → N/m: 1e6.
    let want = 1.0 / (1.0 / (k0 * 1e6) + c) * 1e-6;
    assert!((k1 / want - 1.0).abs() < 1e-9, "{k1} kN/mm vs 1 / (1 / {k0} + c) = {want}");
}

/// The rig at a shear span far above the wall (H0 = 2, 3.5 and 6 times the wall's height
/// of 1.2 m; the beam, as deep as the wall's quarter, has its centroid well below the
/// actuator's point): the rigid monolith rocks about its toe at the hand statics
/// `V = N_total L / (2 H0)` (moments about the toe of the vertical loads, the force's arm
/// H0), every increment converged, and the beam stays on the wall (its measuring point
/// moves by the imposed drift, nothing is thrown). The lever of the actuator above the
/// beam's centroid was integrated with the beam's own inertia about its centroid instead
/// of about the actuator's point: the rotation about the held point ran unstable.
#[test]
fn a_monolith_rocks_at_its_closed_form_at_any_shear_span() {
    let (n, w, _) = forces();
    let wall = inplane_block(45.0, RIGID_KN);
    for h0 in [2.4, 4.2, 7.2] {
        let v = (n + w) * L / (2.0 * h0);
        let p = InPlaneParams { shear_span_m: Some(h0), ..params(0.5) };
        let dem = penalty(&wall, &p);
        let peak = dem.positive.unwrap().peak_force_kn * 1e3;
        assert!((peak / v - 1.0).abs() < 0.02, "H0 {h0} m: DEM peak {peak} N vs {v} N");
        assert_eq!(dem.unconverged, 0, "H0 {h0} m");
        let last = dem.curve.last().unwrap();
        assert!((last.drift_pct / 0.5 - 1.0).abs() < 0.01, "H0 {h0} m: {last:?}");
        let s = SolverParams::default();
        let la = limit_in_plane(&wall, &s, &p, &s.limit).unwrap();
        assert!((la.peak_force_kn * 1e3 / v - 1.0).abs() < 1e-6, "H0 {h0} m: limit {} kN", la.peak_force_kn);
    }
}

/// The ± asymmetry an analysis reads from a push read both ways (the protocol's compared
/// run, `InPlaneReading::negative_peak_kn`), against the statics of the monolith:
///
/// * an inclined load `tan β` adds `n tan β` to the +x push's force and takes it from the
///   −x push's, so on a sliding monolith (friction μ, capacity `μ (n + w)` each way) the −x
///   peak exceeds the +x one by `−2 n tan β`, with the run's own −x push (a cyclic run to
///   the same drift) agreeing;
/// * an eccentric load `e0` moves the rocking capacity about the pushed toe to
///   `((n + w) L / 2 ∓ e0 P) / H0`, so the −x peak exceeds the +x one by `2 e0 P / H0`,
///   read from the second run with the eccentricity mirrored;
/// * a centred, plumb load reads no asymmetry, and a run not read both ways reads none
///   (NaN).
#[test]
fn a_push_read_both_ways_gives_the_rigs_asymmetry_by_its_statics() {
    use drystone::protocol::{InPlane, Protocol, RunOutcome};
    let (n, w, p) = forces();
    let s = SolverParams::default();
    let compared = |drift: f64| Protocol::InPlane(InPlane(params(drift))).observed().unwrap();
    let asymmetry_n = |layout: &Layout, drift: f64| {
        let o = compared(drift).run(layout, s).observed().unwrap();
        o.in_plane.unwrap().peak_asymmetry_kn * 1e3
    };
    // The inclined load on a sliding monolith (μ = 0.2: it slides before it rocks).
    let mu: f64 = 0.2;
    let phi = mu.atan().to_degrees();
    let tan_b = -0.013;
    let inclined = with(VerticalLoadRig { incline: tan_b, ..VerticalLoadRig::default() }, 1e10, phi);
    let a = asymmetry_n(&inclined, 0.5);
    let want = -2.0 * n * tan_b;
    assert!((a / want - 1.0).abs() < 0.02, "incline: {a} N vs −2 n tan β = {want} N");
    let both =
        penalty(&inclined, &InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.5]), ..params(0.5) });
    let ran = (both.negative.unwrap().peak_force_kn - both.positive.unwrap().peak_force_kn) * 1e3;
    assert!((a / ran - 1.0).abs() < 0.02, "incline: read {a} N vs the run's own −x push {ran} N");
    // The eccentric load on a rocking monolith.
    let e0 = 0.03;
    let eccentric = with(VerticalLoadRig { eccentricity_m: e0, ..VerticalLoadRig::default() }, RIGID_KN, 45.0);
    let a = asymmetry_n(&eccentric, 0.5);
    let want = 2.0 * e0 * p / H0;
    assert!((a / want - 1.0).abs() < 0.05, "eccentricity: {a} N vs 2 e0 P / H0 = {want} N");
    let (vp, vn) = (((n + w) * L / 2.0 - e0 * p) / H0, ((n + w) * L / 2.0 + e0 * p) / H0);
    assert!((want - (vn - vp)).abs() < 1e-9 * want);
    // Plumb and centred: none; not read both ways: NaN.
    let plain = with(VerticalLoadRig::default(), RIGID_KN, 45.0);
    let a = asymmetry_n(&plain, 0.5);
    assert!(a.abs() < 1e-9, "plain: {a} N");
    let once = Protocol::InPlane(InPlane(params(0.5))).run(&plain, s).observed().unwrap();
    assert!(once.in_plane.unwrap().peak_asymmetry_kn.is_nan());
}

/// The monolith's rigid statics at a rotation θ (rad) about its pushed toe, the beam turning
/// with it (its centroid and the actuator at H0 above the base, on the wall's vertical
/// axis at θ = 0): the actuator's displacement `u = L/2 (1 − cos θ) + H0 sin θ` (m) and the
/// force `V = [W (L/2 cos θ − H/2 sin θ) + N (L/2 cos θ − H0 sin θ)] / (L/2 sin θ + H0 cos θ)`
/// (N), from the moments about the toe of the wall's weight W at its centroid, the vertical
/// force N (the beam's weight in it) at the beam's centroid and V at the actuator.
fn rocking_at(theta: f64) -> (f64, f64) {
    let (n, w, _) = forces();
    let (c, s) = (theta.cos(), theta.sin());
    let u = L / 2.0 * (1.0 - c) + H0 * s;
    let v = (w * (L / 2.0 * c - H / 2.0 * s) + n * (L / 2.0 * c - H0 * s)) / (L / 2.0 * s + H0 * c);
    (u, v)
}

/// [`rocking_at`] at the drift `drift_pct` (the actuator's displacement over H0), N.
fn rocking_force_at_drift(drift_pct: f64) -> f64 {
    let target = drift_pct / 100.0 * H0;
    let (mut lo, mut hi) = (0.0, std::f64::consts::FRAC_PI_2);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if rocking_at(mid).0 < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    rocking_at(0.5 * (lo + hi)).1
}

/// A monolith rocked far past its peak follows its rigid statics by nscd to 50 % drift,
/// where the vertical force's moment has turned the force negative (at 37 % it passes
/// through zero); the penalty DEM follows it within 5 % to the largest drift it accepts,
/// `max_drift_pct` of its face-angle tolerance (8.8 % at the default 10°), and refuses a
/// larger one by name (past it a block's bed contact turns from a face into an edge, which
/// locked the rotation at 10° and held 4.2 kN at 30 % on a one-block wall whose statics
/// give 3.5 kN).
#[test]
fn a_monolith_rocked_to_large_drifts_follows_its_rigid_statics_within_each_methods_reach() {
    let v0 = rocking_force_at_drift(0.0);
    let nscd = run_in_plane_nscd(&inplane_block(45.0, RIGID_KN), &SolverParams::default().nscd, &params(50.0)).unwrap();
    for d in [5.0, 10.0, 20.0, 30.0, 40.0, 50.0] {
        let p = nscd.curve.iter().min_by(|a, b| (a.drift_pct - d).abs().total_cmp(&(b.drift_pct - d).abs())).unwrap();
        let v = rocking_force_at_drift(p.drift_pct);
        assert!(
            (p.force_kn * 1e3 - v).abs() < 0.01 * v0,
            "nscd at {} %: {} kN vs the statics' {} N",
            p.drift_pct,
            p.force_kn,
            v
        );
    }
    assert!(rocking_force_at_drift(50.0) < 0.0 && nscd.curve.last().unwrap().force_kn < 0.0);
    let s = SolverParams::default();
    let max = drystone::loading::inplane::max_drift_pct(s.face_angle_tolerance_deg);
    assert!((max - 100.0 * 10f64.to_radians().tan() / 2.0).abs() < 1e-12, "{max}");
    let dem = penalty(&inplane_block(45.0, 1e11), &params(max));
    assert_eq!(dem.unconverged, 0);
    for d in [2.0, 5.0, max] {
        let p = dem.curve.iter().min_by(|a, b| (a.drift_pct - d).abs().total_cmp(&(b.drift_pct - d).abs())).unwrap();
        let v = rocking_force_at_drift(p.drift_pct);
        assert!(
            (p.force_kn * 1e3 / v - 1.0).abs() < 0.05,
            "penalty at {} %: {} kN vs the statics' {} N",
            p.drift_pct,
            p.force_kn,
            v
        );
    }
    let e = run_in_plane_penalty(&inplane_block(45.0, 1e11), s, &params(50.0), &mut |_, _, _| {}).unwrap_err();
    assert!(matches!(e, drystone::loading::inplane::InPlaneError::DriftReach { .. }), "{e}");
    let text = e.to_string();
    assert!(text.contains("drift_pct = 50") && text.contains("--solver nscd") && text.contains("8.8 %"), "{text}");
}

/// A monolith that rocks under a beam held level (double curvature) turns about its toes
/// and lifts the beam, which does not turn: nscd and limit analysis read `rocking` from the
/// crack's opening (they read `sliding` from the beam's rotation, none), at the capacity
/// `(N L + W L / 2) / H` within 1 %.
#[test]
fn a_monolith_rocking_under_a_beam_held_level_is_read_as_rocking() {
    let sigma0 = 0.1e6;
    let fixed = InPlaneParams {
        sigma0_mpa: sigma0 * 1e-6,
        shear_span_m: None,
        beam_rotation: drystone::loading::inplane::BeamRotation::Fixed,
        drift_pct: 1.0,
        ..InPlaneParams::default()
    };
    let n = sigma0 * L * T;
    let w = DENSITY * G * L * T * H;
    let double = (n * L + w * L / 2.0) / H;
    let s = SolverParams::default();
    let nscd = run_in_plane_nscd(&inplane_block(45.0, RIGID_KN), &s.nscd, &fixed).unwrap();
    let la = limit_in_plane(&inplane_block(45.0, RIGID_KN), &s, &fixed, &s.limit).unwrap();
    for (name, m, peak) in [
        ("nscd", &nscd.mechanism, nscd.positive.unwrap().peak_force_kn),
        ("limit analysis", &la.mechanism, la.peak_force_kn),
    ] {
        assert_eq!(m.kind, MechanismKind::Rocking, "{name}: {m:?}");
        assert!(m.opening_share > 0.9, "{name}: {m:?}");
        assert!((peak * 1e3 / double - 1.0).abs() < 0.01, "{name}: {peak} kN vs {double} N");
    }
}

#[test]
fn the_newton_solve_rocks_a_monolith_to_its_capacity_and_counts_what_it_hands_over() {
    let (n, w, _) = forces();
    let wall = inplane_block(45.0, 1e11);
    let default = penalty(&wall, &params(0.5));
    assert_eq!(default.newton_handed_over, None, "the default has no Newton stage");
    let s = SolverParams { kind: drystone::dem::SolverKind::Newton, ..SolverParams::default() };
    let r = run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let handed = r.newton_handed_over.expect("a Newton stage");
    assert!(handed < r.curve.len(), "{handed} of {} increments", r.curve.len() - 1);
    // The statics of the rigid block: N_total L / (2 H0), approached from below by the
    // joints' rotation at 0.5 % drift, as the default's peak is.
    let capacity = (n + w) * L / 2.0 / H0;
    let (peak, base) = (r.positive.unwrap().peak_force_kn * 1e3, default.positive.unwrap().peak_force_kn * 1e3);
    assert!(peak < capacity && peak / capacity > 0.9, "Newton {peak} N vs rigid {capacity} N");
    assert!((peak / base - 1.0).abs() < 0.01, "Newton {peak} N vs the default's {base} N");
    assert_eq!(r.unconverged, 0);
}
