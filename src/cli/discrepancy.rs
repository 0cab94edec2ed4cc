//! `drystone discrepancy` and `drystone synthesize`.

use anyhow::{bail, Context, Result};
use drystone::discrepancy::{synthetic_master_seed, synthetic_observables, SynthesisRequest};
use drystone::discrepancy::{write_synthetic, Settings};
use drystone::effects::Effect;
use drystone::io::table::{read_measured_collapse, read_measured_displacement};
use drystone::study::discrepancy::{analyse, input_of, observations_of, setup_of, write_analysis};
use drystone::study::HeldDir;
use drystone::study::Study;
use drystone::study::{estimated_blocks, human_seconds, simulation_seconds};

/// The longest `synthesize` may be estimated to take on this machine, seconds.
const MAX_SYNTHESIZE_SECONDS: f64 = 3600.0;
use std::path::{Path, PathBuf};

/// The study, output directory, threads and measured data of `drystone discrepancy` and
/// `drystone design`.
#[derive(clap::Args)]
pub struct AnalysisInput {
    /// Study file (TOML) with [measured] data (and an optional [discrepancy] table).
    pub study: PathBuf,
    /// Output directory. Default: out/<study name>-discrepancy, or out/<study
    /// name>-design for `drystone design`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads: 0 or absent means all cores. The results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Directory with measured data in the paper's format (as `drystone synthesize`
    /// writes), used instead of the study's [measured] files.
    #[arg(long)]
    pub measured: Option<PathBuf>,
    /// Directory of forward runs kept between commands and processes (made if absent):
    /// a run of the same build, study inputs, model and realization already in it is read
    /// instead of made again, the same bit for bit, and every run made is kept there.
    /// Default: `NAME-runs` beside the output directory (`out/NAME-runs` for the default
    /// output directories, NAME the study's name), so that `drystone discrepancy` and
    /// `drystone design` of one study read each other's runs; give the same directory to
    /// the analysis of the follow-up study a design writes, and each runs only what the
    /// others have not.
    #[arg(long, value_name = "DIR")]
    pub run_store: Option<PathBuf>,
    /// Keep no forward run and read none: every run is made (no run store).
    #[arg(long, conflicts_with = "run_store")]
    pub no_run_store: bool,
}

impl AnalysisInput {
    /// The run store of `--run-store`, or by default `NAME-runs` beside the output
    /// directory `out` of the study named `study_name` ([`default_store_dir`]), opened;
    /// `None` with `--no-run-store`.
    pub fn store(
        &self,
        out: &Path,
        study_name: &str,
    ) -> Result<Option<std::sync::Arc<drystone::discrepancy::RunStore>>> {
        if self.no_run_store {
            return Ok(None);
        }
        let dir = self.run_store.clone().unwrap_or_else(|| default_store_dir(out, study_name));
        Ok(Some(std::sync::Arc::new(drystone::discrepancy::RunStore::open(dir)?)))
    }
}

/// The default run store of a study named `study_name` whose analysis writes to `out`:
/// `NAME-runs` in `out`'s parent directory (`out/NAME-runs` for the default
/// `out/NAME-discrepancy` and `out/NAME-design`).
pub(crate) fn default_store_dir(out: &Path, study_name: &str) -> PathBuf {
    let parent = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or_else(|| Path::new("."));
    parent.join(format!("{study_name}-runs"))
}

/// The line a command prints of its run store: runs read and kept, and a warning when runs
/// could not be kept ([`drystone::discrepancy::RunStore::summary`]).
pub(crate) fn store_line(store: &Option<std::sync::Arc<drystone::discrepancy::RunStore>>) -> Option<String> {
    store.as_ref().map(|s| s.summary())
}

/// Options of `drystone discrepancy`.
#[derive(clap::Args)]
pub struct DiscrepancyArgs {
    #[command(flatten)]
    pub input: AnalysisInput,
    /// Realizations per group on the fitting grids, overriding the study file.
    #[arg(long)]
    pub realizations: Option<u64>,
    /// Directory of data sets of one design (subdirectories, each with the measured files):
    /// the forward runs are made once and every set is analysed against them, one JSON
    /// line per set (a power study).
    #[arg(long, conflicts_with = "measured")]
    pub measured_sets: Option<PathBuf>,
    /// Score candidates by their surrogates only (no full runs of the best two): faster,
    /// for power studies; the report says so.
    #[arg(long)]
    pub no_confirm: bool,
    /// Twice the realizations on the grids, the full runs and the independent layouts,
    /// and finer grids (6 intervals per axis, 4 nodes per axis of two-parameter
    /// effects): about three times the cost of the defaults, for a final answer.
    #[arg(long)]
    pub thorough: bool,
    /// Print one JSON object: verdict, cause, candidates, baseline, extended.
    #[arg(long)]
    pub json: bool,
}

pub(crate) fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let n = threads.unwrap_or(0);
    let n = if n == 0 { 0 } else { n.min(4 * std::thread::available_parallelism().map_or(1, |c| c.get())) };
    Ok(rayon::ThreadPoolBuilder::new().num_threads(n).build()?)
}

/// Replaces the study's measured data by the two files of `dir` (as `synthesize` writes).
pub(crate) fn use_measured_dir(st: &mut Study, dir: &Path) -> Result<()> {
    let c = dir.join("tilting_table_collapse.csv");
    let d = dir.join("tilting_table_displacement.csv");
    st.measured.collapse = read_measured_collapse(&c)?;
    st.measured.displacement = if d.exists() { read_measured_displacement(&d)? } else { vec![] };
    let m = dir.join(drystone::io::measured::MECHANISM_FILE);
    st.measured.mechanism = if m.exists() { drystone::io::table::read_measured_mechanism(&m)? } else { vec![] };
    st.check_measured()?;
    Ok(())
}

/// The progress of a long command (`discrepancy`, `calibrate`): its lines on stderr, as
/// `COMMAND: line`, when stderr is not a terminal (a batch log then shows the command
/// advancing; a terminal has the progress bars); warnings (`warning: …`) always.
pub fn progress_lines(command: &'static str) -> impl Fn(&str) + Sync {
    use std::io::IsTerminal;
    let terminal = std::io::stderr().is_terminal();
    move |line: &str| {
        if line.starts_with("warning:") {
            eprintln!("{line}");
        } else if !terminal {
            eprintln!("{command}: {line}");
        }
    }
}

/// Runs the analysis and writes its report; prints the JSON object or a summary. Every
/// study takes this one path ([`drystone::study::discrepancy::analyse`]); what its protocol
/// declares ([`drystone::study::discrepancy::AnalysisWay`]) is where its measured data come
/// from, how its study becomes the analysis's input, its reading the fit does not hold and
/// whether a named cause is written as an extended study.
pub fn discrepancy(a: DiscrepancyArgs) -> Result<()> {
    let mut st = Study::from_file(&a.input.study)?;
    if let Some(elsewhere) = st.protocol.analysis().measured_elsewhere {
        if a.input.measured.is_some() || a.measured_sets.is_some() {
            bail!(
                "{}: --measured and --measured-sets read the tilting table's files; {elsewhere}",
                a.input.study.display()
            );
        }
    }
    if let Some(dir) = &a.input.measured {
        use_measured_dir(&mut st, dir)?;
    }
    // The study's inputs it accepts and does not read, as `drystone run` warns of them.
    for w in st.warnings() {
        eprintln!("warning: {w}");
    }
    let mut s: Settings = st.discrepancy.clone();
    apply_options(&a, &mut s)?;
    s.validate().with_context(|| a.input.study.display().to_string())?;
    if let Some(dir) = &a.measured_sets {
        return measured_sets(&mut st, &s, dir, a.input.threads);
    }
    let mut input = input_of(&st, s)?;
    let dir = a.input.out.clone().unwrap_or_else(|| PathBuf::from("out").join(format!("{}-discrepancy", st.name)));
    input.setup.store = a.input.store(&dir, &st.name)?;
    // The directory is held from here to the end: a second command on it is refused.
    let held = HeldDir::acquire(&dir)?;
    let pool = pool(a.input.threads)?;
    let t0 = std::time::Instant::now();
    let progress = progress_lines("discrepancy");
    let done = pool.install(|| analyse(&st, input, &progress))?;
    if let Some(line) = store_line(&done.input.setup.store) {
        eprintln!("{line}");
    }
    let extended_study = write_analysis(&held, &st, &done)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&done.json())?);
        return Ok(());
    }
    print_summary(&done.run, &st.name, pool.current_num_threads(), t0.elapsed().as_secs_f64(), &dir);
    for line in done.held.iter().flat_map(|c| &c.summary) {
        println!("{line}");
    }
    if let Some(p) = extended_study {
        println!("extended model: drystone run {}", p.display());
    }
    Ok(())
}

/// The summary `drystone discrepancy` prints: verdict, cause, gain and the candidates.
fn print_summary(run: &drystone::discrepancy::Run, name: &str, threads: usize, seconds: f64, dir: &Path) {
    let an = &run.analysis;
    println!(
        "discrepancy {}: {} observations of {} specimens, {} candidates, {} threads, {:.1} s -> {}",
        name,
        run.obs.len(),
        run.specimens.len(),
        an.candidates.len(),
        threads,
        seconds,
        dir.display()
    );
    println!("verdict: {}", an.verdict.name());
    if let Some(c) = &an.cause {
        let p: Vec<String> = c.parameters.iter().map(|(k, v)| format!("{k} = {v:.4e}")).collect();
        println!(
            "{}: {} ({})",
            if an.verdict == drystone::discrepancy::Verdict::Explained { "cause" } else { "partial explanation" },
            c.name,
            p.join(", ")
        );
        if an.tie.len() > 1 {
            println!("indistinguishable from: {}", an.tie[1..].join(", "));
        }
    }
    for f in &an.refuted {
        println!("refuted by the {}: {} ({})", f.reading, f.candidate, f.words);
    }
    if let Some((g, lo, hi)) = run.gain {
        println!(
            "held-out error {:.3} -> {:.3} (gain {g:.3}, 95 % interval [{lo:.3}, {hi:.3}])",
            an.baseline_heldout_error,
            an.baseline_heldout_error - g
        );
    }
    println!("{:<28} {:>14} {:>10}  parameters", "candidate", "held-out error", "AICc");
    println!("{:<28} {:>14.3} {:>10.1}", "baseline", an.baseline_heldout_error, an.baseline_information_criterion);
    for c in &an.candidates {
        let p: Vec<String> = c.parameters.iter().map(|(k, v)| format!("{k} = {v:.3e}")).collect();
        println!("{:<28} {:>14.3} {:>10.1}  {}", c.name, c.heldout_error, c.information_criterion, p.join(", "));
    }
    let runs: Vec<String> = an.forward_runs.iter().map(|r| format!("{} {}", r.stage, r.runs)).collect();
    let total: usize = an.forward_runs.iter().map(|r| r.runs).sum();
    println!("forward runs: {total} ({})", runs.join(", "));
    println!("report: {}", dir.join("discrepancy.md").display());
}

/// The settings of `a` applied to `s` (`--thorough`, `--realizations`, `--no-confirm`).
fn apply_options(a: &DiscrepancyArgs, s: &mut Settings) -> Result<()> {
    if a.thorough {
        s.thorough();
    }
    if let Some(n) = a.realizations {
        if n == 0 {
            bail!("--realizations must be at least 1");
        }
        s.realizations = n;
        s.extension_realizations = s.extension_realizations.max(n + 3);
    }
    if a.no_confirm {
        s.confirm = false;
    }
    Ok(())
}

/// Analyses every data set (a subdirectory with the two measured files) of `dir` against
/// one preparation of the forward runs, printing one JSON line per set: each set's
/// observations as the study's protocol reads them ([`input_of`]), the groups of the
/// first.
fn measured_sets(st: &mut Study, s: &Settings, dir: &Path, threads: Option<usize>) -> Result<()> {
    let mut sets: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("tilting_table_collapse.csv").exists())
        .collect();
    sets.sort();
    if sets.is_empty() {
        bail!("{}: no data set (a subdirectory with tilting_table_collapse.csv)", dir.display());
    }
    let mut all = Vec::new();
    let mut first = None;
    for set in &sets {
        use_measured_dir(st, set)?;
        let input = input_of(st, s.clone()).with_context(|| set.display().to_string())?;
        all.push(input.obs);
        first.get_or_insert(input.setup);
    }
    let template: Vec<_> = all.iter().flatten().cloned().collect();
    let Some(setup) = first else { bail!("{}: no data set", dir.display()) };
    let pool = pool(threads)?;
    let progress = progress_lines("discrepancy");
    let prepared =
        pool.install(|| drystone::discrepancy::prepare_with(&setup, &template, s, &st.library, &progress))?;
    for (set, obs) in sets.iter().zip(all) {
        let name = set.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        progress(&format!("data set {name}"));
        let run = pool.install(|| drystone::discrepancy::analyze_with(&prepared, obs, st.seed, &progress))?;
        let an = &run.analysis;
        let line = serde_json::json!({
            "set": name,
            "verdict": an.verdict.name(),
            "cause": an.cause.as_ref().map(|c| c.name.split('+').map(str::to_string).collect::<Vec<_>>()),
            "tie": an.tie,
            "parameters": an.cause.as_ref().map(|c| c.parameters.clone()),
        });
        println!("{line}");
    }
    Ok(())
}

/// Options of `drystone synthesize`.
#[derive(clap::Args)]
pub struct SynthesizeArgs {
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
}

/// `drystone synthesize`: [`synthesize`].
///
/// # Errors
/// Those of [`synthesize`].
pub fn synthesize_command(a: SynthesizeArgs) -> Result<()> {
    synthesize(&a.study, a.effect.as_deref(), a.seed, a.specimens, a.out)
}

/// Writes synthetic measured data with hidden effects.
pub fn synthesize(study: &Path, effects: Option<&str>, seed: u64, specimens: u64, out: Option<PathBuf>) -> Result<()> {
    let st = Study::from_file(study)?;
    if specimens == 0 || specimens > 10_000 {
        bail!("--specimens must be in [1, 10000], got {specimens}");
    }
    let s = &st.discrepancy;
    let setup = setup_of(&st, specimens);
    let course_m = drystone::discrepancy::course_height(&setup);
    let effects: Vec<Effect> = match effects {
        None => vec![],
        Some(text) => text.split(',').map(|e| st.library.parse(e.trim(), course_m)).collect::<Result<_, _>>()?,
    };
    let mut names = std::collections::BTreeSet::new();
    for e in &effects {
        if !names.insert(e.name().to_string()) {
            bail!("--effect: {} is given twice; give each effect once", e.name());
        }
    }
    let threads = rayon::current_num_threads().max(1) as f64;
    let blocks: f64 = st.groups.iter().flat_map(|g| g.walls.iter()).map(estimated_blocks).fold(0.0, f64::max);
    let cost = simulation_seconds(specimens as f64 * st.groups.len() as f64, blocks) / threads;
    if cost > MAX_SYNTHESIZE_SECONDS {
        bail!(
            "--specimens {specimens}: {} simulations of walls of up to about {blocks:.0} blocks would take about {} on {threads} thread(s); the limit is {} (give fewer --specimens)",
            specimens * st.groups.len() as u64,
            human_seconds(cost),
            human_seconds(MAX_SYNTHESIZE_SECONDS)
        );
    }
    eprintln!(
        "synthesize: {} simulations, about {} on {threads} thread(s)",
        specimens * st.groups.len() as u64,
        human_seconds(cost)
    );
    let template = observations_of(&st, s.sigma).unwrap_or_default();
    let req = SynthesisRequest {
        effects: effects.clone(),
        seed,
        specimens,
        sigma: s.sigma,
        reading: s.reading,
        observables: synthetic_observables(&setup, &template),
    };
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-synthetic-{seed}", st.name)));
    let (c, d) = drystone::discrepancy::synthesize(&setup, &req);
    write_synthetic(&dir, &c, &d)?;
    let labels: Vec<String> = effects.iter().map(|e| e.label()).collect();
    println!(
        "synthetic data of {}: {} specimens per group, effects [{}], master seed {} (the study's is {}): {} collapse angles, {} displacements -> {}",
        st.name,
        specimens,
        labels.join(", "),
        synthetic_master_seed(seed, st.seed),
        st.seed,
        c.len(),
        d.len(),
        dir.display()
    );
    println!("analyse with: drystone discrepancy {} --measured {}", study.display(), dir.display());
    Ok(())
}
