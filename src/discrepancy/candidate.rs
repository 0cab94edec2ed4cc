//! A candidate explanation of the discrepancy: one effect, a pair of effects, or the
//! specimen scatter, each with its surrogate over its parameters ([`super::fit`]).

use super::fit::{to_value, to_x, Surface, SCATTER_ANGLE_MAX_DEG, SCATTER_DISP_MAX};
use super::predictive::Simulated;
use crate::effects::{EffectDef, ParamDef, Scale, WallKind};
use std::sync::Arc;

/// A candidate explanation: one effect, a pair, or the specimen scatter, with its
/// surrogate.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The effects (empty for the scatter hypothesis).
    pub effects: Vec<Arc<EffectDef>>,
    /// The parameters, in coordinate order, with their ranges for the analysed walls.
    pub params: Vec<ParamDef>,
    /// The surrogate over their parameters.
    pub surface: Surface,
    /// The declared kinds of the analysed walls ([`WallKind`]), in order: a parameter with
    /// a range of a wall's kind takes the value at the same coordinate in that range
    /// ([`ParamDef::at_for`]). Empty when no wall declares one.
    pub kinds: Vec<WallKind>,
}

/// The name of the specimen-scatter hypothesis.
pub const SCATTER: &str = "scatter";

impl Candidate {
    /// `a+b` style name, or `scatter`.
    pub fn name(&self) -> String {
        if self.effects.is_empty() {
            return SCATTER.into();
        }
        self.effects.iter().map(|e| e.name.as_str()).collect::<Vec<_>>().join("+")
    }

    /// The specimen-scatter hypothesis (no mechanism).
    pub fn is_scatter(&self) -> bool {
        self.effects.is_empty()
    }

    /// The scatter hypothesis on a baseline (`angle`: each key a collapse angle;
    /// `mechanism`: each key a mechanism observation, left as the baseline has it).
    pub fn scatter(base: Vec<Simulated>, angle: Vec<bool>, mechanism: Vec<bool>) -> Candidate {
        let p = |name: &str, unit: &str, max: f64| ParamDef {
            name: name.into(),
            unit: unit.into(),
            min: 0.0,
            max,
            scale: Scale::Linear,
            neutral: 0.0,
            range_per_course_height: false,
            source: String::new(),
            kinds: vec![],
        };
        Candidate {
            kinds: vec![],
            effects: vec![],
            params: vec![p("angle_sd_deg", "deg", SCATTER_ANGLE_MAX_DEG), p("displacement_cv", "-", SCATTER_DISP_MAX)],
            surface: Surface::Scatter { base, angle, mechanism },
        }
    }

    /// Parameter values at `x` for each declared kind of the analysed walls that has a range
    /// of its own for one of them: `(kind, [effect.param → value])`, the parameters
    /// without a range of the kind at their broad-range value.
    pub fn values_by_kind(&self, x: &[f64]) -> Vec<(WallKind, Vec<(String, f64)>)> {
        let names = self.values(x);
        self.kinds
            .iter()
            .filter(|&&k| self.params.iter().any(|p| p.has_kind(k)))
            .map(|&k| {
                let v = names
                    .iter()
                    .zip(self.params.iter().zip(x))
                    .map(|((n, _), (p, &xi))| (n.clone(), p.at_for(Some(k), xi)))
                    .collect();
                (k, v)
            })
            .collect()
    }

    /// Whether the candidate's model at search coordinates `x` is the baseline's: the
    /// specimen-scatter hypothesis (no effect on the wall, any `x`), or every coordinate
    /// exactly at its parameter's neutral value's (an effect there leaves the model
    /// unchanged, [`ParamDef::neutral`]; the surrogate grids read the baseline's runs at that
    /// node). `false` when `x` has another length than the parameters.
    pub fn is_baseline_at(&self, x: &[f64]) -> bool {
        self.is_scatter()
            || (self.params.len() == x.len()
                && self.params.iter().zip(x).all(|(q, xi)| to_x(q, q.neutral).clamp(0.0, 1.0) == *xi))
    }

    /// Parameter values at `x`, as `effect.param` → value.
    pub fn values(&self, x: &[f64]) -> Vec<(String, f64)> {
        let mut names = Vec::new();
        if self.effects.is_empty() {
            names.extend(self.params.iter().map(|p| format!("{SCATTER}.{}", p.name)));
        } else {
            let mut k = 0;
            for e in &self.effects {
                for p in &e.parameters {
                    names.push(format!("{}.{}", e.name, p.name));
                    k += 1;
                }
            }
            debug_assert_eq!(k, self.params.len());
        }
        names.into_iter().zip(self.params.iter().zip(x)).map(|(n, (p, &xi))| (n, to_value(p, xi))).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn single(name: &str) -> Candidate {
        let def = crate::effects::Library::builtin().get(name).unwrap();
        Candidate {
            params: def.params_for(0.2),
            effects: vec![def],
            kinds: vec![],
            surface: Surface::axis(vec![], vec![]),
        }
    }

    /// The baseline's model: a seating gap of 0 m (its range's lower end, coordinate 0), a
    /// stiffness factor of 1 (inside its log range 0.05–2, at ln 20 / ln 40 of it), and the
    /// scatter hypothesis anywhere; a gap a millionth of its range up or a factor at either
    /// end of its range is another model.
    #[test]
    fn the_neutral_values_and_the_scatter_hypothesis_are_the_baselines_model() {
        let gap = single("seating_gap");
        assert!(gap.is_baseline_at(&[0.0]));
        assert!(!gap.is_baseline_at(&[1e-6]));
        assert!(!gap.is_baseline_at(&[]), "a coordinate missing is not the baseline");
        let kn = single("kn_scale");
        let one = to_x(&kn.params[0], 1.0);
        assert!((to_value(&kn.params[0], one) - 1.0).abs() < 1e-12, "the factor at its neutral coordinate is 1");
        assert!(kn.is_baseline_at(&[one]));
        assert!(!kn.is_baseline_at(&[0.0]) && !kn.is_baseline_at(&[1.0]));
        let scatter = Candidate::scatter(vec![], vec![], vec![]);
        assert!(scatter.is_baseline_at(&[0.3, 0.7]));
    }
}
