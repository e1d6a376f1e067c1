//! A slow, exhaustive minimum-effort search, the test oracle of the planner (issue 19, item 2):
//! every goal representative within two turns of each joint and of the base, every seed the
//! planner knows in both orientations (the line, loops beside it and on it, loops along either
//! joint, the coil, the NFA's path), each solved on a finer coarse basis (16 spans, and a line
//! of more than a turn and its loops on 16 spans per turn of its longest travel too), all
//! feasible solutions of a representative within 50 % of its best refined on up to 64 spans, the
//! best certified plan kept. A representative whose effort lower bound exceeds the best effort
//! found is skipped: the bound is a proof, not a heuristic, so the search stays exhaustive over
//! its seeds. It takes about a second per problem.

use std::f64::consts::TAU;

use super::discrete::Targets;
use super::engine::{COARSE_SQP, Candidate, SPANS_PER_TURN, Tables};
use super::seeds::{self, Line, SeedKind};
use super::{OptimalOptions, OptimalPlanner, sqp};
use crate::model::wrap_angle;
use crate::plan::{Method, Motion, PlanningProblem};
use crate::planners::chain::LINE_SPANS_PER_TURN;

/// Turns either way of each joint and of the base around the nearest representative.
const TURNS: i32 = 2;

/// The reference's best certified effort \[rad^2/s\] on `problem` (rest to rest), with the joint
/// goal `theta(T)` of its plan; `None` when no candidate is certified.
pub(crate) fn reference_effort(problem: &PlanningProblem) -> Option<(f64, [f64; 2])> {
    let options = OptimalOptions { coarse_spans: 16, max_spans: 64, finalists: 8, ..OptimalOptions::default() };
    let planner = OptimalPlanner::new(options);
    let o = &planner.options;
    let k = problem.robot.lumped();
    let tables = Tables::default();
    let grid = seeds::curvature_grid(&k);
    let kappa_max = seeds::curvature_bound_on(&grid);
    let sites = seeds::coil_sites_on(&k, o.max_loop_radius, &grid);
    let nfa = planner.nfa_path(problem);
    let (q0, qd) = (problem.start, problem.goal);
    let near = |from: f64, to: f64| from + wrap_angle(to - from);
    let (t1, t2, phi) = (near(q0.theta1, qd.theta1), near(q0.theta2, qd.theta2), near(q0.phi, qd.phi));
    // Representatives with their lines, needed rotation and bound, least bound first.
    let mut reps = Vec::new();
    for i in -TURNS..=TURNS {
        for j in -TURNS..=TURNS {
            let end = [t1 + TAU * f64::from(i), t2 + TAU * f64::from(j)];
            let line =
                Line { start: [q0.theta1, q0.theta2], end, initial_velocity: [0.0; 2], horizon: problem.horizon };
            for m in -TURNS..=TURNS {
                let targets = Targets {
                    start: line.start,
                    initial_velocity: [0.0; 2],
                    end,
                    phi_start: q0.phi,
                    phi_end: phi + TAU * f64::from(m),
                };
                reps.push((targets, line));
            }
        }
    }
    let mut best = f64::INFINITY;
    let mut prepared = Vec::new();
    for (targets, line) in reps {
        let disc = planner.discretise(problem, targets, o.coarse_spans, o.quadrature_nodes, &tables).ok()?;
        let x_line = disc.project(|t| line.at(t)).ok()?;
        let needed = -(targets.phi_start - disc.holonomy_integral(&x_line) - targets.phi_end);
        let bound = seeds::effort_lower_bound(&line, needed, kappa_max);
        prepared.push((bound, targets, line, disc, x_line, needed));
    }
    prepared.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut motions = Vec::new();
    for (bound, targets, line, disc, x_line, needed) in prepared {
        if bound > best {
            continue;
        }
        let r = o.max_loop_radius;
        let mut kinds = Vec::new();
        for orientation in [1, -1] {
            for side in [1, 0, -1] {
                kinds.push(line.loop_seed(&k, needed, side, orientation, r));
            }
            for axis in [0, 1] {
                if let SeedKind::AxisLoop { radius, turns, .. } = line.axis_loop_seed(&k, needed, axis, r) {
                    kinds.push(SeedKind::AxisLoop { axis, orientation, radius, turns });
                }
            }
        }
        let site = if needed >= 0.0 { &sites[0] } else { &sites[1] };
        let coil = line.coil(site, needed, r);
        let mut starts = vec![(disc.clone(), o.coarse_spans, x_line.clone(), None)];
        // The line and loops on the coarse basis and, for a line of more than a turn, on twice
        // the planner's spans per turn of its longest travel (`LINE_SPANS_PER_TURN`) too.
        let travel = (0..2).map(|j| (line.end[j] - line.start[j]).abs()).fold(0.0, f64::max);
        let long = ((2 * LINE_SPANS_PER_TURN) as f64 * travel / TAU).ceil() as usize;
        let mut bases = vec![(disc.clone(), o.coarse_spans)];
        if long > o.coarse_spans {
            let spans = long.min(o.max_spans);
            if let Ok(d) = planner.discretise(problem, targets, spans, o.quadrature_nodes, &tables) {
                if let Ok(x) = d.project(|t| line.at(t)) {
                    starts.push((d.clone(), spans, x, None));
                }
                bases.push((d, spans));
            }
        }
        for (disc, spans) in &bases {
            let residual =
                |kind: SeedKind| disc.project(|t| line.path(kind, t)).map_or(f64::NAN, |x| disc.evaluate(&x, 0).c);
            for &kind in &kinds {
                let fitted = line.fit_radius(kind, r, residual);
                for seed in [kind, fitted] {
                    if let Ok(x) = disc.project(|t| line.path(seed, t)) {
                        starts.push((disc.clone(), *spans, x, None));
                    }
                }
            }
        }
        if let SeedKind::Coil { turns, .. } = coil {
            let spans = o.coarse_spans.max(SPANS_PER_TURN * turns);
            if let Ok(fine) = planner.discretise(problem, targets, spans, o.quadrature_nodes, &tables) {
                let residual =
                    |kind: SeedKind| fine.project(|t| line.path(kind, t)).map_or(f64::NAN, |x| fine.evaluate(&x, 0).c);
                let fitted = line.fit_radius(coil, r, residual);
                if let Ok(x) = fine.project(|t| line.path(fitted, t)) {
                    let guess = (needed.abs() > 0.0).then(|| -2.0 * fine.evaluate(&x, 0).f / needed);
                    starts.push((fine, spans, x, guess));
                }
            }
        }
        if let Some((path, end, phi)) = &nfa {
            let same = (0..2).all(|j| (end[j] - targets.end[j]).abs() < 1e-6) && (phi - targets.phi_end).abs() < 1e-6;
            if same && let Ok(x) = disc.project(|t| path.at(t)) {
                starts.push((disc.clone(), o.coarse_spans, x, None));
            }
        }
        let mut coarse: Vec<Candidate> = Vec::new();
        for (d, spans, x0, guess) in starts {
            let Ok(result) = sqp::solve(&d, x0, &COARSE_SQP, guess) else { continue };
            if result.c.abs() <= 1e-6 && result.f.is_finite() {
                let iterations = result.iterations;
                coarse.push(Candidate { disc: d, result, spans, nodes: o.quadrature_nodes, iterations, motion: None });
            }
        }
        coarse.sort_by(|a, b| a.result.f.total_cmp(&b.result.f));
        let Some(first) = coarse.first().map(|c| c.result.f) else { continue };
        let mut refined: Vec<f64> = Vec::new();
        for c in coarse {
            if c.result.f > 1.5 * first.min(best) || refined.len() >= o.finalists {
                break;
            }
            if refined.iter().any(|f| (f - c.result.f).abs() <= 1e-6 * f.abs()) {
                continue;
            }
            refined.push(c.result.f);
            let Ok(c) = planner.refine(problem, c, &tables) else { continue };
            if !c.result.converged() {
                continue;
            }
            let end = c.disc.targets().end;
            let motion = planner.to_motion(problem, c, 0, 0);
            let Ok(trajectory) = motion.trajectory(problem, o.samples) else { continue };
            let margins = motion.margins(&trajectory);
            let Ok(plan) = crate::plan::Plan::verified(
                Method::Optimal,
                problem,
                &motion as &dyn Motion,
                trajectory,
                margins,
                0.0,
                &o.ode,
                o.tolerance,
            ) else {
                continue;
            };
            if plan.verification.certified && motion.stats.effort < best {
                best = motion.stats.effort;
                motions.push((best, end));
            }
        }
    }
    motions.into_iter().min_by(|a, b| a.0.total_cmp(&b.0))
}
