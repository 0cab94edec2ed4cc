//! The ensemble around a survey: the tracing tolerance and the stones' depths drawn per
//! realization (`drystone import --seed`, `survey::surveyed_wall`, a study's `survey`
//! group).

use drystone::generator::distribution::Unit;
use drystone::generator::spec::Batter;
use drystone::generator::{generate, generate_batch, Distribution, GeneratedWall, SectionPart, Wall};
use drystone::layout::{LayoutSpec, MaterialSpec};
use drystone::survey::{import, surveyed_wall, ImportOptions, Section, SurveyMaterials, Uncertainty};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::Scratch;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The generated wall's elevation as an SVG drawing in metres, y down, one polygon per
/// stone.
fn export_svg(g: &GeneratedWall) -> String {
    let mut s = String::from("<svg xmlns=\"http://www.w3.org/2000/svg\">\n");
    for p in &g.pieces {
        let list: Vec<String> = p.polygon.iter().map(|q| format!("{},{}", q[0], -q[1])).collect();
        s += &format!("  <polygon id=\"{}\" points=\"{}\"/>\n", p.id, list.join(" "));
    }
    s + "</svg>\n"
}

/// A generated wall (a preset of studies/walls at `seed`, realization 0) traced in SVG, and
/// the options it is imported with.
fn surveyed(dir: &Path, file: &str, seed: u64) -> (PathBuf, ImportOptions) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let wall = Wall::from_file(&root.join(file)).unwrap();
    let g = generate(&wall, seed, 0).unwrap();
    let name = Path::new(file).file_stem().unwrap().to_string_lossy().to_string();
    let svg = write(dir, &format!("{name}.svg"), &export_svg(&g));
    let options = ImportOptions {
        format: None,
        scale_m_per_unit: Some(1.0),
        section: Some(Section { base_m: wall.base_width, top_m: wall.top_width, batter: wall.batter }),
        hull_nonconvex: false,
        unit: None,
        y_up: false,
        materials: SurveyMaterials {
            materials: g.layout.materials.clone(),
            stone_material: None,
            table_material: None,
        },
        base_sliding: Default::default(),
        name: None,
        max_hull_vertices: None,
        full_hull: false,
    };
    (svg, options)
}

/// A small running-bond wall traced in SVG: 18 stones 0.15 × 0.05 m, 0.12 m thick.
fn small(dir: &Path) -> (PathBuf, ImportOptions) {
    let text = "version = 1\nname = \"small\"\n[geometry]\nlength_m = 0.6\nheight_m = 0.2\nbase_width_m = 0.12\n\
                top_width_m = 0.12\n[arrangement]\nkind = \"discontinuous\"\n[courses]\nheight_m = 0.05\n[blocks]\n\
                length_m = 0.15\nmaterial = \"stone\"\n[[materials]]\nname = \"stone\"\ndensity_kg_per_m3 = 2200\n\
                kn_pa_per_m = 1e8\nks_pa_per_m = 5e7\nfriction_deg = 30\n";
    let p = write(dir, "small.toml", text);
    let wall = Wall::from_file(&p).unwrap();
    let g = generate(&wall, 1, 0).unwrap();
    let svg = write(dir, "small.svg", &export_svg(&g));
    let options = ImportOptions {
        format: None,
        scale_m_per_unit: Some(1.0),
        section: Some(Section { base_m: 0.12, top_m: 0.12, batter: Batter::Symmetric }),
        hull_nonconvex: false,
        unit: None,
        y_up: false,
        materials: SurveyMaterials::one(MaterialSpec { ..g.layout.materials[0].clone() }),
        base_sliding: Default::default(),
        name: None,
        max_hull_vertices: None,
        full_hull: false,
    };
    (svg, options)
}

fn json(l: &LayoutSpec) -> String {
    serde_json::to_string(&l.blocks).unwrap()
}

/// The penetration depth of two convex polygons (the least overlap of their projections on
/// their edges' normals), m: an independent check of the layout's own.
fn penetration(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    let mut depth = f64::INFINITY;
    for poly in [p, q] {
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let n = [b[1] - a[1], a[0] - b[0]];
            let len = n[0].hypot(n[1]);
            let proj = |s: &[[f64; 2]]| {
                s.iter()
                    .map(|v| (v[0] * n[0] + v[1] * n[1]) / len)
                    .fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x), h.max(x)))
            };
            let ((p0, p1), (q0, q1)) = (proj(p), proj(q));
            depth = depth.min(p1.min(q1) - p0.max(q0));
        }
    }
    depth
}

#[test]
fn without_tolerance_and_at_full_depth_the_ensemble_is_the_survey_as_traced() {
    let dir = Scratch::created("survey-ensemble-traced");
    let (svg, options) = surveyed(&dir, "studies/walls/sbl.toml", 3);
    let traced = import(&svg, &options).unwrap();
    let thickness = options.section.unwrap().base_m;
    for u in
        [Uncertainty::default(), Uncertainty { tolerance_m: 0.0, depth: Some(Distribution::fixed(thickness, Unit::M)) }]
    {
        let wall = surveyed_wall(&svg, &options, &u).unwrap();
        for r in [0, 5] {
            let g = generate(&wall, 11, r).unwrap();
            assert_eq!(json(&g.layout), json(&traced.layout), "{u:?} realization {r}");
        }
    }
}

#[test]
fn every_realization_is_apart_within_the_tolerance_and_repeats_bit_for_bit() {
    let dir = Scratch::created("survey-ensemble-draws");
    for (svg, options, t) in [
        {
            let (s, o) = small(&dir);
            (s, o, 0.004)
        },
        {
            let (s, o) = surveyed(&dir, "studies/walls/sbl.toml", 3);
            (s, o, 0.002)
        },
    ] {
        let traced = import(&svg, &options).unwrap();
        let wall = surveyed_wall(&svg, &options, &Uncertainty { tolerance_m: t, depth: None }).unwrap();
        let trace = wall.traced.as_deref().unwrap();
        let (mut per_corner, mut largest) = (0, 0.0f64);
        let batch = generate_batch(&wall, 42, 0..8);
        for r in 0..8u64 {
            let (g, report) = drystone::generator::traced::generate(&wall, trace, 42, r).unwrap();
            // The same realization alone, in a batch on the thread pool, and again.
            let again = generate(&wall, 42, r).unwrap();
            assert_eq!(json(&g.layout), json(&again.layout));
            assert_eq!(json(&g.layout), json(&batch[r as usize].as_ref().unwrap().layout));
            // The layout's own check (convex blocks, no overlap beyond 1e-5 m) and an
            // independent one on the drawn outlines.
            g.check().unwrap_or_else(|e| panic!("{}: realization {r}: {e}", svg.display()));
            for i in 0..g.pieces.len() {
                for j in i + 1..g.pieces.len() {
                    let d = penetration(&g.pieces[i].polygon, &g.pieces[j].polygon);
                    assert!(d <= 1e-5, "realization {r}: {} and {} overlap by {d}", g.pieces[i].id, g.pieces[j].id);
                }
            }
            // Every corner within the tolerance of its traced place.
            let mut max = 0.0f64;
            for (p, s) in g.pieces.iter().zip(&trace.stones) {
                assert_eq!(p.id, s.id);
                for (a, b) in p.polygon.iter().zip(&s.polygon) {
                    max = max.max((a[0] - b[0]).hypot(a[1] - b[1]));
                }
            }
            assert!(max <= t * (1.0 + 1e-9), "realization {r}: a corner moved {max} m > {t} m");
            assert!((max - report.max_displacement_m).abs() < 1e-15);
            largest = largest.max(max);
            per_corner += usize::from(!report.affine);
            assert_ne!(json(&g.layout), json(&traced.layout), "realization {r} is the trace");
        }
        assert!(largest > 0.5 * t, "{}: the largest move {largest} m is far below {t} m", svg.display());
        // Every realization drawn corner by corner (none left to the affine fallback),
        // the irregular wall with its wedges too.
        assert_eq!(per_corner, 8, "{}: {per_corner} of 8 draws moved the corners", svg.display());
        let (a, b) = (&batch[0].as_ref().unwrap().layout, &batch[1].as_ref().unwrap().layout);
        assert_ne!(json(a), json(b));
    }
}

#[test]
fn drawn_depths_make_face_stones_with_a_core_behind_within_the_section() {
    let dir = Scratch::created("survey-ensemble-depth");
    let (svg, options) = small(&dir);
    let u = Uncertainty { tolerance_m: 0.0, depth: Some(Distribution::uniform("d", 0.04, 0.09, Unit::M)) };
    let wall = surveyed_wall(&svg, &options, &u).unwrap();
    let g = generate(&wall, 9, 2).unwrap();
    g.check().unwrap();
    let faces: Vec<_> = g.pieces.iter().filter(|p| p.part == SectionPart::NegativeLeaf).collect();
    let cores: Vec<_> = g.pieces.iter().filter(|p| p.part == SectionPart::Hearting).collect();
    assert_eq!((faces.len(), cores.len()), (18, 18));
    let mut depths = Vec::new();
    for (f, c) in faces.iter().zip(&cores) {
        assert_eq!(c.id, format!("{}.core", f.id));
        let y = |p: &drystone::generator::Piece| {
            p.vertices.iter().fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(v[1]), h.max(v[1])))
        };
        let ((f0, f1), (c0, c1)) = (y(f), y(c));
        assert!((f0 + 0.06).abs() < 1e-12 && (c1 - 0.06).abs() < 1e-12 && (f1 - c0).abs() < 1e-12);
        depths.push(f1 - f0);
        let n = f.polygon.len();
        let area: f64 = (0..n)
            .map(|k| {
                let (p, q) = (f.polygon[k], f.polygon[(k + 1) % n]);
                0.5 * (p[0] * q[1] - q[0] * p[1])
            })
            .sum();
        assert!((f.volume + c.volume - area * 0.12).abs() < 1e-12, "{}", f.id);
    }
    assert!(depths.iter().all(|d| (0.04..0.09).contains(d)), "{depths:?}");
    assert!(depths.windows(2).any(|w| w[0] != w[1]));
}

#[test]
fn bad_uncertainty_is_refused_naming_the_option() {
    let dir = Scratch::created("survey-ensemble-bad");
    let (svg, options) = small(&dir);
    let err = |u: Uncertainty| surveyed_wall(&svg, &options, &u).unwrap_err().to_string();
    for t in [-0.001, f64::NAN, f64::INFINITY, 0.5] {
        let e = err(Uncertainty { tolerance_m: t, depth: None });
        assert!(e.contains("--tolerance-m") && e.contains("tracing tolerance"), "{t}: {e}");
    }
    for (d, what) in [
        (Distribution::uniform("deep", 0.05, 0.2, Unit::M), "within (0, 0.12]"),
        (Distribution::fixed(0.0, Unit::M), "within (0, 0.12]"),
        (Distribution::fixed(0.05, Unit::Deg), "metres"),
    ] {
        let e = err(Uncertainty { tolerance_m: 0.0, depth: Some(d) });
        assert!(e.contains("--depth-m") && e.contains(what), "{e}");
    }
    let e = surveyed_wall(&dir.join("missing.svg"), &options, &Uncertainty::default()).unwrap_err().to_string();
    assert!(e.contains("missing.svg"), "{e}");
    let normal = Uncertainty::depth_from_toml(
        &toml::Value::Table("kind = \"normal\"\nmean = 0.05\nstd = 0.01".parse::<toml::Table>().unwrap()),
        Path::new("s.toml"),
        "groups[a].import.depth_m",
    )
    .unwrap();
    let e = err(Uncertainty { tolerance_m: 0.0, depth: Some(normal) });
    assert!(e.contains("unbounded"), "{e}");
}

#[test]
fn the_command_writes_a_realization_that_repeats_and_refuses_a_tolerance_without_a_seed() {
    let dir = Scratch::created("survey-ensemble-cli");
    let (svg, _) = small(&dir);
    let run = |out: &str, extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_drystone"))
            .arg("import")
            .arg(&svg)
            .arg("--out")
            .arg(dir.join(out))
            .args(["--scale-m-per-unit", "1", "--thickness-m", "0.12", "--density", "2200"])
            .args(["--kn", "1e8", "--ks", "5e7", "--friction-deg", "30"])
            .args(extra)
            .output()
            .unwrap()
    };
    let draw = ["--seed", "5", "--realization", "2", "--tolerance-m", "0.003", "--depth-m", "0.05..0.1"];
    for out in ["a.json", "b.json"] {
        let o = run(out, &draw);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("seed, realization 5, 2") && text.contains("outlines drawn"), "{text}");
    }
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    assert_eq!(read("a.json"), read("b.json"));
    let o = run("c.json", &["--seed", "5", "--realization", "3", "--tolerance-m", "0.003"]);
    assert!(o.status.success());
    assert_ne!(read("a.json"), read("c.json"));
    drystone::layout::Layout::from_file(&dir.join("c.json")).unwrap();
    let o = run("d.json", &["--tolerance-m", "0.003"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--seed"));
    let o = run("e.json", &["--seed", "1", "--tolerance-m=-1"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--tolerance-m"));
    let o = run("f.json", &["--seed", "1", "--depth-m", "0.2"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--depth-m"), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A study of the small traced wall: group `traced` as traced, group `drawn` with the
/// tracing tolerance `t` m (and `extra` lines in its import table).
fn survey_study(dir: &Path, name: &str, solver: &str, t: f64, extra: &str) -> PathBuf {
    let import = "scale_m_per_unit = 1.0\nthickness_m = 0.12\ndensity = 2200\nkn = 1e8\nks = 5e7\nfriction_deg = 30\n";
    let text = format!(
        "version = 1\nname = \"{name}\"\nseed = 5\nrealizations = 4\nprotocol = \"tilt\"\n[tilt]\nstep_deg = 1.0\n\
         resolution_deg = 0.03125\n[solver]\nkind = \"{solver}\"\n\
         [[groups]]\nname = \"traced\"\nsurvey = \"small.svg\"\n[groups.import]\n{import}\
         [[groups]]\nname = \"drawn\"\nsurvey = \"small.svg\"\n[groups.import]\n{import}tolerance_m = {t}\n{extra}"
    );
    write(dir, &format!("{name}.toml"), &text)
}

/// The collapse angles of a study's group, in realization order.
fn angles(rows: &[drystone::ensemble::row::RealizationRow], group: &str) -> Vec<f64> {
    rows.iter()
        .filter(|r| r.group == group)
        .map(|r| r.collapse.collapse_angle_deg.unwrap_or_else(|| panic!("{group} r{}: {}", r.realization, r.error)))
        .collect()
}

fn cov(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0)).sqrt() / m
}

#[test]
fn a_study_of_a_survey_scatters_with_the_tolerance_by_the_dem_and_by_limit_analysis() {
    use drystone::ensemble::Shard;
    use drystone::study::{run_study, Study};
    let dir = Scratch::created("survey-ensemble-study");
    let (svg, options) = small(&dir);
    let traced = import(&svg, &options).unwrap().layout.resolve().unwrap();
    for (name, solver) in [("by_dem", "penalty"), ("by_limit", "limit")] {
        let study = Study::from_file(&survey_study(&dir, name, solver, 0.006, "")).unwrap();
        let rows = run_study(&study, Shard::ALL);
        let (a, b) = (angles(&rows, "traced"), angles(&rows, "drawn"));
        assert_eq!((a.len(), b.len()), (4, 4));
        // As traced: every realization the traced wall.
        assert!(a.iter().all(|x| *x == a[0]), "{name}: {a:?}");
        if solver == "limit" {
            let p = drystone::limit::LimitParams::default();
            let r = drystone::limit::limit_tilt(&traced, &drystone::dem::SolverParams::default(), &p).unwrap();
            assert!((a[0] - r.collapse_angle_deg.unwrap()).abs() < 1e-9, "{name}: {} vs {r:?}", a[0]);
        }
        // Drawn: the angles scatter.
        let c = cov(&b);
        assert!(c > 0.0, "{name}: {b:?}");
        println!("{name}: traced {:.4}°, drawn {b:?} (COV {c:.4})", a[0]);
    }
}

#[test]
fn bad_survey_groups_are_refused_naming_the_group_and_key() {
    use drystone::study::Study;
    let dir = Scratch::created("survey-ensemble-study-bad");
    let _ = small(&dir);
    let walls = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls/cbl.toml");
    let e = |text: &str| {
        let p = write(&dir, "bad.toml", text);
        Study::from_file(&p).unwrap_err().to_string()
    };
    let head = "version = 1\nname = \"bad\"\nseed = 1\nrealizations = 2\nprotocol = \"tilt\"\n";
    let import = "[groups.import]\nthickness_m = 0.12\nscale_m_per_unit = 1\ndensity = 2200\nkn = 1e8\nks = 5e7\nfriction_deg = 30\n";
    let both = e(&format!(
        "{head}[[groups]]\nname = \"g\"\nwall = {:?}\nsurvey = \"small.svg\"\n{import}",
        walls.display().to_string()
    ));
    assert!(both.contains("groups[g]") && both.contains("both"), "{both}");
    let neither = e(&format!("{head}[[groups]]\nname = \"g\"\n"));
    assert!(neither.contains("groups[g]") && neither.contains("survey"), "{neither}");
    let missing = e(&format!("{head}[[groups]]\nname = \"g\"\nsurvey = \"missing.svg\"\n{import}"));
    assert!(missing.contains("groups[g].survey") && missing.contains("missing.svg"), "{missing}");
    let negative =
        e(&format!("{head}[[groups]]\nname = \"g\"\nsurvey = \"small.svg\"\n{import}tolerance_m = -0.001\n"));
    assert!(negative.contains("groups[g].import.tolerance_m"), "{negative}");
    let nan = e(&format!("{head}[[groups]]\nname = \"g\"\nsurvey = \"small.svg\"\n{import}tolerance_m = nan\n"));
    assert!(nan.contains("groups[g].import.tolerance_m"), "{nan}");
    let deep = e(&format!(
        "{head}[[groups]]\nname = \"g\"\nsurvey = \"small.svg\"\n{import}depth_m = {{ kind = \"uniform\", min = 0.1, max = 0.3 }}\n"
    ));
    assert!(deep.contains("groups[g].import.depth_m") && deep.contains("(0, 0.12]"), "{deep}");
    let no_thickness =
        e(&format!("{head}[[groups]]\nname = \"g\"\nsurvey = \"small.svg\"\n[groups.import]\ndensity = 1\n"));
    assert!(no_thickness.contains("groups[g].import.thickness_m"), "{no_thickness}");
    let swept = e(&format!(
        "{head}[sweep]\nfriction_deg = [30, 35]\n[[groups]]\nname = \"g\"\nsurvey = \"small.svg\"\n{import}"
    ));
    assert!(swept.contains("sweep.friction_deg") && swept.contains("group g"), "{swept}");
}

/// The y extent of a block of a layout, m.
fn y_extent(l: &LayoutSpec, id: &str) -> (f64, f64) {
    let b = l.blocks.iter().find(|b| b.id == id).unwrap_or_else(|| panic!("no block {id}"));
    b.vertices.iter().fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v[1]), hi.max(v[1])))
}

/// Depths measured per stone (SVG `data-depth-m` on the stone or a group around it, GeoJSON
/// property `depth_m`), written here by hand: as traced, a stone of a measured depth is
/// its face stone to that depth and the core behind it (worked out by hand: a 0.5 m section
/// centred on y = 0, so the face at −0.25 m); a depth that leaves no core is a through
/// stone; in the ensemble a measured stone keeps its depth in every realization and the
/// other stones draw the depths they draw without the measurement (common random numbers);
/// a depth out of (0, thickness] or not a number is refused naming the element.
#[test]
fn measured_depths_are_kept_in_every_realization_and_leave_the_others_draws() {
    let dir = Scratch::created("survey-measured-depth");
    let svg = |a: &str| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<line id=\"scale\" x1=\"0\" y1=\"0\" x2=\"1000\" y2=\"0\" \
             data-length-m=\"1\"/>\n<rect id=\"a\" x=\"0\" y=\"200\" width=\"400\" height=\"200\"{a}/>\n<rect \
             id=\"b\" x=\"400\" y=\"200\" width=\"400\" height=\"200\"/>\n<g data-depth-m=\"0.498\"><rect id=\"c\" \
             x=\"200\" y=\"0\" width=\"400\" height=\"200\"/></g>\n</svg>\n"
        )
    };
    let options = ImportOptions {
        format: None,
        scale_m_per_unit: None,
        section: Some(Section::uniform(0.5)),
        hull_nonconvex: false,
        unit: None,
        y_up: false,
        materials: SurveyMaterials::one(MaterialSpec {
            name: "stone".into(),
            density_kg_per_m3: 2600.0,
            kn_pa_per_m: 1e9,
            ks_pa_per_m: 5e8,
            friction_deg: 35.0,
            cohesion_pa: 0.0,
            tensile_strength_pa: 0.0,
            closure: Default::default(),
        }),
        base_sliding: Default::default(),
        name: None,
        max_hull_vertices: None,
        full_hull: false,
    };
    let measured = write(&dir, "measured.svg", &svg(" data-depth-m=\"0.2\""));
    let w = import(&measured, &options).unwrap();
    let ids: Vec<&str> = w.layout.blocks.iter().map(|b| b.id.as_str()).collect();
    assert_eq!(ids, ["a", "a.core", "b", "c"], "c's 0.498 m leaves 2 mm, less than a core");
    let close = |(p, q): (f64, f64), (r, s): (f64, f64)| (p - r).abs() < 1e-12 && (q - s).abs() < 1e-12;
    assert!(close(y_extent(&w.layout, "a"), (-0.25, -0.05)));
    assert!(close(y_extent(&w.layout, "a.core"), (-0.05, 0.25)));
    assert!(close(y_extent(&w.layout, "b"), (-0.25, 0.25)));
    assert!((w.volume_m3() - 3.0 * 0.4 * 0.2 * 0.5).abs() < 1e-12);
    // The same survey in GeoJSON, the depth a feature's property.
    let geojson = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"id": "a", "depth_m": 0.2}, "geometry": {"type": "Polygon",
         "coordinates": [[[0, 0], [0.4, 0], [0.4, 0.2], [0, 0.2], [0, 0]]]}},
        {"type": "Feature", "properties": {"id": "b"}, "geometry": {"type": "Polygon",
         "coordinates": [[[0.4, 0], [0.8, 0], [0.8, 0.2], [0.4, 0.2], [0.4, 0]]]}}]}"#;
    let gj =
        import(&write(&dir, "a.geojson", geojson), &ImportOptions { scale_m_per_unit: Some(1.0), ..options.clone() })
            .unwrap();
    assert!(close(y_extent(&gj.layout, "a"), (-0.25, -0.05)));
    assert!(close(y_extent(&gj.layout, "a.core"), (-0.05, 0.25)));
    // The ensemble: a's depth is its measured one; b's and c's draws are those of the survey
    // without the measurement.
    let plain = write(&dir, "plain.svg", &svg(""));
    let u = Uncertainty { tolerance_m: 0.0, depth: Some(Distribution::uniform("d", 0.1, 0.4, Unit::M)) };
    let (with, without) =
        (surveyed_wall(&measured, &options, &u).unwrap(), surveyed_wall(&plain, &options, &u).unwrap());
    for r in 0..4 {
        let (gw, go) = (generate(&with, 11, r).unwrap(), generate(&without, 11, r).unwrap());
        let (lw, lo) = (gw.layout.clone(), go.layout.clone());
        assert!(close(y_extent(&lw, "a"), (-0.25, -0.05)), "realization {r}");
        assert_ne!(y_extent(&lo, "a"), y_extent(&lw, "a"));
        assert_eq!(y_extent(&lw, "b"), y_extent(&lo, "b"), "realization {r}");
        assert!(y_extent(&lw, "c").1 == 0.25 && lw.blocks.iter().all(|b| b.id != "c.core"));
    }
    // Refusals, naming the element.
    for (attr, why) in [
        (" data-depth-m=\"0.7\"", "(0, 0.5]"),
        (" data-depth-m=\"0\"", "(0, 0.5]"),
        (" data-depth-m=\"x\"", "not a number"),
    ] {
        let p = write(&dir, "bad.svg", &svg(attr));
        let e = import(&p, &options).unwrap_err().to_string();
        assert!(e.contains("<rect id=\"a\">") && e.contains(why), "{attr}: {e}");
    }
}
