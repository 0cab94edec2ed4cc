//! How an analysis reports its progress: a callback that takes one line per stage.

/// What an analysis reports as it advances: one line per stage, model or candidate (the
/// command line prints them on stderr when it is not a terminal, so that a batch log shows
/// the analysis advancing). Lines have no trailing newline.
pub type Progress<'a> = &'a (dyn Fn(&str) + Sync);

/// A [`Progress`] that says nothing.
pub fn quiet(_: &str) {}
