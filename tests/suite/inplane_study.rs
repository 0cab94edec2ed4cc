//! The in-plane study on a tiny wall (two courses, a few blocks, a short monotonic history):
//! its `[solver]` table chooses the method as in every study, the groups' own keys are
//! refused in `[in_plane]`.

use drystone::dem::{SolverKind, SolverParams};
use drystone::loading::inplane::{History, InPlaneParams};
use std::path::{Path, PathBuf};

const WALL: &str = r#"version = 1
name = "tiny granite wall"
kind = "sawn_stone"
[geometry]
length_m = 0.4
height_m = 0.3
base_width_m = 0.2
top_width_m = 0.2
batter = "symmetric"
[arrangement]
kind = "discontinuous"
overlap = 0.5
[courses]
height_m = 0.15
[blocks]
length_m = 0.2
material = "granite"
[[materials]]
name = "granite"
density_kg_per_m3 = 2600.0
kn_pa_per_m = 2.0e10
ks_pa_per_m = 1.0e9
friction_deg = 32.2
cohesion_pa = 0.0
tensile_strength_pa = 0.0
[restraints]
base = "free"
ends = { kind = "free" }
"#;

/// Two groups (3 and 2 realizations) on the tiny wall; `extra` goes before `[in_plane]`,
/// `in_plane` into it.
fn study_text(extra: &str, in_plane: &str) -> String {
    format!(
        "version = 1\nname = \"tiny\"\nseed = 7\nrealizations = 3\nprotocol = \"in_plane\"\n{extra}\n[in_plane]\n\
         shear_span_m = 0.35\ndrift_pct = 0.4\n{in_plane}\n[[groups]]\nname = \"a\"\nwall = \"wall.toml\"\n\
         sigma0_mpa = 0.5\n\n[[groups]]\nname = \"b\"\nwall = \"wall.toml\"\nsigma0_mpa = 0.25\nrealizations = 2\n"
    )
}

/// A fresh folder with the tiny wall.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drystone-inplane-study-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("wall.toml"), WALL).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `[solver] kind = "nscd"` runs every realization by non-smooth contact dynamics: the row
/// is the one a direct nscd run of the same realization gives, bit for bit, and not the
/// penalty DEM's; limit analysis, which draws no curve, is refused at `solver.kind`.
#[test]
fn the_solver_table_chooses_the_method() {
    let dir = folder("solver");
    let nscd = write(&dir, "nscd.toml", &study_text("[solver]\nkind = \"nscd\"\n", ""));
    let penalty = write(&dir, "penalty.toml", &study_text("", ""));
    let spec = drystone::study::inplane::load(&nscd).unwrap();
    assert_eq!(spec.solver.kind, SolverKind::Nscd);
    let by_nscd = drystone::study::inplane::run(&nscd, &dir.join("n")).unwrap();
    let by_penalty = drystone::study::inplane::run(&penalty, &dir.join("p")).unwrap();
    assert_eq!(by_nscd.rows.len(), 5);
    let wall = drystone::generator::Wall::from_file(&dir.join("wall.toml")).unwrap();
    for (g, sigma0_mpa, i) in [(0usize, 0.5, 0u64), (1, 0.25, 1)] {
        let index = g as u64 * 10_000 + i;
        let row = by_nscd.rows.iter().find(|r| r.index == index).unwrap();
        let (_, layout) = drystone::effects::realize(&wall, 7, index, &row.group, &[]).unwrap();
        let params = InPlaneParams {
            sigma0_mpa,
            history: History::Monotonic,
            shear_span_m: Some(0.35),
            drift_pct: 0.4,
            ..InPlaneParams::default()
        };
        let solver = SolverParams { kind: SolverKind::Nscd, ..SolverParams::default() };
        let run = drystone::protocol::run(&drystone::protocol::InPlane(params), &layout, solver, &mut ()).unwrap();
        let drystone::protocol::InPlaneRun::Nscd(Ok(direct)) = run else { panic!("{run:?}") };
        let d = direct.positive.unwrap();
        assert_eq!(row.status, "ok", "{row:?}");
        assert_eq!(row.peak_pos_kn.to_bits(), d.peak_force_kn.to_bits());
        assert_eq!(row.stiffness_pos_kn_per_mm.to_bits(), d.initial_stiffness_kn_per_mm.to_bits());
        assert_eq!(row.mechanism, direct.mechanism.kind.name());
        let p = by_penalty.rows.iter().find(|r| r.index == index).unwrap();
        assert_ne!(p.peak_pos_kn.to_bits(), row.peak_pos_kn.to_bits(), "the penalty DEM's row differs");
    }
    let report = std::fs::read_to_string(dir.join("n/report.md")).unwrap();
    assert!(report.contains("non-smooth contact dynamics"), "{report}");
    // A method that gives no curve, and a kind that is not one, refused by key.
    let limit = write(&dir, "limit.toml", &study_text("[solver]\nkind = \"limit\"\n", ""));
    let e = drystone::study::inplane::load(&limit).unwrap_err().to_string();
    assert!(e.contains("solver.kind") && e.contains("limit"), "{e}");
    let bad = write(&dir, "bad.toml", &study_text("[solver]\nkind = \"rigid\"\n", ""));
    let e = drystone::study::inplane::load(&bad).unwrap_err().to_string();
    assert!(e.contains("rigid") && e.contains("kind"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The groups' own keys given in `[in_plane]` (every group would overwrite them) are
/// refused, naming the key.
#[test]
fn the_groups_keys_are_refused_in_the_shared_table() {
    let dir = folder("keys");
    for key in ["sigma0_mpa = 0.5", "history = \"cyclic\""] {
        let p = write(&dir, "study.toml", &study_text("", key));
        let e = drystone::study::inplane::load(&p).unwrap_err().to_string();
        let name = key.split(' ').next().unwrap();
        assert!(e.contains(&format!("in_plane.{name}")), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
