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
mod tests;
