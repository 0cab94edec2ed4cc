//! Anderson mixing of the implicit iteration (type II, mixing parameter 1; Anderson 1965,
//! *J. ACM* 12, 547; Walker & Ni 2011, *SIAM J. Numer. Anal.* 49, 1715).

use nalgebra::{DMatrix, DVector};
use std::collections::VecDeque;

/// Anderson mixing (type II, mixing parameter 1) over the last `depth` iterates.
pub(in crate::dem::drivers) struct AndersonMixing {
    depth: usize,
    /// `(Δx_i, f_{i+1} − f_i)` of the last iterations, oldest first.
    history: VecDeque<(Vec<f64>, Vec<f64>)>,
    /// The last preconditioned residual and the step taken from it.
    last: Option<(Vec<f64>, Vec<f64>)>,
}

impl AndersonMixing {
    pub(in crate::dem::drivers) fn new(depth: usize) -> AndersonMixing {
        AndersonMixing { depth, history: VecDeque::new(), last: None }
    }

    /// Whether the last step [`AndersonMixing::next`] returned mixed in past differences
    /// (false: it was the residual step itself).
    pub(in crate::dem::drivers) fn mixed(&self) -> bool {
        !self.history.is_empty()
    }

    /// The step from the preconditioned residual `f` (flattened, m).
    pub(in crate::dem::drivers) fn next(&mut self, f: Vec<f64>) -> Vec<f64> {
        if let Some((lf, dx)) = self.last.take() {
            if self.depth > 0 {
                let df: Vec<f64> = f.iter().zip(&lf).map(|(a, b)| a - b).collect();
                self.history.push_back((dx, df));
                if self.history.len() > self.depth {
                    self.history.pop_front();
                }
            }
        }
        let mut step = f.clone();
        let m = self.history.len();
        if m > 0 {
            // Normal equations of min ‖f − ΔF γ‖, with a relative ridge of 1e-10 against
            // (near-)collinear differences.
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
            let mut a = DMatrix::<f64>::zeros(m, m);
            let mut b = DVector::<f64>::zeros(m);
            for i in 0..m {
                for j in 0..=i {
                    let v = dot(&self.history[i].1, &self.history[j].1);
                    a[(i, j)] = v;
                    a[(j, i)] = v;
                }
                b[i] = dot(&self.history[i].1, &f);
            }
            let ridge = 1e-10 * (0..m).map(|i| a[(i, i)]).fold(0.0, f64::max);
            for i in 0..m {
                a[(i, i)] += ridge;
            }
            if let Some(g) = a.lu().solve(&b) {
                for (gi, (dx, df)) in g.iter().zip(&self.history) {
                    for ((s, x), y) in step.iter_mut().zip(dx).zip(df) {
                        *s -= gi * (x + y);
                    }
                }
            }
        }
        self.last = Some((f, step.clone()));
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Anderson mixing of depth m solves a linear fixed-point problem `x = x + f(x)`,
    /// `f(x) = b − A x` with A symmetric positive definite of dimension m + 1 or less in at
    /// most m + 2 iterations (it is GMRES), where the plain iteration needs hundreds.
    #[test]
    fn anderson_mixing_solves_a_small_linear_problem_like_gmres() {
        let a = nalgebra::Matrix3::new(1.0, 0.2, 0.0, 0.2, 0.05, 0.01, 0.0, 0.01, 0.002);
        let b = nalgebra::Vector3::new(1.0, -1.0, 0.5);
        let exact = a.try_inverse().unwrap() * b;
        let run = |depth: usize| {
            let mut mixing = AndersonMixing::new(depth);
            let mut x = nalgebra::Vector3::zeros();
            for it in 0..2000 {
                let f = b - a * x;
                if (x - exact).norm() < 1e-9 * exact.norm() {
                    return it;
                }
                let step = mixing.next(f.as_slice().to_vec());
                x += nalgebra::Vector3::from_column_slice(&step);
            }
            2000
        };
        assert!(run(3) <= 5, "{}", run(3));
        assert!(run(0) > 100, "{}", run(0));
    }
}
