//! What a run gives to compare with measured data ([`Observed`]): the collapse angle with
//! its bracket, the top displacements at every stable state and the failure mechanism, as
//! the tilting table and the lateral load give them.

use crate::layout::VerticalLoadRig;
use crate::loading::inplane::{read_curve, CurvePoint, DirectionResult, InPlaneResult, MechanismKind};
use crate::loading::lateral::LateralResult;
use crate::loading::mechanism::MechanismReading;
use crate::loading::monitors::TopMonitor;
use crate::loading::tilt::TiltResult;
use crate::units::m_to_cm;
use serde::Serialize;
use std::sync::Arc;

/// What a run gives to compare with measured data (`drystone discrepancy`): the collapse
/// angle with its bracket, the top displacements at every stable state, the failure
/// mechanism ([`super::RunOutcome::observed`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Observed {
    /// Collapse angle α_max, degrees (`max_angle_deg` if the wall stood); `None` under the
    /// lateral load (no collapse angle).
    pub collapse_deg: Option<f64>,
    /// The first unstable tilt above α_max, degrees (`None` if the wall stood).
    pub first_unstable_deg: Option<f64>,
    /// Stable tilts, degrees (under the lateral load: `[0.0]`, the equilibrium under the
    /// load, or none if the wall found none).
    pub tilt_deg: Vec<f64>,
    /// Left, centre and right top displacements at each stable tilt, cm (out of plane, +y:
    /// the side the wall falls to; NaN for a point the layout has no monitor at).
    pub top_cm: Vec<[f64; 3]>,
    /// The failure mechanism as a person would read it (`None` if the wall stood).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mechanism: Option<MechanismReading>,
    /// The in-plane test's measures of its first direction loaded and its mode (`None`
    /// for the other protocols).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub in_plane: Option<InPlaneObserved>,
    /// What an in-plane run's readings are made from ([`InPlaneReading`]), to read them again
    /// under another vertical-load system ([`Observed::reread`]); `None` for the other
    /// protocols. Not written out.
    #[serde(skip)]
    pub in_plane_reading: Option<Arc<InPlaneReading>>,
}

/// What an in-plane run's readings are made from: the curve of the wall's own shear, the
/// applied vertical force and the vertical-load system of the run, and the mode read from
/// the blocks (which the system does not move).
#[derive(Debug, Clone, PartialEq)]
pub struct InPlaneReading {
    /// The curve of the wall's own shear ([`InPlaneResult::wall_curve`]).
    pub wall_curve: Vec<CurvePoint>,
    /// The applied vertical force `σ0 L t`, N.
    pub vertical_force_n: f64,
    /// The run's vertical-load system.
    pub rig: VerticalLoadRig,
    /// The mechanism's mode.
    pub mode: MechanismKind,
}

/// What an in-plane run gives to compare with measured data: the measures of the first
/// direction loaded (+x) and the mode read from the blocks (`loading::inplane`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InPlaneObserved {
    /// The peak horizontal force, kN.
    pub peak_force_kn: f64,
    /// The drift at the peak, %.
    pub drift_at_peak_pct: f64,
    /// The initial stiffness, the secant at 15 % of the peak, kN/mm.
    pub initial_stiffness_kn_per_mm: f64,
    /// The mechanism's mode (`none`: no joint moved past the threshold).
    pub mode: MechanismKind,
}

impl Observed {
    /// The observables of a tilting-table run: its collapse angle, bracket, the top
    /// displacements at every stable tilt and the mechanism's reading.
    pub fn of_tilt(t: &TiltResult) -> Observed {
        let idx = TopMonitor::ALL.map(|m| m.index_in(&t.monitors));
        let mut tilt_deg = Vec::new();
        let mut top_cm = Vec::new();
        for inc in t.increments.iter().filter(|i| i.stable) {
            tilt_deg.push(inc.alpha_deg);
            top_cm.push(idx.map(|i| i.map_or(f64::NAN, |i| m_to_cm(inc.displacement_m[i]))));
        }
        Observed {
            collapse_deg: Some(t.collapse_angle_deg()),
            first_unstable_deg: t.first_unstable_deg,
            tilt_deg,
            top_cm,
            mechanism: t.mechanism.reading,
            in_plane: None,
            in_plane_reading: None,
        }
    }

    /// The observables of a lateral-load run: the top displacements under the load, as one
    /// state at tilt 0° when the wall found an equilibrium (none when it did not: a
    /// displacement observation of it is then missing, as one above a tilting-table
    /// collapse); no collapse angle, no mechanism.
    pub fn of_lateral(r: &LateralResult) -> Observed {
        let idx = TopMonitor::ALL.map(|m| m.index_in(&r.monitors));
        let (tilt_deg, top_cm) = if r.equilibrium {
            (vec![0.0], vec![idx.map(|i| i.map_or(f64::NAN, |i| m_to_cm(r.displacement_m[i])))])
        } else {
            (vec![], vec![])
        };
        Observed {
            collapse_deg: None,
            first_unstable_deg: None,
            tilt_deg,
            top_cm,
            mechanism: None,
            in_plane: None,
            in_plane_reading: None,
        }
    }

    /// The observables of an in-plane run by the penalty DEM: the measures of its first
    /// direction (+x) and its mode; `None` when the run has no +x branch.
    pub fn of_in_plane(r: &InPlaneResult) -> Option<Observed> {
        let reading = InPlaneReading {
            wall_curve: r.wall_curve.clone(),
            vertical_force_n: r.vertical_force_n,
            rig: r.vertical_load_rig,
            mode: r.mechanism.kind,
        };
        Observed::of_direction(r.positive.as_ref()?, Arc::new(reading))
    }

    fn of_direction(d: &DirectionResult, reading: Arc<InPlaneReading>) -> Option<Observed> {
        Some(Observed {
            in_plane: Some(InPlaneObserved {
                peak_force_kn: d.peak_force_kn,
                drift_at_peak_pct: d.drift_at_peak_pct,
                initial_stiffness_kn_per_mm: d.initial_stiffness_kn_per_mm,
                mode: reading.mode,
            }),
            in_plane_reading: Some(reading),
            ..Observed::default()
        })
    }

    /// The observables of the same in-plane run read under the vertical-load system `rig`
    /// instead of its own: its curve of the wall's own shear with `rig`'s force added
    /// ([`read_curve`], the run's own computation), the mode as it was. Bit for bit those of
    /// a run made with `rig` (the beam's motion is imposed: the system does not move the
    /// wall). `None` when the observables are not an in-plane run's
    /// ([`Observed::in_plane_reading`]); `Some(None)` when the curve read so has no +x
    /// branch.
    pub fn reread(&self, rig: VerticalLoadRig) -> Option<Option<Observed>> {
        let r = self.in_plane_reading.as_ref()?;
        let reading = Arc::new(InPlaneReading { rig, ..(**r).clone() });
        let (_, positive) = read_curve(&r.wall_curve, rig, r.vertical_force_n);
        Some(positive.and_then(|d| Observed::of_direction(&d, reading)))
    }
}
