//! The seating of each block's bed drawn per realization (`[scatter] bed_seating_gap_m` of a
//! wall description; a layout block's `bed_closure`): the closed form of a stack of seated
//! beds, the draws against the stream they are documented to come from, walls without the
//! key unchanged, and bad inputs refused naming the key.

use drystone::dem::{RunToEquilibrium, SolverParams};
use drystone::generator::spec::{DistRef, ScatterSpec};
use drystone::generator::{generate, generate_batch, DistributionSource, GeneratedWall, Wall, WallSpec};
use drystone::layout::{Closure, LayoutSpec};
use rand::distr::Distribution as _;
use rand::SeedableRng;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn granite(with_seating: bool) -> Wall {
    let path = root().join("studies/walls/granite_vasconcelos.toml");
    let mut spec = WallSpec::from_toml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    spec.scatter = with_seating.then(|| ScatterSpec {
        bed_seating_gap_m: Some(DistRef::Name("bed_seating_gap_sawn_granite".into())),
        ..ScatterSpec::default()
    });
    spec.resolve(&path, &DistributionSource::dir(root().join("distributions"))).unwrap()
}

/// A stack of three blocks 0.2 × 0.2 m in plan and `h` high (courses 0, 1, 2) whose beds have
/// the laws `beds` (`None`: the material's linear law), of density `rho` and stiffness `kn`.
fn stack(h: f64, rho: f64, kn: f64, beds: [Option<f64>; 3]) -> drystone::layout::Layout {
    let blocks: Vec<String> = (0..3)
        .map(|i| {
            let (z0, z1) = (i as f64 * h, (i + 1) as f64 * h);
            let bed = match beds[i] {
                Some(g) => format!(r#","bed_closure":{{"seating":{{"max_gap_m":{g:e}}}}}"#),
                None => String::new(),
            };
            format!(
                r#"{{"id":"b{i}","material":"m","course":{i}{bed},"vertices":[[0,0,{z0}],[0.2,0,{z0}],[0.2,0.2,{z0}],[0,0.2,{z0}],[0,0,{z1}],[0.2,0,{z1}],[0.2,0.2,{z1}],[0,0.2,{z1}]]}}"#
            )
        })
        .collect();
    let json = format!(
        r#"{{"version":1,"name":"stack","materials":[{{"name":"m","density_kg_per_m3":{rho},"kn_pa_per_m":{kn:e},
        "ks_pa_per_m":{:e},"friction_deg":35}}],"table":{{"material":"m"}},"blocks":[{}],"restraints":{{}}}}"#,
        kn / 2.0,
        blocks.join(",")
    );
    LayoutSpec::from_json(&json).unwrap().resolve().unwrap()
}

/// The seating law's closure under the pressure `p` (Pa) for a joint of stiffness `kn` and
/// largest gap `g` (m), solved by hand from `q = Kn u²/(2 g)` (u ≤ g) and
/// `q = Kn (u − g/2)` (u > g): `√(2 g p / Kn)` while `p ≤ Kn g / 2`, `p/Kn + g/2` past it;
/// `p/Kn` for the linear joint.
fn seated_closure(p: f64, kn: f64, g: Option<f64>) -> f64 {
    match g {
        None => p / kn,
        Some(g) if p <= 0.5 * kn * g => (2.0 * g * p / kn).sqrt(),
        Some(g) => p / kn + 0.5 * g,
    }
}

/// A stack of rigid blocks on seated beds settles by the sum of its beds' closures, each
/// under the weight above it: bed 0 (three blocks, past its gap: the linear branch), bed 1
/// (two blocks, within its gap: the quadratic branch), bed 2 (one block, no law of its own:
/// linear). Bed 2 lies on block 1, whose own bed is seated: a block's law is its bed's,
/// not its top's.
#[test]
fn a_stack_of_seated_beds_settles_by_the_sum_of_their_closures() {
    let (h, rho, kn) = (0.1, 2400.0, 5e7);
    let beds = [Some(1e-4), Some(4e-4), None];
    let l = stack(h, rho, kn, beds);
    let p1 = rho * drystone::units::STANDARD_GRAVITY * h;
    let closures: Vec<f64> = (0..3).map(|i| seated_closure((3 - i) as f64 * p1, kn, beds[i])).collect();
    // The branches the test means to cover.
    assert!(3.0 * p1 > 0.5 * kn * 1e-4 && 2.0 * p1 < 0.5 * kn * 4e-4);
    let mut sim = drystone::dem::Simulation::new(&l, SolverParams::default());
    let z0: Vec<f64> = (0..3).map(|i| sim.state.bodies[i].pos.z).collect();
    sim.run_to_equilibrium(1e-10, 4_000_000).unwrap();
    let mut expect = 0.0;
    for (i, c) in closures.iter().enumerate() {
        expect += c;
        let u = z0[i] - sim.state.bodies[i].pos.z;
        assert!((u - expect).abs() < 2e-3 * expect, "block {i}: settled {u:e} m, the beds' closures sum to {expect:e}");
    }
    // The same stack with its laws on the other blocks settles otherwise (the law is the
    // bed's under the block that names it).
    let swapped = stack(h, rho, kn, [None, Some(1e-4), Some(4e-4)]);
    let mut sim = drystone::dem::Simulation::new(&swapped, SolverParams::default());
    sim.run_to_equilibrium(1e-10, 4_000_000).unwrap();
    let other: f64 = (0..3).map(|i| seated_closure((3 - i) as f64 * p1, kn, [None, Some(1e-4), Some(4e-4)][i])).sum();
    let u = z0[2] - sim.state.bodies[2].pos.z;
    assert!((u - other).abs() < 2e-3 * other, "swapped: {u:e} vs {other:e}");
    assert!((other - expect).abs() > 0.05 * expect, "{other:e} vs {expect:e}");
}

/// The draws are the realization's `Seating` stream (ChaCha8 seeded with the master seed,
/// stream `16 × realization + 10`, as `drystone::rng` documents), one uniform draw per block
/// in layout order, built here from the stream itself; the beds of the layout carry them.
#[test]
fn the_bed_gaps_are_the_seating_streams_draws_one_per_block() {
    let w = granite(true);
    for (seed, r) in [(20090301u64, 0u64), (20090301, 3), (7, 1)] {
        let g = generate(&w, seed, r).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(16 * r + 10);
        let u = rand::distr::Uniform::new(0.0, 3e-4).unwrap();
        for (p, b) in g.pieces.iter().zip(&g.layout.blocks) {
            let expect = u.sample(&mut rng);
            assert_eq!(p.bed_seating_gap_m, Some(expect), "seed {seed}, realization {r}, block {}", p.id);
            let law = if expect >= 1e-6 {
                Some(Closure::Seating(drystone::closure::Seating { max_gap_m: expect }))
            } else {
                None
            };
            assert_eq!(b.bed_closure, law, "block {}", b.id);
        }
    }
}

fn fingerprint(g: &GeneratedWall) -> String {
    g.layout.to_json()
}

/// The same realization alone, in a batch and on 1, 2 or 4 threads; realizations differ.
#[test]
fn the_bed_gaps_are_the_same_on_any_thread_count() {
    let w = granite(true);
    let alone: Vec<String> = (0..6).map(|i| fingerprint(&generate(&w, 11, i).unwrap())).collect();
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let batch = pool.install(|| generate_batch(&w, 11, 0..6));
        for (i, g) in batch.iter().enumerate() {
            assert_eq!(fingerprint(g.as_ref().unwrap()), alone[i], "realization {i}, {threads} threads");
        }
    }
    assert_ne!(alone[0], alone[1]);
}

/// The seating draws move nothing else: the wall with the key has the geometry, materials
/// and every other layout key of the wall without it, which writes no `bed_closure` and no
/// per-block material.
#[test]
fn the_bed_seating_changes_only_the_beds() {
    let (with, without) = (granite(true), granite(false));
    for r in 0..3 {
        let (a, b) = (generate(&with, 5, r).unwrap(), generate(&without, 5, r).unwrap());
        let mut stripped = a.layout.clone();
        stripped.blocks.iter_mut().for_each(|b| b.bed_closure = None);
        assert_eq!(stripped.to_json(), b.layout.to_json(), "realization {r}");
        assert!(!b.layout.to_json().contains("bed_closure"));
        assert_eq!(b.layout.materials.len(), 1);
        assert!(a.layout.blocks.iter().filter(|b| b.bed_closure.is_some()).count() > a.layout.blocks.len() / 2);
    }
}

fn wall_with_scatter(scatter: &str, extra: &str) -> String {
    let text = std::fs::read_to_string(root().join("studies/walls/granite_vasconcelos.toml")).unwrap();
    let cut = text.rfind("\n[scatter]").unwrap_or(text.len());
    format!("{}\n[scatter]\n{scatter}\n{extra}", &text[..cut])
}

fn error_of(name: &str, text: &str) -> String {
    let dir = crate::common::Scratch::created(&format!("bed-seating-{name}"));
    let path = dir.join("wall.toml");
    std::fs::write(&path, text).unwrap();
    let e = Wall::from_file_with(&path, &DistributionSource::dir(root().join("distributions"))).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains(&path.display().to_string()), "{name}: {msg}");
    msg
}

/// A gap law of another unit, one that reaches below 0 or past the closure laws' 5 cm, or
/// an unbounded one is refused naming `scatter.bed_seating_gap_m`; a layout's bed law out of
/// range names the block.
#[test]
fn bad_bed_seating_gaps_are_refused_naming_the_key() {
    let key = "scatter.bed_seating_gap_m";
    let msg = error_of("unit", &wall_with_scatter("bed_seating_gap_m = \"dip_uniform_10\"", ""));
    assert!(msg.contains(key) && msg.contains("unit"), "{msg}");
    let inline = |kind: &str| format!("\n[distributions.gap]\nunit = \"m\"\n{kind}\n");
    let msg = error_of(
        "negative",
        &wall_with_scatter("bed_seating_gap_m = \"gap\"", &inline("kind = \"uniform\"\nmin = -1e-4\nmax = 3e-4")),
    );
    assert!(msg.contains(key) && msg.contains("[0, 0.05]"), "{msg}");
    let msg = error_of(
        "unbounded",
        &wall_with_scatter("bed_seating_gap_m = \"gap\"", &inline("kind = \"lognormal\"\nmean = 1e-4\ncv = 0.5")),
    );
    assert!(msg.contains(key) && msg.contains("unbounded"), "{msg}");
    let msg = error_of("fixed", &wall_with_scatter("bed_seating_gap_m = 0.2", ""));
    assert!(msg.contains(key), "{msg}");

    let json = r#"{"version":1,"name":"one","materials":[{"name":"m","density_kg_per_m3":2400,"kn_pa_per_m":1e9,
        "ks_pa_per_m":5e8,"friction_deg":30}],"table":{"material":"m"},"blocks":[{"id":"b0","material":"m",
        "bed_closure":{"seating":{"max_gap_m":0.5}},
        "vertices":[[0,0,0],[0.2,0,0],[0.2,0.2,0],[0,0.2,0],[0,0,0.1],[0.2,0,0.1],[0.2,0.2,0.1],[0,0.2,0.1]]}],"restraints":{}}"#;
    let e = LayoutSpec::from_json(json).unwrap().resolve().unwrap_err().to_string();
    assert!(e.contains("blocks[b0].bed_closure.seating.max_gap_m"), "{e}");
}
