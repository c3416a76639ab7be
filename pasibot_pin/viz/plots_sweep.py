"""Figures of a design sweep: the Pareto front of two metrics, and which parameter drives which metric."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pasibot_pin.model.design import SPECS
from pasibot_pin.studies.design_metrics import ALL_METRICS, pareto_mask


def _metrics() -> dict:
    return dict(ALL_METRICS)


def _label(name: str) -> str:
    METRICS = _metrics()

    if name in METRICS:
        unit = METRICS[name].unit
        return f"{name} [{unit}]"
    if name in SPECS:
        return f"{name} [{SPECS[name].unit}]"
    return name


def _values(table, name: str) -> np.ndarray:
    return np.asarray(table.column(name).to_numpy(zero_copy_only=False), dtype=float)


def pareto_masks(table, x: str, y: str, constraints: Sequence = ()) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which rows are feasible, which of those satisfy every constraint, and which of those are on the front.

    Args:
        table: a sweep's results (pyarrow Table).
        x: the metric along x (its ``sense`` in the metrics' table, else min).
        y: the metric along y (its ``sense``, else max).
        constraints: objects with ``metric`` and ``violation(value)`` (<= 0: satisfied), e.g. an
            optimisation's ``--constraint``s (:class:`~pasibot_pin.explore.optimize.Constraint`).

    Returns:
        (feasible, satisfied, front): boolean masks over the table's rows; ``satisfied`` implies
        ``feasible`` and ``front`` implies ``satisfied`` (a design that violates a constraint is never on it).

    """
    metrics = _metrics()
    feasible = np.asarray(table.column("feasible").to_numpy(zero_copy_only=False), dtype=bool)
    satisfied = feasible.copy()
    for c in constraints:
        satisfied &= np.array([c.violation(float(v)) <= 0 for v in _values(table, c.metric)], dtype=bool)
    front = np.zeros(len(feasible), dtype=bool)
    if satisfied.any():
        senses = (metrics[x].sense or "min", metrics[y].sense or "max")
        front[satisfied] = pareto_mask(_values(table, x)[satisfied], _values(table, y)[satisfied], senses)
    return feasible, satisfied, front


def plot_pareto(
    table,
    x: str = "peak_crank_torque_Nm",
    y: str = "stride_m",
    ax=None,
    color: str = "cop_margin_m",
    constraints: Sequence = (),
):
    """The designs in the (x, y) plane and the Pareto front (x as low, y as high as can be) of those that count.

    Only feasible designs that satisfy every constraint are coloured and can be on the front; feasible
    designs that violate a constraint are drawn grey, off the front (:func:`pareto_masks`).

    Args:
        table: a sweep's results (pyarrow Table).
        x: the metric along x (lower is better unless its ``sense`` in
            :data:`~pasibot_pin.studies.design_metrics.METRICS` says otherwise).
        y: the metric along y (higher is better unless its ``sense`` says otherwise).
        ax: axes to draw on (default: a new figure).
        color: the metric that colours the points.
        constraints: the optimisation's constraints (``metric``, ``violation(value)``), if any.

    Returns:
        The figure.

    """
    metrics = _metrics()
    if ax is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        fig, ax = subplots(figsize=(6.4, 4.6))
    fig = ax.figure
    ok, good, front = pareto_masks(table, x, y, constraints)
    xs, ys, cs = _values(table, x), _values(table, y), _values(table, color)
    grey = ok & ~good
    if grey.any():
        named = ", ".join(c.text() if hasattr(c, "text") else c.metric for c in constraints)
        ax.scatter(xs[grey], ys[grey], s=10, color="#c8c8c8", label=f"violate {named} ({grey.sum()})")
    what = "feasible designs" + (" within the constraints" if constraints else "")
    points = ax.scatter(
        xs[good], ys[good], c=cs[good], s=12, cmap="viridis", label=f"{what} ({good.sum()} of {len(ok)})"
    )
    fig.colorbar(points, ax=ax, label=_label(color))
    order = np.argsort(xs[front])
    ax.plot(xs[front][order], ys[front][order], "o-", color="crimson", ms=4, lw=1.2, label="Pareto front")
    senses = (metrics[x].sense or "min", metrics[y].sense or "max")
    ax.set_xlabel(_label(x))
    ax.set_ylabel(_label(y))
    ax.set_title(f"{x} ({senses[0]}) against {y} ({senses[1]})")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def rank_correlations(table, varied: Sequence[str], metrics: Sequence[str]) -> np.ndarray:
    """Spearman rank correlation of each varied parameter (rows) with each metric (columns), feasible designs."""
    from scipy.stats import spearmanr  # deferred: optional extra (scipy)

    ok = np.asarray(table.column("feasible").to_numpy(zero_copy_only=False), dtype=bool)
    out = np.full((len(varied), len(metrics)), np.nan)
    if ok.sum() < 3:
        return out
    for i, p in enumerate(varied):
        for j, m in enumerate(metrics):
            a, b = _values(table, p)[ok], _values(table, m)[ok]
            if np.ptp(a) > 0 and np.ptp(b) > 0:
                out[i, j] = spearmanr(a, b).statistic
    return out


def plot_sensitivity(table, varied: Sequence[str], metrics: Sequence[str] | None = None, ax=None):
    """Heat map of the rank correlation of every varied parameter with every metric (-1 .. 1).

    Returns:
        The figure.

    """
    names = [m for m in _metrics() if m in table.column_names]
    metrics = list(metrics or [m for m in names if np.isfinite(_values(table, m)).any()])
    rho = rank_correlations(table, varied, metrics)
    if ax is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        fig, ax = subplots(figsize=(1.0 + 0.55 * len(metrics), 3.0 + 0.4 * len(varied)))
    fig = ax.figure
    image = ax.imshow(rho, cmap="RdBu_r", vmin=-1, vmax=1, aspect="auto")
    ax.set_xticks(range(len(metrics)), [_label(m) for m in metrics], rotation=60, ha="right", fontsize=8)
    ax.set_yticks(range(len(varied)), [_label(p) for p in varied], fontsize=8)
    for i in range(rho.shape[0]):
        for j in range(rho.shape[1]):
            if np.isfinite(rho[i, j]):
                ax.text(j, i, f"{rho[i, j]:.2f}", ha="center", va="center", fontsize=6)
    fig.colorbar(image, ax=ax, label="Spearman rank correlation [-]")
    ax.set_title("Which parameter drives which metric (feasible designs)")
    return fig
