use super::*;
use crate::dem::{RunToEquilibrium, SolverParams};
use crate::layout::BaseSliding;
use crate::verify::{box_vertices, layout_of};

/// A block `[x0, y0, z0]`–`[x1, y1, z1]` (m) on the table, φ 35°, Kn `kn` Pa/m, Ks Kn/2,
/// settled under gravity.
fn settled_on(min: [f64; 3], max: [f64; 3], kn: f64) -> Simulation {
    let l = layout_of(vec![box_vertices(min, max)], kn, kn / 2.0, 35.0, BaseSliding::Free);
    let mut sim = Simulation::new(&l, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-9, 400_000).unwrap());
    sim
}

fn settled(min: [f64; 3], max: [f64; 3]) -> Simulation {
    settled_on(min, max, 1e8)
}

fn block() -> Simulation {
    settled([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])
}

/// Tilted by 10° (below φ and the rocking limit), a settled block finds its new
/// equilibrium in a few Newton iterations, and it is the one dynamic relaxation finds (the
/// joint sticks, so the equilibrium does not depend on the path): the same pose to 1e-9 m
/// and 1e-8 rad.
#[test]
fn a_block_below_its_friction_angle_converges_in_a_few_iterations_to_the_relaxed_equilibrium() {
    let mut sim = block();
    sim.set_tilt(10f64.to_radians());
    let mut dynamic = sim.clone();
    let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
    let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
    assert!(it <= 6, "{it} iterations");
    assert!(dynamic.run_to_equilibrium(1e-9, 1_000_000).unwrap());
    let (a, b) = (&sim.state.bodies[0], &dynamic.state.bodies[0]);
    assert!((a.pos - b.pos).norm() < 1e-9, "{:?} against {:?}", a.pos, b.pos);
    assert!(a.rot.angle_to(&b.rot) < 1e-8);
}

/// Tilted past its friction angle (40° against φ 35°) a block has no equilibrium: the
/// tangent is singular along the slide, no step length reduces the out-of-balance force,
/// and the solve says so after one or two iterations (not the whole budget), leaving the
/// state as it was.
#[test]
fn a_block_past_its_friction_angle_is_unsolved_at_once_and_left_as_it_was() {
    let mut sim = block();
    sim.set_tilt(40f64.to_radians());
    let before = sim.state.bodies.clone();
    let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
    let Solved::Unsolved(Unsolved::NoDescent, it) = out else { panic!("{out:?}") };
    assert!(it <= 3, "{it} iterations");
    assert_eq!(sim.state.bodies, before);
}

/// A slender rigid block (b = 0.1 m across the tilt, h = 0.4 m) rocks over at
/// tan α = b/h (14.04°); on joints of finite stiffness earlier, since the block's rotation
/// on its compressed strip adds to the eccentricity of its weight (on Kn 1e8 Pa/m already
/// below 12°). On Kn 1e10 Pa/m at 13°, the resultant at 0.46 b/2 from the middle and
/// nine tenths of the base lifted off, Newton converges to the equilibrium dynamic
/// relaxation finds: in about twenty iterations, the line search cutting the steps while
/// the base lifts off (about a dozen), then quadratically. The same pose to 1e-6 m and
/// 1e-5 rad (of a sway of 3e-4 m): the lifted part of the base slips, and the slip left
/// depends on the path (one jump here, the relaxation's steps there).
#[test]
fn a_rocking_block_near_its_limit_converges() {
    let mut sim = settled_on([0.0, -0.05, 0.0], [0.3, 0.05, 0.4], 1e10);
    sim.set_tilt(13f64.to_radians());
    let mut dynamic = sim.clone();
    let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
    let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
    assert!(it <= 25, "{it} iterations");
    assert!(dynamic.run_to_equilibrium(1e-9, 2_000_000).unwrap());
    let (a, b) = (&sim.state.bodies[0], &dynamic.state.bodies[0]);
    assert!((a.pos - b.pos).norm() < 1e-6, "{:?} against {:?}", a.pos, b.pos);
    assert!(a.rot.angle_to(&b.rot) < 1e-5, "{}", a.rot.angle_to(&b.rot));
}

/// Close to its friction angle (33° against φ 35°) the joint carries the slope's load
/// with its shear springs near the slip limit: Newton converges, to the equilibrium the
/// statics give (the joint carries `W sin α` along the slope).
#[test]
fn the_slip_tangent_converges_where_some_sub_contacts_slip() {
    let mut sim = block();
    sim.set_tilt(33f64.to_radians());
    let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
    let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
    assert!(it <= 12, "{it} iterations");
    // Equilibrium: the joint carries W sin α along the slope.
    let w = sim.state.bodies[0].mass * sim.state.gravity_magnitude;
    let fy: f64 = sim.state.contacts.iter().map(|c| c.force.y).sum();
    assert!((fy + w * 33f64.to_radians().sin()).abs() < 1e-6 * w, "{fy} against {}", w * 33f64.to_radians().sin());
}

/// The tangent at an iterate (a rocking block with its base partly lifted, a block on a
/// slope near φ with a sub-contact slipping) against central differences of the jump from
/// the increment's start: each column to 2 % of its largest entry (what is left out: the
/// rotation of the stored shear force and of the normal with the pair).
#[test]
fn the_tangent_is_the_derivative_of_the_jump() {
    for (min, max, tilt) in [([0.0, -0.05, 0.0], [0.3, 0.05, 0.4], 12.0), ([0.0, -0.1, 0.0], [0.3, 0.1, 0.1], 33.0)] {
        let mut sim = settled(min, max);
        sim.set_tilt(f64::to_radians(tilt));
        let settings = NewtonSolve { max_iterations: 14, ..NewtonSolve::default() };
        let (_, last) = iterate(&sim, 1e-12, &settings, |_| None::<()>);
        let probe = last.unwrap().0;
        // The increment the probe reached, from `sim`.
        let b0 = &sim.state.bodies[0];
        let b1 = &probe.state.bodies[0];
        let x = (vec![b1.pos - b0.pos], vec![(b1.rot * b0.rot.inverse()).scaled_axis()]);
        let load = |dx: &PoseIncrement| {
            let mut s = sim.clone();
            s.predict_deferred(&[x.0[0] + dx.0[0]], &[x.1[0] + dx.1[0]]);
            s.assess_predicted();
            let (f, t) = s.unbalanced(0);
            [f.x, f.y, f.z, t.x, t.y, t.z]
        };
        let mut at = sim.clone();
        at.predict_deferred(&x.0, &x.1);
        at.assess_predicted();
        let blocks = tangent::tangent_blocks(&at);
        for dof in 0..6 {
            let eps = if dof < 3 { 1e-9 } else { 1e-8 };
            let mut p = (vec![Vec3::zeros()], vec![Vec3::zeros()]);
            let mut m = p.clone();
            if dof < 3 {
                p.0[0][dof] = eps;
                m.0[0][dof] = -eps;
            } else {
                p.1[0][dof - 3] = eps;
                m.1[0][dof - 3] = -eps;
            }
            let (lp, lm) = (load(&p), load(&m));
            let fd: Vec<f64> = (0..6).map(|i| -(lp[i] - lm[i]) / (2.0 * eps)).collect();
            let col: Vec<f64> = (0..6).map(|i| blocks.diag[0][(i, dof)]).collect();
            let scale = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..6 {
                assert!(
                    (fd[i] - col[i]).abs() <= 0.02 * scale,
                    "{tilt}°: K[{i}][{dof}] = {} against {}",
                    col[i],
                    fd[i]
                );
            }
        }
    }
}
