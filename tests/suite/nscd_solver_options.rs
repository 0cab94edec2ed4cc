//! The NSGS options of the non-smooth solver (`NscdParams::{norm, sweep, relaxation,
//! polygon_passes, polygon_points}`) against the exact rigid limits computed
//! here: every option is a way of solving the same contact problem, so each must bracket
//! the closed form as the default does.

use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::{TiltParams, TiltResult};
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::nscd::{NscdError, NscdParams, NsgsNorm, PolygonPoints, SweepOrder};
use drystone::verify::{box_vertices, layout_of};
use std::path::Path;

fn run(layout: &Layout, params: &NscdParams) -> TiltResult {
    run_tilt_nscd(layout, params, &TiltParams { resolution_deg: 0.05, ..TiltParams::default() }).expect("tilt")
}

/// The bracket holds `exact` (degrees) and is at most 0.05° wide.
fn brackets(name: &str, r: &TiltResult, exact: f64) {
    let up = r.first_unstable_deg.unwrap_or_else(|| panic!("{name}: stood to the largest tilt"));
    assert!(up - r.last_stable_deg <= 0.05 + 1e-9, "{name}: bracket [{}, {up}]", r.last_stable_deg);
    assert!(
        r.last_stable_deg <= exact && exact <= up,
        "{name}: bracket [{:.4}, {up:.4}] misses the exact rigid limit {exact:.4}°",
        r.last_stable_deg
    );
}

/// The 13-box running-bond wall (t/H = 1/3) and a single box (b/h) bracket their closed
/// forms under the quadratic norm, symmetric sweeps and polygon passes.
#[test]
fn every_sweep_option_brackets_the_exact_rigid_limits() {
    let wall =
        Layout::from_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/rigid/running_bond_13.json"))
            .expect("layout");
    let block =
        layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.3, 0.05, 0.25])], 1e13, 5e12, 60.0, BaseSliding::Free);
    let quad = NscdParams { norm: NsgsNorm::Quad, tolerance: 1e-6, ..NscdParams::default() };
    let options = [
        ("quad 1e-6", quad),
        ("quad, symmetric sweeps", NscdParams { sweep: SweepOrder::Symmetric, ..quad }),
        ("quad, 3 polygon passes", NscdParams { polygon_passes: 3, ..quad }),
        ("velocity, under-relaxed 0.8", NscdParams { relaxation: 0.8, ..NscdParams::default() }),
    ];
    for (name, p) in options {
        brackets(&format!("13-box wall, {name}"), &run(&wall, &p), (1.0f64 / 3.0).atan().to_degrees());
        brackets(&format!("box 0.1 x 0.25, {name}"), &run(&block, &p), (0.1f64 / 0.25).atan().to_degrees());
    }
}

/// A box's base has four corners, which the four-point reduction keeps; a hexagonal
/// prism's base has six, of which it keeps the four of the largest quadrilateral (here the
/// rectangle of the four corners at y = ±b), whose lever arm about the toppling edge is
/// the hexagon's own: the limit is unchanged, and both bracket it.
#[test]
fn four_point_polygons_keep_the_limit_of_a_block_on_its_extreme_corners() {
    let p = NscdParams { polygon_points: PolygonPoints::Quad, ..NscdParams::default() };
    let block =
        layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.3, 0.05, 0.25])], 1e13, 5e12, 60.0, BaseSliding::Free);
    brackets("box, four points", &run(&block, &p), (0.1f64 / 0.25).atan().to_degrees());
    // A hexagonal prism, vertices (±c, 0) and (±a/2, ±b), c < a: tilted towards +y it
    // topples about the edge y = b, tan α = b / (h/2). The largest quadrilateral of its
    // base is the rectangle (±a/2, ±b) (area 2ab, against 2cb and less for the others).
    let (a, c, b, h) = (0.2, 0.15, 0.06, 0.3);
    let mut v = Vec::new();
    for z in [0.0, h] {
        for (x, y) in [(c, 0.0), (a / 2.0, b), (-a / 2.0, b), (-c, 0.0), (-a / 2.0, -b), (a / 2.0, -b)] {
            v.push([x, y, z]);
        }
    }
    let hex = layout_of(vec![v], 1e13, 5e12, 60.0, BaseSliding::Free);
    let exact = (b / (h / 2.0)).atan().to_degrees();
    brackets("hexagonal prism, all vertices", &run(&hex, &NscdParams::default()), exact);
    brackets("hexagonal prism, four points", &run(&hex, &p), exact);
}

/// Relaxation outside (0, 2), zero polygon passes and tolerances and budgets out of their
/// ranges (a natural-map tolerance below 1e-12 included) are refused, naming the key.
#[test]
fn nsgs_options_out_of_range_are_refused_by_key() {
    let block =
        layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.3, 0.05, 0.25])], 1e13, 5e12, 60.0, BaseSliding::Free);
    for (key, p) in [
        ("relaxation", NscdParams { relaxation: 2.0, ..NscdParams::default() }),
        ("polygon_passes", NscdParams { polygon_passes: 0, ..NscdParams::default() }),
        ("quad_tolerance", NscdParams { quad_tolerance: 0.0, ..NscdParams::default() }),
        ("quad_after_solves", NscdParams { quad_after_solves: f64::NAN, ..NscdParams::default() }),
        ("natural_tolerance", NscdParams { natural_tolerance: 1e-300, ..NscdParams::default() }),
        ("natural_tolerance", NscdParams { natural_tolerance: 1.0, ..NscdParams::default() }),
        ("apgd_after_solves", NscdParams { apgd_after_solves: -1.0, ..NscdParams::default() }),
    ] {
        match drystone::nscd::NscdSimulation::new(&block, &p) {
            Err(NscdError::Parameter(e)) => assert!(e.to_string().contains(key), "{key}: {e}"),
            other => panic!("{key}: expected a parameter error, got {other:?}"),
        }
    }
}
