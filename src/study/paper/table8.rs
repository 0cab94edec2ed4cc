//! The paper's Table 8 (§6): the lateral capacity ratio sin α_max restrained / free over
//! the (Kn, φ) points of Table 7, from its DEM and from the tilting tests.

use super::table7::Table7;
use crate::study::text::{fixed, pct};
use std::fmt::Write as _;

/// DEM mean.
pub const MEAN: f64 = 1.38;
/// DEM min.
pub const MIN: f64 = 1.14;
/// DEM max.
pub const MAX: f64 = 1.70;
/// Tilting tests (SBR / SBL).
pub const TESTS: f64 = 1.35;

/// Mean, min and max of the finite values (NaN without any).
fn mean_min_max(v: &[f64]) -> (f64, f64, f64) {
    let v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        (f64::NAN, f64::NAN, f64::NAN)
    } else {
        (
            crate::stats::mean(&v),
            v.iter().cloned().fold(f64::INFINITY, f64::min),
            v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        )
    }
}

/// The report section: the ratio from the paper's Table 8, from its Table 7 recomputed, and
/// from drystone's Table 7; why the two DEMs may differ.
pub fn section(t7: &Table7) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "## Restraint ratio: the paper's Table 8\n");
    let (m, lo, hi) = mean_min_max(&t7.ratio);
    let (pm, plo, phi) = mean_min_max(&t7.paper_ratio);
    let _ = writeln!(md, "Lateral capacity ratio sin α_max(restrained) / sin α_max(free) over the (Kn, φ) points.\n");
    let _ = writeln!(md, "| source | mean | min | max |");
    let _ = writeln!(md, "| --- | --- | --- | --- |");
    let _ = writeln!(md, "| paper, Table 8 (DEM) | {MEAN:.2} | {MIN:.2} | {MAX:.2} |");
    let _ =
        writeln!(md, "| paper, Table 7 recomputed here | {} | {} | {} |", fixed(pm, 2), fixed(plo, 2), fixed(phi, 2));
    let _ = writeln!(md, "| paper, tilting tests (SBR / SBL) | {TESTS:.2} | | |");
    let _ = writeln!(md, "| drystone | {} | {} | {} |\n", fixed(m, 2), fixed(lo, 2), fixed(hi, 2));
    let _ = writeln!(
        md,
        "drystone's mean ratio is {} the paper's DEM ({:.2}) and {} the tests ({:.2}).\n",
        pct(m / MEAN - 1.0).replace(" %", " % from"),
        MEAN,
        pct(m / TESTS - 1.0).replace(" %", " % from"),
        TESTS
    );
    let _ = writeln!(md, "Where drystone and the paper's DEM differ, the likely reasons: the paper modelled the stones as clumps of spheres (rounded edges, contact stiffness per sphere pair, not per unit area), whereas drystone uses polyhedra with Kn per unit area integrated exactly over each sub-contact; our wall is a generated layout of the specimen (`studies/walls/sbl.toml`, `sbr.toml`), not the paper's 124-block model; and the restrained ends are held rigidly.\n");
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_min_max_skips_values_that_are_not_finite() {
        assert_eq!(mean_min_max(&[1.0, f64::NAN, 3.0]), (2.0, 1.0, 3.0));
        assert!(mean_min_max(&[f64::NAN]).0.is_nan());
    }
}
