"""Figures of the walking map: the outcome over sole length x crank speed, one panel per variant.

Each cell is coloured by our walking verdict's outcome; where the MuJoCo twin ran, a dot in the
cell's corner is coloured by the twin's outcome (no dot: not run). The grid is drawn by index
(the soles and speeds are not evenly spaced), labelled with the values.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pasibot_pin.files import atomic_path
from pasibot_pin.viz.figure_files import save_figure_file

OUTCOME_COLOURS: dict[str, str] = {
    "walks": "#2ca02c",
    "fell": "#d62728",
    "rolled": "#ff7f0e",
    "slipped": "#1f77b4",
    "stalled": "#9467bd",
    "hopped": "#e377c2",
    "stepped_back": "#17becf",
    "diverged": "#7f7f7f",
    "infeasible_start": "#8c564b",
    "undecided": "#bcbd22",
    "infeasible": "#000000",
}
"""The colour of each outcome (the verdict's, plus ``infeasible``: the design cannot be built)."""


def plot_walking_map(wmap, variant: str, ax=None, twin: bool = True):
    """The outcome of ``variant``'s cells over sole [L] x crank speed [rad/s].

    Args:
        wmap: a :class:`~pasibot_pin.studies.walking_map.WalkingMap`.
        variant: the variant to draw.
        ax: axes to draw on (default: a new figure).
        twin: mark the MuJoCo twin's outcome (a dot) where it ran.

    Returns:
        The figure.

    """
    from matplotlib.patches import Circle, Rectangle  # deferred: heavy (matplotlib), keeps the CLI's start fast

    if ax is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        _fig, ax = subplots(figsize=(4.6, 4.2))
    soles, omegas = wmap.soles, wmap.omegas
    for i, sole in enumerate(soles):
        for j, omega in enumerate(omegas):
            cell = wmap.cell(variant, sole, omega)
            colour = OUTCOME_COLOURS.get(cell.outcome, "white")
            ax.add_artist(Rectangle((i - 0.5, j - 0.5), 1, 1, facecolor=colour, edgecolor="white", lw=1.5))
            label = str(cell.steps) if cell.outcome != "walks" else "W"
            ax.text(i, j, label, ha="center", va="center", fontsize=7, color="white")
            if twin and cell.twin_outcome:
                dot = OUTCOME_COLOURS.get(cell.twin_outcome, "white")
                ax.add_artist(Circle((i + 0.3, j + 0.3), 0.12, facecolor=dot, edgecolor="black", lw=0.6))
    ax.set_xlim(-0.5, len(soles) - 0.5)
    ax.set_ylim(-0.5, len(omegas) - 0.5)
    ax.set_xticks(np.arange(len(soles)), [f"{s:g}" for s in soles])
    ax.set_yticks(np.arange(len(omegas)), [f"{w:g}" for w in omegas])
    ax.set_xlabel("sole each side of the ankle, toe = heel [L]")
    ax.set_ylabel("crank speed omega [rad/s]")
    ax.set_title(f"{variant}: {sum(wmap.cell(variant, s, w).walks for s in soles for w in omegas)} walkers")
    return ax.figure


def walking_map_figure(wmap):
    """One panel per variant and a legend of the outcomes (W: walks; a number: steps before the failure).

    Returns:
        The figure.

    """
    from matplotlib.patches import Patch  # deferred: heavy (matplotlib), keeps the CLI's start fast

    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    variants = wmap.variants
    fig, axes = subplots(1, len(variants), figsize=(4.2 * len(variants), 4.6), squeeze=False)
    for ax, variant in zip(axes[0], variants):
        plot_walking_map(wmap, variant, ax=ax)
    seen = [o for o in OUTCOME_COLOURS if any(c.outcome == o or c.twin_outcome == o for c in wmap.cells)]
    handles = [Patch(facecolor=OUTCOME_COLOURS[o], label=o) for o in seen]
    axes[0][-1].legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    ran = any(c.twin_outcome for c in wmap.cells)
    twin = "MuJoCo twin: not run" if not ran else "dot: MuJoCo twin" + (f", {wmap.twin_note}" if wmap.twin_note else "")
    head = f"Does it walk {wmap.steps} steps? (cell: our verdict, W walks, else steps taken; {twin})"
    fig.suptitle(head, fontsize=10)
    return fig


def save_walking_map_figure(wmap, path: Path, dpi: float = 110) -> Path:
    """Draw :func:`walking_map_figure` and write it to ``path`` (PNG)."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig = walking_map_figure(wmap)
    with atomic_path(Path(path)) as tmp:
        save_figure_file(fig, tmp, dpi)
    plt.close(fig)
    return Path(path)
