//! The compressed sparse column matrices of the cone programs, built from the entries
//! the program lists (row, column, value) by a counting sort on the column.

use clarabel::algebra::CscMatrix;

/// The `m × n` matrix of the entries `(rows[k], cols[k], vals[k])`: the matrix
/// [`CscMatrix::new_from_triplets`] builds (columns in order, rows ascending within each),
/// bit for bit, without its comparison sort of every entry. The programs list most columns'
/// rows in ascending order already; a column that is not is sorted on its own, and entries
/// repeated at one position (which `new_from_triplets` sums) hand the whole matrix to
/// `new_from_triplets`.
///
/// # Panics
/// If the three lists differ in length or an index is out of range.
pub(crate) fn csc_from_entries(
    m: usize,
    n: usize,
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
) -> CscMatrix<f64> {
    assert!(rows.len() == cols.len() && rows.len() == vals.len(), "one row and one column per value");
    let mut colptr = vec![0usize; n + 1];
    for &c in &cols {
        colptr[c + 1] += 1;
    }
    for c in 0..n {
        colptr[c + 1] += colptr[c];
    }
    let mut next = colptr[..n].to_vec();
    let mut order = vec![0usize; vals.len()];
    for (k, &c) in cols.iter().enumerate() {
        assert!(rows[k] < m, "row {} out of {m}", rows[k]);
        order[next[c]] = k;
        next[c] += 1;
    }
    for c in 0..n {
        let column = &mut order[colptr[c]..colptr[c + 1]];
        if column.windows(2).any(|w| rows[w[0]] >= rows[w[1]]) {
            // Stable, as new_from_triplets' sort: repeated rows stay in listed order.
            column.sort_by_key(|&k| rows[k]);
            if column.windows(2).any(|w| rows[w[0]] == rows[w[1]]) {
                return CscMatrix::new_from_triplets(m, n, rows, cols, vals);
            }
        }
    }
    let rowval = order.iter().map(|&k| rows[k]).collect();
    let nzval = order.iter().map(|&k| vals[k]).collect();
    CscMatrix::new(m, n, colptr, rowval, nzval)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn same(a: &CscMatrix<f64>, b: &CscMatrix<f64>) -> bool {
        a.m == b.m
            && a.n == b.n
            && a.colptr == b.colptr
            && a.rowval == b.rowval
            && a.nzval.iter().zip(&b.nzval).all(|(x, y)| x.to_bits() == y.to_bits())
            && a.nzval.len() == b.nzval.len()
    }

    /// Entries in any order, with empty columns, rows out of order within a column and
    /// repeated positions: the same matrix as clarabel's triplet constructor, bit for bit.
    #[test]
    fn the_matrix_is_the_one_of_the_triplet_constructor() {
        let (m, n) = (7, 6);
        let mut state: u64 = 12345;
        let mut next = |k: usize| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 33) as usize % k
        };
        for repeated in [false, true] {
            let (mut r, mut c, mut v) = (Vec::new(), Vec::new(), Vec::new());
            for k in 0..30 {
                let (i, j) = (next(m), next(n - 1)); // the last column stays empty
                if !repeated && r.iter().zip(&c).any(|(&a, &b)| (a, b) == (i, j)) {
                    continue;
                }
                r.push(i);
                c.push(j);
                v.push(0.1 * k as f64 + 1.0 / (1.0 + k as f64));
            }
            let ours = csc_from_entries(m, n, r.clone(), c.clone(), v.clone());
            let theirs = CscMatrix::new_from_triplets(m, n, r, c, v);
            assert!(same(&ours, &theirs), "repeated {repeated}: {ours:?} against {theirs:?}");
        }
    }
}
