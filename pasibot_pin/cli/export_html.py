"""``pasibot export-html``: the walking biped as one self-contained HTML file (meshcat).

The file embeds meshcat's viewer, the scene and the walk as a looping ``Animation``; it
plays offline in any browser with WebGL. Add ``#t=SECONDS`` to its address to pause the walk
at that time. Also the ``animation`` step of ``pasibot analyze`` (``gait.html`` and ``gait.gif``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.model.params import VARIANTS


def add_walk_view_options(parser: argparse.ArgumentParser) -> None:
    """``--variant``, ``--steps``, ``--samples-per-step``, ``--fps``, ``--reactions`` (shared with ``pasibot view``)."""
    parser.add_argument("--variant", default="spring", choices=VARIANTS, help="leg variant (default spring)")
    parser.add_argument("--steps", type=int, default=2, help="steps to walk, one per half crank turn (default 2)")
    parser.add_argument("--samples-per-step", type=int, default=30, help="animation frames per step (default 30)")
    parser.add_argument("--fps", type=float, default=30.0, help="animation frames per second (default 30)")
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
    p.add_argument("--out", type=Path, default=Path("gait.html"), help="HTML file to write (default gait.html)")
    add_walk_view_options(p)
    p.add_argument(
        "--ground-reaction", action="store_true", help="draw the quasi-static ground reaction (0.5 mm per N)"
    )
    p.add_argument("--force", action="store_true", help="overwrite an existing file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Export the walk; refuses to overwrite without ``--force`` (FileExistsError, exit code 2)."""
    from pasibot_pin.viz.viewer import export_html

    export = export_html(
        args.out,
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


def analyze_step(out_dir: Path, args: argparse.Namespace) -> str:
    """``pasibot analyze`` step: ``gait.html`` (3-D, meshcat) and ``gait.gif`` (2-D stick figure)."""
    import math

    import numpy as np

    from pasibot_pin.model.closure import constraint_residual
    from pasibot_pin.model.robot import load
    from pasibot_pin.viz.animation import save_gif
    from pasibot_pin.viz.viewer import export_html

    variant, steps, samples, fps = "spring", 2, 30, 30.0
    robot = load(variant, legs=2)
    omega = math.pi * fps / samples  # the crank speed at which the animation plays [rad/s]
    export = export_html(
        out_dir / "gait.html", robot, steps=steps, samples_per_step=samples, fps=fps, force=True, reactions=omega
    )
    stride = 2  # every other frame: 15 GIF frames per step, played at the same speed as the HTML
    gif_qs = export.q[::stride]
    save_gif(robot, gif_qs, out_dir / "gait.gif", fps=fps / stride, force=True)
    worst = max(float(np.abs(constraint_residual(robot, q, robot.loop_constraints)).max()) for q in export.q)
    return "\n".join(
        [
            "## Watch it walk",
            "",
            f"The {variant} biped walks {steps} steps (one step per half crank turn; the stance foot is welded flat).",
            f"[gait.html](gait.html) is one self-contained page (meshcat, {len(export.q)} frames at {fps:g} fps,"
            " looping; open it in any browser, add `#t=1.0` to the address to pause at 1 s).",
            f"Largest loop-closure residual over the exported frames: {worst:.1e} m.",
            f"Arrows (from the constrained inverse dynamics at the playback crank speed {omega:.3f} rad/s):"
            " magenta, the ground reaction through the centre of pressure (0.5 mm/N); yellow, the force"
            " on the first link of each cut joint (the largest drawn 0.15 m long).",
            "",
            f"![2-D stick animation, {len(gif_qs)} frames](gait.gif)",
        ]
    )
