//! A capacity ensemble at the rigid limit: generate realizations of a wall description and
//! find each one's collapse load multiplier by limit analysis, in parallel over
//! realizations (rayon); print the statistics and the time.
//!
//! ```sh
//! cargo run --release --example limit_ensemble -- [WALL.toml [N [tilt|lateral [SEED]]]]
//! ```
//!
//! By default: the SBL preset (`studies/walls/sbl.toml`), 1000 realizations, the tilting
//! table, the seed of `studies/tilting_table.toml`. Each realization is generated with the
//! library's `generate(wall, seed, i)`, so realization i is the layout a study of that seed
//! runs; the numbers do not depend on the thread count (`RAYON_NUM_THREADS`).

use drystone::dem::SolverParams;
use drystone::generator::{generate, Wall};
use drystone::limit::{limit_lateral, limit_tilt, FlowRule, LimitParams};
use drystone::loading::lateral::LateralParams;
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let wall_file = args.first().map_or_else(|| PathBuf::from("studies/walls/sbl.toml"), PathBuf::from);
    let n: u64 = args.get(1).map_or(Ok(1000), |s| s.parse())?;
    let lateral = match args.get(2).map(String::as_str) {
        None | Some("tilt") => false,
        Some("lateral") => true,
        Some(other) => return Err(format!("protocol {other}: expected tilt or lateral").into()),
    };
    let seed: u64 = args.get(3).map_or(Ok(20210917), |s| s.parse())?;
    let wall = Wall::from_file(&wall_file)?;
    let solver = SolverParams::default();
    let params = LimitParams::default();
    let t0 = Instant::now();
    let rows: Vec<Result<(f64, f64, bool, usize, f64), String>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let t = Instant::now();
            let layout = generate(&wall, seed, i).map_err(|e| e.to_string())?.check().map_err(|e| e.to_string())?;
            let r = if lateral {
                limit_lateral(&layout, &solver, &LateralParams::default(), &params)
            } else {
                limit_tilt(&layout, &solver, &params)
            }
            .map_err(|e| format!("realization {i}: {e}"))?;
            let na = r.governing == FlowRule::NonAssociative;
            Ok((r.load_multiplier, r.associative, na, r.blocks, t.elapsed().as_secs_f64()))
        })
        .collect();
    let total = t0.elapsed().as_secs_f64();
    let ok: Vec<_> = rows.iter().filter_map(|r| r.as_ref().ok()).collect();
    for e in rows.iter().filter_map(|r| r.as_ref().err()).take(5) {
        eprintln!("failed: {e}");
    }
    let m = ok.len() as f64;
    let mean = |f: &dyn Fn(&(f64, f64, bool, usize, f64)) -> f64| ok.iter().map(|r| f(r)).sum::<f64>() / m;
    let lam = mean(&|r| r.0);
    let sd = (ok.iter().map(|r| (r.0 - lam).powi(2)).sum::<f64>() / (m - 1.0).max(1.0)).sqrt();
    let what = if lateral { "lateral pressure multiplier" } else { "tilt multiplier tan(alpha_max)" };
    println!("{}: {} of {n} realizations (seed {seed}), {what}", wall_file.display(), ok.len());
    println!("  lambda mean {lam:.4}, sd {sd:.4}, COV {:.3}", sd / lam);
    if !lateral {
        let deg: Vec<f64> = ok.iter().map(|r| r.0.atan().to_degrees()).collect();
        let md = deg.iter().sum::<f64>() / m;
        let sdd = (deg.iter().map(|d| (d - md).powi(2)).sum::<f64>() / (m - 1.0).max(1.0)).sqrt();
        println!("  alpha_max mean {md:.3} deg, sd {sdd:.3} deg");
    }
    println!(
        "  associative mean {:.4}; non-associative answer governs in {} realizations",
        mean(&|r| r.1),
        ok.iter().filter(|r| r.2).count()
    );
    println!(
        "  blocks per wall {:.0}; time per realization {:.1} ms (mean, one thread); total {total:.2} s on {} threads",
        mean(&|r| r.3 as f64),
        1e3 * mean(&|r| r.4),
        rayon::current_num_threads()
    );
    Ok(())
}
