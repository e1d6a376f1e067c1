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

/// The tables of a planner's calls, by basis, joints, fixed coefficients per end and quadrature
/// nodes per span: built once per planner (a plan's are those of its horizon; on the paper's
/// problem at a = b = 0.1 they were 4 % of a plan's instructions). Shared by the planner's
/// clones; every key says what its table is built from.
#[derive(Debug, Default, Clone)]
pub(super) struct KeptTables(Arc<Mutex<Vec<KeptTable>>>);

/// A kept table with its basis, joints, fixed coefficients per end and nodes per span.
type KeptTable = ((SplineBasis, usize, usize, usize), Arc<Table>);

/// Tables kept per planner before the list is emptied (one per basis and horizon planned).
const KEPT_TABLES: usize = 16;

/// Every planner's tables compare equal (a cache of what its keys determine).
impl PartialEq for KeptTables {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl KeptTables {
    /// The table of `key`: a kept one, else built by `build` and kept.
    fn get(
        &self,
        key: (SplineBasis, usize, usize, usize),
        build: impl FnOnce(SplineBasis) -> Result<Table, Error>,
    ) -> Result<Arc<Table>, Error> {
        let found = |kept: &Vec<KeptTable>| kept.iter().find(|(k, _)| *k == key).map(|(_, t)| t.clone());
        if let Some(t) = found(&self.0.lock().unwrap_or_else(PoisonError::into_inner)) {
            return Ok(t);
        }
        let t = Arc::new(build(key.0.clone())?);
        let mut kept = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        if found(&kept).is_none() {
            if kept.len() >= KEPT_TABLES {
                kept.clear();
            }
            kept.push((key, t.clone()));
        }
        Ok(t)
    }
}

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
                let (joints, fixed) = (self.arm.joints(), self.fixed());
                let t = self.tables.get((basis, joints, fixed, nodes), |b| Table::new(b, joints, fixed, nodes))?;
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
