//! Scanned stones: one closed triangle mesh per stone, from Wavefront OBJ (`v`, `f`; each
//! `o` object a stone) and STL (ASCII, each `solid` a stone; or binary, one stone), or a
//! folder of such files in file-name order. Vertices with the same coordinates are welded;
//! a mesh must then be closed and consistently oriented (every edge shared by two faces in
//! opposite directions). Its block, the contact geometry, is its convex hull
//! ([`crate::geometry::ConvexBlock`], parry3d's hull); its mass, centroid and inertia are
//! the closed mesh's own, by the divergence theorem
//! ([`crate::geometry::mesh_mass_properties`]), written as the block's `own_mass`.

use super::{
    check_size, check_unique_ids, HullSimplification, ImportOptions, ImportedWall, Stone, StoneReport, SurveyError,
    SurveyFormat, DEFAULT_MAX_HULL_VERTICES, HULL_VOLUME_TOLERANCE,
};
use crate::geometry::{mesh_mass_properties, ConvexBlock};
use crate::layout::OwnMassSpec;
use crate::math::Vec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The unit of a mesh's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LengthUnit {
    /// Metres.
    M,
    /// Centimetres.
    Cm,
    /// Millimetres.
    Mm,
}

impl LengthUnit {
    /// Metres per unit.
    pub fn metres(self) -> f64 {
        match self {
            Self::M => 1.0,
            Self::Cm => 0.01,
            Self::Mm => 0.001,
        }
    }

    /// Its name (`m`, `cm`, `mm`).
    pub fn name(self) -> &'static str {
        match self {
            Self::M => "m",
            Self::Cm => "cm",
            Self::Mm => "mm",
        }
    }
}

impl std::str::FromStr for LengthUnit {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "m" => Ok(Self::M),
            "cm" => Ok(Self::Cm),
            "mm" => Ok(Self::Mm),
            _ => Err(format!("unknown unit {s:?}: m, cm or mm")),
        }
    }
}

/// One mesh as read: its stone, the file it is in, its vertices and triangles.
struct Mesh {
    stone: Stone,
    file: PathBuf,
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[usize; 3]>,
}

/// Reads the scanned stones at `path` (a file or a folder) and makes their blocks.
pub(super) fn import(path: &Path, o: &ImportOptions) -> Result<ImportedWall, SurveyError> {
    let files = mesh_files(path, o.format)?;
    let mut meshes = Vec::new();
    for (file, format) in &files {
        let bytes = std::fs::read(file).map_err(|source| SurveyError::Io { path: file.clone(), source })?;
        let stem = file.file_stem().map_or_else(|| "stone".to_string(), |s| s.to_string_lossy().into_owned());
        let read = match format {
            SurveyFormat::Stl => read_stl(file, &bytes, &stem)?,
            _ => read_obj(file, &String::from_utf8_lossy(&bytes), &stem)?,
        };
        meshes.extend(read);
    }
    if meshes.is_empty() {
        return Err(SurveyError::File { path: path.to_owned(), reason: "no mesh found".into() });
    }
    for m in &mut meshes {
        if m.triangles.is_empty() {
            let reason = "the mesh has no triangles".to_string();
            return Err(SurveyError::Element { path: m.file.clone(), element: m.stone.element.clone(), reason });
        }
        (m.vertices, m.triangles) = weld(&m.vertices, &m.triangles);
        // Checked in the file's own coordinates, which the message gives.
        check_closed(&m.vertices, &m.triangles).map_err(|reason| SurveyError::Element {
            path: m.file.clone(),
            element: m.stone.element.clone(),
            reason: format!("stone {}: {reason}", m.stone.id),
        })?;
    }
    let stones: Vec<Stone> = meshes.iter().map(|m| m.stone.clone()).collect();
    check_unique_ids(path, &stones)?;
    let unit = o.unit.unwrap_or(LengthUnit::M);
    let label = format!("--unit {}", unit.name());
    for m in &mut meshes {
        for v in &mut m.vertices {
            let k = unit.metres();
            *v = if o.y_up { [v[0] * k, -v[2] * k, v[1] * k] } else { [v[0] * k, v[1] * k, v[2] * k] };
        }
        if m.vertices.iter().flatten().any(|c| !c.is_finite()) {
            let reason = "a vertex has a coordinate that is not a finite number".to_string();
            return Err(SurveyError::Element { path: m.file.clone(), element: m.stone.element.clone(), reason });
        }
        let (lo, hi) = bounds(&m.vertices);
        check_size(&m.file, &m.stone, (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max), &label)?;
    }
    let (lo, hi) = bounds(&meshes.iter().flat_map(|m| m.vertices.iter().copied()).collect::<Vec<_>>());
    let offset = [-lo[0], -0.5 * (lo[1] + hi[1]), -lo[2]];
    let mut blocks = Vec::with_capacity(meshes.len());
    let mut reports = Vec::with_capacity(meshes.len());
    for m in &mut meshes {
        for v in &mut m.vertices {
            *v = [v[0] + offset[0], v[1] + offset[1], v[2] + offset[2]];
        }
        let (vertices, triangles) = (&m.vertices, &m.triangles);
        let err = |reason: String| SurveyError::Element {
            path: m.file.clone(),
            element: m.stone.element.clone(),
            reason: format!("stone {}: {reason}", m.stone.id),
        };
        let points: Vec<Vec3> = vertices.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect();
        // The stone's own mass properties, at unit density: its block's mass, weight and
        // inertia (the block itself, its contact geometry, is the hull).
        let own = mesh_mass_properties(&points, triangles, 1.0);
        if !(own.volume > 0.0 && own.centroid.iter().all(|c| c.is_finite())) {
            return Err(err("the mesh encloses no volume".into()));
        }
        let hull = ConvexBlock::hull_of(&points).map_err(|e| err(format!("its convex hull cannot be built: {e}")))?;
        let (hull, simplified) = within_budget(hull, o).map_err(err)?;
        reports.push(StoneReport {
            id: m.stone.id.clone(),
            element: m.stone.element.clone(),
            block_volume_m3: hull.volume(),
            survey_volume_m3: own.volume,
            hulled: true,
            simplified,
        });
        let vs = hull.vertices.iter().map(|v| [v.x, v.y, v.z]).collect();
        blocks.push((m.stone.id.clone(), m.stone.material.clone(), vs, Some(OwnMassSpec::of(&own))));
    }
    Ok(ImportedWall {
        source: path.to_owned(),
        format: files[0].1,
        layout: super::layout_of(path, o, blocks),
        stones: reports,
        offset_m: offset,
        scale: None,
        length_m: hi[0] - lo[0],
        height_m: hi[2] - lo[2],
    })
}

/// The stone's hull within the vertex budget ([`ImportOptions::max_hull_vertices`], by
/// default [`DEFAULT_MAX_HULL_VERTICES`]): the full hull if it has no more vertices or
/// [`ImportOptions::full_hull`] is set, else the hull of its vertices'
/// [`crate::geometry::hull::spread_subsample`] with what the simplification left out.
///
/// # Errors
/// The reason, when the simplified hull leaves out more than [`HULL_VOLUME_TOLERANCE`] of
/// the full hull's volume (the caller names the file and the stone), or cannot be built.
fn within_budget(full: ConvexBlock, o: &ImportOptions) -> Result<(ConvexBlock, Option<HullSimplification>), String> {
    let budget = o.max_hull_vertices.unwrap_or(DEFAULT_MAX_HULL_VERTICES);
    if o.full_hull || full.vertices.len() <= budget {
        return Ok((full, None));
    }
    let kept: Vec<Vec3> =
        crate::geometry::hull::spread_subsample(&full.vertices, budget).into_iter().map(|i| full.vertices[i]).collect();
    let hull = ConvexBlock::hull_of(&kept).map_err(|e| format!("its hull simplified to {budget} vertices: {e}"))?;
    let full_volume_m3 = full.volume();
    let volume_change = ((full_volume_m3 - hull.volume()) / full_volume_m3).max(0.0);
    let s = HullSimplification {
        full_vertices: full.vertices.len(),
        kept_vertices: hull.vertices.len(),
        full_volume_m3,
        volume_change,
    };
    if !(volume_change <= HULL_VOLUME_TOLERANCE) {
        return Err(format!(
            "its hull of {} vertices simplified to the budget of {budget} (--max-hull-vertices) leaves out {:.3} % of \
             its volume, more than the {:.3} % allowed: raise --max-hull-vertices or keep the full hull with --full-hull \
             (in a study, the group's import.max_hull_vertices or import.full_hull)",
            s.full_vertices,
            100.0 * volume_change,
            100.0 * HULL_VOLUME_TOLERANCE
        ));
    }
    Ok((hull, Some(s)))
}

/// The mesh files: `path` itself (its format given or by extension), or the OBJ and STL
/// files of the folder `path` in file-name order.
pub(super) fn mesh_files(
    path: &Path,
    format: Option<SurveyFormat>,
) -> Result<Vec<(PathBuf, SurveyFormat)>, SurveyError> {
    if !path.is_dir() {
        let f = format.or_else(|| SurveyFormat::from_path(path)).unwrap_or(SurveyFormat::Obj);
        return Ok(vec![(path.to_owned(), f)]);
    }
    let entries = std::fs::read_dir(path).map_err(|source| SurveyError::Io { path: path.to_owned(), source })?;
    let mut files: Vec<(PathBuf, SurveyFormat)> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter_map(|p| match SurveyFormat::from_path(&p) {
            Some(f @ (SurveyFormat::Obj | SurveyFormat::Stl)) if format.is_none_or(|g| g == f) => Some((p, f)),
            _ => None,
        })
        .collect();
    files.sort_by(|a, b| a.0.cmp(&b.0));
    if files.is_empty() {
        return Err(SurveyError::File { path: path.to_owned(), reason: "the folder has no .obj or .stl file".into() });
    }
    Ok(files)
}

fn bounds(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    points.iter().fold(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]), |(mut lo, mut hi), p| {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
        (lo, hi)
    })
}

/// The meshes of an OBJ file: one per `o` object (the whole file if it has none), its
/// polygons fan-triangulated.
fn read_obj(file: &Path, text: &str, stem: &str) -> Result<Vec<Mesh>, SurveyError> {
    let err = |line: usize, reason: String| SurveyError::Element {
        path: file.to_owned(),
        element: format!("line {line}"),
        reason,
    };
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    // Per object: its name, the line it starts at and its faces (global indices).
    let mut objects: Vec<(Option<String>, usize, Vec<(usize, Vec<usize>)>)> = vec![(None, 1, vec![])];
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let xyz: Vec<f64> = tokens.take(3).map(|t| t.parse::<f64>().unwrap_or(f64::NAN)).collect();
                match xyz.as_slice() {
                    [x, y, z] if xyz.iter().all(|c| c.is_finite()) => vertices.push([*x, *y, *z]),
                    _ => return Err(err(n + 1, format!("{line:?}: a vertex is `v x y z` (three numbers)"))),
                }
            }
            Some("f") => {
                let mut face = Vec::new();
                for t in tokens {
                    let i: i64 = t
                        .split('/')
                        .next()
                        .unwrap_or("")
                        .parse()
                        .map_err(|_| err(n + 1, format!("{t:?} is not a vertex index")))?;
                    let idx = if i > 0 { i - 1 } else { vertices.len() as i64 + i };
                    if i == 0 || idx < 0 {
                        return Err(err(n + 1, format!("vertex index {i} is out of range")));
                    }
                    face.push(idx as usize);
                }
                if face.len() < 3 {
                    return Err(err(n + 1, "a face needs at least 3 vertices".into()));
                }
                if let Some(o) = objects.last_mut() {
                    o.2.push((n + 1, face));
                }
            }
            Some("o") => {
                let name = line[1..].trim().to_string();
                if objects.last().is_some_and(|o| o.2.is_empty()) {
                    objects.pop();
                }
                objects.push((Some(name), n + 1, vec![]));
            }
            _ => {}
        }
    }
    objects.retain(|o| !o.2.is_empty());
    let single = objects.len() == 1;
    let file_name = file.file_name().map_or_else(String::new, |f| f.to_string_lossy().into_owned());
    let mut meshes = Vec::with_capacity(objects.len());
    for (name, line, faces) in objects {
        let id = match (&name, single) {
            (Some(name), false) if !name.is_empty() => name.clone(),
            (_, false) => format!("{stem}.{}", meshes.len()),
            (_, true) => stem.to_string(),
        };
        // The file's name is the error's own; the element names the object in it.
        let element = match &name {
            Some(nm) => format!("object {nm:?} at line {line}"),
            None => file_name.clone(),
        };
        let mut triangles = Vec::new();
        for (at, f) in &faces {
            if let Some(&bad) = f.iter().find(|&&i| i >= vertices.len()) {
                return Err(SurveyError::Element {
                    path: file.to_owned(),
                    element: format!("{element}, line {at}"),
                    reason: format!("a face uses vertex {} of {}", bad + 1, vertices.len()),
                });
            }
            for k in 1..f.len() - 1 {
                triangles.push([f[0], f[k], f[k + 1]]);
            }
        }
        let stone = Stone { id, element, material: None, depth_m: None };
        meshes.push(Mesh { stone, file: file.to_owned(), vertices: vertices.clone(), triangles });
    }
    Ok(meshes)
}

/// The meshes of an STL file: binary (84 + 50 N bytes: one mesh) or ASCII (one per
/// `solid`).
fn read_stl(file: &Path, bytes: &[u8], stem: &str) -> Result<Vec<Mesh>, SurveyError> {
    let file_name = file.file_name().map_or_else(String::new, |f| f.to_string_lossy().into_owned());
    let one = |vertices: Vec<[f64; 3]>| {
        let triangles = (0..vertices.len() / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        let stone = Stone { id: stem.to_string(), element: file_name.clone(), material: None, depth_m: None };
        Mesh { stone, file: file.to_owned(), vertices, triangles }
    };
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * n {
            let f = |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as f64;
            let vertices = (0..n)
                .flat_map(|t| (0..3).map(move |k| 84 + 50 * t + 12 + 12 * k))
                .map(|at| [f(at), f(at + 4), f(at + 8)])
                .collect();
            return Ok(vec![one(vertices)]);
        }
    }
    let text = String::from_utf8_lossy(bytes);
    if !text.trim_start().starts_with("solid") {
        return Err(SurveyError::File {
            path: file.to_owned(),
            reason: "neither ASCII STL (starting with `solid`) nor binary STL (84 + 50 × N bytes)".into(),
        });
    }
    let err = |line: usize, reason: String| SurveyError::Element {
        path: file.to_owned(),
        element: format!("line {line}"),
        reason,
    };
    // Per solid: its name, its line, its vertices (three per facet).
    let mut solids: Vec<(String, usize, Vec<[f64; 3]>)> = Vec::new();
    let mut facet: Vec<[f64; 3]> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let mut tokens = raw.split_whitespace();
        match tokens.next() {
            Some("solid") => solids.push((tokens.collect::<Vec<_>>().join(" "), n + 1, vec![])),
            Some("vertex") => {
                let xyz: Vec<f64> = tokens.take(3).map(|t| t.parse::<f64>().unwrap_or(f64::NAN)).collect();
                match xyz.as_slice() {
                    [x, y, z] if xyz.iter().all(|c| c.is_finite()) => facet.push([*x, *y, *z]),
                    _ => return Err(err(n + 1, format!("{:?}: a vertex is `vertex x y z`", raw.trim()))),
                }
            }
            Some("endloop") => {
                if facet.len() != 3 {
                    return Err(err(n + 1, format!("a facet has {} vertices, not 3", facet.len())));
                }
                let solid = solids.last_mut().ok_or_else(|| err(n + 1, "a facet outside any solid".into()))?;
                solid.2.append(&mut facet);
            }
            _ => {}
        }
    }
    solids.retain(|s| !s.2.is_empty());
    let single = solids.len() == 1;
    Ok(solids
        .into_iter()
        .enumerate()
        .map(|(k, (name, line, vertices))| {
            let mut m = one(vertices);
            if !single {
                m.stone.id = if name.is_empty() { format!("{stem}.{k}") } else { name.clone() };
                m.stone.element = format!("{file_name}, solid {name:?} at line {line}");
            }
            m
        })
        .collect())
}

/// The vertices the triangles use, those with the same coordinates merged (in order of
/// first use), and the triangles on them.
fn weld(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let mut index: BTreeMap<[u64; 3], usize> = BTreeMap::new();
    let mut out = Vec::new();
    let tris = triangles
        .iter()
        .map(|t| {
            t.map(|i| {
                let v = vertices[i];
                *index.entry(v.map(|c| (c + 0.0).to_bits())).or_insert_with(|| {
                    out.push(v);
                    out.len() - 1
                })
            })
        })
        .collect();
    (out, tris)
}

/// Refuses a mesh that is not closed and consistently oriented: every edge of a triangle
/// must be met once in the other direction by another triangle. Degenerate triangles (two
/// corners the same) are left out. The message names an edge at fault by its two corners'
/// coordinates (`vertices`, as the file gives them: the vertices are welded and numbered
/// anew, so the file's own numbering is not at hand).
fn check_closed(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> Result<(), String> {
    let at = |i: usize| format!("({}, {}, {})", vertices[i][0], vertices[i][1], vertices[i][2]);
    let mut directed: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for t in triangles.iter().filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    if directed.len() < 6 {
        return Err("the mesh has fewer than 4 faces: not a closed surface".into());
    }
    if let Some(((a, b), _)) = directed.iter().find(|(_, &n)| n > 1) {
        return Err(format!(
            "the edge from {} to {} is used twice in the same direction: the faces are not consistently oriented (or \
             the surface is not a manifold)",
            at(*a),
            at(*b)
        ));
    }
    let open: Vec<_> = directed.keys().filter(|(a, b)| !directed.contains_key(&(*b, *a))).collect();
    if let Some((a, b)) = open.first() {
        return Err(format!(
            "the mesh is not closed: {} edges belong to one face only (the first from {} to {})",
            open.len(),
            at(*a),
            at(*b)
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        (v, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    }

    #[test]
    fn a_tetrahedron_is_closed_with_a_sixth_of_a_unit() {
        let (v, t) = tetrahedron();
        check_closed(&v, &t).unwrap();
        let pts: Vec<Vec3> = v.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        assert!((mesh_mass_properties(&pts, &t, 1.0).volume - 1.0 / 6.0).abs() < 1e-15);
        let open = check_closed(&v, &t[..3]).unwrap_err();
        assert!(open.contains("not closed") && open.contains("from (1, 0, 0) to (0, 0, 1)"), "{open}");
        let flipped = [t[0], t[1], t[2], [1, 3, 2]];
        assert!(check_closed(&v, &flipped).unwrap_err().contains("oriented"));
    }
}
