//! Study files: which walls, how many realizations, the master seed, the protocol, a sweep
//! over parameters (a cartesian grid) and the measured data to compare with.
//!
//! A study is TOML, strict, `version = 1`, read into a raw [`StudySpec`] and resolved into a
//! checked [`Study`] (every wall generated from its description with the sweep's overrides,
//! every measured file read) before anything runs:
//!
//! ```toml
//! version = 1
//! name = "tilting_table"
//! seed = 2021
//! realizations = 16          # per group and sweep point
//! protocol = "tilt"          # the tilting table, or "lateral" (static pressure)
//!
//! [tilt]                     # optional, TiltParams (degrees)
//! step_deg = 0.5
//!
//! [lateral]                  # optional, LateralParams (protocol "lateral"; Pa)
//! pressure_base_pa = 1000.0
//! pressure_top_pa = 500.0
//! pushover = false           # true: also the collapse load multiplier (DEM and limit)
//!
//! [solver]                   # optional, SolverParams
//! damping = 0.8
//!
//! [[groups]]
//! name = "SBL"
//! wall = "walls/sbl.toml"    # path relative to this file
//! measured_group = "SBL"     # optional, default: the group name
//!
//! [sweep]                    # optional: every combination is a sweep point
//! kn_pa_per_m = [2.5e7, 5.0e7]
//! friction_deg = [30, 40]
//!
//! [measured]                 # optional, paths relative to this file
//! collapse = "../data/paper/tilting_table_collapse.csv"
//! displacement = "../data/paper/tilting_table_displacement.csv"
//! ```
//!
//! Sweep (and per-group `overrides`) keys act on the wall description:
//!
//! | key | effect | unit |
//! | --- | --- | --- |
//! | `kn_pa_per_m` | Kn of every material; Ks follows at the material's own Ks/Kn unless `ks_over_kn` is set | Pa/m |
//! | `ks_over_kn` | Ks = ratio × Kn for every material | – |
//! | `friction_deg` | φ of every material | degrees |
//! | `cohesion_pa` | cohesion of every material | Pa |
//! | `length_m` | wall length L | m |
//! | `arrangement` | `continuous`, `discontinuous` or `irregular` | – |
//! | `ends` | `free`, or `rigid` (every block within the wall's end zone, or [`DEFAULT_END_ZONE_M`] if it has none, held in y) | – |
//! | `motion`, `pga_g` | set by `[shake]`, not in `[sweep]`: a shaking study's motion and PGA level (they act on the protocol) | –, g |
//!
//! A shaking study (`protocol = "shake"`, `[solver] kind = "nscd"`) runs every realization
//! under every motion of its `[shake]` table scaled to every PGA level (incremental
//! dynamic analysis; [`ShakeSpec`]); its report fits the fragility against PGA and draws
//! the static capacity of the same walls beside it (`shaking`):
//!
//! ```toml
//! protocol = "shake"
//! [solver]
//! kind = "nscd"
//! [shake]
//! pga_g = [0.2, 0.4, 0.8]
//! records = ["records/RSN1.AT2"]           # and/or
//! stochastic = { count = 10, duration_s = 5.0 }
//! tail_s = 1.0
//! ```
//!
//! A group may fix its own `realizations` (e.g. 1 for a wall without random input).
//!
//! The modules, in the order a study goes through them: `spec` (the file as written),
//! `resolve` (checked into a [`Study`], with `size` its limits, `provenance` the
//! files it was read from, `read_warnings` the settings it accepts but does not read and
//! `inplane_spec` the in-plane test's keys), `sweep` (the keys and their effect), `run` (one row per
//! realization), `shaking` (the report of a shaking study), `shards` (the run directory, its journal, shards and their merge),
//! `summary` (statistics per group and sweep point), `report` (`report.md` and plots),
//! `paper` (the source paper's tables and figures), [`calibrate`] and `suite`.

pub mod calibrate;
mod checks;
pub mod compression;
pub mod discrepancy;
mod error;
mod estimate;
mod extend;
mod figures;
pub mod followup;
pub mod inplane;
pub mod inplane_discrepancy;
mod inplane_error;
pub mod inplane_loops;
mod inplane_measured;
mod inplane_report;
pub mod inplane_run;
pub mod inplane_spec;
mod lock;
mod measured;
mod motions;
mod outputs;
mod paper;
mod protocol;
mod protocol_table;
mod provenance;
mod read_warnings;
mod report;
mod report_error;
mod resolve;
mod run;
mod shaking;
mod shards;
mod size;
mod solver;
mod spec;
mod static_tables;
mod suite;
mod summary;
mod survey;
mod survey_spec;
mod sweep;
mod text;

pub use error::{CalibrationSpecError, NameError, PaperSpecError, StudyError};
pub use extend::{write_extended, ExtendError, FittedParameter};
pub use figures::write_vtk_realizations;
pub use outputs::{
    verify as verify_outputs, write_named_set, CommandManifest, HeldDir, OutputFile, SetNames, VerifyError,
};
pub use protocol::{StudyKind, StudyProtocol};
pub use protocol_table::ProtocolTable;
pub use provenance::{sha256_hex, InputFile, InputRole, MaterializeError, BUILD, VERSION};
pub use report::write_report;
pub use report_error::ReportError;
pub use resolve::{Group, Measured, ShakeStudy};
pub use run::{run_item, run_study, run_study_with};
pub use shaking::{fragilities, GroupFragility};
pub use shards::{
    check_writable, merge, read_shards, run_into, run_into_observed, write_outputs, Manifest, Merged, OutputError,
    RunMode, StudyRun,
};
pub use size::{
    check_blocks, estimated_blocks, human_bytes, human_seconds, machine_memory, simulation_seconds, SizeError,
    SizeEstimate, BYTES_PER_BLOCK, MAX_BLOCKS,
};
pub use spec::{GroupSpec, MeasuredSpec, ProtocolKind, ShakeSpec, StudySpec};
pub use suite::{is_suite, run_suite, run_suite_with, Suite, SuiteError, SuiteOutcome};
pub use survey_spec::SurveyImportSpec;
pub use sweep::{point_label, SweepEntryError, SweepError, SweepKey, SweepPoint, SweepValue, DEFAULT_END_ZONE_M};

/// A checked study.
#[derive(Debug, Clone)]
pub struct Study {
    /// Name.
    pub name: String,
    /// Description.
    pub description: String,
    /// The study file.
    pub path: std::path::PathBuf,
    /// Master seed.
    pub seed: u64,
    /// Realizations per group and point.
    pub realizations: u64,
    /// The protocol with its parameters.
    pub protocol: protocol::StudyProtocol,
    /// Solver parameters.
    pub solver: crate::dem::SolverParams,
    /// Groups.
    pub groups: Vec<resolve::Group>,
    /// Sweep points (one empty point without a sweep).
    pub points: Vec<sweep::SweepPoint>,
    /// Measured data.
    pub measured: resolve::Measured,
    /// The paper's study reproduced, if any.
    pub paper: Option<spec::PaperStudy>,
    /// Calibration steps.
    pub calibrate: Vec<spec::CalibrateSpec>,
    /// Model-discrepancy settings (defaults where the file has no `[discrepancy]`).
    pub discrepancy: crate::discrepancy::Settings,
    /// The files the study was resolved from (study, effect files, walls, distributions,
    /// measured data), with their hashes and texts: the provenance a run records.
    pub inputs: Vec<provenance::InputFile>,
    /// The effect library: the built-ins and the study's effect files.
    pub library: crate::effects::Library,
    /// Inputs the study accepts but does not use, found when it was read (each names its
    /// key); [`Study::warnings`] adds the protocol's.
    pub read_warnings: Vec<String>,
}
