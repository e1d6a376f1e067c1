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
:class:`Arm`, planned by :func:`plan_arm` (the minimum-effort planner; ``q = (phi, theta_1..
theta_n)``, relative joint angles)::

    arm = ff.Arm.from_file("examples/robots/three_link.toml")
    a = ff.plan_arm(arm, [0, 0.3, -0.4, 0.2], [0.5, 0.8, 0.2, -0.3], 10.0, torques=True)
    a.q.shape, a.tau.shape, a.final_error, a.certificate["torque_certificate"]["certified"]
"""

from ._errors import BadInput, FreefloatError, NoPlan, NotCertified
from ._freefloat import (
    METHODS,
    Arm,
    ArmPlan,
    Domain,
    Plan,
    Robot,
    __version__,
    compare,
    domain,
    plan,
    plan_arm,
    track,
)

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
