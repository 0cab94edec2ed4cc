//! Joint families: how the joints of the presets are classified, the layout JSON carrying
//! the classification and the families' properties (so `drystone tilt` of a generated
//! layout is the model of the study that generated it), family values equal to the rule
//! leaving every number unchanged, and every closure law a file can give passing the joint
//! law's contract.

use drystone::closure::{Hyperbolic, Seating};
use drystone::dem::contact::law::contract::representative_laws;
use drystone::dem::{Simulation, SolverParams};
use drystone::generator::{generate, Wall, WallSpec};
use drystone::layout::{Closure, JointFamily, JointSpec, Layout, LayoutSpec};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use std::collections::BTreeMap;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn preset(name: &str) -> Wall {
    Wall::from_file(&root().join(format!("studies/walls/{name}.toml"))).unwrap()
}

/// The families of the contacts of a layout at rest, counted.
fn families(l: &Layout) -> BTreeMap<JointFamily, usize> {
    let sim = Simulation::new(l, SolverParams::default());
    let mut out = BTreeMap::new();
    for c in &sim.state.contacts {
        *out.entry(l.joint_family(c.a, c.b, &sim.state.contact_normal(c))).or_insert(0) += 1;
    }
    out
}

#[test]
fn the_presets_joints_are_classified_by_course_and_wedge() {
    // CBL: running bond, 9 courses of 8 blocks (some end pieces merged): base joints under
    // the first course only, head joints within courses, bed joints between them.
    let cbl = generate(&preset("cbl"), 1, 0).unwrap().check().unwrap();
    let f = families(&cbl);
    let first: usize = cbl.blocks.iter().filter(|b| b.course == Some(0)).count();
    assert_eq!(f.get(&JointFamily::Base), Some(&first), "{f:?}");
    assert!(f[&JointFamily::Bed] > f[&JointFamily::Head], "{f:?}");
    assert!(!f.contains_key(&JointFamily::Wedge), "{f:?}");
    // Every head joint of a regular wall is vertical, every bed joint horizontal.
    let sim = Simulation::new(&cbl, SolverParams::default());
    for c in sim.state.contacts.iter().filter(|c| c.a.is_some()) {
        let n = sim.state.contact_normal(c);
        match cbl.joint_family(c.a, c.b, &n) {
            JointFamily::Head => assert!(n.z.abs() < 1e-6, "{n:?}"),
            JointFamily::Bed => assert!(n.x.abs() < 1e-6 && n.y.abs() < 1e-6, "{n:?}"),
            other => panic!("{other:?}"),
        }
    }
    // SBL: irregular joints with wedge stones: all four families.
    let sbl = generate(&preset("sbl"), 1, 0).unwrap().check().unwrap();
    let f = families(&sbl);
    assert_eq!(f.len(), 4, "{f:?}");
    assert!(sbl.blocks.iter().any(|b| b.wedge));
}

/// A layout without course indices is classified by the contact normal: a bed joint within
/// 45° of the vertical, a head joint otherwise.
#[test]
fn blocks_without_courses_are_classified_by_the_normal() {
    let mut l = generate(&preset("cbl"), 1, 0).unwrap().check().unwrap();
    let by_course = families(&l);
    for b in &mut l.blocks {
        b.course = None;
    }
    assert_eq!(families(&l), by_course);
}

#[test]
fn a_generated_layout_carries_its_families_through_json() {
    let mut spec = WallSpec::from_toml(
        &std::fs::read_to_string(root().join("studies/walls/sbl.toml")).unwrap(),
        &root().join("studies/walls/sbl.toml"),
    )
    .unwrap();
    spec.joints.head = Some(JointSpec { friction_deg: Some(45.0), ..JointSpec::default() });
    spec.joints.base = Some(JointSpec {
        kn_factor: Some(0.5),
        closure: Some(Closure::Seating(Seating { max_gap_m: 1e-3 })),
        ..JointSpec::default()
    });
    let source = drystone::generator::DistributionSource::default_for(&root().join("studies/walls/sbl.toml"));
    let wall = spec.resolve(&root().join("studies/walls/sbl.toml"), &source).unwrap();
    let g = generate(&wall, 3, 0).unwrap();
    let json = g.layout.to_json();
    assert!(json.contains("\"joint_families\"") && json.contains("\"course\"") && json.contains("\"wedge\": true"));
    let back = LayoutSpec::from_json(&json).unwrap().resolve().unwrap();
    assert_eq!(back, g.check().unwrap());
    let head = back.joint_families.get(JointFamily::Head).unwrap();
    assert!((head.friction.unwrap() - 45f64.to_radians()).abs() < 1e-15);
}

/// Families given exactly the values of the default rule change nothing, bit for bit.
#[test]
fn families_equal_to_the_rule_change_nothing() {
    let wall = preset("cbl");
    let l = generate(&wall, 2, 0).unwrap().check().unwrap();
    let m = &l.materials[0];
    let same = JointSpec {
        kn_pa_per_m: Some(m.kn),
        ks_pa_per_m: Some(m.ks),
        friction_deg: Some(m.friction.to_degrees()),
        ..JointSpec::default()
    };
    let mut spec = generate(&wall, 2, 0).unwrap().layout;
    spec.joint_families.bed = Some(same.clone());
    spec.joint_families.head = Some(JointSpec { kn_factor: Some(1.0), ..JointSpec::default() });
    let with = spec.resolve().unwrap();
    assert!(!with.joint_families.is_empty());
    let tilt = TiltParams { step_deg: 2.0, resolution_deg: 0.5, ..TiltParams::default() };
    let a = run_tilt(&l, SolverParams::default(), &tilt).unwrap();
    let b = run_tilt(&with, SolverParams::default(), &tilt).unwrap();
    // friction_deg round-trips through degrees; the angles still agree bit for bit.
    assert_eq!(a.collapse_angle_deg(), b.collapse_angle_deg());
    assert_eq!(
        a.increments.last().map(|i| i.displacement_m.clone()),
        b.increments.last().map(|i| i.displacement_m.clone())
    );
}

#[test]
fn bad_families_are_refused_naming_the_key() {
    let mut spec = generate(&preset("cbl"), 1, 0).unwrap().layout;
    spec.joint_families.wedge = Some(JointSpec { kn_factor: Some(0.5), ..JointSpec::default() });
    let e = spec.resolve().unwrap_err().to_string();
    assert!(e.contains("joint_families.wedge") && e.contains("no wedge stone"), "{e}");
    let mut spec = generate(&preset("cbl"), 1, 0).unwrap().layout;
    spec.joint_families.base = Some(JointSpec {
        closure: Some(Closure::Hyperbolic(Hyperbolic { max_closure_m: 1.0 })),
        ..JointSpec::default()
    });
    let e = spec.resolve().unwrap_err().to_string();
    assert!(e.contains("joint_families.base.closure.hyperbolic.max_closure_m"), "{e}");
    let mut spec = generate(&preset("cbl"), 1, 0).unwrap().layout;
    spec.joint_families.head = Some(JointSpec { kn_pa_per_m: Some(1e7), kn_factor: Some(0.5), ..JointSpec::default() });
    let e = spec.resolve().unwrap_err().to_string();
    assert!(e.contains("joint_families.head.kn_factor") && e.contains("not both"), "{e}");
    let json = generate(&preset("cbl"), 1, 0).unwrap().layout.to_json().replacen(
        "\"materials\"",
        "\"joint_families\": {\"corner\": {}},\n  \"materials\"",
        1,
    );
    let e = LayoutSpec::from_json(&json).unwrap_err().to_string();
    assert!(e.contains("unknown field `corner`"), "{e}");
    // In a wall file: a wedge family on a wall without wedges.
    let text =
        std::fs::read_to_string(root().join("studies/walls/cbl.toml")).unwrap() + "\n[joints.wedge]\nkn_factor = 0.5\n";
    let p = root().join("studies/walls/cbl.toml");
    let source = drystone::generator::DistributionSource::default_for(&p);
    let e = WallSpec::from_toml(&text, &p).unwrap().resolve(&p, &source).unwrap_err().to_string();
    assert!(e.contains("joints.wedge") && e.contains("only irregular walls"), "{e}");
}

/// Every closure law a file can give is read into the joint law's own enum, is a law the
/// contract test runs, and is written back as it was read.
#[test]
fn every_closure_law_of_the_files_is_under_contract() {
    let texts = ["\"linear\"", "{\"hyperbolic\":{\"max_closure_m\":0.001}}", "{\"seating\":{\"max_gap_m\":0.0002}}"];
    let laws: Vec<_> = representative_laws().iter().map(|j| std::mem::discriminant(&j.closure)).collect();
    for t in texts {
        let c: Closure = serde_json::from_str(t).unwrap();
        assert!(laws.contains(&std::mem::discriminant(&c)), "{t}");
        assert_eq!(serde_json::to_string(&c).unwrap(), t);
        assert!(t.contains(c.name()), "{t}");
    }
    let e = serde_json::from_str::<Closure>("{\"seating\": {\"gap\": 0.001}}").unwrap_err().to_string();
    assert!(e.contains("gap"), "{e}");
}
