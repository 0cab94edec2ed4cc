//! Surrogates of the model over an effect's parameters, and the fits on them.
//!
//! Running the DEM inside an optimizer would cost thousands of ensembles. Instead each
//! candidate is run once on a small grid of parameter values (common random numbers: the
//! same layouts at every node), and the simulated mean and spread of every observable are
//! interpolated between the nodes: piecewise linearly on a one-parameter axis, bilinearly
//! on a two-parameter grid, in the search coordinate `x ∈ [0, 1]` (linear or logarithmic in
//! the parameter, see [`super::effects::Scale`]). A pair of effects is screened with the
//! additive surrogate `m = m₀ + (m_a − m₀) + (m_b − m₀)`, `s² = s₀² + (s_a² − s₀²) +
//! (s_b² − s₀²)`, and confirmed by a full run when it wins.
//!
//! A fit minimises the summed NLPD of the training observations over `x`: a scan of the
//! axis (101 points; 41 × 41 on a grid) and a polish of the best point with Brent's method
//! (argmin's `BrentOpt`), coordinate by coordinate.

use super::effects::{EffectKind, ParamInfo, Scale};
use super::observations::Observation;
use super::predictive::{Predictive, Simulated};
use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentOpt;

/// Search coordinate → parameter value.
pub fn to_value(p: &ParamInfo, x: f64) -> f64 {
    match p.scale {
        Scale::Linear => p.min + x * (p.max - p.min),
        Scale::Log => p.min * (p.max / p.min).powf(x),
    }
}

/// Parameter value → search coordinate (the neutral value of an effect whose neutral is
/// infinite maps to 1).
pub fn to_x(p: &ParamInfo, v: f64) -> f64 {
    if !v.is_finite() {
        return 1.0;
    }
    match p.scale {
        Scale::Linear => (v - p.min) / (p.max - p.min),
        Scale::Log => (v / p.min).ln() / (p.max / p.min).ln(),
    }
}

/// The simulated mean and spread of every observable key at a point of a candidate's
/// parameter space.
#[derive(Debug, Clone)]
pub enum Surface {
    /// One parameter: nodes (sorted `x`) and the simulated values per node and key.
    Axis {
        /// Node coordinates, increasing.
        xs: Vec<f64>,
        /// `[node][key]`.
        sims: Vec<Vec<Simulated>>,
    },
    /// Two parameters on a tensor grid.
    Grid {
        /// First coordinate's nodes, increasing.
        x1: Vec<f64>,
        /// Second coordinate's nodes, increasing.
        x2: Vec<f64>,
        /// `[i * x2.len() + j][key]`.
        sims: Vec<Vec<Simulated>>,
    },
    /// Two one-parameter effects combined additively about the baseline.
    Pair {
        /// First effect's surface.
        a: Box<Surface>,
        /// Second effect's surface.
        b: Box<Surface>,
        /// The baseline, per key.
        base: Vec<Simulated>,
    },
}

fn lerp(a: &Simulated, b: &Simulated, t: f64) -> Simulated {
    Simulated { mean: a.mean + (b.mean - a.mean) * t, sd: a.sd + (b.sd - a.sd) * t, n: a.n.min(b.n) }
}

/// Index of the interval of `xs` holding `x` (clamped) and the fraction within it.
fn locate(xs: &[f64], x: f64) -> (usize, f64) {
    if xs.len() < 2 {
        return (0, 0.0);
    }
    let x = x.clamp(xs[0], xs[xs.len() - 1]);
    let i = xs.windows(2).position(|w| x <= w[1]).unwrap_or(xs.len() - 2);
    let t = if xs[i + 1] > xs[i] { (x - xs[i]) / (xs[i + 1] - xs[i]) } else { 0.0 };
    (i, t)
}

impl Surface {
    /// Number of parameters.
    pub fn dims(&self) -> usize {
        match self {
            Surface::Axis { .. } => 1,
            Surface::Grid { .. } | Surface::Pair { .. } => 2,
        }
    }

    /// The simulated values of every key at `x` (`dims()` coordinates).
    pub fn at(&self, x: &[f64]) -> Vec<Simulated> {
        match self {
            Surface::Axis { xs, sims } => {
                if xs.len() == 1 {
                    return sims[0].clone();
                }
                let (i, t) = locate(xs, x[0]);
                sims[i].iter().zip(&sims[i + 1]).map(|(a, b)| lerp(a, b, t)).collect()
            }
            Surface::Grid { x1, x2, sims } => {
                let (i, t) = locate(x1, x[0]);
                let (j, u) = locate(x2, x[1]);
                let n2 = x2.len();
                let (i1, j1) = ((i + 1).min(x1.len() - 1), (j + 1).min(n2 - 1));
                let row = |ii: usize| -> Vec<Simulated> {
                    sims[ii * n2 + j].iter().zip(&sims[ii * n2 + j1]).map(|(a, b)| lerp(a, b, u)).collect()
                };
                row(i).iter().zip(&row(i1)).map(|(a, b)| lerp(a, b, t)).collect()
            }
            Surface::Pair { a, b, base } => {
                let (sa, sb) = (a.at(&x[..1]), b.at(&x[1..2]));
                base.iter()
                    .zip(sa.iter().zip(&sb))
                    .map(|(o, (p, q))| {
                        let var = o.sd * o.sd + (p.sd * p.sd - o.sd * o.sd) + (q.sd * q.sd - o.sd * o.sd);
                        Simulated {
                            mean: o.mean + (p.mean - o.mean) + (q.mean - o.mean),
                            sd: var.max(0.0).sqrt(),
                            n: o.n.min(p.n).min(q.n),
                        }
                    })
                    .collect()
            }
        }
    }
}

/// The data a fit sees: the observations, their values (measured or synthetic), the key of
/// each observation into the surfaces' keys, and the tilt resolution.
#[derive(Debug, Clone, Copy)]
pub struct Data<'a> {
    /// The observations.
    pub obs: &'a [Observation],
    /// Their values (the observations' own, or a null replicate's).
    pub y: &'a [f64],
    /// Key of each observation.
    pub key: &'a [usize],
    /// Collapse-angle resolution, degrees.
    pub resolution_deg: f64,
}

impl Data<'_> {
    /// NLPD of the observations `which` under the simulated values `sims` (per key).
    pub fn nlpd(&self, sims: &[Simulated], which: &[usize]) -> f64 {
        which.iter().map(|&j| self.predictive(sims, j).nlpd(self.y[j])).sum()
    }

    /// The predictive distribution of observation `j`.
    pub fn predictive(&self, sims: &[Simulated], j: usize) -> Predictive {
        Predictive::new(&sims[self.key[j]], &self.obs[j], self.resolution_deg)
    }
}

struct Along<'a> {
    surface: &'a Surface,
    data: Data<'a>,
    which: &'a [usize],
    x: Vec<f64>,
    axis: usize,
}

impl CostFunction for Along<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, v: &f64) -> Result<f64, argmin::core::Error> {
        let mut x = self.x.clone();
        x[self.axis] = v.clamp(0.0, 1.0);
        Ok(self.data.nlpd(&self.surface.at(&x), self.which))
    }
}

/// Fits the surface's parameters to the observations `which`: returns the best `x` and its
/// summed NLPD.
pub fn fit(surface: &Surface, data: Data<'_>, which: &[usize]) -> (Vec<f64>, f64) {
    let cost = |x: &[f64]| data.nlpd(&surface.at(x), which);
    let (mut best, mut best_cost) = (vec![0.0; surface.dims()], f64::INFINITY);
    let n = if surface.dims() == 1 { 101 } else { 41 };
    let scan: Vec<Vec<f64>> = if surface.dims() == 1 {
        (0..n).map(|i| vec![i as f64 / (n - 1) as f64]).collect()
    } else {
        (0..n * n).map(|k| vec![(k / n) as f64 / (n - 1) as f64, (k % n) as f64 / (n - 1) as f64]).collect()
    };
    for x in scan {
        let c = cost(&x);
        if c < best_cost {
            (best, best_cost) = (x, c);
        }
    }
    let h = 1.0 / (n - 1) as f64;
    for _sweep in 0..surface.dims() {
        for axis in 0..surface.dims() {
            let lo = (best[axis] - h).max(0.0);
            let hi = (best[axis] + h).min(1.0);
            if hi <= lo {
                continue;
            }
            let problem = Along { surface, data, which, x: best.clone(), axis };
            let solver = BrentOpt::new(lo, hi).set_tolerance(1e-6, 1e-8);
            if let Ok(res) = Executor::new(problem, solver).configure(|s| s.max_iters(60)).run() {
                if let Some(v) = res.state.best_param {
                    let mut x = best.clone();
                    x[axis] = v.clamp(0.0, 1.0);
                    let c = cost(&x);
                    if c < best_cost {
                        (best, best_cost) = (x, c);
                    }
                }
            }
        }
    }
    (best, best_cost)
}

/// A candidate explanation: one effect or a pair, with its surrogate.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The effects.
    pub effects: Vec<EffectKind>,
    /// The surrogate over their parameters.
    pub surface: Surface,
}

impl Candidate {
    /// `a+b` style name.
    pub fn name(&self) -> String {
        self.effects.iter().map(|e| e.name()).collect::<Vec<_>>().join("+")
    }

    /// Parameter descriptions, in coordinate order.
    pub fn params(&self) -> Vec<(EffectKind, ParamInfo)> {
        self.effects.iter().flat_map(|&e| e.params().iter().map(move |p| (e, *p))).collect()
    }

    /// Parameter values at `x`, as `effect.param` → value.
    pub fn values(&self, x: &[f64]) -> Vec<(String, f64)> {
        self.params().iter().zip(x).map(|((e, p), &xi)| (format!("{}.{}", e.name(), p.name), to_value(p, xi))).collect()
    }
}

/// Leave-one-specimen-out cross-validation of a surface: for every specimen, fit on the
/// others and score the specimen's observations. Returns the held-out NLPD of every
/// observation and the held-out predictive of every observation.
pub fn loso(surface: &Surface, data: Data<'_>, specimens: &[String]) -> (Vec<f64>, Vec<Predictive>) {
    let n = data.obs.len();
    let mut score = vec![0.0; n];
    let mut pred = vec![Predictive { mean: f64::NAN, sd: f64::NAN }; n];
    for s in specimens {
        let train: Vec<usize> = (0..n).filter(|&j| &data.obs[j].specimen != s).collect();
        let test: Vec<usize> = (0..n).filter(|&j| &data.obs[j].specimen == s).collect();
        let (x, _) = fit(surface, data, &train);
        let sims = surface.at(&x);
        for j in test {
            pred[j] = data.predictive(&sims, j);
            score[j] = pred[j].nlpd(data.y[j]);
        }
    }
    (score, pred)
}

/// AICc = 2k − 2 ln L + 2k(k+1)/(n − k − 1) (Hurvich & Tsai 1989) from the summed NLPD at
/// the full-data fit, `k` parameters and `n` observations.
pub fn aicc(nlpd: f64, k: usize, n: usize) -> f64 {
    let (k, n) = (k as f64, n as f64);
    let corr = if n - k - 1.0 > 0.0 { 2.0 * k * (k + 1.0) / (n - k - 1.0) } else { f64::INFINITY };
    2.0 * k + 2.0 * nlpd + corr
}
