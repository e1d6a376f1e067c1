//! `freefloat track`: a plan tracked in closed loop on a robot that is not the model, once per
//! controller side by side, or as a Monte Carlo run (docs/spec.md §3), for every robot the other
//! commands read (the preset, a TOML robot file with the 2-link keys or `[[link]]`, a URDF).

use std::io::IsTerminal;
use std::process::ExitCode;

use anyhow::Context;
use freefloat::Method;
use freefloat::analysis::shards::Shard;
use freefloat::model::arm::Arm;
use freefloat::plan::clearance::ClearanceReport;
use freefloat::planners::chain::ChainProblem;
use freefloat::report::arm_figure::least_clearance_mark;
use freefloat::report::arm_limit_bounds;
use freefloat::report::io::write_atomic;
use freefloat::report::numbers::{error_number, number, scientific};
use freefloat::report::plot::{Bound, Panel, PictureFormat, PlanFigure, Series, plan_picture};
use freefloat::track::ArmMotion;
use freefloat::track::trials_file::{self, RunSummary};
use freefloat::track::{
    Controller, Disturbances, Gains, History, IdentifyOptions, MonteCarloOptions, Perturbation, ReplanOptions, Summary,
    TrackOptions, Tracked, monte_carlo, summarise, track,
};

use super::args::{ControllerArg, DomainFormat, RobotArgs, TrackArgs, TrackCommand, TrackMergeArgs};
use super::geometry::GeometryArgs;

fn controller(c: ControllerArg) -> Controller {
    match c {
        ControllerArg::Open => Controller::Open,
        ControllerArg::Ct => Controller::Ct,
        ControllerArg::Replan => Controller::Replan,
        ControllerArg::Adaptive => Controller::Adaptive,
    }
}

/// The nominal arm of the flags: any robot the other commands read, `--mount` applied (a 2-link
/// robot file or the preset through the 2-link reader, its checks and messages), with its
/// shapes and the geometry flags (`--obstacle`, `--clearance`, `--no-collide`) as `plan` reads
/// them.
fn model(args: &RobotArgs, geometry: &GeometryArgs) -> anyhow::Result<Arm> {
    match super::any_robot(args)? {
        super::Robot::TwoLink => {
            let (shapes, _) = super::geometry::two_link(args, geometry)?;
            Ok(Arm::from_params(&super::robot(args)?).with_geometry(shapes)?)
        }
        super::Robot::Arm(arm) => Ok(super::geometry::arm_with_flags(&arm, args, geometry)?.0),
    }
}

/// The validated options of the flags for an arm of `n` joints (exit 2 on any bad value).
fn options(args: &TrackArgs, n: usize) -> anyhow::Result<TrackOptions> {
    let torque_bias = match &args.torque_bias {
        None => Vec::new(),
        Some(text) => {
            let bias = super::parse_numbers("--torque-bias", text)?;
            if bias.len() != n {
                anyhow::bail!(
                    "--torque-bias takes {n} comma-separated torques TAU1,..,TAU{n} in N m for this {n}-link arm, got {}",
                    bias.len()
                );
            }
            bias
        }
    };
    let options = TrackOptions {
        controller: Controller::Adaptive,
        rate: args.rate,
        substeps: 1,
        gains: (args.kp.is_some() || args.kd.is_some()).then(|| {
            let default = Gains::for_rate(args.rate);
            Gains { kp: args.kp.unwrap_or(default.kp), kd: args.kd.unwrap_or(default.kd) }
        }),
        replan: ReplanOptions {
            rate: args.replan_rate,
            final_window: args.final_window,
            margin: args.margin.unwrap_or(ReplanOptions::default().margin),
            limit_margin: args.limit_margin.unwrap_or(ReplanOptions::default().limit_margin),
            ..Default::default()
        },
        identify: IdentifyOptions { forgetting_time: args.forgetting, ..Default::default() },
        disturbances: Disturbances {
            torque_noise: args.torque_noise,
            torque_bias,
            torque_limit: args.torque_limit.unwrap_or(f64::INFINITY),
            q_noise: args.noise_q,
            dq_noise: args.noise_dq,
        },
        record: args.out.is_some() || args.plot.is_some(),
        hold_correction: !args.no_hold_correction,
    };
    options.validate()?;
    Ok(options)
}

/// The checked `--out FILE.csv` of a Monte Carlo run or a merge: the extension (any case) and
/// the directory.
fn trials_out(path: &std::path::Path) -> anyhow::Result<()> {
    if !path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("csv")) {
        anyhow::bail!("--out {}: the trials file's name must end in .csv", path.display());
    }
    Ok(freefloat::report::io::check_writable(path)?)
}

/// The shard of `--shard`, checked against the other flags before any work: it needs
/// `--trials` and `--out`.
fn shard(args: &TrackArgs) -> anyhow::Result<Shard> {
    let Some(text) = &args.shard else { return Ok(Shard::ALL) };
    let shard = Shard::parse(text)?;
    if args.trials.is_none() {
        anyhow::bail!(
            "--shard {} needs --trials N: it splits the trials of a Monte Carlo run",
            super::config::quote(text)
        );
    }
    if args.out.is_none() {
        anyhow::bail!(
            "--shard {} needs --out FILE.csv: the shard's trials go to a file for `track merge`",
            super::config::quote(text)
        );
    }
    Ok(shard)
}

/// Runs `freefloat track` or `freefloat track merge`.
pub fn run(args: &TrackArgs) -> anyhow::Result<ExitCode> {
    if let Some(TrackCommand::Merge(m)) = &args.command {
        return merge(m);
    }
    let shard = shard(args)?;
    super::config::distinct_outputs(&[("--out", args.out.as_deref()), ("--plot", args.plot.as_deref())])?;
    if let (Some(path), Some(_)) = (&args.out, args.trials) {
        trials_out(path)?;
    }
    let robot = model(&args.robot, &args.geometry)?;
    let n = robot.joints();
    let start = super::config::arm_angles("--from", &args.ends.from, n + 1)?;
    let goal = super::config::arm_angles("--to", &args.ends.to, n + 1)?;
    let problem = ChainProblem::rest_to_rest(start, goal, super::config::time(args.ends.time)?);
    problem.validate(&robot)?;
    let options = options(args, n)?;
    ReplanOptions::check_margin(&robot, args.margin)?;
    ReplanOptions::check_limit_margin(&robot, args.limit_margin)?;
    let perturbation = Perturbation { relative: args.perturb, mount: args.perturb_mount };
    perturbation.validate()?;
    let truth = args.true_robot.as_deref().map(Arm::load).transpose()?;
    if let (Some(t), Some(path)) = (&truth, &args.true_robot)
        && t.joints() != n
    {
        anyhow::bail!(
            "--true-robot {}: an arm of {} link(s), the model has {n}: the true robot must have the model's links",
            path.display(),
            t.joints()
        );
    }
    let picture = args.plot.as_deref().map(PictureFormat::from_path).transpose()?;
    super::check_outputs(&[args.out.as_ref(), args.plot.as_ref()])?;
    let controllers: Vec<Controller> = args.controller.iter().map(|&c| controller(c)).collect();
    // The budgets (ticks, re-plans, recorded memory) before planning, from the request alone.
    for &controller in &controllers {
        TrackOptions { controller, record: options.record && args.trials.is_none(), ..options.clone() }
            .check_budget(problem.horizon)?;
    }
    // The plan keeps the margins beyond the clearance and inside the limits; the runs are
    // judged at the clearance and the limits.
    let mut options = options;
    let planned = options.replan.first_plan(&robot, &problem)?;
    planned.certified()?;
    let given = args.limit_margin.unwrap_or(ReplanOptions::default().limit_margin);
    if options.replan.limit_margin < given {
        super::note(&format!(
            "note: T = {} s leaves the plan {:.2} % of every limit as headroom, not the --limit-margin {}: a longer --time leaves more\n",
            number(problem.horizon),
            100.0 * options.replan.limit_margin,
            number(given)
        ));
    }
    let plan = &planned.plan;
    if let Some(trials) = args.trials {
        let mc = MonteCarloOptions {
            trials,
            seed: args.seed,
            truth,
            perturbation,
            controllers,
            shard,
            ..Default::default()
        };
        return monte(args, &robot, &problem, plan, &options, &mc);
    }
    let truth = match truth {
        Some(t) => t,
        None => perturbation.apply(&robot, args.seed)?,
    };
    let runs = controllers
        .iter()
        .map(|&controller| {
            let o = TrackOptions { controller, ..options.clone() };
            track(&robot, &problem, plan, &truth, &o, args.seed)
        })
        .collect::<Result<Vec<Tracked>, _>>()?;
    // The files first: stdout never shows a run whose files then fail.
    if let Some(path) = &args.out {
        write_atomic(path, &history_csv(&runs[0])?)?;
    }
    if let (Some(path), Some(format)) = (&args.plot, picture) {
        write_atomic(path, &plan_picture(&figure(&runs, &robot, options.disturbances.torque_limit), format, path)?)?;
    }
    match args.format {
        DomainFormat::Json => super::emit(&format!("{}\n", serde_json::to_string_pretty(&runs)?))?,
        DomainFormat::Table => super::emit(&table(&runs, &truth, &robot))?,
    }
    Ok(ExitCode::SUCCESS)
}

fn monte(
    args: &TrackArgs,
    model: &Arm,
    problem: &ChainProblem,
    plan: &dyn ArmMotion,
    options: &TrackOptions,
    mc: &MonteCarloOptions,
) -> anyhow::Result<ExitCode> {
    let count = mc.shard.indices(mc.trials).count();
    let bar = if std::io::stderr().is_terminal() && !super::output::quiet() {
        indicatif::ProgressBar::new(count as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} trials, {elapsed} elapsed, eta {eta}")
    {
        bar.set_style(style);
    }
    let clock = std::time::Instant::now();
    let (trials, summaries) = monte_carlo(model, problem, plan, options, mc, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let seconds = clock.elapsed().as_secs_f64();
    if let Some(path) = &args.out {
        let run = trials_file::run_description(model, problem, options, mc, Method::Optimal.name());
        write_atomic(path, &trials_file::write(&run, mc.shard, &trials)?)?;
    }
    let runs = trials.len().max(1) as f64;
    super::note(&format!(
        "{} runs in {seconds:.1} s on {} threads ({:.3} s of a thread per run)\n",
        trials.len(),
        rayon::current_num_threads(),
        seconds * rayon::current_num_threads() as f64 / runs
    ));
    // Nothing drawn per trial: every trial is the same run (the table would show N copies).
    let random = [args.perturb, args.perturb_mount, args.torque_noise, args.noise_q, args.noise_dq];
    if mc.trials > 1 && random.iter().all(|v| *v == 0.0) {
        super::note(&format!(
            "note: no --perturb, --perturb-mount, --torque-noise, --noise-q or --noise-dq: nothing is drawn per \
             trial, so the {} trials are one run repeated\n",
            mc.trials
        ));
    }
    let scope = if mc.shard == Shard::ALL {
        format!("{} trials", mc.trials)
    } else {
        format!("{count} of {} trials (shard {}/{})", mc.trials, mc.shard.k, mc.shard.n)
    };
    print_summaries(args.format, &scope, mc.seed, mc.success_tolerance, &summaries)
}

/// The success-rate table (or JSON) of a Monte Carlo run or a merge, deterministic: the same
/// trials print the same bytes.
fn print_summaries(
    format: DomainFormat,
    scope: &str,
    seed: u64,
    tolerance: f64,
    summaries: &[Summary],
) -> anyhow::Result<ExitCode> {
    if format == DomainFormat::Json {
        super::emit(&format!("{}\n", serde_json::to_string_pretty(summaries)?))?;
        return Ok(ExitCode::SUCCESS);
    }
    let mut out = format!("{scope} (seed {seed}), success = final error <= {} rad\n", number(tolerance));
    out += "controller  success        median     p95        max        replan failures\n";
    for s in summaries {
        out += &format!(
            "{:<10}  {:>5.1} % {:>5}  {:<9}  {:<9}  {:<9}  {:>15}\n",
            s.controller.name(),
            100.0 * s.success_rate,
            s.successes,
            quantile(s, s.median_error),
            quantile(s, s.p95_error),
            quantile(s, s.max_error),
            s.replan_failures,
        );
    }
    // Only arms with declared limits can break them: the table of others is as before.
    for s in summaries.iter().filter(|s| s.limit_failures > 0) {
        out += &format!(
            "{}: {} of {} trials failed on a declared position, base or velocity limit\n",
            s.controller.name(),
            s.limit_failures,
            s.trials
        );
    }
    // Only a model with shapes has a clearance: the table of others is as before.
    for s in summaries {
        if let Some(min) = s.min_clearance {
            out += &format!(
                "{}: least clearance {} m; {} of {} trials failed on the clearance (collision)\n",
                s.controller.name(),
                number(min),
                s.collision_failures,
                s.trials
            );
        }
    }
    super::emit(&out)?;
    Ok(ExitCode::SUCCESS)
}

/// `freefloat track merge`: checks the shards' files, writes the merged file and prints the
/// whole run's success rates, computed from the rows as the unsharded run computes them.
fn merge(args: &TrackMergeArgs) -> anyhow::Result<ExitCode> {
    if let Some(path) = &args.out {
        trials_out(path)?;
        let inputs = super::sweep::shard_inputs(&args.files);
        super::config::outputs_apart_from_inputs(&[("--out", Some(path.as_path()))], &inputs)?;
    }
    let files = super::sweep::read_shard_files(&args.files, trials_file::read)?;
    let (merged, run) = trials_file::merge_files(files)?;
    let rows: Vec<_> = merged.rows.iter().map(freefloat::track::Trial::from).collect();
    if let Some(path) = &args.out {
        write_atomic(path, &trials_file::write(&merged.run, merged.shard, &rows)?)?;
    }
    let RunSummary { trials, seed, controllers, success_tolerance } = run;
    let summaries = summarise(&controllers, &rows, success_tolerance);
    super::note(&format!("merged {} files, {} rows\n", args.files.len(), merged.rows.len()));
    print_summaries(args.format, &format!("{trials} trials"), seed, success_tolerance, &summaries)
}

/// A quantile of a summary: the number, `-` without trials, `failed` when it falls on a
/// failed (diverged) trial.
fn quantile(s: &Summary, q: Option<f64>) -> String {
    match q {
        Some(e) => scientific(e, 2),
        None if s.trials == 0 => "-".into(),
        None => "failed".into(),
    }
}

/// The verdict of a failed run: a word and the time (`diverged at 3.21 s`).
fn failure(r: &Tracked) -> Option<String> {
    r.failure.map(|f| format!("{} at {} s", f.reason.replace('_', " "), number(f.t)))
}

/// A torque as the table prints it: 4 decimals, or 4 significant digits when large.
fn torque(x: f64) -> String {
    if x.abs() < 1e6 { format!("{x:.4}") } else { scientific(x, 3) }
}

/// An error with its sign (`+4.349e-9`, `-0.0121`).
fn signed(x: f64) -> String {
    if x >= 0.0 { format!("+{}", error_number(x)) } else { error_number(x) }
}

fn table(runs: &[Tracked], truth: &Arm, nominal: &Arm) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let n = nominal.joints();
    // The shapes and obstacles are the model's in every run: only the rest can differ.
    let bare = |a: &Arm| Arm { geometry: Default::default(), ..a.clone() };
    let same = bare(truth) == bare(nominal);
    let _ = writeln!(out, "true robot: {}", if same { "the model" } else { "differs from the model" });
    let mut row = |name: &str, f: &dyn Fn(&Tracked) -> String| {
        let _ = write!(out, "{name:<26}");
        for r in runs {
            let _ = write!(out, "{:>16}", f(r));
        }
        out.push('\n');
    };
    row("controller", &|r| r.controller.name().to_string());
    row("final error [rad]", &|r| failure(r).unwrap_or_else(|| error_number(r.final_error)));
    for i in 0..=n {
        let axis = if i == 0 { "phi".to_string() } else { format!("theta{i}") };
        row(&format!("  {axis} [rad]"), &|r| if r.failure.is_some() { "-".into() } else { signed(r.final_errors[i]) });
    }
    for k in 0..n {
        row(&format!("peak |tau{}| [N m]", k + 1), &|r| torque(r.peak_torque[k]));
    }
    if runs.iter().any(|r| r.clearance.is_some()) {
        let c = |r: &Tracked, f: &dyn Fn(&ClearanceReport) -> String| r.clearance.as_ref().map_or("-".into(), f);
        row("min clearance [m]", &|r| c(r, &|c| format!("{}{}", number(c.min), if c.holds() { "" } else { " !" })));
        // The bodies as `--no-collide` names them (`link2/obstacle1`), to fit the column.
        row("  between", &|r| c(r, &|c| format!("{}/{}", c.a, c.b).replace(' ', "")));
        row("  at [s]", &|r| c(r, &|c| number(c.time)));
    }
    row("saturated ticks", &|r| format!("{:.1} %", 100.0 * r.saturated_fraction));
    row("re-plans (failed)", &|r| format!("{} ({})", r.replans, r.replan_failures));
    row("re-plan time [s]", &|r| format!("{:.3}", r.replan_seconds));
    row("slowest re-plan [ms]", &|r| format!("{:.2}", 1e3 * r.replan_max_seconds));
    row("wall time [s]", &|r| format!("{:.3}", r.seconds));
    for r in runs {
        if let Some(id) = &r.identification {
            let _ = writeln!(out, "identified inertial parameters ({}), kg m^2:", r.controller.name());
            let _ = writeln!(out, "  {:<16}{:>12}{:>12}{:>12}", "", "nominal", "identified", "true");
            for (i, name) in id.names.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "  {name:<16}{:>12}{:>12}{:>12}",
                    number(id.nominal[i]),
                    number(id.identified[i]),
                    number(id.truth[i])
                );
            }
            let _ = writeln!(
                out,
                "  momentum-map error (G_k/F) against the truth: nominal {}, identified {}",
                error_number(id.nominal_map_error),
                error_number(id.identified_map_error)
            );
        }
    }
    out
}

/// The names of `q`'s coordinates: `phi`, `theta1`, .., `theta{n}`.
fn axes(n: usize) -> Vec<String> {
    std::iter::once("phi".to_string()).chain((1..=n).map(|k| format!("theta{k}"))).collect()
}

fn history_csv(run: &Tracked) -> anyhow::Result<Vec<u8>> {
    let h = run.history.as_ref().context("the run was not recorded")?;
    let n = run.peak_torque.len();
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["t_s".to_string()];
    header.extend(axes(n).iter().map(|a| format!("{a}_ref")));
    header.extend(axes(n));
    header.extend((1..=n).map(|k| format!("tau{k}_Nm")));
    w.write_record(&header)?;
    for i in 0..h.t.len() {
        let mut rec = vec![h.t[i]];
        rec.extend(&h.reference[i]);
        rec.extend(&h.actual[i]);
        rec.extend(&h.tau[i]);
        w.write_record(rec.iter().map(|x| format!("{x:.12e}")))?;
    }
    Ok(w.into_inner()?)
}

/// The picture of `--plot`: the reference once and every controller's run beside it (angles,
/// torques, tracking errors), each series named by its controller.
fn figure(runs: &[Tracked], model: &Arm, torque_limit: f64) -> PlanFigure {
    let recorded: Vec<(&Tracked, &History)> = runs.iter().filter_map(|r| r.history.as_ref().map(|h| (r, h))).collect();
    let Some(&(first, reference)) = recorded.first() else { return PlanFigure::default() };
    let n = first.peak_torque.len();
    let axes = axes(n);
    let series = |label: String, h: &History, f: &dyn Fn(&History, usize) -> f64| Series {
        label,
        points: (0..h.t.len()).map(|i| (h.t[i], f(h, i))).collect(),
    };
    let deg = f64::to_degrees;
    let panel = |title: &str, y: &str, series: Vec<Series>| Panel {
        title: title.into(),
        x_label: "t [s]".into(),
        y_label: y.into(),
        series,
        text: Vec::new(),
        include_zero: false,
        bounds: vec![],
        marks: vec![],
    };
    let name = |r: &Tracked, what: &str| {
        if recorded.len() == 1 { what.to_string() } else { format!("{what} ({})", r.controller.name()) }
    };
    let mut base = vec![series("reference".into(), reference, &|h, i| deg(h.reference[i][0]))];
    let mut joints: Vec<Series> =
        (1..=n).map(|k| series(format!("{} ref", axes[k]), reference, &|h, i| deg(h.reference[i][k]))).collect();
    let (mut torques, mut errors) = (Vec::new(), Vec::new());
    for &(r, h) in &recorded {
        base.push(series(name(r, "actual"), h, &|h, i| deg(h.actual[i][0])));
        for k in 0..n {
            joints.push(series(name(r, &axes[k + 1]), h, &|h, i| deg(h.actual[i][k + 1])));
            torques.push(series(name(r, &format!("tau{}", k + 1)), h, &|h, i| h.tau[i][k]));
        }
        for (k, axis) in axes.iter().enumerate() {
            errors.push(series(name(r, axis), h, &|h, i| deg(h.actual[i][k] - h.reference[i][k])));
        }
    }
    let names: Vec<&str> = recorded.iter().map(|(r, _)| r.controller.name()).collect();
    let mut panels = vec![
        panel("base angle", "phi [deg]", base),
        panel("joint angles", "[deg]", joints),
        panel("torques", "[N m]", torques),
        panel("tracking error (actual - reference)", "[deg]", errors),
    ];
    // The model's declared limits (issue 20 item 7), dashed in the colour of the first run's
    // curve: the base's range on the base panel, each joint's range on the joint panel (its
    // reference is series j), each joint's torque limit and `--torque-limit` on the torques.
    let [ranges, _, torque_limits] = arm_limit_bounds(model);
    for b in ranges {
        match b.series {
            Some(0) => panels[0].bounds.push(b),
            s => panels[1].bounds.push(Bound { series: s.map(|j| j - 1), ..b }),
        }
    }
    panels[2].bounds = torque_limits;
    if torque_limit.is_finite() {
        for value in [torque_limit, -torque_limit] {
            panels[2].bounds.push(Bound { value, label: "--torque-limit".into(), series: None });
        }
    }
    // Each run's least clearance on the true robot (issue 21 item 7).
    for &(r, _) in &recorded {
        if let Some(c) = &r.clearance {
            let mut mark = least_clearance_mark(c);
            if recorded.len() > 1 {
                // Short beside the line (the caption gives the pairs).
                mark.label = format!("{} {:.1} mm", r.controller.name(), 1e3 * c.min);
            }
            panels.iter_mut().for_each(|p| p.marks.push(mark.clone()));
        }
    }
    PlanFigure {
        title: format!("closed loop: {}", names.join(", ")),
        panels,
        caption: recorded
            .iter()
            .map(|(r, _)| {
                let peaks: Vec<String> = r.peak_torque.iter().map(|t| torque(*t)).collect();
                let clearance = r.clearance.as_ref().map_or(String::new(), |c| {
                    format!("; least clearance {:.1} mm ({} / {}, {:.2} s)", 1e3 * c.min, c.a, c.b, c.time)
                });
                format!(
                    "{}: {}; {} re-plans ({} failed); peak torque {} N m{clearance}",
                    r.controller.name(),
                    failure(r).unwrap_or_else(|| format!("final error {} rad", error_number(r.final_error))),
                    r.replans,
                    r.replan_failures,
                    peaks.join(", ")
                )
            })
            .collect(),
    }
}
