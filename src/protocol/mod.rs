//! The protocol seam: one type through which a study, the discrepancy analysis, the
//! command line, the benchmarks and the Python package run a loading protocol on one
//! realization's layout.
//!
//! A protocol is one module of this folder behind one trait ([`LoadingProtocol`]): a type
//! holding its parameters, the result of a run whatever method ran it ([`RunOutcome`]), and
//! the list of the methods that run it, each with its driver, that is both its row of the
//! compatibility table and its dispatch ([`LoadingProtocol::WAYS`]). The registry below
//! lists the protocols once and makes every enum that names them: [`ProtocolKind`] (the
//! name a study file and the command line give), [`Loading`] (the table's rows),
//! [`Protocol`] (a protocol with its parameters) and [`ProtocolRun`] (what a run gave).
//! [`run`] is the one place a method is chosen: it checks the solver against the table
//! ([`check`]) and calls the protocol's way for the solver's method, handing its states to
//! an [`Observer`]. Adding a protocol is its module here, its line in the registry and the
//! drivers it calls (CONTRIBUTING.md).
//!
//! # Words: `kind`, `loading`, `method`
//!
//! Each means one thing across the protocols, the solvers and the studies:
//!
//! * **kind**: a name a file or the command line gives. [`ProtocolKind`] (`protocol =
//!   "tilt"`, `--protocol`; [`Loading::kind`], `study::StudyProtocol::kind`) and
//!   [`SolverKind`] (`[solver] kind`, `--solver`; [`Method::kind`], the first kind of a
//!   method; [`Unsupported::kind`]). Elsewhere a `kind` field or enum names a category of its
//!   own type (`MechanismKind`, `FailureKind`, `WallKind`, `PieceKind`, `EndRestraintKind`),
//!   never a protocol or a solver.
//! * **loading**: a [`Loading`], a protocol without its parameters (a row of the
//!   compatibility table): [`Protocol::loading`], `study::StudyProtocol::loading`,
//!   `study::StudySpec::loading`, [`ProtocolKind::loadings`]. A protocol with its
//!   parameters is a [`Protocol`] (`study::Study::protocol_at`). Two uses keep the word for
//!   something else: the folder `src/loading/` (`crate::loading`, the drivers: the physics
//!   of each protocol) and the column `loading` of the in-plane test's measured specimens
//!   (`Cyclic` or `Monotonic`, the history of the imposed displacement:
//!   `study::inplane::Specimen::loading`, a file key).
//! * **method**: a [`Method`] (the penalty DEM, nscd, limit analysis); a run's variants
//!   are named by it ([`TiltRun::method`], [`LateralRun::method`], [`PushoverRun::method`],
//!   [`InPlaneRun::method`]). The realizations table's `load_multiplier_dem` columns keep
//!   their name from before nscd filled them: the pushover by a method that steps.

pub mod compression;
mod contract;
pub mod inplane;
mod inplane_observed;
pub mod lateral;
mod observed;
mod outcomes;
pub mod pushover;
pub mod shake;
pub mod tilt;
pub mod tilt_by_hand;

pub use compression::{Compression, CompressionRun};
pub use contract::{
    Choice, ChosenBy, Instants, LoadingProtocol, Observables, Observer, Output, RunOutcome, States, Unsupported, Way,
};
pub use inplane::{InPlane, InPlaneRun};
pub use inplane_observed::{InPlaneObserved, InPlaneReading};
pub use lateral::{run_lateral, run_lateral_observed, Lateral, LateralRun};
pub use observed::Observed;
pub use pushover::{Pushover, PushoverRun};
pub use shake::{run_shake, run_shake_observed, Shake};
pub use tilt::{run_tilt, run_tilt_observed, Tilt, TiltRun};
pub use tilt_by_hand::TiltByHand;

use crate::dem::{Method, SolverKind, SolverParams};
use crate::layout::Layout;
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;

/// A protocol the registry lists, with its row of the compatibility table
/// ([`Loading`]); implemented by the registry for every protocol it lists.
pub trait Registered: LoadingProtocol {
    /// Its row of the compatibility table.
    const LOADING: Loading;
}

/// Makes, from the one list of protocols, every enum that names them and their dispatch.
///
/// The list is grouped by the name a study file and the command line give (`protocol =
/// "tilt"`, `--protocol tilt`): a [`ProtocolKind`] with its name, then its protocols, the
/// first the one its table chooses by default (the hand-rolled table and the pushover are
/// chosen within the tilting table's and the lateral load's tables).
macro_rules! registry {
    ($(
        $(#[doc = $kdoc:literal])*
        $kind:ident = $name:literal {
            $($(#[doc = $doc:literal])* $variant:ident($ty:ty)),+ $(,)?
        }
    ),+ $(,)?) => {
        /// A protocol as a study file and the command line name it (`protocol = "tilt"`,
        /// `drystone limit --protocol tilt`): its name is its spelling in either ([`ProtocolKind::name`],
        /// serde's and the command line's alike). Each kind is one or more rows of the
        /// compatibility table ([`ProtocolKind::loadings`]), the one its table chooses
        /// ([`Protocol::tilting`], [`Protocol::lateral`]) being run.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum ProtocolKind {
            $($(#[doc = $kdoc])* #[serde(rename = $name)] $kind,)+
        }

        impl ProtocolKind {
            /// Every kind, in the registry's order.
            pub const ALL: [ProtocolKind; [$(ProtocolKind::$kind),+].len()] = [$(ProtocolKind::$kind),+];

            /// Its name in study files (`protocol = "..."`) and on the command line.
            pub fn name(self) -> &'static str {
                match self {
                    $(ProtocolKind::$kind => $name,)+
                }
            }

            /// Its rows of the compatibility table, in the registry's order: the first is
            /// run unless its table chooses another (`tilt.by_hand`, `lateral.pushover`).
            pub fn loadings(self) -> &'static [Loading] {
                match self {
                    $(ProtocolKind::$kind => &[$(Loading::$variant),+],)+
                }
            }
        }

        /// A protocol, as a row of the compatibility table ([`methods`]).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Loading {
            $($($(#[doc = $doc])* $variant,)+)+
        }

        impl Loading {
            /// Every protocol, in the registry's order.
            pub const ALL: [Loading; [$($(Loading::$variant),+),+].len()] = [$($(Loading::$variant),+),+];

            /// The name a study file and the command line give it: its [`ProtocolKind`].
            pub fn kind(self) -> ProtocolKind {
                match self {
                    $($(Loading::$variant => ProtocolKind::$kind,)+)+
                }
            }

            /// Its name in the Python package's `drystone.supports` and in tables
            /// ([`LoadingProtocol::NAME`]).
            pub fn name(self) -> &'static str {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::NAME,)+)+
                }
            }

            /// What it is, in a phrase (for messages).
            pub fn describe(self) -> &'static str {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::DESCRIPTION,)+)+
                }
            }

            /// Whether it is a motion (a time history) rather than a sequence of static
            /// states: a penalty cascade, a setting of static solves, does not apply to it.
            pub fn is_motion(self) -> bool {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::MOTION,)+)+
                }
            }

            /// Whether its columns of the realizations table are written only to a table a
            /// row of which holds one of them ([`LoadingProtocol::OPTIONAL_COLUMNS`]).
            pub fn optional_columns(self) -> bool {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::OPTIONAL_COLUMNS,)+)+
                }
            }

            /// The solver that runs it when none is named
            /// ([`LoadingProtocol::DEFAULT_SOLVER`]).
            pub fn default_solver(self) -> SolverKind {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::DEFAULT_SOLVER,)+)+
                }
            }

            /// The study key a refusal of the solver is reported at
            /// ([`LoadingProtocol::REFUSAL_KEY`]).
            pub fn refusal_key(self) -> &'static str {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::REFUSAL_KEY,)+)+
                }
            }

            /// Whether its drivers read the layout's vertical-load rig, and its runs can be
            /// read again under another one ([`LoadingProtocol::READS_VERTICAL_LOAD_RIG`]).
            pub fn reads_vertical_load_rig(self) -> bool {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::READS_VERTICAL_LOAD_RIG,)+)+
                }
            }

            /// Whether it loads the wall in its own plane and does not read the effects
            /// across it ([`LoadingProtocol::LOADS_IN_PLANE`]).
            pub fn loads_in_plane(self) -> bool {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::LOADS_IN_PLANE,)+)+
                }
            }

            /// The key of its kind's table that chooses it within its kind, and its value
            /// ([`LoadingProtocol::CHOSEN_BY`]); `None` for the first of its kind.
            pub fn chosen_by(self) -> Option<ChosenBy> {
                match self {
                    $($(Loading::$variant => <$ty as LoadingProtocol>::CHOSEN_BY,)+)+
                }
            }

            /// The protocol of a name; `None` for an unknown one.
            pub fn from_name(name: &str) -> Option<Loading> {
                Loading::ALL.into_iter().find(|l| l.name() == name)
            }
        }

        $($(impl Registered for $ty {
            const LOADING: Loading = Loading::$variant;
        })+)+

        /// Whether `method` runs `protocol`, and what it gives there (`None`: it does not):
        /// the protocol's row ([`LoadingProtocol::WAYS`]). The table below, as README.md's,
        /// is the registry's: a test generates it and prints it to paste when a copy differs.
        ///
        /// | protocol | the penalty DEM (`penalty`, `newton`, `implicit`, `accelerated`, `relaxation`) | non-smooth contact dynamics (`nscd`) | limit analysis (`limit`) |
        /// | --- | --- | --- | --- |
        /// | `tilt`: the tilting table | collapse angle (bisection of static states) | rigid collapse angle | α_max = atan λ |
        /// | `tilt_by_hand`: the tilting table rolled by hand (tilt.by_hand) | – | the rolled table's motion | – |
        /// | `lateral`: the static lateral load | equilibrium under the load | – | whether λ ≥ 1 |
        /// | `pushover`: the lateral pushover (lateral.pushover) | λ by increments (and λ of limit analysis beside it) | rigid λ by bisection | λ |
        /// | `shake`: the shaking table | explicit dynamics with contact damping (`penalty` only) | Moreau–Jean time stepping | – |
        /// | `in_plane`: the in-plane shear-compression test | force-displacement curve (static solve per increment of the imposed displacement) | rigid blocks' force-displacement curve (the beam driven at constant speed) | peak horizontal force under the vertical force, and the mechanism |
        /// | `compression`: the vertical compression test | vertical modulus and cycles (static solve per branch of the vertical force) | – | – |
        pub fn methods(protocol: Loading, method: Method) -> Option<&'static str> {
            match protocol {
                $($(Loading::$variant => <$ty as LoadingProtocol>::way(method).map(|w| w.what),)+)+
            }
        }

        /// The methods `protocol`'s row lists ([`LoadingProtocol::WAYS`], in its order), for
        /// the registry's test that each is listed once.
        #[cfg(test)]
        fn listed(protocol: Loading) -> Vec<Method> {
            match protocol {
                $($(Loading::$variant => <$ty as LoadingProtocol>::WAYS.iter().map(|w| w.method).collect(),)+)+
            }
        }

        /// A loading protocol with its parameters.
        #[derive(Debug, Clone, PartialEq)]
        pub enum Protocol {
            $($($(#[doc = $doc])* $variant($ty),)+)+
        }

        /// What one run of a protocol came to: what the protocol's run gave (the result of
        /// the method that ran it, or the error that ended it, which a study turns into a
        /// status row), or the solver's refusal.
        // One value a run, moved once to its caller: the size of its largest protocol's
        // result (the in-plane test's curve outputs) costs nothing worth a box.
        #[allow(clippy::large_enum_variant)]
        #[derive(Debug, Clone, PartialEq)]
        pub enum ProtocolRun {
            $($($(#[doc = $doc])* $variant(<$ty as LoadingProtocol>::Run),)+)+
            /// The solver does not run the protocol ([`check`]).
            Unsupported(Unsupported),
        }

        impl Protocol {
            /// Its row of the compatibility table, without its parameters.
            pub fn loading(&self) -> Loading {
                match self {
                    $($(Protocol::$variant(_) => Loading::$variant,)+)+
                }
            }

            /// Its name in study files (`protocol = "..."`): its kind's
            /// ([`ProtocolKind::name`]).
            pub fn name(&self) -> &'static str {
                self.loading().kind().name()
            }

            /// The protocol run to compare with measured data
            /// ([`LoadingProtocol::compared`]).
            ///
            /// # Errors
            /// Why the protocol has nothing to compare.
            pub fn observed(&self) -> Result<Protocol, &'static str> {
                match self {
                    $($(Protocol::$variant(p) => p.compared(),)+)+
                }
            }

            /// What its run gives to compare with measured data
            /// ([`LoadingProtocol::observables`]).
            pub fn observables(&self) -> Observables {
                match self {
                    $($(Protocol::$variant(p) => p.observables(),)+)+
                }
            }

            /// The shaking table's parameters and motion, for a protocol that shakes the
            /// table ([`LoadingProtocol::shaking`]).
            pub fn shaking(&self) -> Option<(&crate::loading::shake::ShakeParams, &crate::ground::Motion)> {
                match self {
                    $($(Protocol::$variant(p) => p.shaking(),)+)+
                }
            }

            /// The tilting table's parameters, for a protocol that tilts the table.
            pub fn tilt(&self) -> Option<&TiltParams> {
                match self {
                    $($(Protocol::$variant(p) => p.tilt(),)+)+
                }
            }

            /// Runs the protocol on `layout` with the solver `solver`, handing its states
            /// to `observer` ([`run`]).
            pub fn run_observed(&self, layout: &Layout, solver: SolverParams, observer: &mut dyn Observer) -> ProtocolRun {
                match self {
                    $($(Protocol::$variant(p) => {
                        run(p, layout, solver, observer).map_or_else(ProtocolRun::Unsupported, ProtocolRun::$variant)
                    })+)+
                }
            }
        }

        impl RunOutcome for ProtocolRun {
            fn observed(&self) -> Option<Observed> {
                match self {
                    $($(ProtocolRun::$variant(r) => r.observed(),)+)+
                    ProtocolRun::Unsupported(_) => None,
                }
            }
            fn error(&self) -> Option<String> {
                match self {
                    $($(ProtocolRun::$variant(r) => r.error(),)+)+
                    ProtocolRun::Unsupported(e) => Some(e.to_string()),
                }
            }
            fn does_not_stand(&self) -> bool {
                match self {
                    $($(ProtocolRun::$variant(r) => r.does_not_stand(),)+)+
                    ProtocolRun::Unsupported(_) => false,
                }
            }
            fn refused(&self) -> bool {
                match self {
                    $($(ProtocolRun::$variant(r) => r.refused(),)+)+
                    ProtocolRun::Unsupported(_) => true,
                }
            }
            fn limit(&self) -> Option<&Result<crate::limit::LimitResult, crate::limit::LimitError>> {
                match self {
                    $($(ProtocolRun::$variant(r) => r.limit(),)+)+
                    ProtocolRun::Unsupported(_) => None,
                }
            }
        }
    };
}

registry! {
    /// The tilting table (`[tilt]`): tilted to collapse, or rolled by hand (`by_hand`).
    Tilt = "tilt" {
        /// The tilting table, tilted quasi-statically to collapse ([`tilt`]).
        Tilt(Tilt),
        /// The tilting table rolled by hand in increments ([`tilt_by_hand`]): a motion.
        TiltByHand(TiltByHand),
    },
    /// The static lateral (trapezoidal pressure) load (`[lateral]`): at its service level,
    /// or pushed over to collapse (`pushover`).
    Lateral = "lateral" {
        /// The static lateral (trapezoidal pressure) load at its service level ([`lateral`]).
        Lateral(Lateral),
        /// The lateral load pushed over to collapse ([`pushover`]): its load multiplier λ.
        Pushover(Pushover),
    },
    /// The shaking table (`[shake]`): each realization under each motion scaled to each
    /// PGA level (incremental dynamic analysis).
    Shake = "shake" {
        /// The shaking table under a ground motion ([`shake`]): a motion.
        Shake(Shake),
    },
    /// The in-plane shear–compression test (`[in_plane]`): a loading beam under a constant
    /// vertical force, its horizontal displacement imposed (monotonic or cyclic).
    InPlane = "in_plane" {
        /// The in-plane shear–compression test ([`inplane`]).
        InPlane(InPlane),
    },
    /// The vertical compression test (`[compression]`): the loading beam's vertical force
    /// cycled, the wall's vertical modulus read.
    Compression = "compression" {
        /// The vertical compression test ([`compression`]).
        Compression(Compression),
    },
}

impl Default for ProtocolKind {
    /// The tilting table: a study file without `protocol`.
    fn default() -> ProtocolKind {
        ProtocolKind::Tilt
    }
}

impl ProtocolKind {
    /// The kind of a name (`tilt`, `lateral`, `shake`); `None` for an unknown one.
    pub fn from_name(name: &str) -> Option<ProtocolKind> {
        ProtocolKind::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl std::fmt::Display for ProtocolKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ProtocolKind {
    type Err = String;

    /// [`ProtocolKind::from_name`], with an error naming the kinds.
    fn from_str(name: &str) -> Result<ProtocolKind, String> {
        ProtocolKind::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = ProtocolKind::ALL.into_iter().map(ProtocolKind::name).collect();
            format!("unknown protocol {name:?} (one of {})", names.join(", "))
        })
    }
}

/// Runs protocol `p` on `layout` with the solver `solver`: the one place a method is
/// chosen. The solver is checked against the compatibility table ([`check`]), then the
/// protocol's way for the solver's method ([`LoadingProtocol::WAYS`]) runs, handing its
/// states to `observer`.
///
/// # Errors
/// [`Unsupported`] when the solver does not run the protocol.
pub fn run<P: Registered>(
    p: &P,
    layout: &Layout,
    solver: SolverParams,
    observer: &mut dyn Observer,
) -> Result<P::Run, Unsupported> {
    check(P::LOADING, solver.kind)?;
    let way = P::way(solver.kind.method()).ok_or(Unsupported { protocol: P::LOADING, kind: solver.kind })?;
    Ok((way.run)(p, layout, &solver, observer))
}

/// Whether `method` runs `protocol` ([`methods`]).
pub fn supports(protocol: Loading, method: Method) -> bool {
    methods(protocol, method).is_some()
}

/// Checks that the solver `kind` runs `protocol`: its method is in the table, and a motion
/// is not given a cascade of static solves (`newton`, `implicit`, `accelerated`, `relaxation`).
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

impl Protocol {
    /// The tilting table with its parameters `[tilt]`: rolled by hand when
    /// `params.by_hand` is set ([`TiltByHand`]), else tilted quasi-statically ([`Tilt`]).
    pub fn tilting(params: TiltParams) -> Protocol {
        match params.by_hand {
            Some(hand) => Protocol::TiltByHand(TiltByHand { tilt: params, hand }),
            None => Protocol::Tilt(Tilt(params)),
        }
    }

    /// The lateral load with its parameters `[lateral]`: pushed over to collapse when
    /// `params.pushover` is set ([`Pushover`]), else at its service level ([`Lateral`]).
    pub fn lateral(params: LateralParams) -> Protocol {
        if params.pushover {
            Protocol::Pushover(Pushover(params))
        } else {
            Protocol::Lateral(Lateral(params))
        }
    }

    /// The protocol of kind `kind` whose live load limit analysis multiplies
    /// (`drystone limit --protocol`): the tilting table, its weight along +y (λ = tan
    /// α_max), or the lateral load `lateral` (λ multiplies its pressure); `None` for a kind
    /// without a live load of limit analysis (the shaking table).
    pub fn live_load(kind: ProtocolKind, lateral: LateralParams) -> Option<Protocol> {
        match kind {
            ProtocolKind::Tilt => Some(Protocol::Tilt(Tilt(TiltParams::default()))),
            ProtocolKind::Lateral => Some(Protocol::Lateral(Lateral(lateral))),
            // The in-plane test's live load needs its vertical stress and shear span:
            // `drystone in-plane --solver limit`.
            // The compression test's load is the vertical force, which no mechanism of rigid
            // blocks on cohesionless joints multiplies to collapse.
            ProtocolKind::Shake | ProtocolKind::InPlane | ProtocolKind::Compression => None,
        }
    }

    /// Runs the protocol on `layout` with the solver `solver`, observing nothing
    /// ([`Protocol::run_observed`]).
    pub fn run(&self, layout: &Layout, solver: SolverParams) -> ProtocolRun {
        self.run_observed(layout, solver, &mut ())
    }
}

#[cfg(test)]
mod tests;
