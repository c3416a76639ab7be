"""``pasibot export-html``: the walking biped as one self-contained HTML file (meshcat).

The file embeds meshcat's viewer, the scene and the walk as a looping ``Animation``; it
plays offline in any browser with WebGL. Add ``#t=SECONDS`` to its address to pause the walk
at that time. The ``animation`` section of ``pasibot analyze`` (``gait.html`` and ``gait.gif``) is
:func:`pasibot_pin.report.animation.section`.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.cli.common import (
    add_design_option,
    add_force_option,
    add_fps_option,
    add_steps_option,
    check_output_file,
    design_of,
    file_path,
)
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.params import VARIANTS


def add_walk_view_options(parser: argparse.ArgumentParser) -> None:
    """``--variant``, ``--design``, ``--steps``, ``--samples-per-step``, ``--fps``, ``--reactions`` (with ``view``)."""
    parser.add_argument("--variant", default="spring", choices=VARIANTS, help="leg variant (default spring)")
    add_design_option(parser)
    add_steps_option(parser)
    parser.add_argument("--samples-per-step", type=int, default=30, help="animation frames per step (default 30)")
    add_fps_option(parser)
    parser.add_argument(
        "--reactions",
        type=float,
        default=None,
        metavar="OMEGA",
        help="draw the ground reaction and cut-joint forces at crank speed OMEGA [rad/s] (spring variant)",
    )


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("export-html", help="write the walk as one self-contained HTML file (meshcat animation)")
    p.add_argument(
        "--out",
        type=file_path,
        default=Path("gait.html"),
        metavar="FILE",
        help="HTML file to write (default gait.html)",
    )
    add_walk_view_options(p)
    p.add_argument(
        "--ground-reaction", action="store_true", help="draw the quasi-static ground reaction (0.5 mm per N)"
    )
    add_force_option(p, "overwrite an existing file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Export the walk; refuses to overwrite without ``--force`` (FileExistsError, exit code 2)."""
    from pasibot_pin.viz.viewer import export_html  # deferred: keeps the CLI's start fast

    check_output_file(args.out, "--out", args.force)
    design = design_of(args)
    export = export_html(
        args.out,
        robot=None if design is None else design_robot(design, 2),
        variant=args.variant,
        steps=args.steps,
        samples_per_step=args.samples_per_step,
        fps=args.fps,
        force=args.force,
        ground_reaction=args.ground_reaction,
        reactions=args.reactions,
    )
    size = export.path.stat().st_size / 1e6
    print(
        f"wrote {export.path} ({size:.1f} MB): {args.variant} biped, {args.steps} steps, "
        f"{len(export.q)} frames at {export.fps:g} fps ({export.duration:.2f} s, looping)"
    )
    return 0
