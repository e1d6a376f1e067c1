"""The minimum-effort planner (method="optimal", the default): certified on the paper's five
cases with less effort than the NFA, across sigma = 0 where the NFA has no plan, and its
keywords (initial_velocity, smooth_ends, wrap, cost)."""

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START, wrapped_distance
from test_paper import CASES


@pytest.mark.parametrize("mount, transform", CASES)
def test_optimal_beats_the_nfa_on_the_paper_cases(src, mount, transform):
    robot = src.with_mount(mount, mount)
    p = ff.plan(robot, START, GOAL, HORIZON)
    assert p.method == "optimal" and p.transform is None and p.z is None and p.certified
    assert p.final_error <= 1e-9
    # The goal modulo 2 pi (wrap=True may pick another representative), from the start, at rest.
    assert wrapped_distance(p.q[-1], GOAL) <= 1e-9
    assert np.max(np.abs(p.q[0] - START)) <= 1e-12
    assert np.max(np.abs(p.dq[[0, -1]])) <= 1e-9
    # The effort is the library's exact one, and below the NFA's on the same problem.
    c = p.certificate
    assert p.effort == c["effort"] == c["optimal"]["effort"]
    assert c["optimal"]["termination"] == "converged"
    nfa = ff.plan(robot, START, GOAL, HORIZON, method="nfa", transform=transform)
    assert 0 < p.effort < nfa.effort


def test_optimal_crosses_sigma_zero(src):
    # At a = b = 0, sigma = 0 is sin(theta2) = 0 (Eq. 9): theta2 = 80 deg -> -140 deg crosses it,
    # so start and goal lie in different components of every NFA transformation.
    goal = np.radians([0.0, 180.0, -140.0])
    with pytest.raises(ff.NoPlan):
        ff.plan(src, START, goal, HORIZON, method="nfa")
    p = ff.plan(src, START, goal, HORIZON)
    assert p.final_error <= 1e-9 and wrapped_distance(p.q[-1], goal) <= 1e-9
    s = np.sin(p.q[:, 2])
    assert s[0] > 0 > s[-1] and np.any(np.diff(np.sign(s)) != 0)
    momenta = np.array([src.momentum(q, dq) for q, dq in zip(p.q, p.dq)])
    assert np.max(np.abs(momenta)) <= 1e-12


@pytest.mark.parametrize("velocity", [(0.1, -0.2), np.array([-0.05, 0.3])])
def test_initial_velocity_is_honoured(src, velocity):
    robot = src.with_mount(0.1, 0.1)
    p = ff.plan(robot, START, GOAL, HORIZON, initial_velocity=velocity)
    assert p.final_error <= 1e-9
    np.testing.assert_allclose(p.dq[0, 1:], velocity, rtol=0, atol=1e-12)
    # phi' follows from zero angular momentum; the motion ends at rest.
    assert abs(robot.momentum(p.q[0], p.dq[0])) <= 1e-12
    assert np.max(np.abs(p.dq[-1])) <= 1e-9


def test_smooth_ends_start_and_end_without_acceleration(src):
    robot = src.with_mount(0.1, 0.1)
    cubic = ff.plan(robot, START, GOAL, HORIZON)
    quintic = ff.plan(robot, START, GOAL, HORIZON, smooth_ends=True)
    assert quintic.final_error <= 1e-9 and quintic.certificate["optimal"]["degree"] == 5
    assert np.max(np.abs(quintic.ddq[[0, -1], 1:])) <= 1e-9
    assert np.max(np.abs(cubic.ddq[[0, -1], 1:])) > 1e-3
    # One more condition at each end costs effort.
    assert quintic.effort > cubic.effort


def test_wrap_false_takes_the_goal_literally(src):
    robot = src.with_mount(0.1, 0.1)
    goal = GOAL - np.array([0.0, 0.0, 2 * np.pi])
    wrapped = ff.plan(robot, START, goal, HORIZON)
    literal = ff.plan(robot, START, goal, HORIZON, wrap=False)
    assert np.max(np.abs(literal.q[-1] - goal)) <= 1e-9
    # Modulo 2 pi the shorter representative is found: the same plan as to GOAL.
    assert wrapped.effort < literal.effort
    assert wrapped.effort == pytest.approx(ff.plan(robot, START, GOAL, HORIZON).effort, rel=1e-9)


def test_energy_cost(src):
    robot = src.with_mount(0.1, 0.1)
    effort = ff.plan(robot, START, GOAL, HORIZON)
    energy = ff.plan(robot, START, GOAL, HORIZON, cost="energy")
    assert energy.final_error <= 1e-9
    # Each plan is the better one by its own cost; `effort` is always integral |u|^2 dt.
    assert energy.effort >= effort.effort
    assert energy.certificate["optimal"]["cost"] != pytest.approx(energy.effort)


def test_a_moving_start_is_certified_with_torques(src):
    # The torque certificate integrates the dynamics from the moving start (it used to start
    # from rest and fail).
    p = ff.plan(src.with_mount(0.1, 0.1), START, GOAL, HORIZON, initial_velocity=(0.1, -0.2), torques=True)
    assert p.certificate["torque_certificate"]["certificate"]["certified"]
    assert p.certificate["torque_final_error"] <= 1e-6
