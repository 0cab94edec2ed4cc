//! The solver flags several subcommands share: `--solver` (with the deprecated switches
//! of the penalty cascade on the tilting-table commands) and the `--nscd-*` settings of
//! the non-smooth solver.

use anyhow::{bail, Result};
use drystone::dem::{LimitParams, Method, SolverKind};
use drystone::loading::lateral::LateralParams;
use drystone::loading::tilt::TiltParams;
use drystone::nscd::{NscdParams, NsgsNorm, RestRule, StepSolver};

/// `--solver NAME`.
pub fn parse_solver(name: &str) -> Result<SolverKind, String> {
    name.parse()
}

/// The lateral load's trapezoidal pressure (`drystone lateral`, `drystone limit --protocol
/// lateral`), Pa; defaults those of `[lateral]`.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct Pressure {
    /// Lateral pressure at the base of the wall, Pa.
    #[arg(long, default_value_t = LateralParams::default().pressure_base_pa)]
    pub pressure_base_pa: f64,
    /// Lateral pressure at the top of the wall, Pa.
    #[arg(long, default_value_t = LateralParams::default().pressure_top_pa)]
    pub pressure_top_pa: f64,
}

impl Pressure {
    /// The lateral load `base` with this pressure.
    pub fn apply(self, base: LateralParams) -> LateralParams {
        LateralParams { pressure_base_pa: self.pressure_base_pa, pressure_top_pa: self.pressure_top_pa, ..base }
    }
}

/// `--solver` of the commands whose default is the penalty DEM (`tilt`, `lateral`,
/// `in-plane`, `bench tilt`).
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct SolverChoice {
    /// Solver: `penalty` (the default: the penalty DEM with the protocol's own static
    /// method), `newton` (penalty DEM, a semi-smooth Newton solve of each static increment
    /// before the protocol's own method; about 4 times the default's CPU on a tilt,
    /// BENCHMARKS.md), `implicit`, `accelerated` or `relaxation`
    /// (penalty DEM, one static method forced), `nscd` (non-smooth contact dynamics, rigid
    /// joints), `limit` (limit analysis, rigid joints); `kind` in a study's [solver] table.
    #[arg(long, default_value = "penalty", value_parser = parse_solver)]
    pub solver: SolverKind,
}

/// The solver flags of the tilting-table commands (`tilt`, `bench tilt`): the solver and the
/// deprecated switches of the penalty cascade, which keep working with a deprecation line.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct SolverArgs {
    #[command(flatten)]
    choice: SolverChoice,
    /// Deprecated (`--solver relaxation`): without the secant acceleration of slow creep
    /// and its stability indicator.
    #[arg(long, hide = true)]
    no_acceleration: bool,
    /// Deprecated (`--solver accelerated`): without the implicit relaxation of each
    /// increment.
    #[arg(long, hide = true)]
    no_implicit: bool,
}

impl SolverArgs {
    /// The solver kind, after printing the deprecation line of an old switch given.
    pub fn kind(self) -> SolverKind {
        if self.no_implicit || self.no_acceleration {
            let instead = if self.no_acceleration && self.no_implicit { "relaxation" } else { "accelerated" };
            let flag = if self.no_implicit { "--no-implicit" } else { "--no-acceleration" };
            eprintln!("warning: {flag} is deprecated; the solver is chosen with --solver (here: --solver {instead})");
        }
        self.choice.solver
    }

    /// The tilting table's parameters with the old switches applied (`accelerate`,
    /// `implicit`).
    pub fn tilt_params(self) -> TiltParams {
        TiltParams { accelerate: !self.no_acceleration, implicit: !self.no_implicit, ..TiltParams::default() }
    }
}

/// The non-smooth solver's NSGS settings on the command line (`--solver nscd`; the keys of
/// a study's `[solver.nscd]` table): each overrides [`NscdParams`]' default when given.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct NscdArgs {
    /// What a step of a wall at rest does with `--solver nscd`: `certify` (the default: by
    /// statics where the contacts carry the load inside the reduced Coulomb cones, without
    /// sweeps) or `solve` (always sweep) (docs/nscd.md).
    #[arg(long, value_name = "RULE", value_parser = parse_rest)]
    pub nscd_rest: Option<RestRule>,
    /// NSGS convergence norm of `--solver nscd`: `adaptive` (the default: the velocity norm,
    /// and the quadratic norm too once a step has done --nscd-quad-after-solves local
    /// solves), `velocity` or `quad` (docs/nscd.md).
    #[arg(long, value_name = "NORM", value_parser = parse_norm)]
    pub nscd_norm: Option<NsgsNorm>,
    /// NSGS tolerance of `--solver nscd` in its norm (velocity: over g h [default 1e-7];
    /// quad: dimensionless).
    #[arg(long, value_name = "TOL")]
    pub nscd_tolerance: Option<f64>,
    /// The quadratic norm's tolerance of the adaptive norm [default 1e-4].
    #[arg(long, value_name = "TOL")]
    pub nscd_quad_tolerance: Option<f64>,
    /// Local solves of a step after which the adaptive norm accepts the quadratic norm
    /// [default 1.5e5].
    #[arg(long, value_name = "SOLVES")]
    pub nscd_quad_after_solves: Option<f64>,
    /// Largest number of NSGS sweeps (and APGD iterations) per step [default 2000].
    #[arg(long, value_name = "SWEEPS")]
    pub nscd_max_iterations: Option<u32>,
    /// The method of a step of motion with `--solver nscd`: `apgd` (the default: the
    /// sweeps, then the accelerated projected gradient to the natural-map residual) or
    /// `nsgs` (the sweeps alone, stopped by --nscd-norm) (docs/nscd.md).
    #[arg(long, value_name = "METHOD", value_parser = parse_step_solver)]
    pub nscd_step_solver: Option<StepSolver>,
    /// The natural-map residual every step of motion meets with `apgd` [default 1e-4].
    #[arg(long, value_name = "TOL")]
    pub nscd_natural_tolerance: Option<f64>,
}

/// Limit analysis's settings on the command line (`--solver limit`, `drystone limit`; the
/// keys of a study's `[solver.limit]` table): each overrides [`LimitParams`]' default when
/// given.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct LimitFlags {
    /// Limit analysis: the associative answer only, without the non-associative correction
    /// (`non_associative = false`).
    #[arg(long)]
    pub limit_associative: bool,
    /// Limit analysis: the largest number of cone programs of the non-associative
    /// iteration [default 20].
    #[arg(long, value_name = "N")]
    pub limit_max_iterations: Option<u32>,
    /// Limit analysis: the under-relaxation of the normal forces in the non-associative
    /// iteration, in [0.1, 1] [default 0.5].
    #[arg(long, value_name = "OMEGA")]
    pub limit_relaxation: Option<f64>,
    /// Limit analysis: the non-associative iteration's tolerance on λ [default 1e-5].
    #[arg(long, value_name = "TOL")]
    pub limit_tolerance: Option<f64>,
}

impl LimitFlags {
    /// Some option was given.
    pub fn given(&self) -> bool {
        self.limit_associative
            || self.limit_max_iterations.is_some()
            || self.limit_relaxation.is_some()
            || self.limit_tolerance.is_some()
    }

    /// `base` with the options given; out-of-range values are refused by the analysis
    /// (`LimitParams::validate`, naming the key).
    pub fn apply(&self, base: LimitParams) -> LimitParams {
        LimitParams {
            non_associative: base.non_associative && !self.limit_associative,
            max_iterations: self.limit_max_iterations.unwrap_or(base.max_iterations),
            relaxation: self.limit_relaxation.unwrap_or(base.relaxation),
            tolerance: self.limit_tolerance.unwrap_or(base.tolerance),
        }
    }

    /// `base` with the options given, for the solver `kind`.
    ///
    /// # Errors
    /// An option given with a solver other than `limit`, which would ignore it.
    pub fn params_for(&self, kind: SolverKind, base: LimitParams) -> Result<LimitParams> {
        only_with(
            kind,
            SolverKind::Limit,
            self.given(),
            "the --limit-* options set limit analysis: give them with --solver limit",
        )?;
        Ok(self.apply(base))
    }
}

/// Refuses a solver's own options (`given`) with another solver: `kind` is the solver chosen,
/// `own` the one the options set.
///
/// # Errors
/// `message` when the options are given and `kind` is not `own` (it would ignore them).
fn only_with(kind: SolverKind, own: SolverKind, given: bool, message: &str) -> Result<()> {
    if given && kind != own {
        bail!("{message}");
    }
    Ok(())
}

/// Refuses an option of a command that the chosen solver's method does not read: `flag`
/// (`given` on the command line) sets `what`, which only the methods `readers` read; `kind`
/// is the solver chosen.
///
/// # Errors
/// Naming `flag`, what it sets, the method that would ignore it and what to do (drop it, or
/// choose a solver that reads it), when it is given and `kind`'s method is not a reader.
pub fn only_with_methods(kind: SolverKind, readers: &[Method], flag: &str, given: bool, what: &str) -> Result<()> {
    let method = kind.method();
    if given && !readers.contains(&method) {
        let solvers: Vec<&str> = readers.iter().map(|m| m.kind().name()).collect();
        bail!(
            "{flag} sets {what}, which {} (--solver {}) does not read: drop {flag}, or choose --solver {}",
            method.describe(),
            kind.name(),
            solvers.join(" or ")
        );
    }
    Ok(())
}

/// `--nscd-rest NAME`.
fn parse_rest(name: &str) -> Result<RestRule, String> {
    match name {
        "certify" => Ok(RestRule::Certify),
        "solve" => Ok(RestRule::Solve),
        other => Err(format!("{other:?}: expected certify or solve")),
    }
}

/// `--nscd-step-solver NAME`.
fn parse_step_solver(name: &str) -> Result<StepSolver, String> {
    match name {
        "apgd" => Ok(StepSolver::Apgd),
        "nsgs" => Ok(StepSolver::Nsgs),
        other => Err(format!("{other:?}: expected apgd or nsgs")),
    }
}

/// `--nscd-norm NAME`.
fn parse_norm(name: &str) -> Result<NsgsNorm, String> {
    match name {
        "adaptive" => Ok(NsgsNorm::Adaptive),
        "velocity" => Ok(NsgsNorm::Velocity),
        "quad" => Ok(NsgsNorm::Quad),
        other => Err(format!("{other:?}: expected adaptive, velocity or quad")),
    }
}

impl NscdArgs {
    /// Some option was given.
    pub fn given(&self) -> bool {
        self.nscd_norm.is_some()
            || self.nscd_rest.is_some()
            || self.nscd_tolerance.is_some()
            || self.nscd_quad_tolerance.is_some()
            || self.nscd_quad_after_solves.is_some()
            || self.nscd_max_iterations.is_some()
            || self.nscd_step_solver.is_some()
            || self.nscd_natural_tolerance.is_some()
    }

    /// `base` with the options given; out-of-range values are refused by the solver
    /// (`NscdParams::validate`, naming the key).
    pub fn apply(&self, base: NscdParams) -> NscdParams {
        NscdParams {
            rest: self.nscd_rest.unwrap_or(base.rest),
            norm: self.nscd_norm.unwrap_or(base.norm),
            tolerance: self.nscd_tolerance.unwrap_or(base.tolerance),
            quad_tolerance: self.nscd_quad_tolerance.unwrap_or(base.quad_tolerance),
            quad_after_solves: self.nscd_quad_after_solves.unwrap_or(base.quad_after_solves),
            max_iterations: self.nscd_max_iterations.unwrap_or(base.max_iterations),
            step_solver: self.nscd_step_solver.unwrap_or(base.step_solver),
            natural_tolerance: self.nscd_natural_tolerance.unwrap_or(base.natural_tolerance),
            ..base
        }
    }

    /// Refuses the options of a step of motion (`--nscd-step-solver`,
    /// `--nscd-natural-tolerance`, `--nscd-rest`) for a command whose nscd runs only
    /// release trials (`what`: the tilting table, the table rolled by hand), which take
    /// the NSGS sweeps alone and never certify rest (`NscdParams::for_trials`): they set
    /// the shaking table's steps.
    ///
    /// # Errors
    /// The first of those options given, by name.
    pub fn refuse_motion_options(&self, what: &str) -> Result<()> {
        for (flag, given) in [
            ("--nscd-step-solver", self.nscd_step_solver.is_some()),
            ("--nscd-natural-tolerance", self.nscd_natural_tolerance.is_some()),
            ("--nscd-rest", self.nscd_rest.is_some()),
        ] {
            if given {
                bail!(
                    "{flag} sets a step of motion of the shaking table (drystone shake; solver.nscd in a shaking \
                     study) and is not read by {what}: its release trials take the NSGS sweeps alone (--nscd-norm, \
                     --nscd-tolerance, --nscd-max-iterations) and never certify rest (docs/nscd.md); drop {flag}"
                );
            }
        }
        Ok(())
    }

    /// `base` with the options given, for the solver `kind`.
    ///
    /// # Errors
    /// An option given with a solver other than `nscd`, which would ignore it.
    pub fn params_for(&self, kind: SolverKind, base: NscdParams) -> Result<NscdParams> {
        only_with(
            kind,
            SolverKind::Nscd,
            self.given(),
            "the --nscd-* options set the non-smooth solver: give them with --solver nscd",
        )?;
        Ok(self.apply(base))
    }
}
