//! The reproduction of the paper's results of Sec. 5 (Figs. 4-14) and six beyond it
//! (Figs. 15-20) on the built-in defaults, as figures (SVG and PNG), `summary.md`,
//! `summary.json` and a self-contained `report.html` with an animation of every plan: what
//! `freefloat reproduce` writes.

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use super::arm_figure::arm_animation;
use super::arm3::{
    ARM3_ANIMATION_TITLE, ARM3_FIGURE, ARM3_LIMITED_ANIMATION_TITLE, ARM3_LIMITED_FIGURE, Arm3Row, arm3_animation,
    arm3_figure, arm3_limited_figure, arm3_limited_markdown, arm3_markdown, plan_arm3, plan_arm3_limited,
};
use super::cases::{Case, CaseOutcome, cases, description};
use super::closed_loop::{
    CLOSED_LOOP_FIGURE, ClosedLoop, closed_loop, closed_loop_figure, closed_loop_jobs, closed_loop_markdown,
    closed_loop_text,
};
use super::figures::{animation, plan_figure};
use super::html::{FigureEmbed, Page, page};
use super::io::write_atomic;
use super::methods::{MethodRow, method_jobs, methods_markdown};
use super::plot::{
    GifOptions, PictureFormat, animation_gif, arm_animation_gif, domain_pair_picture, methods_picture, plan_picture,
    sweep_picture,
};
use super::summary::{
    DOMAIN_FIGURES, DomainPanel, DomainRow, SummaryRow, SweepSummary, domain_panel, summary_markdown, sweep_options,
};
use crate::analysis::sweep::Shard;
use crate::error::Error;
use crate::model::{Configuration, InputError, RobotParams, paper_problem};

/// `summary.json`.
#[derive(Serialize)]
struct Summary<'a> {
    problem: Problem,
    cases: &'a [SummaryRow],
    domains: &'a [DomainRow],
    sweep: &'a SweepSummary,
    /// The three methods side by side (Fig. 17).
    methods: &'a [MethodRow],
    /// The 3-link arm (Fig. 18).
    arm3: &'a Arm3Row,
    /// The 3-link arm inside a velocity limit (Fig. 19).
    arm3_limited: &'a Arm3Row,
    /// The closed loop's Monte Carlo (Fig. 20); `null` when its plans failed (see the failures).
    closed_loop: Option<&'a ClosedLoop>,
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

/// The number of jobs that [`reproduce`] reports to its progress callback (with `gif`, one
/// more per plan: the animation of each case and of the 3-link arm's two plans).
pub fn job_count(gif: bool) -> usize {
    let cases = cases().len();
    cases
        + 2 * DOMAIN_FIGURES.len()
        + 1
        + method_jobs().len()
        + 2
        + closed_loop_jobs()
        + if gif { cases + 2 } else { 0 }
}

/// What [`reproduce`] wrote and found.
#[derive(Debug, Clone, PartialEq)]
pub struct Reproduction {
    /// `summary.md`, also written to the directory.
    pub markdown: String,
    /// Number of files written.
    pub files: usize,
    /// Wall time \[s\].
    pub seconds: f64,
    /// What keeps the reproduction from being a success: a figure's case without a plan, or a
    /// paper's NFA case (Figs. 4-8) not certified at both levels. Empty on success.
    pub failures: Vec<String>,
}

/// Plans every case, maps the domains, runs the sweep, draws every figure (SVG and PNG) and writes
/// them with `summary.json`, `summary.md` and `report.html` into `out` (its parent created if
/// missing). `progress(what, seconds, status)` is called once per finished job ([`job_count`] in
/// all), from rayon's threads.
///
/// Everything is written into a fresh directory `.OUT.PID.tmpdir` beside `out`, whose files
/// then replace those of `out` by name, each by one rename ([`super::out_dir::move_into`]).
/// `out` must not exist, be empty, or hold the marker of an earlier run
/// ([`super::out_dir::MARKER`]), checked before any work ([`super::out_dir::check_out_dir`]):
/// nothing freefloat did not write is ever removed or replaced. A run killed before the moves
/// leaves `out` as it was (an interrupted one removes its temporary directory; a killed one's is
/// removed by the next); a signal during the moves waits for them to end.
///
/// With `gif`, also an animated GIF of every plan, `anim-CASE.gif` ([`animation_gif`]) and
/// `anim-arm3.gif` for the 3-link arm ([`arm_animation_gif`]); the page stays self-contained (it does not link them), `summary.md` lists them.
pub fn reproduce(
    out: &Path,
    gif: Option<&GifOptions>,
    trials: usize,
    progress: &(dyn Fn(&str, f64, &str) + Sync),
) -> Result<Reproduction, Error> {
    use super::io::{create_temporary, forget_temporary, remove_stale_temporaries, split_path, temporary_name};
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::from(InputError::Io { path, source })
    };
    super::closed_loop::check_trials(trials)?;
    super::out_dir::check_out_dir(out)?;
    let (parent, name) = split_path(out);
    std::fs::create_dir_all(&parent).map_err(io(&parent))?;
    remove_stale_temporaries(&parent, &name);
    let fresh = parent.join(temporary_name(&name, "tmpdir"));
    let result = create_temporary(&fresh, |p| std::fs::create_dir(p))
        .map_err(io(&fresh))
        .and_then(|()| reproduce_into(&fresh, gif, trials, progress));
    let result = result.and_then(|r| {
        super::io::uninterrupted(|| super::out_dir::move_into(&fresh, out)).map_err(io(out))??;
        Ok(r)
    });
    if fresh.exists() {
        let _cleanup = std::fs::remove_dir_all(&fresh);
    }
    forget_temporary(&fresh);
    result
}

fn reproduce_into(
    out: &Path,
    gif: Option<&GifOptions>,
    trials: usize,
    progress: &(dyn Fn(&str, f64, &str) + Sync),
) -> Result<Reproduction, Error> {
    let clock = Instant::now();
    let all = cases();
    let sweep_opts = sweep_options();
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
        progress(&what, clock.elapsed().as_secs_f64(), &status);
        outcome
    };
    let run_domain = |(figure, a, b): (&str, f64, f64)| {
        let clock = Instant::now();
        let panel = domain_panel(figure, a, b);
        let status = match &panel {
            Ok(p) => format!("{} components", p.row.summary.components),
            Err(_) => "failed".into(),
        };
        progress(&format!("{figure:<14} domain eq14 a, b = {a}, {b} m"), clock.elapsed().as_secs_f64(), &status);
        panel
    };
    let domain_jobs: Vec<(&str, f64, f64)> =
        DOMAIN_FIGURES.iter().flat_map(|(f, mounts)| mounts.iter().map(move |&(a, b)| (*f, a, b))).collect();
    let run_method = |&(method, mount): &(crate::plan::Method, (f64, f64))| {
        let clock = Instant::now();
        let row = MethodRow::run(method, mount);
        let status = match (row.final_error, row.torque_final_error) {
            (Some(v), Some(c)) => format!("{v:.1e} rad, torques {c:.1e} rad"),
            _ => "no plan".into(),
        };
        let what = format!("{:<14} {:<7} a, b = {}, {} m", "fig17", method.name(), mount.0, mount.1);
        progress(&what, clock.elapsed().as_secs_f64(), &status);
        row
    };
    let method_jobs = method_jobs();
    let run_arm3 = || {
        let clock = Instant::now();
        let planned = plan_arm3();
        let status = match &planned {
            Ok(p) => {
                let torque = p.torques.as_ref().map_or(f64::NAN, |t| t.certificate.final_error);
                let ok = if p.certified().is_ok() { "" } else { " (NOT certified)" };
                format!("{:.1e} rad, torques {torque:.1e} rad{ok}", p.verification().final_error)
            }
            Err(_) => "no plan".into(),
        };
        progress(&format!("{ARM3_FIGURE:<14} 3-link arm, optimal"), clock.elapsed().as_secs_f64(), &status);
        // Then the same problem inside a velocity limit at 80 % of this plan's peak (Fig. 19).
        let clock = Instant::now();
        let limited = match &planned {
            Ok(free) => plan_arm3_limited(free),
            // No peak to take 80 % of.
            Err(_) => Err(Error::from(InputError::InvalidParameter {
                name: "fig18".into(),
                value: f64::NAN,
                expected: "a plan of Fig. 18, whose peak speed sets Fig. 19's velocity limit",
            })),
        };
        let status = match &limited {
            Ok(p) => {
                let ok = if p.certified().is_ok() { "" } else { " (NOT certified)" };
                let used = p.limits.most_used().map_or(f64::NAN, |u| 100.0 * u.used);
                format!("{:.1e} rad, limit used {used:.1} %{ok}", p.verification().final_error)
            }
            Err(_) => "no plan".into(),
        };
        let what = format!("{ARM3_LIMITED_FIGURE:<14} 3-link arm, optimal, velocity limit");
        progress(&what, clock.elapsed().as_secs_f64(), &status);
        (planned, limited)
    };
    let robot = RobotParams::src();
    let (((((outcomes, panels), method_rows), (arm3, arm3_limited)), sweep), closed) = rayon::join(
        || {
            rayon::join(
                || {
                    rayon::join(
                        || {
                            rayon::join(
                                || {
                                    rayon::join(
                                        || all.par_iter().map(run_case).collect::<Vec<_>>(),
                                        || domain_jobs.par_iter().map(|&j| run_domain(j)).collect::<Vec<_>>(),
                                    )
                                },
                                || method_jobs.par_iter().map(run_method).collect::<Vec<_>>(),
                            )
                        },
                        run_arm3,
                    )
                },
                || {
                    let clock = Instant::now();
                    let rows = crate::analysis::sweep::run(
                        &crate::model::arm::Arm::from_params(&robot),
                        &sweep_opts,
                        Shard::ALL,
                        &|| {},
                    );
                    let seconds = clock.elapsed().as_secs_f64();
                    progress(
                        &format!("{:<14} mount sweep, {} points", "fig16", sweep_opts.points()),
                        seconds,
                        if rows.is_ok() { "done" } else { "failed" },
                    );
                    rows.map(|rows| (rows, seconds))
                },
            )
        },
        || closed_loop(trials, progress),
    );
    let panels: Vec<DomainPanel> = panels.into_iter().collect::<Result<_, _>>()?;
    let (sweep_rows, sweep_seconds) = sweep?;
    let sweep_summary = SweepSummary::new(&sweep_opts, &sweep_rows, sweep_seconds);
    let rows: Vec<SummaryRow> = all.iter().zip(&outcomes).map(|(c, o)| SummaryRow::new(c, o.as_ref())).collect();
    let arm3_row = Arm3Row::new(arm3.as_ref());
    let arm3_limited_row = Arm3Row::limited(arm3_limited.as_ref());

    // Pictures, each as SVG and PNG, rendered in parallel.
    enum Picture<'a> {
        Plan(&'a CaseOutcome),
        Domains(&'static str, [&'a DomainPanel; 2]),
        Sweep,
        Methods,
        Arm3(&'a crate::planners::arm::ArmPlanned),
        Arm3Limited(&'a crate::planners::arm::ArmPlanned),
        ClosedLoop(&'a ClosedLoop),
    }
    let mut pictures: Vec<(String, Picture)> = Vec::new();
    for (case, outcome) in all.iter().zip(&outcomes) {
        // The sin²-windowed ECSA has no figure in the paper: its picture is named by its case.
        if let Ok(o) = outcome {
            pictures.push((case.figure.unwrap_or(case.id).to_string(), Picture::Plan(o)));
        }
    }
    for (k, (figure, _)) in DOMAIN_FIGURES.iter().enumerate() {
        pictures.push((figure.to_string(), Picture::Domains(figure, [&panels[2 * k], &panels[2 * k + 1]])));
    }
    pictures.push(("fig16".into(), Picture::Sweep));
    pictures.push(("fig17".into(), Picture::Methods));
    if let Ok(p) = &arm3 {
        pictures.push((ARM3_FIGURE.into(), Picture::Arm3(p)));
    }
    if let Ok(p) = &arm3_limited {
        pictures.push((ARM3_LIMITED_FIGURE.into(), Picture::Arm3Limited(p)));
    }
    if let Ok(c) = &closed {
        pictures.push((CLOSED_LOOP_FIGURE.into(), Picture::ClosedLoop(c)));
    }
    // The paper's figures first, then the cases beyond them.
    pictures.sort_by_key(|(name, _)| (!name.starts_with("fig"), name.clone()));
    let rendered: Vec<(String, Vec<u8>, Vec<u8>)> = pictures
        .par_iter()
        .map(|(name, picture)| -> Result<_, Error> {
            let draw = |format: PictureFormat| -> Result<Vec<u8>, Error> {
                let ext = if format == PictureFormat::Svg { "svg" } else { "png" };
                let path = out.join(format!("{name}.{ext}"));
                match picture {
                    Picture::Plan(o) => plan_picture(&plan_figure(o), format, &path),
                    Picture::Domains(_, [p, q]) => {
                        domain_pair_picture([(&p.map, &p.overlay), (&q.map, &q.overlay)], format, &path)
                    }
                    Picture::Sweep => sweep_picture(&sweep_rows, format, &path),
                    Picture::Methods => methods_picture(&method_rows, format, &path),
                    Picture::Arm3(p) => plan_picture(&arm3_figure(p), format, &path),
                    Picture::Arm3Limited(p) => plan_picture(&arm3_limited_figure(p), format, &path),
                    Picture::ClosedLoop(c) => plan_picture(&closed_loop_figure(c), format, &path),
                }
            };
            let (svg, png) = rayon::join(|| draw(PictureFormat::Svg), || draw(PictureFormat::Png));
            let (svg, png) = (svg?, png?);
            write_atomic(&out.join(format!("{name}.svg")), &svg)?;
            write_atomic(&out.join(format!("{name}.png")), &png)?;
            Ok((name.clone(), svg, png))
        })
        .collect::<Result<_, Error>>()?;
    // The animations as GIFs, one case after the other (each draws its frames in parallel).
    let mut gifs = Vec::new();
    for (case, outcome) in all.iter().zip(&outcomes) {
        if let (Some(options), Ok(o)) = (gif, outcome) {
            let (name, clock) = (format!("anim-{}.gif", case.id), Instant::now());
            let path = out.join(&name);
            let bytes = animation_gif(&o.plan, &o.case.title(), options, &path)?;
            write_atomic(&path, &bytes)?;
            progress(
                &format!("{:<14} animation", case.id),
                clock.elapsed().as_secs_f64(),
                &format!("{} KiB", bytes.len() / 1024),
            );
            gifs.push(name);
        }
    }
    let arm_gifs =
        [("arm3", &arm3, ARM3_ANIMATION_TITLE), ("arm3-limits", &arm3_limited, ARM3_LIMITED_ANIMATION_TITLE)];
    for (id, planned, title) in arm_gifs {
        if let (Some(options), Ok(p)) = (gif, planned) {
            let (name, clock) = (format!("anim-{id}.gif"), Instant::now());
            let path = out.join(&name);
            let bytes = arm_animation_gif(p, title, options, &path)?;
            write_atomic(&path, &bytes)?;
            progress(
                &format!("{id:<14} animation"),
                clock.elapsed().as_secs_f64(),
                &format!("{} KiB", bytes.len() / 1024),
            );
            gifs.push(name);
        }
    }
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
                Picture::Methods => (
                    "Fig. 17 (beyond the paper): three methods, effort and peak joint velocity".to_string(),
                    "The paper's problem at a = b = 0, 0.1, 0.2, 0.3 m and at a = 1 m, b = -1 m by the \
                     minimum-effort planner, the NFA and the ECSA (default options): left the effort ∫|u|² dt, \
                     right the peak |u|, on logarithmic axes. The numbers, with peak torques, both certificates \
                     and times, are in the table above."
                        .to_string(),
                    None,
                ),
                Picture::Arm3(p) => (
                    arm3_figure(p).title,
                    format!(
                        "{} Left to right, top to bottom: the angles, the joint velocities with the base's rate \
                         φ' = -(G · θ')/F, the torques from the inverse dynamics (6), the arm's parameters. {}",
                        super::arm3::arm3_text().replace('`', ""),
                        if p.certified().is_ok() {
                            "Both levels certified."
                        } else {
                            "NOT certified at both levels (see the caption)."
                        }
                    ),
                    Some(arm3_animation(p)),
                ),
                Picture::Arm3Limited(p) => (
                    arm3_limited_figure(p).title,
                    format!(
                        "{} {}",
                        super::arm3::arm3_limited_text(&arm3_limited_row),
                        if p.certified().is_ok() {
                            "Both levels certified, inside every limit."
                        } else {
                            "NOT certified (see the caption)."
                        }
                    ),
                    Some(arm_animation(p, "arm3-limits", ARM3_LIMITED_ANIMATION_TITLE)),
                ),
                Picture::ClosedLoop(c) => (closed_loop_figure(c).title, closed_loop_text(c), None),
            };
            FigureEmbed { name: name.clone(), title, description, png: Some(png.clone()), animation: anim }
        })
        .collect();
    let domain_rows: Vec<DomainRow> = panels.iter().map(|p| p.row.clone()).collect();
    let html = page(&Page {
        rows: &rows,
        domains: &domain_rows,
        sweep: Some(&sweep_summary),
        methods: &method_rows,
        arm3: Some(&arm3_row),
        arm3_limited: Some(&arm3_limited_row),
        closed_loop: closed.as_ref().ok(),
        figures: &figures,
        seconds,
    })
    .map_err(|e| InputError::Io { path: out.join("report.html"), source: std::io::Error::other(e) })?;
    write_atomic(&out.join("report.html"), html.as_bytes())?;
    let (q0, qd, horizon) = paper_problem();
    let deg = |q: Configuration| q.to_array().map(f64::to_degrees);
    let summary = Summary {
        problem: Problem { start_deg: deg(q0), goal_deg: deg(qd), horizon, samples: 1001 },
        cases: &rows,
        domains: &domain_rows,
        sweep: &sweep_summary,
        methods: &method_rows,
        arm3: &arm3_row,
        arm3_limited: &arm3_limited_row,
        closed_loop: closed.as_ref().ok(),
        seconds,
    };
    let json = serde_json::to_vec_pretty(&summary)
        .map_err(|e| InputError::Io { path: out.join("summary.json"), source: std::io::Error::other(e) })?;
    write_atomic(&out.join("summary.json"), &json)?;
    let mut md = summary_markdown(&rows, &domain_rows, Some(&sweep_summary))
        + &methods_markdown(&method_rows)
        + &arm3_markdown(&arm3_row)
        + &arm3_limited_markdown(&arm3_limited_row)
        + &closed.as_ref().map_or(String::new(), closed_loop_markdown);
    if !gifs.is_empty() {
        md += &format!(
            "\n## Animations\n\nEach plan's animation as a GIF, beside this file (the report page shows them \
             itself and links no file): {}.\n",
            gifs.join(", ")
        );
    }
    write_atomic(&out.join("summary.md"), md.as_bytes())?;
    let files = 2 * rendered.len() + 3 + gifs.len();
    let mut failures = Vec::new();
    for (case, outcome) in all.iter().zip(&outcomes) {
        match outcome {
            Err(e) if case.figure.is_some() => failures.push(format!("{}: no plan: {e}", case.id)),
            Ok(o)
                if case.paper_seconds().is_some()
                    && case.method_name() == "nfa"
                    && !(o.plan.verification.certified && o.torques.certificate.certified) =>
            {
                failures.push(format!("{}: the paper's case is not certified", case.id));
            }
            _ => {}
        }
    }
    if let Err(e) = arm3.as_ref().map_err(|e| e.to_string()).and_then(|p| p.certified().map_err(|e| e.to_string())) {
        failures.push(format!("{ARM3_FIGURE}: the 3-link arm: {e}"));
    }
    let limited = arm3_limited.as_ref().map_err(|e| e.to_string());
    if let Err(e) = limited.and_then(|p| p.certified().map_err(|e| e.to_string())) {
        failures.push(format!("{ARM3_LIMITED_FIGURE}: the 3-link arm inside a velocity limit: {e}"));
    }
    if let Err(e) = &closed {
        failures.push(format!("{CLOSED_LOOP_FIGURE}: the closed loop: {e}"));
    }
    Ok(Reproduction { markdown: md, files, seconds: clock.elapsed().as_secs_f64(), failures })
}
