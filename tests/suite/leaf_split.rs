//! The `leaf_split` effect against statics. A rigid wall of width b and height H on the
//! tilting table, cut into two leaves tied only by friction, the loose (+y, downhill) leaf
//! taking the share f < ½ of the width: nothing holds the loose leaf back when it tips
//! (its collar joint opens), so it overturns alone, at its own rigid-stack angle
//! `tan α = f b / H` (SPEC §6, the rectangle `tan α = b/h`; a stack of equal rectangles is
//! critical at its lowest joint), the weaker leaf's; the wider uphill leaf stands longer.
//! That is the rigid statics with no force on the collar joint; in the DEM the uphill leaf
//! leans elastically (it rocks a little on its bed under the tilt) and its compatible
//! contact presses the loose leaf's top, so the loose leaf tips up to 0.5° earlier (the
//! lone rigid block of the same size tips within 0.1° of its closed form): the closed form
//! is the upper end of the check.
//! Two equal leaves (f = ½) reach their angle together: the uphill one then leans on the
//! loose one and the friction on the collar joint (where the loose leaf's side rises past
//! the other's) holds it back a little, so the wall collapses between the leaf's angle and
//! the whole section's `tan α = b/H` (statically indeterminate: no closed form). Through
//! stones (left whole every n stones) tie the leaves: the collapse then lies between the
//! loose leaf's angle and the whole section's too.

use drystone::dem::SolverParams;
use drystone::effects::{Effect, EffectDef, Library, ParamDef, Scale, Stage, Step};
use drystone::geometry::sat::separation;
use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::verify::{box_vertices, layout_of, RIGID_KN};
use std::sync::Arc;

/// `courses` courses of `stones` rectangular stones (x length 0.15 m each), width `b`,
/// total height `h`, aligned columns; the course index set on every block.
fn stack(b: f64, h: f64, courses: usize, stones: usize) -> Layout {
    stack_k(b, h, courses, stones, RIGID_KN, RIGID_KN / 2.0)
}

fn stack_k(b: f64, h: f64, courses: usize, stones: usize, kn: f64, ks: f64) -> Layout {
    let hc = h / courses as f64;
    let mut blocks = Vec::new();
    for k in 0..courses {
        for i in 0..stones {
            let x = 0.15 * i as f64;
            blocks.push(box_vertices([x, -b / 2.0, k as f64 * hc], [x + 0.15, b / 2.0, (k + 1) as f64 * hc]));
        }
    }
    let mut layout = layout_of(blocks, kn, ks, 35.0, BaseSliding::Held);
    for (j, blk) in layout.blocks.iter_mut().enumerate() {
        blk.course = Some(j / stones);
    }
    layout
}

fn split(layout: &mut Layout, f: f64, through_every: Option<u32>) {
    let def = EffectDef {
        name: "split".into(),
        description: "two leaves".into(),
        source: "test".into(),
        parameters: vec![ParamDef {
            name: "f".into(),
            unit: "-".into(),
            min: 0.0,
            max: 0.5,
            scale: Scale::Linear,
            neutral: 0.0,
            range_per_course_height: false,
            source: "test".into(),
            kinds: vec![],
        }],
        steps: vec![Step::LeafSplit { parameter: "f".into(), through_stone_every: through_every }],
    };
    let e = Effect::new(Arc::new(def), vec![f], 0.05).unwrap();
    let mut rng = drystone::effects::effect_rng(1, 0, "g", "split");
    e.apply_stage(Stage::Layout, layout, &[], &mut rng).unwrap();
}

fn collapse(layout: &Layout) -> f64 {
    let t = run_tilt(layout, SolverParams::default(), &TiltParams { resolution_deg: 0.0625, ..TiltParams::default() })
        .expect("stands at 0");
    assert!(t.first_unstable_deg.is_some(), "collapses");
    t.collapse_angle_deg()
}

fn deg(t: f64) -> f64 {
    t.atan().to_degrees()
}

#[test]
fn a_loose_leaf_overturns_at_its_own_rigid_angle() {
    let (b, h) = (0.1, 0.3);
    let whole = stack(b, h, 1, 1);
    let alone = collapse(&whole);
    assert!((alone - deg(b / h)).abs() < 0.25, "whole: {alone} against {}", deg(b / h));
    for (courses, f) in [(1, 0.3), (1, 0.4)] {
        let mut l = stack(b, h, courses, 1);
        split(&mut l, f, None);
        assert_eq!(l.blocks.len(), 2 * courses);
        let got = collapse(&l);
        let want = deg(f * b / h);
        eprintln!("{courses} course(s), f {f}: simulated {got:.4} deg, loose leaf {want:.4} deg");
        assert!(got < want + 0.25 && got > want - 0.5, "{courses} course(s), f {f}: {got} against {want}");
    }
    let mut l = stack(b, h, 1, 1);
    split(&mut l, 0.5, None);
    let got = collapse(&l);
    eprintln!("equal leaves: simulated {got:.4} deg (leaf {:.4}, whole {:.4})", deg(0.5 * b / h), deg(b / h));
    assert!(got > deg(0.5 * b / h) + 0.25 && got < deg(b / h), "equal leaves: {got}");
}

#[test]
fn through_stones_put_the_collapse_between_the_leaf_and_the_whole_section() {
    let (b, h) = (0.1, 0.3);
    let mut l = stack(b, h, 2, 4);
    split(&mut l, 0.5, Some(2));
    // Two through stones per course, staggered: 4 + 2 × 2 cut stones → 12 blocks.
    assert_eq!(l.blocks.len(), 12);
    let ids: Vec<&str> = l.blocks.iter().map(|b| b.id.as_str()).collect();
    assert_eq!(&ids[..8], &["b0", "b1n", "b2", "b3n", "b4n", "b5", "b6n", "b7"]);
    let got = collapse(&l);
    let (leaf, whole) = (deg(0.5 * b / h), deg(b / h));
    eprintln!("through stones every 2: {got:.4} deg (leaf {leaf:.4}, whole {whole:.4})");
    assert!(got > leaf + 0.5 && got < whole + 0.25, "{got} not between {leaf} and {whole}");
}

#[test]
fn a_split_generated_wall_keeps_its_volume_convex_blocks_and_no_overlap() {
    use drystone::generator::{generate, Wall};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (name, through) in [("cbl", None), ("sbr", Some(3))] {
        let wall = Wall::from_file(&root.join("studies/walls").join(format!("{name}.toml"))).unwrap();
        let g = generate(&wall, 7, 1).unwrap();
        let before = g.check().unwrap();
        let mut after = before.clone();
        split(&mut after, 0.4, through);
        let vol = |l: &Layout| l.blocks.iter().map(|b| b.shape.volume()).sum::<f64>();
        assert!((vol(&after) - vol(&before)).abs() < 1e-9 * vol(&before), "{name}: volume");
        assert!(after.blocks.len() > before.blocks.len());
        assert_eq!(
            after.end_restraints.len() - before.end_restraints.len(),
            after
                .blocks
                .iter()
                .filter(|b| b.id.ends_with('p')
                    && before.end_restraints.iter().any(|(i, _)| format!("{}p", before.blocks[*i].id) == b.id))
                .count()
        );
        // The +y part of every cut block takes 0.4 of the width at its height: its
        // vertices lie on the +y face or on the cut surface.
        for (i, a) in after.blocks.iter().enumerate() {
            for c in after.blocks.iter().skip(i + 1) {
                let s = separation(&a.shape, &c.shape);
                assert!(s.distance > -1e-8, "{name}: {} and {} overlap by {}", a.id, c.id, -s.distance);
            }
        }
        let p_vol: f64 = after.blocks.iter().filter(|b| b.id.ends_with('p')).map(|b| b.shape.volume()).sum();
        let n_vol: f64 = after.blocks.iter().filter(|b| b.id.ends_with('n')).map(|b| b.shape.volume()).sum();
        assert!((p_vol / (p_vol + n_vol) - 0.4).abs() < 0.02, "{name}: loose leaf share {}", p_vol / (p_vol + n_vol));
    }
    // The built-in effect at its neutral value changes nothing.
    let wall = Wall::from_file(&root.join("studies/walls/cbl.toml")).unwrap();
    let before = generate(&wall, 7, 1).unwrap().check().unwrap();
    let mut after = before.clone();
    let e = Library::builtin().parse("leaf_split=0", 0.05).unwrap();
    let mut rng = drystone::effects::effect_rng(1, 0, "g", "leaf_split");
    e.apply_stage(Stage::Layout, &mut after, &[], &mut rng).unwrap();
    assert_eq!(after.blocks.len(), before.blocks.len());
}
