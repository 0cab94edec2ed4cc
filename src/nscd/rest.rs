//! The rest certificate: a step of a wall at rest whose load its contacts can carry is
//! solved by statics, not by sweeps.
//!
//! # What is certified
//!
//! Take a step that starts with every block at rest relative to the table (`v⁻ = 0`) under
//! a load `F = D + a L` (D the dead load: weight, external loads, restraint springs and
//! ropes at the current poses; `L = −m e_d` per block the d'Alembert force of a unit base
//! acceleration along axis d, `a` its value at `t + θh`). If contact forces `f` exist at
//! the closed points (gap ≤ 0) that balance every block under F and lie inside the
//! **reduced** Coulomb cones `‖f_t‖ ≤ μ* fₙ`, `μ* = sin φ = μ / √(1 + μ²)`, then `v⁺ = 0`
//! with the impulses `r = h f` solves the step's Signorini–Coulomb problem exactly: every
//! relative velocity is zero, every impulse is inside its (full) cone, the open points
//! carry nothing and keep their gaps.
//!
//! # Why the reduced cone: non-associated friction
//!
//! With associated friction (a convex step problem) any such `f` in the full cones would
//! do: the end-of-step velocity is unique, so it is rest. Coulomb's friction is not
//! associated (sliding does not dilate), and then a load that a statically admissible
//! field carries may still move the blocks: the lower-bound theorem does not hold. It
//! holds again with the cone reduced to `tan φ* = sin φ`: Radenković's theorem (1961; for
//! the joints of block assemblies de Buhan & de Felice 1997, "A homogenization approach to
//! the ultimate strength of brick masonry", J. Mech. Phys. Solids 45:1085) bounds the
//! non-associated collapse load from below by the associated one with φ*. A load inside
//! the reduced cones admits no mechanism, so the rest is the step's only solution, and the
//! full solve, started from the same rest, would find it. Between the reduced and the full
//! capacity a step is not certified and goes to the sweeps.
//!
//! # How it is used
//!
//! For each axis d of a base acceleration the largest and smallest certified `a` are found
//! once, by two second-order cone programs (maximise λ subject to the block equations
//! under `D + λ L` and the reduced cones; Clarabel, Goulart & Chen 2024), with their force
//! fields `f₊`, `f₋`. Every `a` in `[a₋, a₊]` is then certified by the convex combination
//! of the two fields (equilibrium is linear in λ, the cones are convex); a base
//! acceleration with several components by the combination of the axes' fields and the
//! field at `a = 0` (weights `a_d / a_±,d`, summing to at most 1). The fields are those of
//! one set of contact points at one set of poses: any re-detection, motion, change of
//! tilt or of external load starts a new certificate.

use super::delassus::{PointRows, TABLE};
use crate::math::Vec3;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

/// Largest certified base acceleration, in g (a bound of the cone program).
const CAP_G: f64 = 10.0;

/// The reduced friction coefficient `μ* = sin φ = μ/√(1 + μ²)` of `μ = tan φ`.
pub fn reduced_friction(mu: f64) -> f64 {
    mu / (1.0 + mu * mu).sqrt()
}

/// The statics of a wall at rest: what the cone programs need.
pub struct Statics<'a> {
    /// The contact points' rows (frames, lever arms, bodies, μ, Signorini term).
    pub rows: &'a [PointRows],
    /// Mass of every body, kg (fixed bodies: ignored).
    pub mass: &'a [f64],
    /// Whether a body moves (false: fixed, no equations).
    pub free: &'a [bool],
    /// Whether a body's y translation is held (rigid end restraint: no y equation).
    pub held_y: &'a [bool],
    /// Dead load per body: force (N) and moment about the centroid (N·m), table frame.
    pub dead: &'a [(Vec3, Vec3)],
    /// Largest block radius, m (the moments' scale).
    pub length_scale: f64,
    /// Magnitude of gravity, m/s².
    pub gravity: f64,
    /// `θ h`, s: a point's gap is its Signorini term times this (the term of an open point
    /// is `g / (θ h)` for a wall at rest).
    pub closing: f64,
    /// A point whose gap is at most this is closed, m ([`GAP_TOLERANCE`]).
    pub gap_tolerance: f64,
}

/// The gap below which a point counts as closed for the certificate, m: the rounding of a
/// generated layout's coincident faces (1e-17 to 1e-11 m on the SBL preset wall). The full
/// solve would close such a gap within the step, moving the blocks by at most this much;
/// the certified step leaves them where they are.
pub const GAP_TOLERANCE: f64 = 1e-9;

/// The certified range of one axis of the base acceleration.
#[derive(Debug, Clone)]
struct Axis {
    /// Largest certified acceleration, m/s² (≥ 0).
    plus: f64,
    /// Smallest certified acceleration, m/s² (≤ 0).
    minus: f64,
    /// Forces at `plus` and at `minus` per point, N, local frames.
    f_plus: Vec<Vec3>,
    f_minus: Vec<Vec3>,
}

/// The rest certificate of one set of contact points at one set of poses and dead loads
/// (see the module doc); axes are computed when first needed.
#[derive(Debug, Clone, Default)]
pub struct Certificate {
    /// Per axis x, y, z: not computed yet (`None`), no certified range (`Some(None)`), or
    /// the range.
    axes: [Option<Option<Axis>>; 3],
    /// Cone programs solved.
    pub programs: u32,
}

impl Certificate {
    /// The axes `forces(a_g)` reads: those along which `a_g` (m/s², table frame) has a
    /// component, or y for the field at rest when it has none.
    fn axes_of(a_g: Vec3) -> impl Iterator<Item = usize> {
        let any = a_g != Vec3::zeros();
        (0..3).filter(move |&d| if any { a_g[d] != 0.0 } else { d == 1 })
    }

    /// Whether [`Self::forces`] of `a_g` needs cone programs not solved yet (then call
    /// [`Self::prepare`] first).
    pub fn needs_programs(&self, a_g: Vec3) -> bool {
        Self::axes_of(a_g).any(|d| self.axes[d].is_none())
    }

    /// Solves the cone programs of the axes `a_g` needs (two per axis, once).
    pub fn prepare(&mut self, statics: &Statics<'_>, a_g: Vec3) {
        for d in Self::axes_of(a_g) {
            self.axis(statics, d);
        }
    }

    /// The contact forces (N, local frames, per point) that carry the base acceleration
    /// `a_g` (m/s², table frame) with the blocks at rest, or `None` if `a_g` is outside the
    /// certified range, the dead load alone is not certified, or the axes it needs have
    /// not been prepared ([`Self::prepare`]).
    pub fn forces(&self, a_g: Vec3) -> Option<Vec<Vec3>> {
        let mut weight_sum = 0.0;
        let mut parts: Vec<(f64, &Vec<Vec3>)> = Vec::new();
        // The field at a = 0 comes from the first axis used (y if none is).
        let mut zero_axis = None;
        for d in Self::axes_of(a_g) {
            let axis = self.axes[d].as_ref()?.as_ref()?;
            zero_axis.get_or_insert(axis);
            if a_g[d] == 0.0 {
                continue;
            }
            let (w, field) =
                if a_g[d] > 0.0 { (a_g[d] / axis.plus, &axis.f_plus) } else { (a_g[d] / axis.minus, &axis.f_minus) };
            if !w.is_finite() {
                return None;
            }
            weight_sum += w;
            parts.push((w, field));
        }
        if weight_sum > 1.0 {
            return None;
        }
        let axis0 = zero_axis?;
        // f₀ = (−a₋ f₊ + a₊ f₋)/(a₊ − a₋), the field at a = 0 on the axis's segment.
        let span = axis0.plus - axis0.minus;
        let (c_plus, c_minus) = if span > 0.0 { (-axis0.minus / span, axis0.plus / span) } else { (0.5, 0.5) };
        let rest = 1.0 - weight_sum;
        let mut f: Vec<Vec3> =
            axis0.f_plus.iter().zip(&axis0.f_minus).map(|(p, m)| (p * c_plus + m * c_minus) * rest).collect();
        for (w, field) in parts {
            for (fi, g) in f.iter_mut().zip(field) {
                *fi += g * w;
            }
        }
        Some(f)
    }

    /// The range of axis `d`, computed on first use.
    fn axis(&mut self, statics: &Statics<'_>, d: usize) {
        if self.axes[d].is_none() {
            let plus = largest(statics, d, 1.0);
            let minus = largest(statics, d, -1.0);
            self.programs += 2;
            self.axes[d] = Some(match (plus, minus) {
                (Some((ap, fp)), Some((am, fm))) if ap >= 0.0 && am >= 0.0 => {
                    Some(Axis { plus: ap, minus: -am, f_plus: fp, f_minus: fm })
                }
                _ => None,
            });
        }
    }
}

/// The equation rows of the statics: six per free body, less the y translation a rigid end
/// restraint holds (it takes any force); `(row of each body's force and moment components
/// or usize::MAX, their number, the free bodies' weight in N)`.
fn equation_rows(s: &Statics<'_>) -> (Vec<[usize; 6]>, usize, f64) {
    let nb = s.mass.len();
    let mut eq = vec![[usize::MAX; 6]; nb];
    let mut neq = 0;
    let mut force_scale = 0.0;
    for k in 0..nb {
        if s.free[k] {
            for q in 0..6 {
                if !(q == 1 && s.held_y[k]) {
                    eq[k][q] = neq;
                    neq += 1;
                }
            }
            force_scale += s.mass[k] * s.gravity;
        }
    }
    (eq, neq, force_scale)
}

/// The largest base acceleration (m/s², along `sign` times axis d) carried at rest inside
/// the reduced cones, and its forces (N per point, local frames); `None` if the program
/// has no solution (not even the dead load is carried).
fn largest(s: &Statics<'_>, d: usize, sign: f64) -> Option<(f64, Vec<Vec3>)> {
    let nb = s.mass.len();
    let (eq, neq, force_scale) = equation_rows(s);
    if neq == 0 || !(force_scale > 0.0) {
        return None;
    }
    let (fs, ls) = (force_scale, s.length_scale.max(1e-12));
    // Points that can carry a force: closed (no Signorini term), with a body that moves.
    let mut col_of = vec![usize::MAX; s.rows.len()];
    let mut nvar = 1;
    for (k, r) in s.rows.iter().enumerate() {
        if r.bias * s.closing <= s.gap_tolerance && (s.free[r.b] || (r.a != TABLE && s.free[r.a])) {
            col_of[k] = nvar;
            nvar += 3;
        }
    }
    let (mut ri, mut ci, mut vv) = (Vec::new(), Vec::new(), Vec::new());
    let mut push = |r: usize, c: usize, v: f64| {
        if v != 0.0 && r != usize::MAX {
            ri.push(r);
            ci.push(c);
            vv.push(v);
        }
    };
    // Block equations: Σ contact forces + D + λ g (−m sign e_d) = 0 (λ in g).
    let mut b = vec![0.0; neq];
    for k in 0..nb {
        if !s.free[k] {
            continue;
        }
        let (df, dm) = s.dead[k];
        for q in 0..3 {
            if eq[k][q] != usize::MAX {
                b[eq[k][q]] = -df[q] / fs;
            }
            b[eq[k][3 + q]] = -dm[q] / (fs * ls);
        }
        push(eq[k][d], 0, -sign * s.mass[k] * s.gravity / fs);
    }
    for (k, row) in s.rows.iter().enumerate() {
        let c0 = col_of[k];
        if c0 == usize::MAX {
            continue;
        }
        for (body, arm, sgn) in [(row.b, row.r_b, 1.0), (row.a, row.r_a, -1.0)] {
            if body == TABLE || !s.free[body] {
                continue;
            }
            for j in 0..3 {
                let e = row.frame.column(j).into_owned();
                let m = (arm / ls).cross(&e);
                for q in 0..3 {
                    push(eq[body][q], c0 + j, sgn * e[q]);
                    push(eq[body][3 + q], c0 + j, sgn * m[q]);
                }
            }
        }
    }
    // λ ≤ CAP_G, then the cones.
    let mut row = neq;
    let push2 = |r: usize, c: usize, v: f64, ri: &mut Vec<usize>, ci: &mut Vec<usize>, vv: &mut Vec<f64>| {
        ri.push(r);
        ci.push(c);
        vv.push(v);
    };
    push2(row, 0, 1.0, &mut ri, &mut ci, &mut vv);
    b.push(CAP_G);
    row += 1;
    let mut cones: Vec<SupportedConeT<f64>> =
        vec![SupportedConeT::ZeroConeT(neq), SupportedConeT::NonnegativeConeT(row - neq)];
    for (k, r) in s.rows.iter().enumerate() {
        let c0 = col_of[k];
        if c0 == usize::MAX {
            continue;
        }
        push2(row, c0, -reduced_friction(r.mu), &mut ri, &mut ci, &mut vv);
        push2(row + 1, c0 + 1, -1.0, &mut ri, &mut ci, &mut vv);
        push2(row + 2, c0 + 2, -1.0, &mut ri, &mut ci, &mut vv);
        b.extend([0.0, 0.0, 0.0]);
        row += 3;
        cones.push(SupportedConeT::SecondOrderConeT(3));
    }
    let a = CscMatrix::new_from_triplets(row, nvar, ri, ci, vv);
    let p = CscMatrix::zeros((nvar, nvar));
    let mut q = vec![0.0; nvar];
    q[0] = -1.0;
    let settings = DefaultSettings { verbose: false, max_iter: 200, max_threads: 1, ..DefaultSettings::default() };
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if sol.status != SolverStatus::Solved || !sol.x[0].is_finite() {
        return None;
    }
    let forces = col_of
        .iter()
        .map(|&c| if c == usize::MAX { Vec3::zeros() } else { Vec3::new(sol.x[c], sol.x[c + 1], sol.x[c + 2]) * fs })
        .collect();
    Some((sol.x[0] * s.gravity, forces))
}
