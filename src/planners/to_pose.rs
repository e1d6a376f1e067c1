//! Planning to a tool pose `(x, y, psi)` instead of a goal configuration (`--to-ee`, Python's
//! `goal_ee`; docs/spec.md §1): the goal configurations are the free-floating inverse
//! kinematics' solutions, each is planned, and the certified plan of least effort is kept.
//!
//! The pose is in the inertial frame with the system's centre of mass at the origin (m, m, rad).
//! At zero momentum the centre of mass stays there (Eq. 2), so the pose fixes where the tool
//! ends, and the base angle `phi` follows from the joint angles wherever the mount is off the
//! base's centre of mass. One routine per robot model: [`plan_to_pose`] for the paper's 2-link
//! robot (the closed form's two elbows), [`plan_arm_to_pose`] for any arm (every branch of
//! [`Arm::inverse_kinematics`], each reported with what became of it).

use serde::Serialize;

use super::arm::{ArmPlanned, ArmRequest, plan_arm};
use super::chain::ChainProblem;
use super::{Planned, Planner};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::model::arm::kinematics::IkBranch;
use crate::model::kinematics::{Elbow, inverse_kinematics};
use crate::model::{Configuration, InputError};
use crate::plan::{Method, PlanningProblem};

/// Plans from `problem.start` to the end-effector pose `(x, y, psi)` (inertial frame, the
/// system's centre of mass at the origin; m, m, rad) instead of `problem.goal`: the goal
/// configurations are the free-floating inverse kinematics' solutions
/// ([`inverse_kinematics`], `phi` of the start where the pose leaves it free), each angle the
/// representative nearest the start's; with `elbow` only that solution, else each is planned and
/// the certified plan of least effort kept. Unreachable poses are [`InputError::Unreachable`].
pub fn plan_to_pose(
    planner: &dyn Planner,
    problem: &PlanningProblem,
    pose: (f64, f64, f64),
    elbow: Option<Elbow>,
) -> Result<(Elbow, Planned), Error> {
    let solutions = inverse_kinematics(&problem.robot, pose, problem.start.phi).map_err(InputError::from)?;
    let near = |x: f64, reference: f64| x + std::f64::consts::TAU * ((reference - x) / std::f64::consts::TAU).round();
    let mut best: Option<(Elbow, Planned)> = None;
    let mut first_error = None;
    for (e, q) in solutions.into_iter().filter(|(e, _)| elbow.is_none_or(|want| want == *e)) {
        let s = problem.start;
        let goal = Configuration::new(near(q.phi, s.phi), near(q.theta1, s.theta1), near(q.theta2, s.theta2));
        match planner.plan(&PlanningProblem { goal, ..*problem }) {
            Ok(planned) if planned.plan.verification.certified => {
                if best.as_ref().is_none_or(|(_, b)| planned.plan.effort < b.plan.effort) {
                    best = Some((e, planned));
                }
            }
            Ok(planned) => first_error = first_error.or(planned.plan.certified().err()),
            Err(err) => first_error = first_error.or(Some(err)),
        }
    }
    match (best, first_error) {
        (Some(best), _) => Ok(best),
        (None, Some(err)) => Err(err),
        (None, None) => Err(InputError::InvalidParameter {
            name: "elbow".into(),
            value: f64::NAN,
            expected: "an elbow that reaches the pose (at a = b = 0 the two coincide: leave it unset)",
        }
        .into()),
    }
}

/// One branch of the inverse kinematics of a pose goal, planned or not.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseBranch {
    /// The branch and its residual ([`IkBranch`]).
    #[serde(flatten)]
    pub solution: IkBranch,
    /// The certified plan's effort \[rad^2/s\], when the branch reached the pose and was planned.
    pub effort: Option<f64>,
    /// Why the branch has no certified plan (it missed the pose, it is not the branch asked
    /// for, or the planner's error).
    pub error: Option<String>,
    /// This branch's plan is the one reported (the certified plan of least effort).
    pub kept: bool,
}

/// A pose goal: the pose and every inverse-kinematics branch tried, in the order tried.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseGoal {
    /// `(x, y, psi)` \[m, m, rad\], the system's centre of mass at the origin.
    pub pose: [f64; 3],
    /// Every branch tried, in the order tried.
    pub branches: Vec<PoseBranch>,
}

impl PoseGoal {
    /// The branch whose plan is kept, if any.
    pub fn kept(&self) -> Option<&PoseBranch> {
        self.branches.iter().find(|b| b.kept)
    }

    /// How many branches reached the pose.
    pub fn reached(&self) -> usize {
        self.branches.iter().filter(|b| b.solution.reached).count()
    }

    /// One line for a plan's notes: how many branches were tried and reached the pose, and the
    /// one kept.
    pub fn note(&self) -> String {
        let kept = self.kept().map_or("none".to_string(), |b| format!("`{}`", b.solution.branch));
        format!(
            "pose goal: {} inverse-kinematics branch(es) tried, {} reached the pose; kept {kept}, the certified \
             plan of least effort",
            self.branches.len(),
            self.reached()
        )
    }
}

/// Plans `request` for `arm` with `method` to the tool pose `(x, y, psi)` (inertial frame, the
/// system's centre of mass at the origin; m, m, rad) instead of `request.problem.goal`: every
/// branch of [`Arm::inverse_kinematics`] from the start that reaches the pose (only the one
/// named `branch`, when given, e.g. `up` or `down` of a 2-link arm) is planned with the rest of
/// the request, and the certified plan of least effort is kept (ties: the first tried).
///
/// Returns the pose goal with every branch's outcome and the kept plan (its problem's goal is
/// the kept branch's configuration). Errors:
/// - bad input: an unreachable pose ([`InputError::Unreachable`]), a `branch` that no reaching
///   branch carries or no branch that reaches the pose ([`InputError::PoseBranch`]), or the
///   request's own (returned at once, as [`plan_arm`]'s);
/// - no certified plan on any reaching branch: the first branch's error, or the reason its plan
///   was not certified.
pub fn plan_arm_to_pose(
    arm: &Arm,
    method: Method,
    request: &ArmRequest,
    pose: (f64, f64, f64),
    branch: Option<&str>,
) -> Result<(PoseGoal, ArmPlanned), Error> {
    let solutions = arm.inverse_kinematics(pose, &request.problem.start).map_err(InputError::from)?;
    let mut goal = PoseGoal { pose: [pose.0, pose.1, pose.2], branches: Vec::with_capacity(solutions.len()) };
    let mut best: Option<(usize, ArmPlanned)> = None;
    let mut first_error = None;
    for solution in solutions {
        let mut tried = PoseBranch { solution, effort: None, error: None, kept: false };
        if branch.is_some_and(|name| name != tried.solution.branch) {
            tried.error = Some("not the branch asked for".into());
        } else if !tried.solution.reached {
            tried.error =
                Some(format!("the inverse kinematics stopped {:.2e} m from the pose", tried.solution.residual));
        } else if let Err(outside) = within_ranges(arm, &mut tried.solution.q, &request.problem.start) {
            // Another branch may be inside every range: this one is reported, not fatal.
            tried.error = Some(outside.to_string());
            first_error = first_error.or(Some(outside.into()));
        } else {
            let problem = ChainProblem { goal: tried.solution.q.clone(), ..request.problem.clone() };
            match plan_arm(arm, method, &ArmRequest { problem, ..request.clone() }) {
                Ok(planned) => match planned.certified() {
                    Ok(()) => {
                        tried.effort = Some(planned.effort());
                        if best.as_ref().is_none_or(|(_, b)| planned.effort() < b.effort()) {
                            best = Some((goal.branches.len(), planned));
                        }
                    }
                    Err(e) => {
                        tried.error = Some(e.to_string());
                        first_error = first_error.or(Some(e));
                    }
                },
                Err(e) if e.is_bad_input() => return Err(e),
                Err(e) => {
                    tried.error = Some(e.to_string());
                    first_error = first_error.or(Some(e));
                }
            }
        }
        goal.branches.push(tried);
    }
    match (best, first_error) {
        (Some((k, planned)), _) => {
            goal.branches[k].kept = true;
            Ok((goal, planned))
        }
        (None, Some(e)) => Err(e),
        (None, None) => {
            let reaching: Vec<String> =
                goal.branches.iter().filter(|b| b.solution.reached).map(|b| b.solution.branch.clone()).collect();
            let residual = goal.branches.iter().map(|b| b.solution.residual).fold(f64::INFINITY, f64::min);
            Err(InputError::PoseBranch {
                branch: branch.filter(|_| !reaching.is_empty()).map(str::to_string),
                reaching,
                tried: goal.branches.len(),
                residual,
            }
            .into())
        }
    }
}

/// Turns each angle of `q` (`phi, theta_1..n`) that has a range (the base's, a joint's) by
/// whole turns into it, the turn nearest `start`'s angle (a limited angle is literal: the
/// planner does not wrap it); the first angle of which no turn is inside its range is
/// [`InputError::InvalidText`] naming it, the range and the pose's branch.
fn within_ranges(arm: &Arm, q: &mut [f64], start: &[f64]) -> Result<(), InputError> {
    use std::f64::consts::TAU;
    for (i, x) in q.iter_mut().enumerate() {
        let range = if i == 0 { arm.limits.base } else { arm.limits.joint(i - 1).position };
        let Some([lo, hi]) = range else { continue };
        let (first, last) = (((lo - *x) / TAU).ceil(), ((hi - *x) / TAU).floor());
        if first > last {
            let name = if i == 0 { "phi".to_string() } else { format!("theta{i}") };
            return Err(InputError::InvalidText {
                name: "--to-ee branch".into(),
                text: format!(
                    "{name} = {:.6} deg, no turn of it inside [{:.6}, {:.6}] deg",
                    x.to_degrees(),
                    lo.to_degrees(),
                    hi.to_degrees()
                ),
                expected: "an inverse-kinematics solution inside every declared range (another branch, or a pose \
                           inside the robot's ranges)",
            });
        }
        *x += ((start[i] - *x) / TAU).round().clamp(first, last) * TAU;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::arm::Arm;

    fn three_link() -> Arm {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots/three_link.toml");
        Arm::load(&path).expect("the example")
    }

    /// At rest at the example's start (the goal is replaced by each branch's).
    fn request() -> ArmRequest {
        let start: Vec<f64> = [0.0_f64, 60.0, -30.0, -30.0].iter().map(|x| x.to_radians()).collect();
        ArmRequest::new(ChainProblem::rest_to_rest(start.clone(), start, 10.0))
    }

    /// The tool pose of the arm at (30, 120, 40, -60) deg: reachable by construction.
    fn reachable_pose(arm: &Arm) -> (f64, f64, f64) {
        let end: Vec<f64> = [30.0_f64, 120.0, 40.0, -60.0].iter().map(|x| x.to_radians()).collect();
        let [x, y, psi] = arm.task_point(&end, &[0.0; 4]).end_effector;
        (x, y, psi)
    }

    /// The kept plan ends at the pose (by the arm's own forward kinematics), it is the least
    /// effort of the certified branches, and every reaching branch was planned.
    #[test]
    fn the_kept_branch_ends_on_the_pose_with_the_least_effort() {
        let arm = three_link();
        let request = request();
        let pose = reachable_pose(&arm);
        let (goal, planned) = plan_arm_to_pose(&arm, Method::Optimal, &request, pose, None).expect("plans");
        let kept = goal.kept().expect("a kept branch");
        assert!(planned.certified().is_ok());
        // The verified motion's end (the system integrated with the plan's controls).
        let [xe, ye, _] = arm.task_point(&planned.verification().reached, &[0.0; 4]).end_effector;
        let miss = (xe - pose.0).hypot(ye - pose.1);
        // The certificate's tolerance (1e-9 rad) times the reach (about 2 m) bounds the miss.
        assert!(miss < 1e-8, "the tool ends {miss} m from the pose");
        let efforts: Vec<f64> = goal.branches.iter().filter_map(|b| b.effort).collect();
        assert!(efforts.iter().all(|&e| planned.effort() <= e));
        assert_eq!(kept.effort, Some(planned.effort()));
        assert!(goal.branches.iter().filter(|b| b.solution.reached).all(|b| b.effort.is_some() || b.error.is_some()));
        assert!(goal.note().contains(&kept.solution.branch));
    }

    /// A branch name that no reaching branch carries is bad input naming those that do.
    #[test]
    fn an_unknown_branch_is_bad_input_naming_the_reaching_ones() {
        let arm = three_link();
        let request = request();
        let e = plan_arm_to_pose(&arm, Method::Optimal, &request, reachable_pose(&arm), Some("sideways"))
            .expect_err("no such branch");
        assert!(e.is_bad_input());
        let text = e.to_string();
        assert!(text.contains("sideways") && text.contains("those that do"), "{text}");
    }

    /// A limited angle of a branch is turned into its range by whole turns, the turn nearest
    /// the start; an angle no turn of which is inside is named with the range.
    #[test]
    fn a_branch_angle_is_turned_into_its_range_or_named() {
        use crate::model::arm::{JointLimits, Limits};
        let deg = |x: f64| x.to_radians();
        let range = |lo: f64, hi: f64| JointLimits { position: Some([deg(lo), deg(hi)]), ..JointLimits::default() };
        let limited = |lo, hi| {
            let joints = vec![JointLimits::default(), range(lo, hi), JointLimits::default()];
            three_link().with_limits(Limits { joints, base: Some([deg(-400.0), deg(400.0)]) }).expect("limits")
        };
        let start = [deg(350.0), 0.0, 0.0, 0.0];
        let mut q = [deg(-20.0), 0.3, deg(-112.7), 0.1];
        within_ranges(&limited(200.0, 300.0), &mut q, &start).expect("a turn inside");
        // theta2 one turn up into its range; phi the turn nearest the start's 350 deg (340, not -20).
        assert!((q[2] - deg(247.3)).abs() < 1e-12 && (q[0] - deg(340.0)).abs() < 1e-12, "{q:?}");
        assert!(
            q[1].to_bits() == 0.3f64.to_bits() && q[3].to_bits() == 0.1f64.to_bits(),
            "angles without a range untouched"
        );
        let e = within_ranges(&limited(-10.0, 180.0), &mut [0.0, 0.0, deg(-112.7), 0.0], &start).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("theta2 = -112.7") && text.contains("no turn of it inside [-10"), "{text}");
    }

    /// With a range that one inverse-kinematics branch keeps and another leaves, the pose is
    /// planned by the branch inside (before, the branch outside was fatal bad input, exit 2).
    #[test]
    fn a_branch_outside_a_range_is_reported_and_another_planned() {
        use crate::model::arm::{JointLimits, Limits};
        let arm = three_link();
        let request = request();
        let pose = reachable_pose(&arm);
        let branches = arm.inverse_kinematics(pose, &request.problem.start).expect("reachable");
        let reaching: Vec<f64> = branches.iter().filter(|b| b.reached).map(|b| b.q[2]).collect();
        // A range from the start's theta2 to the first branch's that leaves some other branch's out.
        let (theta, from) = (reaching[0], request.problem.start[2]);
        let range = [theta.min(from) - 0.1, theta.max(from) + 0.1];
        assert!(reaching.iter().any(|t| *t < range[0] || *t > range[1]), "a branch outside: {reaching:?} {range:?}");
        let joints = vec![
            JointLimits::default(),
            JointLimits { position: Some(range), ..JointLimits::default() },
            JointLimits::default(),
        ];
        let limited = arm.with_limits(Limits { joints, base: None }).expect("limits");
        let (goal, planned) = plan_arm_to_pose(&limited, Method::Optimal, &request, pose, None).expect("plans");
        assert!(planned.certified().is_ok());
        let kept = goal.kept().expect("a kept branch");
        assert!((kept.solution.q[2] - theta).abs() < 1e-12, "the branch inside kept");
        let outside = goal.branches.iter().filter_map(|b| b.error.as_deref()).filter(|e| e.contains("no turn"));
        assert!(outside.count() >= 1, "{:?}", goal.branches.iter().map(|b| &b.error).collect::<Vec<_>>());
    }

    /// A pose beyond the reach is bad input (unreachable), before any planning.
    #[test]
    fn a_pose_out_of_reach_is_bad_input() {
        let arm = three_link();
        let e = plan_arm_to_pose(&arm, Method::Optimal, &request(), (50.0, 0.0, 0.0), None).expect_err("far");
        assert!(e.is_bad_input(), "{e}");
    }
}
