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
"""

from ._errors import BadInput, FreefloatError, NoPlan, NotCertified
from ._freefloat import METHODS, Domain, Plan, Robot, __version__, compare, domain, plan, track

__all__ = [
    "METHODS",
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
    "track",
]
