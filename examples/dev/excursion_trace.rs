//! Diagnostic: the largest block excursion (`loading::excursion`) after each increment of an
//! in-plane run, with the block's speed and contacts, to find where a block leaves the wall.
//! `cargo run --release --example excursion_trace -- LAYOUT.json SIGMA0_MPA [cyclic]`
use drystone::dem::SolverParams;
use drystone::loading::excursion::JointNeighbours;
use drystone::loading::inplane::{run_in_plane_penalty, History, InPlaneParams, Rig};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let layout = drystone::layout::Layout::from_file(std::path::Path::new(&args[1])).expect("layout");
    let sigma0: f64 = args[2].parse().expect("sigma0");
    let cyclic = args.get(3).is_some_and(|a| a == "cyclic");
    let params = InPlaneParams {
        sigma0_mpa: sigma0,
        shear_span_m: Some(1.325),
        drift_pct: 3.25,
        history: if cyclic { History::Cyclic } else { History::Monotonic },
        ..InPlaneParams::default()
    };
    let rig = Rig::build(&layout, &params).expect("rig");
    let nb = JointNeighbours::of(&rig.layout);
    let mut reference = None;
    let mut k = 0usize;
    let mut last = 0.0;
    let _ = run_in_plane_penalty(&layout, SolverParams::default(), &params, &mut |drift, conv, sim| {
        let now: Vec<_> = sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
        let r = reference.get_or_insert_with(|| now.clone());
        let (e, b) = nb.largest(r, &now);
        if e > last + 1e-3 || k % 500 == 0 {
            let id = b.map_or("-".to_string(), |b| sim.state.bodies[b].id.clone());
            let v = b.map_or(0.0, |b| sim.state.bodies[b].vel.norm());
            let (fx, _) = b.map_or((Default::default(), Default::default()), |b| sim.unbalanced(b));
            let d = b.map_or(Default::default(), |b| now[b].0 - r[b].0);
            let turn = b.map_or(Default::default(), |b| (now[b].1 * r[b].1.inverse()).scaled_axis());
            println!(
                "   moved {:.2} {:.2} {:.2} mm, turned {:.4} {:.4} {:.4} rad",
                d.x * 1e3,
                d.y * 1e3,
                d.z * 1e3,
                turn.x,
                turn.y,
                turn.z
            );
            println!(
                "inc {k} drift {drift:+.3} % conv {conv} excursion {:.2} mm block {id} speed {v:.3e} m/s unbalanced {:.3e} N",
                e * 1e3,
                fx.norm()
            );
            last = e;
        }
        k += 1;
    });
}
