//! The loops as the analysis's held reading: each model run once, judged against the baseline, reported.

use super::{baseline_candidate, check_models, measured_loops, LoopCandidate, LoopCheck, LoopModel, MeasuredLoops};
use crate::discrepancy::{HeldReading, Run};
use crate::effects::Effect;
use crate::loading::inplane::InPlaneParams;
use crate::study::discrepancy::{Analysis, AnalysisError};
use crate::study::inplane::InPlaneStudyError;
use crate::study::Study;

/// The cyclic loops as the analysis's held reading ([`crate::discrepancy::HeldReading`]):
/// asked of each candidate that may be named before it is confirmed or named (a model whose
/// loops' χ² fails, p < 0.05, and exceeds the baseline's by more than `2 ×`
/// [`crate::discrepancy::REFUTE_NATS`] is refuted by them), and reported after the analysis
/// for the baseline, every model it judged and the models of the tie (module
/// documentation). Each model's loops are run once (by its name and parameters).
pub struct LoopsReading {
    /// The analysis's groups, solver and seed.
    setup: crate::discrepancy::Setup,
    /// The measured groups.
    groups: Vec<MeasuredLoops>,
    /// The study's test (its history, shear span, solver settings), at each group's σ0.
    test: InPlaneParams,
    /// The walls' mean course height, m.
    course_m: f64,
    /// The models checked, in the order first asked: name, parameters' bits and the check of
    /// that model alone.
    checked: std::sync::Mutex<Vec<(String, Vec<u64>, LoopCheck)>>,
}

impl LoopsReading {
    /// The loops of the in-plane study `study` analysed as `input` (its groups, solver, seed
    /// and run store); `None` when the study has no cyclic specimen with a measured curve
    /// (`[measured] curves`).
    ///
    /// # Errors
    /// [`InPlaneStudyError::Invalid`] at `protocol` for a study of another protocol.
    pub fn of(study: &Study, input: &Analysis) -> Result<Option<LoopsReading>, InPlaneStudyError> {
        let Some((groups, test)) = measured_loops(study, input)? else {
            return Ok(None);
        };
        Ok(Some(LoopsReading {
            course_m: crate::discrepancy::course_height(&input.setup),
            setup: input.setup.clone(),
            groups,
            test,
            checked: std::sync::Mutex::new(vec![]),
        }))
    }

    /// The check of one model, run once.
    fn model(
        &self,
        m: &LoopCandidate,
        progress: crate::discrepancy::Progress<'_>,
    ) -> Result<LoopCheck, InPlaneStudyError> {
        let bits: Vec<u64> = m.1.iter().map(|(_, v)| v.to_bits()).collect();
        let lock = || self.checked.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((_, _, c)) = lock().iter().find(|(n, b, _)| *n == m.0 && *b == bits) {
            return Ok(c.clone());
        }
        let params = |sigma0_mpa: f64| InPlaneParams { sigma0_mpa, ..self.test.clone() };
        let c = check_models(&self.setup, &params, &self.groups, std::slice::from_ref(m), progress)?;
        lock().push((m.0.clone(), bits, c.clone()));
        Ok(c)
    }

    /// The loops of the in-plane study `study` analysed as `input` as the analysis's held
    /// reading ([`LoopsReading::of`]): the in-plane test's
    /// [`crate::study::discrepancy::AnalysisWay::held`].
    ///
    /// # Errors
    /// As [`LoopsReading::of`].
    pub fn held(study: &Study, input: &Analysis) -> Result<Option<Box<dyn HeldReading>>, AnalysisError> {
        Ok(LoopsReading::of(study, input)?.map(|r| Box::new(r) as Box<dyn HeldReading>))
    }

    fn held_error(e: InPlaneStudyError) -> crate::discrepancy::DiscrepancyError {
        crate::discrepancy::DiscrepancyError::Held { reading: "cyclic loops".into(), message: e.to_string() }
    }

    /// The check of the baseline, every model judged (at its latest parameters) and the
    /// models of `run`'s tie, with the peaks refit at the friction each model's loops read
    /// ([`refit_peaks`]).
    ///
    /// # Errors
    /// A fitted parameter refused, a run's layout not made.
    pub fn check(&self, run: &Run, progress: crate::discrepancy::Progress<'_>) -> Result<LoopCheck, InPlaneStudyError> {
        let mut models: Vec<(LoopCandidate, bool)> = vec![(baseline_candidate(), false)];
        let judged: Vec<String> = {
            let all = self.checked.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            let mut names: Vec<String> = vec![];
            for (n, _, _) in all.iter() {
                if n != "baseline" && !names.contains(n) {
                    names.push(n.clone());
                }
            }
            names
        };
        // In the order checked; a model whose wall is the baseline's takes the baseline's
        // loops (`true`), not run again.
        for name in judged.iter().chain(run.analysis.tie.iter().filter(|t| !judged.contains(t))) {
            let parameters = run
                .analysis
                .candidates
                .iter()
                .find(|r| &r.name == name)
                .map(|r| r.parameters.clone())
                .unwrap_or_default();
            if run.is_baseline_model(name) {
                models.push(((name.clone(), parameters, vec![]), true));
                continue;
            }
            let effects = run
                .fitted_effects(name, self.course_m)
                .map_err(|e| InPlaneStudyError::Write(format!("the loops of {name}: {e}")))?;
            let Some(effects) = effects else { continue };
            models.push(((name.clone(), parameters, effects), false));
        }
        let checks: Vec<Option<LoopCheck>> = models
            .iter()
            .map(|(m, as_baseline)| if *as_baseline { Ok(None) } else { self.model(m, progress).map(Some) })
            .collect::<Result<_, _>>()?;
        let runs =
            self.checked.lock().unwrap_or_else(std::sync::PoisonError::into_inner).iter().map(|c| c.2.runs).sum();
        let Some(first) = checks.first().and_then(Option::as_ref) else {
            return Err(InPlaneStudyError::Write("the loops: the baseline was not run".into()));
        };
        let base = first.models.first();
        let mut check = LoopCheck {
            min_drift_pct: first.min_drift_pct,
            measured_sigma: first.measured_sigma,
            models: models
                .iter()
                .zip(&checks)
                .filter_map(|(((name, parameters, _), _), c)| match c {
                    Some(c) => c.models.first().cloned(),
                    None => base.map(|b| LoopModel {
                        name: name.clone(),
                        parameters: parameters.clone(),
                        baseline_wall: true,
                        ..b.clone()
                    }),
                })
                .collect(),
            runs,
            own_histories: first.own_histories,
            baseline_heldout_error: f64::NAN,
            cause: None,
        };
        // Each model was checked alone: judged against the baseline once assembled, as the
        // analysis's verdict judges it.
        super::judge_against_baseline(&mut check.models);
        refit_peaks(&mut check, run);
        Ok(check)
    }

    /// The lines the command prints of `check`.
    pub fn summary(check: &LoopCheck) -> Vec<String> {
        let mut summary =
            vec!["the cyclic loops (a reading the fit does not hold): the loops' damping ratio, χ² over the stresses"
                .to_string()];
        for m in &check.models {
            let read = m
                .friction_read
                .map(|f| format!("  μ_r read {:.4} [{:.4}, {:.4}], χ² {:.1}", f.friction, f.low, f.high, f.chi2))
                .unwrap_or_default();
            let peaks = m
                .peaks
                .as_ref()
                .map(|p| format!("; held-out error with it {:.2}", p.heldout_error))
                .unwrap_or_default();
            summary.push(format!(
                "  {:<36} χ² {:>8.1}  p {:.2e}  {}{read}{peaks}",
                m.name,
                m.chi2,
                m.p_value,
                m.verdict.words()
            ));
        }
        if let Some((m, p)) = check.standing().first().and_then(|m| m.peaks.as_ref().map(|p| (m, p))) {
            summary.push(format!(
                "  both readings leave standing: {} with μ_r {:.4} held, held-out error {:.2} (baseline {:.2})",
                m.name,
                m.friction_read.map_or(f64::NAN, |f| f.friction),
                p.heldout_error,
                check.baseline_heldout_error
            ));
        }
        summary
    }
}

impl crate::discrepancy::HeldReading for LoopsReading {
    fn name(&self) -> &str {
        "loops"
    }

    fn judge(
        &self,
        name: &str,
        parameters: &[(String, f64)],
        effects: &[Effect],
        progress: crate::discrepancy::Progress<'_>,
    ) -> Result<Option<crate::discrepancy::Refutation>, crate::discrepancy::DiscrepancyError> {
        progress(&format!("the cyclic loops of {name}, before it may be named"));
        let base = self.model(&baseline_candidate(), progress).map_err(Self::held_error)?;
        let m = self
            .model(&(name.to_string(), parameters.to_vec(), effects.to_vec()), progress)
            .map_err(Self::held_error)?;
        let (Some(b), Some(m)) = (base.models.first(), m.models.first()) else { return Ok(None) };
        // A baseline with nothing read is no yardstick: its χ² counts as 0.
        let base_chi2 = if b.chi2.is_finite() { b.chi2 } else { 0.0 };
        let excess = m.chi2 - base_chi2;
        let read = m.groups.iter().filter(|g| g.z.is_finite()).count();
        Ok(super::refutes_beyond_baseline(m.chi2, m.p_value, b.chi2).then(|| {
            crate::discrepancy::Refutation {
                candidate: name.to_string(),
                reading: "loops".into(),
                nats: excess / 2.0,
                words: format!(
                    "the cyclic loops' damping ratio: χ² {:.1} (p {:.1e}) over {read} stresses against the baseline's {:.1}",
                    m.chi2, m.p_value, base_chi2
                ),
            }
        }))
    }

    fn report(
        &self,
        run: &Run,
        progress: crate::discrepancy::Progress<'_>,
    ) -> Result<Option<crate::discrepancy::HeldReport>, crate::discrepancy::DiscrepancyError> {
        let check = self.check(run, progress).map_err(Self::held_error)?;
        let json =
            serde_json::to_value(&check).map_err(|e| Self::held_error(InPlaneStudyError::Write(e.to_string())))?;
        Ok(Some(crate::discrepancy::HeldReport {
            key: "loops",
            markdown: check.markdown(),
            summary: Self::summary(&check),
            json,
        }))
    }
}

/// Refits each model of `check` with a friction read to `run`'s observations with the
/// bearing friction held at that read ([`LoopModel::peaks`]), and records the baseline's
/// and the cause's held-out errors beside them.
pub fn refit_peaks(check: &mut LoopCheck, run: &Run) {
    for m in &mut check.models {
        let Some(f) = m.friction_read else { continue };
        let effects: Vec<&str> = if m.name == "baseline" { vec![] } else { m.name.split('+').collect() };
        m.peaks = run.refit_held(&effects, "rig_friction", f.friction);
    }
    check.baseline_heldout_error = run.analysis.baseline_heldout_error;
    check.cause = run.analysis.cause.as_ref().map(|c| (c.name.clone(), c.heldout_error));
}
