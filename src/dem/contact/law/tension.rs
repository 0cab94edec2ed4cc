//! Tension cut-off sub-model: whether a joint carries tension at a sub-contact.
//!
//! Dry joints carry none ([`TensionCutoff::NoTension`]). A joint given a tensile strength
//! `T` (Pa) carries tension while it is intact (bonded) and the pressure at every node of
//! the sub-contact stays above `−T`; once the pressure anywhere drops below `−T` the joint
//! breaks and never carries tension again (3DEC's residual-strength convention, Itasca
//! 3DEC manual).

/// Tension cut-off of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TensionCutoff {
    /// No tension at all (a dry, cohesionless joint).
    #[default]
    NoTension,
    /// Tension up to a tensile strength while the joint is intact.
    Strength {
        /// Tensile strength T, Pa (> 0).
        pa: f64,
    },
}

impl TensionCutoff {
    /// `NoTension` for a strength of 0 Pa, `Strength` otherwise (the layout file's
    /// `tensile_strength_pa`).
    pub fn from_strength(pa: f64) -> Self {
        if pa > 0.0 {
            TensionCutoff::Strength { pa }
        } else {
            TensionCutoff::NoTension
        }
    }

    /// The tensile strength, Pa (0 without tension).
    pub fn strength(self) -> f64 {
        match self {
            TensionCutoff::NoTension => 0.0,
            TensionCutoff::Strength { pa } => pa,
        }
    }
}

/// The tension kernel: given the nodal pressures `q()` (Pa, compression positive) of a
/// sub-contact, breaks an intact joint whose pressure falls below `−T` anywhere (clearing
/// `bonded`), and returns whether the sub-contact carries tension this step. The pressures
/// are asked only of an intact joint with a tensile strength (a dry joint, the common
/// case, needs none: the contact pass does not evaluate them).
#[inline(always)]
pub fn carries_tension(t: TensionCutoff, bonded: &mut bool, q: impl FnOnce() -> [f64; 3]) -> bool {
    match t {
        TensionCutoff::NoTension => false,
        TensionCutoff::Strength { pa } => {
            if *bonded && q().iter().any(|&v| v < -pa) {
                *bonded = false;
            }
            *bonded
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    /// The kernel's rule, case by case: a dry joint never carries tension and an intact
    /// joint with a strength `T` carries it until a nodal pressure falls below `−T`, for
    /// good; the nodal pressures are asked only of an intact joint with a strength.
    #[test]
    fn tension_is_carried_by_an_intact_joint_above_its_strength_and_pressures_asked_only_there() {
        let asked = Cell::new(0);
        let q = |v: [f64; 3]| {
            let asked = &asked;
            move || {
                asked.set(asked.get() + 1);
                v
            }
        };
        let strength = TensionCutoff::from_strength(1e4);
        // A dry joint: no tension, intact or not, and no pressure asked.
        let mut bonded = true;
        assert!(!carries_tension(TensionCutoff::NoTension, &mut bonded, q([-5e3, 0.0, 1e3])));
        assert!(bonded && asked.get() == 0);
        // Intact, every pressure above −T: tension carried.
        assert!(carries_tension(strength, &mut bonded, q([-5e3, 0.0, 1e3])));
        assert!(bonded && asked.get() == 1);
        // A pressure below −T: broken, no tension.
        assert!(!carries_tension(strength, &mut bonded, q([1e3, -2e4, 0.0])));
        assert!(!bonded && asked.get() == 2);
        // Broken for good, whatever the pressures, which are not asked.
        assert!(!carries_tension(strength, &mut bonded, q([-5e3, 0.0, 1e3])));
        assert!(!bonded && asked.get() == 2);
    }
}
