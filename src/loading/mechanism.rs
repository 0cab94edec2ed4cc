//! The collapse mechanism read from the motion between the last stable and the collapsed
//! state of a test: the failing joints, the groups of blocks they cut loose, and whether
//! each joint slid or opened.

use super::monitors::body_motion;
use crate::dem::Simulation;
use serde::{Deserialize, Serialize};

/// Failure mode of a joint or of the wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MechanismKind {
    /// Relative sliding along the failing joints.
    Sliding,
    /// Rotation about an edge, the failing joints opening.
    Toppling,
    /// Some failing joints slide, others open.
    Mixed,
    /// No collapse.
    None,
}

/// The collapse mechanism.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mechanism {
    /// Overall kind.
    pub kind: MechanismKind,
    /// The governing joint: the lowest failing joint, named `table/ID` or `ID_A/ID_B`.
    pub joint: String,
    /// Every joint between a moving and a resting body, with its kind, lowest first.
    pub joints: Vec<(String, MechanismKind)>,
    /// Ids of the blocks that moved.
    pub blocks: Vec<String>,
    /// The mechanism as a person would read it (failure height, kind, start, extent);
    /// `None` when nothing moved.
    #[serde(default)]
    pub reading: Option<MechanismReading>,
}

impl Mechanism {
    /// No mechanism (the wall stood).
    pub fn none() -> Mechanism {
        Mechanism { kind: MechanismKind::None, joint: String::new(), joints: vec![], blocks: vec![], reading: None }
    }
}

/// Share of the largest motion above which a joint counts as failing (its relative motion)
/// or a group of blocks as moving (its largest body motion) in [`mechanism`].
pub const MECHANISM_SHARE: f64 = 0.25;

/// The root of `i` in the union-find forest `parent` (path halving).
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Joins the groups of `i` and `j`, the lower index the root.
fn join(parent: &mut [usize], i: usize, j: usize) {
    let (ri, rj) = (root(parent, i), root(parent, j));
    if ri != rj {
        parent[ri.max(rj)] = ri.min(rj);
    }
}

/// The kind of a mechanism from the kinds of its joints: none without joints, sliding or
/// toppling when every joint agrees, else mixed.
fn overall_kind(kinds: impl Iterator<Item = MechanismKind> + Clone) -> MechanismKind {
    let mut all = kinds.clone().peekable();
    if all.peek().is_none() {
        MechanismKind::None
    } else if kinds.clone().all(|k| k == MechanismKind::Sliding) {
        MechanismKind::Sliding
    } else if kinds.clone().all(|k| k == MechanismKind::Toppling) {
        MechanismKind::Toppling
    } else {
        MechanismKind::Mixed
    }
}

/// The collapse mechanism from the motion between a stable and a failed state of the same
/// simulation.
///
/// Read from the joints, not from the blocks one by one (a block at the foot of a toppling
/// stack rotates with it but moves less than a third as far as the top):
/// 1. every joint that carries force in the stable state gets its relative motion, the
///    largest over its nodes of the change of the B − A node separation (m);
/// 2. a joint *fails* if that motion exceeds [`MECHANISM_SHARE`] of the largest one;
/// 3. the blocks joined by intact joints form rigid groups; a group *rests* if it holds a
///    fixed body or is held by the table through an intact joint, or if no block of it
///    moved (centroid motion plus rotation times radius) more than [`MECHANISM_SHARE`] of
///    the largest block motion (e.g. an end-restrained group); the others *move*; nothing
///    moves if no block moved more than 1e-9 of the largest block radius (rounding);
/// 4. the mechanism's joints are those between a moving and a resting group, each sliding
///    if its largest tangential relative motion exceeds its largest opening, else toppling;
///    the governing joint is the lowest (mean node height in the stable state).
pub fn mechanism(stable: &Simulation, failed: &Simulation) -> Mechanism {
    let nb = stable.state.bodies.len();
    let moved: Vec<f64> = stable
        .state
        .bodies
        .iter()
        .zip(&failed.state.bodies)
        .map(|(s, f)| body_motion(&(s.pos, s.rot), &(f.pos, f.rot), s.radius))
        .collect();
    // Motion below a nanometre per metre of block size is rounding, not a mechanism.
    let max_radius = stable.state.bodies.iter().map(|b| b.radius).fold(0.0, f64::max);
    let max_moved = moved.iter().cloned().fold(0.0, f64::max);
    let max_moved = if max_moved > 1e-9 * max_radius { max_moved } else { 0.0 };
    // Relative motion, largest opening and slip, and mean node height of every
    // load-carrying joint.
    struct JointMotion {
        contact: usize,
        relative: f64,
        open: f64,
        slip: f64,
        z: f64,
    }
    let mut motions = Vec::new();
    for (ci, c) in stable.state.contacts.iter().enumerate() {
        if c.force.norm() == 0.0 {
            continue; // not a load-carrying joint in the stable state
        }
        let (mut relative, mut open, mut slip, mut z) = (0.0f64, 0.0f64, 0.0f64, 0.0);
        let n = failed.state.contact_normal(c);
        for nd in &c.nodes {
            let (a0, b0) = stable.state.node_points(c, nd);
            let (a1, b1) = failed.state.node_points(c, nd);
            let dd = (b1 - a1) - (b0 - a0);
            let dn = dd.dot(&n);
            relative = relative.max(dd.norm());
            open = open.max(dn);
            slip = slip.max((dd - n * dn).norm());
            z += 0.5 * (a0.z + b0.z) / c.nodes.len() as f64;
        }
        motions.push(JointMotion { contact: ci, relative, open, slip, z });
    }
    let max_relative = motions.iter().map(|m| m.relative).fold(0.0, f64::max);
    // Rigid groups: union-find over the bodies and the ground (index nb) through intact joints.
    let mut parent: Vec<usize> = (0..=nb).collect();
    for (k, b) in stable.state.bodies.iter().enumerate() {
        if b.fixed() {
            join(&mut parent, k, nb);
        }
    }
    for m in &motions {
        if m.relative <= MECHANISM_SHARE * max_relative {
            let c = &stable.state.contacts[m.contact];
            join(&mut parent, c.a.unwrap_or(nb), c.b);
        }
    }
    let mut group_motion = vec![0.0f64; nb + 1];
    for (k, &d) in moved.iter().enumerate() {
        let r = root(&mut parent, k);
        group_motion[r] = group_motion[r].max(d);
    }
    let ground = root(&mut parent, nb);
    let moving: Vec<bool> = (0..nb)
        .map(|k| {
            let r = root(&mut parent, k);
            let cut_off = r != ground && group_motion[r] > MECHANISM_SHARE * max_moved;
            max_moved > 0.0 && (cut_off || moved[k] > MECHANISM_SHARE * max_moved)
        })
        .collect();
    let is_moving = |i: Option<usize>| i.is_some_and(|i| moving[i]);
    let mut joints: Vec<(f64, String, MechanismKind)> = motions
        .iter()
        .filter(|m| {
            let c = &stable.state.contacts[m.contact];
            is_moving(c.a) != is_moving(Some(c.b))
        })
        .map(|m| {
            let kind = if m.slip > m.open { MechanismKind::Sliding } else { MechanismKind::Toppling };
            (m.z, stable.state.joint_name(&stable.state.contacts[m.contact]), kind)
        })
        .collect();
    joints.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let kind = overall_kind(joints.iter().map(|j| j.2));
    let motions: Vec<BlockMotion> = stable
        .state
        .bodies
        .iter()
        .zip(&moved)
        .zip(&moving)
        .map(|((b, &d), &m)| {
            let bb = b.world_shape().aabb();
            BlockMotion { x: (bb.min.x, bb.max.x), z: (bb.min.z, bb.max.z), moved: d, moving: m, fixed: b.fixed() }
        })
        .collect();
    let reading = read_mechanism(&motions, kind);
    Mechanism {
        reading,
        kind,
        joint: joints.first().map(|j| j.1.clone()).unwrap_or_default(),
        joints: joints.into_iter().map(|j| (j.1, j.2)).collect(),
        blocks: stable.state.bodies.iter().zip(&moving).filter(|(_, m)| **m).map(|(b, _)| b.id.clone()).collect(),
    }
}

/// What kind of failure a wall showed, as a person reads it (the source paper's words,
/// Santa-Cruz et al. 2021, §2.2: CBL "toppling", SBR "bending"), or as drystone reads a
/// realization ([`MechanismReading`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// A part of the wall overturns about a bed joint (the failing joints open).
    Toppling,
    /// A part of the wall slides along a bed joint.
    Sliding,
    /// The wall bulges out between held ends: rotation of the blocks in a central section
    /// while both ends stay (catenary action; the paper's SBR walls).
    Bending,
    /// Some failing joints slide, others open.
    Mixed,
}

impl FailureKind {
    /// Every kind, in the order of the files.
    pub const ALL: [FailureKind; 4] =
        [FailureKind::Toppling, FailureKind::Sliding, FailureKind::Bending, FailureKind::Mixed];

    /// The name in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            FailureKind::Toppling => "toppling",
            FailureKind::Sliding => "sliding",
            FailureKind::Bending => "bending",
            FailureKind::Mixed => "mixed",
        }
    }

    /// The kind of a name.
    pub fn from_name(name: &str) -> Option<FailureKind> {
        FailureKind::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Where along the wall a failure started.
///
/// A realization reads `end`, `centre` or `uniform` ([`MechanismReading`]); an observer
/// may also say `random`: "started in a random section" (the paper's SBL walls), a
/// section somewhere, end or centre, not the whole length at once.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureStart {
    /// In an outer quarter of the wall's length.
    End,
    /// In the central half of the wall's length.
    Centre,
    /// The whole length at once (a uniform, two-dimensional failure).
    Uniform,
    /// A section somewhere (end or centre), not the whole length: observed only.
    Random,
}

impl FailureStart {
    /// Every start an observer may read, in the order of the files.
    pub const ALL: [FailureStart; 4] =
        [FailureStart::End, FailureStart::Centre, FailureStart::Uniform, FailureStart::Random];
    /// The starts a realization reads (the categories of the predictive).
    pub const SIMULATED: [FailureStart; 3] = [FailureStart::End, FailureStart::Centre, FailureStart::Uniform];

    /// The name in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            FailureStart::End => "end",
            FailureStart::Centre => "centre",
            FailureStart::Uniform => "uniform",
            FailureStart::Random => "random",
        }
    }

    /// The start of a name.
    pub fn from_name(name: &str) -> Option<FailureStart> {
        FailureStart::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether an observer's reading `self` agrees with a realization's start `simulated`
    /// (`random` agrees with `end` and `centre`).
    pub fn matches(self, simulated: FailureStart) -> bool {
        match self {
            FailureStart::Random => matches!(simulated, FailureStart::End | FailureStart::Centre),
            s => s == simulated,
        }
    }

    /// How many of the simulated starts an observer's reading covers (2 for `random`).
    pub fn covers(self) -> usize {
        FailureStart::SIMULATED.iter().filter(|s| self.matches(**s)).count()
    }
}

/// The failure mechanism as a person would read it, from a realization: the quantities of
/// the measured mechanism file ([`crate::io::measured::MeasuredMechanism`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MechanismReading {
    /// The lowest bed joint of the moving part as a fraction of the wall's height: the
    /// lowest bottom of a moving block in the last stable state, over the height of the
    /// wall's blocks, both from the table (0: the table joint, the whole wall moves).
    pub failure_height_fraction: f64,
    /// The kind: the mechanism's toppling, sliding or mixed, or `bending` when a toppling
    /// or mixed mechanism started in the centre while both ends stood (the blocks of each
    /// outer eighth of the length moved less than [`LEADING_SHARE`] of the largest motion).
    pub kind: FailureKind,
    /// Where along the wall it started: the *leading part* is every block that moved at
    /// least [`LEADING_SHARE`] of the largest block motion between the last stable and the
    /// first unstable state; `uniform` if it spans at least [`UNIFORM_SPAN`] of the
    /// wall's length, else `centre` if its motion-weighted centre lies in the central half
    /// of the length, else `end`.
    pub start: FailureStart,
    /// The share of the wall's length the moving blocks span, in [0, 1].
    pub extent_fraction: f64,
}

/// Share of the largest block motion above which a block belongs to the leading part of a
/// failure ([`MechanismReading::start`]).
pub const LEADING_SHARE: f64 = 0.5;

/// Share of the wall's length the leading part must span for a failure to read as
/// `uniform` (the whole length at once).
pub const UNIFORM_SPAN: f64 = 0.75;

/// One block as [`read_mechanism`] sees it (table frame, m, last stable state).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockMotion {
    /// Lowest and highest x of the block.
    pub x: (f64, f64),
    /// Lowest and highest z of the block.
    pub z: (f64, f64),
    /// Its motion between the stable and the failed state, m (centroid motion plus
    /// rotation times radius).
    pub moved: f64,
    /// Part of the mechanism (a moving block).
    pub moving: bool,
    /// A fixed body (not part of the wall: stops, supports).
    pub fixed: bool,
}

/// Reads a mechanism of kind `kind` from its blocks ([`MechanismReading`]); `None` when
/// nothing moves (`kind` is [`MechanismKind::None`] or no block of the wall is moving) or
/// the wall has no extent.
pub fn read_mechanism(blocks: &[BlockMotion], kind: MechanismKind) -> Option<MechanismReading> {
    let wall: Vec<&BlockMotion> = blocks.iter().filter(|b| !b.fixed).collect();
    let kind = match kind {
        MechanismKind::None => return None,
        MechanismKind::Sliding => FailureKind::Sliding,
        MechanismKind::Toppling => FailureKind::Toppling,
        MechanismKind::Mixed => FailureKind::Mixed,
    };
    let fold = |f: &dyn Fn(&BlockMotion) -> f64, min: bool| {
        wall.iter().map(|b| f(b)).fold(if min { f64::INFINITY } else { f64::NEG_INFINITY }, |a, v| {
            if min {
                a.min(v)
            } else {
                a.max(v)
            }
        })
    };
    let (z0, z1) = (fold(&|b| b.z.0, true), fold(&|b| b.z.1, false));
    let (x0, x1) = (fold(&|b| b.x.0, true), fold(&|b| b.x.1, false));
    let (height, length) = (z1 - z0, x1 - x0);
    let moving: Vec<&&BlockMotion> = wall.iter().filter(|b| b.moving).collect();
    if moving.is_empty() || !(height > 0.0 && length > 0.0) {
        return None;
    }
    let bottom = moving.iter().map(|b| b.z.0).fold(f64::INFINITY, f64::min);
    let failure_height_fraction = ((bottom - z0) / height).clamp(0.0, 1.0);
    let span = |set: &[&&BlockMotion]| {
        let lo = set.iter().map(|b| b.x.0).fold(f64::INFINITY, f64::min);
        let hi = set.iter().map(|b| b.x.1).fold(f64::NEG_INFINITY, f64::max);
        ((hi - lo) / length).clamp(0.0, 1.0)
    };
    let extent_fraction = span(&moving);
    let largest = wall.iter().map(|b| b.moved).fold(0.0, f64::max);
    let leading: Vec<&&BlockMotion> = wall.iter().filter(|b| b.moved >= LEADING_SHARE * largest).collect();
    let start = if span(&leading) >= UNIFORM_SPAN {
        FailureStart::Uniform
    } else {
        let w: f64 = leading.iter().map(|b| b.moved).sum();
        let xc = leading.iter().map(|b| b.moved * 0.5 * (b.x.0 + b.x.1)).sum::<f64>() / w.max(f64::MIN_POSITIVE);
        if (xc - 0.5 * (x0 + x1)).abs() <= 0.25 * length {
            FailureStart::Centre
        } else {
            FailureStart::End
        }
    };
    // Both ends standing: the largest motion of the blocks reaching into each outer eighth.
    let end_motion = |left: bool| {
        wall.iter()
            .filter(|b| if left { b.x.0 < x0 + 0.125 * length } else { b.x.1 > x1 - 0.125 * length })
            .map(|b| b.moved)
            .fold(0.0, f64::max)
    };
    let ends_stand = end_motion(true) < LEADING_SHARE * largest && end_motion(false) < LEADING_SHARE * largest;
    let kind = if start == FailureStart::Centre && ends_stand && kind != FailureKind::Sliding {
        FailureKind::Bending
    } else {
        kind
    };
    Some(MechanismReading { failure_height_fraction, kind, start, extent_fraction })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hand-made wall: 5 courses of 0.1 m, 4 blocks of 0.25 m per course (length 1 m,
    /// height 0.5 m), each block's motion from `motion(course, column)` (0: resting).
    fn wall(motion: impl Fn(usize, usize) -> f64) -> Vec<BlockMotion> {
        let mut v = Vec::new();
        for c in 0..5 {
            for k in 0..4 {
                let d = motion(c, k);
                v.push(BlockMotion {
                    x: (0.25 * k as f64, 0.25 * (k + 1) as f64),
                    z: (0.1 * c as f64, 0.1 * (c + 1) as f64),
                    moved: d,
                    moving: d > 0.0,
                    fixed: false,
                });
            }
        }
        v
    }

    /// The top 60 % of the wall overturns as one along the whole length (the paper's CBL):
    /// the moving part starts at the bed joint 40 % up, uniform, over the whole length.
    #[test]
    fn a_wall_whose_top_60_percent_topples_reads_0_4_uniform() {
        let w = wall(|c, _| if c >= 2 { 0.01 * (c - 1) as f64 } else { 0.0 });
        let r = read_mechanism(&w, MechanismKind::Toppling).unwrap();
        assert!((r.failure_height_fraction - 0.4).abs() < 1e-12, "{r:?}");
        assert_eq!((r.kind, r.start), (FailureKind::Toppling, FailureStart::Uniform));
        assert!((r.extent_fraction - 1.0).abs() < 1e-12);
    }

    /// The whole wall overturns about the table joint: failure height 0.
    #[test]
    fn a_wall_toppling_at_the_base_reads_0() {
        let w = wall(|c, _| 0.01 * (c + 1) as f64);
        let r = read_mechanism(&w, MechanismKind::Toppling).unwrap();
        assert_eq!(r.failure_height_fraction, 0.0);
        assert_eq!((r.kind, r.start), (FailureKind::Toppling, FailureStart::Uniform));
        // A fixed stop beside the wall is not part of it: the same reading.
        let mut with_stop = w.clone();
        with_stop.push(BlockMotion { x: (-0.1, 1.1), z: (-0.2, 0.02), moved: 0.0, moving: false, fixed: true });
        assert_eq!(read_mechanism(&with_stop, MechanismKind::Toppling), Some(r));
    }

    /// A bulge of the two central columns above the first course, both ends standing (the
    /// paper's SBR): bending from the centre, over half the length, from the first bed joint.
    #[test]
    fn a_centre_bulge_between_standing_ends_reads_bending_from_the_centre() {
        let w = wall(|c, k| if c >= 1 && (k == 1 || k == 2) { 0.005 * c as f64 } else { 0.0 });
        let r = read_mechanism(&w, MechanismKind::Toppling).unwrap();
        assert!((r.failure_height_fraction - 0.2).abs() < 1e-12, "{r:?}");
        assert_eq!((r.kind, r.start), (FailureKind::Bending, FailureStart::Centre));
        assert!((r.extent_fraction - 0.5).abs() < 1e-12);
        // The same motion sliding is not bending.
        assert_eq!(read_mechanism(&w, MechanismKind::Sliding).unwrap().kind, FailureKind::Sliding);
    }

    /// The left end falls first: an end start, toppling (an end moved).
    #[test]
    fn a_failure_at_one_end_reads_end() {
        let w = wall(|c, k| {
            if c >= 3 && k == 0 {
                0.02
            } else if c >= 3 && k == 1 {
                0.005
            } else {
                0.0
            }
        });
        let r = read_mechanism(&w, MechanismKind::Mixed).unwrap();
        assert!((r.failure_height_fraction - 0.6).abs() < 1e-12, "{r:?}");
        assert_eq!((r.kind, r.start), (FailureKind::Mixed, FailureStart::End));
        assert!((r.extent_fraction - 0.5).abs() < 1e-12);
    }

    #[test]
    fn nothing_moving_reads_nothing() {
        assert_eq!(read_mechanism(&wall(|_, _| 0.0), MechanismKind::Toppling), None);
        assert_eq!(read_mechanism(&wall(|_, _| 1.0), MechanismKind::None), None);
    }

    #[test]
    fn names_round_trip_and_random_covers_end_and_centre() {
        for k in FailureKind::ALL {
            assert_eq!(FailureKind::from_name(k.name()), Some(k));
        }
        for s in FailureStart::ALL {
            assert_eq!(FailureStart::from_name(s.name()), Some(s));
        }
        assert!(FailureStart::Random.matches(FailureStart::End) && FailureStart::Random.matches(FailureStart::Centre));
        assert!(!FailureStart::Random.matches(FailureStart::Uniform));
        assert_eq!((FailureStart::Random.covers(), FailureStart::End.covers()), (2, 1));
    }
}
