//! The seeded wall generator: from a wall description and a seed, a layout of convex blocks
//! that the DEM loads.
//!
//! ```text
//!  walls/NAME.toml ─▶ WallSpec ─resolve─▶ Wall ─┐
//!  distributions/*.toml (named laws) ───────────┘
//!  (master seed, realization i) ─ rng_for(seed, i, Layout) ─▶ generate ─▶ GeneratedWall
//!                                                                         ├─ layout (JSON, `drystone tilt`)
//!                                                                         ├─ VTK (ParaView)  [`crate::io::render`]
//!                                                                         └─ SVG drawing     [`crate::io::render`]
//! ```
//!
//! The module in the order of the pipeline: [`spec`] (the file as written, serde types),
//! `resolve` (every value checked, defaults filled in) into `wall` (the checked [`Wall`]),
//! [`distribution`] (the named random laws), `build` (the construction in the elevation
//! plane, below) and `realization` (extrusion, ids, materials, the layout: [`generate`]).
//!
//! # Frame and units
//!
//! The table frame of [`crate::geometry`]: x along the wall (0 ≤ x ≤ L), y out of plane (+y
//! is the side the wall falls to), z up (the table is z = 0, the wall top z = H). Everything
//! inside is SI (m); dips are degrees in files and in [`Samples`], converted once with
//! [`crate::units::deg_to_rad`].
//!
//! # The section and the blocks
//!
//! The cross-section (y–z) is a trapezoid: width B at z = 0 and b at z = H, faces at
//! [`Wall::faces_at`] (symmetric batter by default, or one vertical face). In a single-leaf
//! section (the default; see [Double-faced sections](#double-faced-sections)) every block
//! is a *through stone*: it spans the whole thickness, so it is a convex polygon P of the
//! elevation plane (x–z) extruded in y between the two faces. Its vertices are, for every
//! vertex (x, z) of P, the points (x, y₋(z), z) and (x, y₊(z), z). The faces are planes and
//! y₋, y₊ are affine in z, so the block is convex whenever P is, lies inside the envelope
//! whenever P lies in [0, L] × [0, H], and two blocks overlap exactly when their polygons do.
//! Its volume is `area(P) × width(z̄)` with z̄ the centroid height of P (the width is affine
//! in z). The construction is therefore a tiling of the elevation rectangle by convex
//! polygons.
//!
//! # Double-faced sections
//!
//! `[section] leaves = 2` cuts every elevation piece across the thickness by planes
//! parallel to the faces ([`SectionPart`]): a −y leaf between y₋(z) and y₋(z) + w, the
//! hearting between y₋(z) + w and y₊(z) − w (cut along x into equal pieces no longer than
//! `hearting_stone_m`), a +y leaf between y₊(z) − w and y₊(z), w = `leaf_width_m`
//! (measured horizontally; each leaf follows its own face's batter); without `leaf_width_m`
//! the two leaves meet at the centre line (y₋ + y₊)/2. Every one of these surfaces is
//! affine in z, so each part is still the polygon (or a vertical slice of it) extruded
//! between two planes: convex, inside the envelope, and touching its neighbours along
//! shared planes only; its volume is `area × its width at the centroid height`. Stones
//! holding the points `(j + ½) s` (s = `through_stone_spacing_m`, shifted by s/2 from one
//! course with through stones to the next) of every `through_stone_every_courses`-th course
//! from the base stay whole (through stones); wedges are always cut. The section draws
//! nothing: the elevation is that of the single-leaf wall, bit for bit.
//!
//! # Construction, course by course (bottom up)
//!
//! 1. **Course heights.** A fixed height h gives n = max(1, round(H/h)) equal courses of
//!    H/n. A random law is drawn course by course while the sum stays ≤ H − h̄/2 (h̄ the
//!    law's mean); what is left (between h̄/2 and h̄/2 + one draw) is split into
//!    max(1, round(rest/h̄)) equal top courses. The nominal course tops are Z₁ … Zₙ = H.
//! 2. **Head joints.** `continuous`: at multiples of the block length l from x = 0 in every
//!    course. `discontinuous` (running bond): the same, shifted by `overlap × l` in every
//!    odd course (default half a block). `irregular`: the first block of a course is a
//!    random fraction in [½, 1) of a drawn length (so courses do not all start with a joint
//!    at the same place); then drawn lengths while they fit; the last block takes the rest
//!    (split in two if longer than the law's largest value). No end piece is shorter than
//!    `min_end_fraction × l̄`: continuous and running-bond walls merge a shorter cut piece
//!    into its neighbour; irregular walls make the first block at least that long and stop
//!    drawing lengths so that the last one is too.
//! 3. **Open head joints (micro-gaps).** `micro_gap_m = w` opens every interior head joint
//!    by w; `void_fraction = f` opens each course's interior head joints by
//!    `f L / (number of interior head joints)` (a course of one block is shortened at both
//!    ends instead), which leaves exactly the fraction f of each horizontal course open.
//! 4. **Stone bed (bottom).** Course 0 stands on the table (z = 0). A stone of a higher
//!    course over [a, b] gets a straight bed: the line of least area above the top surface
//!    of the course below over [a, b] (the edge of that surface's upper convex hull above
//!    the stone's mid-point). It rests on the two highest points under it. Its slope is at
//!    most that of the steepest dip the law can draw, and its rise over half the stone at
//!    most half the course height (a steeper hull edge is replaced by the supporting line
//!    of the limiting slope). The top course (the copes) lies flat on the highest point
//!    under it.
//! 5. **Stone top.** The top course is cut flat at z = H. Any other stone's top is a
//!    straight *bed-joint segment* through (mid-point, Z_{k+1}) tilted by a **dip** θ drawn
//!    from the dip law (z rises with x for θ > 0; continuous and discontinuous walls have
//!    θ = 0). The dip acts in the elevation plane (x–z) only. If the stone would be thinner
//!    than `min_thickness_fraction × h_k` at one end, the segment is raised (never
//!    re-tilted) until it is not. Every course's tops are capped at its *ceiling*
//!    Z_{k+1} + ½ l_max tan θ_max (l_max the longest block of the course, θ_max the
//!    steepest dip of the law): an unraised segment never reaches it, so the cap only trims
//!    raised stones and no raise propagates up the wall. Below the top course the ceiling
//!    is also at most `H − min_thickness_fraction × h_top`, so the copes keep their
//!    thickness. A capped top is min(segment, ceiling): still concave, the stone convex.
//!    A stone left with (almost) no area between its bed and its top makes the realization
//!    fail with [`GeneratorError::Infeasible`] (dips far too steep for the course heights);
//!    the property tests never meet it for dips up to 25° and blocks up to 4 course heights
//!    long.
//! 6. **Wedge stones.** Between a stone's straight bed and the tilted, stepped top surface
//!    under it there are gaps, one per piece of that surface: the region between a straight
//!    piece below and the bed line above, cut by vertical lines at the head joints. Where
//!    the head joints are open (step 3) the stone's slot reaches to the middle of each open
//!    joint (and to the wall's end), and its bed line is extended over it: the wedges fill
//!    under the open joint too, which then leaves only its own width open. Each gap is
//!    convex (between two lines, within an x-interval) and becomes a **wedge** (a small
//!    through prism, triangular or quadrilateral in elevation) of the wedge material,
//!    listed with the course it supports. Gaps thinner than `min_wedge_thickness_m` or
//!    shorter than `min_wedge_length_m` stay open; a gap longer than a drawn
//!    `wedge_length_m` is cut into several wedges; with `wedge_fill = p` (wedge frequency)
//!    a gap gets its wedges with probability p only. A wedge is also dropped (its gap left
//!    open) if the convex hull built from its vertices, as the DEM builds it, does not have
//!    its volume: quickhull can fail on a thin sliver. Continuous and discontinuous walls
//!    have no gaps and so no wedges.
//! 7. Every polygon is clipped to 0 ≤ z ≤ H (half-planes keep it convex).
//!
//! So every block is convex, inside the envelope and the base course sits on the table by
//! construction; blocks touch along shared lines but never overlap (the tests check all
//! three with the DEM's own narrow phase). The volume is the envelope volume × (1 − stated
//! void fraction) up to the thin gaps left open (well under 1 %).
//!
//! # Defaults (all documented on the fields of [`spec`])
//!
//! | key | default |
//! | --- | --- |
//! | `geometry.batter` | `symmetric` |
//! | `arrangement.overlap` (discontinuous) | 0.5 |
//! | `arrangement.dip_deg` (irregular) | uniform on [−20°, 20°] |
//! | `arrangement.min_wedge_thickness_m` | 0.01 × mean course height |
//! | `arrangement.min_wedge_length_m` | 0.05 × mean block length |
//! | `arrangement.wedge_length_m` | none (one wedge per gap) |
//! | `arrangement.wedge_fill` | 1 (every gap thick and long enough gets its wedge) |
//! | `courses.min_thickness_fraction` | 0.4 |
//! | `blocks.min_end_fraction` | 0.25 |
//! | `blocks.material` / `wedge_material` / `restraints.table_material` | first material / block material / block material |
//! | `head_joints` | closed |
//! | `section.leaves` | 1 (through stones) |
//! | `section.leaf_width_m` / `hearting_stone_m` / `through_stone_spacing_m` / `through_stone_every_courses` | leaves meet at the centre line / one hearting piece per stone / no through stones / 1 |
//! | `restraints.base` / `restraints.ends.kind` | `free` / `free` |
//! | `gravity_m_per_s2` | 9.81 |
//!
//! # The wall file
//!
//! ```toml
//! version = 1
//! name = "full-scale wall, irregular joints"
//!
//! [geometry]                  # metres
//! length_m = 4.0
//! height_m = 1.0
//! base_width_m = 0.45
//! top_width_m = 0.25
//! batter = "symmetric"        # or "vertical_negative_y", "vertical_positive_y"
//!
//! [arrangement]
//! kind = "irregular"          # "continuous", "discontinuous" (+ overlap = 0.5), "irregular"
//! dip_deg = "dip_uniform_20"  # a number (fixed) or a distribution name (unit deg)
//!
//! [courses]
//! height_m = "course_height_full_scale"   # number or distribution (unit m)
//!
//! [blocks]
//! length_m = "block_length_full_scale"    # number or distribution (unit m)
//! material = "stone"
//!
//! [head_joints]               # optional; at most one of the two
//! void_fraction = 0.0         # or micro_gap_m = 0.0005
//!
//! [[materials]]               # the layout file's material fields
//! name = "stone"
//! density_kg_per_m3 = 2400
//! kn_pa_per_m = 1.0e8
//! ks_pa_per_m = 5.0e7
//! friction_deg = 30
//! cohesion_pa = 1.0e5
//!
//! [section]                   # optional; default one leaf of through stones
//! leaves = 2                  # 1 or 2 (double-faced)
//! leaf_width_m = 0.10         # each leaf from its face; the hearting between (2w < b)
//! hearting_stone_m = 0.25     # hearting pieces at most this long along x
//! through_stone_spacing_m = 1.0   # through stones 1 m apart along a course
//! through_stone_every_courses = 2 # in every other course from the base
//!
//! [restraints]
//! base = "free"               # or "held"
//! ends = { kind = "rigid", zone_m = 0.05 }   # "free"; "spring" + stiffness_n_per_m
//!
//! [scatter]                   # optional: what differs between nominally equal walls
//! kn_factor = "kn_factor_lognormal_cv20"   # per-block Kn, Ks factor (Material stream)
//! friction_offset_deg = "friction_offset_truncated_normal_2"   # per-block φ offset (Material stream)
//! bed_seating_gap_m = "bed_seating_gap_sawn_granite"   # per-block bed seating g₀ (Seating stream)
//!
//! [distributions.my_dip]      # optional inline distributions, same keys as the files
//! unit = "deg"
//! kind = "truncated_normal"
//! mean = 0.0
//! std = 8.0
//! min = -20.0
//! max = 20.0
//! ```
//!
//! Named distributions are looked up inline first, then in `distributions/NAME.toml` (see
//! [`distribution`]); `drystone generate --distributions DIR` overrides the directory.
//!
//! # Seeds and determinism
//!
//! All geometry draws come, in a fixed order (course heights; then per course: block
//! lengths, wedge lengths and dips, left to right), from one `ChaCha8Rng`:
//! [`crate::rng::rng_for`]`(seed, realization, Purpose::Layout)`; material scatter draws
//! from the `Material` stream of the same realization (a Kn factor, then a friction offset,
//! per block in layout order), and the beds' seating from its `Seating` stream (one g₀ per
//! block in layout order), so that a key added to `[scatter]` moves no other draw and a
//! wall without it gives the layout it always gave. Realization i is therefore the same
//! bit for bit whether generated alone or in a batch ([`generate_batch`] runs on rayon
//! threads and returns the same values), and nothing iterates a hash map.
//!
//! # Block ids
//!
//! Stones `c{k}s{i}` (course k from 0 at the base, i from 0 at x = 0); wedges `c{k}w{j}`
//! (the wedges under course k). In a double-faced section a cut piece's parts add `n` (−y
//! leaf), `h0`, `h1`, … (hearting, left to right) and `p` (+y leaf) to its id. Layout order: course by course, each course's wedges before
//! its stones.

pub mod distribution;
pub mod spec;

mod build;
mod generate;
mod polygon;
mod realization;
mod resolve;
mod trace;
pub mod trace_draw;
pub mod traced;
mod wall;

pub use build::{PieceKind, Samples};
pub use distribution::{Distribution, DistributionSource, DistributionSpec};
pub use generate::{generate, generate_batch};
pub(crate) use polygon::area as polygon_area;
pub(crate) use realization::{centroid_z, extrude_polygon, hull_is_faithful};
pub use realization::{GeneratedWall, Piece, SectionPart};
pub use spec::{WallKind, WallSpec};
pub use traced::{TraceSetting, Traced, TracedStone};
pub(crate) use wall::faces_at;
pub use wall::{Arrangement, Ends, HeadGap, Irregular, Scatter, Section, Wall};

/// The wall of a test: the description `text` (TOML) with one material `m` (2000 kg/m³,
/// Kn 1e8 Pa/m, Ks 5e7 Pa/m, φ 30°) appended, resolved with the built-in distributions.
///
/// # Panics
/// A description that does not resolve.
#[cfg(test)]
pub(crate) fn test_wall(text: &str) -> Wall {
    let text = format!(
        "{text}[[materials]]\nname = \"m\"\ndensity_kg_per_m3 = 2000\nkn_pa_per_m = 1e8\nks_pa_per_m = 5e7\nfriction_deg = 30\n"
    );
    let p = std::path::Path::new("t.toml");
    WallSpec::from_toml(&text, p).unwrap().resolve(p, &DistributionSource::default()).unwrap()
}

use crate::layout::LayoutError;
use std::path::PathBuf;
use thiserror::Error;

/// Generator errors. Every variant names the file at fault and, for a value, the key.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum GeneratorError {
    /// A file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not valid TOML for the format (syntax, unknown key, wrong type, missing key).
    #[error("{}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// toml's message, with the key, line and column.
        message: String,
    },
    /// A value out of range.
    #[error("{}: {key} = {value}: {reason}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The key, e.g. `geometry.top_width_m`.
        key: String,
        /// The value as given.
        value: String,
        /// What is wrong.
        reason: String,
    },
    /// A distribution name that is neither inline nor a file.
    #[error(
        "{}: {key} = {name:?}: unknown distribution (searched inline and {}; available: {})",
        path.display(),
        if searched.is_empty() { "no distributions directory".to_string() } else { searched.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ") },
        if available.is_empty() { "none".to_string() } else { available.join(", ") }
    )]
    UnknownDistribution {
        /// The wall file.
        path: PathBuf,
        /// The key that names it.
        key: String,
        /// The name.
        name: String,
        /// Directories searched.
        searched: Vec<PathBuf>,
        /// Names that exist.
        available: Vec<String>,
    },
    /// The description is valid but this realization cannot be built (e.g. dips far too
    /// steep for the course heights).
    #[error("{}: {reason} (check {key})", path.display())]
    Infeasible {
        /// The wall file.
        path: PathBuf,
        /// The key most likely at fault.
        key: String,
        /// What happened.
        reason: String,
    },
    /// The generated layout failed the layout checks (a generator bug).
    #[error("generated layout is invalid (a generator bug, please report): {0}")]
    Layout(#[from] LayoutError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn wall(text: &str) -> Wall {
        let p = Path::new("inline.toml");
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("distributions");
        WallSpec::from_toml(text, p).unwrap().resolve(p, &DistributionSource::dir(dir)).unwrap()
    }

    const BASE: &str = r#"
version = 1
name = "t"
[geometry]
length_m = 1.5
height_m = 0.375
base_width_m = 0.15
top_width_m = 0.077
[courses]
height_m = 0.04
[blocks]
length_m = 0.2
[[materials]]
name = "c"
density_kg_per_m3 = 2128
kn_pa_per_m = 1.75e8
ks_pa_per_m = 0.86e8
friction_deg = 32
"#;

    #[test]
    fn running_bond_has_the_paper_layout() {
        let w = wall(&format!("{BASE}\n[arrangement]\nkind = \"discontinuous\"\n"));
        let g = generate(&w, 1, 0).unwrap();
        // 9 courses of 41.67 mm; even courses 7 blocks + a half, odd ones a half + 7 blocks.
        assert_eq!(g.course_tops_m.len(), 9);
        assert_eq!(g.counts(), (9 * 8, 0));
        let c1: Vec<&Piece> = g.pieces.iter().filter(|p| p.course == 1).collect();
        assert!((c1[0].polygon[1][0] - 0.1).abs() < 1e-12);
        assert!((g.volume() - w.envelope_volume()).abs() < 1e-12 * w.envelope_volume());
        g.layout.resolve().unwrap();
    }

    #[test]
    fn the_documented_wall_file_resolves_and_generates() {
        let src = include_str!("mod.rs");
        let start = src.find("//! ```toml\n//! version = 1").expect("example in the module doc");
        let body: String = src[start..]
            .lines()
            .skip(1)
            .take_while(|l| !l.starts_with("//! ```"))
            .map(|l| l.strip_prefix("//! ").or(l.strip_prefix("//!")).unwrap_or(l))
            .collect::<Vec<_>>()
            .join("\n");
        let w = wall(&body);
        let g = generate(&w, 1, 0).unwrap();
        assert!(g.counts().1 > 0);
        assert!(g.pieces.iter().all(|p| p.material.starts_with("stone~")));
        g.check().unwrap();
    }
}
