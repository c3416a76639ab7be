"""Figures of the 3-D walking map: the outcome over the feet's lateral reach x crank speed.

One panel per foot family (:mod:`pasibot_pin.studies.walking_map3d`): the comb's reach past the
midline, and the legs' spacing with centred plates. Each cell is coloured by our 3-D verdict; a dot
in its corner by the MuJoCo twin's on the 3-D export (no dot: not run). The cell's text is ``W``
(walks) or the steps taken, and the largest hip roll [deg].
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pasibot_pin.files import atomic_path
from pasibot_pin.viz.figure_files import save_figure_file
from pasibot_pin.viz.plots_walking import OUTCOME_COLOURS

COLOURS_3D: dict[str, str] = {**OUTCOME_COLOURS, "tipped": "#8c564b", "collided": "#17becf", "refused": "#000000"}
"""The colour of each 3-D outcome (the planar ones, ``tipped``, ``collided`` and ``refused``)."""

AXIS_LABELS: dict[str, str] = {
    "comb": "comb prong's reach past the midline [L]",
    "narrow": "leg plane to midline, centred 1.2 L plates [L]",
}


def plot_walking_map3d(wmap, feet: str, ax=None, twin: bool = True):
    """The outcome of one foot family's cells over its lateral value [L] x crank speed [rad/s].

    Args:
        wmap: a :class:`~pasibot_pin.studies.walking_map3d.WalkingMap3D`.
        feet: ``comb`` or ``narrow``.
        ax: axes to draw on (default: a new figure).
        twin: mark the MuJoCo twin's outcome (a dot) where it ran.

    Returns:
        The figure.

    """
    from matplotlib.patches import Circle, Rectangle  # deferred: heavy (matplotlib), keeps the CLI's start fast

    if ax is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        _fig, ax = subplots(figsize=(4.8, 4.2))
    cells = wmap.family(feet)
    values = sorted({c.value for c in cells}, reverse=feet == "narrow")  # support nearer the body to the right
    omegas = sorted({c.omega for c in cells})
    for c in cells:
        i, j = values.index(c.value), omegas.index(c.omega)
        ax.add_patch(Rectangle((i - 0.5, j - 0.5), 1, 1, facecolor=COLOURS_3D.get(c.outcome, "white"),
                               edgecolor="white", lw=1.5))  # fmt: skip
        label = "W" if c.walks else str(c.steps)
        roll = "" if not np.isfinite(c.max_hip_roll_deg) else f"\n{min(c.max_hip_roll_deg, 99):.1f} deg"
        ax.text(i, j, label + roll, ha="center", va="center", fontsize=7, color="white")
        if twin and c.twin_outcome:
            dot = COLOURS_3D.get(c.twin_outcome, "white")
            ax.add_patch(Circle((i + 0.3, j + 0.3), 0.12, facecolor=dot, edgecolor="black", lw=0.6))
    ax.set_xlim(-0.5, len(values) - 0.5)
    ax.set_ylim(-0.5, len(omegas) - 0.5)
    ax.set_aspect("equal")
    ax.set_xticks(np.arange(len(values)), [f"{v:g}" for v in values])
    ax.set_yticks(np.arange(len(omegas)), [f"{w:g}" for w in omegas])
    ax.set_xlabel(AXIS_LABELS.get(feet, f"{feet} [L]"))
    ax.set_ylabel("crank speed omega [rad/s]")
    ax.set_title(f"{feet}: {sum(c.walks for c in cells)} of {len(cells)} walk upright")
    return ax.figure


def walking_map3d_figure(wmap):
    """One panel per foot family and a legend of the outcomes.

    Returns:
        The figure.

    """
    from matplotlib.patches import Circle, Patch  # deferred: heavy (matplotlib), keeps the CLI's start fast

    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    families = list(dict.fromkeys(c.feet for c in wmap.cells))
    widths = [len({c.value for c in wmap.family(feet)}) for feet in families]  # one cell the same size everywhere
    fig, axes = subplots(1, len(families), figsize=(1.0 * sum(widths) + 3.5, 4.4), squeeze=False,
                         gridspec_kw={"width_ratios": widths})  # fmt: skip
    for ax, feet in zip(axes[0], families):
        plot_walking_map3d(wmap, feet, ax=ax)
    seen = [o for o in COLOURS_3D if any(c.outcome == o or c.twin_outcome == o for c in wmap.cells)]
    handles = [Patch(facecolor=COLOURS_3D[o], label=o) for o in seen]
    handles.append(Circle((0, 0), 1, facecolor="white", edgecolor="black", label="dot: MuJoCo twin (3-D export)"))
    axes[0][-1].legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    fig.suptitle(
        f"Does it walk {wmap.steps} steps in 3-D without tipping? (W walks, else steps taken; largest hip roll)",
        fontsize=10,
    )
    return fig


def save_walking_map3d_figure(wmap, path: Path, dpi: float = 110) -> Path:
    """Draw :func:`walking_map3d_figure` and write it to ``path`` (PNG)."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig = walking_map3d_figure(wmap)
    with atomic_path(Path(path)) as tmp:
        save_figure_file(fig, tmp, dpi)
    plt.close(fig)
    return Path(path)
