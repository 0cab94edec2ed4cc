//! The overshoot of a table rolled by hand, as the quasi-static tilting tests load it
//! (the effect `table_kick`; the dynamic run of the kicks is `loading::tilt_hand`).

/// The increment between the stops of the paper's table, degrees (Santa-Cruz et al. 2021,
/// §2.2: "in increments of 5°").
pub const PAPER_INCREMENT_DEG: f64 = 5.0;

/// The tilt (degrees) at which the quasi-static tests load a wall when the table's angle is
/// `alpha_deg` and each stop of a table rolled by hand in the paper's 5° increments kicks
/// the wall as much as an extra inclination `overshoot_deg` would (`Layout::table_overshoot_deg`,
/// set by the effect `table_kick`): `max(α, s + Δ)`, s the last stop at or below α
/// (`s = 5° ⌊α / 5°⌋`, from the first stop on; a wall on a level table is not kicked).
/// Exactly `alpha_deg` when the overshoot is 0.
///
/// The quasi-static equivalent of the kicks of
/// [`run_tilt_by_hand`](crate::loading::tilt_hand::run_tilt_by_hand): the wall is loaded to
/// `s + Δ` at every stop s and the roll adds nothing until the table passes `s + Δ`, so a
/// wall collapses at a stop when the stop lies within Δ of its static limit, and at its
/// static limit otherwise, as in the dynamic run; the readings at a stop are those of the
/// wall loaded to `s + Δ` (the elastic part of a transient kick is recovered in the
/// dynamic run: an upper bound). A stop of peak angular deceleration `α̈` pushes a block at
/// height z above the table's axis downhill by `α̈ (z + d)`; in the dynamic run the
/// stops' effective overshoot is about 20–40 % of `atan(α̈ (z̄ + d) / g)` at the centroid
/// height z̄ (docs/discrepancy.md, "The table rolled by hand").
pub fn effective_tilt_deg(alpha_deg: f64, overshoot_deg: f64) -> f64 {
    if overshoot_deg == 0.0 {
        return alpha_deg;
    }
    let increment = PAPER_INCREMENT_DEG;
    let stop = (alpha_deg / increment).floor() * increment;
    if stop < increment {
        return alpha_deg;
    }
    alpha_deg.max(stop + overshoot_deg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overshoot_loads_each_stop_to_the_stop_plus_the_overshoot() {
        assert_eq!(effective_tilt_deg(12.3, 0.0), 12.3);
        assert_eq!(effective_tilt_deg(4.9, 2.0), 4.9);
        assert_eq!(effective_tilt_deg(5.0, 2.0), 7.0);
        assert_eq!(effective_tilt_deg(6.5, 2.0), 7.0);
        assert_eq!(effective_tilt_deg(7.5, 2.0), 7.5);
        assert_eq!(effective_tilt_deg(10.0, 2.0), 12.0);
        // Non-decreasing in α (the bisections rely on it).
        let mut last = 0.0;
        for k in 0..4000 {
            let a = effective_tilt_deg(k as f64 * 0.01, 3.0);
            assert!(a >= last);
            last = a;
        }
    }
}
