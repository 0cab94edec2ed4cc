//! The solver seam end to end: a study's `[solver] kind` chooses the solver of every
//! realization, with the same tables; each solver checked against a closed form.

use drystone::dem::{SolverKind, SolverParams};
use drystone::ensemble::Shard;
use drystone::layout::BaseSliding;
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::study::{run_study, Study};
use drystone::verify::{box_vertices, layout_of};
use std::path::{Path, PathBuf};

fn study(name: &str, solver: &str, protocol: &str) -> PathBuf {
    let walls = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls");
    let dir = std::env::temp_dir().join(format!("drystone-seam-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = format!(
        "version = 1\nname = \"{name}\"\nseed = 1\nrealizations = 2\nprotocol = \"{protocol}\"\n\
         [solver]\nkind = \"{solver}\"\n[[groups]]\nname = \"CBL\"\nwall = {:?}\n",
        walls.join("cbl.toml")
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// `kind = "limit"`: every CBL realization collapses at the rigid overturning of the
/// section as one monolith about its toe, tan α = (B/2) / z_c = 0.075 / 0.1674 (the
/// through-stone layout on a held base), by limit analysis.
#[test]
fn a_study_by_limit_analysis_gives_the_monolith_angle() {
    let s = Study::from_file(&study("limit_cbl", "limit", "tilt")).unwrap();
    let rows = run_study(&s, Shard::ALL);
    let exact = (0.075_f64 / 0.1674).atan().to_degrees();
    for r in &rows {
        let a = r.collapse.collapse_angle_deg.expect("collapsed");
        assert!((a - exact).abs() < 0.05, "{a} vs {exact}: {}", r.error);
        assert_eq!(r.collapse.first_unstable_deg, Some(a));
        assert_eq!(r.collapse.collapse_reason, "no_equilibrium");
        assert_eq!(r.collapse.mechanism, "toppling");
    }
}

/// `kind = "nscd"` is refused for the lateral load, naming the key; an unknown kind is
/// refused by the study file's parser.
#[test]
fn a_solver_that_cannot_run_the_protocol_is_refused_naming_the_key() {
    let e = Study::from_file(&study("nscd_lateral", "nscd", "lateral")).unwrap_err().to_string();
    assert!(e.contains("solver.kind"), "{e}");
    let e = Study::from_file(&study("rigid", "rigid", "tilt")).unwrap_err().to_string();
    assert!(e.contains("rigid") && e.contains("nscd"), "{e}");
}

/// The same rigid block through the seam with every solver: the penalty methods at a stiff
/// joint below the rigid limit by the Winkler rotation, the non-smooth solver's bracket
/// holding the rigid limit tan α = b/h itself.
#[test]
fn every_solver_runs_the_tilting_table_through_the_seam() {
    let (b, h) = (0.1125, 0.375);
    let l = layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [0.3, b / 2.0, h])], 1e11, 5e10, 60.0, BaseSliding::Free);
    let rigid = (b / h).atan().to_degrees();
    let params = TiltParams { resolution_deg: 0.0625, ..TiltParams::default() };
    let nscd = run_tilt(&l, SolverParams { kind: SolverKind::Nscd, ..SolverParams::default() }, &params).unwrap();
    let up = nscd.first_unstable_deg.unwrap();
    assert!(nscd.last_stable_deg <= rigid && rigid <= up, "nscd [{}, {up}] vs {rigid}", nscd.last_stable_deg);
    // The penalty methods agree with each other within one bracket, below the rigid limit
    // (the exact finite-rotation Winkler angle of this block is 16.31°, `drystone verify`).
    for kind in
        [SolverKind::Penalty, SolverKind::Newton, SolverKind::Implicit, SolverKind::Accelerated, SolverKind::Relaxation]
    {
        let r = run_tilt(&l, SolverParams { kind, ..SolverParams::default() }, &params).unwrap();
        let up = r.first_unstable_deg.unwrap();
        assert!(r.last_stable_deg <= 16.31 + 0.02 && up >= 16.31 - 0.02, "{kind}: [{}, {up}]", r.last_stable_deg);
        // Only a Newton stage hands increments over; it solves the block's stable ones itself.
        let handed: Vec<f64> = r.increments.iter().filter(|i| i.newton_handed_over).map(|i| i.alpha_deg).collect();
        if kind == SolverKind::Newton {
            let stable = r.increments.iter().filter(|i| i.stable && i.alpha_deg < 15.0).count();
            let early = handed.iter().filter(|&&a| a < 15.0).count();
            assert!(stable > 0 && early == 0, "{kind}: handed over at {handed:?}");
        } else {
            assert!(handed.is_empty(), "{kind}: handed over at {handed:?}");
        }
    }
}

/// The compatibility table reaches studies: `protocol = "lateral"` with `pushover = true`
/// and `kind = "nscd"` runs the rigid pushover in every realization (as
/// `loading::lateral_nscd` alone, bit for bit) and `kind = "limit"` the limit analysis of
/// the same pressure; the rigid λ by bisection lies within its 1 % bracket of the
/// associative limit load multiplier's non-associative answer or below it (a lower bound by
/// dynamics of rigid blocks against the statics' λ), and each row's status says whether
/// λ ≥ 1.
#[test]
fn a_study_runs_the_rigid_pushover_and_limit_analysis_through_the_table() {
    use drystone::layout::Layout;
    use drystone::loading::lateral::LateralParams;
    let wall = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/studies/walls/tiny_running_bond.toml");
    let dir = std::env::temp_dir().join(format!("drystone-seam-{}-pushover", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |kind: &str| {
        let text = format!(
            "version = 1\nname = \"push_{kind}\"\nseed = 3\nrealizations = 2\nprotocol = \"lateral\"\n\
             [lateral]\npushover = true\npressure_base_pa = 400.0\npressure_top_pa = 400.0\n\
             [solver]\nkind = \"{kind}\"\n[[groups]]\nname = \"tiny\"\nwall = {wall:?}\n"
        );
        let path = dir.join(format!("{kind}.toml"));
        std::fs::write(&path, text).unwrap();
        Study::from_file(&path).unwrap()
    };
    let (nscd, limit) = (file("nscd"), file("limit"));
    let (a, b) = (run_study(&nscd, Shard::ALL), run_study(&limit, Shard::ALL));
    let params =
        LateralParams { pressure_base_pa: 400.0, pressure_top_pa: 400.0, pushover: true, ..LateralParams::default() };
    for (i, (rn, rl)) in a.iter().zip(&b).enumerate() {
        assert!(rn.error.is_empty() || !rn.status.is_ok(), "{rn:?}");
        let layout: Layout = drystone::effects::realize(&nscd.groups[0].walls[0], 3, i as u64, "tiny", &[]).unwrap().1;
        let direct = drystone::loading::lateral_nscd::run_lateral_nscd(&layout, &nscd.solver.nscd, &params).unwrap();
        assert_eq!(rn.pushover.load_multiplier_dem, Some(direct.lambda_stable), "{rn:?}");
        assert_eq!(rn.pushover.load_multiplier_dem_unstable, direct.lambda_unstable);
        let rigid = direct.lambda_stable;
        let lim = rl.pushover.load_multiplier_limit.expect("limit λ");
        assert!(rigid <= lim * 1.02, "nscd λ {rigid} against limit analysis {lim}");
        assert!(rigid >= 0.8 * lim, "nscd λ {rigid} against limit analysis {lim}");
        assert_eq!(rn.status == drystone::ensemble::row::Status::Stood, rigid >= 1.0, "{rn:?}");
        assert_eq!(rl.status == drystone::ensemble::row::Status::Stood, lim >= 1.0, "{rl:?}");
    }
}

/// The command line reads the same table: `tilt --solver limit` and `lateral --solver
/// limit` are the limit analyses of `drystone limit` (the same load multiplier to the
/// last digit), `tilt --by-hand` with the penalty solver is refused naming the methods
/// that run it, and `lateral --solver nscd` without `--pushover` still runs the rigid
/// pushover, with a deprecation line.
#[test]
fn the_command_line_follows_the_table() {
    use std::process::Command;
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_drystone")).args(args).output().unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let lambda = |json: &str| -> f64 {
        let v: serde_json::Value = serde_json::from_str(json).expect(json);
        v["load_multiplier"].as_f64().expect("load_multiplier")
    };
    let layout = "data/layouts/single_block.json";
    let (code, tilt, err) = run(&["tilt", layout, "--solver", "limit", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let (_, limit, _) = run(&["limit", layout, "--json"]);
    assert_eq!(lambda(&tilt).to_bits(), lambda(&limit).to_bits());
    let (code, lateral, err) = run(&["lateral", layout, "--solver", "limit", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let (_, limit, _) = run(&["limit", layout, "--protocol", "lateral", "--json"]);
    assert_eq!(lambda(&lateral).to_bits(), lambda(&limit).to_bits());
    let (code, _, err) = run(&["tilt", layout, "--by-hand", "--solver", "penalty"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("rolled by hand") && err.contains("nscd"), "{err}");
    let (code, out, err) = run(&["lateral", layout, "--solver", "nscd", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("deprecated") && lambda(&out) > 0.0, "{err}");
}

/// Every solver kind of the one list (`SolverKind::ALL`) is accepted by `--solver` of each
/// command that takes it (clap reads it through `FromStr`: a name it refuses is "invalid
/// value", a name it accepts gets past the options to the missing input), and the Python
/// package's tests run every one of them (`SOLVERS` of `python/tests/test_model.py`, the
/// names `drystone.supports` parses through the same `FromStr`).
#[test]
fn every_solver_kind_is_accepted_by_the_command_line_and_the_python_tests() {
    use std::process::Command;
    let commands: [&[&str]; 5] = [
        &["tilt", "/nonexistent/layout.json"],
        &["lateral", "/nonexistent/layout.json"],
        &["shake", "/nonexistent/layout.json"],
        &["in-plane", "/nonexistent/layout.json"],
        &["bench", "no_such_case"],
    ];
    let refused = |args: &[&str], name: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_drystone")).args(args).args(["--solver", name]).output().unwrap();
        assert!(!out.status.success(), "{args:?} --solver {name} ran");
        String::from_utf8_lossy(&out.stderr).contains("invalid value")
    };
    for args in commands {
        for k in SolverKind::ALL {
            assert_eq!(k.name().parse::<SolverKind>(), Ok(k));
            assert!(!refused(args, k.name()), "{args:?} --solver {} refused by the command line", k.name());
        }
        assert!(refused(args, "rigid"), "{args:?} --solver rigid accepted");
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("python/tests/test_model.py")).unwrap();
    let line = text.lines().find(|l| l.starts_with("SOLVERS = (")).expect("SOLVERS in test_model.py");
    let listed: Vec<&str> = line.split('"').skip(1).step_by(2).collect();
    assert_eq!(listed, SolverKind::ALL.map(SolverKind::name), "python/tests/test_model.py's SOLVERS");
}
