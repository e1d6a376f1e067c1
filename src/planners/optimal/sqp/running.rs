//! Inequality rows that are local in the variables but for one running sum, and the QP's
//! banded form of them: a row `g_i` whose gradient is `l_i + a_i grad y_k`, with `l_i` and `a_i`
//! local and `y_k = y_{k-1} + (a quantity local in x)` a running sum at point `k` (the base angle
//! `phi(t_k) = phi(t_{k-1}) - integral g`, Eq. 7 at zero momentum), is dense through `grad y_k`,
//! and a few dozen such rows fill the QP's KKT factor whole. The QP takes instead, for each
//! point `k` of an active such row, the variable `e_k = grad y_k^T d` defined by the local rows
//! `e_k - e_j - (grad y_k - grad y_j)^T d = 0` (`j` the point before it), and the row as
//! `l_i^T d + a_i e_k`: the same QP (the same minimiser and multipliers of the rows), whose KKT
//! stays sparse under Clarabel's AMD ordering.

/// One row's local gradient and the running sum it takes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunningRow {
    /// The row's index among the inequalities.
    pub row: usize,
    /// The point `k` of the running sum `y_k` it takes.
    pub point: usize,
    /// `a_i`: the row's derivative in `y_k`.
    pub slope: f64,
    /// `l_i`: the row's gradient at fixed `y_k`, as `(free index, derivative)` pairs.
    pub local: Vec<(usize, f64)>,
}

/// The running sum's steps and the rows that take it (see the module docs); the rows' full
/// gradients stay in [`super::Inequalities::rows`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Running {
    /// `grad y_k - grad y_{k-1}` for every point `k` (`grad y_{-1} = 0`), sparse.
    pub steps: Vec<Vec<(usize, f64)>>,
    /// The rows with a local form, by increasing row index.
    pub rows: Vec<RunningRow>,
}

impl Running {
    /// The local form of row `i`, if it has one.
    pub(super) fn row(&self, i: usize) -> Option<&RunningRow> {
        self.rows.binary_search_by_key(&i, |r| r.row).ok().map(|k| &self.rows[k])
    }

    /// The QP's rows defining `e` at `points` (increasing): for each, its `(free index,
    /// derivative)` pairs of `grad y_k - grad y_j` in `dim` variables (`j` the point before, or
    /// `grad y_k` for the first).
    pub(super) fn links(&self, points: &[usize], dim: usize) -> Vec<Vec<(usize, f64)>> {
        let mut sum = vec![0.0; dim];
        let mut from = 0;
        points
            .iter()
            .map(|&k| {
                for step in &self.steps[from..=k] {
                    for &(i, v) in step {
                        sum[i] += v;
                    }
                }
                from = k + 1;
                let link: Vec<(usize, f64)> =
                    sum.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(i, v)| (i, *v)).collect();
                sum.iter_mut().for_each(|v| *v = 0.0);
                link
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The links' sums telescope: their sum to a point is the running sum's gradient there,
    /// the steps' sum to that point.
    #[test]
    fn links_sum_to_the_running_gradient() {
        let steps = vec![vec![(0, 1.0)], vec![(1, 2.0)], vec![(0, 0.5), (2, 3.0)], vec![(3, 4.0)]];
        let running = Running { steps, rows: Vec::new() };
        let links = running.links(&[1, 3], 4);
        assert_eq!(links[0], vec![(0, 1.0), (1, 2.0)]);
        assert_eq!(links[1], vec![(0, 0.5), (2, 3.0), (3, 4.0)]);
    }

    /// Rows are found by their index among the inequalities, and others have no local form.
    #[test]
    fn rows_found_by_index() {
        let rows = [3, 7].map(|row| RunningRow { row, point: row, slope: 1.0, local: Vec::new() }).to_vec();
        let running = Running { steps: Vec::new(), rows };
        assert_eq!(running.row(7).map(|r| r.point), Some(7));
        assert!(running.row(5).is_none());
    }
}
