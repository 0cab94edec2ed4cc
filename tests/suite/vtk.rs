//! The ParaView time series of a test (`io::series`) read back with vtkio, checked against
//! the tilt's own result, and the mechanism drawing of its first unstable state.

use drystone::dem::SolverParams;
use drystone::io::mechanism::{mechanism_svg, MechanismFigure};
use drystone::io::series::{lateral_frames, tilt_frames, write_series, Recorder};
use drystone::layout::Layout;
use drystone::loading::lateral::LateralParams;
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_lateral_observed;
use drystone::protocol::run_tilt_observed;
use std::path::{Path, PathBuf};
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece, UnstructuredGridPiece};

fn layout() -> Layout {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    Layout::from_file(&root.join("data/layouts/single_block.json")).expect("the shipped layout")
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("drystone-vtk-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The `(timestep, file)` of every `part="0"` (blocks) entry of a `.pvd` file.
fn pvd_blocks(path: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    let attr = |line: &str, key: &str| -> String {
        let start = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        line[start..].split('"').next().unwrap().to_string()
    };
    text.lines()
        .filter(|l| l.contains("<DataSet") && l.contains("part=\"0\""))
        .map(|l| (attr(l, "timestep").parse().unwrap(), attr(l, "file")))
        .collect()
}

fn grid(path: &Path) -> UnstructuredGridPiece {
    let vtk = vtkio::Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match vtk.data {
        DataSet::UnstructuredGrid { mut pieces, .. } => match pieces.remove(0) {
            Piece::Inline(p) => *p,
            _ => panic!("an inline piece"),
        },
        _ => panic!("an unstructured grid"),
    }
}

fn f64s(b: &IOBuffer) -> Vec<f64> {
    match b {
        IOBuffer::F64(v) => v.clone(),
        other => panic!("f64 data, got {other:?}"),
    }
}

fn cell_array<'a>(g: &'a UnstructuredGridPiece, name: &str) -> &'a IOBuffer {
    g.data
        .cell
        .iter()
        .find_map(|a| match a {
            Attribute::DataArray(d) if d.name == name => Some(&d.data),
            _ => None,
        })
        .unwrap_or_else(|| panic!("cell data {name}"))
}

/// The points of a grid as (x, y, z).
fn points(g: &UnstructuredGridPiece) -> Vec<[f64; 3]> {
    f64s(&g.points).chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
}

#[test]
fn a_tilt_series_reads_back_with_its_times_blocks_and_final_displacement() {
    let l = layout();
    let mut rec = Recorder::default();
    let r =
        run_tilt_observed(&l, SolverParams::default(), &TiltParams::default(), &mut |a, s, sim| rec.observe(a, s, sim))
            .unwrap();
    let unstable = r.first_unstable_deg.expect("the block topples");
    let dir = temp("tilt");
    let (series, others) = tilt_frames(&rec, &r);
    let pvd = write_series(&dir, "tilt", &rec, &series).unwrap();
    write_series(&dir, "unstable_trials", &rec, &others).unwrap();

    // Times: every stable state of the result in increasing α, then the first unstable.
    let entries = pvd_blocks(&pvd);
    let mut expected: Vec<f64> = r.increments.iter().filter(|i| i.stable).map(|i| i.alpha_deg).collect();
    expected.push(unstable);
    let times: Vec<f64> = entries.iter().map(|e| e.0).collect();
    assert_eq!(times, expected);
    // The other unstable trials: every unstable increment of the result but the first unstable.
    let trials: Vec<f64> = pvd_blocks(&dir.join("unstable_trials.pvd")).iter().map(|e| e.0).collect();
    let mut failed: Vec<f64> =
        r.increments.iter().filter(|i| !i.stable && i.alpha_deg != unstable).map(|i| i.alpha_deg).collect();
    failed.sort_by(f64::total_cmp);
    assert_eq!(trials, failed);

    // Blocks: one per layout block, each as its faces.
    let first = grid(&dir.join(&entries[0].1));
    let last = grid(&dir.join(&entries.last().unwrap().1));
    let faces = l.blocks[0].shape.faces.len();
    assert_eq!(last.cells.types.len(), faces);
    let block_ids = match cell_array(&last, "block") {
        IOBuffer::I32(v) => v.clone(),
        other => panic!("{other:?}"),
    };
    let mut distinct = block_ids.clone();
    distinct.dedup();
    assert_eq!(distinct.len(), l.blocks.len());
    let moving = match cell_array(&last, "moving") {
        IOBuffer::I32(v) => v.clone(),
        other => panic!("{other:?}"),
    };
    assert!(moving.iter().all(|m| *m == 1), "the toppling block moves");

    // The top-centre monitor is the centre of the top face: its y displacement from the
    // settled state to the last state, from the points written, is the tilt's.
    let (p0, p1) = (points(&first), points(&last));
    let zmax = l.blocks[0].shape.vertices.iter().map(|v| v.z).fold(f64::MIN, f64::max);
    let top: Vec<usize> = (0..p0.len()).filter(|&i| (l.blocks[0].shape.vertices[i].z - zmax).abs() < 1e-12).collect();
    assert_eq!(top.len(), 4);
    let mean_y = |p: &[[f64; 3]]| top.iter().map(|&i| p[i][1]).sum::<f64>() / 4.0;
    let written = mean_y(&p1) - mean_y(&p0);
    let centre = r.monitors.iter().position(|m| m == "top_centre").unwrap();
    let reported = r.increments.iter().find(|i| !i.stable && i.alpha_deg == unstable).unwrap().displacement_m[centre];
    assert!((written - reported).abs() <= 1e-9 * reported.abs().max(1e-3), "{written} vs {reported}");
    assert!(reported > 1e-3, "the first unstable state has moved: {reported}");

    // The displacement cell data is the centroid's (the mean of a box's corners).
    let mean = |p: &[[f64; 3]], k: usize| p.iter().map(|q| q[k]).sum::<f64>() / p.len() as f64;
    let d = f64s(cell_array(&last, "displacement"));
    for k in 0..3 {
        assert!((d[k] - (mean(&p1, k) - mean(&p0, k))).abs() < 1e-12, "component {k}");
    }
    let mag = f64s(cell_array(&last, "displacement_magnitude"))[0];
    assert!((mag - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()).abs() < 1e-15);

    // Sub-contacts: the table carries the block's weight in the settled state.
    let contacts = grid(&dir.join(entries[0].1.replace("_blocks_", "_contacts_")));
    let normal = contacts
        .data
        .point
        .iter()
        .find_map(|a| match a {
            Attribute::DataArray(d) if d.name == "normal_force_n" => Some(f64s(&d.data)),
            _ => None,
        })
        .unwrap();
    let weight = l.blocks[0].shape.mass_properties(l.materials[0].density).mass * 9.81;
    let total: f64 = normal.iter().sum();
    assert!((total - weight).abs() < 1e-3 * weight, "{total} vs {weight}");

    // The mechanism drawing of the same state marks the governing joint.
    let state = &rec.states[series.last().unwrap().state];
    let svg = mechanism_svg(&MechanismFigure {
        layout: &l,
        poses: &state.poses,
        displacement_m: &[reported.abs()],
        moving: &series.last().unwrap().moving,
        joint: &r.mechanism.joint,
        title: "single block",
        subtitle: "",
    });
    assert_eq!(r.mechanism.joint, "table/b0");
    assert_eq!(
        svg.matches(r##"stroke="#d62728" stroke-width="4" stroke-linecap"##).count(),
        2,
        "the joint in both views"
    );
    assert!(svg.contains("table/b0"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_lateral_series_has_the_settled_and_the_loaded_state() {
    let l = layout();
    let mut rec = Recorder::default();
    let p = LateralParams { pressure_base_pa: 200.0, pressure_top_pa: 100.0, ..LateralParams::default() };
    let r = run_lateral_observed(&l, SolverParams::default(), &p, &mut |a, s, sim| rec.observe(a, s, sim)).unwrap();
    let dir = temp("lateral");
    let pvd = write_series(&dir, "lateral", &rec, &lateral_frames(&rec)).unwrap();
    let entries = pvd_blocks(&pvd);
    assert_eq!(entries.iter().map(|e| e.0).collect::<Vec<_>>(), vec![0.0, 1.0]);
    let last = grid(&dir.join(&entries[1].1));
    let d = f64s(cell_array(&last, "displacement"));
    assert!(r.equilibrium);
    assert!(d[1] > 0.0, "the block is pushed towards +y: {d:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
