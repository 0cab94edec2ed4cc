//! The report of a shaking study (protocol `shake`): per group, the fragility curve
//! P(collapse | PGA) fitted by maximum likelihood on the binomial counts of each PGA level
//! (Baker 2015, [`crate::stats::fragility`]) with its parametric bootstrap band, the
//! incremental dynamic analysis (IDA) curves, and beside them the static capacity of the
//! same walls on the tilting table, λ g with λ = tan α_max, by limit analysis of the same
//! realizations ([`crate::limit::limit_tilt`]: the rigid-block collapse multiplier, the
//! non-associative correction on where sliding governs).
//!
//! Outputs: `fragility.csv` (one row per group and level), `static_capacity.csv` (one row
//! per group and realization), `shaking.svg` and the report's sections. A deterministic
//! function of the rows (in index order) and the study: the bootstrap of group `g` draws
//! from `rng_for(seed, 2³³ + g, Bootstrap)`, its block of streams
//! ([`super::summary::StreamBlock`]).

use super::figures::shake_series;
use super::motions::ShakeStudy;
use super::protocol_table::ProtocolTable;
use super::report::ensemble_report;
use super::report_error::ReportError;
use super::spec::StudySpec;
use super::summary::{CellSummary, Comparison};
use super::sweep::{SweepKey, SweepValue};
use super::text::{fixed, md_table};
use super::Study;
use crate::ensemble::row::{RealizationRow, Status};
use crate::ground::Motion;
use crate::io::plot::{self, IdaCurve, IntensityFragilityPanel};
use crate::io::replace_file_with;
use crate::io::series::SeriesError;
use crate::io::table::{SimpleTable, TableColumn};
use crate::layout::Layout;
use crate::protocol::{Protocol, Shake};
use crate::stats::fragility::{fragility_band, FragilityBand, IntensityFragility, LevelCount};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Bootstrap replicates of the fragility band.
pub const BOOTSTRAP_REPLICATES: usize = 1000;

/// The first bootstrap stream of the fragility bands (group `g` draws from this plus `g`):
/// the study's block of them ([`super::summary::StreamBlock::Shaking`]).
const STREAM: u64 = super::summary::StreamBlock::Shaking.base();

/// The fragility of one group.
#[derive(Debug, Clone)]
pub struct GroupFragility {
    /// Group name.
    pub group: String,
    /// Counts per PGA level (runs: realizations that stood or collapsed; failed ones left
    /// out).
    pub levels: Vec<LevelCount>,
    /// Failed runs per level (layout, blow-up).
    pub failed: Vec<u64>,
    /// The maximum-likelihood fit with its band; `None` where the counts do not overlap.
    pub band: Option<FragilityBand>,
    /// Static capacity λ = tan α_max of each realization by limit analysis, g (NaN where it
    /// failed), in realization order.
    pub capacity: Vec<f64>,
}

/// The counts of every group's rows at every level of the study.
pub fn group_counts(
    study: &Study,
    shake: &ShakeStudy,
    rows: &[RealizationRow],
    g: usize,
) -> (Vec<LevelCount>, Vec<u64>) {
    let name = &study.groups[g].name;
    let mut counts = Vec::new();
    let mut failed = Vec::new();
    for &level in &shake.levels {
        let at: Vec<&RealizationRow> =
            rows.iter().filter(|r| &r.group == name && r.shake.pga_g == Some(level)).collect();
        let ok = at.iter().filter(|r| r.status.is_ok()).count() as u64;
        let collapses = at.iter().filter(|r| r.status == Status::Collapsed).count() as u64;
        counts.push(LevelCount { intensity: level, runs: ok, collapses });
        failed.push(at.len() as u64 - ok);
    }
    (counts, failed)
}

/// The static capacity λ = tan α_max (g) of realizations `0..n` of group `g` at the
/// study's first sweep point, by limit analysis; NaN where the layout or the analysis
/// failed.
fn static_capacity(study: &Study, g: usize) -> Vec<f64> {
    let group = &study.groups[g];
    let Some(wall) = group.walls.first() else { return vec![] };
    // The tilting table by limit analysis, through the protocol seam.
    let solver = crate::dem::SolverParams { kind: crate::dem::SolverKind::Limit, ..study.solver };
    let tilt = crate::protocol::Tilt(crate::loading::tilt::TiltParams::default());
    let capacity = |run: crate::protocol::TiltRun| match run {
        crate::protocol::TiltRun::Limit(r) => r.ok().map(|l| l.load_multiplier),
        crate::protocol::TiltRun::Penalty(_) | crate::protocol::TiltRun::Nscd(_) => None,
    };
    (0..study.group_realizations(g))
        .into_par_iter()
        .map(|r| {
            crate::effects::realize(wall, study.seed, r, &group.name, &group.effects)
                .ok()
                .and_then(|(_, layout)| crate::protocol::run(&tilt, &layout, solver, &mut ()).ok())
                .and_then(capacity)
                .unwrap_or(f64::NAN)
        })
        .collect()
}

/// The fragility of every group: counts, fit and band, static capacities.
pub fn fragilities(study: &Study, rows: &[RealizationRow]) -> Vec<GroupFragility> {
    let Some(shake) = study.protocol.shake() else { return vec![] };
    let grid = intensity_grid(shake);
    (0..study.groups.len())
        .map(|g| {
            let (levels, failed) = group_counts(study, shake, rows, g);
            let band = fragility_band(&levels, &grid, BOOTSTRAP_REPLICATES, study.seed, STREAM + g as u64);
            GroupFragility {
                group: study.groups[g].name.clone(),
                levels,
                failed,
                band,
                capacity: static_capacity(study, g),
            }
        })
        .collect()
}

/// 81 intensities from 0 to 1.25 times the highest level, g (the band's abscissae).
fn intensity_grid(shake: &ShakeStudy) -> Vec<f64> {
    let top = shake.levels.last().copied().unwrap_or(1.0) * 1.25;
    (1..=80).map(|k| top * k as f64 / 80.0).collect()
}

/// `θ (lo – hi)`; an end beyond 100 times the value (or not finite) is `unbounded`.
fn with_range(v: f64, r: (f64, f64), d: usize) -> String {
    let end = |x: f64| if x.is_finite() && x.abs() <= 100.0 * v.abs() { fixed(x, d) } else { "unbounded".into() };
    format!("{} ({} – {})", fixed(v, d), end(r.0), end(r.1))
}

/// Mean and range of the finite values.
fn capacity_text(c: &[f64]) -> String {
    let f: Vec<f64> = c.iter().copied().filter(|v| v.is_finite()).collect();
    if f.is_empty() {
        return "–".into();
    }
    let mean = f.iter().sum::<f64>() / f.len() as f64;
    let lo = f.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = f.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    format!("{} ({} – {}), n = {}", fixed(mean, 3), fixed(lo, 3), fixed(hi, 3), f.len())
}

/// The report's sections of a shaking study, `fragility.csv`, `static_capacity.csv` and
/// `shaking.svg` into `dir`. Returns the fragility table as text (what `drystone run`
/// prints).
///
/// # Errors
/// [`ReportError`] naming the file.
pub fn shake_sections(
    study: &Study,
    shake: &ShakeStudy,
    rows: &[RealizationRow],
    dir: &Path,
    md: &mut String,
) -> Result<String, ReportError> {
    let frag = fragilities(study, rows);
    let p = &shake.params;
    let method = crate::protocol::shake::study_notes(&study.solver);
    let _ = writeln!(
        md,
        "Master seed {}; {} realization(s) per group; protocol: shaking table (base acceleration along +y), {} motion(s) × {} PGA level(s) (incremental dynamic analysis: each motion scaled to each level); motion simulated {}, then {} s of free motion; a block has fallen past {}° of rotation; {method}.\n",
        study.seed,
        study.realizations,
        shake.motions.len(),
        shake.levels.len(),
        p.duration_s.map_or("whole".to_string(), |d| format!("for {d} s at most")),
        p.tail_s,
        p.fall_rotation_deg,
    );
    convergence_line(study, rows, md);
    let table = fragility_text(&frag, md);
    write_tables(&frag, dir)?;
    let ida = ida_curves(study, rows);
    // The rotation axis ends a quarter above the largest rotation of a run that stood
    // (collapsed runs are drawn at its top), at most the fall rotation.
    let standing = ida.iter().flat_map(|c| c.points.iter().filter(|p| !p.2).map(|p| p.1)).fold(0.0, f64::max);
    let cap = if standing > 0.0 { (1.25 * standing).min(p.fall_rotation_deg) } else { p.fall_rotation_deg };
    let panels: Vec<IntensityFragilityPanel> = frag.iter().enumerate().map(|(g, f)| panel(g, f)).collect();
    replace_file_with(&dir.join("shaking.svg"), |path| -> Result<(), ReportError> {
        let title = format!("{}: incremental dynamic analysis and fragility against PGA", study.name);
        Ok(plot::ida_and_fragility(
            path,
            &title,
            "PGA [g]",
            "max rocking rotation [deg] (x: collapsed)",
            cap,
            &ida,
            &panels,
        )?)
    })?;
    let _ = writeln!(md, "![IDA curves and fragility against PGA, static capacity beside it](shaking.svg)\n");
    Ok(table)
}

/// The line of the report on the steps of the runs (`nscd`) whose natural-map residual is
/// above the solver's `natural_tolerance` (the `unconverged_steps` column), settling
/// included, with the largest residual; none for rows that hold no count (`penalty`).
fn convergence_line(study: &Study, rows: &[RealizationRow], md: &mut String) {
    let counted: Vec<&RealizationRow> = rows.iter().filter(|r| r.shake.unconverged_steps.is_some()).collect();
    if counted.is_empty() {
        return;
    }
    let unconverged: u64 = counted.iter().filter_map(|r| r.shake.unconverged_steps).sum();
    let steps: u64 = counted.iter().map(|r| r.steps).sum();
    let runs = counted.iter().filter(|r| r.shake.unconverged_steps.is_some_and(|n| n > 0)).count();
    let worst = counted.iter().filter_map(|r| r.shake.max_natural_residual).fold(0.0f64, f64::max);
    let _ = writeln!(
        md,
        "Unconverged steps (natural-map residual above {:.0e}, settling included): {unconverged} of {steps} steps, in {runs} of {} run(s); largest natural-map residual {worst:.1e}.\n",
        study.solver.nscd.natural_tolerance,
        counted.len()
    );
}

/// The cells of one group's line of the fragility table: group, counts per level, θ and
/// β with their bootstrap ranges, the static capacity.
fn fragility_cells(f: &GroupFragility) -> [String; 5] {
    let counts: Vec<String> = f
        .levels
        .iter()
        .zip(&f.failed)
        .map(|(l, &x)| {
            let failed = if x > 0 { format!(" ({x} failed)") } else { String::new() };
            format!("{}: {}/{}{failed}", fixed(l.intensity, 2), l.collapses, l.runs)
        })
        .collect();
    let (theta, beta) = match &f.band {
        Some(b) => (with_range(b.fit.median, b.median_ci95, 3), with_range(b.fit.beta, b.beta_ci95, 3)),
        None => (no_fit(&f.levels), "–".into()),
    };
    [f.group.clone(), counts.join(", "), theta, beta, capacity_text(&f.capacity)]
}

/// The fragility table into `md`; the same as text.
fn fragility_text(frag: &[GroupFragility], md: &mut String) -> String {
    let _ = writeln!(md, "## Fragility against PGA\n");
    let _ = writeln!(
        md,
        "P(collapse | PGA = x) = Φ(ln(x / θ) / β), θ and β by maximum likelihood on the counts of each level (Baker 2015), with the 2.5–97.5 % range of {BOOTSTRAP_REPLICATES} parametric bootstrap refits (`unbounded` where refits leave the data's range: few runs). Collapse: a block fell. Static capacity: λ = tan α_max of the same realizations on the tilting table, by limit analysis (rigid blocks, non-associative friction), the constant base acceleration λ g the wall carries.\n"
    );
    let header = [
        "group",
        "collapses / runs at each PGA [g]",
        "θ [g] (95 % bootstrap)",
        "β (95 % bootstrap)",
        "static λ = tan α_max: mean (min – max)",
    ];
    md_table(md, &header, frag.iter().map(|f| fragility_cells(f).to_vec()));
    let _ = writeln!(md);
    let mut text = String::new();
    for f in frag {
        let [g, counts, theta, beta, lambda] = fragility_cells(f);
        let _ = writeln!(
            text,
            "{g}: collapses/runs at PGA [g] {counts}\n  median θ {theta} g, β {beta}; static λ {lambda}"
        );
    }
    for f in frag {
        let (Some(b), true) = (&f.band, f.capacity.iter().any(|v| v.is_finite())) else { continue };
        let c: Vec<f64> = f.capacity.iter().copied().filter(|v| v.is_finite()).collect();
        let mean = c.iter().sum::<f64>() / c.len() as f64;
        let _ = writeln!(
            md,
            "- {}: the median PGA of collapse is {} times the static capacity λ g ({} g against {} g).",
            f.group,
            fixed(b.fit.median / mean, 2),
            fixed(b.fit.median, 3),
            fixed(mean, 3),
        );
    }
    let _ = writeln!(md);
    text
}

/// What the counts say without a finite fit.
fn no_fit(levels: &[LevelCount]) -> String {
    let below = levels.iter().filter(|l| l.runs > 0 && l.collapses == 0).map(|l| l.intensity).fold(f64::NAN, f64::max);
    let above =
        levels.iter().filter(|l| l.runs > 0 && l.collapses == l.runs).map(|l| l.intensity).fold(f64::NAN, f64::min);
    format!("no finite fit (no level with both outcomes): between {} and {}", fixed(below, 3), fixed(above, 3))
}

/// The plot's panel of one group.
fn panel(g: usize, f: &GroupFragility) -> IntensityFragilityPanel {
    let (x, p, lo, hi) = match &f.band {
        Some(b) => (
            b.intensity.clone(),
            b.intensity.iter().map(|&x| b.fit.probability(x)).collect(),
            b.lower.clone(),
            b.upper.clone(),
        ),
        None => (vec![], vec![], vec![], vec![]),
    };
    IntensityFragilityPanel {
        label: f.group.clone(),
        series: g,
        x,
        p,
        lo,
        hi,
        empirical: f
            .levels
            .iter()
            .filter(|l| l.runs > 0)
            .map(|l| (l.intensity, l.collapses as f64 / l.runs as f64))
            .collect(),
        capacity: f.capacity.clone(),
    }
}

/// One IDA curve per (group, motion, realization): the largest rocking rotation at each
/// level, in level order; failed runs left out.
fn ida_curves(study: &Study, rows: &[RealizationRow]) -> Vec<IdaCurve> {
    let mut curves: Vec<((usize, String, u64), IdaCurve)> = Vec::new();
    for r in rows.iter().filter(|r| r.status.is_ok()) {
        let Some(g) = study.groups.iter().position(|g| g.name == r.group) else { continue };
        let (Some(x), Some(y)) = (r.shake.pga_g, r.shake.max_rotation_deg) else { continue };
        let key = (g, r.shake.motion.clone(), r.realization);
        let point = (x, y, r.status == Status::Collapsed);
        match curves.iter_mut().find(|(k, _)| *k == key) {
            Some((_, c)) => c.points.push(point),
            None => curves.push((key, IdaCurve { series: g, points: vec![point] })),
        }
    }
    curves
        .into_iter()
        .map(|(_, mut c)| {
            c.points.sort_by(|a, b| a.0.total_cmp(&b.0));
            c
        })
        .collect()
}

/// `fragility.csv` and `static_capacity.csv`.
fn write_tables(frag: &[GroupFragility], dir: &Path) -> Result<(), ReportError> {
    let mut t = SimpleTable::default();
    let mut group = Vec::new();
    let (mut pga, mut runs, mut collapses, mut failed) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut observed, mut fitted, mut theta, mut beta) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for f in frag {
        for (l, &x) in f.levels.iter().zip(&f.failed) {
            group.push(f.group.clone());
            pga.push(l.intensity);
            runs.push(l.runs);
            collapses.push(l.collapses);
            failed.push(x);
            observed.push(if l.runs > 0 { l.collapses as f64 / l.runs as f64 } else { f64::NAN });
            let fit: Option<IntensityFragility> = f.band.as_ref().map(|b| b.fit);
            fitted.push(fit.map_or(f64::NAN, |b| b.probability(l.intensity)));
            theta.push(fit.map_or(f64::NAN, |b| b.median));
            beta.push(fit.map_or(f64::NAN, |b| b.beta));
        }
    }
    t.columns = vec![
        ("group".into(), TableColumn::Text(group)),
        ("pga_g".into(), TableColumn::Number(pga)),
        ("runs".into(), TableColumn::Count(runs)),
        ("collapses".into(), TableColumn::Count(collapses)),
        ("failed".into(), TableColumn::Count(failed)),
        ("p_observed".into(), TableColumn::Number(observed)),
        ("p_fitted".into(), TableColumn::Number(fitted)),
        ("median_g".into(), TableColumn::Number(theta)),
        ("beta".into(), TableColumn::Number(beta)),
    ];
    t.write_csv(&dir.join("fragility.csv"))?;
    let mut c = SimpleTable::default();
    let (mut group, mut real, mut lambda, mut alpha) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for f in frag {
        for (r, &l) in f.capacity.iter().enumerate() {
            group.push(f.group.clone());
            real.push(r as u64);
            lambda.push(l);
            alpha.push(l.atan().to_degrees());
        }
    }
    c.columns = vec![
        ("group".into(), TableColumn::Text(group)),
        ("realization".into(), TableColumn::Count(real)),
        ("lambda_g".into(), TableColumn::Number(lambda)),
        ("alpha_max_deg".into(), TableColumn::Number(alpha)),
    ];
    c.write_csv(&dir.join("static_capacity.csv"))?;
    Ok(())
}

/// The shaking table's study: its table's protocol at a sweep point (the point's motion
/// scaled to its PGA level), the ensemble's report with its sections (`shake_sections`)
/// and the point's ParaView series; its warnings, the motions that cannot reach its levels.
impl ProtocolTable for ShakeStudy {
    fn write_into(&self, spec: &mut StudySpec) {
        // A shaking study's motions are not written (the analysis refuses the shaking table).
        spec.shake = None;
    }

    /// The shaking table under the point's motion (sweep key `motion`) scaled to its PGA
    /// level (`pga_g`). A point whose motion is missing (a study not made by
    /// [`StudySpec::resolve`]) gets an empty motion, which the protocol refuses with an
    /// error row.
    fn at(&self, point: &[(SweepKey, SweepValue)]) -> Protocol {
        let value = |key: SweepKey| point.iter().find(|(k, _)| *k == key).map(|(_, v)| v);
        let name = value(SweepKey::Motion).map(|v| v.to_string()).unwrap_or_default();
        let pga = value(SweepKey::PgaG).and_then(SweepValue::number).unwrap_or(0.0);
        let motion = self.motion(&name, pga).unwrap_or_else(|| Motion {
            name,
            dt_s: 0.0,
            horizontal_g: vec![],
            vertical_g: None,
        });
        Protocol::Shake(Shake { params: self.params, motion: Box::new(motion) })
    }

    fn of_group(&self, _group: usize, point: &[(SweepKey, SweepValue)]) -> Protocol {
        self.at(point)
    }

    fn write_report(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
        ensemble_report(study, rows, dir)
    }

    fn report_sections(
        &self,
        study: &Study,
        rows: &[RealizationRow],
        dir: &Path,
        _cells: &[CellSummary],
        _cmp: &[Comparison],
        md: &mut String,
    ) -> Result<String, ReportError> {
        shake_sections(study, self, rows, dir, md)
    }

    fn write_series(
        &self,
        study: &Study,
        point: usize,
        layout: &Layout,
        out: &Path,
    ) -> Result<Option<PathBuf>, SeriesError> {
        shake_series(study, point, layout, out)
    }

    fn warnings(&self) -> Vec<String> {
        ShakeStudy::warnings(self)
    }

    fn shake(&self) -> Option<&ShakeStudy> {
        Some(self)
    }
}
