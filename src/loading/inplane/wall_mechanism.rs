//! The mechanism read from the blocks' motion ([`InPlaneMechanism`], [`read_mechanism`]) over
//! the joints of a state ([`mechanism_joints`]), and the half-cycle it is read over
//! ([`HalfCycle`]).

use crate::dem::contact::types::Contact;
use crate::dem::Simulation;
use crate::math::Vec3;
use serde::{Deserialize, Serialize};

/// A joint takes part in the mechanism when its largest relative motion is at least this
/// share of the beam's \[0.05\].
pub const ACTIVE_JOINT_SHARE: f64 = 0.05;

/// The kind of an in-plane mechanism.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MechanismKind {
    /// The part that moves with the beam rotates about a toe (flexural; the database's
    /// failure type 1), above a horizontal or a stepped crack.
    Rocking,
    /// One bed joint slides (shear; type 0).
    Sliding,
    /// The part that moves with the beam translates along a stepped crack through bed and
    /// head joints at several courses (diagonal shear; type 0).
    Diagonal,
    /// Rotation and translation in comparable shares (type 0.5).
    Mixed,
    /// No joint moved past the threshold.
    None,
}

impl MechanismKind {
    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            MechanismKind::Rocking => "rocking",
            MechanismKind::Sliding => "sliding",
            MechanismKind::Diagonal => "diagonal",
            MechanismKind::Mixed => "mixed",
            MechanismKind::None => "none",
        }
    }

    /// The database's failure type: 1 flexural, 0.5 mixed, 0 shear (Vanin et al. 2017);
    /// `None` for no mechanism.
    pub fn failure_type(self) -> Option<f64> {
        match self {
            MechanismKind::Rocking => Some(1.0),
            MechanismKind::Mixed => Some(0.5),
            MechanismKind::Sliding | MechanismKind::Diagonal => Some(0.0),
            MechanismKind::None => None,
        }
    }
}

/// The mechanism read from the blocks' motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneMechanism {
    /// Its kind.
    pub kind: MechanismKind,
    /// The share of the beam's horizontal motion that the moving part's rotation (about y,
    /// the mean of its blocks') about the crack's foot explains, in [0, 1]: 1 for a rotation
    /// about a toe, 0 for a translation. Where no block moves with the beam (the crack
    /// along the beam's bed), the crack's opening share.
    pub rotation_share: f64,
    /// The share of the crack's relative motion that is opening (normal), in [0, 1].
    pub opening_share: f64,
    /// The crack's shape: `horizontal` (bed joints at one level), `stepped` (bed and head
    /// joints at several levels), or `none`.
    pub crack: String,
    /// The moving joints (`ID_A/ID_B`, `table/ID`), in contact order.
    pub joints: Vec<String>,
    /// The heights of the moving bed joints, m, lowest first.
    pub bed_levels_m: Vec<f64>,
    /// The blocks that move with the beam (rigidly joined to it by joints that do not
    /// move), the beam excluded.
    pub moving_blocks: Vec<String>,
}

/// A joint for the mechanism reading: its bodies, normal and points (table frame).
#[derive(Debug, Clone)]
pub struct MechanismJoint {
    /// Body A (`None`: the table).
    pub a: Option<usize>,
    /// Body B.
    pub b: usize,
    /// `ID_A/ID_B` or `table/ID`.
    pub name: String,
    /// Unit normal A → B.
    pub normal: Vec3,
    /// Points on the joint, m.
    pub points: Vec<Vec3>,
    /// The joint's elastic range, m: over its sub-contacts, the largest shear deflection
    /// its springs carry before they slip, `(Fn tan φ + c A) / (Ks A)`, plus the largest
    /// normal deflection `Fn / (Kn A)`, with the normal forces `Fn` of the state the joints
    /// are taken in (the penalty DEM's springs; 0 for the rigid joints of nscd and limit
    /// analysis). A relative motion within it may be the springs' alone, so
    /// [`read_mechanism`] does not count it as the joint moving.
    pub elastic_m: f64,
}

/// The joints of a simulation's current contacts, for [`read_mechanism`].
pub fn mechanism_joints(sim: &Simulation) -> Vec<MechanismJoint> {
    let st = &sim.state;
    st.contacts
        .iter()
        .map(|c: &Contact| MechanismJoint {
            a: c.a,
            b: c.b,
            name: st.joint_name(c),
            normal: st.contact_normal(c),
            points: c
                .nodes
                .iter()
                .map(|nd| {
                    let (pa, pb) = st.node_points(c, nd);
                    0.5 * (pa + pb)
                })
                .collect(),
            elastic_m: elastic_deflection(c),
        })
        .collect()
}

/// A contact's elastic range for [`MechanismJoint::elastic_m`], m.
fn elastic_deflection(c: &Contact) -> f64 {
    let j = &c.joint;
    let (mut shear, mut normal) = (0.0_f64, 0.0_f64);
    for s in c.subs.iter().filter(|s| s.area > 0.0) {
        let fn_ = s.state.normal.max(0.0);
        if j.ks > 0.0 {
            shear = shear.max((fn_ * j.tan_phi + j.cohesion * s.area) / (j.ks * s.area));
        }
        if j.kn > 0.0 {
            normal = normal.max(fn_ / (j.kn * s.area));
        }
    }
    shear + normal
}

/// Reads the mechanism of a motion of the blocks: `motion(k, x)` is the displacement (or
/// virtual velocity) of body k's material point at `x` (table frame), `ids` the bodies' ids,
/// `beam` the beam's index and `scale` the beam's motion (the relative motions are compared
/// with it). A joint moves when its largest relative motion reaches [`ACTIVE_JOINT_SHARE`]
/// of `scale` and passes its elastic range ([`MechanismJoint::elastic_m`]: the motion its
/// springs alone may give, as the elastic shear of a loading beam's bed under a wall that
/// rocks); the joints that do not move join the blocks into rigid groups, and the
/// crack is the moving joints around the beam's group (bed joints: a normal within 45° of z;
/// head joints: within 45° of x). `rotation(k)` is body k's rotation about y and `anchor`
/// the actuator's point (table frame): the mechanism is rocking where the group's rotation
/// about the crack's foot explains at least two thirds of the beam's motion at the anchor
/// (a rotation about a toe, whatever the crack's steps), shear (sliding on one bed level
/// without head joints, diagonal otherwise) where it explains at most a third (a
/// translation along the crack), mixed between. Where no block moves with the beam (the
/// crack along the beam's bed) the share read is the crack's opening share instead: a
/// beam held level does not turn with a wall that rocks under it.
pub fn read_mechanism(
    joints: &[MechanismJoint],
    ids: &[String],
    beam: usize,
    anchor: Vec3,
    scale: f64,
    motion: impl Fn(usize, &Vec3) -> Vec3,
    rotation: impl Fn(usize) -> f64,
) -> InPlaneMechanism {
    let n = ids.len();
    // Union of the bodies joined by joints that do not move (index n: the table).
    let mut parent: Vec<usize> = (0..=n).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let stats = joint_motions(joints, &motion);
    let moves = |i: usize| {
        let (largest, j) = (stats[i].0, &joints[i]);
        scale > 0.0 && largest >= ACTIVE_JOINT_SHARE * scale && largest > j.elastic_m
    };
    for (i, j) in joints.iter().enumerate() {
        if !moves(i) {
            let (ra, rb) = (root(&mut parent, j.a.unwrap_or(n)), root(&mut parent, j.b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // The group that moves with the beam (index n: the table).
    let rb = root(&mut parent, beam);
    let mut group: Vec<bool> = (0..=n).map(|k| root(&mut parent, k) == rb).collect();
    // A part turning about a point inside the wall (a rigid wall rocking on a stepped
    // crack) moves its joints near the pivot by less than the share: they join it to the
    // table although the beam moved. Its blocks are then those whose motion is nearer the
    // beam's rigid motion than rest, and its crack every joint between them and the rest.
    let glued = scale > 0.0 && group[n] && motion(beam, &anchor).norm() >= ACTIVE_JOINT_SHARE * scale;
    if glued {
        group = moving_with(joints, n, beam, &motion);
    }
    // The crack: the moving joints around the group that moves with the beam (joints
    // inside it, or between blocks left behind, are not its crack).
    let (mut open, mut slide) = (0.0, 0.0);
    let mut active = Vec::new();
    let mut levels: Vec<f64> = Vec::new();
    let mut heads = 0usize;
    for (i, j) in joints.iter().enumerate() {
        if !(glued || moves(i)) || group[j.a.unwrap_or(n)] == group[j.b] {
            continue;
        }
        let (_, jo, js) = stats[i];
        open += jo;
        slide += js;
        active.push(j.name.clone());
        if j.normal.z.abs() >= std::f64::consts::FRAC_1_SQRT_2 {
            let z = j.points.iter().map(|p| p.z).sum::<f64>() / j.points.len().max(1) as f64;
            levels.push(z);
        } else if j.normal.x.abs() >= std::f64::consts::FRAC_1_SQRT_2 {
            heads += 1;
        }
    }
    levels.sort_by(f64::total_cmp);
    let mut distinct: Vec<f64> = Vec::new();
    for z in levels {
        if distinct.last().is_none_or(|&l| z - l > 0.01) {
            distinct.push(z);
        }
    }
    let moving_blocks = (0..n).filter(|&k| k != beam && group[k]).map(|k| ids[k].clone()).collect();
    let share = if open + slide > 0.0 { open / (open + slide) } else { 0.0 };
    // How much of the beam's motion the moving part's rotation about the crack's foot
    // explains: 1 for a rotation about a toe, 0 for a translation.
    let group: Vec<usize> = (0..n).filter(|&k| group[k]).collect();
    let theta = group.iter().map(|&k| rotation(k)).sum::<f64>() / group.len().max(1) as f64;
    let foot = distinct.first().copied().unwrap_or(0.0).min(anchor.z);
    let u = motion(beam, &anchor).x;
    let rotating = if u.abs() > 0.0 { (theta.abs() * (anchor.z - foot) / u.abs()).min(1.0) } else { 0.0 };
    // A crack along the beam's own bed (no block moves with the beam): the wall under it
    // turns or slides and the beam follows, turned with it or, held level, lifted by it
    // (double curvature), so the beam's rotation need not read the wall's; the crack's own
    // motion does, opening where the wall turns about its toes and sliding where it slides.
    let rotating = if group.len() == 1 && !active.is_empty() { share } else { rotating };
    let kind = if active.is_empty() {
        MechanismKind::None
    } else if rotating >= 2.0 / 3.0 {
        MechanismKind::Rocking
    } else if rotating <= 1.0 / 3.0 {
        if distinct.len() <= 1 && heads == 0 {
            MechanismKind::Sliding
        } else {
            MechanismKind::Diagonal
        }
    } else {
        MechanismKind::Mixed
    };
    let crack = if active.is_empty() {
        "none"
    } else if distinct.len() <= 1 && heads == 0 {
        "horizontal"
    } else {
        "stepped"
    };
    InPlaneMechanism {
        kind,
        rotation_share: rotating,
        opening_share: share,
        crack: crack.to_string(),
        joints: active,
        bed_levels_m: distinct,
        moving_blocks,
    }
}

/// Per joint: its largest relative motion, its opening and its sliding (sums over its
/// points; m), from the bodies' motions `motion(k, x)` (m) at the points `x`.
fn joint_motions(joints: &[MechanismJoint], motion: &impl Fn(usize, &Vec3) -> Vec3) -> Vec<(f64, f64, f64)> {
    joints
        .iter()
        .map(|j| {
            let (mut largest, mut jo, mut js) = (0.0_f64, 0.0, 0.0);
            for x in &j.points {
                let ua = j.a.map_or(Vec3::zeros(), |a| motion(a, x));
                let d = motion(j.b, x) - ua;
                let dn = d.dot(&j.normal);
                jo += dn.abs();
                js += (d - j.normal * dn).norm();
                largest = largest.max(d.norm());
            }
            (largest, jo, js)
        })
        .collect()
}

/// Per body (index n: the table, never), whether it moves with the beam `beam`: whether
/// its motion (`motion(k, x)`, m) at the mean of its joints' points is nearer the beam's
/// rigid motion there than rest. The beam always does.
fn moving_with(joints: &[MechanismJoint], n: usize, beam: usize, motion: &impl Fn(usize, &Vec3) -> Vec3) -> Vec<bool> {
    let mut at = vec![(Vec3::zeros(), 0usize); n];
    for j in joints {
        for k in j.a.into_iter().chain([j.b]) {
            for x in &j.points {
                at[k].0 += x;
                at[k].1 += 1;
            }
        }
    }
    let mut with = vec![false; n + 1];
    for (k, (sum, count)) in at.iter().enumerate() {
        if *count == 0 {
            continue;
        }
        let x = sum / *count as f64;
        let own = motion(k, &x);
        with[k] = (own - motion(beam, &x)).norm() < own.norm();
    }
    with[beam] = true;
    with
}

/// The poses of the bodies: centroid (m) and rotation, in the simulation's body order.
pub(crate) type Poses = Vec<(Vec3, nalgebra::UnitQuaternion<f64>)>;

/// The mechanism read between the poses `reference` and those at the largest positive
/// displacement (`scale`, m, the displacement from `reference`; `at`, the poses); `anchor`
/// the beam's anchor (m, world) at `reference`. Read by [`HalfCycle::mechanism`] for both
/// drivers.
fn mechanism_at_reading(
    ref_joints: &[MechanismJoint],
    ids: &[String],
    beam: usize,
    anchor: Vec3,
    reference: &Poses,
    scale: f64,
    at: &Poses,
) -> InPlaneMechanism {
    let motion = |k: usize, x: &Vec3| -> Vec3 {
        let (p0, q0) = reference[k];
        let (p1, q1) = at[k];
        p1 + (q1 * q0.inverse()) * (x - p0) - x
    };
    let turn = |k: usize| (at[k].1 * reference[k].1.inverse()).scaled_axis().y;
    read_mechanism(ref_joints, ids, beam, anchor, scale.max(0.0), motion, turn)
}

/// The start of the positive half-cycle that leads to the mechanism's reading: the poses
/// where the displacement last came up through zero before its largest positive value (the
/// state under the vertical force for a monotonic run). The mechanism of a cyclic run is the
/// motion of that half-cycle, as a laboratory reads the mechanism a push opens, not the
/// residual slips the earlier cycles left.
pub(crate) struct HalfCycle {
    /// The last upward crossing: its displacement (m) and poses.
    start: (f64, Poses),
    /// The crossing of the reading kept.
    kept: (f64, Poses),
    /// The last displacement seen, m.
    last: f64,
}

impl HalfCycle {
    /// Starting at the reference state.
    pub(crate) fn new(reference: &Poses) -> HalfCycle {
        HalfCycle { start: (0.0, reference.clone()), kept: (0.0, reference.clone()), last: 0.0 }
    }

    /// Sees an increment's displacement `top` (m) and poses.
    pub(crate) fn step(&mut self, top: f64, now: &Poses) {
        if self.last < 0.0 && top >= 0.0 {
            self.start = (top, now.clone());
        }
        self.last = top;
    }

    /// The reading moved to the current increment: its half-cycle's start is kept.
    pub(crate) fn keep(&mut self) {
        self.kept = self.start.clone();
    }

    /// The mechanism read between the kept start and `reading` ([`mechanism_at_reading`];
    /// `anchor` and `reference` those under the vertical force, the anchor moved with the
    /// beam, body `beam`, to the start).
    pub(crate) fn mechanism(
        &self,
        ref_joints: &[MechanismJoint],
        ids: &[String],
        beam: usize,
        anchor: Vec3,
        reference: &Poses,
        reading: &(f64, Poses),
    ) -> InPlaneMechanism {
        let (u0, base) = (&self.kept.0, &self.kept.1);
        let anchor = anchor + (base[beam].0 - reference[beam].0);
        mechanism_at_reading(ref_joints, ids, beam, anchor, base, reading.0 - u0, &reading.1)
    }
}
