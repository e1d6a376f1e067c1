"""Type stubs of the native module ``freefloat._freefloat`` (PyO3). Import from ``freefloat``."""

from os import PathLike
from typing import Any, Literal, Optional, Sequence, Union, final

import numpy as np
import numpy.typing as npt

from ._errors import FreefloatError

_Method = Literal["nfa", "ecsa"]
_TransformName = Literal["auto", "eq11", "eq12", "eq14", "global"]
_WindowName = Literal["none", "sin2"]
_Angles = Union[Sequence[float], npt.NDArray[np.floating[Any]]]

METHODS: list[str]
"""The planning methods, e.g. ``["nfa", "ecsa"]``."""

__version__: str

__all__ = ["Domain", "METHODS", "Plan", "Robot", "__version__", "_time_plan", "compare", "domain", "plan"]

@final
class Robot:
    """A planar free-floating robot, SI units (the library's ``RobotParams``). Immutable.

    A base of mass ``M`` and moment of inertia ``I`` carries a two-link arm (lengths ``l1``,
    ``l2``, joint-to-centre-of-mass distances ``d1``, ``d2``, masses ``m1``, ``m2``) whose first
    joint sits at ``(a, b)`` in the base frame, measured from the base's centre of mass.
    Every value must be finite; masses, inertia and lengths positive; ``0 < d_i <= l_i``,
    else :class:`freefloat.BadInput`.
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
    ) -> Robot: ...
    @staticmethod
    def src() -> Robot:
        """The paper's SRC manipulator: l1 = 0.619, l2 = 0.6, d1 = 0.313, d2 = 0.287 m,
        M = 12.9 kg, I = 0.208 kg m^2, m1 = 4.5, m2 = 1.5 kg, mounted at a = b = 0."""
    @staticmethod
    def from_toml(path: Union[str, PathLike[str]]) -> Robot:
        """Reads a robot file (``[robot]`` with every key, optional ``[mount]``; unknown keys
        are errors). Raises :class:`freefloat.BadInput` when unreadable or invalid."""
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
    """A certified plan: the sampled trajectory (N samples, both ends included) as float64
    NumPy arrays in SI units and radians, and its certificate."""

    @property
    def t(self) -> npt.NDArray[np.float64]:
        """Sample times [s], shape (N,), from 0 to T."""
    @property
    def q(self) -> npt.NDArray[np.float64]:
        """Configurations (phi, theta1, theta2) [rad], shape (N, 3); ``q[-1]`` is the goal."""
    @property
    def dq(self) -> npt.NDArray[np.float64]:
        """Velocities [rad/s], shape (N, 3); ``dq[:, 1:]`` are the controls u."""
    @property
    def ddq(self) -> Optional[npt.NDArray[np.float64]]:
        """Accelerations [rad/s^2], shape (N, 3), exact (automatic differentiation); computed
        for ``torques=True`` (NFA) and always by ECSA, else None."""
    @property
    def z(self) -> Optional[npt.NDArray[np.float64]]:
        """Chained-form state z, shape (N, 3) (NFA only), else None."""
    @property
    def tau(self) -> Optional[npt.NDArray[np.float64]]:
        """Joint torques (tau1, tau2) [N m], shape (N, 2), with ``torques=True``, else None."""
    @property
    def method(self) -> str:
        """``"nfa"`` or ``"ecsa"``."""
    @property
    def transform(self) -> Optional[str]:
        """The NFA's transformation (``"eq11"``, ``"eq12"``, ``"eq14"``, ``"global"``), None for
        ECSA."""
    @property
    def effort(self) -> float:
        """The control effort ``integral_0^T |u(t)|^2 dt`` [rad^2/s], ``u = dq[:, 1:]``, by the
        composite Simpson rule over the samples (Simpson's 3/8 rule on the last three intervals
        when their number is odd): an O(h^4) approximation, not an exact integral."""
    @property
    def final_error(self) -> float:
        """Verified final error ``max_i |wrap(q_i(T) - qd_i)|`` [rad]: system (7) integrated
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
        """The report of ``freefloat plan --format json``, same keys (``method``,
        ``transform``, ``mount``, ``time``, ``samples``, ``z0``, ``zd``, ``final_error``,
        ``max_abs_u``, ``min_abs_sigma``, ``min_abs_p``, ``max_abs_torque``,
        ``torque_final_error``, ``torque_certificate``, ``seconds``, ``iterations``, ...)."""

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

def plan(
    robot: Robot,
    start: _Angles,
    goal: _Angles,
    T: float,
    *,
    method: _Method = "nfa",
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    tolerance: float = 1e-9,
    harmonics: int = 1,
    window: _WindowName = "none",
) -> Plan:
    """Plans a motion from ``start`` to ``goal`` = (phi, theta1, theta2) [rad] in ``T`` [s],
    at rest at both ends, zero angular momentum, and certifies it.

    ``method``: ``"nfa"`` (Normal Form Approach) or ``"ecsa"``. ``transform`` (NFA):
    ``"auto"`` tries the paper's eq12 (a = b = 0) or eq14 and falls back to the global normal
    form. ``torques=True`` adds exact accelerations, the joint torques and the second
    certificate (full dynamics from rest, tolerance 1e-6 rad). ``harmonics``, ``window``: the
    ECSA's control series. The GIL is released while planning.

    Raises :class:`BadInput` (bad parameters), :class:`NoPlan` (no plan with this method),
    :class:`NotCertified` (final error above ``tolerance``, or the torque certificate failing).
    """

def compare(
    robot: Robot,
    start: _Angles,
    goal: _Angles,
    T: float,
    *,
    methods: Optional[Sequence[str]] = None,
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    tolerance: float = 1e-9,
    harmonics: int = 1,
    window: _WindowName = "none",
    strict: bool = True,
) -> dict[str, Union[Plan, FreefloatError]]:
    """The same problem with each of ``methods`` (default: every method, NFA and ECSA), as a
    dict method -> :class:`Plan`. With ``strict=False`` a method without a certified plan maps
    to its exception instead of raising it (bad input always raises)."""

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
    goal: _Angles,
    T: float,
    *,
    method: _Method = "nfa",
    transform: _TransformName = "auto",
    samples: int = 1001,
    torques: bool = False,
    repeats: int = 1,
) -> list[float]:
    """Wall time [s] of the Rust planning call alone (what :func:`plan` runs without the GIL),
    once per repeat: the reference of ``bench/plan_overhead.py``."""
