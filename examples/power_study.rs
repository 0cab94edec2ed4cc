//! Power study of the model-discrepancy analysis on the test bed of `tests/discrepancy/`:
//! for every effect of the library, data sets with the effect hidden at a strength drawn
//! from a seeded RNG (20 per effect by default), and null data sets (40), each with 6
//! specimens per group built with seeds the study does not use; prints the detection rate
//! per effect (named alone, and named or tied with the named cause) and the false-alarm
//! rate.
//!
//! ```sh
//! cargo run --release --example power_study [-- DATASETS_PER_EFFECT NULL_DATASETS]
//! ```

use drystone::discrepancy::analysis::{analyze, calibrate_margins, NullSource};
use drystone::discrepancy::effects::{Effect, EffectKind};
use drystone::discrepancy::fit::Data;
use drystone::discrepancy::observations::{observations, specimens};
use drystone::discrepancy::simulate::{run_models, GroupSetup, Setup};
use drystone::discrepancy::synthesize::{observables_of, synthesize, Request};
use drystone::discrepancy::{build_library, Keys};
use drystone::study::discrepancy::setup_of;
use drystone::study::Study;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// The hidden strength of each effect: the range the test bed resolves (the same as the
/// test's).
fn hidden(kind: EffectKind, rng: &mut ChaCha8Rng) -> Effect {
    let mut u = |lo: f64, hi: f64| rng.random_range(lo..=hi);
    let values = match kind {
        EffectKind::KnScale => vec![u(0.2, 0.5)],
        EffectKind::JointClosure => vec![u(0.05, 0.2), u(5e-4, 2e-3)],
        EffectKind::SeatingGap => vec![u(1e-3, 2.5e-3)],
        EffectKind::InitialLean => vec![u(1.5, 3.0)],
        EffectKind::EdgeRounding => vec![u(0.005, 0.012)],
        EffectKind::RestraintStiffness => vec![u(20.0, 200.0)],
        EffectKind::TransverseDip => vec![u(13.0, 15.0)],
    };
    Effect::new(kind, values, kind.random_form().is_some()).expect("in range")
}

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let per_effect = args.first().copied().unwrap_or(20);
    let nulls = args.get(1).copied().unwrap_or(40);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let study = Study::from_file(&root.join("tests/discrepancy/study.toml")).expect("test study");
    let s = study.discrepancy.clone();
    let setup = setup_of(&study, s.realizations, &s);
    let full = Setup {
        groups: setup
            .groups
            .iter()
            .map(|g| GroupSetup { realizations: s.extension_realizations, ..g.clone() })
            .collect(),
        ..setup.clone()
    };
    let t0 = std::time::Instant::now();
    let baseline = run_models(&full, &[vec![]], None).remove(0);
    let pool: Vec<_> = baseline.iter().map(|o| o[s.realizations as usize..].to_vec()).collect();
    let groups: Vec<(String, String)> = setup.groups.iter().map(|g| (g.name.clone(), g.name.clone())).collect();
    let template = observables_of(&setup, &[]);
    let mut secret = ChaCha8Rng::seed_from_u64(20_261_122);
    let mut cases: Vec<Option<EffectKind>> = Vec::new();
    for k in EffectKind::ALL {
        cases.extend(std::iter::repeat_n(Some(k), per_effect));
    }
    cases.extend(std::iter::repeat_n(None, nulls));
    let mut library = None;
    let mut tally: Vec<(String, usize, usize, usize)> = Vec::new();
    for (i, kind) in cases.iter().enumerate() {
        let effects: Vec<Effect> = kind.map(|k| hidden(k, &mut secret)).into_iter().collect();
        let req =
            Request { effects, seed: 50_000 + i as u64, specimens: 6, sigma: s.sigma, observables: template.clone() };
        let (c, d) = synthesize(&setup, &req);
        let obs = observations(&c, &d, &groups, s.sigma, "synthetic").expect("observations");
        let keys = Keys::new(&setup, &obs);
        let lib = library.get_or_insert_with(|| build_library(&setup, &keys, &baseline, &s).expect("library"));
        let sp = specimens(&obs);
        let m = calibrate_margins(
            lib,
            &obs,
            &keys.of,
            &sp,
            s.resolution_deg,
            s.null_replicates,
            11,
            NullSource::Pool(&pool, &keys.keys),
        );
        let y: Vec<f64> = obs.iter().map(|o| o.value).collect();
        let a = analyze(lib, Data { obs: &obs, y: &y, key: &keys.of, resolution_deg: s.resolution_deg }, &sp, m);
        let name = kind.map_or("null".to_string(), |k| k.name().to_string());
        let named = a.cause.as_ref().map(|c| c.effects.join("+"));
        let (exact, tied) = match kind {
            Some(k) => (named.as_deref() == Some(k.name()), a.tie.iter().any(|t| t == k.name())),
            None => (named.is_none(), named.is_none()),
        };
        match tally.iter_mut().find(|t| t.0 == name) {
            Some(t) => {
                t.1 += 1;
                t.2 += exact as usize;
                t.3 += (exact || tied) as usize;
            }
            None => tally.push((name.clone(), 1, exact as usize, (exact || tied) as usize)),
        }
        eprintln!(
            "{i:>4} {name:<20} verdict {:<12} named {:?} tie {:?} ({:.0} s)",
            a.verdict.name(),
            named,
            a.tie,
            t0.elapsed().as_secs_f64()
        );
    }
    println!("| hidden effect | data sets | named alone | named or tied |");
    println!("| --- | --- | --- | --- |");
    for (name, n, exact, tied) in &tally {
        if name == "null" {
            println!(
                "| none (null) | {n} | no_effect: {exact} ({:.0} %) | false alarms: {} ({:.0} %) |",
                100.0 * *exact as f64 / *n as f64,
                n - exact,
                100.0 * (n - exact) as f64 / *n as f64
            );
        } else {
            println!(
                "| {name} | {n} | {exact} ({:.0} %) | {tied} ({:.0} %) |",
                100.0 * *exact as f64 / *n as f64,
                100.0 * *tied as f64 / *n as f64
            );
        }
    }
    println!("({:.0} s)", t0.elapsed().as_secs_f64());
}
