//! Command handlers of the `drystone` binary that are longer than a few lines.

pub mod discrepancy;
