//! Coarse solves given up where they cannot matter any more (issue 19, speed): once a plan is
//! refined, a coarse solution whose cost ends more than 20 % above it is neither a finalist nor
//! a far finalist (see [`ChainPlanner::search`](super::ChainPlanner)), so its solve is wasted.
//!
//! On the paper's problem at a = 1, b = -1 (89 coarse solves, 3425 SQP iterations, best plan
//! 42.98 rad^2/s) 45 lines of base targets `phid +- 2 pi` ran all 40 coarse iterations with the
//! residual still 4 to 6 rad and the cost rising past the plan's, and 22 coils started on the
//! constraint at 150 to 420 and ended, 2 to 5 ms each, at 100 to 320. The watch stops both
//! kinds: 1476 iterations instead of 3425, the same plan. On the 300 recorded two-link problems
//! and the 50 random mounts of the paper's problem every effort is the same to 1e-9 (1.38 of
//! 1.61 million iterations); with the fall extrapolated from the first iterate instead of from
//! the arrival on the constraint, three (recorded problems 112, 128, 282) lost their plan to a
//! line that reached the constraint at 66.8 and fell to 47.4 after.

/// Iterations before a solve may be given up, but for a cost far above the ceiling
/// ([`FAR_ABOVE`]) (its first steps still find their way: a coil's cost can fall by a third in
/// one step, a line's residual by half in ten).
const FIRST: usize = 10;

/// The residual \[rad\] above which a solve that has not halved it is making no progress (a coil
/// starts on the constraint, a line beside one within 1 rad of it).
const STUCK_RESIDUAL: f64 = 0.1;

/// The residual \[rad\] up to which a solve counts as on the constraint, its cost only falling.
const ON_CONSTRAINT: f64 = 1e-2;

/// Iterations on the constraint before its cost's fall is extrapolated (a line that reaches it
/// at a high cost then falls fast: on recorded problem 128 from 49.7 to 41.5 in ten).
const ON_FOR: usize = 5;

/// Safety factor on the cost's fall still to come, extrapolated at its rate so far.
const FALL_MARGIN: f64 = 2.0;

/// Whatever its residual, a solve whose cost is above the ceiling by the first factor from
/// iterate [`FAR_SOON`] on, or by the second from [`FIRST`] on, is given up. On the 300
/// recorded two-link problems, the 50 random mounts of the paper's problem and issue 19's table,
/// of the coarse solves that ended at or under their ceiling none had been above 3.58 times its
/// ceiling from its 5th iterate on, nor above 2.06 times from its 10th (measured again after
/// the search changed; 2.54 and 1.82 when these factors were set, on 9059 such solves): the
/// margins to 4 and 2.5 are thin, and tighter factors lose plans. On the paper's problem
/// at a = 1, b = -1 it stops lines that climb to 2.5 to 4 times the ceiling on their way to the
/// constraint and coils that start on it at 5 to 8 times: 1204 SQP iterations instead of 1487
/// (the same plan; 1295 with 3 as the second factor).
const FAR_ABOVE: [f64; 2] = [4.0, 2.5];

/// The iterate from which a cost [`FAR_ABOVE`]'s first factor above the ceiling gives a solve up.
const FAR_SOON: usize = 5;

/// The watch of one coarse solve ([`crate::planners::optimal::sqp::solve_watched`]) against a
/// cost `ceiling`, 1.2 times the best refined plan's cost.
pub(super) struct Hopeless {
    ceiling: f64,
    max_iterations: usize,
    /// `|c|` at the start \[rad\].
    start_residual: f64,
    /// The cost at each iterate so far.
    costs: Vec<f64>,
    /// The first iterate from which every one is on the constraint (within [`ON_CONSTRAINT`]).
    landed: Option<usize>,
}

impl Hopeless {
    /// The watch of a solve of at most `max_iterations` against `ceiling`.
    pub(super) fn new(ceiling: f64, max_iterations: usize) -> Self {
        Self { ceiling, max_iterations, start_residual: f64::NAN, costs: Vec::new(), landed: None }
    }

    /// Whether to give the solve up at its `k`-th iterate, of cost `f` and residual `c`: where
    /// its cost is far above the ceiling ([`FAR_ABOVE`]); after [`FIRST`] iterations, where its
    /// cost is above the ceiling and either it is stuck off the constraint (the residual above
    /// [`STUCK_RESIDUAL`] and more than half the start's: the cost rises as the residual falls,
    /// on the example above from 20 to 200 while the residual went from 5 to 4 rad), or it is on
    /// the constraint and its cost, falling at twice its fastest rate so far (the mean since the
    /// start or over the last five iterations) for the iterations left, would still end above
    /// the ceiling.
    pub(super) fn abandon(&mut self, k: usize, f: f64, c: f64) -> bool {
        if k == 0 {
            self.start_residual = c.abs();
        }
        self.costs.push(f);
        let r = c.abs();
        if r > ON_CONSTRAINT {
            self.landed = None;
        } else if self.landed.is_none() {
            self.landed = Some(k);
        }
        if k < FAR_SOON || !(f > self.ceiling) || self.costs.len() != k + 1 {
            return false;
        }
        if f > FAR_ABOVE[0] * self.ceiling || (k >= FIRST && f > FAR_ABOVE[1] * self.ceiling) {
            return true;
        }
        if k < FIRST {
            return false;
        }
        if r > STUCK_RESIDUAL && r > 0.5 * self.start_residual {
            return true;
        }
        let Some(landed) = self.landed.filter(|&l| k >= l + ON_FOR) else { return false };
        let mean = (self.costs[landed] - f) / (k - landed) as f64;
        let recent = (self.costs[k - ON_FOR] - f) / ON_FOR as f64;
        let rate = mean.max(recent).max(0.0);
        let left = self.max_iterations.saturating_sub(k) as f64;
        f - FALL_MARGIN * rate * left > self.ceiling
    }
}
