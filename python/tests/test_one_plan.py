"""One ``plan`` for every robot, one ``Plan`` class (issue 19 item 5): ``ff.plan`` takes a
``Robot`` or an ``Arm`` of any number of links and returns a ``Plan`` with the same attributes
and certificate keys; ``ArmPlan`` is another name of ``Plan``; a keyword that does not apply to
an arm is a ``ValueError`` naming it and why; ``plan_arm`` is a deprecated alias."""

import math
import pickle
from pathlib import Path

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START, wrapped_distance

ROBOTS = Path(__file__).resolve().parents[2] / "examples" / "robots"
ARM_START = [0.0, 0.3, -0.4, 0.2]
ARM_GOAL = [0.5, 0.8, 0.2, -0.3]

ARRAYS = ("t", "q", "dq", "ddq", "ddtheta", "tau", "z", "base", "end_effector", "end_effector_velocity")


def public(p):
    return {name for name in dir(p) if not name.startswith("_")}


@pytest.fixture(scope="module")
def three_link():
    return ff.Arm.from_file(ROBOTS / "three_link.toml")


def test_arm_plan_is_another_name_of_plan():
    assert ff.ArmPlan is ff.Plan


@pytest.mark.parametrize("method", ["optimal", "nfa", "ecsa"])
def test_the_src_arm_plans_as_the_src_robot(src, method):
    """The paper's robot given as a 2-link ``Arm`` (mounted off the centre) is planned as the
    ``Robot``: the same class, effort, arrays and certificate keys, for every method."""
    robot = src.with_mount(0.1, 0.1)
    arm = ff.Arm.from_robot(robot)
    assert arm.joints == 2 and not arm.constrained
    # The ECSA's motion here misses the torque certificate (its open-loop full dynamics drift),
    # on either route: compare its velocity-level plans.
    torques = method != "ecsa"
    by_robot = ff.plan(robot, START, GOAL, HORIZON, method=method, torques=torques)
    by_arm = ff.plan(arm, START, GOAL, HORIZON, method=method, torques=torques)
    assert type(by_arm) is type(by_robot) is ff.Plan
    assert by_arm.effort == pytest.approx(by_robot.effort, rel=1e-9)
    assert public(by_arm) == public(by_robot)
    assert set(by_arm.certificate) == set(by_robot.certificate)
    for name in ARRAYS:
        x, y = getattr(by_arm, name), getattr(by_robot, name)
        assert (x is None) == (y is None), name
        if x is not None:
            assert x.shape == y.shape, name
            np.testing.assert_allclose(x, y, rtol=0.0, atol=1e-9, err_msg=name)
    assert by_arm.final_error <= by_arm.tolerance and by_arm.joints == 2


def test_a_three_link_arm_gets_a_plan_to_its_goal(three_link):
    """A 3-link arm's plan is a ``Plan`` of 3 joints: it starts at the start, ends at the goal
    (modulo 2 pi), at rest, with the shapes of n = 3 and None where the NFA's fields are."""
    p = ff.plan(three_link, ARM_START, ARM_GOAL, 8.0, samples=301, torques=True)
    assert type(p) is ff.Plan and p.joints == 3 and p.method == "optimal"
    assert p.q.shape == (301, 4) and p.dq.shape == (301, 4) and p.tau.shape == (301, 3)
    assert p.ddtheta.shape == (301, 3)
    np.testing.assert_array_equal(p.ddtheta, p.ddq[:, 1:])
    np.testing.assert_allclose(p.q[0], ARM_START, atol=1e-12)
    assert wrapped_distance(p.q[-1], ARM_GOAL) <= 1e-6
    assert np.max(np.abs(p.dq[[0, -1], 1:])) <= 1e-9
    assert p.t[-1] == pytest.approx(8.0, rel=1e-12) and p.horizon == pytest.approx(8.0, rel=1e-12)
    assert p.final_error <= p.tolerance and p.certified
    assert p.z is None and p.transform is None and p.elbow is None
    assert p.certificate["joints"] == 3
    # One class: it pickles through the one constructor, equal field by field.
    back = pickle.loads(pickle.dumps(p))
    assert type(back) is ff.Plan and repr(back) == repr(p) and back.joints == 3
    np.testing.assert_array_equal(back.q, p.q)


def test_an_old_arm_plan_pickle_loads_as_a_plan(three_link):
    """A state pickled by the former ``ArmPlan`` (no ``z``, ``transform``, ``elbow``; a stored
    ``ddtheta``) loads through ``_arm_plan_from_state`` as a ``Plan``."""
    p = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, samples=51)
    rebuild, (state,) = p.__reduce__()
    old = {k: v for k, v in state.items() if k not in ("z", "transform", "elbow")}
    old["ddtheta"] = p.ddtheta
    back = ff._freefloat._arm_plan_from_state(old)
    assert type(back) is ff.Plan and back.z is None and back.transform is None and back.elbow is None
    np.testing.assert_array_equal(back.ddtheta, p.ddtheta)
    assert back.certificate == p.certificate
    # A former Plan's state (no joints, no horizon) takes them from q and the report.
    older = {k: v for k, v in state.items() if k not in ("joints", "horizon")}
    back = rebuild(older)
    assert back.joints == 3 and back.horizon == p.horizon


@pytest.mark.parametrize("function", [ff.plan, ff.compare])
def test_an_nfa_keyword_for_an_arm_is_a_value_error_naming_it(three_link, function):
    with pytest.raises(ValueError, match="transform") as e:
        function(three_link, ARM_START, ARM_GOAL, 10.0, transform="eq14")
    assert isinstance(e.value, ff.BadInput) and e.value.name == "transform"
    assert "NFA" in str(e.value) and "3 links" in str(e.value)
    # Never silently ignored, whatever its value (the default too).
    with pytest.raises(ValueError, match="transform"):
        function(three_link, ARM_START, ARM_GOAL, 10.0, transform="auto")
    # An unknown keyword is a TypeError, as for any function.
    with pytest.raises(TypeError, match="smoothness"):
        function(three_link, ARM_START, ARM_GOAL, 10.0, smoothness=2)


def test_a_two_link_arm_with_its_own_limits_goes_the_arm_way(src, tmp_path):
    """A 2-link arm of the paper's model whose robot file declares a velocity limit is planned
    by the arm pipeline, which keeps the limit (the 2-link pipeline would not see it), and it
    refuses ``transform`` for that reason."""
    free = ff.plan(src, START, GOAL, HORIZON)
    peak = float(np.max(np.abs(free.dq[:, 1])))
    limit = 0.9 * peak
    text = ff.Arm.from_robot(src).to_toml()
    first = text.index("[[link]]") + len("[[link]]\n")
    (tmp_path / "limited.toml").write_text(text[:first] + f"limit = {{ velocity = {limit!r} }}\n" + text[first:])
    arm = ff.Arm.from_file(tmp_path / "limited.toml")
    assert arm.joints == 2 and arm.constrained
    p = ff.plan(arm, START, GOAL, HORIZON)
    assert type(p) is ff.Plan and p.final_error <= p.tolerance
    assert np.max(np.abs(p.dq[:, 1])) <= limit * (1 + 1e-6)
    # A limit cannot lower the least effort, but each plan is the least on its own basis: the
    # limited one, at its velocity limit where it leaves rest, is solved on end spans graded to
    # h/64, the free one on h/4 (docs/spec.md §2, `chain::limits::ends`), and both approach the
    # infimum from rest from above (here the limited plan came 0.09 % under the free one).
    assert p.effort >= free.effort * (1 - 2e-3)
    with pytest.raises(ValueError, match="limits or shapes") as e:
        ff.plan(arm, START, GOAL, HORIZON, transform="eq14")
    assert e.value.name == "transform"


def test_plan_arm_warns_and_returns_the_same_plan(three_link):
    with pytest.warns(DeprecationWarning, match="plan_arm is deprecated"):
        old = ff.plan_arm(three_link, ARM_START, ARM_GOAL, 10.0, samples=101, torques=True)
    new = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, samples=101, torques=True)
    assert type(old) is type(new) is ff.Plan
    assert old.effort == new.effort and old.final_error == new.final_error
    for name in ARRAYS:
        x, y = getattr(old, name), getattr(new, name)
        assert (x is None) == (y is None), name
        if x is not None:
            np.testing.assert_array_equal(x, y, err_msg=name)
    assert set(old.certificate) == set(new.certificate)
    assert math.isclose(old.horizon, new.horizon, rel_tol=0.0, abs_tol=0.0)
