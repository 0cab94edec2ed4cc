//! The in-plane study's statistics (`summary.csv`: per group and observable the ensemble's
//! mean, σ, COV and 95 % band), its comparison with the measured specimens
//! (`comparison.csv`), its figures (`curves_<group>.svg`, `mechanism_<group>.svg`) and its
//! report (`report.md`): the in-plane protocol's report of the study core's rows
//! ([`super::StudyProtocol::write_report`]).

use super::inplane::{drawing, readings};
use super::inplane_measured::{file_stem, Specimen};
use super::inplane_spec::InPlaneStudy;
use super::protocol_table::ProtocolTable;
use super::report_error::ReportError;
use super::spec::StudySpec;
use super::summary::{CellSummary, Comparison};
use super::sweep::{SweepKey, SweepValue};
use super::Study;
use crate::dem::SolverParams;
use crate::ensemble::row::{InPlaneColumns, RealizationRow};
use crate::io::inplane::{crack_map_svg, force_drift, ForceDriftCurve};
use crate::io::series::SeriesError;
use crate::layout::Layout;
use crate::loading::inplane::{mechanism_joints, Rig};
use crate::protocol::{InPlane, Protocol};
use crate::stats::{mean, quantile, sd};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The observables compared, with their row accessors.
const OBSERVABLES: [(&str, &str, fn(&InPlaneColumns) -> f64, fn(&Specimen) -> f64); 19] = [
    ("peak_pos_kn", "peak force + (kN)", |r| r.peak_pos_kn, |s| s.vmax_pos_kn),
    ("peak_neg_kn", "peak force − (kN)", |r| r.peak_neg_kn, |s| s.vmax_neg_kn),
    ("drift_at_peak_pos_pct", "drift at peak + (%)", |r| r.drift_at_peak_pos_pct, |s| s.dmax_pos_pct),
    ("drift_at_peak_neg_pct", "drift at peak − (%)", |r| r.drift_at_peak_neg_pct, |s| s.dmax_neg_pct),
    ("ultimate_drift_pos_pct", "ultimate drift + (%)", |r| r.ultimate_drift_pos_pct, |s| s.du_pos_pct),
    ("stiffness_pos_kn_per_mm", "initial stiffness + (kN/mm)", |r| r.stiffness_pos_kn_per_mm, |s| s.kel_pos),
    ("failure_type", "failure type (1 rocking, 0.5 mixed, 0 shear)", |r| r.failure_type, |s| s.failure_type),
    ("damping_ratio", "loops' equivalent damping ratio, cycles ≥ 1 % drift", |r| r.damping_ratio, |s| s.damping_ratio),
    (
        "force_at_0_25_pos_kn",
        "envelope's force at 0.25 % drift + (kN)",
        |r| r.force_at_0_25_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[0],
    ),
    (
        "force_at_0_5_pos_kn",
        "envelope's force at 0.5 % drift + (kN)",
        |r| r.force_at_0_5_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[1],
    ),
    (
        "force_at_1_pos_kn",
        "envelope's force at 1 % drift + (kN)",
        |r| r.force_at_1_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[2],
    ),
    (
        "force_at_2_pos_kn",
        "envelope's force at 2 % drift + (kN)",
        |r| r.force_at_2_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[3],
    ),
    (
        "force_at_1_neg_kn",
        "envelope's force at 1 % drift − (kN)",
        |r| r.force_at_1_neg_kn,
        |s| s.readings_neg.force_at_drift_kn[2],
    ),
    (
        "drift_at_80_pos_pct",
        "drift at 80 % of the peak + (%)",
        |r| r.drift_at_80_pos_pct,
        |s| s.readings_pos.drift_at_80_pct,
    ),
    (
        "drift_at_95_pos_pct",
        "drift at 95 % of the peak + (%)",
        |r| r.drift_at_95_pos_pct,
        |s| s.readings_pos.drift_at_95_pct,
    ),
    (
        "plateau_slope_pos_kn_per_pct",
        "plateau slope past 95 % of the peak + (kN per % drift)",
        |r| r.plateau_slope_pos_kn_per_pct,
        |s| s.readings_pos.plateau_slope_kn_per_pct,
    ),
    ("vertical_modulus_mpa", "wall's vertical modulus, loading phase (MPa)", |r| r.vertical_modulus_mpa, |s| s.epc_mpa),
    (
        "largest_block_excursion_mm",
        "largest excursion of a block from its course (mm), simulated only",
        |r| r.largest_block_excursion_mm,
        |_| f64::NAN,
    ),
    (
        "course_widening_mm",
        "widening of the most widened course at the history's end (mm), simulated only",
        |r| r.course_widening_mm,
        |_| f64::NAN,
    ),
];

/// Mean, σ, COV and the 95 % band (2.5 % and 97.5 % quantiles) of the finite values.
fn stats(x: &[f64]) -> (usize, f64, f64, f64, f64, f64) {
    let v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    let (m, s) = (mean(&v), sd(&v));
    (v.len(), m, s, s / m, quantile(&v, 0.025), quantile(&v, 0.975))
}

fn f(v: f64, d: usize) -> String {
    if v.is_finite() {
        format!("{v:.d$}")
    } else {
        "–".into()
    }
}

/// The method of the study's runs in the report's words: the penalty DEM with its
/// tolerance, another method with what it gives (its cell of the protocol's `WAYS`).
fn method_words(solver: SolverParams) -> String {
    let method = solver.kind.method();
    if solver.kind.is_penalty() {
        let cascade = solver.kind.cascade(crate::loading::inplane::CASCADE).unwrap_or(crate::loading::inplane::CASCADE);
        let stages = super::report::cascade_words(cascade);
        format!(
            "the penalty DEM (`{}`: {stages}, to the unbalanced-force ratio {:e} and every block's local ratio {} \
             per increment of the imposed displacement)",
            solver.kind.name(),
            solver.penalty.tolerance,
            crate::loading::inplane::LOCAL_TOLERANCE
        )
    } else {
        let what = crate::protocol::methods(crate::protocol::Loading::InPlane, method).unwrap_or_default();
        format!("{} ({what})", method.describe())
    }
}

/// Writes the in-plane study's `summary.csv`, `comparison.csv`, figures and `report.md`
/// into `out` from its rows `rows` (every realization of the study, in item order); returns
/// the text `drystone run` prints of it (none: the report is the file).
///
/// # Errors
/// [`ReportError`] naming the file that could not be written.
pub(super) fn report(
    study: &Study,
    test: &InPlaneStudy,
    out: &Path,
    rows: &[RealizationRow],
) -> Result<String, ReportError> {
    let (path, solver, specimens) = (&study.path, study.solver, &test.specimens);
    let mut md = String::new();
    let mut summary = String::from("group,observable,n,mean,sd,cov,band_lo,band_hi\n");
    let mut comparison = String::from(
        "group,specimen,observable,measured,sim_mean,sim_sd,band_lo,band_hi,inside_band,ratio_measured_to_mean\n",
    );
    let _ = writeln!(md, "# {}\n", study.name);
    let _ = writeln!(md, "{}\n", study.description.trim());
    let ok = rows.iter().filter(|r| r.status.is_ok()).count();
    let _ = writeln!(
        md,
        "Study file `{}`; seed {}; {} realizations ({} failed); {:.1} s of run time summed over the realizations. \
         Method: {}, and limit analysis beside it. {}, largest drift {} %.\n",
        path.display(),
        study.seed,
        rows.len(),
        rows.len() - ok,
        rows.iter().map(|r| r.wall_time_s).sum::<f64>(),
        method_words(solver),
        match (test.params.beam_rotation, test.params.shear_span_m) {
            (crate::loading::inplane::BeamRotation::Fixed, _) => "Beam held level: no shear span".to_string(),
            (_, Some(h)) => format!("Shear span {h} m"),
            (_, None) => "Shear span –".to_string(),
        },
        test.params.drift_pct
    );
    let _ = writeln!(
        md,
        "Readings as the measured files define them: the displacement is read on the loading beam at the measuring \
         point ({}), the drift is that displacement over the point's height (`drift_% = displacement_mm / {} × 100`), \
         and the stiffness (kN/mm) is read on the same displacement. The wall's vertical modulus is the secant of the \
         vertical loading phase (the stress the actuator adds over the wall's shortening, the beam's settlement \
         over the wall's height), as the database's `Epc` is read from the compression cycles at the start of each \
         test. Measured columns are data drystone did not make; the simulated columns are its own.\n",
        test.params.measuring_height_m.map_or_else(
            || "the actuator's height, the shear span, where a test reports none".to_string(),
            |h| format!("{h} m")
        ),
        test.params.measuring_height_m.or(test.params.shear_span_m).map_or("H".to_string(), |h| format!("{}", h * 1e3))
    );
    for (g, (core, group)) in study.groups.iter().zip(&test.groups).enumerate() {
        let ran: Vec<&RealizationRow> = rows.iter().filter(|r| r.group == core.name && r.status.is_ok()).collect();
        let rs: Vec<&InPlaneColumns> = ran.iter().map(|r| readings(r)).collect();
        let ms: Vec<&Specimen> =
            group.specimens.iter().filter_map(|u| specimens.iter().find(|s| &s.unit == u)).collect();
        let _ = writeln!(md, "## {}\n", core.name);
        if !core.effects.is_empty() {
            let stated: Vec<String> = group
                .stated
                .iter()
                .map(|(_, name, values)| {
                    let v: Vec<String> = values.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                    format!("`{name}` ({})", v.join(", "))
                })
                .collect();
            let _ = writeln!(md, "The model extended by {}.\n", stated.join(", "));
        }
        let _ = writeln!(
            md,
            "σ0 = {} MPa, {} history, wall `{}`; {} realizations; measured: {}.\n",
            group.sigma0_mpa,
            group.history.name(),
            group.source.display(),
            rs.len(),
            if ms.is_empty() {
                "none".to_string()
            } else {
                ms.iter().map(|m| m.unit.clone()).collect::<Vec<_>>().join(", ")
            }
        );
        observables_table(&core.name, &rs, &ms, &mut summary, &mut comparison, &mut md);
        let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
        for r in &rs {
            *kinds.entry(r.in_plane_mechanism.as_str()).or_default() += 1;
        }
        let la: Vec<f64> = rs.iter().map(|r| r.limit_peak_kn).collect();
        let (_, la_m, _, _, _, _) = stats(&la);
        let mut la_kinds: BTreeMap<&str, usize> = BTreeMap::new();
        for r in &rs {
            *la_kinds.entry(r.limit_mechanism.as_str()).or_default() += 1;
        }
        let rock = rs.first().map_or(f64::NAN, |r| r.rocking_kn);
        let _ = writeln!(
            md,
            "\nMechanism ({}): {}; measured: {}. Limit analysis: peak {} kN (mean), mechanism {}. The \
             monolith's rigid rocking capacity N_total L / (2 H0) is {} kN.\n",
            solver.kind.method().describe().trim_start_matches("the "),
            kinds.iter().map(|(k, n)| format!("{k} {n}")).collect::<Vec<_>>().join(", "),
            if ms.is_empty() {
                "–".into()
            } else {
                ms.iter().map(|m| format!("{} ({})", m.modes, m.unit)).collect::<Vec<_>>().join(", ")
            },
            f(la_m, 2),
            la_kinds.iter().map(|(k, n)| format!("{k} {n}")).collect::<Vec<_>>().join(", "),
            f(rock, 2)
        );
        figures(study, test, g, (ran.first().copied(), &rs), &ms, out, &mut md)?;
    }
    for (name, text) in [("summary.csv", &summary), ("comparison.csv", &comparison), ("report.md", &md)] {
        crate::io::replace_file(&out.join(name), text.as_bytes())?;
    }
    Ok(String::new())
}

/// The observables of the group `name` (`rs` its rows that ran, `ms` its measured
/// specimens): its statistics' lines of `summary.csv`, its comparison's lines of
/// `comparison.csv` and its table in the report `md`.
fn observables_table(
    name: &str,
    rs: &[&InPlaneColumns],
    ms: &[&Specimen],
    summary: &mut String,
    comparison: &mut String,
    md: &mut String,
) {
    let _ = writeln!(md, "| observable | measured | simulated mean | σ | COV | 95 % band | measured inside |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- |");
    for (key, label, get, meas) in OBSERVABLES {
        let d = if key == "damping_ratio" { 3 } else { 2 };
        let x: Vec<f64> = rs.iter().map(|r| get(r)).collect();
        let (n, m, s, cov, lo, hi) = stats(&x);
        if n == 0 {
            continue;
        }
        let _ = writeln!(summary, "\"{}\",{key},{n},{m},{s},{cov},{lo},{hi}", name);
        let measured: Vec<f64> = ms.iter().map(|s| meas(s)).filter(|v| v.is_finite()).collect();
        let inside = measured.iter().filter(|v| **v >= lo && **v <= hi).count();
        for (sp, v) in ms.iter().map(|s| (s, meas(s))).filter(|(_, v)| v.is_finite()) {
            let _ = writeln!(
                comparison,
                "\"{}\",{},{key},{v},{m},{s},{lo},{hi},{},{}",
                name,
                sp.unit,
                v >= lo && v <= hi,
                v / m
            );
        }
        let _ = writeln!(
            md,
            "| {label} | {} | {} | {} | {} | [{}, {}] | {} |",
            if measured.is_empty() {
                "–".into()
            } else {
                measured.iter().map(|v| f(*v, d)).collect::<Vec<_>>().join(", ")
            },
            f(m, d),
            f(s, d),
            f(cov, 3),
            f(lo, d),
            f(hi, d),
            if measured.is_empty() { "–".into() } else { format!("{inside} of {}", measured.len()) }
        );
    }
}

/// The figures of group `g` (`first` its first row that ran and `rs` the readings of those
/// that ran, `ms` its measured specimens): the curves over the measured envelopes
/// (`curves_<slug>.svg`) and the mechanism of the first realization that ran beside the
/// measured crack maps (`mechanism_<slug>.svg`), written into `out` and linked in `md`.
///
/// # Errors
/// A figure that cannot be written.
fn figures(
    study: &Study,
    test: &InPlaneStudy,
    g: usize,
    (first, rs): (Option<&RealizationRow>, &[&InPlaneColumns]),
    ms: &[&Specimen],
    out: &Path,
    md: &mut String,
) -> Result<(), ReportError> {
    let (core, path, solver) = (&study.groups[g], &study.path, study.solver);
    let slug: String =
        core.name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect();
    // The curves over the measured envelopes.
    let mut curves: Vec<ForceDriftCurve> = rs
        .iter()
        .enumerate()
        .map(|(k, r)| ForceDriftCurve {
            label: (k == 0).then(|| "simulated (each realization)".to_string()),
            colour: 0,
            measured: false,
            points: r.curve(),
        })
        .collect();
    for (k, m) in ms.iter().enumerate() {
        if !m.envelope.is_empty() {
            curves.push(ForceDriftCurve {
                label: Some(format!("{} envelope (measured)", m.unit)),
                colour: k + 1,
                measured: true,
                points: m.envelope.clone(),
            });
        }
    }
    let svg = out.join(format!("curves_{slug}.svg"));
    force_drift(&svg, &core.name, &curves)?;
    let _ = writeln!(md, "![force-drift curves](curves_{slug}.svg)\n");
    // The mechanism of realization 0 beside the measured crack map.
    if let Some((r0, (poses, mechanism))) = first.and_then(|r| drawing(study, r).map(|d| (r, d))) {
        let params = test.params_of(g);
        let item = study.items().into_iter().nth(r0.index as usize);
        let layout = item.map(|it| super::run::realize_item(study, &it));
        if let Some(Ok(rig)) = layout
            .map(|l| l.map_err(|e| e.to_string()).and_then(|l| Rig::build(&l, &params).map_err(|e| e.to_string())))
        {
            {
                let sim = crate::dem::Simulation::new(&rig.layout, solver);
                let svg = crack_map_svg(
                    &rig.layout,
                    &poses,
                    &mechanism_joints(&sim),
                    &mechanism,
                    &format!("{}: realization 0, {}", core.name, mechanism.kind.name()),
                );
                let p = out.join(format!("mechanism_{slug}.svg"));
                crate::io::replace_file(&p, svg.as_bytes())?;
                let _ = write!(md, "![mechanism, realization 0](mechanism_{slug}.svg)");
                if let Some(dir) = &test.crackmaps {
                    for m in ms {
                        let name = format!("crackmap_{}.png", file_stem(m));
                        let from = path.parent().unwrap_or(Path::new(".")).join(dir).join(&name);
                        if from.exists() && std::fs::copy(&from, out.join(&name)).is_ok() {
                            let _ = write!(md, " ![measured crack map {}]({name})", m.unit);
                        }
                    }
                }
                md.push_str("\n\n");
            }
        }
    }
    Ok(())
}

/// The in-plane test's study: each group's vertical stress and history its own protocol,
/// its own report (`report`: statistics per observable, the comparison
/// with the measured specimens, its figures), no ensemble sections and no time series.
impl ProtocolTable for InPlaneStudy {
    fn write_into(&self, spec: &mut StudySpec) {
        spec.in_plane = Some(self.params.clone());
        for (g, own) in spec.groups.iter_mut().zip(&self.groups) {
            g.sigma0_mpa = Some(own.sigma0_mpa);
            g.history = Some(own.history);
            g.specimens.clone_from(&own.specimens);
        }
    }

    /// The first group's protocol (its vertical stress and history; the table's without
    /// groups); the point's values are not the test's.
    fn at(&self, _point: &[(SweepKey, SweepValue)]) -> Protocol {
        Protocol::InPlane(InPlane(self.groups.first().map_or_else(|| self.params.clone(), |_| self.params_of(0))))
    }

    /// Group `group`'s protocol; [`ProtocolTable::at`] for an index past the groups.
    fn of_group(&self, group: usize, point: &[(SweepKey, SweepValue)]) -> Protocol {
        if group < self.groups.len() {
            Protocol::InPlane(InPlane(self.params_of(group)))
        } else {
            self.at(point)
        }
    }

    fn write_report(&self, study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<String, ReportError> {
        report(study, self, dir, rows)
    }

    /// None: its report is its own, whole ([`ProtocolTable::write_report`]), which does not
    /// ask for these.
    fn report_sections(
        &self,
        _study: &Study,
        _rows: &[RealizationRow],
        _dir: &Path,
        _cells: &[CellSummary],
        _cmp: &[Comparison],
        _md: &mut String,
    ) -> Result<String, ReportError> {
        Ok(String::new())
    }

    /// None: the in-plane test records no time series.
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

    fn in_plane(&self) -> Option<&InPlaneStudy> {
        Some(self)
    }
}
