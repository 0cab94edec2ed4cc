//! Surveyed walls → layouts: `drystone import`.
//!
//! A wall that exists is surveyed rather than generated: an elevation traced from a
//! photograph as one outline per stone, or one closed mesh per scanned stone. [`import`]
//! reads such a survey and writes the layout file the rest of the tool reads (the format of
//! `drystone generate … --out LAYOUT.json`, [`crate::layout`]). See docs/survey.md.
//!
//! # Traced elevations (SVG, GeoJSON, DXF)
//!
//! Every stone is a closed polygon of the wall's elevation plane (x along the wall, z up),
//! extruded through the wall's section as the generator extrudes its through stones
//! ([`crate::generator`]: the faces `y₋(z)`, `y₊(z)` of a section of width B at the base
//! and b at the top with its batter, [`Section`]). A convex outline is one block; a
//! non-convex outline is refused, naming the stone and its convexity deficit, unless
//! [`ImportOptions::hull_nonconvex`] replaces it by its convex hull (the volume added is
//! reported). Outlines that overlap by more than [`crate::layout::OVERLAP_TOLERANCE_M`]
//! are refused, naming both stones.
//!
//! * SVG: `<polygon>`, `<polyline>` (closed), `<rect>` and `<path>` (M, L,
//!   H, V, Z, absolute and relative) with the `transform`s of the element and its groups;
//!   SVG's y axis points down and is flipped (z = −y × scale). The scale, metres per user
//!   unit, is [`ImportOptions::scale_m_per_unit`] or a `<line id="scale">` with a
//!   `data-length-m` attribute (its length in metres).
//! * GeoJSON: `Polygon` and `MultiPolygon` features, coordinates `[x, z]` in metres (times
//!   the scale if one is given).
//! * DXF (ASCII): closed `LWPOLYLINE`s and old-style `POLYLINE`s without bulges, y up,
//!   with `depth_m=D` text labels inside the stones whose depth was measured; any other
//!   entity off the `IGNORE` layer refused; the scale from
//!   [`ImportOptions::scale_m_per_unit`] or the header's `$INSUNITS`.
//!
//! # Scanned stones (OBJ, STL)
//!
//! One closed triangle mesh per stone (a file, or an `o` object of an OBJ file; a folder of
//! such files is read in file-name order); its convex hull is the block (the contact
//! geometry), and its mass, centroid and inertia are the closed mesh's own, by the
//! divergence theorem ([`crate::geometry::mesh_mass_properties`]), written as the block's
//! `own_mass` ([`crate::layout::OwnMassSpec`]); the mesh's volume is reported beside the
//! hull's. Units by [`LengthUnit`]; z up
//! unless [`ImportOptions::y_up`]. A stone longer than [`MAX_STONE_M`] or shorter than
//! [`MIN_STONE_M`] is refused as a probable unit mistake (traced stones too).
//!
//! # The ensemble around a survey
//!
//! [`surveyed_wall`] makes a traced elevation a [`crate::generator::Wall`] whose
//! realizations draw the survey's uncertainty ([`Uncertainty`]: the tracing tolerance, the
//! stones' unknown depths; [`crate::generator::traced`]): `drystone import --seed N
//! --realization R` writes one, a study group naming a `survey` runs them through its
//! protocol.
//!
//! # The frame
//!
//! The survey is translated into the table frame of [`crate::geometry`]: the lowest point
//! of the wall on the table (z = 0), its leftmost point at x = 0; a traced wall's section is
//! centred as the generator's (y = 0 its centre plane for a symmetric batter), a scanned
//! wall's y extent is centred on y = 0. The table (the plane z = 0) is the foundation the
//! lowest stones stand on, as in a generated wall's layout.

mod dxf;
mod elevation;
pub mod ensemble;
mod error;
mod geojson;
mod mesh;
mod svg;

pub use elevation::Section;
pub use ensemble::{surveyed_wall, Uncertainty};
pub use error::SurveyError;
pub use mesh::LengthUnit;

use crate::layout::{BaseSliding, LayoutError, LayoutSpec, MaterialSpec, RestraintSpec, TableSpec};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The longest stone accepted, m: a longer one is a probable unit mistake.
pub const MAX_STONE_M: f64 = 5.0;

/// The shortest stone accepted (its longest extent), m: a shorter one is a probable unit
/// mistake.
pub const MIN_STONE_M: f64 = 0.005;

/// The survey formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurveyFormat {
    /// A traced elevation drawn in SVG.
    Svg,
    /// A traced elevation as GeoJSON polygons (metres).
    Geojson,
    /// A traced elevation as closed LWPOLYLINEs of an ASCII DXF drawing.
    Dxf,
    /// Scanned stones, Wavefront OBJ meshes.
    Obj,
    /// Scanned stones, STL meshes (ASCII or binary).
    Stl,
}

impl SurveyFormat {
    /// The format of a file by its extension (`.svg`, `.geojson` or `.json`, `.dxf`,
    /// `.obj`, `.stl`; any case), if it is one.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "svg" => Some(Self::Svg),
            "geojson" | "json" => Some(Self::Geojson),
            "dxf" => Some(Self::Dxf),
            "obj" => Some(Self::Obj),
            "stl" => Some(Self::Stl),
            _ => None,
        }
    }

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Svg => "svg",
            Self::Geojson => "geojson",
            Self::Dxf => "dxf",
            Self::Obj => "obj",
            Self::Stl => "stl",
        }
    }

    /// Whether it is a traced elevation (SVG, GeoJSON) rather than scanned stones.
    pub fn is_elevation(self) -> bool {
        matches!(self, Self::Svg | Self::Geojson | Self::Dxf)
    }
}

impl std::str::FromStr for SurveyFormat {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "svg" => Ok(Self::Svg),
            "geojson" => Ok(Self::Geojson),
            "dxf" => Ok(Self::Dxf),
            "obj" => Ok(Self::Obj),
            "stl" => Ok(Self::Stl),
            _ => Err(format!("unknown survey format {s:?}: svg, geojson, dxf, obj or stl")),
        }
    }
}

/// The materials of an imported wall: the layout's material fields ([`MaterialSpec`]), the
/// stones' material (a stone may name another: `data-material` in SVG, the `material`
/// property in GeoJSON) and the table's.
///
/// As a TOML file (`--materials FILE`):
///
/// ```toml
/// stone_material = "granite"   # default: the first material
/// table_material = "granite"   # default: the stone material
/// [[materials]]                # the keys of a layout's (and a wall description's) materials
/// name = "granite"
/// density_kg_per_m3 = 2600
/// kn_pa_per_m = 1.0e9
/// ks_pa_per_m = 5.0e8
/// friction_deg = 35
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurveyMaterials {
    /// The materials.
    pub materials: Vec<MaterialSpec>,
    /// The stones' material. Default: the first.
    #[serde(default)]
    pub stone_material: Option<String>,
    /// The table's material. Default: the stones'.
    #[serde(default)]
    pub table_material: Option<String>,
}

impl SurveyMaterials {
    /// One material named `stone` for the stones and the table.
    pub fn one(material: MaterialSpec) -> Self {
        Self { materials: vec![material], stone_material: None, table_material: None }
    }

    /// Reads a materials file (TOML, above).
    ///
    /// # Errors
    /// [`SurveyError::File`]: the file cannot be read (named as the materials file), or
    /// toml's message (key, line).
    pub fn from_file(path: &Path) -> Result<Self, SurveyError> {
        let text = std::fs::read_to_string(path).map_err(|e| SurveyError::File {
            path: path.to_owned(),
            reason: format!("cannot read the materials file: {e}"),
        })?;
        let m: Self =
            toml::from_str(&text).map_err(|e| SurveyError::File { path: path.to_owned(), reason: e.to_string() })?;
        // A stone or table material the file does not define, named by its own key (the
        // layout would name `table.material`, a key the user did not write).
        let names: Vec<&str> = m.materials.iter().map(|x| x.name.as_str()).collect();
        for (key, given) in [("stone_material", &m.stone_material), ("table_material", &m.table_material)] {
            if let Some(g) = given.as_deref().filter(|g| !names.contains(g)) {
                return Err(SurveyError::File {
                    path: path.to_owned(),
                    reason: format!("{key} = {g:?} is not among its [[materials]] ({})", names.join(", ")),
                });
            }
        }
        Ok(m)
    }

    /// The stones' material name.
    fn stone(&self) -> String {
        self.stone_material.clone().or_else(|| self.materials.first().map(|m| m.name.clone())).unwrap_or_default()
    }
}

/// How to import a survey.
#[derive(Debug, Clone)]
pub struct ImportOptions {
    /// The format; `None`: by the file's extension ([`SurveyFormat::from_path`]).
    pub format: Option<SurveyFormat>,
    /// Traced elevations: metres per unit of the drawing (SVG: per user unit; GeoJSON:
    /// per coordinate unit, default 1). SVG needs it unless it has a scale line.
    pub scale_m_per_unit: Option<f64>,
    /// Traced elevations: the section the outlines are extruded through (required).
    pub section: Option<Section>,
    /// Traced elevations: a non-convex outline becomes its convex hull instead of an
    /// error (the volume added is reported). Default false.
    pub hull_nonconvex: bool,
    /// Scanned stones: the unit of the mesh coordinates. `None`: metres.
    pub unit: Option<LengthUnit>,
    /// Scanned stones: the mesh's y axis is up (converted by the rotation (x, y, z) →
    /// (x, −z, y) about x). Default false: z up.
    pub y_up: bool,
    /// The materials.
    pub materials: SurveyMaterials,
    /// The base course's restraint on the table. Default free.
    pub base_sliding: BaseSliding,
    /// The layout's name; `None`: the survey's file name.
    pub name: Option<String>,
    /// Scanned stones: the most vertices a stone's hull keeps; a hull with more is
    /// simplified to this many (see [`DEFAULT_MAX_HULL_VERTICES`] for how the hull is
    /// simplified and why the default). `None`: [`DEFAULT_MAX_HULL_VERTICES`]. At least 4.
    pub max_hull_vertices: Option<usize>,
    /// Scanned stones: keep every stone's full hull, whatever its number of vertices.
    /// Default false.
    pub full_hull: bool,
}

/// The default vertex budget of a scanned stone's hull ([`ImportOptions::max_hull_vertices`]).
///
/// **Why a budget.** Contact detection between two blocks is a separating-axis test
/// ([`crate::geometry::sat`]): each face normal of one block against every vertex of the
/// other, and the edge pairs whose arcs cross on the Gauss map, each against both blocks'
/// vertices. For two hulls of V vertices (F ≈ 2V triangular faces, E ≈ 3V edges) that is
/// about 2·F·V + E² ≈ 13 V² operations per pair and per detection, against ≈ 800 for two
/// generated blocks of 8 vertices. A stone scanned at 1 mm keeps tens of thousands of hull
/// vertices, ≈ 10¹⁰ operations per pair, which no run can afford; the budget bounds it.
///
/// **How.** A hull with more vertices than the budget becomes the hull of a subsample of
/// its vertices ([`crate::geometry::hull::spread_subsample`]: the extreme vertices along 26
/// directions, then farthest-point sampling). The subsample's vertices are the stone's own,
/// so the simplified hull lies inside the full hull, keeps its lowest point and its corners,
/// and adds no overlap with a neighbour; it only leaves out a fraction of the full hull's
/// volume, which the import reports and refuses above [`HULL_VOLUME_TOLERANCE`], naming the
/// file and the stone (raise the budget, or keep the full hull with
/// [`ImportOptions::full_hull`]).
///
/// **The default.** A round stone is the worst case. The hull of N points spread evenly
/// over a sphere of radius R (2N equilateral triangles of side a, a² = 8π R²/(√3 N)) leaves
/// out π a² R / 2 of its volume, a fraction √3 π/N ≈ 5.4/N, its faces a mean
/// 1.8 R/N inside the sphere; farthest-point sampling comes close (≈ 6/N, measured on UV
/// spheres of 3,542 to 39,802 hull vertices: 0.38 % to 0.60 % at 1,000). At 1,000 vertices
/// a round stone's block lies a mean 0.2 % of its radius inside its full hull (0.3 mm on a
/// 0.3 m stone, below the accuracy of a photogrammetric scan) and loses under 1 % of its
/// volume ([`HULL_VOLUME_TOLERANCE`]); a pair of such blocks costs ≈ 1.3·10⁷ operations per
/// detection (milliseconds), against ≈ 2·10¹⁰ for two hulls of 40,000 vertices.
pub const DEFAULT_MAX_HULL_VERTICES: usize = 1000;

/// The largest fraction of a scanned stone's full hull volume a simplified hull may leave
/// out (1 %) before the import refuses it ([`DEFAULT_MAX_HULL_VERTICES`]): the stone's
/// mesh volume, its `own_mass`, may then exceed its block's volume by as much
/// ([`crate::layout::SIMPLIFIED_HULL_VOLUME_TOLERANCE`], the same figure).
pub const HULL_VOLUME_TOLERANCE: f64 = crate::layout::SIMPLIFIED_HULL_VOLUME_TOLERANCE;

/// One stone as the survey gave it: an outline (traced) or a mesh (scanned), before it is
/// made a block.
#[derive(Debug, Clone)]
pub(crate) struct Stone {
    /// The stone's id in the layout.
    pub id: String,
    /// Where it is in the file (`<path id="s3"> at line 12`, `feature 2`, `object "a"`).
    pub element: String,
    /// Its material, if the survey names one.
    pub material: Option<String>,
    /// Its depth into the wall from the traced (−y) face, m, if the survey states it (SVG
    /// `data-depth-m`, GeoJSON property `depth_m`): a measured depth, used in every
    /// realization in place of the depth law's draw.
    pub depth_m: Option<f64>,
}

/// One traced outline: the stone and its corners (x, z) in the survey's frame after the
/// scale, m (open: the closing corner is not repeated).
#[derive(Debug, Clone)]
pub(crate) struct Outline {
    pub stone: Stone,
    pub points: Vec<[f64; 2]>,
}

/// What became of one stone.
#[derive(Debug, Clone, PartialEq)]
pub struct StoneReport {
    /// The block's id.
    pub id: String,
    /// Where the stone is in the survey.
    pub element: String,
    /// The block's volume, m³ (the convex hull's for a hulled stone or a mesh).
    pub block_volume_m3: f64,
    /// The stone's own volume, m³: its outline's area × the section's width at its centroid
    /// height (traced), or the closed mesh's volume (scanned).
    pub survey_volume_m3: f64,
    /// Whether the block is the stone's convex hull rather than the stone itself.
    pub hulled: bool,
    /// A scanned stone's hull simplified to the vertex budget; `None`: the full hull (or a
    /// traced stone).
    pub simplified: Option<HullSimplification>,
}

/// How a scanned stone's hull was simplified to the vertex budget
/// ([`ImportOptions::max_hull_vertices`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HullSimplification {
    /// The full hull's vertices.
    pub full_vertices: usize,
    /// The simplified hull's vertices (at most the budget).
    pub kept_vertices: usize,
    /// The full hull's volume, m³.
    pub full_volume_m3: f64,
    /// The fraction of the full hull's volume the simplified hull leaves out, in [0, 1)
    /// (the simplified hull lies inside the full one).
    pub volume_change: f64,
}

impl StoneReport {
    /// The volume the block adds to the stone (its hull's excess), m³ (0 for a block that is
    /// the stone).
    pub fn added_m3(&self) -> f64 {
        if self.hulled {
            // A hull holds its stone: a difference below zero is rounding.
            (self.block_volume_m3 - self.survey_volume_m3).max(0.0)
        } else {
            0.0
        }
    }
}

/// An imported wall: its layout and what became of each stone.
#[derive(Debug, Clone)]
pub struct ImportedWall {
    /// The survey file (or folder).
    pub source: PathBuf,
    /// Its format.
    pub format: SurveyFormat,
    /// The layout (checked: it resolves).
    pub layout: LayoutSpec,
    /// One report per block, in layout order.
    pub stones: Vec<StoneReport>,
    /// The translation from the survey's frame (after scale and axes) to the table frame, m.
    pub offset_m: [f64; 3],
    /// The scale used (traced elevations), m per unit, and where it came from.
    pub scale: Option<(f64, String)>,
    /// The wall's length (x extent) and height (z extent), m.
    pub length_m: f64,
    /// See `length_m`.
    pub height_m: f64,
}

impl ImportedWall {
    /// The blocks' total volume, m³.
    pub fn volume_m3(&self) -> f64 {
        self.stones.iter().map(|s| s.block_volume_m3).sum()
    }

    /// The volume the convex hulls add to the stones, m³.
    pub fn added_m3(&self) -> f64 {
        self.stones.iter().map(StoneReport::added_m3).sum()
    }

    /// The number of blocks standing on the table: their lowest corner within 1e-9 m of
    /// z = 0 (the others rest on stones, or fall when the wall settles).
    pub fn on_table(&self) -> usize {
        let lowest = |b: &crate::layout::BlockSpec| b.vertices.iter().map(|v| v[2]).fold(f64::INFINITY, f64::min);
        self.layout.blocks.iter().filter(|b| lowest(b) <= 1e-9).count()
    }
}

/// Imports the survey at `path` (a file, or for scanned stones a folder of OBJ and STL
/// files read in file-name order) into a checked layout.
///
/// # Errors
/// A [`SurveyError`] naming the file and the element, feature, object or line at fault;
/// [`SurveyError::Option`] for an option that is out of range or not for the format.
pub fn import(path: &Path, options: &ImportOptions) -> Result<ImportedWall, SurveyError> {
    let format = match options.format {
        Some(f) => f,
        None if path.is_dir() => SurveyFormat::Obj,
        None => SurveyFormat::from_path(path).ok_or_else(|| SurveyError::File {
            path: path.to_owned(),
            reason: "unknown survey format: name it with --format svg|geojson|dxf|obj|stl, or use one of the \
                     extensions .svg, .geojson (.json), .dxf, .obj, .stl"
                .into(),
        })?,
    };
    check_options(format, options)?;
    let mut wall =
        if format.is_elevation() { elevation::import(path, format, options)? } else { mesh::import(path, options)? };
    check_layout(path, &mut wall)?;
    Ok(wall)
}

/// Refuses the options that do not apply to `format`, and out-of-range values.
fn check_options(format: SurveyFormat, o: &ImportOptions) -> Result<(), SurveyError> {
    let refuse = |option: &str, value: String, reason: &str| {
        Err(SurveyError::Option { option: option.into(), value, reason: reason.into() })
    };
    if format.is_elevation() {
        if let Some(u) = o.unit {
            return refuse("--unit", u.name().into(), "is for scanned stones; a drawing's unit is --scale-m-per-unit");
        }
        if o.y_up {
            return refuse("--y-up", "true".into(), "is for scanned stones; a drawing is an elevation (x, z)");
        }
        if let Some(s) = o.scale_m_per_unit {
            if !(s.is_finite() && s > 0.0) {
                return refuse("--scale-m-per-unit", s.to_string(), "must be a positive number (metres per unit)");
            }
        }
        match &o.section {
            None => return refuse("--thickness-m", "none".into(), "a traced elevation needs the wall's thickness"),
            Some(s) => s.check()?,
        }
    } else {
        if let Some(s) = o.scale_m_per_unit {
            return refuse("--scale-m-per-unit", s.to_string(), "is for traced elevations; a mesh's unit is --unit");
        }
        if o.section.is_some() {
            return refuse(
                "--thickness-m",
                "given".into(),
                "is for traced elevations; a scanned stone has its own depth",
            );
        }
        if o.hull_nonconvex {
            return refuse(
                "--hull-nonconvex",
                "true".into(),
                "is for traced elevations; a scanned stone is always its hull",
            );
        }
        if let Some(n) = o.max_hull_vertices {
            if n < 4 {
                return refuse("--max-hull-vertices", n.to_string(), "must be at least 4 (a tetrahedron)");
            }
            if o.full_hull {
                return refuse("--max-hull-vertices", n.to_string(), "and --full-hull exclude each other");
            }
        }
    }
    if format.is_elevation() {
        if let Some(n) = o.max_hull_vertices {
            return refuse(
                "--max-hull-vertices",
                n.to_string(),
                "is for scanned stones; a traced stone is its outline",
            );
        }
        if o.full_hull {
            return refuse("--full-hull", "true".into(), "is for scanned stones; a traced stone is its outline");
        }
    }
    if o.materials.materials.is_empty() {
        return refuse("--materials", "none".into(), "at least one material is needed");
    }
    Ok(())
}

/// A block of an imported survey: its id, its material (`None`: the stones'), its vertices
/// (table frame, m) and its own mass properties (a scanned stone's mesh; `None`: its hull's).
pub(crate) type SurveyBlock = (String, Option<String>, Vec<[f64; 3]>, Option<crate::layout::OwnMassSpec>);

/// The layout of the blocks `blocks`.
pub(crate) fn layout_of(path: &Path, o: &ImportOptions, blocks: Vec<SurveyBlock>) -> LayoutSpec {
    let stone = o.materials.stone();
    let table = o.materials.table_material.clone().unwrap_or_else(|| stone.clone());
    let name = o.name.clone().unwrap_or_else(|| {
        format!(
            "{} (imported)",
            path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
        )
    });
    LayoutSpec {
        version: crate::layout::LAYOUT_VERSION,
        name,
        gravity_m_per_s2: crate::units::STANDARD_GRAVITY,
        materials: o.materials.materials.clone(),
        table: TableSpec { material: table },
        blocks: blocks
            .into_iter()
            .map(|(id, material, vertices, own_mass)| crate::layout::BlockSpec {
                id,
                material: material.unwrap_or_else(|| stone.clone()),
                vertices,
                fixed: false,
                course: None,
                wedge: false,
                own_mass,
                bed_closure: None,
            })
            .collect(),
        restraints: RestraintSpec { base_sliding: o.base_sliding, ends: vec![], ropes: vec![] },
        monitors: vec![],
        joint_families: Default::default(),
    }
}

/// Checks the layout as `drystone tilt` would; an overlap of two blocks names both stones'
/// elements.
fn check_layout(path: &Path, wall: &mut ImportedWall) -> Result<(), SurveyError> {
    match wall.layout.resolve() {
        Ok(_) => Ok(()),
        Err(LayoutError::Overlap { a, b, depth_m }) => {
            let named = |id: &str| {
                wall.stones
                    .iter()
                    .find(|s| s.id == id)
                    .map_or_else(|| "the table".to_string(), |s| format!("{id} ({})", s.element))
            };
            Err(SurveyError::Overlap { path: path.to_owned(), a: named(&a), b: named(&b), depth_m })
        }
        Err(source) => Err(SurveyError::Layout { path: path.to_owned(), source }),
    }
}

/// Refuses ids given twice, naming both elements.
pub(crate) fn check_unique_ids(path: &Path, stones: &[Stone]) -> Result<(), SurveyError> {
    let mut seen: std::collections::BTreeMap<&str, &str> = std::collections::BTreeMap::new();
    for s in stones {
        if let Some(first) = seen.insert(&s.id, &s.element) {
            return Err(SurveyError::Element {
                path: path.to_owned(),
                element: s.element.clone(),
                reason: format!("id {:?} is also the id of {first}; every stone needs its own id", s.id),
            });
        }
    }
    Ok(())
}

/// Refuses a stone that names a material not among the materials given, naming its element.
pub(crate) fn check_materials(path: &Path, stones: &[Stone], o: &ImportOptions) -> Result<(), SurveyError> {
    let names: Vec<&str> = o.materials.materials.iter().map(|m| m.name.as_str()).collect();
    for s in stones {
        if let Some(m) = s.material.as_deref().filter(|m| !names.contains(m)) {
            return Err(SurveyError::Element {
                path: path.to_owned(),
                element: s.element.clone(),
                reason: format!("material {m:?} is not among the materials given ({})", names.join(", ")),
            });
        }
    }
    Ok(())
}

/// Refuses a stone whose longest extent `extent_m` is outside [`MIN_STONE_M`],
/// [`MAX_STONE_M`] (a probable unit mistake; `unit` names the conversion used).
pub(crate) fn check_size(path: &Path, stone: &Stone, extent_m: f64, unit: &str) -> Result<(), SurveyError> {
    if (MIN_STONE_M..=MAX_STONE_M).contains(&extent_m) {
        return Ok(());
    }
    if !(extent_m > 0.0) {
        // A stone of no extent (a mesh without triangles, an outline a transform collapses):
        // not a unit mistake.
        return Err(SurveyError::Element {
            path: path.to_owned(),
            element: stone.element.clone(),
            reason: format!("stone {} has no extent (every corner at one point)", stone.id),
        });
    }
    Err(SurveyError::Size {
        path: path.to_owned(),
        stone: stone.id.clone(),
        element: stone.element.clone(),
        extent_m,
        unit: unit.to_owned(),
    })
}

/// A number as the survey's messages print it (m, a scale): plain between 1e-4 and 1e6, in
/// scientific notation outside (a scale of 1e300 is not written out in 301 digits).
pub fn short_number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Reads a file as text.
/// The files a survey at `path` reads: its `.obj` and `.stl` files in file-name order for
/// a folder of scanned stones, else `path` itself (a folder that cannot be listed is
/// returned as itself, for the caller's read to name it).
pub fn survey_files(path: &Path) -> Vec<PathBuf> {
    if !path.is_dir() {
        return vec![path.to_owned()];
    }
    match mesh::mesh_files(path, None) {
        Ok(files) => files.into_iter().map(|(p, _)| p).collect(),
        Err(_) => vec![path.to_owned()],
    }
}

pub(crate) fn read_text(path: &Path) -> Result<String, SurveyError> {
    std::fs::read_to_string(path).map_err(|source| SurveyError::Io { path: path.to_owned(), source })
}
