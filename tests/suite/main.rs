//! The integration tests, in one binary: each file of this folder is one module (one
//! subject: `nscd_motion`, `limit_analysis`, ...), and `cargo test --release --test suite
//! MODULE::` runs one of them. One binary links the library once instead of once per file,
//! and its tests share the cores: see BENCHMARKS.md, "The tests".

#[path = "../common/mod.rs"]
mod common;
#[path = "../realwalls/mod.rs"]
mod realwalls;
#[path = "../common/winkler.rs"]
mod winkler;
#[path = "../common/winkler_exact.rs"]
mod winkler_exact;

mod acceleration;
mod bad_inputs;
mod bad_inputs_hand;
mod bad_inputs_measured;
mod bad_inputs_mechanism;
mod bad_inputs_motion;
mod bad_inputs_read;
mod base_restraint;
mod bed_seating;
mod compression;
mod compression_study;
mod design;
mod determinism;
mod discrepancy;
mod discrepancy_cli;
mod discrepancy_engine;
mod discrepancy_realwalls;
mod dispatch;
mod effect_priors;
mod effects_in_studies;
mod fine_reference;
mod fuzz;
mod generator_bad_input;
mod generator_golden;
mod generator_presets;
mod generator_properties;
mod generator_stats;
mod implicit;
mod inplane;
mod inplane_discrepancy;
mod inplane_loops;
mod inplane_replay;
mod inplane_rig;
mod inplane_study;
mod inplane_whole;
mod joint_families;
mod lateral;
mod lateral_pushover;
mod layers;
mod layout_errors;
mod leaf_split;
mod limit_analysis;
mod limit_cli;
mod lmgc90_rigid_limits;
mod lmgc90_shake;
mod mechanism;
mod moved_keys;
mod nscd_cli;
mod nscd_motion;
mod nscd_residual;
mod nscd_rest;
mod nscd_rigid_limits;
mod nscd_solver_options;
mod own_mass;
mod paper_studies;
mod patch_reuse;
mod penalty_exact_winkler;
mod penalty_kn_sweep;
mod predictor;
mod provenance;
mod readings_only;
mod resume;
mod rope;
mod rope_tilt;
mod run_store;
mod sanity;
mod shake;
mod shake_penalty;
mod shake_study;
mod sizes;
mod slurm;
mod solver_seam;
mod stiff_end_budget;
mod stiffness_range;
mod studies;
mod survey;
mod survey_ensemble;
mod survey_large_stones;
mod survey_real_stones;
mod survey_traced_granite;
mod tilt_hand;
mod timestep;
mod verification;
mod vtk;
