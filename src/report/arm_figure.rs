//! The figure and the page's animation of any arm's plan, with the arm's declared limits (issue
//! 20 item 7): dashed limit lines on the angle, rate and torque panels, and the joints at their
//! limit in each animation frame. Fig. 18 and Fig. 19 ([`super::arm3`]) and `plan --robot
//! --plot` draw through these.

use super::figures::{Animation, AnimationLeast, AnimationScene, BASE_SIZE, animation_samples};
use super::plot::scene::{CLEAR_COLOUR, COLLISION_COLOUR};
use super::plot::scene::{Scene, nearest_instant};
use super::plot::{Bound, Mark, Panel, PlanFigure, Series, joints_at_limit, watches_limits};
use crate::model::arm::Arm;
use crate::model::arm::collision::Body;
use crate::plan::clearance::ClearanceReport;
use crate::planners::arm::ArmPlanned;

/// The limit lines of an arm's figure ([`arm_plan_figure`]), in each panel's units and in the
/// colour of the curve they bound: `[angles, rates, torques]`. On the angle panel \[deg\] each
/// joint's position range (both ends, series `j + 1`) and the base's range (series 0); on the
/// rate panel \[rad/s\] `±` each joint's velocity limit; on the torque panel \[N m\] `±` each
/// joint's torque limit. A quantity without a limit draws nothing.
pub fn arm_limit_bounds(arm: &Arm) -> [Vec<Bound>; 3] {
    let limits = &arm.limits;
    let mut angles = Vec::new();
    if let Some([lo, hi]) = limits.base {
        for v in [lo, hi] {
            angles.push(Bound { value: v.to_degrees(), label: "φ range".into(), series: Some(0) });
        }
    }
    let (mut rates, mut torques) = (Vec::new(), Vec::new());
    for j in 0..arm.joints() {
        let l = limits.joint(j);
        if let Some([lo, hi]) = l.position {
            for v in [lo, hi] {
                angles.push(Bound { value: v.to_degrees(), label: format!("θ{} range", j + 1), series: Some(j + 1) });
            }
        }
        if let Some(v) = l.velocity {
            for v in [v, -v] {
                rates.push(Bound { value: v, label: format!("θ{}' limit", j + 1), series: Some(j) });
            }
        }
        if let Some(v) = l.torque {
            for v in [v, -v] {
                torques.push(Bound { value: v, label: format!("τ{} limit", j + 1), series: Some(j) });
            }
        }
    }
    [angles, rates, torques]
}

/// The figure of any arm's plan: angles \[deg\], joint velocities with the base's rate
/// \[rad/s\], torques \[N m\] (when computed), each with the arm's declared limits as dashed
/// lines ([`arm_limit_bounds`]), and the arm's parameters (read from `source`); the caption
/// gives both certificates and, with limits, the most-used one.
pub fn arm_plan_figure(p: &ArmPlanned, title: String, source: &str) -> PlanFigure {
    let tr = &p.trajectory;
    let n = p.arm.joints();
    let series = |label: String, f: &dyn Fn(usize) -> f64| Series {
        label,
        points: tr.iter().enumerate().map(|(i, s)| (s.t, f(i))).collect(),
    };
    let x_label = "t [s]".to_string();
    let mut angles = vec![series("φ".into(), &|i| tr[i].phi.to_degrees())];
    angles.extend((0..n).map(|j| series(format!("θ{}", j + 1), &|i| tr[i].theta[j].to_degrees())));
    let mut rates: Vec<Series> = (0..n).map(|j| series(format!("θ{}'", j + 1), &|i| tr[i].rate[j])).collect();
    rates.push(series("φ' (Eq. 7)".into(), &|i| p.arm.base_rate(&tr[i].theta, &tr[i].rate)));
    let torques = match &p.torques {
        Some(t) => (0..n).map(|j| series(format!("τ{}", j + 1), &|i| t.tau[i][j])).collect(),
        None => vec![],
    };
    let [angle_bounds, rate_bounds, torque_bounds] = arm_limit_bounds(&p.arm);
    let mut text = vec![
        format!("{source}:"),
        format!("base: M = {} kg, I = {} kg m²", p.arm.base.mass, p.arm.base.inertia),
        format!("mount: a = {} m, b = {} m", p.arm.mount.a, p.arm.mount.b),
    ];
    for (k, l) in p.arm.links.iter().enumerate() {
        text.push(format!(
            "link {}: l = {} m, d = {} m, m = {} kg, I = {:.4} kg m²",
            k + 1,
            l.length,
            l.com,
            l.mass,
            l.inertia
        ));
    }
    text.push(format!("effort ∫|θ'|² dt = {:.4} rad²/s, plan {:.1} ms", p.effort(), p.seconds * 1e3));
    let mut panels = vec![
        Panel {
            title: "Base orientation and joint angles".into(),
            x_label: x_label.clone(),
            y_label: "angle [deg]".into(),
            series: angles,
            bounds: angle_bounds,
            ..Default::default()
        },
        Panel {
            title: "Joint velocities (controls) and the base's rate".into(),
            x_label: x_label.clone(),
            y_label: "rate [rad/s]".into(),
            series: rates,
            include_zero: true,
            bounds: rate_bounds,
            ..Default::default()
        },
        Panel {
            title: "Joint torques τ".into(),
            x_label,
            y_label: "τ [N m]".into(),
            series: torques,
            include_zero: true,
            // Without torques the panel is empty: its limits alone are no picture.
            bounds: if p.torques.is_some() { torque_bounds } else { vec![] },
            ..Default::default()
        },
        Panel { title: "The arm".into(), text, ..Default::default() },
    ];
    let clearance = p.verification().clearance;
    if let Some(c) = &clearance {
        for panel in panels.iter_mut().filter(|panel| !panel.series.is_empty()) {
            panel.marks.push(least_clearance_mark(c));
        }
    }
    let v = p.verification();
    let verdict = |ok: bool| if ok { "certified" } else { "NOT certified" };
    // Within the tolerance but colliding or over a limit is not certified either (issues 20, 21).
    let broken = match (v.collision(), v.limits.as_ref().map_or(Ok(()), |l| l.check())) {
        (Err(_), _) => Some("NOT certified (it collides, below)"),
        (_, Err(_)) => Some("NOT certified (over a limit)"),
        _ => None,
    };
    let velocity = match broken {
        Some(why) if v.certified => why,
        _ => verdict(v.certified),
    };
    let mut caption = vec![format!(
        "velocity level: verified final error {:.2e} rad (tolerance {:.0e}): {};  max |momentum| {:.1e} kg m²/s;  \
         peak |θ'| = {:.4} rad/s",
        v.final_error,
        v.tolerance,
        velocity,
        v.max_abs_momentum,
        p.stats().map_or(0.0, |s| s.peak_velocity)
    )];
    if let Some(t) = &p.torques {
        let c = &t.certificate;
        let peaks: Vec<String> = t.max_abs_torque.iter().map(|x| format!("{x:.4}")).collect();
        caption.push(format!(
            "torque level: forward dynamics from rest, final error {:.2e} rad (tolerance {:.0e}): {};  peak |τ| = {} N m",
            c.final_error,
            c.tolerance,
            verdict(c.certified),
            peaks.join(", ")
        ));
    }
    if let Some(u) = p.limits.most_used() {
        caption.push(format!(
            "limits (dashed): the most used is {}'s {} limit, {:.1} % at t = {:.2} s; {}",
            u.name,
            u.quantity.name(),
            100.0 * u.used,
            u.time,
            if p.limits.inside { "every limit holds on the verified motion" } else { "a limit is EXCEEDED" }
        ));
    }
    if let Some(c) = &clearance {
        caption.push(format!(
            "clearance (solid vertical line): least {:.1} mm between {} and {} at t = {:.2} s, required {:.1} mm: {}",
            c.min * 1e3,
            c.a,
            c.b,
            c.time,
            c.required * 1e3,
            if c.holds() { "CLEAR" } else { "COLLIDES" }
        ));
    }
    PlanFigure { title, panels, caption }
}

/// The vertical line of an arm figure's panels at the least clearance `c` of the verified
/// motion: at its time \[s\], labelled with the clearance \[mm\] and the pair, purple
/// ([`CLEAR_COLOUR`]) when it holds, red ([`COLLISION_COLOUR`]) when it does not.
pub fn least_clearance_mark(c: &ClearanceReport) -> Mark {
    let hex = if c.holds() { CLEAR_COLOUR } else { COLLISION_COLOUR };
    let channel = |k: usize| hex.get(1 + 2 * k..3 + 2 * k).and_then(|h| u8::from_str_radix(h, 16).ok()).unwrap_or(0);
    Mark {
        x: c.time,
        label: format!("least clearance {:.1} mm, {} / {}", c.min * 1e3, c.a, c.b),
        colour: (channel(0), channel(1), channel(2)),
    }
}

/// The page's animation of an arm's plan, `id` and `title` its own: the arm's points
/// ([`Arm::joint_positions`]) at up to 501 samples, and the joints at their limit at each
/// ([`joints_at_limit`], on the samples' angles and rates).
pub fn arm_animation(p: &ArmPlanned, id: &str, title: &str) -> Animation {
    let indices = animation_samples(p.trajectory.len());
    let round = |x: f64| (x * 1e5).round() / 1e5;
    let points = indices
        .iter()
        .map(|&i| {
            let s = &p.trajectory[i];
            let q: Vec<f64> = std::iter::once(s.phi).chain(s.theta.iter().copied()).collect();
            p.arm.joint_positions(&q).iter().flat_map(|xy| xy.map(round)).collect()
        })
        .collect();
    let at_limit = if watches_limits(&p.arm.limits) {
        indices
            .iter()
            .map(|&i| {
                let s = &p.trajectory[i];
                let hot = joints_at_limit(&p.arm.limits, &s.theta, &s.rate);
                hot.iter().enumerate().filter(|(_, h)| **h).map(|(j, _)| j + 1).collect()
            })
            .collect()
    } else {
        Vec::new()
    };
    let t: Vec<f64> = indices.iter().map(|&i| round(p.trajectory[i].t)).collect();
    let qs: Vec<Vec<f64>> = indices
        .iter()
        .map(|&i| std::iter::once(p.trajectory[i].phi).chain(p.trajectory[i].theta.iter().copied()).collect())
        .collect();
    Animation {
        scene: animation_scene(&p.arm, p.verification().clearance, &t, &qs),
        id: id.into(),
        title: title.into(),
        mount: [p.arm.mount.a, p.arm.mount.b],
        base_size: BASE_SIZE,
        t,
        phi: indices.iter().map(|&i| round(p.trajectory[i].phi)).collect(),
        points,
        at_limit,
    }
}

/// The page's scene of `arm`'s geometry over the samples at times `t` \[s\] and configurations
/// `qs` \[rad\], with the verified motion's least clearance `least` marked at the sample nearest
/// its time; `None` without shapes and obstacles.
fn animation_scene(arm: &Arm, least: Option<ClearanceReport>, t: &[f64], qs: &[Vec<f64>]) -> Option<AnimationScene> {
    let scene = Scene::new(arm, least)?;
    let round = |o: &Vec<[f64; 2]>| -> Vec<[f64; 2]> { o.iter().map(|p| p.map(|x| (x * 1e5).round() / 1e5)).collect() };
    let obstacles: Vec<Vec<[f64; 2]>> = scene.obstacle_outlines().iter().map(round).collect();
    let least = match (least, nearest_instant(t, least.map_or(0.0, |c| c.time))) {
        (Some(c), Some(sample)) => {
            let q = &qs[sample];
            let placed = scene.placed_bodies(arm, q);
            let outlines = [c.a, c.b]
                .iter()
                .flat_map(|&body| match body {
                    Body::Base => placed.first().cloned().unwrap_or_default(),
                    Body::Link(k) => placed.get(k).cloned().unwrap_or_default(),
                    Body::Obstacle(k) => obstacles.get(k.wrapping_sub(1)).cloned().into_iter().collect(),
                })
                .map(|o| round(&o))
                .collect();
            Some(AnimationLeast {
                t: c.time,
                min: c.min,
                required: c.required,
                between: [c.a.to_string(), c.b.to_string()],
                holds: c.holds(),
                sample,
                outlines,
                points: scene.least_points(arm, q),
                colour: scene.marker_colour().unwrap_or(CLEAR_COLOUR).to_string(),
                caption: scene.caption().unwrap_or_default(),
            })
        }
        _ => None,
    };
    Some(AnimationScene {
        bodies: scene.bodies.iter().map(|b| b.iter().map(round).collect()).collect(),
        obstacles,
        least,
    })
}
