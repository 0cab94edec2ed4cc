//! The settling under gravity alone (α = 0) that starts every protocol, with the checks that
//! the layout stands as given: every free block touches something, the relaxation reaches
//! equilibrium, and no block moved more than [`settle_tolerance`] on the way: the motion
//! the joints' own closure can explain, with a margin.

use super::monitors::{body_motion, BodyPose};
use crate::dem::{DemError, DensityScaling, RunToEquilibrium, Simulation};
use crate::layout::Layout;

/// Margin of the settling tolerance, as a fraction of the layout's height \[0.02\]: twice
/// the largest linear elastic closure a valid layout can have under its own weight (see
/// `layout::MAX_CLOSURE_RATIO`).
pub const SETTLE_TOLERANCE_FRACTION: f64 = 0.02;

/// Largest motion of a block while settling (centroid displacement plus rotation times the
/// block's radius), m: [`SETTLE_TOLERANCE_FRACTION`] of the layout height H, plus the
/// closure every joint of a stack could take, `n · c_max`, with `n` the number of joints a
/// stack of the lowest blocks would have (H over the smallest block height, at most 100) and
/// `c_max` the largest closure of any material's or joint family's law under the full
/// weight (with the densest material): `ρ g H / Kn`,
/// plus the largest initial gap of a seating law, or the maximum closure of a hyperbolic
/// law. A block that moves more was not supported as given: it fell, slid off or dropped
/// onto its support.
pub fn settle_tolerance(layout: &Layout) -> f64 {
    let h = layout.bounds().extent().z;
    let lowest = layout.blocks.iter().map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
    let joints = (h / lowest.max(0.01 * h)).ceil();
    let rho = layout.materials.iter().map(|m| m.density).fold(0.0, f64::max);
    let closure = layout
        .closure_laws()
        .into_iter()
        .map(|(kn, law)| {
            let elastic = rho * layout.gravity * h / kn;
            law.closure_under(elastic)
        })
        .fold(0.0, f64::max);
    SETTLE_TOLERANCE_FRACTION * h + joints * closure
}

/// Why a layout does not stand as given.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum SettleError {
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
    /// A free block has no contact within the contact margin at α = 0.
    #[error("the layout does not stand as given: block {block} touches nothing (no block or table within the {margin_m:e} m contact margin)")]
    Untouched {
        /// Block id.
        block: String,
        /// Contact margin, m.
        margin_m: f64,
    },
    /// No equilibrium under gravity within the step budget.
    #[error("no equilibrium under gravity alone (the table level, α = 0) within {steps} steps (unbalanced-force ratio {ratio:.3e}){}", why(*.damping, *.ratio, *.tolerance))]
    NoEquilibrium {
        /// Steps tried.
        steps: u64,
        /// Ratio reached.
        ratio: f64,
        /// The ratio asked for.
        tolerance: f64,
        /// The local damping coefficient used.
        damping: f64,
    },
    /// A block moved too far while settling.
    #[error("the layout does not stand as given: block {block} moved {moved_m:.3e} m while settling under gravity ({})", allowed(*.tolerance_m))]
    Moved {
        /// Block id.
        block: String,
        /// Its motion, m.
        moved_m: f64,
        /// The tolerance, m (0 for rigid contacts).
        tolerance_m: f64,
    },
}

/// What motion a settling may show: the joints' closure for a penalty model; none for rigid
/// contacts (tolerance 0), where any motion under gravity alone means the block is not
/// supported.
fn allowed(tolerance_m: f64) -> String {
    if tolerance_m > 0.0 {
        format!("at most {tolerance_m:.3e} m, what the closure of its joints explains")
    } else {
        "rigid contacts, whose joints do not close: it did not come to rest under gravity alone".to_string()
    }
}

/// The unbalanced-force ratio below which a settling that stalls has come to rest to the
/// rounding of its forces rather than failed to: a hundredth of the default tolerance
/// (`PenaltyParams::default().tolerance`, 1e-4). A wall that does not stand keeps
/// accelerating, and its ratio stays of the order of its sliding or toppling share of the
/// weight (1e-2 to 1).
const ROUNDING_FLOOR_RATIO: f64 = 1e-6;

/// The likely cause of a failed settling.
fn why(damping: f64, ratio: f64, tolerance: f64) -> String {
    if damping == 0.0 {
        ": without local damping (damping 0) dynamic relaxation does not converge; give a damping \
         coefficient in (0, 1), 0.8 by default"
            .to_string()
    } else if ratio <= ROUNDING_FLOOR_RATIO {
        format!(
            ": the layout stands, but the tolerance {tolerance:.0e} is below the ratio its forces' rounding \
             lets the relaxation reach; give a tolerance of at least {:.0e}",
            10f64.powf((10.0 * ratio).log10().ceil())
        )
    } else {
        ": the layout does not stand".to_string()
    }
}

/// Settles `sim` (a fresh simulation of `layout`, table level) to an unbalanced-force ratio
/// below `tolerance` within `max_steps` steps, and checks that the layout stood as given.
///
/// # Errors
/// [`SettleError::Untouched`] for the first free block (in layout order) without a contact,
/// [`SettleError::NoEquilibrium`] (where the ratio stalled at the rounding floor, 1e-6,
/// with every block where it was laid: the message names the tolerance it can reach),
/// [`SettleError::Moved`] for the lowest block as laid that moved more than the
/// tolerance (also where the ratio stalled at the rounding floor), [`SettleError::Dem`] if the state blows up (with block
/// density scaling, after a second attempt with scalar scaling, which `sim` then keeps).
pub fn settle(sim: &mut Simulation, layout: &Layout, tolerance: f64, max_steps: u64) -> Result<(), SettleError> {
    let mut touched = vec![false; sim.state.bodies.len()];
    for c in &sim.state.contacts {
        touched[c.b] = true;
        if let Some(a) = c.a {
            touched[a] = true;
        }
    }
    if let Some(k) = (0..sim.state.bodies.len()).find(|&k| !sim.state.bodies[k].fixed() && !touched[k]) {
        return Err(SettleError::Untouched {
            block: sim.state.bodies[k].id.clone(),
            margin_m: sim.params().contact_margin_m,
        });
    }
    let start: Vec<BodyPose> = sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
    let fresh = matches!(sim.params().density_scaling, DensityScaling::Block { .. }).then(|| sim.clone());
    let settled = match (sim.run_to_equilibrium(tolerance, max_steps), fresh) {
        // Block-scaled dynamics can blow up when a block falls (light soft directions of a
        // block mass thrown into re-closing contacts): settle again with scalar scaling,
        // which the simulation keeps, as the tilting table does for an increment.
        (Err(DemError::NonFinite { .. }), Some(fresh)) => {
            *sim = fresh;
            sim.set_density_scaling(DensityScaling::Scalar);
            sim.run_to_equilibrium(tolerance, max_steps)?
        }
        (r, _) => r?,
    };
    let ratio = sim.stats().unbalanced_ratio;
    let no_equilibrium =
        || SettleError::NoEquilibrium { steps: max_steps, ratio, tolerance, damping: sim.params().damping };
    // A settling stalled at the rounding floor has come to rest: whether where it was laid
    // (the tolerance is what failed) or elsewhere (the layout did not stand) is the motion's.
    if !settled && !(ratio <= ROUNDING_FLOOR_RATIO) {
        return Err(no_equilibrium());
    }
    let tolerance_m = settle_tolerance(layout);
    // Of the blocks that moved past the tolerance, the lowest as laid is named: what rests on
    // a block that gave way moves with it, often farther (a loading beam on a block laid
    // above the table falls with it), and is no cause.
    let lowest = sim
        .state
        .bodies
        .iter()
        .zip(&start)
        .filter(|(b, _)| !b.fixed())
        .map(|(b, from)| (b, from.0.z, body_motion(from, &(b.pos, b.rot), b.radius)))
        .filter(|(_, _, moved)| !(*moved <= tolerance_m))
        .min_by(|x, y| x.1.total_cmp(&y.1));
    if let Some((b, _, moved_m)) = lowest {
        return Err(SettleError::Moved { block: b.id.clone(), moved_m, tolerance_m });
    }
    if !settled {
        return Err(no_equilibrium());
    }
    Ok(())
}
