//! Time of one limit analysis against the size of the wall: a wall description generated at
//! growing lengths (its height, section and joints kept), one realization each, the tilting
//! table.
//!
//! ```sh
//! cargo run --release --example limit_scaling -- [WALL.toml [SEED]]
//! ```
//!
//! By default the SBL preset (`studies/walls/sbl.toml`, about 110 stones per 1.5 m) at
//! lengths from 0.5 m to 30 m (about 2,000 blocks). Each size is timed over repeats
//! adding up to at least 0.2 s; the median is printed.

use drystone::dem::SolverParams;
use drystone::generator::{generate, Wall};
use drystone::limit::{limit_tilt, LimitParams};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let wall_file = args.first().map_or_else(|| PathBuf::from("studies/walls/sbl.toml"), PathBuf::from);
    let seed: u64 = args.get(1).map_or(Ok(20210917), |s| s.parse())?;
    let base = Wall::from_file(&wall_file)?;
    println!("{}: seed {seed}, realization 0, tilting table", wall_file.display());
    println!(
        "{:>8} {:>7} {:>9} {:>9} {:>10} {:>10} {:>8} {:>7}",
        "length_m", "blocks", "contacts", "points", "time_ms", "ms/block", "lambda", "repeats"
    );
    for length in [0.5, 1.5, 3.0, 6.0, 12.0, 20.0, 30.0] {
        let wall = Wall { length, ..base.clone() };
        let layout = generate(&wall, seed, 0)?.check()?;
        let mut times = Vec::new();
        let mut last = None;
        let t_all = Instant::now();
        while times.len() < 3 || (t_all.elapsed().as_secs_f64() < 0.2 && times.len() < 200) {
            let t = Instant::now();
            let r = limit_tilt(&layout, &SolverParams::default(), &LimitParams::default())?;
            times.push(t.elapsed().as_secs_f64());
            last = Some(r);
        }
        times.sort_by(f64::total_cmp);
        let med = times[times.len() / 2];
        let r = last.expect("timed at least once");
        println!(
            "{length:>8.1} {:>7} {:>9} {:>9} {:>10.2} {:>10.4} {:>8.4} {:>7}",
            r.blocks,
            r.contacts,
            r.contact_points,
            med * 1e3,
            med * 1e3 / r.blocks as f64,
            r.load_multiplier,
            times.len()
        );
    }
    Ok(())
}
