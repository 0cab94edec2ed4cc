//! The in-plane test's errors ([`InPlaneError`]) and the checks of a layout against the
//! penalty DEM's reach ([`check_cyclic_slip_range`], [`check_joint_closure`],
//! [`check_drift_reach`]).

#[cfg(doc)]
use super::MAX_HEIGHT_RATIO;
use super::{History, InPlaneParams};
use crate::dem::DemError;
use crate::layout::Layout;
use crate::loading::settle::SettleError;
use crate::range::OutOfRange;

/// Errors of the in-plane test.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum InPlaneError {
    /// A parameter out of its range.
    #[error("in_plane.{0}")]
    Parameter(OutOfRange),
    /// A solver setting out of its range.
    #[error("solver: {0}")]
    Solver(OutOfRange),
    /// The measuring point is below the wall's top.
    #[error(
        "in_plane.measuring_height_m = {measuring_height_m} m is below the wall's height {height_m} m: the displacement is read on the loading beam, on top of the wall"
    )]
    MeasuringPoint {
        /// The measuring point's height, m.
        measuring_height_m: f64,
        /// The wall's height, m.
        height_m: f64,
    },
    /// The shear span is below the wall's top.
    #[error(
        "in_plane.shear_span_m = {shear_span_m} m is below the wall's height {height_m} m: the horizontal force acts on the beam, on top of the wall"
    )]
    ShearSpan {
        /// The shear span given, m.
        shear_span_m: f64,
        /// The wall's height, m.
        height_m: f64,
    },
    /// The shear span or the measuring point is implausibly far above the wall.
    #[error(
        "in_plane.{key} = {value_m} m is more than {ratio} times the wall's height {height_m} m: a probable unit mistake (millimetres for metres?); it is a height on the loading beam, above the wall's top"
    )]
    TooHigh {
        /// The key (`shear_span_m`, `measuring_height_m`).
        key: &'static str,
        /// The value given, m.
        value_m: f64,
        /// The wall's height, m.
        height_m: f64,
        /// [`MAX_HEIGHT_RATIO`].
        ratio: f64,
    },
    /// The blocks the beam would bear on (those level with the top, within half a course of
    /// it) cover too little of the wall's length: one block standing above the wall, or a
    /// top course with stones missing.
    #[error(
        "the loading beam would bear on {} only: {} at {top_m:.4} m and {} {covered_pct:.0} % of the wall's length under the beam (at least {need_pct:.0} % needed); {}",
        if blocks.len() == 1 { format!("block {}", blocks[0]) } else { format!("blocks {}", blocks.join(", ")) },
        if blocks.len() == 1 { "it tops the wall alone" } else { "they top the wall" },
        if blocks.len() == 1 { "covers" } else { "cover" },
        if blocks.len() == 1 { "a block above or apart from the wall?" } else { "stones missing from the top course?" }
    )]
    TopAlone {
        /// The blocks level with the top, in layout order.
        blocks: Vec<String>,
        /// Its top, m.
        top_m: f64,
        /// The share of the length under the beam, %.
        covered_pct: f64,
        /// [`super::BEARING_SHARE`] in %.
        need_pct: f64,
    },
    /// The top course is not level enough to carry the beam: some of its stones lie lower
    /// than the others by more than the joints' closure under the vertical stress takes up
    /// ([`super::level_tolerance_m`]), so the beam, laid on the highest, would bear on part of
    /// the top.
    #[error(
        "the top course is not level enough to carry the loading beam: {} top{} {step_min_mm:.3}{} mm below the wall's top {height_m:.4} m, more than the {tolerance_mm:.4} mm the joints' closure under σ0 {sigma0_mpa} MPa takes up (half the beam joint's closure: within it every top stone carries at least half of σ0); the beam would bear on {} alone ({bearing_pct:.0} % of the wall's length). Level the top course (as a laboratory beds its beam on a levelled top), or edit the layout so the stones named reach the top",
        list_ids(low, "block", "blocks"),
        if low.len() == 1 { "s" } else { "" },
        if step_max_mm - step_min_mm > 1e-6 { format!("–{step_max_mm:.3}") } else { String::new() },
        list_ids(bearing, "block", "blocks")
    )]
    NotLevel {
        /// The top course's stones below the tolerance (ids).
        low: Vec<String>,
        /// The stones the beam would bear on (ids).
        bearing: Vec<String>,
        /// The wall's top, m.
        height_m: f64,
        /// How far below the top the highest of the low stones tops, mm.
        step_min_mm: f64,
        /// How far below the top the lowest of them tops, mm.
        step_max_mm: f64,
        /// The level tolerance ([`super::level_tolerance_m`]), mm.
        tolerance_mm: f64,
        /// The vertical stress, MPa.
        sigma0_mpa: f64,
        /// The share of the wall's length under the stones the beam would bear on, %.
        bearing_pct: f64,
    },
    /// The layout does not stand under gravity alone.
    #[error(transparent)]
    DoesNotStand(SettleError),
    /// The wall does not stand under the vertical force.
    #[error(
        "the wall does not stand under the vertical force of {force_kn:.1} kN: block {block} moved {moved_mm:.2} mm (at most {allowed_mm:.2} mm, what its joints' closure explains){}", if *.equilibrium { "" } else { ", and no equilibrium was reached" }
    )]
    UnderVerticalForce {
        /// The block that moved most.
        block: String,
        /// How far, mm.
        moved_mm: f64,
        /// The tolerance, mm.
        allowed_mm: f64,
        /// The vertical force, kN.
        force_kn: f64,
        /// Whether the relaxation reached equilibrium.
        equilibrium: bool,
    },
    /// The vertical force crushes the wall's joints before they carry it: the mean stress
    /// at the base reaches the faces' crushing strength.
    #[error(
        "the vertical stress crushes the wall: {stress_mpa:.3} MPa at its base (the vertical force {force_kn:.1} kN and the wall's own weight over its plan area) reaches the crushing strength fc = {strength_mpa:.3} MPa of {joint}, and a joint carries at most fc over its area; give a vertical stress below fc (the compression test's --raise-to-mpa finds the strength)"
    )]
    Crushes {
        /// The crushing joint rule, as the layout names it (`material NAME`, …).
        joint: String,
        /// Its crushing strength fc, MPa.
        strength_mpa: f64,
        /// The mean stress at the wall's base, (N + W) / (L t), MPa.
        stress_mpa: f64,
        /// The vertical force N, kN.
        force_kn: f64,
    },
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
    /// The non-smooth solver refused the layout or blew up.
    #[error(transparent)]
    Nscd(#[from] crate::nscd::NscdError),
    /// The layout's geometry is degenerate for the beam.
    #[error("the loading beam cannot be built on this layout: {0}")]
    Beam(String),
    /// A cyclic history by the penalty DEM on joints too stiff in shear for it
    /// ([`MIN_CYCLIC_SLIP_RANGE_M`]).
    #[error(
        "material {material}: its joints' elastic slip range tan φ σ0 / Ks = {range_um:.2} µm (φ {friction_deg:.1}°, Ks {ks_pa_per_m:.3e} Pa/m, σ0 {sigma0_mpa} MPa) is below the {min_um:.0} µm a cyclic history by the penalty DEM needs: the path's own errors within an increment exceed it, the joints slip against the load and their friction falls over the cycles. Run it monotonic, with --solver nscd (rigid joints, which reverse exactly), or with Ks at most {ks_max_pa_per_m:.3e} Pa/m"
    )]
    CyclicSlipRange {
        /// The material's name in the layout.
        material: String,
        /// Its elastic slip range, µm.
        range_um: f64,
        /// Its friction angle, degrees.
        friction_deg: f64,
        /// Its shear stiffness, Pa/m.
        ks_pa_per_m: f64,
        /// The vertical stress, MPa.
        sigma0_mpa: f64,
        /// [`MIN_CYCLIC_SLIP_RANGE_M`], µm.
        min_um: f64,
        /// The largest Ks that gives the range at this φ and σ0, Pa/m.
        ks_max_pa_per_m: f64,
    },
    /// Joints that the vertical stress closes past the penalty DEM's small overlaps
    /// ([`MAX_CLOSURE_SHARE`]).
    #[error(
        "material {material}: the vertical stress σ0 {sigma0_mpa} MPa closes its joints by σ0 / Kn = {closure_mm:.3} mm (Kn {kn_pa_per_m:.3e} Pa/m), {share_pct:.1} % of the lowest block's height ({height_mm:.1} mm); the penalty DEM's contacts hold for overlaps up to {max_pct:.0} % of it, a σ0 of at most {sigma0_max_mpa:.3} MPa on these joints. Check the stress's unit (MPa) and Kn, or run --solver nscd or limit (rigid joints)"
    )]
    JointClosure {
        /// The material's name in the layout.
        material: String,
        /// The vertical stress, MPa.
        sigma0_mpa: f64,
        /// The joints' closure `σ0 / Kn`, mm.
        closure_mm: f64,
        /// Its normal stiffness, Pa/m.
        kn_pa_per_m: f64,
        /// The closure over the lowest block's height, %.
        share_pct: f64,
        /// The lowest block's height, mm.
        height_mm: f64,
        /// [`MAX_CLOSURE_SHARE`], %.
        max_pct: f64,
        /// The largest σ0 the bound allows on these joints, MPa.
        sigma0_max_mpa: f64,
    },
    /// A drift past the penalty DEM's reach ([`check_drift_reach`]).
    #[error(
        "in_plane.drift_pct = {drift_pct} % is past the {max_pct:.1} % the penalty DEM follows with its face-angle tolerance of {tolerance_deg}°: a part of the wall turns by up to twice the drift, and a block turned past the tolerance against its bed is in contact by its edge instead of its face, which locks its rotation there (the beam then slides over the wall; a one-block wall at 30 % drift holds 4.2 kN where its statics give 3.5 kN). Run it by --solver nscd (rigid joints, exact at any drift), or to at most {max_pct:.1} %"
    )]
    DriftReach {
        /// The largest drift asked for, %.
        drift_pct: f64,
        /// The largest drift the penalty DEM follows, %.
        max_pct: f64,
        /// The solver's face-angle tolerance, degrees.
        tolerance_deg: f64,
    },
    /// The method chosen does not run this form of the test (the protocol seam's
    /// refusal, or a setting the method cannot state), as text.
    #[error("{0}")]
    Unsupported(String),
}

impl InPlaneError {
    /// Whether the test refused its parameters for the wall before running it: a value out
    /// of range once the wall is known, a wall the beam cannot be laid on, joints or a
    /// drift past the method's reach, a form of the test the method does not run. Not the
    /// wall failing to stand (`DoesNotStand`, `UnderVerticalForce`) nor a solver's
    /// blow-up (`Dem`, `Nscd`, `Beam`).
    pub fn is_refusal(&self) -> bool {
        match self {
            InPlaneError::Parameter(_)
            | InPlaneError::Solver(_)
            | InPlaneError::MeasuringPoint { .. }
            | InPlaneError::ShearSpan { .. }
            | InPlaneError::TooHigh { .. }
            | InPlaneError::TopAlone { .. }
            | InPlaneError::NotLevel { .. }
            | InPlaneError::CyclicSlipRange { .. }
            | InPlaneError::JointClosure { .. }
            | InPlaneError::DriftReach { .. }
            | InPlaneError::Unsupported(_) => true,
            InPlaneError::DoesNotStand(_)
            | InPlaneError::UnderVerticalForce { .. }
            | InPlaneError::Crushes { .. }
            | InPlaneError::Dem(_)
            | InPlaneError::Nscd(_)
            | InPlaneError::Beam(_) => false,
        }
    }

    /// Whether the wall did not stand as given: under gravity, under the vertical force, or
    /// crushed by it (a realization's outcome, not a refusal of its input).
    pub fn does_not_stand(&self) -> bool {
        matches!(
            self,
            InPlaneError::DoesNotStand(_) | InPlaneError::UnderVerticalForce { .. } | InPlaneError::Crushes { .. }
        )
    }
}

/// The least elastic slip range `tan φ σ0 / Ks` of a joint that a cyclic history by the
/// penalty DEM accepts, m (20 µm). Below it the path's own errors within an increment (the
/// predictor's mismatch, the relaxation's swing, out of plane and in torsion) exceed the
/// slip a joint takes elastically, so joints slip in senses the load does not drive and
/// their friction falls over the cycles. Measured on one block under σ0 = 0.5 MPa on a base
/// of φ 10° (μN 18.7 kN), cycled to ±0.25 and ±0.5 % twice at the defaults, the least force
/// 0.2 mm past a reversal: Ks 4e9 Pa/m (22 µm) 16.5–18.7 kN, 1e10 (8.8 µm) 13.9 kN, 4e10
/// (2.2 µm) 4.1 kN, 4e11 (0.22 µm) −9.5 kN, against the motion for whole half-cycles.
/// The granite walls' joints (Ks 1e9 Pa/m) have about 300 µm at 0.5 MPa. A monotonic
/// history does not reverse and is not refused; nscd's rigid joints reverse exactly.
pub const MIN_CYCLIC_SLIP_RANGE_M: f64 = 20e-6;

/// Refuses a cyclic history by the penalty DEM on a layout whose joints' elastic slip
/// range at the applied vertical stress is below [`MIN_CYCLIC_SLIP_RANGE_M`], naming the
/// material of the least range (its index in the layout), the range, and the Ks that would
/// give it.
///
/// # Errors
/// [`InPlaneError::CyclicSlipRange`].
pub fn check_cyclic_slip_range(wall: &Layout, params: &InPlaneParams) -> Result<(), InPlaneError> {
    if params.history != History::Cyclic {
        return Ok(());
    }
    let sigma0 = params.sigma0_mpa * 1e6;
    let range = |m: &crate::layout::Material| m.friction.tan() * sigma0 / m.ks;
    let least = used_materials(wall).min_by(|a, b| range(a.1).total_cmp(&range(b.1)));
    match least {
        Some((k, m)) if range(m) < MIN_CYCLIC_SLIP_RANGE_M => Err(InPlaneError::CyclicSlipRange {
            material: wall.material_names.get(k).cloned().unwrap_or_else(|| k.to_string()),
            range_um: range(m) * 1e6,
            friction_deg: m.friction.to_degrees(),
            ks_pa_per_m: m.ks,
            sigma0_mpa: params.sigma0_mpa,
            min_um: MIN_CYCLIC_SLIP_RANGE_M * 1e6,
            ks_max_pa_per_m: m.friction.tan() * sigma0 / MIN_CYCLIC_SLIP_RANGE_M,
        }),
        _ => Ok(()),
    }
}

/// The largest closure of a joint under the vertical stress that the penalty DEM accepts,
/// as a share of the lowest block's height \[0.01\]. The penalty method reads a contact's
/// force from the blocks' overlap on the geometry as laid, which holds while overlaps are
/// small beside the blocks (Cundall & Hart 1992, "Numerical modelling of discontinua",
/// Eng. Comput. 9:101; 3DEC's guidance on the choice of Kn): past about a percent of a
/// block's height the sub-contacts' faces turn and slide into each other and the forces
/// stop being the joint's law. A stress that closes linear joints (`q = Kn u`) further is
/// a unit mistake or a joint far softer than stone's; at σ0 = 1000 MPa the granite wall
/// (Kn 2e10 Pa/m, courses of about 0.15 m) would close each joint by 50 mm, and its run
/// blew up or gave a force of the wrong sign throughout; its bound is some 30 MPa. Joints with a nonlinear closure law are bounded by their law.
pub const MAX_CLOSURE_SHARE: f64 = 0.01;

/// Refuses a run by the penalty DEM whose vertical stress closes a material's linear joints
/// (`σ0 / Kn`) by more than [`MAX_CLOSURE_SHARE`] of the lowest block's height, naming the
/// material.
///
/// # Errors
/// [`InPlaneError::JointClosure`].
pub fn check_joint_closure(wall: &Layout, params: &InPlaneParams) -> Result<(), InPlaneError> {
    let height =
        wall.blocks.iter().filter(|b| !b.fixed).map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
    if !height.is_finite() {
        return Ok(());
    }
    let sigma0 = params.sigma0_mpa * 1e6;
    let worst = used_materials(wall).filter(|(_, m)| m.closure.is_linear()).min_by(|a, b| a.1.kn.total_cmp(&b.1.kn));
    match worst {
        Some((k, m)) if sigma0 / m.kn > MAX_CLOSURE_SHARE * height => Err(InPlaneError::JointClosure {
            material: wall.material_names.get(k).cloned().unwrap_or_else(|| k.to_string()),
            sigma0_mpa: params.sigma0_mpa,
            closure_mm: sigma0 / m.kn * 1e3,
            kn_pa_per_m: m.kn,
            share_pct: 100.0 * sigma0 / m.kn / height,
            height_mm: height * 1e3,
            max_pct: 100.0 * MAX_CLOSURE_SHARE,
            sigma0_max_mpa: MAX_CLOSURE_SHARE * height * m.kn * 1e-6,
        }),
        _ => Ok(()),
    }
}

/// The largest drift the penalty DEM's in-plane test follows, %, for the contact
/// detection's face-angle tolerance `tolerance_deg` (degrees;
/// [`crate::dem::SolverParams::face_angle_tolerance_deg`], default 10°):
/// `100 tan(tolerance) / 2` (8.8 % at the default).
///
/// Why: a block's contact with its bed is a face while the two faces are within the
/// tolerance of each other, and an edge (a thin strip along it) past it (Cundall 1988's
/// contact features; `dem::contact::geometry`). A block turned past the tolerance about its
/// toe is thus pushed back from the edge onto its face, and its rotation locks there: the
/// beam, its displacement imposed, slides over it. Measured on one block (1.0 × 0.2 ×
/// 1.2 m, Kn 1e10 Pa/m, φ 45°, σ0 0.1 MPa, H0 1.2 m) against its rigid statics (the block
/// and the beam turning about the toe, the vertical force at the beam's centroid), which
/// nscd follows to 0.2 % at every drift: the penalty DEM's force is within 5 % of it up to
/// 10 % drift (5.6°; the joints' elasticity moves the toe inwards), its rotation stops at
/// 10.0° (18 % drift), and the force stays above the statics from there (4.22 kN at 30 %
/// where they give 3.53; +0.60 kN at 50 %, where they give −0.92); with a 20° tolerance
/// the lock moves to 20°. A whole wall rocking about its
/// toe turns by the drift (rad); a part of it turning about a point half way down the
/// shear span, by twice the drift: the bound keeps that within the tolerance. The tests
/// that drystone's in-plane data come from reach 3.4 %.
pub fn max_drift_pct(tolerance_deg: f64) -> f64 {
    100.0 * tolerance_deg.to_radians().tan() / 2.0
}

/// Refuses a run by the penalty DEM whose largest drift is past [`max_drift_pct`] of the
/// solver's face-angle tolerance (`tolerance_deg`, degrees).
///
/// # Errors
/// [`InPlaneError::DriftReach`].
pub fn check_drift_reach(params: &InPlaneParams, tolerance_deg: f64) -> Result<(), InPlaneError> {
    let max_pct = max_drift_pct(tolerance_deg);
    if params.drift_pct > max_pct {
        return Err(InPlaneError::DriftReach { drift_pct: params.drift_pct, max_pct, tolerance_deg });
    }
    Ok(())
}

/// The materials of `wall` that a joint of the test has: those of its blocks and of the
/// table (a materials list may name others, which no joint reads), with their indices.
fn used_materials(wall: &Layout) -> impl Iterator<Item = (usize, &crate::layout::Material)> {
    let used: std::collections::BTreeSet<usize> =
        wall.blocks.iter().map(|b| b.material).chain(std::iter::once(wall.table_material)).collect();
    wall.materials.iter().enumerate().filter(move |(k, _)| used.contains(k))
}

/// `ids` as a phrase: `block b1`, `blocks b1, b2 and b3`, the first six and how many more.
fn list_ids(ids: &[String], one: &str, many: &str) -> String {
    const SHOWN: usize = 6;
    match ids {
        [] => format!("no {many}"),
        [a] => format!("{one} {a}"),
        _ if ids.len() <= SHOWN => {
            format!("{many} {} and {}", ids[..ids.len() - 1].join(", "), ids[ids.len() - 1])
        }
        _ => format!("{many} {} and {} more", ids[..SHOWN].join(", "), ids.len() - SHOWN),
    }
}
