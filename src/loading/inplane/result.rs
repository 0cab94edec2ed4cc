//! The outcome of an in-plane test ([`InPlaneResult`]) and how a driver's run makes it
//! ([`result_of`] from its curve, mechanism and [`Work`]).

#[cfg(doc)]
use super::read_curve;
use super::readings::nan;
use super::{direction, CurvePoint, DirectionResult, History, InPlaneMechanism, InPlaneParams, Mirror, Poses, Rig};
use crate::layout::{Layout, VerticalLoadRig};
use crate::math::Vec3;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The outcome of an in-plane test by the penalty DEM or by non-smooth contact dynamics
/// ([`crate::loading::inplane_nscd`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneResult {
    /// The force–displacement curve, one point per static solve (the first the state under
    /// the vertical force).
    pub curve: Vec<CurvePoint>,
    /// The positive direction (+x).
    pub positive: Option<DirectionResult>,
    /// The negative direction (cyclic histories).
    pub negative: Option<DirectionResult>,
    /// The mechanism at the largest positive drift.
    pub mechanism: InPlaneMechanism,
    /// The bodies' poses there (centroid m, rotation as a scaled axis rad), layout order
    /// with the beam last, for drawing.
    #[serde(skip)]
    pub poses_at_reading: Vec<(Vec3, Vec3)>,
    /// The applied vertical force `σ0 L t`, kN.
    pub vertical_force_kn: f64,
    /// The axial force at the base, self-weight included, kN.
    pub n_total_kn: f64,
    /// The rigid rocking capacity `N_total L / (2 H0)`, kN (a reference, not a result).
    pub rocking_force_kn: f64,
    /// Wall length, height, thickness, m.
    pub length_m: f64,
    /// See `length_m`.
    pub height_m: f64,
    /// See `length_m`.
    pub thickness_m: f64,
    /// The height of the horizontal force, m: the shear span `H0` with the beam's rotation
    /// free; with it held level, the height of the beam's constraint ([`Rig::anchor_z_m`]),
    /// which is no shear span (the held rotation sets the moment) and is not reported as one.
    pub shear_span_m: f64,
    /// The height of the measuring point, m: `top_mm` is read there and the drift is
    /// `top_mm` over it ([`Rig::measure_z_m`]; 0 when read from results written before it
    /// was recorded).
    #[serde(default)]
    pub measuring_height_m: f64,
    /// The wall's vertical modulus, MPa, as the laboratory reads it from the vertical
    /// loading phase (the database's `Epc`, Vanin et al. 2017): the secant of the loading
    /// branch, the vertical stress added by the actuator's force (`(N − W_beam) / (L t)`)
    /// over the wall's shortening (the beam's settlement under it, its centroid's, over the
    /// wall's height `H`). It holds every joint of the wall's height (base, beds, the beam's
    /// bed) and the blocks are rigid, so it is about `Kn H / n_joints` for linear joints.
    /// NaN where the method has no joint compliance (non-smooth contact dynamics: rigid
    /// contacts) or when read from results written before it was recorded.
    #[serde(default = "nan")]
    pub wall_vertical_modulus_mpa: f64,
    /// The largest excursion of any block from the rigid motion of its course over the
    /// history, mm ([`crate::loading::excursion`]: the distance of its centroid from where the
    /// nearer-moving of its course neighbours carries it): a wall that stays whole keeps it
    /// to the joints' own deformation and the crack's opening beside a block; a block shed
    /// from the wall reads its walk. The wall's blocks only: the loading beam's slip along
    /// the top course is the rig's (sliding under the beam). NaN when read from results
    /// written before it was recorded.
    #[serde(default = "nan")]
    pub largest_block_excursion_mm: f64,
    /// The block of `largest_block_excursion_mm` (empty: none moved from its course).
    #[serde(default)]
    pub excursion_block: String,
    /// The first block shed from the wall: its excursion passed a quarter of its smallest
    /// extent ([`crate::loading::excursion::SHED_SHARE`]); every increment from then on with
    /// a block shed is counted in `unconverged`, and a study's row reads `shed_block`.
    /// Empty: the wall stayed whole.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub shed_block: String,
    /// The widening of the most widened course at the history's end, mm: the span of its
    /// blocks' centroids along the wall's length, less that under the vertical force
    /// ([`crate::loading::excursion::course_widening`]). A cyclic history ends at zero drift, where it reads the spread
    /// the cycles left (the end columns walked outwards, head joints left open); a monotonic
    /// one at its largest drift, where it includes the open cracks of the mechanism. NaN
    /// when read from results written before it was recorded.
    #[serde(default = "nan")]
    pub course_widening_mm: f64,
    /// The course of `course_widening_mm` (0 at the base; `None`: no course widened).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub widened_course: Option<usize>,
    /// The push read both ways ([`InPlaneParams::mirror_reading`]; `None`: read one way).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mirror: Option<Box<Mirror>>,
    /// Increments not converged: with a block shed from the wall (`shed_block`, both
    /// methods); for the penalty DEM, static solves that ended at the step budget rather
    /// than in equilibrium, with a block out of balance, or with a block thrown from the
    /// wall (one that walked from every joint neighbour by more than the increment can move
    /// it, once more when solved again from the increment's start); for nscd, increments
    /// with a step whose contact problem did not meet its criterion.
    pub unconverged: usize,
    /// Increments solved again from their start, warming up from the smallest increment:
    /// those whose relaxation blew up from the predicted state, and those whose relaxation
    /// threw a block off the path (the penalty DEM's driver, see `unconverged`).
    pub retried: usize,
    /// Of the increments kept, those whose semi-smooth Newton solve (`--solver newton`,
    /// `dem::drivers::newton`) found no equilibrium and handed the increment to the
    /// protocol's own static method, dynamic relaxation (`None`: the solve has no Newton
    /// stage).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub newton_handed_over: Option<usize>,
    /// Engine steps, settling included.
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// The curve of the wall's own shear: `curve` before the rig's vertical-load system
    /// added its force (the same as `curve` for an ideal vertical force). With
    /// `vertical_load_rig` it gives the force read under any other such system without a
    /// new run ([`read_curve`]: the beam's motion is imposed, so the system leaves the
    /// wall's motion as it is). Not written to the results (empty when read from them).
    #[serde(skip)]
    pub wall_curve: Vec<CurvePoint>,
    /// The rig's vertical-load system the run had (`Layout::vertical_load_rig`). Not
    /// written to the results (ideal when read from them).
    #[serde(skip)]
    pub vertical_load_rig: Box<VerticalLoadRig>,
    /// The applied vertical force `σ0 L t`, N, as the rig's system reads it (0 when read
    /// from the results).
    #[serde(skip)]
    pub vertical_force_n: f64,
}

/// What a driver's run cost, for its [`InPlaneResult`].
pub(crate) struct Work {
    /// Static solves (increments) that did not converge.
    pub unconverged: usize,
    /// Increments solved again from their start.
    pub retried: usize,
    /// Increments the Newton stage handed over (`None`: no Newton stage).
    pub newton_handed_over: Option<usize>,
    /// Engine steps.
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// When the run started.
    pub t0: Instant,
    /// The wall's vertical modulus read in the vertical loading phase, MPa (NaN: none).
    pub vertical_modulus_mpa: f64,
    /// The largest excursion of a block from its course over the history.
    pub excursion: Excursion,
}

/// The largest excursion of a block from its course over a history
/// ([`crate::loading::excursion`]), and the block.
#[derive(Debug, Clone, Default)]
pub(crate) struct Excursion {
    /// The largest excursion, m.
    pub largest_m: f64,
    /// The block's id (empty: none).
    pub block: String,
    /// The first block shed from the wall ([`crate::loading::excursion::SHED_SHARE`]; empty:
    /// none).
    pub shed: String,
    /// The widening of the most widened course in the last poses read, m, and the course
    /// ([`crate::loading::excursion::course_widening`]).
    pub widening: (f64, Option<usize>),
}

impl Excursion {
    /// Reads the poses `now` against `reference` and keeps the largest; whether a block is
    /// shed from the wall in `now` (the first one shed is kept).
    pub(crate) fn read(
        &mut self,
        neighbours: &crate::loading::excursion::JointNeighbours,
        reference: &Poses,
        now: &Poses,
        layout: &Layout,
    ) -> bool {
        // The loading beam is the rig's: its slip along the top course is a mechanism
        // (sliding under the beam), not a block shed from the wall.
        let beam = layout.blocks.iter().position(|b| b.id == super::BEAM_ID);
        let ((e, k), shed) = neighbours.read_but(reference, now, beam);
        if e > self.largest_m {
            self.largest_m = e;
            self.block = k.map_or_else(String::new, |k| layout.blocks[k].id.clone());
        }
        if let (Some(k), true) = (shed, self.shed.is_empty()) {
            self.shed = layout.blocks[k].id.clone();
        }
        self.widening = crate::loading::excursion::course_widening(layout, reference, now, beam);
        shed.is_some()
    }
}

/// The result of a driver's run: the curve's per-direction outputs (the negative direction
/// of a cyclic history only), the mechanism, the poses at the reading and the rig's
/// references.
pub(crate) fn result_of(
    rig: &Rig,
    params: &InPlaneParams,
    mut curve: Vec<CurvePoint>,
    mechanism: InPlaneMechanism,
    at: &Poses,
    work: Work,
) -> InPlaneResult {
    let wall_curve = curve.clone();
    rig.add_vertical_load_rig(&mut curve);
    InPlaneResult {
        positive: direction(&curve, 1.0),
        negative: if params.pushes_negative() { direction(&curve, -1.0) } else { None },
        curve,
        wall_curve,
        vertical_load_rig: Box::new(rig.layout.vertical_load_rig),
        vertical_force_n: rig.vertical_force_n,
        mechanism,
        poses_at_reading: at.iter().map(|(p, q)| (*p, q.scaled_axis())).collect(),
        vertical_force_kn: rig.vertical_force_n * 1e-3,
        n_total_kn: rig.n_total_n() * 1e-3,
        rocking_force_kn: rig.rocking_force_n(params.beam_rotation) * 1e-3,
        length_m: rig.length_m,
        height_m: rig.height_m,
        thickness_m: rig.thickness_m,
        shear_span_m: rig.anchor_z_m,
        measuring_height_m: rig.measure_z_m,
        wall_vertical_modulus_mpa: work.vertical_modulus_mpa,
        largest_block_excursion_mm: work.excursion.largest_m * 1e3,
        excursion_block: work.excursion.block,
        shed_block: work.excursion.shed,
        course_widening_mm: work.excursion.widening.0 * 1e3,
        widened_course: work.excursion.widening.1,
        mirror: (params.mirror_reading && params.history == History::Monotonic)
            .then(|| Box::new(Mirror { wall_curve: None })),
        unconverged: work.unconverged,
        retried: work.retried,
        newton_handed_over: work.newton_handed_over,
        steps: work.steps,
        dt_s: work.dt_s,
        wall_time_s: work.t0.elapsed().as_secs_f64(),
    }
}
