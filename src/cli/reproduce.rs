//! `freefloat reproduce`: the paper's results of Sec. 5 (Figs. 4-14) and two beyond it
//! (Figs. 15-16) on the built-in defaults, as figures (SVG and PNG), `summary.md`,
//! `summary.json` and a self-contained `report.html` with an animation of every plan.

use std::io::IsTerminal;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context;
use freefloat::Transform;
use freefloat::analysis::sweep::Shard;
use freefloat::report::html::{FigureEmbed, Page, page};
use freefloat::report::io::write_atomic;
use freefloat::report::plot::{PictureFormat, domain_pair_picture, plan_picture, sweep_picture};
use freefloat::report::{
    Case, CaseMethod, CaseOutcome, DOMAIN_FIGURES, DomainPanel, DomainRow, SummaryRow, SweepSummary, animation, cases,
    domain_panel, plan_figure, summary_markdown, sweep_options,
};
use rayon::prelude::*;
use serde::Serialize;

use super::args::ReproduceArgs;

/// One progress line per finished job on stderr, only when stderr is a terminal.
struct Progress {
    total: usize,
    done: AtomicUsize,
    on: bool,
}

impl Progress {
    fn line(&self, what: &str, seconds: f64, status: &str) {
        let k = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if self.on {
            eprintln!("[{k:>2}/{}] {what:<46} {status:<58} {:>7.1} ms", self.total, seconds * 1e3);
        }
    }
}

/// `summary.json`.
#[derive(Serialize)]
struct Summary<'a> {
    problem: Problem,
    cases: &'a [SummaryRow],
    domains: &'a [DomainRow],
    sweep: &'a SweepSummary,
    /// Wall time of the computation and the pictures (before the page and the summary) \[s\].
    seconds: f64,
}

#[derive(Serialize)]
struct Problem {
    start_deg: [f64; 3],
    goal_deg: [f64; 3],
    horizon: f64,
    samples: usize,
}

/// What a figure shows, in words, with the verdict of its certificates.
fn description(outcome: &CaseOutcome) -> String {
    let case = &outcome.case;
    let title = case.title();
    let paper = title.split(':').next().unwrap_or_default();
    let verdict = match (outcome.plan.verification.certified, outcome.torques.certificate.certified) {
        (true, true) => "Both levels certified.",
        (true, false) => "Certified at the velocity level, not at the torque level (see the caption).",
        (false, _) => "NOT certified at the velocity level (see the caption).",
    };
    match case.method {
        CaseMethod::Nfa(Transform::Global) => format!(
            "Beyond the paper: a = 1 m, b = -1 m, where the paper calls the NFA impossible (q0 and qd lie in \
             different components of the domain of Eq. (14), Fig. 14 right). The global normal form plans it with \
             band steering; the open-loop torque plan of such fast loops is ill-conditioned. {verdict}"
        ),
        CaseMethod::Nfa(_) => format!(
            "As the paper's {paper}: base orientation and joint positions; normal-form variables z; velocity \
             controls u; torques τ from the inverse dynamics (6). {verdict}"
        ),
        CaseMethod::Ecsa(_) => format!(
            "As the paper's {paper}: base orientation and joint positions; velocity controls u (constant + first \
             harmonic: not zero at the ends); torques τ. The forward dynamics of the torque certificate starts \
             from rest, the plain series does not (the sin² window, in the summary, does). {verdict}"
        ),
    }
}

/// Runs `reproduce`: exit 0 when every figure's case has a plan and the paper's NFA cases
/// (Figs. 4-8) are certified at both levels; 3 otherwise (everything is still written).
pub fn run(args: &ReproduceArgs) -> anyhow::Result<ExitCode> {
    let out = &args.out;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let clock = Instant::now();
    let all = cases();
    let sweep_opts = sweep_options();
    let progress = Progress {
        total: all.len() + 2 * DOMAIN_FIGURES.len() + 1,
        done: AtomicUsize::new(0),
        on: std::io::stderr().is_terminal(),
    };
    // Cases, domain maps and the sweep, on all of rayon's threads.
    let run_case = |case: &Case| {
        let clock = Instant::now();
        let outcome = case.run();
        let status = match &outcome {
            Ok(o) => {
                let mark = |ok: bool| if ok { "" } else { " (NOT certified)" };
                let (v, c) = (&o.plan.verification, &o.torques.certificate);
                format!(
                    "{:.1e} rad{}, torques {:.1e} rad{}",
                    v.final_error,
                    mark(v.certified),
                    c.final_error,
                    mark(c.certified)
                )
            }
            Err(_) => "no plan".into(),
        };
        let what =
            format!("{:<14} {:<4} {:<6} a, b = {}, {} m", case.id, case.method_name(), case.variant(), case.a, case.b);
        progress.line(&what, clock.elapsed().as_secs_f64(), &status);
        outcome
    };
    let run_domain = |(figure, a, b): (&str, f64, f64)| {
        let clock = Instant::now();
        let panel = domain_panel(figure, a, b);
        let status = match &panel {
            Ok(p) => format!("{} components", p.row.summary.components),
            Err(_) => "failed".into(),
        };
        progress.line(&format!("{figure:<14} domain eq14 a, b = {a}, {b} m"), clock.elapsed().as_secs_f64(), &status);
        panel
    };
    let domain_jobs: Vec<(&str, f64, f64)> =
        DOMAIN_FIGURES.iter().flat_map(|(f, mounts)| mounts.iter().map(move |&(a, b)| (*f, a, b))).collect();
    let robot = freefloat::RobotParams::src();
    let ((outcomes, panels), sweep) = rayon::join(
        || {
            rayon::join(
                || all.par_iter().map(run_case).collect::<Vec<_>>(),
                || domain_jobs.par_iter().map(|&j| run_domain(j)).collect::<Vec<_>>(),
            )
        },
        || {
            let clock = Instant::now();
            let rows = freefloat::analysis::sweep::run(&robot, &sweep_opts, Shard::ALL, &|| {});
            let seconds = clock.elapsed().as_secs_f64();
            progress.line(
                &format!("{:<14} mount sweep, {} points", "fig16", sweep_opts.points()),
                seconds,
                if rows.is_ok() { "done" } else { "failed" },
            );
            rows.map(|rows| (rows, seconds))
        },
    );
    let panels: Vec<DomainPanel> = panels.into_iter().collect::<Result<_, _>>()?;
    let (sweep_rows, sweep_seconds) = sweep?;
    let sweep_summary = SweepSummary::new(&sweep_opts, &sweep_rows, sweep_seconds);
    let rows: Vec<SummaryRow> = all.iter().zip(&outcomes).map(|(c, o)| SummaryRow::new(c, o.as_ref())).collect();

    // Pictures, each as SVG and PNG, rendered in parallel.
    enum Picture<'a> {
        Plan(&'a CaseOutcome),
        Domains(&'static str, [&'a DomainPanel; 2]),
        Sweep,
    }
    let mut pictures: Vec<(String, Picture)> = Vec::new();
    for (case, outcome) in all.iter().zip(&outcomes) {
        if let (Some(figure), Ok(o)) = (case.figure, outcome) {
            pictures.push((figure.to_string(), Picture::Plan(o)));
        }
    }
    for (k, (figure, _)) in DOMAIN_FIGURES.iter().enumerate() {
        pictures.push((figure.to_string(), Picture::Domains(figure, [&panels[2 * k], &panels[2 * k + 1]])));
    }
    pictures.push(("fig16".into(), Picture::Sweep));
    pictures.sort_by(|a, b| a.0.cmp(&b.0));
    let rendered: Vec<(String, Vec<u8>, Vec<u8>)> = pictures
        .par_iter()
        .map(|(name, picture)| -> anyhow::Result<_> {
            let draw = |format: PictureFormat| -> Result<Vec<u8>, freefloat::Error> {
                let ext = if format == PictureFormat::Svg { "svg" } else { "png" };
                let path = out.join(format!("{name}.{ext}"));
                match picture {
                    Picture::Plan(o) => plan_picture(&plan_figure(o), format, &path),
                    Picture::Domains(_, [p, q]) => {
                        domain_pair_picture([(&p.map, &p.overlay), (&q.map, &q.overlay)], format, &path)
                    }
                    Picture::Sweep => sweep_picture(&sweep_rows, format, &path),
                }
            };
            let (svg, png) = rayon::join(|| draw(PictureFormat::Svg), || draw(PictureFormat::Png));
            let (svg, png) = (svg?, png?);
            write_atomic(&out.join(format!("{name}.svg")), &svg)?;
            write_atomic(&out.join(format!("{name}.png")), &png)?;
            Ok((name.clone(), svg, png))
        })
        .collect::<anyhow::Result<_>>()?;
    let seconds = clock.elapsed().as_secs_f64();

    // The page: every figure with its description, and an animation for each plan.
    let figures: Vec<FigureEmbed> = pictures
        .iter()
        .zip(&rendered)
        .map(|((name, picture), (_, _, png))| {
            let (title, description, anim) = match picture {
                Picture::Plan(o) => (o.case.title(), description(o), Some(animation(o))),
                Picture::Domains(f, [p, q]) => (
                    format!(
                        "Fig. {}: domains of existence of feedback (14), a, b = ({}, {}) m and ({}, {}) m",
                        f.trim_start_matches("fig"),
                        p.row.summary.mount[0],
                        p.row.summary.mount[1],
                        q.row.summary.mount[0],
                        q.row.summary.mount[1]
                    ),
                    "As the paper's figure: the joint torus (θ1, θ2) cut by σ = 0 (Eq. 9) and P = 0 (Eq. 13) into \
                     components; q0's component in green, q0, qd and the Eq. (14) plan's path. At a = 1, b = -1 q0 \
                     and qd lie in different components: no Eq. (14) plan (Fig. 15 plans it with the global normal \
                     form)."
                        .to_string(),
                    None,
                ),
                Picture::Sweep => (
                    "Fig. 16 (beyond the paper): mounting-point map".to_string(),
                    "A coarse map over the mounting point (a, b): left, the share of the torus taken by q0's \
                     component of the domain of Eq. (14) (where plans from q0 may go); right, the best NFA success \
                     rate over random start/goal pairs (certified plans, best of the applicable transformations). \
                     The paper's advice, mount the arm where the domain is large, read off one picture."
                        .to_string(),
                    None,
                ),
            };
            FigureEmbed { name: name.clone(), title, description, png: Some(png.clone()), animation: anim }
        })
        .chain(all.iter().zip(&outcomes).filter(|(c, _)| c.figure.is_none()).filter_map(|(c, o)| {
            let o = o.as_ref().ok()?;
            Some(FigureEmbed {
                name: c.id.to_string(),
                title: c.title(),
                description: "Beyond the paper, no figure: the ECSA's controls times sin²(πt/T), so that the plan \
                              starts and ends at rest like the NFA's; its torques are then certified from rest \
                              (see the summary). The animation shows the plan."
                    .into(),
                png: None,
                animation: Some(animation(o)),
            })
        }))
        .collect();
    let domain_rows: Vec<DomainRow> = panels.iter().map(|p| p.row.clone()).collect();
    let html =
        page(&Page { rows: &rows, domains: &domain_rows, sweep: Some(&sweep_summary), figures: &figures, seconds })?;
    write_atomic(&out.join("report.html"), html.as_bytes())?;
    let (q0, qd, horizon) = freefloat::paper_problem();
    let deg = |q: freefloat::Configuration| q.to_array().map(f64::to_degrees);
    let summary = Summary {
        problem: Problem { start_deg: deg(q0), goal_deg: deg(qd), horizon, samples: 1001 },
        cases: &rows,
        domains: &domain_rows,
        sweep: &sweep_summary,
        seconds,
    };
    write_atomic(&out.join("summary.json"), &serde_json::to_vec_pretty(&summary)?)?;
    let md = summary_markdown(&rows, &domain_rows, Some(&sweep_summary));
    write_atomic(&out.join("summary.md"), md.as_bytes())?;
    print!("{md}");
    let files = 2 * rendered.len() + 3;
    println!("\nwrote {files} files to {} in {:.2} s", out.display(), clock.elapsed().as_secs_f64());

    let mut ok = true;
    for (case, outcome) in all.iter().zip(&outcomes) {
        match outcome {
            Err(e) if case.figure.is_some() => {
                eprintln!("{}: no plan: {e}", case.id);
                ok = false;
            }
            Ok(o)
                if case.paper_seconds().is_some()
                    && case.method_name() == "nfa"
                    && !(o.plan.verification.certified && o.torques.certificate.certified) =>
            {
                eprintln!("{}: the paper's case is not certified", case.id);
                ok = false;
            }
            _ => {}
        }
    }
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(3) })
}
