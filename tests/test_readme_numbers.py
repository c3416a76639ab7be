"""The README's and docs' figures are what the code computes: a number that drifts fails here.

Each figure is read from the README or a docs/*.md page by a pattern (found exactly once across
them, so it cannot be quoted twice and drift in one place) and computed again through the library,
then compared at the precision the text prints it. Timings: only docs/timings.md quotes one, and
it names the machine it was measured on.
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
from pasibot_pin.studies.methods.spring_fit import fit_result

ROOT = Path(__file__).resolve().parents[1]
PAGES = {
    path.relative_to(ROOT).as_posix(): path.read_text(encoding="utf-8")
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
}
README = "\n".join(PAGES.values())  # the README and every docs page, searched together


def _once(pattern: str, flags: int = 0) -> re.Match:
    """The one match of ``pattern`` in the README and docs (a second quote could drift on its own)."""
    found = [(name, m) for name, text in PAGES.items() for m in re.finditer(pattern, text, flags)]
    assert len(found) == 1, f"{pattern!r} found {len(found)} times: {[name for name, _ in found]}"
    return found[0][1]


def _fit(name: str, preset: str):
    choices = PRESETS[preset]
    return fit_result(run_scenario(SCENARIOS[name], choices), choices.fit_thetas, warn=False)


def _number(text: str) -> float:
    return float(text.replace("−", "-"))


@pytest.mark.parametrize("run", ["run1", "run2", "run3", "run4"])
def test_stiffness_table_row(run):
    row = _once(rf"^\| run {run[-1]} \|(.*)$", re.M)
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
    sentence = _once(
        r"from ([0-9.]+)° to ([0-9.]+)° of the stance crank,\s+(\d+) of (\d+) samples\): the motion demands a CoP "
        r"from (\S+) mm to (\S+) mm \(run4: (\S+) to (\S+) mm\)",
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
    parallel = _once(r"\(run1: (\d+) of (\d+)\s+samples, from ([0-9.]+)° to ([0-9.]+)°\)")
    assert parallel, "the README's parallel-variant sentence changed shape"
    _, par = scenario_contact("run1", variant="parallel")
    events = {e["edge"]: math.degrees(e["theta"]) for e in par.tip_events()}
    assert (int(parallel.group(1)), int(parallel.group(2))) == (int(np.sum(par.feasible)), len(par))
    assert (float(parallel.group(3)), float(parallel.group(4))) == (round(events["heel"], 1), round(events["toe"], 1))


def test_readme_stiffness_sentence():
    """The README's short K_e sentence: the default model's fits, rounded as printed."""
    match = _once(r"whole stance as fit window it\s+gives (\d+), (\d+), (\d+) and (\d+) N\.m/rad")
    expected = [round(_fit(run, "default").K_e) for run in ("run1", "run2", "run3", "run4")]
    assert [int(x) for x in match.groups()] == expected


TIMING = re.compile(r"\b\d+(?:\.\d+)?\s?(?:s|seconds|min)\b(?:\s+(?:wall|of CPU|CPU))", re.I)


def test_timings_come_from_one_measured_page():
    """No page but docs/timings.md quotes a wall or CPU time; that page names its machine and its source."""
    for name, text in PAGES.items():
        if name != "docs/timings.md":
            assert not TIMING.search(text), f"{name} quotes a timing: {TIMING.search(text).group(0)!r}"
            assert "takes about" not in text, name
    page = PAGES["docs/timings.md"]
    assert "benchmarks/bench_demo.py" in page
    machine = re.search(r"Measured on a (\d+)-core (\S+) .*Python (\d+\.\d+)", page, re.S)
    assert machine, "docs/timings.md does not name the machine"
    row = re.search(r"\| `make demo`.*?\| (\d+) \| (\d+) \|", page)
    assert row and int(row.group(1)) > 0 and int(row.group(2)) > 0


@pytest.mark.slow
def test_spring_study_bullets():
    """The README's spring-study bullets: k_g, the margin K_e - k_g, run 1's and run 4's hip excursion."""
    from pasibot_pin.studies.simulation_study import SimulateSettings, run_simulation, simulation_setup
    from pasibot_pin.studies.spring_study import scenario_inputs, toppling_stiffness

    readme = (ROOT / "README.md").read_text()
    inputs = scenario_inputs("run1")
    k_g = toppling_stiffness(inputs.robot)
    assert f"toppling stiffness k_g ≈ {round(k_g)} N.m/rad" in readme
    assert f"only ~{round(inputs.fit.stiffness - k_g)} N.m/rad" in readme
    pitch = {}
    for name in ("run1", "run4"):
        run = run_simulation(simulation_setup(SimulateSettings(scenario=name, steps=2, cases=False)))
        pitch[name] = math.degrees(float(np.max(np.abs(run.runs["fitted"].hip_pitch))))
    assert f"Run 1 swings up to {round(pitch['run1'])}° over two steps" in readme
    assert f"holds the hip\n  within about {round(pitch['run4'])}°" in readme


@pytest.mark.slow
@pytest.mark.integration
def test_readme_answers_are_the_report_answers_box(analyzed):
    """The README's answers (between its markers) are the answers box that opens the report a plain install of this
    checkout writes (``pasibot analyze``): the walks on the floor, the motor's peak and mean, the recommended spring
    and its margin, line for line; the README marks the walking answer's slot, which the report fills."""
    from pasibot_pin.report.answers import WALKING_SLOT

    block = _once(r"<!-- answers: begin -->\n(.*?)\n<!-- answers: end -->", re.S).group(1).splitlines()
    assert block.count(WALKING_SLOT) == 1  # the walking answer's slot is marked where another study fills it
    box = [line[2:] for line in analyzed.section("Answers").splitlines() if line.startswith("> ")]
    assert len(box) >= 4 and box == [line for line in block if line != WALKING_SLOT]


def test_the_masses_quoted_are_the_code_s_one_per_variant():
    """Issue 34: one mass per variant. The robot of `info`, `walk` and the design files (the default design's,
    its `body_mass` on the hip) and the seed scenario's (`load()`, the report's percentage rule) are quoted
    where the docs name them, each computed here by summing the model's body masses."""
    from pasibot_pin.model.design import Design, design_robot
    from pasibot_pin.model.robot import load, total_mass
    from pasibot_pin.model.scenarios import SEED_ROUNDED_FOOT_MASS, SEED_ROUNDED_LINK_MASSES

    def mass(design: Design) -> float:
        robot = design_robot(design, 2, visuals=False)
        assert sum(robot.model.inertias[j].mass for j in range(1, robot.model.njoints)) == total_mass(robot)
        return total_mass(robot)

    spring, rigid, parallel = (mass(Design(variant=v)) for v in ("spring", "rigid", "parallel"))
    body = Design().body_mass
    m = _once(
        r"`body_mass`, (\d+) kg by default, on the hip: ([\d.]+) kg \(spring, rigid\)\s+and ([\d.]+) kg \(parallel\)"
    )
    assert (float(m.group(1)), m.group(2), m.group(3)) == (body, f"{spring:.2f}", f"{parallel:.2f}")
    assert f"{rigid:.2f}" == f"{spring:.2f}"  # the rigid foot's mass is the spring foot's
    m = _once(r"the parallel robot weighs\s+([\d.]+) kg against the spring robot's ([\d.]+) kg with the same (\d+) kg")
    assert (m.group(1), m.group(2), float(m.group(3))) == (f"{parallel:.2f}", f"{spring:.2f}", body)
    seed = load("spring", 2, visuals=False)
    m = _once(r"Table 7\.1\.2 \(hip ([\d.]+) kg, ([\d.]+) kg in all\)")
    assert (m.group(1), m.group(2)) == (f"{seed.masses.hip:.2f}", f"{total_mass(seed):.2f}")
    assert seed.masses.hip == pytest.approx(0.25 * 65.0)  # the report's 25 % of the 65 kg human
    m = _once(r"Their sum is ([\d.]+) kg, not 65 kg")  # the seed's rounded table: its text's body and two legs
    leg = sum(SEED_ROUNDED_LINK_MASSES[f"l{i}"] for i in range(1, 8)) + SEED_ROUNDED_FOOT_MASS
    assert m.group(1) == f"{SCENARIOS['run1'].body_mass + 2 * leg:.1f}"
