//! A block held by one rope on the tilting table, by both solvers, against the taut-string
//! statics of docs/rope.md across the documented ranges of the rope's pretension T₀ (up
//! to 1e6 N), axial stiffness EA and wrap depth d, and the penalty engine's critical time
//! step with the rope's stiffness in it.
//!
//! The statics: a rigid block b × h rotated by θ about its downhill toe presses the rope
//! at its bearing point (mid-height z_c = h/2 of the band [0, h]) by `δ = z_c sin θ + d`;
//! the rope pulls back with `F = 2 T δ / L`, `L = √(s² + δ²)`,
//! `T = max(0, T₀ + EA (L − L_ref)/L_ref)`, `L_ref = √(s² + d²)`, and the moments about the
//! toe balance where `W R sin(α − α₀ + θ) = F z_c cos θ` (R the half diagonal,
//! α₀ = atan(b/h)). Along the path the tilt rises with θ up to its first maximum, the
//! collapse angle (solved here by a scan, not by the code under test); a maximum above
//! the largest tilt tried (80°) means the block stands to it.

use drystone::dem::timestep::Stiffness;
use drystone::dem::{SolverParams, WallState};
use drystone::layout::{BaseSliding, Layout, Rope};
use drystone::loading::tilt::TiltParams;
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::nscd::NscdParams;
use drystone::protocol::run_tilt;
use drystone::verify::{layout_of, rect_block, DENSITY};

/// Joint stiffness, Pa/m: a stone joint (the rope is soft beside it, the block near rigid).
const KN: f64 = 1e11;

/// The block: 0.09 m thick (y), 0.3 m high, 0.4 m long (x); free limit atan(0.3) = 16.70°.
const B: f64 = 0.09;
const H: f64 = 0.3;
const L: f64 = 0.4;

/// The block with one rope at mid-length over its whole height.
fn block_with_rope(t0: f64, ea: f64, s: f64, d: f64) -> Layout {
    let mut layout = layout_of(vec![rect_block(B, H, L)], KN, KN / 2.0, 30.0, BaseSliding::Held);
    layout.ropes.push(Rope {
        x: L / 2.0,
        z_lo: 0.0,
        z_hi: H,
        pretension: t0,
        axial_stiffness: ea,
        span: s,
        wrap_depth: d,
    });
    layout
}

/// The taut-string statics (module doc): the collapse angle, degrees (capped at 90).
fn statics_deg(layout: &Layout, t0: f64, ea: f64, s: f64, d: f64) -> f64 {
    let w = DENSITY * B * H * L * layout.gravity;
    let r = (B * B + H * H).sqrt() / 2.0;
    let a0 = (B / H).atan();
    let zc = H / 2.0;
    let force = |theta: f64| {
        let delta = zc * theta.sin() + d;
        let ll = (s * s + delta * delta).sqrt();
        let l_ref = (s * s + d * d).sqrt();
        let t = (t0 + ea * (ll - l_ref) / l_ref).max(0.0);
        2.0 * t * delta / ll
    };
    let alpha = |theta: f64| {
        let x = force(theta) * zc * theta.cos() / (w * r);
        if x >= 1.0 {
            std::f64::consts::FRAC_PI_2
        } else {
            a0 - theta + x.asin()
        }
    };
    let (mut best, mut theta) = (alpha(0.0), 0.0);
    while theta < 0.6 {
        theta += 1e-5;
        let a = alpha(theta);
        if a < best {
            break;
        }
        best = a;
    }
    best.to_degrees()
}

fn tilt() -> TiltParams {
    TiltParams { resolution_deg: 0.125, ..TiltParams::default() }
}

/// The cases (T₀ N, EA N, s m, d m) across the documented ranges, from a rope too weak to
/// matter to one of 1e6 N, each with its statics.
const CASES: [(f64, f64, f64, f64); 6] = [
    (300.0, 6e4, 0.1, 0.0),
    (300.0, 6e4, 0.1, 0.01),
    (1e6, 6e4, 0.1, 0.0),
    (3e4, 1e10, 0.1, 0.0),
    (20.0, 1.0, 0.1, 0.04),
    (50.0, 1e4, 0.1, 0.0),
];

fn check(name: &str, got: f64, want: f64) {
    let want_capped = want.min(80.0);
    eprintln!("{name}: simulated {got:.3}°, taut-string statics {want:.3}°");
    assert!((got - want_capped).abs() <= 0.5, "{name}: {got}° against the statics {want_capped}°");
}

#[test]
fn a_block_held_by_a_rope_tilts_to_the_taut_string_statics_by_the_penalty_engine() {
    for (t0, ea, s, d) in CASES {
        let layout = block_with_rope(t0, ea, s, d);
        let want = statics_deg(&layout, t0, ea, s, d);
        let got = run_tilt(&layout, SolverParams::default(), &tilt()).expect("stands at 0").collapse_angle_deg();
        check(&format!("penalty T0 {t0} EA {ea} s {s} d {d}"), got, want);
    }
}

#[test]
fn a_block_held_by_a_rope_tilts_to_the_taut_string_statics_by_nscd() {
    for (t0, ea, s, d) in CASES {
        let layout = block_with_rope(t0, ea, s, d);
        let want = statics_deg(&layout, t0, ea, s, d);
        let got = run_tilt_nscd(&layout, &NscdParams::default(), &tilt()).expect("stands at 0").collapse_angle_deg();
        check(&format!("nscd T0 {t0} EA {ea} s {s} d {d}"), got, want);
    }
}

/// The critical step's stiffness includes the rope: a lone bearer's diagonal block gets
/// the rope's `dF/dδ̄`, at δ̄ = 0 and d = 0 the taut string's geometric `2 T₀ / s` on the
/// block's y translation, so that the block's eigenvalue against its mass is at least
/// `2 T₀ / (s m)`.
#[test]
fn the_critical_step_includes_the_rope_s_geometric_stiffness() {
    let (t0, s) = (1e6, 0.1);
    let layout = block_with_rope(t0, 6e4, s, 0.0);
    let st = WallState::new(&layout);
    let mut k = Stiffness::new(&st.bodies, &[]);
    k.add_restraints(&st.bodies, &st.restraint, &st.ropes, 0.0);
    let m = DENSITY * B * H * L;
    let lambda = k.body_eigenvalues()[0];
    assert!(lambda >= 2.0 * t0 / (s * m) * (1.0 - 1e-9), "λ {lambda} below 2 T₀/(s m) = {}", 2.0 * t0 / (s * m));
}

/// The generated small wall with its ends held (`tests/discrepancy/walls/small_restrained.toml`,
/// seed 7), with `effect` applied (none: the rigid ends).
fn small_wall(effect: Option<&str>) -> Layout {
    use drystone::effects::{effect_rng, Library, Stage, REFERENCE_COURSE_HEIGHT_M};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let wall =
        drystone::generator::Wall::from_file(&root.join("tests/discrepancy/walls/small_restrained.toml")).unwrap();
    let mut l = drystone::generator::generate(&wall, 7, 0).unwrap().check().unwrap();
    if let Some(e) = effect {
        let mut rng = effect_rng(0, 0, "test", "e");
        let e = Library::builtin().parse(e, REFERENCE_COURSE_HEIGHT_M).unwrap();
        for stage in [Stage::Layout, Stage::JointLaw, Stage::Restraints] {
            e.apply_stage(stage, &mut l, &[], &mut rng).unwrap();
        }
    }
    l
}

/// `end_rope` across its documented ranges (T₀ 50–1500 N, EA 1e4–2e5 N) on a wall whose
/// ends are held: a rope can only hold the wall more than free ends and less than rigid
/// ones, and a tighter rope more than a slacker one, by either solver. Under nscd the rope
/// acts from the middle of its range (it used to give the free wall's row there).
///
/// Three ropes along the diagonal of the range, each at least as tight and as stiff as the
/// one before: its slack, soft corner (50 N, 1e4 N), the middle of the pretension's range
/// (300 N, 1e4 N) and its tight, stiff corner (1500 N, 2e5 N). The bounds are checked at
/// both corners and the middle, the order along the path between them, and that the rope
/// acts (holds the wall above its free ends) from the middle up, at both stiffnesses. The
/// other three points of the 3 × 2 grid of pretension and stiffness this test used to run
/// (50 N and 300 N at 2e5 N, 1500 N at 1e4 N) repeated the same checks inside the same
/// bounds, at 20–35 s a tilt of a roped wall by nscd; the rope's own statics across its
/// ranges are the block tests above.
#[test]
fn end_rope_holds_a_wall_between_free_and_rigid_ends_by_both_solvers() {
    let tilt = TiltParams { step_deg: 1.0, resolution_deg: 0.25, ..TiltParams::default() };
    let mut free = small_wall(None);
    free.end_restraints.clear();
    let rigid = small_wall(None);
    let res = tilt.resolution_deg;
    for solver in ["penalty", "nscd"] {
        let run = |l: &Layout| match solver {
            "penalty" => run_tilt(l, SolverParams::default(), &tilt).unwrap().collapse_angle_deg(),
            _ => run_tilt_nscd(l, &NscdParams::default(), &tilt).unwrap().collapse_angle_deg(),
        };
        let (lo, hi) = (run(&free), run(&rigid));
        eprintln!("{solver}: free ends {lo:.3}°, rigid ends {hi:.3}°");
        assert!(hi > lo + 4.0 * res, "{solver}: the case needs the ends to matter");
        let mut last = lo - res;
        for (t0, ea) in [(50.0, 1e4), (300.0, 1e4), (1500.0, 2e5)] {
            let got = run(&small_wall(Some(&format!("end_rope={t0}:{ea}"))));
            eprintln!("{solver}: end_rope T0 {t0} N, EA {ea} N: {got:.3}°");
            assert!(got >= last - 2.0 * res, "{solver} T0 {t0} EA {ea}: {got}° below {last}° of a slacker rope");
            assert!(got >= lo - 2.0 * res && got <= hi + 2.0 * res, "{solver}: {got}° outside [{lo}, {hi}]");
            if t0 >= 300.0 {
                assert!(got > lo + 2.0 * res, "{solver}: a rope of {t0} N, EA {ea} N acts ({got}° against free {lo}°)");
            }
            last = got;
        }
    }
}

/// A rope without pretension that just touches the face (T₀ = 0, d = 0) pulls only by its
/// elongation, `F ≈ EA δ³ / s³`: no stiffness as built, a stiff one a few millimetres on. A
/// stiff rope (EA 1e6 N) catches the block within the per-increment collapse displacement
/// once it tips past its free limit (16.70°), and it stands to the largest tilt (80°) by
/// the penalty engine and by nscd. Before the nscd trial's window was sized by the rope's
/// stiffness over the deflections a trial reaches (it was sized by the pretension's alone,
/// none at T₀ = 0: the rigid trial's 40 steps), nscd called the tipping a mechanism and
/// gave the free block's 16.625°.
#[test]
fn a_rope_without_pretension_holds_the_block_by_its_elongation_by_both_solvers() {
    let layout = block_with_rope(0.0, 1e6, 0.1, 0.0);
    let free = (B / H).atan().to_degrees();
    let penalty = run_tilt(&layout, SolverParams::default(), &tilt()).expect("stands at 0").collapse_angle_deg();
    let nscd = run_tilt_nscd(&layout, &NscdParams::default(), &tilt()).expect("stands at 0");
    eprintln!("T0 0, EA 1e6: penalty {penalty:.3}°, nscd {:.3}° (free block {free:.3}°)", nscd.collapse_angle_deg());
    assert!(penalty >= 80.0, "penalty {penalty}°");
    assert!(nscd.collapse_angle_deg() >= 80.0, "nscd {}°: {:?}", nscd.collapse_angle_deg(), nscd.collapse_reason);
}

/// A block behind a slack rope (T₀ 20 N, EA 2e5 N, no wrap): the rope's force
/// `2 T δ / L` is far below what holds the block at its free limit, so by the statics the
/// block tips at the free block's limit atan(b/h) = 16.70° (the snap: the first maximum of
/// the tilt along the path); the rope's elongation then catches it, the statics' tilt
/// along the path rising again past 80° within a few centimetres (solved by the scan
/// here, to the total collapse displacement). Both solvers report the two apart: the snap
/// as the bracket, the fall (none: it stands to 80°) in `after_snap`, with how far the
/// wall went before the rope caught it. They used to report the snap alone, as the
/// collapse.
#[test]
fn a_block_behind_a_slack_rope_snaps_then_stands_by_both_solvers() {
    let (t0, ea, s, d) = (20.0, 2e5, 0.1, 0.0);
    let layout = block_with_rope(t0, ea, s, d);
    let free = (B / H).atan().to_degrees();
    let snap = statics_deg(&layout, t0, ea, s, d);
    assert!((snap - free).abs() < 0.1, "statics' snap {snap}° vs the free limit {free}°");
    // The statics' tilt along the path past the snap, up to the total collapse displacement
    // (half the thickness at the top, y = h sin θ − b (1 − cos θ) of the top's far corner).
    let w = DENSITY * B * H * L * layout.gravity;
    let (r, a0, zc) = ((B * B + H * H).sqrt() / 2.0, (B / H).atan(), H / 2.0);
    let mut best = 0.0_f64;
    let mut theta = 0.0_f64;
    while H * theta.sin() < 0.5 * B {
        let delta = zc * theta.sin();
        let ll = (s * s + delta * delta).sqrt();
        let force = 2.0 * (t0 + ea * (ll - s) / s).max(0.0) * delta / ll;
        let x = force * zc * theta.cos() / (w * r);
        best = best.max(if x >= 1.0 { 90.0 } else { (a0 - theta + x.asin()).to_degrees() });
        theta += 1e-5;
    }
    assert!(best >= 80.0, "the statics' fall {best}°");
    let penalty = run_tilt(&layout, SolverParams::default(), &tilt()).expect("stands at 0");
    let nscd = run_tilt_nscd(&layout, &NscdParams::default(), &tilt()).expect("stands at 0");
    for (name, res) in [("penalty", &penalty), ("nscd", &nscd)] {
        eprintln!("{name}: snap {:.3}°, after it {:?}", res.collapse_angle_deg(), res.after_snap);
        assert!((res.collapse_angle_deg() - free).abs() <= 0.5, "{name}: snap {}°", res.collapse_angle_deg());
        let fall = res.after_snap.unwrap_or_else(|| panic!("{name}: no fall reported past the snap"));
        assert!(fall.falls_last_stable_deg >= 80.0 && fall.falls_first_unstable_deg.is_none(), "{name}: {fall:?}");
        assert!(fall.caught_displacement_m > 0.0 && fall.caught_displacement_m < 0.5 * B, "{name}: {fall:?}");
    }
}
