//! The solver axis: the method a protocol runs by ([`Method`]: the penalty DEM, non-smooth
//! contact dynamics, limit analysis), its spelling in files and on the command line
//! ([`SolverKind`]: a method, and for the penalty DEM the stages of its static cascade) and
//! the stages themselves ([`Cascade`]). Plain data, read by the parameters, the solver seam
//! (`dem::solve`), the protocols and their one compatibility table
//! (`protocol::supports`).
//!
//! Both enums, their lists ([`Method::ALL`], [`SolverKind::ALL`]), their names (serde's,
//! [`SolverKind::name`], `FromStr`, hence `--solver` and the Python package's
//! `drystone.supports`) and the method of each kind are made by one list, the
//! `solvers!` invocation below: a method or a kind is added there, once, and the
//! compiler points to every exhaustive match that must say what it does.

use serde::{Deserialize, Serialize};

/// Makes, from the one list of methods and their kinds, [`Method`] and [`SolverKind`] with
/// their lists, names and the method of each kind.
///
/// Each method is listed with a phrase naming it in messages, then its solver kinds with
/// their names in files and on the command line; its first kind selects it with the
/// protocol's default cascade ([`Method::kind`]).
macro_rules! solvers {
    ($(
        $(#[doc = $mdoc:literal])*
        $method:ident = $describe:literal {
            $($(#[$kattr:meta])* $kind:ident = $name:literal),+ $(,)?
        }
    ),+ $(,)?) => {
        /// The method a protocol runs by: one axis, whatever the cascade of a penalty
        /// solve.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum Method {
            $($(#[doc = $mdoc])* $method,)+
        }

        impl Method {
            /// Every method, in the order of the list.
            pub const ALL: [Method; [$(Method::$method),+].len()] = [$(Method::$method),+];

            /// What it is, in a phrase (for messages).
            pub fn describe(self) -> &'static str {
                match self {
                    $(Method::$method => $describe,)+
                }
            }

            /// The solver kind that selects this method with the protocol's default
            /// cascade: the first of its kinds.
            pub fn kind(self) -> SolverKind {
                match self {
                    $(Method::$method => [$(SolverKind::$kind),+][0],)+
                }
            }

            /// The solver kinds that select it, in the order of the list.
            pub fn kinds(self) -> &'static [SolverKind] {
                match self {
                    $(Method::$method => &[$(SolverKind::$kind),+],)+
                }
            }
        }

        /// The solver a protocol runs on: `[solver] kind = "..."` in a study, `--solver
        /// NAME` on `drystone tilt`, `lateral` and `bench`. Default [`SolverKind::Penalty`].
        ///
        /// The first four are the penalty DEM (3DEC-style sub-contact springs, Kn and Ks
        /// from the layout) and differ only in how a static state is found ([`Cascade`]);
        /// their results agree within one bracket of the protocol, their costs differ
        /// (BENCHMARKS.md).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash, Serialize, Deserialize)]
        pub enum SolverKind {
            $($($(#[$kattr])* #[serde(rename = $name)] $kind,)+)+
        }

        impl SolverKind {
            /// Every solver kind, in the order of the list.
            pub const ALL: [SolverKind; [$($(SolverKind::$kind),+),+].len()] = [$($(SolverKind::$kind),+),+];

            /// Its name in files and on the command line (the serde name).
            pub fn name(self) -> &'static str {
                match self {
                    $($(SolverKind::$kind => $name,)+)+
                }
            }

            /// The method it selects.
            pub fn method(self) -> Method {
                match self {
                    $($(SolverKind::$kind => Method::$method,)+)+
                }
            }
        }
    };
}

solvers! {
    /// The penalty DEM (3DEC-style sub-contact springs, Kn and Ks from the layout): static
    /// states by its [`Cascade`], motion by explicit dynamics.
    Penalty = "the penalty DEM" {
        /// The penalty DEM with each protocol's default cascade: the tilting table runs the
        /// implicit iteration, its stall probe and accelerated dynamic relaxation; settling
        /// and the static lateral load run plain dynamic relaxation.
        #[default]
        Penalty = "penalty",
        /// The penalty DEM, the semi-smooth Newton solve of each increment first
        /// (`dem::drivers::newton`), then the protocol's default cascade where it ends
        /// unsolved.
        Newton = "newton",
        /// The penalty DEM: implicit iteration → stall probe → accelerated, probed dynamic
        /// relaxation.
        Implicit = "implicit",
        /// The penalty DEM, accelerated and probed dynamic relaxation without the implicit
        /// iteration (formerly `--no-implicit`, `implicit = false` in `[tilt]`).
        Accelerated = "accelerated",
        /// The penalty DEM, plain dynamic relaxation with local damping (formerly
        /// `--no-implicit --no-accelerate`).
        Relaxation = "relaxation",
    },
    /// Non-smooth contact dynamics (Moreau–Jean time stepping, NSGS; rigid joints).
    Nscd = "non-smooth contact dynamics" {
        /// Non-smooth contact dynamics (Moreau–Jean; rigid joints: Kn and Ks are not used).
        Nscd = "nscd",
    },
    /// Limit analysis (lower-bound statics of rigid blocks; rigid joints).
    Limit = "limit analysis" {
        /// Limit analysis (lower-bound statics of rigid blocks; rigid joints).
        Limit = "limit",
    },
}

impl Method {
    /// Its name: the [`SolverKind`] that selects it with the protocol's default cascade.
    pub fn name(self) -> &'static str {
        self.kind().name()
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

impl Method {
    /// Whether it draws a path of states under an imposed displacement (a
    /// force–displacement curve): the penalty DEM and nscd do; limit analysis gives the
    /// collapse load and its mechanism alone.
    pub fn draws_curves(self) -> bool {
        match self {
            Method::Penalty | Method::Nscd => true,
            Method::Limit => false,
        }
    }

    /// The other methods whose settings (`[solver.<name>]`) it does not read, of which a
    /// study warns: the penalty DEM runs no non-smooth solver, nscd no penalty solve;
    /// limit analysis reads `[solver.limit]` alone and runs beside the others, so a study
    /// warns of none.
    pub fn does_not_read(self) -> &'static [Method] {
        match self {
            Method::Penalty => &[Method::Nscd],
            Method::Nscd => &[Method::Penalty],
            Method::Limit => &[],
        }
    }

    /// Whether its steps of motion are solved to a tolerance (nscd: each step's contact
    /// problem to its natural-map residual, the steps left above it counted); the penalty
    /// DEM's explicit steps have no tolerance, limit analysis no steps.
    pub fn solves_steps_to_a_tolerance(self) -> bool {
        match self {
            Method::Nscd => true,
            Method::Penalty | Method::Limit => false,
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl SolverKind {
    /// The kind of a name, `None` for an unknown one.
    pub fn from_name(name: &str) -> Option<SolverKind> {
        SolverKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether it names a cascade of its own rather than the protocol's default (the
    /// penalty kinds other than `penalty`): a setting of static solves, which motion does not
    /// run.
    pub fn names_cascade(self) -> bool {
        match self {
            SolverKind::Newton | SolverKind::Implicit | SolverKind::Accelerated | SolverKind::Relaxation => true,
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

    /// Whether it is the kind that a study file without `[solver] kind` and a command without
    /// `--solver` give (its `Default`, `penalty`; a protocol may state its own default,
    /// `protocol::LoadingProtocol::DEFAULT_SOLVER`).
    pub fn is_default(self) -> bool {
        self == SolverKind::default()
    }

    /// Whether it names the semi-smooth Newton solve of each increment first, whatever the
    /// protocol's default cascade (`newton`): its own cascade's choice
    /// ([`SolverKind::cascade`] over a default without it).
    pub fn runs_newton(self) -> bool {
        self.cascade(Cascade::RELAXATION).is_some_and(|c| c.newton)
    }

    /// The stages of a static solve for a protocol whose default is `protocol_default`;
    /// `None` for a solver that is not a penalty method.
    pub fn cascade(self, protocol_default: Cascade) -> Option<Cascade> {
        match self {
            SolverKind::Penalty => Some(protocol_default),
            SolverKind::Newton => Some(Cascade { newton: true, ..protocol_default }),
            SolverKind::Implicit => Some(Cascade::IMPLICIT),
            SolverKind::Accelerated => Some(Cascade { newton: false, implicit: false, accelerate: true }),
            SolverKind::Relaxation => Some(Cascade::RELAXATION),
            SolverKind::Nscd | SolverKind::Limit => None,
        }
    }
}

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
    /// The semi-smooth Newton solve of the increment first (`dem::drivers::newton`); where
    /// it ends unsolved, the state is as it was and the next stage runs.
    pub newton: bool,
    /// The implicit iteration (and the probe of its drift where it stalls).
    pub implicit: bool,
    /// The secant acceleration and stability indicator in dynamic relaxation.
    pub accelerate: bool,
}

impl Cascade {
    /// Every stage.
    pub const FULL: Cascade = Cascade { newton: true, implicit: true, accelerate: true };
    /// Every stage but the Newton solve.
    pub const IMPLICIT: Cascade = Cascade { newton: false, implicit: true, accelerate: true };
    /// The Newton solve, then plain dynamic relaxation.
    pub const NEWTON_RELAXATION: Cascade = Cascade { newton: true, implicit: false, accelerate: false };
    /// Plain dynamic relaxation.
    pub const RELAXATION: Cascade = Cascade { newton: false, implicit: false, accelerate: false };
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
        assert_eq!(SolverKind::Implicit.cascade(Cascade::RELAXATION), Some(Cascade::IMPLICIT));
        assert_eq!(SolverKind::Newton.cascade(Cascade::RELAXATION), Some(Cascade::NEWTON_RELAXATION));
        assert_eq!(SolverKind::Newton.cascade(Cascade::IMPLICIT), Some(Cascade::FULL));
        assert!(!SolverKind::Nscd.is_penalty() && !SolverKind::Limit.is_penalty());
        assert!(SolverKind::Relaxation.is_penalty());
        for k in SolverKind::ALL {
            assert_eq!(k.is_penalty(), k.cascade(Cascade::IMPLICIT).is_some(), "{k}");
            assert_eq!(k.method().kind().method(), k.method());
        }
        assert!(SolverKind::Implicit.names_cascade() && !SolverKind::Penalty.names_cascade());
        let newton: Vec<SolverKind> = SolverKind::ALL.into_iter().filter(|k| k.runs_newton()).collect();
        assert_eq!(newton, [SolverKind::Newton]);
    }

    /// The one list makes every spelling agree: a kind's serde name (a study file) is its
    /// name (`--solver`, `drystone.supports`), every kind is in `ALL` once and belongs to
    /// the kinds of its method, and a method's name is its first kind's.
    #[test]
    fn one_list_names_every_kind_and_method_once() {
        for k in SolverKind::ALL {
            assert_eq!(toml::Value::try_from(k).unwrap().as_str(), Some(k.name()), "{k:?}");
            assert_eq!(toml::Value::String(k.name().into()).try_into::<SolverKind>().unwrap(), k);
            assert_eq!(SolverKind::ALL.iter().filter(|&&j| j == k).count(), 1, "{k:?}");
            assert!(k.method().kinds().contains(&k), "{k:?}");
        }
        let listed: Vec<SolverKind> = Method::ALL.iter().flat_map(|m| m.kinds().iter().copied()).collect();
        assert_eq!(listed, SolverKind::ALL);
        for m in Method::ALL {
            assert_eq!(toml::Value::try_from(m).unwrap().as_str(), Some(m.name()), "{m:?}");
            assert_eq!(m.kind(), m.kinds()[0]);
            assert_eq!(m.kind().cascade(Cascade::RELAXATION), m.kind().is_penalty().then_some(Cascade::RELAXATION));
        }
        assert_eq!(
            SolverKind::ALL.map(SolverKind::name),
            ["penalty", "newton", "implicit", "accelerated", "relaxation", "nscd", "limit"]
        );
        assert_eq!(Method::ALL.map(Method::name), ["penalty", "nscd", "limit"]);
        assert_eq!(SolverKind::default(), SolverKind::Penalty);
    }
}
