//! The `[solver]` table of a study file, read and checked alike whatever the protocol:
//! without `kind` a study runs by its protocol's default solver
//! ([`crate::protocol::Loading::default_solver`], as the command line does), and a method
//! the protocol's `WAYS` does not offer is refused at the key that chooses it
//! ([`crate::protocol::Loading::refusal_key`]).

use crate::dem::SolverParams;
use crate::protocol::Loading;

/// Whether a study file's text gives `[solver] kind`.
pub(super) fn kind_given(text: &str) -> bool {
    text.parse::<toml::Table>()
        .ok()
        .and_then(|t| t.get("solver").and_then(|s| s.as_table()).map(|s| s.contains_key("kind")))
        .unwrap_or(false)
}

/// The solver of a study of `loading` as its file states it: `solver` with its kind the
/// protocol's default when the file's `text` gives none.
pub(super) fn with_default_kind(mut solver: SolverParams, loading: Loading, text: &str) -> SolverParams {
    if !kind_given(text) {
        solver.kind = loading.default_solver();
    }
    solver
}

/// The method's checks of a study's solver for its protocol: the method offered by the
/// protocol ([`crate::protocol::check`]), its own settings in range, and limit analysis's
/// (which runs beside the other methods too). The error is the key at fault and why.
pub(super) fn check_method(loading: Loading, solver: &SolverParams) -> Result<(), (String, String)> {
    let range = |table: &'static str| move |e: crate::range::OutOfRange| (format!("{table}.{}", e.key), e.reason());
    crate::protocol::check(loading, solver.kind)
        .map_err(|e| (e.protocol.refusal_key().to_string(), format!("{e}: give [solver] kind = one of these")))?;
    solver.validate_method().map_err(range("solver"))?;
    solver.limit.validate().map_err(range("solver.limit"))?;
    Ok(())
}
