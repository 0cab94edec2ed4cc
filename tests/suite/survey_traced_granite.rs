//! A real elevation: the granite walls' as-built course patterns, traced from the specimens'
//! crack maps by `data/inplane_granite/trace/trace_crackmaps.py` (a script that reads the
//! drawings' pixels, independent of the importer), imported and tested in plane.
//!
//! What is whose: the drawings and `walls.csv` are the laboratory's (data drystone did not
//! make); the nominal stones (0.20 m by 0.15 m, half stones at the ends of every other
//! course, a 1.0 m by 1.2 m by 0.2 m wall) are the paper's description; the generated wall
//! is drystone's own, from the wall description of the same walls.

use drystone::dem::SolverParams;
use drystone::generator::Wall;
use drystone::layout::MaterialSpec;
use drystone::loading::inplane::{run_in_plane_penalty, InPlaneParams};
use drystone::survey::{import, ImportOptions, Section, SurveyMaterials};
use std::path::{Path, PathBuf};

use crate::common::Scratch;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn traced(unit: &str) -> PathBuf {
    root().join(format!("data/inplane_granite/trace/traced_{unit}.svg"))
}

/// The import of the traced walls: a 0.2 m single leaf of the wall description's granite.
fn options() -> ImportOptions {
    ImportOptions {
        format: None,
        scale_m_per_unit: None,
        section: Some(Section::uniform(0.2)),
        hull_nonconvex: false,
        unit: None,
        y_up: false,
        materials: SurveyMaterials::one(MaterialSpec {
            name: "granite".into(),
            density_kg_per_m3: 2600.0,
            kn_pa_per_m: 2.0e10,
            ks_pa_per_m: 1.0e9,
            friction_deg: 32.2,
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

/// The laboratory's columns `column` of the rows of `walls.csv` whose `key` column is `value`.
fn measured(key: &str, value: &str, column: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(root().join("data/inplane_granite/walls.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (k, c) = (at(key), at(column));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[k] == value)
        .filter_map(|r| r[c].parse::<f64>().ok())
        .collect()
}

/// Each traced wall is the paper's wall: 1.0 m by 1.2 m, eight courses of 0.15 m (within
/// the trace's reading, ±8 mm), every stone a whole (0.20 m) or a half (0.10 m) within
/// ±25 mm (a stone split at a toe is read from its pieces), every course filling the
/// length, the volume 0.24 m³ and no hull added.
#[test]
fn the_traced_granite_walls_have_the_papers_stones_and_courses() {
    for unit in ["WS100", "WS175", "WS250"] {
        let w = import(&traced(unit), &options()).unwrap();
        assert!((w.length_m - 1.0).abs() < 1e-9 && (w.height_m - 1.2).abs() < 1e-9, "{unit}: {w:?}");
        assert!((w.volume_m3() - 0.24).abs() < 1e-9 && w.added_m3().abs() < 1e-12, "{unit}");
        let extent = |b: &drystone::layout::BlockSpec, k: usize| {
            let lo = b.vertices.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min);
            let hi = b.vertices.iter().map(|v| v[k]).fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        };
        let mut courses: Vec<(f64, f64, f64)> = Vec::new(); // bottom, top, length filled
        for b in &w.layout.blocks {
            let (x0, x1) = extent(b, 0);
            let (z0, z1) = extent(b, 2);
            let len = x1 - x0;
            assert!((len - 0.2).abs() < 0.025 || (len - 0.1).abs() < 0.025, "{unit}: a stone {len} m long");
            match courses.iter_mut().find(|c| (c.0 - z0).abs() < 1e-9) {
                Some(c) => c.2 += len,
                None => courses.push((z0, z1, len)),
            }
        }
        assert_eq!(courses.len(), 8, "{unit}: {courses:?}");
        for c in &courses {
            assert!((c.1 - c.0 - 0.15).abs() < 0.008, "{unit}: a course {} m high", c.1 - c.0);
            assert!((c.2 - 1.0).abs() < 1e-9, "{unit}: a course fills {} m", c.2);
        }
    }
}

/// The as-built WS.100 and a generated wall of the same description (realization 0 of
/// the bundled study's seed), tested alike at 0.5 MPa: their peaks within 5 % of each
/// other, the as-built's vertical modulus within 30 % of the laboratory's `Epc` at
/// 0.5 MPa (the joints' Kn is the wall description's estimate, not fitted), and the peak
/// within 10 % of the specimen's, below it (drystone's monotonic peaks on these walls
/// are 4-9 % low: README, "In-plane tests").
#[test]
fn the_as_built_wall_and_a_generated_one_of_its_description_carry_alike_in_plane() {
    let params =
        InPlaneParams { sigma0_mpa: 0.5, shear_span_m: Some(1.325), drift_pct: 3.25, ..InPlaneParams::default() };
    let s = SolverParams::default();
    let as_built = import(&traced("WS100"), &options()).unwrap().layout.resolve().unwrap();
    let wall = Wall::from_file(&root().join("studies/walls/granite_vasconcelos.toml")).unwrap();
    let (_, generated) = drystone::effects::realize(&wall, 20090301, 0, "g", &[]).unwrap();
    let a = run_in_plane_penalty(&as_built, s, &params, &mut |_, _, _| {}).unwrap();
    let g = run_in_plane_penalty(&generated, s, &params, &mut |_, _, _| {}).unwrap();
    let (pa, pg) = (a.positive.as_ref().unwrap().peak_force_kn, g.positive.as_ref().unwrap().peak_force_kn);
    assert!((pa / pg - 1.0).abs() < 0.05, "as built {pa} kN, generated {pg} kN");
    let epc = measured("sigma0_applied_MPa", "0.5", "Epc_MPa");
    assert!(!epc.is_empty());
    let epc = epc.iter().sum::<f64>() / epc.len() as f64;
    let e = a.wall_vertical_modulus_mpa;
    assert!((e / epc - 1.0).abs() < 0.3, "vertical modulus {e} MPa, measured {epc}");
    let v = measured("unit", "WS.100", "Vmax_pos_kN")[0];
    assert!(pa < v && pa > 0.9 * v, "as built {pa} kN, WS.100 {v} kN");
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// An in-plane study names a survey as a core study's group does: its row is the direct
/// run of the imported wall, bit for bit; a group naming both a wall and a survey, none,
/// an `import` table beside a wall description, or a survey without its thickness, is
/// refused naming the key.
#[test]
fn an_in_plane_study_runs_a_survey_and_refuses_a_bad_group_by_key() {
    let dir = Scratch::created("inplane-survey");
    let svg = traced("WS100");
    let group = |extra: &str| {
        format!(
            "version = 1\nname = \"s\"\nseed = 3\nrealizations = 1\nprotocol = \"in_plane\"\n[in_plane]\n\
             shear_span_m = 1.325\ndrift_pct = 0.3\n[[groups]]\nname = \"traced\"\nsigma0_mpa = 0.5\n{extra}\n"
        )
    };
    let import_table = "import = { thickness_m = 0.2, density = 2600.0, kn = 2.0e10, ks = 1.0e9, friction_deg = 32.2 }";
    let ok = write(&dir, "ok.toml", &group(&format!("survey = {:?}\n{import_table}", svg.display().to_string())));
    let run = crate::common::run_study_file(&ok, &dir.join("out")).unwrap();
    assert_eq!(run.rows.len(), 1);
    let row = &run.rows[0];
    assert!(row.status.is_ok(), "{row:?}");
    let layout = import(&svg, &options()).unwrap().layout.resolve().unwrap();
    let params =
        InPlaneParams { sigma0_mpa: 0.5, shear_span_m: Some(1.325), drift_pct: 0.3, ..InPlaneParams::default() };
    let direct = run_in_plane_penalty(&layout, SolverParams::default(), &params, &mut |_, _, _| {}).unwrap();
    assert_eq!(crate::common::in_plane(row).peak_pos_kn.to_bits(), direct.positive.unwrap().peak_force_kn.to_bits());
    let wall = root().join("studies/walls/granite_vasconcelos.toml");
    let s = |p: &Path| format!("{:?}", p.display().to_string());
    for (name, extra, key) in [
        ("both", format!("survey = {}\nwall = {}\n{import_table}", s(&svg), s(&wall)), "groups[traced]"),
        ("none", String::new(), "groups[traced]"),
        ("import", format!("wall = {}\n{import_table}", s(&wall)), "groups[traced].import"),
        (
            "thick",
            format!("survey = {}\nimport = {{ density = 2600.0 }}", s(&svg)),
            "groups[traced].import.thickness_m",
        ),
        ("missing", format!("survey = {}\n{import_table}", s(&dir.join("no.svg"))), "groups[traced].survey"),
        ("specimens", format!("survey = {}\n{import_table}\nspecimens = [\"A\", \"A\"]", s(&svg)), "groups[traced].specimens[1]"),
        // Scanned stones (a folder) take no thickness: they have their own.
        ("scanned", format!("survey = {}\n{import_table}", s(&dir)), "groups[traced].import.thickness_m"),
        (
            "both materials",
            format!("survey = {}\nimport = {{ thickness_m = 0.2, materials = \"m.toml\", kn = 5e9 }}", s(&svg)),
            "groups[traced].import.kn",
        ),
        (
            "twice",
            format!("survey = {}\n{import_table}\n[[groups]]\nname = \"traced\"\nsigma0_mpa = 0.5\nsurvey = {}\n{import_table}", s(&svg), s(&svg)),
            "groups[traced].name",
        ),
    ] {
        let p = write(&dir, &format!("{name}.toml"), &group(&extra));
        let e = crate::common::run_study_file(&p, &dir.join(name)).unwrap_err();
        assert!(e.contains(key), "{name}: {e}");
    }
}

/// The rig on surveyed walls written by hand: a materials list with a material no stone
/// uses (soft slate beside the granite) is tested on its stones' joints (the slate's would
/// close 5 mm under 0.5 MPa and be refused); a stone drawn above the wall is refused by
/// name as the only support of the beam, never with a NaN.
#[test]
fn the_rig_reads_the_materials_its_joints_use_and_names_a_stone_standing_alone() {
    let dir = Scratch::created("inplane-survey-rig");
    let svg = |extra: &str| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\"><line id=\"scale\" x1=\"0\" y1=\"0\" x2=\"1000\" y2=\"0\" \
             data-length-m=\"1\"/><rect id=\"a\" x=\"0\" y=\"800\" width=\"500\" height=\"200\"/><rect id=\"b\" \
             x=\"500\" y=\"800\" width=\"500\" height=\"200\"/><rect id=\"c\" x=\"0\" y=\"600\" width=\"1000\" \
             height=\"200\"/>{extra}</svg>"
        )
    };
    let mut o = options();
    let mut slate = o.materials.materials[0].clone();
    slate.name = "slate".into();
    slate.kn_pa_per_m = 1e8;
    o.materials.materials.push(slate);
    let params = InPlaneParams { sigma0_mpa: 0.5, shear_span_m: Some(0.5), drift_pct: 0.1, ..InPlaneParams::default() };
    let wall = import(&write(&dir, "w.svg", &svg("")), &o).unwrap().layout.resolve().unwrap();
    run_in_plane_penalty(&wall, SolverParams::default(), &params, &mut |_, _, _| {}).unwrap();
    let floating = "<rect id=\"f\" x=\"200\" y=\"300\" width=\"200\" height=\"100\"/>";
    let wall = import(&write(&dir, "f.svg", &svg(floating)), &options()).unwrap().layout.resolve().unwrap();
    let e = run_in_plane_penalty(&wall, SolverParams::default(), &params, &mut |_, _, _| {}).unwrap_err().to_string();
    assert!(e.contains("block f only") && e.contains("tops the wall alone") && !e.contains("NaN"), "{e}");
}
