"""A results table that streams to disk, survives interruptions and resumes.

A run's folder holds:

* ``plan.json``: what the run evaluates (a resumed run must have the same plan);
* ``parts/part-NNNNNN.parquet``: finished designs, written every few seconds, each file written
  under a temporary name and renamed, so an interrupted run (Ctrl-C, a crash, a lost worker)
  keeps every design it finished and never leaves half a file;
* ``results.parquet`` (and ``results.csv`` on request): every row, sorted by ``index``, once the
  run is complete.

Rows: ``index``, every parameter of the design record by its flat name (``variant``, ``L``, ``K``,
``r1`` .. ``r13``, ...; null for an unset optional one), every metric of
:data:`~pasibot_pin.studies.design_metrics.METRICS`, then ``feasible``, ``failure`` and
``reason``; a run may add columns of its own (the floor simulation's) after the metrics.
"""

from __future__ import annotations

import json
import math
import shutil
import time
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np

from pasibot_pin.errors import ParameterError
from pasibot_pin.files import MARKER, atomic_path, write_text_atomic
from pasibot_pin.model.design import CHOICES, Design
from pasibot_pin.studies.design_metrics import METRICS

PLAN_FILE = "plan.json"
PARTS = "parts"
RESULTS = "results.parquet"
RESULTS_CSV = "results.csv"
OWNED = (PLAN_FILE, PARTS, RESULTS, RESULTS_CSV, "pareto.png", "sensitivity.png", "best", "optuna.log")
"""The names a run writes in its folder (``--force`` removes these, nothing else)."""

FLUSH_SECONDS: float = 2.0
"""Finished rows are written at least this often [s]; the first finished rows at once (a run shows
on disk that it works, and an interrupted one keeps them)."""


def parameter_names() -> list[str]:
    """The design record's flat parameter names, in the record's order."""
    return list(Design().values())


def schema(extra: Mapping[str, str] | None = None):
    """The table's pyarrow schema (fixed, so every part and every executor agree)."""
    import pyarrow as pa  # deferred: optional extra (pyarrow)

    types = {"float": pa.float64(), "int": pa.int64(), "str": pa.string(), "bool": pa.bool_()}
    fields = [pa.field("index", pa.int64())]
    fields += [pa.field(name, pa.string() if name in CHOICES else pa.float64()) for name in parameter_names()]
    fields += [pa.field(name, pa.float64()) for name in METRICS]
    fields += [pa.field(name, types[kind]) for name, kind in (extra or {}).items()]
    fields += [pa.field("feasible", pa.bool_()), pa.field("failure", pa.string()), pa.field("reason", pa.string())]
    return pa.schema(fields)


def design_row(index: int, values: Mapping[str, object], metrics_row: Mapping[str, object], **extra) -> dict:
    """One table row: the design's flat values (None: null), any extra columns, its metrics."""
    row: dict[str, object] = {"index": int(index)}
    row.update(values)  # an unset optional parameter (None) is a null
    row.update(extra)
    row.update(metrics_row)
    return row


class ResultStore:
    """The results of one run in ``folder`` (see the module's notes).

    Args:
        folder: the run's folder.
        plan: the run's plan record (JSON-able); compared with the saved one to resume.
        total: the number of rows of a complete run.
        force: start over: remove what an earlier run wrote in ``folder`` (only the names of
            :data:`OWNED`).
        extra: extra columns and their kinds (``float``, ``int``, ``str``, ``bool``).

    Raises:
        FileExistsError: ``folder`` holds another run (a different plan) or other files, and
            ``force`` is false. Raised before any work.

    """

    def __init__(
        self,
        folder: Path,
        plan: Mapping,
        total: int,
        force: bool = False,
        extra: Mapping[str, str] | None = None,
    ):
        self.folder = Path(folder)
        self.plan = json.loads(json.dumps(plan))  # as it reads back from the file
        self.total = int(total)
        self.schema = schema(extra)
        self._buffer: list[dict] = []
        self._last_flush = -math.inf  # the first rows are written as soon as they finish
        self._check(force)
        self.done: set[int] = self._done_indices()

    # ---- folder
    def _check(self, force: bool) -> None:
        folder = self.folder
        if folder.exists() and not folder.is_dir():
            raise ParameterError(f"--out {folder} is a file, not a folder")
        if force and folder.is_dir():
            for name in OWNED:
                target = folder / name
                if target.is_dir():
                    shutil.rmtree(target)
                elif target.exists():
                    target.unlink()
        saved = folder / PLAN_FILE
        if saved.is_file():
            try:
                old = json.loads(saved.read_text())
            except json.JSONDecodeError:
                old = None
            if old != self.plan:
                raise FileExistsError(
                    f"--out {folder} holds a different run ({PLAN_FILE} differs); "
                    "use another folder, or --force to replace it"
                )
        elif not force and folder.is_dir() and any(entry.name != MARKER for entry in folder.iterdir()):
            raise FileExistsError(f"--out {folder} is not empty and holds no run; use another folder or --force")
        (folder / PARTS).mkdir(parents=True, exist_ok=True)
        if not saved.is_file():
            write_text_atomic(saved, json.dumps(self.plan, indent=2) + "\n")

    def _parts(self) -> list[Path]:
        return sorted((self.folder / PARTS).glob("part-*.parquet"))

    def _done_indices(self) -> set[int]:
        import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

        done: set[int] = set()
        for part in self._parts():
            done.update(int(i) for i in pq.read_table(part, columns=["index"]).column("index").to_pylist())
        return done

    @property
    def complete(self) -> bool:
        """Every row of the run is on disk."""
        return len(self.done) >= self.total

    # ---- writing
    def add(self, rows: Iterable[Mapping]) -> None:
        """Buffer finished rows; write them when :data:`FLUSH_SECONDS` have passed since the last part."""
        for row in rows:
            self._buffer.append(dict(row))
            self.done.add(int(row["index"]))
        if time.monotonic() - self._last_flush >= FLUSH_SECONDS:
            self.flush()

    def flush(self) -> None:
        """Write the buffered rows as one part (temporary name, then rename)."""
        import pyarrow as pa  # deferred: optional extra (pyarrow)
        import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

        self._last_flush = time.monotonic()
        if not self._buffer:
            return
        table = pa.Table.from_pylist(self._buffer, schema=self.schema)
        first = min(int(r["index"]) for r in self._buffer)
        number = len(self._parts())
        target = self.folder / PARTS / f"part-{number:06d}-{first:08d}.parquet"
        with atomic_path(target) as tmp:  # removed on any error or signal, never left half written
            pq.write_table(table, tmp)
        self._buffer.clear()

    def table(self):
        """Every row on disk (and buffered), sorted by ``index`` (a pyarrow Table)."""
        import pyarrow as pa  # deferred: optional extra (pyarrow)
        import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

        tables = [pq.read_table(p, schema=self.schema) for p in self._parts()]
        if self._buffer:
            tables.append(pa.Table.from_pylist(self._buffer, schema=self.schema))
        if not tables:
            return self.schema.empty_table()
        table = pa.concat_tables(tables)
        return table.take(pa.compute.sort_indices(table, sort_keys=[("index", "ascending")]))

    def finish(self, csv: bool = False) -> Path:
        """Write ``results.parquet`` (and ``results.csv``) from every part, atomically."""
        import pyarrow.csv as pcsv  # deferred: optional extra (pyarrow)
        import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

        self.flush()
        table = self.table()
        target = self.folder / RESULTS
        with atomic_path(target) as tmp:
            pq.write_table(table, tmp)
        if csv:
            with atomic_path(self.folder / RESULTS_CSV) as tmp:
                pcsv.write_csv(table, tmp)
        return target


def column(table, name: str, rows: Sequence[int] | None = None):
    """One column as a numpy array (optionally only ``rows``)."""
    values = np.asarray(table.column(name).to_numpy(zero_copy_only=False))
    return values if rows is None else values[np.asarray(rows, dtype=int)]
