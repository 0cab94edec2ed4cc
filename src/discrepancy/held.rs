//! A reading the fit does not hold ([`HeldReading`]), which a protocol asks of a candidate
//! at its fitted parameters before it is named (the rule: [`super::refute`]), and its
//! report after the analysis ([`HeldReport`]).

use super::progress::Progress;
use super::refute::Refutation;
use super::DiscrepancyError;
use crate::effects::Effect;

/// A reading the fit does not hold, which a protocol asks of a candidate at its fitted
/// parameters (the in-plane test's cyclic loops, `study::inplane_loops`), and its report
/// after the analysis.
pub trait HeldReading: Sync {
    /// Its name in the report and the refutations (`loops`).
    fn name(&self) -> &str;

    /// Whether the reading refutes the model `name` (`baseline` never asked) of the effects
    /// `effects` at the parameters `parameters` (`effect.param`, value): `Some` with the
    /// reading's words when it does, by the module's rule (its statistic worse than the
    /// baseline's by [`super::REFUTE_NATS`] nats).
    ///
    /// # Errors
    /// [`DiscrepancyError::Held`] when the reading cannot be made (its measured files, its
    /// runs).
    fn judge(
        &self,
        name: &str,
        parameters: &[(String, f64)],
        effects: &[Effect],
        progress: Progress<'_>,
    ) -> Result<Option<Refutation>, DiscrepancyError>;

    /// Its report after the analysis `run` (the baseline and the models of the tie),
    /// `None` when it has nothing to report.
    ///
    /// # Errors
    /// As [`HeldReading::judge`].
    fn report(&self, run: &super::Run, progress: Progress<'_>) -> Result<Option<HeldReport>, DiscrepancyError>;
}

/// A held reading's report after the analysis: its section of the report, its JSON and the
/// lines the command prints.
#[derive(Debug, Clone)]
pub struct HeldReport {
    /// Its output file's name (`loops.json`) and its key in the command's JSON (`loops`).
    pub key: &'static str,
    /// Its section of the report (Markdown, appended to `discrepancy.md`).
    pub markdown: String,
    /// What it found, as JSON (the file `<key>.json` and the key of `--json`'s object).
    pub json: serde_json::Value,
    /// The lines the command prints after its summary.
    pub summary: Vec<String>,
}
