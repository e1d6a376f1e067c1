"""Issue 24, items 2 and 5: every bound of the command line holds in Python too (the library's
one validation layer, checked before anything is allocated), and input that would be silently
misread (a complex start, ECSA keywords given to another method) is refused."""

import time

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START

ARM_START = [0.0, 0.3, -0.4, 0.2]
ARM_GOAL = [0.5, 0.8, 0.2, -0.3]


@pytest.fixture(scope="module")
def arm():
    return ff.Arm(M=10.0, I=0.5, links=[(0.5, 0.25, 2.0, 0.05)] * 3)


def _refused_quickly(call):
    """The call raises BadInput within seconds: refused up front, not after allocating."""
    clock = time.monotonic()
    with pytest.raises(ff.BadInput) as info:
        call()
    assert time.monotonic() - clock < 20.0
    return info.value


@pytest.mark.parametrize("method", ["optimal", "nfa", "ecsa"])
def test_plan_samples_are_bounded(src, method):
    # 1e9 samples would need about 24 GB; the command line's bound is 1,048,576.
    e = _refused_quickly(lambda: ff.plan(src, START, GOAL, HORIZON, method=method, samples=10**9))
    assert "memory" in str(e) and "1048576" in str(e)


def test_compare_and_plan_arm_samples_are_bounded(src, arm):
    _refused_quickly(lambda: ff.compare(src, START, GOAL, HORIZON, samples=10**9))
    _refused_quickly(lambda: ff.plan(arm, ARM_START, ARM_GOAL, HORIZON, samples=10**9))
    _refused_quickly(lambda: ff.plan(arm, ARM_START, ARM_GOAL, HORIZON, method="ecsa", samples=10**9))


@pytest.mark.parametrize("tolerance", [0.5, 1e-2, float("inf")])
def test_tolerances_are_bounded(src, arm, tolerance):
    # The command line's --tolerance is at most 1e-3 rad: a looser certificate certifies nothing.
    _refused_quickly(lambda: ff.plan(src, START, GOAL, HORIZON, tolerance=tolerance))
    _refused_quickly(lambda: ff.plan(arm, ARM_START, ARM_GOAL, HORIZON, tolerance=tolerance))


def test_domain_memory_is_bounded(src):
    # 8192^2 cells at 28 bytes need 1.9 GB: beyond the 1 GiB budget.
    e = _refused_quickly(lambda: ff.domain(src, grid=8192))
    assert "memory" in str(e)


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(rate=0.5, replan_rate=0.5),  # below the 1 Hz floor (the default gains suit any rate above)
        dict(rate=1e6, T=1e6),  # 1e12 control ticks
        dict(T=1e5),  # 5e5 re-plans at 5 Hz
    ],
)
def test_track_budgets_and_stability_are_bounded(src, kwargs):
    T = kwargs.pop("T", HORIZON)
    _refused_quickly(lambda: ff.track(src, START, GOAL, T, **kwargs))


def test_plan_arm_harmonics_need_the_ecsa(arm):
    for kwargs in (dict(harmonics=3), dict(window="sin2")):
        with pytest.raises(ff.BadInput):
            ff.plan(arm, ARM_START, ARM_GOAL, HORIZON, **kwargs)


@pytest.mark.parametrize(
    "start",
    [
        np.array(START, dtype=complex),
        np.array(START, dtype=np.complex64),
        [complex(x, 0.5) for x in START],
        [START[0], 1j, START[2]],
    ],
)
def test_complex_numbers_are_refused(src, arm, start):
    # NumPy would drop the imaginary part with a ComplexWarning: a silent wrong start.
    with pytest.raises(TypeError, match="complex"):
        ff.plan(src, start, GOAL, HORIZON)
    with pytest.raises(TypeError, match="complex"):
        ff.plan(src, START, start, HORIZON)
    with pytest.raises(TypeError, match="complex"):
        ff.domain(src, start=start)
    with pytest.raises(TypeError, match="complex"):
        src.momentum(start, [0.0, 0.0, 0.0])
    with pytest.raises(TypeError, match="complex"):
        ff.plan(arm, np.array(ARM_START, dtype=complex), ARM_GOAL, HORIZON)
