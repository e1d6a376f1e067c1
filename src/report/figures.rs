//! What the report draws of a plan: the four panels of Figs. 4-12 and the animation data.

use serde::Serialize;

use super::cases::CaseOutcome;
use super::summary::fmt_pair;
use crate::model::Configuration;
use crate::model::kinematics::pose;
use crate::report::plot::{Panel, PlanFigure, Series};

/// The four panels of a plan figure (as in the paper's Figs. 4-12), and a caption with both
/// certificates.
pub fn plan_figure(o: &CaseOutcome) -> PlanFigure {
    let tr = &o.plan.trajectory;
    let t = &tr.t;
    let column = |f: &dyn Fn(usize) -> f64| t.iter().enumerate().map(|(i, &t)| (t, f(i))).collect::<Vec<_>>();
    let series = |label: &str, f: &dyn Fn(usize) -> f64| Series { label: label.into(), points: column(f) };
    let x_label = "t [s]".to_string();
    let angles = Panel {
        title: "Base orientation and joint positions".into(),
        x_label: x_label.clone(),
        y_label: "angle [deg]".into(),
        series: vec![
            series("φ", &|i| tr.q[i][0].to_degrees()),
            series("θ1", &|i| tr.q[i][1].to_degrees()),
            series("θ2", &|i| tr.q[i][2].to_degrees()),
        ],
        ..Default::default()
    };
    let second = match (&tr.z, &o.ecsa) {
        (Some(z), _) => Panel {
            title: format!("Normal-form variables z ({})", o.case.variant()),
            x_label: x_label.clone(),
            y_label: "z (rad, mixed units)".into(),
            series: (0..3).map(|k| series(&format!("z{}", k + 1), &|i| z[i][k])).collect(),
            ..Default::default()
        },
        (None, Some(s)) => Panel {
            title: format!(
                "ECSA iteration: {} Jacobian pseudo-inverse steps, residual {:.1e} rad",
                s.stats.iterations, s.stats.residual
            ),
            x_label: "iteration".into(),
            y_label: "log10 of the end-point residual [rad]".into(),
            series: vec![
                Series {
                    label: "max |K(c) - qd| (no z: no normal form)".into(),
                    points: s.stats.residual_history.iter().enumerate().map(|(k, r)| (k as f64, r.log10())).collect(),
                },
                Series {
                    label: "tolerance".into(),
                    points: vec![
                        (0.0, s.stats.tolerance.log10()),
                        (s.stats.residual_history.len().saturating_sub(1).max(1) as f64, s.stats.tolerance.log10()),
                    ],
                },
            ],
            ..Default::default()
        },
        _ => Panel { title: "(no z)".into(), ..Default::default() },
    };
    let controls = Panel {
        title: "Velocity controls u".into(),
        x_label: x_label.clone(),
        y_label: "u [rad/s]".into(),
        series: vec![series("u1 = θ1'", &|i| tr.dq[i][1]), series("u2 = θ2'", &|i| tr.dq[i][2])],
        text: vec![],
        include_zero: true,
        bounds: vec![],
        marks: vec![],
    };
    let torques = match &tr.tau {
        Some(tau) => Panel {
            title: "Joint torques τ".into(),
            x_label,
            y_label: "τ [N m]".into(),
            series: vec![series("τ1", &|i| tau[i][0]), series("τ2", &|i| tau[i][1])],
            text: vec![],
            include_zero: true,
            bounds: vec![],
            marks: vec![],
        },
        None => Panel { title: "(no torques)".into(), ..Default::default() },
    };
    let v = &o.plan.verification;
    let c = &o.torques.certificate;
    let verdict = |ok: bool| if ok { "certified" } else { "NOT certified" };
    // Within the tolerance but colliding is not certified either (issue 21): said on the caption.
    let collides = crate::plan::certificate::collision(v.clearance.as_ref()).is_err();
    let velocity = if v.certified && collides { "NOT certified (it collides, below)" } else { verdict(v.certified) };
    let mut caption = vec![
        format!(
            "velocity level: verified final error {:.2e} rad (tolerance {:.0e}): {};  peak |u1|, |u2| = {} rad/s",
            v.final_error,
            v.tolerance,
            velocity,
            fmt_pair(o.plan.max_abs_u, 4)
        ),
        format!(
            "torque level: forward dynamics from rest, final error {:.2e} rad (tolerance {:.0e}): {};  \
             peak |τ1|, |τ2| = {} N m",
            c.final_error,
            c.tolerance,
            verdict(c.certified),
            fmt_pair(o.torques.max_abs_torque, 4)
        ),
    ];
    if let Some(dq) = tr.dq.first().filter(|dq| dq[1].abs().max(dq[2].abs()) > 1e-9) {
        caption.push(format!(
            "u(0) = ({:.4}, {:.4}) rad/s: the plan does not start at rest, so the torque plan (from rest) cannot follow it",
            dq[1], dq[2]
        ));
    }
    if let Some(b) = o.nfa.and_then(|d| d.band) {
        caption.push(format!(
            "band steering: {} loops of amplitude {:.2} rad; the open-loop torque plan of such fast loops is ill-conditioned",
            b.loops, b.amplitude
        ));
    }
    PlanFigure { title: o.case.title(), panels: vec![angles, second, controls, torques], caption }
}

/// Side lengths of the base rectangle drawn by the animation \[m\] (illustrative: the paper
/// gives the base's mass and inertia, not its shape).
pub const BASE_SIZE: [f64; 2] = [0.6, 0.5];

/// The animation data of a plan: poses at up to 501 of its samples.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Animation {
    /// The case's identifier.
    pub id: String,
    /// Its title.
    pub title: String,
    /// Mounting point `[a, b]` \[m\].
    pub mount: [f64; 2],
    /// Base rectangle \[m\] ([`BASE_SIZE`]).
    pub base_size: [f64; 2],
    /// Times \[s\].
    pub t: Vec<f64>,
    /// Base orientation `phi` \[rad\] at each time.
    pub phi: Vec<f64>,
    /// Flattened poses per time \[m\]: `[base x, base y, joint1 x, y, .., joint n x, y, tip x, y]`
    /// (`2 (n + 2)` numbers for `n` links; the mounting point is joint 1).
    pub points: Vec<Vec<f64>>,
    /// Per time, the joints (counted from 1) at their position range or velocity limit
    /// ([`crate::report::plot::joints_at_limit`]), drawn in red by `page.js`; empty (and left out
    /// of the page's data) for a robot without such limits.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub at_limit: Vec<Vec<usize>>,
    /// The robot's shapes, the obstacles and the least clearance (issue 21), drawn by `page.js`;
    /// `None` (and left out of the page's data) for a robot without shapes or obstacles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene: Option<AnimationScene>,
}

/// What the page's animation draws of an arm's geometry (`page.js`; the GIF draws the same,
/// [`crate::report::plot::scene`]). Outlines are closed polygons `[[x, y], ..]` \[m\].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnimationScene {
    /// Per body, its shapes' outlines in its own frame: the base's (origin at its centre of mass,
    /// x axis at `phi`) first, then link `k`'s (origin at joint `k`, x axis along the link).
    pub bodies: Vec<Vec<Vec<[f64; 2]>>>,
    /// The obstacles' outlines in the inertial frame, obstacle 1 first.
    pub obstacles: Vec<Vec<[f64; 2]>>,
    /// The least clearance of the verified motion, when it was checked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub least: Option<AnimationLeast>,
}

/// The least clearance as the page's animation marks it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnimationLeast {
    /// Its time \[s\] (the certificate's, [`crate::plan::clearance::ClearanceReport::time`]).
    pub t: f64,
    /// The clearance \[m\] (negative: the depth of the overlap).
    pub min: f64,
    /// The clearance asked for \[m\].
    pub required: f64,
    /// The pair, e.g. `["base", "link 4"]`.
    pub between: [String; 2],
    /// Whether the clearance holds (the marker is red when it does not).
    pub holds: bool,
    /// The sample (index into `t`) nearest its time, where the marker is drawn.
    pub sample: usize,
    /// The pair's outlines at that sample, in the inertial frame.
    pub outlines: Vec<Vec<[f64; 2]>>,
    /// The pair's nearest points at that sample `[on a, on b]` \[m\], when found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub points: Option<[[f64; 2]; 2]>,
    /// The marker's colour (`#rrggbb`).
    pub colour: String,
    /// The words shown, e.g. `least clearance 12.3 mm, base / link 4, t = 6.11 s`.
    pub caption: String,
}

/// The indices of at most about 501 evenly spaced samples of `n`, the last one included: the
/// frames of a page's animation.
pub(crate) fn animation_samples(n: usize) -> Vec<usize> {
    let step = n.div_ceil(501).max(1);
    let mut indices: Vec<usize> = (0..n).step_by(step).collect();
    if n > 0 && indices.last() != Some(&(n - 1)) {
        indices.push(n - 1);
    }
    indices
}

/// The animation of a planned case.
pub fn animation(o: &CaseOutcome) -> Animation {
    let tr = &o.plan.trajectory;
    let indices = animation_samples(tr.t.len());
    let round = |x: f64| (x * 1e5).round() / 1e5;
    let robot = &o.plan.problem.robot;
    let points = indices
        .iter()
        .map(|&i| {
            let p = pose(robot, &Configuration::from_array(tr.q[i]));
            [p.base, p.joint1, p.joint2, p.tip].iter().flat_map(|xy| xy.map(round)).collect()
        })
        .collect();
    Animation {
        id: o.case.id.into(),
        title: o.case.title(),
        mount: [robot.mount.a, robot.mount.b],
        base_size: BASE_SIZE,
        t: indices.iter().map(|&i| round(tr.t[i])).collect(),
        phi: indices.iter().map(|&i| round(tr.q[i][0])).collect(),
        points,
        at_limit: Vec::new(),
        scene: None,
    }
}
