//! What a run gives to compare with measured data ([`Observed`]): the collapse angle with
//! its bracket, the top displacements at every stable state and the failure mechanism, as
//! the tilting table and the lateral load give them.

use super::inplane_observed::{InPlaneObserved, InPlaneReading};
use crate::loading::lateral::LateralResult;
use crate::loading::mechanism::MechanismReading;
use crate::loading::monitors::TopMonitor;
use crate::loading::tilt::TiltResult;
use crate::units::m_to_cm;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What a run gives to compare with measured data (`drystone discrepancy`): the collapse
/// angle with its bracket, the top displacements at every stable state, the failure
/// mechanism ([`super::RunOutcome::observed`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
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
    /// What the readings of a run under a vertical-load rig are made from
    /// ([`InPlaneReading`]), to read them again under another vertical-load system
    /// ([`Observed::reread`]); `None` for a protocol that reads no rig
    /// ([`super::LoadingProtocol::READS_VERTICAL_LOAD_RIG`]). Not written out.
    #[serde(skip)]
    pub rig_reading: Option<Arc<InPlaneReading>>,
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
            ..Observed::default()
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
            ..Observed::default()
        }
    }
}
