//! Criterion benches: the contact kernel (narrow phase of two stacked blocks), the joint law
//! of one sub-contact (fully and partly compressed), one engine step of the paper's 16-block
//! cube, and one engine step and one implicit iteration of the SBL wall near collapse (the
//! preset, seed 20210917, realization 0, settled and tilted to 17°). Fixed inputs.

use criterion::{criterion_group, criterion_main, Criterion};
use drystone::dem::contact::geometry::block_block;
use drystone::dem::contact::law::{evaluate, JointParams, Kinematics, Quadrature, SubContactState};
use drystone::dem::RunToEquilibrium;
use drystone::dem::{Simulation, SolverParams};
use drystone::geometry::ConvexBlock;
use drystone::Vec3;
use std::hint::black_box;

fn narrow_phase(c: &mut Criterion) {
    let a = ConvexBlock::cuboid(Vec3::zeros(), Vec3::new(0.2, 0.15, 0.05)).unwrap();
    let b = ConvexBlock::cuboid(Vec3::new(0.1, 0.0, 0.05), Vec3::new(0.3, 0.15, 0.1)).unwrap();
    let s = SolverParams::default().patch();
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

fn joint_law(c: &mut Criterion) {
    let p = JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0);
    let n = Vec3::new(0.01, 0.02, 1.0).normalize();
    for (name, gaps) in
        [("joint_law_compressed", [-1e-5, -2e-5, -1.5e-5]), ("joint_law_partly_open", [-1e-5, 2e-5, -0.5e-5])]
    {
        let mut s = SubContactState::new(false);
        let mut sign = 1.0;
        c.bench_function(name, |bch| {
            bch.iter(|| {
                // Shear back and forth, inside and past the slip limit.
                sign = -sign;
                let k = Kinematics { normal: n, gaps, du_shear: Vec3::new(3e-6, -1e-6, 0.0) * sign, area: 0.01 };
                evaluate(&p, Quadrature::Exact, &mut s, black_box(&k))
            })
        });
    }
}

/// The SBL wall, realization 0, settled and tilted to 17° (2,000 steps of relaxation).
fn sbl_at_17deg() -> Simulation {
    let wall = drystone::generator::Wall::from_file(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/walls/sbl.toml"
    )))
    .unwrap();
    let layout = drystone::generator::generate(&wall, 20210917, 0).unwrap().check().unwrap();
    let mut sim = Simulation::new(&layout, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-4, 100_000).unwrap());
    sim.set_tilt(17f64.to_radians());
    for _ in 0..2000 {
        sim.step().unwrap();
    }
    sim
}

fn sbl_step(c: &mut Criterion) {
    let mut sim = sbl_at_17deg();
    c.bench_function("sbl_step_17deg", |bch| bch.iter(|| sim.step().unwrap()));
}

/// One iteration of the implicit relaxation (assembly and factorization of the stiffness,
/// one solve, two contact passes) with the copy of the state it starts from.
fn sbl_implicit_iteration(c: &mut Criterion) {
    use drystone::dem::drivers::implicit::{implicit_relaxation, ImplicitSolve};
    let sim = sbl_at_17deg();
    let one = ImplicitSolve { max_iterations: 1, ..ImplicitSolve::default() };
    c.bench_function("sbl_implicit_iteration_17deg", |bch| {
        bch.iter_batched(
            || sim.clone(),
            |mut s| implicit_relaxation(&mut s, 1e-12, &one, |_| None::<()>),
            criterion::BatchSize::LargeInput,
        )
    });
}

criterion_group!(benches, narrow_phase, joint_law, engine_step, sbl_step, sbl_implicit_iteration);
criterion_main!(benches);
