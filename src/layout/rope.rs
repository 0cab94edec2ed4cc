//! The rope restraint of a layout: a tension-only flexible member with a pretension that
//! bears on the downhill (+y) face of the wall in one section over a height band
//! (`restraints.ropes`), as the tensioned ropes at the ends of the source paper's SBR
//! specimens (Santa-Cruz et al. 2021, §2.1: "a rope manually tensioned at the specimen
//! ends", 1.4 m apart on the 1.5 m wall).
//!
//! ```json
//! "restraints": {"base_sliding": "held", "ends": [],
//!   "ropes": [{"x_m": 0.05, "band_m": [0.0, 0.375], "pretension_n": 300,
//!              "axial_stiffness_n": 6e4, "span_m": 0.1, "wrap_depth_m": 0.0}]}
//! ```
//!
//! The law the DEM applies ([`crate::dem::rope`], docs/rope.md): the rope is a taut string
//! across the face in the section `x = x_m`, its two legs of free length `span_m` (s) each
//! running to anchors fixed to the table; it lies on the face as built over the band and is
//! pushed out by the blocks it bears on. Its single tension is
//! `T = max(0, T₀ + EA (ℓ − ℓ_ref) / ℓ_ref)` with `ℓ = 2 √(s² + δ̄²)`, `ℓ_ref = 2 √(s² + d²)`
//! (`d` the wrap depth, the rope's deflection by the face as built), and its force on the
//! wall is `F = 2 T δ̄ / √(s² + δ̄²)` towards −y, shared by the blocks it bears on.

use super::{invalid, Block, LayoutError};
use serde::{Deserialize, Serialize};

/// Range of a rope's pretension T₀, N (0 to a winch's pull).
pub const ROPE_PRETENSION_RANGE_N: (f64, f64) = (0.0, 1e6);

/// Range of a rope's axial stiffness EA, N (a thread to a steel cable).
pub const ROPE_AXIAL_STIFFNESS_RANGE_N: (f64, f64) = (1.0, 1e10);

/// A rope restraint as written in the layout file (`restraints.ropes[k]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RopeSpec {
    /// x of the section the rope crosses (table frame), m. Every free block whose extent in
    /// x contains it and whose height overlaps the band bears on the rope.
    pub x_m: f64,
    /// The height band the rope bears on, `[z_lo, z_hi]` above the table, m (0 ≤ z_lo < z_hi).
    pub band_m: [f64; 2],
    /// Pretension T₀ with the wall as built, N, in [`ROPE_PRETENSION_RANGE_N`].
    pub pretension_n: f64,
    /// Axial stiffness EA of the rope, N, in [`ROPE_AXIAL_STIFFNESS_RANGE_N`]: the tension
    /// rises by EA times the rope's strain.
    pub axial_stiffness_n: f64,
    /// Free length s of each of the rope's two legs, from the face to its anchor, m (> 0).
    pub span_m: f64,
    /// Wrap depth d, m (≥ 0, < span): how far the face as built pushes the rope out of the
    /// straight line between its anchors. Default 0: the rope just touches the face and
    /// presses it only once the wall moves into it.
    #[serde(default)]
    pub wrap_depth_m: f64,
}

/// A checked rope restraint, SI values (see [`RopeSpec`] for each field's meaning).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rope {
    /// x of the section, m.
    pub x: f64,
    /// Bottom of the band, m above the table.
    pub z_lo: f64,
    /// Top of the band, m above the table.
    pub z_hi: f64,
    /// Pretension T₀, N.
    pub pretension: f64,
    /// Axial stiffness EA, N.
    pub axial_stiffness: f64,
    /// Free length s of each leg, m.
    pub span: f64,
    /// Wrap depth d, m.
    pub wrap_depth: f64,
}

impl Rope {
    /// The height (m) of the band `block` covers (0 if it does not bear on the rope: it
    /// does not reach the section in x or the band in z). The block's geometry as built,
    /// table frame.
    pub fn bearing_height(&self, block: &Block) -> f64 {
        let bb = block.shape.aabb();
        if !(bb.min.x <= self.x && self.x <= bb.max.x) {
            return 0.0;
        }
        (bb.max.z.min(self.z_hi) - bb.min.z.max(self.z_lo)).max(0.0)
    }
}

/// The shortest leg a rope may have, m (`span_m`): the solvers' default contact margin.
pub const MIN_ROPE_SPAN_M: f64 = 1e-3;

/// Checks that no rope pushes the wall over as built: a rope with a wrap depth d presses
/// the face with `F₀ = 2 T₀ d / √(s² + d²)` (N, towards −y) at the middle `z_c` of its
/// band within the wall's height; a wall of weight `W` (its free blocks, N) on a level
/// table resists that push about its uphill toe with a moment of at most `W B` (`B` the
/// free blocks' extent in y, m), so `F₀ z_c > W B` topples it before any load.
///
/// # Errors
/// [`LayoutError::Invalid`] naming `restraints.ropes[k].wrap_depth_m`, with the push and
/// the wall's resisting moment.
pub fn check_as_built(ropes: &[Rope], blocks: &[Block], densities: &[f64], gravity: f64) -> Result<(), LayoutError> {
    let free: Vec<&Block> = blocks.iter().filter(|b| !b.fixed).collect();
    let weight: f64 = free.iter().map(|b| b.mass_properties(densities[b.material]).mass * gravity).sum();
    let (mut y0, mut y1, mut z0, mut z1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for b in &free {
        let bb = b.shape.aabb();
        (y0, y1, z0, z1) = (y0.min(bb.min.y), y1.max(bb.max.y), z0.min(bb.min.z), z1.max(bb.max.z));
    }
    for (k, r) in ropes.iter().enumerate() {
        let push = 2.0 * r.pretension * r.wrap_depth / (r.span * r.span + r.wrap_depth * r.wrap_depth).sqrt();
        let zc = 0.5 * (r.z_lo.max(z0) + r.z_hi.min(z1));
        if push * zc > weight * (y1 - y0) {
            return Err(invalid(
                format!("restraints.ropes[{k}].wrap_depth_m"),
                r.wrap_depth,
                &format!(
                    "with pretension_n = {} the rope pushes the wall as built with 2 T₀ d / √(s² + d²) = {push:.4e} N \
                     at {zc:.3} m, a moment of {:.4e} N·m against the {:.4e} N·m its weight ({weight:.4e} N) over \
                     its width ({:.3} m) can resist: it topples before any load (reduce the wrap depth or the pretension)",
                    r.pretension,
                    push * zc,
                    weight * (y1 - y0),
                    y1 - y0
                ),
            ));
        }
    }
    Ok(())
}

impl RopeSpec {
    /// Checks the values against `blocks` (the rope must bear on at least one free block).
    ///
    /// # Errors
    /// [`LayoutError::Invalid`] naming `restraints.ropes[k].KEY`.
    pub fn resolve(&self, k: usize, blocks: &[Block]) -> Result<Rope, LayoutError> {
        let key = |f: &str| format!("restraints.ropes[{k}].{f}");
        let in_range = |f: &str, v: f64, (lo, hi): (f64, f64)| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(v)
            } else {
                Err(invalid(key(f), v, &format!("must be in [{lo:e}, {hi:e}]")))
            }
        };
        if !self.x_m.is_finite() {
            return Err(invalid(key("x_m"), self.x_m, "must be finite"));
        }
        let [z_lo, z_hi] = self.band_m;
        if !(z_lo.is_finite() && z_hi.is_finite() && 0.0 <= z_lo && z_lo < z_hi) {
            return Err(invalid(
                key("band_m"),
                format!("[{z_lo}, {z_hi}]"),
                "needs 0 <= z_lo < z_hi, m above the table",
            ));
        }
        let pretension = in_range("pretension_n", self.pretension_n, ROPE_PRETENSION_RANGE_N)?;
        let axial_stiffness = in_range("axial_stiffness_n", self.axial_stiffness_n, ROPE_AXIAL_STIFFNESS_RANGE_N)?;
        if !(self.span_m.is_finite() && self.span_m >= MIN_ROPE_SPAN_M) {
            let v = self.span_m;
            let shown = if v == 0.0 || (1e-4..1e6).contains(&v.abs()) { v.to_string() } else { format!("{v:e}") };
            return Err(invalid(
                key("span_m"),
                shown,
                &format!(
                    "must be a finite number of at least {MIN_ROPE_SPAN_M} m (a leg shorter than the solvers' \
                     contact margin stretches without bound under a deflection the contacts allow)"
                ),
            ));
        }
        let d = self.wrap_depth_m;
        if !(d.is_finite() && 0.0 <= d && d < self.span_m) {
            return Err(invalid(key("wrap_depth_m"), d, "needs 0 <= wrap depth < span_m"));
        }
        let rope = Rope { x: self.x_m, z_lo, z_hi, pretension, axial_stiffness, span: self.span_m, wrap_depth: d };
        if !blocks.iter().any(|b| !b.fixed && rope.bearing_height(b) > 0.0) {
            return Err(invalid(
                key("x_m"),
                self.x_m,
                "the rope bears on no free block: no free block reaches this section within the band",
            ));
        }
        Ok(rope)
    }
}
