"""The command line: exit statuses and what it prints."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from nav_bench.cli import main

ROOT = Path(__file__).resolve().parents[1]
BROKEN = ROOT / "tests" / "data" / "broken_worlds"


def test_validate_accepts_the_shipped_files(capsys):
    assert main(["validate", str(ROOT / "worlds"), str(ROOT / "configs")]) == 0
    out = capsys.readouterr().out
    checked = int(out.split(" of ")[1].split()[0])
    assert checked >= 7


@pytest.mark.parametrize("name", sorted(p.name for p in BROKEN.glob("*.yaml")))
def test_validate_refuses_each_broken_file_with_exit_2(name, capsys):
    assert main(["validate", str(BROKEN / name)]) == 2
    err = capsys.readouterr().err
    assert str(BROKEN / name) in err


def test_validate_missing_file_is_bad_input(tmp_path, capsys):
    assert main(["validate", str(tmp_path / "nope.yaml")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_unknown_planner_suggests_the_closest(capsys):
    code = main(["episode", str(ROOT / "worlds/paper/open_room.yaml"), "--planner", "eopcc"])
    assert code == 2
    assert "did you mean 'eopc'" in capsys.readouterr().err.lower()


def test_unknown_planner_parameter_is_bad_input(capsys):
    code = main(["episode", str(ROOT / "worlds/paper/open_room.yaml"), "--planner", "eopc:RRR=0.4"])
    assert code == 2
    assert "'RR'" in capsys.readouterr().err


def test_bad_cli_argument_exits_2():
    with pytest.raises(SystemExit) as info:
        main(["episode", "w.yaml", "--seed", "abc"])
    assert info.value.code == 2


def test_show_writes_a_png(tmp_path, capsys):
    out = tmp_path / "w.png"
    assert main(["show", str(ROOT / "worlds/paper/long_wall.yaml"), "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "long_wall: 10 m x 10 m, 1 obstacles" in capsys.readouterr().out


def test_a_closed_pipe_ends_quietly():
    """`nav-bench list | head -1`: the reader closes the pipe early; no traceback, exit 0."""
    proc = subprocess.run(f"{sys.executable} -m nav_bench list | head -1", shell=True,
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.stdout.count("\n") == 1
    assert "Traceback" not in proc.stderr and "Error" not in proc.stderr
