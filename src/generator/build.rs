//! The construction in the wall's elevation plane (x–z), course by course, bottom up. See
//! the [module doc](super) for the method (steps 1–7); this file implements it in stages:
//! course tops, head joints, and per stone its bed, the wedges under it, its top and its
//! polygon. Every draw comes from the realization's layout stream in this order: course
//! heights; then per course its block lengths, and per stone (left to right) its wedges'
//! fill and lengths, then its dip.

use super::polygon::{area, least_line_above, region, top_segments, HalfPlane, Line, Seg, P2};
use super::wall::{Arrangement, HeadGap, Irregular, Wall};
use super::GeneratorError;
use rand::distr::Distribution as _;
use rand::Rng;
use serde::Serialize;

/// Stone or wedge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PieceKind {
    /// A block of a course.
    Stone,
    /// A wedge stone filling a gap under a stone.
    Wedge,
}

/// The values drawn from the laws, as used in the wall (for goodness-of-fit checks).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Samples {
    /// Course heights drawn and used, bottom up, m (random laws only; the top course(s)
    /// that take the rest are not included).
    pub course_heights_m: Vec<f64>,
    /// Per course, the block lengths drawn and used between the first and the last block,
    /// left to right, m (irregular only; the end pieces are not included).
    pub block_lengths_m: Vec<Vec<f64>>,
    /// Dip of every stone's top segment, degrees, in layout order (0 for continuous and
    /// discontinuous walls).
    pub dips_deg: Vec<f64>,
}

/// One piece in the elevation plane, before extrusion.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Piece2 {
    pub kind: PieceKind,
    pub course: usize,
    /// Counter-clockwise polygon (x right, z up), m.
    pub polygon: Vec<P2>,
    /// Drawn dip of the stone's top, degrees (stones below the top course).
    pub dip_deg: Option<f64>,
}

/// Output of the elevation construction.
pub(crate) struct Elevation {
    pub pieces: Vec<Piece2>,
    pub course_tops: Vec<f64>,
    pub samples: Samples,
}

fn infeasible(wall: &Wall, key: &str, reason: String) -> GeneratorError {
    GeneratorError::Infeasible { path: wall.source.clone(), key: key.into(), reason }
}

/// Nominal course tops Z_1..Z_n (Z_n = H exactly).
fn course_tops<R: Rng + ?Sized>(wall: &Wall, rng: &mut R, samples: &mut Samples) -> Vec<f64> {
    let h = wall.height;
    let d = &wall.course_height;
    let mut heights = Vec::new();
    if d.is_fixed() {
        let n = ((h / d.mean()).round() as usize).max(1);
        heights = vec![h / n as f64; n];
    } else {
        let mean = d.mean();
        let top_min = 0.5 * mean;
        let mut sum = 0.0;
        loop {
            let x = d.sample(rng);
            if sum + x <= h - top_min {
                samples.course_heights_m.push(x);
                heights.push(x);
                sum += x;
            } else {
                break;
            }
        }
        let rest = h - sum;
        let k = ((rest / mean).round() as usize).max(1);
        for _ in 0..k {
            heights.push(rest / k as f64);
        }
    }
    let mut tops = Vec::with_capacity(heights.len());
    let mut z = 0.0;
    for (i, hk) in heights.iter().enumerate() {
        z += hk;
        tops.push(if i + 1 == heights.len() { h } else { z });
    }
    tops
}

/// Head-joint positions of course `k`: 0 = x_0 < x_1 < … < x_m = L.
fn head_joints<R: Rng + ?Sized>(wall: &Wall, k: usize, rng: &mut R, samples: &mut Samples) -> Vec<f64> {
    let l = wall.length;
    let d = &wall.block_length;
    let lbar = d.mean();
    let e_min = wall.min_end_fraction * lbar;
    let mut xs = vec![0.0];
    match &wall.arrangement {
        Arrangement::Continuous | Arrangement::Discontinuous { .. } => {
            let offset = match wall.arrangement {
                Arrangement::Discontinuous { overlap } if k % 2 == 1 => overlap * lbar,
                _ => 0.0,
            };
            let mut j = 0usize;
            loop {
                let x = offset + j as f64 * lbar;
                j += 1;
                if x >= l - e_min {
                    break;
                }
                if x >= e_min {
                    xs.push(x);
                }
            }
        }
        Arrangement::Irregular(_) => {
            let first = d.sample(rng) * rand::distr::Uniform::new(0.5, 1.0).expect("valid").sample(rng);
            let mut x = first.max(e_min);
            let mut lengths = Vec::new();
            if x < l - e_min {
                xs.push(x);
                loop {
                    let li = d.sample(rng);
                    if x + li <= l - e_min {
                        x += li;
                        xs.push(x);
                        lengths.push(li);
                    } else {
                        break;
                    }
                }
                // An over-long last piece is split in two.
                let rest = l - x;
                if rest > d.practical_max() && rest / 2.0 >= e_min {
                    xs.push(x + rest / 2.0);
                }
            }
            samples.block_lengths_m.push(lengths);
        }
    }
    xs.push(l);
    xs
}

/// Builds the elevation of one realization. `rng` is the realization's layout stream.
pub(crate) fn build<R: Rng + ?Sized>(wall: &Wall, rng: &mut R) -> Result<Elevation, GeneratorError> {
    let mut samples = Samples::default();
    let tops = course_tops(wall, rng, &mut samples);
    let c = Construction::new(wall, &tops);
    let mut lower = vec![Seg { x0: 0.0, z0: 0.0, x1: wall.length, z1: 0.0 }];
    let mut pieces = Vec::new();
    for k in 0..tops.len() {
        lower = c.course(k, &lower, rng, &mut samples, &mut pieces)?;
    }
    Ok(Elevation { pieces, course_tops: tops, samples })
}

/// What every stone of a realization needs: the wall, the nominal course tops and the
/// derived tolerances and limits.
struct Construction<'a> {
    wall: &'a Wall,
    /// Nominal course tops Z₁ … Zₙ = H, m.
    tops: &'a [f64],
    /// Mean course height and mean block length, m.
    hbar: f64,
    lbar: f64,
    /// Vertices closer than this are merged, m.
    snap: f64,
    /// The irregular arrangement's parameters (None: no wedges, no dips).
    irregular: Option<&'a Irregular>,
    /// Thinnest and shortest wedge kept, m (infinite without wedges).
    t_w: f64,
    l_w: f64,
    /// Slope of the steepest dip the law can draw.
    tan_max: f64,
    /// Thinnest stone of the top course, m.
    top_min: f64,
}

/// Where a stone goes: course `k`, block `i` of `m`, over [a, b] (m) in the slot
/// [slot.0, slot.1] (to the middle of its open head joints, or to the wall's end).
#[derive(Clone, Copy)]
struct Place {
    k: usize,
    i: usize,
    a: f64,
    b: f64,
    slot: (f64, f64),
    /// The stone's ceiling (the course cap), below the top course, m.
    cap: Option<f64>,
}

impl<'a> Construction<'a> {
    fn new(wall: &'a Wall, tops: &'a [f64]) -> Self {
        let hbar = wall.course_height.mean();
        let lbar = wall.block_length.mean();
        let snap = 1e-4 * hbar;
        let (irregular, t_w, l_w) = match &wall.arrangement {
            Arrangement::Irregular(ir) => {
                (Some(&**ir), ir.min_wedge_thickness.max(snap), ir.min_wedge_length.max(1e-6 * lbar))
            }
            _ => (None, f64::INFINITY, f64::INFINITY),
        };
        let tan_max = match irregular {
            Some(ir) => {
                let (lo, hi) = ir.dip.support();
                crate::units::deg_to_rad(lo.abs().max(hi.abs())).tan()
            }
            None => 0.0,
        };
        let mut c = Construction { wall, tops, hbar, lbar, snap, irregular, t_w, l_w, tan_max, top_min: 0.0 };
        c.top_min = wall.min_thickness_fraction * c.nominal(tops.len() - 1);
        c
    }

    /// Nominal height of course `k`, m.
    fn nominal(&self, k: usize) -> f64 {
        self.tops[k] - if k == 0 { 0.0 } else { self.tops[k - 1] }
    }

    /// Lays course `k` on `lower` (the top surface of the course below, left to right) and
    /// returns this course's top surface. Stones and wedges go to `pieces`.
    fn course<R: Rng + ?Sized>(
        &self,
        k: usize,
        lower: &[Seg],
        rng: &mut R,
        samples: &mut Samples,
        pieces: &mut Vec<Piece2>,
    ) -> Result<Vec<Seg>, GeneratorError> {
        let (wall, l, n) = (self.wall, self.wall.length, self.tops.len());
        let xs = head_joints(wall, k, rng, samples);
        let m = xs.len() - 1;
        let (gap, single_shrink) = open_joints(wall.head_gap, l, m);
        // Ceiling of this course's tops: an unshifted top segment never reaches it (it is
        // the nominal top plus the rise of the steepest dip over half the longest block);
        // below the top course it also leaves the top course its minimum thickness.
        let longest = xs.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        let mut cap = self.tops[k] + 0.5 * longest * self.tan_max;
        if k + 2 == n {
            cap = cap.min(wall.height - self.top_min);
        }
        let mut new_top: Vec<Seg> = Vec::with_capacity(m + 2);
        for i in 0..m {
            let a = if i == 0 { single_shrink } else { xs[i] + 0.5 * gap };
            let b = if i + 1 == m { l - single_shrink } else { xs[i + 1] - 0.5 * gap };
            if b - a <= 0.0 {
                return Err(infeasible(
                    wall,
                    "head_joints",
                    format!("course {k}: the open head joints ({gap} m) leave no room for block {i}"),
                ));
            }
            let slot = (if i == 0 { 0.0 } else { xs[i] }, if i + 1 == m { l } else { xs[i + 1] });
            let place = Place { k, i, a, b, slot, cap: (k + 1 < n).then_some(cap) };
            self.stone(place, lower, rng, samples, pieces, &mut new_top)?;
        }
        new_top.sort_by(|p, q| p.x0.total_cmp(&q.x0));
        Ok(new_top)
    }

    /// One stone and the wedges under it: its bed, its wedges, its top, its polygon. The
    /// stone's top edges (and wedge tops it leaves exposed) go to `new_top`.
    fn stone<R: Rng + ?Sized>(
        &self,
        p: Place,
        lower: &[Seg],
        rng: &mut R,
        samples: &mut Samples,
        pieces: &mut Vec<Piece2>,
        new_top: &mut Vec<Seg>,
    ) -> Result<(), GeneratorError> {
        let (k, i, a, b) = (p.k, p.i, p.a, p.b);
        let bottom = self.bed(p, lower)?;
        let mut wedge_tops: Vec<Seg> = Vec::new();
        if k > 0 && self.irregular.is_some() {
            self.wedges(p, bottom, lower, rng, pieces, &mut wedge_tops);
        }
        let (top, dip_deg) = self.stone_top(p, bottom, rng, samples);
        let h = self.wall.height;
        let mut planes =
            vec![HalfPlane::Above(bottom), HalfPlane::Below(top), HalfPlane::z_min(0.0), HalfPlane::z_max(h)];
        if let Some(c) = p.cap {
            planes.push(HalfPlane::z_max(c));
        }
        let poly = region(a, b, -h, 2.0 * h, &planes, self.snap);
        if poly.len() < 3 || area(&poly) <= 1e-4 * self.hbar * self.lbar {
            return Err(infeasible(
                self.wall,
                "arrangement.dip_deg",
                format!(
                    "course {k}, block {i} (x {a:.4}..{b:.4} m) has no room between its bed and the wall top: \
                     dips too steep for the course heights"
                ),
            ));
        }
        top_segments(&poly, new_top);
        // Wedge tops beyond the stone's x-range (where the cap cut the stone short) are
        // exposed: the next course rests on them too.
        let (sx0, sx1) =
            poly.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
        for t in &wedge_tops {
            new_top.extend(t.clip(f64::NEG_INFINITY, sx0));
            new_top.extend(t.clip(sx1, f64::INFINITY));
        }
        pieces.push(Piece2 { kind: PieceKind::Stone, course: k, polygon: poly, dip_deg });
        Ok(())
    }

    /// The stone's bed line: the table for course 0; flat on the highest point under it for
    /// the top course (the copes); else the line of least area above the course below, its
    /// slope limited by the steepest dip and by a rise over half the stone of at most half
    /// the course height (so a capped stone keeps half its course height).
    fn bed(&self, p: Place, lower: &[Seg]) -> Result<Line, GeneratorError> {
        let (k, i, a, b) = (p.k, p.i, p.a, p.b);
        let n = self.tops.len();
        let mid = 0.5 * (a + b);
        let under: Vec<Seg> = lower.iter().filter_map(|s| s.clip(a, b)).collect();
        let max_bed_slope = self.tan_max.min(0.5 * self.nominal(k) / (0.5 * (b - a)));
        let nothing_under =
            || infeasible(self.wall, "head_joints", format!("course {k}, block {i}: nothing underneath to rest on"));
        if k == 0 {
            Ok(Line { xm: mid, zm: 0.0, m: 0.0 })
        } else if k + 1 == n {
            let zmax = under.iter().map(|s| s.z0.max(s.z1)).fold(f64::NEG_INFINITY, f64::max);
            if !zmax.is_finite() {
                return Err(nothing_under());
            }
            Ok(Line { xm: mid, zm: zmax, m: 0.0 })
        } else {
            least_line_above(&under, a, b, max_bed_slope).ok_or_else(nothing_under)
        }
    }

    /// The wedges in the gaps between the stone's bed line `bottom` and the course below:
    /// * under the same ceiling as the stone (where a steep bed rises above the cap the
    ///   stone is cut short, and a wedge there must not reach above it either);
    /// * over the stone's whole slot, out to the middle of its open head joints (and to the
    ///   wall's ends), so that an open joint reaches down only to its neighbours' bed level
    ///   and leaves the stated void (an unfilled column under it would add up to the stated
    ///   void again under steep beds). With closed head joints the slot is the stone itself.
    ///
    /// Their top edges go to `wedge_tops`.
    fn wedges<R: Rng + ?Sized>(
        &self,
        p: Place,
        bottom: Line,
        lower: &[Seg],
        rng: &mut R,
        pieces: &mut Vec<Piece2>,
        wedge_tops: &mut Vec<Seg>,
    ) {
        let (t_w, l_w) = (self.t_w, self.l_w);
        let wedge_len = self.irregular.and_then(|ir| ir.wedge_length.as_ref());
        let fill = self.irregular.map_or(1.0, |ir| ir.wedge_fill);
        let slot_under: Vec<Seg> = lower.iter().filter_map(|s| s.clip(p.slot.0, p.slot.1)).collect();
        for s in &slot_under {
            let (gl, gr) = (bottom.at(s.x0) - s.z0, bottom.at(s.x1) - s.z1);
            if gl.max(gr) < t_w || s.x1 - s.x0 < l_w {
                continue;
            }
            // Wedge frequency: a draw only when some gaps stay empty.
            if fill < 1.0 && rand::distr::Uniform::new(0.0, 1.0).expect("valid").sample(rng) >= fill {
                continue;
            }
            // Cut points along x (wedge length law), else one wedge.
            let mut cuts = vec![s.x0];
            if let Some(wl) = wedge_len {
                let mut x = s.x0;
                loop {
                    let w = wl.sample(rng).max(l_w);
                    if x + w >= s.x1 - l_w {
                        break;
                    }
                    x += w;
                    cuts.push(x);
                }
            }
            cuts.push(s.x1);
            for c in cuts.windows(2) {
                if let Some(poly) = self.wedge(p, bottom, s, c[0], c[1]) {
                    top_segments(&poly, wedge_tops);
                    pieces.push(Piece2 { kind: PieceKind::Wedge, course: p.k, polygon: poly, dip_deg: None });
                }
            }
        }
    }

    /// The wedge between the piece `s` of the surface below and the bed line `bottom` over
    /// [c0, c1], if it is thick enough and has an area.
    fn wedge(&self, p: Place, bottom: Line, s: &Seg, c0: f64, c1: f64) -> Option<Vec<P2>> {
        let h = self.wall.height;
        let (z0, z1) = (s.at(c0), s.at(c1));
        let (g0, g1) = (bottom.at(c0) - z0, bottom.at(c1) - z1);
        if g0.max(g1) < self.t_w {
            return None;
        }
        let under_line = Line { xm: s.x0, zm: s.z0, m: (s.z1 - s.z0) / (s.x1 - s.x0) };
        let mut planes =
            vec![HalfPlane::Above(under_line), HalfPlane::Below(bottom), HalfPlane::z_min(0.0), HalfPlane::z_max(h)];
        if let Some(c) = p.cap {
            planes.push(HalfPlane::z_max(c));
        }
        let poly = region(c0, c1, -h, 2.0 * h, &planes, self.snap);
        (poly.len() >= 3 && area(&poly) > 1e-6 * self.hbar * self.lbar).then_some(poly)
    }

    /// The stone's top line and its dip (degrees): flat at H for the top course; else
    /// through (mid-point, Z_{k+1}) at the drawn dip, raised (never re-tilted) until the
    /// stone is at least `min_thickness_fraction × h_k` thick at both ends.
    fn stone_top<R: Rng + ?Sized>(
        &self,
        p: Place,
        bottom: Line,
        rng: &mut R,
        samples: &mut Samples,
    ) -> (Line, Option<f64>) {
        let (k, a, b) = (p.k, p.a, p.b);
        let mid = 0.5 * (a + b);
        if k + 1 == self.tops.len() {
            return (Line { xm: mid, zm: self.wall.height, m: 0.0 }, None);
        }
        let dip = match self.irregular {
            Some(ir) => ir.dip.sample(rng),
            None => 0.0,
        };
        samples.dips_deg.push(dip);
        let h_min = self.wall.min_thickness_fraction * self.nominal(k);
        let mut t = Line { xm: mid, zm: self.tops[k], m: crate::units::deg_to_rad(dip).tan() };
        let short = (h_min - (t.at(a) - bottom.at(a))).max(h_min - (t.at(b) - bottom.at(b)));
        if short > 0.0 {
            t.zm += short;
        }
        (t, Some(dip))
    }
}

/// The open width of each interior head joint of a course of `m` blocks, and how much a
/// single block is shortened at each end instead (`void_fraction` on a one-block course), m.
fn open_joints(gap: HeadGap, l: f64, m: usize) -> (f64, f64) {
    let width = match gap {
        HeadGap::Closed => 0.0,
        HeadGap::Width(w) => w,
        HeadGap::VoidFraction(f) => {
            if m > 1 {
                f * l / (m - 1) as f64
            } else {
                0.0
            }
        }
    };
    let single_shrink = match gap {
        HeadGap::VoidFraction(f) if m == 1 => 0.5 * f * l,
        _ => 0.0,
    };
    (width, single_shrink)
}
