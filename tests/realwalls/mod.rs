//! Measured data made the way real walls differ from the model, by a path that shares no
//! code with the effect library (`drystone::effects`) or the discrepancy engine:
//!
//! - each specimen is a wall of the study generated with a seed the analysis never uses,
//!   written as layout JSON ([`drystone::layout::Layout::to_json`]) and **edited as a
//!   file**: a shear of every vertex for a wall built out of plumb, an erosion and
//!   dilation of every block (a Minkowski rounding of every edge, with a polyhedral ball),
//!   a factor on a material's Kn and Ks, a softer table material (a softer joint between
//!   the table and the base course), spring end restraints;
//! - the edited file is read back and tilted with `run_tilt` at the study's own tilt step
//!   and resolution;
//! - the collapse angle is a uniform draw inside the simulated bracket (the table tilts
//!   continuously; the model only brackets the angle), the displacements are the mean of
//!   the three top points (free walls) or the centre minus the mean of the ends (held
//!   walls); both get Gaussian noise at a σ **different** from the one the engine
//!   assumes, and are rounded to the study's reading resolutions as real readings are.
//!
//! - the mechanism is read from the edited wall's own run (`TiltResult::mechanism`'s
//!   reading: failure height, kind, start), as a person would read it: the height to the
//!   nearest bed joint of the specimen's own courses with an interval of ± half a mean
//!   course, the kind and the start each misread at a stated rate (replaced by another
//!   category drawn uniformly), from a random stream of its own (the angles and
//!   displacements are the same with or without it); the readings are written as the
//!   measured mechanism file (`drystone::io::measured::MECHANISM_FILE`, the format of
//!   `[measured] mechanism`) and read back by the library's reader
//!   ([`mechanism_observations_via_file`]).
//!
//! - a second, **independent** observer ([`Observer::Independent`]) reads the same runs by
//!   a rule of its own that shares no code with the product's mechanism reading
//!   (`drystone::loading::mechanism`: neither `read_mechanism`, `mechanism`, its shares nor
//!   its block motion): the tilt is run with `run_tilt_observed` (the same parameters, so
//!   the angles and displacements are bit-identical), keeping the last state handed over
//!   as stable at `last_stable_deg` and the last unstable state handed over at
//!   `first_unstable_deg`; each non-fixed block's displacement is the distance its
//!   centroid moved between the two; the **moving part** is every block that moved at
//!   least [`INDEPENDENT_MOVING_SHARE`] (0.2) of the largest displacement (a fixed
//!   fraction, no grouping by joints). It reads
//!   - the **failure height**: the lowest base of the moving blocks (their lowest vertex z
//!     in the layout file, α = 0) over the wall's height (its blocks' vertices), to the
//!     nearest bed joint of the specimen's nominal courses (as the product observer's
//!     height), ± half a mean course;
//!   - the **start**, held walls only: `centre` if the mean centroid x of the moving
//!     blocks lies in the middle fifth of the wall's length, else `end`; a free wall gets
//!     no start;
//!   - the **kind**: `toppling` if the moving blocks' mean rotation between the two
//!     states exceeds [`INDEPENDENT_TOPPLING_DEG`] (2°), else `sliding`; `bending` for a
//!     held wall read `centre` whose end blocks (the first and last block of every
//!     course along the length) are not moving;
//!   - misread at its own rate (0.15 in the power table): the height one course up or
//!     down (half the rate each, kept on the wall), the kind and the start each replaced
//!     by another category drawn uniformly, from a random stream of its own.
//!
//! Used by `tests/suite/discrepancy_realwalls.rs` (the reduced set CI runs) and by
//! `examples/realwall_power.rs` (the power table of BENCHMARKS.md).
#![allow(dead_code)]

use drystone::discrepancy::{Measure, MeasurementSigma, Observable, Observation};
use drystone::generator::{generate, Wall};
use drystone::io::measured::{
    check_mechanism_against_study, mechanism_csv, read_measured_mechanism, MeasuredMechanism, StudyContext,
    MECHANISM_FILE,
};
use drystone::layout::LayoutSpec;
use drystone::loading::mechanism::{FailureKind, FailureStart, MechanismReading};
use drystone::protocol::run_tilt_observed;
use drystone::study::Study;
use parry3d_f64::math::Vector as PVec;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// How a data set's walls differ from the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Edit {
    /// As generated (null data).
    None,
    /// Built out of plumb by this angle, degrees, towards the side the table tilts to.
    Lean(f64),
    /// Every edge of every block rounded with this radius, m.
    Round(f64),
    /// Kn and Ks of every stone material times this factor.
    Stiffness(f64),
    /// The table made of a material with this Kn (Pa/m; Ks half of it): a softer joint
    /// between the table and the base course.
    SoftBase(f64),
    /// End restraints as springs of this stiffness, N/m (free walls unchanged).
    Springs(f64),
    /// A lean (degrees) and a rounding (m) together.
    LeanRound(f64, f64),
}

impl Edit {
    /// A short label.
    pub fn label(&self) -> String {
        match *self {
            Edit::None => "null".into(),
            Edit::Lean(d) => format!("lean {d} deg"),
            Edit::Round(r) => format!("rounding {} mm", r * 1e3),
            Edit::Stiffness(f) => format!("stone Kn x{f}"),
            Edit::SoftBase(k) => format!("table Kn {k:.1e} Pa/m"),
            Edit::Springs(k) => format!("spring ends {k:.0} N/m"),
            Edit::LeanRound(d, r) => format!("lean {d} deg + rounding {} mm", r * 1e3),
        }
    }
}

/// Measurement noise of the data (deliberately not the engine's assumed σ) and the
/// readings' resolution.
#[derive(Debug, Clone, Copy)]
pub struct Noise {
    /// Collapse angle σ, degrees.
    pub angle_deg: f64,
    /// Displacement σ, cm.
    pub displacement_cm: f64,
    /// Angle reading, degrees.
    pub angle_reading_deg: f64,
    /// Displacement reading, cm.
    pub displacement_reading_cm: f64,
}

/// How an observer reads a specimen's failure mechanism: the failure height to the nearest
/// bed joint of the specimen's own (nominal) courses, with a reading interval of ± half its
/// mean course height (clamped to [0, 1]); the kind and the start each replaced, with
/// probability `misreading`, by another category drawn uniformly (kinds: `toppling`,
/// `sliding`, `bending`, `mixed`; starts: `end`, `centre`, `uniform`). The independent
/// observer ([`Observer::Independent`]) also reads its height one bed joint up or down
/// with this probability.
#[derive(Debug, Clone, Copy)]
pub struct MechanismNoise {
    /// Probability of misreading the kind, and independently the start, in [0, 1).
    pub misreading: f64,
}

/// Who reads the specimens' mechanisms (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Observer {
    /// The product's own reading of each run (`TiltResult::mechanism`'s reading), the
    /// height to the nearest bed joint, the kind and the start misread.
    Product,
    /// The independent observer: a rule of its own on the run's last stable and first
    /// unstable states, sharing no code with the product's reading.
    Independent,
}

impl Observer {
    /// `product` or `independent`.
    pub fn name(self) -> &'static str {
        match self {
            Observer::Product => "product",
            Observer::Independent => "independent",
        }
    }
}

/// Share of the largest block displacement at or above which a block is part of the
/// independent observer's moving part.
pub const INDEPENDENT_MOVING_SHARE: f64 = 0.2;

/// Mean rotation of the moving blocks, degrees, above which the independent observer
/// reads `toppling` (else `sliding`).
pub const INDEPENDENT_TOPPLING_DEG: f64 = 2.0;

/// Share of the wall's length, about its middle, where the independent observer reads a
/// start as `centre` (the middle fifth).
pub const INDEPENDENT_CENTRE_SPAN: f64 = 0.2;

/// A specimen's mechanism as the independent observer reads it, before misreading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndependentReading {
    /// The lowest base of the moving blocks over the wall's height (not rounded).
    pub height_fraction: f64,
    /// `toppling`, `sliding` or `bending`.
    pub kind: FailureKind,
    /// `centre` or `end` for a held wall; `None` for a free one.
    pub start: Option<FailureStart>,
    /// Blocks in the moving part.
    pub moving: usize,
    /// The moving blocks' mean rotation between the two states, degrees.
    pub rotation_deg: f64,
}

fn round_to(v: f64, step: f64) -> f64 {
    if step > 0.0 {
        (v / step).round() * step
    } else {
        v
    }
}

// ---------------------------------------------------------------------------------------
// Editing layout JSON.

fn vertices(block: &Value) -> Vec<[f64; 3]> {
    block["vertices"]
        .as_array()
        .expect("vertices")
        .iter()
        .map(|v| {
            let a = v.as_array().expect("vertex");
            [a[0].as_f64().unwrap(), a[1].as_f64().unwrap(), a[2].as_f64().unwrap()]
        })
        .collect()
}

fn set_vertices(block: &mut Value, v: &[[f64; 3]]) {
    block["vertices"] = Value::Array(v.iter().map(|p| serde_json::json!([p[0], p[1], p[2]])).collect());
}

/// Shear every vertex: `y += s · z` (a wall built out of plumb; the table is z = 0).
fn shear(spec: &mut Value, lean_deg: f64) {
    let s = lean_deg.to_radians().tan();
    for b in spec["blocks"].as_array_mut().expect("blocks") {
        let v: Vec<[f64; 3]> = vertices(b).into_iter().map(|[x, y, z]| [x, y + s * z, z]).collect();
        set_vertices(b, &v);
    }
}

type P3 = [f64; 3];

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P3, b: P3) -> P3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn unit(a: P3) -> P3 {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// The supporting planes `n · x = d` (outward unit n) of the hull of `pts`.
fn planes(pts: &[P3]) -> Vec<(P3, f64)> {
    let pp: Vec<PVec> = pts.iter().map(|p| PVec::new(p[0], p[1], p[2])).collect();
    let (hv, tris) = parry3d_f64::transformation::convex_hull(&pp);
    let c = {
        let n = hv.len() as f64;
        let s = hv.iter().fold([0.0; 3], |a, p| [a[0] + p.x, a[1] + p.y, a[2] + p.z]);
        [s[0] / n, s[1] / n, s[2] / n]
    };
    let mut out: Vec<(P3, f64)> = Vec::new();
    for t in tris {
        let [a, b, cc] = t.map(|i| [hv[i as usize].x, hv[i as usize].y, hv[i as usize].z]);
        let mut n = cross(sub(b, a), sub(cc, a));
        if dot(n, n).sqrt() < 1e-14 {
            continue;
        }
        n = unit(n);
        if dot(n, sub(a, c)) < 0.0 {
            n = [-n[0], -n[1], -n[2]];
        }
        let d = dot(n, a);
        if !out.iter().any(|(m, e)| dot(*m, n) > 1.0 - 1e-9 && (e - d).abs() < 1e-9) {
            out.push((n, d));
        }
    }
    out
}

/// The vertices of `{x : n_i · x ≤ d_i − r}` by intersecting every triple of planes.
fn eroded_vertices(pl: &[(P3, f64)], r: f64) -> Vec<P3> {
    let mut out: Vec<P3> = Vec::new();
    let k = pl.len();
    for i in 0..k {
        for j in i + 1..k {
            for l in j + 1..k {
                let (a, b, c) = (pl[i], pl[j], pl[l]);
                let det = dot(a.0, cross(b.0, c.0));
                if det.abs() < 1e-10 {
                    continue;
                }
                let (da, db, dc) = (a.1 - r, b.1 - r, c.1 - r);
                let bc = cross(b.0, c.0);
                let ca = cross(c.0, a.0);
                let ab = cross(a.0, b.0);
                let x = [
                    (da * bc[0] + db * ca[0] + dc * ab[0]) / det,
                    (da * bc[1] + db * ca[1] + dc * ab[1]) / det,
                    (da * bc[2] + db * ca[2] + dc * ab[2]) / det,
                ];
                if pl.iter().all(|(n, d)| dot(*n, x) <= d - r + 1e-10)
                    && !out.iter().any(|p| dot(sub(*p, x), sub(*p, x)) < 1e-20)
                {
                    out.push(x);
                }
            }
        }
    }
    out
}

/// The 12 vertices of a regular icosahedron on the unit sphere.
fn icosahedron() -> Vec<P3> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v = Vec::new();
    for (a, b) in [(1.0, t), (-1.0, t), (1.0, -t), (-1.0, -t)] {
        v.push(unit([0.0, a, b]));
        v.push(unit([a, b, 0.0]));
        v.push(unit([b, 0.0, a]));
    }
    v
}

/// Minkowski rounding of one convex block: erode by r, dilate by a polyhedral ball (the
/// block's own face normals, so flat faces stay where they were, and an icosahedron).
/// The radius is capped at a quarter of the block's thinnest width.
fn rounded(pts: &[P3], r: f64) -> Vec<P3> {
    let pl = planes(pts);
    let thin = pl.iter().map(|(n, d)| pts.iter().map(|p| d - dot(*n, *p)).fold(0.0, f64::max)).fold(f64::MAX, f64::min);
    let r = r.min(0.25 * thin);
    let core = eroded_vertices(&pl, r);
    if core.len() < 4 {
        return pts.to_vec();
    }
    let mut ball: Vec<P3> = pl.iter().map(|(n, _)| *n).collect();
    ball.extend(icosahedron());
    let cloud: Vec<PVec> = core
        .iter()
        .flat_map(|c| ball.iter().map(move |u| PVec::new(c[0] + r * u[0], c[1] + r * u[1], c[2] + r * u[2])))
        .collect();
    let (hv, _) = parry3d_f64::transformation::convex_hull(&cloud);
    hv.iter().map(|p| [p.x, p.y, p.z]).collect()
}

fn round_every_edge(spec: &mut Value, r: f64) {
    for b in spec["blocks"].as_array_mut().expect("blocks") {
        let v = rounded(&vertices(b), r);
        set_vertices(b, &v);
    }
}

fn scale_stone_stiffness(spec: &mut Value, f: f64) {
    for m in spec["materials"].as_array_mut().expect("materials") {
        for key in ["kn_pa_per_m", "ks_pa_per_m"] {
            let v = m[key].as_f64().expect(key);
            m[key] = serde_json::json!(v * f);
        }
    }
}

fn soft_table(spec: &mut Value, kn: f64) {
    let table = spec["table"]["material"].as_str().expect("table material").to_string();
    let mut timber = spec["materials"]
        .as_array()
        .expect("materials")
        .iter()
        .find(|m| m["name"] == table.as_str())
        .expect("the table's material")
        .clone();
    timber["name"] = serde_json::json!("soft_table");
    timber["kn_pa_per_m"] = serde_json::json!(kn);
    timber["ks_pa_per_m"] = serde_json::json!(kn / 2.0);
    spec["materials"].as_array_mut().unwrap().push(timber);
    spec["table"]["material"] = serde_json::json!("soft_table");
}

fn spring_ends(spec: &mut Value, k: f64) {
    if let Some(ends) = spec["restraints"]["ends"].as_array_mut() {
        for e in ends {
            e["kind"] = serde_json::json!("spring");
            e["stiffness_n_per_m"] = serde_json::json!(k);
        }
    }
}

/// Applies an edit to a layout's JSON.
pub fn edit(json: &str, e: Edit) -> String {
    let mut spec: Value = serde_json::from_str(json).expect("layout JSON");
    match e {
        Edit::None => {}
        Edit::Lean(d) => shear(&mut spec, d),
        Edit::Round(r) => round_every_edge(&mut spec, r),
        Edit::Stiffness(f) => scale_stone_stiffness(&mut spec, f),
        Edit::SoftBase(k) => soft_table(&mut spec, k),
        Edit::Springs(k) => spring_ends(&mut spec, k),
        Edit::LeanRound(d, r) => {
            round_every_edge(&mut spec, r);
            shear(&mut spec, d);
        }
    }
    serde_json::to_string(&spec).unwrap()
}

// ---------------------------------------------------------------------------------------
// Specimens and data sets.

/// One tilted specimen: its collapse bracket and top displacements (cm) at stable tilts.
#[derive(Debug, Clone)]
pub struct Specimen {
    /// The wall has end restraints.
    pub held: bool,
    /// Last stable and first unstable tilt, degrees.
    pub bracket: (f64, f64),
    /// Stable tilts, degrees, and the left, centre, right top y displacement there, cm.
    pub top_cm: Vec<(f64, [f64; 3])>,
    /// The mechanism read from the edited wall's own run (`None`: nothing moved or the
    /// wall stood).
    pub mechanism: Option<MechanismReading>,
    /// The mechanism as the independent observer reads the same run (`None`: the wall
    /// stood or nothing moved).
    pub independent: Option<IndependentReading>,
    /// The specimen's bed joints (the table, then its nominal course tops but the last) as
    /// fractions of its height, and its mean course height over its height.
    pub beds: (Vec<f64>, f64),
}

/// Generates realization `k` of `wall` with `seed`, edits it and tilts it at the study's
/// settings.
pub fn specimen(study: &Study, wall: &Wall, seed: u64, k: u64, e: Edit) -> Option<Specimen> {
    let generated = generate(wall, seed, k).ok()?;
    let json = edit(&generated.layout.to_json(), e);
    if let Ok(path) = std::env::var("REALWALLS_DUMP") {
        let _ = std::fs::write(format!("{path}-{k}.json"), &json);
    }
    let edited = LayoutSpec::from_json(&json).and_then(|s| s.resolve()).expect("the edited layout reads back");
    // Every state handed over: (α, stable, each body's id, fixed, centroid and orientation).
    let mut states = Vec::new();
    let t = run_tilt_observed(&edited, study.solver, study.protocol.tilt()?, &mut |alpha, stable, sim| {
        let bodies: Vec<_> = sim.state.bodies.iter().map(|b| (b.id.clone(), b.fixed(), b.pos, b.rot)).collect();
        states.push((alpha, stable, bodies));
    })
    .ok()?;
    let find = |n: &str| t.monitors.iter().position(|m| m == n);
    let idx = [find("top_left")?, find("top_centre")?, find("top_right")?];
    let top_cm = t
        .increments
        .iter()
        .filter(|i| i.stable)
        .map(|i| (i.alpha_deg, idx.map(|j| i.displacement_m[j] * 100.0)))
        .collect();
    let held = !edited.end_restraints.is_empty();
    let tops = &generated.course_tops_m;
    let h = tops.last().copied().unwrap_or(1.0);
    let beds = std::iter::once(0.0).chain(tops[..tops.len().saturating_sub(1)].iter().map(|z| z / h)).collect();
    let beds = (beds, 1.0 / tops.len().max(1) as f64);
    let independent = t.first_unstable_deg.and_then(|up| {
        let stable = states.iter().rev().find(|s| s.1 && s.0 == t.last_stable_deg)?;
        let unstable = states.iter().rev().find(|s| !s.1 && s.0 == up)?;
        let blocks: Vec<LayoutBlock> = serde_json::from_str::<Value>(&json).expect("layout JSON")["blocks"]
            .as_array()
            .expect("blocks")
            .iter()
            .map(|b| LayoutBlock {
                id: b["id"].as_str().expect("block id").to_string(),
                vertices: vertices(b),
                course: b["course"].as_u64().map(|c| c as usize),
            })
            .collect();
        let motions: Vec<(String, f64, f64, f64)> = stable
            .2
            .iter()
            .zip(&unstable.2)
            .filter(|(a, _)| !a.1)
            .map(|(a, b)| {
                assert_eq!(a.0, b.0, "the bodies are in the same order in both states");
                (a.0.clone(), (b.2 - a.2).norm(), a.3.angle_to(&b.3).to_degrees(), a.2.x)
            })
            .collect();
        read_independently(&blocks, &motions, held)
    });
    Some(Specimen {
        held,
        bracket: (t.last_stable_deg, t.first_unstable_deg.unwrap_or(t.last_stable_deg)),
        top_cm,
        mechanism: t.mechanism.reading,
        independent,
        beds,
    })
}

/// A block of the layout file as the independent observer sees it (α = 0).
#[derive(Debug, Clone)]
pub struct LayoutBlock {
    /// Its id.
    pub id: String,
    /// Its vertices, m.
    pub vertices: Vec<[f64; 3]>,
    /// Its course, if the file gives it.
    pub course: Option<usize>,
}

/// The independent observer's reading (module documentation) from the layout file's
/// blocks and, for every non-fixed body, (id, its centroid's displacement between the last
/// stable and the first unstable state (m), its rotation between them (degrees), its
/// centroid x in the last stable state); `None` when nothing moved.
pub fn read_independently(
    blocks: &[LayoutBlock],
    motions: &[(String, f64, f64, f64)],
    held: bool,
) -> Option<IndependentReading> {
    let mine: Vec<&LayoutBlock> = blocks.iter().filter(|b| motions.iter().any(|m| m.0 == b.id)).collect();
    let all = |f: &dyn Fn(&[f64; 3]) -> f64| mine.iter().flat_map(|b| b.vertices.iter().map(f)).collect::<Vec<f64>>();
    let lo = |v: Vec<f64>| v.into_iter().fold(f64::INFINITY, f64::min);
    let hi = |v: Vec<f64>| v.into_iter().fold(f64::NEG_INFINITY, f64::max);
    let (z0, z1) = (lo(all(&|p| p[2])), hi(all(&|p| p[2])));
    let (x0, x1) = (lo(all(&|p| p[0])), hi(all(&|p| p[0])));
    let largest = motions.iter().map(|m| m.1).fold(0.0, f64::max);
    if !(largest > 0.0 && z1 > z0 && x1 > x0) {
        return None;
    }
    let moving: Vec<&(String, f64, f64, f64)> =
        motions.iter().filter(|m| m.1 >= INDEPENDENT_MOVING_SHARE * largest).collect();
    let is_moving = |id: &str| moving.iter().any(|m| m.0 == id);
    let bottom = mine
        .iter()
        .filter(|b| is_moving(&b.id))
        .flat_map(|b| b.vertices.iter().map(|p| p[2]))
        .fold(f64::INFINITY, f64::min);
    let height_fraction = ((bottom - z0) / (z1 - z0)).clamp(0.0, 1.0);
    let n = moving.len() as f64;
    let rotation_deg = moving.iter().map(|m| m.2).sum::<f64>() / n;
    let xc = moving.iter().map(|m| m.3).sum::<f64>() / n;
    let start = held.then(|| {
        if (xc - 0.5 * (x0 + x1)).abs() <= 0.5 * INDEPENDENT_CENTRE_SPAN * (x1 - x0) {
            FailureStart::Centre
        } else {
            FailureStart::End
        }
    });
    // The end blocks: the first and the last block of every course along the length (of
    // the whole wall when the file gives no courses), by their centroid x.
    let centre_x = |b: &LayoutBlock| b.vertices.iter().map(|p| p[0]).sum::<f64>() / b.vertices.len() as f64;
    let mut courses: Vec<Option<usize>> = mine.iter().map(|b| b.course).collect();
    courses.sort();
    courses.dedup();
    let ends_move = courses.iter().any(|c| {
        let row: Vec<&LayoutBlock> = mine.iter().copied().filter(|b| b.course == *c).collect();
        let first = row.iter().copied().min_by(|a, b| centre_x(a).total_cmp(&centre_x(b)));
        let last = row.iter().copied().max_by(|a, b| centre_x(a).total_cmp(&centre_x(b)));
        [first, last].into_iter().flatten().any(|b| is_moving(&b.id))
    });
    let kind = if start == Some(FailureStart::Centre) && !ends_move {
        FailureKind::Bending
    } else if rotation_deg > INDEPENDENT_TOPPLING_DEG {
        FailureKind::Toppling
    } else {
        FailureKind::Sliding
    };
    Some(IndependentReading { height_fraction, kind, start, moving: moving.len(), rotation_deg })
}

/// The observations of one data set: `n` specimens per group of `study`, realizations
/// `first..first + n` of a master seed the analysis never uses, edited by `e`. Collapse
/// angle and the displacement at `tilts_deg` (the centre minus the mean of the ends for
/// held walls, the mean of the three top points for free ones); `sigma` is the σ the
/// engine is told (not the data's). The same as [`data_set_observed`]'s
/// observations, without the mechanisms.
#[allow(clippy::too_many_arguments)] // the data set's coordinates, each a plain number
pub fn data_set(
    study: &Study,
    seed: u64,
    first: u64,
    n: u64,
    e: Edit,
    noise: Noise,
    tilts_deg: &[f64],
    sigma: MeasurementSigma,
) -> Vec<Observation> {
    data_set_observed(study, seed, first, n, e, noise, &[], tilts_deg, sigma).obs
}

/// A data set: the angle and displacement observations, and the mechanisms as seen (one
/// row per specimen whose run read a mechanism, the rows of the measured mechanism file).
#[derive(Debug, Clone)]
pub struct DataSet {
    /// Collapse angles and displacements (as [`data_set`]).
    pub obs: Vec<Observation>,
    /// The mechanisms as an observer read them ([`MechanismNoise`]).
    pub mechanism: Vec<MeasuredMechanism>,
}

/// [`data_set`] and the specimens' mechanisms as seen: each specimen's own reading
/// (`TiltResult::mechanism`) read by an observer with `misreading` ([`MechanismNoise`]),
/// drawn from a stream of its own: the angles and displacements do not depend on it.
#[allow(clippy::too_many_arguments)]
pub fn data_set_with_mechanism(
    study: &Study,
    seed: u64,
    first: u64,
    n: u64,
    e: Edit,
    noise: Noise,
    seen: MechanismNoise,
    tilts_deg: &[f64],
    sigma: MeasurementSigma,
) -> DataSet {
    let mut o = data_set_observed(study, seed, first, n, e, noise, &[(Observer::Product, seen)], tilts_deg, sigma);
    DataSet { obs: o.obs, mechanism: o.mechanisms.remove(0) }
}

/// A data set read by several observers: the angle and displacement observations, and
/// the mechanism rows of each observer (in the order asked for).
#[derive(Debug, Clone)]
pub struct Observed {
    /// Collapse angles and displacements (as [`data_set`]).
    pub obs: Vec<Observation>,
    /// The rows of the measured mechanism file as each observer read them.
    pub mechanisms: Vec<Vec<MeasuredMechanism>>,
}

/// [`data_set`] and the specimens' mechanisms as each of `seen`'s observers reads them,
/// each misreading at its own rate from a stream of its own (the angles, the displacements
/// and every other observer's readings do not depend on it).
#[allow(clippy::too_many_arguments)]
pub fn data_set_observed(
    study: &Study,
    seed: u64,
    first: u64,
    n: u64,
    e: Edit,
    noise: Noise,
    seen: &[(Observer, MechanismNoise)],
    tilts_deg: &[f64],
    sigma: MeasurementSigma,
) -> Observed {
    use rayon::prelude::*;
    let todo: Vec<(usize, u64)> =
        (0..study.groups.len()).flat_map(|gi| (first..first + n).map(move |k| (gi, k))).collect();
    let tilted: Vec<Option<Specimen>> =
        todo.par_iter().map(|&(gi, k)| specimen(study, &study.groups[gi].walls[0], seed, k, e)).collect();
    let mut obs = Vec::new();
    let mut mechanisms = vec![Vec::new(); seen.len()];
    for (&(gi, k), s) in todo.iter().zip(tilted) {
        let g = &study.groups[gi];
        let Some(s) = s else { continue };
        let held = s.held;
        let measure = if held { Measure::CenterMinusMeanOfEnds } else { Measure::MeanOfLeftCenterRight };
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (k << 8) ^ gi as u64);
        let mut z = || -> f64 { StandardNormal.sample(&mut rng) };
        let name = format!("{}-{}", g.name, k);
        let alpha = s.bracket.0 + (s.bracket.1 - s.bracket.0) * rng_uniform(seed, k, gi);
        let angle = round_to(alpha + noise.angle_deg * z(), noise.angle_reading_deg);
        obs.push(Observation {
            specimen: name.clone(),
            group: g.name.clone(),
            observable: Observable::CollapseAngle,
            value: angle,
            sigma: sigma.angle_deg,
        });
        for &t in tilts_deg {
            if t > angle {
                continue;
            }
            let Some((_, [l, c, r])) = s.top_cm.iter().find(|(a, _)| (a - t).abs() < 1e-9) else { continue };
            let v = if held { c - 0.5 * (l + r) } else { (l + c + r) / 3.0 };
            obs.push(Observation {
                specimen: name.clone(),
                group: g.name.clone(),
                observable: Observable::Displacement { measure, tilt_deg: t },
                value: round_to(v + noise.displacement_cm * z(), noise.displacement_reading_cm),
                sigma: sigma.displacement_cm,
            });
        }
        for (&(observer, noise), rows) in seen.iter().zip(&mut mechanisms) {
            let group = g.measured_group.clone();
            match observer {
                Observer::Product => {
                    if let Some(r) = s.mechanism {
                        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x6d65_6368_0000_0000 ^ (k << 8) ^ gi as u64);
                        rows.push(read_as_seen(&r, &s.beds, noise, &mut rng, name.clone(), group));
                    }
                }
                Observer::Independent => {
                    if let Some(r) = s.independent {
                        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x696e_6465_7000_0000 ^ (k << 8) ^ gi as u64);
                        rows.push(read_independent_as_seen(&r, &s.beds, noise, &mut rng, name.clone(), group));
                    }
                }
            }
        }
    }
    Observed { obs, mechanisms }
}

/// The index of the bed joint of `beds` nearest the height fraction `f`.
fn nearest_bed(beds: &[f64], f: f64) -> usize {
    (0..beds.len()).min_by(|&a, &b| (beds[a] - f).abs().total_cmp(&(beds[b] - f).abs())).unwrap_or(0)
}

/// A realization's mechanism as an observer reads it ([`MechanismNoise`]); four draws
/// from `rng` whatever the outcome.
fn read_as_seen(
    r: &MechanismReading,
    beds: &(Vec<f64>, f64),
    seen: MechanismNoise,
    rng: &mut ChaCha8Rng,
    specimen: String,
    group: String,
) -> MeasuredMechanism {
    let f = r.failure_height_fraction;
    let v = beds.0.get(nearest_bed(&beds.0, f)).copied().unwrap_or(f);
    let half = 0.5 * beds.1;
    let kind = misread(&FailureKind::ALL, r.kind, seen.misreading, rng);
    let start = misread(&FailureStart::SIMULATED, r.start, seen.misreading, rng);
    MeasuredMechanism {
        specimen,
        group,
        failure_height: Some((v, (v - half).max(0.0), (v + half).min(1.0))),
        kind: Some(kind),
        start: Some(start),
        extent: None,
        source: "tests/realwalls: the edited wall's own run, read to the nearest bed joint, misread".into(),
        ..Default::default()
    }
}

/// The independent observer's reading as seen ([`Observer::Independent`]): the height to
/// the nearest bed joint, read one joint up or down with probability `misreading / 2`
/// each (kept on the wall); the kind and the start each replaced with probability
/// `misreading` by another category drawn uniformly. Six draws from `rng` whatever the
/// outcome (a free wall's missing start too).
fn read_independent_as_seen(
    r: &IndependentReading,
    beds: &(Vec<f64>, f64),
    seen: MechanismNoise,
    rng: &mut ChaCha8Rng,
    specimen: String,
    group: String,
) -> MeasuredMechanism {
    let (u, up): (f64, bool) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0) < 0.5);
    let mut i = nearest_bed(&beds.0, r.height_fraction);
    if u < seen.misreading && !beds.0.is_empty() {
        i = if up { (i + 1).min(beds.0.len() - 1) } else { i.saturating_sub(1) };
    }
    let v = beds.0.get(i).copied().unwrap_or(r.height_fraction);
    let half = 0.5 * beds.1;
    let kind = misread(&FailureKind::ALL, r.kind, seen.misreading, rng);
    let start = misread(&FailureStart::SIMULATED, r.start.unwrap_or(FailureStart::End), seen.misreading, rng);
    MeasuredMechanism {
        specimen,
        group,
        failure_height: Some((v, (v - half).max(0.0), (v + half).min(1.0))),
        kind: Some(kind),
        start: r.start.map(|_| start),
        extent: None,
        source: "tests/realwalls: the independent observer (centroid motions), to the nearest bed joint, misread"
            .into(),
        ..Default::default()
    }
}

/// `own`, or with probability `e` another of `all` drawn uniformly (two draws from `rng`).
fn misread<T: Copy + PartialEq>(all: &[T], own: T, e: f64, rng: &mut ChaCha8Rng) -> T {
    let (u, j): (f64, f64) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
    let others: Vec<T> = all.iter().copied().filter(|c| *c != own).collect();
    if u < e && !others.is_empty() {
        others[((j * others.len() as f64) as usize).min(others.len() - 1)]
    } else {
        own
    }
}

/// Writes `rows` as the measured mechanism file (`dir/MECHANISM_FILE`, the format of
/// `[measured] mechanism`), reads it back with the library's reader, checks it against
/// the study's groups and returns its observations (`sigma.failure_height` for the heights).
pub fn mechanism_observations_via_file(
    study: &Study,
    dir: &Path,
    rows: &[MeasuredMechanism],
    sigma: MeasurementSigma,
) -> Vec<Observation> {
    std::fs::create_dir_all(dir).expect("a directory for the mechanism file");
    let path: PathBuf = dir.join(MECHANISM_FILE);
    std::fs::write(&path, mechanism_csv(rows)).expect("the mechanism file is written");
    let read = read_measured_mechanism(&path).expect("the mechanism file reads back");
    let groups: Vec<(String, String)> =
        study.groups.iter().map(|g| (g.measured_group.clone(), g.name.clone())).collect();
    let ctx = StudyContext { groups: groups.iter().map(|(m, _)| (m.clone(), f64::INFINITY)).collect(), step_deg: None };
    check_mechanism_against_study(&read, &[], &[], &ctx).expect("the mechanism file is valid");
    drystone::discrepancy::mechanism_observations(&read, &groups, sigma).expect("mechanism observations")
}

/// Observations holding every mechanism key of every group (the failure height, each
/// kind, each simulated start): the template a preparation needs for data sets with
/// mechanisms, whatever the misreadings make of them.
pub fn mechanism_template(study: &Study, sigma: MeasurementSigma) -> Vec<Observation> {
    let mut out = Vec::new();
    for g in &study.groups {
        let one = |observable: Observable, sigma: f64| Observation {
            specimen: format!("{}-template", g.name),
            group: g.name.clone(),
            observable,
            value: 1.0,
            sigma,
        };
        out.push(one(Observable::FailureHeight { width: 0.0 }, sigma.failure_height));
        out.extend(FailureKind::ALL.map(|kind| one(Observable::MechanismKind { kind }, 1.0)));
        out.extend(FailureStart::SIMULATED.map(|start| one(Observable::MechanismStart { start }, 1.0)));
    }
    out
}

fn rng_uniform(seed: u64, k: u64, g: usize) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(31) ^ k.rotate_left(17) ^ ((g as u64) << 40));
    rng.random_range(0.0..1.0)
}

/// Which class an analysis's answer falls in, for an edit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Answer {
    /// No cause named.
    NoEffect,
    /// The misfit is significant and unexplained.
    Unexplained,
    /// A named cause (or a tie containing the expected one).
    Right,
    /// A cause named that is not the expected one.
    Wrong,
}

/// The effect names that count as right for an edit.
pub fn expected(e: Edit) -> &'static [&'static str] {
    match e {
        Edit::None => &[],
        Edit::Lean(_) => &["initial_lean"],
        Edit::Round(_) => &["edge_rounding"],
        // Every stone joint: the all-joints factor, or the families that carry most of it.
        Edit::Stiffness(_) => &["kn_scale", "bed_stiffness", "head_stiffness", "base_stiffness", "joint_closure"],
        // A joint-law effect (stiffness of a family or of all joints, a closure law); never
        // a geometric or a restraint effect.
        Edit::SoftBase(_) => {
            &["base_stiffness", "kn_scale", "bed_stiffness", "head_stiffness", "joint_closure", "seating_gap"]
        }
        Edit::Springs(_) => &["restraint_stiffness"],
        Edit::LeanRound(_, _) => &["initial_lean", "edge_rounding"],
    }
}

/// Classifies an analysis's answer: the cause's name (`a` or `a+b`) and its tie.
pub fn classify(e: Edit, verdict: &str, cause: Option<&str>, tie: &[String]) -> Answer {
    let ok = expected(e);
    let members = |name: &str| name.split('+').all(|m| ok.contains(&m));
    match (verdict, cause) {
        ("no_effect", _) => Answer::NoEffect,
        ("unexplained", None) => Answer::Unexplained,
        (_, Some(c)) => {
            if members(c) || tie.iter().any(|t| members(t)) && !ok.is_empty() {
                Answer::Right
            } else if verdict == "unexplained" {
                Answer::Unexplained
            } else {
                Answer::Wrong
            }
        }
        _ => Answer::NoEffect,
    }
}
