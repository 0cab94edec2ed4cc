//! Which method runs which protocol: the one compatibility table of the product.
//!
//! A study (at resolve time, naming `solver.kind`), the command line, the Python package
//! and every protocol's run ask [`supports`] or [`check`]; none decides it on its own. The
//! table ([`methods`]) is an exhaustive match over [`Loading`] and [`Method`]: a new
//! protocol or method does not compile until its row is written.

use crate::dem::{Method, SolverKind};

/// A protocol, with the variants that change which methods run it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Loading {
    /// The tilting table, tilted quasi-statically to collapse (`loading::tilt`).
    Tilt,
    /// The tilting table rolled by hand in increments (`tilt.by_hand`, `loading::tilt_hand`):
    /// a motion.
    TiltByHand,
    /// The static lateral (trapezoidal pressure) load at its service level
    /// (`loading::lateral`).
    Lateral,
    /// The lateral load pushed over to collapse (`lateral.pushover`): its load multiplier λ.
    Pushover,
    /// The shaking table under a ground motion (`loading::shake`): a motion.
    Shake,
}

impl Loading {
    /// Every protocol kind.
    pub const ALL: [Loading; 5] =
        [Loading::Tilt, Loading::TiltByHand, Loading::Lateral, Loading::Pushover, Loading::Shake];

    /// Its place in [`Loading::ALL`]: an exhaustive match, so that the compiler points to a
    /// new variant here, beside the list it joins (checked at compile time).
    const fn place(self) -> usize {
        match self {
            Loading::Tilt => 0,
            Loading::TiltByHand => 1,
            Loading::Lateral => 2,
            Loading::Pushover => 3,
            Loading::Shake => 4,
        }
    }

    /// Its name in the Python package's `drystone.supports` and in tables: `tilt`,
    /// `tilt_by_hand`, `lateral`, `pushover`, `shake`.
    pub fn name(self) -> &'static str {
        match self {
            Loading::Tilt => "tilt",
            Loading::TiltByHand => "tilt_by_hand",
            Loading::Lateral => "lateral",
            Loading::Pushover => "pushover",
            Loading::Shake => "shake",
        }
    }

    /// The protocol of a name; `None` for an unknown one.
    pub fn from_name(name: &str) -> Option<Loading> {
        Loading::ALL.into_iter().find(|l| l.name() == name)
    }

    /// Its name in messages.
    pub fn describe(self) -> &'static str {
        match self {
            Loading::Tilt => "the tilting table",
            Loading::TiltByHand => "the tilting table rolled by hand (tilt.by_hand)",
            Loading::Lateral => "the static lateral load",
            Loading::Pushover => "the lateral pushover (lateral.pushover)",
            Loading::Shake => "the shaking table",
        }
    }

    /// Whether it is a motion (time history) rather than a sequence of static states: a
    /// penalty cascade, a setting of static solves, does not apply to it.
    pub fn is_motion(self) -> bool {
        match self {
            Loading::TiltByHand | Loading::Shake => true,
            Loading::Tilt | Loading::Lateral | Loading::Pushover => false,
        }
    }
}

// `Loading::ALL` lists every variant once, in the order of `Loading::place`.
const _: () = {
    let mut i = 0;
    while i < Loading::ALL.len() {
        assert!(Loading::ALL[i].place() == i, "Loading::ALL lists every variant once, in order");
        i += 1;
    }
};

/// Whether `method` runs `protocol`, and what it gives there (`None`: it does not).
///
/// | protocol | penalty DEM | nscd | limit analysis |
/// | --- | --- | --- | --- |
/// | tilt | collapse angle (bisection of static states) | rigid collapse angle | α_max = atan λ |
/// | tilt by hand | – | the rolled table's motion | – |
/// | lateral | equilibrium under the load | – | whether λ ≥ 1 |
/// | pushover | λ by increments (and λ of limit analysis beside it) | rigid λ by bisection | λ |
/// | shake | explicit dynamics with contact damping | Moreau–Jean time stepping | – |
pub fn methods(protocol: Loading, method: Method) -> Option<&'static str> {
    match (protocol, method) {
        (Loading::Tilt, Method::Penalty) => Some("the penalty DEM, any cascade"),
        (Loading::Tilt, Method::Nscd) => Some("non-smooth contact dynamics, rigid joints"),
        (Loading::Tilt, Method::Limit) => Some("limit analysis, rigid joints"),
        (Loading::TiltByHand, Method::Nscd) => Some("non-smooth contact dynamics"),
        (Loading::TiltByHand, Method::Penalty | Method::Limit) => None,
        (Loading::Lateral, Method::Penalty) => Some("the penalty DEM, any cascade"),
        (Loading::Lateral, Method::Limit) => Some("limit analysis: whether the load multiplier reaches 1"),
        (Loading::Lateral, Method::Nscd) => None,
        (Loading::Pushover, Method::Penalty) => Some("the penalty DEM, any cascade"),
        (Loading::Pushover, Method::Nscd) => Some("non-smooth contact dynamics, rigid joints"),
        (Loading::Pushover, Method::Limit) => Some("limit analysis, rigid joints"),
        (Loading::Shake, Method::Penalty) => Some("explicit dynamics with contact damping"),
        (Loading::Shake, Method::Nscd) => Some("non-smooth contact dynamics"),
        (Loading::Shake, Method::Limit) => None,
    }
}

/// Whether `method` runs `protocol` ([`methods`]).
pub fn supports(protocol: Loading, method: Method) -> bool {
    methods(protocol, method).is_some()
}

/// A solver that does not run a protocol, with what does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.message())]
pub struct Unsupported {
    /// The protocol asked.
    pub protocol: Loading,
    /// The solver asked.
    pub kind: SolverKind,
}

impl Unsupported {
    fn message(&self) -> String {
        let ways: Vec<String> = Method::ALL
            .into_iter()
            .filter_map(|m| methods(self.protocol, m).map(|what| format!("{} ({what})", m.name())))
            .collect();
        let why = if supports(self.protocol, self.kind.method()) {
            "names a cascade of static solves, which a motion does not run".to_string()
        } else {
            format!("is {}", self.kind.method().describe())
        };
        format!(
            "{} runs by solver kind {}; solver {} {why}",
            self.protocol.describe(),
            join_or(&ways),
            self.kind.name()
        )
    }
}

/// `a`, `a or b`, `a, b or c`.
fn join_or(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [a] => a.clone(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// Checks that the solver `kind` runs `protocol`: its method is in the table, and a motion
/// is not given a cascade of static solves (`implicit`, `accelerated`, `relaxation`).
///
/// # Errors
/// [`Unsupported`], naming the methods that run the protocol.
pub fn check(protocol: Loading, kind: SolverKind) -> Result<(), Unsupported> {
    let cascade_on_motion = protocol.is_motion() && kind.names_cascade();
    if supports(protocol, kind.method()) && !cascade_on_motion {
        Ok(())
    } else {
        Err(Unsupported { protocol, kind })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every protocol runs by at least one method; the motions by no static cascade; every
    /// refusal names the methods that do run the protocol.
    #[test]
    fn the_table_is_whole_and_its_refusals_name_the_way() {
        for p in Loading::ALL {
            assert!(Method::ALL.into_iter().any(|m| supports(p, m)), "{p:?}");
            for k in SolverKind::ALL {
                match check(p, k) {
                    Ok(()) => assert!(supports(p, k.method()) && !(p.is_motion() && k.names_cascade())),
                    Err(e) => {
                        let text = e.to_string();
                        assert!(text.contains(p.describe()) && text.contains(k.name()), "{text}");
                        for m in Method::ALL.into_iter().filter(|&m| supports(p, m)) {
                            assert!(text.contains(m.name()), "{text}");
                        }
                    }
                }
            }
        }
        assert!(check(Loading::Shake, SolverKind::Relaxation)
            .unwrap_err()
            .to_string()
            .contains("cascade of static solves"));
        assert!(check(Loading::Tilt, SolverKind::Relaxation).is_ok());
        assert!(check(Loading::TiltByHand, SolverKind::Penalty).is_err());
        assert!(check(Loading::Lateral, SolverKind::Nscd).is_err());
        assert!(check(Loading::Pushover, SolverKind::Nscd).is_ok());
        for p in Loading::ALL {
            assert_eq!(Loading::from_name(p.name()), Some(p));
        }
    }
}
