//! The table of `plan` (docs/spec.md §3): one for every robot, built from the plan's report. The
//! paper's 2-link robot's lines in their order; an arm's plan has those that apply to it (same
//! labels) and a few of its own (the velocity level's angular momentum, the minimum-effort
//! planner's stop, the end effector at `T`, the `n`-joint ECSA's iteration).

use freefloat::plan::Method;
use freefloat::report::io::PlanReport;
use freefloat::report::numbers::{error_number, number, rounded, scientific, significant};
use freefloat::report::plan_report::{EcsaAccount, OptimalAccount, TorqueAccount};

/// Angles \[rad\] in degrees rounded to 4 decimals: `(45, 120, 80)`.
pub fn degrees(q: &[f64]) -> String {
    format!("({})", q.iter().map(|x| rounded(x.to_degrees(), 4)).collect::<Vec<_>>().join(", "))
}

fn vec3(z: Option<[f64; 3]>) -> String {
    z.map(|z| format!("({}, {}, {})", rounded(z[0], 6), rounded(z[1], 6), rounded(z[2], 6)))
        .unwrap_or_else(|| "-".into())
}

/// `CERTIFIED` or `NOT CERTIFIED`.
fn verdict(ok: bool) -> &'static str {
    if ok { "CERTIFIED" } else { "NOT CERTIFIED" }
}

/// A per-joint label padded to the values' column: `max |u1|, |u2|` for two joints,
/// `max |u1|, .., |u4|` for more.
fn per_joint(symbol: &str, joints: usize) -> String {
    let label = match joints {
        1 => format!("max |{symbol}1|"),
        2 => format!("max |{symbol}1|, |{symbol}2|"),
        n => format!("max |{symbol}1|, .., |{symbol}{n}|"),
    };
    format!("{label:<25}")
}

/// The method's line: the 2-link pipeline's, or an arm's (`n`-link arm, its solver's account).
fn method(r: &PlanReport) -> String {
    match (&r.optimal, &r.ecsa) {
        (Some(OptimalAccount::Arm(o)), _) => {
            format!("optimal (minimum effort), {}-link arm, {} SQP iterations", r.joints, o.iterations)
        }
        (_, Some(EcsaAccount::Arm(e))) => format!(
            "ecsa ({} harmonic(s), window {}, {}), {}-link arm, {} iterations in {} continuation steps",
            e.harmonics,
            e.window.name(),
            e.solver.name(),
            r.joints,
            e.iteration.iterations,
            e.continuation_steps
        ),
        _ => match r.method {
            Method::Nfa => format!("NFA, transform {}", r.transform.map(|t| t.name()).unwrap_or("-")),
            Method::Ecsa => format!("ECSA, {} iterations", r.iterations.unwrap_or(0)),
            Method::Optimal => format!("optimal (minimum effort), {} SQP iterations", r.iterations.unwrap_or(0)),
        },
    }
}

/// Whether the report is of an arm's plan (the `n`-joint planners: the minimum-effort one or the
/// ECSA), not of the 2-link pipeline.
fn of_arm(r: &PlanReport) -> bool {
    matches!(r.optimal, Some(OptimalAccount::Arm(_))) || matches!(r.ecsa, Some(EcsaAccount::Arm(_)))
}

/// The human-readable report of a plan's report `r`; `base_residual` is the largest residual of
/// the base row of Eq. (6) \[N m\] (with torques).
pub fn table(r: &PlanReport, base_residual: Option<f64>) -> String {
    let arm = of_arm(r);
    let mut s = String::new();
    s += &format!("freefloat plan: {}, mount (a, b) = ({}, {}) m\n", method(r), number(r.mount[0]), number(r.mount[1]));
    s += &format!("  start q0 [deg]           {}\n", degrees(&r.start));
    s += &format!("  goal  qd [deg]           {}\n", degrees(&r.goal));
    s += &format!("  horizon                  {} s, {} samples\n", number(r.time), r.samples);
    if r.z0.is_some() {
        s += &format!("  z0, zd                   {}  ->  {}\n", vec3(r.z0), vec3(r.zd));
    }
    s += &format!("  reached q(T) [deg]       {}\n", degrees(&r.reached));
    // Each level's own verdict: a failed torque level does not mark the velocity level.
    s += &format!(
        "  verified final error     {} rad (tolerance {})  {}\n",
        error_number(r.final_error),
        number(r.tolerance),
        verdict(r.verification.certified)
    );
    if arm {
        // The velocity level's; with `--torques` the torque level's follows, each named.
        s += &format!(
            "  max |angular momentum|   {} kg m^2/s (velocity level)\n",
            scientific(r.verification.max_abs_momentum, 2)
        );
    }
    // Unknown (`None`) for an arm's plan, whose motion has no configuration between stages.
    if let Some(deviation) = r.max_path_deviation {
        s += &format!(
            "  max deviation from plan  {} rad ({} integrator steps)\n",
            error_number(deviation),
            r.verify_steps
        );
    }
    s += &format!("  effort                   {} rad^2/s (integral of |u|^2 dt)\n", number(r.effort));
    let list = |v: &[f64]| v.iter().map(|x| number(*x)).collect::<Vec<_>>().join(", ");
    s += &format!("  {}{} rad/s\n", per_joint("u", r.joints), list(&r.max_abs_u));
    match &r.optimal {
        Some(OptimalAccount::TwoLink(o)) => {
            s += &format!(
                "  optimality               KKT residual {}, holonomy residual {} rad, {} spline spans (degree {})\n",
                scientific(o.kkt_residual, 1),
                scientific(o.holonomy_residual, 1),
                o.spans,
                o.degree
            );
        }
        Some(OptimalAccount::Arm(o)) => {
            s += &format!(
                "  optimality               KKT residual {}, holonomy residual {} rad, {} spline spans\n",
                scientific(o.kkt_residual, 1),
                scientific(o.holonomy_residual, 1),
                o.spans
            );
            if !o.converged {
                s += &format!(
                    "  SQP                      stopped ({}) at KKT residual {}: a feasible plan, not proven the \
                     least effort\n",
                    o.termination.name(),
                    scientific(o.kkt_residual, 1)
                );
            }
        }
        None => {}
    }
    if let (Some(sigma), Some(p)) = (r.min_abs_sigma, r.min_abs_p) {
        s += &format!("  min |sigma|, |P|         {}, {}\n", rounded(sigma, 6), rounded(p, 6));
    }
    match &r.ecsa {
        Some(EcsaAccount::TwoLink(x)) => {
            let [u0, u1] = &r.controls_at_ends;
            s += &format!("  controls                 {} harmonic(s), window {}\n", x.harmonics, x.window.name());
            s += &format!(
                "  iteration residuals      {} rad ({})\n",
                x.residual_history.iter().map(|&r| scientific(r, 1)).collect::<Vec<_>>().join(", "),
                x.termination_name()
            );
            s += &format!(
                "  u(0), u(T)               ({}, {}), ({}, {}) rad/s{}\n",
                rounded(u0[0], 6),
                rounded(u0[1], 6),
                rounded(u1[0], 6),
                rounded(u1[1], 6),
                if x.window == freefloat::Window::None { "  (plain series: not at rest)" } else { "" }
            );
        }
        Some(EcsaAccount::Arm(e)) => {
            s += &format!(
                "  iteration                residual {} rad (tolerance {}), {}, {} x {} quadrature nodes\n",
                scientific(e.iteration.residual, 1),
                number(e.iteration.tolerance),
                e.iteration.termination,
                e.quadrature_pieces,
                e.quadrature_nodes
            );
        }
        None => {}
    }
    if let Some(b) = r.band {
        s += &format!(
            "  band steering            N = {} loops of amplitude A = {:.2} rad, eps = {:.3}, lambda in [{:.3}, {:.3}]\n",
            b.loops, b.amplitude, b.margin, b.lambda_range[0], b.lambda_range[1]
        );
    }
    let travel = r.joint_travel.iter().enumerate().map(|(k, x)| match k {
        0 => format!("phi {:.1}", x.to_degrees()),
        k => format!("theta{k} {:.1}", x.to_degrees()),
    });
    s += &format!("  joint travel [deg]       {}\n", travel.collect::<Vec<_>>().join(", "));
    if arm {
        let e = r.robot.task_point(&r.reached, &vec![0.0; r.reached.len()]).end_effector;
        s += &format!(
            "  end effector at T        ({} m, {} m, {} deg)\n",
            rounded(e[0], 6),
            rounded(e[1], 6),
            rounded(e[2].to_degrees(), 4)
        );
    }
    for b in r.to_ee.iter().flat_map(|goal| &goal.branches) {
        let outcome = match (b.effort, &b.error) {
            (Some(effort), _) => format!("effort {}{}", number(effort), if b.kept { "  (kept)" } else { "" }),
            (None, Some(e)) => e.clone(),
            (None, None) => "-".into(),
        };
        s += &format!(
            "  --to-ee branch           {}: residual {} m, {}\n",
            b.solution.branch,
            scientific(b.solution.residual, 1),
            outcome
        );
    }
    s += &torque_lines(r, base_residual);
    if let Some(c) = &r.closed_loop {
        let status = if c.certified { "CERTIFIED: executable with feedback" } else { "NOT CERTIFIED" };
        s += &format!(
            "  closed loop (ct, {} Hz)  final error {} rad (tolerance {})  {status}\n",
            number(c.rate),
            error_number(c.final_error),
            number(c.tolerance)
        );
    }
    let torques = r.seconds.torques.map(|t| format!(", torques {} ms", significant(t * 1e3, 4))).unwrap_or_default();
    let verify = r.seconds.verify.map(|t| format!(", verify {} ms", significant(t * 1e3, 4))).unwrap_or_default();
    let torque_verify = match &r.torque_certificate {
        Some(TorqueAccount::TwoLink(t)) => {
            format!(", torque certificate {} ms", significant(t.seconds.verify * 1e3, 4))
        }
        _ => String::new(),
    };
    s += &format!(
        "  time                     plan {} ms{torques}{verify}{torque_verify}\n",
        significant(r.seconds.plan * 1e3, 4)
    );
    for note in &r.notes {
        s += &format!("  note: {note}\n");
    }
    s
}

/// The torque level's lines (with torques): the peak torques, the forward-dynamics certificate,
/// the base row of Eq. (6).
fn torque_lines(r: &PlanReport, base_residual: Option<f64>) -> String {
    let (Some(tau), Some(account)) = (&r.max_abs_torque, &r.torque_certificate) else { return String::new() };
    let level = if matches!(account, TorqueAccount::Arm(_)) { " (torque level)" } else { "" };
    let (final_error, tolerance, certified, deviation, steps, momentum) = match account {
        TorqueAccount::TwoLink(t) => {
            let c = &t.certificate;
            (c.final_error, c.tolerance, c.certified, Some(c.max_path_deviation), c.stats.accepted, c.max_abs_momentum)
        }
        TorqueAccount::Arm(a) => {
            let c = &a.certificate;
            (c.final_error, c.tolerance, c.certified, c.max_path_deviation, c.stats.accepted, c.max_abs_momentum)
        }
    };
    let mut s = String::new();
    let list = tau.iter().map(|x| number(*x)).collect::<Vec<_>>().join(", ");
    s += &format!("  {}{list} N m\n", per_joint("tau", tau.len()));
    s += &format!(
        "  torque final error       {} rad (tolerance {})  {}\n",
        error_number(final_error),
        number(tolerance),
        verdict(certified)
    );
    if let Some(deviation) = deviation {
        s += &format!("  torque path deviation    {} rad ({steps} integrator steps)\n", error_number(deviation));
    }
    s += &format!("  max |angular momentum|   {} kg m^2/s{level}\n", error_number(momentum));
    if let Some(residual) = base_residual {
        s += &format!("  max |base row of (6)|    {} N m\n", error_number(residual));
    }
    s
}
