//! How the sign of the service-displacement difference between joint arrangements depends
//! on what the source paper does not state: the block length and the load level.
//!
//! ```sh
//! cargo run --release --example joint_arrangement_sign -- [N [SEED]]
//! ```
//!
//! The full-scale walls of `studies/joint_arrangement.toml` (continuous, running bond,
//! irregular; L 4 m, H 1 m, ends restrained, Kn 1e8 Pa/m, c 100 kPa) with their blocks
//! `0.5 × s` m long (the irregular wall's lengths uniform in `[0.4 s, 0.6 s]` m), for
//! s = 0.4, 0.6, 1, 1.6, under the lateral pressure of the study (1.0 kPa at the base, 0.5 kPa
//! at the top) times a load level of 0.5, 1 and 3 (the DEM collapse multiplier of these
//! walls is 4.8 to 6.6: `studies/joint_arrangement_capacity.toml`). Each cell: the static lateral load
//! (`loading::lateral`) on the continuous and the running-bond wall (no random input) and
//! on N irregular realizations (default 3; the seed of the study); the table gives the top
//! displacement of each and the relative differences (continuous − running bond) / running
//! bond and (irregular mean − running bond) / running bond, with their signs. Rayon over
//! the runs; the numbers do not depend on the thread count.

use drystone::dem::SolverParams;
use drystone::generator::{generate, DistributionSource, Wall, WallSpec};
use drystone::loading::lateral::LateralParams;
use drystone::protocol::run_lateral;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

const SCALES: [f64; 4] = [0.4, 0.6, 1.0, 1.6];
const LEVELS: [f64; 3] = [0.5, 1.0, 3.0];
const ARRANGEMENTS: [&str; 3] = ["continuous", "discontinuous", "irregular"];

/// The preset of `arrangement` with its block lengths scaled by `s`.
fn wall(arrangement: &str, s: f64) -> Result<Wall, Box<dyn std::error::Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls");
    let file: PathBuf = match arrangement {
        "irregular" => dir.join("full_scale.toml"),
        a => dir.join(format!("full_scale_{a}.toml")),
    };
    let text = std::fs::read_to_string(&file)?;
    let text = if arrangement == "irregular" {
        let t = text.replace("length_m = \"block_length_full_scale\"", "length_m = \"block_length_scaled\"");
        format!(
            "{t}\n[distributions.block_length_scaled]\nunit = \"m\"\nkind = \"uniform\"\nmin = {}\nmax = {}\n",
            0.4 * s,
            0.6 * s
        )
    } else {
        text.replace("length_m = 0.5\n", &format!("length_m = {}\n", 0.5 * s))
    };
    let source = DistributionSource::default_for(&file);
    Ok(WallSpec::from_toml(&text, &file)?.resolve(&file, &source)?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().map_or(Ok(3), |s| s.parse())?;
    let seed: u64 = args.get(1).map_or(Ok(20210917), |s| s.parse())?;
    let t0 = Instant::now();
    // Every run: (scale index, level index, arrangement index, realization).
    let mut runs = Vec::new();
    for si in 0..SCALES.len() {
        for li in 0..LEVELS.len() {
            for (ai, a) in ARRANGEMENTS.iter().enumerate() {
                let count = if *a == "irregular" { n } else { 1 };
                runs.extend((0..count).map(|r| (si, li, ai, r)));
            }
        }
    }
    let walls: Vec<Vec<Wall>> = SCALES
        .iter()
        .map(|&s| ARRANGEMENTS.iter().map(|a| wall(a, s)).collect::<Result<Vec<_>, _>>())
        .collect::<Result<_, _>>()?;
    // The top displacement of each run, m; `None` if the wall collapsed under the load.
    let out: Vec<Result<(usize, usize, usize, Option<f64>), String>> = runs
        .par_iter()
        .map(|&(si, li, ai, r)| {
            let layout = generate(&walls[si][ai], seed, r)
                .and_then(|g| g.check())
                .map_err(|e| format!("{} s {}: {e}", ARRANGEMENTS[ai], SCALES[si]))?;
            let params = LateralParams {
                pressure_base_pa: 1000.0 * LEVELS[li],
                pressure_top_pa: 500.0 * LEVELS[li],
                ..LateralParams::default()
            };
            let res = run_lateral(&layout, SolverParams::default(), &params).map_err(|e| e.to_string())?;
            Ok((si, li, ai, res.equilibrium.then_some(res.max_displacement_m)))
        })
        .collect();
    for e in out.iter().filter_map(|r| r.as_ref().err()) {
        eprintln!("failed: {e}");
    }
    let ok: Vec<_> = out.iter().filter_map(|r| r.as_ref().ok()).collect();
    println!(
        "Top displacement (mm) under the lateral load of studies/joint_arrangement.toml times the level; irregular: mean of {n} realizations (seed {seed})"
    );
    println!("| block length (m) | level | continuous | running bond | irregular | (cont − rb)/rb | (irr − rb)/rb |");
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for (si, s) in SCALES.iter().enumerate() {
        for (li, l) in LEVELS.iter().enumerate() {
            // The mean over the runs of a cell, mm; `None` if any collapsed.
            let mean = |ai: usize| {
                let v: Option<Vec<f64>> =
                    ok.iter().filter(|r| r.0 == si && r.1 == li && r.2 == ai).map(|r| r.3.map(|d| 1e3 * d)).collect();
                v.filter(|v| !v.is_empty()).map(|v| v.iter().sum::<f64>() / v.len() as f64)
            };
            let show = |v: Option<f64>| v.map_or("collapsed".to_string(), |v| format!("{v:.4}"));
            let rel = |a: Option<f64>, d: Option<f64>| match (a, d) {
                (Some(a), Some(d)) => format!("{:+.0} %", 100.0 * (a - d) / d),
                _ => "–".to_string(),
            };
            let (c, d, i) = (mean(0), mean(1), mean(2));
            let len = if *s == 1.0 {
                "0.5 (irr. 0.4–0.6)".to_string()
            } else {
                format!("{:.2} (irr. {:.2}–{:.2})", 0.5 * s, 0.4 * s, 0.6 * s)
            };
            println!("| {len} | {l} | {} | {} | {} | {} | {} |", show(c), show(d), show(i), rel(c, d), rel(i, d));
        }
    }
    println!("{} runs in {:.1} s on {} threads", runs.len(), t0.elapsed().as_secs_f64(), rayon::current_num_threads());
    Ok(())
}
