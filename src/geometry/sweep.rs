//! Broad phase: sweep and prune over axis-aligned bounding boxes (pure geometry, used by
//! the DEM's contact detection and the layout's overlap check).

use super::Aabb;

/// Pairs `(i, j)`, `i < j`, whose boxes grown by `margin` (m) overlap, sorted
/// lexicographically. Sweep along x after sorting the boxes by their lower x bound
/// (stable sort on index ties), so the result is deterministic.
pub fn sweep_pairs(boxes: &[Aabb], margin: f64) -> Vec<(usize, usize)> {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| boxes[i].min.x.total_cmp(&boxes[j].min.x).then(i.cmp(&j)));
    let mut pairs = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let reach = boxes[i].max.x + 2.0 * margin;
        for &j in &order[k + 1..] {
            if boxes[j].min.x > reach {
                break;
            }
            if boxes[i].overlaps(&boxes[j], margin) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn finds_exactly_the_overlapping_pairs() {
        let b = |x: f64| Aabb { min: Vec3::new(x, 0.0, 0.0), max: Vec3::new(x + 1.0, 1.0, 1.0) };
        let boxes = vec![b(0.0), b(3.0), b(0.999), b(2.0)];
        // b(0.999) ends 1 mm short of b(2): apart without margin, paired with a 1 mm margin.
        assert_eq!(sweep_pairs(&boxes, 0.0), vec![(0, 2), (1, 3)]);
        assert_eq!(sweep_pairs(&boxes, 0.001), vec![(0, 2), (1, 3), (2, 3)]);
    }
}
