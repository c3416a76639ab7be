"""``pasibot simulate --ground floor``: the spring cases with both feet on a floor (the default ground).

Maps the flags to :func:`pasibot_pin.studies.floor_cases.floor_study` and
:mod:`pasibot_pin.report.floor`; with ``--study``, to
:func:`pasibot_pin.studies.weld_vs_floor.floor_spring_study` (weld against floor, the
scenario or ``all`` of runs 1-4). The welded-only flags are refused.
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import check_output_folder, design_of, given
from pasibot_pin.errors import ParameterError
from pasibot_pin.studies.floor_cases import FloorStudySettings, case_summary, floor_study
from pasibot_pin.studies.floor_static import floor_static_study
from pasibot_pin.studies.spring_study import SPRING_CASES, scenario_key
from pasibot_pin.studies.weld_vs_floor import WALKING_SCENARIOS, FloorSpringSettings, floor_spring_study


def run_floor(args: argparse.Namespace) -> int:
    """The spring cases on the floor: print each outcome, write the CSV and the figure (or the study's files)."""
    for flag, value in (
        ("--stiffness", args.stiffness),
        ("--rest-angle", args.rest_angle),
        ("--damping", args.damping),
        ("--steps", args.steps if given(args, "steps") else None),
        ("--gif", args.gif or None),
        ("--html", args.html or None),
    ):
        if value is not None:
            raise ParameterError(
                f"{flag} applies to --ground weld only (the floor runs the fitted, no, half and twice springs)"
            )
    dt = 1e-3 if args.dt is None else args.dt
    if args.study and args.design is not None:
        raise ParameterError("--study runs the seed scenarios; it takes no --design")
    if args.study and args.spatial:
        raise ParameterError("--3d runs the spring cases (or --design) on the 3-D floor; --study is the planar floor's")
    if args.study:
        return _run_study(args, dt)
    duration = 10.0 if args.duration is None else args.duration
    design = design_of(args)
    scenario = "design" if design is not None else scenario_key(args.scenario)
    settings = FloorStudySettings(
        "run1" if design else scenario, duration, args.mu, dt, cases=not args.no_cases, design=design,
        spatial=args.spatial,
    )  # fmt: skip
    check_output_folder(args.out, "--out")
    from pasibot_pin.report.floor import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
        floor_files,
        write_floor,
    )

    csv_path, png_path = floor_files(args.out, scenario, args.force, spatial=args.spatial)
    study = floor_study(settings, on_case=lambda case: print(case_summary(case), flush=True))
    for path in write_floor(study, csv_path, png_path):
        print(f"wrote {path}")
    return 0


def _run_study(args: argparse.Namespace, dt: float) -> int:
    """``--study``: weld against floor for the scenario (or all four runs); the tables, CSVs and figures.

    The quasi-static K_e x beta0 sweep too, unless ``--no-cases``.
    """
    from pasibot_pin.report.floor import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
        floor_spring_files,
        floor_spring_line,
        write_floor_spring,
    )

    scenarios = WALKING_SCENARIOS if args.scenario == "all" else (args.scenario,)
    duration = 2.0 if args.duration is None else args.duration
    settings = FloorSpringSettings(scenarios=scenarios, duration=duration, mu=args.mu, dt=dt)
    check_output_folder(args.out, "--out")
    floor_spring_files(args.out, args.force, sweep=not args.no_cases)  # FileExistsError before any work
    cases = SPRING_CASES[:1] if args.no_cases else SPRING_CASES
    study = floor_spring_study(settings, cases, on_row=lambda row: print(floor_spring_line(row), flush=True))
    statics = None if args.no_cases else floor_static_study(settings.scenarios, settings.mu, settings.static_samples)
    for sweep in statics or []:
        holds = [(c.holds, c.weld_excursion < float("inf")) for row in sweep.cells for c in row]
        print(
            f"  {sweep.scenario} quasi-static K_e x beta0: the floor holds {sum(h for h, _ in holds)} of "
            f"{len(holds)} cells, the weld {sum(w for _, w in holds)}",
            flush=True,
        )
    for path in write_floor_spring(study, args.out, force=args.force, statics=statics):
        print(f"wrote {path}")
    return 0
