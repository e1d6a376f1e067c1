"""A mount sweep on Dask: for a grid of mounting points ``(a, b)``, plan seeded random
start/goal pairs with freefloat's minimum-effort planner and report, per point, how many plans
were certified and their mean effort. Each mounting point is one task; robots travel to the
workers pickled, the numbers come back, and the result equals the serial run's exactly (the same
code on the same inputs).

Runs on a ``LocalCluster`` by default; give a scheduler's address to use a real cluster (every
worker needs ``pip install ./python``)::

    python python/examples/dask_sweep.py                       # LocalCluster, 2 workers
    python python/examples/dask_sweep.py --scheduler tcp://10.0.0.5:8786 --steps 21 --trials 50

(``pip install "dask[distributed]"``.)
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np

import freefloat as ff


def pairs(seed: int, trials: int) -> list[tuple[list[float], list[float]]]:
    """``trials`` seeded start/goal pairs [rad]: the same pairs at every mounting point."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(trials):
        start = np.radians(rng.uniform([-90, 30, 30], [90, 150, 150])).tolist()
        goal = np.radians(rng.uniform([-90, 30, 30], [90, 150, 150])).tolist()
        out.append((start, goal))
    return out


def sweep_point(robot: ff.Robot, a: float, b: float, problems: list[Any], horizon: float) -> dict[str, Any]:
    """One mounting point: every pair planned (optimal planner), certified or not."""
    mounted = robot.with_mount(a, b)
    efforts, failures = [], []
    for start, goal in problems:
        try:
            plan = ff.plan(mounted, start, goal, horizon, samples=201)
            efforts.append(plan.effort)
        except ff.FreefloatError as e:
            failures.append(e.kind)
    return {
        "a": a,
        "b": b,
        "certified": len(efforts),
        "trials": len(problems),
        "mean_effort": sum(efforts) / len(efforts) if efforts else None,
        "failures": failures,
    }


def grid(steps: int, half_width: float) -> list[tuple[float, float]]:
    """``steps x steps`` mounting points on ``[-half_width, half_width]^2`` [m]."""
    values = np.linspace(-half_width, half_width, steps).tolist() if steps > 1 else [0.0]
    return [(a, b) for a in values for b in values]


def serial(robot: ff.Robot, points: list[tuple[float, float]], problems: list[Any], horizon: float) -> list[dict]:
    """The sweep in this process, in the grid's order."""
    return [sweep_point(robot, a, b, problems, horizon) for a, b in points]


def distributed(client: Any, robot: ff.Robot, points: list[tuple[float, float]], problems: list[Any],
                horizon: float) -> list[dict]:
    """The sweep on a Dask client, one task per mounting point, in the grid's order."""
    robot_future, problems_future = client.scatter([robot, problems], broadcast=True)
    futures = [client.submit(sweep_point, robot_future, a, b, problems_future, horizon, pure=False)
               for a, b in points]
    return client.gather(futures)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scheduler", help="address of a Dask scheduler (default: a LocalCluster)")
    parser.add_argument("--workers", type=int, default=2, help="LocalCluster workers (default 2)")
    parser.add_argument("--steps", type=int, default=4, help="mounting points per axis (default 4)")
    parser.add_argument("--half-width", type=float, default=0.3, help="grid half-width [m] (default 0.3)")
    parser.add_argument("--trials", type=int, default=10, help="start/goal pairs per point (default 10)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--time", type=float, default=10.0, help="horizon T [s]")
    args = parser.parse_args()

    from dask.distributed import Client, LocalCluster

    robot = ff.Robot.src()
    points = grid(args.steps, args.half_width)
    problems = pairs(args.seed, args.trials)
    clock = time.perf_counter()
    reference = serial(robot, points, problems, args.time)
    serial_s = time.perf_counter() - clock
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True)
        client = Client(cluster)
    with client:
        client.run(lambda: None)  # the workers are up before the clock starts
        workers = len(client.scheduler_info()["workers"])
        clock = time.perf_counter()
        result = distributed(client, robot, points, problems, args.time)
        dask_s = time.perf_counter() - clock
    same = result == reference
    print(f"{len(points)} mounting points x {len(problems)} pairs: serial {serial_s:.2f} s, "
          f"dask {dask_s:.2f} s on {workers} workers (speed-up {serial_s / dask_s:.2f}x); "
          f"results equal to the serial run: {same}")
    for row in result:
        effort = "-" if row["mean_effort"] is None else f"{row['mean_effort']:.4f} rad^2/s"
        print(f"  a = {row['a']:+.3f}, b = {row['b']:+.3f}: {row['certified']}/{row['trials']} certified, "
              f"mean effort {effort}")
    if not same:
        raise SystemExit("the distributed results differ from the serial run")


if __name__ == "__main__":
    main()
