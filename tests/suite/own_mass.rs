//! A scanned stone's mass, centroid and inertia are its closed mesh's, not its convex
//! hull's; its block (the contact geometry) stays the hull. The meshes are written here by
//! hand and their mass properties worked out by hand (the L-shaped prism as three unit
//! cubes, each cube's own inertia `s⁵/6` shifted by the parallel-axis theorem), never by the
//! code under test. A generated wall carries no `own_mass`: its layout file and its tilt
//! are those of the build before the stored mass properties (pinned below).

use drystone::dem::state::bodies_of;
use drystone::dem::SolverParams;
use drystone::generator::{generate, DistributionSource, WallSpec};
use drystone::layout::{LayoutSpec, MaterialSpec};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::survey::{import, ImportOptions, LengthUnit, SurveyMaterials};
use std::path::{Path, PathBuf};

use crate::common::Scratch;

const DENSITY: f64 = 2200.0;

fn options(unit: LengthUnit) -> ImportOptions {
    ImportOptions {
        format: None,
        scale_m_per_unit: None,
        section: None,
        hull_nonconvex: false,
        unit: Some(unit),
        y_up: false,
        materials: SurveyMaterials::one(MaterialSpec {
            name: "stone".into(),
            density_kg_per_m3: DENSITY,
            kn_pa_per_m: 1e9,
            ks_pa_per_m: 5e8,
            friction_deg: 30.0,
            cohesion_pa: 0.0,
            tensile_strength_pa: 0.0,
            closure: Default::default(),
        }),
        base_sliding: Default::default(),
        name: None,
        max_hull_vertices: None,
        full_hull: false,
    }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-300)
}

/// The L-shaped prism of section (x, z) the square [0, 2]² less the square [1, 2]², 1 unit
/// deep in y (three unit cubes at (0.5, 0.5, 0.5), (1.5, 0.5, 0.5), (0.5, 0.5, 1.5)), as an
/// OBJ of two hexagonal faces and six quads, outward.
pub(crate) fn l_prism_obj() -> String {
    let section = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)];
    let mut obj: String =
        [0.0, 1.0].iter().flat_map(|y| section.iter().map(move |(x, z)| format!("v {x} {y} {z}\n"))).collect();
    obj += "f 1 2 3 4 5 6\nf 12 11 10 9 8 7\n";
    for i in 1..=6 {
        let j = i % 6 + 1;
        obj += &format!("f {j} {i} {} {}\n", i + 6, j + 6);
    }
    obj
}

/// Worked by hand, in the mesh's unit (here cm): volume 3; centroid
/// ((0.5 + 1.5 + 0.5)/3, 0.5, (0.5 + 0.5 + 1.5)/3) = (5/6, 1/2, 5/6). Offsets of the cubes
/// from it: (−1/3, 0, −1/3), (2/3, 0, −1/3), (−1/3, 0, 2/3). Per unit density:
/// Ixx = 3/6 + Σ(dy² + dz²) = 1/2 + 6/9 = 7/6; Iyy = 1/2 + Σ(dx² + dz²) = 1/2 + 12/9 = 11/6;
/// Izz = 1/2 + Σ(dx² + dy²) = 7/6; Ixz = −Σ dx dz = −(1/9 − 2/9 − 2/9) = 1/3; Ixy = Iyz = 0.
/// The import puts the stone on the table at x = 0 with its y extent centred on 0 (y − 1/2),
/// and in metres (×1e-2 on lengths, ×1e-6 on the volume, ×1e-10 on the inertia per density).
/// Its hull adds the triangle across the notch: 3.5 cm³.
#[test]
fn an_l_shaped_scanned_stone_has_its_meshs_mass_centroid_and_inertia_and_its_hull_for_contacts() {
    let dir = Scratch::created("own-mass-l");
    let w = import(&write(&dir, "ell.obj", &l_prism_obj()), &options(LengthUnit::Cm)).unwrap();
    let b = &w.layout.blocks[0];
    let own = b.own_mass.expect("a scanned stone carries its own mass properties");
    assert!(close(own.volume_m3, 3e-6, 1e-12), "{own:?}");
    let c = [5.0 / 6.0 * 1e-2, 0.0, 5.0 / 6.0 * 1e-2];
    for k in 0..3 {
        assert!((own.centroid_m[k] - c[k]).abs() < 1e-15, "{own:?}");
    }
    let i = [[7.0 / 6.0, 0.0, 1.0 / 3.0], [0.0, 11.0 / 6.0, 0.0], [1.0 / 3.0, 0.0, 7.0 / 6.0]];
    for r in 0..3 {
        for k in 0..3 {
            assert!((own.inertia_m5[r][k] - i[r][k] * 1e-10).abs() < 1e-12 * 1e-10, "{r}{k}: {own:?}");
        }
    }
    assert_eq!(b.vertices.len(), 10, "the block is the hull: the notch's inner corner dropped");
    assert!(close(w.stones[0].block_volume_m3, 3.5e-6, 1e-12) && close(w.stones[0].survey_volume_m3, 3e-6, 1e-12));

    // Through the layout file: the block's mass is the mesh's (6.6 g), not the hull's (7.7 g).
    let text = w.layout.to_json();
    assert!(text.contains("\"own_mass\""), "{text}");
    let layout = LayoutSpec::from_json(&text).unwrap().resolve().unwrap();
    let mp = layout.blocks[0].mass_properties(DENSITY);
    assert!(close(mp.mass, 3e-6 * DENSITY, 1e-12), "{}", mp.mass);
    assert!(close(layout.blocks[0].shape.volume(), 3.5e-6, 1e-12));
    let body = &bodies_of(&layout)[0];
    assert!(close(body.mass, 3e-6 * DENSITY, 1e-12), "{}", body.mass);
    for k in 0..3 {
        assert!((body.pos[k] - c[k]).abs() < 1e-15, "the body's origin is the mesh's centroid: {:?}", body.pos);
        for r in 0..3 {
            assert!((body.inertia[(r, k)] - i[r][k] * 1e-10 * DENSITY).abs() < 1e-12 * 1e-10 * DENSITY);
        }
    }
    // The hull's corners about the body's origin: the corner (0, −1/2, 0) cm at −c.
    let corner = body.shape.vertices.iter().map(|v| (v + body.pos - nalgebra::Vector3::new(0.0, -0.005, 0.0)).norm());
    assert!(corner.fold(f64::INFINITY, f64::min) < 1e-15);
}

/// A unit cube (1 m): volume 1, centroid at its centre, inertia 1/6 per unit density about
/// every axis through it, no products; the same with every face turned inwards (the mesh's
/// orientation is either, consistently).
#[test]
fn a_unit_cube_mesh_has_a_cubes_mass_properties_whichever_way_its_faces_turn() {
    let dir = Scratch::created("own-mass-cube");
    let v = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
    let quads = [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [3, 4, 8, 7], [1, 5, 8, 4], [2, 3, 7, 6]];
    let faces = |reverse: bool| -> String {
        quads
            .iter()
            .map(|q| {
                let mut q = q.to_vec();
                if reverse {
                    q.reverse();
                }
                format!("f {}\n", q.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" "))
            })
            .collect()
    };
    for (name, reverse) in [("out.obj", false), ("in.obj", true)] {
        let w = import(&write(&dir, name, &format!("{v}{}", faces(reverse))), &options(LengthUnit::M)).unwrap();
        let own = w.layout.blocks[0].own_mass.unwrap();
        assert!((own.volume_m3 - 1.0).abs() < 1e-15, "{name}: {own:?}");
        assert!((own.centroid_m[0] - 0.5).abs() < 1e-15 && own.centroid_m[1].abs() < 1e-15, "{name}: {own:?}");
        assert!((own.centroid_m[2] - 0.5).abs() < 1e-15, "{name}: {own:?}");
        for r in 0..3 {
            for k in 0..3 {
                let want = if r == k { 1.0 / 6.0 } else { 0.0 };
                assert!((own.inertia_m5[r][k] - want).abs() < 1e-15, "{name} {r}{k}: {own:?}");
            }
        }
        let l = w.layout.resolve().unwrap();
        assert!((l.blocks[0].mass_properties(DENSITY).mass - DENSITY).abs() < 1e-9);
    }
}

/// Stored mass properties a stone cannot have are refused naming the block and the key.
#[test]
fn impossible_own_mass_is_refused_naming_the_block_and_the_key() {
    let layout = |own: &str| {
        format!(
            r#"{{"version":1,"materials":[{{"name":"m","density_kg_per_m3":2000,"kn_pa_per_m":1e9,
            "ks_pa_per_m":5e8,"friction_deg":30}}],"table":{{"material":"m"}},
            "blocks":[{{"id":"b0","material":"m","vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
            "own_mass":{own}}}]}}"#
        )
    };
    let cube = "[[0.1,0,0],[0,0.1,0],[0,0,0.1]]";
    let e = |own: String| LayoutSpec::from_json(&layout(&own)).unwrap().resolve().unwrap_err().to_string();
    let big = e(format!(r#"{{"volume_m3":1.5,"centroid_m":[0.5,0.5,0.5],"inertia_m5":{cube}}}"#));
    assert!(big.contains("blocks[b0].own_mass.volume_m3") && big.contains("convex hull"), "{big}");
    let zero = e(format!(r#"{{"volume_m3":0,"centroid_m":[0.5,0.5,0.5],"inertia_m5":{cube}}}"#));
    assert!(zero.contains("blocks[b0].own_mass.volume_m3"), "{zero}");
    let out = e(format!(r#"{{"volume_m3":0.5,"centroid_m":[0.5,0.5,1.5],"inertia_m5":{cube}}}"#));
    assert!(out.contains("blocks[b0].own_mass.centroid_m") && out.contains("inside"), "{out}");
    let skew =
        e(r#"{"volume_m3":0.5,"centroid_m":[0.5,0.5,0.5],"inertia_m5":[[0.1,0.01,0],[0,0.1,0],[0,0,0.1]]}"#.into());
    assert!(skew.contains("blocks[b0].own_mass.inertia_m5") && skew.contains("symmetric"), "{skew}");
    let rod = e(r#"{"volume_m3":0.5,"centroid_m":[0.5,0.5,0.5],"inertia_m5":[[0.1,0,0],[0,0.1,0],[0,0,0.3]]}"#.into());
    assert!(rod.contains("blocks[b0].own_mass.inertia_m5") && rod.contains("sum of the other two"), "{rod}");
    let unknown = LayoutSpec::from_json(&layout(r#"{"volume":0.5}"#)).unwrap_err().to_string();
    assert!(unknown.contains("volume"), "{unknown}");
}

/// A generated wall has no `own_mass`: its layout file is byte for byte what the build
/// before stored mass properties wrote (the FNV-1a 64 hash of `drystone generate`'s file,
/// pinned from that build), and its tilt by the penalty DEM brackets its collapse where that
/// build's `drystone tilt` did.
#[test]
fn a_generated_walls_layout_file_and_tilt_are_unchanged() {
    let text = "version = 1\nname = \"small running bond\"\n[geometry]\nlength_m = 0.6\nheight_m = 0.2\n\
                base_width_m = 0.12\ntop_width_m = 0.08\n[arrangement]\nkind = \"discontinuous\"\n[courses]\n\
                height_m = 0.05\n[blocks]\nlength_m = 0.15\nmaterial = \"stone\"\n[[materials]]\nname = \"stone\"\n\
                density_kg_per_m3 = 2200\nkn_pa_per_m = 1e8\nks_pa_per_m = 5e7\nfriction_deg = 30\n";
    let p = Path::new("small.toml");
    let wall = WallSpec::from_toml(text, p).unwrap().resolve(p, &DistributionSource::default()).unwrap();
    let g = generate(&wall, 7, 0).unwrap();
    let json = g.layout.to_json();
    assert!(!json.contains("own_mass"));
    let fnv = json.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3));
    assert_eq!((json.len(), fnv), PINNED_LAYOUT, "the generated layout file changed");
    let r = run_tilt(&g.layout.resolve().unwrap(), SolverParams::default(), &TiltParams::default()).unwrap();
    assert_eq!((r.last_stable_deg, r.first_unstable_deg), PINNED_TILT, "the generated wall's tilt changed");
}

/// `drystone generate small.toml --seed 7 --out l.json` of the build before: its length in
/// bytes and its FNV-1a 64 hash.
const PINNED_LAYOUT: (usize, u64) = (13492, 3718194638181681420);

/// `drystone tilt l.json` of the build before: the last stable and the first unstable tilt,
/// degrees.
const PINNED_TILT: (f64, Option<f64>) = (28.5, Some(28.625));

/// An effect that reshapes blocks refuses a scanned stone (its hull would no longer be the
/// stone's), naming the effect and the block; one that does not reshape (a joint factor)
/// acts on it; a reshaping effect at its neutral value leaves it alone.
#[test]
fn a_reshaping_effect_refuses_a_scanned_stone_by_name() {
    use drystone::effects::{effect_rng, Library, Stage};
    let dir = Scratch::created("own-mass-effect");
    let w = import(&write(&dir, "ell.obj", &l_prism_obj()), &options(LengthUnit::Cm)).unwrap();
    let layout = w.layout.resolve().unwrap();
    let apply = |e: &str| {
        let mut l = layout.clone();
        let e = Library::builtin().parse(e, drystone::effects::REFERENCE_COURSE_HEIGHT_M).unwrap();
        let mut rng = effect_rng(0, 0, "test", "e");
        [Stage::Layout, Stage::JointLaw, Stage::Restraints]
            .into_iter()
            .try_for_each(|stage| e.apply_stage(stage, &mut l, &[], &mut rng))
            .map(|_| l)
            .map_err(|e| e.to_string())
    };
    for effect in ["initial_lean=1", "edge_rounding=0.001"] {
        let e = apply(effect).unwrap_err();
        assert!(
            e.contains(effect.split('=').next().unwrap()) && e.contains("block ell") && e.contains("own mass"),
            "{e}"
        );
    }
    let same = apply("initial_lean=0").unwrap();
    assert_eq!(same.blocks[0], layout.blocks[0]);
}
