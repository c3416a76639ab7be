"""The robot of a scenario: the default biped with a scenario's masses under a set of modelling choices.

:mod:`pasibot_pin.model.scenarios` holds the scenarios and presets as data; this builds from them
the mass model (:func:`scenario_masses`) and the robot (:func:`scenario_robot`) the torque,
contact and energy studies run on.

Units: SI [kg, m].
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import pinocchio as pin

from pasibot_pin.model.params import Geometry, MassModel, percentage_mass_model
from pasibot_pin.model.robot import PasibotRobot, apply_masses, load
from pasibot_pin.model.scenarios import (
    SEED_ROUNDED_FOOT_MASS,
    SEED_ROUNDED_LINK_MASSES,
    ModelChoices,
    Scenario,
    seed_foot_com,
)

__all__ = ["scenario_masses", "scenario_robot"]


@lru_cache(maxsize=4)
def _base_robot(variant: str, inertia: str) -> PasibotRobot:
    return load(variant, 2, inertia=inertia)


def scenario_masses(
    scenario: Scenario, choices: ModelChoices, geometry: Geometry | None = None, variant: str = "spring"
) -> MassModel:
    """The mass model of ``scenario`` under ``choices`` for ``variant`` [kg, m]."""
    geometry = geometry or Geometry()
    base = percentage_mass_model(geometry, variant)
    links = dict(base.links)
    hip = scenario.body_mass
    foot = base.foot
    if choices.masses == "rounded":
        links.update(SEED_ROUNDED_LINK_MASSES)
        hip = scenario.seed_body_mass
        foot = SEED_ROUNDED_FOOT_MASS
    if choices.swap_l5_l6:
        links["l5"], links["l6"] = links["l6"], links["l5"]
    toe, heel = geometry.foot_extent(variant)
    foot_com = seed_foot_com(toe, heel) if choices.seed_foot else base.foot_com
    return MassModel(
        hip=hip,
        links=links,
        foot=foot,
        foot_com=foot_com,
        hip_com=(scenario.body_com_dx, 0.0),
        rule=f"scenario {scenario.name}, masses {choices.masses}" + (", L5/L6 swapped" if choices.swap_l5_l6 else ""),
    )


def scenario_robot(scenario: Scenario, choices: ModelChoices, variant: str = "spring") -> PasibotRobot:
    """The default biped of ``variant`` with the masses of ``scenario`` under ``choices`` (a copy)."""
    base = _base_robot(variant, choices.inertia)
    masses = scenario_masses(scenario, choices, base.geometry, variant)
    model = pin.Model(base.model)
    apply_masses(model, masses, base.geometry, variant, 2, choices.inertia)
    return replace(
        base, model=model, data=model.createData(), masses=masses, constraint_models=list(base.constraint_models)
    )
