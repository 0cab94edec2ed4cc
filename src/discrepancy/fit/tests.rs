//! Tests of the surrogates (linear, grid, slice, corrected) and their fits, on surfaces whose answer is stated by hand.

use super::*;
use crate::discrepancy::observations::Observable;
use crate::discrepancy::predictive::Heights;

fn sim(mean: f64) -> Simulated {
    Simulated { mean, sd: 1.0, n: 4, err: 0.0, heights: Heights::NONE }
}

#[test]
fn linear_data_have_no_surrogate_error() {
    let xs = vec![0.0, 0.25, 0.5, 0.75, 1.0];
    let sims: Vec<Vec<Simulated>> = xs.iter().map(|&x| vec![sim(2.0 * x)]).collect();
    let s = Surface::axis(xs, sims);
    let v = s.at(&[0.6])[0];
    assert!((v.mean - 1.2).abs() < 1e-12 && v.err < 1e-12);
}

#[test]
fn curvature_shows_as_surrogate_error_between_nodes_only() {
    let xs = vec![0.0, 0.25, 0.5, 0.75, 1.0];
    let sims: Vec<Vec<Simulated>> = xs.iter().map(|&x| vec![sim(x * x)]).collect();
    let s = Surface::axis(xs, sims);
    assert!(s.at(&[0.5])[0].err < 1e-12);
    let mid = s.at(&[0.625])[0];
    // Linear interpolation misses x² by h²/4 at mid-interval (h = 0.25): 0.0156; the
    // estimate is of that order.
    let miss = (mid.mean - 0.625f64.powi(2)).abs();
    assert!(mid.err > 0.5 * miss && mid.err < 2.0 * miss, "{mid:?} miss {miss}");
}

/// Six specimens read exactly at the mean of a linear surrogate at x = 0.6: the fit
/// inverts the line (closed form) and every held-out prediction is centred on the
/// data.
#[test]
fn a_fit_recovers_the_point_of_a_linear_surrogate() {
    let xs = vec![0.0, 0.25, 0.5, 0.75, 1.0];
    let sims: Vec<Vec<Simulated>> = xs.iter().map(|&x| vec![sim(10.0 + 4.0 * x)]).collect();
    let s = Surface::axis(xs, sims);
    let obs: Vec<Observation> = (0..6)
        .map(|i| Observation {
            specimen: format!("S{i}"),
            group: "G".into(),
            observable: Observable::CollapseAngle,
            value: 12.4,
            sigma: 0.2,
        })
        .collect();
    let y = vec![12.4; 6];
    let key = vec![0usize; 6];
    let weight = vec![1.0; 6];
    let reading =
        Reading { angle_deg: 1e-6, displacement_cm: 1e-6, misreading: 0.1, neighbour_joint: 0.0, ..Reading::default() };
    let data = Data { obs: &obs, y: &y, key: &key, weight: &weight, reading, bracket_deg: 0.0 };
    let all: Vec<usize> = (0..6).collect();
    let (x, _) = fit(&s, data, &all);
    // Brent's tolerance is on the score, flat at its minimum: x to about 1e-3 (a mean
    // 0.004° off against a predictive σ of 1.1°).
    assert!((x[0] - 0.6).abs() < 1e-3, "{x:?}");
    let specimens: Vec<String> = obs.iter().map(|o| o.specimen.clone()).collect();
    let (_, pred, whole) = loso(&s, data, &specimens);
    assert_eq!(whole, fit(&s, data, &all), "the full-data fit of the shared scan");
    for p in pred {
        assert!((p.mean - 12.4).abs() < 1e-3, "{p:?}");
    }
}

/// The three-coordinate grid (an effect on the readings only beside a two-parameter
/// one) is exact on a trilinear function, its nodes and the scan cover the cube.
#[test]
fn a_three_coordinate_grid_interpolates_trilinearly() {
    let f = |a: f64, b: f64, c: f64| 1.0 + 2.0 * a - 3.0 * b + 0.5 * c + a * b * c;
    let (x1, x2, x3) = (vec![0.0, 0.5, 1.0], vec![0.0, 1.0], vec![0.0, 0.25, 1.0]);
    let mut sims = Vec::new();
    for &a in &x1 {
        for &b in &x2 {
            for &c in &x3 {
                sims.push(vec![sim(f(a, b, c))]);
            }
        }
    }
    let s = Surface::Grid3 { x1, x2, x3, sims };
    assert_eq!(s.dims(), 3);
    for x in [[0.0, 0.0, 0.0], [0.5, 1.0, 0.25], [0.3, 0.6, 0.9], [1.0, 0.2, 0.1]] {
        let v = s.at(&x)[0].mean;
        // Linear along every axis within a cell (a b c is linear in each alone).
        let (a, b, c) = (x[0], x[1], x[2]);
        let ca = if a <= 0.5 { (0.0, 0.5) } else { (0.5, 1.0) };
        let cc = if c <= 0.25 { (0.0, 0.25) } else { (0.25, 1.0) };
        let (ta, tc) = ((a - ca.0) / (ca.1 - ca.0), (c - cc.0) / (cc.1 - cc.0));
        let mut want = 0.0;
        for (wa, va) in [(1.0 - ta, ca.0), (ta, ca.1)] {
            for (wb, vb) in [(1.0 - b, 0.0), (b, 1.0)] {
                for (wc, vc) in [(1.0 - tc, cc.0), (tc, cc.1)] {
                    want += wa * wb * wc * f(va, vb, vc);
                }
            }
        }
        assert!((v - want).abs() < 1e-12, "{x:?}: {v} vs {want}");
    }
    let scan = scan_points(&s);
    assert_eq!(scan.len(), 11 * 11 * 11);
    assert_eq!((scan[0].clone(), scan[scan.len() - 1].clone()), (vec![0.0; 3], vec![1.0; 3]));
}

/// A slice holds one coordinate: it is the surface at that coordinate, one dimension
/// fewer, and a fit on it finds the other coordinates as a fit of the whole surface
/// with that coordinate given would (here a line in `a` whose slope `c` sets, the data
/// made at `a` = 0.3 with `c` = 0.8, by the closed form, not by the surface).
#[test]
fn a_slice_is_the_surface_at_its_held_coordinate_and_fits_the_others() {
    let f = |a: f64, b: f64, c: f64| 10.0 + (2.0 + 3.0 * c) * a + 0.0 * b;
    let (x1, x2, x3) = (vec![0.0, 0.25, 0.5, 0.75, 1.0], vec![0.0, 1.0], vec![0.0, 0.4, 0.8, 1.0]);
    let mut sims = Vec::new();
    for &a in &x1 {
        for &b in &x2 {
            for &c in &x3 {
                sims.push(vec![sim(f(a, b, c))]);
            }
        }
    }
    let grid = Surface::Grid3 { x1, x2, x3, sims };
    let slice = Surface::Slice { inner: Box::new(grid.clone()), axis: 2, value: 0.8 };
    assert_eq!(slice.dims(), 2);
    for x in [[0.0, 0.0], [0.3, 0.6], [1.0, 1.0]] {
        assert_eq!(slice.at(&x)[0].mean, grid.at(&[x[0], x[1], 0.8])[0].mean);
    }
    let held = Surface::Slice { inner: Box::new(slice.clone()), axis: 1, value: 0.0 };
    assert_eq!(held.dims(), 1);
    let want = f(0.3, 0.0, 0.8);
    let obs: Vec<Observation> = (0..5)
        .map(|i| Observation {
            specimen: format!("S{i}"),
            group: "G".into(),
            observable: Observable::CollapseAngle,
            value: want,
            sigma: 0.2,
        })
        .collect();
    let y = vec![want; 5];
    let (key, weight) = (vec![0usize; 5], vec![1.0; 5]);
    let reading =
        Reading { angle_deg: 1e-6, displacement_cm: 1e-6, misreading: 0.1, neighbour_joint: 0.0, ..Reading::default() };
    let data = Data { obs: &obs, y: &y, key: &key, weight: &weight, reading, bracket_deg: 0.0 };
    let (x, _) = fit(&held, data, &(0..5).collect::<Vec<_>>());
    assert!((x[0] - 0.3).abs() < 1e-3, "{x:?}");
    // Held at another slope, the same data give another `a`: the held coordinate
    // is what the fit is conditioned on.
    let other = Surface::Slice {
        inner: Box::new(Surface::Slice { inner: Box::new(grid), axis: 2, value: 0.0 }),
        axis: 1,
        value: 0.0,
    };
    let (x, _) = fit(&other, data, &(0..5).collect::<Vec<_>>());
    assert!((x[0] - 0.3 * (2.0 + 3.0 * 0.8) / 2.0).abs() < 1e-3, "{x:?}");
    // Every coordinate held: one point, no scan.
    let point = Surface::Slice { inner: Box::new(held), axis: 0, value: 0.3 };
    assert_eq!((point.dims(), scan_points(&point)), (0, vec![vec![]]));
    assert_eq!(fit(&point, data, &[0]).0, Vec::<f64>::new());
}

/// A surface re-centred on a full run: the full run's values at its point, the
/// surrogate's changes elsewhere (mean and variance), the full run's size everywhere.
#[test]
fn a_corrected_surface_is_the_full_run_at_its_point_and_the_surrogate_s_shape_elsewhere() {
    let xs = vec![0.0, 0.5, 1.0];
    let sims: Vec<Vec<Simulated>> = xs
        .iter()
        .map(|&x| vec![Simulated { mean: 2.0 * x, sd: 1.0 + x, n: 2, err: 0.0, heights: Heights::NONE }])
        .collect();
    let inner = Surface::axis(xs, sims);
    let full = vec![Simulated { mean: 7.0, sd: 3.0, n: 9, err: 0.0, heights: Heights::NONE }];
    let c = Surface::Corrected { inner: Box::new(inner), x0: vec![0.0], full: full.clone() };
    let at0 = c.at(&[0.0])[0];
    assert_eq!((at0.mean, at0.sd, at0.n), (7.0, 3.0, 9));
    let at1 = c.at(&[1.0])[0];
    assert!((at1.mean - 9.0).abs() < 1e-12);
    // 3² + (2² − 1²) = 12.
    assert!((at1.sd - 12f64.sqrt()).abs() < 1e-12, "{at1:?}");
    assert_eq!(at1.n, 9);
}
