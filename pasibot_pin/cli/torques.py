"""``pasibot torques``: crank and ankle torques of a seed scenario, and the fitted ankle spring.

Maps flags to :func:`pasibot_pin.studies.torques_study.scenario_torques` and writes through
:mod:`pasibot_pin.report.torques` (the ``dynamics`` step of ``pasibot analyze`` is
:func:`pasibot_pin.report.torques.section`).
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import (
    add_design_option,
    add_output_options,
    add_scenario_option,
    atomic_path,
    check_outputs,
    design_of,
)
from pasibot_pin.model.scenarios import ACCELERATION_MODES, PRESETS, SWING_FOOT_MODES, get_scenario
from pasibot_pin.model.variants import get_variant


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("torques", help="crank/ankle torques of a seed scenario and the fitted ankle spring K_e")
    add_scenario_option(p)
    p.add_argument("--preset", default="default", help=f"modelling preset: {', '.join(PRESETS)} (default default)")
    p.add_argument("--omega", type=float, default=None, help="override the crank speed [rad/s] (0 = quasi-static)")
    p.add_argument(
        "--samples", type=int, default=None, help="samples over one stance, 2..100000 (default 61; not with a window)"
    )
    p.add_argument("--steps", type=int, default=1, help="half crank turns (steps) to run, stance swapping (default 1)")
    p.add_argument("--swing-foot", choices=SWING_FOOT_MODES, default=None, help="override: level or square")
    p.add_argument("--accelerations", choices=ACCELERATION_MODES, default=None, help="override the acceleration mode")
    p.add_argument("--inertia", choices=("point", "uniform"), default=None, help="override: point masses or rods")
    p.add_argument("--no-swap", action="store_true", help="undo the seed's L5/L6 mass swap")
    add_output_options(p, "write the samples to this CSV file", "write torques vs beta with the fit to this image")
    add_design_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print K_e and write the optional CSV and plot."""
    from pasibot_pin.report.torques import write_beta_plot, write_result_csv  # deferred: keeps the CLI's start fast
    from pasibot_pin.studies.torques_study import (  # deferred: keeps the CLI's start fast
        TorqueSettings,
        scenario_torques,
    )

    design = design_of(args)
    check_outputs(args, "torques_design" if design is not None else f"torques_{get_scenario(args.scenario).name}")
    settings = TorqueSettings(
        scenario=args.scenario,
        preset=args.preset,
        omega=args.omega,
        samples=args.samples,
        steps=args.steps,
        swing_foot=args.swing_foot,
        accelerations=args.accelerations,
        inertia=args.inertia,
        swap_l5_l6=False if args.no_swap else None,
        design=design,
    )
    res = scenario_torques(settings)
    scenario, fit = res.scenario, res.fit
    omega = res.result.omega
    note = "" if omega == scenario.omega else f" (the scenario's own: {scenario.omega:g} rad/s)"
    print(
        f"scenario {scenario.name} ({scenario.description}) at omega = {omega:g} rad/s{note}; "
        f"preset {args.preset}; {len(res.result)} samples"
    )
    if fit is not None:
        print(fit.summary())
    elif design is not None:  # a variant without a free ankle: T_e is zero, the crank torques are the answer
        variant = get_variant(design.variant)
        ta = res.result.Ta
        print(
            f"no ankle spring to fit: variant {variant.name} has no free ankle ({variant.description}); "
            f"crank torque T_a from {ta.min():.2f} to {ta.max():.2f} N.m"
        )
    if scenario.seed_K_e is not None:
        print(
            f"seed stored K_e = {scenario.seed_K_e:.2f} N.m/rad (without swap and lag: {scenario.seed_K_e_clean:.2f})"
        )
    if args.csv is not None:
        with atomic_path(args.csv) as tmp:
            write_result_csv(tmp, res.result)
        print(f"wrote {args.csv}")
    if args.plot is not None:
        with atomic_path(args.plot) as tmp:
            write_beta_plot(tmp, res)
        print(f"wrote {args.plot}")
    return 0
