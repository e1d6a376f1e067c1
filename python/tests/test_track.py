"""freefloat.track: closed-loop execution on a robot that is not the model (issue 12)."""

from pathlib import Path

import numpy as np
import pytest

import freefloat as ff

Q0 = np.radians([45.0, 120.0, 80.0])
QD = np.radians([0.0, 180.0, 140.0])
ROBOTS = Path(__file__).resolve().parents[2] / "examples" / "robots"


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


def _three_link_at(tmp_path, velocity_deg):
    """The 3-link example arm with a velocity limit [deg/s] on every joint, as a robot file."""
    text = (ROBOTS / "three_link.toml").read_text()
    limit = f"limit = {{ velocity = {float(np.radians(velocity_deg))!r} }}\n"
    text = text.replace("[[link]]\n", "[[link]]\n" + limit)
    path = tmp_path / "three_link_limited.toml"
    path.write_text(text)
    return ff.Arm.from_file(path)


def test_the_result_reports_the_limit_margin_used(tmp_path):
    """The plans keep limit_margin inside the limits, less where the horizon is too short for
    the whole of it (the command line says so in a note): the result says which margin was
    kept. The 3-link example at 20 deg/s reaches (30, 60, -30, 20) deg from rest in 19.6 s at
    its limits, so 20 s is too short for 5 % (about 20.6 s) and 25 s is not."""
    arm = _three_link_at(tmp_path, 20.0)
    start, goal = np.zeros(4), np.radians([30.0, 60.0, -30.0, 20.0])
    short = ff.track(arm, start, goal, 20.0, controller="ct")
    assert 0.0 < short["limit_margin_used"] < 0.05
    roomy = ff.track(arm, start, goal, 25.0, controller="ct")
    assert roomy["limit_margin_used"] == 0.05
    asked = ff.track(arm, start, goal, 25.0, controller="ct", limit_margin=0.02)
    assert asked["limit_margin_used"] == 0.02
    unlimited = ff.track(ff.Robot.src().with_mount(0.1, 0.1), Q0, QD, 10.0, controller="ct")
    assert unlimited["limit_margin_used"] == 0.0
