"""Type stubs of the native module ``freefloat._freefloat`` (PyO3). Import from ``freefloat``."""

from os import PathLike
from typing import Any, Literal, Mapping, Optional, Sequence, Tuple, Union, final, overload

import numpy as np
import numpy.typing as npt

from ._errors import FreefloatError

_Method = Literal["optimal", "nfa", "ecsa"]
_TransformName = Literal["auto", "eq11", "eq12", "eq14", "global"]
_WindowName = Literal["none", "sin2"]
_CostName = Literal["effort", "energy"]
_ElbowName = Literal["up", "down"]
_Angles = Union[Sequence[float], npt.NDArray[np.floating[Any]]]
_Pair = Union[Tuple[float, float], Sequence[float], npt.NDArray[np.floating[Any]]]
_LinkKey = Literal["length", "com", "mass", "inertia"]
_LinkSpec = Union[Mapping[_LinkKey, float], Tuple[float, float, float], Tuple[float, float, float, float], Sequence[float]]

METHODS: list[str]
"""The planning methods, the default first: ``["optimal", "nfa", "ecsa"]`` (the order of
:func:`compare`)."""

__version__: str

__all__ = [
    "Arm",
    "ArmPlan",
    "Domain",
    "METHODS",
    "Plan",
    "Robot",
    "__version__",
    "_time_plan",
    "compare",
    "domain",
    "plan",
    "plan_arm",
]

@final
class Robot:
    """A planar free-floating robot, SI units (the library's ``RobotParams``). Immutable.

    A base of mass ``M`` and moment of inertia ``I`` carries a two-link arm (lengths ``l1``,
    ``l2``, joint-to-centre-of-mass distances ``d1``, ``d2``, masses ``m1``, ``m2``) whose first
    joint sits at ``(a, b)`` in the base frame, measured from the base's centre of mass.
    Every value must be finite; masses, inertia and lengths positive; ``0 < d_i <= l_i``,
    else :class:`freefloat.BadInput`. ``i1``, ``i2`` are the links' moments of inertia about
    their centres of mass [kg m^2], 0 (the paper's point masses) by default.
    """

    def __new__(
        cls,
        *,
        l1: float,
        l2: float,
        d1: float,
        d2: float,
        M: float,
        I: float,
        m1: float,
        m2: float,
        a: float = 0.0,
        b: float = 0.0,
        i1: float = 0.0,
        i2: float = 0.0,
    ) -> Robot: ...
    @staticmethod
    def src() -> Robot:
        """The paper's SRC manipulator: l1 = 0.619, l2 = 0.6, d1 = 0.313, d2 = 0.287 m,
        M = 12.9 kg, I = 0.208 kg m^2, m1 = 4.5, m2 = 1.5 kg, mounted at a = b = 0."""
    @staticmethod
    def from_toml(path: Union[str, PathLike[str]]) -> Robot:
        """Reads a 2-link robot file: TOML (``[robot]`` with every key and optional ``[mount]``,
        or two ``[[link]]`` tables with their inertias; unknown keys are errors) or, for a name
        ending in ``.urdf``, a URDF. Raises :class:`freefloat.BadInput` when unreadable, invalid
        or not of 2 links."""
    def with_mount(self, a: float, b: float) -> Robot:
        """The same robot with the arm mounted at ``(a, b)`` [m]."""
    def momentum(self, q: _Angles, dq: _Angles) -> float:
        """The angular momentum ``F phi' + G theta1' + H theta2'`` (Eqs. 4-5) [kg m^2/s] at
        ``q`` [rad] with velocities ``dq`` [rad/s]: zero along every plan."""
    @property
    def l1(self) -> float:
        """Length of link 1 [m]."""
    @property
    def l2(self) -> float:
        """Length of link 2 [m]."""
    @property
    def d1(self) -> float:
        """Joint 1 to the centre of mass of link 1 [m]."""
    @property
    def d2(self) -> float:
        """Joint 2 to the centre of mass of link 2 [m]."""
    @property
    def M(self) -> float:
        """Base mass [kg]."""
    @property
    def I(self) -> float:
        """Base moment of inertia [kg m^2]."""
    @property
    def m1(self) -> float:
        """Mass of link 1 [kg]."""
    @property
    def m2(self) -> float:
        """Mass of link 2 [kg]."""
    @property
    def a(self) -> float:
        """Mounting point along the base's X axis [m]."""
    @property
    def b(self) -> float:
        """Mounting point along the base's Y axis [m]."""
    def __eq__(self, other: object, /) -> bool: ...

@final
class Plan:
    """A certified plan of a :class:`Robot` or of an :class:`Arm` of any number of links ``n``
    (2 for a :class:`Robot`): the sampled trajectory (N samples, both ends included) as float64
    NumPy arrays in SI units and radians, and its certificate. One class for every robot (issue
    19 item 5); ``ArmPlan`` is another name of it. What does not apply to a plan is None:
    ``z`` and ``transform`` outside the NFA, ``elbow`` outside a :class:`Robot`'s plan to
    ``goal_ee``, ``tau`` without ``torques=True``."""

    @property
    def t(self) -> npt.NDArray[np.float64]:
        """Sample times [s], shape (N,), from 0 to T."""
    @property
    def q(self) -> npt.NDArray[np.float64]:
        """Configurations (phi, theta_1..theta_n) [rad, relative joint angles], shape
        (N, n + 1); ``q[-1]`` is the goal (with ``wrap=True`` modulo 2 pi)."""
    @property
    def dq(self) -> npt.NDArray[np.float64]:
        """Velocities [rad/s], shape (N, n + 1): ``dq[:, 0]`` is the base's (zero angular
        momentum), ``dq[:, 1:]`` the controls u (the joint velocities)."""
    @property
    def ddq(self) -> Optional[npt.NDArray[np.float64]]:
        """Accelerations (phi'', theta_1''..theta_n'') [rad/s^2], shape (N, n + 1), exact;
        computed by the optimal planner, the ECSA and every arm's plan, and by the NFA with
        ``torques=True``; else None."""
    @property
    def ddtheta(self) -> Optional[npt.NDArray[np.float64]]:
        """Joint accelerations [rad/s^2], shape (N, n): ``ddq[:, 1:]``, None where ``ddq``
        is."""
    @property
    def z(self) -> Optional[npt.NDArray[np.float64]]:
        """Chained-form state z, shape (N, 3) (NFA only), else None."""
    @property
    def joints(self) -> int:
        """The number of joints ``n`` (2 for a :class:`Robot`)."""
    @property
    def horizon(self) -> float:
        """The horizon ``T`` [s]: the one given, or with ``T="auto"`` the shortest one found."""
    @property
    def tau(self) -> Optional[npt.NDArray[np.float64]]:
        """Joint torques (tau_1..tau_n) [N m], shape (N, n), with ``torques=True``, else None."""
    @property
    def base(self) -> npt.NDArray[np.float64]:
        """Base centre of mass ``(xb, yb)`` [m], shape (N, 2), in the inertial frame with the
        system's centre of mass at the origin (it stays there: zero linear momentum); the
        base's angle is ``q[:, 0]``."""
    @property
    def end_effector(self) -> npt.NDArray[np.float64]:
        """End-effector pose ``(xe, ye, psie)`` [m, m, rad], shape (N, 3), same frame: the tip of
        link n (a URDF's tool frame) and its absolute angle ``psie = phi + theta_1 + .. +
        theta_n`` (not wrapped)."""
    @property
    def end_effector_velocity(self) -> npt.NDArray[np.float64]:
        """End-effector velocity ``(xe', ye', psie')`` [m/s, m/s, rad/s], shape (N, 3), exact at
        each sample (forward-mode differentiation along ``dq``)."""
    @property
    def method(self) -> str:
        """``"optimal"``, ``"nfa"`` or ``"ecsa"``."""
    @property
    def transform(self) -> Optional[str]:
        """The NFA's transformation (``"eq11"``, ``"eq12"``, ``"eq14"``, ``"global"``), None for
        the other methods (and every arm's plan)."""
    @property
    def elbow(self) -> Optional[str]:
        """The elbow (``"up"``, ``"down"``) of the inverse-kinematics solution planned to, for a
        :class:`Robot`'s plan to ``goal_ee``; None for a plan to a goal configuration and for an
        arm's plan (whose branch ``certificate["to_ee"]`` names)."""
    @property
    def effort(self) -> float:
        """The control effort ``integral_0^T |u(t)|^2 dt`` [rad^2/s], ``u = dq[:, 1:]``, as the
        library reports it (``certificate["effort"]``): exact for the optimal planner (Gauss-
        Legendre on its spline's knot spans); for NFA and ECSA the composite Simpson rule over
        the samples, an O(h^4) approximation."""
    @property
    def final_error(self) -> float:
        """Verified final error ``max_i |wrap(q_i(T) - qd_i)|`` [rad]: the system integrated
        from the start with the planned controls (Dormand-Prince 5(4), rtol = atol = 1e-12)."""
    @property
    def tolerance(self) -> float:
        """The tolerance of ``final_error`` [rad]."""
    @property
    def certified(self) -> bool:
        """Every certificate holds (always True for a returned plan: a failure raises
        :class:`freefloat.NotCertified`, which carries the plan)."""
    @property
    def certificate(self) -> dict[str, Any]:
        """The report of ``freefloat plan --format json``, the one report of every plan and
        robot, same keys (``method``, ``transform``, ``mount``, ``time``, ``samples``,
        ``joints``, ``robot``, ``start``, ``goal``, ``z0``, ``zd``, ``final_error``,
        ``tolerance``, ``certified``, ``reached``, ``verification``, ``max_abs_u`` (n values),
        ``min_abs_sigma``/``min_abs_p`` (None unless 2 links), ``joint_travel``, ``effort``,
        ``optimal`` (the optimal planner's cost, residuals and SQP iterations) or ``ecsa``,
        ``max_abs_torque``/``torque_final_error``/``torque_certificate`` (None without
        ``torques=True``), ``seconds``, ``iterations``, ``notes``, ``to_ee`` (an arm's plan to
        ``goal_ee``), ...)."""

@final
class Domain:
    """The domain of existence of one transformation on a grid x grid map of the
    (theta1, theta2) torus (the paper's Figs. 13-14), with its connected components."""

    @property
    def labels(self) -> npt.NDArray[np.int64]:
        """Component of each cell, -1 outside the domain; shape (grid, grid), indexed
        ``labels[i2, i1]`` (rows theta2, columns theta1, both at ``centres``); components are
        numbered by decreasing area."""
    @property
    def centres(self) -> npt.NDArray[np.float64]:
        """Cell centres ``(i + 1/2) 2 pi / grid`` [rad], shape (grid,)."""
    @property
    def transform(self) -> str:
        """The transformation mapped (``"auto"`` resolved)."""
    @property
    def grid(self) -> int: ...
    @property
    def components(self) -> int:
        """Number of resolved connected components."""
    @property
    def component_fractions(self) -> list[float]:
        """Area share of each resolved component, decreasing."""
    @property
    def slivers(self) -> int:
        """Number of unresolved components (wedges thinner than a cell)."""
    @property
    def sliver_fraction(self) -> float: ...
    @property
    def defined_fraction(self) -> float:
        """Area share of the whole domain."""
    @property
    def start_component(self) -> Optional[int]: ...
    @property
    def goal_component(self) -> Optional[int]: ...
    @property
    def start_component_fraction(self) -> float:
        """Area share of the start's component: where a plan from the start may go."""
    @property
    def start_goal_connected(self) -> bool: ...
    @property
    def seconds(self) -> float:
        """Wall time of the map [s]."""
    @property
    def summary(self) -> dict[str, Any]:
        """The summary of ``freefloat domain --format json`` (same keys, without the plan)."""

@overload
def plan(
    robot: Robot,
    start: _Angles,
    goal: _Angles,
    T: float,
    *,
    goal_ee: None = None,
    elbow: None = None,
    method: _Method = "optimal",
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    tolerance: float = 1e-9,
    harmonics: int = 1,
    window: _WindowName = "none",
    smooth_ends: bool = False,
    initial_velocity: Optional[_Pair] = None,
    wrap: bool = True,
    cost: _CostName = "effort",
) -> Plan: ...
@overload
def plan(
    robot: Robot,
    start: _Angles,
    goal: None = None,
    *,
    T: float,
    goal_ee: _Angles,
    elbow: Optional[_ElbowName] = None,
    method: _Method = "optimal",
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    tolerance: float = 1e-9,
    harmonics: int = 1,
    window: _WindowName = "none",
    smooth_ends: bool = False,
    initial_velocity: Optional[_Pair] = None,
    wrap: bool = True,
    cost: _CostName = "effort",
) -> Plan:
    """Plans a motion from ``start`` = (phi, theta1, theta2) [rad] in ``T`` [s] with zero
    angular momentum, to rest at the goal, and certifies it. The goal is either

    * ``goal`` = (phi, theta1, theta2) [rad], joint space: ``plan(robot, start, goal, T)``; or
    * ``goal_ee`` = (x, y, psi) [m, m, rad], the end-effector pose in the inertial frame with
      the system's centre of mass at the origin (``psi = phi + theta1 + theta2``), by keyword:
      ``plan(robot, start, T=10.0, goal_ee=(x, y, psi))``. The goal configurations are the
      free-floating inverse kinematics' solutions, each angle nearest the start's; with
      ``elbow="up"`` or ``"down"`` only that one is planned, else both and the certified plan
      of least effort is kept (``Plan.elbow`` says which).

    Exactly one of ``goal`` and ``goal_ee`` (else :class:`BadInput`); ``T`` is required
    (``TypeError`` when missing). A pose out of reach is :class:`BadInput` with ``kind ==
    "unreachable"`` and ``numbers`` = {``x``, ``y``, ``psi`` [rad], ``distance``, ``min``,
    ``max``} [m]: the wrist point's distance from the centre of mass and the reachable range.

    ``method``: ``"optimal"`` (default; the minimum-effort joint path under the base's
    holonomy constraint, across sigma = 0 as anywhere), ``"nfa"`` (Normal Form Approach) or
    ``"ecsa"``. Each method's keywords, given with a value other than their default to another
    method, are :class:`BadInput` (``kind == "misplaced_option"``):

    * NFA: ``transform``: ``"auto"`` tries the paper's eq12 (a = b = 0) or eq14 and falls back
      to the global normal form.
    * ECSA: ``harmonics``, ``window``: its control series.
    * optimal: ``smooth_ends=True`` also zeroes the joint accelerations at both ends (quintic
      splines: torques start and end at zero); ``initial_velocity`` = (dtheta1, dtheta2)
      [rad/s] at t = 0, for re-planning while moving (default: at rest); ``wrap=False`` takes
      the goal's angles literally instead of modulo 2 pi; ``cost``: ``"effort"``
      (``integral |theta'|^2 dt``) or ``"energy"`` (the kinetic energy).

    ``torques=True`` adds exact accelerations, the joint torques and the second certificate
    (full dynamics from rest, tolerance 1e-6 rad). The GIL is released while planning.

    Raises :class:`BadInput` (bad parameters), :class:`NoPlan` (no plan with this method),
    :class:`NotCertified` (final error above ``tolerance``, or the torque certificate failing).
    """

@overload
def compare(
    robot: Robot,
    start: _Angles,
    goal: _Angles,
    T: float,
    *,
    goal_ee: None = None,
    elbow: None = None,
    methods: Optional[Sequence[str]] = None,
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    tolerance: float = 1e-9,
    harmonics: int = 1,
    window: _WindowName = "none",
    smooth_ends: bool = False,
    initial_velocity: Optional[_Pair] = None,
    wrap: bool = True,
    cost: _CostName = "effort",
    strict: bool = True,
) -> dict[str, Union[Plan, FreefloatError]]: ...
@overload
def compare(
    robot: Robot,
    start: _Angles,
    goal: None = None,
    *,
    T: float,
    goal_ee: _Angles,
    elbow: Optional[_ElbowName] = None,
    methods: Optional[Sequence[str]] = None,
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    tolerance: float = 1e-9,
    harmonics: int = 1,
    window: _WindowName = "none",
    smooth_ends: bool = False,
    initial_velocity: Optional[_Pair] = None,
    wrap: bool = True,
    cost: _CostName = "effort",
    strict: bool = True,
) -> dict[str, Union[Plan, FreefloatError]]:
    """The same problem with each of ``methods`` (default: :data:`METHODS`, optimal, NFA and
    ECSA), as a dict method -> :class:`Plan`. ``goal`` or ``goal_ee`` (with ``elbow``) and
    ``T`` as for :func:`plan`. Each method takes its own keywords and ignores the others' (as
    ``freefloat compare``). With ``strict=False`` a method without a certified plan maps to its
    exception instead of raising it (bad input always raises)."""

def domain(
    robot: Robot,
    transform: _TransformName = "auto",
    grid: int = 720,
    *,
    start: Optional[_Angles] = None,
    goal: Optional[_Angles] = None,
) -> Domain:
    """The domain map of ``transform`` (``"auto"``: eq12 at a = b = 0, else eq14) on a
    grid x grid map of the torus; ``start`` and ``goal`` [rad] (default: the paper's
    (45, 120, 80) and (0, 180, 140) deg) are located on it. The GIL is released."""

def _time_plan(
    robot: Robot,
    start: _Angles,
    goal: Optional[_Angles] = None,
    T: Optional[float] = None,
    *,
    goal_ee: Optional[_Angles] = None,
    elbow: Optional[_ElbowName] = None,
    method: _Method = "optimal",
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    smooth_ends: bool = False,
    initial_velocity: Optional[_Pair] = None,
    wrap: bool = True,
    cost: _CostName = "effort",
    repeats: int = 1,
) -> list[float]:
    """Wall time [s] of the Rust planning call alone (what :func:`plan` runs without the GIL),
    once per repeat: the reference of ``bench/plan_overhead.py``."""

def track(
    robot: Union[Robot, "Arm"],
    start: _Angles,
    goal: _Angles,
    T: float,
    *,
    controller: Literal["open", "ct", "replan", "adaptive"] = "adaptive",
    true_robot: Optional[Union[Robot, "Arm"]] = None,
    perturb: float = 0.0,
    perturb_mount: float = 0.0,
    torque_noise: float = 0.0,
    q_noise: float = 0.0,
    dq_noise: float = 0.0,
    rate: float = 1000.0,
    replan_rate: float = 5.0,
    margin: Optional[float] = None,
    limit_margin: Optional[float] = None,
    seed: int = 0,
) -> dict[str, Any]:
    """Plans ``start -> goal`` [rad] (``n + 1`` angles each) in ``T`` [s] with the minimum-effort
    planner on ``robot`` (a :class:`Robot` or an :class:`Arm` of any number of links: the model), then executes the plan in closed loop, in simulation, on the true robot:
    ``true_robot``, or ``robot`` with each mass, inertia, length and centre-of-mass distance
    perturbed by up to ``perturb`` (relative) and the mount by up to ``perturb_mount`` [m],
    seeded by ``seed``. ``controller``: ``"open"`` (the planned torques), ``"ct"`` (computed
    torque with joint PD), ``"replan"`` (ct plus re-planning at ``replan_rate`` [Hz] from the
    measured state), ``"adaptive"`` (replan on a model whose momentum map is identified on
    line). ``torque_noise`` (relative), ``q_noise`` [rad], ``dq_noise`` [rad/s]: disturbances;
    ``rate``: control rate [Hz] with zero-order hold. For an arm with shapes or obstacles the plan
    and every re-plan keep ``margin`` [m] (default 0.02) beyond the arm's clearance, and the run
    fails (``failure`` ``collision``) only under the clearance itself; a ``margin`` for a robot
    without shapes or obstacles is :class:`BadInput`. For an arm with limits the plan and every
    re-plan keep ``limit_margin`` (default 0.05, in ``[0, 1)``) of every limit as headroom
    (velocity, acceleration, torque limits times ``1 - limit_margin``, ranges shrunk about their
    centre; less where ``T`` is too short for it), and the run fails only outside the limits
    themselves; a ``limit_margin`` above 0 for a robot without limits is :class:`BadInput`. Returns a
    dict: ``final_error`` [rad],
    ``final_errors`` per coordinate, ``peak_torque`` [N m], ``replans``, ``replan_failures``,
    ``saturated_fraction``, ``seconds``, ``identification`` (adaptive),
    ``hold_correction`` (the feedforward's correction for the zero-order hold, or None), and
    ``limit_margin_used``: the limit margin the plan and the re-plans kept (``limit_margin``, or
    less where ``T`` is too short for it, as the command line's note says; 0 for a robot without
    limits). The GIL is
    released. Raises :class:`BadInput` for bad options, :class:`NoPlan`/:class:`NotCertified`
    when the plan itself fails."""

@final
class Arm:
    """A planar free-floating robot with a serial arm of ``n`` revolute links (1 to 15), SI
    units (the library's ``Arm``): the robots of ``freefloat plan --robot FILE`` with
    ``[[link]]`` tables or ``--urdf FILE``. Immutable; ``==`` compares every parameter.

    A base of mass ``M`` [kg] and moment of inertia ``I`` [kg m^2] about its centre of mass
    carries links from the base outwards, each a dict ``{"length": l, "com": d, "mass": m,
    "inertia": i}`` or a tuple ``(l, d, m)`` / ``(l, d, m, i)``: length joint to next joint
    [m], distance from the joint to the link's centre of mass along the link [m], mass [kg],
    moment of inertia about the link's centre of mass [kg m^2] (default 0, a point mass).
    Joint 1 sits at ``(a, b)`` [m] in the base frame, measured from the base's centre of mass.

    Coordinates are ``q = (phi, theta_1, ..., theta_n)`` [rad]: the base angle and the
    *relative* joint angles (link ``k`` points along ``phi + theta_1 + ... + theta_k``).

    Invalid values are :class:`freefloat.BadInput` naming the key as the robot file does:
    ``robot.M``, ``robot.I``, ``mount.a``, ``link[k].mass`` (``k`` from 1), ``link`` for the
    number of links; a missing or unknown key of a link dict is ``BadInput`` too. Limits: masses
    1e-3 to 1e6 kg, lengths 1e-3 to 1e3 m, ``0 <= com <= length``, and the last link must carry
    inertia about its joint (``com > 0`` or ``inertia > 0``).
    """

    def __new__(
        cls,
        *,
        M: float,
        I: float,
        links: Sequence[_LinkSpec],
        a: float = 0.0,
        b: float = 0.0,
    ) -> Arm: ...
    @staticmethod
    def from_file(path: Union[str, PathLike[str]]) -> Arm:
        """Reads and validates a robot file: a URDF when the name ends in ``.urdf`` (a planar
        chain of revolute joints about z; fixed joints merged; the first joint's origin is the
        mount), else TOML (``[robot]`` with ``M``, ``I``, optional ``[mount]``, and
        ``[[link]]`` tables; or the 2-link SRC file, whose links are point masses). Raises
        :class:`freefloat.BadInput` naming the file, key or URDF element at fault."""
    @staticmethod
    def from_robot(robot: Robot) -> Arm:
        """The 2-link :class:`Robot` as an arm (same base, mount, links and link inertias)."""
    def to_robot(self) -> Robot:
        """The arm as a 2-link :class:`Robot`, for :func:`plan` and its every method;
        :class:`freefloat.BadInput` unless the arm has 2 links with ``com > 0``."""
    def to_toml(self) -> str:
        """The arm as a TOML robot file (``[robot]``, ``[mount]``, ``[[link]]``)."""
    def to_urdf(self) -> str:
        """The arm as a URDF that :meth:`from_file` reads back to the same arm."""
    def with_mount(self, a: float, b: float) -> Arm:
        """The same arm with joint 1 mounted at ``(a, b)`` [m]."""
    def momentum(self, q: _Angles, dq: _Angles) -> float:
        """The angular momentum ``F(theta) phi' + G(theta) . theta'`` [kg m^2/s] about the
        system's centre of mass, at ``q`` = (phi, theta_1..theta_n) [rad] with velocities
        ``dq`` [rad/s] (n + 1 values each): zero along every plan."""
    def inverse_kinematics(self, pose: Sequence[float], start: _Angles) -> list[dict[str, Any]]:
        """The free-floating inverse kinematics of the tool pose ``(x, y, psi)`` [m, m, rad]
        from ``start`` (n + 1 angles [rad]): every branch tried, as dicts ``{"branch", "q",
        "residual" [m], "reached"}``; a pose out of reach raises :class:`BadInput`."""
    @property
    def joints(self) -> int:
        """The number of joints (links) ``n``."""
    @property
    def M(self) -> float:
        """Base mass [kg]."""
    @property
    def I(self) -> float:
        """Base moment of inertia about its centre of mass [kg m^2]."""
    @property
    def a(self) -> float:
        """Mounting point of joint 1 along the base's X axis [m]."""
    @property
    def b(self) -> float:
        """Mounting point of joint 1 along the base's Y axis [m]."""
    @property
    def constrained(self) -> bool:
        """The arm carries limits or shapes of its own (its robot file's): ``freefloat.plan``
        then plans it by the arm pipeline, which checks them, even with 2 links."""
    @property
    def links(self) -> list[dict[str, float]]:
        """The links, base outwards, as dicts ``{"length", "com", "mass", "inertia"}`` (a new
        list on each access)."""

ArmPlan = Plan
"""Another name of :class:`Plan` (an :class:`Arm`'s plan was once its own class): every
robot's plan is a :class:`Plan`."""

def plan_arm(
    arm: Union[Arm, Robot],
    start: _Angles,
    goal: Optional[_Angles],
    T: Union[float, Literal["auto"]],
    *,
    goal_ee: Optional[Sequence[float]] = None,
    branch: Optional[str] = None,
    samples: int = 1001,
    torques: bool = False,
    wrap: bool = True,
    initial_velocity: Optional[_Angles] = None,
    tolerance: float = 1e-9,
    method: _Method = "optimal",
    harmonics: int = 1,
    window: Literal["none", "sin2"] = "none",
    smooth_ends: bool = False,
    cost: _CostName = "effort",
    limits: Optional[Mapping[str, Optional[Mapping[str, Any]]]] = None,
    obstacles: Optional[Sequence[Union[str, Tuple[Any, ...]]]] = None,
    clearance: Optional[float] = None,
    no_collide: Optional[Sequence[Tuple[str, str]]] = None,
) -> Plan:
    """Deprecated as ``freefloat.plan_arm`` (a ``DeprecationWarning``): ``freefloat.plan(arm,
    ...)`` takes any arm and calls this.

    Plans the minimum-effort motion of ``arm`` from ``start`` to ``goal`` = (phi,
    theta_1..theta_n) [rad, relative joint angles; n + 1 values] in ``T`` [s] at zero angular
    momentum, to rest at the goal, and certifies it (the planner of ``freefloat plan`` for an
    arm of any ``n``). A 2-link :class:`Robot` is accepted and planned as an arm.

    ``goal_ee`` = (x, y, psi) [m, m, rad] instead of ``goal`` (``goal=None``; the command line's
    ``--to-ee``): the tool pose in the inertial frame, the system's centre of mass at the origin;
    every branch of :meth:`Arm.inverse_kinematics` that reaches it (only the one named
    ``branch``, e.g. ``"up"``, when given) is planned and the certified plan of least effort
    kept; ``plan.certificate["to_ee"]`` lists each branch with its effort or error. A branch
    name that no reaching branch carries, or a pose that no branch reaches, is
    :class:`BadInput` (kind ``pose_branch``).

    ``T="auto"`` (issue 20 item 4; the command line's ``--time auto``): the shortest horizon,
    to 1 %, in which a certified plan fits every limit, for ``method="optimal"`` and an arm with
    a velocity, acceleration or torque limit (else :class:`BadInput` naming ``T="auto"``); the
    plan's ``horizon`` is the one found.
    ``initial_velocity`` = (dtheta_1..dtheta_n) [rad/s] at t = 0 (default: at rest);
    ``wrap=False`` takes the goal's angles literally instead of modulo 2 pi; ``samples`` is the
    number of samples of the arrays (at least 2). ``torques=True`` adds the joint torques and
    the second certificate (the full dynamics integrated with the planned torques, tolerance
    1e-6 rad). ``method`` is ``"optimal"`` (minimum effort) or ``"ecsa"`` (the
    paper's reference method, from rest only; its motions can cost far more effort), with
    ``harmonics`` (1 to 4) and ``window`` (``"none"`` or ``"sin2"``) as in :func:`plan`
    (given with another method: :class:`BadInput`); ``"nfa"`` plans a 2-link arm of the paper's
    model (the NFA's plan of its :class:`Robot`, checked against the arm's limits and shapes:
    :class:`NotCertified` outside them; to a goal configuration in a given ``T``) and is
    :class:`BadInput` with the reason for any other arm (the chained form is the 2-link
    robot's).
    ``obstacles`` (issue 21; the command line's ``--obstacle``, in the inertial frame whose origin
    is the system's centre of mass, m): a list of ``("circle", x, y, r)``, ``("capsule", x1, y1,
    x2, y2, r)``, ``("box", x, y, w, h)``, ``("polygon", [x1, y1, x2, y2, ...])`` (convex) or
    spec strings ``"circle:X,Y,R"``; ``clearance`` the least distance [m] every checked pair
    keeps (``--clearance``; default the arm's own, 0); ``no_collide`` pairs of bodies not to
    check, e.g. ``[("base", "link2")]``. A plan that comes closer is :class:`NotCertified`
    (kind ``collision``); ``plan.certificate["clearance"]`` gives the least clearance, its pair
    and time.
    The GIL is released while planning.

    Raises :class:`BadInput` (bad parameters, named: ``start.len``, ``goal[2]``,
    ``initial_velocity.len``, ``method``, ...; a 1-link arm whose goal phi is not the one its
    joint path fixes, ``kind == "holonomy_fixed"``), :class:`NoPlan` (the planner did not
    converge), :class:`NotCertified` (a certificate failing; it carries the plan).
    """
