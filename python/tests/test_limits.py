"""The robot's limits from Python (issue 20): ``limits=`` on ``plan`` (SI units, radians) over
the arm's own; a plan inside a binding limit is certified, one over a limit is ``NotCertified``
naming the joint and the quantity; bad ``limits`` are ``BadInput``."""

import math
from pathlib import Path

import pytest

import freefloat as ff

ROBOTS = Path(__file__).resolve().parents[2] / "examples" / "robots"
START = [math.radians(x) for x in (0.0, 60.0, -30.0, -30.0)]
GOAL = [math.radians(x) for x in (30.0, 120.0, 40.0, -60.0)]


@pytest.fixture(scope="module")
def three_link():
    return ff.Arm.from_file(ROBOTS / "three_link.toml")


def test_a_binding_velocity_limit_holds(three_link):
    limit = math.radians(30.0)  # below the free plan's 0.584 rad/s on theta2
    plan = ff.plan(three_link, START, GOAL, 10.0, limits={"theta2": {"velocity": limit}})
    uses = plan.certificate["limits"]["uses"]
    (use,) = [u for u in uses if u["name"] == "theta2" and u["quantity"] == "velocity"]
    assert 0.95 < use["use"] <= 1.0 + 1e-9
    assert plan.certificate["limits"]["inside"] is True


def test_the_ecsa_over_a_limit_is_not_certified(three_link):
    with pytest.raises(ff.NotCertified, match="theta1's velocity"):
        ff.plan(three_link, START, GOAL, 10.0, method="ecsa", limits={"theta1": {"velocity": 0.01}})


def test_bad_limits_are_bad_input(three_link):
    for limits in ({"theta9": {"velocity": 1.0}}, {"theta1": {"speed": 1.0}}, {"theta1": {"velocity": -1.0}},
                   {"theta1": {"position": [1.0, -1.0]}}):
        with pytest.raises(ff.BadInput):
            ff.plan(three_link, START, GOAL, 10.0, limits=limits)
