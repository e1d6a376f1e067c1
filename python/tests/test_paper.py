"""The paper's five NFA cases and ECSA (Sec. 5): the goal is reached and certified; the plans
are motions of the robot (zero angular momentum, velocities consistent with positions)."""

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START, wrapped_distance

CASES = [
    # (a = b, transform)
    (0.0, "eq11"),
    (0.0, "eq12"),
    (0.1, "eq14"),
    (0.2, "eq14"),
    (0.3, "eq14"),
]


@pytest.mark.parametrize("mount, transform", CASES)
def test_nfa_reaches_the_goal(src, mount, transform):
    robot = src.with_mount(mount, mount)
    p = ff.plan(robot, START, GOAL, HORIZON, method="nfa", transform=transform)
    assert p.method == "nfa" and p.transform == transform and p.certified
    assert p.final_error <= 1e-9
    # The planned path ends at the goal, taken literally (not modulo 2 pi), and starts at q0.
    assert np.max(np.abs(p.q[-1] - GOAL)) <= 1e-9
    assert np.max(np.abs(p.q[0] - START)) <= 1e-12
    # At rest at both ends.
    assert np.max(np.abs(p.dq[[0, -1]])) <= 1e-9
    c = p.certificate
    assert c["method"] == "nfa" and c["transform"] == transform and c["certified"] is True
    assert c["final_error"] == p.final_error and c["mount"] == [mount, mount]
    assert wrapped_distance(c["reached"], GOAL) == pytest.approx(p.final_error, abs=1e-15)


def test_ecsa_reaches_the_goal(src):
    p = ff.plan(src.with_mount(0.1, 0.1), START, GOAL, HORIZON, method="ecsa")
    assert p.method == "ecsa" and p.transform is None and p.z is None
    assert p.final_error <= 1e-9
    assert wrapped_distance(p.q[-1], GOAL) <= 1e-9
    c = p.certificate
    assert c["iterations"] >= 1 and c["ecsa"]["residual"] <= c["ecsa"]["residual_tolerance"]


@pytest.mark.parametrize("method", ff.METHODS)
def test_plan_is_a_motion_of_the_robot(src, method):
    robot = src.with_mount(0.2, 0.2)
    # 2001 samples: the optimal plan's velocity ramps within graded end layers (T / 128 here).
    p = ff.plan(robot, START, GOAL, HORIZON, method=method, samples=2001)
    # Zero angular momentum F phi' + G th1' + H th2' along the samples.
    momenta = np.array([robot.momentum(q, dq) for q, dq in zip(p.q, p.dq)])
    assert np.max(np.abs(momenta)) <= 1e-12
    # dq is the time derivative of q: central differences, error O(h^2).
    h = p.t[1] - p.t[0]
    central = (p.q[2:] - p.q[:-2]) / (2 * h)
    scale = 1.0 + np.max(np.abs(p.dq))
    assert np.max(np.abs(central - p.dq[1:-1])) <= 1e-3 * scale
    # The effort is integral |u|^2 dt: compare with the trapezoid rule over the same samples.
    u2 = np.sum(p.dq[:, 1:] ** 2, axis=1)
    trapezoid = float(np.sum((u2[1:] + u2[:-1]) / 2) * h)
    assert p.effort > 0 and p.effort == pytest.approx(trapezoid, rel=1e-4)


def test_compare_plans_every_method(src):
    plans = ff.compare(src, START, GOAL, HORIZON)
    assert list(plans) == ["optimal", "nfa", "ecsa"]
    for method, p in plans.items():
        assert isinstance(p, ff.Plan) and p.method == method and p.final_error <= 1e-9


def test_compare_not_strict_keeps_the_errors(src):
    robot = src.with_mount(1.0, -1.0)
    plans = ff.compare(robot, START, GOAL, HORIZON, transform="eq14", strict=False)
    assert isinstance(plans["nfa"], ff.NoPlan)
    assert isinstance(plans["optimal"], ff.Plan) and plans["optimal"].final_error <= 1e-9
    assert isinstance(plans["ecsa"], ff.Plan) and plans["ecsa"].final_error <= 1e-9
    with pytest.raises(ff.NoPlan):
        ff.compare(robot, START, GOAL, HORIZON, transform="eq14")
