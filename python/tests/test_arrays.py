"""Shapes and dtypes of the results, torques, the domain grid, the GIL."""

import threading

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START


@pytest.mark.parametrize("samples", [2, 101, 1001])
def test_plan_arrays(src, samples):
    p = ff.plan(src, START, GOAL, HORIZON, method="nfa", samples=samples)
    assert p.t.shape == (samples,) and p.t.dtype == np.float64
    for a in (p.q, p.dq, p.z, p.end_effector, p.end_effector_velocity):
        assert a.shape == (samples, 3) and a.dtype == np.float64
    assert p.base.shape == (samples, 2) and p.base.dtype == np.float64
    assert p.ddq is None and p.tau is None
    assert p.t[0] == 0.0 and p.t[-1] == HORIZON and np.all(np.diff(p.t) > 0)
    assert p.certificate["samples"] == samples


def test_inputs_may_be_lists_tuples_or_arrays(src):
    a = ff.plan(src, list(START), tuple(GOAL), HORIZON)
    b = ff.plan(src, np.asarray(START), GOAL, HORIZON)
    assert np.array_equal(a.q, b.q)


@pytest.mark.parametrize(
    "method, kwargs, samples",
    # The optimal plan's accelerations ramp within graded end layers (T / 128 here): finer
    # samples for the central differences below.
    [("nfa", {}, 201), ("ecsa", {"window": "sin2"}, 201), ("optimal", {"smooth_ends": True}, 2001)],
)
def test_torques(src, method, kwargs, samples):
    robot = src.with_mount(0.2, 0.2)
    p = ff.plan(robot, START, GOAL, HORIZON, method=method, torques=True, samples=samples, **kwargs)
    assert p.tau.shape == (samples, 2) and p.tau.dtype == np.float64
    assert p.ddq.shape == (samples, 3) and p.ddq.dtype == np.float64
    c = p.certificate
    assert c["torque_final_error"] <= 1e-6 and c["certified"] is True
    assert c["max_abs_torque"] == pytest.approx(np.max(np.abs(p.tau), axis=0).tolist(), rel=1e-12)
    assert c["seconds"]["torques"] is not None
    # ddq is the time derivative of dq (central differences, O(h^2)).
    h = p.t[1] - p.t[0]
    central = (p.dq[2:] - p.dq[:-2]) / (2 * h)
    assert np.max(np.abs(central - p.ddq[1:-1])) <= 1e-2 * (1 + np.max(np.abs(p.ddq)))


@pytest.mark.parametrize("method", ff.METHODS)
def test_certificate_has_the_cli_keys(src, method):
    c = ff.plan(src, START, GOAL, HORIZON, method=method).certificate
    keys = ["method", "transform", "mount", "time", "samples", "z0", "zd", "final_error", "max_abs_u",
            "min_abs_sigma", "min_abs_p", "max_abs_torque", "torque_final_error", "seconds", "iterations",
            "effort"]
    assert all(key in c for key in keys)
    # The key order of the CLI's JSON report (PlanReport's fields).
    assert list(c)[:5] == ["method", "transform", "mount", "time", "samples"]
    assert c["time"] == HORIZON and c["start"] == pytest.approx(list(START))
    assert c["method"] == method and ("optimal" in c) == (method == "optimal")


@pytest.mark.parametrize("grid", [16, 101, 720])
def test_domain_grid(src, grid):
    d = ff.domain(src.with_mount(0.3, 0.3), "eq14", grid)
    assert d.labels.shape == (grid, grid) and d.labels.dtype == np.int64
    assert d.centres.shape == (grid,)
    assert d.labels.min() >= -1 and d.labels.max() < d.components + d.slivers
    # The fractions are the label counts.
    counts = np.bincount(d.labels[d.labels >= 0].ravel())
    assert d.component_fractions == pytest.approx((counts[: d.components] / grid**2).tolist())
    assert d.summary["grid"] == grid and d.summary["transform"] == "eq14"


def test_domain_auto_and_centred_halves(src):
    d = ff.domain(src, grid=64)
    assert d.transform == "eq12"
    # a = b = 0: sin(theta2) != 0, the two halves of the torus: rows of theta2 in (0, pi) and (pi, 2 pi).
    assert d.components == 2 and d.component_fractions == [0.5, 0.5]
    upper = d.labels[d.centres < np.pi]
    lower = d.labels[d.centres > np.pi]
    assert len(np.unique(upper)) == 1 and len(np.unique(lower)) == 1 and upper[0, 0] != lower[0, 0]
    with pytest.raises(ff.BadInput):
        ff.domain(src, grid=2)


def test_planning_releases_the_gil(src):
    # Two threads planning at once give the same plans as one after the other.
    robot = src.with_mount(0.1, 0.1)
    expected = ff.plan(robot, START, GOAL, HORIZON).q
    results = [None, None]

    def work(i):
        results[i] = ff.plan(robot, START, GOAL, HORIZON).q

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(r, expected) for r in results)


def test_reprs(src):
    p = ff.plan(src, START, GOAL, HORIZON, method="nfa")
    assert repr(p).startswith("Plan(method='nfa', transform='eq12'")
    assert repr(ff.plan(src, START, GOAL, HORIZON)).startswith("Plan(method='optimal', samples=1001")
    assert repr(ff.domain(src, grid=16)).startswith("Domain(transform='eq12'")
    assert ff.METHODS == ["optimal", "nfa", "ecsa"]
