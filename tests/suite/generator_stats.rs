//! The values a generated wall uses follow their laws: one-sample Kolmogorov–Smirnov tests
//! (statistic and asymptotic p-value in `drystone::stats::ks`) over several thousand
//! dips, block lengths and course heights, p > 0.01.
//!
//! Only values used whatever their size are tested, so that the stopping rules of the
//! construction do not bias the sample: every dip; per course, the first M interior block
//! lengths, where M draws of the largest length still fit after the longest possible first
//! piece; per wall, the first N course heights, where N draws of the largest height still
//! fit below the top course's minimum.

use drystone::generator::{generate, Arrangement, Distribution, DistributionSpec, Wall};
use drystone::stats::ks::ks_test;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn preset(name: &str) -> Wall {
    Wall::from_file(&root().join("studies/walls").join(format!("{name}.toml"))).unwrap()
}

fn library(name: &str) -> Distribution {
    let p = root().join("distributions").join(format!("{name}.toml"));
    DistributionSpec::from_file(&p).unwrap().resolve(name, &p, "").unwrap()
}

fn dip_law(w: &Wall) -> &Distribution {
    match &w.arrangement {
        Arrangement::Irregular(ir) => &ir.dip,
        _ => panic!("not irregular"),
    }
}

/// Dips of realizations 0, 1, … of `seed` until at least `n` are collected.
fn dips(w: &Wall, seed: u64, n: usize) -> Vec<f64> {
    let mut xs = Vec::new();
    let mut r = 0;
    while xs.len() < n {
        xs.extend(generate(w, seed, r).unwrap().samples.dips_deg);
        r += 1;
    }
    xs
}

/// Interior block lengths used whatever their values (see the module doc).
fn lengths(w: &Wall, seed: u64, n: usize) -> Vec<f64> {
    let d = &w.block_length;
    let lmax = d.practical_max();
    let e_min = w.min_end_fraction * d.mean();
    let first_max = lmax.max(e_min);
    let m = ((w.length - e_min - first_max) / lmax).floor() as usize;
    assert!(m >= 1, "wall too short for an unbiased sample");
    let mut xs = Vec::new();
    let mut r = 0;
    while xs.len() < n {
        for course in generate(w, seed, r).unwrap().samples.block_lengths_m {
            assert!(course.len() >= m);
            xs.extend_from_slice(&course[..m]);
        }
        r += 1;
    }
    xs
}

/// Course heights used whatever their values (see the module doc).
fn heights(w: &Wall, seed: u64, n: usize) -> Vec<f64> {
    let d = &w.course_height;
    let k = ((w.height - 0.5 * d.mean()) / d.practical_max()).floor() as usize;
    assert!(k >= 1, "wall too low for an unbiased sample");
    let mut xs = Vec::new();
    let mut r = 0;
    while xs.len() < n {
        let g = generate(w, seed, r).unwrap();
        assert!(g.samples.course_heights_m.len() >= k);
        xs.extend_from_slice(&g.samples.course_heights_m[..k]);
        r += 1;
    }
    xs
}

#[track_caller]
fn assert_fits(what: &str, xs: &[f64], law: &Distribution) -> f64 {
    let (d, p) = ks_test(xs, |x| law.cdf(x));
    println!("{what}: n = {}, D = {d:.5}, p = {p:.4}", xs.len());
    assert!(p > 0.01, "{what}: KS rejects the law {:?} (n = {}, D = {d}, p = {p})", law.law, xs.len());
    p
}

#[test]
fn dips_follow_their_laws() {
    let w = preset("full_scale");
    assert_fits("full-scale dips, uniform ±20°", &dips(&w, 11, 4000), dip_law(&w));
    let w = preset("sbl");
    assert_fits("SBL dips, uniform ±10°", &dips(&w, 12, 4000), dip_law(&w));
    // A non-uniform law end to end: the truncated normal of distributions/.
    let mut w = preset("full_scale");
    let law = library("dip_truncated_normal_8");
    if let Arrangement::Irregular(ir) = &mut w.arrangement {
        ir.dip = law.clone();
    }
    assert_fits("full-scale dips, truncated normal σ 8°", &dips(&w, 13, 4000), &law);
}

#[test]
fn the_test_has_power_against_a_wrong_law() {
    let w = preset("full_scale");
    let xs = dips(&w, 11, 4000);
    let wrong = Distribution::uniform("wrong", -18.0, 18.0, drystone::generator::distribution::Unit::Deg);
    let (_, p) = ks_test(&xs, |x| wrong.cdf(x));
    assert!(p < 1e-6, "{p}");
}

#[test]
fn block_lengths_follow_their_laws() {
    let w = preset("full_scale");
    assert_fits("full-scale block lengths, uniform 0.4-0.6 m", &lengths(&w, 21, 4000), &w.block_length);
    let w = preset("sbl");
    assert_fits("SBL stone lengths, uniform 80-120 mm", &lengths(&w, 22, 4000), &w.block_length);
    // A truncated normal law on a long wall.
    let mut w = preset("full_scale");
    let spec = "unit = \"m\"\nkind = \"truncated_normal\"\nmean = 0.5\nstd = 0.08\nmin = 0.3\nmax = 0.7";
    let law =
        DistributionSpec::from_toml(spec, Path::new("inline")).unwrap().resolve("tn", Path::new("inline"), "").unwrap();
    w.block_length = law.clone();
    w.length = 12.0;
    assert_fits("block lengths, truncated normal 0.5 ± 0.08 m", &lengths(&w, 23, 4000), &law);
}

#[test]
fn course_heights_follow_their_laws() {
    // Tall walls give many course heights per realization.
    let mut w = preset("full_scale");
    w.height = 8.0;
    assert_fits("course heights, uniform 0.17-0.23 m", &heights(&w, 31, 3000), &w.course_height);
    let mut w = preset("sbl");
    w.height = 2.0;
    assert_fits("SBL course heights, uniform 40-60 mm", &heights(&w, 32, 3000), &w.course_height);
}
