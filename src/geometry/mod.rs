//! Convex polyhedral blocks: hulls, faces, mass properties, bounding boxes, frames.
//!
//! # Frames
//!
//! * **Table frame** (also called the *layout frame* or *world frame*): x along the wall, y out
//!   of plane (positive = the side the wall falls to when the table tilts), z up, normal to the
//!   table. The table surface is the plane z = 0. Block vertices in a layout file are given in
//!   this frame, in metres.
//! * **Body frame** of a block: origin at the block's centroid, axes parallel to the table
//!   frame *in the reference configuration* (the layout as read). A block's pose is the
//!   translation of its centroid and the rotation `R` taking body-frame vectors to the table
//!   frame: `x_world = c + R x_body`.
//!
//! The hull itself is computed with parry3d (`transformation::try_convex_hull`, quickhull);
//! coplanar hull triangles are merged into polygonal faces here, because the contact
//! detection of the DEM works with true faces (3DEC's face–face, edge–face, vertex–face
//! contacts, Cundall 1988; Hart, Cundall & Lemos 1988).

pub mod hull;
pub mod polygon;
pub mod sat;
pub mod sweep;

use crate::math::Vec3;
use nalgebra::Matrix3;
use parry3d_f64::math::Vector as PVec;
use thiserror::Error;

/// Errors in building a convex block.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum GeometryError {
    /// Fewer than 4 vertices, or all vertices (nearly) coplanar: no volume.
    #[error("needs at least 4 non-coplanar vertices (got {count} vertices spanning no volume)")]
    Degenerate {
        /// Number of vertices given.
        count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {index} has a non-finite coordinate {value:?}")]
    NonFinite {
        /// Index of the offending vertex in the input list.
        index: usize,
        /// The vertex as given.
        value: [f64; 3],
    },
    /// A vertex lies strictly inside the convex hull of the others: the block as given is not
    /// a convex polyhedron (or lists an interior point).
    #[error("not convex: vertex {index} {value:?} lies {depth_m:.3e} m inside the hull of the others")]
    NotConvex {
        /// Index of the offending vertex in the input list.
        index: usize,
        /// The vertex as given.
        value: [f64; 3],
        /// Depth of the vertex below the hull surface, m.
        depth_m: f64,
    },
    /// The hull algorithm failed.
    #[error("convex hull failed: {0}")]
    Hull(String),
}

/// A planar face of a convex block.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// Indices into [`ConvexBlock::vertices`], counter-clockwise seen from outside
    /// (right-handed about `normal`). At least 3.
    pub vertices: Vec<usize>,
    /// Outward unit normal, in the frame of the block's vertices.
    pub normal: Vec3,
    /// Plane offset: `normal · x = offset` for every point x of the face, m.
    pub offset: f64,
}

/// Mass properties of a homogeneous block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Volume, m³.
    pub volume: f64,
    /// Mass, kg (`density × volume`).
    pub mass: f64,
    /// Centroid in the frame of the vertices, m.
    pub centroid: Vec3,
    /// Inertia tensor about the centroid, axes of the vertex frame, kg·m².
    pub inertia: Matrix3<f64>,
}

/// Axis-aligned bounding box, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// Bounding box of a point set. Panics never; an empty set gives an inverted box.
    pub fn from_points<'a>(pts: impl IntoIterator<Item = &'a Vec3>) -> Self {
        let mut min = Vec3::repeat(f64::INFINITY);
        let mut max = Vec3::repeat(f64::NEG_INFINITY);
        for p in pts {
            min = min.inf(p);
            max = max.sup(p);
        }
        Aabb { min, max }
    }

    /// True if the boxes, each grown by `margin` (m) on every side, overlap.
    pub fn overlaps(&self, other: &Aabb, margin: f64) -> bool {
        (0..3).all(|k| self.min[k] - margin <= other.max[k] && other.min[k] - margin <= self.max[k])
    }

    /// Edge lengths, m.
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }
}

/// A convex polyhedron given by its hull vertices and polygonal faces.
///
/// Built from any vertex list by [`ConvexBlock::from_vertices`]; coordinates in metres in the
/// frame the caller uses (the table frame for a layout, the body frame inside the DEM).
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexBlock {
    /// Hull vertices, m.
    pub vertices: Vec<Vec3>,
    /// Polygonal faces, outward normals.
    pub faces: Vec<Face>,
    /// Unique edges as pairs of vertex indices (i < j).
    pub edges: Vec<(usize, usize)>,
    /// The two faces that meet at each edge, in the order of [`ConvexBlock::edges`] (the
    /// edge's arc on the Gauss map, used by the separating-axis test).
    pub edge_faces: Vec<[usize; 2]>,
}

fn to_p(v: &Vec3) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

fn from_p(v: &PVec) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

impl ConvexBlock {
    /// Builds the convex block whose hull is the given vertices.
    ///
    /// Every input vertex must lie on the hull surface (within `1e-9 × size`), otherwise the
    /// input is not a convex polyhedron and [`GeometryError::NotConvex`] names the vertex.
    /// Duplicate vertices are allowed and merged.
    ///
    /// # Errors
    /// [`GeometryError::NonFinite`], [`GeometryError::Degenerate`], [`GeometryError::NotConvex`].
    pub fn from_vertices(input: &[Vec3]) -> Result<Self, GeometryError> {
        for (i, v) in input.iter().enumerate() {
            if !v.iter().all(|c| c.is_finite()) {
                return Err(GeometryError::NonFinite { index: i, value: [v.x, v.y, v.z] });
            }
        }
        if input.len() < 4 {
            return Err(GeometryError::Degenerate { count: input.len() });
        }
        let bb = Aabb::from_points(input);
        let size = bb.extent().norm();
        if size <= 0.0 {
            return Err(GeometryError::Degenerate { count: input.len() });
        }
        // Volume check before the hull: the largest tetrahedron spanned must have volume.
        if !spans_volume(input, size) {
            return Err(GeometryError::Degenerate { count: input.len() });
        }
        let pts: Vec<PVec> = input.iter().map(to_p).collect();
        let (hv, tris) =
            parry3d_f64::transformation::try_convex_hull(&pts).map_err(|e| GeometryError::Hull(format!("{e:?}")))?;
        if tris.len() < 4 {
            return Err(GeometryError::Degenerate { count: input.len() });
        }
        let mut hull_vertices: Vec<Vec3> = hv.iter().map(from_p).collect();
        let tol = 1e-9 * size.max(1e-12);
        let mut faces = merge_coplanar(&hull_vertices, &tris, tol)?;
        if !hull_is_valid(&hull_vertices, &faces, 1e-7 * size) {
            // Quickhull can return inconsistent triangles on thin slivers: rebuild the faces
            // from the supporting planes of the input points.
            let mut pts: Vec<Vec3> = Vec::new();
            for p in input {
                if !pts.iter().any(|q| (q - p).norm() <= tol) {
                    pts.push(*p);
                }
            }
            faces = faces_from_planes(&pts, brute_force_planes(&pts, 1e-9 * size), tol)?;
            hull_vertices = pts;
            if !hull_is_valid(&hull_vertices, &faces, 1e-7 * size) {
                return Err(GeometryError::Hull("no consistent convex hull (degenerate sliver?)".into()));
            }
        }
        // Keep only vertices used by faces, re-index.
        let mut used = vec![usize::MAX; hull_vertices.len()];
        let mut vertices = Vec::new();
        let mut faces_out = Vec::with_capacity(faces.len());
        for f in faces {
            let idx = f
                .vertices
                .iter()
                .map(|&i| {
                    if used[i] == usize::MAX {
                        used[i] = vertices.len();
                        vertices.push(hull_vertices[i]);
                    }
                    used[i]
                })
                .collect();
            faces_out.push(Face { vertices: idx, normal: f.normal, offset: f.offset });
        }
        let block = ConvexBlock::from_parts(vertices, faces_out);
        // Convexity of the input: every input vertex on the hull surface, its depth the
        // smallest `offset − normal · v` over the faces. A vertex of the hull that is within
        // the tolerance of one of its own faces passes without the others (the smallest over
        // all faces is no larger); only the input's other points are measured against every
        // face.
        let deep = 1e-7 * size.max(1e-12);
        let bits = |v: &Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
        let mut hull_keys: Vec<([u64; 3], usize)> =
            block.vertices.iter().enumerate().map(|(i, v)| (bits(v), i)).collect();
        hull_keys.sort_unstable();
        let mut faces_at: Vec<Vec<usize>> = vec![Vec::new(); block.vertices.len()];
        for (fi, f) in block.faces.iter().enumerate() {
            for &i in &f.vertices {
                faces_at[i].push(fi);
            }
        }
        for (i, v) in input.iter().enumerate() {
            if let Ok(k) = hull_keys.binary_search_by(|e| e.0.cmp(&bits(v))) {
                let own = &faces_at[hull_keys[k].1];
                if own.iter().any(|&fi| block.faces[fi].offset - block.faces[fi].normal.dot(v) <= deep) {
                    continue;
                }
            }
            let depth = block.signed_distance(v);
            if depth > deep {
                return Err(GeometryError::NotConvex { index: i, value: [v.x, v.y, v.z], depth_m: depth });
            }
        }
        Ok(block)
    }

    /// The convex block spanned by `points`: their convex hull (parry3d's quickhull), the
    /// points inside it dropped. Unlike [`ConvexBlock::from_vertices`], the points need not
    /// all lie on the hull: this is the block of a non-convex shape (a scanned stone's mesh)
    /// taken as its hull.
    ///
    /// # Errors
    /// [`GeometryError::NonFinite`], [`GeometryError::Hull`], and those of
    /// [`ConvexBlock::from_vertices`] on the hull's vertices.
    pub fn hull_of(points: &[Vec3]) -> Result<Self, GeometryError> {
        if let Some((i, v)) = points.iter().enumerate().find(|(_, v)| !v.iter().all(|c| c.is_finite())) {
            return Err(GeometryError::NonFinite { index: i, value: [v.x, v.y, v.z] });
        }
        let pts: Vec<PVec> = points.iter().map(to_p).collect();
        let (hv, _) =
            parry3d_f64::transformation::try_convex_hull(&pts).map_err(|e| GeometryError::Hull(format!("{e:?}")))?;
        ConvexBlock::from_vertices(&hv.iter().map(from_p).collect::<Vec<_>>())
    }

    fn from_parts(vertices: Vec<Vec3>, faces: Vec<Face>) -> Self {
        let mut edges = Vec::new();
        for f in &faces {
            let n = f.vertices.len();
            for k in 0..n {
                let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
                let e = if a < b { (a, b) } else { (b, a) };
                edges.push(e);
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let mut edge_faces = vec![[usize::MAX; 2]; edges.len()];
        for (fi, f) in faces.iter().enumerate() {
            let n = f.vertices.len();
            for k in 0..n {
                let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
                let e = if a < b { (a, b) } else { (b, a) };
                if let Ok(i) = edges.binary_search(&e) {
                    let slot = if edge_faces[i][0] == usize::MAX { 0 } else { 1 };
                    edge_faces[i][slot] = fi;
                }
            }
        }
        ConvexBlock { vertices, faces, edges, edge_faces }
    }

    /// Axis-aligned box with corners `min` and `max` (m).
    ///
    /// # Errors
    /// [`GeometryError::Degenerate`] if any edge length is not positive.
    pub fn cuboid(min: Vec3, max: Vec3) -> Result<Self, GeometryError> {
        let mut v = Vec::with_capacity(8);
        for &z in &[min.z, max.z] {
            for &y in &[min.y, max.y] {
                for &x in &[min.x, max.x] {
                    v.push(Vec3::new(x, y, z));
                }
            }
        }
        if (0..3).any(|k| max[k] - min[k] <= 0.0 || !(max[k] - min[k]).is_finite()) {
            return Err(GeometryError::Degenerate { count: 8 });
        }
        Self::from_vertices(&v)
    }

    /// Prism along x with a trapezoidal cross-section in the y–z plane.
    ///
    /// The section has its bottom edge from `y_bottom.0` to `y_bottom.1` at `z0` and its top
    /// edge from `y_top.0` to `y_top.1` at `z1`, and the prism spans `x0..x1`. All in m.
    /// A wall's symmetric batter with base B and top b centred on y = 0 is
    /// `y_bottom = (-B/2, B/2)`, `y_top = (-b/2, b/2)`.
    ///
    /// # Errors
    /// [`GeometryError::Degenerate`] for zero length, height or width.
    pub fn trapezoidal_prism(
        x0: f64,
        x1: f64,
        z0: f64,
        z1: f64,
        y_bottom: (f64, f64),
        y_top: (f64, f64),
    ) -> Result<Self, GeometryError> {
        let mut v = Vec::with_capacity(8);
        for &x in &[x0, x1] {
            v.push(Vec3::new(x, y_bottom.0, z0));
            v.push(Vec3::new(x, y_bottom.1, z0));
            v.push(Vec3::new(x, y_top.1, z1));
            v.push(Vec3::new(x, y_top.0, z1));
        }
        Self::from_vertices(&v)
    }

    /// Signed distance-like measure of a point to the hull: the minimum over faces of
    /// `offset − normal · p` (m). Positive inside, zero on the surface, negative outside
    /// (outside it is a lower bound of the true distance's magnitude).
    pub fn signed_distance(&self, p: &Vec3) -> f64 {
        self.faces.iter().map(|f| f.offset - f.normal.dot(p)).fold(f64::INFINITY, f64::min)
    }

    /// Mass properties for a homogeneous density (kg/m³), by decomposition into tetrahedra
    /// from an interior point (exact for polyhedra; Tonon 2004, "Explicit exact formulas for
    /// the 3-D tetrahedron inertia tensor in terms of its vertex coordinates").
    pub fn mass_properties(&self, density: f64) -> MassProperties {
        let o = self.vertices.iter().sum::<Vec3>() / self.vertices.len() as f64;
        let triangles = self
            .faces
            .iter()
            .flat_map(|f| (1..f.vertices.len() - 1).map(move |k| [f.vertices[0], f.vertices[k], f.vertices[k + 1]]));
        let sums = TetraSums::of(&self.vertices, o, triangles);
        sums.mass_properties(o, density)
    }

    /// Volume, m³.
    pub fn volume(&self) -> f64 {
        self.mass_properties(1.0).volume
    }

    /// Bounding box of the vertices.
    pub fn aabb(&self) -> Aabb {
        Aabb::from_points(&self.vertices)
    }

    /// The same block with every vertex mapped by `f` (a rigid motion keeps it convex; the
    /// face normals are recomputed).
    pub fn transformed(&self, f: impl Fn(&Vec3) -> Vec3, rot: &Matrix3<f64>) -> ConvexBlock {
        let vertices: Vec<Vec3> = self.vertices.iter().map(&f).collect();
        let faces = self
            .faces
            .iter()
            .map(|fc| {
                let normal = rot * fc.normal;
                let offset = normal.dot(&vertices[fc.vertices[0]]);
                Face { vertices: fc.vertices.clone(), normal, offset }
            })
            .collect();
        ConvexBlock { vertices, faces, edges: self.edges.clone(), edge_faces: self.edge_faces.clone() }
    }
}

/// The sums over the signed tetrahedra `(o, p₀, p₁, p₂)` of a closed surface's triangles:
/// volume, first moment and second moment `∫ x xᵀ dV`, all about `o`.
#[derive(Clone, Copy)]
struct TetraSums {
    vol: f64,
    first: Vec3,
    second: Matrix3<f64>,
}

impl TetraSums {
    fn of(vertices: &[Vec3], o: Vec3, triangles: impl Iterator<Item = [usize; 3]>) -> TetraSums {
        let mut vol = 0.0;
        let mut first = Vec3::zeros();
        // Second moment  ∫ x xᵀ dV  about o.
        let mut second = Matrix3::zeros();
        for [a, b, c] in triangles {
            let p0 = vertices[a] - o;
            let p1 = vertices[b] - o;
            let p2 = vertices[c] - o;
            let v = p0.dot(&p1.cross(&p2)) / 6.0;
            vol += v;
            first += v * (p0 + p1 + p2) / 4.0;
            // ∫ x xᵀ over tetra (0,p0,p1,p2) = v/20 (Σ pi piᵀ + (Σ pi)(Σ pi)ᵀ)
            let s = p0 + p1 + p2;
            let c = p0 * p0.transpose() + p1 * p1.transpose() + p2 * p2.transpose() + s * s.transpose();
            second += c * (v / 20.0);
        }
        TetraSums { vol, first, second }
    }

    /// The mass properties at `density` of the solid the sums describe about `o`.
    fn mass_properties(&self, o: Vec3, density: f64) -> MassProperties {
        let TetraSums { vol, first, second } = *self;
        let centroid_rel = first / vol;
        // Shift the second moment to the centroid.
        let second_c = second - centroid_rel * centroid_rel.transpose() * vol;
        let inertia = (Matrix3::identity() * second_c.trace() - second_c) * density;
        MassProperties { volume: vol, mass: vol * density, centroid: o + centroid_rel, inertia }
    }
}

/// Mass properties of the solid a closed triangle mesh encloses, for a homogeneous density
/// (kg/m³): volume (m³), mass (kg), centroid (m, the vertices' frame) and inertia tensor
/// about the centroid (kg·m², the vertices' axes). The mesh need not be convex.
///
/// By the divergence theorem: the solid is the signed sum of the tetrahedra joining a
/// reference point (the vertices' mean, for round-off; any point gives the same sums) to
/// each triangle, whose volume, first and second moments are exact polynomials of the
/// corners (Mirtich 1996, "Fast and accurate computation of polyhedral mass properties",
/// J. Graphics Tools 1(2); Eberly, "Polyhedral Mass Properties (Revisited)", Geometric
/// Tools 2002; each tetrahedron's second moment by Tonon 2004).
///
/// `triangles` index `vertices`; the mesh must be closed and consistently oriented (every
/// edge met once in each direction), which is not checked here. Either orientation is
/// accepted: an inward-oriented mesh's signed sums are negated. An open or inconsistently
/// oriented mesh gives meaningless figures; a mesh enclosing no volume gives a zero volume
/// and a non-finite centroid.
pub fn mesh_mass_properties(vertices: &[Vec3], triangles: &[[usize; 3]], density: f64) -> MassProperties {
    let o = if vertices.is_empty() { Vec3::zeros() } else { vertices.iter().sum::<Vec3>() / vertices.len() as f64 };
    let mut sums = TetraSums::of(vertices, o, triangles.iter().copied());
    if sums.vol < 0.0 {
        sums = TetraSums { vol: -sums.vol, first: -sums.first, second: -sums.second };
    }
    sums.mass_properties(o, density)
}

fn spans_volume(pts: &[Vec3], size: f64) -> bool {
    // Farthest pair, then the point farthest from that line, then from that plane.
    let p0 = pts[0];
    let p1 = *pts.iter().max_by(|a, b| (*a - p0).norm().total_cmp(&(*b - p0).norm())).unwrap_or(&p0);
    let d = p1 - p0;
    if d.norm() <= 1e-9 * size {
        return false;
    }
    let p2 =
        *pts.iter().max_by(|a, b| d.cross(&(*a - p0)).norm().total_cmp(&d.cross(&(*b - p0)).norm())).unwrap_or(&p0);
    let n = d.cross(&(p2 - p0));
    if n.norm() <= 1e-9 * size * size {
        return false;
    }
    let nn = n.normalize();
    pts.iter().any(|p| nn.dot(&(p - p0)).abs() > 1e-7 * size)
}

/// Groups hull triangles into polygonal faces by plane ([`hull::coplanar_planes`]), and
/// orders each face's vertices counter-clockwise about the outward normal.
fn merge_coplanar(v: &[Vec3], tris: &[[u32; 3]], tol: f64) -> Result<Vec<Face>, GeometryError> {
    faces_from_planes(v, hull::coplanar_planes(v, tris, tol), tol)
}

/// Supporting planes of a small point set by brute force: every plane through three points
/// with all points on one side (within `tol`) is a face plane. O(n⁴), exact up to `tol`; the
/// fallback when the quickhull result fails validation (it can, on thin slivers).
fn brute_force_planes(v: &[Vec3], tol: f64) -> Vec<(Vec3, f64, Vec<usize>)> {
    let n = v.len();
    let mut planes: Vec<(Vec3, f64, Vec<usize>)> = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let nrm = (v[j] - v[i]).cross(&(v[k] - v[i]));
                let len = nrm.norm();
                if len <= 1e-300 {
                    continue;
                }
                for sign in [1.0, -1.0] {
                    let nn = nrm * (sign / len);
                    let off = nn.dot(&v[i]);
                    if v.iter().all(|p| nn.dot(p) <= off + tol)
                        && !planes.iter().any(|(pn, po, _)| pn.dot(&nn) > 1.0 - 1e-9 && (po - off).abs() <= 10.0 * tol)
                    {
                        let on: Vec<usize> = (0..n).filter(|&m| (nn.dot(&v[m]) - off).abs() <= tol).collect();
                        planes.push((nn, off, on));
                    }
                }
            }
        }
    }
    planes
}

/// A hull is valid if its faces bound a convex polyhedron within `tol` (m): a closed,
/// consistently oriented topological sphere, locally convex at every edge and vertex
/// ([`hull::is_convex_polyhedron`], which proves convexity without testing every vertex
/// against every face), and the points of `vertices` no face uses (collinear or coplanar
/// points the faces dropped) lie behind every face.
fn hull_is_valid(vertices: &[Vec3], faces: &[Face], tol: f64) -> bool {
    if !hull::is_convex_polyhedron(vertices, faces, tol) {
        return false;
    }
    let mut used = vec![false; vertices.len()];
    faces.iter().flat_map(|f| &f.vertices).for_each(|&i| used[i] = true);
    let behind = |p: &Vec3| faces.iter().all(|f| f.normal.dot(p) <= f.offset + tol);
    vertices.iter().zip(&used).all(|(p, &u)| u || behind(p))
}

fn faces_from_planes(v: &[Vec3], faces: Vec<(Vec3, f64, Vec<usize>)>, tol: f64) -> Result<Vec<Face>, GeometryError> {
    if faces.len() < 4 {
        return Err(GeometryError::Degenerate { count: v.len() });
    }
    let mut out = Vec::with_capacity(faces.len());
    for (n, _, mut idx) in faces {
        // Refit the plane through the face's vertices along the merged normal.
        let fc = idx.iter().map(|&i| v[i]).sum::<Vec3>() / idx.len() as f64;
        let (u, w) = polygon::plane_basis(&n);
        idx.sort_by(|&i, &j| {
            let (pi, pj) = (v[i] - fc, v[j] - fc);
            let ai = pi.dot(&w).atan2(pi.dot(&u));
            let aj = pj.dot(&w).atan2(pj.dot(&u));
            ai.total_cmp(&aj)
        });
        // Drop vertices collinear with their neighbours (edge midpoints of the hull).
        let pts2: Vec<[f64; 2]> = idx.iter().map(|&i| [(v[i] - fc).dot(&u), (v[i] - fc).dot(&w)]).collect();
        let keep = polygon::strictly_convex_indices(&pts2, tol);
        let idx: Vec<usize> = keep.into_iter().map(|k| idx[k]).collect();
        if idx.len() < 3 {
            continue;
        }
        let offset = idx.iter().map(|&i| n.dot(&v[i])).sum::<f64>() / idx.len() as f64;
        out.push(Face { vertices: idx, normal: n, offset });
    }
    // Deterministic face order: by normal components then offset.
    out.sort_by(|a, b| {
        let ka = (a.normal.z, a.normal.y, a.normal.x, a.offset);
        let kb = (b.normal.z, b.normal.y, b.normal.x, b.offset);
        ka.partial_cmp(&kb).unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn box_mass_properties_match_closed_form() {
        let (a, b, c) = (0.2, 0.1, 0.05);
        let blk = ConvexBlock::cuboid(Vec3::new(1.0, -0.5, 0.0), Vec3::new(1.0 + a, -0.5 + b, c)).unwrap();
        assert_eq!(blk.vertices.len(), 8);
        assert_eq!(blk.faces.len(), 6);
        assert_eq!(blk.edges.len(), 12);
        let rho = 2400.0;
        let mp = blk.mass_properties(rho);
        let m = rho * a * b * c;
        assert_relative_eq!(mp.volume, a * b * c, max_relative = 1e-12);
        assert_relative_eq!(mp.centroid, Vec3::new(1.0 + a / 2.0, -0.5 + b / 2.0, c / 2.0), epsilon = 1e-12);
        assert_relative_eq!(mp.inertia[(0, 0)], m * (b * b + c * c) / 12.0, max_relative = 1e-10);
        assert_relative_eq!(mp.inertia[(1, 1)], m * (a * a + c * c) / 12.0, max_relative = 1e-10);
        assert_relative_eq!(mp.inertia[(2, 2)], m * (a * a + b * b) / 12.0, max_relative = 1e-10);
        assert!(mp.inertia[(0, 1)].abs() < 1e-12 * m);
    }

    #[test]
    fn trapezoid_prism_centroid_and_inertia_match_closed_form() {
        // Section: bottom width B at z=0, top width T at z=H, symmetric; length L along x.
        let (bw, tw, h, l) = (0.15, 0.077, 0.375, 1.5);
        let blk = ConvexBlock::trapezoidal_prism(0.0, l, 0.0, h, (-bw / 2.0, bw / 2.0), (-tw / 2.0, tw / 2.0)).unwrap();
        assert_eq!(blk.faces.len(), 6);
        let mp = blk.mass_properties(1.0);
        let area = (bw + tw) / 2.0 * h;
        assert_relative_eq!(mp.volume, area * l, max_relative = 1e-12);
        let zc = h * (bw + 2.0 * tw) / (3.0 * (bw + tw));
        assert_relative_eq!(mp.centroid.z, zc, max_relative = 1e-12);
        assert!(mp.centroid.y.abs() < 1e-14);
        // Second moment of area of a trapezoid about its centroidal axis parallel to the bases:
        // I = h³ (B² + 4BT + T²) / (36 (B + T)).
        let iy = h.powi(3) * (bw * bw + 4.0 * bw * tw + tw * tw) / (36.0 * (bw + tw));
        let izz_section = mp.inertia[(1, 1)] - mp.volume * l * l / 12.0; // ∫ z² dV part
        assert_relative_eq!(izz_section, iy * l, max_relative = 1e-10);
    }

    #[test]
    fn mass_properties_agree_with_parry_for_an_irregular_block() {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.21, 0.01, 0.0),
            Vec3::new(0.19, 0.14, 0.02),
            Vec3::new(-0.01, 0.12, 0.0),
            Vec3::new(0.02, 0.01, 0.07),
            Vec3::new(0.2, 0.0, 0.06),
            Vec3::new(0.18, 0.15, 0.09),
            Vec3::new(0.0, 0.13, 0.05),
        ];
        let blk = ConvexBlock::from_vertices(&pts).unwrap();
        let mp = blk.mass_properties(1000.0);
        let pp: Vec<PVec> = pts.iter().map(to_p).collect();
        let poly = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&pp).unwrap();
        let pm = parry3d_f64::mass_properties::MassProperties::from_convex_polyhedron(
            1000.0,
            poly.points(),
            &parry3d_f64::transformation::convex_hull(&pp).1,
        );
        assert_relative_eq!(mp.mass, pm.mass(), max_relative = 1e-9);
        let c = pm.local_com;
        assert_relative_eq!(mp.centroid, Vec3::new(c.x, c.y, c.z), epsilon = 1e-12);
        // Principal moments agree.
        let mut ours: Vec<f64> = mp.inertia.symmetric_eigenvalues().iter().copied().collect();
        ours.sort_by(f64::total_cmp);
        let pi = pm.principal_inertia();
        let mut theirs = [pi.x, pi.y, pi.z];
        theirs.sort_by(f64::total_cmp);
        for k in 0..3 {
            assert_relative_eq!(ours[k], theirs[k], max_relative = 1e-8);
        }
    }

    #[test]
    fn non_convex_and_degenerate_inputs_are_rejected() {
        let mut pts: Vec<Vec3> = ConvexBlock::cuboid(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0)).unwrap().vertices;
        pts.push(Vec3::new(0.5, 0.5, 0.5));
        assert!(matches!(ConvexBlock::from_vertices(&pts), Err(GeometryError::NotConvex { index: 8, .. })));
        let flat = vec![Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::new(1.0, 1.0, 0.0)];
        assert!(matches!(ConvexBlock::from_vertices(&flat), Err(GeometryError::Degenerate { .. })));
        let three = vec![Vec3::zeros(), Vec3::x(), Vec3::y()];
        assert!(matches!(ConvexBlock::from_vertices(&three), Err(GeometryError::Degenerate { .. })));
        let nan = vec![Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::new(f64::NAN, 0.0, 1.0)];
        assert!(matches!(ConvexBlock::from_vertices(&nan), Err(GeometryError::NonFinite { index: 3, .. })));
    }

    #[test]
    fn the_hull_of_a_non_convex_point_set_drops_its_inner_points() {
        // A unit cube with two points inside it: the hull is the cube.
        let mut pts: Vec<Vec3> = ConvexBlock::cuboid(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0)).unwrap().vertices;
        pts.push(Vec3::new(0.5, 0.5, 0.5));
        pts.push(Vec3::new(0.5, 0.5, 0.9));
        let blk = ConvexBlock::hull_of(&pts).unwrap();
        assert_eq!(blk.vertices.len(), 8);
        assert_eq!(blk.faces.len(), 6);
        assert_relative_eq!(blk.volume(), 1.0, epsilon = 1e-12);
        pts.push(Vec3::new(f64::NAN, 0.0, 0.0));
        assert!(matches!(ConvexBlock::hull_of(&pts), Err(GeometryError::NonFinite { index: 10, .. })));
    }

    #[test]
    fn thin_sliver_gets_a_valid_hull_and_its_true_volume() {
        // A sliver wedge for which quickhull returns inconsistent triangles (found by the
        // generator): a triangle A, B, C in the x–z plane whose half-width in y is linear.
        let (a, b, c) = (
            (0.24980422391327317, 0.04531873824754805, 0.22501931971624725),
            (0.24980422391327317, 0.04573339409453124, 0.22463118616890096),
            (0.19620242069766625, 0.022864852626500776, 0.24603700544577842),
        );
        let pts: Vec<Vec3> =
            [a, b, c].iter().flat_map(|&(x, z, hw)| [Vec3::new(x, -hw, z), Vec3::new(x, hw, z)]).collect();
        let blk = ConvexBlock::from_vertices(&pts).unwrap();
        assert!(hull_is_valid(&blk.vertices, &blk.faces, 1e-12));
        // Volume = area of the x–z triangle × 2 × mean half-width (linear over the triangle).
        let area = 0.5 * ((b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)).abs();
        let exact = area * 2.0 * (a.2 + b.2 + c.2) / 3.0;
        assert_relative_eq!(blk.volume(), exact, max_relative = 1e-9);
    }

    #[test]
    fn faces_are_ccw_about_outward_normals() {
        let blk = ConvexBlock::trapezoidal_prism(0.0, 1.0, 0.0, 0.4, (-0.1, 0.1), (-0.05, 0.05)).unwrap();
        for f in &blk.faces {
            let p: Vec<Vec3> = f.vertices.iter().map(|&i| blk.vertices[i]).collect();
            let mut area = Vec3::zeros();
            for k in 1..p.len() - 1 {
                area += (p[k] - p[0]).cross(&(p[k + 1] - p[0]));
            }
            assert!(area.dot(&f.normal) > 0.0);
            for q in &p {
                assert!((f.normal.dot(q) - f.offset).abs() < 1e-12);
            }
        }
    }

    // ---- the local hull code against the global definitions ----

    /// The definition the edge-adjacent merge must reproduce: each hull triangle searched
    /// against every face already made (O(T²)).
    fn merge_coplanar_by_search(v: &[Vec3], tris: &[[u32; 3]], tol: f64) -> Result<Vec<Face>, GeometryError> {
        let centre = v.iter().sum::<Vec3>() / v.len() as f64;
        let mut faces: Vec<(Vec3, f64, Vec<usize>)> = Vec::new();
        for t in tris {
            let (a, b, c) = (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
            let nrm = (b - a).cross(&(c - a));
            if nrm.norm() == 0.0 {
                continue;
            }
            let mut n = nrm.normalize();
            if n.dot(&(a - centre)) < 0.0 {
                n = -n;
            }
            let off = n.dot(&a);
            if let Some(f) = faces
                .iter_mut()
                .find(|(fn_, fo, _)| fn_.dot(&n) > 1.0 - 1e-9 && (fo - off).abs() <= tol.max(1e-12) * 10.0)
            {
                for &i in t {
                    if !f.2.contains(&(i as usize)) {
                        f.2.push(i as usize);
                    }
                }
            } else {
                faces.push((n, off, t.iter().map(|&i| i as usize).collect()));
            }
        }
        faces_from_planes(v, faces, tol)
    }

    /// The global definition of a valid hull the local proof must agree with: every vertex
    /// behind every face (within `tol`, O(V·F)), each edge met twice, V − E + F = 2.
    fn every_vertex_behind_every_face(vertices: &[Vec3], faces: &[Face], tol: f64) -> bool {
        let behind = faces.iter().all(|f| vertices.iter().all(|p| f.normal.dot(p) <= f.offset + tol));
        let mut edges: Vec<(usize, usize)> = faces
            .iter()
            .flat_map(|f| {
                let n = f.vertices.len();
                (0..n).map(move |k| {
                    let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
                    (a.min(b), a.max(b))
                })
            })
            .collect();
        let half_edges = edges.len();
        edges.sort_unstable();
        edges.dedup();
        let used: std::collections::BTreeSet<usize> = faces.iter().flat_map(|f| f.vertices.iter().copied()).collect();
        behind && half_edges == 2 * edges.len() && used.len() as i64 - edges.len() as i64 + faces.len() as i64 == 2
    }

    /// Random point sets of the shapes the generator and the survey make: boxes cut by
    /// random planes, points on a sphere, a cube with its faces gridded (many coplanar
    /// triangles), slivers and near-duplicates.
    fn differential_cases() -> Vec<Vec<Vec3>> {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
        let mut cases = Vec::new();
        for _ in 0..300 {
            let c = Vec3::new(rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0), rng.random_range(0.0..3.0));
            let e = Vec3::new(rng.random_range(0.05..0.6), rng.random_range(0.05..0.4), rng.random_range(0.03..0.3));
            let mut pts: Vec<Vec3> = (0..8)
                .map(|k| c + Vec3::new(e.x * (k & 1) as f64, e.y * ((k >> 1) & 1) as f64, e.z * ((k >> 2) & 1) as f64))
                .collect();
            for p in pts.iter_mut() {
                *p += Vec3::new(rng.random_range(-0.2..0.2), 0.0, rng.random_range(-0.2..0.2)).component_mul(&e);
            }
            cases.push(pts.clone());
            // A prism of a random convex section (the generator's extrusions).
            let m = rng.random_range(3..9);
            let sec: Vec<[f64; 2]> = (0..m)
                .map(|k| {
                    let a = std::f64::consts::TAU * (k as f64 + rng.random_range(0.0..0.8)) / m as f64;
                    [c.x + e.x * a.cos(), c.z + e.z * a.sin()]
                })
                .collect();
            let (y0, y1) = (c.y - e.y, c.y + e.y * rng.random_range(0.2..1.0));
            cases.push(sec.iter().flat_map(|q| [Vec3::new(q[0], y0, q[1]), Vec3::new(q[0], y1, q[1])]).collect());
        }
        for n in [20, 80, 300] {
            let pts: Vec<Vec3> = (0..n)
                .map(|_| {
                    let v = Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    v.normalize() * 0.2
                })
                .collect();
            cases.push(pts);
        }
        let mut grid = Vec::new();
        for i in 0..=4 {
            for j in 0..=4 {
                for k in 0..=4 {
                    if [i, j, k].iter().any(|&x| x == 0 || x == 4) {
                        grid.push(Vec3::new(i as f64 * 0.1, j as f64 * 0.07, k as f64 * 0.05));
                    }
                }
            }
        }
        // The grid with noise below and about the merge tolerance (1e-9 of the size): near-
        // coplanar triangles, points dropped from faces, points just outside a face.
        for noise in [1e-12, 3e-10, 2e-9] {
            let g = grid
                .iter()
                .map(|p| {
                    p + Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                        * noise
                })
                .collect();
            cases.push(g);
        }
        cases.push(grid);
        // The sliver of `thin_sliver_gets_a_valid_hull_and_its_true_volume`, on which
        // quickhull's triangles are inconsistent (both definitions must refuse them).
        let sliver = [
            (0.24980422391327317, 0.04531873824754805, 0.22501931971624725),
            (0.24980422391327317, 0.04573339409453124, 0.22463118616890096),
            (0.19620242069766625, 0.022864852626500776, 0.24603700544577842),
        ];
        cases.push(sliver.iter().flat_map(|&(x, z, hw)| [Vec3::new(x, -hw, z), Vec3::new(x, hw, z)]).collect());
        cases
    }

    #[test]
    fn edge_adjacent_merge_and_local_convexity_agree_with_the_global_definitions() {
        let (mut compared, mut refused) = (0, 0);
        for pts in differential_cases() {
            let size = Aabb::from_points(&pts).extent().norm();
            let pp: Vec<PVec> = pts.iter().map(to_p).collect();
            let (hv, tris) = parry3d_f64::transformation::try_convex_hull(&pp).unwrap();
            let hv: Vec<Vec3> = hv.iter().map(from_p).collect();
            let tol = 1e-9 * size;
            let new = merge_coplanar(&hv, &tris, tol);
            let old = merge_coplanar_by_search(&hv, &tris, tol);
            assert_eq!(new, old, "{pts:?}");
            if let Ok(faces) = new {
                for t in [1e-7 * size, 1e-12] {
                    let valid = hull_is_valid(&hv, &faces, t);
                    assert_eq!(valid, every_vertex_behind_every_face(&hv, &faces, t), "{pts:?}");
                    refused += usize::from(!valid);
                }
                compared += 1;
            }
        }
        assert!(compared > 500 && refused > 0, "{compared} {refused}");
    }

    #[test]
    fn the_local_proof_refuses_a_valley_an_open_surface_a_turned_face_and_two_cubes() {
        let cube = ConvexBlock::cuboid(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        assert!(hull_is_valid(&cube.vertices, &cube.faces, 1e-12));
        // A valley roof: the cube's top replaced by two faces sloping down to a ridge at
        // x = 0.5, z = 0.8 (a concave edge); every face planar, the surface a closed sphere.
        let mut v: Vec<Vec3> = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.]]
            .iter()
            .chain(&[[1., 1., 1.], [0., 1., 1.], [0.5, 0., 0.8], [0.5, 1., 0.8]])
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect();
        let centre = v.iter().sum::<Vec3>() / v.len() as f64;
        let face = |v: &[Vec3], mut idx: Vec<usize>| {
            // Newell's normal of the listed order, turned outwards.
            let mut n = Vec3::zeros();
            for k in 0..idx.len() {
                let (a, b) = (v[idx[k]], v[idx[(k + 1) % idx.len()]]);
                n += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
            }
            let c = idx.iter().map(|&i| v[i]).sum::<Vec3>() / idx.len() as f64;
            if n.dot(&(c - centre)) < 0.0 {
                n = -n;
                idx.reverse();
            }
            let n = n.normalize();
            Face { offset: n.dot(&v[idx[0]]), vertices: idx, normal: n }
        };
        let lists = [vec![0, 1, 2, 3], vec![0, 1, 5, 8, 4], vec![3, 2, 6, 9, 7], vec![0, 3, 7, 4], vec![1, 2, 6, 5]];
        let mut faces: Vec<Face> = lists.iter().map(|l| face(&v, l.clone())).collect();
        faces.push(face(&v, vec![4, 8, 9, 7]));
        faces.push(face(&v, vec![8, 5, 6, 9]));
        assert!(!hull_is_valid(&v, &faces, 1e-12));
        assert!(!every_vertex_behind_every_face(&v, &faces, 1e-12));
        // The same with the ridge raised to z = 1.2: a convex roof, accepted by both.
        v[8].z = 1.2;
        v[9].z = 1.2;
        let faces: Vec<Face> =
            lists.iter().chain(&[vec![4, 8, 9, 7], vec![8, 5, 6, 9]]).map(|l| face(&v, l.clone())).collect();
        assert!(hull_is_valid(&v, &faces, 1e-12));
        assert!(every_vertex_behind_every_face(&v, &faces, 1e-12));
        // Open: a face left out.
        assert!(!hull_is_valid(&cube.vertices, &cube.faces[1..], 1e-12));
        // A face reversed: the orientation is not consistent.
        let mut flipped = cube.faces.clone();
        flipped[0].vertices.reverse();
        assert!(!hull_is_valid(&cube.vertices, &flipped, 1e-12));
        // Two disjoint cubes: V − E + F = 4.
        let mut two_v = cube.vertices.clone();
        two_v.extend(cube.vertices.iter().map(|v| v + Vec3::new(3.0, 0.0, 0.0)));
        let mut two_f = cube.faces.clone();
        two_f.extend(cube.faces.iter().map(|f| Face {
            vertices: f.vertices.iter().map(|i| i + 8).collect(),
            normal: f.normal,
            offset: f.offset + 3.0 * f.normal.x,
        }));
        assert!(!hull_is_valid(&two_v, &two_f, 1e-12));
    }

    #[test]
    fn a_spread_subsample_keeps_the_extremes_and_is_deterministic() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let pts: Vec<Vec3> = (0..2000)
            .map(|_| Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-0.5..0.5), rng.random_range(-0.3..0.3)))
            .collect();
        let k = hull::spread_subsample(&pts, 100);
        assert_eq!(k.len(), 100);
        assert_eq!(k, hull::spread_subsample(&pts, 100));
        assert!(k.windows(2).all(|w| w[0] < w[1]));
        for axis in 0..3 {
            let max = pts.iter().map(|p| p[axis]).fold(f64::NEG_INFINITY, f64::max);
            assert!(k.iter().any(|&i| pts[i][axis] == max));
        }
        assert_eq!(hull::spread_subsample(&pts[..50], 100), (0..50).collect::<Vec<_>>());
    }
}
