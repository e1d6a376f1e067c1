//! The clearance rows of the planner (issue 21 item 4): their derivatives are those of their
//! values; the search's last resort finds a clear plan where the search with the rows did not. (That a colliding plan becomes collision-free, judged by the certificate on the
//! integrated motion, is tested on the SPART-like fixture in tests/it/geometry.rs.)

use nalgebra::DVector;

use super::discrete::Targets;
use super::tests::three_link;
use super::*;
use crate::model::Mount;
use crate::model::arm::collision::Geometry;
use crate::model::arm::{Base, Link};
use crate::model::geometry::Shape;
use crate::planners::optimal::sqp::Discretised;

/// The 3-link arm with capsule links of width 4 cm.
fn with_links(arm: Arm, obstacles: Vec<Shape>, clearance: f64) -> Arm {
    let links = arm.links.iter().map(|l| vec![Shape::capsule([0.0, 0.0], [l.length, 0.0], 0.02).unwrap()]).collect();
    let geometry = Geometry { links, obstacles, clearance, ..Default::default() };
    arm.with_geometry(geometry).expect("valid geometry")
}

fn problem() -> ChainProblem {
    let deg = |v: [f64; 4]| v.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
    ChainProblem::rest_to_rest(deg([0.0, 20.0, 40.0, -30.0]), deg([40.0, 120.0, -30.0, 60.0]), 8.0)
}

/// The clearance rows' gradients agree with central differences of their values to 1e-6
/// relative, at a point of a coarse discretisation of the 3-link problem: the rows of the
/// robot's own bodies (local in the coefficients) and the rows against an obstacle (through
/// `phi(t)`, whose gradient reaches every earlier coefficient). A body more than
/// `NEAR` = 0.1 m from the obstacle keeps its row without a gradient (by design: it cannot
/// become active in one step), so such rows are left out of the comparison; the obstacle is
/// placed where some rows are near, and those must reach coefficients outside their own span.
#[test]
fn clearance_rows_derivatives_match_central_differences() {
    let obstacle = Shape::circle([0.5, 0.3], 0.1).unwrap();
    let arm = with_links(three_link(), vec![obstacle], 0.0);
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let problem = problem();
    let targets = Targets {
        start: problem.start[1..].to_vec(),
        initial_velocity: vec![0.0; 3],
        end: problem.goal[1..].to_vec(),
        phi_start: problem.start[0],
        phi_end: problem.goal[0],
    };
    let disc = planner.discretise(&problem, targets, 8, 8, &Default::default()).expect("discretises");
    let x = DVector::from_fn(disc.dim(), |i, _| 0.3 * (i as f64 * 0.7).sin());
    let limited = super::limits::Limited::new(&planner, &disc).expect("clamped basis");
    let at = limited.inequalities(&x, 1).expect("rows");
    assert!(!at.values.is_empty());
    // Rows of width beyond one span's (p + 1) n = 12 coefficients: an obstacle's, through phi(t).
    let dense = at.rows.iter().filter(|r| r.len() > 12).count();
    assert!(dense > 0, "no obstacle row carries phi's gradient");
    let h = 1e-6;
    for k in [0, 3, 7, disc.dim() / 2, disc.dim() - 1] {
        let mut up = x.clone();
        up[k] += h;
        let mut down = x.clone();
        down[k] -= h;
        let (gu, gd) = (limited.inequalities(&up, 0).unwrap(), limited.inequalities(&down, 0).unwrap());
        for (i, row) in at.rows.iter().enumerate().filter(|(_, r)| !r.is_empty()) {
            let exact: f64 = row.iter().filter(|(j, _)| *j == k).map(|(_, v)| v).sum();
            let numeric = (gu.values[i] - gd.values[i]) / (2.0 * h);
            assert!((exact - numeric).abs() <= 1e-6 * (1.0 + numeric.abs()), "row {i}, x[{k}]: {exact} vs {numeric}");
        }
    }
}

/// The rows of the robot's own bodies hold at the denser points only in the knot spans that
/// meet a window of `ChainPlanner::clearance_dense` (the re-solve of a dip, `keep_clear.rs`), at
/// `CLEARANCE_PIECES` elsewhere: on the 3-link arm's coarse basis, a window inside one span adds
/// one span's share of what the denser rows everywhere add (every pair, 12 points more a span),
/// and a window that is that span's closed interval the same (its neighbours only touch it).
#[test]
fn denser_rows_only_in_the_windows_spans() {
    let arm = with_links(three_link(), Vec::new(), 0.0);
    let problem = problem();
    let targets = Targets {
        start: problem.start[1..].to_vec(),
        initial_velocity: vec![0.0; 3],
        end: problem.goal[1..].to_vec(),
        phi_start: problem.start[0],
        phi_end: problem.goal[0],
    };
    let sparse = ChainPlanner::new(arm, ChainOptions::default());
    let disc = sparse.discretise(&problem, targets, 8, 8, &Default::default()).expect("discretises");
    let b = disc.basis().breakpoints().to_vec();
    let x = DVector::from_fn(disc.dim(), |i, _| 0.3 * (i as f64 * 0.7).sin());
    let rows = |dense: Option<Vec<[f64; 2]>>, pieces: usize| {
        let planner =
            ChainPlanner { clearance_pieces: pieces, clearance_dense: dense.map(Into::into), ..sparse.clone() };
        let limited = super::limits::Limited::new(&planner, &disc).expect("clamped basis");
        limited.inequalities(&x, 0).expect("rows").values.len()
    };
    let four = rows(None, super::limits::CLEARANCE_PIECES);
    let everywhere = rows(None, 16);
    let h = b[4] - b[3];
    let inside = rows(Some(vec![[b[3] + 0.1 * h, b[3] + 0.2 * h]]), 16);
    assert!(inside > four, "no denser rows in the window's span");
    assert_eq!(everywhere - four, (b.len() - 1) * (inside - four), "rows {four}, {inside}, {everywhere}");
    assert_eq!(rows(Some(vec![[b[3], b[4]]]), 16), inside, "a window's ends reach into its neighbours");
}

/// The 3-link example (examples/robots/three_link.toml, capsule links) around an obstacle that
/// its unconstrained plan crosses by 0.069 m.
fn around_the_obstacle(clearance: f64) -> (Arm, ChainProblem) {
    use crate::model::arm::collision::Body;
    let deg = |v: [f64; 4]| v.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
    let path = std::path::Path::new("examples/robots/three_link.toml");
    let toml = Arm::from_toml(include_str!("../../../examples/robots/three_link.toml"), path).unwrap();
    let obstacle = Shape::circle([-0.4, 0.1], 0.05).unwrap();
    let mut arm = with_links(toml, vec![obstacle], clearance);
    arm.geometry.excluded.push((Body::Link(1), Body::Link(3)));
    (arm, ChainProblem::rest_to_rest(deg([0.0, 0.0, 30.0, 30.0]), deg([20.0, 90.0, 30.0, -30.0]), 8.0))
}

/// At 0.01 m the repair of the unconstrained plan stalls off the holonomy (3e-4 rad); done in
/// two steps, to touching and from there to 0.01 m, it gives a plan clear by 0.01 m on the
/// integrated motion (before: the colliding plan, exit 3).
#[test]
fn a_stalled_repair_is_done_in_two_steps() {
    let (arm, problem) = around_the_obstacle(0.01);
    let planner = ChainPlanner::new(arm, ChainOptions::default());
    let free = ChainPlanner { clearance_rows: false, ..planner.clone() }.plan(&problem).unwrap();
    assert!(free.verification.clearance.unwrap().min < 0.0, "the unconstrained plan crosses the obstacle");
    let plan = planner.plan(&problem).unwrap();
    let v = &plan.verification;
    let clearance = v.clearance.expect("the arm has shapes");
    assert!(v.certified && clearance.holds(), "certified {}, clearance {:?}", v.certified, clearance);
}

/// The shortest horizon keeps the clearance (issue 20 item 4 with issue 21): the arm of
/// [`around_the_obstacle`] at 0.01 m, its joints limited to 20 deg/s. The plan at the horizon found is
/// certified on the integrated motion, inside every limit and clear of the obstacle by the
/// clearance asked for; the horizon is within 1 % of the largest known to fail.
#[test]
fn the_shortest_horizon_keeps_the_clearance() {
    use crate::model::arm::{JointLimits, Limits};
    let (arm, problem) = around_the_obstacle(0.01);
    let planner = ChainPlanner::new(arm.clone(), ChainOptions::default());
    let free = ChainPlanner { clearance_rows: false, ..planner }.plan(&problem).unwrap();
    let free_clearance = free.verification.clearance.unwrap();
    assert!(free_clearance.min < 0.0, "the unconstrained plan crosses the obstacle: {free_clearance:?}");
    let joint = JointLimits { velocity: Some(20f64.to_radians()), ..Default::default() };
    let limited = arm.with_limits(Limits { joints: vec![joint; 3], base: None }).unwrap();
    let s = ChainPlanner::new(limited, ChainOptions::default()).shortest_horizon(&problem).expect("a horizon");
    let v = &s.plan.verification;
    let clearance = v.clearance.expect("the arm has shapes");
    assert!(v.certified && clearance.holds(), "certified {}, clearance {:?}", v.certified, clearance);
    assert!(v.limits.as_ref().is_some_and(|l| l.inside), "limits {:?}", v.limits);
    assert!(s.horizon <= s.infeasible_below * 1.01 + 1e-12, "{} / {}", s.horizon, s.infeasible_below);
    eprintln!(
        "auto with clearance: T = {:.4} s ({} probes, {:.0} ms), clearance {:.4} m (unconstrained plan: {:.4} m)",
        s.horizon,
        s.probes,
        1e3 * s.seconds,
        clearance.min,
        free_clearance.min
    );
}

/// The first of `examples/profile_clearance.rs random`'s problems on the SPART-like fixture
/// (rate limits lifted) at 0.02 m: the free plan passes 0.256 m inside the base and the search
/// with the rows stalls from every seed (it returned that colliding plan before the last resort,
/// [`ChainPlanner::soft_search`]); the plan is certified and keeps the clearance on the
/// integrated motion.
#[test]
fn the_last_resort_clears_where_the_search_with_rows_stalls() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/spart_like_4dof_geometry.urdf");
    let mut arm = Arm::from_urdf_str(&std::fs::read_to_string(path).unwrap(), path.as_ref()).unwrap();
    for j in &mut arm.limits.joints {
        (j.velocity, j.torque, j.acceleration) = (None, None, None);
    }
    arm.geometry.clearance = 0.02;
    let (start, goal) = super::tests_clearance_oracle::random_problem();
    let plan = ChainPlanner::new(arm, ChainOptions::default())
        .plan(&ChainProblem::rest_to_rest(start, goal, 10.0))
        .expect("a plan");
    let report = plan.verification.clearance.expect("shapes");
    assert!(plan.verification.certified, "not certified");
    assert!(report.holds() && report.min >= 0.02, "least clearance {}", report.min);
}

/// `freefloat track`'s first plan on the SPART-like tight fixture (its shapes from `<visual>`,
/// its limits less `track`'s 5 % headroom) from (0, 30, -60, 45, -30) to (30, 60, -30, 20, -60)
/// deg in 24 s, keeping 0.015 m: the search with the rows certifies a plan that dips to
/// 0.008 m between the rows' points, and its re-solves keeping more stalled (the planner
/// returned that plan, under the clearance). The dip is now solved again on denser rows at the clearance asked too;
/// that re-solve stalls 1.3e-6 rad off the holonomy and is moved onto it
/// (`limits::onto_holonomy`), a plan kept for the end of the search. The plan must be certified,
/// clear on the integrated motion and inside every limit.
#[test]
fn a_dip_between_the_rows_is_solved_again_on_denser_rows() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/spart_like_4dof_tight.urdf");
    let mut arm = Arm::from_urdf_str(&std::fs::read_to_string(path).unwrap(), path.as_ref()).unwrap();
    let deg = |v: [f64; 5]| v.iter().map(|x| x.to_radians()).collect::<Vec<_>>();
    let problem =
        ChainProblem::rest_to_rest(deg([0.0, 30.0, -60.0, 45.0, -30.0]), deg([30.0, 60.0, -30.0, 20.0, -60.0]), 24.0);
    arm.limits = arm.limits.with_headroom(0.05, &[problem.start.as_slice(), problem.goal.as_slice()], &[]);
    arm.geometry.clearance = 0.015;
    let plan = ChainPlanner::new(arm, ChainOptions::default()).plan(&problem).expect("a plan");
    let report = plan.verification.clearance.expect("shapes");
    assert!(plan.verification.certified, "not certified: final error {}", plan.verification.final_error);
    assert!(report.holds() && report.min >= 0.015, "least clearance {}", report.min);
    assert!(plan.verification.limits.as_ref().is_some_and(|l| l.inside), "outside a limit");
}

/// A plan from a state inside the clearance it should keep wins the clearance back
/// ([`ClearanceRise`], a re-plan of `track` from inside its margin): the 3-link problem of
/// [`around_the_obstacle`] with the obstacle moved to 0.01 m from the start, where the tool
/// heads at first. Planned keeping 0.03 m more than the clearance asked (none) from 1 s on,
/// rising linearly from none at the start, the plan is certified, and at 2000 times of its
/// motion it keeps what the rise asks at that time (the rows keep 1e-3 m more than asked, for
/// the dip between their points), so 0.03 m from 1 s on; the plan without the rise comes under
/// 0.03 m after 1 s (so the rise has work to do).
#[test]
fn a_plan_from_inside_the_margin_wins_it_back() {
    let (arm, problem) = around_the_obstacle(0.0);
    let free = ChainPlanner::new(arm.clone(), ChainOptions::default());
    let free = ChainPlanner { clearance_rows: false, ..free }.plan(&problem).unwrap();
    let q = |p: &ChainPlan, t: f64| {
        let at = p.at(t);
        std::iter::once(at.phi).chain(at.theta.iter().copied()).collect::<Vec<f64>>()
    };
    let (t0, t1) = (arm.tool_point(&problem.start), arm.tool_point(&q(&free, 0.5)));
    let way = [t1[0] - t0[0], t1[1] - t0[1]];
    let norm = way[0].hypot(way[1]);
    // The obstacle's centre on the tool's way, where the start's clearance is 0.01 m.
    let placed = |s: f64| {
        let centre = [t0[0] + s * way[0] / norm, t0[1] + s * way[1] / norm];
        let mut arm = arm.clone();
        arm.geometry.obstacles = vec![Shape::circle(centre, 0.05).unwrap()];
        arm
    };
    let start_clearance = |s: f64| {
        let arm = placed(s);
        arm.geometry.min_clearance(&arm, &problem.start).unwrap().distance
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if start_clearance(mid) < 0.01 { lo = mid } else { hi = mid }
    }
    let arm = placed(hi);
    assert!((start_clearance(hi) - 0.01).abs() < 1e-9);
    let clearance = |p: &ChainPlan, t: f64| arm.geometry.min_clearance(&arm, &q(p, t)).unwrap().distance;
    let rise = ClearanceRise { extra: 0.03, over: 1.0 };
    let times = || (0..=2000).map(|i| problem.horizon * i as f64 / 2000.0);
    let plain = ChainPlanner::new(arm.clone(), ChainOptions::default()).plan(&problem).unwrap();
    let least_after = times().filter(|&t| t >= 1.0).map(|t| clearance(&plain, t)).fold(f64::INFINITY, f64::min);
    assert!(least_after < 0.03, "without the rise: {least_after} m after 1 s");
    let options = ChainOptions { clearance_rise: rise, ..Default::default() };
    let plan = ChainPlanner::new(arm.clone(), options).plan(&problem).unwrap();
    assert!(plan.verification.certified && plan.verification.collision().is_ok(), "{:?}", plan.verification);
    let worst = times()
        .map(|t| (clearance(&plan, t) - rise.at(t), t))
        .fold((f64::INFINITY, 0.0), |m, x| if x.0 < m.0 { x } else { m });
    eprintln!(
        "least after 1 s: {least_after} m without the rise; worst {worst:?}, effort {} against {}",
        plan.effort(),
        plain.effort()
    );
    assert!(worst.0 >= 0.0, "under the rise by {} m at t = {} s", -worst.0, worst.1);
}

/// A 2-link arm whose 0.6 m link 2 is longer than the 0.3 m link 1 plus the base's half width
/// (base box 0.4 m x 0.4 m, mount a = 0.2 m, 4 cm capsules): folding joint 2 through 180 deg
/// passes link 2 through the base.
pub(super) fn fold_arm() -> Arm {
    let capsule = |l: f64| vec![Shape::capsule([0.0, 0.0], [l, 0.0], 0.02).unwrap()];
    let arm = Arm {
        base: Base { mass: 10.0, inertia: 0.2 },
        mount: Mount { a: 0.2, b: 0.0 },
        links: vec![
            Link { length: 0.3, com: 0.15, mass: 1.0, inertia: 0.0075 },
            Link { length: 0.6, com: 0.3, mass: 1.0, inertia: 0.03 },
        ],
        limits: Default::default(),
        geometry: Default::default(),
    };
    let base = vec![Shape::rectangle([0.0, 0.0], [0.4, 0.4]).unwrap()];
    let geometry = Geometry { base, links: vec![capsule(0.3), capsule(0.6)], ..Default::default() };
    arm.with_geometry(geometry).expect("valid geometry")
}

/// A 2-link arm whose 0.6 m link 2 is longer than the 0.3 m link 1 plus the base's half width:
/// folded back (theta2 = 180 deg) it reaches 0.1 m past the centre of the 0.4 m x 0.4 m base
/// box. From theta2 = 120 to -120 deg the short way (through 180 deg, the free plan's) passes
/// through the base; the long way (through 0, 240 deg of travel) clears it. The search with the
/// rows stalled on the long way's line (101 rad^2/s at its iteration cap) and the last resort
/// tried the free plan's representative only: the planner returned the short way, 0.22 m into
/// the base (stop 61). The plan must now be certified, clear on the integrated motion, and reach
/// theta2 = -120 deg the long way: its joint 2 ends 240 deg below its start.
#[test]
fn the_last_resort_tries_the_other_clear_lines() {
    let arm = fold_arm();
    let problem =
        ChainProblem::rest_to_rest(vec![0.0, 0.0, 120f64.to_radians()], vec![0.0, 0.0, -120f64.to_radians()], 6.0);
    let plan = ChainPlanner::new(arm, ChainOptions::default()).plan(&problem).expect("a plan");
    let report = plan.verification.clearance.expect("shapes");
    assert!(plan.verification.certified, "not certified");
    assert!(
        report.holds() && report.min >= 0.0,
        "least clearance {} between {} and {}",
        report.min,
        report.a,
        report.b
    );
    let travel = plan.at(6.0).theta[1] - problem.start[2];
    assert!((travel + 240f64.to_radians()).abs() < 1e-6, "joint 2 moved {} deg", travel.to_degrees());
}
