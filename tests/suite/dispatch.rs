//! `Simulation::step` runs a copy of the step compiled for the CPU's instruction set (AVX-512
//! or AVX2 where present). Every copy this CPU runs must give the same state bit for bit as
//! the baseline build of the same step: the same IEEE-754 operations in the same order, only
//! encoded differently. Checked on an irregular wall (wedges, steep beds: partly open
//! sub-contacts, slip) tilted to 16°, where blocks creep, slide and re-detect their contacts.

use drystone::dem::RunToEquilibrium;
use drystone::dem::{Isa, Simulation, SolverParams};
use drystone::generator::{generate, Wall};
use std::path::PathBuf;

/// Every bit of the bodies' state and of the joints' history.
fn state_bits(sim: &Simulation) -> Vec<u64> {
    let mut v = Vec::new();
    for b in &sim.state.bodies {
        for x in b.pos.iter().chain(b.vel.iter()).chain(b.angvel.iter()).chain(b.rot.coords.iter()) {
            v.push(x.to_bits());
        }
    }
    for c in &sim.state.contacts {
        v.extend(c.force.iter().map(|x| x.to_bits()));
        for s in &c.subs {
            v.extend(s.state.shear.iter().map(|x| x.to_bits()));
            v.push(s.state.normal.to_bits());
            v.push(s.state.slipping as u64);
        }
    }
    v.push(sim.stats().unbalanced_ratio.to_bits());
    v.push(sim.dt().to_bits());
    v
}

#[test]
fn every_compiled_step_equals_the_portable_step_bit_for_bit() {
    let wall = Wall::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/walls/sbl.toml")).unwrap();
    let layout = generate(&wall, 20210917, 0).unwrap().check().unwrap();
    let mut reference = Simulation::new(&layout, SolverParams::default());
    assert!(reference.run_to_equilibrium(1e-4, 100_000).unwrap());
    reference.set_tilt(16f64.to_radians());
    // One copy per instruction set this CPU runs; `step` itself (the best one) as well.
    let variants: Vec<Isa> = Isa::ALL.into_iter().filter(|v| *v != Isa::Portable && v.available()).collect();
    println!("instruction sets checked against the baseline: {variants:?}, and step()'s choice {:?}", Isa::best());
    let mut sims: Vec<Simulation> = (0..=variants.len()).map(|_| reference.clone()).collect();
    let detections = reference.detections();
    let mut slipping = 0;
    for i in 0..1500 {
        reference.step_with(Isa::Portable).unwrap().unwrap();
        for (k, sim) in sims.iter_mut().enumerate() {
            match variants.get(k) {
                Some(&v) => sim.step_with(v).unwrap().unwrap(),
                None => sim.step().unwrap(),
            }
        }
        if i % 100 == 99 {
            let bits = state_bits(&reference);
            for (k, sim) in sims.iter().enumerate() {
                assert_eq!(state_bits(sim), bits, "{:?}: states differ after {} steps", variants.get(k), i + 1);
            }
            slipping = slipping
                .max(reference.state.contacts.iter().flat_map(|c| &c.subs).filter(|s| s.state.slipping).count());
        }
    }
    // The run exercised what it is meant to: motion past the re-detection threshold and
    // joints at the slip limit.
    assert!(reference.detections() > detections, "no re-detection in the run");
    assert!(slipping > 0, "no sub-contact slipped");
}
