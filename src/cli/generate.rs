//! `drystone generate`: one layout of a wall description.

use anyhow::{bail, Context, Result};
use drystone::generator::{generate, DistributionSource, Wall};
use drystone::io::OutputFormat;
use drystone::study::{check_blocks, estimated_blocks, human_bytes, machine_memory, BYTES_PER_BLOCK};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Options of `drystone generate`.
#[derive(clap::Args)]
pub struct GenerateArgs {
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
}

/// `drystone generate`: [`run`].
///
/// # Errors
/// Those of [`run`].
pub fn command(a: GenerateArgs) -> Result<ExitCode> {
    run(&a.wall, a.seed, a.realization, &a.out, a.distributions)
}

/// Generates realization `realization` of the wall with master seed `seed`, writes it to
/// `out` (format by extension) and prints what it holds. A wall whose layout would exceed
/// `run`'s limits ([`drystone::study::MAX_BLOCKS`] estimated blocks, or more memory
/// than the machine has) is refused before anything is generated.
pub fn run(wall: &Path, seed: u64, realization: u64, out: &Path, distributions: Option<PathBuf>) -> Result<ExitCode> {
    let Some(format) = OutputFormat::from_path(out) else {
        bail!("--out {}: unknown extension; use .json, .vtk or .svg", out.display());
    };
    let source = distributions.map_or_else(|| DistributionSource::default_for(wall), DistributionSource::dir);
    let w = Wall::from_file_with(wall, &source)?;
    // The limits of `run`, before anything is allocated.
    if let Err(reason) = check_blocks(&w) {
        bail!("{}: {reason}", wall.display());
    }
    let need = estimated_blocks(&w) * BYTES_PER_BLOCK;
    if let Some(have) = machine_memory() {
        if need > have {
            bail!(
                "{}: the layout would need about {} of memory; this machine has {}",
                wall.display(),
                human_bytes(need),
                human_bytes(have)
            );
        }
    }
    let t0 = std::time::Instant::now();
    let g = generate(&w, seed, realization)?;
    let dt = t0.elapsed().as_secs_f64();
    g.check()?;
    std::fs::write(out, drystone::io::render(&g, &w, format)?).with_context(|| format!("writing {}", out.display()))?;
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
