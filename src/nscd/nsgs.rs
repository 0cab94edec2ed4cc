//! The non-linear Gauss–Seidel iteration (NSGS) of one step: the sweeps over the contact
//! points, each solving its local Coulomb problem ([`super::local::solve`]) with the
//! current velocities of its two bodies and writing its impulse change back to them, and
//! the stopping rule ([`super::NsgsNorm`]).
//!
//! The seam of a variant of the iteration is here and in [`super::local`]: the order of a
//! sweep is a [`SweepPlan`] (the contact polygons, runs of points of one pair, in the
//! points' fixed order; [`super::SweepOrder`] reverses every other sweep), the local solve
//! is [`super::local::solve_from`], and [`solve`] is the loop that joins them.
//!
//! # The work of one point
//!
//! A point reads the velocities of its two bodies, which a contact polygon's points share:
//! the visit of a polygon keeps them in registers (`v`, `ω` of A and B) and writes them
//! back when it ends. The point's relative velocity is `u = Eᵀ((v_B + ω_B × r_B) − (v_A +
//! ω_A × r_A))` and an impulse change `Δr` moves the bodies by `Δv = ±M⁻¹ E Δr`, `Δω = ±I⁻¹
//! (r × E Δr)` ([`super::delassus`]): per point only its frame, its two lever arms, its
//! Delassus block and inverse, μ and the Signorini term are read, so the points of a wall
//! of a few thousand fit in a core's second-level cache.

use super::delassus::{PointRows, TABLE};
use super::held::Held;
use super::local;
use super::{NscdParams, NsgsNorm, SweepOrder};
use crate::math::{Mat3, Vec3};

/// The order of a sweep: the contact polygons (runs `[start, end)` of the points of one
/// pair) in the points' fixed order (the table's contacts first, then pairs in block
/// order). Built at each contact detection.
#[derive(Debug, Clone, Default)]
pub struct SweepPlan {
    groups: Vec<(usize, usize)>,
    widest: usize,
}

impl SweepPlan {
    /// The plan of `keys`, the pair key of every point in order (points of one pair are
    /// consecutive).
    pub fn new(keys: impl ExactSizeIterator<Item = (usize, usize)>) -> SweepPlan {
        let keys: Vec<(usize, usize)> = keys.collect();
        let mut groups = Vec::new();
        let mut start = 0;
        for k in 1..=keys.len() {
            if k == keys.len() || keys[k] != keys[start] {
                groups.push((start, k));
                start = k;
            }
        }
        let widest = groups.iter().map(|(a, b)| b - a).max().unwrap_or(0);
        SweepPlan { groups, widest }
    }

    /// The contact polygons, in the order of a forward sweep.
    pub fn groups(&self) -> &[(usize, usize)] {
        &self.groups
    }
}

/// The bodies' side of the iteration: velocities (updated in place, m/s and rad/s, table
/// frame), inverse masses per axis (1/kg), inverse inertias in the table frame (1/(kg·m²))
/// and radii (m, for the velocity norm).
pub struct BodyState<'a> {
    /// Velocities of the centroids.
    pub vel: &'a mut [Vec3],
    /// Angular velocities.
    pub angvel: &'a mut [Vec3],
    /// Inverse masses per axis (0 on an axis a restraint holds, 0 for fixed blocks).
    pub inv_m: &'a [Vec3],
    /// Inverse inertias (zeros for fixed blocks).
    pub inv_i: &'a [Mat3],
    /// The mobility of each constrained body ([`Held`]; its `inv_m` and `inv_i` are zero),
    /// `None` for the others.
    pub held: &'a [Option<Held>],
    /// Radii.
    pub radius: &'a [f64],
}

/// What the sweeps of a step did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepOutcome {
    /// Sweeps taken.
    pub sweeps: u32,
    /// The last sweep met the stopping rule.
    pub converged: bool,
    /// The largest change of a block point's velocity over the last sweep, m/s.
    pub residual_m_per_s: f64,
    /// The quadratic norm of the last sweep, when the stopping rule read it (0 otherwise).
    pub quad: f64,
}

/// Scratch of the iteration, kept across steps to avoid allocations.
#[derive(Debug, Clone, Default)]
pub struct NsgsScratch {
    sweep_vel: Vec<Vec3>,
    sweep_angvel: Vec<Vec3>,
    group_start: Vec<Vec3>,
    /// Each point's slip multiplier ν at its last slip this step (s/kg; 0: none yet), the
    /// start of its next slip solve ([`local::solve_from`]).
    nu: Vec<f64>,
}

/// The sweeps of one step from the impulses `impulse` (local frames, N·s; the warm start,
/// already applied to `bodies`' velocities) until the stopping rule of `p` holds or
/// [`NscdParams::max_iterations`] sweeps; `gh` is g h (m/s), the velocity norm's unit.
pub fn solve(
    plan: &SweepPlan,
    rows: &[PointRows],
    impulse: &mut [Vec3],
    bodies: &mut BodyState<'_>,
    p: &NscdParams,
    gh: f64,
    scratch: &mut NsgsScratch,
) -> SweepOutcome {
    let BodyState { vel, angvel, inv_m, inv_i, held, radius } = bodies;
    let (vel, angvel): (&mut [Vec3], &mut [Vec3]) = (vel, angvel);
    scratch.sweep_vel.resize(vel.len(), Vec3::zeros());
    scratch.sweep_angvel.resize(vel.len(), Vec3::zeros());
    scratch.group_start.resize(plan.widest, Vec3::zeros());
    scratch.nu.clear();
    scratch.nu.resize(rows.len(), 0.0);
    // The sweep from which the adaptive norm also accepts the quadratic one.
    let quad_after = (p.quad_after_solves / rows.len().max(1) as f64).ceil().min(u32::MAX as f64) as u32;
    let (mut residual, mut quad) = (0.0, 0.0);
    let ng = plan.groups.len();
    for it in 1..=p.max_iterations {
        scratch.sweep_vel.copy_from_slice(vel);
        scratch.sweep_angvel.copy_from_slice(angvel);
        let backward = p.sweep == SweepOrder::Symmetric && it % 2 == 0;
        let track_quad = match p.norm {
            NsgsNorm::Velocity => false,
            NsgsNorm::Quad => true,
            NsgsNorm::Adaptive => it >= quad_after,
        };
        let (mut sum_du, mut sum_wr) = (0.0f64, 0.0f64);
        for gi in 0..ng {
            let (g0, g1) = plan.groups[if backward { ng - 1 - gi } else { gi }];
            if track_quad {
                scratch.group_start[..g1 - g0].copy_from_slice(&impulse[g0..g1]);
            }
            visit(
                &rows[g0..g1],
                &mut impulse[g0..g1],
                &mut scratch.nu[g0..g1],
                backward,
                p,
                vel,
                angvel,
                (inv_m, inv_i, held),
            );
            if track_quad {
                for ((row, r), r0) in rows[g0..g1].iter().zip(&impulse[g0..g1]).zip(&scratch.group_start) {
                    let dr = r - r0;
                    if dr != Vec3::zeros() {
                        sum_du += (row.w * dr).norm_squared();
                    }
                    sum_wr += (row.w * r).norm_squared();
                }
            }
        }
        // The largest change of a block point's velocity over the sweep.
        residual = 0.0f64;
        for k in 0..vel.len() {
            let dv = (vel[k] - scratch.sweep_vel[k]).norm() + (angvel[k] - scratch.sweep_angvel[k]).norm() * radius[k];
            residual = residual.max(dv);
        }
        if track_quad {
            quad = if sum_wr > 0.0 { (sum_du / sum_wr).sqrt() } else { sum_du.sqrt() / gh };
        }
        let converged = match p.norm {
            NsgsNorm::Velocity => residual / gh <= p.tolerance,
            NsgsNorm::Quad => quad <= p.tolerance,
            NsgsNorm::Adaptive => residual / gh <= p.tolerance || (track_quad && quad <= p.quad_tolerance),
        };
        if converged {
            return SweepOutcome { sweeps: it, converged: true, residual_m_per_s: residual, quad };
        }
    }
    SweepOutcome { sweeps: p.max_iterations, converged: false, residual_m_per_s: residual, quad }
}

/// One visit of a contact polygon (its points `rows`, their impulses `impulse`): up to
/// [`NscdParams::polygon_passes`] passes over its points (backward if `backward`), the two
/// bodies' velocities held in registers; `nu` the points' slip multipliers.
#[allow(clippy::too_many_arguments)]
#[inline]
fn visit(
    rows: &[PointRows],
    impulse: &mut [Vec3],
    nu: &mut [f64],
    backward: bool,
    p: &NscdParams,
    vel: &mut [Vec3],
    angvel: &mut [Vec3],
    (inv_m, inv_i, held): (&[Vec3], &[Mat3], &[Option<Held>]),
) {
    let (a, b) = (rows[0].a, rows[0].b);
    let has_a = a != TABLE;
    let z = Vec3::zeros();
    let (mut va, mut wa, ma, ia) =
        if has_a { (vel[a], angvel[a], inv_m[a], inv_i[a]) } else { (z, z, z, Mat3::zeros()) };
    let (mut vb, mut wb, mb, ib) = (vel[b], angvel[b], inv_m[b], inv_i[b]);
    let (ha, hb) = (if has_a { held[a].as_ref() } else { None }, held[b].as_ref());
    let omega = p.relaxation;
    let n = rows.len();
    for pass in 0..p.polygon_passes {
        let last = pass + 1 == p.polygon_passes;
        let (mut pass_du, mut pass_wr) = (0.0f64, 0.0f64);
        for idx in 0..n {
            let k = if backward { n - 1 - idx } else { idx };
            let row = &rows[k];
            let d = (vb + wb.cross(&row.r_b)) - (va + wa.cross(&row.r_a));
            let u = row.frame.tr_mul(&d);
            let r_old = impulse[k];
            let mut q = u - row.w * r_old;
            q.x += row.bias;
            let mut r = local::solve_from(&row.w, &row.w_inv, &q, row.mu, &mut nu[k]);
            if omega != 1.0 {
                r = local::project(&(omega * r + (1.0 - omega) * r_old), row.mu);
            }
            let dr = r - r_old;
            if dr != Vec3::zeros() {
                let pw = row.frame * dr;
                vb += mb.component_mul(&pw);
                wb += ib * row.r_b.cross(&pw);
                va -= ma.component_mul(&pw);
                wa -= ia * row.r_a.cross(&pw);
                if let Some(h) = hb {
                    let (dv, dw) = h.apply(&pw, &row.r_b.cross(&pw));
                    vb += dv;
                    wb += dw;
                }
                if let Some(h) = ha {
                    let (dv, dw) = h.apply(&pw, &row.r_a.cross(&pw));
                    va -= dv;
                    wa -= dw;
                }
                impulse[k] = r;
                if !last {
                    pass_du = pass_du.max((row.w * dr).norm_squared());
                    pass_wr = pass_wr.max((row.w * r).norm_squared());
                }
            }
        }
        if last || pass_du <= p.tolerance * p.tolerance * pass_wr {
            break;
        }
    }
    vel[b] = vb;
    angvel[b] = wb;
    if has_a {
        vel[a] = va;
        angvel[a] = wa;
    }
}

/// The natural-map residual of a step's contact problem at the impulses `impulse` (local
/// frames, N·s) and the bodies' velocities `vel`, `angvel` consistent with them,
/// dimensionless; `gh` is g h (m/s), the floor of its denominator (a wall in free flight).
///
/// Per point α, De Saxcé's natural map of the Signorini–Coulomb conditions (De Saxcé &
/// Feng 1998; the residual of Acary, Brémond & Huber 2018 and of the FCLIB benchmarks):
///
/// ```text
/// φ_α = r_α − proj_{K_μ}(r_α − ρ_α (u_α + μ ‖u_{t,α}‖ e_n)),    ρ_α = 1 / w̄_α,  w̄_α = tr W_αα / 3
/// ```
///
/// zero exactly when the point's impulse and relative velocity (with the Signorini term)
/// satisfy Signorini and Coulomb, whatever method made them. It is weighted into a
/// velocity (`w̄_α φ_α`, m/s) and taken relative to the velocities the impulses produce,
/// as LMGC90's quadratic norm is: `‖(w̄_α φ_α)‖₂ / max(‖(W_αα r_α)‖₂, g h)`. A point held
/// against slip (`base_sliding = "held"`) is a Coulomb point at
/// [`super::contacts::HELD_FRICTION`].
pub fn natural_residual(rows: &[PointRows], impulse: &[Vec3], vel: &[Vec3], angvel: &[Vec3], gh: f64) -> f64 {
    let mut sum = NaturalSum::default();
    for (row, r) in rows.iter().zip(impulse) {
        let mut u = row.velocity(vel, angvel);
        u.x += row.bias;
        sum.add(row, r, &u);
    }
    sum.residual(gh)
}

/// The sums of [`natural_residual`] point by point, for a loop that already has each
/// point's relative velocity: the same additions in the same order give the same value
/// bit for bit.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct NaturalSum {
    num: f64,
    den: f64,
}

impl NaturalSum {
    /// Adds the point `row` at the impulse `r` and the relative velocity `u` (local frame,
    /// m/s, Signorini's term added to uₙ).
    #[inline(always)]
    pub(super) fn add(&mut self, row: &PointRows, r: &Vec3, u: &Vec3) {
        let wbar = row.w.trace() / 3.0;
        if !(wbar > 0.0) {
            return;
        }
        let rho = 1.0 / wbar;
        let ut = (u.y * u.y + u.z * u.z).sqrt();
        let phi = r - local::project(&(r - rho * Vec3::new(u.x + row.mu * ut, u.y, u.z)), row.mu);
        self.num += wbar * wbar * phi.norm_squared();
        self.den += (row.w * r).norm_squared();
    }

    /// The residual of the points added; `gh` (m/s) the floor of its denominator.
    pub(super) fn residual(&self, gh: f64) -> f64 {
        if self.num == 0.0 {
            0.0
        } else {
            self.num.sqrt() / self.den.sqrt().max(gh)
        }
    }
}
