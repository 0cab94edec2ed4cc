//! The contract every loading protocol keeps ([`LoadingProtocol`]), what a run gives
//! ([`RunOutcome`]), who watches it ([`Observer`]) and the refusal of a solver that does not
//! run a protocol ([`Unsupported`]).
//!
//! A protocol is one module of this folder: a type holding its parameters, the result of
//! one run whatever method ran it, and the list of the methods that run it, each with its
//! driver, that is both its row of the compatibility table and its dispatch
//! ([`LoadingProtocol::WAYS`]): the choice of a method is made there and nowhere else. The registry in `protocol/mod.rs`
//! lists the protocols once and makes every enum that names them.

use super::observed::Observed;
use crate::dem::state::Body;
use crate::dem::{Method, Simulation, SolverKind, SolverParams};
use crate::layout::Layout;

/// Who watches a run: the command line's recorders, the study's ParaView series, a
/// benchmark's counters, the Python package's callbacks. Observing changes nothing in the
/// run. Both methods default to doing nothing; `()` observes nothing.
pub trait Observer {
    /// A static state of a quasi-static protocol as it is reached (the penalty DEM): the
    /// tilting table at `at` degrees, the lateral load at load multiplier `at` (0 for the
    /// settled state before the load); `stable` whether the state is in equilibrium (an
    /// unstable one is handed over in the state its mechanism is read from).
    fn state(&mut self, at: f64, stable: bool, sim: &Simulation) {
        let _ = (at, stable, sim);
    }

    /// An instant of a motion (the shaking table): `time_s` from the start of the motion,
    /// the bodies in layout order, in the table frame.
    fn instant(&mut self, time_s: f64, bodies: &[Body]) {
        let _ = (time_s, bodies);
    }
}

impl Observer for () {}

/// An observer made of a closure over the static states ([`Observer::state`]).
pub struct States<F: FnMut(f64, bool, &Simulation)>(pub F);

impl<F: FnMut(f64, bool, &Simulation)> Observer for States<F> {
    fn state(&mut self, at: f64, stable: bool, sim: &Simulation) {
        (self.0)(at, stable, sim)
    }
}

/// An observer made of a closure over the instants of a motion ([`Observer::instant`]).
pub struct Instants<F: FnMut(f64, &[Body])>(pub F);

impl<F: FnMut(f64, &[Body])> Observer for Instants<F> {
    fn instant(&mut self, time_s: f64, bodies: &[Body]) {
        (self.0)(time_s, bodies)
    }
}

/// One way a method runs a protocol: the method, what it gives there (its cell of the
/// compatibility table) and the driver that runs it.
pub struct Way<P: LoadingProtocol> {
    /// The method.
    pub method: Method,
    /// What the method gives for the protocol, in a phrase (the table's cell).
    pub what: &'static str,
    /// Runs the protocol `P` on a layout with the solver's settings, handing its states to
    /// the observer. Called only once the seam has checked the solver
    /// ([`super::check`]).
    pub run: fn(&P, &Layout, &SolverParams, &mut dyn Observer) -> P::Run,
}

/// A loading protocol: one module of `protocol/`, registered once in `protocol/mod.rs`
/// under the name a study file and the command line give it (its [`super::ProtocolKind`]:
/// the hand-rolled table and the pushover are chosen within the tilting table's and the
/// lateral load's tables).
pub trait LoadingProtocol: Sized + 'static {
    /// Its name in tables and in the Python package's `drystone.supports`.
    const NAME: &'static str;
    /// What it is, in a phrase (for messages).
    const DESCRIPTION: &'static str;
    /// Whether it is a motion (a time history) rather than a sequence of static states: a
    /// penalty cascade, a setting of static solves, does not apply to it.
    const MOTION: bool;
    /// The solver that runs it when none is named: a study without `[solver] kind`, the
    /// command line without `--solver` (the penalty DEM unless the protocol says
    /// otherwise).
    const DEFAULT_SOLVER: SolverKind = SolverKind::Penalty;
    /// The study key a refusal of the solver is reported at: the key that chose this
    /// protocol over the one that would run (`tilt.by_hand`), or `solver.kind`.
    const REFUSAL_KEY: &'static str = "solver.kind";
    /// Whether its columns of the realizations table (`io::table`) are written only to a
    /// table a row of which holds one of them (the pushover's load multipliers, which a
    /// study of the lateral load at its service level leaves out), rather than to every
    /// table \[false\].
    const OPTIONAL_COLUMNS: bool = false;
    /// Whether its drivers read the layout's vertical-load rig
    /// ([`crate::layout::Layout::vertical_load_rig`], set by the effects that act on the
    /// readings only), so that its runs can be read again under another one
    /// ([`super::Observed::reread`]) \[false\]. A study of a protocol that does not read it
    /// refuses those effects.
    const READS_VERTICAL_LOAD_RIG: bool = false;
    /// Whether it loads the wall in its own plane (the in-plane test), so that its runs do
    /// not read the effects that act across the plane
    /// ([`crate::effects::EffectDef::not_read_in_plane`]: a lean, a table's overshoot):
    /// the discrepancy analysis's default search leaves them out and refuses one named
    /// \[false\].
    const LOADS_IN_PLANE: bool = false;
    /// The key of its kind's table that chooses it within its kind, and the value that
    /// chooses it ([`ChosenBy`]); `None` for the first protocol of its kind, which its
    /// kind's name chooses.
    const CHOSEN_BY: Option<ChosenBy>;
    /// What one run gives, whatever method ran it.
    type Run: RunOutcome;

    /// Its row of the compatibility table and its dispatch: the methods that run it, each
    /// once ([`Way`]: what it gives there and the driver it runs). A method the row does not
    /// list does not run the protocol: the seam refuses it by name ([`Unsupported`]), it is
    /// never sent down another method's driver.
    const WAYS: &'static [Way<Self>];

    /// How `method` runs the protocol ([`LoadingProtocol::WAYS`]), `None` if it does not.
    fn way(method: Method) -> Option<&'static Way<Self>> {
        Self::WAYS.iter().find(|w| w.method == method)
    }

    /// The protocol to run to compare with measured data (`drystone discrepancy`), or why
    /// it has nothing to compare.
    ///
    /// # Errors
    /// The reason, in a sentence.
    fn compared(&self) -> Result<super::Protocol, &'static str>;

    /// What the protocol's run gives to compare with measured data, for the discrepancy
    /// analysis to check each observation against ([`Observables`]).
    fn observables(&self) -> Observables;

    /// The shaking table's parameters and motion, for a protocol that shakes the table;
    /// `None` by default.
    fn shaking(&self) -> Option<(&crate::loading::shake::ShakeParams, &crate::ground::Motion)> {
        None
    }

    /// The tilting table's parameters, for a protocol that tilts the table (the
    /// discrepancy analysis reads its increment and resolution); `None` by default.
    fn tilt(&self) -> Option<&crate::loading::tilt::TiltParams> {
        None
    }
}

/// The key of a kind's table that chooses a protocol within its kind (`[tilt] by_hand`,
/// `[lateral] pushover = true`) and the value that chooses it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChosenBy {
    /// The kind's table (`tilt`).
    pub table: &'static str,
    /// Its key (`by_hand`).
    pub key: &'static str,
    /// The value that chooses the protocol.
    pub value: Choice,
}

/// The value of a key that chooses a protocol within its kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Choice {
    /// A table of its own, its keys' defaults (`[tilt.by_hand]`).
    Table,
    /// `true` (`pushover = true`).
    True,
}

/// A kind of output a protocol's run gives to compare with measured data
/// (`drystone discrepancy`): each observable of the analysis is of one
/// (`discrepancy::Observable::output`), and a protocol lists those it gives
/// ([`Observables::outputs`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// The collapse angle α_max, read from the bracket of the run's collapse.
    CollapseAngle,
    /// The top displacements at the run's states (the stable tilts, or the one equilibrium
    /// under a load).
    Displacements,
    /// The failure mechanism as a person reads it: its failure height, kind and start.
    Mechanism,
    /// The measures of a force–displacement curve's first direction loaded: peak force,
    /// drift at the peak, initial stiffness.
    CurveMeasures,
    /// The mode of the mechanism at the peak of a force–displacement curve (sliding,
    /// rocking, diagonal or mixed).
    MechanismMode,
}

/// What a protocol's run gives to compare with measured data (`drystone discrepancy`):
/// which observables exist ([`Output`]) and at which states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observables {
    /// What the run gives; an observation of another output is refused.
    pub outputs: &'static [Output],
    /// Width of the bracket of a simulated collapse angle, degrees; `None`: the protocol
    /// gives no collapse angle (and does not list [`Output::CollapseAngle`]).
    pub collapse_bracket_deg: Option<f64>,
    /// The step of the tilts at which the run gives displacements, degrees (a displacement
    /// observation at a tilt off its multiples is refused); `None`: one state, at tilt 0
    /// (the equilibrium under a load).
    pub state_step_deg: Option<f64>,
}

impl Observables {
    /// Whether the run gives `output`.
    pub fn gives(&self, output: Output) -> bool {
        self.outputs.contains(&output)
    }

    /// Whether the run gives displacements at tilt `tilt_deg`, degrees.
    pub fn reaches_tilt(&self, tilt_deg: f64) -> bool {
        match self.state_step_deg {
            Some(step) => {
                let k = (tilt_deg / step).round();
                (k * step - tilt_deg).abs() <= 1e-9
            }
            None => tilt_deg == 0.0,
        }
    }
}

/// What a run of a protocol gives, whatever method ran it.
pub trait RunOutcome {
    /// What the run gives to compare with measured data ([`Observed`]); `None` for a run
    /// that ended in an error or gives nothing to compare.
    fn observed(&self) -> Option<Observed>;
    /// The error that ended the run, if any, as text.
    fn error(&self) -> Option<String>;
    /// Whether the run ended because the layout did not stand as given under gravity alone
    /// (as opposed to a blow-up or a bad parameter).
    fn does_not_stand(&self) -> bool;
    /// Whether the run ended because the protocol refused its parameters for this layout
    /// before running it (a value out of range once the wall's dimensions are known, a wall
    /// the rig cannot be laid on, a stiffness or drift past the method's reach), as
    /// opposed to a blow-up. `false` by default: the protocols whose parameters are all
    /// checked before a layout exists.
    fn refused(&self) -> bool {
        false
    }
    /// What limit analysis gave, for a run by limit analysis (the collapse load multiplier
    /// of the protocol's live load, `drystone limit`); `None` for a run by another method
    /// (the default).
    fn limit(&self) -> Option<&Result<crate::limit::LimitResult, crate::limit::LimitError>> {
        None
    }
}

/// A solver that does not run a protocol, with the methods that do (the compatibility
/// table's row of the protocol, [`super::methods`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.message())]
pub struct Unsupported {
    /// The protocol asked.
    pub protocol: super::Loading,
    /// The solver asked.
    pub kind: SolverKind,
}

impl Unsupported {
    fn message(&self) -> String {
        let ways: Vec<String> = Method::ALL
            .into_iter()
            .filter_map(|m| super::methods(self.protocol, m).map(|what| format!("{} ({what})", m.name())))
            .collect();
        let why = if super::supports(self.protocol, self.kind.method()) {
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
