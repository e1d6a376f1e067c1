//! `freefloat reproduce`: the paper's results of Sec. 5 on the built-in defaults.

use std::process::ExitCode;

use freefloat::{Mount, NfaOptions, NormalFormPlanner, Planner, PlanningProblem, RobotParams, Transform};

use super::args::ReproduceArgs;

/// The paper's five NFA cases (Figs. 4-8): mounting point and transformation.
pub const NFA_CASES: [(&str, f64, Transform); 5] = [
    ("fig04", 0.0, Transform::Eq11),
    ("fig05", 0.0, Transform::Eq12),
    ("fig06", 0.1, Transform::Eq14),
    ("fig07", 0.2, Transform::Eq14),
    ("fig08", 0.3, Transform::Eq14),
];

/// Runs `reproduce`: for now the table of the paper's five NFA cases.
pub fn run(_args: &ReproduceArgs) -> anyhow::Result<ExitCode> {
    println!("The paper's NFA cases: q0 = (45, 120, 80) deg -> qd = (0, 180, 140) deg, T = 10 s, 1001 samples");
    println!(
        "{:<6} {:>9} {:>6} {:>12} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "figure", "a = b [m]", "eq", "final err", "max|u1|", "max|u2|", "plan [ms]", "verify[ms]", "certified"
    );
    let mut all = true;
    for (fig, a, transform) in NFA_CASES {
        let robot = RobotParams::src().with_mount(Mount::new(a, a)?)?;
        let options = NfaOptions { transform: Some(transform), ..Default::default() };
        let plan = NormalFormPlanner::new(options).plan(&PlanningProblem::paper(robot))?;
        let v = &plan.verification;
        all &= v.certified;
        println!(
            "{fig:<6} {a:>9.1} {:>6} {:>12.3e} {:>10.6} {:>10.6} {:>10.3} {:>10.3} {:>10}",
            transform.name(),
            v.final_error,
            plan.max_abs_u[0],
            plan.max_abs_u[1],
            plan.seconds.plan * 1e3,
            plan.seconds.verify * 1e3,
            if v.certified { "yes" } else { "NO" }
        );
    }
    Ok(if all { ExitCode::SUCCESS } else { ExitCode::from(3) })
}
