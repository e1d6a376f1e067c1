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


# Issue 20 item 4: T="auto", the shortest horizon (to 1 %) inside the arm's limits.
VELOCITY = math.radians(30.0)  # [rad/s] on every joint
ALL_VELOCITY = {f"theta{k}": {"velocity": VELOCITY} for k in (1, 2, 3)}


@pytest.fixture(scope="module")
def shortest(three_link):
    return ff.plan(three_link, START, GOAL, "auto", limits=ALL_VELOCITY)


def test_auto_plans_at_the_shortest_horizon_inside_the_limits(shortest):
    assert shortest.certified
    limits = shortest.certificate["limits"]
    assert limits["inside"] is True
    # The horizon found is the plan's: its arrays end there and the report says so.
    assert shortest.horizon == pytest.approx(shortest.t[-1], rel=1e-12)
    assert shortest.certificate["time"] == pytest.approx(shortest.horizon, rel=1e-12)
    # At the shortest horizon the velocity limit binds (within the search's 1 %) ...
    uses = [u["use"] for u in limits["uses"] if u["quantity"] == "velocity"]
    assert 0.98 < max(uses) <= 1.0 + 1e-9
    # ... and the sampled joint rates stay inside it.
    assert abs(shortest.dq[:, 1:]).max() <= VELOCITY * (1.0 + 1e-9)


def test_a_horizon_below_the_shortest_fails(three_link, shortest):
    # 1.2 % shorter than the horizon found, beyond the search's 1 %: no plan inside the limit
    # (the library's HorizonTooShort, naming the limit that binds).
    with pytest.raises(ff.NoPlan, match="velocity"):
        ff.plan(three_link, START, GOAL, shortest.horizon / 1.012, limits=ALL_VELOCITY)


def test_auto_without_a_rate_limit_is_bad_input(three_link):
    cases = [
        (three_link, {}),  # no limit at all
        (three_link, {"limits": {"theta1": {"position": [-3.0, 3.0]}}}),  # a position limit only
        (three_link, {"limits": ALL_VELOCITY, "method": "ecsa"}),  # not the optimal method
    ]
    for arm, kwargs in cases:
        with pytest.raises(ff.BadInput, match='T="auto".*velocity, acceleration or torque limit'):
            ff.plan(arm, START, GOAL, "auto", **kwargs)
    # The 2-link pipeline (a Robot without limits=) has no limits.
    src = ff.Robot.src()
    with pytest.raises(ff.BadInput, match='T="auto".*has no limits'):
        ff.plan(src, [0.0, 2.0, 1.4], [0.5, 3.0, 2.4], "auto")


def test_another_string_for_T_is_bad_input(three_link):
    for text in ("Auto", "shortest", "10"):
        with pytest.raises(ff.BadInput, match="T"):
            ff.plan(three_link, START, GOAL, text, limits=ALL_VELOCITY)
