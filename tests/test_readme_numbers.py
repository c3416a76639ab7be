"""The README's figures are what the code computes: a number that drifts fails here.

Each figure is read from the README text by a pattern and computed again through the library,
then compared at the precision the README prints it.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from pasibot_pin.dynamics.inverse import run_scenario
from pasibot_pin.model.scenarios import PRESETS, SCENARIOS
from pasibot_pin.studies.contact import scenario_contact
from pasibot_pin.studies.spring_fit import fit_result

README = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")


def _fit(name: str, preset: str):
    choices = PRESETS[preset]
    return fit_result(run_scenario(SCENARIOS[name], choices), choices.fit_thetas, warn=False)


def _number(text: str) -> float:
    return float(text.replace("−", "-"))


@pytest.mark.parametrize("run", ["run1", "run2", "run3", "run4"])
def test_stiffness_table_row(run):
    row = re.search(rf"^\| run {run[-1]} \|(.*)$", README, re.M)
    assert row, f"no README table row for {run}"
    cells = [c.strip() for c in row.group(1).split("|")]
    default, seed, stored, clean = cells[2], cells[3], cells[4], cells[5]
    scenario = SCENARIOS[run]
    fit_default, fit_seed = _fit(run, "default"), _fit(run, "seed")
    assert _number(default.split()[0]) == round(fit_default.K_e, 2)
    assert _number(seed.split()[0]) == round(fit_seed.K_e, 2)
    assert _number(stored) == scenario.seed_K_e
    assert _number(clean) == scenario.seed_K_e_clean
    assert round(_fit(run, "seed-clean").K_e, 2) == pytest.approx(scenario.seed_K_e_clean, abs=0.011)
    for cell, fit in ((default, fit_default), (seed, fit_seed)):
        r2 = re.search(r"R² ([0-9.]+)", cell)
        if r2:
            assert float(r2.group(1)) == round(fit.r2, 2)


def test_contact_findings():
    sentence = re.search(
        r"from ([0-9.]+)° to ([0-9.]+)° of the stance crank,\s+(\d+) of (\d+) samples\): the motion demands a CoP "
        r"from (\S+) mm to (\S+) mm \(run4: (\S+) to (\S+) mm\)",
        README,
    )
    assert sentence, "the README's contact sentence changed shape"
    enter, leave, ok, total, lo, hi, lo4, hi4 = sentence.groups()
    _, run1 = scenario_contact("run1")
    _, run4 = scenario_contact("run4")
    events = {e["edge"]: math.degrees(e["theta"]) for e in run1.tip_events()}
    assert (float(enter), float(leave)) == (round(events["heel"], 1), round(events["toe"], 1))
    assert (int(ok), int(total)) == (int(np.sum(run1.feasible)), len(run1))
    for text, value in zip((lo, hi, lo4, hi4), (*run1.sole_needed(), *run4.sole_needed())):
        assert _number(text) == round(1e3 * value)
    parallel = re.search(r"\(run1: (\d+) of (\d+)\s+samples, from ([0-9.]+)° to ([0-9.]+)°\)", README)
    assert parallel, "the README's parallel-variant sentence changed shape"
    _, par = scenario_contact("run1", variant="parallel")
    events = {e["edge"]: math.degrees(e["theta"]) for e in par.tip_events()}
    assert (int(parallel.group(1)), int(parallel.group(2))) == (int(np.sum(par.feasible)), len(par))
    assert (float(parallel.group(3)), float(parallel.group(4))) == (round(events["heel"], 1), round(events["toe"], 1))
