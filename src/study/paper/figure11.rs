//! The paper's Figure 11 (§4.2, after Zanelli et al. 2019): drift against L/H with the ends
//! restrained and free. The figure is not tabulated; its finding, stated in the text, is
//! what is checked.

use super::{arrangement_name, curve, restrained, PaperError};
use crate::io::table::{SimpleTable, TableColumn};
use crate::study::summary::CellSummary;
use crate::study::text::{fixed, sci, verdict};
use crate::study::{Study, SweepKey};
use std::fmt::Write as _;
use std::path::Path;

/// "For L/H greater than 4, the restriction no longer influences the out-of-plane
/// behavior" (§4.2).
pub const THRESHOLD_L_OVER_H: f64 = 4.0;

/// The restraint stops mattering where the restrained drift is at least this fraction of
/// the free drift (our reading of "no longer influences": within 10 %).
pub const RESTRAINT_IRRELEVANT_RATIO: f64 = 0.9;

/// The report section: per arrangement, the drift of the restrained and the free wall
/// against L/H and where the restraint stops mattering; the plot and its data.
///
/// # Errors
/// [`PaperError`] naming the file.
pub fn section(study: &Study, cells: &[CellSummary], dir: &Path) -> Result<String, PaperError> {
    let mut md = String::new();
    let _ = writeln!(md, "## Length/height ratio against the paper's Figure 11\n");
    let np = study.points.len();
    let lh: Vec<f64> = (0..np)
        .map(|p| study.sweep_number(p, SweepKey::LengthM).unwrap_or(f64::NAN) / study.groups[0].walls[p].height)
        .collect();
    let mut series = Vec::new();
    let mut csv_cols: Vec<(String, TableColumn)> = vec![("l_over_h".into(), TableColumn::Number(lh.clone()))];
    let drift_of = |gi: usize| -> Vec<f64> {
        (0..np)
            .map(|p| cells.iter().find(|c| c.group_index == gi && c.point == p).map_or(f64::NAN, |c| c.drift.mean))
            .collect()
    };
    // Pair groups by arrangement: restrained with free.
    for (arr, gr, gf) in pairs(study) {
        let (dr, df) = (drift_of(gr), drift_of(gf));
        let ratio: Vec<f64> = dr.iter().zip(&df).map(|(r, f)| r / f).collect();
        let _ = writeln!(md, "### {arr} joints (groups `{}` and `{}`)\n", study.groups[gr].name, study.groups[gf].name);
        let _ = writeln!(md, "| L/H | drift, restrained ends | drift, free ends | restrained / free |");
        let _ = writeln!(md, "| --- | --- | --- | --- |");
        for p in 0..np {
            let _ = writeln!(md, "| {} | {} | {} | {} |", fixed(lh[p], 1), sci(dr[p]), sci(df[p]), fixed(ratio[p], 3));
        }
        let threshold = threshold(&lh, &ratio);
        let ok = threshold.is_some_and(|t| (t - THRESHOLD_L_OVER_H).abs() <= 1.0 + 1e-9);
        let _ = writeln!(
            md,
            "\nThe restraint stops mattering (restrained drift ≥ {:.0} % of the free drift from there on) at L/H = {}; the paper: above L/H ≈ {}. drystone {} (within one step of L/H).\n",
            100.0 * RESTRAINT_IRRELEVANT_RATIO,
            threshold.map_or("never in the range swept".into(), |t| format!("{t:.1}")),
            THRESHOLD_L_OVER_H,
            verdict(ok)
        );
        series.push(curve(format!("{arr}, restrained"), lh.clone(), dr.clone()));
        series.push(curve(format!("{arr}, free"), lh.clone(), df.clone()));
        csv_cols.push((format!("{arr}_restrained_drift"), TableColumn::Number(dr)));
        csv_cols.push((format!("{arr}_free_drift"), TableColumn::Number(df)));
        csv_cols.push((format!("{arr}_ratio"), TableColumn::Number(ratio)));
    }
    let _ = writeln!(md, "Where this disagrees, the likely reasons: Figure 11 comes from Zanelli et al. (2019) with 3DEC models whose block sizes and restraint details the paper does not give; ours holds every block within 0.05 m of an end rigidly in y (`ends = \"rigid\"`), the stiffest reading.\n");
    super::plot_bands(
        dir,
        "figure11_length_height.svg",
        "Drift against L/H (paper Figure 11)",
        "L/H",
        "drift (top displacement / H)",
        &series,
    )?;
    SimpleTable { columns: csv_cols }.write_csv(&dir.join("figure11.csv"))?;
    let _ = writeln!(md, "![Figure 11](figure11_length_height.svg)\n\nData: `figure11.csv`.\n");
    Ok(md)
}

/// For each arrangement, in the order the groups first show it: its name and the groups
/// with restrained and with free ends (arrangements lacking either are left out).
fn pairs(study: &Study) -> Vec<(&'static str, usize, usize)> {
    let mut arrangements: Vec<&str> = Vec::new();
    for g in &study.groups {
        let a = arrangement_name(&g.walls[0].arrangement);
        if !arrangements.contains(&a) {
            arrangements.push(a);
        }
    }
    let find = |arr: &str, held: bool| {
        study
            .groups
            .iter()
            .position(|g| arrangement_name(&g.walls[0].arrangement) == arr && restrained(&g.walls[0].ends) == held)
    };
    arrangements.into_iter().filter_map(|arr| Some((arr, find(arr, true)?, find(arr, false)?))).collect()
}

/// The smallest L/H from which on the restraint changes the drift by less than 10 %.
fn threshold(lh: &[f64], ratio: &[f64]) -> Option<f64> {
    let mut threshold = None;
    for p in (0..lh.len()).rev() {
        if ratio[p].is_finite() && ratio[p] >= RESTRAINT_IRRELEVANT_RATIO {
            threshold = Some(lh[p]);
        } else {
            break;
        }
    }
    threshold
}
