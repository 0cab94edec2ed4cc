//! Running a study: one realization per work item, in parallel, into rows.

use super::{point_label, ProtocolKind, Study};
use crate::ensemble::row::{RealizationRow, Status};
use crate::ensemble::{self, Item, Shard};
use crate::generator::generate;
use crate::loading::lateral::{run_lateral, LateralError};
use crate::loading::tilt::{run_tilt, TiltError};
use crate::units::m_to_cm;
use std::time::Instant;

/// Runs one realization of a study: generate the layout of its group and sweep point from
/// `(seed, realization)`, run the protocol, and record the outcome. Never panics on a bad
/// realization: failures become rows with their [`Status`].
pub fn run_item(study: &Study, item: &Item) -> RealizationRow {
    let t0 = Instant::now();
    let group = &study.groups[item.group];
    let wall = &group.walls[item.point];
    let base = RealizationRow {
        index: item.index as u64,
        study: study.name.clone(),
        group: group.name.clone(),
        point: item.point as u64,
        sweep: point_label(&study.points[item.point]),
        seed: study.seed,
        realization: item.realization,
        status: Status::LayoutFailed,
        error: String::new(),
        blocks: 0,
        collapse_angle_deg: None,
        first_unstable_deg: None,
        collapse_reason: String::new(),
        mechanism: String::new(),
        joint: String::new(),
        moving_blocks: 0,
        tilt_deg: vec![],
        disp_top_left_cm: vec![],
        disp_top_centre_cm: vec![],
        disp_top_right_cm: vec![],
        lateral_disp_left_cm: None,
        lateral_disp_centre_cm: None,
        lateral_disp_right_cm: None,
        lateral_disp_max_cm: None,
        lateral_drift: None,
        steps: 0,
        dt_s: 0.0,
        wall_time_s: 0.0,
    };
    let layout = match generate(wall, study.seed, item.realization).and_then(|g| g.check()) {
        Ok(l) => l,
        Err(e) => {
            let mut r = RealizationRow::failed(base, Status::LayoutFailed, e.to_string());
            r.wall_time_s = t0.elapsed().as_secs_f64();
            return r;
        }
    };
    let mut row = RealizationRow { blocks: layout.blocks.len() as u64, ..base };
    match study.protocol {
        ProtocolKind::Tilt => match run_tilt(&layout, study.solver, &study.tilt) {
            Ok(t) => {
                row.status = if t.first_unstable_deg.is_some() { Status::Collapsed } else { Status::Stood };
                row.collapse_angle_deg = t.first_unstable_deg.map(|_| t.collapse_angle_deg);
                row.first_unstable_deg = t.first_unstable_deg;
                row.collapse_reason = t.collapse_reason.map(|r| format!("{r:?}").to_lowercase()).unwrap_or_default();
                row.mechanism = format!("{:?}", t.mechanism.kind).to_lowercase();
                row.joint = t.mechanism.joint.clone();
                row.moving_blocks = t.mechanism.blocks.len() as u64;
                let find = |name: &str| t.monitors.iter().position(|m| m == name);
                let (il, ic, ir) = (find("top_left"), find("top_centre"), find("top_right"));
                for inc in t.increments.iter().filter(|i| i.stable) {
                    row.tilt_deg.push(inc.alpha_deg);
                    let get = |i: Option<usize>| i.map_or(f64::NAN, |i| m_to_cm(inc.displacement_m[i]));
                    row.disp_top_left_cm.push(get(il));
                    row.disp_top_centre_cm.push(get(ic));
                    row.disp_top_right_cm.push(get(ir));
                }
                row.steps = t.steps;
                row.dt_s = t.dt_s;
            }
            Err(TiltError::NoInitialEquilibrium { steps, ratio }) => {
                row.status = Status::NoInitialEquilibrium;
                row.error =
                    format!("no equilibrium at alpha = 0 within {steps} steps (unbalanced-force ratio {ratio:.3e})");
            }
            Err(TiltError::Dem(e)) => {
                row.status = Status::BlewUp;
                row.error = e.to_string();
            }
            Err(e) => {
                row.status = Status::BlewUp;
                row.error = e.to_string();
            }
        },
        ProtocolKind::Lateral => match run_lateral(&layout, study.solver, &study.lateral) {
            Ok(r) => {
                row.steps = r.steps;
                row.dt_s = r.dt_s;
                match &r.collapse_reason {
                    None => {
                        row.status = Status::Stood;
                        let find = |name: &str| {
                            r.monitors.iter().position(|m| m == name).map(|i| m_to_cm(r.displacement_m[i]))
                        };
                        row.lateral_disp_left_cm = find("top_left");
                        row.lateral_disp_centre_cm = find("top_centre");
                        row.lateral_disp_right_cm = find("top_right");
                        row.lateral_disp_max_cm = Some(m_to_cm(r.max_displacement_m));
                        row.lateral_drift = Some(r.drift);
                    }
                    Some(why) => {
                        row.status = Status::Collapsed;
                        row.collapse_reason = why.clone();
                        row.error = format!(
                            "collapsed under the lateral load ({why}): top displacement {:.2} cm when stopped",
                            m_to_cm(r.max_displacement_m)
                        );
                    }
                }
            }
            Err(LateralError::NoInitialEquilibrium { steps, ratio }) => {
                row.status = Status::NoInitialEquilibrium;
                row.error =
                    format!("no equilibrium under gravity within {steps} steps (unbalanced-force ratio {ratio:.3e})");
            }
            Err(e) => {
                row.status = Status::BlewUp;
                row.error = e.to_string();
            }
        },
    }
    row.wall_time_s = t0.elapsed().as_secs_f64();
    row
}

/// Runs the items of a shard of a study in parallel on the current rayon pool; rows in item
/// order.
///
/// Items are scheduled longest first, by the number of blocks of their layout (generating a
/// layout takes about a millisecond; the DEM run grows with the blocks), so that the
/// expensive walls do not run last on one thread while the others idle.
pub fn run_study(study: &Study, shard: Shard) -> Vec<RealizationRow> {
    let items = shard.select(&study.items());
    let cost: Vec<f64> = items
        .iter()
        .map(|it| {
            generate(&study.groups[it.group].walls[it.point], study.seed, it.realization)
                .map_or(0.0, |g| g.layout.blocks.len() as f64)
        })
        .collect();
    ensemble::run_scheduled(&items, &cost, &study.name, |it| run_item(study, it))
}

/// What a run directory holds besides its tables: enough to merge shards.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    /// The study file as given on the command line.
    pub study: std::path::PathBuf,
    /// Realizations per group and point actually run.
    pub realizations: u64,
    /// This shard, 1-based `K/N` (`1/1` for a whole run).
    pub shard: String,
    /// Items of the whole study.
    pub total_items: usize,
    /// Items in this directory.
    pub items: usize,
}

/// Errors of running or merging a study's outputs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// A table.
    #[error(transparent)]
    Table(#[from] crate::io::table::TableError),
    /// The report.
    #[error(transparent)]
    Report(#[from] super::summary::ReportError),
    /// A file.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Shards that do not fit together.
    #[error("merge: {0}")]
    Merge(String),
}

fn write_manifest(dir: &std::path::Path, m: &Manifest) -> Result<(), RunError> {
    let path = dir.join("manifest.json");
    let text =
        serde_json::to_string_pretty(m).map_err(|e| RunError::File { path: path.clone(), message: e.to_string() })?;
    std::fs::write(&path, text).map_err(|e| RunError::File { path, message: e.to_string() })
}

/// Writes a run's outputs into `dir` (created if needed): the tables and the manifest, and,
/// for a complete run, `summary.csv`, `report.md` and the plots. Returns the comparison
/// text for a complete run.
///
/// # Errors
/// [`RunError`] naming the file.
pub fn write_outputs(
    study: &Study,
    study_arg: &std::path::Path,
    shard: Shard,
    rows: &[RealizationRow],
    dir: &std::path::Path,
) -> Result<Option<String>, RunError> {
    std::fs::create_dir_all(dir).map_err(|e| RunError::File { path: dir.to_owned(), message: e.to_string() })?;
    crate::io::table::write_realizations(rows, dir)?;
    write_manifest(
        dir,
        &Manifest {
            study: study_arg.to_owned(),
            realizations: study.realizations,
            shard: format!("{}/{}", shard.k + 1, shard.n),
            total_items: study.items().len(),
            items: rows.len(),
        },
    )?;
    if shard.n == 1 {
        Ok(Some(super::report::write_report(study, rows, dir)?))
    } else {
        Ok(None)
    }
}

/// Reads shard directories, checks that they are the shards of one run and cover every
/// item exactly once, and returns the manifest of the first and the rows in item order.
///
/// # Errors
/// [`RunError::Merge`] naming what does not fit.
pub fn read_shards(dirs: &[std::path::PathBuf]) -> Result<(Manifest, Vec<RealizationRow>), RunError> {
    let mut first: Option<Manifest> = None;
    let mut rows = Vec::new();
    for d in dirs {
        let mpath = d.join("manifest.json");
        let text = std::fs::read_to_string(&mpath)
            .map_err(|e| RunError::File { path: mpath.clone(), message: e.to_string() })?;
        let m: Manifest =
            serde_json::from_str(&text).map_err(|e| RunError::File { path: mpath.clone(), message: e.to_string() })?;
        if let Some(f) = &first {
            if f.study != m.study || f.realizations != m.realizations || f.total_items != m.total_items {
                return Err(RunError::Merge(format!("{} is from another run than {}", d.display(), dirs[0].display())));
            }
        } else {
            first = Some(m.clone());
        }
        let part = crate::io::table::read_realizations(&d.join("realizations.parquet"))?;
        if part.len() != m.items {
            return Err(RunError::Merge(format!(
                "{}: manifest says {} items, table has {}",
                d.display(),
                m.items,
                part.len()
            )));
        }
        rows.extend(part);
    }
    let first = first.ok_or_else(|| RunError::Merge("no shard directories given".into()))?;
    rows.sort_by_key(|r| r.index);
    for (i, r) in rows.iter().enumerate() {
        if r.index as usize != i {
            return Err(RunError::Merge(format!(
                "item {} is {} (the shards must cover items 0..{} exactly once)",
                i,
                if (r.index as usize) < i { "duplicated" } else { "missing" },
                first.total_items
            )));
        }
    }
    if rows.len() != first.total_items {
        return Err(RunError::Merge(format!("{} of {} items present", rows.len(), first.total_items)));
    }
    Ok((first, rows))
}
