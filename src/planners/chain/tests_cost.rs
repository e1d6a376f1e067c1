//! Tests of the chain planner's energy cost and smooth ends (issue 19 item 2): the energy density
//! against the model's inertia matrix, the discretisation's derivatives, quintic ends, and each
//! cost's plan winning its own cost.

use nalgebra::{DMatrix, DVector};

use super::discrete::Targets;
use super::energy::{energy, energy_floor, reduced_inertia};
use super::tests::three_link;
use super::*;
use crate::numerics::quadrature::GaussLegendre;
use crate::planners::optimal::Cost;
use crate::planners::optimal::sqp::Discretised;

fn problem() -> ChainProblem {
    ChainProblem::rest_to_rest(vec![0.3, 0.5, -0.4, 0.8], vec![-0.2, 1.4, 0.3, -0.6], 10.0)
}

/// `integral_0^T 1/2 q'^T M q' dt` of a plan, `q' = (phi', theta')` with the plan's own base rate,
/// by a 16-point Gauss–Legendre rule on 200 pieces (independent of the planner's quadrature).
fn kinetic_energy_integral(arm: &Arm, plan: &ChainPlan) -> f64 {
    let rule = GaussLegendre::new(16);
    rule.integrate_composite(0.0, plan.horizon(), 200, |t| {
        let p = plan.at(t);
        let m = arm.inertia_matrix(&p.theta);
        let phi_rate = arm.base_rate(&p.theta, &p.rate);
        let mut q = vec![phi_rate];
        q.extend_from_slice(&p.rate);
        let q = DVector::from_vec(q);
        0.5 * q.dot(&(&m * &q))
    })
}

/// The energy density is the kinetic energy `1/2 q'^T M q'` with the base's rate from the
/// momentum constraint (Eq. 5), at random points of a 3-link and a 7-link arm; the reduced
/// matrix `R` is positive definite there and the floor below its least eigenvalue.
#[test]
fn chain_energy_density_is_the_kinetic_energy_at_zero_momentum() {
    let mut state = 0x19_u64;
    let mut uniform = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 6.0 - 3.0
    };
    for arm in [three_link(), super::tests::seven_link()] {
        let n = arm.joints();
        let floor = energy_floor(&arm);
        assert!(floor > 0.0, "a positive floor");
        for _ in 0..20 {
            let theta: Vec<f64> = (0..n).map(|_| uniform()).collect();
            let rate: Vec<f64> = (0..n).map(|_| uniform()).collect();
            let m = arm.inertia_matrix(&theta);
            let mut q = vec![arm.base_rate(&theta, &rate)];
            q.extend_from_slice(&rate);
            let q = DVector::from_vec(q);
            let expected = 0.5 * q.dot(&(&m * &q));
            let e = energy(&arm, &theta, &rate);
            assert!((e - expected).abs() <= 1e-12 * expected.abs().max(1.0), "{e} vs {expected}");
            let r = DMatrix::from_row_slice(n, n, &reduced_inertia(&arm, &theta));
            let least = r.symmetric_eigenvalues().iter().copied().fold(f64::INFINITY, f64::min);
            assert!(least > floor, "lambda_min {least} above the floor {floor}");
        }
    }
}

/// With the energy cost and smooth ends (quintic, 3 fixed coefficients per end) the
/// discretisation's gradients and Hessians equal central differences of its values and
/// gradients (3-link arm, a curved path).
#[test]
fn chain_energy_derivatives_match_differences() {
    let options = ChainOptions { cost: Cost::Energy, smooth_ends: true, ..ChainOptions::default() };
    let planner = ChainPlanner::new(three_link(), options);
    let p = problem();
    let targets = Targets {
        start: p.start[1..].to_vec(),
        initial_velocity: vec![0.1, 0.0, -0.2],
        end: p.goal[1..].to_vec(),
        phi_start: 0.3,
        phi_end: -0.2,
    };
    let tables = tables::Tables::default();
    let disc = planner.discretise(&p, targets, 4, 8, &tables).unwrap();
    let x = disc
        .project(|t, out| {
            out.copy_from_slice(&[0.5 + 0.9 * (t / 3.0).sin(), -0.4 + 0.7 * (t / 2.0).cos(), 0.8 - 0.1 * t])
        })
        .unwrap();
    let e = disc.evaluate(&x, 2);
    assert!((e.f - disc.cost(&x)).abs() <= 1e-12 * e.f.abs(), "order 0 and 2 agree on the energy");
    let h = 1e-6;
    for i in 0..x.len() {
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[i] += h;
        xm[i] -= h;
        let (ep, em) = (disc.evaluate(&xp, 1), disc.evaluate(&xm, 1));
        let gf = (ep.f - em.f) / (2.0 * h);
        assert!((gf - e.grad_f[i]).abs() <= 1e-7 * (1.0 + gf.abs()), "grad_f[{i}]: {gf} vs {}", e.grad_f[i]);
        for k in 0..x.len() {
            let hf = (ep.grad_f[k] - em.grad_f[k]) / (2.0 * h);
            assert!(
                (hf - e.hess_f_or(disc.effort_hessian())[(i, k)]).abs() <= 1e-6 * (1.0 + hf.abs()),
                "hess_f[{i}, {k}]: {hf} vs {}",
                e.hess_f_or(disc.effort_hessian())[(i, k)]
            );
        }
    }
}

/// Smooth ends at n = 3: `theta''(0) = theta''(T) = 0` (quintic splines), the start velocity
/// and the rest at T kept, certified, converged (KKT residual within the SQP's tolerance).
#[test]
fn chain_smooth_ends_start_and_end_without_acceleration() {
    let options = ChainOptions { smooth_ends: true, ..ChainOptions::default() };
    let planner = ChainPlanner::new(three_link(), options);
    let u0 = vec![0.2, -0.1, 0.3];
    let plan = planner.plan(&ChainProblem { initial_velocity: u0.clone(), ..problem() }).unwrap();
    assert!(plan.verification.certified);
    assert_eq!(plan.basis().degree(), 5);
    let (start, end) = (plan.at(0.0), plan.at(10.0));
    for (j, u) in u0.iter().enumerate() {
        assert!(start.acceleration[j].abs() <= 1e-9 && end.acceleration[j].abs() <= 1e-9, "joint {j}");
        assert!((start.rate[j] - u).abs() <= 1e-12 && end.rate[j].abs() <= 1e-12, "joint {j}");
    }
    assert!(plan.stats.kkt_residual <= 1e-6, "kkt {:e}", plan.stats.kkt_residual);
}

/// The energy cost at n = 3: the energy plan's kinetic-energy integral (measured independently of
/// the planner's quadrature) is at most the effort plan's, and the effort plan's effort at most
/// the energy plan's; both certified, the energy plan converged with its cost reported.
#[test]
fn chain_energy_and_effort_plans_each_win_their_own_cost() {
    let arm = three_link();
    let effort_plan = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem()).unwrap();
    let options = ChainOptions { cost: Cost::Energy, ..ChainOptions::default() };
    let energy_plan = ChainPlanner::new(arm.clone(), options).plan(&problem()).unwrap();
    assert!(effort_plan.verification.certified && energy_plan.verification.certified);
    let (e_of_effort, e_of_energy) =
        (kinetic_energy_integral(&arm, &effort_plan), kinetic_energy_integral(&arm, &energy_plan));
    assert!(e_of_energy <= e_of_effort * (1.0 + 1e-9), "energy: {e_of_energy} > {e_of_effort}");
    assert!(
        effort_plan.effort() <= energy_plan.effort() * (1.0 + 1e-9),
        "effort: {} > {}",
        effort_plan.effort(),
        energy_plan.effort()
    );
    assert!((energy_plan.stats.cost - e_of_energy).abs() <= 1e-6 * e_of_energy, "the reported cost is the energy");
    assert!((effort_plan.stats.cost - effort_plan.effort()).abs() <= 1e-12 * effort_plan.effort());
    assert!(energy_plan.stats.kkt_residual <= 1e-6, "kkt {:e}", energy_plan.stats.kkt_residual);
}

/// `plan_arm` passes the energy cost and smooth ends to the planner for a 3-link arm (they were
/// refused before issue 19), and refuses them for the ECSA, whose controls have neither.
#[test]
fn plan_arm_passes_cost_and_smooth_ends_through() {
    use crate::plan::Method;
    use crate::planners::arm::{ArmRequest, plan_arm};
    let arm = three_link();
    let request = ArmRequest { cost: Cost::Energy, smooth_ends: true, ..ArmRequest::new(problem()) };
    let planned = plan_arm(&arm, Method::Optimal, &request).unwrap();
    planned.certified().unwrap();
    let stats = planned.stats().unwrap();
    let crate::planners::arm::ArmPlan::Optimal(plan) = &planned.plan else { panic!("the optimal plan") };
    let measured = kinetic_energy_integral(&arm, plan);
    assert!((stats.cost - measured).abs() <= 1e-6 * measured, "the cost is the energy: {} vs {measured}", stats.cost);
    let first = &planned.trajectory[0];
    assert!(first.acceleration.iter().all(|a| a.abs() <= 1e-9), "smooth start");
    for bad in [
        ArmRequest { smooth_ends: true, ..ArmRequest::new(problem()) },
        ArmRequest { cost: Cost::Energy, ..ArmRequest::new(problem()) },
    ] {
        let err = plan_arm(&arm, Method::Ecsa, &bad).unwrap_err();
        assert!(err.is_bad_input(), "{err}");
    }
}
