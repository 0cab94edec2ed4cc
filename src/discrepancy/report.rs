//! The discrepancy report: `discrepancy.md`, `discrepancy.json` (the command-line contract),
//! `residuals.svg` (standardized held-out residuals of every observation, baseline and
//! extended model) and `displacement_<group>.svg` (displacement against tilt, both models'
//! bands and the measured points).

use super::analysis::Ranked;
use super::observations::{Family, Observable, Observation};
use super::predictive::Predictive;
use super::simulate::Outcome;
use super::Run;
use crate::io::plot::{bands, residuals, BandSeries, PlotError, ResidualSeries};
use crate::io::FileError;
use crate::protocol::Output;
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

fn params_json(r: &Ranked) -> Value {
    Value::Object(r.parameters.iter().map(|(k, v)| (k.clone(), json!(v))).collect())
}

/// Whether a search coordinate is at a bound of its range.
fn at_bound(x: f64) -> bool {
    x <= 1e-6 || x >= 1.0 - 1e-6
}

/// The fitted parameters at a bound of their range (the data would take them further).
fn bound_names(r: &Ranked) -> Vec<String> {
    r.parameters.iter().zip(&r.x).filter(|(_, &x)| at_bound(x)).map(|((k, _), _)| k.clone()).collect()
}

/// The fitted values in the ranges of each declared kind of the analysed walls.
fn by_kind(run: &Run, r: &Ranked) -> Vec<(crate::effects::WallKind, Vec<(String, f64)>)> {
    run.analysis.pool.get(r.index).filter(|c| c.name() == r.name).map_or(vec![], |c| c.values_by_kind(&r.x))
}

/// `parameters`, and `at_bound` (names of the parameters fitted at a bound of their range)
/// and `parameters_by_kind` (`{kind: {effect.param: value}}`) when not empty.
fn add_bounds_and_kinds(run: &Run, r: &Ranked, v: &mut Value) {
    let bound = bound_names(r);
    if !bound.is_empty() {
        v["at_bound"] = json!(bound);
    }
    let kinds = by_kind(run, r);
    if !kinds.is_empty() {
        v["parameters_by_kind"] = Value::Object(
            kinds
                .into_iter()
                .map(|(k, ps)| {
                    (k.name().to_string(), Value::Object(ps.into_iter().map(|(n, x)| (n, json!(x))).collect()))
                })
                .collect(),
        );
    }
}

fn ranked_json(run: &Run, r: &Ranked) -> Value {
    let mut v = json!({
        "name": r.name,
        "effects": r.name.split('+').collect::<Vec<_>>(),
        "parameters": params_json(r),
        "heldout_error": r.heldout_error,
        "difference_se": r.difference_se,
        "information_criterion": r.information_criterion,
        "confirmed_by_full_run": r.confirmed,
    });
    add_bounds_and_kinds(run, r, &mut v);
    v
}

fn observations_json(obs: &[Observation], pred: &[Predictive]) -> Value {
    Value::Array(
        obs.iter()
            .zip(pred)
            .map(|(o, p)| {
                json!({
                    "specimen": o.specimen,
                    "group": o.group,
                    "observable": o.observable.label(),
                    "unit": o.observable.unit(),
                    "value": o.value,
                    "sigma": o.sigma,
                    "mean": p.mean,
                    "sd": p.sd,
                    "z": p.z(o.value),
                })
            })
            .collect(),
    )
}

/// One row of the diagnosis: a group's observable, measured against simulated.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DiagnosisRow {
    /// Group.
    pub group: String,
    /// Observable label.
    pub observable: String,
    /// Unit.
    pub unit: String,
    /// Specimens measured.
    pub n: usize,
    /// Measured mean.
    pub measured_mean: f64,
    /// Specimen-to-specimen standard deviation.
    pub measured_sd: f64,
    /// Simulated mean (baseline).
    pub simulated_mean: f64,
    /// Realization-to-realization standard deviation (baseline).
    pub simulated_sd: f64,
    /// Mean standardized residual.
    pub mean_z: f64,
}

/// The diagnosis table: every key of the run, with the baseline's full run.
pub fn diagnosis(run: &Run, outcomes: &[Vec<Outcome>]) -> Vec<DiagnosisRow> {
    let sims = run.keys.simulated(outcomes);
    run.keys
        .keys
        .iter()
        .enumerate()
        .map(|(k, (_, ob))| {
            let idx: Vec<usize> = (0..run.obs.len()).filter(|&j| run.keys.of[j] == k).collect();
            let vals: Vec<f64> = idx.iter().map(|&j| run.obs[j].value).collect();
            let z: Vec<f64> = idx.iter().map(|&j| run.analysis.baseline_predictive[j].z(run.obs[j].value)).collect();
            DiagnosisRow {
                group: run.obs[idx[0]].group.clone(),
                observable: ob.label(),
                unit: ob.unit().to_string(),
                n: vals.len(),
                measured_mean: crate::stats::mean(&vals),
                measured_sd: if vals.len() > 1 { crate::stats::sd(&vals) } else { 0.0 },
                simulated_mean: sims[k].mean,
                simulated_sd: sims[k].sd,
                mean_z: crate::stats::mean(&z),
            }
        })
        .collect()
}

/// The JSON object of the command-line contract.
pub fn report_json(run: &Run) -> Value {
    let a = &run.analysis;
    let cause = a.cause.as_ref().map(|c| {
        let mut v =
            json!({ "name": c.name, "effects": c.name.split('+').collect::<Vec<_>>(), "parameters": params_json(c) });
        add_bounds_and_kinds(run, c, &mut v);
        v
    });
    let extended = a.cause.as_ref().map(|c| {
        let (g, lo, hi) = run.gain.unwrap_or((0.0, 0.0, 0.0));
        json!({
            "effects": run.extended.as_ref().map(|(e, _)| e.iter().map(|e| e.label()).collect::<Vec<_>>()),
            "heldout_error": c.heldout_error,
            "gain": { "heldout_error": g, "ci95": [lo, hi] },
            "heldout": observations_json(&run.obs, &c.predictive),
            "observations": observations_json(&run.obs, &run.extended_predictive),
        })
    });
    let mut v = json!({
        "verdict": a.verdict.name(),
        "cause": cause,
        "partial": a.verdict == super::analysis::Verdict::Unexplained && a.cause.is_some(),
        "systematic_misfit": a.systematic,
        "refuted": a.refuted,
        "check": a.check,
        "design": run.design,
        "cause_interval": run.cause_interval,
        "tie": a.tie,
        "named_alone": a.named_alone(),
        "tie_checks": a.tie_checks,
        "screen_gain": a.screen_gain,
        "candidates": a.candidates.iter().map(|r| ranked_json(run, r)).collect::<Vec<_>>(),
        "baseline": {
            "heldout_error": a.baseline_heldout_error,
            "information_criterion": a.baseline_information_criterion,
            "observations": observations_json(&run.obs, &a.baseline_predictive),
        },
        "extended": extended,
        "margins": a.margins,
        "weights": a.weights,
        "identifiability": a.identifiability,
        "diagnosis": diagnosis(run, &run.baseline),
        "forward_runs": a.forward_runs,
        "settings": run.settings,
    });
    if let (Some(plan), Some(m)) = (&run.followup, v.as_object_mut()) {
        m.insert("followup".into(), json!(plan));
    }
    v
}

/// `name = value` for every fitted parameter, flagging a value at a bound of its range
/// (the data would take it further: the range, or the effect, does not fit them), with
/// its value for each declared kind of wall that has a range of its own (`[kind: value]`).
fn fmt_params(run: &Run, r: &Ranked) -> String {
    let kinds = by_kind(run, r);
    r.parameters
        .iter()
        .enumerate()
        .zip(r.x.iter().chain(std::iter::repeat(&0.5)))
        .map(|((i, (k, v)), x)| {
            let bound = if at_bound(*x) { " (at a bound of its range)" } else { "" };
            let per: Vec<String> = kinds
                .iter()
                .filter_map(|(kind, ps)| {
                    ps.get(i).filter(|(_, pv)| pv != v).map(|(_, pv)| format!("{}: {pv:.3e}", kind.name()))
                })
                .collect();
            let per = if per.is_empty() { String::new() } else { format!(" [{}]", per.join(", ")) };
            format!("{k} = {v:.3e}{per}{bound}")
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The Markdown report.
pub fn report_markdown(run: &Run, study: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Model discrepancy: {study}\n");
    verdict_section(&mut md, run);
    diagnosis_section(&mut md, run);
    candidates_section(&mut md, run);
    weights_section(&mut md, run);
    extended_section(&mut md, run);
    if let Some(plan) = &run.followup {
        md.push_str(&super::design::markdown(plan));
    }
    runs_section(&mut md, run);
    md
}

/// The forward runs the analysis made, by stage, and their total.
fn runs_section(md: &mut String, run: &Run) {
    let runs = &run.analysis.forward_runs;
    if runs.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "## Forward runs
"
    );
    let _ = writeln!(md, "| stage | runs |\n| --- | --- |");
    for r in runs {
        let _ = writeln!(md, "| {} | {} |", r.stage, r.runs);
    }
    let total: usize = runs.iter().map(|r| r.runs).sum();
    let _ = writeln!(md, "| total | {total} |\n");
}

/// The verdict, its predictive check, what would separate a tie and the measurement σ used.
fn verdict_section(md: &mut String, run: &Run) {
    let a = &run.analysis;
    let verdict = match (&a.cause, a.tie.len(), a.verdict) {
        (Some(c), _, super::analysis::Verdict::Unexplained) => format!(
            "**unexplained**: the best candidate `{}` ({}) beats the baseline but still misfits the data (posterior predictive check), a partial explanation at most",
            c.name,
            fmt_params(run, c)
        ),
        (Some(c), 1, _) => format!("**explained** by `{}` ({})", c.name, fmt_params(run, c)),
        (Some(c), _, _) => format!(
            "**explained**, best `{}` ({}), but indistinguishable from: {}",
            c.name,
            fmt_params(run, c),
            a.tie[1..].join(", ")
        ),
        (None, _, _) => format!("**{}**", a.verdict.name()),
    };
    let _ = writeln!(md, "Verdict: {verdict}.\n");
    if !a.refuted.is_empty() {
        let _ = writeln!(
            md,
            "Refuted by a reading, and so neither confirmed, named nor in the tie (a candidate that predicts one reading worse than the baseline by more than {} nats, a likelihood ratio of 20, and beyond {} standard errors over the specimens; a held reading by its own statistic):\n",
            super::REFUTE_NATS,
            super::REFUTE_Z
        );
        for f in &a.refuted {
            let _ = writeln!(md, "- `{}`, by the {}: {}", f.candidate, f.reading, f.words);
        }
        md.push('\n');
    }
    match (a.named_alone(), &a.cause) {
        (Some(c), _) => {
            let _ = writeln!(md, "Named alone: `{c}` (the tie check clears every challenger; the one meaning of \"named alone\", which `drystone design` predicts).\n");
        }
        (None, Some(_)) if a.verdict != super::analysis::Verdict::Explained => {
            let _ = writeln!(
                md,
                "Not named alone: the verdict is {}, the best candidate only a partial explanation.\n",
                a.verdict.name()
            );
        }
        (None, Some(_)) => {
            let _ = writeln!(md, "Not named alone: the tie holds {} models.\n", a.tie.len());
        }
        (None, None) => {}
    }
    if let Some(m) = &a.systematic {
        let z: Vec<String> = m.groups.iter().map(|(g, z)| format!("{g} {z:+.2}")).collect();
        let _ = writeln!(
            md,
            "The baseline's misfit is systematic in the {}: its mean standardized residual has one sign in every group ({}), so `scatter` (a spread alone) is not a cause of it.\n",
            m.family,
            z.join(", ")
        );
    }
    if let Some(ch) = &a.check {
        let measures = if curve_measures(run) {
            "the peak forces, drifts and stiffnesses"
        } else {
            "the collapse angles, displacements and failure heights"
        };
        let _ = writeln!(md, "Posterior predictive check of the {} model: score {:.3} per specimen on {measures} against {:.3}, the 95th percentile of the same score on {} data sets simulated from its own independent layouts ({}).{}\n",
            if a.verdict == super::analysis::Verdict::NoEffect || a.cause.is_none() { "baseline" } else { "extended" },
            ch.score, ch.envelope, ch.replicates, if ch.passes() { "passes" } else { "fails" },
            if ch.missed.is_empty() { String::new() } else {
                format!(" Observables it misses (mean z): {}.", ch.missed.iter().map(|(k, z)| format!("{k} ({z:+.2})")).collect::<Vec<_>>().join(", "))
            });
    }
    if let Some(d) = &run.design {
        let _ = writeln!(md, "This design cannot separate `{}` and `{}`: they differ most in {} ({:.2} predictive σ); about {} specimens of that group would tell them apart (two-sided 5 %, power 80 %; check with `drystone synthesize`).\n",
            d.candidates.0, d.candidates.1, d.observable, d.effect_size, d.specimens);
    }
    let s = &run.settings;
    let used = |family: Family, setting: f64, unit: &str, what: &str| {
        match run.sigma_estimate[family.index()] {
        Some((sd, dof)) if sd > setting => format!("{sd:.3} {unit} ({what}: the spread the specimens show beyond the model's, {dof} degrees of freedom, larger than the setting {setting} {unit})"),
        Some((sd, dof)) => format!("{setting} {unit} ({what}: the setting; the specimens' spread beyond the model's is {sd:.3} {unit}, {dof} degrees of freedom)"),
        None => format!("{setting} {unit} ({what}: the setting; too few specimens per group for an estimate)"),
    }
    };
    if curve_measures(run) {
        let _ = writeln!(
            md,
            "Measurement σ used: {}, {}, {}, {}, {}; readings taken as intervals of {} kN, {} %, {} kN/mm, {} MPa and {} kN (asymmetries).\n",
            used(Family::PeakForce, s.sigma.force_kn, "kN", "peak forces"),
            used(Family::DriftAtPeak, s.sigma.drift_pct, "%", "drifts at the peak"),
            used(Family::InitialStiffness, s.sigma.stiffness_kn_per_mm, "kN/mm", "initial stiffnesses"),
            used(Family::VerticalModulus, s.sigma.modulus_mpa, "MPa", "walls' vertical moduli"),
            used(Family::PeakAsymmetry, s.sigma.asymmetry_kn, "kN", "peaks' ± asymmetries"),
            s.reading.force_kn,
            s.reading.drift_pct,
            s.reading.stiffness_kn_per_mm,
            s.reading.modulus_mpa,
            s.reading.asymmetry_kn
        );
        for note in &s.sigma_notes {
            let _ = writeln!(md, "- {note}");
        }
        if !s.sigma_notes.is_empty() {
            let _ = writeln!(md);
        }
        return;
    }
    let _ = writeln!(
        md,
        "Measurement σ used: {}, {}; readings taken as intervals of {} deg and {} cm.\n",
        used(Family::CollapseAngle, s.sigma.angle_deg, "deg", "collapse angles"),
        used(Family::Displacement, s.sigma.displacement_cm, "cm", "displacements"),
        s.reading.angle_deg,
        s.reading.displacement_cm
    );
}
/// What the model gets wrong: the baseline against every group and observable.
fn diagnosis_section(md: &mut String, run: &Run) {
    let _ = writeln!(md, "## What the model gets wrong\n");
    let _ = writeln!(md, "Baseline ensemble against every observation: measured mean ± specimen σ, simulated mean ± realization σ, and the mean standardized residual z = (measured − predicted)/predictive σ.\n");
    let _ = writeln!(md, "| group | observable | n | measured | simulated | mean z | spread ratio (sim/meas) |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- |");
    for r in diagnosis(run, &run.baseline) {
        let ratio = if r.measured_sd > 0.0 { format!("{:.2}", r.simulated_sd / r.measured_sd) } else { "–".into() };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2} ± {:.2} {} | {:.2} ± {:.2} {} | {:+.2} | {} |",
            r.group,
            r.observable,
            r.n,
            r.measured_mean,
            r.measured_sd,
            r.unit,
            r.simulated_mean,
            r.simulated_sd,
            r.unit,
            r.mean_z,
            ratio
        );
    }
    let _ = writeln!(md, "\n![standardized residuals](residuals.svg)\n");
}
/// The candidates ranked, the margins and their false-alarm rate, the tie checks.
fn candidates_section(md: &mut String, run: &Run) {
    let a = &run.analysis;
    let _ = writeln!(md, "## Candidates\n");
    let _ = writeln!(md, "Held-out error: mean score per specimen (negative log predictive probability of each reading, a specimen's displacements counting as one observation), each specimen predicted by the model fitted to the other specimens (leave one specimen out); ± the standard error of its difference to the baseline. AICc at the fit to all data, n = specimens. Common random numbers: the same layouts and seeds for every candidate. `full run`: re-run as a full ensemble at its fitted parameters and scored by that run.\n");
    let _ = writeln!(md, "| rank | candidate | fitted parameters | held-out error | AICc | scored by |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- |");
    let _ = writeln!(
        md,
        "| – | baseline | – | {:.3} | {:.1} | full run |",
        a.baseline_heldout_error, a.baseline_information_criterion
    );
    for (i, c) in a.candidates.iter().enumerate() {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.3} ± {:.3} | {:.1} | {} |",
            i + 1,
            c.name,
            fmt_params(run, c),
            c.heldout_error,
            c.difference_se,
            c.information_criterion,
            if c.confirmed {
                "full run"
            } else if c.name == "scatter" {
                "analytic"
            } else {
                "surrogate"
            }
        );
    }
    let m = &a.margins;
    let _ = writeln!(md, "\nMargins from {} null data sets drawn from the baseline on independent layouts, read as the data are: a cause must beat the baseline by {:.3} (held-out error), on the surrogates as the null data sets were scored (here the best does by {:.3}) and again after the confirmation runs; the baseline's misfit is significant above {:.3} (the two margins set together, so that a new null data set raises either alarm with probability at most 5 %: (u + 2)/(n + 1) for u of the n null sets above either). False alarms of margins set on one half of the null data sets, counted on the other half, both ways, {} data sets: {} ({:.1} %, 95 % Clopper–Pearson interval [{:.1} %, {:.1} %]).\n", m.replicates, m.baseline, a.screen_gain, m.misfit, m.false_alarms.1, m.false_alarms.0, 100.0 * m.false_alarms.0 as f64 / m.false_alarms.1.max(1) as f64, 100.0 * m.false_alarm_interval.0, 100.0 * m.false_alarm_interval.1);
    if !a.tie_checks.is_empty() {
        let _ = writeln!(md, "Ties: a challenger is in the tie when it beats the cause on 5 % or more of {} data sets simulated from the cause's own independent layouts, read as the data are (the design cannot separate them), or when its held-out difference to the cause is under two standard errors (the data cannot).\n", a.check.as_ref().map_or(0, |c| c.replicates));
        let readings = a.tie_checks.iter().any(|t| t.on_measures.is_some());
        if readings {
            let _ = writeln!(md, "With the mechanism read, the same tests are made on the collapse angles and displacements alone: a challenger they separate is out of the tie unless the readings' own held-out difference favours it by more than two of its standard errors (readings that cannot tell two models apart do not undo the angles' separation).\n");
            let _ = writeln!(
                md,
                "| challenger | beats the cause on its data | held-out difference (sum) | standard error | on the measures: beats the cause | difference | standard error | the readings' difference | standard error | in the tie |"
            );
            let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
        } else {
            let _ = writeln!(
                md,
                "| challenger | beats the cause on its data | held-out difference (sum) | standard error | in the tie |"
            );
            let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
        }
        for t in &a.tie_checks {
            let measures = t.on_measures.as_ref().map_or(String::new(), |m| {
                format!(
                    " {:.1} % | {:.2} | {:.2} | {:.2} | {:.2} |",
                    100.0 * m.reversal_rate,
                    m.difference,
                    m.difference_se,
                    m.readings_difference,
                    m.readings_difference_se
                )
            });
            let _ = writeln!(
                md,
                "| `{}` | {:.1} % | {:.2} | {:.2} |{} {} |",
                t.name,
                100.0 * t.reversal_rate,
                t.difference,
                t.difference_se,
                measures,
                if t.tied { "yes" } else { "no" }
            );
        }
        let _ = writeln!(md);
    }
}
/// The models' weights and what separates the leading ones.
fn weights_section(md: &mut String, run: &Run) {
    let w = &run.analysis.weights;
    if w.models.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "## Weights of the causes
"
    );
    let _ = writeln!(md, "How much the data favour each model among those compared, from the held-out scores per specimen above: pseudo-BMA+ weights (Bayesian bootstrap over specimens, {} draws; Yao et al. 2018) and stacking weights (the mixture of the models that predicts held-out specimens best), each with its 95 % bootstrap interval. The models that share the weight: {} (the fewest, heaviest first, holding {:.0} % of the pseudo-BMA+ weight). The verdict and its tie do not depend on the weights.\n", w.draws, w.shared.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "), 100.0 * w.shared_share);
    let _ = writeln!(md, "| model | pseudo-BMA+ weight | 95 % interval | stacking weight | 95 % interval |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
    for m in &w.models {
        let _ = writeln!(
            md,
            "| `{}` | {:.3} | [{:.3}, {:.3}] | {:.3} | [{:.3}, {:.3}] |",
            m.name,
            m.pseudo_bma,
            m.pseudo_bma_interval.0,
            m.pseudo_bma_interval.1,
            m.stacking,
            m.stacking_interval.0,
            m.stacking_interval.1
        );
    }
    let id = &run.analysis.identifiability;
    if id.pairs.is_empty() {
        let _ = writeln!(md);
        return;
    }
    let _ = writeln!(md, "\nWhat separates the leading models ({}): the expected log predictive difference per observation (nats; the Kullback–Leibler divergence of the two fitted predictives, weighted as in the score) when the first or the second is true, for the three observables that separate them best, and per replicate of the design (one specimen of every group). A pair below {} nats per replicate both ways is indistinguishable under this design.\n", id.leading.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "), id.threshold);
    let _ = writeln!(
        md,
        "| models | best separating observables (first true / second true) | per replicate | indistinguishable |"
    );
    let _ = writeln!(md, "| --- | --- | --- | --- |");
    for p in &id.pairs {
        let keys: Vec<String> = p
            .keys
            .iter()
            .take(3)
            .map(|k| format!("{} ({:.3} / {:.3})", k.observable, k.first_true, k.second_true))
            .collect();
        let _ = writeln!(
            md,
            "| `{}` – `{}` | {} | {:.3} / {:.3} | {} |",
            p.models.0,
            p.models.1,
            keys.join(", "),
            p.per_replicate.0,
            p.per_replicate.1,
            if p.indistinguishable { "yes" } else { "no" }
        );
    }
    let none = id.indistinguishable();
    if !none.is_empty() {
        let _ = writeln!(
            md,
            "\nIndistinguishable under this design: {}.",
            none.iter().map(|(a, b)| format!("`{a}` and `{b}`")).collect::<Vec<_>>().join("; ")
        );
    }
    let _ = writeln!(md);
}

/// The extended model, when one was run: its gain and its values beside the baseline's.
fn extended_section(md: &mut String, run: &Run) {
    let a = &run.analysis;
    if let (Some((effects, _)), Some((g, lo, hi))) = (&run.extended, run.gain) {
        let _ = writeln!(md, "## Extended model\n");
        let labels: Vec<String> = effects.iter().map(|e| e.label()).collect();
        let _ = writeln!(md, "The baseline extended by {} (fitted to all specimens), run as a full ensemble. Held-out error {:.3} → {:.3}: gain {g:.3} per specimen, 95 % bootstrap interval over specimens [{lo:.3}, {hi:.3}].\n", labels.join(", "), a.baseline_heldout_error, a.baseline_heldout_error - g);
        let _ = writeln!(md, "| group | observable | measured | baseline | extended |");
        let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
        let base = run.keys.simulated(&run.baseline);
        let ext = run.keys.simulated(&run.extended.as_ref().map(|e| e.1.clone()).unwrap_or_default());
        for (k, (_, ob)) in run.keys.keys.iter().enumerate() {
            let vals: Vec<f64> =
                (0..run.obs.len()).filter(|&j| run.keys.of[j] == k).map(|j| run.obs[j].value).collect();
            let group = &run.obs[run.keys.of.iter().position(|&x| x == k).unwrap_or(0)].group;
            let sd = if vals.len() > 1 { crate::stats::sd(&vals) } else { 0.0 };
            let _ = writeln!(
                md,
                "| {group} | {} | {:.2} ± {:.2} | {:.2} ± {:.2} | {:.2} ± {:.2} |",
                ob.label(),
                crate::stats::mean(&vals),
                sd,
                base[k].mean,
                base[k].sd,
                ext[k].mean,
                ext[k].sd
            );
        }
        let _ = writeln!(md);
        for g in displacement_groups(run) {
            let _ = writeln!(md, "![displacement against tilt, {g}](displacement_{g}.svg)\n");
        }
    }
}

/// Whether the observations are a force–displacement curve's measures
/// ([`Output::CurveMeasures`]), not collapse angles and displacements.
fn curve_measures(run: &Run) -> bool {
    run.obs.iter().any(|o| o.observable.output() == Output::CurveMeasures)
}

fn displacement_groups(run: &Run) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for o in &run.obs {
        if o.observable.family() == Some(Family::Displacement) && !v.contains(&o.group) {
            v.push(o.group.clone());
        }
    }
    v
}

/// The standardized held-out residuals of every observation, baseline and best candidate
/// (the cause, or the first candidate), as the plot draws them: one label per observation
/// (`SPECIMEN observable`) and one series per model.
fn residual_series(run: &Run) -> (Vec<String>, Vec<ResidualSeries>) {
    let a = &run.analysis;
    let zb: Vec<f64> = run.obs.iter().zip(&a.baseline_predictive).map(|(o, p)| p.z(o.value)).collect();
    let best_pred = a.cause.as_ref().or(a.candidates.first()).map(|c| c.predictive.clone()).unwrap_or_default();
    let ze: Vec<f64> = run.obs.iter().zip(&best_pred).map(|(o, p)| p.z(o.value)).collect();
    let best = a.cause.as_ref().or(a.candidates.first()).map(|c| c.name.clone()).unwrap_or_else(|| "baseline".into());
    let labels: Vec<String> = run.obs.iter().map(|o| format!("{} {}", o.specimen, o.observable.label())).collect();
    let series = vec![ResidualSeries { label: "baseline".into(), z: zb }, ResidualSeries { label: best, z: ze }];
    (labels, series)
}

/// The band of a displacement measure over the tilts of a group's outcomes.
fn band(
    outcomes: &[Outcome],
    measure: super::observations::Measure,
    label: &str,
    measured: Vec<(f64, f64)>,
) -> BandSeries {
    let mut tilts: Vec<f64> = outcomes.iter().flat_map(|o| o.observed.tilt_deg.iter().copied()).collect();
    tilts.sort_by(f64::total_cmp);
    tilts.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let (mut x, mut mid, mut lo, mut hi) = (vec![], vec![], vec![], vec![]);
    for t in tilts {
        let ob = Observable::Displacement { measure, tilt_deg: t };
        let v: Vec<f64> = outcomes
            .iter()
            .filter(|o| o.observed.tilt_deg.iter().any(|u| (u - t).abs() < 1e-9))
            .filter_map(|o| o.value(&ob))
            .collect();
        if v.len() * 2 < outcomes.len().max(1) {
            continue;
        }
        let (m, s) = (crate::stats::mean(&v), if v.len() > 1 { crate::stats::sd(&v) } else { 0.0 });
        x.push(t);
        mid.push(m);
        lo.push(m - s);
        hi.push(m + s);
    }
    BandSeries { label: label.to_string(), x, mid, lo, hi, measured, points_label: None, specimens: vec![] }
}

/// Errors of writing the discrepancy outputs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WriteError {
    /// A file or directory could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The JSON report could not be serialized.
    #[error("discrepancy.json: {0}")]
    Json(#[from] serde_json::Error),
}

/// Writes the report files into `dir`.
///
/// # Errors
/// [`WriteError`]: the file system's or the plot's error, with the file.
pub fn write_report(dir: &Path, run: &Run, study: &str) -> Result<(), WriteError> {
    std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
    let json = serde_json::to_string_pretty(&report_json(run))?;
    for (name, text) in [("discrepancy.json", json), ("discrepancy.md", report_markdown(run, study))] {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(FileError::at(&p))?;
    }
    let (labels, series) = residual_series(run);
    residuals(&dir.join("residuals.svg"), "standardized held-out residuals", &labels, &series)?;
    for g in displacement_groups(run) {
        let Some(group_index) = run.obs.iter().position(|o| o.group == g).map(|j| run.keys.keys[run.keys.of[j]].0)
        else {
            continue;
        };
        let Some(measure) =
            run.obs.iter().filter(|o| o.group == g).find_map(|o| o.observable.displacement().map(|(m, _)| m))
        else {
            continue;
        };
        let measured: Vec<(f64, f64)> = run
            .obs
            .iter()
            .filter(|o| o.group == g)
            .filter_map(|o| o.observable.tilt_deg().map(|t| (t, o.value)))
            .collect();
        let mut series = vec![band(&run.baseline[group_index], measure, "baseline", measured.clone())];
        if let Some((effects, outs)) = &run.extended {
            let label = effects.iter().map(|e| e.label()).collect::<Vec<_>>().join(", ");
            series.push(band(&outs[group_index], measure, &label, vec![]));
        }
        let p = dir.join(format!("displacement_{g}.svg"));
        bands(&p, &format!("{g}: {}", measure.name()), "tilt [deg]", "displacement [cm]", &series)?;
    }
    Ok(())
}
