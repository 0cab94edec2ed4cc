//! Reporting a study: `summary.csv`, `report.md` and SVG plots, with the comparison with
//! the measured data and, for a study of the source paper, its table or figure. Everything
//! here is a deterministic function of the rows (in index order) and the study.

use super::paper;
use super::summary::{comparison_text, comparisons, measure_of, summarize, write_summary_csv, CellSummary, Comparison};
use super::text::{fixed, md_table, sci};
use super::Study;
use crate::dem::Cascade;
use crate::ensemble::row::RealizationRow;
use crate::io::plot::{self, BandSeries, HistogramPanel};
use crate::io::{replace_file, replace_file_with};
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;
use crate::stats;
use std::fmt::Write as _;
use std::path::Path;

pub use super::report_error::ReportError;

/// One note per group whose realizations all gave the same values (σ = 0 over more than one
/// realization, every compared quantity): its band has zero width, which says nothing of how
/// real walls vary, only that the group's layouts have no random input that matters.
fn degenerate_groups(cmp: &[Comparison]) -> Vec<String> {
    let mut groups: Vec<&str> = Vec::new();
    for c in cmp {
        if !groups.contains(&c.group.as_str()) {
            groups.push(&c.group);
        }
    }
    groups
        .into_iter()
        .filter_map(|g| {
            let of: Vec<&Comparison> = cmp.iter().filter(|c| c.group == g).collect();
            let n = of[0].simulated_n;
            (n > 1 && of.iter().all(|c| c.simulated_sd == 0.0)).then(|| {
                format!(
                    "{g}: all {n} realizations gave the same values (σ = 0), so its 95 % band has zero \
                     width. The layouts of this group have no random input that matters (e.g. a \
                     regular bond of blocks of one size, and no material scatter): the band says \
                     nothing of how real walls of this kind vary: judge the gap against the \
                     measurements' own spread instead. Give the wall file a source of scatter \
                     (block sizes, joint parameters) to study that variability."
                )
            })
        })
        .collect()
}

/// The solver that ran a study of static states, as the study file names it (`[solver]
/// kind`), with its method and, for the penalty DEM, the stages its static solves ran
/// (`cascade`: the protocol's, with the kind's choice applied) and its settings.
pub(super) fn solver_text(study: &Study, cascade: Cascade) -> String {
    let kind = study.solver.kind;
    let method = kind.method().describe();
    if !kind.is_penalty() {
        return format!("solver `{kind}`: {method}");
    }
    let stages = cascade_words(cascade);
    let on = |b: bool| if b { "on" } else { "off" };
    format!(
        "solver `{kind}`: {method}, static states by {stages}, equilibrium at unbalanced-force ratio {}, secant predictor {}, local damping {}, sub-contact subdivisions {}",
        study.solver.penalty.tolerance,
        on(study.solver.penalty.predictor),
        study.solver.damping,
        study.solver.subcontact_subdivisions
    )
}

/// The stages of a penalty cascade in the reports' words: the iterations that run first,
/// then the dynamic relaxation they hand over to.
pub(super) fn cascade_words(cascade: Cascade) -> String {
    let stages = match (cascade.implicit, cascade.accelerate) {
        (true, true) => "the implicit iteration, then accelerated dynamic relaxation",
        (true, false) => "the implicit iteration, then plain dynamic relaxation",
        (false, true) => "accelerated dynamic relaxation, without the implicit iteration",
        (false, false) => "plain dynamic relaxation",
    };
    if cascade.newton {
        format!("the Newton solve, then {stages}")
    } else {
        stages.to_string()
    }
}

fn num(v: f64) -> String {
    fixed(v, 3)
}

/// A cell in a plot: its group, and its sweep point if there is a sweep.
fn cell_title(c: &CellSummary) -> String {
    if c.sweep.is_empty() {
        c.group.clone()
    } else {
        format!("{} {}", c.group, c.sweep)
    }
}

/// The sweep of a cell in a table: its label, or `–` without a sweep.
fn sweep_label(c: &CellSummary) -> &str {
    if c.sweep.is_empty() {
        "–"
    } else {
        &c.sweep
    }
}

/// Writes the report of a whole study into `dir`: `summary.csv`, `report.md` and the plots
/// (the ensemble's, [`ensemble_report`], or the in-plane test's with its `comparison.csv`,
/// [`super::StudyProtocol::write_report`]). Returns what `drystone run` prints: the
/// measured-against-simulated table and the paper comparison, if any.
///
/// # Errors
/// [`ReportError`] naming the file.
pub fn write_report(study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
    study.protocol.write_report(study, rows, dir)
}

/// The ensemble's report: `summary.csv` of its cells, `report.md` with the protocol's
/// sections ([`super::StudyProtocol::report_sections`]), the paper's, the warnings and the
/// failed realizations, and the plots. Returns what `drystone run` prints.
///
/// # Errors
/// [`ReportError`] naming the file.
pub(super) fn ensemble_report(study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
    let cells = summarize(study, rows);
    let cmp = comparisons(study, &cells);
    write_summary_csv(&cells, &dir.join("summary.csv"))?;
    let mut md = String::new();
    let _ = writeln!(md, "# Study `{}`\n", study.name);
    if !study.description.is_empty() {
        let _ = writeln!(md, "{}\n", study.description.trim());
    }
    let mut printed = study.protocol.report_sections(study, rows, dir, &cells, &cmp, &mut md)?;
    if !cmp.is_empty() {
        printed = comparison_text(&cmp);
    }
    if let Some(p) = study.paper {
        let section = paper::section(p, study, &cells, dir)?;
        printed.push_str(&section);
        md.push_str(&section);
    }
    let warnings = study.warnings();
    if !warnings.is_empty() {
        let _ = writeln!(md, "## Warnings\n");
        for w in &warnings {
            let _ = writeln!(md, "- {w}");
        }
        let _ = writeln!(md);
    }
    let failed: Vec<&RealizationRow> = rows.iter().filter(|r| !r.status.is_ok()).collect();
    if !failed.is_empty() {
        let _ = writeln!(md, "## Failed realizations\n");
        for r in failed {
            let _ = writeln!(
                md,
                "- {} realization {} ({}): {} — {}",
                r.group,
                r.realization,
                r.sweep,
                r.status.as_str(),
                r.error
            );
        }
    }
    replace_file(&dir.join("report.md"), md.as_bytes())?;
    Ok(printed)
}

/// The report of a static lateral load study: top displacement and drift per cell.
pub(super) fn lateral_sections(study: &Study, l: &LateralParams, cells: &[CellSummary], md: &mut String) {
    let _ = writeln!(
        md,
        "Master seed {}; {} realization(s) per group and sweep point unless the group fixes its own; protocol: static lateral load, trapezoidal pressure {} Pa at the base to {} Pa at the top, normal to the loaded face, pushing towards +y; {}.\n",
        study.seed,
        study.realizations,
        l.pressure_base_pa,
        l.pressure_top_pa,
        solver_text(study, l.cascade(study.solver.kind))
    );
    let _ = writeln!(md, "## Top displacement under the lateral load\n");
    let _ = writeln!(md, "Top displacement: the largest of the three top points (left, centre, right), in mm; drift = top displacement / H. Statistics over the realizations that reached equilibrium.\n");
    let mm = |v: f64| num(10.0 * v);
    let header = [
        "group",
        "sweep",
        "n",
        "failed",
        "collapsed",
        "mean [mm]",
        "σ [mm]",
        "COV",
        "min",
        "max",
        "95 % CI of mean [mm]",
        "95 % bootstrap COV",
        "centre mean [mm]",
        "drift mean",
        "drift σ",
    ];
    md_table(
        md,
        &header,
        cells.iter().map(|c| {
            let s = &c.lateral_max;
            let head = [c.n.to_string(), c.failed.to_string(), c.lateral_collapsed.to_string()];
            let tail = [
                format!("{} .. {}", num(s.cov_boot95.0), num(s.cov_boot95.1)),
                mm(c.lateral_centre.mean),
                sci(c.drift.mean),
                sci(c.drift.sd),
            ];
            cell_row(c, head, spread_cells(s, mm), tail)
        }),
    );
    let _ = writeln!(md);
    if cells.iter().any(|c| c.pushover) {
        capacity_table(l, cells, md);
    }
}

/// The collapse load multipliers of a pushover study (`[lateral] pushover = true`), by the
/// DEM pushover and by limit analysis, beside the service displacement.
fn capacity_table(l: &LateralParams, cells: &[CellSummary], md: &mut String) {
    let _ = writeln!(
        md,
        "## Collapse load multiplier of the pressure
"
    );
    let _ = writeln!(
        md,
        "λ: the multiple of the pressure above at which the wall collapses. DEM: the last stable λ of the penalty DEM pushover (λ doubled from 1, then bisected to {} of λ; the joints' Kn, Ks, friction, cohesion and tension); limit: limit analysis of the same layout (rigid blocks, the joints' full strength). DEM / limit: the ratio per realization. Service: the top displacement of the service test above (λ = 1). A joint without tensile strength keeps no cohesion in the DEM where it carries no compression, while limit analysis keeps c A in every joint's cone: for walls with cohesion, the DEM's rigid limit is limit analysis at c = 0 (a `cohesion_pa` sweep).\n",
        l.penalty_pushover_resolution()
    );
    let header = [
        "group",
        "sweep",
        "n",
        "λ DEM mean",
        "σ",
        "COV",
        "min .. max",
        "λ limit mean",
        "σ",
        "COV",
        "min .. max",
        "DEM / limit mean",
        "service [mm]",
    ];
    let stat =
        |s: &crate::stats::Summary| [num(s.mean), num(s.sd), num(s.cov), format!("{} .. {}", num(s.min), num(s.max))];
    md_table(
        md,
        &header,
        cells.iter().map(|c| {
            let mut row = vec![c.group.clone(), sweep_label(c).into(), c.n.to_string()];
            row.extend(stat(&c.lambda_dem));
            row.extend(stat(&c.lambda_limit));
            row.push(num(c.lambda_ratio.mean));
            row.push(num(10.0 * c.lateral_max.mean));
            row
        }),
    );
    let _ = writeln!(md);
}

/// The tilting-table part of the report: collapse angles, displacements, measured against
/// simulated, plots.
pub(super) fn tilt_sections(
    study: &Study,
    tilt: &TiltParams,
    rows: &[RealizationRow],
    dir: &Path,
    cells: &[CellSummary],
    cmp: &[Comparison],
    md: &mut String,
) -> Result<(), ReportError> {
    tilt_plots(study, tilt.step_deg, rows, cells, dir)?;
    let _ = writeln!(
        md,
        "Master seed {}; {} realization(s) per group and sweep point; protocol: tilting table, tilt step {}°, collapse bracket {}°; {}.\n",
        study.seed,
        study.realizations,
        tilt.step_deg,
        tilt.resolution_deg,
        solver_text(study, tilt.cascade(study.solver.kind))
    );
    collapse_table(cells, md);
    displacement_table(cells, md);
    if !cmp.is_empty() {
        comparison_table(cmp, md);
        misses_section(cmp, md);
    }
    mechanism_table(study, rows, md);
    let _ = writeln!(md, "\n## Plots\n");
    let _ = writeln!(md, "![collapse angle histograms](collapse_angle_histograms.svg)\n");
    let _ = writeln!(md, "![displacement against tilt](displacement_vs_tilt.svg)\n");
    let _ = writeln!(md, "![fragility curves](fragility.svg)\n");
    let figures = super::figures::mechanism_figures(study, rows, dir)?;
    if !figures.is_empty() {
        let _ = writeln!(md, "## Mechanisms\n");
        let _ = writeln!(
            md,
            "Per group, the realization with the median collapse angle (at the first sweep point), run again and drawn at its first unstable state: moving blocks coloured by their displacement since the settled state, the governing joint in red.\n"
        );
        for (group, file) in figures {
            let _ = writeln!(md, "![{group}: collapse mechanism]({file})\n");
        }
    }
    Ok(())
}

/// The histograms of the collapse angle, the displacement against tilt and the fragility
/// curves, as SVG files in `dir`.
fn tilt_plots(
    study: &Study,
    step_deg: f64,
    rows: &[RealizationRow],
    cells: &[CellSummary],
    dir: &Path,
) -> Result<(), ReportError> {
    let hist_panels: Vec<HistogramPanel> = cells
        .iter()
        .map(|c| HistogramPanel {
            title: cell_title(c),
            simulated: c.angles.clone(),
            measured: study
                .measured
                .collapse
                .iter()
                .filter(|m| m.group == study.groups[c.group_index].measured_group && c.point == 0)
                .map(|m| m.collapse_angle_deg)
                .collect(),
        })
        .collect();
    replace_file_with(&dir.join("collapse_angle_histograms.svg"), |p| -> Result<(), ReportError> {
        Ok(plot::histograms(p, "collapse angle [deg]", step_deg.max(0.25), &hist_panels)?)
    })?;
    replace_file_with(&dir.join("displacement_vs_tilt.svg"), |p| -> Result<(), ReportError> {
        let title = "Out-of-plane top displacement: ensemble mean, 5-95 % band, measured";
        Ok(plot::bands(p, title, "tilt [deg]", "displacement [cm]", &displacement_series(study, step_deg, rows))?)
    })?;
    replace_file_with(&dir.join("fragility.svg"), |p| -> Result<(), ReportError> {
        let title = "Fragility P(collapse | tilt): fitted lognormal (line), simulated (points), measured (rings)";
        Ok(plot::bands(p, title, "tilt [deg]", "P(collapse)", &fragility_series(study, cells))?)
    })
}

/// The collapse angle per cell.
fn collapse_table(cells: &[CellSummary], md: &mut String) {
    let _ = writeln!(md, "## Collapse angle α_max [deg]\n");
    let header = [
        "group",
        "sweep",
        "n",
        "failed",
        "stood",
        "mean",
        "σ",
        "COV",
        "min",
        "max",
        "95 % CI of mean",
        "95 % bootstrap σ",
        "lognormal median, β",
        "load multiplier λ = tan α_max at the mean (95 % CI)",
    ];
    md_table(
        md,
        &header,
        cells.iter().map(|c| {
            let s = &c.collapse;
            let head = [s.n.to_string(), c.failed.to_string(), c.stood.to_string()];
            let tail = [
                format!("{} .. {}", num(s.sd_boot95.0), num(s.sd_boot95.1)),
                c.fragility.map_or("–".into(), |f| format!("{:.2}, {:.3}", f.median, f.beta)),
                load_multiplier(s.mean, s.mean_ci95),
            ];
            cell_row(c, head, spread_cells(s, num), tail)
        }),
    );
}

/// A statistic's mean, σ, COV, min, max and the 95 % interval of its mean, each value but
/// the COV (`num`) written by `f`.
fn spread_cells(s: &crate::stats::Summary, f: impl Fn(f64) -> String) -> [String; 6] {
    [f(s.mean), f(s.sd), num(s.cov), f(s.min), f(s.max), format!("{} .. {}", f(s.mean_ci95.0), f(s.mean_ci95.1))]
}

/// A cell's row of a statistics table: its group and sweep, then `head` (its counts), the
/// `spread` of its statistic ([`spread_cells`]) and the table's own `tail` columns.
fn cell_row<const H: usize, const T: usize>(
    c: &CellSummary,
    head: [String; H],
    spread: [String; 6],
    tail: [String; T],
) -> Vec<String> {
    let mut row = vec![c.group.clone(), sweep_label(c).into()];
    row.extend(head);
    row.extend(spread);
    row.extend(tail);
    row
}

/// The load multiplier of a tilting-table collapse angle (degrees), λ = tan α_max: the
/// out-of-plane load `W sin α` over the weight's normal component `W cos α` at collapse
/// (Santa-Cruz et al. 2021, Eq. 1), at the mean and at the ends of its interval (tan is
/// monotonic on [0°, 90°)).
fn load_multiplier(mean: f64, ci: (f64, f64)) -> String {
    let t = |a: f64| {
        if a.is_finite() && (0.0..90.0).contains(&a) {
            format!("{:.3}", a.to_radians().tan())
        } else {
            "–".into()
        }
    };
    format!("{} ({} .. {})", t(mean), t(ci.0), t(ci.1))
}

/// The displacement at 5° and 10° per cell.
fn displacement_table(cells: &[CellSummary], md: &mut String) {
    let _ = writeln!(md, "\n## Displacement of the top at 5° and 10° [cm]\n");
    let header = ["group", "sweep", "measure", "n at 5°", "mean at 5°", "σ", "n at 10°", "mean at 10°", "σ"];
    md_table(
        md,
        &header,
        cells.iter().map(|c| {
            vec![
                c.group.clone(),
                sweep_label(c).into(),
                c.measure.clone(),
                c.disp5.n.to_string(),
                num(c.disp5.mean),
                num(c.disp5.sd),
                c.disp10.n.to_string(),
                num(c.disp10.mean),
                num(c.disp10.sd),
            ]
        }),
    );
}

/// Measured against simulated, one line per comparison.
fn comparison_table(cmp: &[Comparison], md: &mut String) {
    let _ = writeln!(md, "\n## Measured against simulated\n");
    let _ = writeln!(
        md,
        "The band is the simulated 95 % prediction interval of one realization (mean ± t σ √(1 + 1/n)).\n"
    );
    let header = [
        "group",
        "quantity",
        "measured mean ± σ (n)",
        "simulated mean ± σ (n)",
        "simulated − measured",
        "95 % band",
        "measured mean inside",
        "specimens inside",
    ];
    md_table(
        md,
        &header,
        cmp.iter().map(|c| {
            vec![
                c.group.clone(),
                c.quantity.clone(),
                format!("{:.2} ± {:.2} ({})", c.measured_mean, c.measured_sd, c.measured_n),
                format!("{:.2} ± {:.2} ({})", c.simulated_mean, c.simulated_sd, c.simulated_n),
                format!("{:+.2}", c.simulated_mean - c.measured_mean),
                format!("{:.2} .. {:.2}", c.band.0, c.band.1),
                (if c.inside { "yes" } else { "**no**" }).into(),
                format!("{}/{}", c.specimens_inside, c.measured_n),
            ]
        }),
    );
}

/// The comparisons whose measured mean falls outside the simulated band, and the groups
/// whose band says nothing.
fn misses_section(cmp: &[Comparison], md: &mut String) {
    let misses: Vec<&Comparison> = cmp.iter().filter(|c| !c.inside).collect();
    let _ = writeln!(md, "\n### Where the simulation misses\n");
    if misses.is_empty() {
        let _ = writeln!(md, "Every measured mean falls inside the simulated 95 % band.");
    } else {
        for c in misses {
            let rel = if c.measured_mean != 0.0 {
                100.0 * (c.simulated_mean - c.measured_mean) / c.measured_mean.abs()
            } else {
                f64::NAN
            };
            let _ = writeln!(
                md,
                "- {} {}: measured {:.2} ± {:.2}, simulated {:.2} ± {:.2}: the simulation is {} by {:.2} ({:+.0} %), outside its 95 % band {:.2} .. {:.2}.",
                c.group,
                c.quantity,
                c.measured_mean,
                c.measured_sd,
                c.simulated_mean,
                c.simulated_sd,
                if c.simulated_mean > c.measured_mean { "high" } else { "low" },
                (c.simulated_mean - c.measured_mean).abs(),
                rel,
                c.band.0,
                c.band.1
            );
        }
        let _ = writeln!(md, "\nNo parameter was tuned per specimen to close these gaps; explaining them is the job of the model-discrepancy analysis.");
    }
    for note in degenerate_groups(cmp) {
        let _ = writeln!(md, "\n{note}");
    }
}

/// Displacement against tilt per group (first sweep point): mean and 5–95 % band over the
/// realizations still standing at each tilt, with the measured points.
fn displacement_series(study: &Study, step: f64, rows: &[RealizationRow]) -> Vec<BandSeries> {
    let mut out = Vec::new();
    for (gi, g) in study.groups.iter().enumerate() {
        let measure = measure_of(study, gi);
        let cell: Vec<&RealizationRow> =
            rows.iter().filter(|r| r.group == g.name && r.point == 0 && r.status.is_ok()).collect();
        let max_tilt = cell.iter().flat_map(|r| r.tilt.tilt_deg.iter().copied()).fold(0.0, f64::max);
        let n = (max_tilt / step).round() as usize;
        let (mut x, mut mid, mut lo, mut hi) = (vec![], vec![], vec![], vec![]);
        for k in 0..=n {
            let t = k as f64 * step;
            let v: Vec<f64> = cell.iter().filter_map(|r| r.disp_measure_at(measure, t)).collect();
            if v.len() < 2.max(cell.len() / 2) {
                continue; // fewer than half the realizations still standing
            }
            x.push(t);
            mid.push(stats::mean(&v));
            lo.push(stats::quantile(&v, 0.05));
            hi.push(stats::quantile(&v, 0.95));
        }
        let measured = study
            .measured
            .displacement
            .iter()
            .filter(|m| m.group == g.measured_group)
            .map(|m| (m.tilt_deg, m.displacement_cm))
            .collect();
        out.push(BandSeries {
            label: format!("{} ({})", g.name, measure),
            x,
            mid,
            lo,
            hi,
            measured,
            points_label: None,
            specimens: vec![],
        });
    }
    out
}

/// The fitted fragility of each cell with the ensemble's empirical points (labelled
/// `simulated`) and, at the first sweep point, the measured specimens' empirical points of
/// its group (labelled `measured`).
fn fragility_series(study: &Study, cells: &[CellSummary]) -> Vec<BandSeries> {
    cells
        .iter()
        .filter_map(|c| {
            let f = c.fragility?;
            let max = c.angles.iter().cloned().fold(0.0, f64::max) * 1.3;
            let x: Vec<f64> = (0..=100).map(|i| max * i as f64 / 100.0).collect();
            let p: Vec<f64> = x.iter().map(|&a| f.probability(a)).collect();
            let mut s = c.angles.clone();
            s.sort_by(f64::total_cmp);
            let measured = s.iter().map(|&a| (a, stats::empirical_fragility(&c.angles, a))).collect();
            let tested: Vec<f64> = study
                .measured
                .collapse
                .iter()
                .filter(|m| m.group == study.groups[c.group_index].measured_group && c.point == 0)
                .map(|m| m.collapse_angle_deg)
                .collect();
            let mut sorted = tested.clone();
            sorted.sort_by(f64::total_cmp);
            let specimens = sorted.iter().map(|&a| (a, stats::empirical_fragility(&tested, a))).collect();
            Some(BandSeries {
                label: cell_title(c),
                x,
                mid: p.clone(),
                lo: p.clone(),
                hi: p,
                measured,
                points_label: Some("simulated".into()),
                specimens,
            })
        })
        .collect()
}

/// Counts of the names in `v` (empty names left out), as `name n` joined by `, `, most
/// frequent first (ties by name).
fn counts(v: &[&str]) -> String {
    let mut c: Vec<(&str, usize)> = Vec::new();
    for x in v.iter().filter(|x| !x.is_empty()) {
        match c.iter_mut().find(|(n, _)| n == x) {
            Some(e) => e.1 += 1,
            None => c.push((x, 1)),
        }
    }
    c.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    if c.is_empty() {
        return "–".into();
    }
    c.iter().map(|(n, k)| format!("{n} {k}")).collect::<Vec<_>>().join(", ")
}

/// The failure mechanisms simulated (per group and sweep point: the failure height's mean
/// and range over the realizations that collapsed, the kinds and starts counted) beside
/// the observed ones of the group's specimens (`[measured] mechanism`).
fn mechanism_table(study: &Study, rows: &[RealizationRow], md: &mut String) {
    let read: Vec<&RealizationRow> = rows.iter().filter(|r| r.collapse.failure_height_fraction.is_some()).collect();
    if read.is_empty() {
        return;
    }
    let _ = writeln!(md, "\n## Failure mechanism: simulated and observed\n");
    let _ = writeln!(
        md,
        "Failure height: the lowest bed joint of the moving part over the wall's height (0: the table joint). Start: where the blocks that moved at least half the largest motion lie (`uniform`: over three quarters of the length or more). Simulated at the first unstable state of each realization that collapsed; observed as read on the specimens.\n"
    );
    let _ = writeln!(md, "| group | point | source | n | failure height | kind | start |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- |");
    let mut keys: Vec<(&str, u64, &str)> = Vec::new();
    for r in &read {
        if !keys.iter().any(|k| k.0 == r.group && k.1 == r.point) {
            keys.push((&r.group, r.point, &r.sweep));
        }
    }
    for (group, point, sweep) in keys {
        let these: Vec<&&RealizationRow> = read.iter().filter(|r| r.group == group && r.point == point).collect();
        let h: Vec<f64> = these.iter().filter_map(|r| r.collapse.failure_height_fraction).collect();
        let (lo, hi) = h.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        let kinds: Vec<&str> = these.iter().map(|r| r.collapse.mechanism_kind.as_str()).collect();
        let starts: Vec<&str> = these.iter().map(|r| r.collapse.mechanism_start.as_str()).collect();
        let label = if sweep.is_empty() { point.to_string() } else { sweep.to_string() };
        let _ = writeln!(
            md,
            "| {group} | {label} | simulated | {} | {:.2} [{:.2}, {:.2}] | {} | {} |",
            h.len(),
            crate::stats::mean(&h),
            lo,
            hi,
            counts(&kinds),
            counts(&starts)
        );
        if point != 0 {
            continue;
        }
        let mg = study.groups.iter().find(|g| g.name == group).map(|g| g.measured_group.as_str()).unwrap_or(group);
        let obs: Vec<&crate::io::table::MeasuredMechanism> =
            study.measured.mechanism.iter().filter(|m| m.group == mg).collect();
        if obs.is_empty() {
            continue;
        }
        let heights: Vec<String> =
            obs.iter().filter_map(|m| m.failure_height.map(|(v, a, b)| format!("{v} [{a}, {b}]"))).collect();
        let kinds: Vec<&str> = obs.iter().map(|m| m.kind.map_or("", |k| k.name())).collect();
        let starts: Vec<&str> = obs.iter().map(|m| m.start.map_or("", |s| s.name())).collect();
        let _ = writeln!(
            md,
            "| {group} | – | observed | {} | {} | {} | {} |",
            obs.len(),
            if heights.is_empty() {
                "–".to_string()
            } else {
                counts(&heights.iter().map(String::as_str).collect::<Vec<_>>())
            },
            counts(&kinds),
            counts(&starts)
        );
    }
}

#[cfg(test)]
#[path = "report_tests.rs"]
mod tests;
