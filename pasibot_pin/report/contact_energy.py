"""The ``contact_energy`` section of ``pasibot analyze``, and the contact / energy file writers.

:func:`section` runs :mod:`pasibot_pin.studies.contact_energy_study` with its default settings,
writes its CSVs and figures into ``out_dir / "contact_energy"`` and returns the Markdown section.
The writers (:func:`write_contact_figure`, :func:`write_energy_csv`, :func:`write_cost_of_transport`)
are shared with the ``contact`` and ``energy`` commands.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pasibot_pin.report.files import FIGURE_DPI, save_figure_file, write_columns_csv, writing
from pasibot_pin.report.markdown import Section, figure, figure_links
from pasibot_pin.studies.contact import ContactResult
from pasibot_pin.studies.contact_energy_study import (
    ContactEnergyResult,
    ContactSweep,
    EnergySweep,
    SingleMotorStudy,
    run,
)
from pasibot_pin.studies.energy import StepEnergy
from pasibot_pin.units import with_unit
from pasibot_pin.viz import plots_contact

SUBDIR: str = "contact_energy"
"""Folder of the section's files, inside the analyze output folder."""

DPI: int = FIGURE_DPI
"""Resolution of the section's figures [dots per inch] (the report's one)."""


def _plots():
    """:mod:`pasibot_pin.viz.plots_contact`, headless (Agg backend)."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")

    return plots_contact


def save_figure(fig, path: Path, dpi: int = DPI) -> None:
    """Save a matplotlib figure (its folder is created) and close it.

    Args:
        fig: the figure.
        path: output file.
        dpi: resolution [dots per inch].

    """
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure_file(fig, path, dpi)
    plt.close(fig)


def write_contact_figure(path: Path, res: ContactResult, title: str, dpi: int = DPI) -> None:
    """Write the heel/toe forces, CoP and friction figure of one contact result."""
    save_figure(_plots().contact_figure(res, title=title), path, dpi)


def write_cost_of_transport(path: Path, rows: Sequence[StepEnergy], dpi: int = DPI) -> None:
    """Write the cost-of-transport figure [-] over the crank speed [rad/s] of energy rows."""
    save_figure(_plots().plot_cost_of_transport(rows), path, dpi)


def write_energy_csv(path: Path, rows: Sequence[StepEnergy]) -> None:
    """Write energy rows as CSV: one line per row, the union of the rows' keys as header.

    Args:
        path: output file; its folder is created.
        rows: :class:`pasibot_pin.studies.energy.StepEnergy` rows.

    """
    table = [{with_unit(k): v for k, v in r.row().items()} for r in rows]  # omega_rad_s, W_crank_net_J, ...
    keys = list(dict.fromkeys(k for row in table for k in row))
    with writing(Path(path)) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=keys, restval="")
        writer.writeheader()
        writer.writerows(table)


def format_first_failure(res: ContactResult) -> str:
    """``"t = ... s, ... deg: reasons"`` of the first infeasible sample, or ``"none"``."""
    first = res.first_failure()
    if first is None:
        return "none"
    t, th, why = first
    return f"t = {t:.3f} s, {math.degrees(th):.1f} deg: {', '.join(why)}"


def _contact_lines(sweep: ContactSweep, sub: Path) -> list[str]:
    lines = [
        f"### Heel/toe contact (mu = {sweep.mu:g}, default model, one right stance)",
        "",
        "The weld's ground wrench is distributed onto heel and toe contacts (unilateral, linearised "
        "Coulomb cone, proxsuite QP). A sample is infeasible when the centre of pressure (CoP) the motion "
        "demands leaves the sole (the foot would tip over that edge) or |Fx| > mu Fz (slip).",
        "",
        "| scenario (variant) | feasible samples [of all] | first failure [s, deg] | CoP demanded [mm] | "
        "max friction needed [-] | CoP crossings of the sole edges [deg] |",
        "|---|---|---|---|---|---|",
    ]
    for case in sweep.cases:
        res = case.contact
        heel, toe = res.sole_needed()
        crossings = "; ".join(
            f"{e['direction']} at {e['edge']} {math.degrees(float(e['theta'])):.1f} deg" for e in res.tip_events()
        )
        lines.append(
            f"| {case.label} | {int(res.feasible.sum())}/{len(res)} | {format_first_failure(res)} | "
            f"{heel * 1e3:+.0f} .. {toe * 1e3:+.0f} | {case.max_mu_needed:.4f} | {crossings or '-'} |"
        )
        stem = f"contact_{case.variant}_{case.scenario}"
        write_columns_csv(sub / f"{stem}.csv", res.columns())
        write_contact_figure(sub / f"{stem}.png", res, f"{case.label}: heel/toe contact, mu = {sweep.mu:g}")
    worst, where = sweep.worst_mu()
    return lines + [
        "",
        "Soles: spring -25 .. +75 mm, parallel -130 .. +75 mm from the ankle (the parallel variant "
        "carries the scenario's body on percentage-rule masses, 20 kg heavier). "
        "With these soles the CoP stays inside only around mid-stance: the welded foot of the "
        "inverse dynamics holds moments a flat foot on the ground cannot. The 'CoP demanded' column is the "
        "sole a foot would need. The largest friction coefficient needed is "
        f"{worst:.2f} ({where}); at 0.1 rad/s it is below 0.001. As an infeasible-friction "
        f"check, run4 on a what-if 2 m sole with mu = 0.01: first failure {format_first_failure(sweep.slip)}.",
        "",
        figure(
            f"{SUBDIR}/contact_spring_run1.png",
            f"run1, spring variant: heel and toe forces [N], centre of pressure [mm] and friction used |Fx|/Fz [-] "
            f"over the stance crank angle [deg], mu = {sweep.mu:g}; shaded: infeasible.",
        ),
        figure_links(
            [
                (f"{SUBDIR}/contact_{c.variant}_{c.scenario}.png", f"the same for {c.label}")
                for c in sweep.cases
                if (c.variant, c.scenario) != ("spring", "run1")
            ],
            "The same figure for every scenario and variant of the table:",
        ),
    ]


def _motor_lines(motor: SingleMotorStudy, sub: Path) -> list[str]:
    rows = []
    for case in motor.flywheels:
        fw = case.flywheel
        if fw is None:
            rows.append(f"| {case.inertia:g} | too small: {case.error} |")
        else:
            rows.append(
                f"| {case.inertia:g} | {fw.speed_fluctuation * 100:.2f} "
                f"({fw.speed_fluctuation_linear * 100:.2f} first order) |"
            )
    write_columns_csv(sub / f"single_motor_{motor.scenario}.csv", motor.columns())
    save_figure(_plots().plot_single_motor(motor.torques, motor.single), sub / f"single_motor_{motor.scenario}.png")
    single, torques = motor.single, motor.torques
    return [
        f"### One motor for both cranks ({motor.scenario}, {motor.omega:g} rad/s)",
        "",
        "The cranks are coupled pi apart by one constraint row q_L - q_R - pi = 0 (Pinocchio's "
        "JointModelMimic is rejected by the constraint algorithms); the motor drives the right crank and "
        "the coupling carries the left crank's torque. Its torque equals T_a + T_a' of the two-motor "
        f"solution to {motor.max_deviation:.1e} N.m (tested).",
        "",
        f"- without a flywheel (the crank speed held at {motor.omega:g} rad/s): peak {single.peak():.2f} N.m and "
        f"{motor.peak_power:.1f} W, RMS {single.rms():.2f} N.m (two motors: peaks "
        f"{np.max(np.abs(torques.Ta)):.2f} and {np.max(np.abs(torques.Ta_swing)):.2f} N.m)",
        f"- with a flywheel of any size the motor gives a constant torque, its mean over a step: "
        f"{motor.mean_torque:.2f} N.m, {motor.mean_power:.1f} W; the flywheel's inertia only sets how much the "
        "crank speed varies (the table)",
        f"- flywheel for a {motor.fluctuation * 100:g} % speed fluctuation: {motor.inertia_for_target:.2f} kg.m^2 "
        "on the crank shaft (a large wheel)",
        "",
        "| flywheel [kg.m^2] | crank speed fluctuation [%] |",
        "|---|---|",
        *rows,
        "",
        figure(
            f"{SUBDIR}/single_motor_{motor.scenario}.png",
            f"{motor.scenario} at {motor.omega:g} rad/s: the single motor's torque [N.m] against the two motors' "
            "over the crank angle [deg].",
        ),
    ]


def _energy_lines(result: ContactEnergyResult, sub: Path) -> list[str]:
    sweep: EnergySweep = result.energy
    power = result.power
    write_energy_csv(sub / "energy.csv", sweep.rows)
    write_cost_of_transport(sub / "cost_of_transport.png", sweep.rows)
    power_png = f"power_{power.variant}_{power.omega:g}.png"
    save_figure(_plots().plot_powers(power.powers, power.theta), sub / power_png)
    return [
        f"### Energy per step and cost of transport (body {result.settings.body_mass:g} kg at joint 8)",
        "",
        "One step = one stance, 8 L = 0.4 m of hip travel. Work = integral of each actuator's power "
        f"(Gauss-Legendre, {result.settings.nodes} nodes); it equals the change of kinetic + potential energy "
        "to 1e-6 (tested). CoT = positive work / (m g d), no regeneration. The parallel variant's extension "
        "links get the thigh's mass per unit length (percentage rule), so it is 20 kg heavier with the same body.",
        "",
        sweep.markdown(),
        "",
        figure(
            f"{SUBDIR}/cost_of_transport.png",
            "Cost of transport [-] against the crank speed [rad/s]: two motors, with the ankle actuators, one motor.",
        ),
        figure(
            f"{SUBDIR}/{power_png}",
            f"Power of each actuator [W] over one step, {power.variant} variant at {power.omega:g} rad/s.",
        ),
    ]


def section(out_dir: Path) -> str:
    """The section's Markdown (:func:`build` without the facts)."""
    return build(out_dir).markdown


def build(out_dir: Path) -> Section:
    """Contact along every scenario, one motor for both cranks, energy and cost of transport over omega.

    Runs the study with its default settings and writes, into ``out_dir / "contact_energy"``:
    ``contact_{variant}_{scenario}.csv/.png``, ``single_motor_run4.csv/.png``, ``energy.csv``,
    ``cost_of_transport.png`` and ``power_spring_5.png``.

    Args:
        out_dir: the analyze output folder.

    Returns:
        The Markdown section for ``report.md``.

    """
    sub = Path(out_dir) / SUBDIR
    sub.mkdir(parents=True, exist_ok=True)
    result = run()
    lines = ["## Beyond the report: contact, one motor, energy", ""]
    lines += _contact_lines(result.contact, sub)
    lines += _motor_lines(result.motor, sub)
    lines += _energy_lines(result, sub)
    run1 = next(c.contact for c in result.contact.cases if (c.variant, c.scenario) == ("spring", "run1"))
    facts = {
        "run1_ok": int(run1.feasible.sum()),
        "run1_n": len(run1),
        "run1_cop": tuple(float(x) for x in run1.sole_needed()),
        "sole": (float(np.min(run1.s_heel)), float(np.max(run1.s_toe))),
        "fluctuation": float(result.motor.fluctuation),
        "motor_peak": float(result.motor.single.peak()),
        "motor_omega": float(result.motor.omega),
        "motor_scenario": result.motor.scenario,
        "flywheel": float(result.motor.inertia_for_target),
    }
    return Section("\n".join(lines), facts)
