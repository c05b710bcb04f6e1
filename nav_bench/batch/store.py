"""Results on disk: append-only, crash-safe, resumable.

A results folder holds::

    episodes.jsonl        one result row per line, appended and fsync'ed as each episode ends
    run.json              the suite as expanded, versions, host, times, status (replaced atomically)
    traces/<job_id>.npz   one trace per episode, for replotting (with the trace's JSON sidecar)
    worlds/<name>.yaml    worlds made by generators, so every row's world_file exists

Only one process writes a folder: the runner's parent (or the Dask client). A row is appended
only after its trace is written, so a row always has its trace. ``kill -9`` can leave a
half-written last line; :meth:`ResultsStore.rows` reports it (a :class:`ResultsWarning` naming
the file and line) and skips it, and :meth:`ResultsStore.repair` (called on resume) cuts it off.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import warnings
from pathlib import Path
from typing import Any

from nav_bench.episode.row import ResultRow, RowSchemaError, check_row
from nav_bench.errors import InputError

EPISODES = "episodes.jsonl"
RUN = "run.json"
TRACES = "traces"
WORLDS = "worlds"

class ResultsWarning(UserWarning):
    """Something in a results folder was repaired or skipped (a torn last line, a duplicate row)."""


def _finite_or_none(value: Any) -> Any:
    """NaN and infinities become null, so every line is strict JSON (jq, pandas, browsers)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite_or_none(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite_or_none(v) for v in value]
    return value


def row_to_line(row: dict[str, Any]) -> str:
    """One row as one line of strict JSON (keys in the row's order), with the newline."""
    return json.dumps(_finite_or_none(row), allow_nan=False, default=str,
                      separators=(",", ":")) + "\n"


def atomic_write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` so that readers see the old or the new file, never a mix."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.chmod(tmp, 0o644)  # mkstemp makes it private; results are meant to be shared
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    _fsync_dir(path.parent)


def _fsync_dir(folder: Path) -> None:
    # make the rename itself durable; not possible (nor needed) on every platform
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


class ResultsStore:
    """One results folder. Reading works on any folder; writing assumes a single writer."""

    def __init__(self, folder: str | Path) -> None:
        self.dir = Path(folder)
        self._file: Any = None

    # -- paths -------------------------------------------------------------------
    @property
    def episodes_path(self) -> Path:
        return self.dir / EPISODES

    @property
    def run_path(self) -> Path:
        return self.dir / RUN

    def trace_path(self, job_id: str) -> Path:
        """Where the trace of ``job_id`` lives (``traces/<job_id>.npz``)."""
        return self.dir / TRACES / f"{job_id}.npz"

    def world_path(self, name: str) -> Path:
        return self.dir / WORLDS / f"{name}.yaml"

    def exists(self) -> bool:
        """True if the folder already holds a run (run.json or rows)."""
        return self.run_path.exists() or self.episodes_path.exists()

    # -- run.json ----------------------------------------------------------------
    def write_run(self, meta: dict[str, Any]) -> None:
        """Replace run.json atomically (temp file + fsync + os.replace)."""
        atomic_write_text(self.run_path, json.dumps(_finite_or_none(meta), indent=2,
                                                    default=str) + "\n")

    def read_run(self) -> dict[str, Any]:
        """The run's metadata; :class:`InputError` if the folder has no readable run.json."""
        try:
            return json.loads(self.run_path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise InputError(f"{self.dir} is not a nav-bench results folder (no {RUN})") from None
        except (OSError, json.JSONDecodeError) as exc:
            raise InputError(f"{self.run_path}: cannot read run metadata: {exc}") from None

    # -- rows ----------------------------------------------------------------------
    def open(self) -> ResultsStore:
        """Create the folder and open episodes.jsonl for appending."""
        (self.dir / TRACES).mkdir(parents=True, exist_ok=True)
        if self._file is None:
            self._file = open(self.episodes_path, "a", encoding="utf-8")  # noqa: SIM115
        return self

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def __enter__(self) -> ResultsStore:
        return self.open()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def append(self, row: ResultRow) -> None:
        """Append one row (checked against the row schema first) and make it durable (flush +
        fsync) before returning. :class:`RowSchemaError` if the row is not valid."""
        data = row.to_json()
        check_row(data)
        if self._file is None:
            self.open()
        self._file.write(row_to_line(data))
        self._file.flush()
        os.fsync(self._file.fileno())

    def _scan(self) -> tuple[list[dict[str, Any]], int | None, int]:
        """Parsed rows, the 1-based number of a torn last line (or None), and its byte offset.

        A torn line is the last one when it lacks its newline: one ``write`` puts a whole line
        including the newline, so a crash can only cut off its end. A bad line that does end
        with a newline is damage of another kind and an :class:`InputError`.
        """
        try:
            data = self.episodes_path.read_bytes()
        except FileNotFoundError:
            return [], None, 0
        if not data:
            return [], None, 0
        complete = data.endswith(b"\n")
        lines = data.split(b"\n")[:-1] if complete else data.split(b"\n")
        rows: list[dict[str, Any]] = []
        offset = 0
        for number, raw in enumerate(lines, start=1):
            if number == len(lines) and not complete:
                return rows, number, offset
            if raw.strip():
                try:
                    row = json.loads(raw)
                except ValueError:
                    row = None
                if not isinstance(row, dict):
                    raise InputError(f"{self.episodes_path}:{number}: not a JSON row; the file "
                                     f"is damaged (more than a torn last line)")
                try:
                    check_row(row)
                except RowSchemaError as exc:
                    raise InputError(f"{self.episodes_path}:{number}: not a valid result row: "
                                     f"{exc}") from None
                rows.append(row)
            offset += len(raw) + 1
        return rows, None, offset

    def results(self) -> list[ResultRow]:
        """Every complete row as a :class:`ResultRow`, in file order (see :meth:`rows`)."""
        return [ResultRow.from_json(r) for r in self.rows()]

    def rows(self) -> list[dict[str, Any]]:
        """Every complete row as stored (JSON objects, each checked against the row schema),
        in file order; a torn last line is skipped with a warning."""
        rows, torn, _ = self._scan()
        if torn is not None:
            warnings.warn(f"{self.episodes_path}:{torn}: incomplete last line (the run was "
                          f"killed while writing it); ignored", ResultsWarning, stacklevel=2)
        return _drop_duplicates(rows, self.episodes_path)

    def repair(self) -> int | None:
        """Cut a torn last line off episodes.jsonl (with a warning); its line number or None."""
        _, torn, offset = self._scan()
        if torn is None:
            return None
        self.close()
        with open(self.episodes_path, "r+b") as f:
            f.truncate(offset)
            f.flush()
            os.fsync(f.fileno())
        warnings.warn(f"{self.episodes_path}:{torn}: incomplete last line (the run was killed "
                      f"while writing it); removed, that episode will run again",
                      ResultsWarning, stacklevel=2)
        return torn

    def done_ids(self) -> set[str]:
        """job_ids that have a complete row."""
        return {r["job_id"] for r in self.rows() if "job_id" in r}


def _drop_duplicates(rows: list[dict[str, Any]], path: Path) -> list[dict[str, Any]]:
    seen: set[str] = set()
    out = []
    for number, row in enumerate(rows, start=1):
        job_id = row.get("job_id")
        if job_id is not None and job_id in seen:
            warnings.warn(f"{path}:{number}: second row for job {job_id!r}; the first is kept",
                          ResultsWarning, stacklevel=3)
            continue
        if job_id is not None:
            seen.add(job_id)
        out.append(row)
    return out
