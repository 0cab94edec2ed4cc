//! The check's report: its table, its verdicts in words and the lines the command prints.

use super::{finite, median, LoopCheck, LoopModel, LoopVerdict, LOOP_REALIZATIONS};
use std::fmt::Write as _;

impl LoopCheck {
    /// The models the loops do not refute whose peaks were refit with the friction their
    /// loops read ([`LoopModel::peaks`]), best held-out error first: what both readings
    /// leave standing. Empty when none.
    pub fn standing(&self) -> Vec<&LoopModel> {
        let mut v: Vec<&LoopModel> = self.models.iter().filter(|m| Self::stands(m) && m.peaks.is_some()).collect();
        v.sort_by(|a, b| {
            let e = |m: &LoopModel| m.peaks.as_ref().map_or(f64::INFINITY, |p| p.heldout_error);
            e(a).total_cmp(&e(b))
        });
        v
    }

    /// Whether a model fits the loops as fitted (its χ²'s p-value at least 0.05).
    pub fn fits(m: &LoopModel) -> bool {
        m.verdict == LoopVerdict::Fits
    }

    /// Whether the loops were read and leave a model standing (it fits them, as fitted or
    /// with the friction they read); a model they did not read is neither standing nor
    /// refuted.
    fn stands(m: &LoopModel) -> bool {
        matches!(m.verdict, LoopVerdict::Fits | LoopVerdict::FitsWithFriction)
    }

    /// How the runs' histories were chosen, in words.
    fn histories_run(&self) -> String {
        let groups = self.models.first().map_or(0, |m| m.groups.len());
        if self.own_histories == groups {
            "each specimen on its own measured history (its curve's turning points, in the laboratory's order) on a \
             layout of its own"
                .to_string()
        } else if self.own_histories == 0 {
            format!("the study's history on {LOOP_REALIZATIONS} layouts a stress")
        } else {
            format!(
                "each specimen on its own measured history where its group has them ({} of {groups} stresses), \
                 elsewhere the study's history on {LOOP_REALIZATIONS} layouts",
                self.own_histories
            )
        }
    }

    /// The report's section (Markdown).
    pub fn markdown(&self) -> String {
        let mut md = String::new();
        let _ = writeln!(md, "## The cyclic loops: a reading the fit does not hold\n");
        let _ = writeln!(
            md,
            "The loops' equivalent viscous damping ratio ξ_eq = E_d / (4π E_s), the median over the cycles of at \
             least {} % drift, of each cyclic specimen's whole measured curve and of each model run cyclic at its \
             fitted parameters, {} ({} runs): the baseline, every candidate asked before it could be named and the \
             models of the tie (a model whose wall is the baseline's, the scatter hypothesis or effects at their \
             neutral values, takes the baseline's loops). A model whose χ² fails (p < 0.05) and exceeds the baseline's by more than {} is \
             refuted by the loops and not named (the verdict's list of refuted candidates). A friction against the motion \
             (`rig_friction`) dissipates `4 μ_r N a` a cycle, a force of the displacement alone (`jack_tilt`, the \
             joints' closure) nothing. Per stress: the specimens' median against the model's mean, z their difference \
             over the standard errors (the specimens' spread σ = {:.4}, pooled); a model fits the loops when Σ z² is \
             below the χ² 95th percentile. The last columns read each run's curve of the wall's own shear again \
             with a bearing friction μ_r in place of the model's (no new run): the μ_r of least χ², its 95 % profile \
             interval, and the χ² there.\n",
            self.min_drift_pct,
            self.histories_run(),
            self.runs,
            2.0 * crate::discrepancy::REFUTE_NATS,
            self.measured_sigma
        );
        let Some(first) = self.models.first() else {
            return md;
        };
        let mut head = String::from("| model |");
        let mut rule = String::from("| --- |");
        for g in &first.groups {
            let _ = write!(head, " {} (z) |", g.group);
            rule.push_str(" --- |");
        }
        head.push_str(" χ² | p | fits the loops | μ_r the loops read (95 %) | χ² there |");
        rule.push_str(" --- | --- | --- | --- | --- |");
        let _ = writeln!(md, "{head}\n{rule}");
        let mut measured = String::from("| measured (median of the specimens) |");
        for g in &first.groups {
            let v: Vec<f64> = g.measured.iter().map(|(_, x)| *x).collect();
            let _ = write!(measured, " {:.4} ({}) |", median(&v), v.len());
        }
        measured.push_str(" | | | | |");
        let _ = writeln!(md, "{measured}");
        for m in &self.models {
            let wall = if m.baseline_wall { " (the baseline's wall)" } else { "" };
            let mut line = format!("| `{}`{wall} |", m.name);
            for g in &m.groups {
                let _ = write!(line, " {:.4} ({:+.1}) |", crate::stats::mean(&finite(&g.simulated)), g.z);
            }
            let fits = match m.verdict {
                LoopVerdict::NotRead => "not read",
                _ if Self::fits(m) => "yes",
                _ => "no",
            };
            let _ = write!(line, " {:.1} | {:.2e} | {fits} |", m.chi2, m.p_value);
            match &m.friction_read {
                Some(f) => {
                    let _ = write!(line, " {:.4} [{:.4}, {:.4}] | {:.1} |", f.friction, f.low, f.high, f.chi2);
                }
                None => line.push_str(" – | – |"),
            }
            let _ = writeln!(md, "{line}");
        }
        let _ = writeln!(md);
        let named = |v: LoopVerdict| -> Vec<String> {
            self.models
                .iter()
                .filter(|m| m.verdict == v)
                .map(|m| match (&m.friction_read, v) {
                    (Some(f), LoopVerdict::FitsWithFriction) if m.friction > 0.0 => format!(
                        "`{}` (μ_r {:.4} [{:.4}, {:.4}] in place of its {:.4})",
                        m.name, f.friction, f.low, f.high, m.friction
                    ),
                    (Some(f), LoopVerdict::FitsWithFriction) => {
                        format!("`{}` (μ_r {:.4} [{:.4}, {:.4}] added)", m.name, f.friction, f.low, f.high)
                    }
                    _ => format!("`{}`", m.name),
                })
                .collect()
        };
        let _ = writeln!(md, "What the loops say of each model:\n");
        for v in [
            LoopVerdict::Fits,
            LoopVerdict::FitsWithFriction,
            LoopVerdict::Misfits,
            LoopVerdict::Refuted,
            LoopVerdict::NotRead,
        ] {
            let n = named(v);
            if matches!(v, LoopVerdict::NotRead | LoopVerdict::Misfits) && n.is_empty() {
                continue;
            }
            let _ = writeln!(md, "- {}: {}", v.words(), if n.is_empty() { "none".into() } else { n.join(", ") });
        }
        let _ = writeln!(md);
        self.peaks_markdown(&mut md);
        md
    }

    /// The section's part on the peaks refit with the friction the loops read.
    fn peaks_markdown(&self, md: &mut String) {
        if !self.models.iter().any(|m| m.peaks.is_some()) {
            return;
        }
        let _ = writeln!(
            md,
            "### The analysis's observations with the friction the loops read
"
        );
        let cause = self.cause.as_ref().map(|(n, e)| format!(", the cause's (`{n}`) {e:.2}")).unwrap_or_default();
        let _ = writeln!(
            md,
            "Each model with `rig_friction` added or its own replaced, its other parameters refit to the analysis's \
             observations with the bearing friction held at the μ_r its loops read (the analysis's surrogates read \
             again, no run), scored as the ranking scores: held-out error per specimen, against the baseline's {:.2}{cause}.\n",
            self.baseline_heldout_error
        );
        let _ = writeln!(md, "| model | loops say | μ_r held | held-out error (± se of the gain) | parameters |");
        let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
        for m in &self.models {
            let (Some(p), Some(f)) = (&m.peaks, &m.friction_read) else { continue };
            let params: Vec<String> = p
                .parameters
                .iter()
                .filter(|(n, _)| !n.starts_with("rig_friction."))
                .map(|(n, v)| if v.abs() >= 0.1 || *v == 0.0 { format!("{n} {v:.3}") } else { format!("{n} {v:.2e}") })
                .collect();
            let _ = writeln!(
                md,
                "| `{}` | {} | {:.4} | {:.2} (± {:.2}) | {} |",
                m.name,
                m.verdict.words(),
                f.friction,
                p.heldout_error,
                p.difference_se,
                if params.is_empty() { "–".into() } else { params.join(", ") }
            );
        }
        let standing = self.standing();
        let _ = writeln!(md);
        match standing.first().and_then(|m| m.peaks.as_ref().map(|p| (m, p))) {
            Some((m, p)) => {
                let others: Vec<String> = standing[1..]
                    .iter()
                    .filter_map(|o| o.peaks.as_ref().map(|q| format!("`{}` {:.2}", o.name, q.heldout_error)))
                    .collect();
                let _ = writeln!(
                    md,
                    "What both readings leave standing: `{}` with μ_r {:.4} held (held-out error {:.2}, gain on the \
                     baseline {:.2} ± {:.2} per specimen){}.\n",
                    m.name,
                    m.friction_read.map_or(f64::NAN, |f| f.friction),
                    p.heldout_error,
                    self.baseline_heldout_error - p.heldout_error,
                    p.difference_se,
                    if others.is_empty() { String::new() } else { format!("; then {}", others.join(", ")) }
                );
            }
            None => {
                let _ = writeln!(md, "What both readings leave standing: none of the models checked.\n");
            }
        }
    }
}
