//! The effect library: each built-in effect acts as its physics says (closed forms on a
//! single block), effects defined in files act as the built-ins made of the same steps, and
//! bad effects are refused with their name and range. (The engine's power on data it did
//! not make is tested in `discrepancy_realwalls.rs`.)

use drystone::closure::Hyperbolic;
use drystone::dem::RunToEquilibrium;
use drystone::dem::SolverParams;
use drystone::effects::{effect_rng, EffectDef, Library, Stage};
use drystone::layout::{BaseSliding, Closure, JointFamily, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::verify::{layout_of, rect_block};
use std::path::Path;

const RIGID: f64 = drystone::verify::RIGID_KN;

fn fine_tilt() -> TiltParams {
    TiltParams { resolution_deg: 1.0 / 16.0, ..TiltParams::default() }
}

fn apply(layout: &mut Layout, e: &str) {
    apply_with(&Library::builtin(), layout, e);
}

fn apply_with(lib: &Library, layout: &mut Layout, e: &str) {
    let mut rng = effect_rng(0, 0, "test", "e");
    let e = lib.parse(e, drystone::effects::REFERENCE_COURSE_HEIGHT_M).unwrap();
    for stage in [Stage::Layout, Stage::JointLaw, Stage::Restraints] {
        e.apply_stage(stage, layout, &[], &mut rng).unwrap();
    }
}

fn collapse_deg(l: &Layout) -> f64 {
    run_tilt(l, SolverParams::default(), &fine_tilt()).unwrap().collapse_angle_deg()
}

/// A rigid block b × h built out of plumb by ψ (sheared): `tan α = b/h − tan ψ`, so it tips
/// about ψ earlier.
#[test]
fn initial_lean_tips_a_rigid_block_earlier_by_the_lean() {
    let (b, h) = (0.1, 0.3);
    let mut l = layout_of(vec![rect_block(b, h, 0.3)], RIGID, RIGID / 2.0, 60.0, BaseSliding::Free);
    let plumb = collapse_deg(&l);
    apply(&mut l, "initial_lean=2.5");
    let lean = collapse_deg(&l);
    let expect = (b / h - 2.5f64.to_radians().tan()).atan().to_degrees();
    let drop = (b / h).atan().to_degrees() - expect;
    // The rigid-limit tolerance of `drystone verify` (the last stable tilt sits up to a
    // bracket below the knife edge), and the drop against the plumb block's own angle.
    assert!((lean - expect).abs() < 0.3, "{lean} vs {expect} (plumb {plumb})");
    assert!((plumb - lean - drop).abs() < 0.1, "tips {} deg earlier, not {drop}", plumb - lean);
}

/// Rounded edges of size r move the pivot inwards: `tan α = (b/2 − r)/(h/2)`.
#[test]
fn edge_rounding_moves_the_pivot_of_a_rigid_block_inwards() {
    let (b, h, r) = (0.1, 0.3, 0.006);
    let mut l = layout_of(vec![rect_block(b, h, 0.3)], RIGID, RIGID / 2.0, 60.0, BaseSliding::Free);
    let plumb = collapse_deg(&l);
    apply(&mut l, &format!("edge_rounding={r}"));
    let expect = ((b / 2.0 - r) / (h / 2.0)).atan().to_degrees();
    let got = collapse_deg(&l);
    let drop = (b / h).atan().to_degrees() - expect;
    assert!((got - expect).abs() < 0.3, "{got} vs {expect}");
    assert!((plumb - got - drop).abs() < 0.1, "{} deg lower, not {drop}", plumb - got);
}

/// The settlement of a block of height h on the table under its own weight, m.
fn settlement(l: &Layout) -> f64 {
    let mut sim = drystone::dem::Simulation::new(l, SolverParams::default());
    let z0 = sim.state.bodies[0].pos.z;
    sim.run_to_equilibrium(1e-9, 2_000_000).unwrap();
    z0 - sim.state.bodies[0].pos.z
}

/// The joint-law effects against the closed forms of their closure laws, for a block
/// pressing the table with σ = ρ g h: linear `u = σ/(s Kn)`, hyperbolic
/// `u = σ/(Kni + σ/Vm)`, seating `u = √(2 g₀ σ / Kn)` (while `u ≤ g₀`).
#[test]
fn joint_law_effects_settle_a_block_by_their_closed_forms() {
    let (b, h, kn) = (0.2, 0.1, 5e7);
    let base = layout_of(vec![rect_block(b, h, 0.2)], kn, kn / 2.0, 35.0, BaseSliding::Free);
    let sigma = drystone::verify::DENSITY * drystone::units::STANDARD_GRAVITY * h;
    let check = |effect: &str, expect: f64| {
        let mut l = base.clone();
        apply(&mut l, effect);
        let u = settlement(&l);
        assert!((u - expect).abs() < 1e-3 * expect, "{effect}: {u:e} vs {expect:e}");
    };
    check("kn_scale=0.25", sigma / (0.25 * kn));
    check("joint_closure=0.1:0.0005", sigma / (0.1 * kn + sigma / 5e-4));
    check("seating_gap=0.002", (2.0 * 0.002 * sigma / kn).sqrt());
    let mut l = base.clone();
    apply(&mut l, "joint_closure=0.1:0.0005");
    assert_eq!(l.materials[0].closure, Closure::Hyperbolic(Hyperbolic { max_closure_m: 5e-4 }));
}

/// An end-restrained block on a frictionless table held at α: rigid, it does not move;
/// with `restraint_stiffness` k, its spring stretches by `W sin α / k`.
#[test]
fn restraint_stiffness_makes_the_end_restraint_a_spring() {
    let mut spec = drystone::layout::LayoutSpec::from_json(
        r#"{"version":1,"name":"held block","materials":[{"name":"m","density_kg_per_m3":2400,"kn_pa_per_m":1e9,
        "ks_pa_per_m":5e8,"friction_deg":0}],"table":{"material":"m"},
        "blocks":[{"id":"b0","material":"m","vertices":[[0,-0.1,0],[0.2,-0.1,0],[0.2,0.1,0],[0,0.1,0],[0,-0.1,0.05],[0.2,-0.1,0.05],[0.2,0.1,0.05],[0,0.1,0.05]]}],
        "restraints":{"ends":[{"blocks":["b0"],"kind":"rigid"}]}}"#,
    )
    .unwrap();
    spec.name = "held block".into();
    let mut l = spec.resolve().unwrap();
    let k = 2e4;
    apply(&mut l, &format!("restraint_stiffness={k}"));
    let mut sim = drystone::dem::Simulation::new(&l, SolverParams::default());
    sim.run_to_equilibrium(1e-9, 2_000_000).unwrap();
    let y0 = sim.state.bodies[0].pos.y;
    let alpha = 10f64.to_radians();
    sim.set_tilt(alpha);
    sim.run_to_equilibrium(1e-9, 4_000_000).unwrap();
    let w = sim.state.bodies[0].mass * drystone::units::STANDARD_GRAVITY;
    let expect = w * alpha.sin() / k;
    let dy = sim.state.bodies[0].pos.y - y0;
    assert!((dy - expect).abs() < 2e-3 * expect, "{dy:e} vs {expect:e}");
}

/// `transverse_dip` tilts the bed joints across the thickness by at most δ, keeps the base
/// on the table and the crest level, and the wall still stands at α = 0.
#[test]
fn transverse_dip_tilts_the_bed_joints_within_the_bound() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let wall = drystone::generator::Wall::from_file(&root.join("tests/discrepancy/walls/small_free.toml")).unwrap();
    let g = drystone::generator::generate(&wall, 7, 0).unwrap();
    let mut l = g.check().unwrap();
    let e = Library::builtin().parse("transverse_dip=8", 0.05).unwrap();
    drystone::effects::apply_all(&mut l, &g, "FREE", &[e]).unwrap();
    let (mut steepest, mut lowest) = (0.0f64, f64::INFINITY);
    for b in &l.blocks {
        lowest = lowest.min(b.shape.vertices.iter().map(|v| v.z).fold(f64::INFINITY, f64::min));
        for f in &b.shape.faces {
            if f.normal.z.abs() > 0.8 {
                steepest = steepest.max((f.normal.y / f.normal.z).abs().atan().to_degrees());
            }
        }
    }
    assert!(lowest.abs() < 1e-12, "the base stays on the table: {lowest}");
    assert!(steepest > 2.0 && steepest < 8.0 + 1e-6, "bed dips across the thickness up to {steepest} deg");
    assert!(run_tilt(&l, SolverParams::default(), &TiltParams { step_deg: 2.0, ..TiltParams::default() }).is_ok());
}

/// Unknown names and out-of-range values are refused with the name and range.
#[test]
fn bad_effects_are_refused_with_their_name_and_range() {
    let lib = Library::builtin();
    let e = lib.parse("lean=2", 0.05).unwrap_err().to_string();
    assert!(e.contains("unknown effect `lean`") && e.contains("initial_lean"), "{e}");
    let e = lib.parse("initial_lean=30", 0.05).unwrap_err().to_string();
    assert!(e.contains("lean_deg = 30") && e.contains("[0, 3]"), "{e}");
    let e = lib.parse("joint_closure=0.1", 0.05).unwrap_err().to_string();
    assert!(e.contains("takes 2 parameter"), "{e}");
    // Length ranges scale with the course height: 3 mm of seating gap on 5 cm courses,
    // 6 mm on 10 cm courses.
    assert!(lib.parse("seating_gap=0.005", 0.05).is_err());
    assert!(lib.parse("seating_gap=0.005", 0.10).is_ok());
}

/// A softer base joint (the `base_stiffness` family effect) settles a block on the table
/// by `σ/(s Kn)` and leaves the bed joint between two blocks as it was.
#[test]
fn base_stiffness_softens_the_table_joint_only() {
    let (b, h, kn) = (0.2, 0.1, 5e7);
    let two = |l: &mut Layout| {
        // Course indices make the block–block joint a bed joint.
        l.blocks[0].course = Some(0);
        l.blocks[1].course = Some(1);
    };
    let stack = || {
        let lower = rect_block(b, h, 0.2);
        let upper: Vec<[f64; 3]> = lower.iter().map(|v| [v[0], v[1], v[2] + h]).collect();
        let mut l = layout_of(vec![lower, upper], kn, kn / 2.0, 35.0, BaseSliding::Free);
        two(&mut l);
        l
    };
    let settle = |l: &Layout| {
        let mut sim = drystone::dem::Simulation::new(l, SolverParams::default());
        let z0 = [sim.state.bodies[0].pos.z, sim.state.bodies[1].pos.z];
        sim.run_to_equilibrium(1e-10, 4_000_000).unwrap();
        (z0[0] - sim.state.bodies[0].pos.z, (z0[1] - sim.state.bodies[1].pos.z) - (z0[0] - sim.state.bodies[0].pos.z))
    };
    let sigma1 = drystone::verify::DENSITY * drystone::units::STANDARD_GRAVITY * h;
    let (base0, bed0) = settle(&stack());
    let mut soft = stack();
    apply(&mut soft, "base_stiffness=0.25");
    assert_eq!(soft.joint_families.get(JointFamily::Base).map(|f| f.kn_factor), Some(0.25));
    let (base1, bed1) = settle(&soft);
    // The base carries both blocks: σ = 2 ρ g h.
    assert!((base0 - 2.0 * sigma1 / kn).abs() < 1e-3 * base0, "{base0:e}");
    assert!((base1 - 2.0 * sigma1 / (0.25 * kn)).abs() < 1e-3 * base1, "{base1:e}");
    assert!((bed1 - bed0).abs() < 1e-3 * bed0, "the bed joint is unchanged: {bed0:e} -> {bed1:e}");
}

/// An effect written in a file acts exactly as the built-in made of the same step.
#[test]
fn an_effect_file_acts_as_the_builtin_of_the_same_steps() {
    let text = r#"
version = 1
name = "my_lean"
description = "the wall leans"
[[parameters]]
name = "psi"
unit = "deg"
min = 0.0
max = 3.0
neutral = 0.0
[[steps]]
kind = "lean"
parameter = "psi"
"#;
    let def = EffectDef::from_toml(text, Path::new("my_lean.toml")).unwrap();
    let mut lib = Library::builtin();
    lib.add(def).unwrap();
    let base = layout_of(vec![rect_block(0.1, 0.3, 0.3)], 1e9, 5e8, 35.0, BaseSliding::Free);
    let (mut a, mut b) = (base.clone(), base);
    apply_with(&lib, &mut a, "my_lean=1.5");
    apply_with(&lib, &mut b, "initial_lean=1.5");
    assert_eq!(a, b);
    // A step naming a parameter the effect does not have is refused, naming the key.
    let bad = text.replace("parameter = \"psi\"", "parameter = \"phi\"");
    let e = EffectDef::from_toml(&bad, Path::new("bad.toml")).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("steps[0].parameter") && e.contains("`phi`"), "{e}");
    let bad = text.replace("kind = \"lean\"", "kind = \"tilt\"");
    let e = EffectDef::from_toml(&bad, Path::new("bad.toml")).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("tilt"), "{e}");
    // A closure step takes the laws of one length parameter by their layout-file names.
    let closure = |law: &str| {
        text.replace("unit = \"deg\"", "unit = \"m\"")
            .replace("max = 3.0", "max = 0.002")
            .replace("kind = \"lean\"", &format!("kind = \"closure\"\nlaw = \"{law}\""))
    };
    assert!(EffectDef::from_toml(&closure("seating"), Path::new("ok.toml")).is_ok());
    let e = EffectDef::from_toml(&closure("bandis"), Path::new("bad.toml")).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("steps[0].law") && e.contains("hyperbolic, seating"), "{e}");
}

/// A value of the wrong type or an unknown key in an effect file is refused at its own
/// line: the file's keys were read through a flattened struct, and every such error was
/// reported at line 1, column 1, wherever it was.
#[test]
fn an_effect_files_type_errors_name_their_own_line() {
    let text = "version = 1\nname = \"soft\"\n[[parameters]]\nname = \"factor\"\nunit = \"-\"\nmin = 0.05\n\
                max = 1.0\nscale = \"log\"\nneutral = 1.0\n[[parameters.kinds]]\nkind = \"sawn_stone\"\nmin = 0.3\n\
                max = 1.0\nas_built = true\n[[steps]]\nkind = \"joint_factor\"\nproperty = \"stiffness\"\n\
                parameter = \"factor\"\n";
    assert!(EffectDef::from_toml(text, Path::new("soft.toml")).is_ok());
    // Line 14: as_built; line 11: the kind; line 2, after the name: a key of no effect file.
    let cases = [
        (text.replace("as_built = true", "as_built = \"yes\""), "line 14", "expected a boolean"),
        (text.replace("kind = \"sawn_stone\"", "kind = \"granite\""), "line 11", "sawn_stone"),
        (text.replace("name = \"soft\"\n", "name = \"soft\"\ncolour = \"red\"\n"), "line 3", "unknown field `colour`"),
    ];
    for (bad, line, what) in cases {
        let e = EffectDef::from_toml(&bad, Path::new("soft.toml")).unwrap_err().to_string();
        assert!(e.contains("soft.toml") && e.contains(line) && e.contains(what), "{line} {what:?}: {e}");
        assert!(!e.contains("line 1, column 1"), "{e}");
    }
}

/// A kind's range that scales with the broad one must lie within it, or a search of that
/// kind could reach a value no one can state; stated `as_built`, it may reach past it.
#[test]
fn a_kinds_range_wider_than_the_broad_one_is_refused_unless_as_built() {
    let text = "version = 1\nname = \"soft\"\n[[parameters]]\nname = \"factor\"\nunit = \"-\"\nmin = 0.05\n\
                max = 1.0\nscale = \"log\"\nneutral = 1.0\n[[parameters.kinds]]\nkind = \"concrete_paver\"\nmin = 0.01\n\
                max = 1.0\n[[steps]]\nkind = \"joint_factor\"\nproperty = \"stiffness\"\n\
                parameter = \"factor\"\n";
    let e = EffectDef::from_toml(text, Path::new("soft.toml")).unwrap_err().to_string();
    assert!(e.contains("soft.toml") && e.contains("concrete_paver") && e.contains("within the broad range"), "{e}");
    let built = text.replace("max = 1.0\n[[steps]]", "max = 1.0\nas_built = true\n[[steps]]");
    assert!(EffectDef::from_toml(&built, Path::new("soft.toml")).is_ok());
    let inside = text.replace("min = 0.01", "min = 0.3");
    assert!(EffectDef::from_toml(&inside, Path::new("soft.toml")).is_ok());
}
