//! What a run gives to compare with measured data ([`Observed`]): the collapse angle with
//! its bracket, the top displacements at every stable state and the failure mechanism, as
//! the tilting table and the lateral load give them.

use crate::loading::inplane::{InPlaneResult, MechanismKind};
use crate::loading::lateral::LateralResult;
use crate::loading::mechanism::MechanismReading;
use crate::loading::monitors::TopMonitor;
use crate::loading::tilt::TiltResult;
use crate::units::m_to_cm;
use serde::Serialize;

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
        Observed { collapse_deg: None, first_unstable_deg: None, tilt_deg, top_cm, mechanism: None, in_plane: None }
    }

    /// The observables of an in-plane run by the penalty DEM: the measures of its first
    /// direction (+x) and its mode; `None` when the run has no +x branch.
    pub fn of_in_plane(r: &InPlaneResult) -> Option<Observed> {
        let d = r.positive.as_ref()?;
        Some(Observed {
            in_plane: Some(InPlaneObserved {
                peak_force_kn: d.peak_force_kn,
                drift_at_peak_pct: d.drift_at_peak_pct,
                initial_stiffness_kn_per_mm: d.initial_stiffness_kn_per_mm,
                mode: r.mechanism.kind,
            }),
            ..Observed::default()
        })
    }
}
