//! Invariants of generated walls over many seeds (property tests): every block convex (it
//! resolves into a `ConvexBlock`, which rejects non-convex vertex lists), no two blocks
//! overlapping (the DEM's own narrow phase, `geometry::sat::separation`), the
//! volume within 1 % of the envelope volume × (1 − stated void fraction), every vertex inside
//! the section envelope, the base course on the table.

use drystone::generator::spec::SectionSpec;
use drystone::generator::spec::{
    ArrangementKind, ArrangementSpec, Batter, BlocksSpec, CoursesSpec, DistRef, EndKind, EndsSpec, GeometrySpec,
    HeadJointsSpec, RestraintsSpec, WallSpec,
};
use drystone::generator::{
    generate, DistributionSource, DistributionSpec, GeneratedWall, HeadGap, PieceKind, Section, SectionPart, Wall,
};
use drystone::geometry::sat::separation;
use drystone::geometry::sweep::sweep_pairs;
use drystone::layout::{BaseSliding, MaterialSpec};
use proptest::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn preset(name: &str) -> Wall {
    Wall::from_file(&root().join("studies/walls").join(format!("{name}.toml"))).unwrap()
}

/// Checks every invariant; returns a description of the first violation.
fn check_invariants(wall: &Wall, g: &GeneratedWall) -> Result<(), String> {
    let layout = g.layout.resolve().map_err(|e| format!("layout does not resolve: {e}"))?;
    let (l, h) = (wall.length, wall.height);
    let tol = 1e-9 * (l + h);
    // Inside the envelope.
    for b in &layout.blocks {
        for v in &b.shape.vertices {
            let (y0, y1) = wall.faces_at(v.z);
            if v.x < -tol || v.x > l + tol || v.z < -tol || v.z > h + tol || v.y < y0 - tol || v.y > y1 + tol {
                return Err(format!("block {} vertex {v:?} outside the envelope", b.id));
            }
        }
    }
    // No overlap, by the DEM narrow phase (stricter than the layout's 1e-5 m tolerance).
    let boxes: Vec<_> = layout.blocks.iter().map(|b| b.shape.aabb()).collect();
    for (i, j) in sweep_pairs(&boxes, 0.0) {
        let s = separation(&layout.blocks[i].shape, &layout.blocks[j].shape);
        if s.distance < -1e-8 {
            return Err(format!(
                "blocks {} and {} overlap by {:e} m",
                layout.blocks[i].id, layout.blocks[j].id, -s.distance
            ));
        }
    }
    // Volume: the hulls' volumes against the envelope × (1 − f) for a stated void fraction
    // f, within 1 % (thin wedge gaps below the minimum wedge thickness stay empty). Wedges
    // fill each stone's slot out to the middle of its open head joints, so an open joint
    // adds only its own width, even under steep beds.
    let vol: f64 = layout.blocks.iter().map(|b| b.shape.volume()).sum();
    let target = wall.envelope_volume() * (1.0 - wall.stated_void_fraction());
    if vol > target * 1.01 || vol < target * 0.99 {
        return Err(format!("volume {vol} vs {target} ({:+.3} %)", 100.0 * (vol / target - 1.0)));
    }
    if (vol - g.volume()).abs() > 1e-9 * target {
        return Err(format!("hull volume {vol} != analytic volume {}", g.volume()));
    }
    // Base course on the table: course 0 stones start at z = 0, nothing is below.
    let zmin = layout.blocks.iter().flat_map(|b| b.shape.vertices.iter().map(|v| v.z)).fold(f64::INFINITY, f64::min);
    if zmin != 0.0 && zmin.abs() > 1e-15 {
        return Err(format!("lowest vertex at z = {zmin}"));
    }
    for p in g.pieces.iter().filter(|p| p.course == 0) {
        if p.kind != PieceKind::Stone || p.polygon.iter().map(|q| q[1]).fold(f64::INFINITY, f64::min) != 0.0 {
            return Err(format!("base-course block {} is not a stone standing on the table", p.id));
        }
    }
    // Course 0 covers the whole length but for the open head joints (counted once across
    // the section: the through stones and the −y leaf).
    let column = |p: &&drystone::generator::Piece| matches!(p.part, SectionPart::Through | SectionPart::NegativeLeaf);
    let base_len: f64 = g
        .pieces
        .iter()
        .filter(|p| p.course == 0)
        .filter(column)
        .map(|p| {
            let xs = p.polygon.iter().map(|q| q[0]);
            xs.clone().fold(f64::NEG_INFINITY, f64::max) - xs.fold(f64::INFINITY, f64::min)
        })
        .sum();
    let n_base = g.pieces.iter().filter(|p| p.course == 0).filter(column).count() as f64;
    let micro = match wall.head_gap {
        HeadGap::Width(w) => w * (n_base - 1.0),
        _ => 0.0,
    };
    if base_len > l + tol || base_len < (1.0 - 2.0 * wall.stated_void_fraction()) * l - micro - 1e-9 * l {
        return Err(format!("base course covers {base_len} m of {l} m"));
    }
    Ok(())
}

/// `cases` cases (or `DRYSTONE_PROPTEST_CASES` for a longer soak), no regression files.
fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("DRYSTONE_PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(cases);
    ProptestConfig {
        cases,
        failure_persistence: None,
        rng_seed: crate::common::proptest_seed(),
        ..ProptestConfig::default()
    }
}

fn run(name: &str, seed: u64, realization: u64) -> Result<(), TestCaseError> {
    let w = preset(name);
    let g = generate(&w, seed, realization).map_err(|e| TestCaseError::fail(format!("{name}: {e}")))?;
    check_invariants(&w, &g)
        .map_err(|e| TestCaseError::fail(format!("{name} seed {seed} realization {realization}: {e}")))
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn sbl_walls_satisfy_the_invariants(seed in any::<u64>(), r in 0u64..1_000_000) {
        run("sbl", seed, r)?;
    }

    #[test]
    fn sbr_walls_satisfy_the_invariants(seed in any::<u64>(), r in 0u64..1_000_000) {
        run("sbr", seed, r)?;
    }

    #[test]
    fn full_scale_irregular_walls_satisfy_the_invariants(seed in any::<u64>(), r in 0u64..1_000_000) {
        run("full_scale", seed, r)?;
    }
}

#[test]
fn regular_presets_satisfy_the_invariants() {
    for name in ["cbl", "full_scale_continuous", "full_scale_discontinuous"] {
        run(name, 1, 0).unwrap();
    }
}

/// A wall description with the given parameters (one material, default keys elsewhere).
#[allow(clippy::too_many_arguments)]
fn spec(
    dims: [f64; 4],
    batter: Batter,
    kind: ArrangementKind,
    course: DistRef,
    block: DistRef,
    dip_max: f64,
    head: HeadJointsSpec,
    inline: BTreeMap<String, DistributionSpec>,
) -> WallSpec {
    WallSpec {
        version: 1,
        name: "property".into(),
        description: String::new(),
        kind: None,
        gravity_m_per_s2: 9.81,
        geometry: GeometrySpec {
            length_m: dims[0],
            height_m: dims[1],
            base_width_m: dims[2],
            top_width_m: dims[3],
            batter,
        },
        arrangement: ArrangementSpec {
            kind,
            overlap: None,
            dip_deg: (kind == ArrangementKind::Irregular).then(|| DistRef::Name("dip".into())),
            min_wedge_thickness_m: None,
            min_wedge_length_m: None,
            wedge_length_m: None,
            wedge_fill: None,
        },
        courses: CoursesSpec { height_m: course, min_thickness_fraction: None },
        blocks: BlocksSpec { length_m: block, min_end_fraction: None, material: None, wedge_material: None },
        head_joints: head,
        section: None,
        materials: vec![MaterialSpec {
            name: "m".into(),
            density_kg_per_m3: 2200.0,
            kn_pa_per_m: 5e7,
            ks_pa_per_m: 2.5e7,
            friction_deg: 35.0,
            cohesion_pa: 0.0,
            tensile_strength_pa: 0.0,
            closure: Default::default(),
        }],
        restraints: RestraintsSpec {
            base: BaseSliding::Held,
            table_material: None,
            ends: EndsSpec { kind: EndKind::Free, zone_m: None, stiffness_n_per_m: None },
        },
        joints: Default::default(),
        scatter: None,
        distributions: {
            let mut m = inline;
            if kind == ArrangementKind::Irregular {
                m.insert(
                    "dip".into(),
                    DistributionSpec::from_toml(
                        &format!("unit = \"deg\"\nkind = \"uniform\"\nmin = {}\nmax = {}", -dip_max, dip_max.max(1e-3)),
                        Path::new("inline"),
                    )
                    .unwrap(),
                );
            }
            m
        },
    }
}

fn uniform_m(lo: f64, hi: f64) -> DistributionSpec {
    DistributionSpec::from_toml(
        &format!("unit = \"m\"\nkind = \"uniform\"\nmin = {lo}\nmax = {hi}"),
        Path::new("inline"),
    )
    .unwrap()
}

proptest! {
    #![proptest_config(config(96))]

    /// Random envelopes, block sizes, dips, batters and open head joints.
    #[test]
    fn random_walls_satisfy_the_invariants(
        seed in any::<u64>(),
        l in 0.6f64..6.0,
        h in 0.2f64..2.0,
        bw in 0.1f64..0.8,
        taper in 0.3f64..1.0,
        batter in prop_oneof![Just(Batter::Symmetric), Just(Batter::VerticalNegativeY), Just(Batter::VerticalPositiveY)],
        kind in prop_oneof![Just(ArrangementKind::Continuous), Just(ArrangementKind::Discontinuous), Just(ArrangementKind::Irregular)],
        courses in 3usize..12,
        aspect in 1.0f64..4.0,
        spread in 0.0f64..0.3,
        dip_max in 0.0f64..25.0,
        head in prop_oneof![
            Just(HeadJointsSpec::default()),
            (0.0f64..0.03).prop_map(|f| HeadJointsSpec { micro_gap_m: None, void_fraction: Some(f) }),
            (0.0f64..0.002).prop_map(|w| HeadJointsSpec { micro_gap_m: Some(w), void_fraction: None }),
        ],
    ) {
        let hbar = h / courses as f64;
        // Block length: `aspect` course heights, at most half the wall.
        let lbar = (aspect * hbar).min(0.5 * l);
        let (course, block, inline) = if kind == ArrangementKind::Irregular && spread > 0.01 {
            let mut m = BTreeMap::new();
            m.insert("ch".to_string(), uniform_m(hbar * (1.0 - spread), hbar * (1.0 + spread)));
            m.insert("bl".to_string(), uniform_m(lbar * (1.0 - spread), lbar * (1.0 + spread)));
            (DistRef::Name("ch".into()), DistRef::Name("bl".into()), m)
        } else {
            (DistRef::Value(hbar), DistRef::Value(lbar), BTreeMap::new())
        };
        // Keep the gaps small against the blocks (a micro-gap, not a missing block).
        let head = match head {
            HeadJointsSpec { micro_gap_m: Some(w), .. } => HeadJointsSpec { micro_gap_m: Some(w.min(0.005 * lbar)), void_fraction: None },
            other => other,
        };
        let s = spec([l, h, bw, bw * taper], batter, kind, course, block, dip_max, head, inline);
        let p = Path::new("property.toml");
        let w = s.resolve(p, &DistributionSource::default()).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let g = generate(&w, seed, 0).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        check_invariants(&w, &g).map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}\n{}", s.to_toml())))?;
    }
}

proptest! {
    #![proptest_config(config(32))]

    /// Double-faced sections: two leaves meeting at the centre line or with hearting (cut
    /// into pieces or not), with or without through stones, on random envelopes, batters
    /// and arrangements.
    #[test]
    fn double_faced_walls_satisfy_the_invariants(
        seed in any::<u64>(),
        l in 0.6f64..5.0,
        h in 0.2f64..1.6,
        bw in 0.15f64..0.7,
        taper in 0.4f64..1.0,
        batter in prop_oneof![Just(Batter::Symmetric), Just(Batter::VerticalNegativeY), Just(Batter::VerticalPositiveY)],
        kind in prop_oneof![Just(ArrangementKind::Continuous), Just(ArrangementKind::Discontinuous), Just(ArrangementKind::Irregular)],
        courses in 3usize..8,
        aspect in 1.0f64..3.0,
        dip_max in 0.0f64..20.0,
        leaf in prop_oneof![Just(None), (0.1f64..0.45).prop_map(Some)],
        hearting in prop_oneof![Just(None), (0.2f64..1.5).prop_map(Some)],
        through in prop_oneof![Just(None), (0.3f64..2.0, 1u32..3).prop_map(Some)],
    ) {
        let hbar = h / courses as f64;
        let lbar = (aspect * hbar).min(0.5 * l);
        let top = bw * taper;
        let mut s = spec([l, h, bw, top], batter, kind, DistRef::Value(hbar), DistRef::Value(lbar), dip_max,
            HeadJointsSpec::default(), BTreeMap::new());
        s.section = Some(SectionSpec {
            leaves: 2,
            leaf_width_m: leaf.map(|f| f * top),
            hearting_stone_m: leaf.and(hearting.map(|f| f * lbar)),
            through_stone_spacing_m: through.map(|(f, _)| f * l),
            through_stone_every_courses: through.map(|(_, n)| n),
        });
        let p = Path::new("property.toml");
        let w = s.resolve(p, &DistributionSource::default()).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let g = generate(&w, seed, 0).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        check_invariants(&w, &g).map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}\n{}", s.to_toml())))?;
        check_leaves(&w, &g).map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}\n{}", s.to_toml())))?;
    }
}

/// Each leaf follows its own face: every vertex of a −y (+y) leaf block lies on the −y
/// (+y) face or on the plane `leaf_width` inside it (the centre line without hearting);
/// hearting vertices lie on the two inner planes; the elevation of every course is covered
/// the same way in each leaf.
fn check_leaves(wall: &Wall, g: &GeneratedWall) -> Result<(), String> {
    let Section::Double { leaf_width, .. } = wall.section else { return Err("not double-faced".into()) };
    let tol = 1e-12 * (wall.length + wall.height);
    for p in &g.pieces {
        for v in &p.vertices {
            let (y0, y1) = wall.faces_at(v[2]);
            let (ni, pi) = match leaf_width {
                Some(w) => (y0 + w, y1 - w),
                None => (0.5 * (y0 + y1), 0.5 * (y0 + y1)),
            };
            let on = |ys: [f64; 2]| ys.iter().any(|y| (v[1] - y).abs() <= tol);
            let ok = match p.part {
                SectionPart::Through => on([y0, y1]),
                SectionPart::NegativeLeaf => on([y0, ni]),
                SectionPart::Hearting => on([ni, pi]),
                SectionPart::PositiveLeaf => on([pi, y1]),
            };
            if !ok {
                return Err(format!("block {} ({:?}) has a vertex {v:?} off its leaf's planes", p.id, p.part));
            }
        }
    }
    let area = |part: SectionPart| -> f64 {
        g.pieces
            .iter()
            .filter(|p| p.part == part || p.part == SectionPart::Through)
            .map(|p| {
                let n = p.polygon.len();
                0.5 * (0..n)
                    .map(|i| {
                        let (a, b) = (p.polygon[i], p.polygon[(i + 1) % n]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum::<f64>()
            })
            .sum()
    };
    let (an, ap) = (area(SectionPart::NegativeLeaf), area(SectionPart::PositiveLeaf));
    if (an - ap).abs() > 1e-9 * an {
        return Err(format!("the leaves' elevations differ: {an} vs {ap} m2"));
    }
    if leaf_width.is_some() && (area(SectionPart::Hearting) - an).abs() > 1e-9 * an {
        return Err(format!(
            "the hearting's elevation differs from the leaves': {} vs {an} m2",
            area(SectionPart::Hearting)
        ));
    }
    Ok(())
}

#[test]
fn a_double_faced_wall_has_its_leaves_hearting_and_through_stones() {
    let path = root().join("studies/walls/full_scale_continuous.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let src = DistributionSource::dir(root().join("distributions"));
    let single = preset("full_scale_continuous");
    // An explicit single leaf is the default, bit for bit.
    let one = format!("{text}\n[section]\nleaves = 1\n");
    let one = WallSpec::from_toml(&one, &path).unwrap().resolve(&path, &src).unwrap();
    assert_eq!(
        serde_json::to_string(&generate(&one, 5, 2).unwrap().layout).unwrap(),
        serde_json::to_string(&generate(&single, 5, 2).unwrap().layout).unwrap()
    );
    // Two leaves 0.1 m wide, hearting in pieces of at most 0.2 m, through stones every 1 m
    // in every other course.
    let two = format!(
        "{text}\n[section]\nleaves = 2\nleaf_width_m = 0.1\nhearting_stone_m = 0.2\n\
         through_stone_spacing_m = 1.0\nthrough_stone_every_courses = 2\n"
    );
    let two = WallSpec::from_toml(&two, &path).unwrap().resolve(&path, &src).unwrap();
    let (g1, g2) = (generate(&single, 5, 2).unwrap(), generate(&two, 5, 2).unwrap());
    check_invariants(&two, &g2).unwrap();
    check_leaves(&two, &g2).unwrap();
    // The same elevation: 5 courses of 8 stones 0.5 m long. Courses 0, 2, 4 hold through
    // stones over x = 0.5, 1.5, 2.5, 3.5 (courses 0 and 4) or 1, 2, 3 (course 2); every
    // other stone is cut into two leaves and three hearting pieces of 0.5/3 m.
    assert_eq!(g1.counts(), (40, 0));
    let through: Vec<(usize, usize)> = g2
        .pieces
        .iter()
        .filter(|p| p.part == SectionPart::Through)
        .map(|p| (p.course, (p.polygon.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min) / 0.5).round() as usize))
        .collect();
    let expected: Vec<(usize, usize)> = [0, 2, 4]
        .iter()
        .flat_map(|&k| if k == 2 { vec![(k, 2), (k, 4), (k, 6)] } else { vec![(k, 1), (k, 3), (k, 5), (k, 7)] })
        .collect();
    assert_eq!(through, expected);
    let cut = 40 - expected.len();
    assert_eq!(g2.counts().0, expected.len() + cut * 5);
    assert!(g2.pieces.iter().filter(|p| p.part == SectionPart::Hearting).all(|p| {
        let xs = p.polygon.iter().map(|q| q[0]);
        (xs.clone().fold(f64::NEG_INFINITY, f64::max) - xs.fold(f64::INFINITY, f64::min) - 0.5 / 3.0).abs() < 1e-12
    }));
    // Volumes: the whole envelope, and each leaf 0.1 m × the elevation.
    assert!((g2.volume() - single.envelope_volume()).abs() < 1e-12 * single.envelope_volume());
    let leaf: f64 = g2.pieces.iter().filter(|p| p.part == SectionPart::PositiveLeaf).map(|p| p.volume).sum();
    assert!((leaf - 0.1 * 4.0 * 1.0 * cut as f64 / 40.0).abs() < 1e-12, "{leaf}");
}

#[test]
fn bad_sections_are_refused_with_their_key() {
    let path = root().join("studies/walls/full_scale_continuous.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let src = DistributionSource::dir(root().join("distributions"));
    for (section, key) in [
        ("leaves = 3", "section.leaves"),
        ("leaves = 1\nleaf_width_m = 0.1", "section.leaf_width_m"),
        ("leaves = 2\nleaf_width_m = 0.125", "section.leaf_width_m"),
        ("leaves = 2\nleaf_width_m = -0.1", "section.leaf_width_m"),
        ("leaves = 2\nhearting_stone_m = 0.2", "section.hearting_stone_m"),
        ("leaves = 2\nthrough_stone_every_courses = 2", "section.through_stone_every_courses"),
        (
            "leaves = 2\nthrough_stone_spacing_m = 1.0\nthrough_stone_every_courses = 0",
            "section.through_stone_every_courses",
        ),
        ("leaves = 2\nthrough_stone_spacing_m = 0", "section.through_stone_spacing_m"),
    ] {
        let t = format!("{text}\n[section]\n{section}\n");
        let e = WallSpec::from_toml(&t, &path).unwrap().resolve(&path, &src).unwrap_err().to_string();
        assert!(e.contains(key) && e.contains("full_scale_continuous.toml"), "{section}: {e}");
    }
}

#[test]
fn end_restraints_hold_exactly_the_blocks_near_the_ends() {
    use drystone::generator::Ends;
    use drystone::layout::EndRestraintKind;
    let path = root().join("studies/walls/sbr.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let spring = text.replace(
        "ends = { kind = \"rigid\", zone_m = 0.05 }",
        "ends = { kind = \"spring\", zone_m = 0.05, stiffness_n_per_m = 2.0e5 }",
    );
    let src = DistributionSource::dir(root().join("distributions"));
    let walls = [
        preset("sbr"),
        preset("full_scale"),
        WallSpec::from_toml(&spring, &path).unwrap().resolve(&path, &src).unwrap(),
    ];
    for w in &walls {
        for r in 0..5 {
            let g = generate(w, 3, r).unwrap();
            let (zone, kind, k) = match w.ends {
                Ends::Rigid { zone } => (zone, EndRestraintKind::Rigid, None),
                Ends::Spring { zone, stiffness } => (zone, EndRestraintKind::Spring, Some(stiffness)),
                Ends::Free => unreachable!(),
            };
            let expected: Vec<&str> = g
                .pieces
                .iter()
                .filter(|p| p.polygon.iter().any(|q| q[0] < zone || q[0] > w.length - zone))
                .map(|p| p.id.as_str())
                .collect();
            assert!(expected.len() >= 2 * g.course_tops_m.len(), "{}: {expected:?}", w.name);
            let ends = &g.layout.restraints.ends;
            assert_eq!(ends.len(), 1);
            assert_eq!(ends[0].kind, kind);
            assert_eq!(ends[0].stiffness_n_per_m, k);
            assert_eq!(ends[0].blocks, expected);
            let layout = g.check().unwrap();
            assert_eq!(layout.end_restraints.len(), expected.len());
        }
    }
    // Free ends restrain nothing; the base restraint is passed through.
    let g = generate(&preset("sbl"), 3, 0).unwrap();
    assert!(g.layout.restraints.ends.is_empty());
    assert_eq!(g.layout.restraints.base_sliding, BaseSliding::Held);
}

#[test]
fn wedge_lengths_cut_long_gaps_into_several_wedges() {
    let path = root().join("studies/walls/full_scale.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("min_wedge_length_m = 0.025\n", "min_wedge_length_m = 0.025\nwedge_length_m = 0.12\n");
    let src = DistributionSource::dir(root().join("distributions"));
    let cut = WallSpec::from_toml(&text, &path).unwrap().resolve(&path, &src).unwrap();
    let whole = preset("full_scale");
    for r in 0..10 {
        let (g, h) = (generate(&cut, 8, r).unwrap(), generate(&whole, 8, r).unwrap());
        check_invariants(&cut, &g).unwrap();
        assert!(g.counts().1 > h.counts().1, "realization {r}: {:?} vs {:?}", g.counts(), h.counts());
        for p in g.pieces.iter().filter(|p| p.kind == PieceKind::Wedge) {
            let xs = p.polygon.iter().map(|q| q[0]);
            let len = xs.clone().fold(f64::NEG_INFINITY, f64::max) - xs.fold(f64::INFINITY, f64::min);
            assert!(len < 0.12 + 0.025 + 1e-9, "wedge {} is {len} m long", p.id);
        }
        // The base course has no wedges and is drawn before any wedge cut: it is the same.
        let s0 = |w: &drystone::generator::GeneratedWall| {
            w.pieces.iter().filter(|p| p.course == 0).map(|p| p.polygon.clone()).collect::<Vec<_>>()
        };
        assert_eq!(s0(&g), s0(&h));
    }
}

#[test]
fn wedge_fill_keeps_about_that_fraction_of_the_gaps() {
    let path = root().join("studies/walls/full_scale.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("min_wedge_length_m = 0.025\n", "min_wedge_length_m = 0.025\nwedge_fill = 0.5\n");
    let src = DistributionSource::dir(root().join("distributions"));
    let half = WallSpec::from_toml(&text, &path).unwrap().resolve(&path, &src).unwrap();
    let full = preset("full_scale");
    let (mut n_half, mut n_full) = (0usize, 0usize);
    for r in 0..200 {
        let g = generate(&half, 4, r).unwrap();
        n_half += g.counts().1;
        n_full += generate(&full, 4, r).unwrap().counts().1;
        // Still convex, inside, without overlaps; only the volume is short by the empty gaps.
        if r < 10 {
            g.layout.resolve().unwrap();
            assert!(g.volume() <= half.envelope_volume() * (1.0 + 1e-12));
        }
    }
    let ratio = n_half as f64 / n_full as f64;
    assert!((ratio - 0.5).abs() < 0.05, "{n_half} / {n_full} = {ratio}");
}

/// Regression (found by `random_walls_satisfy_the_invariants`, seed 5950876065677564813): in
/// a thin irregular wall with steep dips a stone's bed rose above its course's ceiling, so
/// the stone was cut short while the wedge under that bed was not; the next course, resting
/// only on stone tops, overlapped the wedge by up to 4 mm. Wedges now share their stone's
/// ceiling, and wedge tops beyond the stone carry the next course.
#[test]
fn wedges_under_a_stone_cut_by_the_course_ceiling_stay_below_the_next_course() {
    let (bmin, bmax) = (0.05848410288448281, 0.09583405242764714);
    let spread = (bmax - bmin) / (bmax + bmin);
    let hbar = 0.2 / 10.0;
    for dip_max in [24.3, 24.8, 25.0] {
        let mut inline = BTreeMap::new();
        inline.insert("ch".to_string(), uniform_m(hbar * (1.0 - spread), hbar * (1.0 + spread)));
        inline.insert("bl".to_string(), uniform_m(bmin, bmax));
        let s = spec(
            [2.850231464327328, 0.2, 0.1, 0.03],
            Batter::Symmetric,
            ArrangementKind::Irregular,
            DistRef::Name("ch".into()),
            DistRef::Name("bl".into()),
            dip_max,
            HeadJointsSpec::default(),
            inline,
        );
        let w = s.resolve(Path::new("regression.toml"), &DistributionSource::default()).unwrap();
        let g = generate(&w, 5950876065677564813, 0).unwrap();
        check_invariants(&w, &g).unwrap_or_else(|e| panic!("dip ±{dip_max}°: {e}"));
    }
}

/// A stated head-joint void fraction f is the realized one in irregular walls with steep
/// dips, fine (SBL stones, about 15 per course) and coarse (0.3 m stones, 5 per course): the
/// realized void is f plus the thin wedge gaps left open (below the minimum wedge thickness),
/// never f again. Before the wedges filled each stone's slot out to the middle of its open
/// head joints, an open joint reached down to the course below under its neighbours' steep
/// beds, and the realized void came out up to about 2f.
#[test]
fn a_stated_void_fraction_is_the_realized_void_under_steep_beds() {
    let path = root().join("studies/walls/sbl.toml");
    let sbl = std::fs::read_to_string(&path).unwrap();
    let src = DistributionSource::dir(root().join("distributions"));
    let f = 0.03;
    let with_voids = |text: &str| {
        let text = text.replace("\"dip_uniform_10\"", "\"dip_uniform_20\"")
            + &format!("\n[head_joints]\nvoid_fraction = {f}\n");
        WallSpec::from_toml(&text, &path).unwrap().resolve(&path, &src).unwrap()
    };
    let closed = |text: &str| {
        let text = text.replace("\"dip_uniform_10\"", "\"dip_uniform_20\"");
        WallSpec::from_toml(&text, &path).unwrap().resolve(&path, &src).unwrap()
    };
    let coarse = sbl.replace("length_m = \"block_length_sbl\"", "length_m = 0.3");
    for (name, text) in [("fine", sbl.as_str()), ("coarse", coarse.as_str())] {
        let (open_wall, closed_wall) = (with_voids(text), closed(text));
        let mut worst: f64 = 0.0;
        for r in 0..20 {
            let g = generate(&open_wall, 11, r).unwrap();
            // The thin gaps a closed wall of the same law leaves open bound the rest.
            let thin = generate(&closed_wall, 11, r).unwrap().void_fraction();
            let excess = g.void_fraction() - f;
            worst = worst.max(excess);
            assert!(excess > -1e-9, "{name} r{r}: realized void {} below the stated {f}", g.void_fraction());
            assert!(
                excess < thin.max(0.0) + 0.005,
                "{name} r{r}: realized void {:.4} against the stated {f} (thin gaps of the closed wall {thin:.4})",
                g.void_fraction()
            );
        }
        println!("{name}: largest excess void over the stated {f}: {worst:.4}");
    }
}

/// A case the property above once drew (a double-faced irregular wall of 28.6 mm courses
/// and stones with leaves 22.4 mm wide): sliver wedges whose hull the leaves kept and the
/// hearting dropped, so the hearting's elevation came 5.8e-6 m² short of the leaves'. A
/// wedge is now kept or dropped through the whole section.
#[test]
fn a_sliver_wedge_is_kept_or_dropped_through_the_whole_section() {
    let dir = crate::common::Scratch::new("sliver-wedge");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("wall.toml");
    std::fs::write(&path, SLIVER_CASE).unwrap();
    let w = drystone::generator::Wall::from_file(&path).unwrap();
    let g = generate(&w, 5240284217772058972, 0).unwrap();
    check_invariants(&w, &g).unwrap();
    check_leaves(&w, &g).unwrap();
}

const SLIVER_CASE: &str = r#"
version = 1
name = "property"
gravity_m_per_s2 = 9.81

[geometry]
length_m = 1.1047570210993758
height_m = 0.2
base_width_m = 0.5598072189629594
top_width_m = 0.22392288758518375
batter = "symmetric"

[arrangement]
kind = "irregular"
dip_deg = "dip"

[courses]
height_m = 0.028571428571428574

[blocks]
length_m = 0.028571428571428574

[head_joints]

[section]
leaves = 2
leaf_width_m = 0.022392288758518376

[[materials]]
name = "m"
density_kg_per_m3 = 2200.0
kn_pa_per_m = 50000000.0
ks_pa_per_m = 25000000.0
friction_deg = 35.0
cohesion_pa = 0.0
tensile_strength_pa = 0.0

[restraints]
base = "held"

[restraints.ends]
kind = "free"

[distributions.dip]
unit = "deg"
kind = "uniform"
min = -7.160043558826364
max = 7.160043558826364
"#;
