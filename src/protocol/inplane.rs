//! The in-plane shear–compression test: a loading beam on the top course under a constant
//! vertical force, its horizontal displacement imposed quasi-statically (monotonic or in
//! growing cycles); by the penalty DEM (the force–displacement curve,
//! `loading::inplane`), by non-smooth contact dynamics (the rigid blocks' curve, the beam's
//! degrees of freedom constrained in the contact dynamics, `loading::inplane_nscd`) or by
//! limit analysis (the peak force and its mechanism, `limit::inplane`).

use super::contract::{ChosenBy, LoadingProtocol, Observables, Output, RunOutcome, Way};
use super::inplane_observed::{InPlaneObserved, InPlaneReading};
use super::observed::Observed;
use super::Protocol;
use crate::dem::Method;
use crate::layout::VerticalLoadRig;
use crate::limit::inplane::{limit_in_plane, InPlaneLimit};
use crate::loading::inplane::{read_curve, DirectionResult};
use crate::loading::inplane::{run_in_plane_penalty, InPlaneError, InPlaneParams, InPlaneResult};
use crate::loading::inplane_nscd::run_in_plane_nscd;
use std::sync::Arc;

/// The in-plane test with its parameters (`[in_plane]`).
#[derive(Debug, Clone, PartialEq)]
pub struct InPlane(pub InPlaneParams);

/// What an in-plane run gives.
#[derive(Debug, Clone, PartialEq)]
pub enum InPlaneRun {
    /// The penalty DEM: the force–displacement curve, its per-direction outputs and the
    /// mechanism.
    Penalty(Result<InPlaneResult, InPlaneError>),
    /// Non-smooth contact dynamics: the rigid blocks' force–displacement curve (the beam
    /// driven at a constant speed), its per-direction outputs and the mechanism.
    Nscd(Result<InPlaneResult, InPlaneError>),
    /// Limit analysis: the peak horizontal force under the vertical force, and the
    /// mechanism.
    Limit(Result<InPlaneLimit, InPlaneError>),
}

impl LoadingProtocol for InPlane {
    const NAME: &'static str = "in_plane";
    const DESCRIPTION: &'static str = "the in-plane shear-compression test";
    const MOTION: bool = false;
    const CHOSEN_BY: Option<ChosenBy> = None;
    const READS_VERTICAL_LOAD_RIG: bool = true;
    const LOADS_IN_PLANE: bool = true;
    // Its column group (`ensemble::row::InPlaneColumns`) is written to its study's tables
    // only, not to every protocol's.
    const OPTIONAL_COLUMNS: bool = true;
    type Run = InPlaneRun;

    const WAYS: &'static [Way<Self>] = &[
        Way {
            method: Method::Penalty,
            what: "force-displacement curve (static solve per increment of the imposed displacement)",
            run: |p, layout, solver, observer| {
                let run = run_in_plane_penalty(layout, *solver, &p.0, &mut |a, s, sim| observer.state(a, s, sim));
                InPlaneRun::Penalty(with_mirror(run, layout, |l| {
                    run_in_plane_penalty(l, *solver, &p.0, &mut |_, _, _| {})
                }))
            },
        },
        Way {
            method: Method::Nscd,
            what: "rigid blocks' force-displacement curve (the beam driven at constant speed)",
            run: |p, layout, solver, _| {
                let run = run_in_plane_nscd(layout, &solver.nscd, &p.0);
                InPlaneRun::Nscd(with_mirror(run, layout, |l| run_in_plane_nscd(l, &solver.nscd, &p.0)))
            },
        },
        Way {
            method: Method::Limit,
            what: "peak horizontal force under the vertical force, and the mechanism",
            run: |p, layout, solver, _| InPlaneRun::Limit(limit_in_plane(layout, solver, &p.0, &solver.limit)),
        },
    ];

    /// The test pushed monotonically to its drift: the measures of the positive direction
    /// (peak force, drift at the peak, initial stiffness), the mode, and the push read
    /// both ways by its mirror image for the peaks' ± asymmetry
    /// ([`InPlaneParams::mirror_reading`]). A cyclic
    /// specimen's first direction is compared with it: the bundled study's cyclic
    /// ensembles peak within 2 % of its monotonic ones (35.7, 61.4 and 86.1 kN against
    /// 35.4, 60.2 and 84.6 kN; README), at a fortieth of the cost.
    fn compared(&self) -> Result<Protocol, &'static str> {
        let mut p = self.0.clone();
        p.history = crate::loading::inplane::History::Monotonic;
        p.mirror_reading = true;
        Ok(Protocol::InPlane(InPlane(p)))
    }

    /// No collapse angle, no tilt states, no out-of-plane mechanism.
    fn observables(&self) -> Observables {
        Observables {
            outputs: &[Output::CurveMeasures, Output::MechanismMode],
            collapse_bracket_deg: None,
            state_step_deg: None,
        }
    }
}

/// A run read both ways ([`InPlaneResult::mirror`]) under a rig whose
/// eccentricity moves the wall, with its mirror image: `run_mirrored` run on the layout with
/// the rig mirrored ([`VerticalLoadRig::mirrored`]), its curve of the wall's own shear
/// kept as the mirror's curve. A mirror run that fails leaves the asymmetry unread (the
/// run read one way), not the run.
fn with_mirror(
    run: Result<InPlaneResult, InPlaneError>,
    layout: &crate::layout::Layout,
    run_mirrored: impl FnOnce(&crate::layout::Layout) -> Result<InPlaneResult, InPlaneError>,
) -> Result<InPlaneResult, InPlaneError> {
    let mut r = run?;
    if r.mirror.is_some() && layout.vertical_load_rig.eccentricity_m != 0.0 {
        let mut mirror = layout.clone();
        mirror.vertical_load_rig = layout.vertical_load_rig.mirrored();
        match run_mirrored(&mirror) {
            Ok(m) => r.mirror = Some(Box::new(crate::loading::inplane::Mirror { wall_curve: Some(m.wall_curve) })),
            Err(_) => r.mirror = None,
        }
    }
    Ok(r)
}

impl InPlaneRun {
    /// The method that ran it: its variant's name.
    pub fn method(&self) -> Method {
        match self {
            InPlaneRun::Penalty(_) => Method::Penalty,
            InPlaneRun::Nscd(_) => Method::Nscd,
            InPlaneRun::Limit(_) => Method::Limit,
        }
    }
}

impl RunOutcome for InPlaneRun {
    /// The penalty DEM's and nscd's measures of the first direction and its mode
    /// ([`Observed::of_in_plane`]); limit analysis gives no curve to compare.
    fn observed(&self) -> Option<Observed> {
        match self {
            InPlaneRun::Penalty(Ok(r)) | InPlaneRun::Nscd(Ok(r)) => Observed::of_in_plane(r),
            InPlaneRun::Penalty(Err(_)) | InPlaneRun::Nscd(Err(_)) | InPlaneRun::Limit(_) => None,
        }
    }
    fn error(&self) -> Option<String> {
        match self {
            InPlaneRun::Penalty(Err(e)) | InPlaneRun::Nscd(Err(e)) | InPlaneRun::Limit(Err(e)) => Some(e.to_string()),
            InPlaneRun::Penalty(Ok(_)) | InPlaneRun::Nscd(Ok(_)) | InPlaneRun::Limit(Ok(_)) => None,
        }
    }
    fn does_not_stand(&self) -> bool {
        match self {
            InPlaneRun::Penalty(Err(e)) | InPlaneRun::Nscd(Err(e)) | InPlaneRun::Limit(Err(e)) => e.does_not_stand(),
            InPlaneRun::Penalty(Ok(_)) | InPlaneRun::Nscd(Ok(_)) | InPlaneRun::Limit(Ok(_)) => false,
        }
    }
    fn refused(&self) -> bool {
        match self {
            InPlaneRun::Penalty(Err(e)) | InPlaneRun::Nscd(Err(e)) | InPlaneRun::Limit(Err(e)) => e.is_refusal(),
            InPlaneRun::Penalty(Ok(_)) | InPlaneRun::Nscd(Ok(_)) | InPlaneRun::Limit(Ok(_)) => false,
        }
    }
}

impl Observed {
    /// The observables of an in-plane run by the penalty DEM: the measures of its first
    /// direction (+x) and its mode; `None` when the run has no +x branch.
    pub fn of_in_plane(r: &InPlaneResult) -> Option<Observed> {
        let reading = InPlaneReading {
            wall_curve: r.wall_curve.clone(),
            vertical_force_n: r.vertical_force_n,
            rig: *r.vertical_load_rig,
            measuring_height_m: r.measuring_height_m,
            mode: r.mechanism.kind,
            wall_vertical_modulus_mpa: r.wall_vertical_modulus_mpa,
            mirror_wall_curve: r.mirror.as_ref().and_then(|m| m.wall_curve.clone()),
            both_ways: r.mirror.is_some(),
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
                wall_vertical_modulus_mpa: reading.wall_vertical_modulus_mpa,
                peak_asymmetry_kn: reading.negative_peak_kn() - d.peak_force_kn,
            }),
            rig_reading: Some(reading),
            ..Observed::default()
        })
    }

    /// The observables of the same in-plane run read under the vertical-load system `rig`
    /// instead of its own: its curve of the wall's own shear with `rig`'s force added
    /// ([`read_curve`], the run's own computation), the mode as it was. Bit for bit those of
    /// a run made with `rig` (the beam's motion is imposed: the system does not move the
    /// wall). `None` when the observables are not an in-plane run's
    /// ([`Observed::rig_reading`]); `Some(None)` when the curve read so has no +x
    /// branch.
    pub fn reread(&self, rig: VerticalLoadRig) -> Option<Option<Observed>> {
        let r = self.rig_reading.as_ref()?;
        let reading = Arc::new(InPlaneReading { rig, ..(**r).clone() });
        let (_, positive) = read_curve(&r.wall_curve, rig, r.vertical_force_n, r.measuring_height_m);
        Some(positive.and_then(|d| Observed::of_direction(&d, reading)))
    }
}
