"""Does it walk? The answer of the walking map (docs/results/walking_map.csv) in numbers and words.

:func:`walking_answer` reads the figures off a :class:`~pasibot_pin.studies.walking_map.WalkingMap`
(which variants walk, the smallest walking sole at each speed, the fastest walker, the spring
designs' failures, the least motor energy per metre); :func:`walking_paragraph` says them in one
paragraph, the one ``docs/walking.md``, the README and the report quote (``tests/test_walking_map.py``
checks the quotes); :func:`walking_markdown` is the rest of ``docs/walking.md``.

Units: SI; soles over the crank length L; crank speed [rad/s].
"""

from __future__ import annotations

import math
import statistics
from collections import Counter
from dataclasses import dataclass, field

from pasibot_pin.dynamics.verdict import LINKAGE_ADVANCE_PER_STEP
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.paths import result_path
from pasibot_pin.model.variants import get_variant
from pasibot_pin.report.designs_catalog import SWEEP_NAME, Entry, fastest_sweep_design, sweep_entry, sweep_rows
from pasibot_pin.report.markdown import sentence_lines
from pasibot_pin.studies.spring_study import toppling_stiffness
from pasibot_pin.studies.walking_map import (
    MapCell,
    WalkingMap,
)


def committed_sweep_rows() -> list[dict]:
    """The committed walking sweep's rows (:func:`~pasibot_pin.report.designs_catalog.sweep_rows`), none without it."""
    path = result_path(SWEEP_NAME)
    return sweep_rows(path) if path.is_file() else []


@dataclass(frozen=True)
class WalkingAnswer:
    """The walking map's answer.

    Attributes:
        cells: designs in the map [-].
        steps: steps each was asked to walk [-].
        walkers: walkers per variant [-] (every variant, 0 included).
        smallest_sole: per crank speed [rad/s], the smallest walking sole [L] and its variants
            (speeds without a walker are absent).
        fastest: the walker of the highest crank speed on the map's grid (then the smallest sole), or ``None``
            (the map's top-speed walker; the fastest walker found is ``fastest_found``).
        least_energy: the walker of the least motor energy per metre, or ``None``.
        failures: per variant, the count of each failure outcome.
        spring_details: the spring cells' failure details and their counts, most common first.
        soles: the map's soles [L]; omegas: its crank speeds [rad/s].
        spring_range: the fitted springs of the spring cells, in words (K_e [N.m/rad], beta0 [deg]).
        spring_median_s: the median time the spring cells' failures were decided [s].
        spring_by_speed: per crank speed, the spring cells' mean fitted K_e [N.m/rad] and commonest outcome.
        twin_cells: cells the MuJoCo twin walked too [-]; twin_agree: of them, where both engines agree
            that it walks or not [-]; twin_same: where the outcomes are the same [-].
        twin_walkers: the twin's walkers, in words; twin_note: which cells the twin ran (``""``: all).
        fastest_found: the fastest walker found, the walking sweep's (its ``designs/`` entry), or ``None``.

    """

    cells: int
    steps: int
    walkers: dict[str, int]
    smallest_sole: dict[float, tuple[float, tuple[str, ...]]]
    fastest: MapCell | None
    least_energy: MapCell | None
    failures: dict[str, dict[str, int]]
    spring_details: list[tuple[str, int]] = field(default_factory=list)
    soles: tuple[float, ...] = ()
    omegas: tuple[float, ...] = ()
    spring_range: str = ""
    spring_median_s: float = math.nan
    spring_by_speed: dict[float, tuple[float, str]] = field(default_factory=dict)
    twin_cells: int = 0
    twin_agree: int = 0
    twin_same: int = 0
    twin_walkers: tuple[str, ...] = ()
    twin_note: str = ""
    fastest_found: Entry | None = None


def _detail_kind(detail: str) -> str:
    """A failure detail without its numbers and side (``the left foot slid 5.6 mm`` -> ``a foot slid``)."""
    words = [w for w in detail.replace("right", "").replace("left", "").split() if not any(c.isdigit() for c in w)]
    return " ".join(words).replace("the foot", "a foot").replace("  ", " ")


def walking_answer(wmap: WalkingMap, rows: list[dict] | None = None) -> WalkingAnswer:
    """The figures of the answer, read off ``wmap`` and the walking sweep's ``rows`` (default: the committed sweep)."""
    rows = committed_sweep_rows() if rows is None else rows
    found = sweep_entry(rows) if any(r["floor_outcome"] == "walks" for r in rows) else None
    walkers = wmap.walkers()
    smallest: dict[float, tuple[float, tuple[str, ...]]] = {}
    for omega in wmap.omegas:
        here = [c for c in walkers if c.omega == omega]
        if here:
            sole = min(c.sole for c in here)
            smallest[omega] = (sole, tuple(c.variant for c in here if c.sole == sole))
    fastest = max(walkers, key=lambda c: (c.omega, -c.sole), default=None)
    with_energy = [c for c in walkers if math.isfinite(c.energy_per_m_J)]
    least = min(with_energy, key=lambda c: c.energy_per_m_J, default=None)
    failed = [c for c in wmap.cells if not c.walks]
    failures = {v: dict(Counter(c.outcome for c in failed if c.variant == v)) for v in wmap.variants}
    sprung = {v for v in wmap.variants if get_variant(v).spring_joints}  # the record says which have an ankle spring
    spring = [c for c in wmap.cells if c.variant in sprung and not c.walks]
    details = Counter(f"{c.outcome}: {_detail_kind(c.detail)}" for c in spring).most_common()
    k = [c.spring_stiffness for c in spring if math.isfinite(c.spring_stiffness)]
    beta = [math.degrees(c.spring_rest_angle) for c in spring if math.isfinite(c.spring_rest_angle)]
    spring_range = f"K_e {min(k):.0f}-{max(k):.0f} N.m/rad, beta0 {min(beta):.0f}-{max(beta):.0f} deg" if k else ""
    times = sorted(c.decided_at_s for c in spring if math.isfinite(c.decided_at_s))
    median = (times[(len(times) - 1) // 2] + times[len(times) // 2]) / 2 if times else math.nan
    by_speed = {}
    for omega in wmap.omegas:
        here = [c for c in spring if c.omega == omega and math.isfinite(c.spring_stiffness)]
        if here:
            common = Counter(c.outcome for c in here).most_common(1)[0][0]
            by_speed[omega] = (sum(c.spring_stiffness for c in here) / len(here), common)
    return WalkingAnswer(
        cells=len(wmap.cells),
        steps=wmap.steps,
        walkers={v: sum(c.variant == v for c in walkers) for v in wmap.variants},
        smallest_sole=smallest,
        fastest=fastest,
        least_energy=least,
        failures=failures,
        spring_details=details,
        soles=tuple(wmap.soles),
        omegas=tuple(wmap.omegas),
        spring_range=spring_range,
        spring_median_s=median,
        spring_by_speed=by_speed,
        **_twin_figures(wmap),
        fastest_found=found,
    )


def _twin_figures(wmap: WalkingMap) -> dict:
    """The MuJoCo twin's agreement with ours over the cells it walked."""
    both = [c for c in wmap.cells if c.twin_outcome]
    return {
        "twin_cells": len(both),
        "twin_agree": sum(c.walks == (c.twin_outcome == "walks") for c in both),
        "twin_same": sum(c.outcome == c.twin_outcome for c in both),
        "twin_walkers": tuple(_cell_text(c) for c in both if c.twin_outcome == "walks"),
        "twin_note": wmap.twin_note,
    }


def _cell_text(c: MapCell) -> str:
    return f"{c.variant}, sole {c.sole:g} L each side, {c.omega:g} rad/s"


def _list(parts: list[str]) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


def _counts(counts: dict[str, int]) -> str:
    return _list([f"{n} {o}" for o, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))])


WHY: dict[str, str] = {
    "fell": "the body tips over the stance ankle and nothing brings it back",
    "rolled": "the ankle torque tips the foot onto its heel or toe: the centre of pressure leaves the sole",
    "hopped": "the stiff, preloaded spring kicks the robot off the floor",
    "stepped_back": "the body's pitch puts a foot down behind where it stood",
    "slipped": "the stance foot slides more than the limit as the body pitches on the spring",
    "stalled": "the feet scuff in place: the hip does not advance",
}
"""What each failure outcome of a spring design is, physically."""


def toppling_stiffness_seed() -> float:
    """Gravity's toppling stiffness about the stance ankle of the seed spring design, hip level [N.m/rad]."""
    return float(toppling_stiffness(design_robot(Design(), 2, visuals=False)))


def _spring_sentence(a: WalkingAnswer) -> str:
    """Whether a spring design walks and, if none does, how they fail and why."""
    if "spring" not in a.walkers:
        return ""
    n_spring = a.walkers["spring"]
    if n_spring:
        return f"{n_spring} spring designs walk."
    fails = a.failures.get("spring", {})
    total = sum(fails.values())
    k_g = toppling_stiffness_seed()
    ranked = sorted(fails.items(), key=lambda kv: (-kv[1], kv[0]))
    why = "; ".join(f"{o}: {WHY[o]}" for o, _n in ranked if o in WHY)
    return (
        f"No spring design walks (each with its fitted spring, {a.spring_range}): of its {total} cells, "
        f"{_counts(fails)}, decided after {a.spring_median_s:.2f} s (median). Gravity's toppling stiffness about "
        f"the stance ankle is {k_g:.0f} N.m/rad: the spring fitted with the hip held level is "
        f"{_ends(a, k_g)} ({why}). A passive ankle spring holds the hip only at the posture it was fitted to, "
        "while the linkage turns the ankle through the stance."
    )


def _ends(a: WalkingAnswer, k_g: float) -> str:
    """The fitted spring over k_g at the slowest and fastest speeds, with the spring cells' commonest outcome there."""
    parts = []
    for omega in (min(a.omegas), max(a.omegas)):
        k_e, outcome = a.spring_by_speed[omega]
        parts.append(f"{k_e / k_g:.2f} times it at {omega:g} rad/s (mostly {outcome})")
    return " and ".join(parts)


def walking_paragraph(a: WalkingAnswer) -> str:
    """The answer: a lead sentence of at most 40 words, then a table (docs/walking.md, the README, the report)."""
    total = sum(a.walkers.values())
    none = [v for v, n in a.walkers.items() if not n]
    rows = [
        ("designs mapped", f"{a.cells}: a symmetric sole of {min(a.soles):g}-{max(a.soles):g} L each side of the "
         f"ankle x cranks at {min(a.omegas):g}-{max(a.omegas):g} rad/s x the {_list(list(a.walkers))} variants, "
         f"{a.steps} steps each on the floor, judged by the walking verdict"),
        ("walkers by variant", _list([f"{v} {n}" for v, n in a.walkers.items()])),
    ]  # fmt: skip
    if not total:
        lead = f"No design of the walking map's {a.cells} walks {a.steps} steps on the floor."
        return _lead_and_table(lead, [*rows, ("the spring variant", _spring_sentence(a))])
    f, e = a.fastest, a.least_energy
    assert f is not None
    lead = (
        f"{total} of the walking map's {a.cells} designs walk {a.steps} steps on the floor, at up to "
        f"{f.omega:g} rad/s; no {' or '.join(none) or 'other'} design walks."
    )
    if a.fastest_found is not None:
        lead += f" The fastest walker found walks at {a.fastest_found.design.omega:.2f} rad/s."
    by_speed = "; ".join(f"{s:g} L at {w:g} rad/s ({'/'.join(vs)})" for w, (s, vs) in a.smallest_sole.items())
    slow = [f"{w:g}" for w in a.omegas if w not in a.smallest_sole]
    rows.append(("smallest sole that walks", by_speed + (f"; none at {_list(slow)} rad/s" if slow else "")))
    speed = 8.0 * f.advance_per_step * f.omega / math.pi  # L/s: 8 L a step, a step every pi/omega
    if a.fastest_found is not None:  # the map's top speed is the smallest-sole row's last speed
        rows.append(("fastest walker", _fastest_found_text(a.fastest_found)))
    else:
        rows.append(("fastest walker", f"{_cell_text(f)}: {speed:.1f} L/s of hip advance, max hip pitch "
                     f"{f.max_hip_pitch_deg:.1f} deg"))  # fmt: skip
    if e is not None:
        rows.append(("least energy per metre", f"{e.energy_per_m_J:.1f} J/m (cost of transport "
                     f"{e.cost_of_transport:.2f}): {_cell_text(e)}"))  # fmt: skip
    if "spring" in a.walkers:
        rows.append(("the spring variant", _spring_sentence(a)))
    if a.twin_cells or a.twin_note:
        rows.append(("the MuJoCo twin", _twin_sentence(a)))
    return _lead_and_table(lead, rows)


def _fastest_found_text(entry: Entry) -> str:
    """The fastest walker found, in words: its file, soles, speed, hip advance and pitch (the sweep's 20 steps)."""
    d, r = entry.design, entry.sweep
    assert r is not None
    steps = int(float(r["floor_steps"]))
    speed = float(r["floor_advance_m"]) / steps * d.omega / math.pi / d.L  # L/s: a step every pi/omega
    share = float(r["floor_advance_m"]) / (steps * LINKAGE_ADVANCE_PER_STEP * d.L)
    pitch = float(r["floor_max_hip_pitch_deg"])
    return (
        f"`designs/{entry.name}.toml` (the walking sweep's): {d.variant}, soles {d.parallel_toe:.1f} L ahead of "
        f"and {d.parallel_heel:.1f} L behind the ankle, {d.omega:.2f} rad/s: walks {steps} steps, "
        f"{100 * share:.1f} % of the linkage's 8 L a step, {speed:.1f} L/s of hip advance, max hip pitch "
        f"{pitch:.1f} deg"
    )


def _lead_and_table(lead: str, rows: list[tuple[str, str]]) -> str:
    """``lead``, a blank line, then a two-column Markdown table of ``rows``."""
    if len(lead.split()) > 40:
        raise ValueError(f"the walking answer's lead has {len(lead.split())} words, more than 40: {lead}")
    table = ["| question | answer |", "|---|---|", *(f"| {q} | {text.replace('|', '/')} |" for q, text in rows)]
    return "\n".join([lead, "", *table])


def _twin_sentence(a: WalkingAnswer) -> str:
    """How the MuJoCo twin's verdicts compare with ours (or why there are none)."""
    if not a.twin_cells:
        return f"its column is empty ({a.twin_note})" if a.twin_note else ""
    where = f" ({a.twin_note})" if a.twin_note else ""
    return (
        f"the same verdict on the exported model, run on {a.twin_cells} of the cells{where}: it agrees with ours "
        f"on whether the design walks in {a.twin_agree} and on the outcome in {a.twin_same}; "
        f"{len(a.twin_walkers)} of them walk there"
    )


def _grid_table(wmap: WalkingMap, variant: str) -> list[str]:
    """One variant's outcomes as a Markdown table: rows crank speed, columns sole."""
    head = "| omega [rad/s] \\ sole [L] | " + " | ".join(f"{s:g}" for s in wmap.soles) + " |"
    lines = [head, "|" + "---|" * (len(wmap.soles) + 1)]
    for w in wmap.omegas:
        cells = []
        for s in wmap.soles:
            c = wmap.cell(variant, s, w)
            ours = "**walks**" if c.walks else f"{c.outcome} ({c.steps}, {c.decided_at_s:.1f} s)"
            cells.append(f"{ours}; MuJoCo: {c.twin_outcome}" if c.twin_outcome else ours)
        lines.append(f"| {w:g} | " + " | ".join(cells) + " |")
    return lines


def walking_markdown(wmap: WalkingMap) -> str:
    """The map's tables (one per variant: the outcome, steps taken and when it was decided) and the walkers."""
    lines: list[str] = []
    for variant in wmap.variants:
        lines += [f"#### {variant}", "", *_grid_table(wmap, variant), ""]
    lines += [
        "| walker | advance per step [% of 8 L] | max hip pitch [deg] | max slide [mm] | "
        "cost of transport [-] | motor energy [J/m] |",
        "|---|---|---|---|---|---|",
    ]
    for c in sorted(wmap.walkers(), key=lambda c: (c.variant, c.sole, c.omega)):
        lines.append(
            f"| {_cell_text(c)} | {100 * c.advance_per_step:.1f} | {c.max_hip_pitch_deg:.2f} | "
            f"{c.max_slip_mm:.2f} | {c.cost_of_transport:.2f} | {c.energy_per_m_J:.1f} |"
        )
    return "\n".join(lines)


PARAGRAPH = ("<!-- walking answer: generated by pasibot_pin.report.answers.walking.walking_paragraph() -->",
             "<!-- end walking answer -->")  # fmt: skip
"""The markers around the quoted paragraph in docs/walking.md and README.md."""
TABLES = ("<!-- walking tables: generated by pasibot_pin.report.answers.walking.walking_markdown() -->",
          "<!-- end walking tables -->")  # fmt: skip
"""The markers around the map's tables in docs/walking.md."""


def replace_between(text: str, markers: tuple[str, str], body: str) -> str:
    """``text`` with what lies between the two markers replaced by ``body`` (ValueError if a marker is missing)."""
    start, end = markers
    if start not in text or end not in text:
        raise ValueError(f"no {start!r} ... {end!r} block")
    head, rest = text.split(start, 1)
    _old, tail = rest.split(end, 1)
    return f"{head}{start}\n{body}\n{end}{tail}"


def docs_texts(wmap: WalkingMap, doc: str, readme: str, rows: list[dict] | None = None) -> tuple[str, str]:
    """``docs/walking.md`` and ``README.md`` (their texts ``doc`` and ``readme``) with their generated blocks renewed.

    The blocks: the walking answer's paragraph (both), the map's tables, and with the sweep's ``rows``
    (default: the committed sweep, when it is there) its paragraph and the cost paragraph (``doc``).
    ``tools/walking_answer.py`` reads and writes the files.
    """
    rows = committed_sweep_rows() if rows is None else rows
    paragraph = walking_paragraph(walking_answer(wmap, rows))
    text = replace_between(doc, PARAGRAPH, paragraph)
    text = replace_between(text, TABLES, walking_markdown(wmap))
    if rows:
        text = replace_between(text, SWEEP, sweep_paragraph(rows))
        text = replace_between(text, COST, cost_paragraph(wmap, rows))
    return text, replace_between(readme, PARAGRAPH, paragraph)


SWEEP = ("<!-- walking sweep: generated by pasibot_pin.report.answers.walking.sweep_paragraph() -->",
         "<!-- end walking sweep -->")  # fmt: skip
"""The markers around the sweep's paragraph in docs/walking.md."""


def sweep_paragraph(rows: list[dict]) -> str:
    """The walking sweep in one paragraph: its walkers, the fastest, with asymmetric soles."""
    walkers = [r for r in rows if r["floor_outcome"] == "walks"]
    variants = Counter(r["variant"] for r in rows)
    design, fast = fastest_sweep_design(rows)
    speeds = sorted(float(r["omega"]) for r in walkers)
    infeasible = Counter(r["failure"] for r in rows if r["failure"] and not r["floor_outcome"])
    rejected = [r for r in rows if r["failure"] and r["floor_outcome"]]  # walked all the same
    return sentence_lines(
        f"A Latin-hypercube sweep of {len(rows)} designs ({_list([f'{n} {v}' for v, n in sorted(variants.items())])}; "
        f"omega, foot_toe, foot_heel, parallel_toe and parallel_heel varied; 20 steps each, "
        "`docs/results/walking_sweep.csv`) found "
        f"{len(walkers)} walkers, all {_list(sorted({r['variant'] for r in walkers}))}, at "
        f"{speeds[0]:.2f}-{speeds[-1]:.2f} rad/s. The fastest walks at {float(fast['omega']):.2f} rad/s on "
        f"soles of {design.parallel_toe:.1f} L ahead and {design.parallel_heel:.1f} L behind the ankle "
        f"(max |hip pitch| {float(fast['floor_max_hip_pitch_deg']):.1f} deg, "
        f"{float(fast['floor_energy_per_m_J']):.0f} J/m; `designs/{sweep_entry(rows).name}.toml`; the "
        "map's soles are symmetric). "
        + (
            f"{_counts(dict(infeasible))} designs were not walked: their linkage does not work (`design_metrics`). "
            if infeasible
            else ""
        )
        + (
            f"{len(rejected)} designs that the inverse dynamics with the hip held level rejects "
            f"({_list(sorted({r['failure'] for r in rejected}))}) were walked all the same: "
            f"{_counts(dict(Counter(r['floor_outcome'] for r in rejected)))}."
            if rejected
            else ""
        )
    ).strip()


COST = ("<!-- walking cost: generated by pasibot_pin.report.answers.walking.cost_paragraph() -->",
        "<!-- end walking cost -->")  # fmt: skip
"""The markers around the paragraph on where a map's and a sweep's time goes, in docs/walking.md."""


def cost_paragraph(wmap: WalkingMap, rows: list[dict]) -> str:
    """Where the time of the map (its CPU seconds of walks) and of the sweep (its simulated seconds) goes."""
    total = sum(c.cpu_s for c in wmap.cells)
    full = [c for c in wmap.cells if c.steps >= wmap.steps]
    others = sorted(c.decided_at_s for c in wmap.cells if c.steps < wmap.steps and math.isfinite(c.decided_at_s))
    kinds = Counter(c.outcome for c in full)
    walked = [r for r in rows if r["floor_outcome"] == "walks"]
    simulated = sum(float(r["floor_time_s"]) for r in rows if r["floor_outcome"])
    return sentence_lines(
        f"A map's cost is in the runs that take their {wmap.steps} steps: in this one, the {len(full)} cells that "
        f"took them all ({_counts(dict(kinds))}) are {100 * sum(c.cpu_s for c in full) / total:.0f} % of the "
        f"CPU time of its walks ({wmap.steps} steps at 0.5 rad/s are "
        f"{wmap.steps * math.pi / 0.5:.0f} s simulated, at 3 rad/s {wmap.steps * math.pi / 3.0:.0f} s), while "
        f"the other {len(others)} are decided after {statistics.median(others):.2f} s simulated (median). "
        f"A walking sweep costs the same way: in the sweep above, its {len(walked)} walkers took "
        f"{sum(float(r['floor_time_s']) for r in walked):.0f} of its {simulated:.0f} simulated seconds "
        f"(a walker's simulated time grows as 1/omega: {wmap.steps} steps at 0.2 rad/s are "
        f"{wmap.steps * math.pi / 0.2:.0f} s). Fewer `--floor` steps, or a lower bound on omega, is what shortens "
        "such a sweep. `benchmarks/bench_floor_vs_mujoco.py` gives each engine's simulated seconds per CPU second "
        "on a walker."
    )
