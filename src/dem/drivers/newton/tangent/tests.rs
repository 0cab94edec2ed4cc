//! Finite-difference checks of the consistent tangent: `K = −∂R/∂Δq` against central
//! differences of the Newton iteration's own residual (the out-of-balance loads after one
//! jump of the total increment from the increment's start, `super::super::iterate`).

use super::*;
use crate::dem::{RunToEquilibrium, SolverParams};
use crate::layout::BaseSliding;
use crate::verify::{box_vertices, layout_of};

/// The Newton residual of a trial increment `x` from the start state `start`: per body the
/// out-of-balance force and moment (N, N·m, table frame) after one jump of `x`.
fn residual(start: &Simulation, x: &PoseIncrement) -> Vec<[f64; 6]> {
    let mut s = start.clone();
    s.predict_deferred(&x.0, &x.1);
    s.assess_predicted();
    (0..s.state.bodies.len())
        .map(|k| {
            let (f, t) = s.unbalanced(k);
            [f.x, f.y, f.z, t.x, t.y, t.z]
        })
        .collect()
}

/// One entry of the tangent against its central difference.
#[derive(Debug)]
struct Entry {
    /// Row: body and dof (0–2 force, 3–5 moment).
    row: (usize, usize),
    /// Column: body and dof (0–2 translation, 3–5 rotation).
    col: (usize, usize),
    analytic: f64,
    fd: f64,
}

/// Every entry of the tangent at the iterate `x` from `start` against central differences
/// of the residual with steps `h` m and `h` rad.
fn compare(start: &Simulation, x: &PoseIncrement, h: f64) -> Vec<Entry> {
    let nb = start.state.bodies.len();
    let mut at = start.clone();
    at.predict_deferred(&x.0, &x.1);
    at.assess_predicted();
    let blocks = tangent_blocks(&at, x);
    let mut out = Vec::new();
    for j in (0..nb).filter(|&j| !start.state.bodies[j].fixed()) {
        for c in 0..6 {
            let (mut p, mut m) = (x.clone(), x.clone());
            if c < 3 {
                p.0[j][c] += h;
                m.0[j][c] -= h;
            } else {
                p.1[j][c - 3] += h;
                m.1[j][c - 3] -= h;
            }
            let (rp, rm) = (residual(start, &p), residual(start, &m));
            for i in (0..nb).filter(|&i| !start.state.bodies[i].fixed()) {
                let k = if i == j { Some(blocks.diag[i]) } else { blocks.off.get(&(i, j)).copied() };
                for r in 0..6 {
                    let fd = -(rp[i][r] - rm[i][r]) / (2.0 * h);
                    let analytic = k.map_or(0.0, |k| k[(r, c)]);
                    out.push(Entry { row: (i, r), col: (j, c), analytic, fd });
                }
            }
        }
    }
    out
}

/// Entries whose difference exceeds `tol` of the largest entry of the same kind (force
/// rows or moment rows over `rho`, translation or rotation columns times `rho`).
fn disagreeing(entries: &[Entry], rho: f64, tol: f64) -> Vec<&Entry> {
    let kind = |e: &Entry| (e.row.1 >= 3) as usize * 2 + (e.col.1 >= 3) as usize;
    let unit = |e: &Entry| {
        let mut s = 1.0;
        if e.row.1 >= 3 {
            s /= rho;
        }
        if e.col.1 >= 3 {
            s /= rho;
        }
        s
    };
    let mut scale = [0.0f64; 4];
    for e in entries {
        scale[kind(e)] = scale[kind(e)].max(e.fd.abs() * unit(e));
    }
    let big = scale.iter().fold(0.0f64, |m, v| m.max(*v));
    entries.iter().filter(|e| (e.analytic - e.fd).abs() * unit(e) > tol * big).collect()
}

/// A layout of the boxes `blocks` on the table (φ `phi` degrees, Kn `kn` Pa/m, Ks Kn/2)
/// settled under gravity, then tilted by `tilt_deg` and settled again.
fn settle(blocks: Vec<Vec<[f64; 3]>>, kn: f64, phi: f64, tilt_deg: f64) -> Simulation {
    let l = layout_of(blocks, kn, kn / 2.0, phi, BaseSliding::Free);
    let mut sim = Simulation::new(&l, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-9, 2_000_000).unwrap());
    if tilt_deg != 0.0 {
        sim.set_tilt(tilt_deg.to_radians());
        assert!(sim.run_to_equilibrium(1e-9, 2_000_000).unwrap());
    }
    sim
}

/// A deterministic small increment: per free body a translation of `t` m and a rotation of
/// `r` rad in fixed directions that differ from body to body.
fn increment(sim: &Simulation, t: f64, r: f64) -> PoseIncrement {
    let nb = sim.state.bodies.len();
    let dir = |k: usize, s: f64| {
        Vec3::new((1.3 * (k as f64 + s)).sin(), (2.1 * (k as f64 + s)).cos(), (0.7 + k as f64 * s).sin())
    };
    ((0..nb).map(|k| dir(k, 1.0) * t).collect(), (0..nb).map(|k| dir(k, 2.0) * r).collect())
}

/// The largest disagreement between `K v` and the central difference of `−R` along every
/// rigid motion `v` of all free bodies together (three translations, three rotations about
/// their mean centroid), over the rows of the bodies `rows` (whose contacts are all with
/// other free bodies, so that no spring of theirs deforms: what is left is geometric, the
/// forces turning and moving with the bodies), as a fraction of the largest entry of those
/// rows (moments over `rho`, rotations times `rho`).
fn rigid_error(name: &str, sim: &Simulation, x: &PoseIncrement, rows: &[usize], rho: f64) -> f64 {
    let set: Vec<usize> = (0..sim.state.bodies.len()).filter(|&k| !sim.state.bodies[k].fixed()).collect();
    let o = set.iter().map(|&k| sim.state.bodies[k].pos).sum::<Vec3>() / set.len() as f64;
    let scaled =
        |m: &Vector6<f64>, unit: f64| Vector6::from_fn(|i, _| m[i] * unit * if i >= 3 { 1.0 / rho } else { 1.0 });
    let mut modes = Vec::new();
    for mode in 0..6 {
        let mut e = Vec3::zeros();
        e[mode % 3] = 1.0;
        let (v, h, unit) = if mode < 3 {
            (rigid(sim, &set, e, Vec3::zeros(), o), 1e-8, 1.0)
        } else {
            (rigid(sim, &set, Vec3::zeros(), e, o), 1e-8, rho)
        };
        let (kv, fd) = directional(sim, x, &v, h);
        for &k in rows {
            modes.push((mode, k, scaled(&kv[k], unit), scaled(&fd[k], unit)));
        }
    }
    let scale = modes.iter().fold(0.0f64, |m, (_, _, _, fd)| m.max(fd.amax()));
    let mut worst = 0.0f64;
    for (mode, k, kv, fd) in &modes {
        let err = (kv - fd).amax() / scale;
        if err > 1e-3 {
            eprintln!("{name}: rigid mode {mode}, body {k}: K v {:?} against {:?}", kv.as_slice(), fd.as_slice());
        }
        worst = worst.max(err);
    }
    worst
}

/// Prints the entries that disagree.
fn report(name: &str, e: &[&Entry]) {
    for e in e.iter().take(20) {
        eprintln!("{name}: row {:?} col {:?}: K {:.6e} against {:.6e}", e.row, e.col, e.analytic, e.fd);
    }
}

/// `K v` and the central difference of `−R` along `v` (steps of `±h v`) at the iterate
/// `x` from `start`, per body (N, N·m per unit of `v`).
fn directional(
    start: &Simulation,
    x: &PoseIncrement,
    v: &PoseIncrement,
    h: f64,
) -> (Vec<Vector6<f64>>, Vec<Vector6<f64>>) {
    let nb = start.state.bodies.len();
    let mut at = start.clone();
    at.predict_deferred(&x.0, &x.1);
    at.assess_predicted();
    let blocks = tangent_blocks(&at, x);
    let vv: Vec<Vector6<f64>> =
        (0..nb).map(|k| Vector6::new(v.0[k].x, v.0[k].y, v.0[k].z, v.1[k].x, v.1[k].y, v.1[k].z)).collect();
    let mut kv = vec![Vector6::zeros(); nb];
    for i in (0..nb).filter(|&i| !start.state.bodies[i].fixed()) {
        kv[i] += blocks.diag[i] * vv[i];
        for (j, vj) in vv.iter().enumerate().filter(|&(j, _)| j != i) {
            if let Some(k) = blocks.off.get(&(i, j)) {
                kv[i] += k * vj;
            }
        }
    }
    let (p, m) = (along(x, v, h), along(x, v, -h));
    let (rp, rm) = (residual(start, &p), residual(start, &m));
    let fd = (0..nb).map(|i| -(Vector6::from(rp[i]) - Vector6::from(rm[i])) / (2.0 * h)).collect();
    (kv, fd)
}

/// `x + s d`, per body.
fn along(x: &PoseIncrement, d: &PoseIncrement, s: f64) -> PoseIncrement {
    (x.0.iter().zip(&d.0).map(|(a, b)| a + b * s).collect(), x.1.iter().zip(&d.1).map(|(a, b)| a + b * s).collect())
}

/// The rigid motion of the bodies `set` together: translation `t` and rotation `w` about
/// the point `o` (m, rad, table frame).
fn rigid(sim: &Simulation, set: &[usize], t: Vec3, w: Vec3, o: Vec3) -> PoseIncrement {
    let nb = sim.state.bodies.len();
    let mut v = (vec![Vec3::zeros(); nb], vec![Vec3::zeros(); nb]);
    for &k in set {
        v.0[k] = t + w.cross(&(sim.state.bodies[k].pos - o));
        v.1[k] = w;
    }
    v
}

/// The tangent against central differences of the Newton residual on hand-built states:
/// two boxes stacked with the shear force a 20° tilt left in their joint; the same at 33°
/// (φ 35°), the joint near its slip limit; a slender block (0.1 m by 0.4 m) on a base
/// block rocking at 12° on a sliver of its joint; the end of a course (two blocks side by
/// side on the table, a third across their head joint). The iterate is a small jump of
/// every body with the top block turned by 1e-4 rad about the vertical (the joint's
/// normal) relative to the start. Every entry to 1e-4 of the largest of its kind, and
/// along the rigid motions of the whole set (where no spring of the top block deforms and
/// only the forces' turning and moving with the bodies is left, some 1e-6 of the springs'
/// entries) to 1 % of the top block's largest entry: a tangent that leaves out the turning
/// of the normal, the stored shear force or the closures with the pair, or takes the arms
/// at the material points rather than at the mid-points, is off there by 60–170 %.
#[test]
fn the_tangent_is_the_derivative_of_the_residual() {
    let two = |h: f64, w: f64| {
        vec![
            box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1]),
            box_vertices([0.0, -w / 2.0, 0.1], [0.3, w / 2.0, 0.1 + h]),
        ]
    };
    let stack = settle(two(0.1, 0.2), 1e9, 35.0, 20.0);
    let sliding = settle(two(0.1, 0.2), 1e9, 35.0, 33.0);
    let rocking = settle(two(0.4, 0.1), 1e10, 35.0, 12.0);
    let course = settle(
        vec![
            box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1]),
            box_vertices([0.3, -0.1, 0.0], [0.6, 0.1, 0.1]),
            box_vertices([0.15, -0.1, 0.1], [0.45, 0.1, 0.2]),
        ],
        1e9,
        35.0,
        15.0,
    );
    let top = |sim: &Simulation| sim.state.bodies.len() - 1;
    for (name, sim) in [("stack", &stack), ("sliding", &sliding), ("rocking", &rocking), ("course", &course)] {
        let slipping = sim.state.contacts.iter().flat_map(|c| &c.subs).filter(|s| s.state.slipping).count();
        let mut x = increment(sim, 1e-7, 1e-6);
        x.1[top(sim)].z += 1e-4;
        let entries = compare(sim, &x, 1e-9);
        let bad = disagreeing(&entries, 0.15, 1e-4);
        report(name, &bad);
        assert!(bad.is_empty(), "{name}: {} entries disagree", bad.len());
        let err = rigid_error(name, sim, &x, &[top(sim)], 0.15);
        eprintln!("{name}: {slipping} sub-contacts slipping, rigid-motion error {err:.2e}");
        assert!(err < 0.01, "{name}: the rigid motions disagree by {err:.3} of the largest entry");
    }
}
