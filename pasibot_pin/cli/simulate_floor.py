"""``pasibot simulate --ground floor``: the spring cases with both feet on a floor (the default ground).

Maps the flags to :func:`pasibot_pin.studies.floor_study.floor_study` and
:mod:`pasibot_pin.report.floor`; the welded-only flags are refused.
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import check_output_folder, given


def run_floor(args: argparse.Namespace) -> int:
    """The spring cases on the floor: print each outcome, write the CSV and the figure."""
    from pasibot_pin.report.floor import floor_files, write_floor
    from pasibot_pin.studies.floor_study import FloorStudySettings, case_summary, floor_study
    from pasibot_pin.studies.spring_study import scenario_key

    for flag, value in (
        ("--stiffness", args.stiffness),
        ("--rest-angle", args.rest_angle),
        ("--damping", args.damping),
        ("--steps", args.steps if given(args, "steps") else None),
        ("--gif", args.gif or None),
        ("--html", args.html or None),
    ):
        if value is not None:
            raise ValueError(
                f"{flag} applies to --ground weld only (the floor runs the fitted, no, half and twice springs)"
            )
    dt = 1e-3 if args.dt is None else args.dt
    settings = FloorStudySettings(scenario_key(args.scenario), args.duration, args.mu, dt, cases=not args.no_cases)
    check_output_folder(args.out, "--out")
    csv_path, png_path = floor_files(args.out, settings.scenario, args.force)
    study = floor_study(settings, on_case=lambda case: print(case_summary(case), flush=True))
    for path in write_floor(study, csv_path, png_path):
        print(f"wrote {path}")
    return 0
