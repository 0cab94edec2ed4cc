//! `drystone design`: the next experiment for a study's measured data.

use anyhow::{bail, Context, Result};
use drystone::discrepancy::design::{self, DesignSettings};
use drystone::discrepancy::Settings;
use drystone::study::discrepancy::{observations_of, setup_of, write_discrepancy};
use drystone::study::{HeldDir, Study};
use std::path::PathBuf;

/// Options of `drystone design`.
#[derive(clap::Args)]
pub struct DesignArgs {
    #[command(flatten)]
    pub input: super::discrepancy::AnalysisInput,
    /// Specimens of each follow-up (the budget they are compared at).
    #[arg(long, allow_hyphen_values = true, default_value_t = DesignSettings::default().specimens)]
    pub specimens: usize,
    /// Simulated follow-ups per contender taken as the truth.
    #[arg(long, allow_hyphen_values = true, default_value_t = DesignSettings::default().replicates)]
    pub replicates: usize,
    /// Probability of naming the cause alone a follow-up should reach (the report gives
    /// the fewest specimens that reach it).
    #[arg(long, allow_hyphen_values = true, default_value_t = DesignSettings::default().target)]
    pub target: f64,
    /// Score the analysis's candidates by their surrogates only (no full runs of the best
    /// two), as `drystone discrepancy --no-confirm`.
    #[arg(long)]
    pub no_confirm: bool,
    /// Print one JSON object: the discrepancy report's, with `followup`.
    #[arg(long)]
    pub json: bool,
}

/// Runs the discrepancy analysis, designs the next experiment, writes the report (with its
/// section "The next experiment"), `design/design.json` and the best follow-up as a study
/// under `design/followup/`.
pub fn command(a: DesignArgs) -> Result<()> {
    let mut st = Study::from_file(&a.input.study)?;
    if let Some(dir) = &a.input.measured {
        super::discrepancy::use_measured_dir(&mut st, dir)?;
    }
    // The study's inputs it accepts and does not read, as `drystone run` warns of them.
    for w in st.warnings() {
        eprintln!("warning: {w}");
    }
    let mut s: Settings = st.discrepancy.clone();
    if a.no_confirm {
        s.confirm = false;
    }
    s.validate().with_context(|| a.input.study.display().to_string())?;
    let ds =
        DesignSettings { specimens: a.specimens, replicates: a.replicates, target: a.target, ..Default::default() };
    // Named by the flag that sets it (the settings' keys, `design.KEY`, are no file's).
    ds.validate().map_err(|e| match e {
        drystone::discrepancy::DiscrepancyError::Setting { key, value, reason } => {
            let flag = key.strip_prefix("design.").unwrap_or(key).replace('_', "-");
            anyhow::anyhow!("drystone design: --{flag} {value}: must be {reason}")
        }
        other => anyhow::Error::new(other).context("drystone design"),
    })?;
    if st.protocol_at(0).name() != "tilt" {
        bail!(
            "{}: `drystone design` plans tilting-table follow-ups; this study's protocol is {}",
            a.input.study.display(),
            st.protocol_at(0).name()
        );
    }
    let obs = observations_of(&st, s.sigma)?;
    let mut setup = setup_of(&st, s.most_realizations());
    let dir = a.input.out.clone().unwrap_or_else(|| PathBuf::from("out").join(format!("{}-design", st.name)));
    setup.store = a.input.store(&dir, &st.name)?;
    let held = HeldDir::acquire(&dir)?;
    let pool = super::discrepancy::pool(a.input.threads)?;
    let t0 = std::time::Instant::now();
    let progress = super::discrepancy::progress_lines("design");
    let mut run = pool.install(|| drystone::discrepancy::run_with(&setup, obs, &s, st.seed, &st.library, &progress))?;
    let t1 = t0.elapsed().as_secs_f64();
    let menu = drystone::study::followup::menu(&st, &setup, &run)?;
    let plan = pool.install(|| design::design(&run, &setup, menu, &ds, st.seed, &progress))?;
    let t2 = t0.elapsed().as_secs_f64() - t1;
    run.followup = Some(plan.clone());
    write_discrepancy(&held, &st, &run)?;
    let ddir = held.path().join("design");
    std::fs::create_dir_all(&ddir).with_context(|| ddir.display().to_string())?;
    let json = serde_json::json!({ "verdict": run.analysis.verdict.name(), "tie": run.analysis.tie, "followup": plan });
    std::fs::write(ddir.join("design.json"), serde_json::to_string_pretty(&json)?)
        .with_context(|| ddir.join("design.json").display().to_string())?;
    std::fs::write(ddir.join("design.md"), design::markdown(&plan))
        .with_context(|| ddir.join("design.md").display().to_string())?;
    let files = drystone::study::followup::write_followup(
        &st,
        &plan,
        &ddir.join("followup"),
        ds.specimens,
        a.input.measured.as_deref(),
    )?;
    if let Some(line) = super::discrepancy::store_line(&setup.store) {
        eprintln!("{line}");
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&drystone::discrepancy::report_json(&run))?);
        return Ok(());
    }
    let an = &run.analysis;
    println!(
        "design {}: verdict {}, tie {:?}; analysis {t1:.1} s, design {t2:.1} s ({} forward runs), {} threads -> {}",
        st.name,
        an.verdict.name(),
        an.tie,
        plan.runs,
        pool.current_num_threads(),
        dir.display()
    );
    let (truths, others) = plan.contenders.split_at(plan.truths.min(plan.contenders.len()));
    let c: Vec<String> = truths.iter().map(|c| format!("{} {:.2}", c.name, c.prior)).collect();
    println!("contenders (taken as the truth): {}", c.join(", "));
    if !others.is_empty() {
        let o: Vec<&str> = others.iter().map(|c| c.name.as_str()).collect();
        println!("refit beside them: {}", o.join(", "));
    }
    println!("{:<70} {:>8} {:>8} {:>8} {:>10}", "follow-up", "alone", "90% wt", "right", "to target");
    for r in &plan.ranked {
        println!(
            "{:<70} {:>8.2} {:>8.2} {:>8.2} {:>10}",
            r.followup.name,
            r.at_budget.alone,
            r.at_budget.weights_alone,
            r.at_budget.right,
            r.to_target.map_or("-".to_string(), |n| n.to_string())
        );
    }
    if let (Some(b), Some(r)) = (plan.best(), &plan.reported) {
        println!(
            "promise of the best ({}): named alone {:.2} ({:.0} % interval {:.2}-{:.2}), re-estimated on {} fresh \
             replicates per truth (ranking's estimate {:.2})",
            b.followup.name,
            r.chance.alone,
            100.0 * design::Reported::LEVEL,
            r.interval.0,
            r.interval.1,
            r.replicates,
            r.selected
        );
        if r.misleads {
            eprintln!("warning: {}", design::misleading_words(r));
        }
    }
    if let Some(f) = files {
        println!(
            "follow-up study: {} (templates in {})",
            f.study.display(),
            f.templates[0].parent().map_or(String::new(), |p| p.display().to_string())
        );
    }
    Ok(())
}
