"""Where Python users already work (issue 23): pickling (Dask, multiprocessing), the Dask mount
sweep example, the ``freefloat`` command that ``pip install ./python`` puts on PATH, the
numbers of an error under one name, and an ``Arm`` that prints its links as it hands them out."""

import copy
import importlib.util
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import freefloat as ff
from conftest import GOAL, HORIZON, START

ROOT = Path(__file__).resolve().parents[2]
THREE_LINK = ROOT / "examples" / "robots" / "three_link.toml"


def _same_plan(a, b):
    """Every array, number and the certificate equal (the state is copied, not recomputed)."""
    for name in ("t", "q", "dq", "ddq", "z", "tau", "ddtheta", "base", "end_effector", "end_effector_velocity"):
        x, y = getattr(a, name, None), getattr(b, name, None)
        if x is None or y is None:
            assert x is None and y is None, name
        else:
            np.testing.assert_array_equal(x, y, err_msg=name)
    for name in ("method", "transform", "elbow", "effort", "final_error", "tolerance", "certified", "joints"):
        assert getattr(a, name, None) == getattr(b, name, None), name
    assert a.certificate == b.certificate
    assert repr(a) == repr(b)


@pytest.mark.parametrize("protocol", [0, 2, pickle.HIGHEST_PROTOCOL])
def test_robot_and_arm_pickle_round_trip_equal(protocol):
    robot = ff.Robot(l1=0.6, l2=0.5, d1=0.3, d2=0.2, M=10.0, I=0.2, m1=4.0, m2=1.0, a=0.1, b=-0.05, i1=0.01)
    assert pickle.loads(pickle.dumps(robot, protocol)) == robot
    arm = ff.Arm.from_file(THREE_LINK).with_mount(0.05, 0.1)
    back = pickle.loads(pickle.dumps(arm, protocol))
    assert back == arm and back.links == arm.links
    assert copy.deepcopy(robot) == robot and copy.copy(arm) == arm


def test_plans_pickle_round_trip_equal(src):
    plan = ff.plan(src.with_mount(0.1, 0.1), START, GOAL, HORIZON, torques=True)
    _same_plan(pickle.loads(pickle.dumps(plan)), plan)
    nfa = ff.plan(src, START, GOAL, HORIZON, method="nfa")  # z set, tau None
    _same_plan(pickle.loads(pickle.dumps(nfa)), nfa)
    arm = ff.Arm.from_file(THREE_LINK)
    arm_plan = ff.plan(arm, [0, 0.3, -0.4, 0.2], [0.3, 0.8, 0.2, -0.3], 10.0)
    _same_plan(pickle.loads(pickle.dumps(arm_plan)), arm_plan)


def _example():
    spec = importlib.util.spec_from_file_location("dask_sweep", ROOT / "python" / "examples" / "dask_sweep.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_dask_example_equals_the_serial_run_on_two_workers():
    distributed = pytest.importorskip("dask.distributed")
    example = _example()
    robot = ff.Robot.src()
    points = example.grid(2, 0.2)
    problems = example.pairs(3, 3)
    reference = example.serial(robot, points, problems, 10.0)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        result = example.distributed(client, robot, points, problems, 10.0)
    assert result == reference
    assert [(r["a"], r["b"]) for r in result] == points
    assert all(r["trials"] == 3 for r in result)


def _command():
    path = Path(sys.executable).parent / "freefloat"
    if not path.exists():
        pytest.skip("freefloat is not installed as a command in this environment")
    return str(path)


def test_the_installed_command_plans_with_the_binary_exit_codes(tmp_path):
    command = _command()
    ok = subprocess.run([command, "plan", "--mount", "0.1,0.1"], capture_output=True, text=True, cwd=tmp_path)
    assert ok.returncode == 0, ok.stderr
    assert ok.stdout.startswith("freefloat plan: optimal") and "CERTIFIED" in ok.stdout
    # README: --tolerance above 1e-3 rad is bad input (exit 2).
    bad = subprocess.run([command, "plan", "--tolerance", "1"], capture_output=True, text=True, cwd=tmp_path)
    assert bad.returncode == 2 and bad.stderr.startswith("error:"), bad.stderr
    # README: at a = 1, b = -1 start and goal lie in different components of eq14's domain (exit 3).
    none = subprocess.run([command, "plan", "--mount", "1,-1", "--transform", "eq14"], capture_output=True,
                          text=True, cwd=tmp_path)
    assert none.returncode == 3 and "different components" in none.stderr, none.stderr
    usage = subprocess.run([command, "plan", "--no-such-flag"], capture_output=True, text=True, cwd=tmp_path)
    assert usage.returncode == 2
    version = subprocess.run([command, "--version"], capture_output=True, text=True, cwd=tmp_path)
    assert version.returncode == 0 and version.stdout.startswith("freefloat ")


def test_an_unreachable_pose_carries_its_numbers_as_numbers(src):
    with pytest.raises(ff.BadInput) as info:
        ff.plan(src, START, T=HORIZON, goal_ee=(5.0, 5.0, 0.0))
    numbers = info.value.numbers
    assert numbers is info.value.details  # the earlier name, the same dict
    assert set(numbers) >= {"x", "y", "psi", "distance", "min", "max"}
    assert numbers["min"] <= numbers["max"] < numbers["distance"]  # out of reach: beyond the range


def test_arm_prints_its_links_as_the_dicts_it_hands_out():
    arm = ff.Arm.from_file(THREE_LINK)
    text = repr(arm)
    assert repr(arm.links[0]) in text and "(" not in text.split("links=", 1)[1].split("]", 1)[0]
    assert eval(text, {"Arm": ff.Arm}) == arm  # the repr is the constructor call
