//! The static lateral load protocol (Santa-Cruz et al. 2021, §4.1 and §4.2, after
//! Zanelli et al. 2019): a trapezoidal pressure on the face of the wall, applied once, solved
//! to equilibrium; the output is the out-of-plane top displacement and the drift.
//!
//! 1. Gravity only: the layout settles to equilibrium (unbalanced-force ratio below
//!    [`PenaltyParams::tolerance`](crate::dem::PenaltyParams::tolerance)); this is the reference state of every displacement.
//! 2. The pressure is applied at once as a dead load, computed on the reference
//!    configuration, and the model is solved to equilibrium again.
//! 3. Collapse: a top point moves more than [`LateralParams::collapse_displacement_fraction`]
//!    of the wall width, or no equilibrium within [`PenaltyParams::max_steps`](crate::dem::PenaltyParams::max_steps) steps.
//!
//! # The load
//!
//! The pressure varies linearly with height over the wall, from
//! [`LateralParams::pressure_base_pa`] at the lowest point of the wall (z_min) to
//! [`LateralParams::pressure_top_pa`] at its highest (z_max), in Pa (N/m² of face area). It
//! acts normal to the face, inward, on every *loaded face*: a block face whose outward
//! normal points to −y (n_y < −0.5, i.e. within 60° of −y) and that is exposed (the point
//! 2 mm outside its centroid lies in no other block). The wall is therefore pushed towards
//! +y, the side it falls to on the tilting table. On a battered face (normal tilted by the
//! batter angle β from −y) the horizontal component is p cos β per unit face area, that is p
//! per unit of vertical projected area, and a small downward component p sin β comes with
//! it.
//!
//! Per triangle of a face polygon the force is −n ∫p dA = −n A p(z_c) (p linear, so the
//! mean is the value at the centroid) and the moment about the body centroid c is
//! ∫(x − c) × (−p n) dA, integrated exactly with the three edge-midpoint rule (exact for
//! the quadratic integrand).
//!
//! # Defaults, and why
//!
//! The paper gives no values for its "static trapezoidal lateral load due to service
//! conditions". The defaults are p = 1.0 kPa at the base and 0.5 kPa at the top:
//! - on the full-scale wall (H 1.0 m, B 0.45 m, b 0.25 m, 2400 kg/m³, weight 8.24 kN per
//!   metre of wall) the resultant is 0.75 kN/m, a load multiplier of 0.09, a service level
//!   well below the collapse multiplier of such walls (tan α_max ≈ 0.3 on the tilting
//!   table);
//! - it is the order of the wind pressure on a free-standing garden or field wall near the
//!   ground (EN 1991-1-4: peak velocity pressure ≈ 0.5–1 kPa at z ≤ 2 m), or of a light
//!   earth-pressure surcharge on a terrace wall.
//!
//! A study sets other values under `[lateral]`.

use super::monitors::{monitor_displacements, monitor_points, MonitorPoint};
use super::settle::{settle, SettleError};
pub use super::tilt::NoLoad;
use crate::dem::motion::poses;
use crate::dem::{solve_static, Cascade, End, MovedKey, MovedValue};
use crate::dem::{DemError, Simulation, SolverParams};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Static lateral load parameters. Defaults in brackets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LateralParams {
    /// Pressure at the base of the wall (its lowest point), Pa \[1000\].
    pub pressure_base_pa: f64,
    /// Pressure at the top of the wall (its highest point), Pa \[500\].
    pub pressure_top_pa: f64,
    /// Collapse when a top point has moved (in y) more than this fraction of the wall width
    /// \[0.5\].
    pub collapse_displacement_fraction: f64,
    /// Studies only: after the service test, also find the collapse load multiplier λ of
    /// this pressure, by the DEM pushover ([`super::lateral_pushover`]) with a penalty
    /// solver and by limit analysis (`crate::limit::limit_lateral`) of the same layout;
    /// with `[solver] kind = "limit"`, by limit analysis alone \[false\]. The service test
    /// and its columns are unchanged by it.
    pub pushover: bool,
    /// Relative width `(λ_unstable − λ_stable) / λ_unstable` of the pushover's final
    /// bracket of λ, in (0, 1); unset, each method's own: \[0.02\] for the penalty DEM's
    /// pushover ([`PENALTY_PUSHOVER_RESOLUTION`]), \[0.01\] for the rigid pushover by nscd
    /// ([`RIGID_PUSHOVER_RESOLUTION`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pushover_resolution: Option<f64>,
    /// Deprecated: `[solver.penalty] tolerance` (`crate::dem::PenaltyParams::tolerance`),
    /// which this key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Deprecated: `[solver.penalty] max_steps` (`crate::dem::PenaltyParams::max_steps`),
    /// which this key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
}

impl Default for LateralParams {
    fn default() -> Self {
        LateralParams {
            pressure_base_pa: 1000.0,
            pressure_top_pa: 500.0,
            collapse_displacement_fraction: 0.5,
            pushover: false,
            pushover_resolution: None,
            tolerance: None,
            max_steps: None,
        }
    }
}

impl LateralParams {
    /// The stages of the static solve of the load with the solver `kind`: the static
    /// lateral load's default is plain dynamic relaxation ([`Cascade::RELAXATION`]); a
    /// penalty solver with more stages probes up to the collapse displacement.
    /// `Cascade::RELAXATION` for a solver that is not a penalty method.
    pub fn cascade(&self, kind: crate::dem::SolverKind) -> Cascade {
        kind.cascade(Cascade::RELAXATION).unwrap_or(Cascade::RELAXATION)
    }

    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("pressure_base_pa", self.pressure_base_pa, self.pressure_base_pa >= 0.0, ">= 0"),
            ("pressure_top_pa", self.pressure_top_pa, self.pressure_top_pa >= 0.0, ">= 0"),
            (
                "collapse_displacement_fraction",
                self.collapse_displacement_fraction,
                self.collapse_displacement_fraction > 0.0,
                "> 0",
            ),
            (
                "pushover_resolution",
                self.pushover_resolution.unwrap_or(PENALTY_PUSHOVER_RESOLUTION),
                self.pushover_resolution.is_none_or(|r| r > 0.0 && r < 1.0),
                "in (0, 1)",
            ),
        ])?;
        self.moved().iter().try_for_each(MovedKey::check)
    }

    /// The penalty settings written under this table's former keys (deprecated; see
    /// [`MovedKey`]), in field order.
    pub fn moved(&self) -> Vec<MovedKey> {
        [
            self.tolerance.map(|v| MovedKey::new("tolerance", MovedValue::Tolerance(v))),
            self.max_steps.map(|v| MovedKey::new("max_steps", MovedValue::MaxSteps(v))),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    /// These parameters without the former keys ([`Self::moved`]), once they are applied
    /// to the solver's settings.
    pub fn without_moved(self) -> LateralParams {
        LateralParams { tolerance: None, max_steps: None, ..self }
    }

    /// The penalty DEM pushover's final bracket width: [`Self::pushover_resolution`] when
    /// set, else [`PENALTY_PUSHOVER_RESOLUTION`].
    pub fn penalty_pushover_resolution(&self) -> f64 {
        self.pushover_resolution.unwrap_or(PENALTY_PUSHOVER_RESOLUTION)
    }

    /// The rigid pushover's final bracket width: [`Self::pushover_resolution`] when set,
    /// else [`RIGID_PUSHOVER_RESOLUTION`].
    pub fn rigid_pushover_resolution(&self) -> f64 {
        self.pushover_resolution.unwrap_or(RIGID_PUSHOVER_RESOLUTION)
    }
}

/// The penalty DEM pushover's default bracket width (2 % of λ): each of its trials is a
/// static solve of the elastic joints to the unbalanced-force ratio.
pub const PENALTY_PUSHOVER_RESOLUTION: f64 = 0.02;

/// The rigid pushover's default bracket width (1 % of λ), as `drystone lateral --solver
/// nscd`, a study and Python run it.
pub const RIGID_PUSHOVER_RESOLUTION: f64 = 0.01;

/// Outcome of a static lateral load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LateralResult {
    /// Equilibrium reached under the load.
    pub equilibrium: bool,
    /// Why not, when `equilibrium` is false: `total_displacement`, or `step_budget` (no
    /// equilibrium within the step budget).
    pub collapse_reason: Option<String>,
    /// Monitor names (by default `top_left`, `top_centre`, `top_right`).
    pub monitors: Vec<String>,
    /// Out-of-plane (y) displacement of each monitor from the gravity-only state, m; at the
    /// end of the run (the equilibrium, or the state when collapse was declared).
    pub displacement_m: Vec<f64>,
    /// Largest |displacement| of the monitors, m.
    pub max_displacement_m: f64,
    /// Drift: `max_displacement_m` / wall height (dimensionless).
    pub drift: f64,
    /// Wall height H (z extent of the layout), m.
    pub height_m: f64,
    /// Wall width (y extent of the layout), m.
    pub width_m: f64,
    /// Resultant of the pressure on the wall (world frame, N): y is the lateral force.
    pub resultant_n: Vec3,
    /// Total weight of the movable blocks, N.
    pub weight_n: f64,
    /// Number of loaded faces.
    pub loaded_faces: usize,
    /// Unbalanced-force ratio at the end.
    pub unbalanced_ratio: f64,
    /// Engine steps (settling and loaded solve).
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
}

/// Errors of the static lateral load protocol.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum LateralError {
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
    /// The layout does not stand as given under gravity alone (see [`super::settle`]).
    #[error(transparent)]
    DoesNotStand(SettleError),
    /// A lateral-load or solver parameter is out of range.
    #[error("parameter {0}")]
    Parameter(OutOfRange),
    /// The pressure of a pushover resolves to no force ([`check_pushover_force`]).
    #[error(transparent)]
    NoLoad(NoLoad),
    /// The solver chosen does not give the static lateral load's equilibrium
    /// (`protocol::run_lateral`): the protocol seam's refusal (`protocol::Unsupported`), as
    /// text.
    #[error("{0}")]
    Unsupported(String),
}

/// Checks that a pushover has a load to multiply: a collapse multiplier of zero pressure
/// does not exist (the search would double λ to its bound and report that).
///
/// # Errors
/// [`OutOfRange`] for `pressure_base_pa` when both pressures are 0.
pub fn check_pushover_load(params: &LateralParams) -> Result<(), OutOfRange> {
    if params.pressure_base_pa == 0.0 && params.pressure_top_pa == 0.0 {
        return Err(OutOfRange::new(
            "pressure_base_pa",
            0.0,
            "> 0, or pressure_top_pa > 0: a pushover multiplies the pressure, and both are 0",
        ));
    }
    Ok(())
}

/// Checks that the pressure of a pushover resolves to a load on the wall: at least one
/// exposed face takes it and the resultant force is not zero (a wall without an exposed
/// face towards −y, e.g. one whose front faces slope by more than 60° from vertical, takes
/// no pressure, and a multiplier of no load does not exist).
///
/// # Errors
/// [`NoLoad`] with the pressures, the number of loaded faces and the resultant's norm (N).
pub fn check_pushover_force(params: &LateralParams, loads: &[(Vec3, Vec3)], loaded_faces: usize) -> Result<(), NoLoad> {
    let force_n = loads.iter().fold(Vec3::zeros(), |s, (f, _)| s + f).norm();
    if loaded_faces == 0 || !(force_n > 0.0) {
        return Err(NoLoad {
            pressure_base_pa: params.pressure_base_pa,
            pressure_top_pa: params.pressure_top_pa,
            loaded_faces,
            force_n,
        });
    }
    Ok(())
}

/// The pressure load on each body: (force, moment about the body centroid), world frame,
/// N and N·m, for bodies in their current positions. Also returns the number of loaded
/// faces. Fixed bodies get nothing.
///
/// `z0`, `z1`: the heights (m) where the pressure is `p0` and `p1` (Pa); linear in between
/// and extrapolated linearly outside.
pub fn pressure_loads(sim: &Simulation, z0: f64, z1: f64, p0: f64, p1: f64) -> (Vec<(Vec3, Vec3)>, usize) {
    let shapes: Vec<_> = sim.state.bodies.iter().map(|b| b.world_shape()).collect();
    let slope = if z1 > z0 { (p1 - p0) / (z1 - z0) } else { 0.0 };
    let p = |z: f64| p0 + slope * (z - z0);
    let mut out = vec![(Vec3::zeros(), Vec3::zeros()); sim.state.bodies.len()];
    let mut loaded = 0;
    const PROBE_M: f64 = 2e-3;
    for (i, (b, s)) in sim.state.bodies.iter().zip(&shapes).enumerate() {
        if b.fixed() {
            continue;
        }
        for f in &s.faces {
            if f.normal.y >= -0.5 {
                continue;
            }
            let verts: Vec<Vec3> = f.vertices.iter().map(|&k| s.vertices[k]).collect();
            let centroid = verts.iter().fold(Vec3::zeros(), |a, v| a + v) / verts.len() as f64;
            let probe = centroid + f.normal * PROBE_M;
            let covered = shapes.iter().enumerate().any(|(j, o)| j != i && o.signed_distance(&probe) > 0.0);
            if covered {
                continue;
            }
            loaded += 1;
            let (mut force, mut moment) = (Vec3::zeros(), Vec3::zeros());
            for k in 1..verts.len() - 1 {
                let (a, bb, c) = (verts[0], verts[k], verts[k + 1]);
                let area = 0.5 * (bb - a).cross(&(c - a)).norm();
                let tc = (a + bb + c) / 3.0;
                force -= f.normal * (area * p(tc.z));
                // ∫ p (x − c) dA by the edge-midpoint rule (exact for quadratics).
                let mids = [0.5 * (a + bb), 0.5 * (bb + c), 0.5 * (c + a)];
                let first: Vec3 = mids.iter().map(|m| (m - b.pos) * p(m.z)).fold(Vec3::zeros(), |s, v| s + v);
                moment -= (first * (area / 3.0)).cross(&f.normal);
            }
            out[i].0 += force;
            out[i].1 += moment;
        }
    }
    (out, loaded)
}

/// The start the static lateral load and its pushover share: the layout settled under
/// gravity at tilt 0 with the solver's density scaling at most scalar (a load past the
/// wall's capacity collapses it within one solve, and block-scaled collapse dynamics can
/// blow up: `DensityScaling::Block`), its monitors and their positions then, and the
/// pressure's loads at λ = 1 (not applied).
pub(super) struct SettledUnderLoad {
    /// The settled simulation.
    pub sim: Simulation,
    /// The monitor points.
    pub monitors: Vec<MonitorPoint>,
    /// Their world positions in the settled state, m.
    pub reference: Vec<Vec3>,
    /// Force (N) and moment about the centroid (N·m) of the pressure on each body at λ = 1.
    pub loads: Vec<(Vec3, Vec3)>,
    /// Faces the pressure loads.
    pub loaded_faces: usize,
    /// Wall width (y extent), m.
    pub width: f64,
    /// Wall height (z extent), m.
    pub height: f64,
    /// Weight of the movable blocks, N.
    pub weight_n: f64,
    /// The joints' elastic displacement scale before settling
    /// ([`elastic_scale`](super::tilt::elastic_scale)), m.
    pub elastic: f64,
    /// When the test started.
    pub t0: Instant,
}

/// Checks the parameters and the solver's settings, settles the layout and hands the
/// settled state to `observe(0, true, state)`.
///
/// # Errors
/// As [`run_lateral_penalty`].
pub(super) fn prepare(
    layout: &Layout,
    solver: SolverParams,
    params: &LateralParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<SettledUnderLoad, LateralError> {
    params.validate().map_err(LateralError::Parameter)?;
    let solver = crate::dem::with_moved(solver, &params.moved());
    solver.validate_static().map_err(LateralError::Parameter)?;
    let t0 = Instant::now();
    let mut sim =
        Simulation::new(layout, SolverParams { density_scaling: solver.density_scaling.without_block(), ..solver });
    let monitors: Vec<MonitorPoint> = monitor_points(layout, &sim);
    let all = layout.bounds();
    let (width, height) = (all.extent().y, all.extent().z);
    sim.set_tilt(0.0);
    let elastic = super::tilt::elastic_scale(layout, &sim);
    settle(&mut sim, layout, solver.penalty.tolerance, solver.penalty.max_steps).map_err(|e| match e {
        SettleError::Dem(e) => LateralError::Dem(e),
        other => LateralError::DoesNotStand(other),
    })?;
    observe(0.0, true, &sim);
    let reference: Vec<Vec3> = monitors.iter().map(|m| sim.state.bodies[m.body].to_world(&m.local)).collect();
    let (loads, loaded_faces) =
        pressure_loads(&sim, all.min.z, all.max.z, params.pressure_base_pa, params.pressure_top_pa);
    let weight_n =
        sim.state.bodies.iter().filter(|b| !b.fixed()).map(|b| b.mass).sum::<f64>() * sim.state.gravity.norm();
    Ok(SettledUnderLoad { sim, monitors, reference, loads, loaded_faces, width, height, weight_n, elastic, t0 })
}

/// The static lateral load test of a layout by the penalty DEM: the driver of the lateral
/// load's penalty way (`protocol::lateral`), which the protocol seam calls once it has
/// chosen the method (`solver.kind` names the cascade of static solves; the default is
/// plain dynamic relaxation). The states of the test go to `observe(load_factor, stable,
/// state)`: the settled state under gravity alone (load factor 0), then the state at the
/// end of the loaded solve (load factor 1; stable if it is an equilibrium). Observing
/// changes nothing in the test. Run it through `protocol::run_lateral` (or
/// `protocol::Protocol::run`), which chooses the method.
///
/// # Errors
/// [`LateralError::DoesNotStand`] if the layout does not stand as given under gravity,
/// [`LateralError::Dem`] if the state blows up, [`LateralError::Parameter`] for bad
/// parameters. A wall that collapses under the load is a result (`equilibrium` false), not
/// an error.
pub fn run_lateral_penalty(
    layout: &Layout,
    solver: SolverParams,
    params: &LateralParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<LateralResult, LateralError> {
    let SettledUnderLoad { mut sim, monitors, reference, loads, loaded_faces, width, height, weight_n, t0, .. } =
        prepare(layout, solver, params, observe)?;
    let penalty = crate::dem::with_moved(solver, &params.moved()).penalty;
    let mut resultant = Vec3::zeros();
    for (k, (f, m)) in loads.iter().enumerate() {
        sim.state.external_force[k] = *f;
        sim.state.external_torque[k] = *m;
        resultant += f;
    }
    let disp = |sim: &Simulation| monitor_displacements(sim, &monitors, &reference);
    let limit = params.collapse_displacement_fraction * width;
    let check = |sim: &Simulation| disp(sim).iter().any(|d| d.abs() > limit).then_some("total_displacement");
    let solve = crate::dem::StaticSolve::of(&penalty, params.cascade(solver.kind), Some(limit));
    let start = poses(&sim);
    let reason = match solve_static(&mut sim, &solve, &start, check)?.end {
        End::Equilibrium => None,
        End::Stopped(r) => Some(r.to_string()),
        End::Budget => Some("step_budget".to_string()),
        End::Unstable(..) => Some("no_equilibrium".to_string()),
    };
    observe(1.0, reason.is_none(), &sim);
    let displacement_m = disp(&sim);
    let max_displacement_m = displacement_m.iter().fold(0.0_f64, |a, d| a.max(d.abs()));
    Ok(LateralResult {
        equilibrium: reason.is_none(),
        collapse_reason: reason,
        monitors: monitors.iter().map(|m| m.name.clone()).collect(),
        displacement_m,
        max_displacement_m,
        drift: max_displacement_m / height,
        height_m: height,
        width_m: width,
        resultant_n: resultant,
        weight_n,
        loaded_faces,
        unbalanced_ratio: sim.stats().unbalanced_ratio,
        steps: sim.state.steps,
        dt_s: sim.dt(),
        wall_time_s: t0.elapsed().as_secs_f64(),
    })
}
