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
