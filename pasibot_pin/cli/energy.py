"""``pasibot energy``: work per step, spring energy and cost of transport over the crank speed.

For each crank speed and each variant (``spring``, ``parallel``) at the same body mass and
COM: the positive and negative work of the crank motors per step, of one motor driving both
cranks, of the ankle actuators, the energy the ankle spring stores and releases, the peak
and RMS torque of the single motor, and the cost of transport. With ``--flywheel J`` it also
gives the single motor's smoothed torque and the crank speed fluctuation with a flywheel of
inertia J [kg.m^2].
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import (
    add_design_option,
    add_output_options,
    atomic_path,
    check_outputs,
    design_of,
    float_list,
)
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.scenarios import DEFAULT_BODY_MASS

ENERGY_VARIANTS: tuple[str, ...] = ("spring", "parallel")
"""The variants the energy study compares (the rigid leg is the seed's kinematic model, not one of the two
designs whose motors and ankles the study sizes)."""


MAX_ENERGY_NODES: int = 20_000
"""The most inverse-dynamics nodes one ``energy`` run solves (about 4 ms each: a minute and a half)."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "energy", help="work per step, spring energy and cost of transport (spring vs parallel)", description=__doc__
    )
    p.add_argument("--omegas", type=float_list, default=[0.1, 1.0, 5.0], help="crank speeds [rad/s] (default 0.1,1,5)")
    p.add_argument(
        "--body-mass",
        type=float,
        default=DEFAULT_BODY_MASS,
        help=f"body (hip) mass [kg] (default {DEFAULT_BODY_MASS:g})",
    )
    p.add_argument("--com-dx", type=float, default=0.0, help="body COM ahead of joint 8 [m] (default 0)")
    p.add_argument("--variants", default="spring,parallel", help="comma-separated: spring, parallel (default both)")
    p.add_argument("--nodes", type=int, default=48, help="Gauss-Legendre nodes per step (default 48)")
    p.add_argument("--flywheel", type=float, default=None, help="flywheel inertia on the motor shaft [kg.m^2]")
    add_output_options(p, "write the table to this CSV file", "write the cost-of-transport figure to this file")
    add_design_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the table; write the optional CSV and figure."""
    from pasibot_pin.report.contact_energy import (  # deferred: keeps the CLI's start fast
        write_cost_of_transport,
        write_energy_csv,
    )
    from pasibot_pin.studies.contact_energy_study import (  # deferred: keeps the CLI's start fast
        ContactEnergySettings,
        check_flywheel_inertia,
        energy_sweep,
        flywheel_cases,
    )

    check_outputs(args, "energy")
    if args.flywheel is not None:
        check_flywheel_inertia(args.flywheel)
    variants = tuple(v.strip() for v in args.variants.split(","))
    if not any(variants) or not all(variants):
        raise ParameterError(
            f"--variants must be a comma-separated list of {', '.join(ENERGY_VARIANTS)}, got {args.variants!r}"
        )
    for v in variants:
        if v not in ENERGY_VARIANTS:
            raise ParameterError(f"--variants: unknown variant {v!r}; valid: {', '.join(ENERGY_VARIANTS)}")
    if len(set(variants)) != len(variants):
        raise ParameterError(f"--variants names a variant twice: {args.variants!r}")
    work = len(args.omegas) * len(variants) * args.nodes
    if work > MAX_ENERGY_NODES:
        raise ParameterError(
            f"--omegas ({len(args.omegas)} speeds) x --variants ({len(variants)}) x --nodes ({args.nodes}) = {work} "
            f"inverse-dynamics nodes; at most {MAX_ENERGY_NODES} (fewer speeds or nodes)"
        )
    design = design_of(args)
    if design is not None and args.flywheel is not None:
        raise ParameterError("--flywheel sizes the variants' motors; it takes no --design")
    settings = ContactEnergySettings(
        design=design,
        omegas=tuple(args.omegas),
        energy_variants=variants,
        body_mass=args.body_mass,
        body_com_dx=args.com_dx,
        nodes=args.nodes,
    )
    sweep = energy_sweep(settings)
    print(sweep.markdown())
    if args.flywheel is not None:
        print(f"\nflywheel {args.flywheel:g} kg.m^2 on the single motor's shaft:")
        for case in flywheel_cases(args.omegas, variants, args.flywheel, args.body_mass, args.com_dx, args.nodes):
            print(case.summary())
    if args.csv is not None:
        with atomic_path(args.csv) as tmp:
            write_energy_csv(tmp, sweep.rows)
        print(f"wrote {args.csv}")
    if args.plot is not None:
        with atomic_path(args.plot) as tmp:
            write_cost_of_transport(tmp, sweep.rows)
        print(f"wrote {args.plot}")
    return 0 if sweep.all_finite else 1
