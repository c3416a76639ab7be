"""The walking map: the walking verdict over sole length x crank speed, for every variant.

Each cell is one design: the seed design with its variant set, its sole made ``sole`` L long
on *each* side of the ankle (toe = heel; for ``parallel`` the ``parallel_toe`` /
``parallel_heel`` extents ahead of and behind joint 13, for ``rigid`` and ``spring`` the
``foot_toe`` / ``foot_heel`` extents of the sole square to the shank: the same symmetric sole,
so the three variants are compared foot for foot; the ``spring`` variant keeps its fitted ankle
spring), its cranks turning at ``omega``. It walks :data:`MAP_STEPS` steps on the floor
(:func:`~pasibot_pin.studies.walking.walk_design`) and the walking verdict
(:mod:`pasibot_pin.dynamics.verdict`) is its outcome. Where the MuJoCo twin is installed
(``pasibot_pin.studies.twin.mujoco_walk.walk_in_mujoco``, the same verdict on the exported model),
each cell is walked there too; without it the twin's columns are empty and
:attr:`WalkingMap.twin_note` says why.

The map is saved as CSV (:func:`save_map`, read back by :func:`load_map` with the standard
library only: no pyarrow needed to read the committed answer) in ``docs/results/walking_map.csv``;
``make walking-map`` computes it again (``tools/walking_map.py``), then draws ``docs/walking_map.png``
and writes what quotes it (``python -m pasibot_pin.report.answers.walking``).

Units: SI; soles over the crank length L; crank speed [rad/s]; angles in degrees where named ``_deg``.
"""

from __future__ import annotations

import importlib.util
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from pasibot_pin.errors import DesignError
from pasibot_pin.files import append_row, read_rows, write_rows
from pasibot_pin.jobs import Job, run_jobs
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.paths import result_path
from pasibot_pin.model.variants import get_variant
from pasibot_pin.progress import progress_bar
from pasibot_pin.studies.methods.spring_fit import design_spring
from pasibot_pin.studies.twin.mujoco_walk import walk_in_mujoco
from pasibot_pin.studies.walking import WalkSettings, walk_design

SOLES: tuple[float, ...] = (1.5, 3.0, 4.5, 6.0, 8.0, 10.0)
"""Sole extents on each side of the ankle [L]."""

OMEGAS: tuple[float, ...] = (0.5, 1.0, 2.0, 3.0, 5.0, 8.0)
"""Crank speeds [rad/s]."""

MAP_VARIANTS: tuple[str, ...] = ("parallel", "rigid", "spring")
"""The variants mapped."""

MAP_STEPS: int = 20
"""Steps each cell is asked to walk (the verdict's default) [-]."""

MAP_CSV = result_path("walking_map.csv")
"""The committed map: the wheel's copy, else the source checkout's docs/results
(:func:`~pasibot_pin.model.paths.result_path`); ``make walking-map`` (``tools/walking_map.py``) writes it."""
MAP_PNG = MAP_CSV.parents[1] / "walking_map.png"
"""The picture of the map beside the results' folder (a source checkout's ``docs/walking_map.png``), the one
``tools/walking_answer.py`` (``make walking-map``) draws."""

NO_TWIN = "MuJoCo (the mujoco extra) is not installed: the twin's columns are empty"


@dataclass(frozen=True)
class MapCell:
    """One design of the map and its walk.

    Attributes:
        variant: ``parallel``, ``rigid`` or ``spring``.
        sole: the sole's extent on each side of the ankle [L].
        omega: crank speed [rad/s].
        outcome: the walking verdict's outcome (or ``infeasible``: the design cannot be built).
        detail: what decided it, in words.
        decided_at_s: when it was decided [s].
        steps: steps walked [-].
        advance_m: the hip's forward displacement [m].
        advance_per_step: the hip's advance per step over the linkage's 8 L [-] (nan before 3 steps).
        max_hip_pitch_deg: largest |hip pitch| [deg].
        max_slip_mm: largest slide of a weight-bearing foot in one stance [mm].
        cost_of_transport: motor positive work over weight x stride advance [-].
        energy_per_m_J: motor positive work per metre [J/m].
        spring_stiffness: the ankle spring used [N.m/rad] (nan without one).
        spring_rest_angle: its rest angle [rad] (nan without one).
        cpu_s: CPU time of our walk [s].
        twin_outcome: the MuJoCo twin's outcome (``""``: not run).
        twin_steps: its steps (nan: not run) [-].
        twin_detail: what decided it.
        start: how our run started (:attr:`~pasibot_pin.dynamics.floor.FloorResult.start_kind`:
            ``settled``, or ``flat`` when no consistent start was found; ``""``: not recorded).
        start_note: why a consistent start fell back to ``flat`` (``""``: it did not).

    """

    variant: str
    sole: float
    omega: float
    outcome: str
    detail: str
    decided_at_s: float
    steps: int
    advance_m: float
    advance_per_step: float
    max_hip_pitch_deg: float
    max_slip_mm: float
    cost_of_transport: float
    energy_per_m_J: float
    spring_stiffness: float
    spring_rest_angle: float
    cpu_s: float
    twin_outcome: str = ""
    twin_steps: float = math.nan
    twin_detail: str = ""
    start: str = ""
    start_note: str = ""

    @property
    def walks(self) -> bool:
        """True when our verdict is ``walks``."""
        return self.outcome == "walks"


@dataclass
class WalkingMap:
    """Every cell of the map.

    Attributes:
        cells: one :class:`MapCell` per (variant, sole, omega).
        steps: steps each cell was asked to walk [-].
        twin_note: why the twin's columns are empty (``""`` when it ran).

    """

    cells: list[MapCell]
    steps: int = MAP_STEPS
    twin_note: str = ""

    @property
    def variants(self) -> list[str]:
        """The variants, in map order."""
        return list(dict.fromkeys(c.variant for c in self.cells))

    @property
    def soles(self) -> list[float]:
        """The sole extents, increasing [L]."""
        return sorted({c.sole for c in self.cells})

    @property
    def omegas(self) -> list[float]:
        """The crank speeds, increasing [rad/s]."""
        return sorted({c.omega for c in self.cells})

    def cell(self, variant: str, sole: float, omega: float) -> MapCell:
        """The cell of (variant, sole [L], omega [rad/s]) (KeyError if absent)."""
        for c in self.cells:
            if c.variant == variant and c.sole == sole and c.omega == omega:
                return c
        raise KeyError(f"no cell {variant}, sole {sole:g} L, omega {omega:g} rad/s")

    def walkers(self) -> list[MapCell]:
        """The cells whose verdict is ``walks``."""
        return [c for c in self.cells if c.walks]


def map_design(variant: str, sole: float, omega: float, base: Design | None = None) -> Design:
    """The design of one cell: ``base`` (the seed's) with the variant, a symmetric sole and the speed.

    Args:
        variant: ``parallel``, ``rigid`` or ``spring``.
        sole: extent of the sole on each side of the ankle [L].
        omega: crank speed [rad/s].
        base: the other parameters (default: the seed design).

    """
    base = Design() if base is None else base
    toe, heel = get_variant(variant).foot_fields  # the record names the variant's sole fields
    return base.with_(variant=variant, omega=float(omega), **{toe: float(sole), heel: float(sole)})


def twin_walker():
    """``walk_in_mujoco`` of the MuJoCo twin, or ``None`` when MuJoCo (the ``mujoco`` extra) is not installed."""
    if importlib.util.find_spec("mujoco") is None:
        return None
    return walk_in_mujoco


def _verdict_values(verdict) -> dict:
    return {
        "outcome": verdict.outcome,
        "detail": verdict.detail,
        "decided_at_s": float(verdict.decided_at),
        "steps": int(verdict.steps),
        "advance_m": float(verdict.advance_m),
        "advance_per_step": float(verdict.advance_per_step),
        "max_hip_pitch_deg": math.degrees(verdict.max_hip_pitch),
        "max_slip_mm": 1e3 * float(verdict.max_slip_m),
        "cost_of_transport": float(verdict.cost_of_transport),
        "energy_per_m_J": float(verdict.power_per_metre),
    }


def walk_cell(variant: str, sole: float, omega: float, steps: int = MAP_STEPS, twin: bool = True) -> MapCell:
    """Walk one cell (ours, and the twin's when installed and ``twin``); runs in a worker."""
    design = map_design(variant, sole, omega)
    settings = WalkSettings(steps=steps)
    start = time.process_time()
    nan = math.nan
    spring = (nan, nan)
    try:
        robot = design_robot(design, 2, visuals=False)
        fitted = design_spring(design, robot)
        if fitted is not None:
            spring = (float(fitted.stiffness), float(fitted.rest_angle))
        walk = walk_design(design, settings, robot)
        values = _verdict_values(walk.verdict)
        values.update(start=walk.result.start_kind, start_note=walk.result.start_note)
    except (DesignError, ValueError) as err:
        values = dict(outcome="infeasible", detail=str(err).splitlines()[0], decided_at_s=nan, steps=0)
        values.update(dict.fromkeys(("advance_m", "advance_per_step", "max_hip_pitch_deg", "max_slip_mm"), nan))
        values.update(cost_of_transport=nan, energy_per_m_J=nan)
    cpu = time.process_time() - start
    cell = MapCell(variant, float(sole), float(omega), **values, spring_stiffness=spring[0],
                   spring_rest_angle=spring[1], cpu_s=cpu)  # fmt: skip
    walker = twin_walker() if twin else None
    if walker is None or values["outcome"] == "infeasible":
        return cell
    mujoco = walker(design, settings).verdict

    return replace(cell, twin_outcome=mujoco.outcome, twin_steps=float(mujoco.steps), twin_detail=mujoco.detail)


def twin_cell(variant: str, sole: float, omega: float, steps: int = MAP_STEPS) -> tuple[tuple, str, float, str]:
    """The MuJoCo twin's walk of one cell: (key, outcome, steps, detail); runs in a worker."""
    walker = twin_walker()
    if walker is None:
        raise ImportError(NO_TWIN)
    v = walker(map_design(variant, sole, omega), WalkSettings(steps=steps)).verdict
    return (variant, float(sole), float(omega)), v.outcome, float(v.steps), v.detail


def add_twin(wmap: WalkingMap, min_omega: float = 0.0, workers: int = 2, progress: bool = True) -> WalkingMap:
    """``wmap`` with the MuJoCo twin's columns filled for every cell at ``min_omega`` [rad/s] or faster.

    Cells already holding a twin outcome and ``infeasible`` cells are left as they are. The map's
    :attr:`~WalkingMap.twin_note` says which cells the twin ran (empty when it ran on all of them).
    """
    todo = [c for c in wmap.cells if c.omega >= min_omega and not c.twin_outcome and c.outcome != "infeasible"]
    jobs = [Job(_estimate(c.omega, wmap.steps), (c.variant, c.sole, c.omega), twin_cell,
                (c.variant, c.sole, c.omega, wmap.steps)) for c in todo]  # fmt: skip
    found: dict[tuple, tuple] = {}
    bar = progress_bar(len(jobs), 0, progress, unit="walk")

    def on_result(_key, result) -> None:
        found[result[0]] = result[1:]
        bar.update(1)

    try:
        run_jobs(jobs, on_result, workers=max(1, workers))
    finally:
        bar.close()
    cells = []
    for c in wmap.cells:
        twin = found.get((c.variant, c.sole, c.omega))
        cells.append(c if twin is None else replace(c, twin_outcome=twin[0], twin_steps=twin[1], twin_detail=twin[2]))
    slow = [c for c in cells if not c.twin_outcome and c.outcome != "infeasible"]
    ran = [c.omega for c in cells if c.twin_outcome]
    note = NO_TWIN if not ran else f"the twin ran at omega >= {min(ran):g} rad/s only" if slow else ""
    return WalkingMap(cells, wmap.steps, note)


def with_twin_of(wmap: WalkingMap, old: WalkingMap) -> WalkingMap:
    """``wmap`` (our engine walked again, no twin) with the twin's columns and note of ``old``, cell by cell.

    For a change of our engine alone: MuJoCo's outcome of each cell does not depend on it.
    """
    twin = {(c.variant, c.sole, c.omega): c for c in old.cells}
    cells = []
    for c in wmap.cells:
        before = twin.get((c.variant, c.sole, c.omega))
        if before is not None:
            c = replace(
                c, twin_outcome=before.twin_outcome, twin_steps=before.twin_steps, twin_detail=before.twin_detail
            )
        cells.append(c)
    return WalkingMap(cells, wmap.steps, old.twin_note)


def _estimate(omega: float, steps: int) -> float:
    """A walk's CPU time if it walks, for ordering only (slow walks first) [s]."""
    return steps * math.pi / omega


def compute_walking_map(
    soles: Sequence[float] = SOLES,
    omegas: Sequence[float] = OMEGAS,
    variants: Sequence[str] = MAP_VARIANTS,
    steps: int = MAP_STEPS,
    workers: int | None = 2,
    twin: bool = True,
    progress: bool = True,
    partial: Path | None = None,
) -> WalkingMap:
    """Walk every (variant, sole, omega) cell on the local process pool.

    Args:
        soles: sole extents on each side of the ankle [L].
        omegas: crank speeds [rad/s].
        variants: variants.
        steps: steps each cell is asked to walk [-].
        workers: worker processes (:func:`pasibot_pin.jobs.run_jobs`, the process pool of sweeps).
        twin: also walk each cell in MuJoCo when the twin is installed.
        progress: show a progress bar.
        partial: a CSV each finished cell is appended to at once; the cells already in it are not
            walked again (an interrupted map resumes; remove the file to start over).

    Returns:
        :class:`WalkingMap`, cells in (variant, sole, omega) order.

    """
    keys = [(v, float(s), float(w)) for v in variants for s in soles for w in omegas]
    done: dict[tuple, MapCell] = {}
    if partial is not None and Path(partial).is_file():
        done = {(c.variant, c.sole, c.omega): c for c in _read_cells(Path(partial).read_text().splitlines())}
    todo = [k for k in keys if k not in done]
    jobs = [Job(_estimate(k[2], steps), k, walk_cell, (*k, steps, twin)) for k in todo]  # slow walks first
    bar = progress_bar(len(keys), len(keys) - len(todo), progress, unit="walk")

    def on_result(_key: object, cell: object) -> None:
        assert isinstance(cell, MapCell)
        done[(cell.variant, cell.sole, cell.omega)] = cell
        if partial is not None:
            _append_cell(Path(partial), cell)
        bar.update(1)

    try:
        run_jobs(jobs, on_result, workers=max(1, workers or 1))
    finally:
        bar.close()
    note = "" if (twin and twin_walker() is not None) else NO_TWIN
    return WalkingMap([done[k] for k in keys], steps, note)


# --------------------------------------------------------------------------- files
def save_map(wmap: WalkingMap, path: Path = MAP_CSV) -> Path:
    """Write the map as CSV: a ``# steps = N`` line, a ``# twin: ...`` line, then one row per cell."""
    head = (f"# steps = {wmap.steps}", f"# twin: {wmap.twin_note or 'walk_in_mujoco'}")
    return write_rows(Path(path), MapCell, wmap.cells, head)


def _read_cells(lines: Sequence[str]) -> list[MapCell]:
    """The cells of CSV lines (a header, then rows)."""
    return read_rows(lines, MapCell)


def _append_cell(path: Path, cell: MapCell) -> None:
    """Append one finished cell to a partial map (its header first when the file is new)."""
    append_row(path, cell)


def load_map(path: Path = MAP_CSV) -> WalkingMap:
    """Read a map written by :func:`save_map` (standard library only)."""
    lines = Path(path).read_text().splitlines()
    steps = int(lines[0].split("=")[1])
    twin = lines[1].split(":", 1)[1].strip()
    return WalkingMap(_read_cells(lines[2:]), steps, "" if twin == "walk_in_mujoco" else twin)
