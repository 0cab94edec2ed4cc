//! Tests of the study report's helpers ([`super`]).

use super::*;

fn cmp(group: &str, n: usize, sd: f64) -> Comparison {
    Comparison {
        group: group.into(),
        quantity: "collapse angle [deg]".into(),
        measured_n: 3,
        measured_mean: 18.83,
        measured_sd: 0.29,
        simulated_n: n,
        simulated_mean: 20.25,
        simulated_sd: sd,
        band: (20.25 - 2.0 * sd, 20.25 + 2.0 * sd),
        inside: false,
        specimens_inside: 0,
    }
}

/// A group whose realizations all agree gets the note; one with scatter, or a single
/// realization, or one quantity with scatter, does not.
#[test]
fn identical_realizations_are_called_out() {
    let notes = degenerate_groups(&[cmp("CBL", 6, 0.0), cmp("CBL", 6, 0.0), cmp("SBL", 6, 0.2), cmp("ONE", 1, 0.0)]);
    assert_eq!(notes.len(), 1);
    assert!(notes[0].starts_with("CBL: all 6 realizations gave the same values"), "{}", notes[0]);
    assert!(degenerate_groups(&[cmp("X", 6, 0.0), cmp("X", 6, 0.1)]).is_empty());
}
