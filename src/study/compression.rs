//! The vertical compression test's study (`protocol = "compression"`): its keys of the study
//! file (the `[compression]` table, each group's `sigma0_mpa`), its row function and its
//! section of the report. Its run, journal, resume, shards, merge, manifest and
//! `summary.csv` are the study core's (its statistic, the wall's vertical modulus, is
//! `study::summary`'s `MODULUS`).

use super::error::Invalid;
use super::protocol_table::ProtocolTable;
use super::report::{ensemble_report, solver_text};
use super::report_error::ReportError;
use super::spec::{GroupSpec, StudySpec};
use super::summary::{CellSummary, Comparison};
use super::sweep::{SweepKey, SweepValue};
use super::text::md_table;
use super::{Study, StudyError};
use crate::dem::Cascade;
use crate::ensemble::row::{CompressionColumns, RealizationRow, Status};
use crate::io::series::SeriesError;
use crate::layout::Layout;
use crate::loading::compression::{CompressionParams, CompressionResult};
use crate::loading::inplane::BeamRotation;
use crate::protocol::{Compression, Protocol};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A compression study's parameters: the `[compression]` table and each group's vertical
/// stress.
#[derive(Debug, Clone, PartialEq)]
pub struct CompressionStudy {
    /// The `[compression]` table (its `sigma0_mpa` the groups' default).
    pub params: CompressionParams,
    /// Each group's vertical stress, MPa, in the study's group order (`[[groups]]
    /// sigma0_mpa`, or the table's).
    pub sigma0_mpa: Vec<f64>,
}

impl CompressionStudy {
    /// The parameters group `group` runs (its vertical stress); the table's for a group
    /// past the list.
    pub fn params_of(&self, group: usize) -> CompressionParams {
        let sigma0_mpa = self.sigma0_mpa.get(group).copied().unwrap_or(self.params.sigma0_mpa);
        CompressionParams { sigma0_mpa, ..self.params.clone() }
    }
}

impl StudySpec {
    /// The compression test's keys resolved: the `[compression]` table checked, each group's
    /// vertical stress with it (`None` for a study of another protocol, which refuses the
    /// table).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] naming the key: `compression` in a study of another
    /// protocol, a key of the table out of its range (`compression.KEY`), a group's stress
    /// (`groups[NAME].sigma0_mpa`).
    pub(super) fn resolve_compression(&self, invalid: &Invalid) -> Result<Option<CompressionStudy>, StudyError> {
        if !self.reads_table("compression") {
            if self.compression.is_some() {
                return Err(invalid.at(
                    "compression",
                    "is read by the compression test only (protocol = \"compression\", docs/compression.md)".into(),
                ));
            }
            return Ok(None);
        }
        self.refuse_unread_by_compression(invalid)?;
        let params = self.compression.clone().unwrap_or_default();
        params.validate().map_err(|e| invalid.at(&format!("compression.{}", e.key), e.reason()))?;
        if params.beam_rotation == BeamRotation::Fixed && params.shear_span_m.is_some() {
            return Err(invalid.at(
                "compression.shear_span_m",
                "is not read with beam_rotation = \"fixed\" (the beam held level has no actuator's lever): drop it, or give beam_rotation = \"free\"".into(),
            ));
        }
        let mut sigma0_mpa = Vec::with_capacity(self.groups.len());
        for g in &self.groups {
            sigma0_mpa.push(group_stress(g, &params, invalid)?);
        }
        Ok(Some(CompressionStudy { params, sigma0_mpa }))
    }
}

impl StudySpec {
    /// The keys of a compression study that the compression test does not read, refused:
    /// the other protocols' tables (`[tilt]`, `[lateral]`, `[shake]`), `[measured]`,
    /// `[paper]`, `[[calibrate]]`. Accepted, they would leave a study that reads as tuned by
    /// them and runs without them.
    fn refuse_unread_by_compression(&self, invalid: &Invalid) -> Result<(), StudyError> {
        let tables = [
            ("tilt", self.tilt != crate::loading::tilt::TiltParams::default()),
            ("lateral", self.lateral != crate::loading::lateral::LateralParams::default()),
            ("shake", self.shake.is_some()),
            ("measured", self.measured.is_some()),
            ("paper", self.paper.is_some()),
            ("calibrate", !self.calibrate.is_empty()),
        ];
        match tables.iter().find(|(_, given)| *given) {
            Some((k, _)) => Err(invalid.at(
                k,
                "the compression test does not read it (another protocol's key; the compression study reads no measured file)".into(),
            )),
            None => Ok(()),
        }
    }
}

/// Group `g`'s vertical stress (its `sigma0_mpa`, or the table's), checked with the table's
/// other keys.
fn group_stress(g: &GroupSpec, params: &CompressionParams, invalid: &Invalid) -> Result<f64, StudyError> {
    let Some(s) = g.sigma0_mpa else {
        return Ok(params.sigma0_mpa);
    };
    CompressionParams { sigma0_mpa: s, ..params.clone() }
        .validate()
        .map_err(|e| invalid.at(&format!("groups[{}].{}", g.name, e.key), e.reason()))?;
    Ok(s)
}

/// A compression run's readings into the row ([`CompressionColumns`]).
pub(super) fn compression_row(mut row: RealizationRow, r: CompressionResult) -> RealizationRow {
    row.status = Status::Stood;
    let [low, high] = r.strength_bracket_mpa.unwrap_or([f64::NAN, f64::NAN]);
    row.compression = Some(Box::new(CompressionColumns {
        compression_modulus_mpa: r.wall_vertical_modulus_mpa,
        loading_secants_mpa: r.loading_secants_mpa,
        residual_settlements_mm: r.residual_settlements_mm,
        strength_low_mpa: low,
        strength_high_mpa: high,
        compression_unconverged: r.unconverged as u64,
        curve_stress_mpa: r.curve.iter().map(|p| p.stress_mpa).collect(),
        curve_shortening_mm: r.curve.iter().map(|p| p.shortening_mm).collect(),
    }));
    row.steps = r.steps;
    row.dt_s = r.dt_s;
    row
}

/// The compression study's section of the report: the wall's vertical modulus per group
/// (the ensemble's mean, σ, COV and the 95 % interval of the mean, [`CellSummary::modulus`]),
/// the mean secant of each cycle's loading branch and residual settlement, and the strength's
/// bracket where the raise found one.
pub(super) fn compression_sections(
    study: &Study,
    test: &CompressionStudy,
    rows: &[RealizationRow],
    cells: &[CellSummary],
    md: &mut String,
) {
    let p = &test.params;
    let unload = p.unload_to_mpa.map_or("the beam's own weight".to_string(), |u| format!("{u} MPa"));
    let _ = writeln!(
        md,
        "Master seed {}; {} realization(s) per group and sweep point unless the group fixes its own; protocol: the vertical compression test, {} load–unload cycle(s) between each group's σ0 and {unload}, the loading beam's rotation {}{}; {}.\n",
        study.seed,
        study.realizations,
        p.cycles,
        match p.beam_rotation {
            crate::loading::inplane::BeamRotation::Fixed => "held level",
            crate::loading::inplane::BeamRotation::Free => "free",
        },
        p.raise_to_mpa.map_or(String::new(), |r| format!(", then raised to {r} MPa")),
        solver_text(study, study.solver.kind.cascade(crate::loading::inplane::CASCADE).unwrap_or(Cascade::RELAXATION))
    );
    let _ = writeln!(md, "## The wall's vertical modulus\n");
    let _ = writeln!(md, "The secant of the first loading branch (the Stone Masonry Database's `Epc`): the stress the actuator added over the wall's shortening (the beam's settlement over the wall's height). Cycle secants: the mean over the realizations of each cycle's loading branch; residual: the mean settlement left after each unloading, below the first loading at the same stress. Statistics over the realizations that ran.\n");
    let num = |v: f64| if v.is_finite() { format!("{v:.4}") } else { "–".to_string() };
    let header = [
        "group",
        "sweep",
        "σ0 [MPa]",
        "n",
        "failed",
        "modulus mean [MPa]",
        "σ [MPa]",
        "COV",
        "95 % CI of mean [MPa]",
        "cycle secants [MPa]",
        "residuals [mm]",
        "strength [MPa]",
    ];
    md_table(
        md,
        &header,
        cells.iter().map(|c| {
            let s = &c.modulus;
            let of: Vec<&CompressionColumns> = rows
                .iter()
                .filter(|r| r.group == c.group && r.point as usize == c.point && r.status.is_ok())
                .filter_map(|r| r.compression.as_deref())
                .collect();
            let mean_of = |f: fn(&CompressionColumns) -> &Vec<f64>| -> String {
                let len = of.iter().map(|x| f(x).len()).max().unwrap_or(0);
                (0..len)
                    .map(|k| {
                        let v: Vec<f64> = of.iter().filter_map(|x| f(x).get(k).copied()).collect();
                        num(v.iter().sum::<f64>() / v.len() as f64)
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let strength: Vec<String> = of
                .iter()
                .filter(|x| x.strength_low_mpa.is_finite())
                .map(|x| format!("{}–{}", num(x.strength_low_mpa), num(x.strength_high_mpa)))
                .collect();
            vec![
                c.group.clone(),
                c.sweep.clone(),
                num(test.sigma0_mpa.get(c.group_index).copied().unwrap_or(p.sigma0_mpa)),
                c.n.to_string(),
                c.failed.to_string(),
                num(s.mean),
                num(s.sd),
                num(s.cov),
                format!("{} .. {}", num(s.mean_ci95.0), num(s.mean_ci95.1)),
                mean_of(|x| &x.loading_secants_mpa),
                mean_of(|x| &x.residual_settlements_mm),
                if strength.is_empty() { "–".into() } else { strength.join("; ") },
            ]
        }),
    );
    let _ = writeln!(md);
}

/// The compression test's study: each group's vertical stress its own protocol, the
/// ensemble's report with its section (`compression_sections`), no time series.
impl ProtocolTable for CompressionStudy {
    fn write_into(&self, spec: &mut StudySpec) {
        spec.compression = Some(self.params.clone());
        for (g, s) in spec.groups.iter_mut().zip(&self.sigma0_mpa) {
            g.sigma0_mpa = Some(*s);
        }
    }

    /// The first group's protocol (its vertical stress); the point's values are not the
    /// test's.
    fn at(&self, _point: &[(SweepKey, SweepValue)]) -> Protocol {
        Protocol::Compression(Compression(self.params_of(0)))
    }

    fn of_group(&self, group: usize, _point: &[(SweepKey, SweepValue)]) -> Protocol {
        Protocol::Compression(Compression(self.params_of(group)))
    }

    fn write_report(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
        ensemble_report(study, rows, dir)
    }

    fn report_sections(
        &self,
        study: &Study,
        rows: &[RealizationRow],
        _dir: &Path,
        cells: &[CellSummary],
        _cmp: &[Comparison],
        md: &mut String,
    ) -> Result<String, ReportError> {
        compression_sections(study, self, rows, cells, md);
        Ok(String::new())
    }

    /// None: the compression test records no time series.
    fn write_series(
        &self,
        _study: &Study,
        _point: usize,
        _layout: &Layout,
        _out: &Path,
    ) -> Result<Option<PathBuf>, SeriesError> {
        Ok(None)
    }

    fn warnings(&self) -> Vec<String> {
        vec![]
    }
}
