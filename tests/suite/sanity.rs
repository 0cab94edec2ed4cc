//! Physical sanity of the input: layouts that would run but give a silently wrong answer
//! are refused with an error naming the block or key, in every protocol and every
//! density-scaling mode.

use drystone::dem::{DensityScaling, SolverParams};
use drystone::layout::{Layout, LayoutError, LayoutSpec};
use drystone::loading::lateral::{LateralError, LateralParams};
use drystone::loading::settle::SettleError;
use drystone::loading::tilt::{TiltError, TiltParams};
use drystone::protocol::run_lateral;
use drystone::protocol::run_tilt;

/// A box `[x0, x1] × [y0, y1] × [z0, z1]` as a block of material `m`.
fn block(id: &str, [x0, x1]: [f64; 2], [y0, y1]: [f64; 2], [z0, z1]: [f64; 2]) -> String {
    let mut v = Vec::new();
    for z in [z0, z1] {
        for (x, y) in [(x0, y0), (x1, y0), (x1, y1), (x0, y1)] {
            v.push(format!("[{x}, {y}, {z}]"));
        }
    }
    format!(r#"{{"id": "{id}", "material": "m", "vertices": [{}]}}"#, v.join(", "))
}

fn layout_json(blocks: &[String], density: f64, kn: f64, extra: &str) -> String {
    format!(
        r#"{{"version": 1, "materials": [{{"name": "m", "density_kg_per_m3": {density}, "kn_pa_per_m": {kn},
            "ks_pa_per_m": 2.5e7, "friction_deg": 35}}], "table": {{"material": "m"}},
            "blocks": [{}]{extra}}}"#,
        blocks.join(", ")
    )
}

fn parse(json: &str) -> Result<Layout, LayoutError> {
    LayoutSpec::from_json(json)?.resolve()
}

fn stack() -> Vec<String> {
    vec![block("base", [0.0, 0.4], [0.0, 0.2], [0.0, 0.1]), block("top", [0.0, 0.4], [0.0, 0.2], [0.1, 0.2])]
}

fn modes() -> [DensityScaling; 3] {
    [DensityScaling::Off, DensityScaling::Scalar, DensityScaling::Block { mass_floor: 0.05 }]
}

fn tilt_error(l: &Layout, scaling: DensityScaling) -> SettleError {
    let solver = SolverParams { density_scaling: scaling, ..SolverParams::default() };
    match run_tilt(l, solver, &TiltParams::default()) {
        Err(TiltError::DoesNotStand(e)) => e,
        other => panic!("{scaling:?}: expected a layout that does not stand, got {other:?}"),
    }
}

fn lateral_error(l: &Layout) -> SettleError {
    match run_lateral(l, SolverParams::default(), &LateralParams::default()) {
        Err(LateralError::DoesNotStand(e)) => e,
        other => panic!("lateral: expected a layout that does not stand, got {other:?}"),
    }
}

#[test]
fn a_stable_stack_stands() {
    let l = parse(&layout_json(&stack(), 2150.0, 5e7, "")).unwrap();
    for m in modes() {
        let solver = SolverParams { density_scaling: m, ..SolverParams::default() };
        let r = run_tilt(&l, solver, &TiltParams { max_angle_deg: 5.0, ..TiltParams::default() });
        assert!(r.is_ok(), "{m:?}: {r:?}");
    }
}

/// A top block whose centroid lies beyond its support falls off while settling.
#[test]
fn an_overhanging_top_block_is_named() {
    let blocks =
        vec![block("base", [0.0, 0.2], [0.0, 0.2], [0.0, 0.1]), block("top", [0.15, 0.55], [0.0, 0.2], [0.1, 0.2])];
    let l = parse(&layout_json(&blocks, 2150.0, 5e7, "")).unwrap();
    for m in modes() {
        let e = tilt_error(&l, m);
        assert!(matches!(&e, SettleError::Moved { block, .. } if block == "top"), "{m:?}: {e}");
        assert!(e.to_string().contains("does not stand as given: block top moved"), "{e}");
    }
    assert!(matches!(lateral_error(&l), SettleError::Moved { block, .. } if block == "top"));
}

/// A block floating above the table touches nothing.
#[test]
fn a_floating_block_is_named() {
    let mut blocks = stack();
    blocks.push(block("floater", [0.6, 0.8], [0.0, 0.2], [0.5, 0.6]));
    let l = parse(&layout_json(&blocks, 2150.0, 5e7, "")).unwrap();
    for m in modes() {
        let e = tilt_error(&l, m);
        assert!(matches!(&e, SettleError::Untouched { block, .. } if block == "floater"), "{m:?}: {e}");
        assert!(e.to_string().contains("block floater touches nothing"), "{e}");
    }
    assert!(matches!(lateral_error(&l), SettleError::Untouched { block, .. } if block == "floater"));
}

/// A block laid 5 cm above the table with a block resting on it: both fall, the one on top
/// as far or farther, and the one laid in the air is named, not the one that fell with it
/// (as a loading beam on such a block was named).
#[test]
fn a_block_that_gave_way_is_named_not_what_fell_with_it() {
    let blocks = vec![
        block("below", [0.0, 0.2], [0.0, 0.2], [0.05, 0.15]),
        block("above", [0.0, 0.2], [0.0, 0.2], [0.15, 0.25]),
    ];
    let l = parse(&layout_json(&blocks, 2150.0, 5e7, "")).unwrap();
    for m in modes() {
        let e = tilt_error(&l, m);
        assert!(matches!(&e, SettleError::Moved { block, .. } if block == "below"), "{m:?}: {e}");
    }
}

/// An L-shaped block is not replaced by its hull.
#[test]
fn a_non_convex_block_is_refused() {
    let l_shape = r#"{"id": "ell", "material": "m", "vertices": [[0,0,0],[0.4,0,0],[0.4,0.2,0],[0,0.2,0],
        [0,0,0.1],[0.4,0,0.1],[0.4,0.2,0.1],[0,0.2,0.1],[0,0,0.3],[0.1,0,0.3],[0.1,0.2,0.3],[0,0.2,0.3],
        [0.1,0,0.1],[0.1,0.2,0.1]]}"#;
    let e = parse(&layout_json(&[l_shape.to_string()], 2150.0, 5e7, "")).unwrap_err();
    assert!(matches!(&e, LayoutError::NotConvex { id, .. } if id == "ell"), "{e}");
    assert!(e.to_string().contains("block ell is not convex"), "{e}");
}

/// Densities, stiffnesses and gravity outside physical bounds name their key.
#[test]
fn non_physical_materials_are_named() {
    for (density, kn, key) in [
        (1e-300, 5e7, "density_kg_per_m3"),
        (1e6, 5e7, "density_kg_per_m3"),
        (2150.0, 1.0, "kn_pa_per_m"),
        (2150.0, 1e20, "kn_pa_per_m"),
        (2150.0, 1e6, "kn_pa_per_m"), // in range, but the joints would close by 2 % of the height
    ] {
        let e = parse(&layout_json(&stack(), density, kn, "")).unwrap_err();
        assert!(e.to_string().contains(&format!("materials[m].{key}")), "{density} {kn}: {e}");
    }
    let e = parse(&layout_json(&stack(), 2150.0, 5e7, r#", "gravity_m_per_s2": 1e-9"#)).unwrap_err();
    assert!(e.to_string().contains("gravity_m_per_s2"), "{e}");
}

/// A monitor point given in millimetres lies far outside its block.
#[test]
fn a_monitor_in_millimetres_is_named() {
    let mm = r#", "monitors": [{"name": "tip", "block": "top", "point": [200, 100, 200]}]"#;
    let e = parse(&layout_json(&stack(), 2150.0, 5e7, mm)).unwrap_err();
    assert!(e.to_string().contains("monitors[tip].point"), "{e}");
    let m = r#", "monitors": [{"name": "tip", "block": "top", "point": [0.2, 0.1, 0.2]}]"#;
    assert!(parse(&layout_json(&stack(), 2150.0, 5e7, m)).is_ok());
}

/// Seating gaps close under the wall's weight: a stack of ten 5 cm courses on uneven beds
/// (gaps up to 3 mm per joint) settles by more than 2 % of its height, which the closure of
/// its joints explains, and stands.
#[test]
fn seating_gaps_that_close_are_not_a_fall() {
    let blocks: Vec<String> = (0..10)
        .map(|k| block(&format!("c{k}"), [0.0, 0.4], [0.0, 0.2], [0.05 * k as f64, 0.05 * (k + 1) as f64]))
        .collect();
    let mut l = parse(&layout_json(&blocks, 2150.0, 5e7, "")).unwrap();
    l.materials[0].closure = drystone::closure::Closure::Seating(drystone::closure::Seating { max_gap_m: 0.003 });
    let tolerance = drystone::loading::settle::settle_tolerance(&l);
    assert!(tolerance > 0.02 * 0.5 + 9.0 * 0.003, "{tolerance}");
    let r = run_tilt(&l, SolverParams::default(), &TiltParams { max_angle_deg: 2.0, ..TiltParams::default() });
    assert!(r.is_ok(), "{r:?}");
}
