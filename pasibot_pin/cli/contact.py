"""``pasibot contact``: heel/toe contact of the stance foot along a seed scenario.

The ground wrench of the constrained inverse dynamics is distributed onto heel and toe
(unilateral, Coulomb friction, proxsuite QP). Prints where the contact fails (tip over the
heel or toe, slip), the centre of pressure and the friction needed; writes a CSV and a
figure on request. Infeasible samples are reported, never raised.
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import (
    add_design_option,
    add_mu_option,
    add_output_options,
    add_scenario_option,
    atomic_path,
    check_outputs,
    design_of,
)
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.scenarios import PRESETS, get_scenario
from pasibot_pin.report.files import write_columns_csv
from pasibot_pin.studies.contact import CONTACT_SAMPLES, check_sole, design_contact, scenario_contact

CONTACT_VARIANTS: tuple[str, ...] = ("spring", "parallel")
"""The variants the contact study takes (the seed's scenarios and presets are for these two designs)."""


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "contact",
        help="heel/toe contact forces, centre of pressure and friction needed along a seed scenario",
        description=__doc__,
    )
    add_scenario_option(p)
    p.add_argument("--preset", default="default", help=f"modelling preset: {', '.join(PRESETS)} (default default)")
    p.add_argument("--variant", default="spring", choices=CONTACT_VARIANTS, help="spring or parallel (default spring)")
    add_mu_option(p)
    p.add_argument(
        "--samples", type=int, default=CONTACT_SAMPLES, help=f"samples over one stance (default {CONTACT_SAMPLES})"
    )
    p.add_argument(
        "--sole",
        type=float,
        nargs=2,
        metavar=("HEEL", "TOE"),
        default=None,
        help="what-if sole: heel and toe along the sole from the ankle [m] (e.g. -0.2 0.4); default the model's",
    )
    add_output_options(p, "write the samples to this CSV file", "write the forces/CoP/friction figure to this file")
    add_design_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the contact summary; write the optional CSV and figure."""
    from pasibot_pin.report.contact_energy import write_contact_figure  # deferred: keeps the CLI's start fast

    design = design_of(args)
    name = "design" if design is not None else get_scenario(args.scenario).name
    check_outputs(args, f"contact_{args.variant if design is None else design.variant}_{name}")
    if args.samples < 2:
        raise ParameterError(f"parameter '--samples' must be >= 2, got {args.samples!r}")
    sole = check_sole(args.sole, "--sole")
    if design is not None:
        _torques, res = design_contact(design, args.mu, args.samples, sole)
        print(f"design {args.design}, {design.variant} variant, {len(res)} samples over one stance")
    else:
        _torques, res = scenario_contact(args.scenario, args.preset, args.mu, args.samples, sole, args.variant)
        print(f"scenario {name}, {args.variant} variant, preset {args.preset}, {len(res)} samples over one stance")
    print(res.summary())
    if args.csv is not None:
        write_columns_csv(args.csv, res.columns())  # written under a temporary name, then renamed
        print(f"wrote {args.csv}")
    if args.plot is not None:
        with atomic_path(args.plot) as tmp:
            write_contact_figure(tmp, res, f"{name}: heel/toe contact, mu = {args.mu:g}")
        print(f"wrote {args.plot}")
    return 0
