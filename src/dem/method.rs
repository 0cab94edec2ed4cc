//! The solver axis: the method a protocol runs by ([`Method`]: the penalty DEM, non-smooth
//! contact dynamics, limit analysis), its spelling in files and on the command line
//! ([`SolverKind`]: a method, and for the penalty DEM the stages of its static cascade) and
//! the stages themselves ([`Cascade`]). Plain data, read by the parameters, the solver seam
//! (`dem::solve`), the protocols and their one compatibility table
//! (`protocol::supports`).

use serde::{Deserialize, Serialize};

/// The solver a protocol runs on: `[solver] kind = "..."` in a study, `--solver NAME` on
/// `drystone tilt`, `lateral` and `bench`. Default [`SolverKind::Penalty`].
///
/// The first four are the penalty DEM (3DEC-style sub-contact springs, Kn and Ks from the
/// layout) and differ only in how a static state is found ([`Cascade`]); their results
/// agree within one bracket of the protocol, their costs differ (BENCHMARKS.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// The penalty DEM with each protocol's default cascade: the tilting table runs the
    /// implicit iteration, its stall probe and accelerated dynamic relaxation; settling and
    /// the static lateral load run plain dynamic relaxation.
    #[default]
    Penalty,
    /// The penalty DEM, every stage: implicit iteration → stall probe → accelerated,
    /// probed dynamic relaxation.
    Implicit,
    /// The penalty DEM, accelerated and probed dynamic relaxation without the implicit
    /// iteration (formerly `--no-implicit`, `implicit = false` in `[tilt]`).
    Accelerated,
    /// The penalty DEM, plain dynamic relaxation with local damping (formerly
    /// `--no-implicit --no-accelerate`).
    Relaxation,
    /// Non-smooth contact dynamics (Moreau–Jean; rigid joints: Kn and Ks are not used).
    Nscd,
    /// Limit analysis (lower-bound statics of rigid blocks; rigid joints).
    Limit,
}

/// The method a protocol runs by: one axis, whatever the cascade of a penalty solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// The penalty DEM (3DEC-style sub-contact springs, Kn and Ks from the layout): static
    /// states by its [`Cascade`], motion by explicit dynamics.
    Penalty,
    /// Non-smooth contact dynamics (Moreau–Jean time stepping, NSGS; rigid joints).
    Nscd,
    /// Limit analysis (lower-bound statics of rigid blocks; rigid joints).
    Limit,
}

impl Method {
    /// Every method (checked at compile time against `Method::place`).
    pub const ALL: [Method; 3] = [Method::Penalty, Method::Nscd, Method::Limit];

    /// Its place in [`Method::ALL`]: an exhaustive match, so that the compiler points to a
    /// new variant here, beside the list it joins.
    const fn place(self) -> usize {
        match self {
            Method::Penalty => 0,
            Method::Nscd => 1,
            Method::Limit => 2,
        }
    }

    /// Its name: the [`SolverKind`] that selects it with the protocol's default cascade.
    pub fn name(self) -> &'static str {
        self.kind().name()
    }

    /// The solver kind that selects this method with the protocol's default cascade.
    pub fn kind(self) -> SolverKind {
        match self {
            Method::Penalty => SolverKind::Penalty,
            Method::Nscd => SolverKind::Nscd,
            Method::Limit => SolverKind::Limit,
        }
    }

    /// What it is, in a phrase (for messages).
    pub fn describe(self) -> &'static str {
        match self {
            Method::Penalty => "the penalty DEM",
            Method::Nscd => "non-smooth contact dynamics",
            Method::Limit => "limit analysis",
        }
    }

    /// Whether it runs a layout with ropes (`end_rope`): the penalty DEM and nscd carry a
    /// rope's tension along its displacement; limit analysis has no displacement for a
    /// rope and refuses the layout (`limit::LimitError::Ropes`).
    pub fn runs_ropes(self) -> bool {
        match self {
            Method::Penalty | Method::Nscd => true,
            Method::Limit => false,
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl SolverKind {
    /// Every solver kind (checked at compile time against `SolverKind::place`).
    pub const ALL: [SolverKind; 6] = [
        SolverKind::Penalty,
        SolverKind::Implicit,
        SolverKind::Accelerated,
        SolverKind::Relaxation,
        SolverKind::Nscd,
        SolverKind::Limit,
    ];

    /// Its place in [`SolverKind::ALL`]: an exhaustive match, so that the compiler points
    /// to a new variant here, beside the list it joins.
    const fn place(self) -> usize {
        match self {
            SolverKind::Penalty => 0,
            SolverKind::Implicit => 1,
            SolverKind::Accelerated => 2,
            SolverKind::Relaxation => 3,
            SolverKind::Nscd => 4,
            SolverKind::Limit => 5,
        }
    }

    /// Its name in files and on the command line (the serde name).
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Penalty => "penalty",
            SolverKind::Implicit => "implicit",
            SolverKind::Accelerated => "accelerated",
            SolverKind::Relaxation => "relaxation",
            SolverKind::Nscd => "nscd",
            SolverKind::Limit => "limit",
        }
    }

    /// The kind of a name, `None` for an unknown one.
    pub fn from_name(name: &str) -> Option<SolverKind> {
        SolverKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The method it selects.
    pub fn method(self) -> Method {
        match self {
            SolverKind::Penalty | SolverKind::Implicit | SolverKind::Accelerated | SolverKind::Relaxation => {
                Method::Penalty
            }
            SolverKind::Nscd => Method::Nscd,
            SolverKind::Limit => Method::Limit,
        }
    }

    /// Whether it names a cascade of its own rather than the protocol's default (the
    /// penalty kinds other than `penalty`): a setting of static solves, which motion does not
    /// run.
    pub fn names_cascade(self) -> bool {
        match self {
            SolverKind::Implicit | SolverKind::Accelerated | SolverKind::Relaxation => true,
            SolverKind::Penalty | SolverKind::Nscd | SolverKind::Limit => false,
        }
    }

    /// Whether it is the penalty DEM (joints of finite stiffness, static states from
    /// `dem::solve_static`).
    pub fn is_penalty(self) -> bool {
        match self.method() {
            Method::Penalty => true,
            Method::Nscd | Method::Limit => false,
        }
    }

    /// The stages of a static solve for a protocol whose default is `protocol_default`;
    /// `None` for a solver that is not a penalty method.
    pub fn cascade(self, protocol_default: Cascade) -> Option<Cascade> {
        match self {
            SolverKind::Penalty => Some(protocol_default),
            SolverKind::Implicit => Some(Cascade::FULL),
            SolverKind::Accelerated => Some(Cascade { implicit: false, accelerate: true }),
            SolverKind::Relaxation => Some(Cascade::RELAXATION),
            SolverKind::Nscd | SolverKind::Limit => None,
        }
    }
}

// `Method::ALL` and `SolverKind::ALL` list every variant once, in the order of `place`.
const _: () = {
    let mut i = 0;
    while i < Method::ALL.len() {
        assert!(Method::ALL[i].place() == i, "Method::ALL lists every variant once, in order");
        i += 1;
    }
    let mut i = 0;
    while i < SolverKind::ALL.len() {
        assert!(SolverKind::ALL[i].place() == i, "SolverKind::ALL lists every variant once, in order");
        i += 1;
    }
};

impl std::fmt::Display for SolverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for SolverKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        SolverKind::from_name(s).ok_or_else(|| {
            let names: Vec<&str> = SolverKind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown solver {s:?} (one of {})", names.join(", "))
        })
    }
}

/// The stages of the penalty cascade that a static solve runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cascade {
    /// The implicit iteration first (and the probe of its drift where it stalls).
    pub implicit: bool,
    /// The secant acceleration and stability indicator in dynamic relaxation.
    pub accelerate: bool,
}

impl Cascade {
    /// Every stage.
    pub const FULL: Cascade = Cascade { implicit: true, accelerate: true };
    /// Plain dynamic relaxation.
    pub const RELAXATION: Cascade = Cascade { implicit: false, accelerate: false };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names round-trip and the penalty kinds resolve against the protocol's default.
    #[test]
    fn solver_names_and_cascades() {
        for k in SolverKind::ALL {
            assert_eq!(k.name().parse::<SolverKind>().unwrap(), k);
        }
        assert!("rigid".parse::<SolverKind>().unwrap_err().contains("nscd"));
        assert_eq!(SolverKind::Penalty.cascade(Cascade::RELAXATION), Some(Cascade::RELAXATION));
        assert_eq!(SolverKind::Implicit.cascade(Cascade::RELAXATION), Some(Cascade::FULL));
        assert!(!SolverKind::Nscd.is_penalty() && !SolverKind::Limit.is_penalty());
        assert!(SolverKind::Relaxation.is_penalty());
        for k in SolverKind::ALL {
            assert_eq!(k.is_penalty(), k.cascade(Cascade::FULL).is_some(), "{k}");
            assert_eq!(k.method().kind().method(), k.method());
        }
        assert!(SolverKind::Implicit.names_cascade() && !SolverKind::Penalty.names_cascade());
    }
}
