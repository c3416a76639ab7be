"""``pasibot walk``: does a design walk? It is put on the floor and its walk is judged.

The design (``--design FILE``, else the seed's; ``--variant`` and ``--omega`` override it)
starts from a consistent state on the floor, its cranks turn at its speed after a smooth ramp,
and the run stops as soon as the verdict is decided: ``walks`` after ``--steps`` steps, or a
named failure (fell, rolled, slipped, stalled, hopped, stepped_back, tripped on a step edge, diverged;
infeasible_start: the pose it settles into before the cranks turn already breaks a limit, named with its
value). It prints the outcome, the steps, the advance, the largest hip pitch, the slip, the motor torque
and power and the cost of transport; ``--json`` prints one JSON object instead. ``--stability`` adds the Floquet
multipliers of the gait (a fixed point of the step-to-step map, found by shooting).
``--html``/``--gif`` write the walk on the floor with its contact forces. The frontal ZMP line
says whether the soles could hold the planar walk upright sideways; ``--3d`` walks it with the hip
free to roll (its ``--gif``: the side view and the view from behind, the hip's roll in the caption).
``--slope DEG`` tilts the ground; ``--step-height M --step-at M`` puts a step edge on it (its treads
only: a heel or toe that hits the riser has ``tripped``); the GIF and the page draw that ground.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from pasibot_pin.cli.common import (
    add_design_option,
    add_force_option,
    add_mu_option,
    add_out_folder_option,
    add_robot_options,
    check_output_file,
    check_output_folder,
    design_of,
    given,
)
from pasibot_pin.errors import NoFixedPointError, ParameterError
from pasibot_pin.files import OutputFolder
from pasibot_pin.model.design import Design, design_robot

MAX_STEPS = 1000
"""Most steps ``--steps`` takes [-]."""


def check_steps(text: str) -> int:
    """``--steps``: an integer in [1, :data:`MAX_STEPS`], else a one-line ParameterError naming the flag."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 1 <= value <= MAX_STEPS:
        raise ParameterError(f"--steps must be an integer in [1, {MAX_STEPS}], got {text!r}")
    return value


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("walk", help="put a design on the floor: does it walk?", description=__doc__)
    add_design_option(p)
    add_robot_options(p, legs=False)  # --variant given overrides the design's variant
    p.add_argument("--omega", type=float, default=None, help="override the crank speed [rad/s]")
    p.add_argument("--steps", default="20", metavar="N", help=f"steps to walk, 1 to {MAX_STEPS} (default 20)")
    add_mu_option(p)
    p.add_argument("--slope", type=float, default=0.0, metavar="DEG",
                   help="the ground's slope, uphill positive [deg] (default 0: flat)")  # fmt: skip
    p.add_argument("--step-height", type=float, default=0.0, metavar="M",
                   help="a step edge on the ground, up positive [m] (default 0: none; planar walks only; "
                        "a heel or toe that hits its riser has tripped)")  # fmt: skip
    p.add_argument("--step-at", type=float, default=0.0, metavar="M",
                   help="where the step edge is along the ground [m] (default 0; the world's x)")  # fmt: skip
    p.add_argument(
        "--3d",
        dest="spatial",
        action="store_true",
        help="walk in 3-D: a free hip that can roll and yaw, the soles' corners (sole_inner, sole_outer)",
    )
    p.add_argument("--stability", action="store_true", help="also the gait's Floquet multipliers (shooting)")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    p.add_argument("--html", action="store_true", help="also write the walk as a meshcat page (walk_NAME.html)")
    p.add_argument(
        "--gif",
        action="store_true",
        help="also write the walk as a stick GIF, 640 px wide, its camera following the robot (walk_NAME.gif; with "
        "--3d: its side view and its view from behind, 960 px wide)",
    )
    add_out_folder_option(p, Path("out"), "the animations (NAME: the design file's stem, else the variant)")
    add_force_option(p, "overwrite existing animations")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Check the flags and files, walk the design, print the answer, write the files."""
    steps = check_steps(args.steps)  # --omega: checked once, by cli/bounds.py, in the design record's range
    name = args.design.stem if args.design is not None else (args.variant if given(args, "variant") else "seed")
    html = gif = None
    if given(args, "out") and not (args.html or args.gif):
        raise ParameterError("--out names the folder of --gif and --html: give one of them, or leave --out out")
    if args.html or args.gif:
        check_output_folder(args.out, "--out")
        html = check_output_file(args.out / f"walk_{name}.html", "--out", args.force) if args.html else None
        gif = check_output_file(args.out / f"walk_{name}.gif", "--out", args.force) if args.gif else None
    design = design_of(args) or Design()
    if given(args, "variant"):
        design = design.with_(variant=args.variant)
    if args.omega is not None:
        design = design.with_(omega=args.omega)
    from pasibot_pin.studies.walking import check_walk_budget, walk_cost  # deferred: keeps the CLI's start fast

    check_walk_budget(
        walk_cost(design.omega, steps, spatial=args.spatial), f"--steps {steps} at --omega {design.omega:g} rad/s"
    )
    if args.spatial and args.step_height:
        raise ParameterError("--step-height is the planar floor's so far: walk without --3d")
    if html is None and gif is None:
        run_walk = _run_3d if args.spatial else _run_planar
        return run_walk(design, steps, args, None, None)
    folder = OutputFolder(args.out).claim()  # one writer per folder, refused at once (--force: per file, above)
    try:
        code = _run_3d(design, steps, args, html, gif) if args.spatial else _run_planar(design, steps, args, html, gif)
    except BaseException:
        folder.discard()  # what this run added, and the folders it made
        raise
    folder.release()
    return code


def _run_planar(design: Design, steps: int, args: argparse.Namespace, html: Path | None, gif: Path | None) -> int:
    """``walk``: the verdict on the planar floor, its margins, motor and frontal ZMP (``html``/``gif``: the files)."""
    from pasibot_pin.report.walking import (  # deferred: keeps the CLI's start fast
        verdict_json,
        walk_lines,
        write_walk_animation,
    )
    from pasibot_pin.studies.walking import WalkSettings, walk_design  # deferred: keeps the CLI's start fast

    settings = WalkSettings(
        steps=steps, mu=args.mu, slope=math.radians(args.slope), step_height=args.step_height, step_at=args.step_at
    )
    robot = design_robot(design, 2, visuals=html is not None)
    walk = walk_design(design, settings, robot, progress=_progress(args))
    stability, no_gait = None, ""
    if args.stability and not walk.verdict.walks:
        no_gait = f"stability: no periodic gait to linearise (the design {walk.verdict.outcome})"
    elif args.stability:
        from pasibot_pin.studies.gait_stability import gait_stability  # deferred: keeps the CLI's start fast

        try:
            stability = gait_stability(design, walk, robot=robot)
        except NoFixedPointError as err:  # an outcome, not a failure of the command
            no_gait = f"stability: no fixed point near the walk ({err})"
    from pasibot_pin.studies.frontal_zmp import frontal_zmp  # deferred: keeps the CLI's start fast

    zmp = frontal_zmp(robot, walk.result, design.footprint())
    if args.json:
        out = verdict_json(walk, stability)
        out["frontal_zmp_margin_mm"] = None if math.isnan(zmp.min_margin) else 1000 * zmp.min_margin
        if args.stability and stability is None:
            out.update(multipliers=None, stable=False, stability_note=no_gait)
        print(json.dumps(out), flush=True)
    else:
        for line in walk_lines(walk):
            print(line, flush=True)
        print(f"sideways (planar walk, {_plates(design)}): {zmp.summary()}", flush=True)
        if args.stability:
            print(stability.summary() if stability is not None else no_gait, flush=True)
    written = write_walk_animation(walk, robot, html, gif, progress=_progress(args))
    for path in written if not args.json else ():
        print(f"wrote {path}")
    if (html or gif) and not written:
        print("no animation written: the walk has no sample to draw (it diverged at its start)", file=sys.stderr)
    return 0


def _plates(design: Design) -> str:
    """The soles' lateral reach in words, for the frontal ZMP's line."""
    return f"soles {design.sole_outer:g} L outside and {design.sole_inner:g} L inside each leg's plane"


def _bridge(design: Design, walk, robot):
    """How high a comb sole's bridge must arch over the other foot in this walk (``None``: a plain plate)."""
    from pasibot_pin.model.spatial import free_flyer_model  # deferred: keeps the CLI's start fast
    from pasibot_pin.studies.bridge3d import bridge_need  # deferred: keeps the CLI's start fast

    return bridge_need(free_flyer_model(robot.model), walk.result.q, design.footprint())


def _progress(args: argparse.Namespace) -> bool:
    """Whether the walk shows a progress bar: on a terminal's stderr, not for --json (a script reads that)."""
    return not args.json and sys.stderr.isatty()


def _run_3d(design: Design, steps: int, args: argparse.Namespace, html: Path | None, gif: Path | None) -> int:
    """``walk --3d``: the verdict on the 3-D floor and the sideways figures (``html``/``gif``: the walk's files)."""
    from pasibot_pin.studies.walking import WalkSettings, walk_design_3d  # deferred: keeps the CLI's start fast

    robot = design_robot(design, 2, visuals=html is not None)
    settings = WalkSettings(steps=steps, mu=args.mu, slope=math.radians(args.slope))
    walk = walk_design_3d(design, settings, robot, progress=_progress(args))
    if html is not None:
        from pasibot_pin.report.walking import write_walk3d_page  # deferred: keeps the CLI's start fast

        write_walk3d_page(walk, robot, design.footprint(), html)
    if gif is not None:
        from pasibot_pin.report.walking import write_walk3d_gif  # deferred: keeps the CLI's start fast

        write_walk3d_gif(walk, robot, design.footprint(), gif, progress=_progress(args))
    figures = walk.figures()
    bridge = _bridge(design, walk, robot)
    stability, note = _stability_3d(design, walk, robot) if args.stability else (None, "")
    if args.json:
        verdict = walk.verdict
        out: dict[str, object] = {
            "outcome": verdict.outcome,
            "walks": verdict.walks,
            "steps": verdict.steps,
            "decided_at_s": verdict.decided_at,
            "detail": verdict.detail,
            "advance_m": verdict.advance_m,
            "omega_rad_s": walk.omega,
            "dt_s": walk.dt,
            "model": "3d",
            **figures,
            "settled_at_s": None if math.isnan(figures["settled_at_s"]) else figures["settled_at_s"],
            "bridge_heel_m": None if bridge is None else bridge.heel_m,
            "bridge_toe_m": None if bridge is None else bridge.toe_m,
        }
        if args.stability:
            out["multipliers"] = None if stability is None else [[z.real, z.imag] for z in stability.multipliers]
            out["stable"] = stability is not None and stability.stable
            out["stability_note"] = stability.summary() if stability is not None else note
        print(json.dumps(out), flush=True)
        return 0
    print(walk.verdict.summary(), flush=True)
    for written in (html, gif):
        if written is not None:
            print(f"wrote {written}", flush=True)
    print(
        f"3-D: max |hip roll| {figures['max_hip_roll_deg']:.2f} deg (margin {figures['roll_margin_deg']:+.2f} deg "
        f"to tipping), yaw {figures['yaw_per_step_deg']:+.3f} deg/step, "
        f"lateral drift {1000 * figures['lateral_drift_m']:+.1f} mm, "
        f"soles at least {1000 * figures['min_sole_clearance_m']:.1f} mm apart, "
        f"a leg at least {1000 * figures['leg_clearance_m']:.1f} mm from the other",
        flush=True,
    )
    if bridge is not None:
        print(f"comb soles: {bridge.summary()}", flush=True)
    if not math.isnan(figures["settled_at_s"]):
        print(f"the gait settled at {figures['settled_at_s']:.2f} s: each later crank turn repeats the one before")
    if args.stability:
        print(stability.summary() if stability is not None else note, flush=True)
    return 0


def _stability_3d(design: Design, walk, robot):
    """(the 3-D gait's stability, or ``None`` and why not): an outcome, never an error."""
    if not walk.verdict.walks:
        return None, f"stability: no periodic gait to linearise (the design {walk.verdict.outcome})"
    from pasibot_pin.studies.gait_stability3d import gait_stability_3d  # deferred: keeps the CLI's start fast

    try:
        return gait_stability_3d(design, robot=robot), ""
    except (NoFixedPointError, ParameterError) as err:  # a springed variant, or no gait near the planar one
        return None, f"stability: no 3-D fixed point near the walk ({err})"
