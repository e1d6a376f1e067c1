"""Plans the paper's problem (Sec. 5) at a = b = 0.1 with torques and plots it as the paper's
figures do: base and joint angles, normal-form variables z, velocity controls u, joint torques.

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
    p = ff.plan(robot, np.radians([45, 120, 80]), np.radians([0, 180, 140]), 10.0, torques=True)
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
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
        ax.grid(True, alpha=0.3)
        ax.legend()
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    fig.suptitle(
        f"NFA ({p.transform}), a = b = 0.1 m: verified final error {p.final_error:.1e} rad, "
        f"torque level {p.certificate['torque_final_error']:.1e} rad"
    )
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
