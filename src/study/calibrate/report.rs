//! The calibration's outputs: a markdown section and `calibration.md` / `calibration.json`.

use super::{CalibrateError, CalibrateSpec, StepResult};
use crate::study::Study;
use std::fmt::Write as _;
use std::path::Path;

/// The value of the step's parameter with its unit.
pub(super) fn fmt_value(spec: &CalibrateSpec, v: f64) -> String {
    if spec.is_kn() {
        format!("{v:.3e} Pa/m")
    } else {
        format!("{v:.1}°")
    }
}

/// The calibration as markdown (a section of `report.md`).
pub fn markdown(study: &Study, results: &[StepResult]) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "## Calibration against the measured collapse angles: the paper's Table 9\n");
    let _ = writeln!(
        md,
        "Brent root finding (argmin) of mean α_max(x) = measured mean, x = log10 Kn or φ; each evaluation is an ensemble of {} realization(s) with the study's seed. Steps in order; a value found is carried to the later steps of the same material.\n",
        study.realizations
    );
    let _ = writeln!(md, "| step | group | parameter | given | measured α_max [deg] | outcome | drystone | 95 % interval (standard errors) | specimen spread (±1 σ) | paper (Table 9) |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for (i, r) in results.iter().enumerate() {
        let kn = r.parameter == "kn_pa_per_m";
        let v = |x: f64| if kn { format!("{x:.3e}") } else { format!("{x:.1}") };
        let given: Vec<String> = r
            .given
            .iter()
            .map(|(k, x)| if k == "kn_pa_per_m" { format!("Kn {x:.3e}") } else { format!("{k} {x:.1}") })
            .collect();
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} ± {:.2} ({}) | {} | {} | {} | {} | {} |",
            i + 1,
            r.group,
            r.parameter,
            if given.is_empty() { "–".into() } else { given.join(", ") },
            r.measured.0,
            r.measured.1,
            r.measured.2,
            r.outcome.replace('_', " "),
            r.value.map_or("–".into(), v),
            r.interval95.map_or("–".into(), |(a, b)| format!("{} .. {}", v(a), v(b))),
            r.spread.map_or("–".into(), |(a, b)| format!("{} .. {}", v(a), v(b))),
            r.paper_value.map_or("–".into(), v)
        );
    }
    let _ = writeln!(md);
    for (i, r) in results.iter().enumerate() {
        let _ = writeln!(md, "- Step {}: {}.", i + 1, r.note);
        if let (Some(v), Some(p)) = (r.value, r.paper_value) {
            let _ = writeln!(
                md,
                "  drystone {} the paper's value by {:.0} %{}.",
                if v > p { "exceeds" } else { "is below" },
                100.0 * (v / p - 1.0).abs(),
                match r.interval95 {
                    Some((a, b)) if a <= p && p <= b => ", inside the 95 % interval",
                    Some(_) => ", outside the 95 % interval",
                    None => "",
                }
            );
        }
        let ev: Vec<String> = r
            .evaluations
            .iter()
            .map(|e| {
                if r.parameter == "kn_pa_per_m" {
                    format!("{:.3e} → {:.2}°", e.value, e.mean_deg)
                } else {
                    format!("{:.1}° → {:.2}°", e.value, e.mean_deg)
                }
            })
            .collect();
        let _ = writeln!(md, "  Evaluations (value → mean α_max): {}.", ev.join("; "));
    }
    let _ = writeln!(md, "\nThe paper fitted its clump model by hand; drystone's polyhedral blocks with Kn per unit area integrated exactly over the sub-contacts are stiffer in rocking at the same Kn (the paper's clumps touch at sphere caps), so a different Kn is expected where the two models disagree (see the Kn–φ comparison).\n");
    md
}

/// Writes a calibration's outputs (`calibration.md`, `calibration.json`) into `dir` and
/// returns the markdown.
///
/// # Errors
/// [`CalibrateError::Io`] naming the file.
pub fn write_calibration(study: &Study, results: &[StepResult], dir: &Path) -> Result<String, CalibrateError> {
    fn io(path: &Path) -> impl FnOnce(std::io::Error) -> CalibrateError + '_ {
        move |source| CalibrateError::Io { path: path.to_owned(), source }
    }
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let md = format!("# Study `{}`\n\n{}\n\n{}", study.name, study.description.trim(), markdown(study, results));
    let replace = |name: &str, bytes: &[u8]| {
        crate::io::replace_file(&dir.join(name), bytes)
            .map_err(|e| CalibrateError::Io { path: e.path, source: e.source })
    };
    replace("calibration.md", md.as_bytes())?;
    replace("calibration.json", serde_json::to_string_pretty(results).unwrap_or_default().as_bytes())?;
    Ok(md)
}
