"""``pasibot view``: a live 3-D viewer (meshcat, 127.0.0.1 only) that plays the walk.

The browser opens only with ``--open``; otherwise the viewer's address is printed. The
command never waits forever: it plays the walk ``--repeat`` times (default once), keeps the
server up for ``--hold`` more seconds (default 0), then exits. ``--hold -1`` serves until
Ctrl-C.
"""

from __future__ import annotations

import argparse
import math
import time

from pasibot_pin.cli.common import design_of
from pasibot_pin.cli.export_html import add_walk_view_options
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.robot import load


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("view", help="live 3-D viewer in the browser (meshcat) playing the walk")
    add_walk_view_options(p)
    p.add_argument("--open", action="store_true", help="open the viewer in the default web browser")
    p.add_argument("--repeat", type=int, default=1, help="plays of the walk before exiting (default 1)")
    p.add_argument(
        "--hold", type=float, default=0.0, help="seconds to serve after the last play (default 0; -1: until Ctrl-C)"
    )
    p.add_argument("--zmq-url", default=None, help="reuse a running meshcat-server (e.g. tcp://127.0.0.1:6000)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Start the viewer, play the gait live, hold, exit."""
    from pasibot_pin.viz.viewer import (  # deferred: keeps the CLI's start fast
        WalkViewer,
        build_walk_scene,
        check_meshcat_server,
        gait_trajectory,
        reaction_forces,
    )

    if args.repeat < 1:
        raise ParameterError(f"--repeat must be >= 1, got {args.repeat}")
    if not (math.isfinite(args.hold) and (args.hold >= 0 or args.hold == -1)):
        raise ParameterError(f"--hold must be >= 0 s or -1 (until Ctrl-C), got {args.hold}")
    if not (math.isfinite(args.fps) and args.fps > 0):
        raise ParameterError(f"--fps must be a positive frame rate [1/s], got {args.fps}")
    if args.zmq_url is not None:
        check_meshcat_server(args.zmq_url)
    design = design_of(args)
    robot = load(args.variant, legs=2) if design is None else design_robot(design, 2)
    gait = gait_trajectory(robot, steps=args.steps, samples_per_step=args.samples_per_step)
    forces = None if args.reactions is None else reaction_forces(robot, gait, omega=args.reactions)
    viewer = WalkViewer(robot, zmq_url=args.zmq_url, open=args.open)
    try:
        # the gait is also stored as an animation, paused: scrub it in the viewer's controls
        build_walk_scene(viewer, gait.q, args.fps, forces=forces, play=False, repetitions=1)
        print(f"viewer: {viewer.url}", flush=True)
        if args.open:
            time.sleep(2.0)  # let the page connect before the first frame
        duration = len(gait.q) / args.fps * args.repeat
        print(
            f"playing {args.steps} step{'' if args.steps == 1 else 's'} "
            f"({len(gait.q)} frames at {args.fps:g} fps, {duration:.1f} s)",
            flush=True,
        )
        viewer.play(gait.q, fps=args.fps, repetitions=args.repeat)
        if args.hold == -1:
            print("serving until Ctrl-C", flush=True)
            try:
                while True:
                    time.sleep(1.0)
            except KeyboardInterrupt:
                pass
        elif args.hold > 0:
            time.sleep(args.hold)
    finally:
        viewer.close()
    return 0
