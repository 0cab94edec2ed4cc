//! Large scanned stones: a UV sphere of 20,000 triangles (every vertex a hull vertex) imports
//! with its hull's volume inside the analytic bounds of an inscribed polyhedron, its hull
//! simplified to the vertex budget with the volume it leaves out reported (and refused
//! above the tolerance, naming the file and the stone); a non-convex block is still refused
//! by name; a mesh with a degenerate or a duplicated face is handled as a small one is.
//!
//! The references are closed forms of the sphere and of the mesh written here (its
//! vertices on the sphere, its largest angular edge), never the code under test's.

use crate::common::Scratch;
use drystone::layout::{BlockSpec, LayoutSpec, MaterialSpec, RestraintSpec, TableSpec};
use drystone::survey::{import, ImportOptions, SurveyError, SurveyMaterials, HULL_VOLUME_TOLERANCE};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn stone() -> MaterialSpec {
    MaterialSpec {
        name: "stone".into(),
        density_kg_per_m3: 2600.0,
        kn_pa_per_m: 1e10,
        ks_pa_per_m: 5e9,
        friction_deg: 35.0,
        cohesion_pa: 0.0,
        tensile_strength_pa: 0.0,
        closure: Default::default(),
    }
}

fn options() -> ImportOptions {
    ImportOptions {
        format: None,
        scale_m_per_unit: None,
        section: None,
        hull_nonconvex: false,
        unit: None,
        y_up: false,
        materials: SurveyMaterials::one(stone()),
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

/// A UV sphere of radius `r` centred at (0, 0, r): `n` segments round, `m` rings, poles on
/// the z axis; 2n(m − 1) triangles, outward. Returns the OBJ text and the largest angle
/// (rad) between two corners of one triangle.
fn uv_sphere(n: usize, m: usize, r: f64) -> (String, f64) {
    let mut v = vec![[0.0, 0.0, 1.0]];
    for i in 1..m {
        let th = PI * i as f64 / m as f64;
        for j in 0..n {
            let ph = 2.0 * PI * j as f64 / n as f64;
            v.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        }
    }
    v.push([0.0, 0.0, -1.0]);
    let ring = |i: usize, j: usize| 1 + (i - 1) * n + j % n;
    let mut t: Vec<[usize; 3]> = (0..n).map(|j| [0, ring(1, j), ring(1, j + 1)]).collect();
    for i in 1..m - 1 {
        for j in 0..n {
            let (a, b, c, d) = (ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j));
            t.push([a, d, c]);
            t.push([a, c, b]);
        }
    }
    let bottom = v.len() - 1;
    t.extend((0..n).map(|j| [ring(m - 1, j), bottom, ring(m - 1, j + 1)]));
    let angle = |a: [f64; 3], b: [f64; 3]| (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).clamp(-1.0, 1.0).acos();
    let widest = t
        .iter()
        .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
        .map(|(a, b)| angle(v[a], v[b]))
        .fold(0.0, f64::max);
    let mut obj = String::from("o sphere\n");
    for p in &v {
        obj += &format!("v {:.17e} {:.17e} {:.17e}\n", r * p[0], r * p[1], r + r * p[2]);
    }
    for f in &t {
        obj += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    (obj, widest)
}

/// The volume bounds of a polyhedron inscribed in a sphere of radius `r` whose faces' corners
/// are at most `widest` apart (angle): each face lies in a cap of angular radius `widest`
/// round one of its corners, so the polyhedron holds the ball of radius `r cos(widest)`.
fn inscribed_bounds(r: f64, widest: f64) -> (f64, f64) {
    let ball = |x: f64| 4.0 / 3.0 * PI * x.powi(3);
    (ball(r * widest.cos()), ball(r))
}

/// 100 segments × 101 rings: 20,000 triangles, 9,902 vertices, every one on the hull.
#[test]
fn a_sphere_of_twenty_thousand_triangles_imports_with_its_full_hull_within_the_analytic_bounds() {
    let dir = Scratch::created("large-sphere-full");
    let r = 0.15;
    let (obj, widest) = uv_sphere(100, 101, r);
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 20_000);
    let path = write(&dir, "sphere.obj", &obj);
    let (lo, hi) = inscribed_bounds(r, widest);
    let w = import(&path, &ImportOptions { full_hull: true, ..options() }).unwrap();
    let s = &w.stones[0];
    assert!(s.simplified.is_none());
    assert_eq!(w.layout.blocks[0].vertices.len(), 2 + 100 * 100);
    assert!(lo < s.block_volume_m3 && s.block_volume_m3 <= hi, "{lo} < {} <= {hi}", s.block_volume_m3);
    // The mesh is convex: its own volume is its hull's.
    assert!((s.survey_volume_m3 - s.block_volume_m3).abs() <= 1e-12 * hi, "{s:?}");
    // Every hull vertex is a vertex of the mesh, on the sphere (moved onto the table by the
    // import's offset).
    for v in &w.layout.blocks[0].vertices {
        let c = [w.offset_m[0], w.offset_m[1], r + w.offset_m[2]];
        let d = ((v[0] - c[0]).powi(2) + (v[1] - c[1]).powi(2) + (v[2] - c[2]).powi(2)).sqrt();
        assert!((d - r).abs() < 1e-12, "{v:?} at {d}");
    }
}

/// The default budget simplifies the 9,902-vertex hull and reports what it leaves out; a
/// budget too small for the tolerance is refused naming the file and the stone.
#[test]
fn the_vertex_budget_simplifies_a_large_hull_and_reports_the_volume_it_leaves_out() {
    let dir = Scratch::created("large-sphere-budget");
    let r = 0.15;
    let (obj, widest) = uv_sphere(100, 101, r);
    let path = write(&dir, "sphere.obj", &obj);
    let (lo, hi) = inscribed_bounds(r, widest);
    let w = import(&path, &options()).unwrap();
    let (s, h) = (&w.stones[0], w.stones[0].simplified.expect("simplified to the default budget"));
    let budget = drystone::survey::DEFAULT_MAX_HULL_VERTICES;
    assert_eq!(h.full_vertices, 2 + 100 * 100);
    assert!(h.kept_vertices <= budget && h.kept_vertices == w.layout.blocks[0].vertices.len(), "{h:?}");
    assert!(lo < h.full_volume_m3 && h.full_volume_m3 <= hi, "{lo} < {} <= {hi}", h.full_volume_m3);
    // The reported change is the block's loss against the full hull.
    let change = (h.full_volume_m3 - s.block_volume_m3) / h.full_volume_m3;
    assert!((h.volume_change - change).abs() < 1e-12, "{h:?} {change}");
    // Points spread over a sphere: the hull of N leaves out about √3 π / N (the even
    // triangulation's closed form), and at least that.
    let even = 3f64.sqrt() * PI / h.kept_vertices as f64;
    assert!(0.9 * even < h.volume_change && h.volume_change < 1.5 * even, "{h:?} against {even}");
    assert!(h.volume_change <= HULL_VOLUME_TOLERANCE);
    // The kept vertices are the mesh's own: the block lies inside the sphere.
    for v in &w.layout.blocks[0].vertices {
        let c = [w.offset_m[0], w.offset_m[1], r + w.offset_m[2]];
        let d = ((v[0] - c[0]).powi(2) + (v[1] - c[1]).powi(2) + (v[2] - c[2]).powi(2)).sqrt();
        assert!((d - r).abs() < 1e-12, "{v:?} at {d}");
    }
    // The lowest point stays on the table.
    assert_eq!(w.on_table(), 1);
    // A larger budget leaves out less.
    let finer = import(&path, &ImportOptions { max_hull_vertices: Some(3000), ..options() }).unwrap();
    let hf = finer.stones[0].simplified.unwrap();
    assert!(hf.volume_change < h.volume_change / 2.0, "{hf:?} {h:?}");
    // 100 vertices leave out ≈ 5 %: refused, naming the file, the stone and the way out.
    let e = import(&path, &ImportOptions { max_hull_vertices: Some(100), ..options() }).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, SurveyError::Element { .. }), "{text}");
    for part in ["sphere.obj", "stone sphere", "budget of 100", "--max-hull-vertices", "--full-hull", "1.000 %"] {
        assert!(text.contains(part), "{part}: {text}");
    }
    // A file of one mesh is its own element: its name once.
    assert_eq!(text.matches("sphere.obj").count(), 1, "{text}");
    let lost: f64 = text.split("leaves out ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!(lost > 100.0 * HULL_VOLUME_TOLERANCE && lost < 100.0 * 2.0 * 3f64.sqrt() * PI / 100.0, "{lost}");
    // The budget is for meshes, at least 4, and not with --full-hull.
    let e = import(&path, &ImportOptions { max_hull_vertices: Some(3), ..options() }).unwrap_err().to_string();
    assert!(e.contains("--max-hull-vertices") && e.contains("at least 4"), "{e}");
    let e = import(&path, &ImportOptions { max_hull_vertices: Some(50), full_hull: true, ..options() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("--full-hull"), "{e}");
}

/// A layout block of 2,000 vertices on a sphere and one inside it is refused naming the
/// block and the inner vertex; one on the hull's surface but not a corner too.
#[test]
fn a_large_non_convex_block_is_still_refused_by_name() {
    let golden = PI * (3.0 - 5f64.sqrt());
    let on_sphere: Vec<[f64; 3]> = (0..2000)
        .map(|k| {
            // A Fibonacci sphere of radius 0.2 about (0, 0, 0.2): its points are all corners.
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / 2000.0;
            let (s, a) = ((1.0 - z * z).sqrt(), golden * k as f64);
            [0.2 * s * a.cos(), 0.2 * s * a.sin(), 0.2 + 0.2 * z]
        })
        .collect();
    let layout = |vertices: Vec<[f64; 3]>| LayoutSpec {
        version: drystone::layout::LAYOUT_VERSION,
        name: "large".into(),
        gravity_m_per_s2: 9.81,
        materials: vec![stone()],
        table: TableSpec { material: "stone".into() },
        blocks: vec![BlockSpec {
            id: "boulder".into(),
            material: "stone".into(),
            vertices,
            fixed: false,
            course: None,
            wedge: false,
            own_mass: None,
            bed_closure: None,
        }],
        restraints: RestraintSpec::default(),
        monitors: vec![],
        joint_families: Default::default(),
    };
    let mut lowest = on_sphere.clone();
    let bottom = (0..2000).min_by(|&a, &b| on_sphere[a][2].total_cmp(&on_sphere[b][2])).unwrap();
    lowest[bottom][2] = 0.0;
    assert!(layout(lowest.clone()).resolve().is_ok());
    let mut inner = lowest.clone();
    inner.insert(1234, [0.0, 0.0, 0.2]);
    let e = layout(inner).resolve().map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("boulder") && e.contains("not convex") && e.contains("1234"), "{e}");
    // The midpoint of two neighbouring corners lies on the hull (within a chord's sag) but
    // is no corner.
    let mut flat = lowest;
    let (a, b) = (flat[0], flat[1]);
    flat.push([(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0]);
    let e = layout(flat).resolve().map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("boulder") && e.contains("2000"), "{e}");
}

/// A cube mesh with a degenerate triangle (two corners the same) imports as the cube; one
/// with a face given twice is refused naming the stone.
#[test]
fn a_mesh_with_a_degenerate_or_a_duplicate_face_is_handled_as_before() {
    let dir = Scratch::created("large-degenerate-face");
    let cube =
        "o rock\nv 0 0 0\nv 0.2 0 0\nv 0.2 0.2 0\nv 0 0.2 0\nv 0 0 0.2\nv 0.2 0 0.2\nv 0.2 0.2 0.2\nv 0 0.2 0.2\n\
                f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";
    let w = import(&write(&dir, "degenerate.obj", &format!("{cube}f 1 1 2\n")), &options()).unwrap();
    assert!((w.stones[0].block_volume_m3 - 0.008).abs() < 1e-15, "{:?}", w.stones[0]);
    assert!((w.stones[0].survey_volume_m3 - 0.008).abs() < 1e-15, "{:?}", w.stones[0]);
    assert_eq!(w.layout.blocks[0].vertices.len(), 8);
    let e = import(&write(&dir, "twice.obj", &format!("{cube}f 1 4 3 2\n")), &options()).unwrap_err().to_string();
    assert!(
        e.contains("twice.obj")
            && e.contains("object \"rock\"")
            && e.contains("stone twice")
            && e.contains("same direction"),
        "{e}"
    );
}

/// A study's scanned group takes the budget in `[groups.import]`: a budget too small for
/// the tolerance is refused when the study is read, naming the group's survey, the stone and
/// the keys; `full_hull` keeps the full hull; both together, a budget below 4, or either on
/// a traced elevation are refused naming the key.
#[test]
fn a_study_group_of_scanned_stones_takes_the_vertex_budget_in_its_import_table() {
    use drystone::study::Study;
    let dir = Scratch::created("large-sphere-study");
    let (obj, _) = uv_sphere(40, 41, 0.15);
    let sphere = write(&dir, "ball.obj", &obj);
    let study = |name: &str, survey: &Path, extra: &str| {
        let text = format!(
            "version = 1\nname = \"{name}\"\nseed = 3\nrealizations = 1\nprotocol = \"tilt\"\n[solver]\nkind = \
             \"limit\"\n[[groups]]\nname = \"ball\"\nsurvey = {:?}\n[groups.import]\ndensity = 2600\nkn = 1e10\n\
             ks = 5e9\nfriction_deg = 35\n{extra}",
            survey.display().to_string()
        );
        write(&dir, &format!("{name}.toml"), &text)
    };
    // 1,602 hull vertices: simplified to the default 1,000 within the tolerance.
    let blocks = |s: &Study| {
        let (_, layout) = drystone::effects::realize(&s.groups[0].walls[0], 3, 0, "ball", &[]).unwrap();
        layout.blocks[0].shape.vertices.len()
    };
    let s = Study::from_file(&study("default", &sphere, "")).unwrap();
    assert_eq!(blocks(&s), drystone::survey::DEFAULT_MAX_HULL_VERTICES);
    let s = Study::from_file(&study("full", &sphere, "full_hull = true\n")).unwrap();
    assert_eq!(blocks(&s), 2 + 40 * 40);
    let e = Study::from_file(&study("small", &sphere, "max_hull_vertices = 60\n")).unwrap_err().to_string();
    for part in ["groups[ball].survey", "ball.obj", "stone ball", "import.max_hull_vertices", "import.full_hull"] {
        assert!(e.contains(part), "{part}: {e}");
    }
    for (extra, want) in [
        ("max_hull_vertices = 3\n", "at least 4"),
        ("max_hull_vertices = 500\nfull_hull = true\n", "exclude each other"),
    ] {
        let e = Study::from_file(&study("bad", &sphere, extra)).unwrap_err().to_string();
        assert!(e.contains("groups[ball].import.max_hull_vertices") && e.contains(want), "{e}");
    }
    let svg = write(
        &dir,
        "one.svg",
        "<svg xmlns=\"http://www.w3.org/2000/svg\"><rect id=\"s\" x=\"0\" y=\"0\" width=\"1\" height=\"1\"/></svg>",
    );
    let e = Study::from_file(&study("traced", &svg, "full_hull = true\n")).unwrap_err().to_string();
    assert!(e.contains("groups[ball].import.full_hull") && e.contains("scanned stones"), "{e}");
}
