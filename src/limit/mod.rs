//! Limit analysis of rigid block assemblies: the collapse load multiplier from statics
//! alone, as a second-order cone program (Livesley 1978, "Limit analysis of structures
//! formed from rigid blocks", Int. J. Numer. Meth. Eng. 12:1853; Portioli et al. 2014,
//! "Limit analysis of 3D masonry block structures with non-associative frictional joints
//! using cone programming", Comput. Struct. 143:108).
//!
//! By the lower-bound theorem, the collapse multiplier of a live load L on top of a dead
//! load D is the largest λ for which contact forces exist that balance every block under
//! `D + λ L`, with no tension (or at most the joint's tensile strength) and every force
//! inside its Coulomb cone. The contacts are those of the DEM's own detection
//! ([`crate::dem::Simulation::new`] on the layout at rest: the contact polygons of
//! [`crate::dem::contact::geometry`]); the forces act at the polygons' vertices
//! (`model` states the program). Clarabel solves it, as its dual (the kinematic
//! program, whose unknowns are the blocks' virtual velocities) unless the static program's
//! forces are needed; the dual variables of the block equations are the blocks' virtual
//! velocities at collapse, read as a mechanism ([`mechanism`]). Associative friction makes λ an upper estimate where sliding governs;
//! [`flow`] corrects it (Gilbert, Casapulla & Ahmed 2006).
//!
//! # Protocols
//!
//! * **Tilting table** ([`limit_tilt`]): gravity tilted by α is `g (0, sin α, −cos α)` in
//!   the table frame, a dead load `W (0, 0, −1)` and a live load `W (0, 1, 0)` per block of
//!   weight W, both scaled by cos α: λ = tan α_max, α_max = atan λ.
//! * **Lateral pressure** ([`limit_lateral`]): dead load the weight, live load the
//!   trapezoidal pressure of [`crate::loading::lateral`] (the forces and moments of
//!   [`pressure_loads`] on the layout at rest): λ multiplies that pressure.
//!
//! # Restraints
//!
//! A fixed block takes any force. A rigid end restraint holds the block's centroid in y:
//! a free y reaction there, as the DEM holds it. A spring end restraint carries nothing at
//! the rigid limit (its force grows with a displacement the rigid model does not have) and
//! is left out. A base held against sliding has no friction cone at the table. A layout
//! with rope restraints is refused ([`LimitError::Ropes`]): a rope's pretension acts only
//! through its deflection, which the rigid model does not have. A layout whose joints
//! crush (a `crushing` closure law, what the effect `toe_crushing` sets) is refused
//! ([`LimitError::Crushing`], naming the material or joint family): the rigid joints have
//! no crushing law, and the wall without it is not the wall asked for.
//!
//! # What is solved exactly
//!
//! The cones are exact (no linearisation). Contacts are those within the DEM's contact
//! margin at rest, open or closed; edge and vertex contacts are the DEM's nominal thin
//! rectangles ([`crate::dem::SolverParams::degenerate_width_fraction`]).

mod csc;
pub mod flow;
pub mod inplane;
pub mod mechanism;
pub(crate) mod model;

pub use crate::dem::LimitParams;
use crate::dem::SolverParams;
use crate::layout::Layout;
use crate::loading::lateral::{pressure_loads, LateralParams};
use crate::loading::mechanism::Mechanism;
use crate::math::Vec3;
use crate::range::OutOfRange;
use clarabel::solver::SolverStatus;
pub use flow::NonAssociative;
pub use mechanism::{BlockVelocity, JointMode, LimitJoint};
use model::{Friction, Model, Solution};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The live load of a limit analysis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LiveLoad {
    /// Tilting table: the weight along +y; λ = tan α_max.
    Tilt,
    /// The lateral pressure of [`crate::loading::lateral`]: p0 at the base, p1 at the top.
    Lateral {
        /// Pressure at the wall's lowest point, Pa.
        pressure_base_pa: f64,
        /// Pressure at its highest point, Pa.
        pressure_top_pa: f64,
    },
    /// The in-plane shear–compression test ([`inplane::limit_in_plane`]): a horizontal
    /// force on the loading beam at the shear span, under the constant vertical force; the
    /// live load is `N_total` along +x, so λ = V / N_total.
    InPlane {
        /// The applied vertical stress, MPa.
        sigma0_mpa: f64,
        /// The height of the horizontal force, m.
        shear_span_m: f64,
    },
}

/// Which flow rule's answer holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlowRule {
    /// The associative λ: the mechanism has no sliding joint, so it is also a mechanism of
    /// non-dilatant joints (opening and hinging do not depend on the flow rule), or the
    /// correction was not asked for or did not converge (then an upper estimate).
    Associative,
    /// The non-associative λ of the Gilbert et al. iteration (converged).
    NonAssociative,
}

/// The result of a limit analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LimitResult {
    /// The live load.
    pub protocol: LiveLoad,
    /// The collapse load multiplier that holds (see `governing`).
    pub load_multiplier: f64,
    /// Tilting table: α_max = atan(load_multiplier), degrees; `None` for the lateral load.
    pub collapse_angle_deg: Option<f64>,
    /// Which answer `load_multiplier` is.
    pub governing: FlowRule,
    /// λ with associative friction (an upper estimate where sliding governs).
    pub associative: f64,
    /// The non-associative iteration, when the associative mechanism slides and the
    /// correction is on.
    pub non_associative: Option<NonAssociative>,
    /// The collapse mechanism of the answer that holds (the DEM's form).
    pub mechanism: Mechanism,
    /// Its failing joints with their mode, lowest first.
    pub joints: Vec<LimitJoint>,
    /// Virtual velocity of every block at collapse, layout order.
    pub velocities: Vec<BlockVelocity>,
    /// Resultant of the live load, N, table frame.
    pub live_load_n: Vec3,
    /// Total weight of the free blocks, N.
    pub weight_n: f64,
    /// Free blocks, joints and contact points of the program.
    pub blocks: usize,
    /// Joints (contacts).
    pub contacts: usize,
    /// Contact points (polygon vertices).
    pub contact_points: usize,
    /// Clarabel's status of the associative program (`Solved` or `AlmostSolved`): of the
    /// static program where it was solved (a mechanism that slides with the
    /// non-associative correction on, or a joint that slips with μ = 0), else of the
    /// kinematic one.
    pub status: String,
    /// Interior-point iterations of the associative program (as `status`).
    pub solver_iterations: u32,
    /// Clarabel's own time over every program solved (associative and non-associative), s.
    pub solver_time_s: f64,
    /// Wall-clock time of the whole analysis (detection, programs, mechanism), s.
    pub wall_time_s: f64,
}

/// Errors of a limit analysis.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum LimitError {
    /// A parameter is out of range.
    #[error("limit analysis parameter {0}")]
    Parameter(OutOfRange),
    /// The layout has no free block.
    #[error("the layout has no free block: nothing to analyse")]
    NoFreeBlock,
    /// No contact was detected at all.
    #[error("no contacts: no block touches the table or another block within the contact margin")]
    NoContacts,
    /// A free block touches nothing.
    #[error("block {block} touches nothing (no contact within the contact margin): it cannot be in equilibrium")]
    Untouched {
        /// Its id.
        block: String,
    },
    /// A group of blocks touches neither the table nor a fixed block.
    #[error("block {block} and {others} other block(s) touch neither the table nor a fixed block: no load path")]
    Floating {
        /// The group's first block.
        block: String,
        /// The number of the other blocks of the group.
        others: usize,
    },
    /// The live load is zero.
    #[error("the live load is zero (lateral: no exposed face towards -y, or zero pressure)")]
    NoLiveLoad,
    /// λ is unbounded: the contacts and restraints resist any multiple of the live load.
    #[error("the load multiplier is unbounded: nothing limits the live load (the restraints or contacts resist any multiple of it)")]
    Unbounded,
    /// The layout has rope restraints: their force depends on the displacement (a taut
    /// string), which a rigid-plastic limit analysis does not have.
    #[error(
        "the layout has {count} rope restraint(s) (restraints.ropes): limit analysis does not model a rope, whose \
         force grows with the wall's displacement into it; use the penalty or nscd solver"
    )]
    Ropes {
        /// The number of ropes.
        count: usize,
    },
    /// A joint's faces crush ([`Layout::crushing_joint`]): the analysis's joints are rigid,
    /// with no crushing law, and would analyse the wall without it.
    #[error(
        "limit analysis has no crushing law: the faces' crushing of {joint} (closure crushing, strength {:.4} MPa; \
         the effect toe_crushing sets it) is not modelled; use the penalty DEM",
        strength_pa * 1e-6
    )]
    Crushing {
        /// The joint rule, `material NAME` or `joint family NAME`.
        joint: String,
        /// Its crushing strength fc, Pa.
        strength_pa: f64,
    },
    /// No λ balances the dead load.
    #[error("no equilibrium at any load multiplier: the contacts cannot carry the dead load (the mechanism moves block {block} most)")]
    Infeasible {
        /// The block that moves most in the infeasibility certificate.
        block: String,
    },
    /// The wall does not stand as given: the load multiplier λ ≤ 0, so the dead load alone
    /// (λ = 0) already drives the mechanism. No capacity: a protocol reads this as the
    /// tilting table reads a layout that moves while settling.
    #[error(
        "the layout does not stand as given: the load multiplier is {load_multiplier:.4}{} (<= 0: gravity alone \
         moves the mechanism at joint {joint}, block {block} most, virtual velocity {speed:.3}); no capacity and no \
         mechanism to draw",
        angle(*.collapse_angle_deg)
    )]
    DoesNotStand {
        /// The multiplier found (≤ 0, or NaN).
        load_multiplier: f64,
        /// Its angle atan λ on the tilting table, degrees; `None` for the lateral load.
        collapse_angle_deg: Option<f64>,
        /// The mechanism's governing joint.
        joint: String,
        /// The block whose virtual velocity (translation) is largest.
        block: String,
        /// That virtual velocity's norm (normalised mechanism, dimensionless scale).
        speed: f64,
    },
    /// The solver did not solve the program.
    #[error("the cone program solver stopped with status {status}")]
    Solver {
        /// Clarabel's status.
        status: String,
    },
}

/// `, collapse angle A deg` for the tilting table's multiplier.
fn angle(deg: Option<f64>) -> String {
    deg.map_or(String::new(), |a| format!(", collapse angle {a:.2} deg"))
}

/// [`LimitError::DoesNotStand`] for a result whose multiplier is not positive, naming the
/// block whose virtual velocity is largest.
fn check_stands(layout: &Layout, r: &LimitResult) -> Result<(), LimitError> {
    if r.load_multiplier > 0.0 {
        return Ok(());
    }
    let (block, speed) = layout
        .blocks
        .iter()
        .zip(&r.velocities)
        .map(|(b, v)| (b.id.as_str(), v.translation.norm()))
        .fold(("", -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
    Err(LimitError::DoesNotStand {
        load_multiplier: r.load_multiplier,
        collapse_angle_deg: r.collapse_angle_deg,
        joint: r.mechanism.joint.clone(),
        block: block.to_string(),
        speed,
    })
}

/// The tilting-table limit analysis of a layout: λ = tan α_max with the dead load of
/// gravity and the live load of the weights along +y.
///
/// `contact`: the DEM parameters whose narrow-phase fields (contact margin, feature and face
/// tolerances, degenerate width) detect the contacts; its other fields do not matter.
///
/// # Errors
/// See [`LimitError`]; a layout that does not stand at α = 0 (λ ≤ 0) is
/// [`LimitError::DoesNotStand`].
pub fn limit_tilt(layout: &Layout, contact: &SolverParams, params: &LimitParams) -> Result<LimitResult, LimitError> {
    limit_analysis(layout, contact, LiveLoad::Tilt, params)
}

/// The lateral-pressure limit analysis: λ is the multiplier of the pressure of `lateral`
/// (`pressure_base_pa`, `pressure_top_pa`; its other fields are checked, not read) on top
/// of the weight.
///
/// # Errors
/// As [`limit_tilt`]; [`LimitError::Parameter`] for a parameter of `lateral` the lateral
/// load refuses ([`LateralParams::validate`]: a pressure below 0 or not finite).
pub fn limit_lateral(
    layout: &Layout,
    contact: &SolverParams,
    lateral: &LateralParams,
    params: &LimitParams,
) -> Result<LimitResult, LimitError> {
    lateral.validate().map_err(LimitError::Parameter)?;
    let p = LiveLoad::Lateral { pressure_base_pa: lateral.pressure_base_pa, pressure_top_pa: lateral.pressure_top_pa };
    limit_analysis(layout, contact, p, params)
}

/// The limit analysis of a layout under a protocol's live load.
///
/// # Errors
/// See [`LimitError`].
pub fn limit_analysis(
    layout: &Layout,
    contact: &SolverParams,
    protocol: LiveLoad,
    params: &LimitParams,
) -> Result<LimitResult, LimitError> {
    let g = layout.gravity;
    limit_with(layout, contact, protocol, params, |model, sim| match protocol {
        LiveLoad::Tilt => {
            for (k, b) in sim.state.bodies.iter().enumerate() {
                model.live[k] = (Vec3::new(0.0, g * b.mass, 0.0), Vec3::zeros());
            }
        }
        LiveLoad::Lateral { pressure_base_pa, pressure_top_pa } => {
            let all = layout.bounds();
            let (loads, _) = pressure_loads(sim, all.min.z, all.max.z, pressure_base_pa, pressure_top_pa);
            model.live = loads;
        }
        // Its loads and held degrees of freedom are the rig's (`inplane::limit_in_plane`).
        LiveLoad::InPlane { .. } => {}
    })
    .map(|(r, _)| r)
}

/// The limit analysis of a layout whose live load (and any extra dead load or held degree
/// of freedom) `loads` sets on the model built from the layout at rest; returns the result
/// and the model (its joints, for a protocol's own reading of the mechanism).
pub(crate) fn limit_with(
    layout: &Layout,
    contact: &SolverParams,
    protocol: LiveLoad,
    params: &LimitParams,
    loads: impl FnOnce(&mut Model, &crate::dem::Simulation),
) -> Result<(LimitResult, Model), LimitError> {
    params.validate().map_err(LimitError::Parameter)?;
    contact.validate().map_err(LimitError::Parameter)?;
    if !layout.ropes.is_empty() {
        return Err(LimitError::Ropes { count: layout.ropes.len() });
    }
    if let Some((joint, strength_pa)) = layout.crushing_joint() {
        return Err(LimitError::Crushing { joint, strength_pa });
    }
    let t0 = Instant::now();
    let (mut model, sim) = Model::new(layout, contact);
    if model.free() == 0 {
        return Err(LimitError::NoFreeBlock);
    }
    check_support(&model)?;
    loads(&mut model, &sim);
    let live: Vec3 = model.row_of.iter().zip(&model.live).filter(|(r, _)| r.is_some()).map(|(_, l)| l.0).sum();
    let live_moment: f64 = model.live.iter().map(|l| l.1.norm()).sum();
    if live.norm() <= 1e-12 * model.force_scale && live_moment <= 1e-12 * model.force_scale * model.length_scale {
        return Err(LimitError::NoLiveLoad);
    }
    // The kinematic program gives λ and the mechanism; where the mechanism slides and
    // the non-associative iteration is to run, the static program gives the normal forces
    // the iteration starts from (its interior-point forces, not the kinematic program's
    // multipliers, so that the iteration is the one of the static program alone).
    let (mut assoc, kinematic) = match model.solve_kinematic() {
        Some(s) => (s, true),
        None => (model.solve(Friction::Associative), false),
    };
    check_status(&model, &assoc)?;
    let (mut mechanism, mut joints, mut velocities) = mechanism::read(&model, &assoc.velocity);
    let mut slides = joints.iter().any(|j| j.mode == JointMode::Slide);
    if slides && params.non_associative && kinematic {
        let solve_time_s = assoc.solve_time_s;
        assoc = model.solve(Friction::Associative);
        assoc.solve_time_s += solve_time_s;
        check_status(&model, &assoc)?;
        (mechanism, joints, velocities) = mechanism::read(&model, &assoc.velocity);
        slides = joints.iter().any(|j| j.mode == JointMode::Slide);
    }
    let mut governing = FlowRule::Associative;
    let mut load_multiplier = assoc.lambda;
    let mut non_associative = None;
    if slides && params.non_associative {
        if let Some((na, s)) = flow::gilbert(&model, &assoc, params.max_iterations, params.relaxation, params.tolerance)
        {
            if na.converged {
                governing = FlowRule::NonAssociative;
                load_multiplier = na.load_multiplier;
                (mechanism, joints, velocities) = mechanism::read(&model, &s.velocity);
            }
            non_associative = Some(na);
        }
    }
    let weight_n = model.force_scale;
    let solver_time_s = assoc.solve_time_s + non_associative.as_ref().map_or(0.0, |n| n.solve_time_s);
    let r = LimitResult {
        protocol,
        load_multiplier,
        collapse_angle_deg: match protocol {
            LiveLoad::Tilt => Some(load_multiplier.atan().to_degrees()),
            LiveLoad::Lateral { .. } | LiveLoad::InPlane { .. } => None,
        },
        governing,
        associative: assoc.lambda,
        non_associative,
        mechanism,
        joints,
        velocities,
        live_load_n: live,
        weight_n,
        blocks: model.free(),
        contacts: model.joints.len(),
        contact_points: model.points.len(),
        status: format!("{:?}", assoc.status),
        solver_iterations: assoc.iterations,
        solver_time_s,
        wall_time_s: t0.elapsed().as_secs_f64(),
    };
    check_stands(layout, &r)?;
    Ok((r, model))
}

/// Every free block touches something, and every group of blocks joined by contacts
/// reaches the table or a fixed block.
fn check_support(model: &Model) -> Result<(), LimitError> {
    if model.joints.is_empty() {
        return Err(LimitError::NoContacts);
    }
    let n = model.ids.len();
    let mut touched = vec![false; n];
    let mut parent: Vec<usize> = (0..=n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let join = |parent: &mut Vec<usize>, i: usize, j: usize| {
        let (ri, rj) = (root(parent, i), root(parent, j));
        if ri != rj {
            parent[ri.max(rj)] = ri.min(rj);
        }
    };
    for (k, r) in model.row_of.iter().enumerate() {
        if r.is_none() {
            join(&mut parent, k, n);
        }
    }
    for j in &model.joints {
        touched[j.b] = true;
        if let Some(a) = j.a {
            touched[a] = true;
        }
        join(&mut parent, j.a.unwrap_or(n), j.b);
    }
    if let Some(k) = (0..n).find(|&k| model.row_of[k].is_some() && !touched[k]) {
        return Err(LimitError::Untouched { block: model.ids[k].clone() });
    }
    let ground = root(&mut parent, n);
    let roots: Vec<usize> = (0..n).map(|k| root(&mut parent, k)).collect();
    if let Some(k) = (0..n).find(|&k| roots[k] != ground) {
        let others = roots.iter().filter(|&&r| r == roots[k]).count() - 1;
        return Err(LimitError::Floating { block: model.ids[k].clone(), others });
    }
    Ok(())
}

/// Maps a solver status to the result or an error.
fn check_status(model: &Model, s: &Solution) -> Result<(), LimitError> {
    match s.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(()),
        SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => Err(LimitError::Unbounded),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            let k = s
                .velocity
                .iter()
                .zip(&model.radius)
                .map(|((v, w), r)| v.norm() + w.norm() * r)
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .map_or(0, |(k, _)| k);
            Err(LimitError::Infeasible { block: model.ids[k].clone() })
        }
        other => Err(LimitError::Solver { status: format!("{other:?}") }),
    }
}
