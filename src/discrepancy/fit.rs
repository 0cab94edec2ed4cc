//! Surrogates of the model over an effect's parameters, and the fits on them.
//!
//! Running the DEM inside an optimizer would cost thousands of ensembles. Instead each
//! candidate is run once on a grid of parameter values (common random numbers: the same
//! layouts at every node), and the simulated mean and spread of every observable are
//! interpolated between the nodes: piecewise linearly on a one-parameter axis, bilinearly
//! on a two-parameter grid, in the search coordinate `x ∈ [0, 1]` (linear or logarithmic in
//! the parameter, see [`crate::effects::Scale`]).
//!
//! **The surrogate's own error.** At every interior node the mean is predicted from its two
//! neighbours alone (leave one node out); the miss `e` measures the curvature the linear
//! interpolation cannot follow over two intervals. Over one interval the error of a smooth
//! curve is a quarter of that, largest mid-interval: at fraction `t` of an interval the
//! surrogate's standard error is `e t (1 − t)` (with `e` interpolated between the nodes
//! that have one), zero at the nodes, which were simulated. It enters every predictive
//! ([`super::predictive`]), so a coarse surrogate widens the predictive instead of
//! pretending to precision.
//!
//! A pair of effects is screened with the additive surrogate `m = m₀ + (m_a − m₀) + (m_b −
//! m₀)`, `s² = s₀² + (s_a² − s₀²) + (s_b² − s₀²)`. A pair with an effect that acts on the
//! readings only (`jack_tilt`, `rig_friction`) is not additive: its surrogate is a tensor
//! grid over both effects' parameters (the readings' coordinate first; two or three
//! coordinates), each node the partner's run at its node read again at the readings'
//! node, which needs no run. The `scatter` hypothesis has no DEM
//! run: it adds a specimen-to-specimen spread `τ` to the baseline's predictive (two
//! parameters: `τ` of the collapse angle, 0–[`SCATTER_ANGLE_MAX_DEG`]°, and of the
//! displacements as a fraction of the baseline's mean, 0–[`SCATTER_DISP_MAX`]).
//!
//! A fit minimises the summed score of the training observations over `x`: a scan of the
//! axis (101 points; 21 × 21 on a grid; 11 × 11 × 11 on three coordinates) and a polish of the best point with Brent's method
//! (argmin's `BrentOpt`), coordinate by coordinate. A specimen's observations are one joint
//! observation: its displacements (one stiffness seen at several tilts) are weighted
//! `1/k` for `k` displacements, its collapse angle 1; the information criterion counts
//! specimens.

use super::observations::Observation;
use super::predictive::{Predictive, Reading, Simulated};
use crate::effects::{ParamDef, Scale};
use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentOpt;

/// Largest specimen scatter of the collapse angle the `scatter` hypothesis considers, deg.
pub const SCATTER_ANGLE_MAX_DEG: f64 = 4.0;
/// Largest specimen scatter of a displacement, as a fraction of the baseline's mean.
pub const SCATTER_DISP_MAX: f64 = 1.5;

/// Search coordinate → parameter value.
pub fn to_value(p: &ParamDef, x: f64) -> f64 {
    match p.scale {
        Scale::Linear => p.min + x * (p.max - p.min),
        Scale::Log => p.min * (p.max / p.min).powf(x),
    }
}

/// Parameter value → search coordinate (the neutral value of an effect whose neutral is
/// infinite maps to 1).
pub fn to_x(p: &ParamDef, v: f64) -> f64 {
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
        /// Leave-one-node-out misses of the means, `[node][key]` ([`Surface::axis`]).
        miss: Vec<Vec<f64>>,
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
    /// Three parameters on a tensor grid: an effect that acts on the readings only (first
    /// coordinate) paired with a two-parameter effect, every node the partner's run read
    /// again ([`crate::effects::EffectDef::acts_on_readings_only`]).
    Grid3 {
        /// First coordinate's nodes, increasing.
        x1: Vec<f64>,
        /// Second coordinate's nodes, increasing.
        x2: Vec<f64>,
        /// Third coordinate's nodes, increasing.
        x3: Vec<f64>,
        /// `[(i * x2.len() + j) * x3.len() + k][key]`.
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
    /// Specimen-to-specimen scatter added to the baseline.
    Scatter {
        /// The baseline, per key.
        base: Vec<Simulated>,
        /// Whether each key is a collapse angle.
        angle: Vec<bool>,
        /// Whether each key is a mechanism observation (no scatter added: the hypothesis
        /// is about angles and displacements).
        mechanism: Vec<bool>,
    },
    /// A surface re-centred on a full run at one point: `at(x) = inner(x) + (full − inner(x₀))`
    /// in the mean and in the variance, the full run's size at every point (the
    /// surrogate's shape, the full run's level). Used twice: every grid is re-centred on
    /// the baseline's full run at its neutral point (so that the baseline and every
    /// candidate are scored with the same number of realizations), and a confirmed
    /// candidate on its own full run at its fitted point.
    Corrected {
        /// The surrogate.
        inner: Box<Surface>,
        /// The point of the full run.
        x0: Vec<f64>,
        /// The full run, per key.
        full: Vec<Simulated>,
    },
    /// A surface with one coordinate held: `at(x)` is `inner` at `x` with `value` inserted
    /// at `axis` (one dimension fewer). Used to refit a model with a parameter another
    /// reading fixes (the bearing friction the in-plane loops read,
    /// `study::inplane_loops`).
    Slice {
        /// The surface.
        inner: Box<Surface>,
        /// The coordinate held, `0..inner.dims()`.
        axis: usize,
        /// Its search coordinate, in `[0, 1]`.
        value: f64,
    },
}

fn lerp(a: &Simulated, b: &Simulated, t: f64) -> Simulated {
    Simulated {
        mean: a.mean + (b.mean - a.mean) * t,
        sd: a.sd + (b.sd - a.sd) * t,
        n: a.n.min(b.n),
        err: a.err + (b.err - a.err) * t,
        heights: a.heights.lerp(&b.heights, t),
    }
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

/// Leave-one-node-out misses of the means along a line of nodes (`[node][key]`): interior
/// nodes their own, end nodes their neighbour's.
fn loo_misses(xs: &[f64], sims: &[Vec<Simulated>]) -> Vec<Vec<f64>> {
    let n = xs.len();
    let keys = sims.first().map_or(0, Vec::len);
    let mut e = vec![vec![f64::NAN; keys]; n];
    for k in 1..n.saturating_sub(1) {
        let t = (xs[k] - xs[k - 1]) / (xs[k + 1] - xs[k - 1]);
        for j in 0..keys {
            let pred = sims[k - 1][j].mean + (sims[k + 1][j].mean - sims[k - 1][j].mean) * t;
            e[k][j] = (sims[k][j].mean - pred).abs();
        }
    }
    if n >= 3 {
        e[0] = e[1].clone();
        e[n - 1] = e[n - 2].clone();
    } else {
        e = vec![vec![0.0; keys]; n];
    }
    for row in &mut e {
        for v in row.iter_mut() {
            if !v.is_finite() {
                *v = 0.0;
            }
        }
    }
    e
}

/// Interpolates along a line of nodes with the surrogate error `e t (1 − t)`.
fn along(xs: &[f64], sims: &[Vec<Simulated>], miss: &[Vec<f64>], x: f64) -> Vec<Simulated> {
    if xs.len() == 1 {
        return sims[0].clone();
    }
    let (i, t) = locate(xs, x);
    sims[i]
        .iter()
        .zip(&sims[i + 1])
        .enumerate()
        .map(|(j, (a, b))| {
            let mut s = lerp(a, b, t);
            let e = miss[i][j] + (miss[i + 1][j] - miss[i][j]) * t;
            s.err = (s.err * s.err + (e * t * (1.0 - t)).powi(2)).sqrt();
            s
        })
        .collect()
}

impl Surface {
    /// A one-parameter surface on nodes `xs` (increasing) with values `sims[node][key]`.
    pub fn axis(xs: Vec<f64>, sims: Vec<Vec<Simulated>>) -> Surface {
        let miss = loo_misses(&xs, &sims);
        Surface::Axis { xs, sims, miss }
    }

    /// Number of parameters.
    pub fn dims(&self) -> usize {
        match self {
            Surface::Axis { .. } => 1,
            Surface::Grid { .. } | Surface::Pair { .. } | Surface::Scatter { .. } => 2,
            Surface::Grid3 { .. } => 3,
            Surface::Corrected { inner, .. } => inner.dims(),
            Surface::Slice { inner, .. } => inner.dims().saturating_sub(1),
        }
    }

    /// Whether this is the additive surface of two single effects ([`Surface::Pair`],
    /// re-centred or not): a pair the analysis adds to its ranking only when it beats
    /// the best single.
    pub fn is_pair(&self) -> bool {
        match self {
            Surface::Pair { .. } => true,
            Surface::Corrected { inner, .. } => inner.is_pair(),
            _ => false,
        }
    }

    /// The simulated values of every key at `x` (`dims()` coordinates).
    pub fn at(&self, x: &[f64]) -> Vec<Simulated> {
        match self {
            Surface::Axis { xs, sims, miss } => along(xs, sims, miss, x[0]),
            Surface::Grid { x1, x2, sims } => {
                // Interpolate along x2 on every x1 row, then along x1.
                let n2 = x2.len();
                let rows: Vec<Vec<Simulated>> = (0..x1.len())
                    .map(|i| {
                        let line: Vec<Vec<Simulated>> = (0..n2).map(|j| sims[i * n2 + j].clone()).collect();
                        along(x2, &line, &loo_misses(x2, &line), x[1])
                    })
                    .collect();
                along(x1, &rows, &loo_misses(x1, &rows), x[0])
            }
            Surface::Grid3 { x1, x2, x3, sims } => {
                // Interpolate along x3 on every (x1, x2) line, then as a grid on (x1, x2).
                let (n2, n3) = (x2.len(), x3.len());
                let plane: Vec<Vec<Simulated>> = (0..x1.len() * n2)
                    .map(|ij| {
                        let line: Vec<Vec<Simulated>> = (0..n3).map(|k| sims[ij * n3 + k].clone()).collect();
                        along(x3, &line, &loo_misses(x3, &line), x[2])
                    })
                    .collect();
                Surface::Grid { x1: x1.clone(), x2: x2.clone(), sims: plane }.at(&x[..2])
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
                            err: (p.err * p.err + q.err * q.err).sqrt(),
                            heights: o.heights.shifted(&[(&p.heights, &o.heights), (&q.heights, &o.heights)]),
                        }
                    })
                    .collect()
            }
            Surface::Scatter { base, angle, mechanism } => base
                .iter()
                .zip(angle.iter().zip(mechanism))
                .map(|(o, (&is_angle, &is_mechanism))| {
                    let tau = if is_mechanism {
                        0.0
                    } else if is_angle {
                        x[0] * SCATTER_ANGLE_MAX_DEG
                    } else {
                        x[1] * SCATTER_DISP_MAX * o.mean.abs()
                    };
                    Simulated { err: (o.err * o.err + tau * tau).sqrt(), ..*o }
                })
                .collect(),
            Surface::Corrected { inner, x0, full } => {
                let at0 = inner.at(x0);
                inner
                    .at(x)
                    .iter()
                    .zip(at0.iter().zip(full))
                    .map(|(s, (s0, f))| Simulated {
                        mean: if s.mean.is_finite() && s0.mean.is_finite() {
                            f.mean + (s.mean - s0.mean)
                        } else {
                            f.mean
                        },
                        sd: if s.sd.is_finite() && s0.sd.is_finite() {
                            (f.sd * f.sd + s.sd * s.sd - s0.sd * s0.sd).max(0.0).sqrt()
                        } else {
                            f.sd
                        },
                        n: f.n,
                        err: s.err,
                        heights: f.heights.shifted(&[(&s.heights, &s0.heights)]),
                    })
                    .collect()
            }
            Surface::Slice { inner, axis, value } => {
                let mut full = x[..self.dims()].to_vec();
                full.insert((*axis).min(full.len()), *value);
                inner.at(&full)
            }
        }
    }
}

/// The data a fit sees: the observations, their values (measured or synthetic), the key of
/// each observation into the surfaces' keys, each observation's weight, the readings'
/// resolutions and the width of a simulated collapse angle's bracket.
#[derive(Debug, Clone, Copy)]
pub struct Data<'a> {
    /// The observations.
    pub obs: &'a [Observation],
    /// Their values (the observations' own, or a null replicate's).
    pub y: &'a [f64],
    /// Key of each observation.
    pub key: &'a [usize],
    /// Weight of each observation (a specimen's displacements share one observation).
    pub weight: &'a [f64],
    /// Reading resolutions.
    pub reading: Reading,
    /// Width of a simulated collapse angle's bracket, degrees (the study's tilt resolution).
    pub bracket_deg: f64,
}

impl Data<'_> {
    /// Weighted score of the observations `which` under the simulated values `sims`.
    pub fn nlpd(&self, sims: &[Simulated], which: &[usize]) -> f64 {
        which.iter().map(|&j| self.score(sims, j)).sum()
    }

    /// Weighted score of observation `j`.
    pub fn score(&self, sims: &[Simulated], j: usize) -> f64 {
        let o = &self.obs[j].observable;
        if let Some(q) = self.reading.category_probability(o, &sims[self.key[j]]) {
            return self.weight[j] * super::predictive::category_score(q, self.y[j]);
        }
        if let Some(width) = o.place_width() {
            let sim = &sims[self.key[j]];
            let r = &self.reading;
            return self.weight[j] * super::predictive::height_score(sim, self.y[j], width, self.obs[j].sigma, r);
        }
        let r = self.reading.of(o);
        self.weight[j] * self.predictive(sims, j).score(self.y[j], r)
    }

    /// Whether the absolute checks of fit read observation `j`: the collapse angles, the
    /// displacements and the failure heights, not the categorical readings of the
    /// mechanism (kind, start). The misfit margin and the posterior predictive check
    /// compare a model's score on the data with its score on data drawn from itself; a
    /// realization's kind and start are classified by the product's own rule
    /// (`loading::mechanism::read_mechanism`: a share of the largest motion, joints that
    /// open or slide), a specimen's by a person whose rule differs from it (what counts as
    /// toppling or as mixed, as a centre start or a uniform one), so on them such a check
    /// would test the reader's convention, not the model. A failure height is a place on
    /// the wall, read alike by any rule up to a neighbouring joint, which its likelihood
    /// allows for ([`super::predictive::Reading::neighbour_joint`]). The categories enter
    /// the comparisons between models (the ranking, the gain margin, the tie checks, the
    /// weights), where a reader's convention costs every model alike.
    pub fn fit_checked(&self, j: usize) -> bool {
        self.obs[j].observable.fit_checked()
    }

    /// Whether observation `j` is a measure that pins a model's parameters: a collapse
    /// angle or a top displacement, read by an instrument of stated σ. A model's parameters
    /// are fitted to these alone ([`loso`], [`profile_intervals`]); the readings of the
    /// failure mechanism (failure height, kind, start) are scored at that fit and so enter
    /// the comparisons between models (the ranking, the margins, the tie checks, the
    /// weights) without moving a parameter. A person reads a mechanism by a rule of their
    /// own (where the moving part starts, what counts as toppling), and a rule that sits a
    /// course higher than the product's, read alike on every specimen, would otherwise pull
    /// a stiffness or a lean the angles pin off its value, and the model would then fail its
    /// predictive check on the angles (the independent observer's readings in
    /// `examples/realwall_power.rs` showed it: restraint stiffness pulled until the held
    /// walls' α_max missed by 4 σ). On angles and displacements alone every observation
    /// pins, and the fits are those of a fit to all.
    pub fn pins(&self, j: usize) -> bool {
        self.obs[j].observable.pins()
    }

    /// The observations that pin the parameters ([`Data::pins`]) among `which`.
    pub fn pinning(&self, which: &[usize]) -> Vec<usize> {
        which.iter().copied().filter(|&j| self.pins(j)).collect()
    }

    /// Every observation's score `scores` with those the absolute checks do not read
    /// ([`Data::fit_checked`]) set to 0 (sums over it are those of the checked
    /// observations, in the same order).
    pub fn checked_scores(&self, scores: &[f64]) -> Vec<f64> {
        masked(scores, |j| self.fit_checked(j))
    }

    /// Every observation's score `scores` split into the measures' ([`Data::pins`]) and
    /// the readings', each with the other's set to 0 (sums over either are those of its
    /// observations, in the same order).
    pub fn split_scores(&self, scores: &[f64]) -> (Vec<f64>, Vec<f64>) {
        (masked(scores, |j| self.pins(j)), masked(scores, |j| !self.pins(j)))
    }

    /// The predictive distribution of observation `j` (of a category's indicator:
    /// [`Predictive::category`]).
    pub fn predictive(&self, sims: &[Simulated], j: usize) -> Predictive {
        match self.reading.category_probability(&self.obs[j].observable, &sims[self.key[j]]) {
            Some(q) => Predictive::category(q),
            None => Predictive::new(&sims[self.key[j]], &self.obs[j], self.bracket_deg),
        }
    }
}

/// `scores` with every entry `keep` refuses set to 0.
fn masked(scores: &[f64], keep: impl Fn(usize) -> bool) -> Vec<f64> {
    scores.iter().enumerate().map(|(j, &s)| if keep(j) { s } else { 0.0 }).collect()
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
/// summed score. The analysis fits through [`fit_folds`], which gives the same results.
#[cfg(test)]
pub fn fit(surface: &Surface, data: Data<'_>, which: &[usize]) -> (Vec<f64>, f64) {
    let cost = |x: &[f64]| data.nlpd(&surface.at(x), which);
    let mut best = (vec![0.0; surface.dims()], f64::INFINITY);
    for x in scan_points(surface) {
        let c = cost(&x);
        if c < best.1 {
            best = (x, c);
        }
    }
    polish(surface, data, which, best)
}

/// Fits the surface's parameters to each set of observations of `folds`: returns each
/// fold's best `x` and its summed score. A scan of the axis (101 points; 21 × 21 on a
/// grid), then a polish of the best point with Brent's method, coordinate by coordinate.
/// The score of every observation at every scan point is computed once for all folds and
/// summed per fold in the fold's order, as [`Data::nlpd`] sums it (the same results, bit
/// for bit, as scanning each fold on its own); the polish is each fold's own.
pub fn fit_folds(surface: &Surface, data: Data<'_>, folds: &[&[usize]]) -> Vec<(Vec<f64>, f64)> {
    let scan = scan_points(surface);
    let mut used = vec![false; data.obs.len()];
    for &j in folds.iter().flat_map(|f| f.iter()) {
        used[j] = true;
    }
    let table: Vec<Vec<f64>> = scan
        .iter()
        .map(|x| {
            let sims = surface.at(x);
            (0..data.obs.len()).map(|j| if used[j] { data.score(&sims, j) } else { 0.0 }).collect()
        })
        .collect();
    folds
        .iter()
        .map(|which| {
            let mut best = (vec![0.0; surface.dims()], f64::INFINITY);
            for (x, row) in scan.iter().zip(&table) {
                let c: f64 = which.iter().map(|&j| row[j]).sum();
                if c < best.1 {
                    best = (x.clone(), c);
                }
            }
            polish(surface, data, which, best)
        })
        .collect()
}

/// The points a fit scans: 101 on the axis of a one-parameter surface, 21 × 21 on a grid,
/// 11 × 11 × 11 on a three-parameter grid ([`Surface::Grid3`]).
pub(super) fn scan_points(surface: &Surface) -> Vec<Vec<f64>> {
    let n = scan_size(surface);
    let at = |i: usize| i as f64 / (n - 1) as f64;
    if surface.dims() == 0 {
        vec![vec![]]
    } else if surface.dims() == 1 {
        (0..n).map(|i| vec![at(i)]).collect()
    } else if surface.dims() == 3 {
        (0..n * n * n).map(|k| vec![at(k / (n * n)), at(k / n % n), at(k % n)]).collect()
    } else {
        (0..n * n).map(|k| vec![(k / n) as f64 / (n - 1) as f64, (k % n) as f64 / (n - 1) as f64]).collect()
    }
}

fn scan_size(surface: &Surface) -> usize {
    match surface.dims() {
        1 => 101,
        3 => 11,
        _ => 21,
    }
}

/// The polish of a scan's best point `(x, cost)` with Brent's method, coordinate by
/// coordinate, within one scan interval of it.
fn polish(
    surface: &Surface,
    data: Data<'_>,
    which: &[usize],
    (mut best, mut best_cost): (Vec<f64>, f64),
) -> (Vec<f64>, f64) {
    let cost = |x: &[f64]| data.nlpd(&surface.at(x), which);
    let h = 1.0 / (scan_size(surface) - 1) as f64;
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

/// The profile interval of every coordinate of a fit at `x`: along each axis (the others
/// at `x`), the connected range around `x` where the summed score of `which` stays within
/// 1.92 of its minimum (a 95 % likelihood-ratio interval, χ²₁ / 2). Returns `(lo, hi)`
/// coordinates.
pub fn profile_intervals(surface: &Surface, data: Data<'_>, which: &[usize], x: &[f64]) -> Vec<(f64, f64)> {
    let f0 = data.nlpd(&surface.at(x), which);
    (0..x.len())
        .map(|axis| {
            let at = |v: f64| {
                let mut y = x.to_vec();
                y[axis] = v;
                data.nlpd(&surface.at(&y), which) - f0 <= 1.92
            };
            let n = 200;
            let h = 1.0 / n as f64;
            let (mut lo, mut hi) = (x[axis], x[axis]);
            while lo - h >= 0.0 && at(lo - h) {
                lo -= h;
            }
            while hi + h <= 1.0 && at(hi + h) {
                hi += h;
            }
            (lo.max(0.0), hi.min(1.0))
        })
        .collect()
}

/// Leave-one-specimen-out cross-validation of a surface: for every specimen, fit on the
/// others' measures ([`Data::pins`]) and score the specimen's observations, readings of
/// the mechanism included. Returns the held-out score of every observation, the held-out
/// predictive of every observation and the fit on every specimen's measures (`x` and the
/// summed score of every observation there), all from one scan ([`fit_folds`]).
pub fn loso(surface: &Surface, data: Data<'_>, specimens: &[String]) -> (Vec<f64>, Vec<Predictive>, (Vec<f64>, f64)) {
    let n = data.obs.len();
    let mut score = vec![0.0; n];
    let mut pred = vec![Predictive { mean: f64::NAN, sd: f64::NAN, dof: f64::NAN }; n];
    let all: Vec<usize> = (0..n).collect();
    let pinning = data.pinning(&all);
    let trains: Vec<Vec<usize>> =
        specimens.iter().map(|s| pinning.iter().copied().filter(|&j| &data.obs[j].specimen != s).collect()).collect();
    let folds: Vec<&[usize]> = trains.iter().map(Vec::as_slice).chain([pinning.as_slice()]).collect();
    let mut fits = fit_folds(surface, data, &folds);
    let mut whole = fits.pop().expect("the full-data fit");
    if pinning.len() < n {
        // Fitted on the measures, scored on every observation (the AICc's likelihood).
        whole.1 = data.nlpd(&surface.at(&whole.0), &all);
    }
    for (s, (x, _)) in specimens.iter().zip(fits) {
        let test: Vec<usize> = (0..n).filter(|&j| &data.obs[j].specimen == s).collect();
        let sims = surface.at(&x);
        for j in test {
            pred[j] = data.predictive(&sims, j);
            score[j] = data.score(&sims, j);
        }
    }
    (score, pred, whole)
}

#[cfg(test)]
mod tests;
