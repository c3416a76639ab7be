"""The design-exploration section: the designer's questions and their answers (docs/results/).

The answers are the designs :mod:`pasibot_pin.report.answers.questions` found (NSGA-II, 600 trials each,
``make answers`` runs them again); here they are evaluated afresh and set beside the seed design.
The same text is quoted in ``docs/design_exploration.md`` and the README; a test compares them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from pasibot_pin.dynamics.verdict import GaitCriteria
from pasibot_pin.explore.plan import Range
from pasibot_pin.model.design import SPECS, Design, design_robot, load_design
from pasibot_pin.report.answers.questions import (
    FLOOR_STEPS,
    QUESTION_RANGES,
    STRAIGHTNESS_FACTOR,
    STRIDE_TOLERANCE,
    answer_path,
    floor_plan,
    read_summary,
    seed_stride_plan,
)
from pasibot_pin.report.answers.walking import walking_answer, walking_paragraph
from pasibot_pin.report.markdown import Section, sentence_lines
from pasibot_pin.studies.design_metrics import dynamic_metrics, path_metrics
from pasibot_pin.studies.walking import WALK_MU
from pasibot_pin.studies.walking_map import MAP_CSV, load_map

COLUMNS: tuple[tuple[str, str, float, str], ...] = (
    ("peak_crank_torque_Nm", "peak crank torque [N.m]", 1.0, "{:.2f}"),
    ("rms_crank_torque_Nm", "RMS crank torque [N.m]", 1.0, "{:.2f}"),
    ("energy_per_step_J", "motor work per step [J]", 1.0, "{:.1f}"),
    ("stride_m", "stride [m]", 1.0, "{:.4f}"),
    ("straightness_m", "stance path straightness [mm]", 1e3, "{:.1f}"),
    ("step_height_m", "step height [m]", 1.0, "{:.3f}"),
    ("cop_margin_m", "CoP margin [m]", 1.0, "{:.3f}"),
)
"""(metric, column title with unit, scale, format) of the answer table."""

PARAMETERS: tuple[tuple[str, str], ...] = (
    ("K", "K [-]"),
    ("r4", "L4 [L]"),
    ("r5", "L5 [L]"),
    ("r6", "L6 [L]"),
    ("foot_toe", "toe [L]"),
    ("foot_heel", "heel [L]"),
    ("body_com_dx", "body COM [m]"),
)


@dataclass(frozen=True)
class Answer:
    """One row of the answer table: a label, its design and its metrics."""

    label: str
    design: Design
    metrics: dict[str, float]


def answers() -> list[Answer]:
    """The seed design and the two answers of question 1, evaluated now (xacro-built robots)."""
    rows = []
    for label, design in (
        ("seed design", Design()),
        ("least torque, same stride", load_design(answer_path(False))),
        ("least torque, same stride, straight path", load_design(answer_path(True))),
    ):
        metrics = path_metrics(design)
        metrics.update(dynamic_metrics(design, design_robot(design, 2)))
        rows.append(Answer(label, design, metrics))
    return rows


def explored() -> tuple[int, float]:
    """(designs evaluated in the two runs, the best CoP margin of any feasible one [m]), from the answers' summary."""
    summary = read_summary()
    return int(summary["designs_explored"]), float(summary["best_cop_margin_m"])


def _cell(value: float, scale: float, fmt: str) -> str:
    return fmt.format(value * scale)


def markdown(rows: list[Answer] | None = None) -> str:
    """The section's Markdown: the question, a table with units, and the verdicts."""
    rows = rows or answers()
    seed, free, straight = rows
    head = "| design | " + " | ".join(t for _, t, _, _ in COLUMNS) + " |"
    lines = [head, "|" + "---|" * (len(COLUMNS) + 1)]
    for r in rows:
        lines.append(f"| {r.label} | " + " | ".join(_cell(r.metrics[m], s, f) for m, _, s, f in COLUMNS) + " |")
    params = ["| design | " + " | ".join(t for _, t in PARAMETERS) + " |", "|" + "---|" * (len(PARAMETERS) + 1)]
    for r in rows:
        values = r.design.values()
        params.append(f"| {r.label} | " + " | ".join(f"{values[p]:.3g}" for p, _ in PARAMETERS) + " |")

    def drop(r: Answer) -> float:
        return 100 * (1 - r.metrics["peak_crank_torque_Nm"] / seed.metrics["peak_crank_torque_Nm"])

    ratio = free.metrics["straightness_m"] / seed.metrics["straightness_m"]
    trials, best_margin = explored()
    verdicts = [
        f"* Keeping the stride within {100 * STRIDE_TOLERANCE:.0f} %, the peak crank torque falls by "
        f"{drop(free):.0f} % ({seed.metrics['peak_crank_torque_Nm']:.2f} -> "
        f"{free.metrics['peak_crank_torque_Nm']:.2f} N.m), but the stance path is {ratio:.0f} times less "
        f"straight: the hip bobs.",
        f"* Keeping the path as straight as {STRAIGHTNESS_FACTOR:g} times the seed's as well, it falls by "
        f"{drop(straight):.0f} % ({straight.metrics['peak_crank_torque_Nm']:.2f} N.m).",
        f"* The spring does not change these numbers (the hip's motion is prescribed). None of the {trials} "
        f"designs explored keeps the centre of pressure inside the sole through the stance: the best margin "
        f"is {best_margin:.3f} m (negative: outside), against {seed.metrics['cop_margin_m']:.3f} m for the seed.",
    ]
    return "\n".join(lines + [""] + params + [""] + verdicts)


@dataclass(frozen=True)
class FloorAnswer:
    """Question 2 on the floor: how the spring designs fared (from docs/results/floor_springs.parquet).

    Attributes:
        trials: designs evaluated [-].
        walkers: designs whose walking verdict is ``walks`` [-].
        best_time: the time to the verdict of the best design (most steps, then longest) [s].
        best_steps: its steps [-].
        most_steps: the most steps any design took [-].
        outcomes: the count of each outcome (``infeasible``: a design that cannot be built or turned).
        best_index: the best design's index in the table.
        best_outcome: its outcome and what decided it.

    """

    trials: int
    walkers: int
    best_time: float
    best_steps: int
    most_steps: int
    outcomes: dict[str, int]
    best_index: int
    best_outcome: str


def floor_answer() -> FloorAnswer:
    """The summary of question 2's run, as ``make answers`` stored it (no pyarrow needed)."""
    return FloorAnswer(**read_summary()["floor"])


def floor_markdown(answer: FloorAnswer | None = None) -> str:
    """Question 2's verdict, one paragraph (the walking verdict's outcomes, counted)."""
    a = answer or floor_answer()
    plan = floor_plan()

    units = {r.name: "" if SPECS[r.name].unit == "-" else f" {SPECS[r.name].unit}" for r in plan.ranges}
    names = ", ".join(f"{r.name} {r.low:g} to {r.high:g}{units[r.name]}" for r in plan.ranges if isinstance(r, Range))
    counts = ", ".join(f"{n} {o}" for o, n in sorted(a.outcomes.items(), key=lambda kv: (-kv[1], kv[0])))
    pitch = math.degrees(GaitCriteria().max_hip_pitch)
    head = (
        f"On the floor (heel and toe contacts, mu = {WALK_MU:g}, body {plan.base.body_mass:g} kg, each design asked "
        f"to walk {FLOOR_STEPS} steps and judged by the walking verdict: fell = |hip pitch| past {pitch:.0f} deg),\n"
        f"NSGA-II over the spring designs, varying {names} ({a.trials} designs)"
    )
    if a.walkers:
        return sentence_lines(f"{head} found {a.walkers} that walk. Outcomes: {counts}.")
    return sentence_lines(
        f"{head} found none that walks: the best took {a.best_steps} steps ({a.best_outcome} at {a.best_time:.2f} s) "
        f"and no design took more than {a.most_steps}. Outcomes: {counts}. With the cranks turning at a set "
        "speed and no controller, a passive ankle spring does not make PASIBOT walk in this range."
    )


def walking_text() -> str:
    """The walking map's answer (:func:`~pasibot_pin.report.answers.walking.walking_paragraph` of the committed map)."""
    if not MAP_CSV.is_file():  # an installed wheel: the map's table stays in the source repository
        return "The walking map's table (docs/results/walking_map.csv) is in the source repository (make walking-map)."
    return walking_paragraph(walking_answer(load_map()))


def question() -> str:
    """The question and how it was answered (one paragraph)."""
    plan = seed_stride_plan()
    names = ", ".join(r.name for r in QUESTION_RANGES)
    return (
        "Which designs (geometry, spring, sole, body COM) minimise the peak crank torque while keeping the seed "
        f"design's stride? NSGA-II over {names} (`pasibot optimize`, {plan.trials} trials per run, population "
        f"{plan.population}; `make answers` runs both again); each design below is evaluated afresh."
    )


def build(out_dir: Path):
    """The report section (no files of its own) and the facts the summary quotes."""
    rows = answers()
    seed, free, straight = rows
    floor = floor_answer()
    walking = walking_text()
    text = "\n".join(
        [
            "## Design exploration: less torque at the same stride",
            "",
            question(),
            "",
            markdown(rows),
            "",
            "### Does it walk? (the walking map, docs/walking.md)",
            "",
            walking,
            "",
            "### Does any spring design walk on the floor?",
            "",
            floor_markdown(floor),
            "",
        ]
    )
    facts = {
        "seed_peak": seed.metrics["peak_crank_torque_Nm"],
        "free_peak": free.metrics["peak_crank_torque_Nm"],
        "straight_peak": straight.metrics["peak_crank_torque_Nm"],
        "straightness_ratio": free.metrics["straightness_m"] / seed.metrics["straightness_m"],
        "floor_trials": floor.trials,
        "floor_walkers": floor.walkers,
        "floor_best_time": floor.best_time,
        "floor_most_steps": floor.most_steps,
    }
    return Section(text, facts)


def section(out_dir: Path) -> str:
    """The report section's Markdown (:func:`build` without the facts)."""
    return build(out_dir).markdown
