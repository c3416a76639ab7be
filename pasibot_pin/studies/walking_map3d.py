"""The 3-D walking map: does the planar walker stay upright sideways, and with which feet.

Each cell is the planar map's walker (the ``parallel`` variant, 6 L soles ahead of and behind
joint 13) at one crank speed, on the 3-D floor (:func:`~pasibot_pin.studies.walking.walk_design_3d`)
with one of two lateral foot families:

- ``comb``: interleaved soles (:func:`comb_fields`). Each sole keeps its 0.06 m plate centred on
  its leg's plane and grows a prong that reaches ``value`` L past the midline, under the other
  leg. The two feet's prongs sit :data:`COMB_CLEARANCE` apart across the midline and from the
  other foot's plate, so the soles can be built as solid plates that never meet.
- ``narrow``: plain centred plates with the legs' planes ``value`` L from the midline
  (``hip_half_width``), the other way to bring the support under the body.

Where MuJoCo (the ``mujoco`` extra) is installed each cell is also walked on the 3-D export
(:func:`~pasibot_pin.studies.twin.mujoco_walk.walk_in_mujoco` with ``spatial=True``), judged the same way.

The map is saved as CSV (:func:`save_map3d`, read back by :func:`load_map3d` with the standard
library only); ``make walking-map-3d`` (``python tools/walking_map3d.py``) computes it.

Units: SI; lateral reaches over the crank length L; crank speed [rad/s]; angles in degrees where
named ``_deg``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

from pasibot_pin.errors import ParameterError, PasibotError
from pasibot_pin.files import append_row, read_rows, write_rows
from pasibot_pin.jobs import Job, run_jobs
from pasibot_pin.model.design import Design
from pasibot_pin.model.paths import result_path
from pasibot_pin.progress import progress_bar
from pasibot_pin.studies.walking import WalkSettings, walk_design_3d
from pasibot_pin.studies.walking_map import twin_walker

COMB_CLEARANCE: float = 0.2
"""The gap left between one foot's sole and the other's, across the midline and beside the plate [L]."""

PLATE: float = 0.6
"""A plate's reach each side of its leg's plane (the design record's default) [L]."""

REACHES: tuple[float, ...] = (0.2, 0.4, 0.6, 0.8, 1.0, 1.2)
"""The comb prongs' reach past the midline [L]."""

HALF_WIDTHS: tuple[float, ...] = (1.4, 1.0, 0.7)
"""The narrow family's leg planes from the midline [L] (0.6 L: the centred plates touch)."""

OMEGAS_3D: tuple[float, ...] = (0.5, 1.0, 2.0, 3.0)
"""Crank speeds [rad/s]: where the planar walker walks."""

MAP3D_STEPS: int = 6
"""Steps each cell is asked to walk [-] (a 3-D step costs about ten planar ones)."""

FAMILIES: tuple[str, ...] = ("comb", "narrow")
"""The lateral foot families."""

MAP3D_CSV = result_path("walking_map3d.csv")
"""The committed 3-D map (read only): the wheel's copy, else the source checkout's docs/results
(:func:`~pasibot_pin.model.paths.result_path`); ``make walking-map-3d`` (``tools/walking_map3d.py``) writes it."""

RECOMMENDED: tuple[str, float, float] = ("comb", 0.6, 2.0)
"""The walker to build: (feet, value [L], omega [rad/s]), the fastest comb walker that both engines walk
upright for 20 steps (``designs/3d/upright_fastest_*``, chosen by ``tools/designs3d.py``; a test holds
them equal)."""


def recommended_walker() -> Design:
    """The design of :data:`RECOMMENDED` (:func:`map3d_design`)."""
    return map3d_design(*RECOMMENDED)


def walker_base() -> Design:
    """The planar map's walker: the seed design, ``parallel`` variant, 6 L each side of joint 13."""
    return Design().with_(variant="parallel", parallel_toe=6.0, parallel_heel=6.0)


def comb_fields(reach: float, hip_half_width: float = 2.0, clearance: float = COMB_CLEARANCE) -> dict[str, float]:
    """The sole fields of interleaved combs whose prongs reach ``reach`` past the midline [L].

    The prong runs from ``clearance / 2`` past the midline to ``reach`` past it; the plate keeps
    :data:`PLATE` toward the midline unless the other foot's prong needs room, when it is cut back
    to leave ``clearance`` beside that prong.

    Raises:
        ParameterError: ``reach`` not past ``clearance / 2``, or so far that no plate is left.

    """
    inner = hip_half_width + reach
    gap_from = min(PLATE, 2.0 * hip_half_width - inner - clearance)
    if not (reach > clearance / 2 and gap_from > -PLATE):
        raise ParameterError(
            f"parameter 'reach' = {reach:g} L: a comb's prong must reach past {clearance / 2:g} L and leave a plate "
            f"(at most {2 * hip_half_width - clearance:g} L past the midline with hip_half_width {hip_half_width:g} L)"
        )
    return {
        "sole_inner": inner,
        "sole_outer": PLATE,
        "sole_gap_from": gap_from,
        "sole_gap_to": hip_half_width + clearance / 2,
    }


def map3d_design(feet: str, value: float, omega: float, base: Design | None = None) -> Design:
    """The design of one cell: ``base`` (:func:`walker_base`) with its feet and crank speed.

    Args:
        feet: ``comb`` (``value``: the prongs' reach past the midline [L]) or ``narrow``
            (``value``: ``hip_half_width`` [L], centred plates).
        value: see ``feet``.
        omega: crank speed [rad/s].
        base: the other parameters.

    """
    base = walker_base() if base is None else base
    if feet == "comb":
        return base.with_(omega=float(omega), **comb_fields(value, base.hip_half_width))
    if feet == "narrow":
        return base.with_(omega=float(omega), hip_half_width=float(value))
    raise ParameterError(f"parameter 'feet' = {feet!r}: choose one of {', '.join(FAMILIES)}")


@dataclass(frozen=True)
class Map3DCell:
    """One design of the 3-D map: our 3-D walk and the twin's.

    Attributes:
        feet: ``comb`` or ``narrow``.
        value: the comb's reach past the midline, or the narrow family's ``hip_half_width`` [L].
        omega: crank speed [rad/s].
        outcome, detail: our verdict and what decided it (``refused``: the design was refused).
        decided_at_s: when it was decided [s].
        steps: steps walked [-].
        advance_m: the hip's forward displacement [m].
        max_hip_roll_deg: largest |hip roll| [deg].
        min_sole_clearance_m: the soles' least distance apart [m].
        cpu_s: CPU time of our walk [s].
        twin_outcome: MuJoCo's outcome on the 3-D export (``""``: not run).
        twin_steps: its steps [-].
        twin_advance_m: its advance [m].
        twin_max_hip_roll_deg: its largest |hip roll| [deg].
        twin_cpu_s: its CPU time [s].

    """

    feet: str
    value: float
    omega: float
    outcome: str
    detail: str
    decided_at_s: float
    steps: int
    advance_m: float
    max_hip_roll_deg: float
    min_sole_clearance_m: float
    cpu_s: float
    twin_outcome: str = ""
    twin_steps: float = math.nan
    twin_advance_m: float = math.nan
    twin_max_hip_roll_deg: float = math.nan
    twin_cpu_s: float = math.nan

    @property
    def walks(self) -> bool:
        """True when our verdict is ``walks``."""
        return self.outcome == "walks"


@dataclass
class WalkingMap3D:
    """Every cell of the 3-D map, and the steps each was asked to walk."""

    cells: list[Map3DCell]
    steps: int = MAP3D_STEPS

    def family(self, feet: str) -> list[Map3DCell]:
        """The cells of one foot family, in map order."""
        return [c for c in self.cells if c.feet == feet]

    def smallest_reach(self) -> dict[float, float]:
        """Each crank speed's least comb reach past the midline that walks in both engines [L].

        NaN where none does; where the twin was not run, our verdict alone.
        """
        out: dict[float, float] = {}
        for c in self.family("comb"):
            both = c.walks and c.twin_outcome in ("", "walks")
            out.setdefault(c.omega, math.nan)
            if both and not (out[c.omega] <= c.value):
                out[c.omega] = c.value
        return out


def walk_cell_3d(feet: str, value: float, omega: float, steps: int = MAP3D_STEPS, twin: bool = True) -> Map3DCell:
    """Walk one cell on our 3-D floor (and the twin's, when installed and ``twin``); runs in a worker."""
    design = map3d_design(feet, value, omega)
    settings = WalkSettings(steps=steps)
    nan = math.nan
    start = time.process_time()
    try:
        walk = walk_design_3d(design, settings)
    except PasibotError as err:
        return Map3DCell(feet, value, omega, "refused", str(err).splitlines()[0], nan, 0, nan, nan, nan,
                         time.process_time() - start)  # fmt: skip
    v, r = walk.verdict, walk.result
    cell = Map3DCell(feet, float(value), float(omega), v.outcome, v.detail, float(v.decided_at), int(v.steps),
                     float(v.advance_m), r.max_hip_roll_deg, r.min_sole_clearance_m,
                     time.process_time() - start)  # fmt: skip
    walker = twin_walker() if twin else None
    if walker is None:
        return cell
    start = time.process_time()
    m = walker(design, settings, spatial=True)
    return Map3DCell(**{**asdict(cell), "twin_outcome": m.verdict.outcome, "twin_steps": float(m.verdict.steps),
                        "twin_advance_m": float(m.verdict.advance_m), "twin_max_hip_roll_deg": m.max_hip_roll_deg,
                        "twin_cpu_s": time.process_time() - start})  # fmt: skip


def compute_walking_map_3d(
    reaches: Sequence[float] = REACHES,
    half_widths: Sequence[float] = HALF_WIDTHS,
    omegas: Sequence[float] = OMEGAS_3D,
    steps: int = MAP3D_STEPS,
    workers: int = 2,
    twin: bool = True,
    progress: bool = True,
    partial: Path | None = None,
) -> WalkingMap3D:
    """Walk every (feet, value, omega) cell on the local process pool.

    Args:
        reaches: the comb family's reaches past the midline [L].
        half_widths: the narrow family's ``hip_half_width`` values [L].
        omegas: crank speeds [rad/s].
        steps: steps each cell is asked to walk [-].
        workers: worker processes.
        twin: also walk each cell in MuJoCo when it is installed.
        progress: show a progress bar.
        partial: a CSV each finished cell is appended to; cells already in it are not walked again.

    """
    keys = [("comb", float(r), float(w)) for r in reaches for w in omegas]
    keys += [("narrow", float(h), float(w)) for h in half_widths for w in omegas]
    done: dict[tuple, Map3DCell] = {}
    if partial is not None and Path(partial).is_file():
        done = {(c.feet, c.value, c.omega): c for c in read_rows(Path(partial).read_text().splitlines(), Map3DCell)}
    todo = [k for k in keys if k not in done]
    jobs = [Job(steps * math.pi / k[2], k, walk_cell_3d, (*k, steps, twin)) for k in todo]
    bar = progress_bar(len(keys), len(keys) - len(todo), progress, unit="walk")

    def on_result(_key: object, cell: object) -> None:
        assert isinstance(cell, Map3DCell)
        done[(cell.feet, cell.value, cell.omega)] = cell
        if partial is not None:
            append_row(Path(partial), cell)
        bar.update(1)

    try:
        run_jobs(jobs, on_result, workers=max(1, workers))
    finally:
        bar.close()
    return WalkingMap3D([done[k] for k in keys], steps)


def save_map3d(wmap: WalkingMap3D, path: Path) -> Path:
    """Write the map as CSV: a ``# steps = N`` line, then one row per cell."""
    return write_rows(Path(path), Map3DCell, wmap.cells, (f"# steps = {wmap.steps}",))


def load_map3d(path: Path) -> WalkingMap3D:
    """Read a map written by :func:`save_map3d` (standard library only)."""
    lines = Path(path).read_text().splitlines()
    return WalkingMap3D(read_rows(lines[1:], Map3DCell), int(lines[0].split("=")[1]))
