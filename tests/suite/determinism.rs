//! Thread count never changes a result (rapier's thread_count_determinism.rs pattern): the
//! same layout gives the same numbers bit for bit, run after run, and inside rayon pools of
//! 1, 2 and 4 threads.

use drystone::dem::{Simulation, SolverParams};
use drystone::layout::Layout;
use drystone::loading::tilt::{TiltParams, TiltResult};
use drystone::protocol::run_tilt;
use rayon::prelude::*;
use std::path::Path;

fn wall() -> Layout {
    Layout::from_file(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/layouts/running_bond_wall.json"))).unwrap()
}

/// Everything but the wall-clock time, with floats as their bit patterns.
fn fingerprint(r: &TiltResult) -> String {
    let mut r = r.clone();
    r.wall_time_s = 0.0;
    let mut s = serde_json::to_string(&r).unwrap();
    for inc in &r.increments {
        for d in &inc.displacement_m {
            s.push_str(&format!("{:016x}", d.to_bits()));
        }
    }
    s.push_str(&format!("{:016x}{:016x}", r.collapse_angle_deg().to_bits(), r.dt_s.to_bits()));
    s
}

fn state_bits(sim: &Simulation) -> Vec<u64> {
    sim.state
        .bodies
        .iter()
        .flat_map(|b| {
            b.pos
                .iter()
                .chain(b.vel.iter())
                .chain(b.angvel.iter())
                .chain(b.rot.coords.iter())
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn same_layout_same_state_bit_for_bit_after_many_steps() {
    let l = wall();
    let run = || {
        let mut sim = Simulation::new(&l, SolverParams::default());
        sim.set_tilt(0.2);
        for _ in 0..3000 {
            sim.step().unwrap();
        }
        state_bits(&sim)
    };
    assert_eq!(run(), run());
}

#[test]
fn tilt_result_is_identical_on_1_2_and_4_threads() {
    let l = wall();
    let params = TiltParams { step_deg: 2.0, resolution_deg: 0.5, ..TiltParams::default() };
    let reference = fingerprint(&run_tilt(&l, SolverParams::default(), &params).unwrap());
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let prints: Vec<String> = pool.install(|| {
            (0..3)
                .into_par_iter()
                .map(|_| fingerprint(&run_tilt(&l, SolverParams::default(), &params).unwrap()))
                .collect()
        });
        for p in prints {
            assert_eq!(p, reference, "{threads} threads");
        }
    }
}
