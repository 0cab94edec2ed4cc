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
//! [`Wall::faces_at`] (symmetric batter by default, or one vertical face). Every block is a
//! *through stone*: it spans the whole thickness, so it is a convex polygon P of the
//! elevation plane (x–z) extruded in y between the two faces. Its vertices are, for every
//! vertex (x, z) of P, the points (x, y₋(z), z) and (x, y₊(z), z). The faces are planes and
//! y₋, y₊ are affine in z, so the block is convex whenever P is, lies inside the envelope
//! whenever P lies in [0, L] × [0, H], and two blocks overlap exactly when their polygons do.
//! Its volume is `area(P) × width(z̄)` with z̄ the centroid height of P (the width is affine
//! in z). The construction is therefore a tiling of the elevation rectangle by convex
//! polygons.
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
//! [restraints]
//! base = "free"               # or "held"
//! ends = { kind = "rigid", zone_m = 0.05 }   # "free"; "spring" + stiffness_n_per_m
//!
//! [scatter]                   # optional: per-block material scatter (Material stream)
//! kn_factor = "kn_factor_lognormal_cv20"
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
//! from the `Material` stream of the same realization. Realization i is therefore the same
//! bit for bit whether generated alone or in a batch ([`generate_batch`] runs on rayon
//! threads and returns the same values), and nothing iterates a hash map.
//!
//! # Block ids
//!
//! Stones `c{k}s{i}` (course k from 0 at the base, i from 0 at x = 0); wedges `c{k}w{j}`
//! (the wedges under course k). Layout order: course by course, each course's wedges before
//! its stones.

pub mod distribution;
pub mod ks;
pub mod spec;

mod build;

pub use distribution::{Distribution, DistributionSource, DistributionSpec};
pub use spec::{Wall, WallSpec};

use crate::layout::{
    BlockSpec, EndRestraintKind, EndRestraintSpec, LayoutError, LayoutSpec, MaterialSpec, RestraintSpec, TableSpec,
};
use crate::rng::{rng_for, Purpose};
use serde::Serialize;
use spec::Ends;
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

/// Stone or wedge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PieceKind {
    /// A block of a course.
    Stone,
    /// A wedge stone filling a gap under a stone.
    Wedge,
}

/// One generated block.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Piece {
    /// Block id in the layout.
    pub id: String,
    /// Stone or wedge.
    pub kind: PieceKind,
    /// Course index (0 at the base); a wedge belongs to the course it supports.
    pub course: usize,
    /// Elevation polygon (x, z), counter-clockwise, m.
    pub polygon: Vec<[f64; 2]>,
    /// Block vertices in the table frame, m (two per polygon vertex: −y face, +y face).
    pub vertices: Vec<[f64; 3]>,
    /// Volume, m³.
    pub volume: f64,
    /// Drawn dip of the stone's top segment, degrees (stones below the top course).
    pub dip_deg: Option<f64>,
    /// Material name in the layout.
    pub material: String,
    /// Held by an end restraint.
    pub restrained: bool,
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

/// One generated realization.
#[derive(Debug, Clone)]
pub struct GeneratedWall {
    /// Master seed.
    pub seed: u64,
    /// Realization index.
    pub realization: u64,
    /// The blocks, in layout order.
    pub pieces: Vec<Piece>,
    /// Nominal course tops Z₁ … Zₙ = H, m.
    pub course_tops_m: Vec<f64>,
    /// Drawn values.
    pub samples: Samples,
    /// The layout (the `drystone tilt` format).
    pub layout: LayoutSpec,
    /// L, H, B, b, m.
    pub dimensions: [f64; 4],
    /// Envelope volume L (B + b) H / 2, m³.
    pub envelope_volume_m3: f64,
    /// The description's stated void fraction.
    pub stated_void_fraction: f64,
}

impl GeneratedWall {
    /// Total block volume, m³.
    pub fn volume(&self) -> f64 {
        self.pieces.iter().map(|p| p.volume).sum()
    }

    /// Void fraction realized: 1 − volume / envelope volume (values within 1e-12 of 0,
    /// rounding in a closed wall, are reported as 0).
    pub fn void_fraction(&self) -> f64 {
        let f = 1.0 - self.volume() / self.envelope_volume_m3;
        if f.abs() < 1e-12 {
            0.0
        } else {
            f
        }
    }

    /// Number of stones and of wedges.
    pub fn counts(&self) -> (usize, usize) {
        let w = self.pieces.iter().filter(|p| p.kind == PieceKind::Wedge).count();
        (self.pieces.len() - w, w)
    }
}

/// Output formats of `drystone generate`, chosen by the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.json`: the layout file that `drystone tilt` reads.
    Json,
    /// `.vtk`: legacy VTK polydata for ParaView ([`crate::io::render`]).
    Vtk,
    /// `.svg`: front elevation and cross-section ([`crate::io::render`]).
    Svg,
}

impl OutputFormat {
    /// The format of a file name by its extension (case-insensitive), if known.
    pub fn from_path(path: &std::path::Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "json" => Some(OutputFormat::Json),
            "vtk" => Some(OutputFormat::Vtk),
            "svg" => Some(OutputFormat::Svg),
            _ => None,
        }
    }
}

impl GeneratedWall {
    /// Checks the layout as `drystone tilt` would (convex blocks, no overlap beyond
    /// [`crate::layout::OVERLAP_TOLERANCE_M`], by the DEM's narrow phase) and returns it.
    ///
    /// # Errors
    /// [`GeneratorError::Layout`] (a generator bug).
    pub fn check(&self) -> Result<crate::layout::Layout, GeneratorError> {
        Ok(self.layout.resolve()?)
    }
}

/// Generates realization `realization` of `wall` from the master seed `seed`.
///
/// # Errors
/// [`GeneratorError::Infeasible`] if this realization cannot be built (far too steep dips
/// for the course heights, or head-joint gaps wider than the blocks).
pub fn generate(wall: &Wall, seed: u64, realization: u64) -> Result<GeneratedWall, GeneratorError> {
    let mut rng = rng_for(seed, realization, Purpose::Layout);
    let elev = build::build(wall, &mut rng)?;
    let (l, h) = (wall.length, wall.height);

    let mut pieces = Vec::with_capacity(elev.pieces.len());
    let (mut stone_no, mut wedge_no) = (vec![0usize; elev.course_tops.len()], vec![0usize; elev.course_tops.len()]);
    // Layout order: per course, wedges then stones (each group keeps its left-to-right order).
    let mut order: Vec<usize> = (0..elev.pieces.len()).collect();
    order.sort_by_key(|&i| (elev.pieces[i].course, elev.pieces[i].kind == PieceKind::Stone));
    for i in order {
        let p = &elev.pieces[i];
        let mut vertices = Vec::with_capacity(2 * p.polygon.len());
        for &[x, z] in &p.polygon {
            let (y0, y1) = wall.faces_at(z);
            vertices.push([x, y0, z]);
            vertices.push([x, y1, z]);
        }
        let a = build::area(&p.polygon);
        let volume = a * wall.width_at(centroid_z(&p.polygon, a));
        // A wedge can be a thin sliver; keep it only if the hull the DEM will build from its
        // vertices is the block (quickhull can fail on slivers): else the gap stays open.
        if p.kind == PieceKind::Wedge && !hull_is_faithful(&vertices, volume) {
            continue;
        }
        let id = match p.kind {
            PieceKind::Stone => {
                stone_no[p.course] += 1;
                format!("c{}s{}", p.course, stone_no[p.course] - 1)
            }
            PieceKind::Wedge => {
                wedge_no[p.course] += 1;
                format!("c{}w{}", p.course, wedge_no[p.course] - 1)
            }
        };
        let (xmin, xmax) =
            p.polygon.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| (lo.min(q[0]), hi.max(q[0])));
        let restrained = match wall.ends {
            Ends::Free => false,
            Ends::Rigid { zone } | Ends::Spring { zone, .. } => xmin < zone || xmax > l - zone,
        };
        pieces.push(Piece {
            id,
            kind: p.kind,
            course: p.course,
            polygon: p.polygon.clone(),
            vertices,
            volume,
            dip_deg: p.dip_deg,
            material: match p.kind {
                PieceKind::Stone => wall.block_material.clone(),
                PieceKind::Wedge => wall.wedge_material.clone(),
            },
            restrained,
        });
    }

    // Materials, with per-block scatter from the Material stream.
    let mut materials = wall.materials.clone();
    if let Some(sc) = &wall.scatter {
        let mut mrng = rng_for(seed, realization, Purpose::Material);
        for p in &mut pieces {
            let base = wall.materials.iter().find(|m| m.name == p.material).expect("checked material");
            let f = sc.kn_factor.as_ref().map_or(1.0, |d| d.sample(&mut mrng));
            let dphi = sc.friction_offset.as_ref().map_or(0.0, |d| d.sample(&mut mrng));
            let name = format!("{}~{}", base.name, p.id);
            materials.push(MaterialSpec {
                name: name.clone(),
                kn_pa_per_m: base.kn_pa_per_m * f,
                ks_pa_per_m: base.ks_pa_per_m * f,
                friction_deg: (base.friction_deg + dphi).clamp(0.0, 89.999),
                ..base.clone()
            });
            p.material = name;
        }
    }

    let restrained: Vec<String> = pieces.iter().filter(|p| p.restrained).map(|p| p.id.clone()).collect();
    let ends = match wall.ends {
        Ends::Free => vec![],
        Ends::Rigid { .. } => {
            vec![EndRestraintSpec { blocks: restrained, kind: EndRestraintKind::Rigid, stiffness_n_per_m: None }]
        }
        Ends::Spring { stiffness, .. } => vec![EndRestraintSpec {
            blocks: restrained,
            kind: EndRestraintKind::Spring,
            stiffness_n_per_m: Some(stiffness),
        }],
    };
    let layout = LayoutSpec {
        version: crate::layout::LAYOUT_VERSION,
        name: format!("{} (seed {seed}, realization {realization})", wall.name),
        gravity_m_per_s2: wall.gravity,
        materials,
        table: TableSpec { material: wall.table_material.clone() },
        blocks: pieces
            .iter()
            .map(|p| BlockSpec {
                id: p.id.clone(),
                material: p.material.clone(),
                vertices: p.vertices.clone(),
                fixed: false,
            })
            .collect(),
        restraints: RestraintSpec { base_sliding: wall.base, ends },
        monitors: vec![],
    };
    Ok(GeneratedWall {
        seed,
        realization,
        pieces,
        course_tops_m: elev.course_tops,
        samples: elev.samples,
        layout,
        dimensions: [l, h, wall.base_width, wall.top_width],
        envelope_volume_m3: wall.envelope_volume(),
        stated_void_fraction: wall.stated_void_fraction(),
    })
}

/// Generates realizations `range` of `wall` in parallel (rayon); element j is
/// `generate(wall, seed, range.start + j)`, identical to generating it alone.
pub fn generate_batch(
    wall: &Wall,
    seed: u64,
    range: std::ops::Range<u64>,
) -> Vec<Result<GeneratedWall, GeneratorError>> {
    use rayon::prelude::*;
    range.into_par_iter().map(|i| generate(wall, seed, i)).collect()
}

/// True if the convex hull of `vertices` (as [`crate::geometry::ConvexBlock`] builds it for
/// the DEM) has the volume `volume` (m³) to 1e-9 relative: the hull is the block.
fn hull_is_faithful(vertices: &[[f64; 3]], volume: f64) -> bool {
    let v: Vec<crate::Vec3> = vertices.iter().map(|q| crate::Vec3::new(q[0], q[1], q[2])).collect();
    match crate::geometry::ConvexBlock::from_vertices(&v) {
        Ok(b) => (b.volume() - volume).abs() <= 1e-9 * volume.abs(),
        Err(_) => false,
    }
}

/// Centroid height of a polygon of signed area `a`.
fn centroid_z(poly: &[[f64; 2]], a: f64) -> f64 {
    let n = poly.len();
    let mut s = 0.0;
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let cr = p[0] * q[1] - q[0] * p[1];
        s += (p[1] + q[1]) * cr;
    }
    s / (6.0 * a)
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

    #[test]
    fn centroid_of_a_rectangle() {
        let r = [[0.0, 1.0], [2.0, 1.0], [2.0, 3.0], [0.0, 3.0]];
        assert!((centroid_z(&r, build::area(&r)) - 2.0).abs() < 1e-15);
    }
}
