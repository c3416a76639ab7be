"""``pasibot contact``: heel/toe contact of the stance foot along a seed scenario.

The ground wrench of the constrained inverse dynamics is distributed onto heel and toe
(unilateral, Coulomb friction, proxsuite QP). Prints where the contact fails (tip over the
heel or toe, slip), the centre of pressure and the friction needed; writes a CSV and a
figure on request. Infeasible samples are reported, never raised.

Also holds the ``contact_energy`` step of ``pasibot analyze`` (:func:`analyze_step`).
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np

from pasibot_pin.cli.common import write_columns_csv


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    from pasibot_pin.model.scenarios import PRESETS, SCENARIOS

    p = sub.add_parser(
        "contact",
        help="heel/toe contact forces, centre of pressure and friction needed along a seed scenario",
        description=__doc__,
    )
    p.add_argument("--scenario", default="run1", help=f"one of {', '.join(SCENARIOS)} (default run1)")
    p.add_argument("--preset", default="default", help=f"modelling preset: {', '.join(PRESETS)} (default default)")
    p.add_argument("--variant", default="spring", help="spring or parallel (default spring)")
    p.add_argument("--mu", type=float, default=0.6, help="Coulomb friction coefficient (default 0.6)")
    p.add_argument("--samples", type=int, default=61, help="samples over one stance (default 61)")
    p.add_argument(
        "--sole",
        type=float,
        nargs=2,
        metavar=("HEEL", "TOE"),
        default=None,
        help="what-if sole: heel and toe along the sole from the ankle [m] (e.g. -0.2 0.4); default the model's",
    )
    p.add_argument("--csv", type=Path, default=None, help="write the samples to this CSV file")
    p.add_argument("--plot", type=Path, default=None, help="write the forces/CoP/friction figure to this file")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.set_defaults(func=run)


def compute(scenario_name: str, preset: str, mu: float, samples: int, sole=None, variant: str = "spring"):
    """(torques, contact) of one scenario over one right stance.

    See :func:`pasibot_pin.studies.contact.scenario_contact`.
    """
    from pasibot_pin.studies.contact import scenario_contact

    if samples < 2:
        raise ValueError(f"parameter '--samples' must be >= 2, got {samples!r}")
    return scenario_contact(scenario_name, preset, mu, samples, sole, variant)


def run(args: argparse.Namespace) -> int:
    """Print the contact summary; write the optional CSV and figure."""
    for path, option in ((args.csv, "--csv"), (args.plot, "--plot")):
        if path is not None and path.exists() and not args.force:
            raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")
    sole = tuple(args.sole) if args.sole is not None else None
    _torques, res = compute(args.scenario, args.preset, args.mu, args.samples, sole, args.variant)
    print(f"scenario {args.scenario}, {args.variant} variant, preset {args.preset}, {len(res)} samples over one stance")
    print(res.summary())
    if args.csv is not None:
        write_columns_csv(args.csv, res.columns())
        print(f"wrote {args.csv}")
    if args.plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        from pasibot_pin.viz.plots_contact import contact_figure

        fig = contact_figure(res, title=f"{args.scenario}: heel/toe contact, mu = {args.mu:g}")
        args.plot.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
    return 0


# --------------------------------------------------------------------------- analyze step
ANALYZE_MU: float = 0.6
"""Friction coefficient of the analyze step (rubber on a dry floor, about)."""
ANALYZE_OMEGAS: tuple[float, ...] = (0.1, 0.5, 1.0, 2.0, 5.0)
"""Crank speeds of the energy table [rad/s]."""
ANALYZE_FLYWHEELS: tuple[float, ...] = (1.0, 5.0, 20.0)
"""Flywheel inertias of the analyze step [kg.m^2]."""


def _fmt_first(res) -> str:
    first = res.first_failure()
    if first is None:
        return "none"
    t, th, why = first
    return f"t = {t:.3f} s, {math.degrees(th):.1f} deg: {', '.join(why)}"


def analyze_step(out_dir: Path, args: argparse.Namespace) -> str:
    """Contact along every scenario, one motor for both cranks, energy and cost of transport over omega."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pasibot_pin.dynamics.inverse import inverse_dynamics, scenario_robot
    from pasibot_pin.model.scenarios import SCENARIOS, get_preset, get_scenario
    from pasibot_pin.studies import energy, single_motor
    from pasibot_pin.viz.plots_contact import contact_figure, plot_cost_of_transport, plot_powers, plot_single_motor

    sub = out_dir / "contact_energy"
    sub.mkdir(parents=True, exist_ok=True)
    lines = [
        "## Beyond the report: contact, one motor, energy",
        "",
        f"### Heel/toe contact (mu = {ANALYZE_MU:g}, default model, one right stance)",
        "",
        "The weld's ground wrench is distributed onto heel and toe contacts (unilateral, linearised "
        "Coulomb cone, proxsuite QP). A sample is infeasible when the centre of pressure (CoP) the motion "
        "demands leaves the sole (the foot would tip over that edge) or |Fx| > mu Fz (slip).",
        "",
        "| scenario (variant) | feasible samples | first failure | CoP demanded [mm] | "
        "max friction needed | CoP crossings of the sole edges |",
        "|---|---|---|---|---|---|",
    ]
    worst_mu = (0.0, "")
    for name, variant in [(n, v) for v in ("spring", "parallel") for n in SCENARIOS]:
        torques, res = compute(name, "default", ANALYZE_MU, 60, variant=variant)
        heel, toe = res.sole_needed()
        crossings = "; ".join(
            f"{e['direction']} at {e['edge']} {math.degrees(e['theta']):.1f} deg" for e in res.tip_events()
        )
        finite = res.mu_needed[np.isfinite(res.mu_needed)]
        if finite.size and np.max(finite) > worst_mu[0]:
            worst_mu = (float(np.max(finite)), f"{name}, {variant}")
        lines.append(
            f"| {name} ({variant}) | {int(res.feasible.sum())}/{len(res)} | {_fmt_first(res)} | {heel * 1e3:+.0f} .. "
            f"{toe * 1e3:+.0f} | {np.max(finite):.4f} | {crossings or '-'} |"
        )
        write_columns_csv(sub / f"contact_{variant}_{name}.csv", res.columns())
        fig = contact_figure(res, title=f"{name} ({variant}): heel/toe contact, mu = {ANALYZE_MU:g}")
        fig.savefig(sub / f"contact_{variant}_{name}.png", dpi=110)
        plt.close(fig)
    _, slip = compute("run4", "default", 0.01, 60, sole=(-1.0, 1.0))
    lines += [
        "",
        "Soles: spring -25 .. +75 mm, parallel -130 .. +75 mm from the ankle (the parallel variant "
        "carries the scenario's body on percentage-rule masses, 20 kg heavier). "
        "With these soles the CoP stays inside only around mid-stance: the welded foot of the "
        "inverse dynamics holds moments a flat foot on the ground cannot. The 'CoP demanded' column is the "
        "sole a foot would need. The largest friction coefficient needed is "
        f"{worst_mu[0]:.2f} ({worst_mu[1]}); at 0.1 rad/s it is below 0.001. As an infeasible-friction "
        f"check, run4 on a what-if 2 m sole with mu = 0.01: first failure {_fmt_first(slip)}.",
        "",
        "![contact run1](contact_energy/contact_spring_run1.png)",
        "",
    ]

    # one motor for both cranks: run4 (5 rad/s), one full turn
    scenario, choices = get_scenario("run4"), get_preset("default")
    robot = scenario_robot(scenario, choices)
    thetas = np.linspace(math.pi / 2, 5 * math.pi / 2, 121)[:-1]
    torques = inverse_dynamics(robot, thetas, scenario.omega)
    single = single_motor.coupled_split(robot, torques)
    both = torques.Ta + torques.Ta_swing
    step = slice(0, 61)  # one step, both ends: the torque repeats every half turn (legs swapped)
    fw_rows = []
    for inertia in ANALYZE_FLYWHEELS:
        try:
            fw = single_motor.flywheel(thetas[step], single.motor[step], scenario.omega, inertia)
            fw_rows.append(
                f"| {inertia:g} | {fw.mean_torque:.2f} | {fw.speed_fluctuation * 100:.2f} % "
                f"({fw.speed_fluctuation_linear * 100:.2f} % first order) |"
            )
        except ValueError as err:
            fw_rows.append(f"| {inertia:g} | - | too small: {err} |")
    j5 = single_motor.inertia_for(thetas[step], single.motor[step], scenario.omega, 0.05)
    write_columns_csv(
        sub / "single_motor_run4.csv",
        {
            "theta_right": thetas,
            "Ta_right": np.where(np.array(torques.stance) == "right", torques.Ta, torques.Ta_swing),
            "Ta_left": single.transmission,
            "motor": single.motor,
        },
    )
    fig = plot_single_motor(torques, single)
    fig.savefig(sub / "single_motor_run4.png", dpi=110)
    plt.close(fig)
    lines += [
        "### One motor for both cranks (run4, 5 rad/s)",
        "",
        "The cranks are coupled pi apart by one constraint row q_L - q_R - pi = 0 (Pinocchio's "
        "JointModelMimic is rejected by the constraint algorithms); the motor drives the right crank and "
        "the coupling carries the left crank's torque. Its torque equals T_a + T_a' of the two-motor "
        f"solution to {np.max(np.abs(single.motor - both)):.1e} N.m (tested).",
        "",
        f"- peak {single.peak():.2f} N.m, RMS {single.rms():.2f} N.m (two motors: peaks "
        f"{np.max(np.abs(torques.Ta)):.2f} and {np.max(np.abs(torques.Ta_swing)):.2f} N.m)",
        f"- flywheel for a 5 % speed fluctuation: {j5:.2f} kg.m^2 on the crank shaft",
        "",
        "| flywheel [kg.m^2] | motor torque with it [N.m] | crank speed fluctuation |",
        "|---|---|---|",
        *fw_rows,
        "",
        "![single motor](contact_energy/single_motor_run4.png)",
        "",
    ]

    # energy over omega, spring vs parallel, body 16 kg at joint 8
    rows = energy.omega_table(ANALYZE_OMEGAS, body_mass=16.0, body_com_dx=0.0)
    table = [r.row() for r in rows]
    keys = list(dict.fromkeys(k for row in table for k in row))
    with (sub / "energy.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=keys, restval="")
        writer.writeheader()
        writer.writerows(table)
    fig = plot_cost_of_transport(rows)
    fig.savefig(sub / "cost_of_transport.png", dpi=110)
    plt.close(fig)
    _, res5 = energy.spring_step_energy(5.0, 16.0, 0.0, fit=False)
    fig = plot_powers(energy.actuator_powers(energy.variant_robot("spring", 16.0), res5), res5.theta)
    fig.savefig(sub / "power_spring_5.png", dpi=110)
    plt.close(fig)
    lines += [
        "### Energy per step and cost of transport (body 16 kg at joint 8)",
        "",
        "One step = one stance, 8 L = 0.4 m of hip travel. Work = integral of each actuator's power "
        "(Gauss-Legendre, 48 nodes); it equals the change of kinetic + potential energy to 1e-6 (tested). "
        "CoT = positive work / (m g d), no regeneration. The parallel variant's extension links get the "
        "thigh's mass per unit length (percentage rule), so it is 20 kg heavier with the same body.",
        "",
        energy.format_table(rows),
        "",
        "![cost of transport](contact_energy/cost_of_transport.png)",
        "![power](contact_energy/power_spring_5.png)",
    ]
    return "\n".join(lines)
