//! The predictive distribution of an observation under a model, and the likelihood of a
//! reading.
//!
//! A model is run for `R` realizations (layouts); their values of an observable have mean
//! `m` and standard deviation `s`. A new specimen's reading is predicted as Student-t with
//! location `m` and scale `S`,
//!
//! `S² = s² (1 + 1/R) + σ_meas² + σ_sur² + b²/12`,
//!
//! the prediction variance of a new draw (Geisser 1993), the measurement error, the
//! surrogate's own error at the point (its leave-one-node-out estimate, [`super::fit`]) and
//! the quantization of a collapse angle bracketed to `b` (the tilt resolution). Its degrees
//! of freedom are Welch–Satterthwaite's, `ν = S⁴ (R − 1) / (s² (1 + 1/R))²`: with few
//! realizations the spread is itself uncertain and the tails are heavy; with many, or when
//! the measurement error dominates, the predictive is Gaussian.
//!
//! A reading is an interval: a value rounded to its resolution `r` (0.5° for the paper's
//! angles, 0.1 cm for its displacements) means the truth is in `[y − r/2, y + r/2]`. Its
//! score is the negative log of the predictive probability of that interval, plus `ln r`
//! (so that for a fine resolution it is the negative log predictive density, NLPD: a proper
//! scoring rule, which charges a wrong mean and a wrong spread alike).
//!
//! **Mechanisms.** A failure height (a fraction of the wall's height) is not a unimodal
//! quantity: a wall fails at the table joint or at one particular bed joint higher up. Its
//! predictive is the distribution of the realizations' failure heights over the height
//! ([`Heights`]: their shares in bins of 1/20 of the height centred on 0, 0.05, …, 1),
//! smoothed by a Gaussian kernel of the reading's σ (0.05 of the height by default, with
//! the surrogate's error added in quadrature) truncated to [0, 1], and mixed with a
//! misreading component: with probability `ε` (\[0.1\], the readings' misreading
//! probability) the reading belongs to none of the simulated failures and is uniform over
//! the height. The joint read need not be the one the model calls the failing joint:
//! observers differ in which block they call the lowest of the moving part (the lowest that
//! moved at all, or the lowest that moved with the rest), by about a course. A reading of
//! the joint `y` with interval `[a, b] = y ± w/2` (clipped to [0, 1]) stands for the failing
//! joint `y` with probability `1 − 2d` and for each neighbouring joint `y ± w` with
//! probability `d` (\[0.25\], `Reading::neighbour_joint`; a neighbour off the wall gives its
//! share to `y`). Its probability is
//! `q = (1 − ε) Σ_s d_s Σ_i m_i K_i([a, b] + s) / K_i([0, 1]) + ε (b − a)` (`s` ∈ {0, ±w},
//! `d_0 = 1 − 2d`, `d_±w = d`; `m_i` the bin shares, `K_i` the kernel's mass about bin
//! centre `c_i`; the uniform alone when no realization gave a height) and the score
//! `−ln q + ln (b − a)`. A model whose failures sit one course from the readings then
//! loses about `ln 2` per specimen, not the several nats a kernel of one twentieth of the
//! height would charge: a difference of definition between the reader and the model is
//! not evidence for a cause, a failure several courses away still is. The misreading component bounds the
//! score of a specimen failing where no realization did (at most `−ln ε`), so one odd
//! reading cannot sink a cause, and a floor keeps every joint possible (a kernel density
//! mixture with a defensive component: Hesterberg 1995, Technometrics 37:185). A kind or a start is a
//! category: of `R` realizations, `k` showed the observed one (which covers `m` of the `K`
//! simulated categories: `random` covers `end` and `centre`); its probability is smoothed
//! for the finite ensemble with the Jeffreys prior, `p = (k + m/2) / (R + K/2)`, and read
//! with a misreading probability `ε` (\[0.1\]: one reading in ten is another category,
//! uniformly), `q = (1 − ε) p + ε (1 − p) m / (K − 1)`. Its score is `−ln q` where the
//! category was seen, `−ln (1 − q)` where it was not (synthetic data sets).

use super::observations::{Family, Observable, Observation, Scale};
use super::simulate::Outcome;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// Mean and standard deviation of a model's simulated values of one observable (degrees
/// or cm), the number of realizations they came from, and the surrogate's error there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Simulated {
    /// Mean over the realizations.
    pub mean: f64,
    /// Sample standard deviation (0 for one realization).
    pub sd: f64,
    /// Realizations that gave a value.
    pub n: usize,
    /// Standard error of the surrogate at this point (0 at a simulated node).
    pub err: f64,
    /// The distribution of the realizations' failure heights (a failure-height key only;
    /// empty otherwise).
    #[serde(skip)]
    pub heights: Heights,
}

/// Bins of [`Heights`]: centres `i / (HEIGHT_BINS − 1)` of the wall's height, `i = 0 ..
/// HEIGHT_BINS`.
pub const HEIGHT_BINS: usize = 21;

/// The share of realizations whose failure height (a fraction of the wall's height) lies
/// in each of [`HEIGHT_BINS`] bins of width `1 / (HEIGHT_BINS − 1)` centred on `0, 0.05, …,
/// 1`; all zero when no realization gave one. Shares sum to 1 otherwise. Interpolated
/// between the surrogate's nodes as a mixture, which is a distribution again.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Heights(pub [f64; HEIGHT_BINS]);

impl Heights {
    /// No realization gave a failure height.
    pub const NONE: Heights = Heights([0.0; HEIGHT_BINS]);

    /// The shares of failure heights `v` (fractions; clamped to [0, 1]; non-finite ones
    /// skipped).
    pub fn of(v: &[f64]) -> Heights {
        let mut h = [0.0; HEIGHT_BINS];
        let last = (HEIGHT_BINS - 1) as f64;
        let n = v.iter().filter(|x| x.is_finite()).count();
        for x in v.iter().filter(|x| x.is_finite()) {
            let i = (x.clamp(0.0, 1.0) * last).round() as usize;
            h[i.min(HEIGHT_BINS - 1)] += 1.0 / n as f64;
        }
        Heights(h)
    }

    /// Whether no realization gave a height.
    pub fn is_empty(&self) -> bool {
        self.0.iter().all(|&m| m <= 0.0)
    }

    /// `self + t (other − self)`, a mixture.
    pub fn lerp(&self, other: &Heights, t: f64) -> Heights {
        if self.is_empty() {
            return *other;
        }
        if other.is_empty() {
            return *self;
        }
        Heights(std::array::from_fn(|i| self.0[i] + (other.0[i] - self.0[i]) * t))
    }

    /// `self + Σ (plus − minus)`, negative shares set to 0 and the rest renormalized (the
    /// additive surrogate of a pair, a surface re-centred on a full run); `self` where
    /// nothing is left, or where an operand is empty.
    pub fn shifted(&self, terms: &[(&Heights, &Heights)]) -> Heights {
        if self.is_empty() || terms.iter().any(|(p, m)| p.is_empty() || m.is_empty()) {
            return *self;
        }
        let mut h: [f64; HEIGHT_BINS] =
            std::array::from_fn(|i| (self.0[i] + terms.iter().map(|(p, m)| p.0[i] - m.0[i]).sum::<f64>()).max(0.0));
        let total: f64 = h.iter().sum();
        if !(total > 1e-12) {
            return *self;
        }
        for m in &mut h {
            *m /= total;
        }
        Heights(h)
    }

    /// The kernel mass of the shares in `[a, b]` (fractions, clipped to [0, 1]): each
    /// bin's Gaussian of standard deviation `sd` truncated to [0, 1] (module
    /// documentation); 0 when empty or when the clipped interval is empty.
    pub fn mass(&self, a: f64, b: f64, sd: f64) -> f64 {
        let (a, b) = (a.max(0.0), b.min(1.0));
        if self.is_empty() || !(b > a) {
            return 0.0;
        }
        let phi = |z: f64| 0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2);
        let sd = sd.max(1e-6);
        let last = (HEIGHT_BINS - 1) as f64;
        let mut p = 0.0;
        for (i, &m) in self.0.iter().enumerate() {
            if m <= 0.0 {
                continue;
            }
            let c = i as f64 / last;
            let whole = phi((1.0 - c) / sd) - phi(-c / sd);
            p += m * (phi((b - c) / sd) - phi((a - c) / sd)).max(0.0) / whole.max(1e-300);
        }
        p
    }

    /// The probability of a failure height read as the joint `y ± w/2` (fractions): the
    /// joint read is the failing joint with probability `1 − 2 d`, the joint one reading
    /// width `w` below or above it with probability `d` each (`d` =
    /// [`Reading::neighbour_joint`]; a neighbour off the wall gives its share to the joint
    /// read), each the kernel mass ([`Heights::mass`]) of its interval, all mixed with
    /// weight `e` ([`Reading::misreading`]) with the uniform over the clipped interval
    /// (module documentation); the uniform alone when empty.
    pub fn probability(&self, y: f64, w: f64, sd: f64, reading: &Reading) -> f64 {
        let (a, b) = ((y - 0.5 * w).max(0.0), (y + 0.5 * w).min(1.0));
        let width = (b - a).max(0.0);
        if self.is_empty() {
            return width;
        }
        let d = reading.neighbour_joint;
        let mut centre = 1.0 - 2.0 * d;
        let mut p = 0.0;
        for shift in [-w, w] {
            let (lo, hi) = ((y + shift - 0.5 * w).max(0.0), (y + shift + 0.5 * w).min(1.0));
            if d > 0.0 && hi > lo {
                p += d * self.mass(lo, hi, sd);
            } else {
                centre += d;
            }
        }
        p += centre * self.mass(a, b, sd);
        let e = reading.misreading;
        (1.0 - e) * p + e * width
    }
}

impl Simulated {
    /// From the outcomes of one group: every realization that gave a value (a collapse
    /// angle is the middle of its bracket; a displacement at a tilt only from realizations
    /// that stood there).
    pub fn of(outcomes: &[Outcome], obs: &Observable) -> Simulated {
        let v: Vec<f64> = outcomes.iter().filter_map(|o| o.value(obs)).filter(|x| x.is_finite()).collect();
        let mut s = Simulated::from_values(&v);
        if obs.place_width().is_some() {
            s.heights = Heights::of(&v);
        }
        s
    }

    /// From values.
    pub fn from_values(v: &[f64]) -> Simulated {
        if v.is_empty() {
            return Simulated { mean: f64::NAN, sd: 0.0, n: 0, err: 0.0, heights: Heights::NONE };
        }
        Simulated {
            mean: crate::stats::mean(v),
            sd: if v.len() > 1 { crate::stats::sd(v) } else { 0.0 },
            n: v.len(),
            err: 0.0,
            heights: Heights::NONE,
        }
    }
}

/// How readings were taken: their resolutions (the interval a rounded value stands for).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Reading {
    /// Collapse angles read to this, degrees \[0.5\] (the paper's Table 2).
    pub angle_deg: f64,
    /// Displacements read to this, cm \[0.1\] (the paper's Table 3).
    pub displacement_cm: f64,
    /// Probability that a mechanism's kind or start is read as another category, and that
    /// a failure height belongs to none of the simulated failures (uniform over the
    /// height) \[0.1\].
    pub misreading: f64,
    /// Share of a failure-height reading that belongs to each neighbouring bed joint, one
    /// reading interval below or above the joint read \[0.25\]: observers differ in which
    /// joint they call the bottom of the moving part (the lowest block that moved at all,
    /// or the lowest that moved with the rest), by about a course; half of a reading's
    /// mass stays on the joint read. 0: the joint read is the failing joint.
    pub neighbour_joint: f64,
    /// In-plane peak forces read to this, kN \[0.1\] (the Stone Masonry Database's digits,
    /// Vanin et al. 2017).
    pub force_kn: f64,
    /// In-plane drifts read to this, % \[0.01\] (the database's digits).
    pub drift_pct: f64,
    /// In-plane initial stiffnesses read to this, kN/mm \[0.1\] (the database's digits).
    pub stiffness_kn_per_mm: f64,
    /// In-plane walls' vertical moduli read to this, MPa \[1\] (the database's digits).
    pub modulus_mpa: f64,
    /// In-plane peaks' ± asymmetries read to this, kN \[0.1\] (the difference of two of the
    /// database's peak forces).
    pub asymmetry_kn: f64,
}

impl Default for Reading {
    fn default() -> Self {
        Reading {
            angle_deg: 0.5,
            displacement_cm: 0.1,
            misreading: 0.1,
            neighbour_joint: 0.25,
            force_kn: 0.1,
            drift_pct: 0.01,
            stiffness_kn_per_mm: 0.1,
            modulus_mpa: 1.0,
            asymmetry_kn: 0.1,
        }
    }
}

impl Reading {
    /// The resolution of an observable's readings.
    pub fn of(&self, o: &Observable) -> f64 {
        match o.scale() {
            Scale::Place { width } => width,
            Scale::Measure(family) => self.of_family(family),
            Scale::Category { .. } => 0.0,
        }
    }

    /// The resolution of a family of measures ([`Observable::family`]).
    pub fn of_family(&self, family: Family) -> f64 {
        match family {
            Family::CollapseAngle => self.angle_deg,
            Family::Displacement => self.displacement_cm,
            Family::PeakForce => self.force_kn,
            Family::DriftAtPeak => self.drift_pct,
            Family::InitialStiffness => self.stiffness_kn_per_mm,
            Family::VerticalModulus => self.modulus_mpa,
            Family::PeakAsymmetry => self.asymmetry_kn,
        }
    }

    /// `v` rounded to the resolution of `o` (a failure height also kept in [0, 1]; a
    /// category's indicator, or a reading of resolution 0, as it is).
    pub fn round(&self, o: &Observable, v: f64) -> f64 {
        match o.scale() {
            Scale::Category { .. } => v,
            Scale::Place { width } => {
                let r = if width > 0.0 { (v / width).round() * width } else { v };
                r.clamp(0.0, 1.0)
            }
            Scale::Measure(family) => {
                let r = self.of_family(family);
                if r > 0.0 {
                    (v / r).round() * r
                } else {
                    v
                }
            }
        }
    }

    /// A failure height `v` (fraction) as a reader of interval width `w` names it, for a
    /// uniform draw `u` in [0, 1): one joint below with probability
    /// [`Reading::neighbour_joint`], one above with the same, else `v` (the draws of the
    /// likelihood's reading model; module documentation). `v` itself when `w` is 0.
    pub fn neighbour_read(&self, v: f64, w: f64, u: f64) -> f64 {
        let d = self.neighbour_joint;
        if !(w > 0.0) {
            v
        } else if u < d {
            v - w
        } else if u < 2.0 * d {
            v + w
        } else {
            v
        }
    }

    /// The probability that a reading of category `o` (covering `m` of `K` simulated
    /// categories, [`Observable::category`]) says "seen", from the share `sim.mean` of
    /// `sim.n` realizations that showed it: Jeffreys-smoothed and misread at
    /// [`Reading::misreading`] (module documentation). `None` for a number.
    pub fn category_probability(&self, o: &Observable, sim: &Simulated) -> Option<f64> {
        let (m, k) = o.category()?;
        let (m, k) = (m as f64, k as f64);
        let n = sim.n as f64;
        let share = if sim.n > 0 && sim.mean.is_finite() { sim.mean.clamp(0.0, 1.0) } else { 0.0 };
        let p = (n * share + 0.5 * m) / (n + 0.5 * k);
        let e = self.misreading;
        Some(((1.0 - e) * p + e * (1.0 - p) * m / (k - 1.0)).clamp(1e-12, 1.0 - 1e-12))
    }
}

/// A Student-t predictive distribution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Predictive {
    /// Location.
    pub mean: f64,
    /// Scale (model spread, measurement, surrogate and bracket errors).
    pub sd: f64,
    /// Degrees of freedom (infinite: Gaussian).
    pub dof: f64,
}

/// Degrees of freedom above which the predictive is taken as Gaussian.
const GAUSSIAN_DOF: f64 = 1e4;

impl Predictive {
    /// The predictive distribution of `obs` from the simulated values; `bracket` is the
    /// width of a simulated collapse angle's bracket (degrees; 0 for displacements).
    pub fn new(sim: &Simulated, obs: &Observation, bracket: f64) -> Predictive {
        let r = sim.n.max(1) as f64;
        let b2 = if obs.observable.is_angle() { bracket * bracket / 12.0 } else { 0.0 };
        let model = sim.sd * sim.sd * (1.0 + 1.0 / r);
        let var = model + b2 + obs.sigma * obs.sigma + sim.err * sim.err;
        let dof = if sim.n >= 2 && model > 0.0 {
            (var * var * (r - 1.0) / (model * model)).min(GAUSSIAN_DOF)
        } else {
            GAUSSIAN_DOF
        };
        Predictive { mean: sim.mean, sd: var.sqrt(), dof }
    }

    /// The standardized predictive's CDF.
    fn cdf(&self, z: f64) -> f64 {
        if self.dof >= GAUSSIAN_DOF {
            0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2)
        } else {
            StudentsT::new(0.0, 1.0, self.dof.max(1.0)).map_or(f64::NAN, |t| t.cdf(z))
        }
    }

    /// Negative log predictive density of `y`.
    pub fn nlpd(&self, y: f64) -> f64 {
        if !self.mean.is_finite() || !(self.sd > 0.0) {
            return NLPD_MISSING;
        }
        let z = (y - self.mean) / self.sd;
        let nu = self.dof.max(1.0);
        let ln_pdf = if nu >= GAUSSIAN_DOF {
            -0.5 * z * z - 0.5 * (2.0 * std::f64::consts::PI).ln()
        } else {
            statrs::function::gamma::ln_gamma(0.5 * (nu + 1.0))
                - statrs::function::gamma::ln_gamma(0.5 * nu)
                - 0.5 * (nu * std::f64::consts::PI).ln()
                - 0.5 * (nu + 1.0) * (1.0 + z * z / nu).ln()
        };
        (self.sd.ln() - ln_pdf).min(NLPD_MISSING)
    }

    /// Negative log probability of a reading `y` of resolution `r` (the interval
    /// `[y − r/2, y + r/2]`), plus `ln r`; the density score where the interval's
    /// probability underflows or `r` is 0.
    pub fn score(&self, y: f64, r: f64) -> f64 {
        if !self.mean.is_finite() || !(self.sd > 0.0) {
            return NLPD_MISSING;
        }
        if r > 0.0 {
            let (a, b) = ((y - 0.5 * r - self.mean) / self.sd, (y + 0.5 * r - self.mean) / self.sd);
            // Upper tail by symmetry, for precision.
            let p = if a > 0.0 { self.cdf(-a) - self.cdf(-b) } else { self.cdf(b) - self.cdf(a) };
            if p > 1e-12 {
                return (-p.ln() + r.ln()).min(NLPD_MISSING);
            }
        }
        self.nlpd(y)
    }

    /// The predictive of a category's indicator read "seen" with probability `q`: mean `q`,
    /// standard deviation `√(q (1 − q))` (for residuals; the score is
    /// `category_score`).
    pub fn category(q: f64) -> Predictive {
        Predictive { mean: q, sd: (q * (1.0 - q)).sqrt().max(1e-9), dof: GAUSSIAN_DOF }
    }

    /// Standardized residual `(y − mean) / sd`.
    pub fn z(&self, y: f64) -> f64 {
        (y - self.mean) / self.sd
    }
}

/// The score of a category's indicator `y` (1: seen) read "seen" with probability `q`:
/// `−ln q` or `−ln (1 − q)`.
pub fn category_score(q: f64, y: f64) -> f64 {
    (if y >= 0.5 { -q.ln() } else { -(1.0 - q).ln() }).min(NLPD_MISSING)
}

/// The score of a failure height read as `y ± w/2` (fractions of the wall's height)
/// against the realizations' distribution `sim.heights`: kernel σ `sqrt(sigma² + err²)`,
/// the reading's neighbouring joints and misreading as `reading` has them
/// ([`Heights::probability`]); `−ln q + ln w` (module documentation). `w` of 0 is read as
/// 0.01, with no neighbouring joints.
pub fn height_score(sim: &Simulated, y: f64, w: f64, sigma: f64, reading: &Reading) -> f64 {
    let (w, reading) = if w > 0.0 { (w, *reading) } else { (0.01, Reading { neighbour_joint: 0.0, ..*reading }) };
    let (a, b) = ((y - 0.5 * w).max(0.0), (y + 0.5 * w).min(1.0));
    let sd = (sigma * sigma + sim.err * sim.err).sqrt();
    let q = sim.heights.probability(y, w, sd, &reading);
    if !(q > 0.0) || !(b > a) {
        return NLPD_MISSING;
    }
    (-q.ln() + (b - a).ln()).min(NLPD_MISSING)
}

/// The score of an observation the model cannot predict (every realization failed, or
/// none stood to its tilt).
pub const NLPD_MISSING: f64 = 50.0;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::Observation;

    fn obs(sigma: f64) -> Observation {
        Observation {
            specimen: "s".into(),
            group: "g".into(),
            observable: Observable::CollapseAngle,
            value: 0.0,
            sigma,
        }
    }

    /// The smoothed, misread category probability against its closed form: 3 of 9
    /// realizations toppled (K = 4 kinds), ε = 0.1: p = (3 + ½)/(9 + 2) = 7/22, q = 0.9 p +
    /// 0.1 (1 − p)/3; none of 9 uniform starts for `random` (m = 2 of K = 3): p = 1/10.5.
    #[test]
    fn a_category_is_smoothed_for_few_realizations_and_misread() {
        use crate::loading::mechanism::{FailureKind, FailureStart};
        let r = Reading::default();
        let sim = Simulated { mean: 3.0 / 9.0, sd: 0.0, n: 9, err: 0.0, heights: Heights::NONE };
        let q = r.category_probability(&Observable::MechanismKind { kind: FailureKind::Toppling }, &sim).unwrap();
        let p = 7.0 / 22.0;
        assert!((q - (0.9 * p + 0.1 * (1.0 - p) / 3.0)).abs() < 1e-15, "{q}");
        let none = Simulated { mean: 0.0, sd: 0.0, n: 9, err: 0.0, heights: Heights::NONE };
        let q = r.category_probability(&Observable::MechanismStart { start: FailureStart::Random }, &none).unwrap();
        let p = 1.0 / 10.5;
        assert!((q - (0.9 * p + 0.1 * (1.0 - p))).abs() < 1e-15, "{q}");
        assert!(
            (category_score(q, 1.0) + q.ln()).abs() < 1e-15 && (category_score(q, 0.0) + (1.0 - q).ln()).abs() < 1e-15
        );
        assert_eq!(r.category_probability(&Observable::CollapseAngle, &sim), None);
    }

    /// A failure height against realizations that failed at the table joint (8) and at
    /// the joint at 0.75 of the height (2): the reading interval's probability is the
    /// closed form of the truncated kernel mixture plus the uniform misreading; a reading
    /// where no realization failed costs at most `−ln ε` more than a certain one, and
    /// the bimodal predictive gives the upper joint a probability a unimodal one centred
    /// on the mean (0.15) would not.
    #[test]
    fn a_failure_height_is_a_smoothed_distribution_over_joints_with_a_misreading_floor() {
        use statrs::distribution::{ContinuousCDF, Normal};
        let v = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.75, 0.75];
        let h = Heights::of(&v);
        assert!((h.0[0] - 0.8).abs() < 1e-15 && (h.0[15] - 0.2).abs() < 1e-15);
        let sim = Simulated { heights: h, ..Simulated::from_values(&v) };
        let (sd, e, w) = (0.05, 0.1, 0.125);
        let r = Reading { misreading: e, neighbour_joint: 0.0, ..Reading::default() };
        let n = Normal::new(0.0, 1.0).unwrap();
        let k = |a: f64, b: f64, c: f64| {
            (n.cdf((b - c) / sd) - n.cdf((a - c) / sd)) / (n.cdf((1.0 - c) / sd) - n.cdf(-c / sd))
        };
        // Reading at the upper joint: [0.6875, 0.8125].
        let (a, b) = (0.75 - w / 2.0, 0.75 + w / 2.0);
        let q = 0.9 * (0.8 * k(a, b, 0.0) + 0.2 * k(a, b, 0.75)) + e * w;
        let got = height_score(&sim, 0.75, w, sd, &r);
        assert!((got - (-q.ln() + w.ln())).abs() < 1e-12, "{got}");
        // Reading at the table joint: [0, 0.0625] (clipped).
        let q0 = 0.9 * (0.8 * k(0.0, 0.0625, 0.0) + 0.2 * k(0.0, 0.0625, 0.75)) + e * 0.0625;
        assert!((height_score(&sim, 0.0, w, sd, &r) - (-q0.ln() + 0.0625f64.ln())).abs() < 1e-12);
        // Nowhere near a simulated failure: bounded by the misreading floor.
        let odd = height_score(&sim, 0.4, w, sd, &r);
        assert!(odd <= -(e * w).ln() + w.ln() + 1e-9 && odd > got, "{odd}");
        // The Student-t about the mean (0.15, sd 0.32) spreads its mass: the upper joint
        // scores better under the joint distribution than under it.
        let t = Predictive::new(
            &sim,
            &Observation { observable: Observable::FailureHeight { width: w }, sigma: sd, ..obs(sd) },
            0.0,
        );
        assert!(got < t.score(0.75, w), "{got} vs {}", t.score(0.75, w));
        // No realization failed with a mechanism: the uniform, score 0.
        let none = Simulated::from_values(&[]);
        assert!(height_score(&none, 0.5, w, sd, &r).abs() < 1e-12);
        // Mixtures: interpolation keeps a distribution; a shift renormalizes.
        let m = h.lerp(&Heights::of(&[0.5]), 0.25);
        assert!((m.0.iter().sum::<f64>() - 1.0).abs() < 1e-12 && (m.0[10] - 0.25).abs() < 1e-15);
        let s = Heights::of(&[0.0]).shifted(&[(&Heights::of(&[0.75]), &Heights::of(&[0.0]))]);
        assert_eq!(s, Heights::of(&[0.75]));
    }

    /// The reading's neighbouring joints: against realizations that all failed at the
    /// joint 0.5 of the height, a reading of that joint and a reading one interval (a
    /// course) above it, with half the mass on the joint read and a quarter on each
    /// neighbour, match the closed form of the three shifted kernels; the reading a course
    /// off costs `ln((1 − 2d) K₀ + d K₁) − ln(d K₀ + …)`, about `ln 2` for a narrow kernel,
    /// where without the neighbours it costs several nats; a neighbour off the wall gives
    /// its share to the joint read.
    #[test]
    fn a_failure_height_read_a_course_off_costs_what_the_neighbouring_joint_is_worth() {
        use statrs::distribution::{ContinuousCDF, Normal};
        let v = [0.5; 10];
        let sim = Simulated { heights: Heights::of(&v), ..Simulated::from_values(&v) };
        let (sd, w) = (0.05, 0.25);
        let n = Normal::new(0.0, 1.0).unwrap();
        let k = |a: f64, b: f64| {
            let (a, b) = (a.max(0.0), b.min(1.0));
            (n.cdf((b - 0.5) / sd) - n.cdf((a - 0.5) / sd)) / (n.cdf(0.5 / sd) - n.cdf(-0.5 / sd))
        };
        let r = Reading::default();
        let (e, d) = (r.misreading, r.neighbour_joint);
        let q = |y: f64| {
            let c = (1.0 - 2.0 * d) * k(y - w / 2.0, y + w / 2.0);
            let nb = d * k(y - 1.5 * w, y - 0.5 * w) + d * k(y + 0.5 * w, y + 1.5 * w);
            (1.0 - e) * (c + nb) + e * w
        };
        let at = height_score(&sim, 0.5, w, sd, &r);
        let off = height_score(&sim, 0.75, w, sd, &r);
        assert!((at - (-q(0.5).ln() + w.ln())).abs() < 1e-12, "{at}");
        assert!((off - (-q(0.75).ln() + w.ln())).abs() < 1e-12, "{off}");
        let cost = off - at;
        assert!(cost > 0.5 && cost < 0.8, "a course off costs {cost}");
        let strict = Reading { neighbour_joint: 0.0, ..r };
        let cost0 = height_score(&sim, 0.75, w, sd, &strict) - height_score(&sim, 0.5, w, sd, &strict);
        assert!(cost0 > 2.0, "without the neighbours a course off costs {cost0}");
        // Two courses off: the misreading floor `−ln ε`, with or without the neighbours.
        let (far, far0) = (height_score(&sim, 1.0, w, sd, &r), height_score(&sim, 1.0, w, sd, &strict));
        assert!((far - far0).abs() < 0.15 && far <= far0, "{far} {far0}");
        // At the table joint the neighbour below is off the wall: its share stays on the
        // joint read, so the probabilities of the readings 0, 0.25, ... still sum to 1.
        let total: f64 = [0.0, 0.25, 0.5, 0.75, 1.0]
            .iter()
            .map(|&y| {
                let (a, b) = ((y - w / 2.0f64).max(0.0), (y + w / 2.0f64).min(1.0));
                (-(height_score(&sim, y, w, sd, &r) - (b - a).ln())).exp()
            })
            .sum();
        assert!((total - 1.0).abs() < 1e-9, "{total}");
        // The reader's draws: below, above, or the joint, in the shares of the model.
        assert_eq!((r.neighbour_read(0.5, w, 0.1), r.neighbour_read(0.5, w, 0.3)), (0.25, 0.75));
        assert_eq!((r.neighbour_read(0.5, w, 0.6), r.neighbour_read(0.5, 0.0, 0.1)), (0.5, 0.5));
    }

    #[test]
    fn gaussian_limit_matches_the_normal_density() {
        let p = Predictive { mean: 1.0, sd: 2.0, dof: f64::INFINITY };
        let z: f64 = 0.75;
        let want = 0.5 * z * z + 2f64.ln() + 0.5 * (2.0 * std::f64::consts::PI).ln();
        assert!((p.nlpd(2.5) - want).abs() < 1e-12);
    }

    #[test]
    fn few_realizations_give_heavy_tails() {
        let sim = Simulated { mean: 10.0, sd: 1.0, n: 3, err: 0.0, heights: Heights::NONE };
        let p = Predictive::new(&sim, &obs(1e-3), 0.0);
        assert!(p.dof < 3.0, "{p:?}");
        let g = Predictive { dof: f64::INFINITY, ..p };
        // Far out the t density is much larger than the Gaussian one.
        assert!(p.nlpd(16.0) < g.nlpd(16.0) - 5.0);
    }

    #[test]
    fn interval_score_tends_to_the_density_score() {
        let p = Predictive { mean: 0.0, sd: 1.0, dof: 5.0 };
        assert!((p.score(0.3, 1e-4) - p.nlpd(0.3)).abs() < 1e-6);
        // A coarse reading is more probable than its density times its width suggests only
        // through curvature: still close for r << sd.
        assert!((p.score(0.3, 0.1) - p.nlpd(0.3)).abs() < 1e-2);
    }
}
