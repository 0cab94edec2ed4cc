//! The `drystone` command line. Thin: parsing, printing, exit codes. `anyhow` lives here only.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use drystone::dem::{DensityScaling, SolverParams};
use drystone::layout::Layout;
use drystone::loading::lateral::{run_lateral, LateralParams};
use drystone::loading::tilt::{run_tilt, TiltParams};
use std::path::PathBuf;
use std::process::ExitCode;

mod cli;

/// `println!` that ends the program quietly when stdout is closed (e.g. piped into `head`)
/// instead of panicking.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout(), $($t)*).is_err() {
            std::process::exit(0);
        }
    }};
}

#[derive(Parser)]
#[command(name = "drystone", version, about = "Out-of-plane collapse of dry stone walls with a rigid-block DEM")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Tilting-table test of a layout to collapse.
    Tilt {
        /// Layout file (JSON).
        layout: PathBuf,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Tilt increment, degrees.
        #[arg(long, default_value_t = TiltParams::default().step_deg)]
        step_deg: f64,
        /// Width of the final collapse bracket, degrees.
        #[arg(long, default_value_t = TiltParams::default().resolution_deg)]
        resolution_deg: f64,
        /// Local damping coefficient.
        #[arg(long, default_value_t = SolverParams::default().damping)]
        damping: f64,
        /// Sub-contact subdivisions per fan-triangle edge.
        #[arg(long, default_value_t = SolverParams::default().subcontact_subdivisions)]
        subdivisions: u32,
        /// Fraction of the critical time-step bound used, in (0, 1].
        #[arg(long, default_value_t = SolverParams::default().timestep_safety)]
        timestep_safety: f64,
        /// Density scaling: `block` (6 × 6 per body), `scalar` or `off` (`density_scaling` in
        /// a study's [solver] table); an increment whose block-scaled dynamics blow up is
        /// repeated with scalar scaling.
        #[arg(long, default_value = "block")]
        density_scaling: String,
        /// Share of the scalar-scaled mass in each block mass (`block` scaling), in (0, 10].
        #[arg(long, default_value_t = SolverParams::default().density_scaling.mass_floor())]
        block_mass_floor: f64,
        /// Unbalanced-force ratio of equilibrium.
        #[arg(long, default_value_t = TiltParams::default().tolerance)]
        tolerance: f64,
        /// Start every increment from the last stable state at rest instead of the secant
        /// prediction of its equilibrium (`predictor = false` in a study's [tilt] table).
        #[arg(long)]
        no_predictor: bool,
    },
    /// Static lateral load: a trapezoidal pressure on the wall face (pushing towards +y),
    /// solved to equilibrium; prints the top displacements and the drift.
    Lateral {
        /// Layout file (JSON).
        layout: PathBuf,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Pressure at the base of the wall, Pa.
        #[arg(long, default_value_t = LateralParams::default().pressure_base_pa)]
        pressure_base_pa: f64,
        /// Pressure at the top of the wall, Pa.
        #[arg(long, default_value_t = LateralParams::default().pressure_top_pa)]
        pressure_top_pa: f64,
        /// Unbalanced-force ratio of equilibrium.
        #[arg(long, default_value_t = LateralParams::default().tolerance)]
        tolerance: f64,
    },
    /// Runs a study (ensembles of realizations) and writes tables, plots and a report.
    Run {
        /// Study file (TOML).
        study: PathBuf,
        /// Output directory. Default: out/<study name>.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads. Default: all cores.
        #[arg(long)]
        threads: Option<usize>,
        /// Run only shard K of N (1-based, e.g. 3/8 for a job array); merge with `drystone merge`.
        #[arg(long)]
        shard: Option<String>,
        /// Realizations per group and sweep point, overriding the study file.
        #[arg(long)]
        realizations: Option<u64>,
        /// For a suite (e.g. studies/paper.toml): run every study at its own full size
        /// instead of the suite's reduced default.
        #[arg(long)]
        full: bool,
    },
    /// Calibrates joint parameters (Kn, φ) of a study's walls against the measured collapse
    /// angles, step by step as its [[calibrate]] table says (Brent root finding, argmin).
    Calibrate {
        /// Study file (TOML) with [[calibrate]] steps.
        study: PathBuf,
        /// Output directory. Default: out/<study name>.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads. Default: all cores.
        #[arg(long)]
        threads: Option<usize>,
        /// Realizations per evaluation, overriding the study file.
        #[arg(long)]
        realizations: Option<u64>,
    },
    /// Merges shard directories of one study run into what an unsharded run writes.
    Merge {
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Shard directories.
        #[arg(required = true)]
        shards: Vec<PathBuf>,
    },
    /// Closed-form verification cases; exit status 1 if any is out of tolerance.
    Verify {
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Generates a wall layout from a wall description (TOML), a seed and a realization index.
    Generate {
        /// Wall description, e.g. studies/walls/sbl.toml.
        wall: PathBuf,
        /// Master seed.
        #[arg(long)]
        seed: u64,
        /// Realization index.
        #[arg(long, default_value_t = 0)]
        realization: u64,
        /// Output file, format by extension: .json (layout for `drystone tilt`), .vtk (ParaView), .svg (drawing).
        #[arg(long)]
        out: PathBuf,
        /// Directory of named distributions [default: the nearest `distributions/` at or above the wall file].
        #[arg(long)]
        distributions: Option<PathBuf>,
    },
    /// Model discrepancy: what the simulation gets wrong against the study's measured data,
    /// the physical effect that explains it (from a library of candidate effects, ranked by
    /// held-out error with margins calibrated on null data), the extended model and its gain.
    Discrepancy {
        /// Study file (TOML) with [measured] data (and an optional [discrepancy] table).
        study: PathBuf,
        /// Output directory. Default: out/<study name>-discrepancy.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads; 0 or absent: all cores.
        #[arg(long)]
        threads: Option<usize>,
        /// Realizations per group on the fitting grids, overriding the study file.
        #[arg(long)]
        realizations: Option<u64>,
        /// Directory with measured data in the paper's format (as `drystone synthesize`
        /// writes), used instead of the study's [measured] files.
        #[arg(long)]
        measured: Option<PathBuf>,
        /// Print one JSON object: verdict, cause, candidates, baseline, extended.
        #[arg(long)]
        json: bool,
    },
    /// Synthetic measured data: the study's walls built with seeds the study does not use,
    /// hidden effects applied, tilted to collapse, with measurement noise; written in the
    /// format of the paper's data files (a power analysis for planning tests).
    Synthesize {
        /// Study file (TOML).
        study: PathBuf,
        /// Hidden effects, `NAME=VALUE[,NAME=VALUE]` (two-parameter effects `NAME=V1:V2`);
        /// absent: null data from the baseline model.
        #[arg(long)]
        effect: Option<String>,
        /// Seed of the synthetic specimens and noise.
        #[arg(long)]
        seed: u64,
        /// Specimens per group.
        #[arg(long, default_value_t = 3)]
        specimens: u64,
        /// Output directory. Default: out/<study name>-synthetic-<seed>.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Benchmarks: `cube16` (the paper's Table 6 element-cost case: `--steps` engine steps of
    /// 16 boxes) or `tilt` (tilting-table tests to collapse of a generated wall, one after
    /// the other on one thread: by default the SBL preset, seed 20210917, realization 0;
    /// `--realizations N` runs realizations 0..N and gives the totals).
    Bench {
        /// Which benchmark: `cube16` or `tilt`.
        case: String,
        /// Steps to time (`cube16`).
        #[arg(long, default_value_t = 20_000)]
        steps: u64,
        /// Wall description (`tilt`).
        #[arg(long, default_value = "studies/walls/sbl.toml")]
        wall: PathBuf,
        /// Master seed of the wall (`tilt`).
        #[arg(long, default_value_t = 20210917)]
        seed: u64,
        /// Realizations 0..N of the wall, run one after the other (`tilt`). A single
        /// realization's step count moves by ±10 % with any change of the numerics (the
        /// near-collapse trials are path-sensitive); compare changes on the total of several.
        #[arg(long, default_value_t = 1)]
        realizations: u64,
        /// Without the secant predictor of the tilting table (`tilt`; for comparison).
        #[arg(long)]
        no_predictor: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run() -> Result<ExitCode> {
    let cli = Cli::parse();
    match cli.command {
        Command::Tilt {
            layout,
            json,
            step_deg,
            resolution_deg,
            damping,
            subdivisions,
            timestep_safety,
            density_scaling,
            block_mass_floor,
            tolerance,
            no_predictor,
        } => {
            let l = Layout::from_file(&layout)?;
            let density_scaling = match density_scaling.as_str() {
                "block" => DensityScaling::Block { mass_floor: block_mass_floor },
                "scalar" => DensityScaling::Scalar,
                "off" => DensityScaling::Off,
                other => bail!("--density-scaling {other}: expected block, scalar or off"),
            };
            let solver = SolverParams {
                damping,
                subcontact_subdivisions: subdivisions,
                timestep_safety,
                density_scaling,
                ..SolverParams::default()
            };
            let params =
                TiltParams { step_deg, resolution_deg, tolerance, predictor: !no_predictor, ..TiltParams::default() };
            let r =
                run_tilt(&l, solver, &params).with_context(|| format!("tilting-table test of {}", layout.display()))?;
            if json {
                out!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                out!("layout            {}", layout.display());
                out!(
                    "collapse angle    {:.2} deg (last stable), first unstable {}",
                    r.collapse_angle_deg,
                    r.first_unstable_deg.map_or("none".into(), |a| format!("{a:.2} deg"))
                );
                out!(
                    "mechanism         {:?} at joint {} ({} blocks moving)",
                    r.mechanism.kind,
                    r.mechanism.joint,
                    r.mechanism.blocks.len()
                );
                out!("steps             {}  (dt {:.3e} s, wall time {:.2} s)", r.steps, r.dt_s, r.wall_time_s);
                if !r.scalar_fallbacks_deg.is_empty() {
                    let at: Vec<String> = r.scalar_fallbacks_deg.iter().map(|a| format!("{a:.3}")).collect();
                    out!(
                        "block scaling     blew up at {} deg; repeated with scalar scaling, kept from there on",
                        at.join(", ")
                    );
                }
                out!("out-of-plane displacement of the top points [cm]:");
                out!("  alpha_deg  {}", r.monitors.join("  "));
                for inc in r.increments.iter().filter(|i| i.stable) {
                    let d: Vec<String> = inc.displacement_m.iter().map(|d| format!("{:>9.3}", d * 100.0)).collect();
                    out!("  {:>9.2}  {}", inc.alpha_deg, d.join("  "));
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Lateral { layout, json, pressure_base_pa, pressure_top_pa, tolerance } => {
            let l = Layout::from_file(&layout)?;
            let params = LateralParams { pressure_base_pa, pressure_top_pa, tolerance, ..LateralParams::default() };
            let r = run_lateral(&l, SolverParams::default(), &params)
                .with_context(|| format!("static lateral load on {}", layout.display()))?;
            if json {
                out!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                out!("layout            {}", layout.display());
                out!(
                    "load              {:.0} Pa at the base, {:.0} Pa at the top: resultant {:.1} N in y ({:.3} of the weight {:.1} N), {} loaded faces",
                    pressure_base_pa,
                    pressure_top_pa,
                    r.resultant_n.y,
                    r.resultant_n.y / r.weight_n,
                    r.weight_n,
                    r.loaded_faces
                );
                match &r.collapse_reason {
                    None => out!("equilibrium       yes (unbalanced-force ratio {:.2e})", r.unbalanced_ratio),
                    Some(why) => out!("equilibrium       NO: collapsed ({why})"),
                }
                out!("top displacement  [cm]");
                for (m, d) in r.monitors.iter().zip(&r.displacement_m) {
                    out!("  {m:<12} {:>9.4}", d * 100.0);
                }
                out!("  {:<12} {:>9.4}", "max", r.max_displacement_m * 100.0);
                out!("drift             {:.3e} (max / H, H = {:.3} m)", r.drift, r.height_m);
                out!("steps             {}  (dt {:.3e} s, wall time {:.2} s)", r.steps, r.dt_s, r.wall_time_s);
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Run { study, out, threads, shard, realizations, full } => {
            if drystone::study::suite::is_suite(&study) {
                if shard.is_some() || realizations.is_some() {
                    bail!(
                        "{}: --shard and --realizations apply to single studies; a suite takes --full",
                        study.display()
                    );
                }
                let suite = drystone::study::suite::Suite::from_file(&study, full)?;
                let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&suite.name));
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build()?;
                let t0 = std::time::Instant::now();
                let report = pool.install(|| drystone::study::suite::run_suite(&suite, &dir, |line| out!("{line}")))?;
                out!(
                    "suite {}: {} studies on {} threads in {:.1} s -> {}",
                    suite.name,
                    suite.studies.len(),
                    pool.current_num_threads(),
                    t0.elapsed().as_secs_f64(),
                    report.display()
                );
                return Ok(ExitCode::SUCCESS);
            }
            if full {
                bail!("{}: --full applies to suites only", study.display());
            }
            let mut st = drystone::study::Study::from_file(&study)?;
            if let Some(n) = realizations {
                if n == 0 {
                    bail!("--realizations must be at least 1");
                }
                st.realizations = n;
            }
            let shard = match shard {
                Some(s) => drystone::ensemble::Shard::parse(&s).map_err(anyhow::Error::msg)?,
                None => drystone::ensemble::Shard::ALL,
            };
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build()?;
            let t0 = std::time::Instant::now();
            let rows = pool.install(|| drystone::study::run::run_study(&st, shard));
            let elapsed = t0.elapsed().as_secs_f64();
            let text = drystone::study::run::write_outputs(&st, &study, shard, &rows, &dir)?;
            let failed = rows.iter().filter(|r| !r.status.is_ok()).count();
            out!(
                "study {}: {} realizations ({} failed) on {} threads in {:.1} s -> {}",
                st.name,
                rows.len(),
                failed,
                pool.current_num_threads(),
                elapsed,
                dir.display()
            );
            if let Some(t) = text {
                out!("{t}");
                out!("report: {}", dir.join("report.md").display());
            } else {
                out!("shard written; join the shards with `drystone merge --out DIR SHARD_DIRS...`");
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Calibrate { study, out, threads, realizations } => {
            let mut st = drystone::study::Study::from_file(&study)?;
            if st.calibrate.is_empty() {
                bail!("{}: no [[calibrate]] steps", study.display());
            }
            if let Some(n) = realizations {
                if n == 0 {
                    bail!("--realizations must be at least 1");
                }
                st.realizations = n;
            }
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build()?;
            let t0 = std::time::Instant::now();
            let results = pool
                .install(|| drystone::study::calibrate::calibrate(&st, &st.calibrate))
                .map_err(|m| anyhow::anyhow!("{}: {m}", study.display()))?;
            let md = drystone::study::suite::write_calibration(&st, &results, &dir)?;
            out!("{md}");
            out!(
                "calibration {}: {} steps on {} threads in {:.1} s -> {}",
                st.name,
                results.len(),
                pool.current_num_threads(),
                t0.elapsed().as_secs_f64(),
                dir.join("calibration.md").display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Merge { out, shards } => {
            let (manifest, rows) = drystone::study::run::read_shards(&shards)?;
            let mut st = drystone::study::Study::from_file(&manifest.study)?;
            st.realizations = manifest.realizations;
            let text =
                drystone::study::run::write_outputs(&st, &manifest.study, drystone::ensemble::Shard::ALL, &rows, &out)?;
            out!("merged {} shards, {} realizations -> {}", shards.len(), rows.len(), out.display());
            if let Some(t) = text {
                out!("{t}");
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Verify { json } => {
            let rep = drystone::verify::run_all();
            if json {
                out!("{}", serde_json::to_string_pretty(&rep)?);
            } else {
                out!("{:<70} {:>9} {:>9} {:>8}  {:<4} {}", "case", "expected", "simulated", "error", "ok", "mechanism");
                for c in &rep.cases {
                    out!(
                        "{:<70} {:>9.3} {:>9.3} {:>+8.3}  {:<4} {}",
                        c.name,
                        c.expected_deg,
                        c.simulated_deg,
                        c.error_deg,
                        if c.ok { "ok" } else { "FAIL" },
                        c.detail
                    );
                }
                out!();
                out!("{:<50} {:>14} {:>14} {:>10} {:<4}", "check", "expected", "simulated", "rel.err", "ok");
                for c in &rep.checks {
                    out!(
                        "{:<50} {:>14.6e} {:>14.6e} {:>10.2e} {:<4} [{}]",
                        c.name,
                        c.expected,
                        c.simulated,
                        c.relative_error,
                        if c.ok { "ok" } else { "FAIL" },
                        c.unit
                    );
                }
            }
            Ok(if rep.all_ok() { ExitCode::SUCCESS } else { ExitCode::from(1) })
        }
        Command::Generate { wall, seed, realization, out, distributions } => {
            use drystone::generator::{generate, DistributionSource, Wall};
            use drystone::io::OutputFormat;
            let Some(format) = OutputFormat::from_path(&out) else {
                bail!("--out {}: unknown extension; use .json, .vtk or .svg", out.display());
            };
            let source = distributions.map_or_else(|| DistributionSource::default_for(&wall), DistributionSource::dir);
            let w = Wall::from_file_with(&wall, &source)?;
            let t0 = std::time::Instant::now();
            let g = generate(&w, seed, realization)?;
            let dt = t0.elapsed().as_secs_f64();
            g.check()?;
            std::fs::write(&out, drystone::io::render(&g, &w, format)?)
                .with_context(|| format!("writing {}", out.display()))?;
            let (stones, wedges) = g.counts();
            out!("wall              {} ({})", w.name, wall.display());
            out!("seed, realization {seed}, {realization}");
            out!(
                "blocks            {} ({stones} stones, {wedges} wedges) in {} courses",
                stones + wedges,
                g.course_tops_m.len()
            );
            out!(
                "volume            {:.6} m3 of {:.6} m3 (void {:.3} %, stated {:.3} %)",
                g.volume(),
                g.envelope_volume_m3,
                100.0 * g.void_fraction(),
                100.0 * g.stated_void_fraction
            );
            out!("generated in      {:.2} ms", dt * 1e3);
            out!("wrote             {}", out.display());
            Ok(ExitCode::SUCCESS)
        }
        Command::Discrepancy { study, out, threads, realizations, measured, json } => {
            cli::discrepancy::discrepancy(cli::discrepancy::DiscrepancyArgs {
                study,
                out,
                threads,
                realizations,
                measured,
                json,
            })?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Synthesize { study, effect, seed, specimens, out } => {
            cli::discrepancy::synthesize(&study, effect.as_deref(), seed, specimens, out)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench { case, wall, seed, json, no_predictor, realizations, .. } if case == "tilt" => {
            use drystone::generator::{generate, DistributionSource, Wall};
            if realizations == 0 {
                bail!("--realizations must be at least 1");
            }
            let w = Wall::from_file_with(&wall, &DistributionSource::default_for(&wall))?;
            let params = TiltParams { predictor: !no_predictor, ..TiltParams::default() };
            if !json {
                out!(
                    "tilt: {}, seed {seed}, realizations 0..{realizations}, one thread, predictor {}",
                    wall.display(),
                    if params.predictor { "on" } else { "off" }
                );
            }
            let mut runs = Vec::new();
            let (mut steps, mut time) = (0u64, 0.0);
            for k in 0..realizations {
                let layout = generate(&w, seed, k)?.check()?;
                let r = run_tilt(&layout, SolverParams::default(), &params)?;
                let per_step = 1e6 * r.wall_time_s / r.steps as f64;
                steps += r.steps;
                time += r.wall_time_s;
                if !json {
                    out!(
                        "  realization {k} ({} blocks): alpha_max {:.4} deg (first unstable {}), {} steps of {:.3e} s, {:.2} s ({per_step:.1} us/step)",
                        layout.blocks.len(),
                        r.collapse_angle_deg,
                        r.first_unstable_deg.map_or("none".into(), |a| format!("{a:.4} deg")),
                        r.steps,
                        r.dt_s,
                        r.wall_time_s
                    );
                }
                runs.push(serde_json::json!({
                    "realization": k, "blocks": layout.blocks.len(),
                    "collapse_angle_deg": r.collapse_angle_deg,
                    "first_unstable_deg": r.first_unstable_deg, "steps": r.steps, "dt_s": r.dt_s,
                    "wall_time_s": r.wall_time_s, "us_per_step": per_step,
                }));
            }
            let per_step = 1e6 * time / steps as f64;
            if json {
                let v = serde_json::json!({
                    "wall": wall.display().to_string(), "seed": seed, "realizations": realizations,
                    "predictor": params.predictor, "steps": steps, "wall_time_s": time,
                    "us_per_step": per_step, "runs": runs,
                });
                out!("{}", serde_json::to_string_pretty(&v)?);
            } else if realizations > 1 {
                out!(
                    "  total: {steps} steps, {time:.2} s ({per_step:.1} us/step); mean {:.0} steps, {:.2} s per test",
                    steps as f64 / realizations as f64,
                    time / realizations as f64
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench { case, steps, json, .. } => {
            if case != "cube16" {
                bail!("unknown benchmark {case:?}; available: cube16, tilt");
            }
            let r = drystone::benchmark::run_cube16(steps, SolverParams::default());
            if json {
                out!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                out!(
                    "cube16: {} bodies, {} contacts, {} sub-contacts, dt {:.3e} s",
                    r.bodies,
                    r.contacts,
                    r.sub_contacts,
                    r.dt_s
                );
                out!("  {} steps at {:.0} steps/s (one thread)", r.steps, r.steps_per_s);
                out!(
                    "  equilibrium (unbalanced-force ratio < 1e-4) after {} steps, {:.3} s",
                    r.steps_to_equilibrium,
                    r.equilibrium_wall_time_s
                );
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
