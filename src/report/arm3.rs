//! Beyond the paper (issue 14, item 3): a 3-link arm on the paper's SRC base,
//! `examples/robots/three_link.toml` (its header gives the source of the parameters), planned rest
//! to rest with a real base reorientation through [`plan_arm`] with the torque level: Fig. 18,
//! its animation, and the `arm3` entry of `summary.*`.

use serde::Serialize;

use super::figures::{Animation, BASE_SIZE};
use super::html::{escape, head_cell};
use super::plot::{Panel, PlanFigure, Series};
use crate::error::Error;
use crate::model::arm::Arm;
use crate::plan::Method;
use crate::planners::arm::{ArmPlanned, ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;

/// The robot file, embedded: `reproduce` reads no file at run time.
pub const THREE_LINK_TOML: &str = include_str!("../../examples/robots/three_link.toml");

/// The figure's name.
pub const ARM3_FIGURE: &str = "fig18";

/// Start `(phi, theta_1, theta_2, theta_3)` \[deg\]: the arm half bent, the base at 0.
pub const ARM3_START_DEG: [f64; 4] = [0.0, 30.0, 60.0, 45.0];
/// Goal \[deg\]: the base turned by 30 deg, every joint moved by tens of degrees.
pub const ARM3_GOAL_DEG: [f64; 4] = [30.0, 75.0, 20.0, 90.0];
/// Horizon `T` \[s\].
pub const ARM3_HORIZON: f64 = 10.0;
/// The animation's title (the report page's and `anim-arm3.gif`'s).
pub const ARM3_ANIMATION_TITLE: &str = "Fig. 18: a 3-link arm";
/// Samples of the trajectory, both ends included (as the paper's cases).
pub const ARM3_SAMPLES: usize = 1001;

/// The 3-link arm of [`THREE_LINK_TOML`].
pub fn three_link_arm() -> Result<Arm, Error> {
    Ok(Arm::from_toml(THREE_LINK_TOML, "examples/robots/three_link.toml".as_ref())?)
}

/// The problem: [`ARM3_START_DEG`] to [`ARM3_GOAL_DEG`] at rest in [`ARM3_HORIZON`], the goal's
/// angles taken literally (no full turn of a joint: a real arm's cables forbid it).
pub fn arm3_problem() -> ChainProblem {
    let rad = |v: [f64; 4]| v.iter().map(|x| x.to_radians()).collect();
    ChainProblem { wrap: false, ..ChainProblem::rest_to_rest(rad(ARM3_START_DEG), rad(ARM3_GOAL_DEG), ARM3_HORIZON) }
}

/// Plans the case: the minimum-effort planner with both certificates.
pub fn plan_arm3() -> Result<ArmPlanned, Error> {
    let request = ArmRequest {
        problem: arm3_problem(),
        samples: ARM3_SAMPLES,
        tolerance: 1e-9,
        torques: true,
        ecsa: Default::default(),
        cost: Default::default(),
        smooth_ends: false,
        shortest_horizon: false,
    };
    plan_arm(&three_link_arm()?, Method::Optimal, &request)
}

/// The `arm3` entry of `summary.json`. Numbers are `null` only without a plan (then `error`
/// says why).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Arm3Row {
    /// The figure, [`ARM3_FIGURE`].
    pub figure: String,
    /// Where the parameters come from.
    pub robot_file: String,
    /// The arm's parameters.
    pub arm: Option<Arm>,
    /// Start and goal `(phi, theta_1..3)` \[deg\], horizon \[s\].
    pub start_deg: [f64; 4],
    /// Goal \[deg\].
    pub goal_deg: [f64; 4],
    /// `T` \[s\].
    pub horizon: f64,
    /// The effort `integral |theta'|^2 dt` \[rad^2/s\].
    pub effort: Option<f64>,
    /// Largest `|theta_j'|` over joints and time \[rad/s\]: the planner's (sampled finely) or the
    /// samples', whichever is larger.
    pub peak_velocity: Option<f64>,
    /// Largest `|theta_j'|` over the samples, per joint \[rad/s\].
    pub max_abs_rate: Option<Vec<f64>>,
    /// Largest `|tau_j|` over the samples, per joint \[N m\].
    pub max_abs_torque: Option<Vec<f64>>,
    /// Velocity certificate: final error \[rad\].
    pub final_error: Option<f64>,
    /// Velocity certificate: largest angular momentum along the integration \[kg m^2/s\].
    pub max_abs_momentum: Option<f64>,
    /// The velocity certificate holds (1e-9 rad).
    pub certified: bool,
    /// Torque certificate (forward dynamics from rest): final error \[rad\].
    pub torque_final_error: Option<f64>,
    /// Torque certificate: largest angular momentum \[kg m^2/s\].
    pub torque_max_abs_momentum: Option<f64>,
    /// The torque certificate holds (1e-6 rad).
    pub torque_certified: bool,
    /// Wall time \[s\]: `[plan and velocity certificate, torques and torque certificate]`.
    pub seconds: Option<[f64; 2]>,
    /// Why there is no plan.
    pub error: Option<String>,
}

impl Arm3Row {
    /// The row of a planned case (or of its failure).
    pub fn new(outcome: Result<&ArmPlanned, &Error>) -> Self {
        let mut row = Self {
            figure: ARM3_FIGURE.into(),
            robot_file: "examples/robots/three_link.toml".into(),
            arm: three_link_arm().ok(),
            start_deg: ARM3_START_DEG,
            goal_deg: ARM3_GOAL_DEG,
            horizon: ARM3_HORIZON,
            effort: None,
            peak_velocity: None,
            max_abs_rate: None,
            max_abs_torque: None,
            final_error: None,
            max_abs_momentum: None,
            certified: false,
            torque_final_error: None,
            torque_max_abs_momentum: None,
            torque_certified: false,
            seconds: None,
            error: None,
        };
        let p = match outcome {
            Ok(p) => p,
            Err(e) => {
                row.error = Some(e.to_string());
                return row;
            }
        };
        let v = p.verification();
        row.effort = Some(p.effort());
        let n = p.arm.joints();
        let rates: Vec<f64> =
            (0..n).map(|j| p.trajectory.iter().map(|s| s.rate[j].abs()).fold(0.0, f64::max)).collect();
        row.peak_velocity = Some(rates.iter().copied().fold(p.stats().map_or(0.0, |s| s.peak_velocity), f64::max));
        row.max_abs_rate = Some(rates);
        (row.final_error, row.max_abs_momentum, row.certified) =
            (Some(v.final_error), Some(v.max_abs_momentum), v.certified);
        if let Some(t) = &p.torques {
            row.max_abs_torque = Some(t.max_abs_torque.clone());
            row.torque_final_error = Some(t.certificate.final_error);
            row.torque_max_abs_momentum = Some(t.certificate.max_abs_momentum);
            row.torque_certified = t.certificate.certified;
        }
        row.seconds = Some([p.seconds, p.torques.as_ref().map_or(0.0, |t| t.seconds)]);
        row
    }

    fn cells(&self) -> [String; 8] {
        let e = |x: Option<f64>| x.map_or("-".to_string(), |x| super::numbers::scientific(x, 2));
        let g = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.4}"));
        let list = |x: &Option<Vec<f64>>| {
            x.as_ref().map_or("-".to_string(), |v| v.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(", "))
        };
        let yes = |ok: bool| if ok { "yes" } else { "NO" };
        [
            g(self.effort),
            g(self.peak_velocity),
            list(&self.max_abs_torque),
            format!("{} ({})", e(self.final_error), yes(self.certified)),
            e(self.max_abs_momentum),
            format!("{} ({})", e(self.torque_final_error), yes(self.torque_certified)),
            e(self.torque_max_abs_momentum),
            self.seconds.map_or("-".to_string(), |s| format!("{:.1} / {:.1}", s[0] * 1e3, s[1] * 1e3)),
        ]
    }
}

const HEADS: [&str; 8] = [
    "effort [rad²/s]",
    "peak |θ'| [rad/s]",
    "peak |τ1|, |τ2|, |τ3| [N m]",
    "final error [rad] (≤ 1e-9)",
    "max |momentum| [kg m²/s]",
    "torque final error [rad] (≤ 1e-6)",
    "torque max |momentum| [kg m²/s]",
    "plan / torques [ms]",
];

/// What the case is, in words (`summary.md`, the page).
pub fn arm3_text() -> String {
    let deg = |v: [f64; 4]| v.map(|x| x.to_string()).join(", ");
    format!(
        "The 3-link arm of `examples/robots/three_link.toml` (the paper's SRC base, M = 12.9 kg, I = 0.208 kg m², \
         with its 1.22 m, 6 kg arm redistributed over three uniform rods of 0.45, 0.40, 0.35 m and 3, 2, 1 kg; the \
         file's header gives the reasoning), from (φ, θ1, θ2, θ3) = ({}) deg to ({}) deg at rest in T = {} s, \
         by the minimum-effort planner (`planners::arm::plan_arm`), the goal's angles taken literally. The base \
         turns by 30 deg only through the arm's loop in joint space (Eq. 7 with n = 3); no joint limits or \
         self-collisions are modelled.",
        deg(ARM3_START_DEG),
        deg(ARM3_GOAL_DEG),
        ARM3_HORIZON
    )
}

/// The `arm3` section of `summary.md`.
pub fn arm3_markdown(row: &Arm3Row) -> String {
    let mut s = format!("\n## A 3-link arm (Fig. 18)\n\n{}\n\n", arm3_text());
    let heads: Vec<String> = HEADS.iter().map(|h| h.replace('|', "\\|")).collect();
    s += &format!("| {} |\n|{}\n| {} |\n", heads.join(" | "), " --- |".repeat(HEADS.len()), row.cells().join(" | "));
    if let Some(err) = &row.error {
        s += &format!("\nNo plan: {err}\n");
    }
    s
}

/// The `arm3` table of `report.html`.
pub fn arm3_html(row: &Arm3Row) -> String {
    let mut s = format!("<p>{}</p>\n<div class=\"scroll\"><table>\n<tr>", escape(&arm3_text().replace('`', "")));
    for h in HEADS {
        s += &head_cell(h);
    }
    s += "</tr>\n<tr>";
    for c in row.cells() {
        s += &format!("<td>{}</td>", escape(&c));
    }
    s += "</tr>\n";
    if let Some(err) = &row.error {
        s += &format!("<tr><td class=\"left no\" colspan=\"8\">no plan: {}</td></tr>\n", escape(err));
    }
    s += "</table></div>\n";
    s
}

/// Fig. 18: angles, joint velocities (with the base's rate), torques, and the arm's parameters.
pub fn arm3_figure(p: &ArmPlanned) -> PlanFigure {
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
    let mut text = vec![
        "examples/robots/three_link.toml:".to_string(),
        format!("base: M = {} kg, I = {} kg m² (the paper's SRC base)", p.arm.base.mass, p.arm.base.inertia),
        format!("mount: a = {} m, b = {} m", p.arm.mount.a, p.arm.mount.b),
    ];
    for (k, l) in p.arm.links.iter().enumerate() {
        text.push(format!(
            "link {}: l = {} m, d = {} m, m = {} kg, I = {:.4} kg m² (uniform rod)",
            k + 1,
            l.length,
            l.com,
            l.mass,
            l.inertia
        ));
    }
    text.push(format!("effort ∫|θ'|² dt = {:.4} rad²/s, plan {:.1} ms", p.effort(), p.seconds * 1e3));
    let panels = vec![
        Panel {
            title: "Base orientation and joint angles".into(),
            x_label: x_label.clone(),
            y_label: "angle [deg]".into(),
            series: angles,
            ..Default::default()
        },
        Panel {
            title: "Joint velocities (controls) and the base's rate".into(),
            x_label: x_label.clone(),
            y_label: "rate [rad/s]".into(),
            series: rates,
            text: vec![],
            include_zero: true,
        },
        Panel {
            title: "Joint torques τ".into(),
            x_label,
            y_label: "τ [N m]".into(),
            series: torques,
            text: vec![],
            include_zero: true,
        },
        Panel { title: "The arm".into(), text, ..Default::default() },
    ];
    let v = p.verification();
    let verdict = |ok: bool| if ok { "certified" } else { "NOT certified" };
    let mut caption = vec![format!(
        "velocity level: verified final error {:.2e} rad (tolerance {:.0e}): {};  max |momentum| {:.1e} kg m²/s;  \
         peak |θ'| = {:.4} rad/s",
        v.final_error,
        v.tolerance,
        verdict(v.certified),
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
    caption.push(
        "the minimum-effort plan leaves and reaches rest through steep velocity ramps in short end spans: the torque \
         peaks sit at t = 0 and t = T"
            .to_string(),
    );
    let title = "Fig. 18 (beyond the paper): a 3-link arm, the base turned by 30 deg, minimum effort".to_string();
    PlanFigure { title, panels, caption }
}

/// The animation of the case: the arm's points ([`Arm::joint_positions`]) at up to 501 samples.
pub fn arm3_animation(p: &ArmPlanned) -> Animation {
    let n = p.trajectory.len();
    let step = n.div_ceil(501).max(1);
    let mut indices: Vec<usize> = (0..n).step_by(step).collect();
    if n > 0 && indices.last() != Some(&(n - 1)) {
        indices.push(n - 1);
    }
    let round = |x: f64| (x * 1e5).round() / 1e5;
    let points = indices
        .iter()
        .map(|&i| {
            let s = &p.trajectory[i];
            let q: Vec<f64> = std::iter::once(s.phi).chain(s.theta.iter().copied()).collect();
            p.arm.joint_positions(&q).iter().flat_map(|xy| xy.map(round)).collect()
        })
        .collect();
    Animation {
        id: "arm3".into(),
        title: ARM3_ANIMATION_TITLE.into(),
        mount: [p.arm.mount.a, p.arm.mount.b],
        base_size: BASE_SIZE,
        t: indices.iter().map(|&i| round(p.trajectory[i].t)).collect(),
        phi: indices.iter().map(|&i| round(p.trajectory[i].phi)).collect(),
        points,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The case plans and is certified at both levels; the base ends turned by 30 deg; the
    /// animation has `n + 2` points per frame; the figure has four panels with three torques.
    #[test]
    fn the_three_link_case_is_certified_and_drawn() {
        let p = plan_arm3().expect("the 3-link case has a plan");
        p.certified().expect("both certificates hold");
        let row = Arm3Row::new(Ok(&p));
        assert!(row.certified && row.torque_certified);
        assert_eq!(row.max_abs_torque.as_ref().map(Vec::len), Some(3));
        let last = p.trajectory.last().expect("samples");
        assert!((last.phi - 30f64.to_radians()).abs() < 1e-8);
        let anim = arm3_animation(&p);
        assert!(anim.points.iter().all(|f| f.len() == 2 * (3 + 2)));
        let figure = arm3_figure(&p);
        assert_eq!(figure.panels[2].series.len(), 3);
        let md = arm3_markdown(&row);
        assert_eq!(md.matches("(yes)").count(), 2, "{md}");
    }
}
