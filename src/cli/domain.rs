//! `freefloat domain`: the domain of existence of a feedback transformation on the joint torus
//! (docs/spec.md §3; Figs. 13-14), its components, and whether `q0` and `qd` are connected.

use std::process::ExitCode;

use freefloat::analysis::domain::{DomainMap, DomainSummary};
use freefloat::planners::{Planned, PlannerOptions, planner};
use freefloat::report::io::write_atomic;
use freefloat::report::plot::{DomainOverlay, PictureFormat, domain_picture};
use freefloat::{Method, NfaOptions, PlanningProblem, Transform};
use serde::Serialize;

use super::args::{DomainArgs, DomainFormat, TransformArg};

/// The NFA plan from q0 to qd with the mapped transformation.
#[derive(Debug, Serialize)]
struct PlanCheck {
    /// A plan exists and is certified.
    certified: bool,
    /// Its verified final error in rad, when a plan exists.
    final_error: Option<f64>,
    /// Why there is no plan.
    error: Option<String>,
}

#[derive(Debug, Serialize)]
struct Report {
    #[serde(flatten)]
    summary: DomainSummary,
    plan: PlanCheck,
    seconds: f64,
}

/// Runs `domain`.
pub fn run(args: &DomainArgs) -> anyhow::Result<ExitCode> {
    let robot = super::robot(&args.robot)?;
    let transform = match args.transform {
        TransformArg::Auto => Transform::auto(&robot),
        TransformArg::Eq11 => Transform::Eq11,
        TransformArg::Eq12 => Transform::Eq12,
        TransformArg::Eq14 => Transform::Eq14,
        TransformArg::Global => Transform::Global,
    };
    let (start, goal, time) = super::ends(&args.ends)?;
    let samples = super::config::samples(args.samples)?;
    let format = args.plot.as_deref().map(PictureFormat::from_path).transpose()?;
    super::check_outputs(&[args.plot.as_ref()])?;
    let clock = std::time::Instant::now();
    let map = DomainMap::new(&robot, transform, args.grid)?;
    let seconds = clock.elapsed().as_secs_f64();
    let summary = map.summary(&start, &goal);
    let problem = PlanningProblem::new(robot, start, goal, time)?;
    let nfa = NfaOptions { transform: Some(transform), samples, ..Default::default() };
    let (plan, path) = match planner(Method::Nfa, &PlannerOptions { nfa, ..Default::default() }).plan(&problem) {
        Ok(Planned { plan, .. }) => {
            let v = &plan.verification;
            let path = plan.trajectory.q.iter().map(|q| (q[1], q[2])).collect::<Vec<_>>();
            (PlanCheck { certified: v.certified, final_error: Some(v.final_error), error: None }, Some(path))
        }
        Err(e) => (PlanCheck { certified: false, final_error: None, error: Some(e.to_string()) }, None),
    };
    if let (Some(path_file), Some(format)) = (&args.plot, format) {
        let note = match (&plan.final_error, &plan.error) {
            (Some(err), _) => format!(
                "NFA plan q0 -> qd: {}, verified final error {} rad",
                if plan.certified { "certified" } else { "NOT certified" },
                super::plan::scientific(*err, 1)
            ),
            (None, Some(e)) => format!("no NFA plan q0 -> qd: {e}"),
            _ => String::new(),
        };
        let overlay = DomainOverlay { start: Some(start), goal: Some(goal), path, plan_note: Some(note) };
        write_atomic(path_file, &domain_picture(&map, &overlay, format, path_file)?)?;
    }
    let report = Report { summary, plan, seconds };
    match args.format {
        DomainFormat::Json => super::emit(&format!("{}\n", serde_json::to_string_pretty(&report)?))?,
        DomainFormat::Table => super::emit(&table(&report))?,
    }
    Ok(ExitCode::SUCCESS)
}

fn table(r: &Report) -> String {
    let s = &r.summary;
    let pct = |x: f64| format!("{:.2} %", 100.0 * x);
    let deg = |q: [f64; 3]| format!("({:.1}, {:.1}) deg", q[1].to_degrees(), q[2].to_degrees());
    let comp = |c: Option<usize>| c.map_or("outside the domain".to_string(), |c| format!("component {c}"));
    let mut t = String::new();
    t += &format!(
        "freefloat domain: {}, mount (a, b) = ({}, {}) m, grid {} x {} ({:.1} ms)\n",
        s.transform.name(),
        super::plan::number(s.mount[0]),
        super::plan::number(s.mount[1]),
        s.grid,
        s.grid,
        r.seconds * 1e3
    );
    t += "  The domain is where the transformation is defined; its singular curves cut the (theta1, theta2)\n";
    t += "  torus into components (numbered 0, 1, ... from the largest). A plan never leaves its component.\n";
    t += &format!("  components               {}", s.components);
    if s.slivers > 0 {
        t += &format!(
            " (+{} slivers: pieces thinner than 3 grid cells, {} of the torus, not counted; a finer --grid may resolve them)",
            s.slivers,
            super::plan::scientific(s.sliver_fraction, 1)
        );
    }
    t += "\n";
    let areas: Vec<String> = s.component_fractions.iter().map(|&f| pct(f)).collect();
    t += &format!("  component areas          {}\n", areas.join(", "));
    t += &format!("  defined                  {}\n", pct(s.defined_fraction));
    t += &format!("  q0 (theta1, theta2)      {}: {}\n", deg(s.start), comp(s.start_component));
    t += &format!("  qd (theta1, theta2)      {}: {}\n", deg(s.goal), comp(s.goal_component));
    t += &format!("  start-component fraction {}\n", pct(s.start_component_fraction));
    t += &format!("  q0, qd connected         {}\n", if s.start_goal_connected { "yes" } else { "no" });
    let plan = match (&r.plan.final_error, &r.plan.error) {
        (Some(e), _) => format!(
            "{}, verified final error {} rad",
            if r.plan.certified { "certified" } else { "NOT certified" },
            super::plan::error_number(*e)
        ),
        (None, Some(e)) => format!("none: {e}"),
        _ => "-".into(),
    };
    t += &format!("  NFA plan q0 -> qd        {plan}\n");
    t
}
