//! `drystone import`: a surveyed wall (a traced elevation or scanned stones) → a layout.

use anyhow::{bail, Context, Result};
use drystone::generator::spec::Batter;
use drystone::generator::Distribution;
use drystone::layout::{BaseSliding, MaterialSpec};
use drystone::survey::{
    import, surveyed_wall, ImportOptions, ImportedWall, LengthUnit, Section, SurveyFormat, SurveyMaterials, Uncertainty,
};
use std::path::PathBuf;
use std::process::ExitCode;

/// Options of `drystone import`.
#[derive(clap::Args)]
pub struct ImportArgs {
    /// The survey: a traced elevation (.svg, .geojson, .dxf) or scanned stones (.obj, .stl, or a
    /// folder of them, one stone per file or object).
    survey: PathBuf,
    /// Its format [default: by the extension; a folder: its files' extensions].
    #[arg(long, value_parser = |s: &str| s.parse::<SurveyFormat>())]
    format: Option<SurveyFormat>,
    /// Output layout file (.json, the format of `drystone generate --out`).
    #[arg(long)]
    out: PathBuf,
    /// Traced elevations: metres per drawing unit (SVG user unit; GeoJSON default 1). SVG
    /// needs it unless the drawing has a <line id="scale" data-length-m="…">, DXF unless
    /// its $INSUNITS is mm, cm or m.
    #[arg(long)]
    scale_m_per_unit: Option<f64>,
    /// Traced elevations: the wall's thickness at its base, m (every stone is a through stone).
    #[arg(long)]
    thickness_m: Option<f64>,
    /// Traced elevations: the wall's thickness at its top, m [default: the base thickness].
    #[arg(long)]
    top_thickness_m: Option<f64>,
    /// Traced elevations: which faces lean when the top is thinner: symmetric,
    /// vertical_negative_y or vertical_positive_y.
    #[arg(long, default_value = "symmetric", value_parser = parse_batter)]
    batter: Batter,
    /// Traced elevations: take a non-convex outline's convex hull (the volume added is
    /// reported) instead of refusing it.
    #[arg(long)]
    hull_nonconvex: bool,
    /// Scanned stones: the unit of the mesh coordinates (m, cm, mm) [default: m].
    #[arg(long, value_parser = |s: &str| s.parse::<LengthUnit>())]
    unit: Option<LengthUnit>,
    /// Scanned stones: the meshes have y up (default z up).
    #[arg(long)]
    y_up: bool,
    /// Scanned stones: the most vertices a stone's hull keeps; a hull with more becomes the
    /// hull of that many of its vertices, spread over it, and the volume it leaves out is
    /// reported (refused above 1 % of the hull's, naming the stone) [default: 1000, for
    /// contact detection's cost; see docs/survey.md].
    #[arg(long)]
    max_hull_vertices: Option<usize>,
    /// Scanned stones: keep every stone's full hull, whatever its number of vertices.
    #[arg(long, conflicts_with = "max_hull_vertices")]
    full_hull: bool,
    /// Materials file (TOML: [[materials]] with the layout's keys, stone_material,
    /// table_material); or give one material by the four flags below.
    #[arg(long, conflicts_with_all = ["density", "kn", "ks", "friction_deg"])]
    materials: Option<PathBuf>,
    /// Stone density, kg/m³.
    #[arg(long)]
    density: Option<f64>,
    /// Joint normal stiffness, Pa/m.
    #[arg(long)]
    kn: Option<f64>,
    /// Joint shear stiffness, Pa/m.
    #[arg(long)]
    ks: Option<f64>,
    /// Joint friction angle, degrees.
    #[arg(long)]
    friction_deg: Option<f64>,
    /// Joint cohesion, Pa (with the flags above).
    #[arg(long, default_value_t = 0.0)]
    cohesion_pa: f64,
    /// The base course on the table: free or held (against sliding).
    #[arg(long, default_value = "free", value_parser = parse_base)]
    base: BaseSliding,
    /// The layout's name [default: the survey's file name].
    #[arg(long)]
    name: Option<String>,
    /// Traced elevations: master seed of the survey's uncertainty; with it the layout is
    /// realization --realization of the ensemble around the survey (the tracing tolerance
    /// and the depths drawn), without it the survey as traced.
    #[arg(long)]
    seed: Option<u64>,
    /// Realization index (with --seed).
    #[arg(long, requires = "seed")]
    realization: Option<u64>,
    /// Tracing tolerance, m (with --seed): every traced corner moves by at most this [default: 0].
    #[arg(long, requires = "seed")]
    tolerance_m: Option<f64>,
    /// Each stone's depth into the wall from the traced (−y) face, m (with --seed): D (fixed)
    /// or A..B (uniform) [default: through stones].
    #[arg(long, requires = "seed", value_parser = |s: &str| Uncertainty::depth_from_text(s))]
    depth_m: Option<Distribution>,
}

fn parse_batter(s: &str) -> Result<Batter, String> {
    match s {
        "symmetric" => Ok(Batter::Symmetric),
        "vertical_negative_y" => Ok(Batter::VerticalNegativeY),
        "vertical_positive_y" => Ok(Batter::VerticalPositiveY),
        _ => Err(format!("unknown batter {s:?}: symmetric, vertical_negative_y or vertical_positive_y")),
    }
}

fn parse_base(s: &str) -> Result<BaseSliding, String> {
    match s {
        "free" => Ok(BaseSliding::Free),
        "held" => Ok(BaseSliding::Held),
        _ => Err(format!("unknown base restraint {s:?}: free or held")),
    }
}

/// The materials of the flags or the file.
fn materials(a: &ImportArgs) -> Result<SurveyMaterials> {
    if let Some(path) = &a.materials {
        return Ok(SurveyMaterials::from_file(path)?);
    }
    let (Some(density), Some(kn), Some(ks), Some(friction_deg)) = (a.density, a.kn, a.ks, a.friction_deg) else {
        bail!("the stones' material: give --materials FILE, or all of --density, --kn, --ks and --friction-deg");
    };
    Ok(SurveyMaterials::one(MaterialSpec {
        name: "stone".into(),
        density_kg_per_m3: density,
        kn_pa_per_m: kn,
        ks_pa_per_m: ks,
        friction_deg,
        cohesion_pa: a.cohesion_pa,
        tensile_strength_pa: 0.0,
        closure: Default::default(),
    }))
}

/// `drystone import`: reads the survey, writes the layout and prints what it holds.
///
/// # Errors
/// Bad options, a survey that cannot be read or made a layout (naming the file and the
/// element at fault), an output that cannot be written.
pub fn command(a: ImportArgs) -> Result<ExitCode> {
    if a.out.extension().and_then(|e| e.to_str()) != Some("json") {
        bail!("--out {}: a layout is a .json file", a.out.display());
    }
    super::check_writable(&a.out)?;
    let section = match (a.thickness_m, a.top_thickness_m) {
        (Some(b), top) => Some(Section { base_m: b, top_m: top.unwrap_or(b), batter: a.batter }),
        (None, Some(_)) => bail!("--top-thickness-m needs --thickness-m (the base thickness)"),
        (None, None) => None,
    };
    let options = ImportOptions {
        format: a.format,
        scale_m_per_unit: a.scale_m_per_unit,
        section,
        hull_nonconvex: a.hull_nonconvex,
        unit: a.unit,
        y_up: a.y_up,
        materials: materials(&a)?,
        base_sliding: a.base,
        name: a.name.clone(),
        max_hull_vertices: a.max_hull_vertices,
        full_hull: a.full_hull,
    };
    if let Some(seed) = a.seed {
        return realization(&a, &options, seed);
    }
    let wall = import(&a.survey, &options)?;
    std::fs::write(&a.out, wall.layout.to_json()).with_context(|| format!("writing {}", a.out.display()))?;
    summary(&wall);
    out!("wrote             {}", a.out.display());
    Ok(ExitCode::SUCCESS)
}

/// `drystone import --seed`: realization `--realization` of the ensemble around the survey
/// written as the layout, with how its outlines were drawn.
fn realization(a: &ImportArgs, options: &ImportOptions, seed: u64) -> Result<ExitCode> {
    let u = Uncertainty { tolerance_m: a.tolerance_m.unwrap_or(0.0), depth: a.depth_m.clone() };
    let wall = surveyed_wall(&a.survey, options, &u)?;
    let traced = wall.traced.as_deref().context("a surveyed wall has its trace")?;
    if traced.scanned.is_some() {
        bail!(
            "--seed {seed}: {}: scanned stones have no uncertainty drawn per realization (every realization is the \
             survey as scanned): import them without --seed",
            a.survey.display()
        );
    }
    let r = a.realization.unwrap_or(0);
    let (g, report) = drystone::generator::traced::generate(&wall, traced, seed, r)?;
    g.check().with_context(|| format!("{}: realization {r}", a.survey.display()))?;
    std::fs::write(&a.out, g.layout.to_json()).with_context(|| format!("writing {}", a.out.display()))?;
    let cores = g.pieces.iter().filter(|p| p.part == drystone::generator::SectionPart::Hearting).count();
    out!("survey            {}", a.survey.display());
    out!("seed, realization {seed}, {r}");
    out!("tolerance         {} m", u.tolerance_m);
    out!("depth             {}", u.depth.as_ref().map_or_else(|| "through stones".to_string(), |d| d.name.clone()));
    out!("stones            {} ({cores} with a core piece behind)", traced.stones.len());
    out!("blocks            {}", g.layout.blocks.len());
    out!("total volume      {:.6e} m3", g.volume());
    out!(
        "outlines drawn    {} attempt(s){}, largest corner move {:.3e} m",
        report.attempts,
        if report.affine { ", affine fallback" } else { "" },
        report.max_displacement_m
    );
    if let (true, Some(why)) = (report.affine, &report.refused) {
        out!("last refused draw {why}");
    }
    out!("wrote             {}", a.out.display());
    Ok(ExitCode::SUCCESS)
}

/// Prints what the import made: counts, volumes, the wall's size, and per stone the hull's
/// volume against the stone's where a hull was taken.
fn summary(w: &ImportedWall) {
    let hulled = w.stones.iter().filter(|s| s.hulled).count();
    out!("survey            {} ({})", w.source.display(), w.format.name());
    if let Some((k, from)) = &w.scale {
        out!("scale             {} m per unit ({from})", drystone::survey::short_number(*k));
    }
    let elements: std::collections::BTreeSet<&str> = w.stones.iter().map(|s| s.element.as_str()).collect();
    out!("stones read       {}", elements.len());
    out!("blocks made       {} ({hulled} convex hulls)", w.layout.blocks.len());
    out!("on the table      {} blocks", w.on_table());
    let meshes = !w.format.is_elevation();
    out!("total volume      {:.6e} m3", w.volume_m3());
    out!("added by hulls    {:.6e} m3", w.added_m3());
    if meshes {
        let own: f64 = w.stones.iter().map(|s| s.survey_volume_m3).sum();
        out!("meshes' volume    {own:.6e} m3 (the blocks' mass and inertia are the closed meshes')");
    }
    out!("wall length       {:.4} m", w.length_m);
    out!("wall height       {:.4} m", w.height_m);
    let simplified: Vec<_> = w.stones.iter().filter_map(|s| s.simplified.map(|h| (s, h))).collect();
    if !simplified.is_empty() {
        out!(
            "hulls simplified  {} to the vertex budget (--max-hull-vertices; --full-hull keeps them)",
            simplified.len()
        );
        out!("{:<20} {:>14} {:>14} {:>14}", "stone", "full hull", "kept", "volume -%");
        for (s, h) in simplified {
            out!(
                "{:<20} {:>14} {:>14} {:>14.4}",
                s.id,
                format!("{} vertices", h.full_vertices),
                format!("{} vertices", h.kept_vertices),
                100.0 * h.volume_change
            );
        }
    }
    if hulled > 0 {
        let own = if meshes { "mesh m3" } else { "stone m3" };
        out!("{:<20} {:>14} {:>14} {:>9}", "stone", "hull m3", own, "added %");
        for s in w.stones.iter().filter(|s| s.hulled) {
            out!(
                "{:<20} {:>14.6e} {:>14.6e} {:>9.2}",
                s.id,
                s.block_volume_m3,
                s.survey_volume_m3,
                100.0 * s.added_m3() / s.survey_volume_m3
            );
        }
    }
}
