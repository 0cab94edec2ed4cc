//! `drystone import`: surveyed walls as layouts. The surveys are written here by hand (SVG,
//! GeoJSON, DXF, OBJ, STL), or exported from a generated wall by this file's own SVG writer,
//! never by the code under test; the expected blocks and volumes are worked out by hand.

use drystone::dem::SolverParams;
use drystone::generator::spec::Batter;
use drystone::generator::{generate, DistributionSource, GeneratedWall, WallSpec};
use drystone::layout::{LayoutSpec, MaterialSpec};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::survey::{import, ImportOptions, LengthUnit, Section, SurveyError, SurveyMaterials};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::Scratch;

fn material(name: &str, density: f64) -> MaterialSpec {
    MaterialSpec {
        name: name.into(),
        density_kg_per_m3: density,
        kn_pa_per_m: 1e8,
        ks_pa_per_m: 5e7,
        friction_deg: 30.0,
        cohesion_pa: 0.0,
        tensile_strength_pa: 0.0,
        closure: Default::default(),
    }
}

/// Options for a traced elevation of constant thickness `t` (m), one material `stone`.
fn traced(t: f64, scale: Option<f64>) -> ImportOptions {
    ImportOptions {
        format: None,
        scale_m_per_unit: scale,
        section: Some(Section::uniform(t)),
        hull_nonconvex: false,
        unit: None,
        y_up: false,
        materials: SurveyMaterials::one(material("stone", 2200.0)),
        base_sliding: Default::default(),
        name: None,
        max_hull_vertices: None,
        full_hull: false,
    }
}

/// Options for scanned stones in `unit`.
fn scanned(unit: LengthUnit) -> ImportOptions {
    ImportOptions { section: None, unit: Some(unit), ..traced(1.0, None) }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A small running-bond wall with a symmetric batter (18 stones).
fn small_wall() -> (drystone::generator::Wall, GeneratedWall) {
    let text = "version = 1\nname = \"small running bond\"\n[geometry]\nlength_m = 0.6\nheight_m = 0.2\n\
                base_width_m = 0.12\ntop_width_m = 0.08\n[arrangement]\nkind = \"discontinuous\"\n[courses]\n\
                height_m = 0.05\n[blocks]\nlength_m = 0.15\nmaterial = \"stone\"\n[[materials]]\nname = \"stone\"\n\
                density_kg_per_m3 = 2200\nkn_pa_per_m = 1e8\nks_pa_per_m = 5e7\nfriction_deg = 30\n";
    let p = Path::new("small.toml");
    let wall = WallSpec::from_toml(text, p).unwrap().resolve(p, &DistributionSource::default()).unwrap();
    let g = generate(&wall, 7, 0).unwrap();
    (wall, g)
}

/// The generated wall's elevation as an SVG drawing: one element per stone, its corners in
/// drawing units of `unit_m` metres, y down, inside a group translated by (dx, dy). With
/// `paths`, every other stone is a relative `<path>` (m, l, z) instead of a `<polygon>`.
fn export_svg(g: &GeneratedWall, unit_m: f64, dx: f64, dy: f64, paths: bool) -> String {
    let mut s = format!(
        "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g transform=\"translate({dx} {dy})\">\n"
    );
    for (i, p) in g.pieces.iter().enumerate() {
        let pts: Vec<(f64, f64)> = p.polygon.iter().map(|q| (q[0] / unit_m, -q[1] / unit_m)).collect();
        if paths && i % 2 == 1 {
            let mut d = format!("m {} {}", pts[0].0, pts[0].1);
            for w in pts.windows(2) {
                d += &format!(" l {} {}", w[1].0 - w[0].0, w[1].1 - w[0].1);
            }
            s += &format!("  <path id=\"{}\" d=\"{d} z\"/>\n", p.id);
        } else {
            let list: Vec<String> = pts.iter().map(|(x, y)| format!("{x},{y}")).collect();
            s += &format!("  <polygon id=\"{}\" points=\"{}\"/>\n", p.id, list.join(" "));
        }
    }
    s + "</g>\n</svg>\n"
}

fn assert_same_blocks(a: &LayoutSpec, b: &LayoutSpec, tol: f64) {
    assert_eq!(a.blocks.len(), b.blocks.len());
    for (x, y) in a.blocks.iter().zip(&b.blocks) {
        assert_eq!(x.id, y.id);
        assert_eq!(x.vertices.len(), y.vertices.len(), "{}", x.id);
        for (p, q) in x.vertices.iter().zip(&y.vertices) {
            for k in 0..3 {
                assert!((p[k] - q[k]).abs() <= tol, "{}: {p:?} vs {q:?}", x.id);
            }
        }
    }
}

fn battered(wall: &drystone::generator::Wall) -> Section {
    Section { base_m: wall.base_width, top_m: wall.top_width, batter: Batter::Symmetric }
}

#[test]
fn a_generated_wall_traced_in_svg_comes_back_with_its_blocks_and_its_collapse_angle() {
    let dir = Scratch::created("survey-roundtrip");
    let (wall, g) = small_wall();
    let options = ImportOptions {
        section: Some(battered(&wall)),
        materials: SurveyMaterials::one(wall.materials[0].clone()),
        ..traced(1.0, Some(1.0))
    };
    // In metres, as drawn.
    let svg = write(&dir, "wall.svg", &export_svg(&g, 1.0, 0.0, 0.0, false));
    let imported = import(&svg, &options).unwrap();
    assert_same_blocks(&g.layout, &imported.layout, 1e-9);
    assert_eq!(imported.stones.len(), 18);
    assert!(imported.stones.iter().all(|s| !s.hulled));
    assert!((imported.volume_m3() - g.volume()).abs() < 1e-12, "{} {}", imported.volume_m3(), g.volume());
    assert!((imported.length_m - 0.6).abs() < 1e-12 && (imported.height_m - 0.2).abs() < 1e-12);
    // In millimetres, shifted, every other stone a relative path.
    let mm = write(&dir, "wall_mm.svg", &export_svg(&g, 1e-3, 120.0, 900.0, true));
    let again = import(&mm, &ImportOptions { scale_m_per_unit: Some(1e-3), ..options.clone() }).unwrap();
    assert_same_blocks(&g.layout, &again.layout, 1e-9);
    // The same tilting-table collapse.
    let params = TiltParams { step_deg: 1.0, resolution_deg: 0.25, ..TiltParams::default() };
    let a = run_tilt(&g.layout.resolve().unwrap(), SolverParams::default(), &params).unwrap();
    let b = run_tilt(&imported.layout.resolve().unwrap(), SolverParams::default(), &params).unwrap();
    assert!(a.collapse_angle_deg() > 5.0, "{}", a.collapse_angle_deg());
    assert!((a.collapse_angle_deg() - b.collapse_angle_deg()).abs() < 1e-9);
}

#[test]
fn irregular_generated_walls_with_wedges_traced_in_svg_come_back_with_their_blocks() {
    let dir = Scratch::created("survey-irregular");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (file, seed) in [("studies/walls/sbl.toml", 3), ("studies/walls/full_scale.toml", 11)] {
        let wall = drystone::generator::Wall::from_file(&root.join(file)).unwrap();
        let g = generate(&wall, seed, 0).unwrap();
        assert!(g.counts().1 > 0, "{file}: no wedges");
        let options = ImportOptions {
            section: Some(Section { base_m: wall.base_width, top_m: wall.top_width, batter: wall.batter }),
            materials: SurveyMaterials {
                materials: g.layout.materials.clone(),
                stone_material: None,
                table_material: None,
            },
            ..traced(1.0, Some(1.0))
        };
        let svg = write(&dir, "irregular.svg", &export_svg(&g, 1.0, 0.0, 0.0, false));
        let imported = import(&svg, &options).unwrap();
        assert_same_blocks(&g.layout, &imported.layout, 1e-9);
    }
}

/// A base stone 300 × 100 mm and on it an L (200 × 100 mm less a 100 × 50 mm notch at its
/// top right), drawn with y down, scale by a 500 mm scale line.
const L_SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 400 300">
  <line id="scale" x1="0" y1="250" x2="500" y2="250" data-length-m="0.5"/>
  <image href="photo.jpg" width="400" height="300"/>
  <g data-ignore="true"><rect x="-50" y="-400" width="600" height="500"/></g>
  <rect id="base" x="0" y="-100" width="300" height="100"/>
  <path id="ell" d="M 0 -100 L 200 -100 L 200 -150 L 100 -150 L 100 -200 L 0 -200 Z"/>
</svg>
"#;

#[test]
fn a_non_convex_stone_is_refused_by_name_or_taken_as_its_hull_on_request() {
    let dir = Scratch::created("survey-ell");
    let svg = write(&dir, "ell.svg", L_SVG);
    let e = import(&svg, &traced(0.25, None)).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, SurveyError::NonConvex { .. }), "{text}");
    // The L: 0.2 × 0.1 − 0.1 × 0.05 = 0.015 m²; its hull adds the triangle of the notch,
    // 0.1 × 0.05 / 2 = 0.0025 m² (16.67 %); the reflex corner at (0.1, 0.15) m.
    for part in
        ["ell.svg", "stone ell", "<path id=\"ell\"> at line 6", "2.5000e-3 m²", "16.67 %", "x = 0.1000 m, z = 0.1500 m"]
    {
        assert!(text.contains(part), "{part:?} not in {text}");
    }
    let w = import(&svg, &ImportOptions { hull_nonconvex: true, ..traced(0.25, None) }).unwrap();
    assert_eq!(w.layout.blocks.len(), 2);
    let ell = &w.stones[1];
    assert!(ell.hulled && ell.id == "ell");
    assert!((ell.survey_volume_m3 - 0.015 * 0.25).abs() < 1e-12, "{}", ell.survey_volume_m3);
    assert!((ell.block_volume_m3 - 0.0175 * 0.25).abs() < 1e-12, "{}", ell.block_volume_m3);
    assert!((w.added_m3() - 0.0025 * 0.25).abs() < 1e-12);
    assert!((w.volume_m3() - (0.03 + 0.0175) * 0.25).abs() < 1e-12);
    // The hull's corners: the L's five convex corners, the notch's corner dropped.
    assert_eq!(w.layout.blocks[1].vertices.len(), 10);
    assert!(w.layout.blocks[1].vertices.iter().all(|v| !((v[0] - 0.1).abs() < 1e-12 && (v[2] - 0.15).abs() < 1e-12)));
    assert_eq!(w.scale.as_ref().unwrap().0, 0.001);
}

/// A closed cube of side `s` with its lowest corner at `o`, outward faces (quads), as OBJ
/// lines after `first` vertices.
fn cube_obj(s: f64, o: [f64; 3], first: usize) -> String {
    let mut t = String::new();
    for (x, y, z) in
        [(0., 0., 0.), (s, 0., 0.), (s, s, 0.), (0., s, 0.), (0., 0., s), (s, 0., s), (s, s, s), (0., s, s)]
    {
        t += &format!("v {} {} {}\n", o[0] + x, o[1] + y, o[2] + z);
    }
    for f in [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [3, 4, 8, 7], [1, 5, 8, 4], [2, 3, 7, 6]] {
        t += &format!("f {}\n", f.map(|i| (i + first).to_string()).join(" "));
    }
    t
}

/// The cube's 12 outward triangles.
fn cube_triangles(s: f32) -> Vec<[[f32; 3]; 3]> {
    let v = |i: usize| {
        [[0., 0., 0.], [s, 0., 0.], [s, s, 0.], [0., s, 0.], [0., 0., s], [s, 0., s], [s, s, s], [0., s, s]][i - 1]
    };
    let quads = [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [3, 4, 8, 7], [1, 5, 8, 4], [2, 3, 7, 6]];
    quads.iter().flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]]).collect()
}

fn binary_stl(tris: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend((tris.len() as u32).to_le_bytes());
    for t in tris {
        b.extend([0u8; 12]);
        for v in t {
            for c in v {
                b.extend(c.to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

fn ascii_stl(tris: &[[[f32; 3]; 3]]) -> String {
    let mut s = "solid cube\n".to_string();
    for t in tris {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for v in t {
            s += &format!("      vertex {} {} {}\n", v[0], v[1], v[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid cube\n"
}

#[test]
fn scanned_cubes_have_their_volume_in_the_unit_given_and_implausible_sizes_are_refused() {
    let dir = Scratch::created("survey-cubes");
    // Two 200 mm cubes, one on the other, as two objects of one OBJ file.
    let obj = format!(
        "# two stones\no lower\n{}o upper\n{}",
        cube_obj(200.0, [0.0; 3], 0),
        cube_obj(200.0, [0.0, 0.0, 200.0], 8)
    );
    let w = import(&write(&dir, "cubes.obj", &obj), &scanned(LengthUnit::Mm)).unwrap();
    assert_eq!(w.layout.blocks.iter().map(|b| b.id.as_str()).collect::<Vec<_>>(), ["lower", "upper"]);
    for s in &w.stones {
        // (200 mm)³ = 8e-3 m³, the mesh's and its hull's.
        assert!((s.survey_volume_m3 - 8e-3).abs() < 1e-15 && (s.block_volume_m3 - 8e-3).abs() < 1e-12, "{s:?}");
    }
    assert!((w.height_m - 0.4).abs() < 1e-12 && (w.length_m - 0.2).abs() < 1e-12);
    let top = w.layout.blocks[1].vertices.iter().map(|v| v[2]).fold(0.0, f64::max);
    assert!((top - 0.4).abs() < 1e-12);
    // A unit cube in mm is 1e-9 m³: a 1 mm stone, refused as a probable unit mistake.
    let e = import(&write(&dir, "tiny.obj", &cube_obj(1.0, [0.0; 3], 0)), &scanned(LengthUnit::Mm)).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, SurveyError::Size { .. }) && text.contains("tiny.obj") && text.contains("--unit mm"), "{text}");
    // The same numbers in cm: a 1 cm cube is 1e-6 m³.
    let w = import(&write(&dir, "cm.obj", &cube_obj(1.0, [0.0; 3], 0)), &scanned(LengthUnit::Cm)).unwrap();
    assert!((w.stones[0].survey_volume_m3 - 1e-6).abs() < 1e-18);
    // A cube 1000 m long.
    let e = import(&write(&dir, "huge.obj", &cube_obj(1000.0, [0.0; 3], 0)), &scanned(LengthUnit::M)).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("huge.obj") && text.contains("1.0000e3 m long") && text.contains("unit mistake"), "{text}");
}

/// A non-convex stone (every real one is) is taken as its convex hull, not refused: an
/// L-shaped prism, its section the square of side 2 cm less a 1 cm square (3 cm²), 1 cm
/// deep, is 3 cm³; its hull adds the triangle across the notch (0.5 cm², 0.5 cm³). The L
/// faces are six-sided polygons, fan-triangulated from their first corner (star-shaped
/// about it).
#[test]
fn a_non_convex_scanned_stone_is_its_convex_hull_with_the_volume_it_adds() {
    let dir = Scratch::created("survey-notched");
    let obj = crate::own_mass::l_prism_obj();
    let w = import(&write(&dir, "notched.obj", &obj), &scanned(LengthUnit::Cm)).unwrap();
    let s = &w.stones[0];
    assert!(s.hulled);
    assert!((s.survey_volume_m3 - 3e-6).abs() < 1e-18, "{s:?}");
    assert!((s.block_volume_m3 - 3.5e-6).abs() < 1e-18, "{s:?}");
    assert!((w.added_m3() - 0.5e-6).abs() < 1e-18);
    // The hull drops the notch's inner corner (1, y, 1): 10 corners of the 12.
    assert_eq!(w.layout.blocks[0].vertices.len(), 10);
}

#[test]
fn binary_and_ascii_stl_and_a_folder_of_stones_read_alike() {
    let dir = Scratch::created("survey-stl");
    let tris = cube_triangles(150.0);
    let stones = dir.join("stones");
    std::fs::create_dir_all(&stones).unwrap();
    std::fs::write(stones.join("b.stl"), binary_stl(&tris)).unwrap();
    write(&stones, "a.stl", &ascii_stl(&tris));
    write(&stones, "notes.txt", "not a stone");
    // Side by side they would overlap entirely: the layout check names both stones.
    let e = import(&stones, &scanned(LengthUnit::Mm)).unwrap_err().to_string();
    assert!(e.contains("stones a (a.stl)") && e.contains("b (b.stl)") && e.contains("overlap"), "{e}");
    std::fs::remove_file(stones.join("b.stl")).unwrap();
    let one = import(&stones.join("a.stl"), &scanned(LengthUnit::Mm)).unwrap();
    std::fs::write(dir.join("d.stl"), binary_stl(&tris)).unwrap();
    let two = import(&dir.join("d.stl"), &scanned(LengthUnit::Mm)).unwrap();
    for w in [&one, &two] {
        assert!((w.stones[0].survey_volume_m3 - 0.15f64.powi(3)).abs() < 1e-15, "{:?}", w.stones[0]);
    }
    // y up: a box 0.1 wide (x), 0.3 tall (file y), 0.2 deep (file z) stands 0.3 m tall.
    let mut tall = String::new();
    for (x, y, z) in [
        (0., 0., 0.),
        (0.1, 0., 0.),
        (0.1, 0.3, 0.),
        (0., 0.3, 0.),
        (0., 0., 0.2),
        (0.1, 0., 0.2),
        (0.1, 0.3, 0.2),
        (0., 0.3, 0.2),
    ] {
        tall += &format!("v {x} {y} {z}\n");
    }
    tall += "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";
    let w = import(&write(&dir, "tall.obj", &tall), &ImportOptions { y_up: true, ..scanned(LengthUnit::M) }).unwrap();
    assert!((w.height_m - 0.3).abs() < 1e-12, "{}", w.height_m);
}

/// Three stones stacked, in metres from an arbitrary origin: a 0.6 × 0.2 base, a 0.4 × 0.15
/// stone centred on it, a triangular cap 0.2 wide and 0.15 tall (given clockwise) of its own
/// material.
const STACK: &str = r#"{"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": "bottom", "properties": {},
  "geometry": {"type": "Polygon", "coordinates": [[[10, 2], [10.6, 2], [10.6, 2.2], [10, 2.2], [10, 2]]]}},
 {"type": "Feature", "properties": {"name": "middle"},
  "geometry": {"type": "Polygon", "coordinates": [[[10.1, 2.2], [10.5, 2.2], [10.5, 2.35], [10.1, 2.35], [10.1, 2.2]]]}},
 {"type": "Feature", "properties": {"material": "cap"},
  "geometry": {"type": "Polygon", "coordinates": [[[10.2, 2.35], [10.3, 2.5], [10.4, 2.35], [10.2, 2.35]]]}}
]}"#;

#[test]
fn a_geojson_stack_of_three_stones_gives_the_blocks_worked_out_by_hand() {
    let dir = Scratch::created("survey-stack");
    let materials = SurveyMaterials {
        materials: vec![material("granite", 2600.0), material("cap", 2000.0)],
        stone_material: Some("granite".into()),
        table_material: None,
    };
    let w = import(&write(&dir, "stack.geojson", STACK), &ImportOptions { materials, ..traced(0.3, None) }).unwrap();
    let l = &w.layout;
    assert_eq!(l.blocks.iter().map(|b| b.id.as_str()).collect::<Vec<_>>(), ["bottom", "middle", "s2"]);
    assert_eq!(l.blocks.iter().map(|b| b.material.as_str()).collect::<Vec<_>>(), ["granite", "granite", "cap"]);
    assert_eq!(l.table.material, "granite");
    let (h, e) = (0.15, 1e-9);
    let expected: [Vec<[f64; 2]>; 3] = [
        vec![[0.0, 0.0], [0.6, 0.0], [0.6, 0.2], [0.0, 0.2]],
        vec![[0.1, 0.2], [0.5, 0.2], [0.5, 0.35], [0.1, 0.35]],
        vec![[0.2, 0.35], [0.4, 0.35], [0.3, 0.5]],
    ];
    for (b, poly) in l.blocks.iter().zip(&expected) {
        let want: Vec<[f64; 3]> = poly.iter().flat_map(|&[x, z]| [[x, -h, z], [x, h, z]]).collect();
        assert_eq!(b.vertices.len(), want.len(), "{}", b.id);
        for (v, u) in b.vertices.iter().zip(&want) {
            assert!((0..3).all(|k| (v[k] - u[k]).abs() < e), "{}: {v:?} vs {u:?}", b.id);
        }
    }
    let volumes: Vec<f64> = w.stones.iter().map(|s| s.block_volume_m3).collect();
    for (v, want) in volumes.iter().zip([0.036, 0.018, 0.0045]) {
        assert!((v - want).abs() < 1e-12, "{volumes:?}");
    }
    assert!((w.height_m - 0.5).abs() < e && (w.length_m - 0.6).abs() < e);
    assert_eq!(w.offset_m, [-10.0, 0.0, -2.0]);
    assert_eq!(w.on_table(), 1);
    l.resolve().unwrap();
}

/// An ASCII DXF file of group codes and values.
fn dxf(pairs: &[(i32, &str)]) -> String {
    pairs.iter().map(|(c, v)| format!("{c:>3}\n{v}\n")).collect()
}

/// A drawing in millimetres (`$INSUNITS` 4), from an origin at (1000, 500) mm: a stone
/// 400 × 150 mm on layer `granite`, a triangle 200 mm wide and 150 mm tall on it on layer
/// `slate`, an open polyline and a line on layer `IGNORE` (neither is a stone); then
/// `extra` entities.
fn drawing(extra: &[(i32, &str)]) -> String {
    let mut p: Vec<(i32, &str)> = vec![(0, "SECTION"), (2, "HEADER"), (9, "$INSUNITS"), (70, "4"), (0, "ENDSEC")];
    p.extend([(0, "SECTION"), (2, "ENTITIES")]);
    p.extend([(0, "LWPOLYLINE"), (5, "2A"), (8, "granite"), (90, "4"), (70, "1")]);
    p.extend([
        (10, "1000"),
        (20, "500"),
        (10, "1400"),
        (20, "500"),
        (10, "1400"),
        (20, "650"),
        (10, "1000"),
        (20, "650"),
    ]);
    p.extend([(0, "LWPOLYLINE"), (5, "2B"), (8, "slate"), (90, "3"), (70, "1")]);
    p.extend([(10, "1100"), (20, "650"), (10, "1300"), (20, "650"), (10, "1200"), (20, "800")]);
    p.extend([(0, "LWPOLYLINE"), (5, "2C"), (8, "IGNORE"), (70, "0"), (10, "0"), (20, "0"), (10, "9000"), (20, "0")]);
    p.extend([(0, "LINE"), (8, "Ignore"), (10, "0"), (20, "0"), (11, "1"), (21, "1")]);
    p.extend_from_slice(extra);
    p.extend([(0, "ENDSEC"), (0, "EOF")]);
    dxf(&p)
}

#[test]
fn a_dxf_drawing_in_millimetres_gives_its_closed_polylines_as_stones() {
    let dir = Scratch::created("survey-dxf");
    let materials = SurveyMaterials {
        materials: vec![material("granite", 2600.0), material("slate", 2700.0)],
        stone_material: None,
        table_material: None,
    };
    let options = ImportOptions { materials, ..traced(0.2, None) };
    let w = import(&write(&dir, "wall.dxf", &drawing(&[])), &options).unwrap();
    let l = &w.layout;
    assert_eq!(l.blocks.iter().map(|b| b.id.as_str()).collect::<Vec<_>>(), ["2A", "2B"]);
    assert_eq!(l.blocks.iter().map(|b| b.material.as_str()).collect::<Vec<_>>(), ["granite", "slate"]);
    let want =
        [[0.1, -0.1, 0.15], [0.1, 0.1, 0.15], [0.3, -0.1, 0.15], [0.3, 0.1, 0.15], [0.2, -0.1, 0.3], [0.2, 0.1, 0.3]];
    for (v, u) in l.blocks[1].vertices.iter().zip(&want) {
        assert!((0..3).all(|k| (v[k] - u[k]).abs() < 1e-12), "{v:?} vs {u:?}");
    }
    // 0.4 × 0.15 × 0.2 and 0.2 × 0.15 / 2 × 0.2, m³.
    assert!((w.stones[0].block_volume_m3 - 0.012).abs() < 1e-15 && (w.stones[1].block_volume_m3 - 0.003).abs() < 1e-15);
    assert_eq!(w.scale.as_ref().unwrap().0, 0.001);
    // An arc segment and an open polyline are refused by handle and line.
    let bulge = [
        (0, "LWPOLYLINE"),
        (5, "3F"),
        (8, "0"),
        (70, "1"),
        (10, "2000"),
        (20, "500"),
        (42, "0.5"),
        (10, "2100"),
        (20, "500"),
        (10, "2100"),
        (20, "600"),
    ];
    let e = error_of(&dir, "arc.dxf", &drawing(&bulge), &options);
    assert!(e.contains("arc.dxf: LWPOLYLINE (handle 3F) at line 91: line 103: a bulge"), "{e}");
    let open = [
        (0, "LWPOLYLINE"),
        (8, "0"),
        (70, "0"),
        (10, "2000"),
        (20, "500"),
        (10, "2100"),
        (20, "500"),
        (10, "2100"),
        (20, "600"),
    ];
    let e = error_of(&dir, "open.dxf", &drawing(&open), &options);
    assert!(e.contains("open.dxf: LWPOLYLINE at line 91: the polyline is not closed"), "{e}");
    // A vertex count (90) the vertices do not match: a truncated entity, refused.
    let short = [
        (0, "LWPOLYLINE"),
        (5, "4D"),
        (8, "0"),
        (90, "7"),
        (70, "1"),
        (10, "2000"),
        (20, "500"),
        (10, "2100"),
        (20, "500"),
        (10, "2100"),
        (20, "600"),
    ];
    let e = error_of(&dir, "short.dxf", &drawing(&short), &options);
    assert!(e.contains("handle 4D") && e.contains("vertex count (90) is 7, but the polyline has 3"), "{e}");
}

/// An old-style POLYLINE (handle `h`) of the corners `xy` (drawing units) with its VERTEX
/// entities and, if `end`, its SEQEND; `flags` its group 70, `bulge` a group 42 on its
/// first vertex.
fn old_polyline(
    h: &'static str,
    xy: &[(&'static str, &'static str)],
    flags: &'static str,
    bulge: bool,
    end: bool,
) -> Vec<(i32, &'static str)> {
    let mut p = vec![(0, "POLYLINE"), (5, h), (8, "0"), (66, "1"), (10, "0"), (20, "0"), (30, "0"), (70, flags)];
    for (k, (x, y)) in xy.iter().enumerate() {
        p.extend([(0, "VERTEX"), (8, "0"), (10, *x), (20, *y), (30, "0")]);
        if bulge && k == 0 {
            p.push((42, "1"));
        }
    }
    if end {
        p.extend([(0, "SEQEND"), (8, "0")]);
    }
    p
}

/// A TEXT label at (x, y) drawing units.
fn text(h: &'static str, x: &'static str, y: &'static str, t: &'static str) -> Vec<(i32, &'static str)> {
    vec![(0, "TEXT"), (5, h), (8, "0"), (10, x), (20, y), (30, "0"), (40, "20"), (1, t)]
}

/// An old-style POLYLINE is a stone as an LWPOLYLINE is; a TEXT or MTEXT `depth_m=D` inside
/// a stone's outline is its measured depth (m); every other entity off the IGNORE layer is
/// refused naming its type, handle and line. The drawing (mm, 0.2 m thick): stone 2A
/// (400 × 150 mm) labelled 0.12 m deep is a face stone from the traced face (y = −0.1) to
/// y = 0.02 and a core behind it to y = 0.1; the POLYLINE 5E beside it (x 0.4–0.8 m, z
/// 0–0.15 m) labelled 0.2 m (the thickness) is a through stone of 0.4 × 0.15 × 0.2 m.
#[test]
fn a_dxf_drawing_reads_old_style_polylines_and_depth_labels_and_refuses_anything_else() {
    let dir = Scratch::created("survey-dxf-old");
    let materials = SurveyMaterials {
        materials: vec![material("granite", 2600.0), material("slate", 2700.0)],
        stone_material: None,
        table_material: None,
    };
    let options = ImportOptions { materials, ..traced(0.2, None) };
    let stone = [("1400", "500"), ("1800", "500"), ("1800", "650"), ("1400", "650")];
    let mut extra = old_polyline("5E", &stone, "1", false, true);
    extra.extend(text("6A", "1200", "560", "depth_m=0.12"));
    extra.extend([(0, "MTEXT"), (5, "6B"), (8, "0"), (10, "1600"), (20, "560"), (1, "DEPTH_M = 0.2")]);
    let w = import(&write(&dir, "old.dxf", &drawing(&extra)), &options).unwrap();
    let ids: Vec<&str> = w.layout.blocks.iter().map(|b| b.id.as_str()).collect();
    assert_eq!(ids, ["2A", "2A.core", "2B", "5E"]);
    let y = |id: &str| {
        let b = w.layout.blocks.iter().find(|b| b.id == id).unwrap();
        b.vertices.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v[1]), hi.max(v[1])))
    };
    for (id, (lo, hi)) in [("2A", (-0.1, 0.02)), ("2A.core", (0.02, 0.1)), ("2B", (-0.1, 0.1)), ("5E", (-0.1, 0.1))] {
        let (a, b) = y(id);
        assert!((a - lo).abs() < 1e-12 && (b - hi).abs() < 1e-12, "{id}: y from {a} to {b}");
    }
    let e5 = w.layout.blocks.iter().find(|b| b.id == "5E").unwrap();
    let (x0, x1) =
        e5.vertices.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v[0]), hi.max(v[0])));
    assert!((x0 - 0.4).abs() < 1e-12 && (x1 - 0.8).abs() < 1e-12, "{x0} {x1}");
    let vol = w.stones.iter().find(|s| s.id == "5E").unwrap().block_volume_m3;
    assert!((vol - 0.012).abs() < 1e-15, "{vol}");

    // Refusals, each naming the file, the entity, its handle and a line.
    let refused = |name: &str, extra: Vec<(i32, &'static str)>| error_of(&dir, name, &drawing(&extra), &options);
    let e = refused("line.dxf", vec![(0, "LINE"), (5, "7A"), (8, "0"), (10, "0"), (20, "0"), (11, "1"), (21, "1")]);
    assert!(e.contains("line.dxf: LINE (handle 7A) at line") && e.contains("IGNORE"), "{e}");
    let e = refused("insert.dxf", vec![(0, "INSERT"), (5, "7B"), (8, "0"), (2, "STONE"), (10, "0"), (20, "0")]);
    assert!(e.contains("INSERT (handle 7B)") && e.contains("explode"), "{e}");
    let e = refused("arc.dxf", old_polyline("7C", &stone, "1", true, true));
    assert!(e.contains("POLYLINE (handle 7C) at line") && e.contains("a bulge"), "{e}");
    let e = refused("seqend.dxf", old_polyline("7D", &stone, "1", false, false));
    assert!(e.contains("POLYLINE (handle 7D)") && e.contains("SEQEND"), "{e}");
    let e = refused("spline.dxf", old_polyline("7E", &stone, "5", false, true));
    assert!(e.contains("POLYLINE (handle 7E)") && e.contains("spline"), "{e}");
    let e = refused("open.dxf", old_polyline("7F", &stone, "0", false, true));
    assert!(e.contains("POLYLINE (handle 7F)") && e.contains("not closed"), "{e}");
    let e = refused("outside.dxf", text("80", "5000", "5000", "depth_m=0.1"));
    assert!(e.contains("TEXT (handle 80)") && e.contains("inside no stone"), "{e}");
    let mut twice = text("81", "1100", "560", "depth_m=0.1");
    twice.extend(text("82", "1300", "560", "depth_m=0.15"));
    let e = refused("twice.dxf", twice);
    assert!(e.contains("TEXT (handle 82)") && e.contains("second depth label") && e.contains("handle 81"), "{e}");
    let e = refused("note.dxf", text("83", "1100", "560", "stone 12"));
    assert!(e.contains("TEXT (handle 83)") && e.contains("not a depth label"), "{e}");
    let e = refused("nan.dxf", text("84", "1100", "560", "depth_m=deep"));
    assert!(e.contains("TEXT (handle 84)") && e.contains("not a number of metres"), "{e}");
    let e = refused("thick.dxf", text("85", "1100", "560", "depth_m=0.5"));
    assert!(e.contains("thick.dxf") && e.contains("LWPOLYLINE (handle 2A)") && e.contains("depth 0.5 m"), "{e}");
}

/// The error of importing `text` as `name` with `options`.
fn error_of(dir: &Path, name: &str, text: &str, options: &ImportOptions) -> String {
    import(&write(dir, name, text), options).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn errors_name_the_file_and_the_element() {
    let dir = Scratch::created("survey-errors");
    let t = traced(0.3, Some(0.001));
    let svg = |body: &str| format!("<svg xmlns=\"http://www.w3.org/2000/svg\">\n{body}\n</svg>\n");
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("curve.svg", svg(r#"<path id="p1" d="M0 0 C 10 10 20 10 30 0 Z"/>"#), vec!["curve.svg", "<path id=\"p1\"> at line 2", "curve or arc"]),
        ("open.svg", svg("<rect id=\"r\" width=\"100\" height=\"50\"/>\n<path d=\"M0 0 L 10 0 L 10 10\"/>"), vec!["open.svg", "<path> at line 3", "not closed"]),
        ("circle.svg", svg(r#"<circle id="c" cx="5" cy="5" r="5"/>"#), vec!["circle.svg", "<circle id=\"c\">", "not an outline"]),
        ("bad.svg", svg(r#"<polygon id="q" points="0,0 10,0 10"/>"#), vec!["bad.svg", "<polygon id=\"q\">", "odd number"]),
        ("twice.svg", svg("<rect id=\"a\" width=\"100\" height=\"50\"/>\n<rect id=\"a\" x=\"100\" width=\"100\" height=\"50\"/>"), vec!["twice.svg", "<rect id=\"a\"> at line 3", "<rect id=\"a\"> at line 2"]),
        ("cross.svg", svg("<rect id=\"a\" width=\"100\" height=\"50\"/>\n<rect id=\"b\" x=\"90\" y=\"-10\" width=\"100\" height=\"50\"/>"), vec!["cross.svg", "stones a (<rect id=\"a\"> at line 2) and b (<rect id=\"b\"> at line 3) overlap by 1.000e-2 m"]),
        ("bow.svg", svg(r#"<polygon id="bow" points="0,0 100,100 100,0 0,60"/>"#), vec!["bow.svg", "<polygon id=\"bow\">", "crosses itself"]),
        ("notxml.svg", "<svg><g></svg>".to_string(), vec!["notxml.svg", "not valid XML"]),
        ("skew.svg", svg(r#"<g transform="wobble(2)"><rect id="a" width="100" height="50"/></g>"#), vec!["skew.svg", "<rect id=\"a\">", "unknown transform"]),
    ];
    for (name, text, parts) in &cases {
        let e = error_of(&dir, name, text, &t);
        for p in parts {
            assert!(e.contains(p), "{name}: {p:?} not in {e}");
        }
    }
    let e = error_of(&dir, "mat.svg", &svg(r#"<g data-material="basalt"><rect id="m" width="1" height="1"/></g>"#), &t);
    assert!(
        e.contains("mat.svg: <rect id=\"m\"> at line 2: material \"basalt\" is not among the materials given (stone)"),
        "{e}"
    );
    let e = error_of(&dir, "noscale.svg", &svg(r#"<rect width="1" height="1"/>"#), &traced(0.3, None));
    assert!(e.contains("noscale.svg") && e.contains("no scale"), "{e}");
    let hole = r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "id": 7, "geometry": {"type": "Polygon",
        "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], [[0.2, 0.2], [0.4, 0.2], [0.4, 0.4], [0.2, 0.2]]]}}]}"#;
    let e = error_of(&dir, "hole.geojson", hole, &traced(0.3, None));
    assert!(e.contains("hole.geojson") && e.contains("feature 0 (id \"7\")") && e.contains("holes (1)"), "{e}");
    let line = r#"{"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 0]]}}"#;
    let e = error_of(&dir, "line.geojson", line, &traced(0.3, None));
    assert!(e.contains("line.geojson: feature 0: geometry type \"LineString\""), "{e}");
    let e = error_of(&dir, "face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", &scanned(LengthUnit::M));
    assert!(e.contains("face.obj: line 4") && e.contains("\"x\" is not a vertex index"), "{e}");
    let open: String =
        cube_obj(0.2, [0.0; 3], 0).lines().filter(|l| *l != "f 2 3 7 6").map(|l| format!("{l}\n")).collect();
    let e = error_of(&dir, "open.obj", &open, &scanned(LengthUnit::M));
    // A file of one mesh is its own element: its name once.
    assert!(
        e.contains("open.obj: stone open: the mesh is not closed: 4 edges") && e.matches("open.obj").count() == 1,
        "{e}"
    );
    let e = error_of(&dir, "wall.dwg", "AC1032", &t);
    assert!(e.contains("wall.dwg") && e.contains("unknown survey format"), "{e}");
    let e = error_of(
        &dir,
        "opt.svg",
        &svg(r#"<rect width="1" height="1"/>"#),
        &ImportOptions { unit: Some(LengthUnit::Mm), ..t.clone() },
    );
    assert!(e.contains("--unit") && e.contains("scanned stones"), "{e}");
}

#[test]
fn the_command_writes_a_layout_and_prints_what_it_made() {
    let dir = Scratch::created("survey-cli");
    let svg = write(&dir, "ell.svg", L_SVG);
    let out = dir.join("ell.json");
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_drystone"))
            .arg("import")
            .arg(&svg)
            .arg("--out")
            .arg(&out)
            .args(["--thickness-m", "0.25", "--density", "2200", "--kn", "1e8", "--ks", "5e7", "--friction-deg", "30"])
            .args(extra)
            .output()
            .unwrap()
    };
    let refused = run(&[]);
    assert_eq!(refused.status.code(), Some(2));
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(err.contains("ell.svg") && err.contains("stone ell") && err.contains("--hull-nonconvex"), "{err}");
    assert!(!out.exists());
    let made = run(&["--hull-nonconvex"]);
    let text = String::from_utf8_lossy(&made.stdout);
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    for part in [
        "stones read       2",
        "blocks made       2 (1 convex hulls)",
        "on the table      1 blocks",
        "added by hulls    6.250000e-4 m3",
        "wall height       0.2000 m",
    ] {
        assert!(text.contains(part), "{part:?} not in\n{text}");
    }
    let layout = drystone::layout::Layout::from_file(&out).unwrap();
    assert_eq!(layout.blocks.len(), 2);
}

/// The fixtures of this file, each with its extension and the options it is read with.
fn fixtures() -> Vec<(&'static str, Vec<u8>, ImportOptions)> {
    vec![
        ("svg", L_SVG.as_bytes().to_vec(), traced(0.25, None)),
        ("geojson", STACK.as_bytes().to_vec(), traced(0.3, None)),
        ("obj", cube_obj(200.0, [0.0; 3], 0).into_bytes(), scanned(LengthUnit::Mm)),
        ("stl", ascii_stl(&cube_triangles(150.0)).into_bytes(), scanned(LengthUnit::Mm)),
        ("stl", binary_stl(&cube_triangles(150.0)), scanned(LengthUnit::Mm)),
        ("dxf", drawing(&[]).into_bytes(), traced(0.2, None)),
    ]
}

proptest::proptest! {
    #![proptest_config(proptest::test_runner::Config {
        cases: 150,
        failure_persistence: None,
        rng_seed: crate::common::proptest_seed(),
        ..Default::default()
    })]

    /// Every fixture with a piece cut out and other text (or a hostile number) put in its
    /// place is imported or refused with an error, never a panic.
    #[test]
    fn altered_surveys_are_imported_or_refused_never_a_panic(
        k in 0usize..6,
        at in 0.0f64..1.0,
        cut in 0usize..12,
        insert in "\\PC{0,6}|-?[0-9]{1,3}(\\.[0-9]+)?(e-?[0-9]{1,3})?|NaN|inf|1e999",
    ) {
        let dir = Scratch::created("survey-fuzz");
        let (ext, mut bytes, options) = fixtures().swap_remove(k);
        let i = ((at * bytes.len() as f64) as usize).min(bytes.len());
        let j = (i + cut).min(bytes.len());
        bytes.splice(i..j, insert.bytes());
        let path = dir.join(format!("altered.{ext}"));
        std::fs::write(&path, &bytes).unwrap();
        if let Ok(w) = import(&path, &options) {
            proptest::prop_assert!(w.layout.resolve().is_ok());
        }
    }
}

/// Hostile inputs of the import, each refused naming what is at fault (or read as
/// documented), none as a misleading cause:
/// * a bow tie whose two lobes cancel (zero signed area) is an outline that crosses
///   itself, not one with "no area";
/// * an empty id (SVG `id=""`, GeoJSON `"id": ""`, a DXF handle left empty) is no id: the
///   stone is `s<N>` (it used to pass to the layout, refused there as `blocks[0].id`
///   without the element);
/// * a binary STL of no triangle, and an outline a transform collapses to a point, have
///   no extent, not a "probable unit mistake";
/// * an OBJ face using a vertex that is not there names its line;
/// * a huge scale is printed in scientific notation, not in 301 digits.
#[test]
fn hostile_surveys_are_refused_by_their_real_cause() {
    let dir = Scratch::created("survey-hostile");
    let t = traced(0.3, Some(0.01));
    let svg = |body: &str| format!("<svg xmlns=\"http://www.w3.org/2000/svg\">\n{body}\n</svg>\n");
    let e = error_of(&dir, "tie.svg", &svg(r#"<polygon id="tie" points="0,0 50,0 0,-30 50,-30"/>"#), &t);
    assert!(e.contains("tie.svg: <polygon id=\"tie\"> at line 2: the outline crosses itself"), "{e}");
    let wall = import(&write(&dir, "noid.svg", &svg(r#"<rect id="" width="50" height="30"/>"#)), &t).unwrap();
    assert_eq!(wall.layout.blocks[0].id, "s0");
    let geo = r#"{"type": "Feature", "id": "", "geometry": {"type": "Polygon",
        "coordinates": [[[0, 0], [1, 0], [1, 0.3], [0, 0.3], [0, 0]]]}}"#;
    let wall = import(&write(&dir, "noid.geojson", geo), &traced(0.3, None)).unwrap();
    assert_eq!(wall.layout.blocks[0].id, "s0");
    let mut p: Vec<(i32, &str)> = vec![(0, "SECTION"), (2, "HEADER"), (9, "$INSUNITS"), (70, "4"), (0, "ENDSEC")];
    p.extend([(0, "SECTION"), (2, "ENTITIES"), (0, "LWPOLYLINE"), (5, ""), (8, "0"), (90, "4"), (70, "1")]);
    p.extend([(10, "0"), (20, "0"), (10, "500"), (20, "0"), (10, "500"), (20, "300"), (10, "0"), (20, "300")]);
    p.extend([(0, "ENDSEC"), (0, "EOF")]);
    let wall = import(&write(&dir, "noid.dxf", &dxf(&p)), &traced(0.3, None)).unwrap();
    assert_eq!(wall.layout.blocks[0].id, "s0");
    let path = dir.join("none.stl");
    std::fs::write(&path, binary_stl(&[])).unwrap();
    let e = import(&path, &scanned(LengthUnit::M)).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("none.stl") && e.contains("no triangles") && !e.contains("unit mistake"), "{e}");
    let e = error_of(&dir, "flat.svg", &svg(r#"<rect id="z" width="50" height="30" transform="scale(0)"/>"#), &t);
    assert!(e.contains("flat.svg: <rect id=\"z\"> at line 2") && !e.contains("unit mistake"), "{e}");
    let obj = cube_obj(0.2, [0.0; 3], 0) + "f 1 2 99\n";
    let e = error_of(&dir, "far.obj", &obj, &scanned(LengthUnit::M));
    assert!(e.contains("far.obj") && e.contains("line 15") && e.contains("vertex 99 of 8"), "{e}");
    let geo = r#"{"type": "Feature", "geometry": {"type": "Polygon",
        "coordinates": [[[0, 0], [1, 0], [1, 0.3], [0, 0.3], [0, 0]]]}}"#;
    let e = error_of(&dir, "huge.geojson", geo, &traced(0.3, Some(1e300)));
    assert!(e.contains("1e300 m per unit") && e.len() < 400, "{e}");
}

/// A materials file naming a stone or table material it does not define is refused naming
/// the file and its key (the layout used to name `table.material`, a key of its own); one
/// that cannot be read is named as the materials file (it was called a survey).
#[test]
fn a_materials_file_naming_a_material_it_lacks_is_refused_by_its_key() {
    let dir = Scratch::created("survey-materials-key");
    let m = "[[materials]]\nname = \"g\"\ndensity_kg_per_m3 = 2600\nkn_pa_per_m = 1e9\nks_pa_per_m = 5e8\nfriction_deg = 35\n";
    for key in ["stone_material", "table_material"] {
        let path = write(&dir, "m.toml", &format!("{key} = \"nope\"\n{m}"));
        let e = SurveyMaterials::from_file(&path).map(|_| ()).unwrap_err().to_string();
        assert!(e.contains("m.toml") && e.contains(&format!("{key} = \"nope\" is not among")), "{e}");
    }
    assert!(SurveyMaterials::from_file(&write(&dir, "ok.toml", &format!("stone_material = \"g\"\n{m}"))).is_ok());
    // A materials file that is not there is named as the materials file, not as a survey.
    let e = SurveyMaterials::from_file(&dir.join("nofile.toml")).map(|_| ()).unwrap_err().to_string();
    assert!(
        e.contains("nofile.toml") && e.contains("cannot read the materials file") && !e.contains("read survey"),
        "{e}"
    );
}

/// The drawing's scale and what is drawn, by hand: one scale line (a second refused naming
/// it, one inside `<defs>` not read), a `<use>` clone refused naming it (its stones would be
/// lost), a stone in a hidden layer (`display:none`) not a stone.
#[test]
fn one_drawn_scale_line_no_clones_and_no_hidden_stones() {
    let dir = Scratch::created("survey-svg-drawn");
    let o = traced(0.2, None);
    let scale = "<line id=\"scale\" x1=\"0\" y1=\"0\" x2=\"1000\" y2=\"0\" data-length-m=\"1\"/>";
    let stone = "<rect id=\"a\" x=\"0\" y=\"800\" width=\"500\" height=\"200\"/>";
    let svg = |body: &str| format!("<svg xmlns=\"http://www.w3.org/2000/svg\">\n{body}\n</svg>\n");
    let twice = svg(&format!(
        "{scale}\n<g data-ignore=\"1\"><line id=\"scale\" x1=\"0\" y1=\"0\" x2=\"100\" y2=\"0\" data-length-m=\"1\"/></g>\n{stone}"
    ));
    let e = error_of(&dir, "twice.svg", &twice, &o);
    assert!(e.contains("a second scale line") && e.contains("line 3"), "{e}");
    let defs = svg(&format!(
        "<defs><line id=\"scale\" x1=\"0\" y1=\"0\" x2=\"100\" y2=\"0\" data-length-m=\"1\"/></defs>\n{stone}"
    ));
    assert!(error_of(&dir, "defs.svg", &defs, &o).contains("no scale"));
    let clone = svg(&format!(
        "{scale}\n<defs><rect id=\"p\" x=\"0\" y=\"0\" width=\"500\" height=\"200\"/></defs>\n<use href=\"#p\" y=\"800\"/>\n{stone}"
    ));
    let e = error_of(&dir, "use.svg", &clone, &o);
    assert!(e.contains("<use> at line 4") && e.contains("clone"), "{e}");
    let hidden = svg(&format!(
        "{scale}\n{stone}\n<g style=\"opacity:1; display : none\"><rect id=\"h\" x=\"2000\" y=\"800\" width=\"500\" height=\"200\"/></g>\n\
         <rect id=\"n\" display=\"none\" x=\"3000\" y=\"800\" width=\"500\" height=\"200\"/>"
    ));
    let w = import(&write(&dir, "hidden.svg", &hidden), &o).unwrap();
    assert_eq!(w.layout.blocks.len(), 1);
    assert!((w.length_m - 0.5).abs() < 1e-12);
}

/// A word among a polygon's coordinates (`nan`, `inf`, a unit written after a number) is
/// refused naming the file, the element and the word: read as the list's end it dropped the
/// stone's last corners, and the pentagon below came out as the unit square.
#[test]
fn a_traced_polygon_with_a_word_among_its_points_is_refused_not_cut_short() {
    let dir = Scratch::created("survey-points-word");
    for (name, word) in [("nan.svg", "nan"), ("inf.svg", "inf"), ("unit.svg", "cm")] {
        let points = format!("0,0 10,0 10,10 0,10 {word},5");
        let text = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\">\n<polygon points=\"{points}\"/>\n</svg>\n"
        );
        let svg = write(&dir, name, &text);
        let e = import(&svg, &traced(0.2, Some(0.01))).expect_err(name).to_string();
        for part in [name, "<polygon> at line 2", &format!("{word:?}"), "not a number"] {
            assert!(e.contains(part), "{part:?} not in {e}");
        }
    }
    // The same pentagon written with numbers only is read with its five corners.
    let svg = write(
        &dir,
        "ok.svg",
        "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<polygon points=\"0,0 10,0 10,10 0,10 -5,5\"/>\n</svg>\n",
    );
    let w = import(&svg, &traced(0.2, Some(0.01))).unwrap();
    assert_eq!(w.layout.blocks[0].vertices.len(), 10);
}
