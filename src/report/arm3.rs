//! Beyond the paper (issue 14, item 3): a 3-link arm on the paper's SRC base,
//! `examples/robots/three_link.toml` (its header gives the source of the parameters), planned rest
//! to rest with a real base reorientation through [`plan_arm`] with the torque level: Fig. 18,
//! its animation, and the `arm3` entry of `summary.*`.

use serde::Serialize;

use super::arm_figure::{arm_animation, arm_plan_figure};
use super::figures::Animation;
use super::html::{escape, head_cell};
use super::plot::PlanFigure;
use crate::error::Error;
use crate::model::arm::{Arm, JointLimits, Limits};
use crate::plan::Method;
use crate::plan::limit_use::{LimitReport, Quantity};
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

/// The figure of the case inside a velocity limit ([`plan_arm3_limited`]).
pub const ARM3_LIMITED_FIGURE: &str = "fig19";
/// The animation's title of the limited case (the page's and `anim-arm3-limits.gif`'s).
pub const ARM3_LIMITED_ANIMATION_TITLE: &str = "Fig. 19: the 3-link arm inside a velocity limit";
/// The velocity limit of every joint in the limited case, as a share of the free plan's peak
/// joint speed (over joints and time): 80 %, so that the limit binds.
pub const ARM3_VELOCITY_SHARE: f64 = 0.8;

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

/// The largest `|theta_j'|` of a plan \[rad/s\]: the planner's (sampled finely) or the
/// samples', whichever is larger.
fn peak_velocity(p: &ArmPlanned) -> f64 {
    let samples = p.trajectory.iter().flat_map(|s| s.rate.iter().map(|r| r.abs())).fold(0.0, f64::max);
    samples.max(p.stats().map_or(0.0, |s| s.peak_velocity))
}

/// The 3-link arm with every joint's velocity limited to [`ARM3_VELOCITY_SHARE`] of `free`'s
/// peak joint speed \[rad/s\] (no other limit).
pub fn arm3_limited_arm(free: &ArmPlanned) -> Result<Arm, Error> {
    let velocity = ARM3_VELOCITY_SHARE * peak_velocity(free);
    let joint = JointLimits { velocity: Some(velocity), ..JointLimits::default() };
    let arm = three_link_arm()?;
    let n = arm.joints();
    Ok(arm.with_limits(Limits { joints: vec![joint; n], base: None })?)
}

/// Plans the case again inside a velocity limit that binds ([`arm3_limited_arm`]): the
/// minimum-effort planner honours it as a constraint, both certificates and the limits' use
/// checked as for any plan (Fig. 19, the `arm3_limited` entry of `summary.*`).
pub fn plan_arm3_limited(free: &ArmPlanned) -> Result<ArmPlanned, Error> {
    let request = ArmRequest { torques: true, ..ArmRequest::new(arm3_problem()) };
    plan_arm(&arm3_limited_arm(free)?, Method::Optimal, &request)
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
    /// The use of each declared limit along the verified motion (absent without limits).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limits: Option<LimitReport>,
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
            limits: None,
        };
        let p = match outcome {
            Ok(p) => p,
            Err(e) => {
                row.error = Some(e.to_string());
                return row;
            }
        };
        let v = p.verification();
        row.arm = Some(p.arm.clone());
        row.limits = (!p.limits.uses.is_empty()).then(|| p.limits.clone());
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

    /// The row of the case inside a velocity limit ([`plan_arm3_limited`]): figure
    /// [`ARM3_LIMITED_FIGURE`].
    pub fn limited(outcome: Result<&ArmPlanned, &Error>) -> Self {
        Self { figure: ARM3_LIMITED_FIGURE.into(), ..Self::new(outcome) }
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

/// The limited case, in words (`summary.md`, the page).
pub fn arm3_limited_text(row: &Arm3Row) -> String {
    let limit = row.arm.as_ref().and_then(|a| a.limits.joint(0).velocity);
    format!(
        "The same problem with every joint's speed limited to {:.0} % of the free plan's peak (|θj'| ≤ {} rad/s), \
         by the same planner, which honours the limit as a constraint: the limit binds (its use is 100 %) and the \
         effort rises. Fig. {} draws the limits as dashed lines; its animation draws a joint at ≥ 99 % of its \
         limit, and the link it drives, in red.",
        100.0 * ARM3_VELOCITY_SHARE,
        limit.map_or("-".to_string(), |v| format!("{v:.4}")),
        ARM3_LIMITED_FIGURE.trim_start_matches("fig"),
    )
}

/// The rows of a limit-use table: limit, bound, largest use \[%\], value there, time \[s\].
fn limit_cells(report: &LimitReport) -> Vec<[String; 5]> {
    report
        .uses
        .iter()
        .map(|u| {
            let unit = match u.quantity {
                Quantity::Position => "rad",
                Quantity::Velocity => "rad/s",
                Quantity::Acceleration => "rad/s²",
                Quantity::Torque => "N m",
            };
            let bound = match u.quantity {
                Quantity::Position => format!("[{:.4}, {:.4}] {unit}", u.limit[0], u.limit[1]),
                _ => format!("± {:.4} {unit}", u.limit[1]),
            };
            [
                format!("{} {}", u.name, u.quantity.name()),
                bound,
                format!("{:.2}", 100.0 * u.used),
                format!("{:.5} {unit}", u.value),
                format!("{:.3}", u.time),
            ]
        })
        .collect()
}

const LIMIT_HEADS: [&str; 5] = ["limit", "bound", "largest use [%]", "value there", "at t [s]"];

/// The limited case's section of `summary.md`: its text, its row, and the use of each limit.
pub fn arm3_limited_markdown(row: &Arm3Row) -> String {
    let mut s = format!("\n### Inside a velocity limit (Fig. 19)\n\n{}\n\n", arm3_limited_text(row));
    let heads: Vec<String> = HEADS.iter().map(|h| h.replace('|', "\\|")).collect();
    s += &format!("| {} |\n|{}\n| {} |\n", heads.join(" | "), " --- |".repeat(HEADS.len()), row.cells().join(" | "));
    if let Some(report) = &row.limits {
        s += &format!("\n| {} |\n|{}\n", LIMIT_HEADS.join(" | "), " --- |".repeat(LIMIT_HEADS.len()));
        for cells in limit_cells(report) {
            s += &format!("| {} |\n", cells.join(" | "));
        }
    }
    if let Some(err) = &row.error {
        s += &format!("\nNo plan: {err}\n");
    }
    s
}

/// The limited case's part of the page's 3-link section: its text, its row, and the use of each
/// limit.
pub fn arm3_limited_html(row: &Arm3Row) -> String {
    let mut s = format!(
        "<h3>Inside a velocity limit (<a href=\"#{ARM3_LIMITED_FIGURE}\">Fig. 19</a>)</h3>\n{}",
        arm3_html(row).replacen(
            &format!("<p>{}</p>", escape(&arm3_text().replace('`', ""))),
            &format!("<p>{}</p>", escape(&arm3_limited_text(row))),
            1
        )
    );
    if let Some(report) = &row.limits {
        s += "<div class=\"scroll\"><table class=\"limits\">\n<tr>";
        for h in LIMIT_HEADS {
            s += &head_cell(h);
        }
        s += "</tr>\n";
        for cells in limit_cells(report) {
            s += "<tr>";
            for c in cells {
                s += &format!("<td>{}</td>", escape(&c));
            }
            s += "</tr>\n";
        }
        s += "</table></div>\n";
    }
    s
}

/// Fig. 19: the limited case ([`plan_arm3_limited`]) as [`arm_plan_figure`] draws it, its
/// velocity limits dashed on the rate panel.
pub fn arm3_limited_figure(p: &ArmPlanned) -> PlanFigure {
    let title =
        "Fig. 19 (beyond the paper): the 3-link arm inside a velocity limit (80 % of Fig. 18's peak)".to_string();
    arm_plan_figure(p, title, "examples/robots/three_link.toml, velocity limits")
}

/// Fig. 18: angles, joint velocities (with the base's rate), torques, and the arm's parameters
/// ([`arm_plan_figure`] with the case's title and a note on the torque peaks).
pub fn arm3_figure(p: &ArmPlanned) -> PlanFigure {
    let title = "Fig. 18 (beyond the paper): a 3-link arm, the base turned by 30 deg, minimum effort".to_string();
    let mut figure = arm_plan_figure(p, title, "examples/robots/three_link.toml");
    figure.caption.push(
        "the minimum-effort plan leaves and reaches rest through steep velocity ramps in short end spans: the torque \
         peaks sit at t = 0 and t = T"
            .to_string(),
    );
    figure
}

/// The animation of the case: the arm's points ([`Arm::joint_positions`]) at up to 501 samples.
pub fn arm3_animation(p: &ArmPlanned) -> Animation {
    arm_animation(p, "arm3", ARM3_ANIMATION_TITLE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::arm_figure::arm_limit_bounds;

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

    /// Fig. 19: the velocity limit at 80 % of the free plan's peak binds (its verified use is
    /// 100 %), the plan is certified inside it, and the figure draws exactly `±limit` \[rad/s\]
    /// on the rate panel and nothing on the panels without limits; the markdown lists the use.
    #[test]
    fn the_limited_case_binds_and_its_figure_draws_the_limits() {
        let free = plan_arm3().expect("the 3-link case has a plan");
        let p = plan_arm3_limited(&free).expect("a plan inside the limit");
        p.certified().expect("certified inside every limit");
        let limit = ARM3_VELOCITY_SHARE * peak_velocity(&free);
        let used = p.limits.most_used().expect("limits are declared");
        assert!(used.used > 0.99 && p.limits.inside, "{used:?}");
        assert!(p.effort() > free.effort());
        let figure = arm3_limited_figure(&p);
        let values: Vec<f64> = figure.panels[1].bounds.iter().map(|b| b.value).collect();
        assert_eq!(values.len(), 6, "± the limit of each of 3 joints");
        for (k, v) in values.iter().enumerate() {
            let expected = if k % 2 == 0 { limit } else { -limit };
            assert!((v - expected).abs() <= 1e-15 * limit, "{v} vs {expected}");
        }
        let series: Vec<Option<usize>> = figure.panels[1].bounds.iter().map(|b| b.series).collect();
        assert_eq!(series, [Some(0), Some(0), Some(1), Some(1), Some(2), Some(2)]);
        assert!(figure.panels[0].bounds.is_empty() && figure.panels[2].bounds.is_empty());
        assert!(figure.caption.iter().any(|c| c.contains("velocity limit")), "{:?}", figure.caption);
        // The free plan's figure has no limits to draw.
        assert!(arm3_figure(&free).panels.iter().all(|panel| panel.bounds.is_empty()));
        let row = Arm3Row::limited(Ok(&p));
        let md = arm3_limited_markdown(&row);
        assert!(md.contains("theta1 velocity") && md.contains("largest use"), "{md}");
        let svg = crate::report::plot::plan_picture(&figure, crate::report::plot::PictureFormat::Svg, "x.svg".as_ref())
            .expect("renders");
        let svg = String::from_utf8(svg).expect("UTF-8");
        let doc = roxmltree::Document::parse(&svg).expect("the SVG parses");
        let legend = doc
            .descendants()
            .filter(|n| n.has_tag_name("text") && n.text().map(str::trim) == Some("limits (dashed)"))
            .count();
        let texts: Vec<&str> =
            doc.descendants().filter_map(|n| n.has_tag_name("text").then(|| n.text()).flatten()).collect();
        assert_eq!(legend, 1, "one legend entry for the joints' limits: {texts:?}");
    }

    /// The angle panel draws a joint's position range in degrees (the panel's unit) and the
    /// base's range on φ's colour; the torque panel `±` the torque limit \[N m\].
    #[test]
    fn limit_bounds_are_in_the_panels_units() {
        let joint = JointLimits { position: Some([-1.0, 2.0]), torque: Some(7.0), ..JointLimits::default() };
        let arm = three_link_arm()
            .unwrap()
            .with_limits(Limits {
                joints: vec![joint, JointLimits::default(), JointLimits::default()],
                base: Some([-0.5, 0.5]),
            })
            .unwrap();
        let [angles, rates, torques] = arm_limit_bounds(&arm);
        let got: Vec<(f64, Option<usize>)> = angles.iter().map(|b| (b.value, b.series)).collect();
        let deg = f64::to_degrees;
        let want = [(deg(-0.5), Some(0)), (deg(0.5), Some(0)), (deg(-1.0), Some(1)), (deg(2.0), Some(1))];
        assert_eq!(got.len(), want.len());
        for ((v, s), (w, t)) in got.iter().zip(want) {
            assert!((v - w).abs() < 1e-12 && *s == t, "{v} {s:?} vs {w} {t:?}");
        }
        assert!(rates.is_empty());
        let t: Vec<f64> = torques.iter().map(|b| b.value).collect();
        assert!(t.len() == 2 && (t[0] - 7.0).abs() < 1e-15 && (t[1] + 7.0).abs() < 1e-15, "{t:?}");
    }

    /// A joint is highlighted in exactly the frames where its exact speed uses ≥ 99 % of its
    /// limit: such frames exist (the limit binds), the first (at rest) is not one; the GIF's
    /// frame is drawn in the highlight colour only then; the page's animation lists the same
    /// joints, and the free plan's none.
    #[test]
    fn a_joint_at_its_limit_is_highlighted() {
        use crate::report::plot::{AT_LIMIT_COLOUR, GifOptions, GifView};
        let free = plan_arm3().expect("the 3-link case has a plan");
        let p = plan_arm3_limited(&free).expect("a plan inside the limit");
        let limit = p.arm.limits.joint(0).velocity.expect("a velocity limit");
        let view = GifView::arm(&p, &GifOptions::default());
        let (mut theta, mut rate) = ([0.0; 3], [0.0; 3]);
        let (mut hot, mut cold) = (None, None);
        for (k, (t, _)) in view.frames().iter().enumerate() {
            p.plan.motion().joint_state(*t, &mut theta, &mut rate);
            let marks = view.at_limit(k);
            for j in 0..3 {
                let used = rate[j].abs() / limit;
                assert_eq!(marks[j], used >= 0.99, "frame {k} joint {} use {used}", j + 1);
                if used >= 0.99 {
                    hot = Some(k);
                }
                if used < 0.5 && marks.iter().all(|m| !m) {
                    cold.get_or_insert(k);
                }
            }
        }
        let (hot, cold) = (hot.expect("a frame at the limit"), cold.expect("a frame far below it"));
        assert_eq!(cold, 0, "at rest at t = 0");
        // The joint's marker (the legend's swatch is a stroke in every frame).
        let colour = format!("fill=\"{AT_LIMIT_COLOUR}\"");
        assert!(view.svg("t", hot).contains(&colour));
        assert!(!view.svg("t", cold).contains(&colour));
        // Without limits, nothing is ever highlighted.
        let free_view = GifView::arm(&free, &GifOptions::default());
        assert!((0..free_view.frames().len()).all(|k| free_view.at_limit(k).iter().all(|m| !m)));
        assert!(arm3_animation(&free).at_limit.is_empty());
        let anim = arm_animation(&p, "arm3-limits", ARM3_LIMITED_ANIMATION_TITLE);
        assert_eq!(anim.at_limit.len(), anim.t.len());
        assert!(anim.at_limit.iter().any(|joints| !joints.is_empty()) && anim.at_limit[0].is_empty());
    }
}
