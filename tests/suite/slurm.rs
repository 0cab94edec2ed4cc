//! The Slurm job array of `examples/slurm/`, run for real when Slurm is installed: the
//! single-node cluster set up (`setup_single_node.sh`, which leaves a running cluster as it
//! is), a small study run as a 3-task array and merged, a lost shard named by `merge`, a
//! killed task resumed from its journal, and the merged outputs compared byte for byte with
//! an unsharded run (`run_example.sh`). Skipped, with a note, where `sbatch` is not on the
//! PATH.

use std::path::Path;
use std::process::Command;

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(program).is_file()))
}

#[test]
fn the_slurm_array_merges_into_the_unsharded_run() {
    if !on_path("sbatch") {
        println!("skipped: sbatch is not on the PATH (install Slurm, e.g. examples/slurm/setup_single_node.sh)");
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let setup = Command::new("bash")
        .arg(root.join("examples/slurm/setup_single_node.sh"))
        .env("SLURM_INSTALL", "0")
        .output()
        .expect("bash runs");
    assert!(
        setup.status.success(),
        "setup_single_node.sh failed:\n{}{}",
        String::from_utf8_lossy(&setup.stdout),
        String::from_utf8_lossy(&setup.stderr)
    );
    let run = Command::new("bash")
        .arg(root.join("examples/slurm/run_example.sh"))
        .env("DRYSTONE", env!("CARGO_BIN_EXE_drystone"))
        .output()
        .expect("bash runs");
    let out = String::from_utf8_lossy(&run.stdout);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "run_example.sh failed:\n{out}{err}");
    assert!(out.contains("merged 3 shards, 6 realizations"), "{out}");
    assert!(out.contains("shard 2/3 missing") || err.contains("shard 2/3 missing"), "{out}{err}");
    assert!(out.contains("1 from the journal"), "{out}");
    assert!(out.contains("identical: 8 files byte for byte"), "{out}");
}
