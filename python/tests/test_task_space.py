"""Task space: the base and end-effector columns of every plan, and plans to an end-effector
pose (goal_ee) by the free-floating inverse kinematics."""

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START


def angle_distance(a, b):
    return abs((a - b + np.pi) % (2 * np.pi) - np.pi)


@pytest.mark.parametrize("method", ff.METHODS)
def test_task_space_columns(src, method):
    robot = src.with_mount(0.1, 0.1)
    p = ff.plan(robot, START, GOAL, HORIZON, method=method, samples=2001)
    n = len(p.t)
    assert p.base.shape == (n, 2) and p.end_effector.shape == (n, 3) and p.end_effector_velocity.shape == (n, 3)
    # psie is the absolute angle of link 2.
    np.testing.assert_allclose(p.end_effector[:, 2], p.q[:, 0] + p.q[:, 1] + p.q[:, 2], rtol=0, atol=1e-14)
    np.testing.assert_allclose(p.end_effector_velocity[:, 2], p.dq.sum(axis=1), rtol=0, atol=1e-14)
    # The velocity is the time derivative of the pose (central differences, O(h^2)).
    gradient = np.gradient(p.end_effector, p.t, axis=0)
    scale = 1.0 + np.max(np.abs(p.end_effector_velocity))
    assert np.max(np.abs(gradient[1:-1] - p.end_effector_velocity[1:-1])) <= 1e-3 * scale
    # The tip is l2 from joint 2 and within reach of the base: |tip - base| <= |(a, b)| + l1 + l2.
    reach = np.hypot(robot.a, robot.b) + robot.l1 + robot.l2
    assert np.max(np.hypot(*(p.end_effector[:, :2] - p.base).T)) <= reach
    # At rest at both ends (the ECSA's plain series is not).
    if method != "ecsa":
        assert np.max(np.abs(p.end_effector_velocity[[0, -1]])) <= 1e-9


def test_base_keeps_the_centre_of_mass_at_the_origin(src):
    # The base moves against the arm: it is not at rest while the arm moves.
    p = ff.plan(src.with_mount(0.2, 0.2), START, GOAL, HORIZON)
    assert np.ptp(p.base[:, 0]) > 1e-3 and np.ptp(p.base[:, 1]) > 1e-3


@pytest.mark.parametrize("mount", [0.0, 0.1, 0.3])
def test_goal_ee_lands_on_the_pose(src, mount):
    robot = src.with_mount(mount, mount)
    pose = ff.plan(robot, START, GOAL, HORIZON, method="nfa", samples=11).end_effector[-1]
    p = ff.plan(robot, START, T=HORIZON, goal_ee=pose)
    assert p.certified and p.final_error <= 1e-9 and p.elbow in ("up", "down")
    x, y, psi = p.end_effector[-1]
    assert np.hypot(x - pose[0], y - pose[1]) <= 1e-9 and angle_distance(psi, pose[2]) <= 1e-9
    assert np.max(np.abs(p.end_effector_velocity[-1])) <= 1e-9
    assert p.certificate["goal"] == pytest.approx(p.q[-1].tolist(), abs=1e-9)
    if mount > 0:
        # Both elbows reach the pose; without one, the plan of least effort is kept.
        plans = {e: ff.plan(robot, START, T=HORIZON, goal_ee=pose, elbow=e) for e in ("up", "down")}
        for e, q in plans.items():
            assert q.elbow == e and np.hypot(*(q.end_effector[-1, :2] - pose[:2])) <= 1e-9
        assert p.effort == min(q.effort for q in plans.values())
        assert not np.allclose(plans["up"].q[-1], plans["down"].q[-1], atol=1e-3)


def test_goal_ee_with_the_nfa_and_compare(src):
    robot = src.with_mount(0.1, 0.1)
    pose = (0.3, 0.4, np.radians(100.0))
    plans = ff.compare(robot, START, T=HORIZON, goal_ee=pose, methods=["optimal", "nfa"], strict=False)
    assert isinstance(plans["optimal"], ff.Plan)
    for p in plans.values():
        if isinstance(p, ff.Plan):
            assert np.hypot(*(p.end_effector[-1, :2] - pose[:2])) <= 1e-9


def test_unreachable_pose_is_bad_input(src):
    robot = src.with_mount(0.1, 0.1)
    # Link 2 as the inverse kinematics sees it: L2 = l2 - m2 d2 / (M + m1 + m2).
    big_l2 = robot.l2 - robot.m2 * robot.d2 / (robot.M + robot.m1 + robot.m2)
    psi = np.radians(30.0)
    # Too far, and too near: the wrist point at the centre of mass.
    for pose in [(2.0, 0.0, 0.0), (big_l2 * np.cos(psi), big_l2 * np.sin(psi), psi)]:
        with pytest.raises(ff.BadInput) as info:
            ff.plan(robot, START, T=HORIZON, goal_ee=pose)
        e = info.value
        assert e.kind == "unreachable" and "out of reach" in str(e)
        d = e.details
        assert d["x"] == pose[0] and d["y"] == pose[1] and d["psi"] == pose[2]
        assert 0 < d["min"] < d["max"] and not d["min"] <= d["distance"] <= d["max"]
        # The wrist point (x, y) - L2 (cos psi, sin psi) is that far from the centre of mass.
        wrist = np.hypot(pose[0] - big_l2 * np.cos(pose[2]), pose[1] - big_l2 * np.sin(pose[2]))
        assert d["distance"] == pytest.approx(wrist, abs=1e-12)
    with pytest.raises(ff.BadInput):
        ff.compare(robot, START, T=HORIZON, goal_ee=(2.0, 0.0, 0.0), strict=False)
