"""The README's pictures: maze_17's contact at 187.8 s (trace of 55eee6e) and the drive probe.

PYTHONPATH=$PWD python results/baselines/vfh_s11/pictures.py TRACE.npz OUT_DIR
"""

from __future__ import annotations

import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from nav_bench.interface import Command
from nav_bench.sim.session import SimSession
from nav_bench.sim.simulation import Simulation
from nav_bench.specs import WorldSpec, load_robot
from nav_bench.world.geometry import static_geometry
from nav_bench.world.load import world_from_data


def maze_17(path: str, out: str, t0: float = 184.8, t1: float = 188.4) -> None:
    trace = np.load(path, allow_pickle=True)
    world = world_from_data(json.loads(str(trace["meta"]))["world"])
    t, true, cmd = trace["t"], trace["true_pose"], trace["cmd"]
    sel = (t >= t0) & (t <= t1)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.8))
    for box in static_geometry(world).boxes:
        cx, cy, sx, sy, yaw = box[:5]  # maze walls: yaw 0 or 90 deg
        if abs(np.sin(yaw)) > 0.5:
            sx, sy = sy, sx
        ax.add_patch(plt.Rectangle((cx - sx / 2, cy - sy / 2), sx, sy, color="0.3"))
    xy = true[sel, :2]
    sc = ax.scatter(xy[:, 0], xy[:, 1], c=t[sel], s=12, cmap="viridis")
    i = int(np.flatnonzero(sel)[-1])
    ax.add_patch(plt.Circle(true[i, :2], 0.18, fill=False, color="r"))
    ax.set_xlim(xy[:, 0].min() - 0.6, xy[:, 0].max() + 0.6)
    ax.set_ylim(xy[:, 1].min() - 0.6, xy[:, 1].max() + 0.6)
    ax.set_aspect("equal")
    ax.set_title("maze_17 (55eee6e, seed 0): true path 184.8-188.4 s, body at the contact")
    fig.colorbar(sc, ax=ax, label="t (s)")
    speed = np.r_[0, np.hypot(*np.diff(true[:, :2], axis=0).T) / np.diff(t)]
    bx.plot(t[sel], cmd[sel, 0], label="v commanded (m/s)")
    bx.plot(t[sel], speed[sel], label="true speed (m/s)")
    bx.plot(t[sel], cmd[sel, 1] / 10, label="omega commanded / 10 (rad/s)")
    bx.axvline(187.8, color="r", ls=":", label="contact")
    bx.set_xlabel("t (s)")
    bx.legend(fontsize=8)
    bx.set_title("the turn on the spot at 5.77 rad/s from 0.37 m/s")
    fig.tight_layout()
    fig.savefig(f"{out}/maze_17_swerve.png", dpi=90)


def probe(out: str) -> None:
    """Empty room: 2 s at 0.37 m/s, then 1.5 s of v = 0 and omega 5.77 or 1.0 rad/s."""
    world = WorldSpec.model_validate({"name": "e", "size": [6.0, 6.0], "start": [2.0, 3.0, 0.0],
                                      "goal": [5.5, 5.5]})
    fig, ax = plt.subplots(figsize=(6, 4))
    with SimSession() as session:
        for omega in (5.77, 1.0):
            sim = Simulation(session, world, load_robot(), np.random.default_rng(0))
            poses = []
            for v, w, n in ((0.37, 0.0, 20), (0.0, omega, 15)):
                for _ in range(n):
                    sim.apply(Command(v, w))
                    sim.step(6)
                    poses.append(sim.true_pose())
            p = np.array(poses)
            moved = np.hypot(*(p[19:, :2] - p[19, :2]).T).max()
            ax.plot(p[:, 0], p[:, 1], ".-", label=f"spin at {omega} rad/s: {moved:.3f} m after the spin command")
    ax.set_aspect("equal")
    ax.legend(fontsize=8)
    ax.set_title("diffbot: drive at 0.37 m/s, then turn on the spot")
    fig.tight_layout()
    fig.savefig(f"{out}/drive_probe.png", dpi=90)


if __name__ == "__main__":
    maze_17(sys.argv[1], sys.argv[2])
    probe(sys.argv[2])
