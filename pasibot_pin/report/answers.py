"""The answers box that opens ``report.md`` (and that the README's results section quotes).

Three questions, each answered in one bullet whose numbers come from code and are stated once:

- does it walk? :func:`walking_answer_lines` (a slot: another study may fill it; keep the signature);
- the motor: :func:`motor_answer_line`, the single-motor study's peak torque and power at its speed
  (:func:`~pasibot_pin.studies.contact_energy_study.single_motor_study`);
- the spring: :func:`spring_answer_line`, the recommended spring and its margin
  (:func:`~pasibot_pin.studies.spring_choice.recommended_spring`).

:func:`answer_lines` gives the box's lines; :func:`build` is the ``pasibot analyze`` step (its facts
carry the lines; :func:`~pasibot_pin.report.markdown.report_text` puts them first, in
:func:`~pasibot_pin.report.markdown.answers_box`).
"""

from __future__ import annotations

import math
from pathlib import Path

from pasibot_pin.model.design import Design
from pasibot_pin.model.scenarios import get_scenario
from pasibot_pin.report.markdown import Section
from pasibot_pin.report.walking_answer import walking_answer
from pasibot_pin.studies.contact_energy_study import single_motor_study
from pasibot_pin.studies.spring_choice import recommended_spring
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import load_map

WALKING_SLOT = "<!-- walking answer: the lines of pasibot_pin.report.answers.walking_answer_lines() -->"
"""The marker of the walking answer's slot in the box."""


def _walk_line(name: str, design, settings) -> str:
    walk = walk_design(design, settings)
    sole = f"toe {design.parallel_toe:g} L, heel {design.parallel_heel:g} L"
    return f"{name} ({design.variant}, {sole}) at {design.omega:g} rad/s: {walk.verdict.summary()}."


def walking_answer_lines() -> list[str]:
    """Does it walk? The walking map's headline (the committed table), then two designs walked now.

    The map: every variant, the same sole ahead of and behind the ankle, over crank speeds, each
    design asked to walk its 20 steps (:mod:`pasibot_pin.studies.walking_map`, ``make walking-map``).
    Then a parallel design whose sole reaches 4.5 L ahead of and behind joint 13, and the seed's
    parallel design, both at 2 rad/s, judged over 4 steps (:class:`WalkSettings`).
    """
    a = walking_answer(load_map())
    walking = [f"{v} ({n})" for v, n in a.walkers.items() if n]
    smallest = ", ".join(f"{sole:g} L at {omega:g} rad/s" for omega, (sole, _) in sorted(a.smallest_sole.items()))
    head = (
        f"- Across the walking map ({a.cells} designs, {a.steps} steps each): walkers by variant "
        f"{', '.join(walking) or 'none'}; no {' or '.join(v for v, n in a.walkers.items() if not n)} design walks. "
        f"Smallest walking sole: {smallest}."
    )
    if a.fastest is not None:
        head += f" Fastest: {a.fastest.variant}, {a.fastest.sole:g} L soles, {a.fastest.omega:g} rad/s."
    settings = WalkSettings(steps=4)
    wide = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=2.0)
    seed = Design(variant="parallel", omega=2.0)
    return [
        head,
        "- " + _walk_line("A long sole", wide, settings),
        "- " + _walk_line("The seed's sole", seed, settings),
    ]


def motor_answer_line(motor) -> str:
    """The motor's bullet from a :class:`~pasibot_pin.studies.contact_energy_study.SingleMotorStudy`."""
    scenario = get_scenario(motor.scenario)
    return (
        f"- **The motor**: one motor driving both cranks ({motor.scenario}: body {scenario.body_mass:g} kg, "
        f"crank speed {motor.omega:g} rad/s, spring biped, stance foot welded) peaks at "
        f"{motor.single.peak():.1f} N.m and {motor.peak_power:.0f} W; its mean, {motor.mean_torque:.2f} N.m "
        f"({motor.mean_power:.0f} W), is all it must give with a flywheel of "
        f"{motor.inertia_for_target:.0f} kg.m² on the crank shaft ({100 * motor.fluctuation:g} % speed fluctuation)."
    )


def spring_answer_line(choice) -> str:
    """The spring's bullet from a :class:`~pasibot_pin.studies.spring_choice.SpringChoice`."""
    return (
        f"- **The spring**: K_e = {choice.stiffness:.0f} N.m/rad at beta0 = {math.degrees(choice.rest_angle):.1f}°, "
        f"the smallest that keeps the welded hip within {math.degrees(choice.limit):.0f}° of level at every "
        f"crank angle of {choice.scenario}'s stance with the cranks held (quasi-static); its margin over "
        f"gravity's toppling stiffness k_g = {choice.toppling:.0f} N.m/rad is {choice.margin:.0f} N.m/rad, "
        f"against {choice.fitted_margin:.1f} for the fitted {choice.fitted_stiffness:.0f} N.m/rad. Walking, "
        "the hip swings further (the report's simulation section)."
    )


def answer_lines(walking: list[str], motor, spring) -> list[str]:
    """The box's lines: the walking answer's slot, then the motor and the spring (Markdown bullets)."""
    return ["- **Does it walk?**", WALKING_SLOT, *(f"  {line}" for line in walking), motor, spring]


def answers() -> list[str]:
    """The box's lines, every study run afresh (:func:`answer_lines`)."""
    return answer_lines(
        walking_answer_lines(), motor_answer_line(single_motor_study()), spring_answer_line(recommended_spring())
    )


def build(out_dir: Path):
    """``pasibot analyze``'s answers step: no files, no text of its own; its facts carry the box's lines."""
    return Section("", {"lines": answers()})
