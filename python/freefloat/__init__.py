"""freefloat: motion planning of planar free-floating space robots: the minimum-effort
planner (``method="optimal"``, the default), the Normal Form Approach (NFA) and the ECSA
comparison method, every plan certified by re-integration.

Angles in radians, SI units, results as NumPy arrays::

    import numpy as np, freefloat as ff
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    p = ff.plan(robot, np.radians([45, 120, 80]), np.radians([0, 180, 140]), 10.0)
    p.q[-1], p.final_error, p.effort, p.end_effector[-1]
    nfa = ff.plan(robot, p.q[0], p.q[-1], 10.0, method="nfa")  # nfa.certificate["transform"]
    ee = ff.plan(robot, p.q[0], T=10.0, goal_ee=(0.3, 0.4, np.radians(100)))  # task space

Any planar serial arm (n links with inertias, from a TOML ``[[link]]`` file or a URDF) is an
:class:`Arm`, planned by the same :func:`plan` (the minimum-effort planner or the ECSA; ``q =
(phi, theta_1..theta_n)``, relative joint angles); the result is the same :class:`Plan`, with
the same arrays (``t, q, dq, ddq, tau, base, end_effector, end_effector_velocity``)::

    arm = ff.Arm.from_file("examples/robots/three_link.toml")
    a = ff.plan(arm, [0, 0.3, -0.4, 0.2], [0.5, 0.8, 0.2, -0.3], 10.0, torques=True)
    a.q.shape, a.tau.shape, a.end_effector[-1], a.certificate["torque_certificate"]["certificate"]["certified"]

``plan_arm`` is kept as a deprecated alias of :func:`plan` for arms, ``ArmPlan`` as another name
of :class:`Plan`.
"""

import warnings as _warnings
from typing import Any as _Any
from typing import Union as _Union


from ._errors import BadInput, FreefloatError, NoPlan, NotCertified
from ._freefloat import (
    METHODS,
    Arm,
    ArmPlan,
    Domain,
    Plan,
    Robot,
    __version__,
    domain,
    track,
)
from ._freefloat import compare as _compare_robot
from ._freefloat import plan as _plan_robot
from ._freefloat import plan_arm as _plan_arm

#: Keywords of :func:`plan` that an arm planned by the arm pipeline takes (every arm but a
#: 2-link arm of the paper's model without limits or shapes, which goes the 2-link way).
_ARM_KEYWORDS = frozenset(
    ("samples", "torques", "wrap", "initial_velocity", "tolerance", "method", "harmonics", "window",
     "smooth_ends", "cost", "limits", "obstacles", "clearance", "no_collide")
)

#: Keywords that only an arm carries (the 2-link pipeline's robot has neither limits nor shapes).
_ARM_ONLY = ("limits", "obstacles", "clearance", "no_collide")

#: Keywords of :func:`plan` for a :class:`Robot` that the arm pipeline does not take, and why.
_ROBOT_ONLY = {
    "transform": (
        "it picks the NFA's normal form (Eq. 11, 12, 14 or the global one), a transformation of "
        "the paper's 2-link robot; the arm pipeline has no NFA (Eq. 10's chained form is for two "
        "joints)"
    ),
}


def _arm_pipeline(arm: Arm) -> bool:
    """Whether :func:`plan` plans ``arm`` by the arm pipeline: any arm but a 2-link arm of the
    paper's model (:meth:`Arm.to_robot`) without limits or shapes of its own."""
    if arm.joints != 2 or arm.constrained:
        return True
    try:
        arm.to_robot()
    except BadInput:
        return True
    return False


def _paper_model(arm: Arm) -> bool:
    """Whether ``arm`` is a 2-link arm of the paper's model (:meth:`Arm.to_robot`), limits and
    shapes aside: the NFA plans it (checked against them)."""
    if arm.joints != 2:
        return False
    try:
        arm.to_robot()
    except BadInput:
        return False
    return True


def _check_arm_keywords(function: str, arm: Arm, kwargs: dict) -> None:
    """Every keyword of ``kwargs`` is one the arm pipeline takes for ``arm``: one of
    :data:`_ROBOT_ONLY` is :class:`BadInput` (a ``ValueError``) naming it and why, any other
    unknown keyword ``TypeError`` (as for any function)."""
    for name in sorted(kwargs):
        if name in _ROBOT_ONLY:
            pipeline = (
                "a 2-link arm with limits or shapes (or not of the paper's model) is planned by the arm pipeline"
                if arm.joints == 2
                else f"an arm of {arm.joints} links is planned by the arm pipeline"
            )
            expected = f"no {name} for this arm (the keywords {', '.join(sorted(_ARM_KEYWORDS))})"
            raise BadInput(
                f"{function}: {name} does not apply to this Arm: {pipeline}, and {_ROBOT_ONLY[name]}; drop {name}",
                kind="invalid_parameter",
                details={"name": name, "expected": expected},
            )
        if name not in _ARM_KEYWORDS:
            raise TypeError(f"{function}() got an unexpected keyword argument {name!r}")


def plan(robot: _Union[Robot, Arm], start: _Any, goal: _Any = None, T: _Any = None, **kwargs: _Any) -> Plan:
    """Plans a motion of ``robot`` (a :class:`Robot`, or an :class:`Arm` of any number of
    links) from ``start`` to ``goal`` in ``T`` seconds and certifies it; the result is a
    :class:`Plan` for every robot (``ArmPlan`` is another name of the class).

    A :class:`Robot`, or a 2-link :class:`Arm` of the paper's model without limits or shapes of
    its own, takes every method and keyword (the 2-link pipeline); any other :class:`Arm` (the
    arm pipeline) takes ``method="optimal"`` or ``"ecsa"`` (and ``"nfa"`` for a 2-link arm of the
    paper's model with limits or shapes: the NFA's plan of the paper's :class:`Robot`, checked
    against them, :class:`NotCertified` outside) and the keywords ``samples, torques,
    wrap, initial_velocity, tolerance, harmonics, window, smooth_ends, cost, limits, obstacles,
    clearance, no_collide``: ``transform`` (the NFA's) is :class:`BadInput` (a ``ValueError``)
    naming it and why, an unknown keyword ``TypeError``. Its ``goal_ee`` (the command line's
    ``--to-ee``) plans every branch of the arm's inverse kinematics that reaches the pose and
    keeps the certified plan of least effort (``elbow`` only for a 2-link arm). Bad input raises
    :class:`BadInput`, a plan that is not certified :class:`NotCertified`.

    ``T="auto"`` (the command line's ``--time auto``; issue 20 item 4), for an :class:`Arm` of any
    number of links with a velocity, acceleration or torque limit (its own or ``limits=``) and
    ``method="optimal"``: plans at the shortest horizon, to 1 %, in which a certified plan fits
    every limit (the search's first probe is 10 s); the returned plan's ``horizon``, ``t[-1]``
    and ``certificate["time"]`` are the horizon found. Elsewhere (no such limit, another method,
    a :class:`Robot` without ``limits=``) ``T="auto"`` raises :class:`BadInput` naming
    ``T="auto"`` and why; any other string for ``T`` is :class:`BadInput`.
    """
    arm_only = any(kwargs.get(k) is not None for k in _ARM_ONLY)
    auto = isinstance(T, str) and T == "auto"
    if arm_only and isinstance(robot, Robot):
        # Issues 20, 21: the 2-link pipeline does not carry limits or shapes; an arm's does.
        robot = Arm.from_robot(robot)
    if auto and isinstance(robot, Robot):
        # Issue 20 item 4: the shortest horizon is the one inside the arm's limits.
        expected = (
            "the optimal method and an arm with a velocity, acceleration or torque limit: the shortest horizon "
            "is the one in which the motion fits them"
        )
        raise BadInput(
            f'plan: T="auto": a Robot (the 2-link pipeline) has no limits; expected {expected} '
            "(give limits=, and the Robot is planned as an Arm)",
            kind="invalid_parameter",
            details={"name": 'T="auto"', "value": 2, "expected": expected},
        )
    if isinstance(robot, Arm):
        if arm_only or auto or _arm_pipeline(robot):
            return _plan_by_arm_pipeline("plan", robot, start, goal, T, kwargs)
        robot = robot.to_robot()
    return _plan_robot(robot, start, goal, T, **kwargs)


def _plan_by_arm_pipeline(function: str, arm: Arm, start: _Any, goal: _Any, T: _Any, kwargs: dict) -> Plan:
    """:func:`plan` of ``arm`` by the arm pipeline (the native ``plan_arm``), its keywords
    checked first (:func:`_check_arm_keywords`)."""
    kwargs = dict(kwargs)
    goal_ee = kwargs.pop("goal_ee", None)
    elbow = kwargs.pop("elbow", None)
    _check_arm_keywords(function, arm, kwargs)
    if goal_ee is not None or elbow is not None:
        return _plan_arm_to_pose(arm, start, goal, T, goal_ee, elbow, **kwargs)
    if goal is None or T is None:
        raise BadInput(f"{function}: an arm takes start, goal (or goal_ee) and T (n + 1 angles each, T in s)")
    return _plan_arm(arm, start, goal, T, **kwargs)


def _plan_arm_to_pose(arm: Arm, start: _Any, goal: _Any, T: _Any, goal_ee: _Any, elbow: _Any, **kwargs: _Any) -> _Any:
    """:func:`plan` of an arm to the tool pose ``goal_ee = (x, y, psi)`` [m, m, rad] (the command
    line's ``--to-ee``, issue 19 item 4): every branch of the free-floating inverse kinematics
    (:meth:`Arm.inverse_kinematics`) that reaches the pose is planned and the certified plan of
    least effort kept; ``elbow`` ("up", "down") picks one of a 2-link arm's two branches."""
    if goal_ee is None:
        raise BadInput("plan: elbow applies to a goal_ee, not to a goal configuration", kind="conflict")
    if goal is not None:
        raise BadInput("plan: give either goal (joint space) or goal_ee (task space), not both", kind="conflict")
    if T is None:
        raise BadInput("plan: an arm takes start, goal_ee and T (T in s)")
    if elbow is not None and (arm.joints != 2 or elbow not in ("up", "down")):
        raise BadInput(
            f"plan: elbow={elbow!r} chooses between the two inverse-kinematics solutions of a 2-link arm "
            f"(\"up\" or \"down\"); this arm has {arm.joints} link(s): drop elbow (every branch is tried and "
            "the certified plan of least effort kept)",
            kind="invalid_parameter",
            details={"name": "elbow", "expected": '"up" or "down", for a 2-link arm'},
        )
    # The library plans every reaching branch and keeps the least effort (its report's
    # ``to_ee`` lists them), as ``--to-ee`` does.
    return _plan_arm(arm, start, None, T, goal_ee=goal_ee, branch=elbow, **kwargs)


#: Keywords that only one method takes; :func:`compare` gives each method its own and ignores
#: the others' (as ``freefloat compare``).
_OWN_KEYWORDS = {"optimal": ("smooth_ends", "cost"), "ecsa": ("harmonics", "window")}


def compare(
    robot: _Union[Robot, Arm],
    start: _Any,
    goal: _Any = None,
    T: _Any = None,
    *,
    methods: _Any = None,
    strict: bool = True,
    **kwargs: _Any,
) -> _Any:
    """Plans the same problem with each of ``methods``, as a dict method -> plan (issue 19 item
    4: every arm, as ``freefloat compare``).

    A :class:`Robot`, or a 2-link :class:`Arm` that is the paper's model, takes every method
    (default :data:`METHODS`: optimal, NFA and ECSA) and returns :class:`Plan` values. Any other
    :class:`Arm` (or a robot given ``limits``, ``obstacles``, ``clearance`` or ``no_collide``) is
    compared by the arm pipeline: by default ``optimal`` and ``ecsa`` (and ``nfa`` for a 2-link
    arm of the paper's model, its plan checked against the arm's limits and shapes), as
    :class:`Plan` values with the keywords of :func:`plan` for an arm; elsewhere the NFA is
    refused with :class:`BadInput` (the paper's normal form, Eq. 10, is for two joints of the
    paper's model). Each method takes its own keywords and ignores the others'. With ``strict=False``
    a method without a certified plan maps to its exception instead of raising it; bad input
    always raises."""
    arm_only = any(kwargs.get(k) is not None for k in _ARM_ONLY)
    if arm_only and isinstance(robot, Robot):
        robot = Arm.from_robot(robot)
    if isinstance(robot, Arm) and not arm_only and not _arm_pipeline(robot):
        robot = robot.to_robot()
    if not isinstance(robot, Arm):
        return _compare_robot(robot, start, goal, T, methods=methods, strict=strict, **kwargs)
    # A 2-link arm of the paper's model with limits or shapes: the NFA's plan of the paper's Robot
    # checked against them (as the command line's compare).
    served = ("optimal", "nfa", "ecsa") if _paper_model(robot) else ("optimal", "ecsa")
    names = list(served if methods is None else methods)
    for name in names:
        if name not in METHODS:
            raise BadInput(
                f"compare: unknown method {name!r}: expected one of {', '.join(METHODS)}",
                kind="invalid_parameter",
                details={"name": "methods", "expected": ", ".join(METHODS)},
            )
        if name not in served:
            why = (
                "the NFA's normal form (Eq. 10) is for two joints"
                if name == "nfa" and robot.joints != 2
                else "the NFA plans a 2-link arm of the paper's model, and this one is not"
            )
            raise BadInput(
                f"compare: method {name!r} does not serve this arm of {robot.joints} link(s): {why}; "
                f"expected methods among {', '.join(served)}",
                kind="invalid_parameter",
                details={"name": "methods", "expected": ", ".join(served)},
            )
    out = {}
    for name in names:
        others = [k for m, keys in _OWN_KEYWORDS.items() if m != name for k in keys]
        own = {k: v for k, v in kwargs.items() if k not in others}
        try:
            out[name] = plan(robot, start, goal, T, method=name, **own)
        except (NotCertified, NoPlan) as e:
            if strict:
                raise
            out[name] = e
    return out


def plan_arm(arm: _Union[Robot, Arm], start: _Any, goal: _Any, T: float, **kwargs: _Any) -> Plan:
    """Deprecated alias: :func:`plan` takes any arm. Plans ``arm`` (a 2-link :class:`Robot`
    converted) by the arm pipeline, the native function that :func:`plan` calls for an arm."""
    _warnings.warn("freefloat.plan_arm is deprecated: use freefloat.plan(arm, ...)", DeprecationWarning, stacklevel=2)
    return _plan_arm(arm, start, goal, T, **kwargs)



__all__ = [
    "METHODS",
    "Arm",
    "ArmPlan",
    "BadInput",
    "Domain",
    "FreefloatError",
    "NoPlan",
    "NotCertified",
    "Plan",
    "Robot",
    "__version__",
    "compare",
    "domain",
    "plan",
    "plan_arm",
    "track",
]
