//! From quickhull's triangles to a polyhedron's faces, the proof that the faces bound a
//! convex polyhedron, and the deterministic subsample of a hull's vertices that a vertex
//! budget keeps.
//!
//! Every step here is near-linear in the hull's size (sorting its edges), so the hull of a
//! scanned stone whose every mesh vertex is a hull vertex costs no more than reading it.

use super::Face;
use crate::math::Vec3;
use std::collections::BTreeSet;

/// Disjoint sets over `0..n` (path halving; the smaller root is kept, so the sets' roots
/// depend only on the unions made, never on their order's accidents).
struct Sets(Vec<usize>);

impl Sets {
    fn new(n: usize) -> Self {
        Sets((0..n).collect())
    }

    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.0[hi] = lo;
        }
    }
}

/// Whether two planes are one face's: unit normals within `1 − n·n' < 1e-9` (4.5e-5 rad)
/// and offsets within `offset_tol`, m.
fn same_plane(n: &Vec3, off: f64, m: &Vec3, off_m: f64, offset_tol: f64) -> bool {
    n.dot(m) > 1.0 - 1e-9 && (off - off_m).abs() <= offset_tol
}

/// Groups hull triangles into the planes of polygonal faces: each plane's outward unit
/// normal (that of its first triangle, oriented away from the vertices' mean), offset (m)
/// and vertex indices (in order of first use by its triangles, in triangle order). The
/// planes are listed in order of their first triangle.
///
/// The coplanar triangles of a convex hull's face are edge-connected (the face is a convex
/// polygon, triangulated), so the candidates for a triangle's face are found by a union
/// over the hull's shared edges: two triangles sharing an edge are joined when their planes
/// agree within twice the face tolerance (two triangles each within the tolerance of their
/// face's first triangle are within twice it of each other). Within each connected set, a
/// triangle joins the first plane of the set it agrees with (normals within
/// `1 − n·n' < 1e-9`, offsets within `10 tol`), or starts a plane. Degenerate triangles
/// (zero cross product) join no plane. Cost: sorting the 3T half-edges, O(T log T).
pub(super) fn coplanar_planes(v: &[Vec3], tris: &[[u32; 3]], tol: f64) -> Vec<(Vec3, f64, Vec<usize>)> {
    let centre = v.iter().sum::<Vec3>() / v.len() as f64;
    let offset_tol = tol.max(1e-12) * 10.0;
    let planes: Vec<Option<(Vec3, f64)>> = tris
        .iter()
        .map(|t| {
            let (a, b, c) = (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
            let nrm = (b - a).cross(&(c - a));
            if nrm.norm() == 0.0 {
                return None;
            }
            let mut n = nrm.normalize();
            if n.dot(&(a - centre)) < 0.0 {
                n = -n;
            }
            Some((n, n.dot(&a)))
        })
        .collect();
    // The triangles meeting at each edge: sort the half-edges by their undirected edge.
    let mut half: Vec<(u32, u32, usize)> = tris
        .iter()
        .enumerate()
        .flat_map(|(ti, t)| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]), ti)))
        .collect();
    half.sort_unstable();
    let mut sets = Sets::new(tris.len());
    for run in half.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        for (i, x) in run.iter().enumerate() {
            for y in &run[i + 1..] {
                if let (Some((n, o)), Some((m, p))) = (planes[x.2], planes[y.2]) {
                    // Twice the angle and twice the offset of `same_plane`: 1 − cos 2θ < 4e-9.
                    if n.dot(&m) > 1.0 - 5e-9 && (o - p).abs() <= 2.5 * offset_tol {
                        sets.union(x.2, y.2);
                    }
                }
            }
        }
    }
    let mut faces: Vec<(Vec3, f64, Vec<usize>)> = Vec::new();
    let mut members: Vec<BTreeSet<usize>> = Vec::new();
    let mut planes_of_set: Vec<Vec<usize>> = vec![Vec::new(); tris.len()];
    for (ti, t) in tris.iter().enumerate() {
        let Some((n, off)) = planes[ti] else { continue };
        let root = sets.find(ti);
        let found =
            planes_of_set[root].iter().copied().find(|&fi| same_plane(&faces[fi].0, faces[fi].1, &n, off, offset_tol));
        let fi = found.unwrap_or_else(|| {
            faces.push((n, off, Vec::new()));
            members.push(BTreeSet::new());
            planes_of_set[root].push(faces.len() - 1);
            faces.len() - 1
        });
        for &i in t {
            if members[fi].insert(i as usize) {
                faces[fi].2.push(i as usize);
            }
        }
    }
    faces
}

/// Whether `faces` (polygons on `vertices`, each counter-clockwise about its outward unit
/// normal) bound a convex polyhedron, within `tol` (m), checked locally in O(Σ deg²):
///
/// 1. **a closed surface**: every edge is shared by exactly two faces, which run along it
///    in opposite directions (consistently oriented, no boundary, no edge of three faces);
/// 2. **a topological sphere**: the faces are connected through their edges and
///    V − E + F = 2 (a closed, connected, orientable surface of Euler characteristic 2 has
///    genus 0);
/// 3. **locally convex at every edge** (the dihedral test): each vertex of either face
///    lies behind the other face's plane, within `tol`;
/// 4. **locally convex at every vertex**: the vertex's neighbours along its edges lie
///    behind the plane of every face at the vertex, within `tol` (with 3, each face at the
///    vertex is then a facet of the convex cone its edges span, so the faces go once round
///    the vertex).
///
/// A connected set that is locally convex is convex (Tietze 1928, "Über Konvexheit im
/// kleinen und im großen", Math. Z. 28, 697–707; Nakajima 1928); for surfaces, a closed
/// immersed surface that is locally convex everywhere and strictly so somewhere bounds a
/// convex body (van Heijenoort 1952, "On locally convex manifolds", Comm. Pure Appl. Math.
/// 5, 223–242). Conditions 1–4 with `tol = 0` are that hypothesis for a polyhedral sphere
/// (a face's interior points are flat, an edge's are convex by 3, a vertex by 4, and a
/// closed surface has a strictly convex vertex), so they prove the faces bound a convex
/// polyhedron without testing every vertex against every face. Faces of fewer than three
/// vertices fail.
pub(super) fn is_convex_polyhedron(vertices: &[Vec3], faces: &[Face], tol: f64) -> bool {
    if faces.iter().any(|f| f.vertices.len() < 3 || f.vertices.iter().any(|&i| i >= vertices.len())) {
        return false;
    }
    // Half-edges (edge, from, to, face), sorted by their undirected edge.
    let mut half: Vec<((usize, usize), usize, usize, usize)> = faces
        .iter()
        .enumerate()
        .flat_map(|(fi, f)| {
            let n = f.vertices.len();
            (0..n).map(move |k| {
                let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
                ((a.min(b), a.max(b)), a, b, fi)
            })
        })
        .collect();
    half.sort_unstable();
    if half.len() % 2 != 0 {
        return false;
    }
    let mut edges: Vec<((usize, usize), usize, usize)> = Vec::with_capacity(half.len() / 2);
    for pair in half.chunks_exact(2) {
        let ((e, a, b, f), (e1, a1, b1, g)) = (pair[0], pair[1]);
        if e != e1 || a == b || (a, b) != (b1, a1) || f == g || edges.last().is_some_and(|l| l.0 == e) {
            return false;
        }
        edges.push((e, f, g));
    }
    // A topological sphere: connected, V − E + F = 2.
    let mut used = vec![false; vertices.len()];
    faces.iter().flat_map(|f| &f.vertices).for_each(|&i| used[i] = true);
    let nv = used.iter().filter(|&&u| u).count();
    if nv as i64 - edges.len() as i64 + faces.len() as i64 != 2 {
        return false;
    }
    let mut sets = Sets::new(faces.len());
    for &(_, f, g) in &edges {
        sets.union(f, g);
    }
    if (0..faces.len()).any(|f| sets.find(f) != 0) {
        return false;
    }
    let behind = |f: &Face, p: &Vec3| f.normal.dot(p) <= f.offset + tol;
    // Locally convex at every edge: the dihedral test.
    for &(_, f, g) in &edges {
        let (f, g) = (&faces[f], &faces[g]);
        if !g.vertices.iter().all(|&i| behind(f, &vertices[i])) || !f.vertices.iter().all(|&i| behind(g, &vertices[i]))
        {
            return false;
        }
    }
    // Locally convex at every vertex: its neighbours behind each of its faces.
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for &((a, b), _, _) in &edges {
        neighbours[a].push(b);
        neighbours[b].push(a);
    }
    let mut faces_at: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for (fi, f) in faces.iter().enumerate() {
        for &i in &f.vertices {
            faces_at[i].push(fi);
        }
    }
    (0..vertices.len())
        .all(|v| faces_at[v].iter().all(|&fi| neighbours[v].iter().all(|&w| behind(&faces[fi], &vertices[w]))))
}

/// `k` of the points `p`, chosen deterministically to spread over them: first the extreme
/// points along the 26 directions of a cube's faces, edges and corners (±x, ±x ± y, ±x ± y
/// ± z, … : the corners and flats of a stone), then, one at a time, the point farthest from
/// those chosen (farthest-point sampling, Gonzalez 1985, "Clustering to minimize the maximum
/// intercluster distance", Theor. Comput. Sci. 38, 293–306: the chosen points cover the
/// others within twice the best radius any `k` points can). Ties go to the lower index.
/// Returns the chosen indices in increasing order; all of them when `k ≥ p.len()`. Cost
/// O(k · n).
pub fn spread_subsample(p: &[Vec3], k: usize) -> Vec<usize> {
    if k >= p.len() {
        return (0..p.len()).collect();
    }
    let mut chosen = vec![false; p.len()];
    let mut order: Vec<usize> = Vec::with_capacity(k);
    let take = |i: usize, chosen: &mut [bool], order: &mut Vec<usize>| {
        if !chosen[i] && order.len() < k {
            chosen[i] = true;
            order.push(i);
        }
    };
    for dx in [-1.0, 0.0, 1.0] {
        for dy in [-1.0, 0.0, 1.0] {
            for dz in [-1.0, 0.0, 1.0] {
                let d = Vec3::new(dx, dy, dz);
                if d == Vec3::zeros() {
                    continue;
                }
                let mut best = 0;
                for (i, q) in p.iter().enumerate() {
                    if d.dot(q) > d.dot(&p[best]) {
                        best = i;
                    }
                }
                take(best, &mut chosen, &mut order);
            }
        }
    }
    let mut dist: Vec<f64> = vec![f64::INFINITY; p.len()];
    let mut updated = 0;
    while order.len() < k {
        for &c in &order[updated..] {
            for (i, q) in p.iter().enumerate() {
                dist[i] = dist[i].min((q - p[c]).norm_squared());
            }
        }
        updated = order.len();
        let mut far = None;
        for i in 0..p.len() {
            if !chosen[i] && far.is_none_or(|f: usize| dist[i] > dist[f]) {
                far = Some(i);
            }
        }
        match far {
            Some(i) => take(i, &mut chosen, &mut order),
            None => break,
        }
    }
    order.sort_unstable();
    order
}
