//! How far a block leaves the wall: a sanity reading of a run's poses.
//!
//! A wall that stays whole moves as parts: every block moves with at least one of the
//! bodies it shares a joint with (a block of the course beside it, above or below it, the
//! loading beam, or the table, which does not move), even where cracks cut the wall into
//! parts (a block beside a stepped crack moves with its neighbours on its side of it; a
//! block left behind by the part that rocks away rests on the block below it). A block shed
//! from the wall (an end block walking out of its course, a half-block squeezed from under
//! the beam's corner) moves with none of them. The **excursion** of a block is the distance
//! between its centroid and where the rigid motion of the nearest-moving of its joint
//! neighbours carries it; a wall's excursion is the largest of its blocks'.
//!
//! Joint neighbours are read from the layout: two blocks whose bounding boxes touch (within
//! [`TOUCH_TOLERANCE_M`]) over an area (an overlap of at least [`CONTACT_SHARE`] of the
//! smaller block's extent in each of the two directions along the joint), and the table for
//! a block whose bottom is within the tolerance of z = 0. Fixed blocks do not move.
//!
//! A block is **shed** when its excursion exceeds [`SHED_SHARE`] of its smallest extent
//! ([`JointNeighbours::shed_but`]): farther than a joint's deformation or a crack's opening
//! beside it can carry it, it has left the wall.

use crate::layout::Layout;
use crate::math::Vec3;
use nalgebra::UnitQuaternion;

/// How close two blocks' boxes must come to share a joint, m \[2 mm\] (the generator's
/// seating gaps and sawn stone's tolerances are below it).
pub const TOUCH_TOLERANCE_M: f64 = 2e-3;

/// The share of the smaller block's extent along the joint that the two boxes must
/// overlap in each direction to share a joint rather than an edge \[0.1\].
pub const CONTACT_SHARE: f64 = 0.1;

/// The share of a block's smallest extent (of its box as laid) that its excursion must
/// exceed for it to have been shed from the wall \[0.25\]: a block carried that far from
/// every neighbour has lost a quarter of its bearing (25 mm for the 0.1 m half-stones of the
/// bundled granite wall, 37 mm for its 0.15 m courses), where the joints' deformation and
/// the openings of a rocking wall's cracks beside a block that stays in it are a few
/// millimetres. Between the two, `largest_block_excursion_mm` reads a block walking.
pub const SHED_SHARE: f64 = 0.25;

/// The poses of the bodies: centroid (m) and rotation, in the layout's block order.
pub type Poses = [(Vec3, UnitQuaternion<f64>)];

/// A body a block shares a joint with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Neighbour {
    /// Another block of the layout (its index).
    Block(usize),
    /// The table, or a fixed block: it does not move.
    Still,
}

/// Each block's joint neighbours (see the module doc).
#[derive(Debug, Clone)]
pub struct JointNeighbours {
    neighbours: Vec<Vec<Neighbour>>,
    /// Each block's smallest extent as laid, m.
    sizes: Vec<f64>,
}

impl JointNeighbours {
    /// The joint neighbours of the layout's blocks, read from their shapes as laid.
    pub fn of(layout: &Layout) -> JointNeighbours {
        let boxes: Vec<_> = layout.blocks.iter().map(|b| b.shape.aabb()).collect();
        let n = boxes.len();
        let mut neighbours = vec![Vec::new(); n];
        for i in 0..n {
            if layout.blocks[i].fixed {
                continue;
            }
            if boxes[i].min.z <= TOUCH_TOLERANCE_M {
                neighbours[i].push(Neighbour::Still);
            }
            for j in 0..n {
                if i == j || !touch(&boxes[i], &boxes[j]) {
                    continue;
                }
                neighbours[i].push(if layout.blocks[j].fixed { Neighbour::Still } else { Neighbour::Block(j) });
            }
        }
        let sizes = boxes.iter().map(|b| (b.max - b.min).min()).collect();
        JointNeighbours { neighbours, sizes }
    }

    /// The largest excursion of any block between `reference` and `now` (m) and the
    /// block's index; `(0, None)` when no block moved from all of its neighbours.
    pub fn largest(&self, reference: &Poses, now: &Poses) -> (f64, Option<usize>) {
        self.largest_but(reference, now, None)
    }

    /// [`JointNeighbours::largest`] over every block but `skip` (a body of the rig, such as
    /// the in-plane test's loading beam, whose slip on the wall is no block leaving it).
    pub fn largest_but(&self, reference: &Poses, now: &Poses, skip: Option<usize>) -> (f64, Option<usize>) {
        self.read_but(reference, now, skip).0
    }

    /// The block shed from the wall between `reference` and `now` (its excursion above
    /// [`SHED_SHARE`] of its smallest extent; of several, the one farthest past its bound),
    /// every block but `skip` read; `None`: the wall is whole.
    pub fn shed_but(&self, reference: &Poses, now: &Poses, skip: Option<usize>) -> Option<usize> {
        self.read_but(reference, now, skip).1
    }

    /// [`JointNeighbours::largest_but`] and [`JointNeighbours::shed_but`] in one pass over
    /// the blocks.
    pub fn read_but(
        &self,
        reference: &Poses,
        now: &Poses,
        skip: Option<usize>,
    ) -> ((f64, Option<usize>), Option<usize>) {
        let (mut largest, mut shed) = ((0.0, None), (1.0, None));
        for (k, e) in self.excursions(reference, now, skip) {
            if e > largest.0 {
                largest = (e, Some(k));
            }
            let past = e / (SHED_SHARE * self.sizes[k]);
            if past > shed.0 {
                shed = (past, Some(k));
            }
        }
        (largest, shed.1)
    }

    /// Each block's excursion (its index, m), the blocks with no joint neighbour and `skip`
    /// left out.
    fn excursions<'a>(
        &'a self,
        reference: &'a Poses,
        now: &'a Poses,
        skip: Option<usize>,
    ) -> impl Iterator<Item = (usize, f64)> + 'a {
        self.neighbours.iter().enumerate().filter(move |(k, _)| skip != Some(*k)).filter_map(move |(k, ns)| {
            let off = |nb: &Neighbour| match *nb {
                Neighbour::Block(j) => carried_off(reference, now, k, j),
                Neighbour::Still => (now[k].0 - reference[k].0).norm(),
            };
            ns.iter().map(off).min_by(f64::total_cmp).map(|e| (k, e))
        })
    }
}

impl JointNeighbours {
    /// Per block, whether it moved between `start` and `now` by more than `eps` (m) from
    /// where every one of its joint neighbours' rigid motion carries it (it walked alone:
    /// a block with no neighbour never does).
    pub fn walked_alone(&self, start: &Poses, now: &Poses, eps: f64) -> Vec<bool> {
        self.neighbours
            .iter()
            .enumerate()
            .map(|(k, ns)| {
                !ns.is_empty()
                    && ns.iter().all(|nb| match *nb {
                        Neighbour::Block(j) => carried_off(start, now, k, j) > eps,
                        Neighbour::Still => (now[k].0 - start[k].0).norm() > eps,
                    })
            })
            .collect()
    }
}

impl JointNeighbours {
    /// The largest **walk** of a block between `start` and `now` (m) and the block's index
    /// (`(0, None)`: none moved from all of its neighbours): per block, the least over its
    /// joint neighbours of how far it moved from where the neighbour's rigid motion carries
    /// it, its centroid's distance plus its rotation relative to the neighbour's (rad) times
    /// its radius `radii[k]` (m; a bound on the motion of its farthest point, as
    /// [`crate::dem::motion::body_motion`] reads a body's motion). The table and fixed blocks
    /// carry nothing. Over one increment of a quasi-static path it is the block's share of
    /// the mechanism's relative motion; a block shed from the wall, or twisted in its bed,
    /// reads its own motion.
    pub fn largest_walk(&self, start: &Poses, now: &Poses, radii: &[f64]) -> (f64, Option<usize>) {
        let mut worst = (0.0, None);
        for (k, ns) in self.neighbours.iter().enumerate() {
            let r = radii.get(k).copied().unwrap_or(0.0);
            let off = |nb: &Neighbour| match *nb {
                Neighbour::Block(j) => {
                    let turn = now[j].1 * start[j].1.inverse();
                    let carried = (now[j].0 + turn * (start[k].0 - start[j].0), turn * start[k].1);
                    crate::dem::motion::body_motion(&carried, &now[k], r)
                }
                Neighbour::Still => crate::dem::motion::body_motion(&start[k], &now[k], r),
            };
            let Some(w) = ns.iter().map(off).min_by(f64::total_cmp) else {
                continue;
            };
            if w > worst.0 {
                worst = (w, Some(k));
            }
        }
        worst
    }
}

/// Whether two boxes touch over an area: within [`TOUCH_TOLERANCE_M`] along one axis and
/// overlapping by [`CONTACT_SHARE`] of the smaller extent along the other two.
fn touch(a: &crate::geometry::Aabb, b: &crate::geometry::Aabb) -> bool {
    let gap = |k: usize| (a.min[k] - b.max[k]).max(b.min[k] - a.max[k]);
    let overlap = |k: usize| {
        let o = a.max[k].min(b.max[k]) - a.min[k].max(b.min[k]);
        let smaller = (a.max[k] - a.min[k]).min(b.max[k] - b.min[k]);
        o >= CONTACT_SHARE * smaller
    };
    (0..3).any(|k| gap(k) <= TOUCH_TOLERANCE_M && (0..3).filter(|&m| m != k).all(overlap))
}

/// The distance between block `k`'s centroid at `now` and where block `j`'s rigid motion
/// from `reference` to `now` carries it, m.
fn carried_off(reference: &Poses, now: &Poses, k: usize, j: usize) -> f64 {
    let (pj0, qj0) = reference[j];
    let (pj1, qj1) = now[j];
    let carried = pj1 + (qj1 * qj0.inverse()) * (reference[k].0 - pj0);
    (now[k].0 - carried).norm()
}

/// The widening of the most widened course of `layout` in the poses `now` from `reference`
/// (m) and the course: for each course (the blocks' `course`; the block `beam` left out),
/// the span of its blocks' centroids along the wall's length (x) now, less that in
/// `reference`. Where the excursion reads a block leaving
/// every joint neighbour, this reads a course's ends moving apart together with the courses
/// above and below them (an end column walking outwards over the cycles, its head joints
/// left open), which no neighbour of theirs departs from. `(0, None)` for a layout without
/// courses.
pub fn course_widening(layout: &Layout, reference: &Poses, now: &Poses, beam: Option<usize>) -> (f64, Option<usize>) {
    let mut spans: std::collections::BTreeMap<usize, [f64; 4]> = std::collections::BTreeMap::new();
    for (k, b) in layout.blocks.iter().enumerate() {
        let Some(c) = b.course.filter(|_| Some(k) != beam) else { continue };
        let e = spans.entry(c).or_insert([f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY]);
        let (x0, x1) = (reference[k].0.x, now[k].0.x);
        *e = [e[0].min(x0), e[1].max(x0), e[2].min(x1), e[3].max(x1)];
    }
    spans.into_iter().map(|(c, [r0, r1, n0, n1])| ((n1 - n0) - (r1 - r0), Some(c))).fold((0.0, None), |best, w| {
        if w.0 > best.0 {
            w
        } else {
            best
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two courses of 0.2 × 0.2 × 0.15 m boxes: three on the table, two above them
    /// (running bond), as laid; their centroids as the reference poses.
    fn two_courses() -> (Layout, Vec<(Vec3, UnitQuaternion<f64>)>) {
        let mut boxes: Vec<_> = (0..3)
            .map(|i| crate::verify::box_vertices([0.2 * i as f64, -0.1, 0.0], [0.2 * i as f64 + 0.2, 0.1, 0.15]))
            .collect();
        boxes.extend((0..2).map(|i| {
            crate::verify::box_vertices([0.1 + 0.2 * i as f64, -0.1, 0.15], [0.3 + 0.2 * i as f64, 0.1, 0.3])
        }));
        let layout = crate::verify::layout_of(boxes, 1e9, 1e9, 30.0, crate::layout::BaseSliding::Free);
        let reference = layout.blocks.iter().map(|b| (b.centroid(), UnitQuaternion::identity())).collect();
        (layout, reference)
    }

    /// A course whose end blocks move apart by 3 mm and 1 mm is 4 mm wider; a wall moved
    /// and turned rigidly widens none of its courses.
    #[test]
    fn a_course_whose_ends_move_apart_widens_by_their_sum() {
        let (mut layout, reference) = two_courses();
        for (k, b) in layout.blocks.iter_mut().enumerate() {
            b.course = Some(usize::from(k >= 3));
        }
        let mut now = reference.clone();
        now[0].0.x -= 3e-3;
        now[2].0.x += 1e-3;
        let (w, c) = course_widening(&layout, &reference, &now, None);
        assert!((w - 4e-3).abs() < 1e-12 && c == Some(0), "{w} {c:?}");
        let shift = Vec3::new(0.02, 0.0, 0.001);
        let moved: Vec<_> = reference.iter().map(|(p, q)| (p + shift, *q)).collect();
        assert!(course_widening(&layout, &reference, &moved, None).0 < 1e-12);
        // The beam (here the upper course's last block) is left out.
        now = reference.clone();
        now[4].0.x += 5e-3;
        assert!(course_widening(&layout, &reference, &now, Some(4)).0 < 1e-12);
    }

    #[test]
    fn a_wall_that_moves_rigidly_has_no_excursion() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        // The upper course turned by 0.05 rad about y through its left end and shifted; the
        // lower course as laid: every block moves with a neighbour.
        let q = UnitQuaternion::from_scaled_axis(Vec3::new(0.0, 0.05, 0.0));
        let pivot = Vec3::new(0.1, 0.0, 0.15);
        let mut now = reference.clone();
        for k in 3..5 {
            now[k] = (pivot + q * (reference[k].0 - pivot) + Vec3::new(0.01, 0.0, 0.0), q * reference[k].1);
        }
        let (e, _) = nb.largest(&reference, &now);
        assert!(e < 1e-12, "{e}");
    }

    #[test]
    fn a_block_left_behind_by_a_crack_moves_with_the_block_below_it() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        // The right upper block and the right lower block move away 4 cm (a crack through
        // the wall); the rest stays: no block left its neighbours.
        let mut now = reference.clone();
        now[2].0.x += 0.04;
        now[4].0.x += 0.04;
        let (e, _) = nb.largest(&reference, &now);
        assert!(e < 1e-12, "{e}");
    }

    #[test]
    fn a_block_that_walks_out_is_named_with_its_distance() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        // The right upper block slides 7 cm off the wall while everything else stands.
        let mut now = reference.clone();
        now[4].0.x += 0.07;
        let (e, k) = nb.largest(&reference, &now);
        assert!((e - 0.07).abs() < 1e-12, "{e}");
        assert_eq!(k, Some(4));
    }

    #[test]
    fn a_block_is_shed_past_a_quarter_of_its_smallest_extent_and_a_rigid_wall_sheds_none() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        // The upper blocks are 0.15 m high: shed past 37.5 mm of excursion.
        let mut now = reference.clone();
        now[4].0.x += 0.0374;
        assert_eq!(nb.shed_but(&reference, &now, None), None);
        now[4].0.x += 0.0002;
        assert_eq!(nb.shed_but(&reference, &now, None), Some(4));
        assert_eq!(nb.shed_but(&reference, &now, Some(4)), None);
        // The upper course slides 5 cm as one part on the lower: no block left the wall.
        let mut now = reference.clone();
        now[3].0.x += 0.05;
        now[4].0.x += 0.05;
        assert_eq!(nb.shed_but(&reference, &now, None), None);
    }

    #[test]
    fn only_a_block_that_moved_from_all_its_neighbours_walked_alone() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        let mut now = reference.clone();
        // The upper course moves 1 mm together: each upper block moves with the other.
        now[3].0.x += 1e-3;
        now[4].0.x += 1e-3;
        assert_eq!(nb.walked_alone(&reference, &now, 1e-4), vec![false; 5]);
        // From there, block 4 alone moves on.
        let start = now.clone();
        now[4].0.x += 1e-3;
        assert_eq!(nb.walked_alone(&start, &now, 1e-4), vec![false, false, false, false, true]);
    }

    #[test]
    fn a_block_twisted_in_its_bed_walks_by_its_turn_times_its_radius() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        let radii = vec![0.1; 5];
        // The upper course turned 0.05 rad about y with its blocks: no block walked.
        let q = UnitQuaternion::from_scaled_axis(Vec3::new(0.0, 0.05, 0.0));
        let pivot = Vec3::new(0.1, 0.0, 0.15);
        let mut now = reference.clone();
        for k in 3..5 {
            now[k] = (pivot + q * (reference[k].0 - pivot), q * reference[k].1);
        }
        assert!(nb.largest_walk(&reference, &now, &radii).0 < 1e-12);
        // From the wall as laid, block 4 alone twisted 0.03 rad about z (in plan) about its
        // own centroid: its centroid stays, its corners move.
        let mut now = reference.clone();
        now[4].1 = UnitQuaternion::from_scaled_axis(Vec3::new(0.0, 0.0, 0.03));
        let (w, k) = nb.largest_walk(&reference, &now, &radii);
        assert_eq!(k, Some(4));
        assert!((w - 0.03 * 0.1).abs() < 1e-9, "{w}");
        assert!(nb.largest(&reference, &now).0 < 1e-12, "the centroid's excursion does not see a twist");
    }

    #[test]
    fn the_table_holds_the_base_course_and_edges_are_not_joints() {
        let (layout, reference) = two_courses();
        let nb = JointNeighbours::of(&layout);
        // The whole base course moves 3 cm on the table and the upper course with it: the
        // base blocks still move with each other (a wall sliding as a whole is whole).
        let mut now = reference.clone();
        for p in &mut now {
            p.0.x += 0.03;
        }
        assert!(nb.largest(&reference, &now).0 < 1e-12);
        // Blocks 0 and 4 meet at an edge only (block 4 starts at x = 0.3 over block 1's
        // right half and block 2's left half): not neighbours.
        assert!(!nb.neighbours[0].contains(&Neighbour::Block(4)));
        assert!(nb.neighbours[4].contains(&Neighbour::Block(1)) && nb.neighbours[4].contains(&Neighbour::Block(2)));
    }
}
