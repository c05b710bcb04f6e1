"""Physics fidelity against the 240 Hz / 50-iteration reference, and what each setting costs.

For each physics setting (rate in Hz, Bullet solver iterations, contact ERP: Bullet's own or
``20 / rate``, i.e. penetration removed at 20/s, nav-bench's default) the robot is driven through
scripted scenes with the control cycle at 10 Hz (``round(physics_hz / 10)`` physics steps per
cycle, as an episode steps) and odometry noise off, and measured on what the benchmark's rows
depend on:

* **tracking**: from rest, 3 s of each command (v m/s, omega rad/s); achieved (v, omega) per
  control cycle from the true pose. ``ss err`` is the mean error over the last second relative
  to the command; ``rms vs ref`` the RMS difference of the achieved speeds from the reference
  setting's, cycle by cycle (the step response included); ``pose vs ref`` the distance between
  the final positions;
* **odometry**: a 24 s scripted drive (straight, curves, turn on the spot); drift of the wheel
  odometry from the true pose per metre travelled (position m/m, heading deg/m), and the end
  position's distance from the reference setting's;
* **stopping**: full speed (0.75 m/s), then ``v = 0``: distance and time to rest;
* **wall**: driving at full speed into a wall head-on and at 45 deg for 5 s: contact episodes
  (the row's ``collisions``), deepest penetration, jitter while pressed (std of position over
  the last 2 s), climb (rise of the base), and tunnelling (the body's centre past the face);
* **mover**: a box mover (0.4 m) at 0.4 m/s (the paper worlds' speeds) and 1.0 m/s runs into
  the standing robot and on through its path: contact episodes, penetration, climb,
  tunnelling (the mover passes the robot's centre), how far the robot is pushed;
* **cost**: physics steps and simulated seconds per wall second driving in the open, and the
  wall time of one ``goal_seek`` episode in a paper world (median of repeats, interleaved so
  every setting sees the same load).

Run::

    PYTHONPATH=. python benchmarks/bench_physics.py            # all settings, ~5 min
    PYTHONPATH=. python benchmarks/bench_physics.py --quick    # fewer settings and repeats

Writes ``results/fidelity/physics.md`` and ``physics.json`` (``--out`` to change the folder).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.interface import Command, wrap_angle
from nav_bench.sim.session import SimSession
from nav_bench.sim.simulation import Simulation
from nav_bench.specs import PlannerSetSpec, RobotSpec, WorldSpec, load_robot
from nav_bench.world.load import load_world

CONTROL_HZ = 10.0
FULL_SPEED = 0.75  # m/s: the default robot's wheel-speed limit x wheel radius
WALL_FACE_X = 3.0  # m: the near face of the test wall
EPISODE_WORLD = "worlds/paper/long_wall.yaml"

TRACK_COMMANDS = ((0.5, 0.0), (0.25, 0.0), (0.75, 0.0), (0.0, 1.0), (0.3, 0.6))
# (v, omega, seconds): the odometry drive
ODOMETRY_SCRIPT = ((0.5, 0.0, 4.0), (0.4, 0.5, 4.0), (0.0, 1.0, 3.0), (0.3, -0.4, 5.0),
                   (0.6, 0.0, 3.0), (0.2, 0.8, 5.0))


@dataclass(frozen=True)
class PhysicsSetting:
    """One engine configuration: physics steps per second and solver iterations per step."""

    hz: float
    iterations: int = 50
    # 1/s: contact ERP = recovery / hz (SimSession's contact_recovery_hz); None: Bullet's own ERP
    recovery: float | None = None
    # m/s: the solver stops early below this velocity error (SimSession's solver_residual);
    # None: Bullet's own (1e-7)
    residual: float | None = None

    @property
    def name(self) -> str:
        erp = "" if self.recovery is None else f" / ERP {self.recovery:g}/hz"
        res = "" if self.residual is None else f" / residual {self.residual:g}"
        return f"{self.hz:g} Hz / {self.iterations} it{erp}{res}"

    @property
    def steps_per_cycle(self) -> int:
        return max(1, round(self.hz / CONTROL_HZ))


REFERENCE = PhysicsSetting(240.0, 50)
SETTINGS = (REFERENCE, PhysicsSetting(120.0), PhysicsSetting(80.0), PhysicsSetting(60.0),
            PhysicsSetting(40.0), PhysicsSetting(30.0), PhysicsSetting(240.0, 20),
            PhysicsSetting(120.0, 20), PhysicsSetting(60.0, 20), PhysicsSetting(60.0, 10),
            PhysicsSetting(240.0, 50, 20.0), PhysicsSetting(120.0, 50, 20.0),
            PhysicsSetting(80.0, 50, 20.0), PhysicsSetting(60.0, 50, 20.0),
            PhysicsSetting(40.0, 50, 20.0), PhysicsSetting(30.0, 50, 20.0),
            PhysicsSetting(60.0, 50, 30.0))
# the shipped setting (60 Hz, contact recovery 20/s) with looser solver stopping thresholds
RESIDUAL_SETTINGS = (REFERENCE, PhysicsSetting(60.0, 50, 20.0),
                     *(PhysicsSetting(60.0, 50, 20.0, r) for r in (1e-5, 1e-4, 1e-3, 1e-2)))
QUICK_SETTINGS = (REFERENCE, PhysicsSetting(120.0), PhysicsSetting(60.0),
                  PhysicsSetting(60.0, 20), PhysicsSetting(240.0, 50, 20.0),
                  PhysicsSetting(60.0, 50, 20.0))


@dataclass
class Fidelity:
    """Every measured figure of one setting (units in the names)."""

    setting: str
    hz: float
    iterations: int
    tracking: dict[str, dict[str, float]] = field(default_factory=dict)
    odometry: dict[str, float] = field(default_factory=dict)
    stopping: dict[str, float] = field(default_factory=dict)
    wall: dict[str, dict[str, float]] = field(default_factory=dict)
    mover: dict[str, dict[str, float]] = field(default_factory=dict)
    cost: dict[str, float] = field(default_factory=dict)


def exact_robot() -> RobotSpec:
    """The default robot with odometry noise off (drift is then the physics' own)."""
    robot = load_robot()
    return robot.model_copy(update={"odometry": robot.odometry.model_copy(
        update={"wheel_noise": 0.0})})


def world(start: tuple[float, float, float], obstacles: list | None = None,
          movers: list | None = None) -> WorldSpec:
    """A 10 m x 10 m world built in code; start yaw in degrees."""
    return WorldSpec.model_validate({
        "name": "bench_physics", "size": [10.0, 10.0], "boundary": False, "start": list(start),
        "goal": [9.0, 9.0], "obstacles": obstacles or [], "movers": movers or []})


def open_sim(session: SimSession, spec: WorldSpec, setting: PhysicsSetting) -> Simulation:
    session.solver_iterations, session.contact_recovery_hz = setting.iterations, setting.recovery
    session.solver_residual = setting.residual
    session.reset(setting.hz)  # applies the rate, the iterations and the contact ERP
    return Simulation(session, spec, exact_robot(), np.random.default_rng(0), setting.hz)


def cycle_poses(sim: Simulation, setting: PhysicsSetting, cmd: Command, seconds: float) -> np.ndarray:
    """Drive ``cmd`` for ``seconds``; (C, 3) true poses at the end of each control cycle."""
    sim.apply(cmd)
    poses = []
    for _ in range(round(seconds * CONTROL_HZ)):
        sim.step(setting.steps_per_cycle)
        poses.append(sim.true_pose())
    return np.asarray(poses)


def achieved_speeds(start: np.ndarray, poses: np.ndarray, cycle_s: float) -> np.ndarray:
    """(C, 2) achieved (v, omega) per cycle from consecutive poses (v along the mid heading)."""
    all_poses = np.vstack([start, poses])
    d = np.diff(all_poses, axis=0)
    dyaw = np.array([wrap_angle(a) for a in d[:, 2]])
    mid = all_poses[:-1, 2] + dyaw / 2.0
    v = (d[:, 0] * np.cos(mid) + d[:, 1] * np.sin(mid)) / cycle_s
    return np.column_stack([v, dyaw / cycle_s])


# ------------------------------------------------------------------------------------- scenes
def measure_tracking(session: SimSession, setting: PhysicsSetting) -> dict[str, dict[str, float]]:
    out = {}
    for v, omega in TRACK_COMMANDS:
        sim = open_sim(session, world((5.0, 5.0, 0.0)), setting)
        start = sim.true_pose()
        poses = cycle_poses(sim, setting, Command(v, omega), 3.0)
        speeds = achieved_speeds(start, poses, 1.0 / CONTROL_HZ)
        steady = speeds[-10:].mean(axis=0)
        out[f"v={v:g},w={omega:g}"] = {
            "v_ss": float(steady[0]), "omega_ss": float(steady[1]),
            "v_err_pct": 100.0 * (steady[0] - v) / v if v else 100.0 * float(steady[0]),
            "omega_err_pct": (100.0 * (steady[1] - omega) / omega if omega
                              else float(np.degrees(steady[1]))),
            "speeds": speeds.tolist(), "end": poses[-1].tolist()}
    return out


def measure_odometry(session: SimSession, setting: PhysicsSetting) -> dict[str, float]:
    sim = open_sim(session, world((2.0, 2.0, 0.0)), setting)
    path = 0.0
    prev = sim.true_pose()
    for v, omega, seconds in ODOMETRY_SCRIPT:
        for pose in cycle_poses(sim, setting, Command(v, omega), seconds):
            path += float(np.hypot(*(pose[:2] - prev[:2])))
            prev = pose
    true, odom = sim.true_pose(), sim.odometry_pose()
    return {"path_m": path, "drift_m_per_m": float(np.hypot(*(odom[:2] - true[:2]))) / path,
            "heading_deg_per_m": math.degrees(abs(wrap_angle(odom[2] - true[2]))) / path,
            "end_x": float(true[0]), "end_y": float(true[1])}


def measure_stopping(session: SimSession, setting: PhysicsSetting) -> dict[str, float]:
    sim = open_sim(session, world((1.0, 5.0, 0.0)), setting)
    cycle_poses(sim, setting, Command(FULL_SPEED, 0.0), 2.0)
    start = sim.true_pose()
    poses = cycle_poses(sim, setting, Command(0.0, 0.0), 2.0)
    moved = np.hypot(*(np.diff(np.vstack([start, poses])[:, :2], axis=0).T))
    at_rest = np.flatnonzero(moved < 1e-4)  # < 1 mm/s over a cycle
    return {"distance_m": float(np.hypot(*(poses[-1, :2] - start[:2]))),
            "time_s": float((at_rest[0] + 1) / CONTROL_HZ) if at_rest.size else math.inf,
            "yaw_deg": math.degrees(abs(wrap_angle(poses[-1, 2] - start[2])))}


def _press(sim: Simulation, setting: PhysicsSetting, cmd: Command, seconds: float,
           other: int) -> dict[str, np.ndarray]:
    """Step one physics step at a time; per step: position, base height, deepest contact."""
    sim.apply(cmd)
    client, robot = sim.session.client, sim.robot.body_id
    xs, zs, depth = [], [], []
    for _ in range(round(seconds * setting.hz)):
        sim.step(1)
        (x, y, z), _ = sim.robot.link_pose()
        xs.append((x, y))
        zs.append(z)
        pts = client.getContactPoints(bodyA=robot, bodyB=other)
        depth.append(max((-p[8] for p in pts), default=0.0))
    return {"xy": np.asarray(xs), "z": np.asarray(zs), "depth": np.asarray(depth)}


def measure_wall(session: SimSession, setting: PhysicsSetting) -> dict[str, dict[str, float]]:
    out = {}
    wall = [{"box": {"center": [WALL_FACE_X + 0.1, 5.0], "size": [0.2, 6.0]}}]
    for name, yaw in (("head-on", 0.0), ("45 deg", 45.0)):
        sim = open_sim(session, world((2.0, 5.0, yaw), wall), setting)
        rest_z = sim.robot.link_pose()[0][2]
        radius = sim.robot_info.radius
        rec = _press(sim, setting, Command(FULL_SPEED, 0.0), 6.0, sim.scene.body_ids[0])
        last = rec["xy"][-round(2.0 * setting.hz):]
        out[name] = {
            "contacts": sim.collisions, "penetration_mm": 1e3 * float(rec["depth"].max()),
            "jitter_mm": 1e3 * float(last[:, 0].std()),  # across the wall's face
            "climb_mm": 1e3 * float(rec["z"].max() - rest_z),
            "gap_mm": 1e3 * float(WALL_FACE_X - (rec["xy"][-1, 0] + radius)),
            "slide_m": float(rec["xy"][-1, 1] - 5.0),
            "tunnelled": float(rec["xy"][:, 0].max() > WALL_FACE_X)}
    return out


# (name, mover speed m/s, robot's command v m/s): standing robot run into, and head-on
MOVER_SCENES = (("0.4 m/s, robot standing", 0.4, 0.0), ("0.7 m/s, robot standing", 0.7, 0.0),
                ("1.0 m/s, robot standing", 1.0, 0.0), ("0.5 m/s, robot at 0.5 m/s head-on", 0.5, 0.5))


def measure_mover(session: SimSession, setting: PhysicsSetting) -> dict[str, dict[str, float]]:
    out = {}
    for name, speed, robot_v in MOVER_SCENES:
        mover = {"shape": {"box": {"size": [0.4, 0.4]}}, "path": [[1.0, 5.0], [9.5, 5.0]],
                 "speed": speed, "mode": "pingpong"}
        sim = open_sim(session, world((4.0, 5.0, 180.0), movers=[mover]), setting)
        rest_z = sim.robot.link_pose()[0][2]
        start = sim.true_pose()
        seconds = 6.0 / speed  # the mover's front ends 7.2 m along: well past the start
        rec = _press(sim, setting, Command(robot_v, 0.0), seconds, sim.movers.body_ids[0])
        mover_x = sim.mover_positions()[0, 0]
        robot_x = rec["xy"][-1, 0]
        out[name] = {
            "contacts": sim.collisions, "penetration_mm": 1e3 * float(rec["depth"].max()),
            "climb_mm": 1e3 * float(rec["z"].max() - rest_z),
            "pushed_m": float(np.hypot(*(rec["xy"][-1] - start[:2]))),
            "tunnelled": float(mover_x > robot_x)}
    return out


def measure_cost(setting: PhysicsSetting, repeats: int) -> dict[str, float]:
    """Steps/s driving a curve in the open, and one goal_seek episode's wall time (medians)."""
    rates, episodes = [], []
    spec = load_world(EPISODE_WORLD)
    settings = EpisodeSettings(physics_hz=setting.hz, record_trace=False)
    for _ in range(repeats):
        with SimSession(physics_hz=setting.hz, solver_iterations=setting.iterations,
                        contact_recovery_hz=setting.recovery, solver_residual=setting.residual) as session:
            sim = open_sim(session, world((2.0, 2.0, 0.0)), setting)
            sim.apply(Command(0.3, 0.2))
            sim.step(setting.steps_per_cycle * 10)
            n = setting.steps_per_cycle * 300  # 30 simulated s
            t0 = time.perf_counter()
            for _ in range(300):
                sim.step(setting.steps_per_cycle)
            rates.append(n / (time.perf_counter() - t0))
            t0 = time.perf_counter()
            result = run_episode(spec, PlannerSetSpec(planner="goal_seek"), seed=0,
                                 settings=settings, session=session)
            episodes.append(time.perf_counter() - t0)
    steps_s = statistics.median(rates)
    return {"steps_per_s": steps_s, "sim_s_per_s": steps_s / setting.hz,
            "episode_wall_s": statistics.median(episodes), "episode_sim_s": result.row.time_s,
            "episode_outcome": result.row.outcome}


# -------------------------------------------------------------------------------------- report
def compare(results: list[Fidelity]) -> None:
    """Fill the per-setting differences from the reference (the first result)."""
    ref = results[0]
    for res in results:
        for key, track in res.tracking.items():
            a, b = np.asarray(track["speeds"]), np.asarray(ref.tracking[key]["speeds"])
            track["v_rms_vs_ref"] = float(np.sqrt(np.mean((a[:, 0] - b[:, 0]) ** 2)))
            track["omega_rms_vs_ref"] = float(np.sqrt(np.mean((a[:, 1] - b[:, 1]) ** 2)))
            track["pose_vs_ref_mm"] = 1e3 * float(np.hypot(
                *(np.asarray(track["end"][:2]) - np.asarray(ref.tracking[key]["end"][:2]))))
        res.odometry["end_vs_ref_mm"] = 1e3 * float(np.hypot(
            res.odometry["end_x"] - ref.odometry["end_x"],
            res.odometry["end_y"] - ref.odometry["end_y"]))


def wall_cells(w: dict[str, float]) -> list[str]:
    return [f"{w['contacts']:.0f}", f"{w['penetration_mm']:.2f}", f"{w['jitter_mm']:.3f}",
            f"{w['climb_mm']:.2f}", f"{w['gap_mm']:.2f}", f"{w['slide_m']:+.3f}",
            "yes" if w["tunnelled"] else "no"]


def mover_cells(m: dict[str, float]) -> list[str]:
    return [f"{m['contacts']:.0f}", f"{m['penetration_mm']:.2f}", f"{m['climb_mm']:.2f}",
            f"{m['pushed_m']:.3f}", "yes" if m["tunnelled"] else "no"]


def markdown(results: list[Fidelity], header: str) -> str:
    ref = results[0]
    lines = [header, ""]

    def table(title: str, cols: list[str], rows: list[list[str]]) -> None:
        lines.extend([f"### {title}", "", "| setting | " + " | ".join(cols) + " |",
                      "|---|" + "---:|" * len(cols)])
        lines.extend("| " + " | ".join(r) + " |" for r in rows)
        lines.append("")

    keys = list(ref.tracking)
    table("Tracking: steady-state error of achieved v / omega vs the command, % (last 1 s of "
          "3 s from rest; where omega = 0, the yaw rate in deg/s)",
          keys, [[r.setting] + [f"{t['v_err_pct']:+.2f} / {t['omega_err_pct']:+.2f}"
                                for t in r.tracking.values()] for r in results])
    table("Tracking vs the reference: RMS difference of achieved v (mm/s) / omega (mrad/s) "
          "per control cycle over 3 s from rest (step response included)",
          keys, [[r.setting] + [f"{1e3 * t['v_rms_vs_ref']:.1f} / {1e3 * t['omega_rms_vs_ref']:.1f}"
                                for t in r.tracking.values()] for r in results])
    table("Tracking vs the reference: end position after 3 s, distance from the reference's (mm)",
          keys, [[r.setting] + [f"{t['pose_vs_ref_mm']:.1f}" for t in r.tracking.values()]
                 for r in results])
    table("Odometry (noise off) and stopping from 0.75 m/s",
          ["drift mm/m", "heading deg/m", "end vs ref mm", "stop m", "stop s", "stop yaw deg"],
          [[r.setting, f"{1e3 * r.odometry['drift_m_per_m']:.2f}",
            f"{r.odometry['heading_deg_per_m']:.3f}", f"{r.odometry['end_vs_ref_mm']:.1f}",
            f"{r.stopping['distance_m']:.3f}", f"{r.stopping['time_s']:.1f}",
            f"{r.stopping['yaw_deg']:.2f}"] for r in results])
    for scene in ref.wall:
        table(f"Wall at full speed, {scene}, 6 s (jitter: std across the face over the last 2 s; climb: base height change, negative = sinks; gap: face to body edge at the end)",
              ["contacts", "penetration mm", "jitter mm", "climb mm", "gap mm", "slide m",
               "tunnelled"],
              [[r.setting, *wall_cells(r.wall[scene])] for r in results])
    for scene in ref.mover:
        table(f"Box mover (0.4 m) at {scene}",
              ["contacts", "penetration mm", "climb mm", "pushed m", "tunnelled"],
              [[r.setting, *mover_cells(r.mover[scene])] for r in results])
    if all(r.cost for r in results):
        table(f"Cost (median of repeats; goal_seek in {EPISODE_WORLD}, "
              "shared 2-core machine under load)",
              ["physics steps/s", "sim s per wall s", "x ref", "episode wall s", "x ref",
               "episode outcome"],
              [[r.setting, f"{r.cost['steps_per_s']:,.0f}", f"{r.cost['sim_s_per_s']:,.0f}",
                f"{r.cost['sim_s_per_s'] / ref.cost['sim_s_per_s']:.2f}",
                f"{r.cost['episode_wall_s']:.3f}",
                f"{ref.cost['episode_wall_s'] / r.cost['episode_wall_s']:.2f}",
                f"{r.cost['episode_outcome']} {r.cost['episode_sim_s']:.1f} s"] for r in results])
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    which = parser.add_mutually_exclusive_group()  # each picks its own list of settings
    which.add_argument("--quick", action="store_true", help="fewer settings and repeats")
    which.add_argument("--residual", action="store_true",
                       help="the shipped setting with looser solver stopping thresholds")
    parser.add_argument("--repeats", type=int, default=3, help="cost repeats per setting")
    parser.add_argument("--out", default="results/fidelity", help="folder for physics.md/json")
    args = parser.parse_args()
    settings = RESIDUAL_SETTINGS if args.residual else QUICK_SETTINGS if args.quick else SETTINGS
    repeats = 1 if args.quick else args.repeats
    results = [Fidelity(s.name, s.hz, s.iterations) for s in settings]
    for setting, res in zip(settings, results, strict=True):
        # a session per setting: Bullet keeps a contact ERP once set, and has no call to
        # restore its own
        with SimSession(physics_hz=setting.hz, solver_iterations=setting.iterations,
                        contact_recovery_hz=setting.recovery, solver_residual=setting.residual) as session:
            res.tracking = measure_tracking(session, setting)
            res.odometry = measure_odometry(session, setting)
            res.stopping = measure_stopping(session, setting)
            res.wall = measure_wall(session, setting)
            res.mover = measure_mover(session, setting)
            print(f"measured {setting.name}", flush=True)
    costs: dict[str, list[dict[str, float]]] = {s.name: [] for s in settings}
    for _ in range(repeats):  # interleaved: every setting sees the same load
        for setting in settings:
            costs[setting.name].append(measure_cost(setting, 1))
    for setting, res in zip(settings, results, strict=True):
        runs = costs[setting.name]
        res.cost = {key: (statistics.median(run[key] for run in runs)
                          if isinstance(runs[0][key], float) else runs[0][key])
                    for key in runs[0]}
    compare(results)
    header = (f"## Physics fidelity vs {REFERENCE.name} (control at {CONTROL_HZ:g} Hz, "
              "odometry noise off)\n\nMeasured by `PYTHONPATH=. python benchmarks/bench_physics.py"
              f"{' --quick' if args.quick else ''}{' --residual' if args.residual else ''}` ({time.strftime('%Y-%m-%d')}).")
    text = markdown(results, header)
    print(text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "physics.md").write_text(text + "\n")
    for res in results:
        for track in res.tracking.values():
            track.pop("speeds")
    (out / "physics.json").write_text(json.dumps([asdict(r) for r in results], indent=1) + "\n")


if __name__ == "__main__":
    main()
