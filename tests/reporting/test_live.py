"""The live map view (nav_bench.reporting.live): frames every 0.5 s simulated, GIF without a screen."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from nav_bench.errors import InputError
from nav_bench.reporting.live import LiveView
from nav_bench.specs import WorldSpec

WORLD = WorldSpec(name="room", size=(6.0, 4.0), start=[1.0, 2.0], goal=(5.0, 2.0))


def state(t: float) -> dict:
    pmo = np.full((44, 64), 50, dtype=np.uint8)
    pmo[:, : int(10 * t) + 1] = 10
    return {"pmo": pmo, "bounds": [-0.2, -0.2, 6.2, 4.2], "target": [5.0, 2.0], "mode": "goal"}


def replan_event(t: float) -> dict:
    pts = [[1.5 + 0.5 * np.cos(a), 2.0 + 0.5 * np.sin(a)] for a in np.linspace(0, 2 * np.pi, 16,
                                                                             endpoint=False)]
    return {"kind": "replan", "t": t, "data": {"breakpoint": [1.5, 2.0], "neighbours": pts,
                                               "risk": [0, 50, 100, 0] * 4,
                                               "candidate": [True, False] * 8, "chosen": 0}}


def test_gif_has_one_frame_per_half_second_plus_the_final_state(tmp_path) -> None:
    path = tmp_path / "ep.gif"
    view = LiveView(WORLD, every_s=0.5, save=path)
    for k in range(23):  # t = 0.0 .. 2.2 s at 10 Hz: frames at 0, 0.5, 1.0, 1.5, 2.0 and the end
        t = 0.1 * k
        view.update(t, np.array([1.0 + 0.1 * k, 2.0, 0.0]), state(t),
                    [replan_event(t)] if k == 7 else [])
    view.close()
    view.close()  # idempotent
    with Image.open(path) as gif:
        assert gif.n_frames == 6
        assert gif.info["duration"] == 500  # real-time playback by default
    assert view.frames_drawn == 6


def test_frames_for_a_planner_without_grids(tmp_path) -> None:
    path = tmp_path / "plain.gif"
    with LiveView(WORLD, every_s=1.0, save=path, fps=4) as view:
        for k in range(11):
            view.update(0.1 * k, np.array([1.0, 2.0, 0.1 * k]), {}, [])
    with Image.open(path) as gif:
        assert gif.n_frames == 2 and gif.info["duration"] == 250


def test_bad_requests_are_clear_errors(tmp_path) -> None:
    with pytest.raises(InputError, match=r"\.gif or \.mp4"):
        LiveView(WORLD, save=tmp_path / "x.avi")
    with pytest.raises(InputError, match="backend"):
        LiveView(WORLD, show=True)  # the test run uses the non-interactive Agg backend
    with pytest.raises(InputError, match="every_s"):
        LiveView(WORLD, every_s=0)


def chain_plan(bx: float, chosen_xy: tuple[float, float], trigger: str) -> dict:
    pts = [[bx + 0.5, 2.0]] * 16
    pts[3] = list(chosen_xy)
    return {"breakpoint": [bx, 2.0], "neighbours": pts, "risk": [0] * 16, "candidate": [True] * 16,
            "chosen": 3, "trigger": trigger}


def test_the_chain_is_drawn_numbered_with_eo_stops_apart(tmp_path) -> None:
    view = LiveView(WORLD, every_s=0.5, save=tmp_path / "chain.gif")
    plans = [chain_plan(1.5, (2.0, 2.5), "eo_stop"), chain_plan(2.0, (2.5, 2.5), "blocked_path"),
             chain_plan(2.5, (3.0, 2.0), "blocked_path")]
    for k, plan in enumerate(plans):
        view.update(0.5 * k, np.array([1.0 + k, 2.0, 0.0]), state(0.0),
                    [{"kind": "replan", "t": 0.5 * k, "data": plan}])
    view.close()
    xs, ys = view._chain.get_data()
    assert list(zip(xs, ys, strict=True)) == [(1.5, 2.0), (2.0, 2.5), (2.0, 2.0), (2.5, 2.5), (2.5, 2.0), (3.0, 2.0)]
    assert view._breakpoints["eo_stop"].get_offsets().tolist() == [[1.5, 2.0]]
    assert view._breakpoints["blocked_path"].get_offsets().tolist() == [[2.0, 2.0], [2.5, 2.0]]
    assert [t.get_text() for t in view.ax.texts if t.get_text()] == ["1", "2", "3"]
