//! The vertical compression test of a wall: the wall between the foundation (the table) and
//! the loading beam, the vertical force cycled between two stresses and then, optionally,
//! raised ([`run_compression_penalty`]).
//!
//! # The rig
//!
//! The in-plane test's rig ([`crate::loading::inplane::Rig`]) with no lateral drive: the
//! loading beam laid on the top course, its horizontal degrees of freedom and its rotations
//! out of the plane held, its rotation in the plane held (the beam kept level,
//! [`BeamRotation::Fixed`], the default) or free about the actuator's point at the shear
//! span, as the in-plane test holds it. The vertical force `N = σ L t` (σ the stress on the
//! wall's top, the beam's weight part of it) acts on the beam.
//!
//! # The history
//!
//! The first loading branch is the in-plane test's vertical phase, one computation
//! ([`stand_under_vertical_force`]): the wall settled under gravity with the beam on it,
//! then solved under `σ0`. Then `cycles` load–unload cycles: unloaded to
//! [`CompressionParams::unload_to_mpa`] (by default the actuator at zero, the beam's own
//! weight on the wall) and loaded again to `σ0`, the first cycle's loading branch being the
//! first loading. Each branch's end is one static solve from its start, as the vertical
//! phase's is; the curve's points within a branch are static solves from the branch's start
//! on a copy of the state ([`CompressionParams::points_per_branch`]), read beside it. After
//! the cycles, optionally, the stress raised from the unloaded state to
//! [`CompressionParams::raise_to_mpa`] in `points_per_branch` increments, each a static
//! solve from the last, stopping at the first that finds no equilibrium: on joints whose law
//! bounds the pressure (the `crushing` closure law, `q = min(Kn u, fc)`) the wall's
//! compressive strength is bracketed there.
//!
//! # The readings
//!
//! As the Stone Masonry Database reads them (Vanin et al. 2017, Bull. Earthquake Eng.
//! 15:5435):
//!
//! * the wall's vertical modulus `Epc`: the secant of the first loading branch, the stress
//!   the actuator added over the wall's shortening (the beam's settlement over the wall's
//!   height `H`); the in-plane test reads the same number from its vertical phase;
//! * the secant of each cycle's loading branch, `(σ0 − σu) H / Δz`;
//! * the residual settlement after each unloading, mm: how far below the first loading
//!   branch's state at the unloading stress `σu` the beam stands (at the default `σu`, the
//!   settled state under the beam's own weight); a wall of linear elastic joints returns to
//!   it (no residual);
//! * the force–shortening curve, and the compressive strength's bracket where the raise lost
//!   equilibrium.
//!
//! A wall of rigid blocks on linear joints of normal stiffness `Kn` in `c` full-length
//! courses has every joint of its height in series (the table's, the `c − 1` beds, the
//! beam's): its modulus is `Kn H / (c + 1)` (`tests/suite/compression.rs`).

use crate::dem::motion::poses;
use crate::dem::{solve_static, DemError, End, Simulation, SolverParams, StaticSolve};
use crate::layout::{Layout, VerticalLoadRig};
use crate::loading::inplane::{
    check_joint_closure, stand_under_vertical_force, BeamRotation, InPlaneError, InPlaneParams, Rig, VerticalPhase,
};
use crate::math::Vec3;
use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The most load–unload cycles ([`CompressionParams::cycles`]).
pub const MAX_CYCLES: u32 = 100;

/// The most curve points a branch may ask ([`CompressionParams::points_per_branch`]).
pub const MAX_POINTS_PER_BRANCH: u32 = 100;

/// The compression test's parameters (`[compression]` in a study). Defaults in brackets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CompressionParams {
    /// The vertical stress on the wall's top at which the modulus is read, MPa, in (0,
    /// 1000], the beam's weight part of it (the wall's self-weight comes on top) \[0.5\].
    pub sigma0_mpa: f64,
    /// Load–unload cycles to `sigma0_mpa`, in [1, 100] \[3\]: the granite walls' tests
    /// started with compression cycles whose loading branch gave `Epc` (Vasconcelos &
    /// Lourenço 2009, J. Struct. Eng. 135(10):1269; the database's `Epc_MPa`,
    /// data/inplane_granite/README.md, which does not give their count: three is this
    /// default's reading of the paper).
    pub cycles: u32,
    /// The stress each unloading goes down to, MPa, at least the beam's own weight over the
    /// wall's plan area and below `sigma0_mpa`; unset: the beam's own weight (the actuator
    /// at zero) \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unload_to_mpa: Option<f64>,
    /// A stress to raise to after the cycles, MPa, above `sigma0_mpa` and at most 1000, in
    /// `points_per_branch` increments, stopping where equilibrium is lost (the compressive
    /// strength's bracket); unset: no raise \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub raise_to_mpa: Option<f64>,
    /// Curve points per branch (the branch's end included), in [1, 100] \[4\]: the
    /// readings are the branches' ends and do not depend on it, but for the raise, whose
    /// increments it sets.
    pub points_per_branch: u32,
    /// The loading beam's rotation in the wall's plane: held level (`fixed`) or free about
    /// the actuator's point at `shear_span_m` (`free`, the in-plane test's rig)
    /// \[fixed\].
    pub beam_rotation: BeamRotation,
    /// The actuator's height above the base, m, at least the wall's height: with a free
    /// beam rotation it is required (it sets the beam's depth, as the in-plane test's shear
    /// span does), with a held one it is not read \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_span_m: Option<f64>,
}

impl Default for CompressionParams {
    fn default() -> Self {
        CompressionParams {
            sigma0_mpa: 0.5,
            cycles: 3,
            unload_to_mpa: None,
            raise_to_mpa: None,
            points_per_branch: 4,
            beam_rotation: BeamRotation::Fixed,
            shear_span_m: None,
        }
    }
}

impl CompressionParams {
    /// Checks the ranges that need no layout.
    ///
    /// # Errors
    /// The first key out of its range, named.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            (
                "sigma0_mpa",
                self.sigma0_mpa,
                self.sigma0_mpa > 0.0 && self.sigma0_mpa <= 1e3,
                "in (0, 1000] (the vertical stress on the wall's top, MPa)",
            ),
            ("cycles", f64::from(self.cycles), (1..=MAX_CYCLES).contains(&self.cycles), "in [1, 100]"),
            (
                "points_per_branch",
                f64::from(self.points_per_branch),
                (1..=MAX_POINTS_PER_BRANCH).contains(&self.points_per_branch),
                "in [1, 100]",
            ),
        ])?;
        if let Some(u) = self.unload_to_mpa {
            check_ranges(&[(
                "unload_to_mpa",
                u,
                u >= 0.0 && u < self.sigma0_mpa,
                "in [0, sigma0_mpa) (MPa; at least the beam's own weight over the wall's plan area)",
            )])?;
        }
        if let Some(r) = self.raise_to_mpa {
            check_ranges(&[("raise_to_mpa", r, r > self.sigma0_mpa && r <= 1e3, "in (sigma0_mpa, 1000] (MPa)")])?;
        }
        match (self.beam_rotation, self.shear_span_m) {
            (BeamRotation::Free, None) => Err(OutOfRange::without_value(
                "shear_span_m",
                "given: a free beam rotation turns about the actuator's point (its height, m)",
            )),
            (BeamRotation::Free, Some(h0)) => check_ranges(&[("shear_span_m", h0, h0 > 0.0, "> 0 (m above the base)")]),
            (BeamRotation::Fixed, _) => Ok(()),
        }
    }

    /// The in-plane test's parameters whose rig and vertical phase this test shares: its
    /// vertical stress, beam rotation and shear span.
    pub fn rig_params(&self) -> InPlaneParams {
        InPlaneParams {
            sigma0_mpa: self.sigma0_mpa,
            beam_rotation: self.beam_rotation,
            shear_span_m: self.shear_span_m,
            ..InPlaneParams::default()
        }
    }
}

/// Errors of the compression test.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum CompressionError {
    /// A parameter out of its range.
    #[error("compression.{0}")]
    Parameter(OutOfRange),
    /// A solver setting out of its range.
    #[error("solver: {0}")]
    Solver(OutOfRange),
    /// The layout carries terms of the vertical-load rig, which this test does not read.
    #[error(
        "the layout's vertical_load_rig is not ideal ({0:?}): the compression test reads no rig terms (they are the in-plane test's readings of the actuator's force); remove them"
    )]
    RigTerms(VerticalLoadRig),
    /// The rig could not be laid on the wall, or the wall does not stand under gravity or
    /// under the first loading (the in-plane test's vertical phase, its errors).
    #[error(transparent)]
    Rig(InPlaneError),
    /// The largest stress of the history closes a linear joint past what the penalty DEM's
    /// contacts hold ([`check_joint_closure`]).
    #[error(
        "compression.{key} = {stress_mpa} MPa closes the joints of material {material} by {closure_mm:.3} mm, more than the penalty DEM's contacts hold ({max_pct:.0} % of the lowest block's height): at most {max_mpa:.3} MPa on these joints. Check the stress's unit (MPa) and Kn"
    )]
    Closure {
        /// The key of the stress (`sigma0_mpa`, or `raise_to_mpa` when given).
        key: &'static str,
        /// The stress, MPa.
        stress_mpa: f64,
        /// The material's name.
        material: String,
        /// The closure σ / Kn, mm.
        closure_mm: f64,
        /// The largest closure the contacts hold, % of the lowest block's height.
        max_pct: f64,
        /// The largest stress on these joints, MPa.
        max_mpa: f64,
    },
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
}

impl CompressionError {
    /// Whether the test refused its parameters for the wall before running (every error
    /// but the wall not standing, which [`CompressionError::does_not_stand`] tells, and
    /// the engine's blow-up).
    pub fn is_refusal(&self) -> bool {
        match self {
            CompressionError::Parameter(_)
            | CompressionError::Solver(_)
            | CompressionError::RigTerms(_)
            | CompressionError::Closure { .. } => true,
            CompressionError::Rig(e) => e.is_refusal(),
            CompressionError::Dem(_) => false,
        }
    }

    /// Whether the layout did not stand as given (under gravity, or under the first
    /// loading).
    pub fn does_not_stand(&self) -> bool {
        matches!(self, CompressionError::Rig(e) if e.does_not_stand())
    }
}

impl From<InPlaneError> for CompressionError {
    /// The rig's errors, with its parameters named as this test's keys.
    fn from(e: InPlaneError) -> Self {
        match e {
            InPlaneError::Parameter(o) => CompressionError::Parameter(o),
            InPlaneError::Solver(o) => CompressionError::Solver(o),
            InPlaneError::ShearSpan { shear_span_m, .. } => CompressionError::Parameter(OutOfRange::new(
                "shear_span_m",
                shear_span_m,
                "at least the wall's height (the actuator acts on the beam, on top of the wall)",
            )),
            InPlaneError::TooHigh { key, value_m, .. } => CompressionError::Parameter(OutOfRange::new(
                key,
                value_m,
                "at most 10 times the wall's height (a probable unit mistake: millimetres for metres?)",
            )),
            InPlaneError::Dem(d) => CompressionError::Dem(d),
            other => CompressionError::Rig(other),
        }
    }
}

/// Which part of the history a curve point is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Branch {
    /// The settled state under the beam's own weight, before the first loading.
    Start,
    /// A loading branch to `sigma0_mpa`.
    Loading,
    /// An unloading branch.
    Unloading,
    /// The raise after the cycles.
    Raise,
}

/// One point of the force–shortening curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CompressionPoint {
    /// The cycle, from 1 (0 for the start; the raise: `cycles + 1`).
    pub cycle: u32,
    /// Its branch.
    pub branch: Branch,
    /// The vertical stress on the wall's top, MPa (`N / (L t)`, the beam's weight in it).
    pub stress_mpa: f64,
    /// The vertical force on the wall's top, kN (`N`, the beam's weight in it).
    pub force_kn: f64,
    /// The wall's shortening, mm: the beam's settlement from the settled state under its own
    /// weight (positive down).
    pub shortening_mm: f64,
    /// Whether its static solve ended in equilibrium.
    pub converged: bool,
}

/// The outcome of a compression test.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompressionResult {
    /// The wall's vertical modulus, MPa: the secant of the first loading branch (the
    /// database's `Epc`; [`VerticalPhase::vertical_modulus_mpa`], the in-plane test's
    /// `wall_vertical_modulus_mpa` bit for bit on the same rig).
    pub wall_vertical_modulus_mpa: f64,
    /// The secant of each cycle's loading branch, MPa, `cycles` of them, the first
    /// `wall_vertical_modulus_mpa`, the others `(σ0 − σu) H` over the beam's settlement from
    /// the unloaded state.
    pub loading_secants_mpa: Vec<f64>,
    /// The residual settlement after each cycle's unloading, mm, `cycles` of them: how far
    /// below the first loading branch's state at the unloading stress the beam stands
    /// (positive down).
    pub residual_settlements_mm: Vec<f64>,
    /// The force–shortening curve, in the order of the history.
    pub curve: Vec<CompressionPoint>,
    /// The compressive strength's bracket, MPa: the last stress of the raise in equilibrium
    /// and the first without; `None` without a raise, or when every increment of it reached
    /// equilibrium (the strength is above `raise_to_mpa`).
    pub strength_bracket_mpa: Option<[f64; 2]>,
    /// The stress of the readings, MPa.
    pub sigma0_mpa: f64,
    /// The stress unloaded to, MPa (the beam's own weight over the plan area by default).
    pub unload_to_mpa: f64,
    /// The beam's own weight over the wall's plan area, MPa.
    pub beam_stress_mpa: f64,
    /// The stress raised to, MPa (`None`: no raise).
    pub raise_to_mpa: Option<f64>,
    /// Wall length, height, thickness, m.
    pub length_m: f64,
    /// See `length_m`.
    pub height_m: f64,
    /// See `length_m`.
    pub thickness_m: f64,
    /// The wall's self-weight, kN (the beam excluded).
    pub wall_weight_kn: f64,
    /// Static solves after the first loading that ended without equilibrium (the raise's
    /// last, past the strength, included).
    pub unconverged: usize,
    /// Engine steps, settling included (the curve's points within a branch excluded: they
    /// run on copies).
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
}

/// The compression test of a wall by the penalty DEM (module doc): the driver of the
/// protocol's penalty way (`protocol::compression`). `observe(stress_mpa, converged,
/// state)` sees the state at every point of the curve, in its order.
///
/// # Errors
/// See [`CompressionError`]: bad parameters (named), a layout with vertical-load rig terms,
/// a top course not level, a wall that does not stand under gravity or under `sigma0_mpa`
/// (naming the block), a blow-up.
pub fn run_compression_penalty(
    wall: &Layout,
    solver: SolverParams,
    params: &CompressionParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<CompressionResult, CompressionError> {
    let t0 = Instant::now();
    params.validate().map_err(CompressionError::Parameter)?;
    if wall.vertical_load_rig != VerticalLoadRig::default() {
        return Err(CompressionError::RigTerms(wall.vertical_load_rig));
    }
    let rig_params = params.rig_params();
    let rig = Rig::build(wall, &rig_params)?;
    let peak = InPlaneParams { sigma0_mpa: params.raise_to_mpa.unwrap_or(params.sigma0_mpa), ..rig_params };
    let key = if params.raise_to_mpa.is_some() { "raise_to_mpa" } else { "sigma0_mpa" };
    check_joint_closure(wall, &peak).map_err(|e| match e {
        InPlaneError::JointClosure { material, sigma0_mpa, closure_mm, max_pct, sigma0_max_mpa, .. } => {
            CompressionError::Closure {
                key,
                stress_mpa: sigma0_mpa,
                material,
                closure_mm,
                max_pct,
                max_mpa: sigma0_max_mpa,
            }
        }
        other => other.into(),
    })?;
    solver.validate_static().map_err(CompressionError::Solver)?;
    let solver = SolverParams { density_scaling: solver.density_scaling.without_block(), ..solver };
    let area = rig.length_m * rig.thickness_m;
    let beam_stress_mpa = rig.beam_weight_n / area * 1e-6;
    let unload_to = params.unload_to_mpa.unwrap_or(beam_stress_mpa);
    if unload_to < beam_stress_mpa {
        return Err(CompressionError::Parameter(OutOfRange::new(
            "unload_to_mpa",
            unload_to,
            "at least the loading beam's own weight over the wall's plan area (the beam stays on the wall)",
        )));
    }
    let mut settled = None;
    let phase = stand_under_vertical_force(&rig, solver, params.beam_rotation, params.sigma0_mpa, &mut |sim| {
        settled = Some(sim.clone())
    })?;
    let settled = settled.expect("the vertical phase hands over its settled state");
    let n = params.points_per_branch;
    let mut test = Test { rig: &rig, z0: phase.start[rig.beam].0.z, unconverged: 0, curve: Vec::new(), observe };
    test.point(&settled, 0, Branch::Start, beam_stress_mpa, true);
    // The first loading: its points within, then the vertical phase's own end.
    test.probes(&settled, &phase.relax, 1, Branch::Loading, (beam_stress_mpa, params.sigma0_mpa), n)?;
    let VerticalPhase { mut sim, relax, vertical_modulus_mpa, .. } = phase;
    test.point(&sim, 1, Branch::Loading, params.sigma0_mpa, true);
    // The first loading branch's state at the unloading stress: the reference of the
    // residual settlements.
    let z_ref = if unload_to > beam_stress_mpa {
        let mut at = settled.clone();
        test.solve(&mut at, &relax, unload_to)?;
        at.state.bodies[rig.beam].pos.z
    } else {
        test.z0
    };
    let mut secants = vec![vertical_modulus_mpa];
    let mut residuals = Vec::new();
    for cycle in 1..=params.cycles {
        if cycle > 1 {
            test.probes(&sim, &relax, cycle, Branch::Loading, (unload_to, params.sigma0_mpa), n)?;
            let z_unloaded = sim.state.bodies[rig.beam].pos.z;
            let converged = test.step(&mut sim, &relax, params.sigma0_mpa)?;
            test.point(&sim, cycle, Branch::Loading, params.sigma0_mpa, converged);
            let dz = z_unloaded - sim.state.bodies[rig.beam].pos.z;
            secants.push((params.sigma0_mpa - unload_to) * rig.height_m / dz);
        }
        test.probes(&sim, &relax, cycle, Branch::Unloading, (params.sigma0_mpa, unload_to), n)?;
        let converged = test.step(&mut sim, &relax, unload_to)?;
        test.point(&sim, cycle, Branch::Unloading, unload_to, converged);
        residuals.push((z_ref - sim.state.bodies[rig.beam].pos.z) * 1e3);
    }
    let strength_bracket_mpa = match params.raise_to_mpa {
        Some(top) => test.raise(&mut sim, &relax, params.cycles + 1, unload_to, top, n)?,
        None => None,
    };
    Ok(CompressionResult {
        wall_vertical_modulus_mpa: vertical_modulus_mpa,
        loading_secants_mpa: secants,
        residual_settlements_mm: residuals,
        curve: test.curve,
        strength_bracket_mpa,
        sigma0_mpa: params.sigma0_mpa,
        unload_to_mpa: unload_to,
        beam_stress_mpa,
        raise_to_mpa: params.raise_to_mpa,
        length_m: rig.length_m,
        height_m: rig.height_m,
        thickness_m: rig.thickness_m,
        wall_weight_kn: rig.wall_weight_n * 1e-3,
        unconverged: test.unconverged,
        steps: sim.state.steps,
        dt_s: sim.dt(),
        wall_time_s: t0.elapsed().as_secs_f64(),
    })
}

/// The history's bookkeeping: the rig, the beam's settled height, the curve and its
/// observer.
struct Test<'a, 'o> {
    rig: &'a Rig,
    /// The beam's centroid height settled under its own weight, m.
    z0: f64,
    unconverged: usize,
    curve: Vec<CompressionPoint>,
    observe: &'o mut dyn FnMut(f64, bool, &Simulation),
}

impl Test<'_, '_> {
    /// Sets the actuator's force for the stress `stress_mpa` on the wall's top (the beam's
    /// weight part of it) and solves `sim` to equilibrium from its poses; whether it reached
    /// equilibrium.
    fn solve(&self, sim: &mut Simulation, relax: &StaticSolve, stress_mpa: f64) -> Result<bool, DemError> {
        let bi = self.rig.beam;
        let area = self.rig.length_m * self.rig.thickness_m;
        sim.state.external_force[bi] = Vec3::new(0.0, 0.0, -(stress_mpa * 1e6 * area - self.rig.beam_weight_n));
        let start = poses(sim);
        let out = solve_static(sim, relax, &start, |_| None::<()>)?;
        Ok(out.end == End::Equilibrium)
    }

    /// Adds the point of `sim` at the stress `stress_mpa` to the curve and hands it to the
    /// observer.
    fn point(&mut self, sim: &Simulation, cycle: u32, branch: Branch, stress_mpa: f64, converged: bool) {
        let area = self.rig.length_m * self.rig.thickness_m;
        let shortening_mm = (self.z0 - sim.state.bodies[self.rig.beam].pos.z) * 1e3;
        let force_kn = stress_mpa * area * 1e3;
        self.curve.push(CompressionPoint { cycle, branch, stress_mpa, force_kn, shortening_mm, converged });
        (self.observe)(stress_mpa, converged, sim);
    }

    /// The curve's points within a branch from `from` (at `from_mpa`) to `to_mpa`, `n`
    /// points with the branch's end: the `n − 1` within, each a static solve from `from` on a
    /// copy (read beside the history, not counted in its `unconverged`).
    #[allow(clippy::too_many_arguments)]
    fn probes(
        &mut self,
        from: &Simulation,
        relax: &StaticSolve,
        cycle: u32,
        branch: Branch,
        (from_mpa, to_mpa): (f64, f64),
        n: u32,
    ) -> Result<(), DemError> {
        for k in 1..n {
            let stress = from_mpa + (to_mpa - from_mpa) * f64::from(k) / f64::from(n);
            let mut probe = from.clone();
            let converged = self.solve(&mut probe, relax, stress)?;
            self.point(&probe, cycle, branch, stress, converged);
        }
        Ok(())
    }

    /// A solve of the history itself ([`Test::solve`]), counted in `unconverged` when it
    /// reached no equilibrium.
    fn step(&mut self, sim: &mut Simulation, relax: &StaticSolve, stress_mpa: f64) -> Result<bool, DemError> {
        let converged = self.solve(sim, relax, stress_mpa)?;
        self.unconverged += usize::from(!converged);
        Ok(converged)
    }

    /// The raise from `sim` at `from_mpa` to `to_mpa` in `n` increments, each a static
    /// solve from the last, stopping at the first without equilibrium; the bracket of the
    /// strength there (`None`: every increment reached equilibrium).
    fn raise(
        &mut self,
        sim: &mut Simulation,
        relax: &StaticSolve,
        cycle: u32,
        from_mpa: f64,
        to_mpa: f64,
        n: u32,
    ) -> Result<Option<[f64; 2]>, DemError> {
        let mut last = from_mpa;
        for k in 1..=n {
            let stress = from_mpa + (to_mpa - from_mpa) * f64::from(k) / f64::from(n);
            let converged = self.step(sim, relax, stress)?;
            self.point(sim, cycle, Branch::Raise, stress, converged);
            if !converged {
                return Ok(Some([last, stress]));
            }
            last = stress;
        }
        Ok(None)
    }
}
