//! The hysteresis loops of a cyclic in-plane test: the energy each full cycle dissipates and
//! its equivalent viscous damping ratio (Jacobsen's equal-energy definition, as the cyclic
//! tests of masonry walls report it, e.g. Magenes & Calvi 1997, Vasconcelos & Lourenço 2009):
//!
//! ```text
//! ξ_eq = E_d / (4 π E_s),   E_d = ∮ F du,   E_s = (F₊ u₊ + F₋ u₋) / 2
//! ```
//!
//! `E_d` the work the actuator does over one full cycle (the loop's area), `u₊`, `u₋` the
//! cycle's largest and smallest displacements and `F₊`, `F₋` the forces there (`E_s` the
//! mean of the two half-cycles' secant strain energies). A force that depends only on the
//! displacement (elastic, however nonlinear, or a leaning jack's `N u / L`) dissipates
//! nothing; a Coulomb friction `μ N` against the motion adds `4 μ N a` to `E_d` over a
//! cycle of amplitude `a`.
//!
//! The same code reads a measured curve and a run's: a curve is a sequence of (displacement,
//! force) points in the order they were taken, in any consistent units (the damping ratio
//! does not depend on them); points with a non-finite value (the database's `NaN` lines
//! between digitized segments) are skipped.

/// One full cycle of a curve: from an upward crossing of zero displacement to the next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cycle {
    /// Half the cycle's peak-to-peak displacement `(u₊ − u₋) / 2`, in the curve's unit of
    /// displacement.
    pub amplitude: f64,
    /// The energy dissipated `∮ F du` (trapezoidal, the crossings interpolated linearly), in
    /// the curve's force × displacement.
    pub dissipated: f64,
    /// The secant strain energy `(F₊ u₊ + F₋ u₋) / 2`, same unit.
    pub strain_energy: f64,
    /// `ξ_eq = dissipated / (4 π strain_energy)`; NaN where the strain energy is not
    /// positive (a loop that does not push back at its ends).
    pub damping_ratio: f64,
}

/// The full cycles of a curve (`(u, F)` in loading order), in order. A cycle runs from an
/// upward crossing of `u = 0` (from `u < 0` to `u ≥ 0`) to the next, the crossings
/// interpolated linearly; the part before the first crossing and after the last is not a
/// full cycle and is left out. A monotonic curve has none.
pub fn cycles(curve: &[(f64, f64)]) -> Vec<Cycle> {
    let pts: Vec<(f64, f64)> = curve.iter().copied().filter(|(u, f)| u.is_finite() && f.is_finite()).collect();
    // The upward crossings: (index of the point after it, the force interpolated at u = 0).
    // A return to zero read a hair below it (1e-4 of the largest displacement) counts as
    // reaching it: the history's zero is imposed at the actuator, and the displacement is
    // read at the measuring point, which the joints' closure under the vertical force puts
    // above the actuator's anchor by some 0.5 mm (the beam settles after it is held), so
    // the reading carries the beam's residual rotation times that offset (1e-8–1e-7 m,
    // some 1e-6 of the largest displacement). An increment is 1e-3 of it or more.
    let zero = 1e-4 * pts.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    let mut crossings = Vec::new();
    for i in 1..pts.len() {
        let ((u0, f0), (u1, f1)) = (pts[i - 1], pts[i]);
        if u0 < -zero && u1 >= -zero {
            let t = (-u0 / (u1 - u0)).clamp(0.0, 1.0);
            crossings.push((i, f0 + t * (f1 - f0)));
        }
    }
    crossings
        .windows(2)
        .map(|w| {
            let ((a, fa), (b, fb)) = (w[0], w[1]);
            // The closed path: (0, fa), pts[a..b], (0, fb).
            let path = std::iter::once((0.0, fa)).chain(pts[a..b].iter().copied()).chain(std::iter::once((0.0, fb)));
            let mut dissipated = 0.0;
            let (mut hi, mut lo) = ((0.0, fa), (0.0, fa));
            let mut last: Option<(f64, f64)> = None;
            for p in path {
                if let Some((u0, f0)) = last {
                    dissipated += (p.0 - u0) * (f0 + p.1) / 2.0;
                }
                if p.0 > hi.0 {
                    hi = p;
                }
                if p.0 < lo.0 {
                    lo = p;
                }
                last = Some(p);
            }
            let strain_energy = (hi.1 * hi.0 + lo.1 * lo.0) / 2.0;
            let damping_ratio =
                if strain_energy > 0.0 { dissipated / (4.0 * std::f64::consts::PI * strain_energy) } else { f64::NAN };
            Cycle { amplitude: (hi.0 - lo.0) / 2.0, dissipated, strain_energy, damping_ratio }
        })
        .collect()
}

/// The smallest drift amplitude, %, of the cycles [`loop_damping_ratio`] reads: the cycles
/// at and past 1 % drift, where the walls of this test (Vasconcelos & Lourenço 2009) have
/// opened their mechanism (their peaks come at 1.5–3 %), not the small elastic cycles whose
/// loops are mostly digitizing noise.
pub const LOOP_MIN_DRIFT_PCT: f64 = 1.0;

/// The loops' equivalent viscous damping ratio of a cyclic test: the median of
/// [`Cycle::damping_ratio`] over the full cycles of at least `min_amplitude` (the curve's
/// unit of displacement; [`LOOP_MIN_DRIFT_PCT`] of the wall's height for the study's
/// reading), the median so that one badly digitized loop does not move it. NaN when no
/// such cycle has a damping ratio (a monotonic curve, a test that stopped earlier).
pub fn loop_damping_ratio(curve: &[(f64, f64)], min_amplitude: f64) -> f64 {
    let mut xi: Vec<f64> = cycles(curve)
        .into_iter()
        .filter(|c| c.amplitude >= min_amplitude && c.damping_ratio.is_finite())
        .map(|c| c.damping_ratio)
        .collect();
    if xi.is_empty() {
        return f64::NAN;
    }
    xi.sort_by(f64::total_cmp);
    let n = xi.len();
    if n % 2 == 1 {
        xi[n / 2]
    } else {
        (xi[n / 2 - 1] + xi[n / 2]) / 2.0
    }
}

/// The drift a measured history must retreat from its running extreme to turn, %: twice
/// the curve files' rounding of the drift (0.01 %), so that a reading's last digit never
/// makes a turning point.
pub const TURNING_NOISE_PCT: f64 = 0.02;

/// The turning points of a drift history `drift_pct` (%, in the order it was read): the
/// running extreme of each leg, taken where the drift retreats from it by more than
/// `noise_pct` (a hysteresis band: readings that wander within it neither end a leg nor
/// start one), then the extreme of the last leg, where the history ends. Readings before
/// the drift first leaves ±`noise_pct` are skipped; the direction of the first leg is the
/// data's, whichever it is. The result is what [`InPlaneParams::reversals_pct`] replays
/// (`crate::loading::inplane::InPlaneParams`); empty for a history that never leaves the
/// band.
///
/// [`InPlaneParams::reversals_pct`]: crate::loading::inplane::InPlaneParams::reversals_pct
pub fn turning_points(drift_pct: &[f64], noise_pct: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    let (mut dir, mut extreme) = (0.0f64, 0.0f64);
    for &d in drift_pct.iter().filter(|d| d.is_finite()) {
        if dir == 0.0 {
            if d.abs() > noise_pct {
                (dir, extreme) = (d.signum(), d);
            }
            continue;
        }
        if (d - extreme) * dir > 0.0 {
            extreme = d;
        } else if (extreme - d) * dir > noise_pct {
            out.push(extreme);
            (dir, extreme) = (-dir, d);
        }
    }
    if dir != 0.0 && out.last() != Some(&extreme) {
        out.push(extreme);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Full cycles of the amplitudes `amps`, `n` points a quarter, of the force law
    /// `f(u, sense)`, starting at u = 0 going up; at each reversal the force changes at a
    /// standing displacement (a point of the new sense at the same u).
    fn loop_of(amps: &[f64], n: usize, f: impl Fn(f64, f64) -> f64) -> Vec<(f64, f64)> {
        let mut pts = vec![(0.0, f(0.0, 1.0))];
        for &a in amps {
            // 0 → a → −a → 0, the sense of each leg.
            for (from, to) in [(0.0, a), (a, -a), (-a, 0.0)] {
                let steps = if from == a { 2 * n } else { n };
                let s: f64 = if to > from { 1.0 } else { -1.0 };
                if from != 0.0 {
                    // The reversal: the force changes at a standing displacement.
                    pts.push((from, f(from, s)));
                }
                for k in 1..=steps {
                    let u = from + (to - from) * k as f64 / steps as f64;
                    pts.push((u, f(u, s)));
                }
            }
        }
        // One more small step up so that the last cycle's end crossing is seen.
        pts.push((1e-9, f(1e-9, 1.0)));
        pts
    }

    #[test]
    fn an_elastic_loop_dissipates_nothing() {
        // Nonlinear elastic, F = k u + c u³: E_d = 0 whatever the law.
        let pts = loop_of(&[1.0, 2.0], 16, |u, _| 3.0 * u + 0.5 * u.powi(3));
        let c = cycles(&pts);
        // The start (u = 0 going up) is not a crossing from u < 0: the first full cycle is the second.
        assert_eq!(c.len(), 1, "{c:?}");
        for cy in &c {
            assert!(cy.dissipated.abs() < 1e-12, "{cy:?}");
            assert!(cy.damping_ratio.abs() < 1e-12);
        }
    }

    #[test]
    fn coulomb_friction_on_a_spring_gives_its_closed_form() {
        // F = k u + μN sgn(u̇): E_d = 4 μN a, E_s = (k a + μN) a, ξ = μN / (π (k a + μN)).
        let (k, mu_n) = (10.0, 2.0);
        let pts = loop_of(&[1.0, 3.0, 3.0], 32, |u, s| k * u + mu_n * s);
        let c = cycles(&pts);
        assert_eq!(c.len(), 2, "{c:?}");
        for cy in &c {
            let a = cy.amplitude;
            assert!((cy.dissipated - 4.0 * mu_n * a).abs() < 1e-9 * a, "{cy:?}");
            let xi = mu_n / (std::f64::consts::PI * (k * a + mu_n));
            assert!((cy.damping_ratio - xi).abs() < 1e-12, "{} {xi}", cy.damping_ratio);
        }
    }

    #[test]
    fn a_rigid_plastic_loop_is_one_over_pi() {
        // F = F0 sgn(u̇): the rectangle, ξ = 1/π.
        let pts = loop_of(&[0.5, 1.0, 1.0], 8, |_, s| 4.0 * s);
        let xi = loop_damping_ratio(&pts, 0.9);
        assert!((xi - 1.0 / std::f64::consts::PI).abs() < 1e-12, "{xi}");
        // None of at least 1.5.
        assert!(loop_damping_ratio(&pts, 1.5).is_nan());
    }

    #[test]
    fn nan_points_are_skipped_and_units_do_not_matter() {
        let pts = loop_of(&[1.0, 2.0, 2.0], 16, |u, s| 5.0 * u + s);
        let mut gappy = pts.clone();
        gappy.insert(20, (f64::NAN, f64::NAN));
        let scaled: Vec<(f64, f64)> = pts.iter().map(|&(u, f)| (u * 12.0, f * 1e-3)).collect();
        let (a, b, c) =
            (loop_damping_ratio(&pts, 0.5), loop_damping_ratio(&gappy, 0.5), loop_damping_ratio(&scaled, 6.0));
        assert!((a - b).abs() < 1e-12 && (a - c).abs() < 1e-12, "{a} {b} {c}");
        assert!(loop_damping_ratio(&[(0.0, 0.0), (1.0, 1.0), (2.0, 1.5)], 0.0).is_nan());
    }
}
