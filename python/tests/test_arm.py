"""Any planar serial arm from Python (issue 14, item 4): the robot files of the command line
(TOML with ``[[link]]``, URDF) load as ``freefloat.Arm``; ``plan`` plans and certifies them;
its plans conserve angular momentum; a 2-link Robot planned as an arm (the deprecated
``plan_arm``) agrees with ``plan``."""

import math
import threading
from pathlib import Path

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START, wrapped_distance

ROBOTS = Path(__file__).resolve().parents[2] / "examples" / "robots"
THREE_LINK_TOML = ROBOTS / "three_link.toml"
THREE_LINK_URDF = ROBOTS / "three_link.urdf"

# Rest to rest: the base turns by 0.5 rad while every joint moves.
ARM_START = [0.0, 0.3, -0.4, 0.2]
ARM_GOAL = [0.5, 0.8, 0.2, -0.3]

LINK = {"length": 0.4, "com": 0.2, "mass": 2.0, "inertia": 2.0 * 0.4**2 / 12}


@pytest.fixture(scope="module")
def three_link():
    return ff.Arm.from_file(THREE_LINK_TOML)


@pytest.fixture(scope="module")
def three_link_plan(three_link):
    return ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, torques=True)


def test_the_robot_file_loads(three_link):
    assert three_link.joints == 3
    assert three_link.M == 12.9 and three_link.I == 0.208 and three_link.a == 0.0 and three_link.b == 0.0
    assert [link["length"] for link in three_link.links] == [0.45, 0.40, 0.35]
    assert three_link.links[0] == {"length": 0.45, "com": 0.225, "mass": 3.0, "inertia": 0.050625}
    # links print as the dicts arm.links hands out (issue 23), not as tuples
    assert repr(three_link).startswith("Arm(M=12.9, I=0.208, links=[{'length': 0.45, 'com': 0.225, 'mass': 3.0,")


def test_urdf_round_trip(three_link, tmp_path):
    urdf = ff.Arm.from_file(THREE_LINK_URDF)
    assert urdf.joints == three_link.joints
    for name in ("M", "I", "a", "b"):
        assert getattr(urdf, name) == pytest.approx(getattr(three_link, name), abs=1e-12)
    for mine, theirs in zip(urdf.links, three_link.links):
        assert mine.keys() == theirs.keys()
        for key in mine:
            assert mine[key] == pytest.approx(theirs[key], abs=1e-12)
    # The arm's own URDF and TOML read back to the same arm.
    (tmp_path / "arm.urdf").write_text(three_link.to_urdf())
    (tmp_path / "arm.toml").write_text(three_link.to_toml())
    assert ff.Arm.from_file(tmp_path / "arm.urdf") == three_link
    assert ff.Arm.from_file(tmp_path / "arm.toml") == three_link


def test_three_link_rest_to_rest_is_certified(three_link, three_link_plan):
    p = three_link_plan
    n, s = 3, 1001
    assert p.method == "optimal" and p.joints == n and p.certified
    assert p.final_error <= 1e-9
    assert wrapped_distance(p.q[-1], ARM_GOAL) <= 1e-9
    assert np.max(np.abs(p.q[0] - ARM_START)) <= 1e-12
    # At rest at both ends.
    assert np.max(np.abs(p.dq[[0, -1]])) <= 1e-9
    # Shapes.
    assert p.t.shape == (s,) and p.q.shape == (s, n + 1) and p.dq.shape == (s, n + 1)
    assert p.ddtheta.shape == (s, n) and p.tau.shape == (s, n)
    assert p.t[0] == 0.0 and p.t[-1] == pytest.approx(10.0, abs=1e-12)
    assert all(a.dtype == np.float64 for a in (p.t, p.q, p.dq, p.ddtheta, p.tau))
    # The certificate is the CLI's report.
    c = p.certificate
    assert c["method"] == "optimal" and c["joints"] == n and c["certified"] is True
    assert c["final_error"] == p.final_error and c["effort"] == p.effort and c["samples"] == s
    assert c["start"] == ARM_START and c["goal"] == ARM_GOAL and c["time"] == 10.0
    assert len(c["robot"]["links"]) == n
    assert wrapped_distance(c["reached"], ARM_GOAL) == pytest.approx(p.final_error, abs=1e-15)
    # The torque level holds.
    t = c["torque_certificate"]["certificate"]
    assert t["certified"] is True and t["final_error"] <= t["tolerance"]
    assert c["torque_final_error"] == t["final_error"]
    assert c["max_abs_torque"] == pytest.approx(np.max(np.abs(p.tau), axis=0).tolist(), rel=1e-12)
    # The 2-link robot's keys (one report for every arm): the peaks and the base row beside it.
    assert c["torque_certificate"]["max_abs_torque"] == c["max_abs_torque"]
    assert abs(c["torque_certificate"]["max_abs_base_residual"]) < 1e-9


def test_without_torques_there_are_none(three_link):
    p = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, samples=51)
    assert p.tau is None and p.q.shape == (51, 4) and p.ddtheta.shape == (51, 3)
    assert p.certificate["torque_certificate"] is None  # the one report: null without torques
    assert repr(p).startswith("Plan(method='optimal', samples=51, joints=3, final_error=")


def test_planning_in_threads(three_link):
    # The GIL is released while planning; two threads give the plan of one.
    expected = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, samples=101).q
    results = [None, None]

    def work(i):
        results[i] = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, samples=101).q

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(r, expected) for r in results)


def test_momentum_is_conserved(three_link, three_link_plan):
    p = three_link_plan
    momentum = [three_link.momentum(q, dq) for q, dq in zip(p.q, p.dq)]
    assert max(abs(h) for h in momentum) <= 1e-10
    # ... and the base's rate is what keeps it zero: the joints alone carry momentum.
    dq = p.dq.copy()
    dq[:, 0] = 0.0
    assert max(abs(three_link.momentum(q, w)) for q, w in zip(p.q, dq)) > 1e-3


def test_a_robot_planned_as_an_arm_agrees_with_plan(src):
    robot = src.with_mount(0.1, 0.1)
    arm = ff.Arm.from_robot(robot)
    assert arm.joints == 2 and arm.a == 0.1 and arm.b == 0.1
    assert arm.to_robot() == robot
    two_joint = ff.plan(robot, START, GOAL, HORIZON)
    for given in (arm, robot):
        # plan_arm (deprecated) plans a 2-link arm by the arm pipeline, not the 2-link one.
        with pytest.warns(DeprecationWarning):
            n_joint = ff.plan_arm(given, START, GOAL, HORIZON)
        assert n_joint.final_error <= 1e-9
        assert n_joint.effort == pytest.approx(two_joint.effort, rel=1e-6)
        assert np.max(np.abs(n_joint.q[-1] - two_joint.q[-1])) <= 1e-6


def test_constructor_takes_dicts_and_tuples():
    by_dict = ff.Arm(M=15.0, I=0.4, links=[LINK, LINK], a=0.1, b=-0.05)
    by_tuple = ff.Arm(M=15.0, I=0.4, links=[tuple(LINK.values())] * 2, a=0.1, b=-0.05)
    assert by_dict == by_tuple and by_dict.joints == 2
    point_mass = ff.Arm(M=15.0, I=0.4, links=[{"length": 0.4, "com": 0.2, "mass": 2.0}])
    assert point_mass.links[0]["inertia"] == 0.0
    assert ff.Arm(M=15.0, I=0.4, links=[(0.4, 0.2, 2.0)]) == point_mass
    moved = by_dict.with_mount(0.2, 0.3)
    assert (moved.a, moved.b) == (0.2, 0.3) and moved.links == by_dict.links
    # A seven-link arm plans too.
    seven = ff.Arm(M=20.0, I=0.6, links=[LINK] * 7)
    p = ff.plan(seven, [0.0] * 8, [0.3] + [0.2, -0.1] * 3 + [0.1], 10.0, samples=101)
    assert p.final_error <= 1e-9 and p.q.shape == (101, 8)


@pytest.mark.parametrize(
    "links, key",
    [
        ([], "link"),
        ([{**LINK, "mass": -1.0}], "link[1].mass"),
        ([LINK, {**LINK, "com": 0.5}], "link[2].com"),
        ([LINK, {**LINK, "inertia": float("nan")}], "link[2].inertia"),
        ([LINK, {"length": 0.4, "com": 0.2}], "link[2].mass"),
        ([{**LINK, "lenght": 0.4}], "link[1].lenght"),
        ([(0.4, 0.2)], "link[1]"),
        ([LINK] * 16, "link"),
    ],
)
def test_bad_links(links, key):
    with pytest.raises(ff.BadInput) as e:
        ff.Arm(M=15.0, I=0.4, links=links)
    assert e.value.name == key and f"`{key}`" in str(e.value)


def test_bad_base_and_mount():
    with pytest.raises(ff.BadInput, match=r"`robot\.M`"):
        ff.Arm(M=0.0, I=0.4, links=[LINK])
    with pytest.raises(ff.BadInput, match=r"`mount\.a`"):
        ff.Arm(M=15.0, I=0.4, links=[LINK], a=float("inf"))
    with pytest.raises(TypeError, match=r"link\[1\]\.mass"):
        ff.Arm(M=15.0, I=0.4, links=[{**LINK, "mass": "heavy"}])
    with pytest.raises(ff.BadInput) as e:
        ff.Arm.from_file(ROBOTS / "no_such_robot.toml")
    assert "no_such_robot.toml" in str(e.value)


@pytest.mark.parametrize(
    "start, goal, keywords, key",
    [
        ([np.nan, 0.3, -0.4, 0.2], ARM_GOAL, {}, "start[0]"),
        ([0.0, 0.3, -0.4], ARM_GOAL, {}, "start.len"),
        (ARM_START, [0.5, 0.8, 0.2, -0.3, 0.0], {}, "goal.len"),
        (ARM_START, ARM_GOAL, {"initial_velocity": [0.0, 0.1]}, "initial_velocity.len"),
        (ARM_START, ARM_GOAL, {"method": "nfa"}, "method"),
        (ARM_START, ARM_GOAL, {"method": "rrt"}, "method"),
        (ARM_START, ARM_GOAL, {"samples": 1}, "samples"),
        (ARM_START, ARM_GOAL, {"tolerance": 0.0}, "tolerance"),
    ],
)
def test_bad_problems(three_link, start, goal, keywords, key):
    with pytest.raises(ff.BadInput) as e:
        ff.plan(three_link, start, goal, 10.0, **keywords)
    assert e.value.name == key and key in str(e.value)


def test_method_refusals_give_the_reason(three_link, src):
    with pytest.raises(ff.BadInput, match="chained form"):
        ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, method="nfa")
    # The ECSA plans any arm (issue 14); from rest only.
    # (The CLI test's problem: from ARM_START the iteration ends on a motion whose certificate
    # at rtol 1e-12 misses 1e-9 rad, NotCertified.)
    start = [math.radians(x) for x in (0, 60, -30, -30)]
    goal = [math.radians(x) for x in (30, 120, 40, -60)]
    plan = ff.plan(three_link, start, goal, 10.0, method="ecsa")
    assert plan.certified and plan.method == "ecsa"
    # Its harmonics and window, as for plan; given to another method they are misplaced.
    two = ff.plan(three_link, start, goal, 10.0, method="ecsa", harmonics=2, window="sin2")
    assert two.certified and two.certificate["ecsa"]["harmonics"] == 2
    assert two.certificate["ecsa"]["window"] == "sin_squared"
    with pytest.raises(ff.BadInput, match="harmonics"):
        ff.plan(three_link, start, goal, 10.0, harmonics=2)
    with pytest.raises(ff.BadInput, match="window"):
        ff.plan(three_link, start, goal, 10.0, method="ecsa", window="hann")
    with pytest.raises(ff.BadInput, match="from rest"):
        ff.plan(three_link, start, goal, 10.0, method="ecsa", initial_velocity=[0.1, 0.0, 0.0])
    # A 2-link arm of the paper's model: the NFA's plan of its Robot (the same effort).
    with pytest.warns(DeprecationWarning):
        nfa = ff.plan_arm(src, START, GOAL, HORIZON, method="nfa")
    assert nfa.certified and nfa.effort == pytest.approx(ff.plan(src, START, GOAL, HORIZON, method="nfa").effort)
    with pytest.raises(TypeError):
        ff.plan("three_link.toml", ARM_START, ARM_GOAL, 10.0)


def test_one_link_goal_off_its_holonomy_is_bad_input():
    arm = ff.Arm(M=15.0, I=0.4, links=[LINK])
    with pytest.raises(ff.BadInput) as e:
        ff.plan(arm, [0.0, 0.0], [0.5, 0.3], 10.0)
    assert e.value.kind == "holonomy_fixed"
    reachable = e.value.details["reachable"]
    p = ff.plan(arm, [0.0, 0.0], [reachable, 0.3], 10.0)
    assert p.final_error <= 1e-9 and p.q.shape == (1001, 2)


def test_bad_horizon_and_bad_urdf(three_link, tmp_path):
    with pytest.raises(ff.BadInput) as e:
        ff.plan(three_link, ARM_START, ARM_GOAL, float("nan"))
    assert e.value.name == "horizon"
    # A prismatic joint is no planar revolute chain: the error names the joint.
    urdf = three_link.to_urdf()
    joint2 = urdf.index('<joint name="joint2" type="continuous">')
    bad = urdf[:joint2] + urdf[joint2:].replace('type="continuous"', 'type="prismatic"', 1)
    (tmp_path / "bad.urdf").write_text(bad)
    with pytest.raises(ff.BadInput) as e:
        ff.Arm.from_file(tmp_path / "bad.urdf")
    assert e.value.kind == "urdf" and "joint2" in e.value.details["element"]


def test_plan_serves_every_arm_with_the_task_space_arrays(three_link):
    # One `plan` for every robot: an Arm of 3 links gets the arrays of a 2-link Plan, the end
    # effector the tool point of the arm's own forward kinematics (recomputed here from the
    # links: the centre of mass at the origin), the base's rate and acceleration consistent.
    p = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, samples=201)
    s, n = 201, 3
    assert isinstance(p, ff.Plan)
    assert p.ddq.shape == (s, n + 1) and p.base.shape == (s, 2)
    assert p.end_effector.shape == (s, 3) and p.end_effector_velocity.shape == (s, 3)
    np.testing.assert_array_equal(p.ddq[:, 1:], p.ddtheta)
    links = three_link.links
    for i in range(0, s, 50):
        q = p.q[i]
        psi = np.cumsum(q)[1:]
        e = np.stack([np.cos(psi), np.sin(psi)], axis=1)
        mount = np.array([np.cos(q[0]) * three_link.a - np.sin(q[0]) * three_link.b,
                          np.sin(q[0]) * three_link.a + np.cos(q[0]) * three_link.b])
        joint = mount.copy()
        moment = np.zeros(2)
        for k, link in enumerate(links):
            moment += link["mass"] * (joint + link["com"] * e[k])
            joint = joint + link["length"] * e[k]
        base = -moment / (three_link.M + sum(l["mass"] for l in links))
        np.testing.assert_allclose(p.base[i], base, atol=1e-12)
        np.testing.assert_allclose(p.end_effector[i, :2], joint + base, atol=1e-12)
        assert p.end_effector[i, 2] == pytest.approx(q.sum(), abs=1e-12)
    # A 2-link paper-model Arm goes the 2-link way: a Plan, every method.
    src_arm = ff.Arm.from_robot(ff.Robot.src())
    assert isinstance(ff.plan(src_arm, START, GOAL, HORIZON, method="nfa"), ff.Plan)


def test_compare_serves_every_arm(three_link):
    """Issue 19 item 4: ``compare`` on a 3-link arm runs the minimum-effort planner and the
    ECSA (each with its own keywords, the others' ignored), each plan the one ``plan`` gives,
    certified; the NFA is refused with the reason (its normal form is for two joints)."""
    plans = ff.compare(three_link, ARM_START, ARM_GOAL, 10.0, harmonics=2, smooth_ends=True)
    assert set(plans) == {"optimal", "ecsa"}
    own = {"optimal": {"smooth_ends": True}, "ecsa": {"harmonics": 2}}
    for method, p in plans.items():
        assert isinstance(p, ff.Plan) and p.final_error <= 1e-9
        single = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, method=method, **own[method])
        assert p.effort == pytest.approx(single.effort, rel=1e-9)
        assert np.max(np.abs(p.q[-1] - single.q[-1])) <= 1e-12
    # The minimum-effort plan costs no more than the ECSA's certified plan of the same problem.
    assert plans["optimal"].effort <= plans["ecsa"].effort
    with pytest.raises(ff.BadInput, match="two joints"):
        ff.compare(three_link, ARM_START, ARM_GOAL, 10.0, methods=["optimal", "nfa"])
    with pytest.raises(ff.BadInput, match="unknown method"):
        ff.compare(three_link, ARM_START, ARM_GOAL, 10.0, methods=["fastest"])


def test_goal_ee_serves_every_arm(three_link):
    """Issue 19 item 4: ``goal_ee`` on a 3-link arm (the command line's ``--to-ee``) plans every
    branch of the inverse kinematics that reaches the pose and keeps the certified plan of least
    effort; its tool ends on the pose; what cannot be asked of an arm of 3 links is BadInput."""
    pose = ff.plan(three_link, ARM_START, ARM_GOAL, 10.0).end_effector[-1]
    p = ff.plan(three_link, ARM_START, T=10.0, goal_ee=pose)
    assert isinstance(p, ff.Plan) and p.final_error <= 1e-9
    assert np.max(np.abs(p.end_effector[-1][:2] - pose[:2])) <= 1e-8
    assert abs(math.remainder(p.end_effector[-1][2] - pose[2], math.tau)) <= 1e-8
    branches = [b for b in three_link.inverse_kinematics(pose, ARM_START) if b["reached"]]
    assert branches and all(b["residual"] <= 1e-6 for b in branches)
    efforts = [ff.plan(three_link, ARM_START, b["q"], 10.0).effort for b in branches]
    assert p.effort == pytest.approx(min(efforts), rel=1e-9)
    # The report lists every branch tried, the kept one with the plan's effort.
    listed = p.certificate["to_ee"]["branches"]
    kept = [b for b in listed if b["kept"]]
    assert len(listed) >= len(branches) and len(kept) == 1, listed
    assert kept[0]["effort"] == pytest.approx(p.effort, rel=1e-12)
    with pytest.raises(ff.BadInput, match="elbow"):
        ff.plan(three_link, ARM_START, T=10.0, goal_ee=pose, elbow="up")
    with pytest.raises(ff.BadInput, match="not both"):
        ff.plan(three_link, ARM_START, ARM_GOAL, 10.0, goal_ee=pose)
    with pytest.raises(ff.BadInput, match="out of reach"):
        ff.plan(three_link, ARM_START, T=10.0, goal_ee=(50.0, 0.0, 0.0))
    with pytest.raises(ff.BadInput):
        three_link.inverse_kinematics((0.5, float("nan"), 0.0), ARM_START)


def test_a_two_link_arm_with_limits_plans_and_compares_the_nfa_checked_against_them():
    """A 2-link arm of the paper's model given limits is planned and compared as on the command
    line: the NFA plans the paper's Robot (the same plan, its effort equal) and its motion is
    checked against the limits; a limit under the NFA's peak is NotCertified naming it."""
    arm = ff.Arm.from_robot(ff.Robot.src())
    limits = {"theta1": {"velocity": 5.0}}
    plans = ff.compare(arm, START, GOAL, HORIZON, limits=limits)
    assert set(plans) == {"optimal", "nfa", "ecsa"}
    for p in plans.values():
        assert p.certified and p.final_error <= 1e-9
        assert p.certificate["limits"]["inside"] is True, p.certificate["limits"]
    paper = ff.plan(ff.Robot.src(), START, GOAL, HORIZON, method="nfa")
    assert plans["nfa"].method == "nfa" and plans["nfa"].effort == pytest.approx(paper.effort, rel=1e-12)
    # The NFA's peak theta2 rate is far above 0.01 rad/s: outside, never a plan.
    peak = float(np.max(np.abs(paper.dq[:, 2])))
    assert peak > 0.01
    with pytest.raises(ff.NotCertified, match="theta2"):
        ff.plan(arm, START, GOAL, HORIZON, method="nfa", limits={"theta2": {"velocity": 0.01}})
    with pytest.raises(ff.BadInput, match="method"):
        ff.plan(arm, START, T=HORIZON, goal_ee=(0.5, 0.5, 0.0), method="nfa", limits=limits)


def test_a_robot_and_an_arm_plan_carry_the_same_arrays_and_keys(three_link, three_link_plan):
    # Issue 19 item 5: one plan for every robot, the same arrays and the one report's keys.
    two = ff.plan(ff.Robot.src(), START, GOAL, HORIZON)
    three = three_link_plan
    public = lambda p: {name for name in dir(p) if not name.startswith("_")}  # noqa: E731
    # One class (ArmPlan another name of it): the same attributes, elbow None for an arm.
    assert type(two) is type(three) is ff.Plan is ff.ArmPlan
    assert public(three) == public(two) and three.elbow is None
    assert (two.joints, three.joints) == (2, 3)
    assert two.horizon == HORIZON and three.horizon == 10.0
    np.testing.assert_array_equal(two.ddtheta, two.ddq[:, 1:])
    assert two.ddtheta.shape == (len(two.t), 2) and three.ddtheta.shape == (len(three.t), 3)
    assert three.z is None and three.transform is None
    assert set(two.certificate) == set(three.certificate)
