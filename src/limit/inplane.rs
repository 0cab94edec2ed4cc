//! The in-plane shear–compression test by limit analysis: the largest horizontal force the
//! wall carries under the constant vertical force, and its mechanism.
//!
//! The rig is the penalty DEM's ([`crate::loading::inplane::Rig`]): the loading beam on the
//! top course. Dead load: every block's weight, and on the beam the applied vertical force
//! `N = σ0 L t` in place of its weight. Live load: a horizontal force `N_total` (the axial
//! force at the base) along +x on the beam at the shear span `H0`, that is at the centroid
//! with the moment `(H0 − z_beam) N_total` about y; so λ = V / N_total, and the peak force is
//! `λ N_total`. The beam's out-of-plane degrees of freedom (y, rotations about x and z) are
//! held, and its rotation about y with [`BeamRotation::Fixed`] (free reactions of the
//! program: [`super::model`]). A monolithic wall gives `V = N_total L / (2 H0)` (rocking
//! about the toe) or `μ N_total` (sliding), whichever is smaller (`drystone verify`). The
//! rig's terms (`Layout::vertical_load_rig`) add their bearing's friction `μ_r N` and the
//! incline's `N tan β` to the peak, and the eccentric load's moment `e0 (N − W_beam)` to the
//! beam's dead load; the lean of its jack, the lag of its load and the beam's rotational
//! restraint need a displacement and add nothing.

use super::{limit_with, LimitError, LimitParams, LimitResult, LiveLoad};
use crate::dem::SolverParams;
use crate::layout::Layout;
use crate::loading::inplane::{
    read_mechanism, BeamRotation, InPlaneError, InPlaneMechanism, InPlaneParams, MechanismJoint, Rig,
};
use crate::math::Vec3;
use serde::{Deserialize, Serialize};

/// What limit analysis gives for the in-plane test.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneLimit {
    /// The peak horizontal force `λ N_total` (plus the rig's bearing friction, if any), kN.
    pub peak_force_kn: f64,
    /// The axial force at the base, self-weight included, kN.
    pub n_total_kn: f64,
    /// The applied vertical force, kN.
    pub vertical_force_kn: f64,
    /// The rigid rocking capacity of the monolithic wall, kN (a reference).
    pub rocking_force_kn: f64,
    /// The height of the horizontal force, m: the shear span `H0` with the beam's rotation
    /// free; with it held level, the height of the beam's constraint
    /// ([`Rig::anchor_z_m`](crate::loading::inplane::Rig::anchor_z_m)), which is no shear span
    /// and is not reported as one.
    pub shear_span_m: f64,
    /// The mechanism read from the collapse velocities ([`read_mechanism`]).
    pub mechanism: InPlaneMechanism,
    /// The limit analysis (λ = V / N_total, the flow rule, the joints, the velocities).
    pub limit: LimitResult,
}

/// The limit analysis of the in-plane test of `wall` (see the module doc).
///
/// # Errors
/// The rig's refusals ([`InPlaneError`]: parameters, the shear span, a top course not
/// level); a limit analysis error as [`InPlaneError::Unsupported`] with its message (a wall
/// that does not stand, an unbounded program).
pub fn limit_in_plane(
    wall: &Layout,
    contact: &SolverParams,
    params: &InPlaneParams,
    limit: &LimitParams,
) -> Result<InPlaneLimit, InPlaneError> {
    let rig = Rig::build(wall, params)?;
    let beam = rig.beam;
    let n_total = rig.n_total_n();
    let tag = LiveLoad::InPlane { sigma0_mpa: params.sigma0_mpa, shear_span_m: rig.anchor_z_m };
    let (r, model) = limit_with(&rig.layout, contact, tag, limit, |model, sim| {
        let zc = sim.state.bodies[beam].pos.z;
        // The rig's eccentric vertical load: its moment about y at the pose of the collapse's
        // start (the load's lag and the beam's restraint need a displacement).
        let eccentric = rig.layout.vertical_load_rig.eccentricity_m * (rig.vertical_force_n - rig.beam_weight_n);
        model.dead[beam] = (Vec3::new(0.0, 0.0, -rig.vertical_force_n), Vec3::new(0.0, eccentric, 0.0));
        model.live[beam] = (Vec3::new(n_total, 0.0, 0.0), Vec3::new(0.0, (rig.anchor_z_m - zc) * n_total, 0.0));
        model.held.extend([(beam, 1), (beam, 3), (beam, 5)]);
        if params.beam_rotation == BeamRotation::Fixed {
            model.held.push((beam, 4));
        }
    })
    .map_err(|e: LimitError| InPlaneError::Unsupported(format!("limit analysis: {e}")))?;
    let joints: Vec<MechanismJoint> = model
        .joints
        .iter()
        .map(|j| MechanismJoint {
            a: j.a,
            b: j.b,
            name: j.name.clone(),
            normal: j.frame[0],
            points: j.points.clone().map(|p| model.points[p].x).collect(),
            elastic_m: 0.0,
        })
        .collect();
    let v = &r.velocities;
    let scale = v[beam].translation.x.abs();
    let anchor = Vec3::new(model.centroid[beam].x, model.centroid[beam].y, rig.anchor_z_m);
    let mechanism = read_mechanism(
        &joints,
        &model.ids,
        beam,
        anchor,
        scale,
        |k, x| v[k].translation + v[k].rotation.cross(&(x - model.centroid[k])),
        |k| v[k].rotation.y,
    );
    // The rig's vertical load: its bearing's friction resists the beam's motion and its
    // incline pushes it; its lean needs a displacement, which the collapse of rigid blocks
    // does not have.
    let rig_friction_n = rig.layout.vertical_load_rig.actuator_force_n(rig.vertical_force_n, 0.0, 1.0);
    Ok(InPlaneLimit {
        peak_force_kn: (r.load_multiplier * n_total + rig_friction_n) * 1e-3,
        n_total_kn: n_total * 1e-3,
        vertical_force_kn: rig.vertical_force_n * 1e-3,
        rocking_force_kn: rig.rocking_force_n(params.beam_rotation) * 1e-3,
        shear_span_m: rig.anchor_z_m,
        mechanism,
        limit: r,
    })
}
