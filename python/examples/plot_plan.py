"""Plans the paper's problem (Sec. 5) at a = b = 0.1 with torques and plots it as the paper's
figures do: base and joint angles, normal-form variables z, velocity controls u, joint torques
(NFA); and, in task space, the paths of the end-effector and of the base for the NFA and the
minimum-effort plan (method="optimal"), with the end-effector's speed.

Usage: python examples/plot_plan.py [OUT.png]   (default: plan.png; needs Matplotlib)
"""

import sys

import numpy as np

import freefloat as ff


def main():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("Matplotlib is not installed (pip install matplotlib): nothing to plot.")
        return 0
    out = sys.argv[1] if len(sys.argv) > 1 else "plan.png"
    robot = ff.Robot.src().with_mount(0.1, 0.1)
    start, goal = np.radians([45, 120, 80]), np.radians([0, 180, 140])
    p = ff.plan(robot, start, goal, 10.0, method="nfa", torques=True)
    best = ff.plan(robot, start, goal, 10.0, method="optimal", torques=True)
    fig, axes = plt.subplots(2, 3, figsize=(15, 7))
    panels = [
        (axes[0, 0], np.degrees(p.q), ["phi", "theta1", "theta2"], "angles [deg]"),
        (axes[0, 1], p.z, ["z1", "z2", "z3"], "normal-form variables z"),
        (axes[1, 0], p.dq[:, 1:], ["u1", "u2"], "velocity controls u [rad/s]"),
        (axes[1, 1], p.tau, ["tau1", "tau2"], "joint torques tau [N m]"),
    ]
    for ax, data, labels, title in panels:
        for column, label in zip(data.T, labels):
            ax.plot(p.t, column, label=label)
        ax.set_title(title)
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
        ax.legend()
    # Task space: the inertial frame with the system's centre of mass at the origin.
    ax = axes[0, 2]
    for plan, style, name in [(p, "-", f"NFA ({p.transform})"), (best, "--", "optimal")]:
        ax.plot(plan.end_effector[:, 0], plan.end_effector[:, 1], style, color="C0", label=f"end-effector, {name}")
        ax.plot(plan.base[:, 0], plan.base[:, 1], style, color="C1", label=f"base, {name}")
    for plan, marker, name in [(p, "o", "start"), (p, "s", "goal")]:
        i = 0 if name == "start" else -1
        ax.plot(*plan.end_effector[i, :2], marker, color="k", label=name)
        ax.plot(*plan.base[i, :2], marker, color="k")
    ax.plot(0.0, 0.0, "+", color="k", markersize=12, label="centre of mass")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("task space: paths [m]")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    ax = axes[1, 2]
    for plan, style, name in [(p, "-", "NFA"), (best, "--", "optimal")]:
        speed = np.hypot(plan.end_effector_velocity[:, 0], plan.end_effector_velocity[:, 1])
        ax.plot(plan.t, speed, style, color="C0", label=f"{name}: effort {plan.effort:.4f} rad^2/s")
    ax.set_title("end-effector speed [m/s]")
    ax.set_xlabel("t [s]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.suptitle(
        f"NFA ({p.transform}) and optimal, a = b = 0.1 m: verified final errors {p.final_error:.1e}, "
        f"{best.final_error:.1e} rad; torque level {p.certificate['torque_final_error']:.1e} rad (NFA)"
    )
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
