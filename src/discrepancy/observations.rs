//! Observations: the measured data as one long table (specimen, group, observable, tilt,
//! value, measurement σ).
//!
//! The study's `[measured]` files are the input: collapse angles (the paper's Table 2,
//! degrees) and top displacements at given tilts (Table 3, cm). Measurement σ defaults
//! come from the paper: the tilt was read to 0.5° and the displacement instrument had a
//! precision of 5 mm (Santa-Cruz et al. 2021, Section 2); both are taken as one standard
//! deviation. A study may override them (`[discrepancy]`).
//!
//! Observed failure mechanisms (`[measured] mechanism`) give up to three observations per
//! specimen: the failure height (a fraction of the wall's height, read as an interval:
//! the observable carries its width), and the kind and the start as categories, each an
//! indicator (value 1: the specimen showed it; 0 only in synthetic data sets) scored with
//! a misreading probability ([`super::predictive`]). The extent is not scored.

use super::inplane::{InPlaneQuantity, IN_PLANE_MODES};
use crate::loading::inplane::MechanismKind as InPlaneMode;
use crate::loading::mechanism::{FailureKind, FailureStart};
use crate::protocol::{Observed, Output};
use serde::Serialize;
use std::fmt;

pub use crate::ensemble::row::Measure;

/// What is observed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Observable {
    /// The collapse angle α_max, degrees.
    CollapseAngle,
    /// A top displacement measure at a tilt, cm.
    Displacement {
        /// The measure.
        measure: Measure,
        /// The tilt, degrees.
        tilt_deg: f64,
    },
    /// The failure height: the bed joint at the bottom of the moving part over the wall's
    /// height, a fraction in [0, 1], read as an interval of width `width` about the value.
    FailureHeight {
        /// Width of the reading interval (fraction of the height; not part of the key).
        width: f64,
    },
    /// Whether the failure was of this kind (value 1 or 0).
    MechanismKind {
        /// The kind.
        #[serde(rename = "failure_kind")]
        kind: FailureKind,
    },
    /// Whether the failure started here (value 1 or 0; `random`: end or centre).
    MechanismStart {
        /// The start.
        start: FailureStart,
    },
    /// A measure of the in-plane shear–compression test (peak force kN, drift at the peak
    /// %, initial stiffness kN/mm), of the first direction loaded.
    InPlane {
        /// The measure.
        quantity: InPlaneQuantity,
    },
    /// Whether the in-plane mechanism was of this mode (value 1 or 0): rocking, sliding,
    /// diagonal or mixed (`loading::inplane::read_mechanism`; the database's failure type 1
    /// is rocking, 0 sliding or diagonal, 0.5 mixed).
    InPlaneMode {
        /// The mode.
        mode: InPlaneMode,
    },
}

impl InPlaneQuantity {
    /// Its family of measures.
    pub fn family(self) -> Family {
        match self {
            InPlaneQuantity::PeakForce => Family::PeakForce,
            InPlaneQuantity::DriftAtPeak => Family::DriftAtPeak,
            InPlaneQuantity::InitialStiffness => Family::InitialStiffness,
            InPlaneQuantity::VerticalModulus => Family::VerticalModulus,
            InPlaneQuantity::PeakAsymmetry => Family::PeakAsymmetry,
        }
    }
}

/// A family of measures: the observables whose measurement σ and spread the analysis
/// estimates together, each read to its resolution ([`super::predictive::Reading::of_family`])
/// with its stated σ ([`MeasurementSigma::of_family`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Collapse angles, degrees.
    CollapseAngle,
    /// Top displacements, cm.
    Displacement,
    /// In-plane peak forces, kN.
    PeakForce,
    /// In-plane drifts at the peak, %.
    DriftAtPeak,
    /// In-plane initial stiffnesses, kN/mm.
    InitialStiffness,
    /// The in-plane walls' vertical moduli, MPa.
    VerticalModulus,
    /// The in-plane peaks' ± asymmetries, kN.
    PeakAsymmetry,
}

impl Family {
    /// Every family, in the order of its index (the arrays of per-family estimates).
    pub const ALL: [Family; 7] = [
        Family::CollapseAngle,
        Family::Displacement,
        Family::PeakForce,
        Family::DriftAtPeak,
        Family::InitialStiffness,
        Family::VerticalModulus,
        Family::PeakAsymmetry,
    ];

    /// Its index in [`Family::ALL`] (0 collapse angles, 1 displacements, 2 in-plane peak
    /// forces, 3 drifts, 4 stiffnesses, 5 vertical moduli, 6 peak asymmetries).
    pub fn index(self) -> usize {
        match self {
            Family::CollapseAngle => 0,
            Family::Displacement => 1,
            Family::PeakForce => 2,
            Family::DriftAtPeak => 3,
            Family::InitialStiffness => 4,
            Family::VerticalModulus => 5,
            Family::PeakAsymmetry => 6,
        }
    }

    /// Whether the null data draw its spread's factor whether or not the design holds it
    /// (the tilting table's families: their draws come first in the stream), or only when
    /// it does (the in-plane test's).
    pub fn always_drawn(self) -> bool {
        match self {
            Family::CollapseAngle | Family::Displacement => true,
            Family::PeakForce
            | Family::DriftAtPeak
            | Family::InitialStiffness
            | Family::VerticalModulus
            | Family::PeakAsymmetry => false,
        }
    }
}

/// The families of measures ([`Family`]): collapse angles, displacements and the in-plane
/// test's peak forces, drifts and stiffnesses.
pub const MEASURE_FAMILIES: usize = Family::ALL.len();

/// A set of categories of which a specimen shows one (its indicators read together).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CategorySet {
    /// The failure's kind ([`FailureKind`]).
    FailureKind,
    /// Where the failure started ([`FailureStart`]).
    FailureStart,
    /// The in-plane mechanism's mode ([`IN_PLANE_MODES`]).
    InPlaneMode,
}

impl CategorySet {
    /// Every set, in the order a specimen's categories are drawn.
    pub const ALL: [CategorySet; 3] = [CategorySet::FailureKind, CategorySet::FailureStart, CategorySet::InPlaneMode];

    /// Its index in [`CategorySet::ALL`].
    pub fn index(self) -> usize {
        match self {
            CategorySet::FailureKind => 0,
            CategorySet::FailureStart => 1,
            CategorySet::InPlaneMode => 2,
        }
    }

    /// Whether the absolute checks of fit read it (`fit::Data::fit_checked`): not the
    /// tilting table's kind and start, which a person names by a rule of their own; the
    /// in-plane mode, the database's failure type, is read.
    pub fn fit_checked(self) -> bool {
        match self {
            CategorySet::FailureKind | CategorySet::FailureStart => false,
            CategorySet::InPlaneMode => true,
        }
    }
}

/// How an observable is read and scored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    /// A measure of a family: an instrument's reading of stated σ, rounded to the family's
    /// resolution; it pins a model's parameters.
    Measure(Family),
    /// A place on the wall (the failure height, a fraction of the height) read as an
    /// interval of width `width` about the value, a neighbouring joint possibly named.
    Place {
        /// The interval's width.
        width: f64,
    },
    /// A category of a set (value 1: seen), covering `covers` of the set's `of` simulated
    /// categories.
    Category {
        /// The set.
        set: CategorySet,
        /// The simulated categories the observed one covers.
        covers: usize,
        /// The simulated categories of the set.
        of: usize,
    },
}

/// Which of a specimen's observations count as one between them in the comparison of
/// models ([`super::compare::specimen_weights`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Share {
    /// An observation alone (weight 1): a collapse angle, an in-plane measure.
    Own,
    /// One of the specimen's displacements, one curve between them (weight 1/k); their
    /// null draws share one deviate.
    Displacements,
    /// One reading of the specimen's mechanism (failure height, kind, start, mode: one
    /// mechanism seen, read several ways; weight 1/k).
    Mechanism,
}

impl Observable {
    /// Its value in a run's observables (degrees, cm, a fraction, kN, % or kN/mm; 1 or 0
    /// for a category): the collapse angle as the middle of its bracket (last stable, first
    /// unstable: the unbiased point value of an angle known to lie in the bracket); `None`
    /// for a displacement at a tilt the realization did not stand to (the chance of
    /// standing is carried by the collapse angle), for a mechanism of a wall that stood and
    /// for a measure the protocol did not give.
    pub fn of(&self, observed: &Observed) -> Option<f64> {
        match *self {
            Observable::CollapseAngle => {
                let a = observed.collapse_deg?;
                Some(observed.first_unstable_deg.map_or(a, |b| 0.5 * (a + b)))
            }
            Observable::Displacement { measure, tilt_deg } => {
                let i = observed.tilt_deg.iter().position(|t| (t - tilt_deg).abs() < 1e-9)?;
                let [l, c, r] = observed.top_cm[i];
                Some(measure.of(l, c, r))
            }
            Observable::FailureHeight { .. } => observed.mechanism.map(|m| m.failure_height_fraction),
            Observable::MechanismKind { kind } => observed.mechanism.map(|m| f64::from(u8::from(m.kind == kind))),
            Observable::MechanismStart { start } => {
                observed.mechanism.map(|m| f64::from(u8::from(start.matches(m.start))))
            }
            Observable::InPlane { quantity } => quantity.of(observed.in_plane.as_ref()?),
            Observable::InPlaneMode { mode } => super::inplane::mode_value(mode, observed.in_plane.as_ref()?),
        }
    }
}

impl Observable {
    /// How it is read and scored: the one mapping of the observables to their family of
    /// measures, reading interval or category, from which [`Observable::pins`],
    /// [`Observable::family`], [`Observable::category`] and the like follow.
    pub fn scale(&self) -> Scale {
        match *self {
            Observable::CollapseAngle => Scale::Measure(Family::CollapseAngle),
            Observable::Displacement { .. } => Scale::Measure(Family::Displacement),
            Observable::InPlane { quantity } => Scale::Measure(quantity.family()),
            Observable::FailureHeight { width } => Scale::Place { width },
            Observable::MechanismKind { .. } => {
                Scale::Category { set: CategorySet::FailureKind, covers: 1, of: FailureKind::ALL.len() }
            }
            Observable::MechanismStart { start } => Scale::Category {
                set: CategorySet::FailureStart,
                covers: start.covers(),
                of: FailureStart::SIMULATED.len(),
            },
            Observable::InPlaneMode { .. } => {
                Scale::Category { set: CategorySet::InPlaneMode, covers: 1, of: IN_PLANE_MODES.len() }
            }
        }
    }

    /// The protocol's output it is read from: a protocol lists the outputs it gives
    /// ([`crate::protocol::Observables::outputs`]), and an observation of another is
    /// refused.
    pub fn output(&self) -> Output {
        match self {
            Observable::CollapseAngle => Output::CollapseAngle,
            Observable::Displacement { .. } => Output::Displacements,
            Observable::FailureHeight { .. } | Observable::MechanismKind { .. } | Observable::MechanismStart { .. } => {
                Output::Mechanism
            }
            Observable::InPlane { .. } => Output::CurveMeasures,
            Observable::InPlaneMode { .. } => Output::MechanismMode,
        }
    }

    /// Whether it is a measure that pins a model's parameters (a collapse angle, a top
    /// displacement, an in-plane measure, read by an instrument of stated σ), not a
    /// reading of the failure mechanism (height, kind, start, mode; see `fit::Data::pins`).
    pub fn pins(&self) -> bool {
        match self.scale() {
            Scale::Measure(_) => true,
            Scale::Place { .. } | Scale::Category { .. } => false,
        }
    }

    /// Short label: `alpha_max`, `disp@5`.
    pub fn label(&self) -> String {
        match self {
            Observable::CollapseAngle => "alpha_max".into(),
            Observable::Displacement { tilt_deg, .. } => format!("disp@{tilt_deg}"),
            Observable::FailureHeight { .. } => "failure_height".into(),
            Observable::MechanismKind { kind } => format!("kind={}", kind.name()),
            Observable::MechanismStart { start } => format!("start={}", start.name()),
            Observable::InPlane { quantity } => quantity.name().into(),
            Observable::InPlaneMode { mode } => format!("mode={}", mode.name()),
        }
    }

    /// Its family of measures ([`Family`]); `None` for a reading of the mechanism.
    pub fn family(&self) -> Option<Family> {
        match self.scale() {
            Scale::Measure(family) => Some(family),
            Scale::Place { .. } | Scale::Category { .. } => None,
        }
    }

    /// Whether it is the collapse angle: a measure of degrees whose simulated value is the
    /// middle of a bracket, scattered by an added σ.
    pub fn is_angle(&self) -> bool {
        self.family() == Some(Family::CollapseAngle)
    }

    /// An observation of the failure mechanism (failure height, kind or start; the
    /// in-plane mode).
    pub fn is_mechanism(&self) -> bool {
        !self.pins()
    }

    /// A category (kind, start, mode): `(m, K)`, the simulated categories the observed one
    /// covers and the simulated categories in all; `None` for a number.
    pub fn category(&self) -> Option<(usize, usize)> {
        match self.scale() {
            Scale::Category { covers, of, .. } => Some((covers, of)),
            Scale::Measure(_) | Scale::Place { .. } => None,
        }
    }

    /// The set of categories it is one of; `None` for a number.
    pub fn category_set(&self) -> Option<CategorySet> {
        match self.scale() {
            Scale::Category { set, .. } => Some(set),
            Scale::Measure(_) | Scale::Place { .. } => None,
        }
    }

    /// The width of the interval a place on the wall is read as (the failure height);
    /// `None` for a measure or a category.
    pub fn place_width(&self) -> Option<f64> {
        match self.scale() {
            Scale::Place { width } => Some(width),
            Scale::Measure(_) | Scale::Category { .. } => None,
        }
    }

    /// Which of a specimen's observations it counts as one with ([`Share`]).
    pub fn share(&self) -> Share {
        match self.scale() {
            Scale::Measure(Family::Displacement) => Share::Displacements,
            Scale::Measure(
                Family::CollapseAngle
                | Family::PeakForce
                | Family::DriftAtPeak
                | Family::InitialStiffness
                | Family::VerticalModulus
                | Family::PeakAsymmetry,
            ) => Share::Own,
            Scale::Place { .. } | Scale::Category { .. } => Share::Mechanism,
        }
    }

    /// Whether the absolute checks of fit read it (`fit::Data::fit_checked`): every
    /// number, and the categories whose set is checked ([`CategorySet::fit_checked`]).
    pub fn fit_checked(&self) -> bool {
        match self.scale() {
            Scale::Measure(_) | Scale::Place { .. } => true,
            Scale::Category { set, .. } => set.fit_checked(),
        }
    }

    /// The measure and the tilt of a top displacement; `None` for another observable.
    pub fn displacement(&self) -> Option<(Measure, f64)> {
        match *self {
            Observable::Displacement { measure, tilt_deg } => Some((measure, tilt_deg)),
            Observable::CollapseAngle
            | Observable::FailureHeight { .. }
            | Observable::MechanismKind { .. }
            | Observable::MechanismStart { .. }
            | Observable::InPlane { .. }
            | Observable::InPlaneMode { .. } => None,
        }
    }

    /// The tilt a displacement is read at, degrees; `None` for another observable.
    pub fn tilt_deg(&self) -> Option<f64> {
        self.displacement().map(|(_, t)| t)
    }

    /// Unit of its values.
    pub fn unit(&self) -> &'static str {
        match self {
            Observable::CollapseAngle => "deg",
            Observable::Displacement { .. } => "cm",
            Observable::FailureHeight { .. } => "H",
            Observable::InPlane { quantity } => quantity.unit(),
            Observable::MechanismKind { .. } | Observable::MechanismStart { .. } | Observable::InPlaneMode { .. } => {
                "-"
            }
        }
    }

    /// The same observable (same kind, measure and tilt).
    pub fn same(&self, other: &Observable) -> bool {
        match *self {
            Observable::CollapseAngle => matches!(other, Observable::CollapseAngle),
            Observable::Displacement { measure: a, tilt_deg: t } => {
                other.displacement().is_some_and(|(b, u)| a == b && (t - u).abs() < 1e-9)
            }
            Observable::FailureHeight { .. } => matches!(other, Observable::FailureHeight { .. }),
            Observable::MechanismKind { kind: a } => matches!(*other, Observable::MechanismKind { kind: b } if a == b),
            Observable::MechanismStart { start: a } => {
                matches!(*other, Observable::MechanismStart { start: b } if a == b)
            }
            Observable::InPlane { quantity: a } => matches!(*other, Observable::InPlane { quantity: b } if a == b),
            Observable::InPlaneMode { mode: a } => matches!(*other, Observable::InPlaneMode { mode: b } if a == b),
        }
    }
}

impl fmt::Display for Observable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label())
    }
}

/// One measured value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Observation {
    /// Specimen, e.g. `SBL2`.
    pub specimen: String,
    /// Group of the study it belongs to, e.g. `SBL`.
    pub group: String,
    /// What was measured.
    pub observable: Observable,
    /// The value, in the observable's unit (degrees or cm).
    pub value: f64,
    /// Measurement standard deviation, same unit.
    pub sigma: f64,
}

/// Measurement standard deviations.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MeasurementSigma {
    /// Collapse angle, degrees \[0.5\] (angles read to 0.5°).
    pub angle_deg: f64,
    /// Displacement, cm \[0.5\] (instrument precision 5 mm).
    pub displacement_cm: f64,
    /// Failure height, fraction of the wall's height \[0.05\]: where the moving part of a
    /// specimen starts differs from where a realization's does by about half a course of
    /// the paper's walls (9 courses) beyond the reading interval; also the smoothing width
    /// of the realizations' few values.
    pub failure_height: f64,
    /// In-plane peak force, kN \[0.5\]: estimate (reasoning: a load cell of the 100-200 kN
    /// class read to about 1 % of the walls' 16-96 kN peaks; the papers give no precision).
    pub force_kn: f64,
    /// In-plane drift, % \[0.05\]: estimate (reasoning: the top displacement of a 1.2 m wall
    /// read to about 0.6 mm by its transducers and the digitized curves).
    pub drift_pct: f64,
    /// In-plane initial stiffness, kN/mm \[2\]: estimate (reasoning: the secant at 15 % of the
    /// peak divides 2-14 kN by 0.1-0.6 mm of displacement, so a 0.02 mm reading error is
    /// 3-20 % of the 9-36 kN/mm the walls show).
    pub stiffness_kn_per_mm: f64,
    /// The in-plane wall's vertical modulus, MPa \[400\]: estimate (reasoning: the modulus
    /// of a 1.2 m wall read from its shortening under 0.5-1.25 MPa, some 0.1-0.5 mm, by
    /// transducers of about 0.01 mm and over compression cycles whose loading branches
    /// differ; the database gives one value per stress level of the granite walls, 3.3-4.7
    /// GPa, so about 10 % of it; the papers give no precision).
    pub modulus_mpa: f64,
    /// The in-plane peak's ± asymmetry, kN \[0.7\]: estimate (reasoning: the difference of
    /// two peak readings of one specimen, each of σ `force_kn` = 0.5 kN, so √2 × 0.5).
    pub asymmetry_kn: f64,
}

impl MeasurementSigma {
    /// The stated σ of a family of measures.
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
}

impl Default for MeasurementSigma {
    fn default() -> Self {
        MeasurementSigma {
            angle_deg: 0.5,
            displacement_cm: 0.5,
            failure_height: 0.05,
            force_kn: 0.5,
            drift_pct: 0.05,
            stiffness_kn_per_mm: 2.0,
            modulus_mpa: 400.0,
            asymmetry_kn: 0.7,
        }
    }
}

/// The specimens of the observations, in first-seen order.
pub fn specimens(obs: &[Observation]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for o in obs {
        if !out.contains(&o.specimen) {
            out.push(o.specimen.clone());
        }
    }
    out
}

/// Pooled degrees of freedom below which [`measurement_sigma`] gives no estimate.
pub const MIN_SIGMA_DOF: usize = 4;

/// The measurement σ of one family of measures ([`Observable::family`]: collapse angles,
/// displacements, or one of the in-plane measures) as the data show it: for every observable key (group and observable) with at least two
/// specimens, the specimens' sample variance minus the model's realization variance there
/// (what the model's layouts explain) minus the reading's rounding variance r²/12 (the
/// likelihood takes readings as intervals), pooled over the keys with the weights of their
/// precision, `(n − 1) / (2 τ⁴)` (`τ²` the sample variance the key should show: its
/// model's spread, σ² and the rounding), so that a group whose layouts barely scatter
/// (where σ is most of the spread) is not drowned by one whose layouts scatter a lot;
/// the degrees of freedom returned are `Σ (n − 1)`. A shift of a group's mean (a mechanism the model lacks) does not
/// enter it; only a spread the model does not have does. `None` below [`MIN_SIGMA_DOF`]
/// degrees of freedom.
///
/// `obs[j]` belongs to key `key[j]`; `model_sd[k]` is the model's realization standard
/// deviation at key `k`; `family` selects the measures ([`Observable::family`]).
pub fn measurement_sigma(
    obs: &[Observation],
    key: &[usize],
    model_sd: &[f64],
    reading: f64,
    family: Family,
) -> Option<(f64, usize)> {
    // Per key: (n − 1, sample variance, model variance).
    let mut terms: Vec<(f64, f64, f64)> = Vec::new();
    for (k, sd) in model_sd.iter().enumerate() {
        let y: Vec<f64> = (0..obs.len())
            .filter(|&j| key[j] == k && obs[j].observable.family() == Some(family))
            .map(|j| obs[j].value)
            .collect();
        if y.len() < 2 || !sd.is_finite() {
            continue;
        }
        let m = y.iter().sum::<f64>() / y.len() as f64;
        let s2 = y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (y.len() - 1) as f64;
        terms.push(((y.len() - 1) as f64, s2, sd * sd));
    }
    let dof: usize = terms.iter().map(|t| t.0 as usize).sum();
    if dof < MIN_SIGMA_DOF {
        return None;
    }
    let r2 = reading * reading / 12.0;
    // Each key's excess variance s² − sd² − r²/12, weighted by its precision (n − 1) / (2 τ⁴),
    // τ² = sd² + σ² + r²/12 its expected sample variance: a key whose layouts scatter
    // little tells much more about σ than one whose layouts scatter a lot. Started from
    // the (n − 1)-weighted pool, refined twice.
    let pooled = |w: &dyn Fn(&(f64, f64, f64)) -> f64| {
        let (num, den) = terms.iter().fold((0.0, 0.0), |(a, b), t| (a + w(t) * (t.1 - t.2 - r2), b + w(t)));
        if den > 0.0 {
            (num / den).max(0.0)
        } else {
            0.0
        }
    };
    let mut sigma2 = pooled(&|t| t.0);
    for _ in 0..2 {
        let s = sigma2;
        sigma2 = pooled(&|t| t.0 / (2.0 * (t.2 + s + r2).powi(2)).max(f64::MIN_POSITIVE));
    }
    Some((sigma2.sqrt(), dof))
}

mod read;

pub use read::{mechanism_observations, observations, ObservationError};

#[cfg(test)]
mod tests;
