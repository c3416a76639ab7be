"""Markdown pieces of ``report.md``: figures with captions, and the summary of verdicts that opens it.

- :func:`figure`: an embedded figure and its caption line; :func:`figure_links`: a captioned list of
  links (for the many per-scenario figures).
- :class:`Section`: a section's Markdown and the few numbers (its *facts*) the summary quotes.
- :func:`summary`: what the seed claims, what the model finds, where they differ, one row per
  claim, built from the sections' facts (every number comes from the run that wrote the report).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field


def figure(path: str, caption: str) -> str:
    """An embedded figure followed by its caption (an italic line), as Markdown.

    The image's alternative text is the caption without square brackets (units), which Markdown would
    read as a nested link.
    """
    alt = caption.replace("[", "").replace("]", "")
    return f"![{alt}]({path})\n\n*{caption}*\n"


def figure_links(items: Iterable[tuple[str, str]], intro: str) -> str:
    """A bullet list of figure links, each with its caption: ``- [name](path): caption``."""
    lines = [intro, ""]
    lines += [f"- [{path.rsplit('/', 1)[-1]}]({path}): {caption}" for path, caption in items]
    return "\n".join(lines) + "\n"


@dataclass
class Section:
    """One section of ``report.md``.

    Attributes:
        markdown: the section's text.
        facts: the numbers the summary quotes (name -> value, SI units unless the name says).

    """

    markdown: str
    facts: dict = field(default_factory=dict)


def _deg(rad: float) -> str:
    return f"{math.degrees(rad):.1f}°" if math.isfinite(rad) else "fell"


def _runs_pitch(run1: float, run23) -> str:
    """'the largest hip pitch is 41.3° in run 1; runs 2 and 3 fell' (a fall has no largest pitch)."""
    held = [(f"run {k}", v) for k, v in zip((1, 2, 3), (run1, *run23)) if math.isfinite(v)]
    fell = [f"{k}" for k, v in zip((1, 2, 3), (run1, *run23)) if not math.isfinite(v)]
    parts = [f"the largest hip pitch is {' and '.join(f'{_deg(v)} in {name}' for name, v in held)}"] if held else []
    if fell:
        parts.append(("run " if len(fell) == 1 else "runs ") + " and ".join(fell) + " fell")
    return "; ".join(parts)


def _kinematics_rows(kin: Mapping) -> list[tuple[str, str, str, str]]:
    """The summary's rows of the kinematics section (the straight line, the level foot)."""
    if not kin:  # the section did not run
        return []
    rows: list[tuple[str, str, str, str]] = []
    rows += [
        (
            "Hoeken + pantograph: a straight stance line",
            "the ankle moves on a nearly straight line in stance (§4)",
            f"stroke {kin['stroke_L']:.3f} L, off the line by at most {kin['band_L']:.4f} L",
            "agree",
        ),
        (
            "the parallel extension keeps the foot level",
            "the standing foot stays parallel to the ground (§4.3)",
            f"within {kin['parallel_pitch_deg']:.3f}° in stance; the rigid foot tilts up to "
            f"{kin['rigid_pitch_deg']:.1f}°",
            "agree",
        ),
    ]
    return rows


def _torque_rows(tor: Mapping) -> list[tuple[str, str, str, str]]:
    """The summary's rows of the torques section (the seed's K_e, run 4's fit)."""
    if not tor:  # the section did not run
        return []
    rows: list[tuple[str, str, str, str]] = []
    seed = ", ".join(f"{v:.0f}" for v in tor["seed_stored"])
    preset = ", ".join(f"{v:.2f}" for v in tor["seed_preset"])
    model = ", ".join(f"{v:.1f}" for v in tor["default"])
    slow = [d for n, d in tor["window_delta"].items() if n != "run4"]
    fast = tor["window_delta"]["run4"]
    window = f"{min(slow):+.0f} to {max(slow):+.0f} N.m/rad in runs 1–3, {fast:+.0f} in run 4"
    rows.append(
        (
            "the ankle spring K_e of runs 1–4 [N.m/rad]",
            f"{seed} (§7)",
            f"{preset} with the seed's modelling choices (reproduced); {model} with exact masses and the whole "
            "stance as fit window",
            f"differ: the seed's fit window adds {window}; its rounded masses add a little",
        )
    )
    rows.append(
        (
            "run 4 (5 rad/s): one K_e",
            "T_e is non-linear, K_e may be incorrect (§7.4)",
            f"R² = {tor['run4_r2']:.2f}: a linear spring does not fit",
            "agree",
        )
    )
    return rows


def _simulation_rows(sim: Mapping) -> list[tuple[str, str, str, str]]:
    """The summary's row of the simulation section (does the spring keep the robot upright?)."""
    if not sim:  # the section did not run
        return []
    rows: list[tuple[str, str, str, str]] = []
    rows.append(
        (
            "the fitted spring keeps the walking robot upright",
            "the spring avoids instability of the biped (§8)",
            f"K_e exceeds gravity's toppling stiffness k_g by only {sim['margin_run1']:.1f} N.m/rad (run 1); "
            f"with the hip free, {_runs_pitch(sim['run1_fitted'], sim['run23_fitted'])}; without a spring "
            f"the robot falls within {sim['fall_min']:.1f}–{sim['fall_max']:.1f} s",
            "differ: neutral stability at best (welded stance foot)",
        )
    )
    return rows


def _contact_rows(con: Mapping) -> list[tuple[str, str, str, str]]:
    """The summary's rows of the contact and energy section (the flat foot, one motor)."""
    if not con:  # the section did not run
        return []
    rows: list[tuple[str, str, str, str]] = []
    rows.append(
        (
            "the stance foot stays flat on the ground",
            "assumed (the foot is welded to the ground in the dynamics)",
            f"the centre of pressure is inside the sole ({1e3 * con['sole'][0]:+.0f} to "
            f"{1e3 * con['sole'][1]:+.0f} mm from the ankle) for {con['run1_ok']} of {con['run1_n']} samples "
            f"of run 1's stance; the motion asks for {1e3 * con['run1_cop'][0]:+.0f} to "
            f"{1e3 * con['run1_cop'][1]:+.0f} mm",
            "differ: the sole would roll over its heel or toe",
        )
    )
    rows.append(
        (
            "one motor for both legs",
            "future work (§8)",
            f"one motor can drive both cranks ({con['motor_scenario']}, {con['motor_omega']:g} rad/s); its peak "
            "torque and power, and the flywheel a constant torque would need, are in the answers above",
            "new",
        )
    )
    return rows


def _floor_rows(floor: Mapping) -> list[tuple[str, str, str, str]]:
    """The summary's row of the floor section (the fitted spring on a real floor)."""
    if not floor:  # the section did not run
        return []
    rows: list[tuple[str, str, str, str]] = []
    rows.append(
        (
            "the fitted spring on a real floor (run 1)",
            "not studied (the stance foot is welded)",
            f"from a state it can hold ({floor['floor_start']}), the largest hip pitch over "
            f"{floor['duration']:g} s is {_deg(floor['floor_max_pitch'])} against {_deg(floor['weld_max_pitch'])} "
            f"welded; {floor['floor_outcome']}",
            "new: the weld "
            + ("overstates" if floor["floor_max_pitch"] < floor["weld_max_pitch"] else "understates")
            + " the hip's swing (runs 2-4: docs/floor.md)",
        )
    )
    return rows


def _design_rows(design: Mapping) -> list[tuple[str, str, str, str]]:
    """The summary's row of the design exploration (a better design)."""
    if not design:  # the section did not run
        return []
    rows: list[tuple[str, str, str, str]] = []
    rows.append(
        (
            "a better design: less crank torque at the same stride",
            "future work: other geometries (§8)",
            f"peak {design['seed_peak']:.2f} -> {design['free_peak']:.2f} N.m, but a "
            f"{design['straightness_ratio']:.0f} times less straight path; {design['straight_peak']:.2f} N.m "
            f"keeping it straight; on the floor {_walk_count(design.get('floor_walkers', 0), design['floor_trials'])} "
            f"(best {design['floor_best_time']:.2f} s, {design['floor_most_steps']} steps)",
            "new",
        )
    )
    return rows


def _walk_count(k: int, n: int) -> str:
    """How many of ``n`` spring designs walk, in words: "none of the 120 spring designs walk", "1 of ... walks"."""
    return f"{k or 'none'} of the {n} spring designs walk{'s' if k == 1 else ''}"


def summary(facts: Mapping[str, Mapping]) -> str:
    """The report's opening section: the seed's claims against the model's findings.

    Args:
        facts: section name -> that section's :attr:`Section.facts` (a missing section leaves its rows out).

    Returns:
        The ``## Summary`` section.

    """
    rows = [
        *_kinematics_rows(facts.get("kinematics", {})),
        *_torque_rows(facts.get("dynamics", {})),
        *_simulation_rows(facts.get("simulation", {})),
        *_contact_rows(facts.get("contact_energy", {})),
        *_floor_rows(facts.get("floor", {})),
        *_design_rows(facts.get("design_exploration", {})),
    ]
    lines = [
        "## Summary",
        "",
        '"The seed" is the source report this project models (D\'Alessandro & Venezia, *Two-legged walking '
        "robot*, Polytechnic of Bari). Each row: what it claims, what this model finds (numbers from this run), "
        "and the verdict. The sections below give the detail and every figure.",
        "",
        "| question | the seed claims | the model finds | verdict |",
        "|---|---|---|---|",
    ]
    lines += [f"| {q} | {s} | {m} | {v} |" for q, s, m, v in rows]
    return "\n".join(lines) + "\n"


def sentence_lines(text: str) -> str:
    """``text`` with one sentence per line (Markdown renders it as the same paragraph; no line runs long)."""
    return re.sub(r"\. (?=[A-Z0-9`(])", ".\n", text)


def answers_box(lines: list[str]) -> str:
    """The ``## Answers`` section: the lines in a quoted box, then where the numbers come from.

    Marker lines (HTML comments, such as the walking answer's slot) are left out of the box.
    """
    shown = [line for line in lines if not line.lstrip().startswith("<!--")]
    body = "\n".join(f"> {line}" if line else ">" for line in shown)
    return (
        "## Answers\n\n"
        + body
        + "\n\nThe walks are judged by `pasibot_pin.dynamics.verdict` on the floor (heel and toe contacts, or each "
        "sole's corners in 3-D); the motor's numbers come from the recommended walker's own walk "
        "(`pasibot_pin.studies.motor_load`), the welded-hip spring's from `pasibot_pin.studies.spring_choice`.\n"
    )


def report_text(sections: Iterable[str], facts: Mapping[str, Mapping], lead: Iterable[str] = ()) -> str:
    """``report.md``: the title, the answers box, ``lead``, the :func:`summary` of verdicts, then ``sections``.

    The answers box (:func:`answers_box`) holds ``facts["answers"]["lines"]`` (from
    :mod:`pasibot_pin.report.answers`); without them the report opens with the lead sections (the walking one:
    :mod:`pasibot_pin.report.walking_section`), then the summary.
    """
    lines = facts.get("answers", {}).get("lines")
    head = [answers_box(lines)] if lines else []
    first = [f"{text}\n" for text in lead if text]
    body = [f"{text}\n" for text in sections if text]
    return "\n".join(["# PASIBOT analysis", "", *head, *first, summary(facts), *body])
