"""Errors: bad input, no plan, not certified; each carries the library's message and numbers."""

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START

SRC = dict(l1=0.619, l2=0.6, d1=0.313, d2=0.287, M=12.9, I=0.208, m1=4.5, m2=1.5)


def test_exception_hierarchy():
    for cls in (ff.BadInput, ff.NoPlan, ff.NotCertified):
        assert issubclass(cls, ff.FreefloatError) and issubclass(cls, Exception)


@pytest.mark.parametrize(
    "key, value",
    [("M", -1.0), ("l1", 0.0), ("d1", 0.7), ("I", float("nan")), ("m2", float("inf"))],
)
def test_bad_robot_parameter(key, value):
    with pytest.raises(ff.BadInput) as info:
        ff.Robot(**{**SRC, key: value})
    e = info.value
    assert e.kind == "invalid_parameter" and e.name == f"robot.{key}"
    assert e.expected and e.message == str(e)
    if np.isfinite(value):
        assert e.value == value


def test_robot_keywords_round_trip():
    robot = ff.Robot(**SRC, a=0.1, b=-0.2)
    assert (robot.l1, robot.M, robot.I, robot.a, robot.b) == (0.619, 12.9, 0.208, 0.1, -0.2)
    assert robot == ff.Robot.src().with_mount(0.1, -0.2)
    assert eval(repr(robot), {"Robot": ff.Robot}) == robot
    with pytest.raises(TypeError):
        ff.Robot(0.619, 0.6, 0.313, 0.287, 12.9, 0.208, 4.5, 1.5)  # keywords only


def test_robot_file(tmp_path):
    text = "[robot]\n" + "".join(f"{k} = {v}\n" for k, v in SRC.items()) + "[mount]\na = 0.1\nb = 0.1\n"
    path = tmp_path / "robot.toml"
    path.write_text(text)
    assert ff.Robot.from_toml(path) == ff.Robot.src().with_mount(0.1, 0.1)
    path.write_text(text + "extra = 1\n")
    with pytest.raises(ff.BadInput) as info:
        ff.Robot.from_toml(path)
    assert info.value.kind == "robot_file"
    with pytest.raises(ff.BadInput):
        ff.Robot.from_toml(tmp_path / "missing.toml")


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(method="newton"),
        dict(transform="eq13"),
        dict(samples=1),
        dict(samples=-5),
        dict(tolerance=0.0),
        dict(method="ecsa", harmonics=9),
        dict(window="hann"),
        dict(cost="time"),
        dict(initial_velocity=(0.1,)),
        dict(initial_velocity=(0.1, 0.2, 0.3)),
        dict(initial_velocity=(float("nan"), 0.0)),
        dict(goal_ee=(0.5, 0.0, 0.0), elbow="sideways"),
    ],
)
def test_bad_options(src, kwargs):
    with pytest.raises(ff.BadInput):
        ff.plan(src, START, GOAL, HORIZON, **kwargs)


@pytest.mark.parametrize(
    "method, kwargs",
    [
        ("optimal", dict(transform="eq12")),
        ("optimal", dict(harmonics=2)),
        ("nfa", dict(window="sin2")),
        ("nfa", dict(smooth_ends=True)),
        ("ecsa", dict(initial_velocity=(0.1, 0.0))),
        ("nfa", dict(wrap=False)),
        ("ecsa", dict(cost="energy")),
    ],
)
def test_keywords_of_another_method_are_bad_input(src, method, kwargs):
    # As `freefloat plan` rejects misplaced flags; default values are accepted by every method.
    with pytest.raises(ff.BadInput) as info:
        ff.plan(src, START, GOAL, HORIZON, method=method, **kwargs)
    assert info.value.kind == "misplaced_option" and info.value.details["method"] == method
    ff.plan(src, START, GOAL, HORIZON, method=method, initial_velocity=(0.0, 0.0), cost="effort", samples=11)


def test_goal_keywords(src):
    with pytest.raises(TypeError, match="'T'"):
        ff.plan(src, START, GOAL)
    with pytest.raises(TypeError, match="'T'"):
        ff.plan(src, START, goal_ee=(0.5, 0.0, 0.0))
    with pytest.raises(ff.BadInput, match="not both"):
        ff.plan(src, START, GOAL, HORIZON, goal_ee=(0.5, 0.0, 0.0))
    with pytest.raises(ff.BadInput, match="goal_ee"):
        ff.plan(src, START, T=HORIZON)
    with pytest.raises(ff.BadInput, match="elbow"):
        ff.plan(src, START, GOAL, HORIZON, elbow="up")
    for pose in [(0.5, 0.0), (0.5, float("inf"), 0.0)]:
        with pytest.raises(ff.BadInput) as info:
            ff.plan(src, START, T=HORIZON, goal_ee=pose)
        assert info.value.name == "goal_ee"


def test_bad_problem(src):
    with pytest.raises(ff.BadInput):
        ff.plan(src, START, GOAL, -1.0)
    with pytest.raises(ff.BadInput) as info:
        ff.plan(src, START[:2], GOAL, HORIZON)
    assert info.value.name == "start"
    with pytest.raises(ff.BadInput) as info:
        ff.plan(src.with_mount(0.1, 0.1), START, GOAL, HORIZON, method="nfa", transform="eq11")
    assert info.value.kind == "transform_unavailable"


def test_goal_in_another_component_is_no_plan(src):
    # The goal's theta2 mirrored: across P = 0 of Eq. (14) at a = b = 0.3.
    goal = GOAL * np.array([1.0, 1.0, -1.0])
    robot = src.with_mount(0.3, 0.3)
    with pytest.raises(ff.NoPlan) as info:
        ff.plan(robot, START, goal, HORIZON, method="nfa", transform="eq14")
    e = info.value
    assert e.kind == "different_components" and "different components" in str(e)
    assert e.details["start_sign"] * e.details["goal_sign"] == -1.0
    # The domain map agrees: start and goal are not connected.
    assert not ff.domain(robot, "eq14", 256, goal=goal).start_goal_connected


def test_path_leaving_the_domain_is_no_plan(src):
    with pytest.raises(ff.NoPlan) as info:
        ff.plan(src.with_mount(1.0, -1.0), START, GOAL, HORIZON, method="nfa", transform="eq14")
    assert info.value.kind and info.value.details


@pytest.mark.parametrize("method", ff.METHODS)
def test_impossible_tolerance_is_not_certified(src, method):
    with pytest.raises(ff.NotCertified) as info:
        ff.plan(src.with_mount(0.1, 0.1), START, GOAL, HORIZON, method=method, tolerance=1e-300)
    e = info.value
    assert e.level == "velocity" and e.tolerance == 1e-300
    assert 1e-300 < e.final_error <= 1e-9
    # The uncertified plan travels with the exception.
    assert isinstance(e.plan, ff.Plan) and not e.plan.certified
    assert e.plan.final_error == e.final_error and e.plan.q.shape == (1001, 3)


def test_torque_certificate_failure_is_not_certified(src):
    # The ECSA's plain trigonometric series does not start at rest: its torques cannot be
    # followed from rest (README), so the torque level is not certified.
    with pytest.raises(ff.NotCertified) as info:
        ff.plan(src, START, GOAL, HORIZON, method="ecsa", torques=True)
    e = info.value
    assert e.level == "torque" and e.final_error > e.tolerance == 1e-6
    assert e.plan.tau.shape == (1001, 2)
