//! The paper's Figure 10 (§4.1): top displacement of the full-scale wall under the static
//! trapezoidal load against Kn, for continuous, discontinuous and irregular joints. The
//! figure is not tabulated; its findings, stated in the text, are what is checked.

use super::{arrangement_name, curve, PaperError};
use crate::io::plot::BandSeries;
use crate::io::table::{SimpleTable, TableColumn};
use crate::study::summary::CellSummary;
use crate::study::text::{finite_mean, fixed, md_table, pct, verdict};
use crate::study::{Study, SweepKey};
use std::fmt::Write as _;
use std::path::Path;

/// Continuous joints: displacement relative to discontinuous, "decrease by
/// approximately 40 %".
pub const CONTINUOUS_VS_DISCONTINUOUS: f64 = -0.40;
/// Irregular joints: mean displacement relative to discontinuous, "25 % lower".
pub const IRREGULAR_VS_DISCONTINUOUS: f64 = -0.25;
/// Irregular joints: COV of the displacement, "between approximately 21 and 25 %".
pub const IRREGULAR_COV: (f64, f64) = (0.21, 0.25);

/// Top displacement per Kn and arrangement, mm (NaN where a cell is missing).
struct Figure10 {
    kn: Vec<f64>,
    continuous: Vec<f64>,
    discontinuous: Vec<f64>,
    irregular: Vec<f64>,
    irregular_sd: Vec<f64>,
    irregular_cov: Vec<f64>,
}

fn mm(cm: f64) -> f64 {
    10.0 * cm
}

/// The report section: the table, the findings against the paper's, the plot and its data.
///
/// # Errors
/// [`PaperError`] naming the file.
pub fn section(study: &Study, cells: &[CellSummary], dir: &Path) -> Result<String, PaperError> {
    let mut md = String::new();
    let _ = writeln!(md, "## Joint arrangement against the paper's Figure 10\n");
    let data = table(study, cells, &mut md);
    findings(&data, &mut md);
    let _ = writeln!(md, "Where these disagree, the likely reasons: the paper's Figure 9 layouts and block sizes are not given (ours: 0.5 m × 0.2 m blocks, irregular courses 0.17–0.23 m with wedges, see `studies/walls/full_scale*.toml`); the meaning of *continuous* (ours: head joints aligned through all courses; a reading where each course is one block would make the continuous wall much stiffer between its restrained ends); the load values (not given; ours in `[lateral]`); and 3DEC's deformable-block and contact discretisation against our rigid blocks with exactly integrated sub-contacts.\n");
    figure(data, dir)?;
    let _ = writeln!(md, "![Figure 10](figure10_joint_arrangement.svg)\n\nData: `figure10.csv`.\n");
    Ok(md)
}

/// The displacements per Kn, written as a markdown table.
fn table(study: &Study, cells: &[CellSummary], md: &mut String) -> Figure10 {
    let cell = |arr: &str, p: usize| {
        cells
            .iter()
            .find(|c| c.point == p && arrangement_name(&study.groups[c.group_index].walls[p].arrangement) == arr)
    };
    let mut d = Figure10 {
        kn: vec![],
        continuous: vec![],
        discontinuous: vec![],
        irregular: vec![],
        irregular_sd: vec![],
        irregular_cov: vec![],
    };
    let _ = writeln!(md, "Top displacement (largest of the three top points) under the static trapezoidal load, mm. Irregular: mean ± σ over the realizations that reached equilibrium.\n");
    let _ = writeln!(
        md,
        "| Kn [1e7 Pa/m] | continuous | discontinuous | irregular mean ± σ (n) | irregular COV | continuous vs discontinuous | irregular vs discontinuous |"
    );
    let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- |");
    for p in 0..study.points.len() {
        let k = study.sweep_number(p, SweepKey::KnPaPerM).unwrap_or(f64::NAN);
        let get = |arr: &str| cell(arr, p).map_or(f64::NAN, |c| mm(c.lateral_max.mean));
        let (c, dd) = (get("continuous"), get("discontinuous"));
        let (i, isd, icov, n) = cell("irregular", p).map_or((f64::NAN, f64::NAN, f64::NAN, 0), |c| {
            (mm(c.lateral_max.mean), mm(c.lateral_max.sd), c.lateral_max.cov, c.lateral_max.n)
        });
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} ± {} ({}) | {} | {} | {} |",
            fixed(k / 1e7, 1),
            fixed(c, 3),
            fixed(dd, 3),
            fixed(i, 3),
            fixed(isd, 3),
            n,
            fixed(icov, 3),
            pct(c / dd - 1.0),
            pct(i / dd - 1.0)
        );
        d.kn.push(k);
        d.continuous.push(c);
        d.discontinuous.push(dd);
        d.irregular.push(i);
        d.irregular_sd.push(isd);
        d.irregular_cov.push(icov);
    }
    d
}

/// The paper's findings (§4.1 text) against ours.
fn findings(d: &Figure10, md: &mut String) {
    let rel = |a: &[f64]| -> Vec<f64> { a.iter().zip(&d.discontinuous).map(|(x, y)| x / y - 1.0).collect() };
    let cd = finite_mean(&rel(&d.continuous));
    let id = finite_mean(&rel(&d.irregular));
    let covs: Vec<f64> = d.irregular_cov.iter().copied().filter(|x| x.is_finite()).collect();
    let (cov_lo, cov_hi) = if covs.is_empty() {
        (f64::NAN, f64::NAN)
    } else {
        (covs.iter().cloned().fold(f64::INFINITY, f64::min), covs.iter().cloned().fold(f64::NEG_INFINITY, f64::max))
    };
    let disc = &d.discontinuous;
    let disc_largest = (0..d.kn.len()).all(|p| disc[p] >= d.continuous[p] && disc[p] >= d.irregular[p]);
    let decreasing = |v: &[f64]| v.windows(2).all(|w| w[1] <= w[0]);
    let near = |ours: f64, paper: f64| (ours - paper).abs() <= 0.10;
    let cov_ok = cov_lo >= IRREGULAR_COV.0 - 0.05 && cov_hi <= IRREGULAR_COV.1 + 0.05;
    let yes = |b: bool| if b { "yes" } else { "no" };
    let dec = decreasing(&d.continuous) && decreasing(disc) && decreasing(&d.irregular);
    let row = |finding: &str, paper: String, ours: String, verdict_text: String| {
        vec![finding.to_string(), paper, ours, verdict_text]
    };
    let rows = vec![
        row(
            "continuous vs discontinuous, mean over Kn",
            pct(CONTINUOUS_VS_DISCONTINUOUS),
            pct(cd),
            format!("{} (within 10 points)", verdict(near(cd, CONTINUOUS_VS_DISCONTINUOUS))),
        ),
        row(
            "irregular mean vs discontinuous, mean over Kn",
            pct(IRREGULAR_VS_DISCONTINUOUS),
            pct(id),
            format!("{} (within 10 points)", verdict(near(id, IRREGULAR_VS_DISCONTINUOUS))),
        ),
        row(
            "irregular COV over Kn",
            format!("{:.0}–{:.0} %", 100.0 * IRREGULAR_COV.0, 100.0 * IRREGULAR_COV.1),
            format!("{}–{} %", fixed(100.0 * cov_lo, 0), fixed(100.0 * cov_hi, 0)),
            format!("{} (within 5 points)", verdict(cov_ok)),
        ),
        row(
            "discontinuous has the largest displacement at every Kn",
            "yes".into(),
            yes(disc_largest).into(),
            verdict(disc_largest).into(),
        ),
        row("displacement falls as Kn grows (every arrangement)", "yes".into(), yes(dec).into(), verdict(dec).into()),
    ];
    md.push('\n');
    md_table(md, &["finding (paper §4.1)", "paper", "drystone", ""], rows);
    md.push('\n');
}

/// `figure10_joint_arrangement.svg` and `figure10.csv`.
fn figure(d: Figure10, dir: &Path) -> Result<(), PaperError> {
    let x: Vec<f64> = d.kn.iter().map(|k| k / 1e7).collect();
    let series = vec![
        curve("continuous".into(), x.clone(), d.continuous.clone()),
        curve("discontinuous".into(), x.clone(), d.discontinuous.clone()),
        BandSeries {
            label: "irregular mean ± σ".into(),
            x,
            mid: d.irregular.clone(),
            lo: d.irregular.iter().zip(&d.irregular_sd).map(|(m, s)| m - s).collect(),
            hi: d.irregular.iter().zip(&d.irregular_sd).map(|(m, s)| m + s).collect(),
            measured: vec![],
            points_label: None,
            specimens: vec![],
        },
    ];
    super::plot_bands(
        dir,
        "figure10_joint_arrangement.svg",
        "Top displacement under the trapezoidal load (paper Figure 10)",
        "Kn [1e7 Pa/m]",
        "top displacement [mm]",
        &series,
    )?;
    SimpleTable {
        columns: vec![
            ("kn_pa_per_m".into(), TableColumn::Number(d.kn)),
            ("continuous_mm".into(), TableColumn::Number(d.continuous)),
            ("discontinuous_mm".into(), TableColumn::Number(d.discontinuous)),
            ("irregular_mean_mm".into(), TableColumn::Number(d.irregular)),
            ("irregular_sd_mm".into(), TableColumn::Number(d.irregular_sd)),
            ("irregular_cov".into(), TableColumn::Number(d.irregular_cov)),
        ],
    }
    .write_csv(&dir.join("figure10.csv"))?;
    Ok(())
}
