//! The tables of one planning call (a spline basis with its quadrature, by uniform spans, nodes
//! per span and end grading), shared by the seeds solved in parallel, and the discretisations on
//! them.

use std::sync::{Arc, Mutex, PoisonError};

use super::discrete::{Discretisation, Table, Targets};
use super::{ChainPlanner, ChainProblem};
use crate::error::Error;
use crate::model::InputError;
use crate::planners::optimal::Cost;
use crate::planners::optimal::spline::SplineBasis;

/// The tables built in one planning call, by (uniform spans, quadrature nodes, end grading),
/// shared by the seeds solved in parallel.
#[derive(Default)]
pub(super) struct Tables(Mutex<Vec<TableEntry>>);

/// A cached table with its (uniform spans, quadrature nodes, end grading).
type TableEntry = ((usize, usize, usize), Arc<Table>);

impl ChainPlanner {
    /// The discretisation of `targets` on `spans` uniform spans and `nodes` nodes per span.
    pub(super) fn discretise(
        &self,
        problem: &ChainProblem,
        targets: Targets,
        spans: usize,
        nodes: usize,
        tables: &Tables,
    ) -> Result<Discretisation, Error> {
        self.discretise_graded(problem, targets, [spans, nodes, self.options.grading], tables)
    }

    /// [`Self::discretise`] with `grading` graded knots per end.
    pub(super) fn discretise_graded(
        &self,
        problem: &ChainProblem,
        targets: Targets,
        [spans, nodes, grading]: [usize; 3],
        tables: &Tables,
    ) -> Result<Discretisation, Error> {
        // Built under the lock: a table is built once however many seeds ask for it.
        let mut cache = tables.0.lock().unwrap_or_else(PoisonError::into_inner);
        let cached = cache.iter().find(|(key, _)| *key == (spans, nodes, grading)).map(|(_, t)| t.clone());
        let table = match cached {
            Some(t) => t,
            None => {
                let basis = match &self.options.knots {
                    Some(b) if b.last().is_some_and(|&t| (t - problem.horizon).abs() <= 1e-12 * problem.horizon) => {
                        SplineBasis::on_breakpoints(self.degree(), b)?
                    }
                    Some(b) => {
                        return Err(Error::from(InputError::InvalidParameter {
                            name: "knots".into(),
                            value: b.last().copied().unwrap_or(f64::NAN),
                            expected: "breakpoints that end at the problem's horizon",
                        }));
                    }
                    None => SplineBasis::graded(self.degree(), problem.horizon, spans, grading)?,
                };
                let t = Arc::new(Table::new(basis, self.arm.joints(), self.fixed(), nodes)?);
                cache.push(((spans, nodes, grading), t.clone()));
                t
            }
        };
        drop(cache);
        let disc = Discretisation::on(self.connection.clone(), table, targets);
        Ok(match self.options.cost {
            Cost::Effort => disc,
            Cost::Energy => disc.with_energy(self.arm.clone()),
        })
    }
}
