//! Tests of the domain maps (Figs. 13-14): halves at `a = b = 0`, labels, components on the
//! torus, the paper's `q0` and `qd`.

use super::*;
use crate::model::{Mount, paper_problem};

fn robot(a: f64, b: f64) -> RobotParams {
    RobotParams::src().with_mount(Mount::new(a, b).unwrap()).unwrap()
}

/// a = b = 0: the domain of Eq. (14) is sin(theta2) != 0 (sigma = -C I_P s2, P = -C s2): two
/// components, exactly the two halves of the grid, the same as Eqs. (11)-(12).
#[test]
fn centred_mount_has_two_halves() {
    for n in [16, 64, 720] {
        for transform in [Transform::Eq14, Transform::Eq11, Transform::Eq12] {
            let map = DomainMap::new(&robot(0.0, 0.0), transform, n).unwrap();
            let c = map.components();
            assert_eq!(c.len(), 2, "{transform:?}, N = {n}");
            // The grid's own count of the cells with sin(theta2) > 0.
            let upper = (0..n).filter(|&i2| map.centre(0, i2).1.sin() > 0.0).count() * n;
            assert_eq!(upper, n * n / 2);
            for comp in c {
                assert_eq!(comp.cells, upper);
                assert!((comp.fraction - 0.5).abs() < 1e-15);
            }
            assert!((map.defined_fraction() - 1.0).abs() < 1e-15);
            assert_ne!(c[0].signs.branch, c[1].signs.branch);
        }
    }
}

/// The grid's cell count, labels and component records agree, and every component has one
/// sign pattern, equal to the pointwise signs of each of its cells.
#[test]
fn labels_are_consistent() {
    let map = DomainMap::new(&robot(0.3, 0.3), Transform::Eq14, 128).unwrap();
    let n = map.grid();
    let mut counts = vec![0; map.components().len()];
    for i2 in 0..n {
        for i1 in 0..n {
            match (map.status(i1, i2), map.component(i1, i2)) {
                (CellStatus::Defined(s), Some(c)) => {
                    counts[c] += 1;
                    assert_eq!(s, map.components()[c].signs);
                    // A neighbour in the same component has the same signs: no cut inside.
                    if map.component(i1 + 1, i2) == Some(c) {
                        assert_eq!(map.status(i1 + 1, i2), CellStatus::Defined(s));
                    }
                }
                (CellStatus::Undefined(_), None) => {}
                other => panic!("inconsistent cell ({i1}, {i2}): {other:?}"),
            }
        }
    }
    let listed: Vec<usize> = map.components().iter().map(|c| c.cells).collect();
    assert_eq!(counts, listed);
    assert!(listed.windows(2).all(|w| w[0] >= w[1]), "not sorted: {listed:?}");
}

/// Off-centre mounting points split the torus into more pieces (Figs. 13-14), and the pieces
/// still cover the torus: the conditions fail only on curves.
#[test]
fn off_centre_mounts_have_more_components() {
    for a in [0.1, 0.2, 0.3] {
        let coarse = DomainMap::new(&robot(a, a), Transform::Eq14, 360).unwrap();
        let fine = DomainMap::new(&robot(a, a), Transform::Eq14, 720).unwrap();
        assert!(coarse.resolved_count() > 2, "a = b = {a}: {} components", coarse.resolved_count());
        // The resolved count has converged; the slivers' area shrinks with the cells.
        assert_eq!(coarse.resolved_count(), fine.resolved_count());
        let slivers = |m: &DomainMap| m.components().iter().filter(|c| !c.resolved).map(|c| c.fraction).sum::<f64>();
        assert!(slivers(&fine) < 1e-4 && slivers(&fine) <= slivers(&coarse));
        assert!((coarse.defined_fraction() - 1.0).abs() < 1e-12);
    }
}

/// The paper's q0 and qd lie in one component of the domain of Eq. (14) for a = b = 0.1,
/// 0.2, 0.3, where the paper's NFA succeeds (Figs. 6-8), and of Eqs. (11)-(12) at a = b = 0.
#[test]
fn paper_start_and_goal_are_connected() {
    let (q0, qd, _) = paper_problem();
    for (a, transform) in
        [(0.0, Transform::Eq12), (0.1, Transform::Eq14), (0.2, Transform::Eq14), (0.3, Transform::Eq14)]
    {
        let map = DomainMap::new(&robot(a, a), transform, 720).unwrap();
        let s = map.summary(&q0, &qd);
        assert!(s.start_goal_connected, "a = b = {a}: {s:?}");
        assert!(s.start_component_fraction > 0.0 && s.start_component_fraction <= 1.0);
    }
}

/// Component labelling on the torus: a band that leaves the grid on one side and comes back
/// on the other is one component; the same band without wrap-around would be several.
#[test]
fn wrapping_bands_are_one_component() {
    let n = 12;
    // A diagonal band two cells wide: (i, i) and (i + 1, i), wrapping on both axes.
    let mut keys = vec![0u8; n * n];
    for i in 0..n {
        keys[i * n + i] = 1;
        keys[i * n + (i + 1) % n] = 1;
    }
    let (labels, comps) = label_components(n, &keys);
    assert_eq!(comps, vec![(2 * n, 0)]);
    assert_eq!(labels.iter().filter(|&&l| l == 0).count(), 2 * n);
    // A horizontal band across the seam theta2 = 0 (rows n-1 and 0), a vertical one across
    // theta1 = 0, and a separate blob with another key.
    let mut keys = vec![0u8; n * n];
    for i in 0..n {
        keys[i] = 1;
        keys[(n - 1) * n + i] = 1;
    }
    for i2 in 3..6 {
        keys[i2 * n] = 2;
        keys[i2 * n + n - 1] = 2;
    }
    keys[8 * n + 5] = 3;
    let (labels, comps) = label_components(n, &keys);
    assert_eq!(comps.iter().map(|c| c.0).collect::<Vec<_>>(), vec![2 * n, 6, 1]);
    assert_eq!(labels[0], labels[(n - 1) * n + 3]);
    assert_eq!(labels[3 * n], labels[5 * n + n - 1]);
    assert_eq!(labels[8 * n + 4], NONE);
    // Equal keys that only touch diagonally are not connected.
    let mut keys = vec![0u8; n * n];
    keys[0] = 1;
    keys[n + 1] = 1;
    assert_eq!(label_components(n, &keys).1.len(), 2);
}

/// The table-driven map evaluates the same functions as `shape` at the centres.
#[test]
fn samples_match_shape() {
    let r = robot(0.2, -0.1);
    let map = DomainMap::new(&r, Transform::Eq14, 37).unwrap();
    let k = r.lumped();
    for (i1, i2) in [(0, 0), (5, 30), (36, 36), (18, 2)] {
        let (t1, t2) = map.centre(i1, i2);
        let s = shape(&k, t1, t2);
        let idx = i2 * 37 + i1;
        assert!((map.curves()[0].values[idx] - s.sigma).abs() < 1e-13);
        assert!((map.curves()[1].values[idx] - s.P).abs() < 1e-13);
        assert_eq!(map.cell_of(t1, t2), (i1, i2));
        assert_eq!(map.cell_of(t1 - 4.0 * std::f64::consts::PI, t2 + std::f64::consts::TAU), (i1, i2));
    }
}

/// A point just across a zero curve from its cell's centre is put in the component on its
/// own side; a point on no side (on sin theta2 = 0) is outside.
#[test]
fn component_at_respects_sides() {
    let map = DomainMap::new(&robot(0.0, 0.0), Transform::Eq12, 8).unwrap();
    let above = map.component_at(&Configuration::new(0.0, 1.0, 1e-9)).unwrap();
    let below = map.component_at(&Configuration::new(0.0, 1.0, -1e-9)).unwrap();
    assert_ne!(above, below);
    assert_eq!(map.components()[above].signs.branch, 1);
    assert_eq!(map.component_at(&Configuration::new(0.0, 1.0, 0.0)), None);
    // Cell centres at (k + 1/2) 45 deg: theta2 = 1 deg is in cell 0, whose centre is above.
    assert_eq!(map.component_at(&Configuration::new(0.0, 1.0, 1f64.to_radians())), Some(above));
}

#[test]
fn bad_inputs_are_errors() {
    assert!(matches!(
        DomainMap::new(&RobotParams::src(), Transform::Eq14, 2),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    assert!(matches!(DomainMap::new(&robot(0.1, 0.0), Transform::Eq11, 16), Err(Error::TransformUnavailable { .. })));
}

/// Classes: at a = b = 0 the rows next to theta2 = 0 and pi are crossings, all others
/// defined with the branch sign(s2).
#[test]
fn classes_mark_crossings() {
    let n = 8;
    let map = DomainMap::new(&robot(0.0, 0.0), Transform::Eq11, n).unwrap();
    for i2 in 0..n {
        let expected = if [0, n / 2 - 1, n / 2, n - 1].contains(&i2) {
            CellClass::Crossing(Singularity::SinTheta2)
        } else {
            CellClass::Defined { branch: if i2 < n / 2 { 1 } else { -1 } }
        };
        assert_eq!(map.class(3, i2), expected, "row {i2}");
    }
}

/// The global normal form's domain `{sigma != 0}` has two components, each about half the
/// torus, for every mounting point tested (up to |a|, |b| = 1), and the paper's q0 and qd
/// share one (beyond the paper: where Eq. (14) leaves q0 and qd apart, e.g. a = 1, b = -1).
#[test]
fn global_domain_is_two_halves() {
    let (q0, qd, _) = crate::model::paper_problem();
    for (a, b) in [(0.0, 0.0), (0.1, 0.1), (0.3, 0.3), (1.0, -1.0), (0.5, 0.5), (-1.0, 1.0), (0.7, 0.0), (0.0, -1.0)] {
        let map = DomainMap::new(&robot(a, b), Transform::Global, 256).unwrap();
        let summary = map.summary(&q0, &qd);
        assert_eq!(summary.components, 2, "({a}, {b})");
        for f in &summary.component_fractions {
            assert!((f - 0.5).abs() < 0.05, "({a}, {b}): {f}");
        }
        assert!(summary.start_goal_connected, "({a}, {b})");
    }
}
