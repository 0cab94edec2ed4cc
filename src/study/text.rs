//! How the reports write numbers: a dash for a value that is not finite (an empty cell, a
//! ratio with nothing to divide).

/// A markdown table into `md`: the header row, the separator row, then one row per entry
/// of `rows`; cells as given (`| a | b |`, an empty cell as `| |`).
pub(crate) fn md_table(md: &mut String, header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) {
    fn line(md: &mut String, cells: impl Iterator<Item = impl AsRef<str>>) {
        md.push('|');
        for c in cells {
            let c = c.as_ref();
            md.push_str(if c.is_empty() { " |" } else { " " });
            if !c.is_empty() {
                md.push_str(c);
                md.push_str(" |");
            }
        }
        md.push('\n');
    }
    line(md, header.iter());
    line(md, header.iter().map(|_| "---"));
    for r in rows {
        line(md, r.iter());
    }
}

/// `v` with `d` decimals, `–` when not finite.
pub(crate) fn fixed(v: f64, d: usize) -> String {
    if v.is_finite() {
        format!("{v:.d$}")
    } else {
        "–".into()
    }
}

/// `v` in scientific notation with 3 decimals, `–` when not finite.
pub(crate) fn sci(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3e}")
    } else {
        "–".into()
    }
}

/// A fraction as a signed whole percentage (`+12 %`), `–` when not finite.
pub(crate) fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{:+.0} %", 100.0 * v)
    } else {
        "–".into()
    }
}

/// `agrees`, or `**disagrees**` (bold in markdown).
pub(crate) fn verdict(ok: bool) -> &'static str {
    if ok {
        "agrees"
    } else {
        "**disagrees**"
    }
}

/// Mean of the finite values, NaN if there are none.
pub(crate) fn finite_mean(v: &[f64]) -> f64 {
    let v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        f64::NAN
    } else {
        crate::stats::mean(&v)
    }
}
