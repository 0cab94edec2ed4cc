//! The best follow-up written as a study a laboratory can run and fill in: the first
//! campaign's study with the follow-up's walls as an extra group where it has new walls,
//! its measured files (the first campaign's, to which the follow-up's rows are added), and
//! empty templates of the follow-up's rows in the formats `[measured]` reads.

use crate::discrepancy::design::{FollowUp, FollowUpKind, GroupWall, Plan};
use crate::discrepancy::Observable;
use crate::discrepancy::Setup;
use crate::discrepancy::{DiscrepancyError, Run};
use crate::io::measured::MECHANISM_FILE;
use crate::study::Study;
use std::path::{Path, PathBuf};

/// The directory of the templates in the follow-up's directory.
pub const TEMPLATE_DIR: &str = "templates";

/// Header of a measured collapse-angle file.
const COLLAPSE_HEADER: &str = "specimen,group,collapse_angle_deg";
/// Header of a measured displacement file.
const DISPLACEMENT_HEADER: &str = "specimen,group,measure,tilt_deg,displacement_cm";
/// Header of a measured mechanism file.
const MECHANISM_HEADER: &str =
    "specimen,group,failure_height_fraction,failure_height_low,failure_height_high,kind,start,extent_fraction,source";

/// The files of a written follow-up.
#[derive(Debug, Clone, PartialEq)]
pub struct FollowUpFiles {
    /// The study (`followup_study.toml`).
    pub study: PathBuf,
    /// The measured files the study reads (the first campaign's rows): collapse,
    /// displacement, mechanism.
    pub measured: [PathBuf; 3],
    /// The templates of the follow-up's rows: collapse, displacement, mechanism.
    pub templates: [PathBuf; 3],
    /// The specimens to test, `(specimen, group)`.
    pub specimens: Vec<(String, String)>,
}

fn io(path: &Path, e: std::io::Error) -> crate::discrepancy::DiscrepancyError {
    crate::discrepancy::DiscrepancyError::Design {
        specimen: path.display().to_string(),
        observable: format!("cannot be written: {e}"),
    }
}

fn write(path: &Path, text: &str) -> Result<(), crate::discrepancy::DiscrepancyError> {
    if let Some(d) = path.parent() {
        std::fs::create_dir_all(d).map_err(|e| io(d, e))?;
    }
    std::fs::write(path, text).map_err(|e| io(path, e))
}

/// The first campaign's measured file `kind`, copied, or a header-only file.
fn copy_or_header(from: Option<PathBuf>, to: &Path, header: &str) -> Result<(), crate::discrepancy::DiscrepancyError> {
    match from {
        Some(f) => {
            let text = std::fs::read_to_string(&f).map_err(|e| io(&f, e))?;
            write(to, &text)
        }
        None => write(to, &format!("{header}\n")),
    }
}

/// Writes `plan`'s best follow-up for `study` into `dir` (see the module documentation):
/// `followup_study.toml`, `walls/` (every group's wall description with its overrides
/// applied, and the new walls), `distributions/` (a copy of the named distributions the
/// walls use), `measured/` (the first campaign's files: the follow-up's rows are added
/// to them), `templates/` (the follow-up's rows to fill in: header-only collapse and
/// displacement files, the mechanism file with a row per specimen and empty fields) and
/// `README.md` (what to test and read). `specimens` new specimens are named
/// `<group>_F1`, `<group>_F2`, ….
///
/// `measured_dir` is the directory the first campaign's data were read from instead of the
/// study's `[measured]` files (`--measured DIR`, its files named as `drystone synthesize`
/// writes them): `measured/` then copies its files (a missing displacement or mechanism
/// file is written header-only, as the analysis read none); without it, the files the
/// study's `[measured]` table names.
///
/// # Errors
/// [`crate::discrepancy::DiscrepancyError::Design`] naming a file that cannot be read or
/// written; `None` in the plan is not an error (nothing is written, `Ok(None)`).
pub fn write_followup(
    study: &Study,
    plan: &Plan,
    dir: &Path,
    specimens: usize,
    measured_dir: Option<&Path>,
) -> Result<Option<FollowUpFiles>, crate::discrepancy::DiscrepancyError> {
    let Some(best) = plan.best() else { return Ok(None) };
    let f = &best.followup;
    let text = std::fs::read_to_string(&study.path).map_err(|e| io(&study.path, e))?;
    let mut doc: toml::Table =
        text.parse().map_err(|e: toml::de::Error| crate::discrepancy::DiscrepancyError::Design {
            specimen: study.path.display().to_string(),
            observable: e.to_string(),
        })?;
    let base = study.path.parent().map(Path::to_path_buf).unwrap_or_default();
    let abs = |p: &str| -> String {
        let p = base.join(p);
        std::fs::canonicalize(&p).unwrap_or(p).display().to_string()
    };
    doc.insert("name".into(), toml::Value::String(format!("{}_followup", study.name)));
    // Every group's wall, with its overrides applied, and the new one.
    let mut groups = Vec::new();
    for g in &study.groups {
        let file = format!("walls/{}.toml", g.name);
        let Some(spec) = &g.spec else {
            return Err(crate::discrepancy::DiscrepancyError::Design {
                specimen: g.name.clone(),
                observable: format!(
                    "a surveyed group ({}) has no wall description for a follow-up to copy",
                    g.wall_path.display()
                ),
            });
        };
        write(&dir.join(&file), &toml::to_string(spec).unwrap_or_default())?;
        let old = doc
            .get("groups")
            .and_then(|v| v.as_array())
            .and_then(|a| a.iter().find(|t| t.get("name").and_then(|n| n.as_str()) == Some(g.name.as_str())).cloned());
        let mut t = old.and_then(|v| v.as_table().cloned()).unwrap_or_default();
        t.insert("name".into(), toml::Value::String(g.name.clone()));
        t.insert("wall".into(), toml::Value::String(file));
        t.remove("overrides");
        groups.push(toml::Value::Table(t));
    }
    if let (Some(g), Some(spec)) = (&f.new_group, &f.new_spec) {
        let file = format!("walls/{}.toml", g.name);
        write(&dir.join(&file), &toml::to_string(spec).unwrap_or_default())?;
        let from = doc.get("groups").and_then(|v| v.as_array()).and_then(|a| {
            a.iter().find(|t| t.get("name").and_then(|n| n.as_str()) == Some(f.from_group.as_str())).cloned()
        });
        let mut t = from.and_then(|v| v.as_table().cloned()).unwrap_or_default();
        t.insert("name".into(), toml::Value::String(g.name.clone()));
        t.insert("wall".into(), toml::Value::String(file));
        t.remove("overrides");
        t.remove("measured_group");
        groups.push(toml::Value::Table(t));
    }
    doc.insert("groups".into(), toml::Value::Array(groups));
    if let Some(v) = doc.get_mut("effect_files").and_then(|v| v.as_array_mut()) {
        for p in v.iter_mut() {
            if let Some(s) = p.as_str() {
                *p = toml::Value::String(abs(s));
            }
        }
    }
    copy_distributions(study, dir)?;
    // The measured files: the first campaign's (those the analysis read: the measured
    // directory's when given, else the study's own), and the templates of the follow-up's
    // rows.
    let measured_spec = doc.get("measured").and_then(|v| v.as_table()).cloned().unwrap_or_default();
    let names = ["tilting_table_collapse.csv", "tilting_table_displacement.csv", MECHANISM_FILE];
    let original = |i: usize, key: &str| match measured_dir {
        // The collapse file is always read from the directory; the others when present.
        Some(m) => Some(m.join(names[i])).filter(|p| i == 0 || p.exists()),
        None => measured_spec.get(key).and_then(|v| v.as_str()).map(|s| base.join(s)),
    };
    let headers = [COLLAPSE_HEADER, DISPLACEMENT_HEADER, MECHANISM_HEADER];
    let measured = names.map(|n| dir.join("measured").join(n));
    let templates = names.map(|n| dir.join(TEMPLATE_DIR).join(n));
    for (i, key) in ["collapse", "displacement", "mechanism"].into_iter().enumerate() {
        copy_or_header(original(i, key), &measured[i], headers[i])?;
    }
    let mut m = measured_spec.clone();
    for (i, key) in ["collapse", "displacement", "mechanism"].into_iter().enumerate() {
        m.insert(key.into(), toml::Value::String(format!("measured/{}", names[i])));
    }
    if let Some(p) = measured_spec.get("paper_dem").and_then(|v| v.as_str()) {
        m.insert("paper_dem".into(), toml::Value::String(abs(p)));
    }
    doc.insert("measured".into(), toml::Value::Table(m));
    let specimens: Vec<(String, String)> =
        (1..=specimens).map(|i| (format!("{}_F{i}", f.group), f.group.clone())).collect();
    write(&templates[0], &format!("{COLLAPSE_HEADER}\n"))?;
    write(&templates[1], &format!("{DISPLACEMENT_HEADER}\n"))?;
    let mech_rows: String = if f.observables.iter().any(Observable::is_mechanism) {
        specimens.iter().map(|(s, g)| format!("{s},{g},,,,,,,\n")).collect()
    } else {
        String::new()
    };
    write(&templates[2], &format!("{MECHANISM_HEADER}\n{mech_rows}"))?;
    let header = format!(
        "# The follow-up designed by `drystone design` for study {}: {}.\n# Add the follow-up's rows (templates/) to measured/ and run `drystone discrepancy` on this study.\n",
        study.name, f.name
    );
    let study_file = dir.join("followup_study.toml");
    write(&study_file, &format!("{header}{}", toml::to_string(&doc).unwrap_or_default()))?;
    write(&dir.join("README.md"), &readme(study, plan, f, &specimens))?;
    Ok(Some(FollowUpFiles { study: study_file, measured, templates, specimens }))
}

/// Copies the named distributions the study's walls use (the first directory each wall's
/// `distributions/` search finds) into `dir/distributions/`, each file once.
///
/// # Errors
/// A directory or file that cannot be read, a file that cannot be written (named).
fn copy_distributions(study: &Study, dir: &Path) -> Result<(), crate::discrepancy::DiscrepancyError> {
    for g in &study.groups {
        let source = crate::generator::DistributionSource::default_for(&g.wall_path);
        for d in source.dirs.iter().take(1) {
            let entries = std::fs::read_dir(d).map_err(|e| io(d, e))?;
            for e in entries.flatten() {
                let p = e.path();
                if p.extension().is_some_and(|x| x == "toml") {
                    let to = dir.join("distributions").join(e.file_name());
                    if !to.exists() {
                        let text = std::fs::read_to_string(&p).map_err(|e| io(&p, e))?;
                        write(&to, &text)?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// What the laboratory reads on each specimen, as sentences.
fn readings(f: &FollowUp) -> Vec<String> {
    let mut out = Vec::new();
    if f.observables.iter().any(Observable::is_angle) {
        out.push("the collapse angle (degrees): `templates/tilting_table_collapse.csv`".to_string());
    }
    let disp: Vec<String> = f
        .observables
        .iter()
        .filter_map(|o| o.displacement().map(|(measure, tilt_deg)| format!("{} at {tilt_deg}°", measure.name())))
        .collect();
    if !disp.is_empty() {
        out.push(format!(
            "the top displacements (cm): {}: `templates/tilting_table_displacement.csv`",
            disp.join(", ")
        ));
    }
    if f.observables.iter().any(Observable::is_mechanism) {
        out.push(format!(
            "the failure mechanism: the failure height as a fraction of the wall's height with its reading interval \
             (the bed joint at the bottom of the moving part, ± half a course), the kind (toppling, sliding, bending, \
             mixed) and the start (end, centre, uniform, random): `templates/{MECHANISM_FILE}`"
        ));
    }
    out
}

fn readme(study: &Study, plan: &Plan, f: &FollowUp, specimens: &[(String, String)]) -> String {
    let mut s = format!("# Follow-up of {}\n\n", study.name);
    s += &format!("**{}** ({} specimens", f.name, specimens.len());
    if let Some(r) = &plan.reported {
        s += &format!(
            "): the probability that the cause is then named alone is {:.2} (95 % Monte Carlo interval {:.2}–{:.2}, \
             re-estimated on simulations independent of those that chose it; right, alone or shared: {:.2}).\n\n",
            r.chance.alone, r.interval.0, r.interval.1, r.chance.right
        );
    } else if let Some(b) = plan.best() {
        s += &format!(
            "): the probability that the cause is then named alone is {:.2} (right, alone or shared: {:.2}).\n\n",
            b.at_budget.alone, b.at_budget.right
        );
    } else {
        s += ").\n\n";
    }
    match f.kind {
        FollowUpKind::Height | FollowUpKind::Length | FollowUpKind::Restraint => {
            s += &format!(
                "Build the walls of group `{}` as `walls/{}.toml` describes them (the group `{}` of the first campaign with {}), and tilt them as the first campaign's.\n\n",
                f.group,
                f.group,
                f.from_group,
                match f.kind {
                    FollowUpKind::Height => "its height changed",
                    FollowUpKind::Length => "its length changed",
                    _ => "its end restraint changed",
                }
            );
        }
        _ => s += &format!("Build and tilt more walls of group `{}` as the first campaign's.\n\n", f.group),
    }
    s += "Specimens:";
    for (sp, g) in specimens {
        s += &format!(" `{sp}` ({g})");
    }
    s += "\n\nRead on each:\n\n";
    for r in readings(f) {
        s += &format!("- {r}\n");
    }
    s += "\nThen add the rows to the files under `measured/` (the first campaign's) and run\n`drystone discrepancy followup_study.toml`: both campaigns are analysed together, each specimen on its own wall.\n";
    s
}

/// The design's menu of follow-ups for a study's groups ([`crate::discrepancy::design::menu`]
/// on the study's walls).
///
/// # Errors
/// As [`crate::discrepancy::design::menu`].
pub fn menu(study: &Study, setup: &Setup, run: &Run) -> Result<Vec<FollowUp>, DiscrepancyError> {
    // A surveyed group has no wall description to edit: the menu's follow-ups are on the
    // described walls.
    let walls: Vec<GroupWall<'_>> = study
        .groups
        .iter()
        .filter_map(|g| g.spec.as_ref().map(|spec| GroupWall { name: &g.name, spec, wall_path: &g.wall_path }))
        .collect();
    crate::discrepancy::design::menu(&walls, setup, run)
}
