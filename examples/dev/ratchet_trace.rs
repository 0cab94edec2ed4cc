//! Diagnostic: every increment of a cyclic in-plane run by the penalty DEM (shear span
//! 1.325 m), the motion of named blocks from their poses under the vertical force (dx, dz
//! mm; rotation about y, mrad), as CSV on stdout: where a wall's blocks ratchet over the
//! cycles (the beam is `loading_beam`).
//! `[DRIFT=3] [STEP_MM=0.25] [SOLVER=penalty] [TOL=1e-4] cargo run --release --example
//! ratchet_trace -- LAYOUT.json SIGMA0_MPA BLOCK...`
use drystone::dem::SolverParams;
use drystone::loading::inplane::{run_in_plane_penalty, History, InPlaneParams};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let layout = drystone::layout::Layout::from_file(std::path::Path::new(&args[1])).expect("layout");
    let sigma0: f64 = args[2].parse().expect("sigma0");
    let names: Vec<String> = args[3..].to_vec();
    let params = InPlaneParams {
        sigma0_mpa: sigma0,
        shear_span_m: Some(1.325),
        drift_pct: std::env::var("DRIFT").map_or(3.0, |v| v.parse().expect("DRIFT")),
        history: History::Cyclic,
        step_mm: std::env::var("STEP_MM").map_or(InPlaneParams::default().step_mm, |v| v.parse().expect("STEP_MM")),
        ..InPlaneParams::default()
    };
    let mut solver = SolverParams::default();
    if let Ok(k) = std::env::var("SOLVER") {
        solver.kind = drystone::dem::SolverKind::from_name(&k).expect("SOLVER");
    }
    if let Ok(t) = std::env::var("TOL") {
        solver.penalty.tolerance = t.parse().expect("TOL");
    }
    let mut reference: Option<Vec<_>> = None;
    let mut idx: Vec<usize> = Vec::new();
    print!("k,drift,conv");
    for n in &names {
        print!(",{n}_dx,{n}_dz,{n}_ry");
    }
    println!();
    let mut k = 0usize;
    let _ = run_in_plane_penalty(&layout, solver, &params, &mut |drift, conv, sim| {
        let now: Vec<_> = sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
        if idx.is_empty() {
            idx = names
                .iter()
                .map(|n| sim.state.bodies.iter().position(|b| &b.id == n).unwrap_or_else(|| panic!("{n}")))
                .collect();
        }
        let r = reference.get_or_insert_with(|| now.clone());
        print!("{k},{drift:.5},{}", conv as u8);
        for &b in &idx {
            let d = now[b].0 - r[b].0;
            let turn = (now[b].1 * r[b].1.inverse()).scaled_axis();
            print!(",{:.4},{:.4},{:.4}", d.x * 1e3, d.z * 1e3, turn.y * 1e3);
        }
        println!();
        k += 1;
    });
}
