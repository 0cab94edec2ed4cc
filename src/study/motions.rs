//! The motions and levels of a shaking study (protocol `shake`): the `[shake]` table
//! checked, its records read, its stochastic motions generated and its pulses sampled
//! ([`ShakeStudy`]), and the sweep keys `motion` and `pga_g` they add to the study's
//! points.

use super::error::Invalid;
use super::provenance::InputRole;
use super::size;
use super::spec::StudySpec;
use super::sweep::SweepKey;
use super::StudyError;
use crate::ground::Motion;
use crate::loading::shake::ShakeParams;
use crate::protocol::Unsupported;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The shaking-table part of a checked study (protocol `shake`): its parameters, its
/// motions as read or generated (unscaled) and its PGA levels. The study's points carry
/// the sweep keys `motion` (a motion's name) and `pga_g` (a level): see
/// [`Study::protocol_at`](super::Study::protocol_at).
#[derive(Debug, Clone, PartialEq)]
pub struct ShakeStudy {
    /// Shaking-table parameters.
    pub params: ShakeParams,
    /// The motions, in the order records, stochastic, pulses; names unique.
    pub motions: Vec<Motion>,
    /// PGA levels, g, increasing.
    pub levels: Vec<f64>,
}

impl ShakeStudy {
    /// The warnings of the study's motions, one line per motion and cause (without the
    /// `warning: ` prefix), in motion order: a motion sampled coarser than
    /// [`crate::ground::COARSE_RECORD_DT_S`] (content above its Nyquist frequency is lost),
    /// and a motion whose highest level exceeds [`crate::ground::PLAUSIBLE_PGA_G`] (each
    /// motion is scaled to every level, so its PGA is the level). Empty when none applies.
    pub fn warnings(&self) -> Vec<String> {
        let top = self.levels.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut out = Vec::new();
        for m in &self.motions {
            if m.dt_s > crate::ground::COARSE_RECORD_DT_S {
                out.push(format!(
                    "motion {} is sampled every {} s ({:.1} samples per second): content above {:.1} Hz is lost",
                    m.name,
                    m.dt_s,
                    1.0 / m.dt_s,
                    0.5 / m.dt_s
                ));
            }
            if top > crate::ground::PLAUSIBLE_PGA_G {
                out.push(format!(
                    "motion {} is scaled to PGA {top:.3e} g, implausible for a ground motion (above {} g): check \
                     shake.pga_g",
                    m.name,
                    crate::ground::PLAUSIBLE_PGA_G
                ));
            }
        }
        out
    }

    /// The motion named `name` scaled to `pga_g`; `None` for an unknown name.
    pub fn motion(&self, name: &str, pga_g: f64) -> Option<Motion> {
        self.motions.iter().find(|m| m.name == name).map(|m| m.scaled_to_pga(pga_g))
    }
}

impl StudySpec {
    /// The `[shake]` table of a shaking study checked, its records read (each one an
    /// input file of the study), its stochastic motions generated from the study's seed and
    /// its pulses sampled at the solver's step; `None` for another protocol, which must not
    /// have the table.
    pub(super) fn resolve_shake(
        &self,
        dir: &Path,
        invalid: &Invalid,
        files: &mut Vec<(InputRole, PathBuf)>,
    ) -> Result<Option<ShakeStudy>, StudyError> {
        // The `[shake]` table is read by the shaking table alone.
        let spec = match (&self.shake, self.reads_table("shake")) {
            (None, true) => {
                return Err(invalid.at(
                    "shake",
                    "protocol = \"shake\" needs a [shake] table with pga_g levels and motions (records, stochastic or pulses)"
                        .into(),
                ))
            }
            (Some(_), false) => {
                return Err(invalid.at("shake", "the [shake] table is read only with protocol = \"shake\"".into()))
            }
            (None, false) => return Ok(None),
            (Some(s), true) => s,
        };
        // The step pulses are sampled at (nscd's own; the penalty solver's is far smaller and
        // reads the motion by linear interpolation: 1 ms at most) and the step each motion is
        // checked against here (nscd's; the penalty solver's, from the realizations' masses
        // and stiffnesses, by `check_penalty_steps` once the groups are resolved).
        let Some(rule) = crate::protocol::shake::step_rule(&self.solver) else {
            // Refused by `check_scalars` before this (`protocol::check`: a cascade of static
            // solves on a motion; limit analysis has no motion).
            return Err(super::error::unsupported(
                invalid,
                Unsupported { protocol: self.loading(), kind: self.solver.kind },
            ));
        };
        let (pulse_dt, nscd_dt) = (rule.pulse_dt_s, rule.fixed_dt_s);
        let params = spec.params();
        params.validate().map_err(|e| invalid.at(&format!("shake.{}", e.key), e.reason()))?;
        check_levels(&spec.pga_g).map_err(|r| invalid.at("shake.pga_g", r.to_string()))?;
        let mut motions = Vec::new();
        for (i, r) in spec.records.iter().enumerate() {
            let p = dir.join(r);
            let m = crate::ground::read_record_with(&p, spec.columns.as_ref()).map_err(|source| {
                StudyError::Record { path: invalid.0.to_owned(), key: format!("shake.records[{i}]"), source }
            })?;
            files.push((InputRole::Record, p));
            motions.push((
                format!("shake.records[{i}]"),
                if spec.baseline_correction { m.baseline_corrected() } else { m },
            ));
        }
        if let Some(table) = &spec.stochastic {
            motions.extend(stochastic_motions(table, self.seed, invalid)?);
        }
        for (i, p) in spec.pulses.iter().enumerate() {
            let key = format!("shake.pulses[{i}]");
            if !(p.amplitude_g().is_finite() && p.amplitude_g() != 0.0) {
                return Err(invalid.at(&key, format!("amplitude_g must be finite and not 0, got {}", p.amplitude_g())));
            }
            if !(p.period_s().is_finite() && p.period_s() > 0.0) {
                return Err(invalid.at(&key, format!("period_s must be > 0, got {}", p.period_s())));
            }
            check_pulse(p, pulse_dt).map_err(|m| invalid.at(&key, m))?;
            motions.push((key, p.sampled(pulse_dt, 0.0)));
        }
        if motions.is_empty() {
            return Err(invalid.at("shake", "no motions: give records, stochastic = { count = N } or pulses".into()));
        }
        for (i, (key, m)) in motions.iter().enumerate() {
            if let Some(c) = m.name.chars().find(|c| matches!(c, ';' | '=') || c.is_control()) {
                return Err(invalid.at(
                    key,
                    format!(
                        "the motion's name {:?} contains {c:?}, which a sweep label cannot hold; rename the file",
                        m.name
                    ),
                ));
            }
            if let Some((other, _)) = motions[..i].iter().find(|(_, n)| n.name == m.name) {
                return Err(invalid.at(
                    key,
                    format!("two motions are named {:?} (also {other}); motions are told apart by name", m.name),
                ));
            }
            if let Some(dt) = nscd_dt {
                crate::loading::shake::check_steps(m, &params, dt).map_err(|e| invalid.at(key, e.to_string()))?;
            }
            if m.pga_g() == 0.0 {
                return Err(invalid.at(
                    key,
                    format!("motion {:?} has no acceleration (PGA 0): it cannot be scaled to a level", m.name),
                ));
            }
        }
        Ok(Some(ShakeStudy {
            params,
            motions: motions.into_iter().map(|(_, m)| m).collect(),
            levels: spec.pga_g.clone(),
        }))
    }
}

/// Checks that a pulse sampled every `dt_s` seconds is resolved (its period spans at least
/// [`crate::ground::MIN_SAMPLES_PER_PERIOD`] samples) and within the motion limits.
fn check_pulse(p: &crate::ground::Pulse, dt_s: f64) -> Result<(), String> {
    let t = p.period_s();
    if t / dt_s < crate::ground::MIN_SAMPLES_PER_PERIOD {
        return Err(format!(
            "period_s = {t}: the pulse spans {:.1} steps of {dt_s:e} s, too few to resolve it (at least {}); give \
             period_s >= {:e} or a smaller [solver.nscd] dt_s",
            t / dt_s,
            crate::ground::MIN_SAMPLES_PER_PERIOD,
            crate::ground::MIN_SAMPLES_PER_PERIOD * dt_s
        ));
    }
    let span = if p.name() == "ricker" { 2.0 * t } else { t };
    crate::ground::check_motion_size((span / dt_s).ceil() + 1.0, span).map_err(|m| format!("period_s = {t}: {m}"))
}

/// Why a shaking study's `[shake] pga_g` levels cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LevelsError {
    /// No level.
    #[error("needs at least one PGA level, g")]
    Empty,
    /// A level not finite or not > 0, g.
    #[error("levels must be finite and > 0 g, got {0}")]
    NotPositive(f64),
    /// Two levels out of order, g.
    #[error("levels must increase, got {0} then {1}")]
    NotIncreasing(f64, f64),
    /// A level above [`MAX_LEVEL_PGA_G`], g.
    #[error("levels must be at most {MAX_LEVEL_PGA_G} g (no ground motion comes near; check the unit), got {0:e}")]
    TooLarge(f64),
}

/// The largest PGA level a shaking study accepts, g \[100\]: twenty times the level it
/// warns about ([`crate::ground::PLAUSIBLE_PGA_G`]); far above it the d'Alembert force
/// swamps gravity by orders of magnitude and every run ends `blew_up` or at once.
pub const MAX_LEVEL_PGA_G: f64 = 100.0;

/// PGA levels: at least one, each finite, > 0 and at most [`MAX_LEVEL_PGA_G`], strictly
/// increasing.
fn check_levels(levels: &[f64]) -> Result<(), LevelsError> {
    if levels.is_empty() {
        return Err(LevelsError::Empty);
    }
    if let Some(v) = levels.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(LevelsError::NotPositive(*v));
    }
    if let Some(v) = levels.iter().find(|v| **v > MAX_LEVEL_PGA_G) {
        return Err(LevelsError::TooLarge(*v));
    }
    if let Some(w) = levels.windows(2).find(|w| w[1] <= w[0]) {
        return Err(LevelsError::NotIncreasing(w[0], w[1]));
    }
    Ok(())
}

/// The generated motions of `[shake] stochastic = { count = N, ... }`: motion `i` is
/// [`crate::ground::StochasticMotion::generate`]`(seed, i)` with the table's parameters.
fn stochastic_motions(table: &toml::Table, seed: u64, invalid: &Invalid) -> Result<Vec<(String, Motion)>, StudyError> {
    let mut rest = table.clone();
    let count = match rest.remove("count") {
        Some(toml::Value::Integer(n)) if n >= 1 => n as u64,
        Some(v) => return Err(invalid.at("shake.stochastic.count", format!("must be an integer >= 1, got {v}"))),
        None => return Err(invalid.at("shake.stochastic.count", "missing: how many motions to generate".into())),
    };
    if count > size::MAX_SWEEP_POINTS {
        return Err(
            invalid.at("shake.stochastic.count", format!("{count} motions; the limit is {}", size::MAX_SWEEP_POINTS))
        );
    }
    let model: crate::ground::StochasticMotion = toml::Value::Table(rest)
        .try_into()
        .map_err(|e: toml::de::Error| invalid.at("shake.stochastic", e.message().to_string()))?;
    model.validate().map_err(|e| invalid.at(&format!("shake.stochastic.{}", e.key), e.reason()))?;
    Ok((0..count).map(|i| (format!("shake.stochastic (motion {i})"), model.generate(seed, i))).collect())
}

/// The sweep of the study's points: the file's `[sweep]`, and for a shaking study the
/// protocol's keys `motion` (every motion's name) and `pga_g` (every level), which sort
/// after the wall's keys: the motion varies after the wall, the level fastest.
pub(super) fn protocol_sweep(
    sweep: &BTreeMap<String, Vec<toml::Value>>,
    shake: Option<&ShakeStudy>,
) -> BTreeMap<String, Vec<toml::Value>> {
    let mut out = sweep.clone();
    if let Some(s) = shake {
        let names = s.motions.iter().map(|m| toml::Value::String(m.name.clone())).collect();
        out.insert(SweepKey::Motion.as_str().to_string(), names);
        out.insert(SweepKey::PgaG.as_str().to_string(), s.levels.iter().map(|&l| toml::Value::Float(l)).collect());
    }
    out
}
