use drystone::verify::*;
use drystone::loading::tilt::*;
use drystone::dem::SolverParams;
use drystone::dem::contact::law::Quadrature;
use drystone::layout::BaseSliding;
#[test]
fn scratch() {
    let (b,h)=(0.1125,0.375);
    for kn in [5e7, 1e9] {
        let exp = winkler_collapse_angle(b,h,DENSITY,9.81,kn).to_degrees();
        for q in [Quadrature::Exact, Quadrature::Vertex] {
        for n in [1u32,2,4,8] {
            let l = layout_of(vec![rect_block(b, h, 0.3)], kn, kn / 2.0, 60.0, BaseSliding::Free);
            let solver = SolverParams { subcontact_subdivisions: n, quadrature: q, ..SolverParams::default() };
            let p = TiltParams{resolution_deg:0.01, ..TiltParams::default()};
            let t=std::time::Instant::now();
            let r = run_tilt(&l, solver, &p).unwrap();
            println!("kn {kn:e} {q:?} n {n} exp {exp:.3} sim {:.3} steps {} reason {:?} {:.2}s", r.collapse_angle_deg, r.steps, r.collapse_reason, t.elapsed().as_secs_f64());
        }}
    }
}
