//! The rig ([`Rig`]): the loading beam laid on the wall, its constraint and the moment and
//! forces of the rig's vertical-load system ([`add_rig_force`], [`read_curve`]); the mirror
//! reading ([`Mirror`]); the one-block wall's elastic stiffness ([`one_block_stiffness`]).

use super::{
    direction, BeamRotation, CurvePoint, DirectionResult, InPlaneError, InPlaneParams, OutOfPlane, MAX_HEIGHT_RATIO,
};
use crate::dem::{DofConstraint, Simulation};
use crate::geometry::ConvexBlock;
use crate::layout::{Block, Layout, VerticalLoadRig};
use crate::math::Vec3;
use crate::range::OutOfRange;
use serde::{Deserialize, Serialize};

/// The id of the loading beam's block in the rig's layout.
pub const BEAM_ID: &str = "loading_beam";

/// The largest level tolerance of the top course, as a share of the wall's height \[0.002\]
/// (2.4 mm on a 1.2 m wall): a cap on [`level_tolerance_m`], reached only by joints whose
/// closure under the vertical stress is several millimetres (soft or seated beds).
pub const LEVEL_TOLERANCE_FRACTION: f64 = 0.002;

/// The smallest level tolerance, m \[1e-9\]: the rounding of coordinates in metres, far
/// below any closure of a joint of the stiffnesses the layout files allow.
pub const LEVEL_TOLERANCE_FLOOR_M: f64 = 1e-9;

/// How far below the wall's top a top stone's top may lie and still carry the loading beam,
/// m: half the closure `u0` of the beam's joint under the vertical stress `sigma0_pa` (Pa)
/// by the joint's closure law (`σ0 / Kn` on a linear joint), the least over the top stones'
/// `materials` (the beam takes the highest block's material), between
/// [`LEVEL_TOLERANCE_FLOOR_M`] and [`LEVEL_TOLERANCE_FRACTION`] of the wall's `height_m`.
///
/// Why half the closure: the beam is laid on the highest stones and pressed down by the
/// vertical force `N = σ0 L t`. A share `s` of the top lying `g` lower than the rest, on
/// linear joints of stiffness `Kn`, closes `u_h = σ0 / Kn + s g` under the higher stones and
/// `u_h − g` under the lower ones, so these carry `σ0 − Kn g (1 − s)`: nothing once `g`
/// reaches `σ0 / (Kn (1 − s))`, and at least half of `σ0` for `g ≤ σ0 / (2 Kn)` whatever
/// their share. Within the tolerance every top stone carries the beam with at least half the
/// stress; past it the beam bears on part of the top, a test the rig does not model. The
/// joints below the top course add their compliance in series and only widen the band, so
/// the bound is on the safe side. (A laboratory beds its beam on a levelled top; granite
/// joints of Kn 2e10 Pa/m at 0.5 MPa take up 12.5 µm.)
pub fn level_tolerance_m(materials: &[&crate::layout::Material], sigma0_pa: f64, height_m: f64) -> f64 {
    let closure = |m: &crate::layout::Material| -> f64 {
        if m.closure.is_linear() {
            return sigma0_pa / m.kn;
        }
        // The closure law's pressure rises with the closure: bracket σ0, then bisect.
        let q = |u: f64| m.closure.pressure(m.kn, u);
        let (mut lo, mut hi) = (0.0, sigma0_pa / m.kn);
        let cap = LEVEL_TOLERANCE_FRACTION * height_m * 2.0;
        while q(hi) < sigma0_pa && hi < cap {
            (lo, hi) = (hi, 2.0 * hi);
        }
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if q(mid) < sigma0_pa {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    };
    let u0 = materials.iter().map(|m| closure(m)).fold(f64::INFINITY, f64::min);
    (0.5 * u0).clamp(LEVEL_TOLERANCE_FLOOR_M, LEVEL_TOLERANCE_FRACTION * height_m)
}

/// The share of the wall's length the blocks carrying the beam must cover \[0.8\].
pub const BEARING_SHARE: f64 = 0.8;

/// The rig: the wall's layout with the loading beam, and what the test needs of them.
#[derive(Debug, Clone)]
pub struct Rig {
    /// The layout with the beam as its last block.
    pub layout: Layout,
    /// The beam's block index.
    pub beam: usize,
    /// Wall length L (x extent), height H (z extent), thickness t (y extent), m.
    pub length_m: f64,
    /// See `length_m`.
    pub height_m: f64,
    /// See `length_m`.
    pub thickness_m: f64,
    /// The wall's lowest x, m (the toes are at `x_min` and `x_min + L`).
    pub x_min: f64,
    /// The applied vertical force `σ0 L t`, N.
    pub vertical_force_n: f64,
    /// The wall's self-weight (the beam excluded), N.
    pub wall_weight_n: f64,
    /// The beam's weight, N (part of `vertical_force_n`).
    pub beam_weight_n: f64,
    /// The height of the horizontal force (the anchor), m: `H0`, or the beam's centroid
    /// with a held rotation.
    pub anchor_z_m: f64,
    /// The beam's centroid height, m.
    pub beam_z_m: f64,
    /// The height of the measuring point, m ([`InPlaneParams::measuring_height_m`], or the
    /// actuator's height: `H0` with the beam's rotation free, the wall's height with it
    /// held). The drift is the displacement there over this height.
    pub measure_z_m: f64,
    /// What holds the blocks out of the wall's plane ([`InPlaneParams::out_of_plane`]).
    pub out_of_plane: OutOfPlane,
}

impl Rig {
    /// The axial force at the base, `N + W_wall`, N.
    pub fn n_total_n(&self) -> f64 {
        self.vertical_force_n + self.wall_weight_n
    }

    /// Builds the rig on `wall`: checks the shear span and the top course's level, and lays
    /// the beam (see the module doc).
    ///
    /// # Errors
    /// [`InPlaneError::Parameter`], [`InPlaneError::ShearSpan`], [`InPlaneError::NotLevel`]
    /// naming the block, [`InPlaneError::Beam`].
    pub fn build(wall: &Layout, params: &InPlaneParams) -> Result<Rig, InPlaneError> {
        params.validate().map_err(InPlaneError::Parameter)?;
        if wall.blocks.iter().any(|b| b.id == BEAM_ID) {
            return Err(InPlaneError::Beam(format!("the layout already has a block named {BEAM_ID}")));
        }
        let bounds = wall.bounds();
        let e = bounds.extent();
        let (length, thickness, height) = (e.x, e.y, e.z);
        if !(length > 0.0 && thickness > 0.0 && height > 0.0) {
            return Err(InPlaneError::Beam("the layout has no extent".into()));
        }
        let top = bounds.max.z;
        check_top_level(wall, top, height, length, params.sigma0_mpa * 1e6)?;
        let (depth, anchor_z) = match params.beam_rotation {
            BeamRotation::Free => {
                let h0 = params.shear_span_m.expect("validated");
                if h0 < top - 1e-9 {
                    return Err(InPlaneError::ShearSpan { shear_span_m: h0, height_m: top });
                }
                if h0 > MAX_HEIGHT_RATIO * top {
                    return Err(InPlaneError::TooHigh {
                        key: "shear_span_m",
                        value_m: h0,
                        height_m: top,
                        ratio: MAX_HEIGHT_RATIO,
                    });
                }
                ((2.0 * (h0 - top)).clamp(0.05 * height, 0.25 * height), h0)
            }
            BeamRotation::Fixed => (0.1 * height, top + 0.05 * height),
        };
        let lever = match params.beam_rotation {
            BeamRotation::Free => anchor_z,
            BeamRotation::Fixed => top,
        };
        params.check_path(lever).map_err(InPlaneError::Parameter)?;
        let measure_z = params.measuring_height_m.unwrap_or(lever);
        if measure_z < top - 1e-9 {
            return Err(InPlaneError::MeasuringPoint { measuring_height_m: measure_z, height_m: top });
        }
        if measure_z > MAX_HEIGHT_RATIO * top {
            return Err(InPlaneError::TooHigh {
                key: "measuring_height_m",
                value_m: measure_z,
                height_m: top,
                ratio: MAX_HEIGHT_RATIO,
            });
        }
        let (x0, x1, y0, y1) = (bounds.min.x, bounds.max.x, bounds.min.y, bounds.max.y);
        let corners: Vec<Vec3> = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
            .iter()
            .flat_map(|&(x, y)| [Vec3::new(x, y, top), Vec3::new(x, y, top + depth)])
            .collect();
        let shape = ConvexBlock::from_vertices(&corners).map_err(|e| InPlaneError::Beam(e.to_string()))?;
        // The beam's material: that of the highest block (the top course's), so that the
        // beam–wall joint has the bed joints' law.
        let material = wall
            .blocks
            .iter()
            .max_by(|a, b| a.shape.aabb().max.z.total_cmp(&b.shape.aabb().max.z))
            .map_or(0, |b| b.material);
        let g = wall.gravity;
        let wall_weight: f64 = wall
            .blocks
            .iter()
            .filter(|b| !b.fixed)
            .map(|b| b.mass_properties(wall.materials[b.material].density).mass)
            .sum::<f64>()
            * g;
        let beam_weight = wall.materials[material].density * shape.volume() * g;
        let vertical_force_n = params.sigma0_mpa * 1e6 * length * thickness;
        if vertical_force_n < beam_weight {
            return Err(InPlaneError::Parameter(OutOfRange::new(
                "sigma0_mpa",
                params.sigma0_mpa,
                "at least the loading beam's own weight over the wall's plan area (the beam is part of the applied force)",
            )));
        }
        let mut layout = wall.clone();
        layout.blocks.push(Block {
            id: BEAM_ID.to_string(),
            material,
            shape,
            fixed: false,
            course: None,
            wedge: false,
            own_mass: None,
            bed_closure: None,
        });
        let beam = layout.blocks.len() - 1;
        Ok(Rig {
            layout,
            beam,
            length_m: length,
            height_m: top,
            thickness_m: thickness,
            x_min: x0,
            vertical_force_n,
            wall_weight_n: wall_weight,
            beam_weight_n: beam_weight,
            anchor_z_m: anchor_z,
            beam_z_m: top + 0.5 * depth,
            measure_z_m: measure_z,
            out_of_plane: params.out_of_plane,
        })
    }

    /// The constraint of a block of the wall (not the beam) at the pose of its body `b`:
    /// with [`OutOfPlane::Held`], its translation across the wall (y) and its rotations
    /// about x and z held where they are (the plane model, [`OutOfPlane`]); `None` with
    /// [`OutOfPlane::Free`].
    pub fn block_constraint_of(&self, b: &crate::dem::state::Body) -> Option<DofConstraint> {
        match self.out_of_plane {
            OutOfPlane::Held => Some(DofConstraint::free().hold_translation(b, 1).hold_rotation(0).hold_rotation(2)),
            OutOfPlane::Free => None,
        }
    }

    /// The beam's constraint at its pose in `sim` (see the module doc): x held at the
    /// anchor, y and the rotations about x and z held, the rotation about y held if
    /// `rotation` is [`BeamRotation::Fixed`].
    pub fn constraint(&self, sim: &Simulation, rotation: BeamRotation) -> DofConstraint {
        self.constraint_of(&sim.state.bodies[self.beam], rotation)
    }

    /// The beam's constraint at the pose of its body `b` (any engine's; see
    /// [`Rig::constraint`]).
    pub fn constraint_of(&self, b: &crate::dem::state::Body, rotation: BeamRotation) -> DofConstraint {
        let anchor = Vec3::new(0.0, 0.0, self.anchor_z_m - b.pos.z);
        let c = DofConstraint { anchor, ..DofConstraint::free() }
            .hold_translation(b, 0)
            .hold_translation(b, 1)
            .hold_rotation(0)
            .hold_rotation(2);
        match rotation {
            BeamRotation::Free => c,
            BeamRotation::Fixed => c.hold_rotation(1),
        }
    }

    /// Adds to each point of `curve` what the rig's terms that the readings carry add to
    /// it (`Layout::vertical_load_rig`, [`add_rig_force`]); nothing for an ideal rig.
    pub fn add_vertical_load_rig(&self, curve: &mut [CurvePoint]) {
        add_rig_force(self.layout.vertical_load_rig, self.vertical_force_n, self.measure_z_m, curve);
    }

    /// The moment the rig's terms that move the wall apply to the beam about y, with the
    /// beam's pose `beam` as its reference (`Layout::vertical_load_rig`: `e0 P`, `−κ P u_c`
    /// and `−K_θ θ`, P the force the jacks apply, `N − W_beam`); `None` when the rig has no
    /// term that moves the wall.
    pub fn beam_moment(&self, beam: &crate::dem::state::Body) -> Option<crate::dem::RigMoment> {
        let r = &self.layout.vertical_load_rig;
        let p = self.vertical_force_n - self.beam_weight_n;
        r.moves_wall().then(|| crate::dem::RigMoment {
            axis: 1,
            along: 0,
            at_reference_nm: r.eccentricity_m * p,
            per_displacement_n: -r.fixed_share * p,
            per_rotation_nm: -r.rotational_stiffness_nm_per_rad,
            reference_pos: beam.pos,
            reference_rot: beam.rot,
        })
    }

    /// The rigid rocking capacity of the monolithic wall, N: `N_total L / (2 H0)` with the
    /// beam's rotation free; with it held (double curvature: the wall turns about its toe
    /// and bears on the level beam at its opposite top corner), `(N L + W L / 2) / H`.
    pub fn rocking_force_n(&self, rotation: BeamRotation) -> f64 {
        match rotation {
            BeamRotation::Free => self.n_total_n() * self.length_m / (2.0 * self.anchor_z_m),
            BeamRotation::Fixed => (self.vertical_force_n + 0.5 * self.wall_weight_n) * self.length_m / self.height_m,
        }
    }
}

/// Checks that the top course of `wall` is level enough to carry the beam under the
/// vertical stress `sigma0_pa` (Pa): every block whose top lies within half the smallest
/// block's height of the wall's top `top` (m; the top course) lies within
/// [`level_tolerance_m`] of it, and those blocks cover at least [`BEARING_SHARE`] of the
/// wall's length `length` (m; a top course with gaps). `height` is the wall's height, m.
///
/// # Errors
/// [`InPlaneError::NotLevel`], naming the stones below the tolerance and those the beam would
/// bear on; [`InPlaneError::TopAlone`], naming the blocks level with the top where they cover
/// too little of the length (a block standing above the wall, or stones missing from the top).
fn check_top_level(wall: &Layout, top: f64, height: f64, length: f64, sigma0_pa: f64) -> Result<(), InPlaneError> {
    let band = top - 0.5 * wall.blocks.iter().map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
    // The top course: the blocks reaching into the band under the top; the beam's joint is
    // made with their materials.
    let course: Vec<&Block> = wall.blocks.iter().filter(|b| b.shape.aabb().max.z > band).collect();
    let materials: Vec<&crate::layout::Material> = course.iter().map(|b| &wall.materials[b.material]).collect();
    let tol = level_tolerance_m(&materials, sigma0_pa, height);
    let (bearing, low): (Vec<&Block>, Vec<&Block>) =
        course.iter().copied().partition(|b| b.shape.aabb().max.z >= top - tol);
    if !low.is_empty() {
        let ids = |bs: &[&Block]| -> Vec<String> { bs.iter().map(|b| b.id.clone()).collect() };
        let lowest = low.iter().map(|b| b.shape.aabb().max.z).fold(f64::INFINITY, f64::min);
        let highest_low = low.iter().map(|b| b.shape.aabb().max.z).fold(f64::NEG_INFINITY, f64::max);
        let bearing_length: f64 = bearing.iter().map(|b| b.shape.aabb().extent().x).sum();
        return Err(InPlaneError::NotLevel {
            low: ids(&low),
            bearing: ids(&bearing),
            height_m: top,
            step_min_mm: (top - highest_low) * 1e3,
            step_max_mm: (top - lowest) * 1e3,
            tolerance_mm: tol * 1e3,
            sigma0_mpa: sigma0_pa * 1e-6,
            bearing_pct: (100.0 * bearing_length / length).min(100.0),
        });
    }
    let mut spans: Vec<(f64, f64)> = bearing.iter().map(|b| (b.shape.aabb().min.x, b.shape.aabb().max.x)).collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut covered = 0.0;
    let mut reach = f64::NEG_INFINITY;
    for (a, b) in spans {
        let a = a.max(reach);
        if b > a {
            covered += b - a;
        }
        reach = reach.max(b);
    }
    if covered < BEARING_SHARE * length {
        // Every block reaching near the top is level with it, and they cover too little: a
        // block standing alone above the wall (drawn or laid apart from it), or a top course
        // with stones missing.
        return Err(InPlaneError::TopAlone {
            blocks: bearing.iter().map(|b| b.id.clone()).collect(),
            top_m: top,
            covered_pct: 100.0 * covered / length,
            need_pct: 100.0 * BEARING_SHARE,
        });
    }
    Ok(())
}

/// Adds to each point of `curve` what the rig's terms that the readings carry
/// ([`VerticalLoadRig::reads_only`]) add to it under the applied vertical force `n` (N):
/// to the force, `n (u / L + μ_r sgn(u̇) + tan β)`, u the point's displacement, u̇'s sense
/// that of the increment that led to it (none at the first point); then to the displacement
/// the series compliance's `c V` (V the force so read) and to the drift its share over the
/// measuring point's height `measure_z_m` (m). Nothing for an ideal rig. The one place the
/// rig's readings enter a curve: [`Rig::add_vertical_load_rig`] in a run, [`read_curve`] on
/// a run's curve of the wall's own shear.
pub fn add_rig_force(r: VerticalLoadRig, n: f64, measure_z_m: f64, curve: &mut [CurvePoint]) {
    let Some(r) = r.reads_only() else {
        return;
    };
    let mut last = None;
    for p in curve.iter_mut() {
        // The sense of the increment that led to the point (0 at the first, or none).
        let sense = last.map_or(0.0, |u0: f64| {
            let du = p.top_mm - u0;
            if du == 0.0 {
                0.0
            } else {
                du.signum()
            }
        });
        last = Some(p.top_mm);
        p.force_kn += 1e-3 * r.actuator_force_n(n, 1e-3 * p.top_mm, sense);
        if r.series_compliance_m_per_n != 0.0 {
            let extra_m = r.series_compliance_m_per_n * p.force_kn * 1e3;
            p.top_mm += extra_m * 1e3;
            p.drift_pct += 100.0 * extra_m / measure_z_m;
        }
    }
}

/// The push towards −x of a monotonic run read both ways, as its mirror image
/// ([`InPlaneResult::mirror`](super::InPlaneResult::mirror)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mirror {
    /// The curve of the wall's own shear pushed the other way, read as its mirror image
    /// (+x): a second monotonic run with the rig's eccentricity `e0` mirrored, made where the
    /// eccentricity is not 0 (a moment on the beam whose sense the push's does not follow).
    /// `None`: the run's own `wall_curve` is its mirror (the wall's layout taken as one of
    /// an ensemble that is its own mirror image).
    pub wall_curve: Option<Vec<CurvePoint>>,
}

/// The force read and the first direction's outputs (+x, [`direction`]) of a run's curve of
/// the wall's own shear (`wall_curve`, [`InPlaneResult::wall_curve`](super::InPlaneResult::wall_curve)) under the rig's
/// terms `rig` and the applied vertical force `vertical_force_n` (N), the displacement read
/// at the height `measure_z_m` (m): the same computation as the run's own
/// ([`Rig::add_vertical_load_rig`], then [`direction`]), so that a run with `rig` and a run
/// without it read here give the same numbers, bit for bit.
pub fn read_curve(
    wall_curve: &[CurvePoint],
    rig: VerticalLoadRig,
    vertical_force_n: f64,
    measure_z_m: f64,
) -> (Vec<CurvePoint>, Option<DirectionResult>) {
    let mut curve = wall_curve.to_vec();
    add_rig_force(rig, vertical_force_n, measure_z_m, &mut curve);
    let positive = direction(&curve, 1.0);
    (curve, positive)
}

/// The elastic stiffness (N/m) of a one-block wall of length `l`, thickness `t` and height
/// `h` (weight `w`, N) on a linear joint of normal and shear stiffness `kn`, `ks` (Pa/m),
/// under the loading beam (its centroid, where the horizontal force and the vertical force
/// `n` (N, the beam's weight included) act, at the shear span `h0`) on a joint of the same
/// law, the beam's rotation free; the displacement read on the beam at the height `hm`
/// (the measuring point, at least `h`: `h0` for the actuator's point).
///
/// Small displacements with the vertical loads staying vertical (first-order P–Δ). The
/// unknowns: the force V, the base joint's rotation θ and the beam joint's ψ (about their
/// centres; rotational stiffness `Kn I`, I = t L³ / 12), each joint's shear slip `V / (Ks A)`
/// (A = L t). For an imposed beam displacement `u = 2 V / (Ks A) + θ h + (θ + ψ)(h0 − h)`:
///
/// ```text
/// Kn I θ = V h0 + n u + w (V / (Ks A) + θ h / 2)                    (base joint)
/// Kn I ψ = V (h0 − h) + n (V / (Ks A) + (θ + ψ)(h0 − h))              (beam joint)
/// ```
///
/// and the stiffness is `V / (2 V / (Ks A) + θ h + (θ + ψ)(hm − h))` (at `hm = h0`, `V / u`).
/// Without vertical load, read at the wall's top, it is `1 / (2 / (Ks A) + h0 h / (Kn I))`.
/// The block is rigid (the DEM's blocks are) and the joints stay closed (while
/// `V h0 < N_total L / 6`).
#[allow(clippy::too_many_arguments)]
pub fn one_block_stiffness(l: f64, t: f64, h: f64, h0: f64, hm: f64, kn: f64, ks: f64, n: f64, w: f64) -> f64 {
    let (a, i) = (l * t, t * l.powi(3) / 12.0);
    let (kr, c) = (kn * i, 1.0 / (ks * a));
    let e = h0 - h;
    // Unknowns (V, θ, ψ) for u = 1: rows base joint, beam joint, kinematics.
    let m = nalgebra::Matrix3::new(
        -(h0 + w * c),
        kr - w * h / 2.0,
        0.0,
        -(e + n * c),
        -n * e,
        kr - n * e,
        2.0 * c,
        h + e,
        e,
    );
    let rhs = nalgebra::Vector3::new(n, 0.0, 1.0);
    match m.lu().solve(&rhs) {
        Some(x) => x[0] / (2.0 * x[0] * c + x[1] * h + (x[1] + x[2]) * (hm - h)),
        None => f64::NAN,
    }
}
