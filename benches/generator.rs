//! Criterion benches of the wall generator: one realization of each irregular preset (the
//! full-scale wall must take well under 100 ms), with and without the layout check (hulls
//! and the DEM narrow phase over every touching pair). Seeded inputs; the realization index
//! advances every iteration so no two iterations build the same wall.

use criterion::{criterion_group, criterion_main, Criterion};
use drystone::generator::{generate, Wall};
use std::hint::black_box;
use std::path::PathBuf;

fn preset(name: &str) -> Wall {
    Wall::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/walls").join(format!("{name}.toml")))
        .expect("preset loads")
}

fn generator(c: &mut Criterion) {
    for (name, bench) in [
        ("full_scale", "generate_full_scale_irregular"),
        ("sbl", "generate_sbl"),
        ("full_scale_discontinuous", "generate_full_scale_running_bond"),
    ] {
        let w = preset(name);
        let mut i = 0u64;
        c.bench_function(bench, |b| {
            b.iter(|| {
                i += 1;
                generate(black_box(&w), 2021, i).expect("generates")
            })
        });
    }
    let w = preset("full_scale");
    let mut i = 0u64;
    c.bench_function("generate_and_check_full_scale_irregular", |b| {
        b.iter(|| {
            i += 1;
            generate(black_box(&w), 2021, i).expect("generates").check().expect("valid layout")
        })
    });
    c.bench_function("load_wall_description_full_scale", |b| b.iter(|| preset(black_box("full_scale"))));
}

criterion_group!(benches, generator);
criterion_main!(benches);
