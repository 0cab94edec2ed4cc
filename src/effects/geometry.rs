//! Layout-stage effects: transformations of a checked layout's block geometry.
//!
//! Each keeps every block a convex polyhedron and never makes two blocks overlap: the
//! shear and the bed tilt are continuous maps of the whole layout (shared faces stay
//! shared), the rounding only removes material.

use crate::geometry::{ConvexBlock, GeometryError};
use crate::layout::Layout;
use crate::math::Vec3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// A failed block: its id and the reason.
pub type BlockFailure = (String, GeometryError);

/// Applies `f` to every vertex of every block and to every monitor point, and rebuilds the
/// blocks as the hulls of the moved vertices.
fn map_layout(layout: &mut Layout, f: impl Fn(&Vec3) -> Vec3) -> Result<(), BlockFailure> {
    for b in &mut layout.blocks {
        let moved: Vec<Vec3> = b.shape.vertices.iter().map(&f).collect();
        b.shape = ConvexBlock::hull_of(&moved).map_err(|e| (b.id.clone(), e))?;
    }
    for m in &mut layout.monitors {
        m.point = f(&m.point);
    }
    Ok(())
}

/// `initial_lean`: the wall built out of plumb by `psi` (rad) towards +y (the side it falls
/// to), course by course: every point moves by `z tan ψ` in y (a shear; the base stays on
/// the table). A rigid block of width b and height h then tips at `tan α = b/h − tan ψ`.
///
/// # Errors
/// The block that could not be rebuilt.
pub fn shear_out_of_plumb(layout: &mut Layout, psi: f64) -> Result<(), BlockFailure> {
    if psi == 0.0 {
        return Ok(());
    }
    let t = psi.tan();
    map_layout(layout, |p| Vec3::new(p.x, p.y + p.z * t, p.z))
}

/// `edge_rounding`: every edge and corner of every block rounded by `r` (m), as wear does:
/// the block is eroded by `r` (every face plane moved `r` inwards) and dilated again by a
/// ball of radius `r`, the ball taken as the polyhedron of the block's face normals, its
/// edge bisectors and its corner normals (a one-facet rounding of every edge and corner).
/// Flat faces stay in their planes and shrink by `r` at each edge, so every pivot of the
/// block (the edge of a face it rests on) moves `r` inwards; the rounded block lies inside
/// the original, so no overlap is made. `r` is capped at a quarter of the block's smallest
/// width. A rigid rectangular block of width b and height h then tips at
/// `tan α = (b/2 − r)/(h/2)`.
///
/// # Errors
/// The block that could not be rebuilt.
pub fn round_edges(layout: &mut Layout, r: f64) -> Result<(), BlockFailure> {
    if r <= 0.0 {
        return Ok(());
    }
    for b in &mut layout.blocks {
        b.shape = rounded(&b.shape, r).map_err(|e| (b.id.clone(), e))?;
    }
    Ok(())
}

/// The rounded block (see [`round_edges`]).
fn rounded(s: &ConvexBlock, r: f64) -> Result<ConvexBlock, GeometryError> {
    let planes: Vec<(Vec3, f64)> =
        s.faces.iter().map(|f| (f.normal, f.normal.dot(&s.vertices[f.vertices[0]]))).collect();
    let width = planes
        .iter()
        .map(|(n, d)| s.vertices.iter().map(|v| d - n.dot(v)).fold(0.0, f64::max))
        .fold(f64::INFINITY, f64::min);
    let r = r.min(0.25 * width);
    let eroded = erode(&planes, r);
    if eroded.len() < 4 {
        return Ok(s.clone());
    }
    // The ball's directions: face normals, edge bisectors, corner normals.
    let mut dirs: Vec<Vec3> = planes.iter().map(|p| p.0).collect();
    for &(i, j) in &s.edges {
        let adj: Vec<&Vec3> =
            s.faces.iter().filter(|f| f.vertices.contains(&i) && f.vertices.contains(&j)).map(|f| &f.normal).collect();
        if adj.len() == 2 {
            dirs.push((adj[0] + adj[1]).normalize());
        }
    }
    for k in 0..s.vertices.len() {
        let sum: Vec3 = s.faces.iter().filter(|f| f.vertices.contains(&k)).map(|f| f.normal).sum();
        if sum.norm() > 1e-12 {
            dirs.push(sum.normalize());
        }
    }
    let pts: Vec<Vec3> = eroded.iter().flat_map(|v| dirs.iter().map(move |u| v + u * r)).collect();
    ConvexBlock::hull_of(&pts)
}

/// The vertices of `{x : n·x ≤ d − r}` for the planes `(n, d)`: the intersections of
/// every three planes that satisfy all of them (deduplicated).
fn erode(planes: &[(Vec3, f64)], r: f64) -> Vec<Vec3> {
    let tol = 1e-12 * (1.0 + planes.iter().map(|p| p.1.abs()).fold(0.0, f64::max));
    let mut out: Vec<Vec3> = Vec::new();
    let n = planes.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let m = crate::math::Mat3::from_rows(&[
                    planes[i].0.transpose(),
                    planes[j].0.transpose(),
                    planes[k].0.transpose(),
                ]);
                let rhs = Vec3::new(planes[i].1 - r, planes[j].1 - r, planes[k].1 - r);
                let Some(x) = m.lu().solve(&rhs) else { continue };
                if !x.iter().all(|c| c.is_finite()) {
                    continue;
                }
                if planes.iter().all(|(nn, d)| nn.dot(&x) <= d - r + 1e3 * tol)
                    && !out.iter().any(|p| (p - x).norm() < 1e-10)
                {
                    out.push(x);
                }
            }
        }
    }
    out
}

/// `transverse_dip`: every bed joint between two courses dips across the wall's thickness
/// by its own angle, uniform in `[−δ, δ]` (`max_dip` in rad), drawn in course order from
/// `rng`. A point on the bed joint at nominal height `Zₖ` (`course_tops_m`, the tops of the
/// courses, m) moves by `(y − y_c) tan δₖ` in z, with `y_c` the wall's centre line; a point
/// is on the bed joint nearest to it. The table and the wall's crest stay level. Bed
/// faces and vertical head joints stay plane; the shared faces of neighbours move
/// together, so no overlap is made.
///
/// # Errors
/// The block that could not be rebuilt.
pub fn tilt_beds_across(
    layout: &mut Layout,
    max_dip: f64,
    course_tops_m: &[f64],
    rng: &mut ChaCha8Rng,
) -> Result<(), BlockFailure> {
    if max_dip <= 0.0 || course_tops_m.len() < 2 {
        return Ok(());
    }
    let n = course_tops_m.len();
    // Interfaces: the table (level), the joints between courses, the crest (level).
    let mut levels = vec![(0.0, 0.0)];
    for &z in &course_tops_m[..n - 1] {
        let dip: f64 = rng.random_range(-max_dip..=max_dip);
        levels.push((z, dip.tan()));
    }
    levels.push((course_tops_m[n - 1], 0.0));
    let bounds = layout.bounds();
    let yc = 0.5 * (bounds.min.y + bounds.max.y);
    map_layout(layout, |p| {
        let (_, t) =
            levels.iter().min_by(|a, b| (a.0 - p.z).abs().total_cmp(&(b.0 - p.z).abs())).copied().unwrap_or((0.0, 0.0));
        Vec3::new(p.x, p.y, p.z + (p.y - yc) * t)
    })
}

/// `base_restraint`: stops of height `h_s` (m) on the downhill side (+y) of the first
/// course, as the source paper's set-up had them ("the base of the specimens was
/// restrained with two wooden pieces, to avoid sliding failure", Santa-Cruz et al. 2021,
/// §2.1). Each block standing on the table gets a fixed stop bearing on its downhill face
/// (the face whose outward normal has the largest y component, at least 0.5) from the
/// table up to `h_s`: the prism spanned by that part of the face and the same points moved
/// `max(h_s, 5 mm)` downhill, appended to the layout as a fixed block `stop_ID` of
/// material `material` (the face's shape is followed, so a battered face is held over its
/// height, not at its toe alone). A block held so can no longer rotate about its toe: it
/// overturns about the stop's top edge, its toe sliding uphill on the table; for a
/// rectangular block of width b, height h on a table of friction μ against a smooth stop,
/// `tan α = (b + 2 μ h_s) / (h − 2 h_s)` (moments about the stop's edge, the toe carrying
/// the weight's normal component). `h_s = 0` adds nothing.
///
/// # Errors
/// The block whose stop could not be built.
pub fn add_base_stops(layout: &mut Layout, h_s: f64, material: usize) -> Result<(), BlockFailure> {
    if h_s.is_nan() || h_s <= 0.0 {
        return Ok(());
    }
    let wall: Vec<usize> = (0..layout.blocks.len()).filter(|&i| !layout.blocks[i].fixed).collect();
    let z0 = wall.iter().map(|&i| layout.blocks[i].shape.aabb().min.z).fold(f64::INFINITY, f64::min);
    let size = wall.iter().map(|&i| layout.blocks[i].shape.aabb().extent().norm()).fold(0.0, f64::max);
    let tol = 1e-9 * size.max(1e-3);
    let zc = z0 + h_s;
    let t = h_s.max(0.005);
    let mut stops = Vec::new();
    for &i in &wall {
        let b = &layout.blocks[i];
        if b.shape.aabb().min.z > z0 + 1e-6 * size.max(1e-3) {
            continue; // not on the table
        }
        let Some(face) =
            b.shape.faces.iter().filter(|f| f.normal.y >= 0.5).max_by(|a, c| a.normal.y.total_cmp(&c.normal.y))
        else {
            continue;
        };
        let v: Vec<Vec3> = face.vertices.iter().map(|&k| b.shape.vertices[k]).collect();
        let mut pts: Vec<Vec3> = v.iter().filter(|p| p.z <= zc + tol).copied().collect();
        for k in 0..v.len() {
            let (p, q) = (v[k], v[(k + 1) % v.len()]);
            if (p.z - zc) * (q.z - zc) < 0.0 {
                let s = (zc - p.z) / (q.z - p.z);
                pts.push(p + (q - p) * s);
            }
        }
        if pts.len() < 3 {
            continue;
        }
        let out: Vec<Vec3> = pts.iter().map(|p| p + Vec3::new(0.0, t, 0.0)).collect();
        pts.extend(out);
        let shape = ConvexBlock::hull_of(&pts).map_err(|e| (format!("stop_{}", b.id), e))?;
        stops.push(crate::layout::Block {
            id: format!("stop_{}", b.id),
            material,
            shape,
            fixed: true,
            course: None,
            wedge: false,
            own_mass: None,
            bed_closure: None,
        });
    }
    layout.blocks.extend(stops);
    Ok(())
}

/// `leaf_split`: the section split into two leaves, as a double-faced wall whose leaves are
/// tied only by friction (and by through stones, if any). Every block (stones and wedges;
/// fixed blocks excepted) is cut by the surface that leaves the share `f` (in (0, 1)) of
/// the section's width on the +y side (the side the wall falls to: the loose leaf) at every
/// height: `y_c(z) = y₊(z) − f (y₊(z) − y₋(z))`, with `y₋`, `y₊` the wall's faces, taken
/// affine in z through the extreme y of the blocks' vertices at the base and at the crest
/// (the trapezoidal section of a generated wall; a plane, vertical for a rectangular or
/// symmetric section with `f = ½`). Its −y part keeps the block's place (id `IDn`), its +y
/// part is appended (id `IDp`, same material, course, wedge flag and end restraint). With
/// `through_every = n ≥ 1`, in course k the stones i = 0, 1, … (left to right) with
/// `(i + k ⌊n/2⌋) mod n = 0` stay whole (through stones every n stones, staggered course to
/// course; n = 1: every stone). A part thinner than 1e-6 of the block's volume is not cut
/// off. `f = 0` changes nothing. Rigid leaves: the +y leaf of width `f b` and height h
/// tips alone at `tan α = f b / h` (Ita, Santa-Cruz et al. 2023: delamination of the
/// section, then overturning of the loose leaf).
///
/// # Errors
/// The block whose part could not be built.
pub fn split_leaves(layout: &mut Layout, f: f64, through_every: Option<u32>) -> Result<(), BlockFailure> {
    if f.is_nan() || f <= 0.0 || f >= 1.0 {
        return Ok(());
    }
    let wall: Vec<usize> = (0..layout.blocks.len()).filter(|&i| !layout.blocks[i].fixed).collect();
    if wall.is_empty() {
        return Ok(());
    }
    let verts = || wall.iter().flat_map(|&i| layout.blocks[i].shape.vertices.iter());
    let (z0, z1) = verts().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v.z), hi.max(v.z)));
    let tol = 1e-9 * (z1 - z0).max(1e-3);
    let ys = |z: f64| {
        verts()
            .filter(|v| (v.z - z).abs() <= 1e3 * tol)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v.y), hi.max(v.y)))
    };
    let ((a0, b0), (a1, b1)) = (ys(z0), ys(z1));
    // y_c(z) = c0 + m (z − z0).
    let (c0, c1) = (b0 - f * (b0 - a0), b1 - f * (b1 - a1));
    let m = if z1 > z0 { (c1 - c0) / (z1 - z0) } else { 0.0 };
    let side = move |v: &Vec3| v.y - (c0 + m * (v.z - z0));
    // Through stones.
    let mut through = vec![false; layout.blocks.len()];
    if let Some(n) = through_every.filter(|&n| n >= 1).map(|n| n as usize) {
        let mut courses: std::collections::BTreeMap<usize, Vec<usize>> = std::collections::BTreeMap::new();
        for &i in &wall {
            let b = &layout.blocks[i];
            if let (Some(k), false) = (b.course, b.wedge) {
                courses.entry(k).or_default().push(i);
            }
        }
        for (k, mut stones) in courses {
            stones.sort_by(|&p, &q| {
                let (a, b) = (layout.blocks[p].shape.aabb().min, layout.blocks[q].shape.aabb().min);
                a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
            });
            for (j, &i) in stones.iter().enumerate() {
                through[i] = (j + k * (n / 2)) % n == 0;
            }
        }
    }
    let mut added = Vec::new();
    for &i in &wall {
        if through[i] {
            continue;
        }
        let b = &layout.blocks[i];
        let Some((neg, pos)) = cut(&b.shape, &side, tol).map_err(|e| (b.id.clone(), e))? else { continue };
        added.push((i, pos));
        let b = &mut layout.blocks[i];
        b.shape = neg;
        b.id.push('n');
    }
    for (i, pos) in added {
        let b = &layout.blocks[i];
        let id = format!("{}p", b.id.strip_suffix('n').unwrap_or(&b.id));
        let new = crate::layout::Block {
            id,
            material: b.material,
            shape: pos,
            fixed: false,
            course: b.course,
            wedge: b.wedge,
            own_mass: None,
            bed_closure: b.bed_closure,
        };
        let j = layout.blocks.len();
        layout.blocks.push(new);
        if let Some(&(_, r)) = layout.end_restraints.iter().find(|(k, _)| *k == i) {
            layout.end_restraints.push((j, r));
        }
    }
    Ok(())
}

/// The parts of `s` with `side ≤ 0` and `side ≥ 0` (`side` affine), or None if one of them
/// is empty or thinner than 1e-6 of the volume.
fn cut(
    s: &ConvexBlock,
    side: &impl Fn(&Vec3) -> f64,
    tol: f64,
) -> Result<Option<(ConvexBlock, ConvexBlock)>, GeometryError> {
    let d: Vec<f64> = s.vertices.iter().map(side).collect();
    if d.iter().all(|&x| x >= -tol) || d.iter().all(|&x| x <= tol) {
        return Ok(None);
    }
    let (mut neg, mut pos) = (Vec::new(), Vec::new());
    for (v, &x) in s.vertices.iter().zip(&d) {
        if x <= tol {
            neg.push(*v);
        }
        if x >= -tol {
            pos.push(*v);
        }
    }
    for &(i, j) in &s.edges {
        let (di, dj) = (d[i], d[j]);
        if (di < -tol && dj > tol) || (di > tol && dj < -tol) {
            let t = di / (di - dj);
            let p = s.vertices[i] + (s.vertices[j] - s.vertices[i]) * t;
            neg.push(p);
            pos.push(p);
        }
    }
    let (n, p) = (ConvexBlock::hull_of(&neg)?, ConvexBlock::hull_of(&pos)?);
    let v = s.volume();
    if n.volume() < 1e-6 * v || p.volume() < 1e-6 * v {
        return Ok(None);
    }
    Ok(Some((n, p)))
}
