//! The extended study: the study a discrepancy analysis ends with, written as files that
//! `drystone run` runs as the extended model.
//!
//! ```text
//! DIR/extended_study.toml      the study, every group with the named effect at its fitted
//!                              values (a comment gives each parameter's interval)
//! DIR/walls/GROUP.toml         each group's wall, its overrides applied, every named
//!                              distribution it uses written inline
//! DIR/data/*.csv               the measured data the analysis used
//! ```
//!
//! The directory is self-contained (effect files the study uses are copied to `DIR/effects/`):
//! it can be moved, and `drystone run
//! DIR/extended_study.toml` gives the ensemble the analysis reported for the extended model
//! at the same seed.

use super::spec::{EffectsSpec, GroupSpec, MeasuredSpec, ProtocolKind, StudySpec};
use super::Study;
use crate::effects::Effect;
use crate::generator::DistributionSpec;
use crate::io::FileError;
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

pub use crate::discrepancy::FittedParameter;

/// Errors of writing the extended study.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExtendError {
    /// A file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A wall or distribution could not be read or written.
    #[error("{0}")]
    Wall(String),
}

fn effects_spec(effects: &[Effect]) -> EffectsSpec {
    effects
        .iter()
        .map(|e| {
            let values: BTreeMap<String, f64> =
                e.def.parameters.iter().zip(&e.values).map(|(p, v)| (p.name.clone(), *v)).collect();
            (e.name().to_string(), values)
        })
        .collect()
}

/// The wall of a group as a self-contained TOML: its overrides applied, every named
/// distribution inline.
fn wall_text(study: &Study, group: usize) -> Result<String, ExtendError> {
    let g = &study.groups[group];
    let Some(mut spec) = g.spec.clone() else {
        return Err(ExtendError::Wall(format!(
            "group {}: a surveyed group has no wall description to extend (its wall is its survey, {})",
            g.name,
            g.wall_path.display()
        )));
    };
    if let Some(w) = g.walls.first() {
        for d in w.distributions() {
            if d.source.as_os_str().is_empty() || d.source == g.wall_path || spec.distributions.contains_key(&d.name) {
                continue;
            }
            let ds = DistributionSpec::from_file(&d.source).map_err(|e| ExtendError::Wall(e.to_string()))?;
            spec.distributions.insert(d.name.clone(), ds);
        }
    }
    Ok(spec.to_toml())
}

/// Writes the extended study of `study` into `dir`: every group runs with its own effects
/// and then `extra` (the effects the analysis named, at their fitted values); `fitted`
/// documents them in a comment. Returns the study file's path.
///
/// # Errors
/// [`ExtendError`] naming the file.
pub fn write_extended(
    study: &Study,
    extra: &[Effect],
    fitted: &[FittedParameter],
    note: &str,
    dir: &Path,
) -> Result<PathBuf, ExtendError> {
    for sub in ["walls", "data"] {
        let d = dir.join(sub);
        std::fs::create_dir_all(&d).map_err(FileError::at(&d))?;
    }
    let mut effect_files = Vec::new();
    for f in study.inputs.iter().filter(|f| f.role == super::provenance::InputRole::Effect) {
        let name = f.path.rsplit('/').next().unwrap_or("effect.toml");
        let d = dir.join("effects");
        std::fs::create_dir_all(&d).map_err(FileError::at(&d))?;
        let p = d.join(name);
        std::fs::write(&p, &f.text).map_err(FileError::at(&p))?;
        effect_files.push(PathBuf::from(format!("effects/{name}")));
    }
    let mut groups = Vec::new();
    for (i, g) in study.groups.iter().enumerate() {
        let wall = format!("walls/{}.toml", g.name);
        let p = dir.join(&wall);
        std::fs::write(&p, wall_text(study, i)?).map_err(FileError::at(&p))?;
        let mut effects = effects_spec(&g.effects);
        effects.extend(effects_spec(extra));
        groups.push(GroupSpec {
            name: g.name.clone(),
            wall: Some(PathBuf::from(wall)),
            survey: None,
            import: None,
            measured_group: Some(g.measured_group.clone()),
            overrides: BTreeMap::new(),
            realizations: g.realizations,
            effects,
            sigma0_mpa: None,
            history: None,
            specimens: vec![],
        });
    }
    let mut c = String::from("specimen,group,collapse_angle_deg\n");
    for m in &study.measured.collapse {
        let _ = writeln!(c, "{},{},{}", m.specimen, m.group, m.collapse_angle_deg);
    }
    let mut d = String::from("specimen,group,measure,tilt_deg,displacement_cm\n");
    for m in &study.measured.displacement {
        let _ = writeln!(d, "{},{},{},{},{}", m.specimen, m.group, m.measure, m.tilt_deg, m.displacement_cm);
    }
    let mut measured = MeasuredSpec {
        collapse: None,
        displacement: None,
        mechanism: None,
        paper_dem: None,
        walls: None,
        envelopes: None,
        crackmaps: None,
        curves: None,
    };
    if !study.measured.mechanism.is_empty() {
        let p = dir.join("data").join(crate::io::measured::MECHANISM_FILE);
        std::fs::write(&p, crate::io::measured::mechanism_csv(&study.measured.mechanism)).map_err(FileError::at(&p))?;
        measured.mechanism = Some(PathBuf::from(format!("data/{}", crate::io::measured::MECHANISM_FILE)));
    }
    for (name, text, n) in [
        ("tilting_table_collapse.csv", c, study.measured.collapse.len()),
        ("tilting_table_displacement.csv", d, study.measured.displacement.len()),
    ] {
        if n == 0 {
            continue;
        }
        let p = dir.join("data").join(name);
        std::fs::write(&p, text).map_err(FileError::at(&p))?;
        let rel = Some(PathBuf::from(format!("data/{name}")));
        if name.contains("collapse") {
            measured.collapse = rel;
        } else {
            measured.displacement = rel;
        }
    }
    let mut spec = StudySpec {
        version: 1,
        name: format!("{}_extended", study.name),
        description: format!("{} Extended: {note}", study.description.trim()),
        seed: study.seed,
        realizations: study.realizations,
        protocol: ProtocolKind::default(),
        tilt: TiltParams::default(),
        lateral: LateralParams::default(),
        shake: None,
        in_plane: None,
        compression: None,
        solver: study.solver,
        groups,
        sweep: BTreeMap::new(),
        measured: (measured.collapse.is_some() || measured.displacement.is_some() || measured.mechanism.is_some())
            .then_some(measured),
        paper: None,
        calibrate: vec![],
        discrepancy: Some(study.discrepancy.clone()),
        effects: BTreeMap::new(),
        effect_files,
    };
    study.protocol.write_into(&mut spec);
    let mut t = String::new();
    let _ = writeln!(t, "# The extended model of `{}`: {note}", study.name);
    for p in fitted {
        let _ = writeln!(t, "#   {} = {:.4e}, interval [{:.4e}, {:.4e}]", p.name, p.value, p.interval.0, p.interval.1);
    }
    let _ = writeln!(t, "# Run it with: drystone run extended_study.toml (in this directory)\n");
    t += &toml::to_string_pretty(&spec).map_err(|e| ExtendError::Wall(e.to_string()))?;
    let p = dir.join("extended_study.toml");
    std::fs::write(&p, t).map_err(FileError::at(&p))?;
    Ok(p)
}
