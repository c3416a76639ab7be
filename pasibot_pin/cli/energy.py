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
import csv
import math
from pathlib import Path

from pasibot_pin.model.params import VARIANTS


def _floats(text: str) -> list[float]:
    try:
        values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError as err:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from err
    if not values:
        raise argparse.ArgumentTypeError("expected at least one number")
    return values


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "energy", help="work per step, spring energy and cost of transport (spring vs parallel)", description=__doc__
    )
    p.add_argument("--omegas", type=_floats, default=[0.1, 1.0, 5.0], help="crank speeds [rad/s] (default 0.1,1,5)")
    p.add_argument("--body-mass", type=float, default=16.0, help="body (hip) mass [kg] (default 16)")
    p.add_argument("--com-dx", type=float, default=0.0, help="body COM ahead of joint 8 [m] (default 0)")
    p.add_argument("--variants", default="spring,parallel", help="comma-separated: spring, parallel (default both)")
    p.add_argument("--nodes", type=int, default=48, help="Gauss-Legendre nodes per step (default 48)")
    p.add_argument("--flywheel", type=float, default=None, help="flywheel inertia on the motor shaft [kg.m^2]")
    p.add_argument("--csv", type=Path, default=None, help="write the table to this CSV file")
    p.add_argument("--plot", type=Path, default=None, help="write the cost-of-transport figure to this file")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the table; write the optional CSV and figure."""
    from pasibot_pin.studies import energy, single_motor

    for path, option in ((args.csv, "--csv"), (args.plot, "--plot")):
        if path is not None and path.exists() and not args.force:
            raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")
    variants = [v.strip() for v in args.variants.split(",") if v.strip()]
    for v in variants:
        if v not in VARIANTS:
            raise ValueError(f"parameter '--variants': unknown variant {v!r}; valid: {', '.join(VARIANTS)}")
    rows = energy.omega_table(args.omegas, args.body_mass, args.com_dx, args.nodes, variants)
    print(energy.format_table(rows))
    if args.flywheel is not None:
        print(f"\nflywheel {args.flywheel:g} kg.m^2 on the single motor's shaft:")
        for omega in args.omegas:
            for variant in variants:
                _, res = energy.step_energy(variant, omega, args.body_mass, args.com_dx, args.nodes, fit=False)
                torque = res.Ta + res.Ta_swing
                try:
                    fw = single_motor.flywheel(res.theta_right, torque, omega, args.flywheel)
                    print(
                        f"  {variant:8s} omega {omega:g} rad/s: motor {fw.mean_torque:+.3f} N.m constant instead of "
                        f"peak {fw.peak_without:.3f} N.m; speed fluctuation {fw.speed_fluctuation * 100:.3f} %"
                    )
                except ValueError as err:
                    print(f"  {variant:8s} omega {omega:g} rad/s: {err}")
    if args.csv is not None:
        table = [r.row() for r in rows]
        keys = list(dict.fromkeys(k for row in table for k in row))
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        with args.csv.open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=keys, restval="")
            writer.writeheader()
            writer.writerows(table)
        print(f"wrote {args.csv}")
    if args.plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        from pasibot_pin.viz.plots_contact import plot_cost_of_transport

        fig = plot_cost_of_transport(rows)
        args.plot.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
    return 0 if all(math.isfinite(r.cot["motors"]) for r in rows) else 1
