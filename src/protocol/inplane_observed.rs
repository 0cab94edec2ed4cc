//! What an in-plane run gives to compare with measured data ([`InPlaneObserved`], a part of
//! [`super::Observed`]; made by [`super::Observed::of_in_plane`]), and what its readings are
//! made from ([`InPlaneReading`], to read them again: [`super::Observed::reread`]).

use crate::layout::VerticalLoadRig;
use crate::loading::inplane::{read_curve, CurvePoint, MechanismKind};
use serde::{Deserialize, Serialize};

/// What an in-plane run gives to compare with measured data: the measures of the first
/// direction loaded (+x) and the mode read from the blocks (`loading::inplane`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InPlaneObserved {
    /// The peak horizontal force, kN.
    pub peak_force_kn: f64,
    /// The drift at the peak, %.
    pub drift_at_peak_pct: f64,
    /// The initial stiffness, the secant at 15 % of the peak, kN/mm.
    pub initial_stiffness_kn_per_mm: f64,
    /// The mechanism's mode (`none`: no joint moved past the threshold).
    pub mode: MechanismKind,
    /// The wall's vertical modulus read in the vertical loading phase, MPa
    /// ([`crate::loading::inplane::InPlaneResult::wall_vertical_modulus_mpa`]; NaN: none).
    #[serde(default = "nan")]
    pub wall_vertical_modulus_mpa: f64,
    /// The ± asymmetry of the peak, kN: the peak of the push towards −x less that towards
    /// +x, each as a magnitude (the database's `Vmax_neg − Vmax_pos`), the −x push read as
    /// the mirror image of the +x one ([`InPlaneReading::negative_peak_kn`]); NaN where
    /// the run was not read both ways.
    #[serde(default = "nan")]
    pub peak_asymmetry_kn: f64,
}

/// NaN, for serde's defaults (records written before the modulus was read).
fn nan() -> f64 {
    f64::NAN
}

/// What an in-plane run's readings are made from: the curve of the wall's own shear, the
/// applied vertical force and the vertical-load system of the run, and the mode read from
/// the blocks (which the system does not move).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneReading {
    /// The curve of the wall's own shear ([`crate::loading::inplane::InPlaneResult::wall_curve`]).
    pub wall_curve: Vec<CurvePoint>,
    /// The applied vertical force `σ0 L t`, N.
    pub vertical_force_n: f64,
    /// The run's vertical-load system.
    pub rig: VerticalLoadRig,
    /// The height of the measuring point, m (the drift's lever: the series compliance's
    /// displacement enters the drift over it).
    #[serde(default = "nan")]
    pub measuring_height_m: f64,
    /// The mechanism's mode.
    pub mode: MechanismKind,
    /// The wall's vertical modulus, MPa (which the vertical-load system does not change).
    #[serde(default = "nan")]
    pub wall_vertical_modulus_mpa: f64,
    /// The curve of the wall's own shear pushed towards −x, as its mirror image
    /// ([`crate::loading::inplane::Mirror::wall_curve`]): `None` where
    /// `wall_curve` is its own mirror; `Some` only in runs read both ways.
    #[serde(default)]
    pub mirror_wall_curve: Option<Vec<CurvePoint>>,
    /// Whether the run was read both ways ([`crate::loading::inplane::InPlaneParams::mirror_reading`]).
    #[serde(default)]
    pub both_ways: bool,
}

impl InPlaneReading {
    /// The peak of the push towards −x, kN, as a magnitude: the mirror image of the wall's
    /// own shear (`mirror_wall_curve`, or `wall_curve` where that is its own mirror) read
    /// under the mirrored rig ([`VerticalLoadRig::mirrored`], the readings' terms by
    /// [`read_curve`], the run's own computation). NaN where the run was not read both
    /// ways or the mirror image has no +x branch.
    ///
    /// The mirror image is the push towards −x of the mirrored wall; the wall's layout is
    /// taken as a draw of an ensemble that is its own mirror image (the generator's
    /// distributions do not tell left from right), so the asymmetry this reads is the rig's
    /// alone and a layout's own is part of the spread between specimens.
    pub fn negative_peak_kn(&self) -> f64 {
        if !self.both_ways {
            return f64::NAN;
        }
        let curve = self.mirror_wall_curve.as_deref().unwrap_or(&self.wall_curve);
        let (_, d) = read_curve(curve, self.rig.mirrored(), self.vertical_force_n, self.measuring_height_m);
        d.map_or(f64::NAN, |d| d.peak_force_kn)
    }
}
