"""Overhead of the Python call over the Rust call, on the paper's problem (Sec. 5).

For each case, the median wall time of

* ``rust``: the Rust planning call alone (``freefloat._freefloat._time_plan``: the same
  function ``plan`` runs with the GIL released, timed in Rust, without building Python objects);
* ``python``: ``freefloat.plan(...)`` timed in Python (argument parsing, GIL release, NumPy
  arrays, exceptions' checks);
* ``+read``: the same plus reading every array attribute and the certificate (built as a
  dict on first access);

and the overhead ``python / rust - 1`` (target <= 10 %). The library's own stage times
(``certificate["seconds"]``: plan + torques + verify, median of 50 calls; without the torque
certificate's time) are shown for reference. Timings are reported,
never gated, unless ``--check`` is given (exit 1 above the target).

Usage: python bench/plan_overhead.py [--repeats N] [--check]
"""

import argparse
import statistics
import sys
import time

import numpy as np

import freefloat as ff
from freefloat._freefloat import _time_plan

START = np.radians([45.0, 120.0, 80.0])
GOAL = np.radians([0.0, 180.0, 140.0])
HORIZON = 10.0
TARGET = 0.10

CASES = [
    ("optimal, a = b = 0", ff.Robot.src(), dict(method="optimal")),
    ("optimal, a = b = 0.1", ff.Robot.src().with_mount(0.1, 0.1), dict(method="optimal")),
    ("NFA eq12, a = b = 0", ff.Robot.src(), dict(method="nfa", transform="eq12")),
    ("NFA eq14, a = b = 0.1", ff.Robot.src().with_mount(0.1, 0.1), dict(method="nfa", transform="eq14")),
    ("ECSA, a = b = 0.1", ff.Robot.src().with_mount(0.1, 0.1), dict(method="ecsa")),
    ("NFA eq14 + torques, a = b = 0.1", ff.Robot.src().with_mount(0.1, 0.1),
     dict(method="nfa", transform="eq14", torques=True)),
    ("optimal + torques, a = b = 0.1", ff.Robot.src().with_mount(0.1, 0.1), dict(method="optimal", torques=True)),
]


def python_times(robot, kwargs, repeats, read):
    times = []
    for _ in range(repeats):
        clock = time.perf_counter()
        p = ff.plan(robot, START, GOAL, HORIZON, **kwargs)
        if read:
            (p.t, p.q, p.dq, p.ddq, p.z, p.tau, p.base, p.end_effector, p.end_effector_velocity, p.effort,
             p.certificate)
        times.append(time.perf_counter() - clock)
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=300)
    parser.add_argument("--check", action="store_true", help="exit 1 when an overhead exceeds 10 %%")
    args = parser.parse_args()
    print(f"freefloat {ff.__version__}, median of {args.repeats} calls, 1001 samples, times in ms")
    print(f"{'case':<34}{'rust':>8}{'python':>9}{'overhead':>10}{'+read':>9}{'overhead':>10}{'library stages':>16}")
    worst = 0.0
    for name, robot, kwargs in CASES:
        # Warm up, then interleave the three measurements call by call, so that they share the
        # load of a busy machine (other builds on the same cores) instead of meeting it in turn.
        python_times(robot, kwargs, 20, read=True)
        rust, python, read = [], [], []
        for _ in range(args.repeats):
            rust += _time_plan(robot, START, GOAL, HORIZON, repeats=1, **kwargs)
            python += python_times(robot, kwargs, 1, read=False)
            read += python_times(robot, kwargs, 1, read=True)
        stages = [ff.plan(robot, START, GOAL, HORIZON, **kwargs).certificate["seconds"] for _ in range(50)]
        lib = statistics.median(s["plan"] + s["verify"] + (s["torques"] or 0.0) for s in stages)
        r, p, pr = (statistics.median(x) for x in (rust, python, read))
        worst = max(worst, p / r - 1)
        print(f"{name:<34}{r * 1e3:8.3f}{p * 1e3:9.3f}{100 * (p / r - 1):9.1f}%{pr * 1e3:9.3f}"
              f"{100 * (pr / r - 1):9.1f}%{lib * 1e3:16.3f}")
    verdict = "within" if worst <= TARGET else "ABOVE"
    print(f"largest overhead of the call: {100 * worst:.1f} % ({verdict} the {100 * TARGET:.0f} % target)")
    if args.check and worst > TARGET:
        sys.exit(1)


if __name__ == "__main__":
    main()
