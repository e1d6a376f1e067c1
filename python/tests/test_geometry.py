"""Obstacles and the clearance from Python (issue 21): ``obstacles=``, ``clearance=`` and
``no_collide=`` on ``plan`` for an arm, the command line's ``--obstacle``, ``--clearance`` and
``--no-collide``; the certificate reports the least clearance, a plan that cannot keep the
clearance is refused, bad shapes are ``BadInput``."""

import math

import pytest

import freefloat as ff

# The paper's problem on a 2-link arm whose links are 4 cm wide (TOML `width`).
START = [math.radians(x) for x in (45.0, 120.0, 80.0)]
GOAL = [math.radians(x) for x in (0.0, 180.0, 140.0)]
LINK = "[[link]]\nlength = {}\ncom = {}\nmass = {}\ninertia = 0.0\nwidth = 0.04\n"


@pytest.fixture(scope="module")
def arm(tmp_path_factory):
    path = tmp_path_factory.mktemp("robot") / "shapes.toml"
    path.write_text("[robot]\nM = 12.9\nI = 0.208\n" + LINK.format(0.619, 0.313, 4.5) + LINK.format(0.6, 0.287, 1.5))
    return ff.Arm.from_file(path)


# Below the end effector's path, about (-0.5, -0.42) m at 2.5 s and (-0.22, -0.38) m at 5 s.
BELOW = ("circle", -0.3, -0.65, 0.1)


def test_an_obstacle_is_checked_in_every_form(arm):
    plan = ff.plan(arm, START, GOAL, 10.0, obstacles=[BELOW])
    c = plan.certificate["clearance"]
    assert c["between"] == ["link 2", "obstacle 1"] and c["holds"] is True
    assert 0.05 < c["min"] < 0.3 and 0.0 < c["time"] < 10.0
    # The command line's spec string is the same obstacle; a polygon of its bounding square
    # (convex, around the circle) comes no farther than the circle.
    same = ff.plan(arm, START, GOAL, 10.0, obstacles=["circle:-0.3,-0.65,0.1"])
    assert same.certificate["clearance"]["min"] == pytest.approx(c["min"], abs=1e-12)
    square = [-0.4, -0.75, -0.2, -0.75, -0.2, -0.55, -0.4, -0.55]
    boxed = ff.plan(arm, START, GOAL, 10.0, obstacles=[("polygon", square)])
    assert boxed.certificate["clearance"]["min"] <= c["min"] + 1e-12


def test_a_clearance_the_motion_cannot_keep_is_refused(arm):
    # The end effector starts within 0.5 m of the obstacle: 1 m of clearance is impossible, and
    # the start is refused as bad input before any search, naming the end.
    with pytest.raises(ff.BadInput, match=r"start \(--from\).*under the clearance 1 m"):
        ff.plan(arm, START, GOAL, 10.0, obstacles=[BELOW], clearance=1.0)
    # Excluding the only pair checked that involves the obstacle for link 2 leaves link 1's.
    plan = ff.plan(arm, START, GOAL, 10.0, obstacles=[BELOW], no_collide=[("link2", "obstacle1")])
    assert plan.certificate["clearance"]["between"] == ["link 1", "obstacle 1"]


@pytest.mark.parametrize(
    ("keywords", "named"),
    [
        ({"obstacles": [("circle", 1.0, 1.0)]}, "obstacles"),
        ({"obstacles": [("triangle", 0.0, 0.0, 1.0)]}, "obstacles"),
        ({"obstacles": [42]}, "obstacles"),
        ({"obstacles": [BELOW], "clearance": -1.0}, "clearance"),
        ({"obstacles": [BELOW], "no_collide": [("base", "link9")]}, "no_collide"),
        ({"obstacles": [BELOW], "no_collide": [("base", "wing")]}, "no_collide"),
    ],
)
def test_bad_geometry_is_bad_input_naming_the_keyword(arm, keywords, named):
    # The keyword is named, not the command line's flag.
    with pytest.raises(ff.BadInput, match=named) as error:
        ff.plan(arm, START, GOAL, 10.0, **keywords)
    assert "--" not in str(error.value), str(error.value)


@pytest.mark.parametrize("keywords", [{"obstacles": [BELOW]}, {"clearance": 0.01}])
def test_obstacles_for_a_robot_without_shapes_are_bad_input(tmp_path, keywords):
    # Nothing would be checked, so a plan through the obstacle would pass as clear.
    links = LINK.format(0.619, 0.313, 4.5) + LINK.format(0.6, 0.287, 1.5)
    path = tmp_path / "bare.toml"
    path.write_text("[robot]\nM = 12.9\nI = 0.208\n" + links.replace("width = 0.04\n", ""))
    with pytest.raises(ff.BadInput, match="no shapes"):
        ff.plan(ff.Arm.from_file(path), START, GOAL, 10.0, **keywords)
