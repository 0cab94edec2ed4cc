//! One realization of a wall: the elevation of [`build`](super::build) extruded into
//! through stones, named, given their materials (with per-block scatter from the `Material`
//! stream) and written as a layout with its end restraints. The stages, in order:
//!
//! 1. elevation (course tops, head joints, stones and wedges in x–z): [`super::build`];
//! 2. [`extrude`]: vertices between the two faces, volume, id, end zone;
//! 3. [`scatter_materials`]: one material per block when the wall has `[scatter]` (with a
//!    Kn factor or a friction offset);
//! 4. [`seat_beds`]: each block's bed seating gap when the wall's `[scatter]` draws one;
//! 5. [`layout`]: the layout file with the base and end restraints.

use super::build::{self, Elevation, Piece2, PieceKind, Samples};
use super::polygon;
use super::wall::{Ends, Section, Wall};
use super::GeneratorError;
use crate::closure::{Seating, CLOSURE_RANGE_M};
use crate::layout::{
    BlockSpec, Closure, EndRestraintKind, EndRestraintSpec, LayoutSpec, MaterialSpec, RestraintSpec, TableSpec,
};
use crate::rng::{rng_for, Purpose};
use serde::Serialize;

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
    /// Block vertices in the table frame, m (two per polygon vertex: its −y side, its +y
    /// side).
    pub vertices: Vec<[f64; 3]>,
    /// Volume, m³.
    pub volume: f64,
    /// Drawn dip of the stone's top segment, degrees (stones below the top course).
    pub dip_deg: Option<f64>,
    /// Material name in the layout.
    pub material: String,
    /// Held by an end restraint.
    pub restrained: bool,
    /// Where it lies across the section (`through` for every block of a single-leaf wall).
    #[serde(skip_serializing_if = "SectionPart::is_through")]
    pub part: SectionPart,
    /// The drawn largest initial gap of the block's bed, m (`[scatter] bed_seating_gap_m`;
    /// the layout gives the bed the seating law with it, [`crate::closure::Seating`], when
    /// it is at least the closure laws' smallest length). `None` (not written) without it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bed_seating_gap_m: Option<f64>,
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

    /// Checks the layout as `drystone tilt` would (convex blocks, no overlap beyond
    /// [`crate::layout::OVERLAP_TOLERANCE_M`], by the DEM's narrow phase) and returns it.
    ///
    /// # Errors
    /// [`GeneratorError::Layout`] (a generator bug).
    pub fn check(&self) -> Result<crate::layout::Layout, GeneratorError> {
        Ok(self.layout.resolve()?)
    }
}

/// Realization `realization` of the described wall `wall` (its courses, not a trace) from
/// the master seed `seed`: [`super::generate`] for a wall description.
///
/// # Errors
/// [`GeneratorError::Infeasible`] if this realization cannot be built.
pub(crate) fn generate_described(wall: &Wall, seed: u64, realization: u64) -> Result<GeneratedWall, GeneratorError> {
    let mut rng = rng_for(seed, realization, Purpose::Layout);
    let elev = build::build(wall, &mut rng)?;
    let mut pieces = extrude(wall, &elev);
    let materials = scatter_materials(wall, seed, realization, &mut pieces);
    seat_beds(wall, seed, realization, &mut pieces);
    let layout = layout(wall, format!("{} (seed {seed}, realization {realization})", wall.name), &pieces, materials);
    Ok(GeneratedWall {
        seed,
        realization,
        pieces,
        course_tops_m: elev.course_tops,
        samples: elev.samples,
        layout,
        dimensions: [wall.length, wall.height, wall.base_width, wall.top_width],
        envelope_volume_m3: wall.envelope_volume(),
        stated_void_fraction: wall.stated_void_fraction(),
    })
}

/// The elevation's pieces as blocks between the faces, in layout order (per course, wedges
/// then stones, each group left to right; a double-faced section puts each piece's parts
/// in the order −y leaf, hearting left to right, +y leaf), with their ids, volumes, stone
/// or wedge material and end-zone flag. A wedge (part) whose convex hull is not faithful is
/// dropped (its gap stays open).
fn extrude(wall: &Wall, elev: &Elevation) -> Vec<Piece> {
    let courses = elev.course_tops.len();
    let (mut stone_no, mut wedge_no) = (vec![0usize; courses], vec![0usize; courses]);
    let mut order: Vec<usize> = (0..elev.pieces.len()).collect();
    order.sort_by_key(|&i| (elev.pieces[i].course, elev.pieces[i].kind == PieceKind::Stone));
    let mut pieces = Vec::with_capacity(elev.pieces.len());
    for i in order {
        let p = &elev.pieces[i];
        let (no, letter, material) = match p.kind {
            PieceKind::Stone => (&mut stone_no[p.course], 's', &wall.block_material),
            PieceKind::Wedge => (&mut wedge_no[p.course], 'w', &wall.wedge_material),
        };
        let base_id = format!("c{}{letter}{}", p.course, *no);
        let mut built = Vec::new();
        for (part, suffix, polygon) in parts(wall, p) {
            let (lo, hi) = part.bounds();
            let vertices = extrude_polygon(&polygon, |z| (lo.y(wall, z), hi.y(wall, z)));
            let a = polygon::area(&polygon);
            let zc = centroid_z(&polygon, a);
            let width = match part {
                SectionPart::Through => wall.width_at(zc),
                _ => hi.y(wall, zc) - lo.y(wall, zc),
            };
            let volume = a * width;
            // A wedge can be a thin sliver; keep it only if the hull the DEM will build from
            // the vertices of every part across the section is the block (quickhull can fail
            // on slivers): else the gap stays open through the whole section (a sliver kept
            // in a leaf and dropped from the hearting would leave their elevations unequal).
            if p.kind == PieceKind::Wedge && !hull_is_faithful(&vertices, volume) {
                built.clear();
                break;
            }
            built.push(Piece {
                id: format!("{base_id}{suffix}"),
                kind: p.kind,
                course: p.course,
                restrained: in_end_zone(wall, &polygon),
                polygon,
                vertices,
                volume,
                dip_deg: p.dip_deg,
                material: material.clone(),
                part,
                bed_seating_gap_m: None,
            });
        }
        if !built.is_empty() {
            *no += 1;
        }
        pieces.append(&mut built);
    }
    pieces
}

/// Where a block lies across the section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SectionPart {
    /// Across the whole section, face to face (every block of a single-leaf wall; the
    /// through stones of a double-faced one).
    Through,
    /// The −y leaf of a double-faced section.
    NegativeLeaf,
    /// The hearting between the leaves.
    Hearting,
    /// The +y leaf (the side the wall falls to).
    PositiveLeaf,
}

impl SectionPart {
    /// True for [`SectionPart::Through`] (not written in the generator's JSON).
    pub fn is_through(&self) -> bool {
        *self == SectionPart::Through
    }

    /// The surfaces that bound the part in y.
    fn bounds(self) -> (Surface, Surface) {
        match self {
            SectionPart::Through => (Surface::NegFace, Surface::PosFace),
            SectionPart::NegativeLeaf => (Surface::NegFace, Surface::NegInner),
            SectionPart::Hearting => (Surface::NegInner, Surface::PosInner),
            SectionPart::PositiveLeaf => (Surface::PosInner, Surface::PosFace),
        }
    }
}

/// A surface across the section, each a plane y(z) affine in z (so a polygon of the
/// elevation extruded between two of them is convex, and its volume is its area times the
/// width at its centroid height).
#[derive(Debug, Clone, Copy)]
enum Surface {
    NegFace,
    PosFace,
    /// The inner side of the −y leaf: `leaf_width` in from the −y face (parallel to it), or
    /// the centre line without hearting.
    NegInner,
    /// The inner side of the +y leaf.
    PosInner,
}

impl Surface {
    fn y(self, wall: &Wall, z: f64) -> f64 {
        let (y0, y1) = wall.faces_at(z);
        let leaf = match wall.section {
            Section::Double { leaf_width, .. } => leaf_width,
            Section::Single => None,
        };
        match (self, leaf) {
            (Surface::NegFace, _) => y0,
            (Surface::PosFace, _) => y1,
            (Surface::NegInner | Surface::PosInner, None) => 0.5 * (y0 + y1),
            (Surface::NegInner, Some(w)) => y0 + w,
            (Surface::PosInner, Some(w)) => y1 - w,
        }
    }
}

/// The parts of one elevation piece across the section, each with its id suffix and its
/// elevation polygon: the piece itself as a through block (single leaf, or a through stone
/// of a double-faced wall: see [`is_through_stone`]); else `n` (−y leaf), the hearting
/// `h0`, `h1`, … (cut along x into equal pieces no longer than the hearting stone size) when
/// the leaves have a width, and `p` (+y leaf).
fn parts(wall: &Wall, p: &Piece2) -> Vec<(SectionPart, String, Vec<[f64; 2]>)> {
    let Section::Double { leaf_width, hearting_stone, through } = wall.section else {
        return vec![(SectionPart::Through, String::new(), p.polygon.clone())];
    };
    let (xmin, xmax) = x_range(&p.polygon);
    if p.kind == PieceKind::Stone && through.is_some_and(|(s, every)| is_through_stone(p.course, xmin, xmax, s, every))
    {
        return vec![(SectionPart::Through, String::new(), p.polygon.clone())];
    }
    let mut out = vec![(SectionPart::NegativeLeaf, "n".to_string(), p.polygon.clone())];
    if leaf_width.is_some() {
        let n = hearting_stone.map_or(1, |hs| (((xmax - xmin) / hs).ceil() as usize).max(1));
        let cut = |j: usize| if j == n { xmax } else { xmin + (xmax - xmin) * j as f64 / n as f64 };
        for j in 0..n {
            let poly = if n == 1 { p.polygon.clone() } else { polygon::clip_x(&p.polygon, cut(j), cut(j + 1)) };
            if poly.len() >= 3 && polygon::area(&poly) > 0.0 {
                out.push((SectionPart::Hearting, format!("h{j}"), poly));
            }
        }
    }
    out.push((SectionPart::PositiveLeaf, "p".to_string(), p.polygon.clone()));
    out
}

/// True if the stone of course `k` over `[xmin, xmax)` is a through stone: course `k` is one
/// of every `every`-th from the base (t = k / every), and the stone holds one of the points
/// `(j + ½) s + (t mod 2) s/2`, j = 0, 1, … (through stones `s` apart, staggered by half
/// their spacing from one such course to the next).
fn is_through_stone(k: usize, xmin: f64, xmax: f64, s: f64, every: usize) -> bool {
    if k % every != 0 {
        return false;
    }
    let offset = if (k / every) % 2 == 1 { s } else { 0.5 * s };
    let j = ((xmin - offset) / s).ceil().max(0.0);
    offset + j * s < xmax
}

/// The x extent of a polygon, m.
fn x_range(poly: &[[f64; 2]]) -> (f64, f64) {
    poly.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| (lo.min(q[0]), hi.max(q[0])))
}

/// True if the elevation polygon reaches into an end-restraint zone (x < zone or
/// x > L − zone).
fn in_end_zone(wall: &Wall, polygon: &[[f64; 2]]) -> bool {
    let (xmin, xmax) = x_range(polygon);
    match wall.ends {
        Ends::Free => false,
        Ends::Rigid { zone } | Ends::Spring { zone, .. } => xmin < zone || xmax > wall.length - zone,
    }
}

/// The wall's materials, plus with `[scatter]` one material `NAME~ID` per block (Kn and Ks
/// times the drawn factor, φ plus the drawn offset, clamped to [0°, 89.999°]) drawn from
/// the realization's `Material` stream in layout order; the pieces are renamed to them. A
/// `[scatter]` that draws only the beds' seating keeps the wall's materials
/// ([`super::wall::Scatter::per_block_materials`]).
fn scatter_materials(wall: &Wall, seed: u64, realization: u64, pieces: &mut [Piece]) -> Vec<MaterialSpec> {
    let mut materials = wall.materials.clone();
    let Some(sc) = wall.scatter.as_ref().filter(|sc| sc.per_block_materials()) else { return materials };
    let mut mrng = rng_for(seed, realization, Purpose::Material);
    for p in pieces {
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
    materials
}

/// With `[scatter] bed_seating_gap_m`, each piece's largest bed gap g₀ (m), one draw per
/// piece in layout order from the realization's own `Seating` stream (so the geometry and
/// the material scatter draw the same numbers with it or without it).
fn seat_beds(wall: &Wall, seed: u64, realization: u64, pieces: &mut [Piece]) {
    let Some(d) = wall.scatter.as_ref().and_then(|sc| sc.bed_seating_gap.as_ref()) else { return };
    let mut rng = rng_for(seed, realization, Purpose::Seating);
    for p in pieces {
        p.bed_seating_gap_m = Some(d.sample(&mut rng));
    }
}

/// The seating law of a bed whose largest initial gap is `gap` (m), or `None` (the
/// material's law) for a gap below the closure laws' smallest length (a bed seated flat).
pub(crate) fn bed_closure(gap: Option<f64>) -> Option<Closure> {
    gap.filter(|&g| g >= CLOSURE_RANGE_M.0).map(|g| Closure::Seating(Seating { max_gap_m: g }))
}

/// The layout file named `name`: the pieces as blocks, the table joint, the base restraint
/// and the end restraint on the pieces in the end zones.
fn layout(wall: &Wall, name: String, pieces: &[Piece], materials: Vec<MaterialSpec>) -> LayoutSpec {
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
    LayoutSpec {
        version: crate::layout::LAYOUT_VERSION,
        name,
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
                course: Some(p.course),
                wedge: p.kind == PieceKind::Wedge,
                own_mass: None,
                bed_closure: bed_closure(p.bed_seating_gap_m),
            })
            .collect(),
        restraints: RestraintSpec { base_sliding: wall.base, ends, ropes: vec![] },
        monitors: vec![],
        joint_families: wall.joints.clone(),
    }
}

/// True if the convex hull of `vertices` (as [`crate::geometry::ConvexBlock`] builds it for
/// the DEM) has the volume `volume` (m³) to 1e-9 relative: the hull is the block.
pub(crate) fn hull_is_faithful(vertices: &[[f64; 3]], volume: f64) -> bool {
    let v: Vec<crate::math::Vec3> = vertices.iter().map(|q| crate::math::Vec3::new(q[0], q[1], q[2])).collect();
    match crate::geometry::ConvexBlock::from_vertices(&v) {
        Ok(b) => (b.volume() - volume).abs() <= 1e-9 * volume.abs(),
        Err(_) => false,
    }
}

/// The vertices of the prism of the elevation polygon `polygon` ((x, z), m) between the
/// planes y = faces(z).0 and y = faces(z).1 (each affine in z, so that the prism of a convex
/// polygon is convex): for every vertex (x, z), the points (x, y₋(z), z) and (x, y₊(z), z),
/// in that order (table frame, m).
pub(crate) fn extrude_polygon(polygon: &[[f64; 2]], faces: impl Fn(f64) -> (f64, f64)) -> Vec<[f64; 3]> {
    let mut vertices = Vec::with_capacity(2 * polygon.len());
    for &[x, z] in polygon {
        let (y0, y1) = faces(z);
        vertices.push([x, y0, z]);
        vertices.push([x, y1, z]);
    }
    vertices
}

/// Centroid height of a polygon of signed area `a`.
pub(crate) fn centroid_z(poly: &[[f64; 2]], a: f64) -> f64 {
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

    #[test]
    fn centroid_of_a_rectangle() {
        let r = [[0.0, 1.0], [2.0, 1.0], [2.0, 3.0], [0.0, 3.0]];
        assert!((centroid_z(&r, polygon::area(&r)) - 2.0).abs() < 1e-15);
    }
}
