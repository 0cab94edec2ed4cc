//! The solver parameters of a simulation: one struct, every field with its unit and
//! default, and the density-scaling mode.

use super::contact::geometry::{Fan, PatchParams};
use super::contact::law::Quadrature;
use super::method::SolverKind;
use super::penalty::{MovedKey, PenaltyParams};
use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};

/// Density scaling for static solutions: fictitious inertial masses that leave the
/// weights unchanged and let every body relax at about the same rate (3DEC's density
/// scaling, Itasca 3DEC manual; see `dem::timestep`). Quasi-static results do not depend on
/// it; dynamics need `Off`.
///
/// In TOML: `density_scaling = { kind = "block", mass_floor = 0.05 }`, `{ kind = "scalar" }`
/// or `{ kind = "off" }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum DensityScaling {
    /// True masses.
    Off,
    /// Every body's mass and inertia scaled so that all bodies have the critical step of
    /// the median body (`dem::timestep::density_scaling`).
    Scalar,
    /// Each body's inertial mass is its own 6 × 6 contact-stiffness block plus `mass_floor`
    /// (in (0, 10]) times its scalar-scaled mass (block-Jacobi scaling,
    /// `dem::timestep::block_masses`). The tilting table repeats with `Scalar` (kept from
    /// there on) an increment whose block-scaled dynamics blow up; the static lateral load
    /// uses `Scalar`.
    Block {
        /// Share of the scalar-scaled mass added to each block mass, –.
        mass_floor: f64,
    },
}

impl DensityScaling {
    /// Whether masses are scaled at all.
    pub fn is_on(self) -> bool {
        !matches!(self, DensityScaling::Off)
    }

    /// `Scalar` in place of `Block`, otherwise unchanged.
    pub fn without_block(self) -> DensityScaling {
        match self {
            DensityScaling::Block { .. } => DensityScaling::Scalar,
            other => other,
        }
    }

    /// The block mass floor (1 for the other kinds, which have none).
    pub fn mass_floor(self) -> f64 {
        match self {
            DensityScaling::Block { mass_floor } => mass_floor,
            _ => 1.0,
        }
    }
}

/// `solver` with the former keys `moved` applied to its penalty settings.
pub fn with_moved(solver: SolverParams, moved: &[MovedKey]) -> SolverParams {
    let mut s = solver;
    for m in moved {
        m.value.apply(&mut s.penalty);
    }
    s
}

/// Parameters of a limit analysis (`kind = "limit"`; a `[solver.limit]` table in a study,
/// the `limit` key of a Python solver dict, `--limit-*` on the command line). Defaults in
/// brackets. The method itself is `crate::limit` (Gilbert, Casapulla & Ahmed 2006 for the
/// non-associative iteration); the parameters live beside the other methods' so that every
/// caller reaches them through [`SolverParams`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LimitParams {
    /// Run the non-associative correction when the associative mechanism slides \[true\].
    pub non_associative: bool,
    /// Largest number of cone programs of the non-associative iteration \[20\].
    pub max_iterations: u32,
    /// Under-relaxation ω of the normal forces in the iteration, in [0.1, 1] \[0.5\]. The
    /// iteration stops when λ changes by less than `tolerance` twice, and a change is
    /// proportional to ω: a smaller ω would stop it near the associative answer, a silently
    /// wrong λ.
    pub relaxation: f64,
    /// The iteration has converged when λ changes by less than this, relative to
    /// max(1, |λ|), twice in a row \[1e-5\].
    pub tolerance: f64,
}

impl Default for LimitParams {
    fn default() -> Self {
        LimitParams { non_associative: true, max_iterations: 20, relaxation: 0.5, tolerance: 1e-5 }
    }
}

impl LimitParams {
    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("max_iterations", self.max_iterations as f64, self.max_iterations >= 1, ">= 1"),
            ("relaxation", self.relaxation, (0.1..=1.0).contains(&self.relaxation), "in [0.1, 1]"),
            ("tolerance", self.tolerance, self.tolerance > 0.0 && self.tolerance < 1.0, "in (0, 1)"),
        ])
    }
}

/// Solver parameters. Every field has a documented default (`SolverParams::default()`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverParams {
    /// The solver (`kind = "penalty"` in a study's `[solver]` table, `--solver` on the
    /// command line; see [`SolverKind`]). Default `penalty`: the penalty DEM with each
    /// protocol's default static method. The other fields are the penalty DEM's.
    pub kind: SolverKind,
    /// Local damping coefficient α, dimensionless in [0, 1). Default 0.8 (3DEC, YADE).
    pub damping: f64,
    /// Fraction of the critical time step `2 / (ω_max √(1 + α))` used, with ω_max the
    /// assembly's highest frequency (an upper estimate) and α the local damping (see
    /// `dem::timestep`). Default 0.95.
    pub timestep_safety: f64,
    /// Pairs closer than this get a contact, m. Default 0.001.
    pub contact_margin_m: f64,
    /// Vertices within this distance of the support plane form an edge/vertex feature, m.
    /// Default 0.0005.
    pub feature_tolerance_m: f64,
    /// Faces within this angle of the contact normal form a face feature, degrees. Default 10.
    pub face_angle_tolerance_deg: f64,
    /// Sub-contact density: subdivisions of each fan triangle of a contact polygon per
    /// edge, ≥ 1 (each fan triangle becomes `m²` sub-contacts; see [`Self::fan`]). Each
    /// sub-contact carries one shear spring at its centroid, so `m` sets how well a joint
    /// resists twist about its normal: at 1 a quadrilateral joint has two springs (62 % of
    /// its frictional torque), at 2 eight (95 %). Default 1, which is not converged for
    /// every wall: the main job's SBR walls collapse 0.25–0.5° later at 2 and 3 than at 1
    /// (README, "The model": sub-contacts).
    pub subcontact_subdivisions: u32,
    /// Integration of the joint pressure over a sub-contact. Default `exact`.
    pub quadrature: Quadrature,
    /// Nominal width of edge and vertex contacts, fraction of the smaller block's smallest
    /// dimension. Default 0.05.
    pub degenerate_width_fraction: f64,
    /// Contacts are re-detected when a body has moved this fraction of the margin. Default 0.5.
    pub redetect_fraction: f64,
    /// At a re-detection, a contact whose two bodies have moved relative to each other by
    /// less than this fraction of the re-detection distance (`redetect_fraction ×
    /// contact_margin_m`) since its patch was made keeps its patch and its history instead
    /// of being rebuilt; 0 rebuilds every contact. In [0, 1]. Default 0.1 (50 µm at the
    /// defaults: a patch is then at most 5 % staler than the re-detection distance already
    /// allows).
    pub patch_reuse_fraction: f64,
    /// Density scaling for static solutions. Default `Block { mass_floor: 0.05 }`.
    pub density_scaling: DensityScaling,
    /// Settings of the penalty DEM's solves (a `[solver.penalty]` table in a study), unused
    /// by nscd and limit analysis.
    pub penalty: PenaltyParams,
    /// Settings of the non-smooth contact-dynamics solver (`kind = "nscd"`; a
    /// `[solver.nscd]` table in a study), unused by the penalty DEM.
    pub nscd: super::nscd_params::NscdParams,
    /// Settings of limit analysis (`kind = "limit"`; a `[solver.limit]` table in a study),
    /// unused by the other solvers.
    pub limit: LimitParams,
}

impl Default for SolverParams {
    fn default() -> Self {
        SolverParams {
            kind: SolverKind::Penalty,
            damping: 0.8,
            timestep_safety: 0.95,
            contact_margin_m: 1e-3,
            feature_tolerance_m: 5e-4,
            face_angle_tolerance_deg: 10.0,
            subcontact_subdivisions: 1,
            quadrature: Quadrature::Exact,
            degenerate_width_fraction: 0.05,
            redetect_fraction: 0.5,
            patch_reuse_fraction: 0.1,
            density_scaling: DensityScaling::Block { mass_floor: 0.05 },
            penalty: PenaltyParams::default(),
            nscd: super::nscd_params::NscdParams::default(),
            limit: LimitParams::default(),
        }
    }
}

impl SolverParams {
    /// [`Self::face_angle_tolerance_deg`] in radians.
    pub fn face_angle_tolerance_rad(&self) -> f64 {
        self.face_angle_tolerance_deg.to_radians()
    }

    /// The narrow phase's share of the parameters.
    pub fn patch(&self) -> PatchParams {
        PatchParams {
            contact_margin_m: self.contact_margin_m,
            feature_tolerance_m: self.feature_tolerance_m,
            face_angle_tolerance_rad: self.face_angle_tolerance_rad(),
            degenerate_width_fraction: self.degenerate_width_fraction,
            subcontact_subdivisions: self.subcontact_subdivisions,
            fan: self.fan(),
        }
    }

    /// How the narrow phase fans a contact polygon into triangles for this quadrature:
    /// from a vertex for exact integration (a triangle from its centroid, [`Fan::Shear`]),
    /// from the centroid for the vertex quadrature.
    pub fn fan(&self) -> Fan {
        match self.quadrature {
            Quadrature::Exact => Fan::Shear,
            Quadrature::Vertex => Fan::Centroid,
        }
    }

    /// Checks the settings of the method [`Self::kind`] selects beyond those every run
    /// reads ([`Self::validate`]): nscd's table (keys `nscd.*`) for nscd; nothing more for
    /// the penalty DEM (its table is [`Self::validate`]'s) and limit analysis (whose table a
    /// study checks whatever the kind: it runs beside the other methods).
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate_method(&self) -> Result<(), OutOfRange> {
        match self.kind.method() {
            super::Method::Nscd => self.nscd.validate().map_err(|e| OutOfRange { key: format!("nscd.{}", e.key), ..e }),
            super::Method::Penalty | super::Method::Limit => Ok(()),
        }
    }

    /// Checks ranges for a static solution by dynamic relaxation (the settling, the tilting
    /// table, the static lateral load): those of [`Self::validate`], and local damping in
    /// (0, 1). Without damping the relaxation does not converge, and the undamped explicit
    /// scheme with contacts opening and closing can gain energy and blow up.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate_static(&self) -> Result<(), OutOfRange> {
        self.validate()?;
        check_ranges(&[(
            "damping",
            self.damping,
            self.damping > 0.0,
            "in (0, 1) for a static solution (dynamic relaxation needs local damping)",
        )])
    }

    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        self.penalty.validate().map_err(|e| OutOfRange { key: format!("penalty.{}", e.key), ..e })?;
        check_ranges(&[
            ("damping", self.damping, (0.0..1.0).contains(&self.damping), "in [0, 1)"),
            (
                "timestep_safety",
                self.timestep_safety,
                self.timestep_safety > 0.0 && self.timestep_safety <= 1.0,
                "in (0, 1]",
            ),
        ])?;
        check_ranges(&super::contact::geometry::detection_ranges(
            self.contact_margin_m,
            self.feature_tolerance_m,
            self.face_angle_tolerance_deg,
            self.redetect_fraction,
        ))?;
        check_ranges(&[
            (
                "degenerate_width_fraction",
                self.degenerate_width_fraction,
                self.degenerate_width_fraction > 0.0 && self.degenerate_width_fraction <= 1.0,
                "in (0, 1]",
            ),
            (
                "patch_reuse_fraction",
                self.patch_reuse_fraction,
                (0.0..=1.0).contains(&self.patch_reuse_fraction),
                "in [0, 1]",
            ),
            (
                "density_scaling.mass_floor",
                self.density_scaling.mass_floor(),
                self.density_scaling.mass_floor() > 0.0 && self.density_scaling.mass_floor() <= 10.0,
                "in (0, 10]",
            ),
            (
                "subcontact_subdivisions",
                self.subcontact_subdivisions as f64,
                (1..=64).contains(&self.subcontact_subdivisions),
                "an integer in [1, 64]",
            ),
        ])
    }
}
