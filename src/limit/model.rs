//! The static model of the lower-bound problem: the contact points of every joint (the
//! vertices of the DEM's contact polygons, each with its local frame and tributary area),
//! the bodies' equations, the dead and live loads, and the second-order cone program built
//! on them and solved by Clarabel (Goulart & Chen 2024, an interior-point solver for conic
//! programs).
//!
//! # The program
//!
//! Unknowns: the load multiplier λ (free), one y reaction per block with a rigid end
//! restraint (free), and at every contact point k the force on body B in the point's local
//! frame `(f_n, f_t1, f_t2)` along `(n, t1, t2)`, `n` the contact normal A → B (body A gets
//! the opposite). For every free block, six equations about its centroid:
//!
//! ```text
//! Σ_k (±) [f_n n + f_t1 t1 + f_t2 t2 ;  (x_k − c) × (f_n n + f_t1 t1 + f_t2 t2)] + D + λ L = 0
//! ```
//!
//! with D the dead and L the live load (force, moment about the centroid). At each point
//! `f_n ≥ −T A_k` (T the joint's tensile strength, Pa; 0 for a dry joint) and, unless the
//! joint is held against slip, the Coulomb cone `‖(f_t1, f_t2)‖ ≤ μ f_n + c A_k` (c the
//! cohesion, Pa, A_k the point's tributary area, m²) as an exact second-order cone; with
//! friction fixed ([`Friction::Fixed`], the non-associative iteration), the cone's radius is
//! `μ N̂_k + c A_k` for given normal forces N̂. Maximise λ.
//!
//! # Its dual, the kinematic program
//!
//! [`Model::solve_kinematic`] solves the associative program through its dual (Livesley
//! 1978; Ferris & Tin-Loi 2001, "Limit analysis of frictional block assemblies as a
//! mathematical program with complementarity constraints", Int. J. Mech. Sci. 43:209):
//! unknowns the virtual velocities u of the free blocks (six each), minimise the power of
//! the dead load `−D·u` plus the dissipation of cohesion and tensile strength, subject to
//! `L·u = 1`, no y velocity at a rigid end restraint, no tangential relative velocity at a
//! joint held against slip, and at every point the relative velocity `w = (w_n, w_t1, w_t2)`
//! of B against A in the dual Coulomb cone `w_n − y ≥ μ ‖w_t‖` (y ≥ 0 the opening taken by
//! the tensile strength, where the joint has one or cohesion). Its optimum is λ; the
//! contact forces are its cones' multipliers.
//!
//! Forces are scaled by the total weight of the free blocks and moments by that weight times
//! a length (the largest block radius) so that the program is of order one.

use super::csc::csc_from_entries;
use crate::dem::{Simulation, SolverParams};
use crate::geometry::polygon::plane_basis;
use crate::layout::{EndRestraint, Layout};
use crate::math::Vec3;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT, SupportedConeT::*};

/// A contact point: a vertex of a contact polygon.
#[derive(Debug, Clone)]
pub(crate) struct Point {
    /// Position (mid-plane), m, table frame.
    pub x: Vec3,
    /// Tributary area, m² (a third of each sub-contact triangle it is a corner of).
    pub area: f64,
}

/// A joint: one contact of the DEM's detection, with its law.
#[derive(Debug, Clone)]
pub(crate) struct Joint {
    /// Body A (`None`: the table).
    pub a: Option<usize>,
    /// Body B.
    pub b: usize,
    /// `table/ID` or `ID_A/ID_B`.
    pub name: String,
    /// Frame: normal A → B and two tangents.
    pub frame: [Vec3; 3],
    /// Friction coefficient tan φ.
    pub mu: f64,
    /// Cohesion, Pa.
    pub cohesion: f64,
    /// Tensile strength, Pa.
    pub tension: f64,
    /// False for a joint held against slip (the base restraint): no cone.
    pub can_slip: bool,
    /// Its points, a range of [`Model::points`].
    pub points: std::ops::Range<usize>,
    /// Mean height of its points, m.
    pub z: f64,
}

/// The static model of a layout: bodies, joints, loads.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    /// Block ids.
    pub ids: Vec<String>,
    /// Equation block of each body (`None`: fixed).
    pub row_of: Vec<Option<usize>>,
    /// Centroids, m.
    pub centroid: Vec<Vec3>,
    /// Radii (centroid to farthest vertex), m.
    pub radius: Vec<f64>,
    /// Per body: its x and z extents (lowest, highest), m, and whether it is fixed (the
    /// mechanism reading's view of the blocks).
    pub extents: Vec<((f64, f64), (f64, f64), bool)>,
    /// Joints.
    pub joints: Vec<Joint>,
    /// Contact points.
    pub points: Vec<Point>,
    /// Held degrees of freedom, each a free reaction: (body, dof) with dof 0–2 a
    /// translation at the centroid along x, y, z and 3–5 a rotation about x, y, z (a rigid
    /// end restraint holds dof 1; a protocol's per-degree-of-freedom constraints add
    /// theirs).
    pub held: Vec<(usize, usize)>,
    /// Dead load per body: force (N) and moment about the centroid (N·m), table frame.
    pub dead: Vec<(Vec3, Vec3)>,
    /// Live load per body, as `dead`.
    pub live: Vec<(Vec3, Vec3)>,
    /// Force scale, N (total weight of the free blocks).
    pub force_scale: f64,
    /// Length scale, m (largest block radius).
    pub length_scale: f64,
}

/// Weight ε of the quadratic term ε‖f‖² (forces scaled by the total weight) of the
/// fixed-friction programs.
const FIXED_REGULARISATION: f64 = 1e-6;

/// How the friction cones are bounded.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Friction<'a> {
    /// `‖f_t‖ ≤ μ f_n + c A`: associative (Coulomb cone as the yield surface).
    Associative,
    /// `‖f_t‖ ≤ μ N̂_k + c A` with N̂ given per point, N (scaled): a cone of fixed radius.
    Fixed(&'a [f64]),
}

/// The solution of one cone program.
#[derive(Debug, Clone)]
pub(crate) struct Solution {
    /// Clarabel's status.
    pub status: SolverStatus,
    /// λ.
    pub lambda: f64,
    /// Normal force per point, scaled by the force scale.
    pub normal: Vec<f64>,
    /// Virtual velocity of each body (translation, rotation), from the duals of its
    /// equations; zero for fixed bodies. Normalised so that the live load's power is 1
    /// (units: per force scale).
    pub velocity: Vec<(Vec3, Vec3)>,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Clarabel's solve time, s.
    pub solve_time_s: f64,
}

/// The triplets of a program's constraint matrix, in the order pushed; zero values are
/// left out.
#[derive(Debug, Default)]
struct Entries {
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
}

impl Entries {
    fn push(&mut self, r: usize, c: usize, v: f64) {
        if v != 0.0 {
            self.rows.push(r);
            self.cols.push(c);
            self.vals.push(v);
        }
    }
}

impl Solution {
    /// The solution of a program clarabel could not set up: λ NaN, nothing else.
    fn failed() -> Solution {
        Solution {
            status: SolverStatus::NumericalError,
            lambda: f64::NAN,
            normal: Vec::new(),
            velocity: Vec::new(),
            iterations: 0,
            solve_time_s: 0.0,
        }
    }
}

/// The static program's quadratic term: none with associative friction; with friction
/// fixed, `FIXED_REGULARISATION ‖f‖²` over the force columns `col_pt..nvar`.
fn quadratic_term(friction: Friction, col_pt: usize, nvar: usize) -> CscMatrix<f64> {
    match friction {
        Friction::Associative => CscMatrix::zeros((nvar, nvar)),
        Friction::Fixed(_) => {
            let eps = FIXED_REGULARISATION;
            let cols: Vec<usize> = (col_pt..nvar).collect();
            CscMatrix::new_from_triplets(nvar, nvar, cols.clone(), cols, vec![eps; nvar - col_pt])
        }
    }
}

impl Model {
    /// The model of a layout's contacts as the DEM detects them at rest (`contact`: the
    /// narrow phase's parameters; one sub-contact triangle per polygon edge fanned from a
    /// vertex, so that the points are the polygon's vertices), with the dead load of gravity
    /// and no live load yet.
    pub fn new(layout: &Layout, contact: &SolverParams) -> (Model, Simulation) {
        let params = SolverParams {
            subcontact_subdivisions: 1,
            quadrature: crate::dem::contact::law::Quadrature::Exact,
            density_scaling: crate::dem::DensityScaling::Off,
            ..*contact
        };
        let sim = Simulation::new(layout, params);
        let st = &sim.state;
        let n = st.bodies.len();
        let mut row_of = vec![None; n];
        let mut free = 0;
        for (k, b) in st.bodies.iter().enumerate() {
            if !b.fixed() {
                row_of[k] = Some(free);
                free += 1;
            }
        }
        let g = layout.gravity;
        let dead: Vec<(Vec3, Vec3)> =
            st.bodies.iter().map(|b| (Vec3::new(0.0, 0.0, -g * b.mass), Vec3::zeros())).collect();
        let weight: f64 = st.bodies.iter().filter(|b| !b.fixed()).map(|b| g * b.mass).sum();
        let mut joints = Vec::with_capacity(st.contacts.len());
        let mut points = Vec::new();
        for c in &st.contacts {
            let nrm = st.contact_normal(c);
            let (t1, t2) = plane_basis(&nrm);
            let mut area = vec![0.0; c.nodes.len()];
            for s in &c.subs {
                for &k in &s.nodes {
                    area[k as usize] += s.area / 3.0;
                }
            }
            let start = points.len();
            let mut z = 0.0;
            for (nd, a) in c.nodes.iter().zip(area) {
                let (pa, pb) = st.node_points(c, nd);
                let x = 0.5 * (pa + pb);
                z += x.z / c.nodes.len() as f64;
                points.push(Point { x, area: a });
            }
            joints.push(Joint {
                a: c.a,
                b: c.b,
                name: st.joint_name(c),
                frame: [nrm, t1, t2],
                mu: c.joint.tan_phi,
                cohesion: c.joint.cohesion,
                tension: c.joint.tension.strength(),
                can_slip: c.joint.slip().can_slip,
                points: start..points.len(),
                z,
            });
        }
        let held = layout
            .end_restraints
            .iter()
            .filter(|(i, r)| *r == EndRestraint::Rigid && !st.bodies[*i].fixed())
            .map(|(i, _)| (*i, 1))
            .collect();
        let model = Model {
            ids: st.bodies.iter().map(|b| b.id.clone()).collect(),
            row_of,
            centroid: st.bodies.iter().map(|b| b.pos).collect(),
            radius: st.bodies.iter().map(|b| b.radius).collect(),
            extents: st
                .bodies
                .iter()
                .map(|b| {
                    let bb = b.world_shape().aabb();
                    ((bb.min.x, bb.max.x), (bb.min.z, bb.max.z), b.fixed())
                })
                .collect(),
            joints,
            points,
            held,
            dead,
            live: vec![(Vec3::zeros(), Vec3::zeros()); n],
            force_scale: if weight > 0.0 { weight } else { 1.0 },
            length_scale: st.bodies.iter().map(|b| b.radius).fold(0.0, f64::max).max(1e-9),
        };
        (model, sim)
    }

    /// Each body's velocity (translation, rotation over the length scale `ls`) from the
    /// six entries of its row in `v`, a solution vector; zero for a held body.
    fn velocities(&self, v: &[f64], ls: f64) -> Vec<(Vec3, Vec3)> {
        self.row_of
            .iter()
            .map(|r| match r {
                Some(r) => {
                    let u = &v[6 * r..6 * r + 6];
                    (Vec3::new(u[0], u[1], u[2]), Vec3::new(u[3], u[4], u[5]) / ls)
                }
                None => (Vec3::zeros(), Vec3::zeros()),
            })
            .collect()
    }

    /// Number of free bodies.
    pub fn free(&self) -> usize {
        self.row_of.iter().flatten().count()
    }

    /// The coefficients of a contact point's local force components on the scaled
    /// equations: for each body of the joint with equations (B with +1, A with −1), its
    /// equation block and, per direction d of the frame, the six coefficients of that
    /// force component on the block's force and moment equations.
    fn point_columns(&self, j: &Joint, p: usize) -> [Option<(usize, [[f64; 6]; 3])>; 2] {
        let x = self.points[p].x;
        let ls = self.length_scale;
        let mut out = [None, None];
        for (slot, (body, sign)) in [(Some(j.b), 1.0), (j.a, -1.0)].into_iter().enumerate() {
            let Some(k) = body else { continue };
            let Some(r) = self.row_of[k] else { continue };
            let arm = (x - self.centroid[k]) / ls;
            let mut c = [[0.0; 6]; 3];
            for (d, e) in j.frame.iter().enumerate() {
                let m = arm.cross(e);
                for q in 0..3 {
                    c[d][q] = sign * e[q];
                    c[d][3 + q] = sign * m[q];
                }
            }
            out[slot] = Some((r, c));
        }
        out
    }

    /// The columns of the kinematic program's y variables (one per point of a joint
    /// `needs_y` says carries cohesion or tension), numbered from `first`; `usize::MAX`
    /// elsewhere. Returns them and the number of variables.
    fn tension_columns(&self, first: usize, needs_y: impl Fn(&Joint) -> bool) -> (Vec<usize>, usize) {
        let mut y_of = vec![usize::MAX; self.points.len()];
        let mut nvar = first;
        for j in self.joints.iter().filter(|j| needs_y(j)) {
            for p in j.points.clone() {
                y_of[p] = nvar;
                nvar += 1;
            }
        }
        (y_of, nvar)
    }

    /// The kinematic program's linear objective over `nvar` variables: the dead load's
    /// power, `q_u = −D` (forces over the force scale, moments over force × length scale).
    fn dead_power(&self, nvar: usize) -> Vec<f64> {
        let (fs, ls) = (self.force_scale, self.length_scale);
        let mut q = vec![0.0; nvar];
        for (k, row) in self.row_of.iter().enumerate() {
            let Some(r) = row else { continue };
            let (df, dm) = self.dead[k];
            for d in 0..3 {
                q[6 * r + d] = -df[d] / fs;
                q[6 * r + 3 + d] = -dm[d] / (fs * ls);
            }
        }
        q
    }

    /// The normal force of every point (over the force scale) from the kinematic
    /// program's duals `z`: a joint held against slip's from its non-negative row (rows
    /// from `nzero`, in `points`' order) less its tension T A; a slipping joint's from its
    /// cone's first row (cones from `nzero + nnonneg`) less c A / μ where it has a y.
    fn kinematic_normals<'j>(
        &self,
        z: &[f64],
        points: impl Iterator<Item = (&'j Joint, usize)> + Clone,
        nzero: usize,
        nnonneg: usize,
        y_of: &[usize],
    ) -> Vec<f64> {
        let fs = self.force_scale;
        let mut normal = vec![0.0; self.points.len()];
        for (nn, (j, p)) in (nzero..).zip(points.clone().filter(|(j, _)| !j.can_slip)) {
            normal[p] = z[nn] - j.tension * self.points[p].area / fs;
        }
        let mut sc = nzero + nnonneg;
        for (j, p) in points.filter(|(j, _)| j.can_slip) {
            let ca = if y_of[p] != usize::MAX { j.cohesion * self.points[p].area / (fs * j.mu) } else { 0.0 };
            normal[p] = z[sc] - ca;
            sc += 3;
        }
        normal
    }

    /// Solves the associative program through its dual, the kinematic program: the
    /// blocks' virtual velocities u (six per free block) minimising the power of the dead
    /// load plus the joints' dissipation, with the live load's power 1, every rigid end
    /// restraint's y velocity zero and the relative velocity w of every contact point in
    /// the dual Coulomb cone `w_n ≥ μ ‖w_t‖` (Livesley 1978; Ferris & Tin-Loi 2001). Its
    /// optimum is the same λ; its unknowns are the 6 per block rather than the 3 per
    /// contact point, so the interior-point method factors a system of about half the
    /// size. The contact forces are the multipliers of the cones.
    ///
    /// `None` where it does not apply: a joint that can slip with μ ≤ 0, or a status other
    /// than solved (the caller then solves the static program, whose certificates name
    /// the blocks).
    pub fn solve_kinematic(&self) -> Option<Solution> {
        if self.joints.iter().any(|j| j.can_slip && j.mu <= 0.0) {
            return None;
        }
        let nf = self.free();
        let neq = 6 * nf;
        let (fs, ls) = (self.force_scale, self.length_scale);
        // Variables: u, then one y per point of a slipping joint with cohesion or tension
        // (the multiplier of its f_n ≥ −T A).
        let needs_y = |j: &Joint| j.can_slip && (j.tension != 0.0 || j.cohesion != 0.0);
        let (y_of, nvar) = self.tension_columns(neq, needs_y);
        let mut entries = Entries::default();
        let mut push = |r: usize, c: usize, v: f64| entries.push(r, c, v);
        let mut q = self.dead_power(nvar);
        let mut b = Vec::new();
        // Zero cone: the live load's power is 1; held ends do not move in y; a joint held
        // against slip has no tangential relative velocity.
        let mut row = 0;
        for (k, r) in self.row_of.iter().enumerate() {
            let Some(r) = r else { continue };
            let (lf, lm) = self.live[k];
            for d in 0..3 {
                push(row, 6 * r + d, lf[d] / fs);
                push(row, 6 * r + 3 + d, lm[d] / (fs * ls));
            }
        }
        b.push(1.0);
        row += 1;
        for &(k, d) in &self.held {
            let r = self.row_of[k].expect("held bodies are free");
            push(row, 6 * r + d, 1.0);
            b.push(0.0);
            row += 1;
        }
        let cols: Vec<_> = self
            .joints
            .iter()
            .flat_map(|j| j.points.clone().map(move |p| (j, p)))
            .map(|(j, p)| (j, p, self.point_columns(j, p)))
            .collect();
        for (_, _, c) in cols.iter().filter(|(j, _, _)| !j.can_slip) {
            for d in 1..3 {
                for (r, cc) in c.iter().flatten() {
                    for e in 0..6 {
                        push(row, 6 * r + e, cc[d][e]);
                    }
                }
                b.push(0.0);
                row += 1;
            }
        }
        let nzero = row;
        // Nonnegative: the opening of a joint held against slip (its dissipation T A w_n in
        // the objective), and the y.
        for (j, p, c) in cols.iter().filter(|(j, _, _)| !j.can_slip) {
            let ta = j.tension * self.points[*p].area / fs;
            for (r, cc) in c.iter().flatten() {
                for e in 0..6 {
                    push(row, 6 * r + e, -cc[0][e]);
                    q[6 * r + e] += ta * cc[0][e];
                }
            }
            b.push(0.0);
            row += 1;
        }
        for (_, p, _) in cols.iter().filter(|(j, _, _)| needs_y(j)) {
            push(row, y_of[*p], -1.0);
            b.push(0.0);
            row += 1;
        }
        let nnonneg = row - nzero;
        // Second-order cones: (w_n − y, μ w_t1, μ w_t2), and the cohesion's dissipation
        // c A (w_n − y) / μ with the tension's T A y.
        let mut cones: Vec<SupportedConeT<f64>> = vec![ZeroConeT(nzero)];
        if nnonneg > 0 {
            cones.push(NonnegativeConeT(nnonneg));
        }
        for (j, p, c) in cols.iter().filter(|(j, _, _)| j.can_slip) {
            let y = y_of[*p];
            let area = self.points[*p].area / fs;
            let ca = j.cohesion * area / j.mu;
            for (r, cc) in c.iter().flatten() {
                for e in 0..6 {
                    push(row, 6 * r + e, -cc[0][e]);
                    push(row + 1, 6 * r + e, -j.mu * cc[1][e]);
                    push(row + 2, 6 * r + e, -j.mu * cc[2][e]);
                    q[6 * r + e] += ca * cc[0][e];
                }
            }
            if y != usize::MAX {
                push(row, y, 1.0);
                q[y] = j.tension * area - ca;
            }
            b.extend([0.0, 0.0, 0.0]);
            row += 3;
            cones.push(SecondOrderConeT(3));
        }
        let a = csc_from_entries(row, nvar, entries.rows, entries.cols, entries.vals);
        let p = CscMatrix::zeros((nvar, nvar));
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, kinematic_settings()).ok()?;
        solver.solve();
        let sol = &solver.solution;
        if !matches!(sol.status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            return None;
        }
        let points = cols.iter().map(|(j, p, _)| (*j, *p));
        let normal = self.kinematic_normals(&sol.z, points, nzero, nnonneg, &y_of);
        let velocity = self.velocities(&sol.x, ls);
        Some(Solution {
            status: sol.status,
            lambda: -sol.z[0],
            normal,
            velocity,
            iterations: sol.iterations,
            solve_time_s: sol.solve_time,
        })
    }

    /// Solves the program with the given friction bounds.
    pub fn solve(&self, friction: Friction) -> Solution {
        let nf = self.free();
        let neq = 6 * nf;
        let nh = self.held.len();
        let np = self.points.len();
        let col_pt = 1 + nh;
        let nvar = col_pt + 3 * np;
        let (fs, ls) = (self.force_scale, self.length_scale);
        let mut entries = Entries::default();
        let mut push = |r: usize, c: usize, v: f64| entries.push(r, c, v);
        let mut b = vec![0.0; neq];
        // Loads: dead on the right-hand side, live in λ's column.
        for (k, row) in self.row_of.iter().enumerate() {
            let Some(r) = row else { continue };
            let (df, dm) = self.dead[k];
            let (lf, lm) = self.live[k];
            for d in 0..3 {
                b[6 * r + d] = -df[d] / fs;
                b[6 * r + 3 + d] = -dm[d] / (fs * ls);
                push(6 * r + d, 0, lf[d] / fs);
                push(6 * r + 3 + d, 0, lm[d] / (fs * ls));
            }
        }
        for (h, &(k, d)) in self.held.iter().enumerate() {
            let r = self.row_of[k].expect("held bodies are free");
            push(6 * r + d, 1 + h, 1.0);
        }
        // Contact forces: on B as given, on A the opposite.
        for j in &self.joints {
            for p in j.points.clone() {
                let x = self.points[p].x;
                for (body, sign) in [(Some(j.b), 1.0), (j.a, -1.0)] {
                    let Some(k) = body else { continue };
                    let Some(r) = self.row_of[k] else { continue };
                    let arm = (x - self.centroid[k]) / ls;
                    for (d, e) in j.frame.iter().enumerate() {
                        let m = arm.cross(e);
                        for q in 0..3 {
                            push(6 * r + q, col_pt + 3 * p + d, sign * e[q]);
                            push(6 * r + 3 + q, col_pt + 3 * p + d, sign * m[q]);
                        }
                    }
                }
            }
        }
        // Cones: f_n + T A ≥ 0 where the friction cone does not imply it (a joint with
        // tensile strength or cohesion, one held against slip, or friction fixed), then
        // the friction cones.
        let mut row = neq;
        for j in &self.joints {
            let implied =
                matches!(friction, Friction::Associative) && j.can_slip && j.tension == 0.0 && j.cohesion == 0.0;
            if implied {
                continue;
            }
            for p in j.points.clone() {
                push(row, col_pt + 3 * p, -1.0);
                b.push(j.tension * self.points[p].area / fs);
                row += 1;
            }
        }
        let mut cones: Vec<SupportedConeT<f64>> = vec![ZeroConeT(neq)];
        if row > neq {
            cones.push(NonnegativeConeT(row - neq));
        }
        for j in &self.joints {
            if !j.can_slip {
                continue;
            }
            for p in j.points.clone() {
                let ca = j.cohesion * self.points[p].area / fs;
                match friction {
                    Friction::Associative => {
                        push(row, col_pt + 3 * p, -j.mu);
                        b.push(ca);
                    }
                    // A floor keeps the cone's interior non-empty where N̂ is zero.
                    Friction::Fixed(nhat) => b.push((j.mu * nhat[p].max(0.0) + ca).max(1e-9)),
                }
                push(row + 1, col_pt + 3 * p + 1, -1.0);
                push(row + 2, col_pt + 3 * p + 2, -1.0);
                b.extend([0.0, 0.0]);
                row += 3;
                cones.push(SecondOrderConeT(3));
            }
        }
        let a = csc_from_entries(row, nvar, entries.rows, entries.cols, entries.vals);
        // With friction fixed, a small quadratic term ε‖f‖² makes the force distribution
        // unique (the least-squares one among the optimal), so that the non-associative
        // iteration maps N̂ to one N; it lowers λ by at most ε Σ f² (forces of order 1/np).
        let p = quadratic_term(friction, col_pt, nvar);
        let mut q = vec![0.0; nvar];
        q[0] = -1.0;
        let settings = settings();
        let Ok(mut solver) = DefaultSolver::new(&p, &q, &a, &b, &cones, settings) else {
            return Solution::failed();
        };
        solver.solve();
        let sol = &solver.solution;
        let velocity = self.velocities(&sol.z, ls);
        Solution {
            status: sol.status,
            lambda: sol.x[0],
            normal: (0..np).map(|p| sol.x[col_pt + 3 * p]).collect(),
            velocity,
            iterations: sol.iterations,
            solve_time_s: sol.solve_time,
        }
    }
}

/// Clarabel's settings: quiet, one thread, at most 200 iterations, clarabel's own
/// tolerances (1e-8) for the static program.
fn settings() -> DefaultSettings<f64> {
    DefaultSettings { verbose: false, max_iter: 200, max_threads: 1, ..DefaultSettings::default() }
}

/// The kinematic program's settings: gap and feasibility to 1e-10 (its λ is the dual
/// objective, which at clarabel's 1e-8 can sit 1e-6 from the optimum on ill-conditioned
/// walls; one or two more iterations bring it within 1e-9), no iterative refinement
/// (the factorisation of its smaller system is accurate enough at that tolerance), and
/// steps of up to [`KINEMATIC_STEP_FRACTION`] of the way to the cone boundary.
fn kinematic_settings() -> DefaultSettings<f64> {
    DefaultSettings {
        max_step_fraction: KINEMATIC_STEP_FRACTION,
        tol_feas: KINEMATIC_TOLERANCE,
        tol_gap_abs: KINEMATIC_TOLERANCE,
        tol_gap_rel: KINEMATIC_TOLERANCE,
        iterative_refinement_enable: false,
        ..settings()
    }
}

/// Clarabel's feasibility and gap tolerances for the kinematic program.
const KINEMATIC_TOLERANCE: f64 = 1e-10;

/// The largest fraction of the step to the cone boundary the interior-point method takes in
/// the kinematic program (clarabel's default 0.99). Closer to the boundary, it ends in
/// fewer iterations: 351 against 375 on 32 generated walls (30 SBL, one CBL, one SBR), every
/// λ the same within 1e-9 relative.
const KINEMATIC_STEP_FRACTION: f64 = 0.999;
