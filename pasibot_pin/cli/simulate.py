"""``pasibot simulate``: walk the spring biped with its hip pitch free (does the fitted spring hold the hip?).

``--ground floor`` (default): both feet on a floor, heel and toe unilateral with Coulomb friction
(:mod:`pasibot_pin.studies.floor_cases`); writes ``floor_<scenario>.csv`` (the fitted case: t_s,
hip_pitch_deg, right_mode, left_mode, forces, crank torques) and ``floor_<scenario>.png``, and
prints each case's outcome. ``--ground weld``: the stance foot welded flat
(:mod:`pasibot_pin.studies.simulation_study`); writes ``simulation_<scenario>.png`` and ``.csv``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path

from pasibot_pin.cli import common
from pasibot_pin.cli.bounds import check_integration_steps
from pasibot_pin.errors import ParameterError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("simulate", help="forward-simulate the walking spring biped with the hip pitch free")
    common.add_scenario_option(p)
    p.add_argument("--ground", choices=("floor", "weld"), default="floor", help="feet on a floor (default) or welded")
    p.add_argument("--duration", type=float, help="floor: simulated time per case [s] (default 10; --study: 2)")
    common.add_mu_option(p)
    common.add_design_option(p)
    common.add_steps_option(p, "weld: stance phases to walk")
    common.add_out_folder_option(p, Path("out"), "the CSV, the figure and the animations")
    p.add_argument("--stiffness", type=float, help="K_e [N.m/rad] (default: the inverse-dynamics fit)")
    p.add_argument("--rest-angle", type=float, help="beta0 [deg] (default: the inverse-dynamics fit)")
    p.add_argument("--damping", type=float, help="ankle damping c [N.m.s/rad] (default: critical for the foot)")
    p.add_argument(
        "--swing-ankle", choices=("rest", "spring"), default="rest", help="swing foot at rest angle or sprung"
    )
    p.add_argument("--dt", type=float, help="integration step [s] (default 0.01 rest / 0.002 spring)")
    p.add_argument(
        "--study",
        action="store_true",
        help="floor: weld against floor (--scenario N or all), spring cases and quasi-static K_e x beta0 sweep",
    )
    p.add_argument("--no-cases", action="store_true", help="the fitted spring only (--study: and no sweep)")
    spatial = "floor: the cases on the 3-D floor, the hip free to roll (the design's soles; else centred plates)"
    p.add_argument("--3d", dest="spatial", action="store_true", help=spatial)
    p.add_argument("--gif", action="store_true", help="also write the fitted run as a stick GIF")
    p.add_argument("--html", action="store_true", help="also write the fitted run as a meshcat HTML animation")
    common.add_fps_option(p)
    common.add_force_option(p)
    p.set_defaults(func=run)


FLOOR_MAX_DT: float = 0.01
"""The longest floor time step [s] (the floor's contact solve needs at least 100 steps a second)."""


def check_floor_steps(args: argparse.Namespace) -> None:
    """``--ground floor``: ``--dt`` at most :data:`FLOOR_MAX_DT`, ``--duration`` / ``--dt`` within the step budget.

    Raises:
        ParameterError: naming ``--dt`` or ``--duration``, before any work.

    """
    dt = 1e-3 if args.dt is None else args.dt
    if args.dt is not None and args.dt > FLOOR_MAX_DT:
        raise ParameterError(f"--dt must be in [1e-05, {FLOOR_MAX_DT:g}] s with --ground floor, got {args.dt:g}")
    duration = args.duration if args.duration is not None else (2.0 if args.study else 10.0)
    check_integration_steps(duration, dt, f"--duration {duration:g} s at --dt {dt:g} s")


def run(args: argparse.Namespace) -> int:
    """Simulate the scenario, write plots and CSV, print the excursions."""
    if args.ground == "floor":
        from pasibot_pin.cli.simulate_floor import run_floor  # deferred: keeps the CLI's start fast

        check_floor_steps(args)

        return run_floor(args)
    from pasibot_pin.report.simulation import (  # deferred: keeps the CLI's start fast
        case_line,
        prepare_outputs,
        write_simulation,
    )
    from pasibot_pin.studies.simulation_study import (  # deferred: keeps the CLI's start fast
        SimulateSettings,
        check_fps,
        run_simulation,
        simulation_setup,
    )
    from pasibot_pin.studies.spring_study import scenario_key  # deferred: keeps the CLI's start fast

    floor_only = {
        "--study": args.study,
        "--duration": args.duration,
        "--mu": common.given(args, "mu"),
        "--3d": args.spatial,
    }
    for flag in (f for f, value in {**floor_only, "--design": args.design}.items() if value not in (None, False)):
        raise ParameterError(
            f"{flag} applies to --ground floor only (the welded study: seed scenarios, the foot welded)"
        )
    if args.steps < 1:
        raise ParameterError(f"--steps must be a positive integer, got {args.steps}")
    if args.gif or args.html:
        check_fps(args.fps)
    common.check_output_folder(args.out, "--out")
    settings = SimulateSettings(
        scenario=args.scenario,
        steps=args.steps,
        stiffness=args.stiffness,
        rest_angle=None if args.rest_angle is None else math.radians(args.rest_angle),
        damping=args.damping,
        swing_ankle=args.swing_ankle,
        dt=args.dt,
        cases=not args.no_cases,
    )
    files = prepare_outputs(args.out, scenario_key(args.scenario), gif=args.gif, html=args.html, force=args.force)
    setup = simulation_setup(settings)
    scen, spring = setup.scenario, setup.spring
    print(
        f"scenario {scen.name}: omega = {scen.omega:g} rad/s, "
        f"K_e = {spring.stiffness:.2f} N.m/rad, beta0 = {math.degrees(spring.rest_angle):.2f} deg"
    )
    run = run_simulation(setup, on_case=lambda label, outcome: print(case_line(label, outcome)))
    # every file under a temporary name, all renamed together at the end (none on failure or Ctrl-C)
    targets = (files.plot, None, None, None) if setup.quasi_static else (files.plot, files.csv, files.gif, files.html)
    with common.atomic_paths(*targets) as temps:
        plot, csv, gif, html = temps
        written = write_simulation(dataclasses.replace(files, plot=plot, csv=csv, gif=gif, html=html), run, args.fps)
    if setup.quasi_static:
        print(f"wrote {files.plot} (quasi-static: static equilibria, no walk)")
        return 0
    final = dict(zip(temps, targets))
    for path in written:
        print(f"wrote {final.get(Path(path), path)}")
    return 0
