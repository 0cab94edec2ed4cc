//! `drystone discrepancy` and `drystone synthesize`.

use anyhow::{bail, Context, Result};
use drystone::discrepancy::effects::Effect;
use drystone::discrepancy::{report, synthesize, Settings};
use drystone::io::table::{read_measured_collapse, read_measured_displacement};
use drystone::study::discrepancy::{observations_of, setup_of};
use drystone::study::size::{estimated_blocks, human_seconds, simulation_seconds};
use drystone::study::Study;

/// The longest `synthesize` may be estimated to take on this machine, seconds.
const MAX_SYNTHESIZE_SECONDS: f64 = 3600.0;
use std::path::{Path, PathBuf};

/// Options of `drystone discrepancy`.
pub struct DiscrepancyArgs {
    pub study: PathBuf,
    pub out: Option<PathBuf>,
    pub threads: Option<usize>,
    pub realizations: Option<u64>,
    pub measured: Option<PathBuf>,
    pub json: bool,
}

fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let n = threads.unwrap_or(0);
    let n = if n == 0 { 0 } else { n.min(4 * std::thread::available_parallelism().map_or(1, |c| c.get())) };
    Ok(rayon::ThreadPoolBuilder::new().num_threads(n).build()?)
}

/// Replaces the study's measured data by the two files of `dir` (as `synthesize` writes).
fn use_measured_dir(st: &mut Study, dir: &Path) -> Result<()> {
    let c = dir.join("tilting_table_collapse.csv");
    let d = dir.join("tilting_table_displacement.csv");
    st.measured.collapse = read_measured_collapse(&c)?;
    st.measured.displacement = if d.exists() { read_measured_displacement(&d)? } else { vec![] };
    st.check_measured()?;
    Ok(())
}

/// Runs the analysis and writes its report; prints the JSON object or a summary.
pub fn discrepancy(a: DiscrepancyArgs) -> Result<()> {
    let mut st = Study::from_file(&a.study)?;
    if let Some(dir) = &a.measured {
        use_measured_dir(&mut st, dir)?;
    }
    let mut s: Settings = st.discrepancy.clone();
    if let Some(n) = a.realizations {
        if n == 0 {
            bail!("--realizations must be at least 1");
        }
        s.realizations = n;
        s.extension_realizations = s.extension_realizations.max(n + 3);
    }
    s.validate().with_context(|| a.study.display().to_string())?;
    let obs = observations_of(&st, s.sigma)?;
    let setup = setup_of(&st, s.realizations.max(s.extension_realizations), &s);
    let dir = a.out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-discrepancy", st.name)));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create the output directory {}", dir.display()))?;
    let pool = pool(a.threads)?;
    let t0 = std::time::Instant::now();
    let run = pool.install(|| drystone::discrepancy::run(&setup, obs, &s, st.seed))?;
    report::write(&dir, &run, &st.name)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report::to_json(&run))?);
        return Ok(());
    }
    let an = &run.analysis;
    println!(
        "discrepancy {}: {} observations of {} specimens, {} candidates, {} threads, {:.1} s -> {}",
        st.name,
        run.obs.len(),
        run.specimens.len(),
        an.candidates.len(),
        pool.current_num_threads(),
        t0.elapsed().as_secs_f64(),
        dir.display()
    );
    println!("verdict: {}", an.verdict.name());
    if let Some(c) = &an.cause {
        let p: Vec<String> = c.parameters.iter().map(|(k, v)| format!("{k} = {v:.4e}")).collect();
        println!("cause: {} ({})", c.effects.join("+"), p.join(", "));
        if an.tie.len() > 1 {
            println!("indistinguishable from: {}", an.tie[1..].join(", "));
        }
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
        println!(
            "{:<28} {:>14.3} {:>10.1}  {}",
            c.effects.join("+"),
            c.heldout_error,
            c.information_criterion,
            p.join(", ")
        );
    }
    println!("report: {}", dir.join("discrepancy.md").display());
    Ok(())
}

/// Writes synthetic measured data with hidden effects.
pub fn synthesize(study: &Path, effects: Option<&str>, seed: u64, specimens: u64, out: Option<PathBuf>) -> Result<()> {
    let st = Study::from_file(study)?;
    if specimens == 0 || specimens > 10_000 {
        bail!("--specimens must be in [1, 10000], got {specimens}");
    }
    let effects: Vec<Effect> = match effects {
        None => vec![],
        Some(text) => text.split(',').map(|e| Effect::parse(e.trim())).collect::<Result<_, _>>()?,
    };
    for (i, e) in effects.iter().enumerate() {
        if effects[..i].iter().any(|f| f.kind == e.kind) {
            bail!("--effect: {} is given twice; give each effect once", e.kind.name());
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
    let s = &st.discrepancy;
    let setup = setup_of(&st, specimens, s);
    let template = observations_of(&st, s.sigma).unwrap_or_default();
    let req = synthesize::Request {
        effects: effects.clone(),
        seed,
        specimens,
        sigma: s.sigma,
        observables: synthesize::observables_of(&setup, &template),
    };
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-synthetic-{seed}", st.name)));
    let (c, d) = synthesize::synthesize(&setup, &req);
    synthesize::write(&dir, &c, &d)?;
    let labels: Vec<String> = effects.iter().map(|e| e.label()).collect();
    println!(
        "synthetic data of {}: {} specimens per group, effects [{}], master seed {} (the study's is {}): {} collapse angles, {} displacements -> {}",
        st.name,
        specimens,
        labels.join(", "),
        synthesize::master_seed(seed, st.seed),
        st.seed,
        c.len(),
        d.len(),
        dir.display()
    );
    println!("analyse with: drystone discrepancy {} --measured {}", study.display(), dir.display());
    Ok(())
}
