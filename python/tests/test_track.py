"""freefloat.track: closed-loop execution on a robot that is not the model (issue 12)."""

from pathlib import Path

import numpy as np
import pytest

import freefloat as ff

Q0 = np.radians([45.0, 120.0, 80.0])
QD = np.radians([0.0, 180.0, 140.0])


def test_feedback_on_the_model_reaches_the_goal():
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    r = ff.track(robot, Q0, QD, 10.0, controller="ct")
    assert r["final_error"] <= 1e-6
    assert r["replans"] == 0


def test_adaptive_beats_open_loop_on_a_perturbed_robot():
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    kw = dict(perturb=0.05, perturb_mount=0.01, torque_noise=0.01, seed=3)
    open_loop = ff.track(robot, Q0, QD, 10.0, controller="open", **kw)
    adaptive = ff.track(robot, Q0, QD, 10.0, controller="adaptive", **kw)
    assert adaptive["final_error"] < open_loop["final_error"]
    assert adaptive["final_error"] <= 1e-3
    assert adaptive["identification"] is not None


def test_bad_options_are_bad_input():
    robot = ff.Robot.src()
    with pytest.raises(ff.BadInput):
        ff.track(robot, Q0, QD, 10.0, controller="pid")
    with pytest.raises(ff.BadInput):
        ff.track(robot, Q0, QD, 10.0, rate=0.0)
    with pytest.raises(ff.BadInput):
        ff.track(robot, Q0, QD, 10.0, perturb=2.0)


def test_track_serves_every_arm():
    """Issue 19 item 5: ``track`` takes an ``Arm`` of any number of links (the library's one
    code path, as the command line's ``track``): a 3-link arm reaches its goal on the model
    without re-planning, feedback beats open loop on the perturbed arm, and the paper's robot
    given as an ``Arm`` tracks as the ``Robot``."""
    arm = ff.Arm.from_file(Path(__file__).resolve().parents[2] / "examples" / "robots" / "three_link.toml")
    start, goal = [0.0, 0.3, -0.4, 0.2], [0.5, 0.8, 0.2, -0.3]
    model = ff.track(arm, start, goal, 10.0, controller="ct")
    assert model["final_error"] <= 1e-6 and model["replans"] == 0
    kw = dict(perturb=0.05, perturb_mount=0.01, torque_noise=0.01, seed=3)
    open_loop = ff.track(arm, start, goal, 10.0, controller="open", **kw)
    adaptive = ff.track(arm, start, goal, 10.0, controller="adaptive", **kw)
    assert adaptive["final_error"] < open_loop["final_error"] and adaptive["final_error"] <= 1e-3
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    by_robot = ff.track(robot, Q0, QD, 10.0, controller="ct")
    by_arm = ff.track(ff.Arm.from_robot(robot), Q0, QD, 10.0, controller="ct")
    assert by_arm["final_error"] == pytest.approx(by_robot["final_error"], rel=1e-9, abs=1e-15)


def test_a_margin_without_shapes_is_refused():
    """A margin extends the clearance of a robot's shapes: given for a robot without any, it
    would be accepted and ignored, so it is BadInput naming it (before any planning)."""
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    with pytest.raises(ff.BadInput, match="margin"):
        ff.track(robot, Q0, QD, 10.0, controller="ct", margin=0.05)


def test_a_limit_margin_is_a_fraction_for_a_robot_with_limits():
    """The limit margin (issue 20 item 6) leaves a fraction of every limit as headroom: outside
    [0, 1), or given for a robot without limits (where it would be ignored), it is BadInput
    naming it, before any planning."""
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    with pytest.raises(ff.BadInput, match="limit_margin"):
        ff.track(robot, Q0, QD, 10.0, controller="ct", limit_margin=0.05)
    tight = ff.Arm.from_file(Path(__file__).resolve().parents[2] / "tests" / "fixtures" / "spart_like_4dof_tight.urdf")
    for bad in [-0.1, 1.0, float("nan")]:
        with pytest.raises(ff.BadInput, match="limit_margin"):
            ff.track(tight, [0.0] * 5, [0.1] * 5, 30.0, controller="ct", limit_margin=bad)
