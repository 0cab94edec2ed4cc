//! ParaView time series of a test (VTK XML, written with `vtkio`): the states of a tilt or a
//! lateral load, each as two unstructured grids, and a `.pvd` collection that lists them with
//! their time values.
//!
//! # What is recorded
//!
//! A [`Recorder`] is a protocol's observer (`protocol::Observer`, through `protocol::run`):
//! [`Recorder::observe`] takes the static states a protocol hands over: the pose of
//! every block and the force of every sub-contact. [`tilt_frames`] orders a tilt's states as
//! a series: the settled state at α = 0, every stable increment and stable bisection trial in
//! increasing α, and last the first unstable state (the state the mechanism is read from).
//! The other unstable trials (the first failing increment and the bisection trials that
//! failed above α_max) form a second series.
//!
//! # Files ([`write_series`], `NAME` the series' name)
//!
//! * `NAME.pvd`: the collection; `timestep` is the tilt α in degrees (the load factor, 0 or
//!   1, for a lateral load); each time has two parts: `part="0"` the blocks, `part="1"` the
//!   sub-contacts.
//! * `NAME_blocks_KKKK.vtu`: every block as its polygonal faces (one `Polygon` cell per face,
//!   points in m in the table frame: x along the wall, y out of plane, z normal to the
//!   table). Cell data, repeated on every face of a block: `block` (index in the layout),
//!   `material` (index in the layout), `fixed` (1 or 0), `moving` (1 for the blocks of a
//!   collapse mechanism in an unstable state, see [`Frame::moving`]; 0 in stable states),
//!   `displacement` (centroid displacement since the settled state, m, vector),
//!   `displacement_magnitude` (m) and `rotation_deg` (rotation angle since the settled
//!   state, degrees). Threshold on `block` to pick one block.
//! * `NAME_contacts_KKKK.vtu`: one `Vertex` cell per sub-contact at its centroid. Point data:
//!   `normal_force` (N, vector: the normal force on body B, `n Fn`, compression pointing from
//!   A to B), `normal_force_n` (N, compression positive), `shear_force` (N, vector, on B),
//!   `force` (their sum), `area_m2`, `slipping` and `bonded` (1 or 0), `contact` (index of
//!   the contact), `block_a` (−1 for the table) and `block_b`. Glyph filter on `force` or
//!   `normal_force` shows the load paths.
//!
//! VTK's polyhedron cells would need face streams, which `vtkio` does not write; one polygon
//! per face draws the same solid in ParaView.

use super::{replace_file, FileError};
use crate::dem::Simulation;
use crate::geometry::ConvexBlock;
use crate::loading::mechanism::MECHANISM_SHARE;
use crate::loading::monitors::BodyPose;
use crate::loading::tilt::TiltResult;
use crate::math::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, IOBuffer, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

/// Errors of writing a series.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SeriesError {
    /// A file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// `vtkio` refused a dataset (a bug: the arrays are built consistent).
    #[error("{path}: VTK XML: {message}")]
    Vtk {
        /// The file.
        path: PathBuf,
        /// vtkio's message.
        message: String,
    },
}

/// A block as recorded: its id, material index, whether it is fixed, and its shape in the
/// body frame (origin at its centroid, axes parallel to the table frame in the layout).
#[derive(Debug, Clone)]
pub struct RecordedBlock {
    /// Id as in the layout.
    pub id: String,
    /// Index of its material in the layout.
    pub material: usize,
    /// Never moves.
    pub fixed: bool,
    /// Shape in the body frame, m.
    pub shape: ConvexBlock,
    /// Distance from the centroid to the farthest vertex, m.
    pub radius: f64,
}

/// One sub-contact of a recorded state.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedSubContact {
    /// Centroid, table frame, m.
    pub point: Vec3,
    /// Unit normal from A to B.
    pub normal: Vec3,
    /// Normal force on B, N (compression positive).
    pub normal_force_n: f64,
    /// Shear force on B, N, table frame.
    pub shear_n: Vec3,
    /// Area, m².
    pub area_m2: f64,
    /// On the slip limit.
    pub slipping: bool,
    /// Tensile strength and cohesion intact.
    pub bonded: bool,
    /// Index of the contact in the state.
    pub contact: usize,
    /// Body A (`None`: the table).
    pub a: Option<usize>,
    /// Body B.
    pub b: usize,
}

/// One recorded state: its time value (tilt in degrees, or load factor), whether it is an
/// equilibrium, the pose of every block and the sub-contacts.
#[derive(Debug, Clone)]
pub struct RecordedState {
    /// Tilt α, degrees (tilt), or load factor (lateral load).
    pub time: f64,
    /// An equilibrium.
    pub stable: bool,
    /// Centroid (m) and orientation of every block, in block order.
    pub poses: Vec<BodyPose>,
    /// Every sub-contact.
    pub subs: Vec<RecordedSubContact>,
}

/// The states of a test, as handed to a protocol's observer, in the order reached.
#[derive(Debug, Clone, Default)]
pub struct Recorder {
    /// The blocks (from the first state observed).
    pub blocks: Vec<RecordedBlock>,
    /// The states in the order reached.
    pub states: Vec<RecordedState>,
}

/// The recorder as a protocol's observer (`protocol::Observer`): every static state with
/// its sub-contacts ([`Recorder::observe`]), every instant of a motion as the blocks' poses
/// ([`Recorder::observe_bodies`], stable, no sub-contacts).
impl crate::protocol::Observer for Recorder {
    fn state(&mut self, at: f64, stable: bool, sim: &Simulation) {
        self.observe(at, stable, sim);
    }

    fn instant(&mut self, time_s: f64, bodies: &[crate::dem::state::Body]) {
        self.observe_bodies(time_s, true, bodies, Vec::new());
    }
}

impl Recorder {
    /// Records `sim` at `time` (a static state handed to a protocol's observer).
    pub fn observe(&mut self, time: f64, stable: bool, sim: &Simulation) {
        let mut subs = Vec::new();
        for (ci, c) in sim.state.contacts.iter().enumerate() {
            let normal = sim.state.contact_normal(c);
            for s in &c.subs {
                subs.push(RecordedSubContact {
                    point: sim.state.sub_centroid(c, s),
                    normal,
                    normal_force_n: s.state.normal,
                    shear_n: s.state.shear,
                    area_m2: s.area,
                    slipping: s.state.slipping,
                    bonded: s.state.bonded,
                    contact: ci,
                    a: c.a,
                    b: c.b,
                });
            }
        }
        self.observe_bodies(time, stable, &sim.state.bodies, subs);
    }
}

impl Recorder {
    /// Records the poses of `bodies` (the blocks of any solver, layout order) at `time`,
    /// with the sub-contacts given (none where the solver has no sub-contact forces to
    /// show).
    pub fn observe_bodies(
        &mut self,
        time: f64,
        stable: bool,
        bodies: &[crate::dem::state::Body],
        subs: Vec<RecordedSubContact>,
    ) {
        if self.blocks.is_empty() {
            self.blocks = bodies
                .iter()
                .map(|b| RecordedBlock {
                    id: b.id.clone(),
                    material: b.material,
                    fixed: b.fixed(),
                    shape: b.shape.clone(),
                    radius: b.radius,
                })
                .collect();
        }
        let poses = bodies.iter().map(|b| (b.pos, b.rot)).collect();
        self.states.push(RecordedState { time, stable, poses, subs });
    }
}

/// The frames of a motion: every recorded state in time order, the blocks that moved more
/// than `MECHANISM_SHARE` of the largest motion from the first state marked moving.
pub fn motion_frames(rec: &Recorder) -> Vec<Frame> {
    let Some(first) = rec.states.first() else { return Vec::new() };
    rec.states
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let m = block_motions(rec, first, s);
            let max = m.iter().cloned().fold(0.0, f64::max);
            let moving =
                m.iter().zip(&rec.blocks).map(|(d, b)| !b.fixed && max > 1e-6 && *d > MECHANISM_SHARE * max).collect();
            Frame { state: k, moving }
        })
        .collect()
}

/// One state of a series: the index of the recorded state and which blocks move.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Index into [`Recorder::states`].
    pub state: usize,
    /// Per block: part of the collapse mechanism. In the first unstable state of a tilt,
    /// the mechanism's blocks (`TiltResult::mechanism`); in another unstable state, the
    /// blocks whose motion during the increment (centroid motion plus rotation times radius,
    /// from the stable state it started from) exceeds `MECHANISM_SHARE` of the largest; in
    /// a stable state none.
    pub moving: Vec<bool>,
}

/// The angle of the rotation `q`, rad, in \[0, π\].
fn angle(q: &nalgebra::UnitQuaternion<f64>) -> f64 {
    2.0 * q.imag().norm().atan2(q.scalar().abs())
}

/// Each block's motion ([`motion`]) from the state `from` to the state `to`.
fn block_motions(rec: &Recorder, from: &RecordedState, to: &RecordedState) -> Vec<f64> {
    from.poses.iter().zip(&to.poses).zip(&rec.blocks).map(|((a, b), blk)| motion(a, b, blk.radius)).collect()
}

/// Motion of a block of radius `r` between two poses, m (as the tilt's collapse criterion).
fn motion(from: &BodyPose, to: &BodyPose, r: f64) -> f64 {
    (to.0 - from.0).norm() + angle(&(to.1 * from.1.inverse())) * r
}

/// The frames of a tilt: `(series, other unstable trials)`. The series holds the settled
/// state, the stable states in increasing α and, last, the first unstable state; the other
/// unstable trials are those superseded by the bisection. `rec` must hold the states of the
/// run that gave `result` (see the module documentation).
pub fn tilt_frames(rec: &Recorder, result: &TiltResult) -> (Vec<Frame>, Vec<Frame>) {
    let nb = rec.blocks.len();
    let mut start = 0usize;
    let (mut series, mut others) = (Vec::new(), Vec::new());
    let mut first_unstable = None;
    for (k, s) in rec.states.iter().enumerate() {
        if s.stable {
            series.push(Frame { state: k, moving: vec![false; nb] });
            start = k;
            continue;
        }
        let from = &rec.states[start].poses;
        let m: Vec<f64> =
            from.iter().zip(&s.poses).zip(&rec.blocks).map(|((a, b), blk)| motion(a, b, blk.radius)).collect();
        let max = m.iter().cloned().fold(0.0, f64::max);
        let mut moving: Vec<bool> =
            m.iter().zip(&rec.blocks).map(|(d, b)| !b.fixed && max > 0.0 && *d > MECHANISM_SHARE * max).collect();
        if Some(s.time) == result.first_unstable_deg {
            moving = rec.blocks.iter().map(|b| result.mechanism.blocks.contains(&b.id)).collect();
            if let Some(prev) = first_unstable.replace(Frame { state: k, moving }) {
                others.push(prev);
            }
        } else {
            others.push(Frame { state: k, moving });
        }
    }
    series.sort_by(|a, b| rec.states[a.state].time.total_cmp(&rec.states[b.state].time));
    series.extend(first_unstable);
    others.sort_by(|a, b| rec.states[a.state].time.total_cmp(&rec.states[b.state].time));
    (series, others)
}

/// The frames of a lateral load: every recorded state in order; in an unstable final state
/// the blocks that moved more than `MECHANISM_SHARE` of the largest motion are moving.
pub fn lateral_frames(rec: &Recorder) -> Vec<Frame> {
    let nb = rec.blocks.len();
    rec.states
        .iter()
        .enumerate()
        .map(|(k, s)| {
            if s.stable || k == 0 {
                return Frame { state: k, moving: vec![false; nb] };
            }
            let m = block_motions(rec, &rec.states[0], s);
            let max = m.iter().cloned().fold(0.0, f64::max);
            let moving = m.iter().zip(&rec.blocks).map(|(d, b)| !b.fixed && *d > MECHANISM_SHARE * max).collect();
            Frame { state: k, moving }
        })
        .collect()
}

/// Centroid displacement (m) and rotation angle (degrees) of every block from `reference`
/// to `poses`.
pub fn block_motion(reference: &[BodyPose], poses: &[BodyPose]) -> Vec<(Vec3, f64)> {
    reference.iter().zip(poses).map(|(a, b)| (b.0 - a.0, angle(&(b.1 * a.1.inverse())).to_degrees())).collect()
}

fn vtk(piece: UnstructuredGridPiece) -> Vtk {
    Vtk {
        version: Version::XML { major: 1, minor: 0 },
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(piece),
    }
}

fn flat(v: impl IntoIterator<Item = Vec3>) -> Vec<f64> {
    v.into_iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// The blocks of `state` as an unstructured grid (see the module documentation).
fn blocks_grid(rec: &Recorder, frame: &Frame) -> Vtk {
    let state = &rec.states[frame.state];
    let motion = block_motion(&rec.states[0].poses, &state.poses);
    let (mut points, mut connectivity, mut offsets) = (Vec::new(), Vec::new(), Vec::new());
    let mut cell_block = Vec::new();
    for (bi, (b, (pos, rot))) in rec.blocks.iter().zip(&state.poses).enumerate() {
        let base = points.len() as u64;
        points.extend(b.shape.vertices.iter().map(|v| pos + rot * v));
        for f in &b.shape.faces {
            connectivity.extend(f.vertices.iter().map(|&i| base + i as u64));
            offsets.push(connectivity.len() as u64);
            cell_block.push(bi);
        }
    }
    let per_cell_i = |f: &dyn Fn(usize) -> i32| IOBuffer::I32(cell_block.iter().map(|&b| f(b)).collect());
    let per_cell_f = |f: &dyn Fn(usize) -> f64| IOBuffer::F64(cell_block.iter().map(|&b| f(b)).collect());
    let cell = vec![
        Attribute::scalars("block", 1).with_data(per_cell_i(&|b| b as i32)),
        Attribute::scalars("material", 1).with_data(per_cell_i(&|b| rec.blocks[b].material as i32)),
        Attribute::scalars("fixed", 1).with_data(per_cell_i(&|b| i32::from(rec.blocks[b].fixed))),
        Attribute::scalars("moving", 1).with_data(per_cell_i(&|b| i32::from(frame.moving[b]))),
        Attribute::vectors("displacement").with_data(IOBuffer::F64(flat(cell_block.iter().map(|&b| motion[b].0)))),
        Attribute::scalars("displacement_magnitude", 1).with_data(per_cell_f(&|b| motion[b].0.norm())),
        Attribute::scalars("rotation_deg", 1).with_data(per_cell_f(&|b| motion[b].1)),
    ];
    let ncells = offsets.len();
    vtk(UnstructuredGridPiece {
        points: IOBuffer::F64(flat(points)),
        cells: Cells {
            cell_verts: VertexNumbers::XML { connectivity, offsets },
            types: vec![CellType::Polygon; ncells],
        },
        data: Attributes { point: vec![], cell },
    })
}

/// The sub-contacts of `state` as vertices with their forces (see the module documentation).
fn contacts_grid(state: &RecordedState) -> Vtk {
    let s = &state.subs;
    let n = s.len();
    let fi = |f: &dyn Fn(&RecordedSubContact) -> i32| IOBuffer::I32(s.iter().map(f).collect());
    let point = vec![
        Attribute::vectors("normal_force")
            .with_data(IOBuffer::F64(flat(s.iter().map(|c| c.normal * c.normal_force_n)))),
        Attribute::scalars("normal_force_n", 1).with_data(IOBuffer::F64(s.iter().map(|c| c.normal_force_n).collect())),
        Attribute::vectors("shear_force").with_data(IOBuffer::F64(flat(s.iter().map(|c| c.shear_n)))),
        Attribute::vectors("force")
            .with_data(IOBuffer::F64(flat(s.iter().map(|c| c.normal * c.normal_force_n + c.shear_n)))),
        Attribute::scalars("area_m2", 1).with_data(IOBuffer::F64(s.iter().map(|c| c.area_m2).collect())),
        Attribute::scalars("slipping", 1).with_data(fi(&|c| i32::from(c.slipping))),
        Attribute::scalars("bonded", 1).with_data(fi(&|c| i32::from(c.bonded))),
        Attribute::scalars("contact", 1).with_data(fi(&|c| c.contact as i32)),
        Attribute::scalars("block_a", 1).with_data(fi(&|c| c.a.map_or(-1, |a| a as i32))),
        Attribute::scalars("block_b", 1).with_data(fi(&|c| c.b as i32)),
    ];
    vtk(UnstructuredGridPiece {
        points: IOBuffer::F64(flat(s.iter().map(|c| c.point))),
        cells: Cells {
            cell_verts: VertexNumbers::XML { connectivity: (0..n as u64).collect(), offsets: (1..=n as u64).collect() },
            types: vec![CellType::Vertex; n],
        },
        data: Attributes { point, cell: vec![] },
    })
}

fn write_vtu(path: &Path, data: Vtk) -> Result<(), SeriesError> {
    let mut bytes = Vec::new();
    data.write_xml(&mut bytes).map_err(|e| SeriesError::Vtk { path: path.to_owned(), message: e.to_string() })?;
    Ok(replace_file(path, &bytes)?)
}

/// Checks before a run that a series can be written into `dir`: the directory is made
/// (as [`write_series`] makes it) and a file written there and removed, so that a path
/// that cannot hold the series (a file, a read-only place) is refused before the run
/// rather than after it.
///
/// # Errors
/// [`FileError`] naming `dir` (or the probe file in it).
pub fn check_series_dir(dir: &Path) -> Result<(), FileError> {
    std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
    let probe = dir.join(format!(".drystone-series-check-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(FileError::at(&probe))?;
    std::fs::remove_file(&probe).map_err(FileError::at(&probe))
}

/// Writes the series `frames` of `rec` into `dir` (created if missing) as `NAME.pvd` and two
/// `.vtu` files per frame (module documentation). Returns the `.pvd` path.
///
/// # Errors
/// [`SeriesError::File`] naming the file that could not be written or the directory that
/// could not be created.
pub fn write_series(dir: &Path, name: &str, rec: &Recorder, frames: &[Frame]) -> Result<PathBuf, SeriesError> {
    std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
    let mut pvd = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (k, f) in frames.iter().enumerate() {
        let blocks = format!("{name}_blocks_{k:04}.vtu");
        let contacts = format!("{name}_contacts_{k:04}.vtu");
        write_vtu(&dir.join(&blocks), blocks_grid(rec, f))?;
        write_vtu(&dir.join(&contacts), contacts_grid(&rec.states[f.state]))?;
        let t = rec.states[f.state].time;
        let _ = writeln!(pvd, "    <DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{blocks}\"/>");
        let _ = writeln!(pvd, "    <DataSet timestep=\"{t}\" group=\"\" part=\"1\" file=\"{contacts}\"/>");
    }
    pvd.push_str("  </Collection>\n</VTKFile>\n");
    let path = dir.join(format!("{name}.pvd"));
    replace_file(&path, pvd.as_bytes())?;
    Ok(path)
}
