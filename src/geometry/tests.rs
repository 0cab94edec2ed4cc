//! Tests of the geometry against closed forms and parry3d (mass properties, hulls, faces), and of the import's local convexity proof against the global definitions.

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
    let pts: Vec<Vec3> = [a, b, c].iter().flat_map(|&(x, z, hw)| [Vec3::new(x, -hw, z), Vec3::new(x, hw, z)]).collect();
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
        if let Some(f) =
            faces.iter_mut().find(|(fn_, fo, _)| fn_.dot(&n) > 1.0 - 1e-9 && (fo - off).abs() <= tol.max(1e-12) * 10.0)
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
                let v =
                    Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
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
