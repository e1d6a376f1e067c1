//! Tests of the mounting-point sweep (Sec. 6, item 3): shards merge to the whole, the global
//! rate's column, common random numbers, spans.

use super::*;
use crate::plan::Method;
use crate::planners::arm::{ArmRequest, plan_arm};
use crate::planners::chain::ChainProblem;

fn small() -> SweepOptions {
    SweepOptions {
        a: Span::new("a", -0.3, 0.3, 3).unwrap(),
        b: Span::new("b", -0.2, 0.2, 3).unwrap(),
        grid: 64,
        trials: 6,
        seed: 7,
        ..Default::default()
    }
}

/// `--shard 1/2` + `--shard 2/2` + merge equals the unsharded result exactly, through CSV.
#[test]
fn shards_merge_to_the_whole() {
    let robot = Arm::from_params(&RobotParams::src());
    let options = small();
    let whole = run(&robot, &options, Shard::ALL, &|| {}).unwrap();
    assert_eq!(whole.len(), 9);
    let p = std::path::Path::new("x.csv");
    let mut parts = Vec::new();
    for k in [2, 1] {
        let rows = run(&robot, &options, Shard { k, n: 2 }, &|| {}).unwrap();
        parts.extend(from_csv(&to_csv(&rows).unwrap(), p).unwrap());
    }
    let merged = merge(parts).unwrap();
    assert_eq!(merged, whole);
    assert_eq!(to_csv(&merged).unwrap(), to_csv(&whole).unwrap());
    // The centre point (a = b = 0) has every transformation, the others Eq. (14) only.
    assert!(whole[4].eq12_rate.is_some() && whole[4].eq11_rate.is_some());
    assert_eq!((whole[4].a, whole[4].b), (0.0, 0.0));
    assert!(whole[0].eq12_rate.is_none());
    // Missing or conflicting shards are errors.
    assert!(merge(whole[1..].to_vec()).is_err());
    let mut other = whole.clone();
    other[3].eq14_successes = other[3].eq14_successes.map(|s| s + 1);
    assert!(merge(whole.iter().cloned().chain(std::iter::once(other[3].clone()))).is_err());
}

/// With `global`, the global normal form is rated too (a column of its own, through CSV and
/// merge), and beyond the paper it plans far more pairs than Eq. (14) at a large offset.
#[test]
fn global_rate_is_a_column_of_its_own() {
    let robot = Arm::from_params(&RobotParams::src());
    let options = SweepOptions {
        a: Span::new("a", 1.0, 1.0, 1).unwrap(),
        b: Span::new("b", -1.0, -1.0, 1).unwrap(),
        grid: 32,
        trials: 12,
        global: true,
        ..Default::default()
    };
    let rows = run(&robot, &options, Shard::ALL, &|| {}).unwrap();
    let back = from_csv(&to_csv(&rows).unwrap(), std::path::Path::new("g.csv")).unwrap();
    assert_eq!(merge(back).unwrap(), rows);
    let (global, eq14) = (rows[0].global_successes.unwrap(), rows[0].eq14_successes.unwrap());
    assert!(global > eq14, "global {global} vs eq14 {eq14}");
    assert!(!small().global);
}

#[test]
fn pairs_are_deterministic_uniform_and_independent_of_order() {
    let (s, g) = trial_pair(3, 41);
    assert_eq!(trial_pair(3, 41), (s, g));
    assert_ne!(trial_pair(4, 41).0, s);
    for q in [s, g] {
        assert!(q.is_finite());
    }
    for i in 0..3 {
        let d = (g.to_array()[i] - s.to_array()[i]).abs();
        assert!(d < std::f64::consts::PI);
    }
    // Mean of many draws ~ 1/2, all in [0, 1).
    let xs: Vec<f64> = (0..20_000).map(|k| uniform(1, k, 0)).collect();
    assert!(xs.iter().all(|&x| (0.0..1.0).contains(&x)));
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    assert!((mean - 0.5).abs() < 0.01, "{mean}");
}

#[test]
#[allow(clippy::float_cmp)] // exactness is the property tested: a = 0 exactly in the middle
fn shards_and_spans() {
    assert_eq!(Shard::parse("2/3").unwrap(), Shard { k: 2, n: 3 });
    for bad in ["0/2", "3/2", "x", "1/0", "1/"] {
        assert!(Shard::parse(bad).is_err(), "{bad}");
    }
    assert_eq!(Shard { k: 2, n: 3 }.indices(8).collect::<Vec<_>>(), vec![1, 4, 7]);
    let s = Span::new("a", -0.3, 0.3, 41).unwrap();
    assert_eq!(s.value(20), 0.0);
    assert_eq!((s.value(0), s.value(40)), (-0.3, 0.3));
    assert!(Span::new("a", 0.3, -0.3, 3).is_err());
    assert!(Span::new("a", -0.3, 0.3, 1).is_err());
}

/// The checked file: written and read back equal; a row whose numbers are edited, even with
/// its check recomputed, is refused for its numbers (non-finite, rate not count / trials).
#[test]
fn sweep_file_round_trip_and_row_checks() {
    let robot = Arm::from_params(&RobotParams::src());
    let options = SweepOptions { grid: 16, trials: 2, ..small() };
    let rows = run(&robot, &options, Shard::ALL, &|| {}).unwrap();
    let run_line = file::run_description(&robot, &options);
    let p = std::path::Path::new("s.csv");
    let bytes = file::write(&run_line, Shard::ALL, &rows).unwrap();
    let back = file::read(&bytes, p).unwrap();
    assert_eq!((back.rows.clone(), back.shard, back.run.clone()), (rows.clone(), Shard::ALL, run_line.clone()));
    let merged = file::merge_files(vec![(p.to_path_buf(), back)]).unwrap();
    assert_eq!(file::write(&merged.run, merged.shard, &merged.rows).unwrap(), bytes);
    let mut nan = rows.clone();
    nan[1].start_component_fraction = Some(f64::NAN);
    let e = file::read(&file::write(&run_line, Shard::ALL, &nan).unwrap(), p).unwrap_err().to_string();
    assert!(e.contains("line 5") && e.contains("not a finite number"), "{e}");
    let mut rate = rows.clone();
    rate[2].eq14_rate = Some(0.75);
    let e = file::read(&file::write(&run_line, Shard::ALL, &rate).unwrap(), p).unwrap_err().to_string();
    assert!(e.contains("line 6") && e.contains("do not give the rate"), "{e}");
    // An empty shard still has its header lines.
    let empty = file::write(&run_line, Shard { k: 10, n: 10 }, &[]).unwrap();
    assert_eq!(String::from_utf8(empty.clone()).unwrap().lines().count(), 3);
    assert!(file::read(&empty, p).unwrap().rows.is_empty());
}

/// Every link's inertia is part of a sweep's identity: a run of another robot is another run.
#[test]
fn link_inertias_are_part_of_the_run() {
    let robot = RobotParams::src();
    let run = file::run_description(&Arm::from_params(&robot), &small());
    let heavy = RobotParams { i1: 0.01, ..robot };
    assert_ne!(file::run_description(&Arm::from_params(&heavy), &small()), run);
}

/// A 3-link arm with its centres of mass at half length.
fn three_link() -> Arm {
    use crate::model::arm::{Base, Link};
    let links = [(0.4, 2.0), (0.35, 1.5), (0.25, 0.8)]
        .map(|(l, m)| Link { length: l, com: l / 2.0, mass: m, inertia: m * l * l / 12.0 })
        .to_vec();
    Arm::new(Base { mass: 15.0, inertia: 0.5 }, Mount::default(), links).unwrap()
}

fn effort_options() -> SweepOptions {
    SweepOptions {
        a: Span::new("a", -0.2, 0.2, 2).unwrap(),
        b: Span::new("b", 0.0, 0.3, 2).unwrap(),
        start: vec![0.0, 0.3, -0.2, 0.5],
        goal: vec![0.5, -0.4, 0.6, 0.2],
        nfa: false,
        effort: true,
        ..Default::default()
    }
}

/// The effort metric serves any arm: at every point of a 3-link sweep the effort is that of the
/// certified minimum-effort plan of the reference problem for the arm mounted there (planned
/// separately), the NFA's columns are empty, and shards and the checked file reproduce the
/// whole; the NFA's metric for this arm is bad input naming the reason.
#[test]
fn the_effort_metric_serves_a_three_link_arm() {
    let arm = three_link();
    let options = effort_options();
    let rows = run(&arm, &options, Shard::ALL, &|| {}).unwrap();
    assert_eq!(rows.len(), 4);
    for r in &rows {
        assert_eq!(r.planned, Some(true), "{r:?}");
        assert!(r.eq14_rate.is_none() && r.components.is_none() && r.best_rate().is_none());
        let mounted = Arm::new(arm.base, Mount::new(r.a, r.b).unwrap(), arm.links.clone()).unwrap();
        let problem = ChainProblem::rest_to_rest(options.start.clone(), options.goal.clone(), options.horizon);
        let alone = plan_arm(&mounted, Method::Optimal, &ArmRequest::new(problem)).unwrap();
        assert!((r.effort.unwrap() - alone.effort()).abs() <= 1e-9 * alone.effort(), "{r:?} vs {}", alone.effort());
    }
    // The mount changes the effort (the metric sees the design choice).
    let efforts: Vec<f64> = rows.iter().map(|r| r.effort.unwrap()).collect();
    assert!(efforts.iter().any(|e| (e - efforts[0]).abs() > 1e-6 * efforts[0]), "{efforts:?}");
    let least = least_effort(&rows).unwrap();
    assert!(rows.iter().all(|r| r.effort.unwrap() >= least.effort.unwrap()));
    let mut parts = run(&arm, &options, Shard { k: 2, n: 2 }, &|| {}).unwrap();
    parts.extend(run(&arm, &options, Shard { k: 1, n: 2 }, &|| {}).unwrap());
    assert_eq!(merge(parts).unwrap(), rows);
    let run_line = file::run_description(&arm, &options);
    let p = std::path::Path::new("e.csv");
    let bytes = file::write(&run_line, Shard::ALL, &rows).unwrap();
    assert_eq!(file::read(&bytes, p).unwrap().rows, rows);
    let mut broken = rows.clone();
    broken[0].effort = None;
    let e = file::read(&file::write(&run_line, Shard::ALL, &broken).unwrap(), p).unwrap_err().to_string();
    assert!(e.contains("planned and effort disagree"), "{e}");
    let nfa = SweepOptions { nfa: true, ..options.clone() };
    let e = run(&arm, &nfa, Shard::ALL, &|| {}).unwrap_err();
    assert!(matches!(e, Error::Input(_)) && e.to_string().contains("two joints"), "{e}");
    let short = SweepOptions { start: vec![0.0; 3], goal: vec![0.0; 3], ..options };
    assert!(matches!(run(&arm, &short, Shard::ALL, &|| {}), Err(Error::Input(_))));
}

/// At n = 2 the effort metric adds its columns and leaves the NFA's exactly as without it.
#[test]
fn the_effort_metric_leaves_the_nfa_columns_alone() {
    let robot = Arm::from_params(&RobotParams::src());
    let options = SweepOptions { grid: 16, trials: 3, ..small() };
    let nfa = run(&robot, &options, Shard { k: 1, n: 4 }, &|| {}).unwrap();
    let both = run(&robot, &SweepOptions { effort: true, ..options }, Shard { k: 1, n: 4 }, &|| {}).unwrap();
    for (x, y) in nfa.iter().zip(&both) {
        assert_eq!(SweepRow { planned: None, effort: None, ..y.clone() }, *x);
        assert_eq!(y.planned, Some(true));
        assert!(y.effort.unwrap() > 0.0);
    }
}

/// The sweep plans the robot it is given: before, each point's arm was rebuilt from its masses
/// and lengths only, so a declared velocity limit and the bodies' shapes were dropped without a
/// word. At every point the effort is now that of the plan inside the limit (the arm mounted
/// there planned alone; not the free plan's, which breaks the limit); a mount where an end
/// brings a link into the base is a point without a plan, not a failed sweep; and the run's
/// description names the limits and the shapes (another robot, another run), unchanged without.
#[test]
fn the_effort_metric_keeps_the_robots_limits_and_shapes() {
    use crate::model::arm::collision::Geometry;
    use crate::model::arm::{JointLimits, Limits};
    use crate::model::geometry::Shape;
    use crate::planners::arm::ArmPlanned;
    let (free, options) = (three_link(), effort_options());
    let problem = ChainProblem::rest_to_rest(options.start.clone(), options.goal.clone(), options.horizon);
    let mounted = |arm: &Arm, a: f64, b: f64| Arm { mount: Mount::new(a, b).unwrap(), ..arm.clone() };
    let alone = |arm: &Arm| plan_arm(arm, Method::Optimal, &ArmRequest::new(problem.clone()));
    let points: Vec<(f64, f64)> = (0..options.points()).map(|i| options.mount(i)).collect();
    // 90 % of the least peak joint speed of the free plans: every free plan breaks it.
    let peak = |p: &ArmPlanned| p.trajectory.iter().flat_map(|q| q.rate.iter().map(|u| u.abs())).fold(0.0, f64::max);
    let free_plans: Vec<ArmPlanned> = points.iter().map(|&(a, b)| alone(&mounted(&free, a, b)).unwrap()).collect();
    let v = 0.9 * free_plans.iter().map(peak).fold(f64::INFINITY, f64::min);
    let joint = JointLimits { velocity: Some(v), ..JointLimits::default() };
    let limited = free.clone().with_limits(Limits { joints: vec![joint; 3], base: None }).unwrap();
    let rows = run(&limited, &options, Shard::ALL, &|| {}).unwrap();
    let mut planned = 0;
    for ((r, &(a, b)), f) in rows.iter().zip(&points).zip(&free_plans) {
        match alone(&mounted(&limited, a, b)) {
            Ok(inside) => {
                assert!(inside.certified().is_ok() && peak(&inside) <= v * (1.0 + 1e-9), "{r:?}");
                let e = inside.effort();
                assert!((r.effort.unwrap() - e).abs() <= 1e-9 * e, "{r:?} vs {e}");
                // Not the free plan's effort: that plan breaks the limit (its peak is above v).
                assert!(peak(f) > v && (r.effort.unwrap() - f.effort()).abs() > 1e-9 * f.effort(), "{r:?}");
                planned += 1;
            }
            // E.g. the horizon too short for the limit at this mount: no plan, a row all the same.
            Err(e) => assert!(!e.is_bad_input() && r.planned == Some(false) && r.effort.is_none(), "{r:?}: {e}"),
        }
    }
    assert!(planned >= 1, "{rows:?}");
    // A base disc of 1 m about the base's centre holds link 2 at the start at every mount.
    let capsule = |l: f64| vec![Shape::new(vec![[0.0, 0.0], [l, 0.0]], 0.02).unwrap()];
    let geometry = Geometry {
        base: vec![Shape::circle([0.0, 0.0], 1.0).unwrap()],
        links: free.links.iter().map(|l| capsule(l.length)).collect(),
        ..Geometry::default()
    };
    let shaped = free.clone().with_geometry(geometry).unwrap();
    let rows = run(&shaped, &options, Shard::ALL, &|| {}).unwrap();
    assert!(rows.iter().all(|r| r.planned == Some(false) && r.effort.is_none()), "{rows:?}");
    let described = |arm: &Arm| file::run_description(arm, &options);
    assert!(!described(&free).contains("limits=") && !described(&free).contains("geometry="));
    assert!(described(&limited).contains(" limits=") && described(&shaped).contains(" geometry="));
}
