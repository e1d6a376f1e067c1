"""The paper's problem (Sec. 5) and helpers shared by the tests."""

import numpy as np
import pytest

import freefloat as ff

START = np.radians([45.0, 120.0, 80.0])
GOAL = np.radians([0.0, 180.0, 140.0])
HORIZON = 10.0


def wrapped_distance(a, b):
    """max_i |wrap(a_i - b_i)| [rad], as the library's final error."""
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    return float(np.max(np.abs((d + np.pi) % (2 * np.pi) - np.pi)))


@pytest.fixture(scope="session")
def src():
    return ff.Robot.src()
