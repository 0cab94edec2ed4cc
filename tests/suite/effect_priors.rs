//! The plausible ranges per kind of wall and the joint-form effects: each new effect
//! against its closed form on one or two blocks (shear stiffness: `u = F/(s Ks A)`; dilatant
//! joints: a block slides at `α = φ + i`), the search coordinate mapped into the range of a
//! wall's kind (the CBL dip bound by the batter), and effects with stated values left as
//! they are on every wall.

use drystone::dem::{RunToEquilibrium, SolverParams};
use drystone::effects::{effect_rng, realize, Effect, EffectDef, Library, Stage, WallKind};
use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::verify::{layout_of, rect_block};
use std::path::Path;

fn apply_with(lib: &Library, layout: &mut Layout, e: &str) {
    let mut rng = effect_rng(0, 0, "test", "e");
    let e = lib.parse(e, drystone::effects::REFERENCE_COURSE_HEIGHT_M).unwrap();
    for stage in [Stage::Layout, Stage::JointLaw, Stage::Restraints] {
        e.apply_stage(stage, layout, &[], &mut rng).unwrap();
    }
}

fn collapse_deg(l: &Layout) -> f64 {
    let tilt = TiltParams { resolution_deg: 1.0 / 16.0, ..TiltParams::default() };
    run_tilt(l, SolverParams::default(), &tilt).unwrap().collapse_angle_deg()
}

/// The y displacement of a lone block on the table when the table goes from 0 to α, m.
fn shear_under_tilt(l: &Layout, alpha: f64) -> (f64, f64) {
    let mut sim = drystone::dem::Simulation::new(l, SolverParams::default());
    sim.run_to_equilibrium(1e-10, 4_000_000).unwrap();
    let y0 = sim.state.bodies[0].pos.y;
    sim.set_tilt(alpha);
    sim.run_to_equilibrium(1e-10, 8_000_000).unwrap();
    (sim.state.bodies[0].pos.y - y0, sim.state.bodies[0].mass)
}

/// A flat block b × l on the table, stiff in Kn, tilted to α: the lateral force
/// `F = W sin α` shears its base joint by `F / (Ks A)`, A = b l; `shear_stiffness` s makes
/// it `F / (s Ks A)` and leaves Kn as it was. (Rocking adds `θ h/2` with `θ = F h/2 / (Kn
/// I)`: 1e-4 of the shear here.)
#[test]
fn shear_stiffness_shears_a_block_on_the_table_by_force_over_stiffness() {
    let (b, h, l, kn, ks) = (0.2, 0.05, 0.2, 1e10, 5e6);
    let plain = layout_of(vec![rect_block(b, h, l)], kn, ks, 60.0, BaseSliding::Free);
    let mut soft = plain.clone();
    apply_with(&Library::builtin(), &mut soft, "shear_stiffness=0.25");
    assert_eq!(soft.materials[0].kn, kn);
    assert_eq!(soft.materials[0].ks, 0.25 * ks);
    let alpha = 10f64.to_radians();
    for (layout, s) in [(&plain, 1.0), (&soft, 0.25)] {
        let (dy, mass) = shear_under_tilt(layout, alpha);
        let f = mass * drystone::units::STANDARD_GRAVITY * alpha.sin();
        let expect = f / (s * ks * b * l);
        assert!((dy - expect).abs() < 5e-3 * expect, "s = {s}: {dy:e} vs {expect:e}");
    }
}

/// Patton's law on a block sliding on the table: a flat block (it would topple only at
/// atan(b/h) = 76°) slides at φ; with every joint dilatant by i it slides at φ + i.
#[test]
fn a_dilatant_joint_slides_at_friction_plus_asperity_angle() {
    let text = r#"
version = 1
name = "rough"
[[parameters]]
name = "i"
unit = "deg"
min = 0.0
max = 20.0
neutral = 0.0
[[steps]]
kind = "dilatancy"
parameter = "i"
"#;
    let mut lib = Library::builtin();
    lib.add(EffectDef::from_toml(text, Path::new("rough.toml")).unwrap()).unwrap();
    let (phi, i) = (20.0, 10.0);
    let plain = layout_of(vec![rect_block(0.2, 0.05, 0.2)], 1e9, 5e8, phi, BaseSliding::Free);
    let mut rough = plain.clone();
    apply_with(&lib, &mut rough, &format!("rough={i}"));
    let (a0, a1) = (collapse_deg(&plain), collapse_deg(&rough));
    assert!((a0 - phi).abs() < 0.3, "slides at {a0}, not φ = {phi}");
    assert!((a1 - (phi + i)).abs() < 0.3, "slides at {a1}, not φ + i = {}", phi + i);
}

/// The built-in `dilatant_joints` acts on the bed joints alone: a block on a base-held
/// block slides off it at φ + i, where it slid at φ.
#[test]
fn dilatant_joints_raise_the_bed_joint_friction_only() {
    let (b, h) = (0.2, 0.05);
    let stack = || {
        let lower = rect_block(b, h, 0.2);
        let upper: Vec<[f64; 3]> = lower.iter().map(|v| [v[0], v[1], v[2] + h]).collect();
        let mut l = layout_of(vec![lower, upper], 1e9, 5e8, 25.0, BaseSliding::Held);
        l.blocks[0].course = Some(0);
        l.blocks[1].course = Some(1);
        l
    };
    let plain = stack();
    let mut rough = stack();
    apply_with(&Library::builtin(), &mut rough, "dilatant_joints=8");
    assert_eq!(rough.materials[0].friction, 25f64.to_radians(), "the materials keep φ");
    let (a0, a1) = (collapse_deg(&plain), collapse_deg(&rough));
    assert!((a0 - 25.0).abs() < 0.3, "{a0}");
    assert!((a1 - 33.0).abs() < 0.3, "{a1}");
}

fn small_wall() -> drystone::generator::Wall {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    drystone::generator::Wall::from_file(&root.join("tests/discrepancy/walls/small_free.toml")).unwrap()
}

/// The steepest bed dip across the thickness of a layout, degrees.
fn steepest_dip(l: &Layout) -> f64 {
    let mut steepest = 0.0f64;
    for b in &l.blocks {
        for f in &b.shape.faces {
            if f.normal.z.abs() > 0.8 {
                steepest = steepest.max((f.normal.y / f.normal.z).abs().atan().to_degrees());
            }
        }
    }
    steepest
}

/// The search's top coordinate of `transverse_dip` is 15° in the broad range and the
/// batter's 5.56° on a wall of concrete pavers: the same realization dips up to the bound
/// of its kind. A dip stated as a value (a study's effect) acts as stated on every wall.
#[test]
fn a_search_coordinate_takes_the_range_of_the_walls_kind() {
    let lib = Library::builtin();
    let def = lib.get("transverse_dip").unwrap();
    let mut wall = small_wall();
    let course = drystone::effects::course_height_of(&wall);
    let top = Effect::at_search(def.clone(), &[1.0], course).unwrap();
    assert_eq!(top.values, vec![15.0]);
    assert_eq!(top.for_kind(Some(WallKind::ConcretePaver)).values, vec![5.56]);
    assert_eq!(top.for_kind(None), top);
    let (_, broad) = realize(&wall, 7, 0, "FREE", std::slice::from_ref(&top)).unwrap();
    wall.kind = Some(WallKind::ConcretePaver);
    let (_, paver) = realize(&wall, 7, 0, "FREE", std::slice::from_ref(&top)).unwrap();
    let (d_broad, d_paver) = (steepest_dip(&broad), steepest_dip(&paver));
    assert!(d_broad > 5.56 && d_broad <= 15.0 + 1e-6, "broad: {d_broad}");
    assert!(d_paver > 1.0 && d_paver <= 5.56 + 1e-6, "pavers: {d_paver}");
    // The same draws (the effect's stream), scaled to the bound: δ_j = u_j · bound.
    assert!((d_paver - d_broad * 5.56 / 15.0).abs() < 1e-6 * d_broad, "{d_paver} vs {d_broad} · 5.56/15");
    // Stated values are not remapped.
    let stated = lib.parse("transverse_dip=12", course).unwrap();
    assert_eq!(stated.for_kind(Some(WallKind::ConcretePaver)), stated);
    let (_, as_stated) = realize(&wall, 7, 0, "FREE", &[stated]).unwrap();
    let d_stated = steepest_dip(&as_stated);
    assert!((d_stated - d_broad * 12.0 / 15.0).abs() < 1e-6 * d_broad, "{d_stated} vs {d_broad} · 12/15");
    // A factor's neutral coordinate is the unchanged model for every kind; its ends are the
    // kind's bounds.
    let kn = lib.get("kn_scale").unwrap();
    let p = &kn.parameters[0];
    let xn = p.position(1.0);
    let at = |x: f64| Effect::at_search(kn.clone(), &[x], course).unwrap().for_kind(Some(WallKind::ConcretePaver));
    assert!((at(xn).values[0] - 1.0).abs() < 1e-12);
    assert!((at(0.0).values[0] - 0.2).abs() < 1e-12);
    assert!((at(1.0).values[0] - 2.0).abs() < 1e-12);
}

/// A kind key the wall format does not know is refused naming the key; the bundled walls
/// declare theirs.
#[test]
fn wall_kinds_are_read_and_checked() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("studies/walls/cbl.toml")).unwrap();
    let wall = drystone::generator::WallSpec::from_toml(&text, Path::new("cbl.toml")).unwrap();
    assert_eq!(wall.kind, Some(WallKind::ConcretePaver));
    let bad = text.replace("kind = \"concrete_paver\"", "kind = \"granite\"");
    let e = drystone::generator::WallSpec::from_toml(&bad, Path::new("cbl.toml")).unwrap_err().to_string();
    assert!(e.contains("cbl.toml") && e.contains("granite") && e.contains("concrete_paver"), "{e}");
    for (f, k) in [("sbl", WallKind::ShapedStone), ("sbr", WallKind::ShapedStone)] {
        let w = drystone::generator::Wall::from_file(&root.join(format!("studies/walls/{f}.toml"))).unwrap();
        assert_eq!(w.kind, Some(k), "{f}");
    }
}

/// An effect file's range of a kind is checked as its broad range is: it must hold the
/// neutral value, and a kind unknown to the format is named.
#[test]
fn an_effect_files_kind_ranges_are_checked() {
    let text = r#"
version = 1
name = "soft_beds"
[[parameters]]
name = "factor"
unit = "-"
min = 0.05
max = 2.0
scale = "log"
neutral = 1.0
[[parameters.kinds]]
kind = "concrete_paver"
min = 0.3
max = 2.0
source = "our plate-load tests"
[[steps]]
kind = "joint_factor"
family = "bed"
property = "stiffness"
parameter = "factor"
"#;
    let d = EffectDef::from_toml(text, Path::new("soft.toml")).unwrap();
    assert_eq!(d.parameters[0].range_for(Some(WallKind::ConcretePaver)), (0.3, 2.0, "our plate-load tests"));
    assert_eq!(d.parameters[0].range_for(Some(WallKind::ShapedStone)).0, 0.05);
    let bad = text.replace("min = 0.3", "min = 1.5");
    let e = EffectDef::from_toml(&bad, Path::new("soft.toml")).unwrap_err().to_string();
    assert!(e.contains("soft.toml") && e.contains("parameters[0].kinds") && e.contains("neutral"), "{e}");
    let bad = text.replace("kind = \"concrete_paver\"", "kind = \"adobe\"");
    let e = EffectDef::from_toml(&bad, Path::new("soft.toml")).unwrap_err().to_string();
    assert!(e.contains("soft.toml") && e.contains("adobe"), "{e}");
}
