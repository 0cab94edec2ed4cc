//! Criterion benches: the contact kernel (narrow phase of two stacked blocks) and one engine
//! step of the paper's 16-block cube. Seedless inputs (fixed geometry).

use criterion::{criterion_group, criterion_main, Criterion};
use drystone::dem::contact::geometry::{block_block, ContactSettings};
use drystone::dem::{Simulation, SolverParams};
use drystone::geometry::ConvexBlock;
use drystone::Vec3;
use std::hint::black_box;

fn narrow_phase(c: &mut Criterion) {
    let a = ConvexBlock::cuboid(Vec3::zeros(), Vec3::new(0.2, 0.15, 0.05)).unwrap();
    let b = ConvexBlock::cuboid(Vec3::new(0.1, 0.0, 0.05), Vec3::new(0.3, 0.15, 0.1)).unwrap();
    let s = ContactSettings::default();
    c.bench_function("narrow_phase_face_face", |bch| bch.iter(|| block_block(black_box(&a), black_box(&b), &s)));
}

fn engine_step(c: &mut Criterion) {
    let layout = drystone::benchmark::cube16();
    let mut sim = Simulation::new(&layout, SolverParams::default());
    for _ in 0..1000 {
        sim.step().unwrap();
    }
    c.bench_function("cube16_step", |bch| bch.iter(|| sim.step().unwrap()));
}

criterion_group!(benches, narrow_phase, engine_step);
criterion_main!(benches);
