"""Every answer the package gives a builder, in one place.

The box that opens ``report.md`` (here); the walking map's answer in words
(:mod:`pasibot_pin.report.answers.walking`, quoted by ``docs/walking.md`` and the README); the design
questions' answers (:mod:`pasibot_pin.report.answers.questions`: the optimisation plans, and the committed
answer files in ``docs/results/`` read back). The studies compute (:mod:`pasibot_pin.studies.walking_map`,
:mod:`pasibot_pin.studies.spring_choice`, :mod:`pasibot_pin.studies.motor_load`); these modules say the
answers and return texts; ``tools/answers.py``, ``tools/walking_answer.py`` and ``tools/designs_catalog.py``
write the files.

The answers box that opens ``report.md`` (and that the README's results section quotes).

A builder's questions, each answered in one bullet whose numbers come from code and are stated once:

- does it walk? :func:`walking_answer_lines`: the walking map's headline, the 3-D map's (does it stay
  upright sideways, and on which feet), and the seed's own sole walked now (a slot: another study may
  fill it; keep the signature);
- what to build: :func:`build_answer_line`, the recommended walker
  (:func:`~pasibot_pin.studies.walking_map3d.recommended_walker`) walked now;
- its motor: :func:`motor_answer_line`, from that walk (:func:`~pasibot_pin.studies.motor_load.motor_load`:
  the drive between the foot exchanges, the exchanges as impulses) and through a stated gearbox;
- the spring: :func:`spring_answer_line`: the walker needs none; what the spring variant does on
  the floor; the welded-hip spring of the seed's set-up, once, as what it is
  (:func:`~pasibot_pin.studies.spring_choice.recommended_spring`).

:func:`answer_lines` gives the box's lines; :func:`build` is the ``pasibot analyze`` step (its facts
carry the lines; :func:`~pasibot_pin.report.markdown.report_text` puts them first, in
:func:`~pasibot_pin.report.markdown.answers_box`).
"""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path

from pasibot_pin.model.design import Design
from pasibot_pin.report.answers.walking import walking_answer
from pasibot_pin.report.markdown import Section
from pasibot_pin.studies.motor_load import PEAK_PERCENTILE, MotorLoad, motor_load
from pasibot_pin.studies.spring_choice import recommended_spring
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import load_map
from pasibot_pin.studies.walking_map3d import MAP3D_CSV, RECOMMENDED, load_map3d, recommended_walker

GEAR_RATIO: float = 50.0
"""The gearbox the motor's operating point is stated for [-]."""

GEAR_EFFICIENCY: float = 0.9
"""Its efficiency [-]."""

BUILD_STEPS: int = 6
"""Steps the recommended walker walks for the motor's figures [-]."""

WALKING_SLOT = "<!-- walking answer: the lines of pasibot_pin.report.answers.walking_answer_lines() -->"
"""The marker of the walking answer's slot in the box."""


def walking_answer_lines() -> list[str]:
    """Does it walk? The walking map's headline, the 3-D map's, and the seed's own sole walked now.

    The maps are the committed tables (:mod:`pasibot_pin.studies.walking_map`, ``make walking-map``;
    :mod:`pasibot_pin.studies.walking_map3d`, ``make walking-map-3d``).
    """
    a = walking_answer(load_map())
    smallest = ", ".join(f"{sole:g} L at {omega:g} rad/s" for omega, (sole, _) in sorted(a.smallest_sole.items()))
    head = (
        f"- Across the walking map ({a.cells} designs, {a.steps} steps each, the hip held upright sideways): "
        f"{_walkers(a.walkers)}. Smallest walking sole: {smallest}."
    )
    if a.fastest_found is not None:
        omega = a.fastest_found.design.omega
        head += f" Fastest walker found (the walking sweep): `designs/{a.fastest_found.name}.toml`, {omega:.2f} rad/s."
    seed = Design(variant="parallel", omega=2.0)
    walk = walk_design(seed, WalkSettings(steps=4))
    sole = f"toe {seed.parallel_toe:g} L, heel {seed.parallel_heel:g} L"
    return [head, upright_answer_line(), f"- The seed's sole ({sole}) at 2 rad/s: {walk.verdict.summary()}."]


def _walkers(walkers: dict[str, int]) -> str:
    """How many of the map's designs walk, by variant, in words ("9 of them walk, all parallel; no rigid ...")."""
    some = [(v, n) for v, n in walkers.items() if n]
    total = sum(n for _, n in some)
    if not some:
        return "none of them walks"
    head = f"{total} of them walk" + (
        f", all {some[0][0]}" if len(some) == 1 else f" ({', '.join(f'{n} {v}' for v, n in some)})"
    )
    none = [v for v, n in walkers.items() if not n]
    return head + (f"; no {' or '.join(none)} design walks" if none else "")


def upright_answer_line() -> str:
    """The 3-D map's answer: centred soles tip; interleaved combs past the midline keep it upright (both engines)."""
    m = load_map3d(MAP3D_CSV)
    reach = m.smallest_reach()
    groups: dict[float, list[float]] = {}
    for omega, value in sorted(reach.items()):
        groups.setdefault(value, []).append(omega)
    parts = [
        f"{v:g} L ({100 * v * recommended_walker().L:g} cm) past the midline at {_speeds(ws)}"
        for v, ws in groups.items()
        if math.isfinite(v)
    ]
    narrow = m.family("narrow")
    others = Counter(c.outcome.replace("_", " ") for c in narrow if not c.walks and c.outcome != "tipped")
    spacings = f"{sum(c.outcome == 'tipped' for c in narrow)} of {len(narrow)} spacings tip" + "".join(
        f", {k} {outcome}" for outcome, k in sorted(others.items())
    )
    return (
        f"- **In 3-D** (the hip free to roll; {m.steps} steps each, in our engine and the MuJoCo twin): on soles "
        f"centred on each leg's plane, or legs brought nearer, every walker tips sideways at its first single "
        f"support ({spacings}). Comb soles whose "
        f"prongs pass the midline walk upright: {' and '.join(parts)}."
    )


def _speeds(omegas: list[float]) -> str:
    if len(omegas) == 1:
        return f"{omegas[0]:g} rad/s"
    return f"{', '.join(f'{w:g}' for w in omegas[:-1])} and {omegas[-1]:g} rad/s"


def recommended_walk() -> tuple[Design, object]:
    """The recommended walker and its walk on the floor (:data:`BUILD_STEPS` steps)."""
    design = recommended_walker()
    return design, walk_design(design, WalkSettings(steps=BUILD_STEPS))


def recommended_lines(design: Design, walk) -> tuple[str, str]:
    """The box's lines on the recommended walker from its walk (:data:`BUILD_STEPS` steps): what to build, its motor."""
    load = motor_load(walk.result, walk.omega, walk.settings.crank_ramp)
    return build_answer_line(design, walk), motor_answer_line(load)


def build_answer_line(design: Design, walk) -> str:
    """What to build: the recommended walker, its feet and its crank speed."""
    feet, reach, omega = RECOMMENDED
    name = f"designs/3d/upright_fastest_{feet}{reach:g}L_omega{omega:g}.toml"
    return (
        f"- **What to build**: `{name}`: the parallel extension with {design.parallel_toe:g} L soles ahead of and "
        f"{design.parallel_heel:g} L behind joint 13, interleaved comb soles reaching {reach:g} L "
        f"({100 * reach * design.L:g} cm) past the midline, cranks at {omega:g} rad/s, no ankle spring. The fastest "
        f"walker that stays upright for 20 steps in both engines; on the floor now: {walk.verdict.summary()}."
    )


def motor_answer_line(load: MotorLoad) -> str:
    """Its motor: the drive between the foot exchanges, the exchanges' impulses, and a gearbox's operating point."""
    peak, rms, speed = load.operating_point(GEAR_RATIO, GEAR_EFFICIENCY)
    return (
        f"- **The motor** (each crank of that walker, from its walk, between the foot exchanges; peaks: "
        f"{PEAK_PERCENTILE:g}th percentiles): peak {load.torque_peak_Nm:.1f} N.m, RMS {load.torque_rms_Nm:.1f} N.m, "
        f"peak power {load.power_peak_W:.0f} W at {load.omega:g} rad/s; both cranks' mean positive power "
        f"{load.power_mean_W:.1f} W. A foot exchange passes up to {load.exchange_impulse_Nms:.2f} N.m.s through a "
        f"crank (a {load.speed_dip_rad_s:.1f} rad/s dip with {load.reflected_inertia:g} kg.m^2 reflected on its "
        f"shaft). Behind a {GEAR_RATIO:g}:1 gearbox ({100 * GEAR_EFFICIENCY:g} %): {peak:.2f} N.m peak, "
        f"{rms:.2f} N.m RMS at {_rpm(speed):.0f} rpm."
    )


def _rpm(speed: float) -> float:
    """[rad/s] -> [rev/min]."""
    return speed * 60.0 / (2.0 * math.pi)


def spring_answer_line(choice) -> str:
    """The spring: none for the walker; the spring variant on the floor; the welded-hip spring once."""
    a = walking_answer(load_map())
    fails = a.failures.get("spring", {})
    counts = ", ".join(f"{n} {outcome}" for outcome, n in sorted(fails.items(), key=lambda kv: -kv[1]) if n)
    return (
        f"- **The spring**: none for the walker (its parallel extension carries the foot level); the spring variant "
        f"walks in none of the map's {sum(fails.values())} spring cells ({counts}). With the stance foot welded and "
        f"the hip held level, as the seed simulates it, K_e = {choice.stiffness:.0f} N.m/rad at beta0 = "
        f"{math.degrees(choice.rest_angle):.1f}° keeps that hip within {math.degrees(choice.limit):.0f}° of level "
        f"over {choice.scenario}'s stance (quasi-static)."
    )


def answer_lines(walking: list[str], build: str, motor: str, spring: str) -> list[str]:
    """The box's lines: the walking answer's slot, then what to build, its motor and the spring (Markdown)."""
    return ["- **Does it walk?**", WALKING_SLOT, *(f"  {line}" for line in walking), build, motor, spring]


def answers() -> list[str]:
    """The box's lines, every walk run afresh (:func:`answer_lines`)."""
    build_line, motor_line = recommended_lines(*recommended_walk())  # the lines analyze takes from its walk
    return answer_lines(walking_answer_lines(), build_line, motor_line, spring_answer_line(recommended_spring()))


def build(out_dir: Path):
    """``pasibot analyze``'s answers step: no files, no text of its own; its facts carry the box's own lines.

    Those are the walking answer's (``walking``) and the spring's (``spring``); the recommended walker's two
    lines come from the walking section, which walks it once for them and its animation
    (:func:`pasibot_pin.report.walking_section.build`); :func:`complete` puts the box together.
    """
    return Section("", {"walking": walking_answer_lines(), "spring": spring_answer_line(recommended_spring())})


def complete(facts: dict) -> None:
    """Put the box's lines (:func:`answer_lines`) in ``facts["answers"]["lines"]``, from the two steps' facts.

    ``facts``: step name -> its facts; the answers step's (:func:`build`) and the walking section's
    (``build`` and ``motor``: :func:`recommended_lines`).
    """
    own, walking = facts["answers"], facts["walking"]
    own["lines"] = answer_lines(own["walking"], walking["build"], walking["motor"], own["spring"])
