"""A cheap layout engine for the report's figures: margins from the text the axes will draw.

Matplotlib's constrained layout measures every axes' tight bounding box (every tick label laid out,
twice) before the figure is drawn, which costs more than the drawing. :class:`MarginLayout` instead
estimates, per axes, how far its tick labels, axis labels, title, offset text and any legend anchored
outside it reach beyond it [in], from the strings and their font metrics only (no tick is laid out),
and sets the figure's subplot parameters (``subplots_adjust``) so that everything stays inside the
figure and neighbouring panels do not overlap. It runs at every draw, like any layout engine, so a
figure made with ``ax=None`` in a notebook lays itself out too.

Only figures whose axes sit on one grid (``plt.subplots``; colorbars and twin axes inside its cells)
are laid out; any other axes are left where they are.
"""

from __future__ import annotations

import numpy as np
from matplotlib.layout_engine import LayoutEngine
from matplotlib.text import (  # type: ignore[attr-defined]  # _get_text_metrics_with_cache: matplotlib's own cache
    Text,
    _get_text_metrics_with_cache,
)
from matplotlib.ticker import AutoLocator, MaxNLocator

PAD = 4.0 / 72.0
"""Space kept free at the figure's edges and between panels [in]."""

LINE_HEIGHT = 1.2
"""Height of a line of text, in font sizes (matplotlib's line spacing)."""

_POINT = 1.0 / 72.0  # [in]


def _text_size(renderer, text: Text, s: str | None = None) -> tuple[float, float]:
    """(width, height) [in] of ``text`` (or of the string ``s`` in its font), unrotated; multi-line aware.

    The width comes through matplotlib's own per-renderer cache of text metrics (the one ``Text`` measures
    itself with when drawn), so a tick label measured here is not measured again when it is drawn, and the
    figure's draw measures it the same way (the same call, the same numbers).
    """
    s = text.get_text() if s is None else s
    if not s or not text.get_visible():
        return 0.0, 0.0
    prop = text.get_fontproperties()
    width = 0.0
    lines = s.split("\n")
    for line in lines:
        body, ismath = text._preprocess_math(line)  # type: ignore[attr-defined]  # matplotlib's own splitting
        w, _, _ = _get_text_metrics_with_cache(renderer, body, prop, ismath, renderer.dpi)
        width = max(width, w)
    height = len(lines) * LINE_HEIGHT * prop.get_size_in_points() / 72.0
    return width / renderer.dpi, height


def _rotated(size: tuple[float, float], rotation: float) -> tuple[float, float]:
    """(width, height) of a box of ``size`` turned by ``rotation`` [deg]."""
    c, s = abs(np.cos(np.radians(rotation))), abs(np.sin(np.radians(rotation)))
    return size[0] * c + size[1] * s, size[0] * s + size[1] * c


def _axis_reach(renderer, axis, length: float, fracs_axis: int) -> dict[str, float]:
    """How far an axis' tick labels, label and offset text reach beyond the axes, per side [in].

    Args:
        renderer: the figure's renderer (text metrics).
        axis: an x or y axis.
        length: the axes' extent along the axis [in].
        fracs_axis: 0 for an x axis, 1 for a y axis.

    """
    ax = axis.axes
    reach = {"left": 0.0, "right": 0.0, "bottom": 0.0, "top": 0.0}
    if not axis.get_visible():
        return reach
    along = ("left", "right") if fracs_axis == 0 else ("bottom", "top")
    tick = axis.majorTicks[0]
    locs = np.asarray(axis.get_majorticklocs(), dtype=float)
    frac = locs
    if locs.size:
        point = np.zeros((locs.size, 2))
        point[:, fracs_axis] = locs
        frac = (ax.transScale + ax.transLimits).transform(point)[:, fracs_axis]
        inside = (frac > -1e-9) & (frac < 1 + 1e-9)
        locs, frac = locs[inside], frac[inside]
    labels = axis.get_major_formatter().format_ticks(list(locs)) if locs.size else []
    sides = [(tick.label1, 0), (tick.label2, 1)]
    for label, which in sides:
        if not label.get_visible():
            continue
        across = ("bottom", "top")[which] if fracs_axis == 0 else ("left", "right")[which]
        deepest = 0.0
        for text, f in zip(labels, frac):
            w, h = _rotated(_text_size(renderer, label, text), label.get_rotation())
            deepest = max(deepest, h if fracs_axis == 0 else w)
            half = (w if fracs_axis == 0 else h) / 2.0
            reach[along[0]] = max(reach[along[0]], half - f * length)
            reach[along[1]] = max(reach[along[1]], half - (1 - f) * length)
        out = tick.get_tick_padding() + tick.get_pad()
        reach[across] = max(reach[across], deepest + out * _POINT)
    offset = axis.get_major_formatter().get_offset() if len(labels) else ""  # drawn as the offset text
    offset_h = _text_size(renderer, axis.offsetText, offset)[1]
    if offset_h and axis.offsetText.get_visible():
        reach["bottom" if fracs_axis == 0 else "top"] += offset_h + 3 * _POINT
    label = axis.label
    if label.get_visible() and label.get_text():
        w, h = _rotated(_text_size(renderer, label), label.get_rotation())
        across = axis.get_label_position()
        thick = h if fracs_axis == 0 else w
        reach[across] += thick + axis.labelpad * _POINT
        reach[along[0]] = max(reach[along[0]], ((w if fracs_axis == 0 else h) - length) / 2.0)
        reach[along[1]] = max(reach[along[1]], ((w if fracs_axis == 0 else h) - length) / 2.0)
    return reach


def axes_reach(ax, renderer) -> dict[str, float]:
    """How far everything an axes draws reaches beyond its box, per side [in] (0 where nothing does)."""
    fig = ax.figure
    width_in, height_in = fig.get_size_inches()
    ax.apply_aspect()
    pos = ax.get_position(original=False)
    w, h = pos.width * width_in, pos.height * height_in
    reach = {"left": 0.0, "right": 0.0, "bottom": 0.0, "top": 0.0}
    if not ax.axison:
        return reach
    for axis, k, length in ((ax.xaxis, 0, w), (ax.yaxis, 1, h)):
        for side, value in _axis_reach(renderer, axis, length, k).items():
            reach[side] = max(reach[side], value)
    titles = [t for t in (ax.title, ax._left_title, ax._right_title) if t.get_text()]
    if titles and ax.yaxis.get_major_formatter().get_offset() and getattr(ax, "_autotitlepos", None) is False:
        ax._autotitlepos = True  # an offset text above the axes: let matplotlib lift the title over it
    if titles:
        pad = ax.titleOffsetTrans.get_matrix()[1, 2] / fig.dpi  # the title's pad above the axes
        sizes = [_text_size(renderer, t) for t in titles]
        reach["top"] += max(s[1] for s in sizes) + max(pad, 6 * _POINT)
        over = max(s[0] for s in sizes) - w
        if over > 0:
            reach["left"], reach["right"] = max(reach["left"], over / 2), max(reach["right"], over / 2)
    legend = ax.get_legend()
    if legend is not None and legend._bbox_to_anchor is not None:  # anchored, possibly outside
        box = legend.get_window_extent(renderer)
        x0, y0 = pos.x0 * width_in, pos.y0 * height_in
        reach["left"] = max(reach["left"], x0 - box.x0 / fig.dpi)
        reach["right"] = max(reach["right"], box.x1 / fig.dpi - (x0 + w))
        reach["bottom"] = max(reach["bottom"], y0 - box.y0 / fig.dpi)
        reach["top"] = max(reach["top"], box.y1 / fig.dpi - (y0 + h))
    return reach


class MarginLayout(LayoutEngine):
    """Subplot parameters from the estimated reach of every axes' text (see the module docstring).

    Args:
        pad: free space at the edges and between panels [in].
        passes: how often the margins are re-estimated (tick labels depend on the axes' size).

    """

    _adjust_compatible = True
    _colorbar_gridspec = True

    def __init__(self, *, pad: float = PAD, passes: int = 2, **kwargs):
        super().__init__(**kwargs)
        self._params = {"pad": pad, "passes": passes}

    def set(self, *, pad: float | None = None, passes: int | None = None) -> None:
        """Change the padding [in] or the number of passes."""
        if pad is not None:
            self._params["pad"] = pad
        if passes is not None:
            self._params["passes"] = passes

    def execute(self, fig) -> None:
        """Set ``fig``'s subplot parameters so that every axes' text fits (axes on one grid only)."""
        for _ in range(int(self._params["passes"])):
            if not self._adjust(fig):
                return

    def _adjust(self, fig) -> bool:
        pad = self._params["pad"]
        cells = []
        grid = None
        for ax in fig.axes:
            spec = ax.get_subplotspec()
            if spec is None:
                continue
            top = spec.get_topmost_subplotspec()
            if grid is None:
                grid = top.get_gridspec()
            elif top.get_gridspec() is not grid:
                return False
            cells.append((ax, top))
        if grid is None:
            return False
        renderer = fig.canvas.get_renderer()
        width_in, height_in = fig.get_size_inches()
        nrows, ncols = grid.get_geometry()
        left, right = np.zeros(ncols), np.zeros(ncols)
        bottom, top_m = np.zeros(nrows), np.zeros(nrows)
        for ax, spec in cells:
            reach = axes_reach(ax, renderer)
            pos = ax.get_position(original=False)
            cell = spec.get_position(fig)
            # what sticks out of the cell [in]: the reach less the room between the axes and the cell's edge
            out_left = reach["left"] - (pos.x0 - cell.x0) * width_in
            out_right = reach["right"] - (cell.x1 - pos.x1) * width_in
            out_bottom = reach["bottom"] - (pos.y0 - cell.y0) * height_in
            out_top = reach["top"] - (cell.y1 - pos.y1) * height_in
            left[spec.colspan.start] = max(left[spec.colspan.start], out_left)
            right[spec.colspan.stop - 1] = max(right[spec.colspan.stop - 1], out_right)
            bottom[spec.rowspan.stop - 1] = max(bottom[spec.rowspan.stop - 1], out_bottom)
            top_m[spec.rowspan.start] = max(top_m[spec.rowspan.start], out_top)
        suptitle = fig._suptitle
        sup = _text_size(renderer, suptitle)[1] + pad if suptitle is not None and suptitle.get_text() else 0.0
        lm, rm = left[0] + pad, right[-1] + pad
        bm, tm = bottom[-1] + pad, top_m[0] + pad + sup
        wgap = max([right[c] + left[c + 1] + pad for c in range(ncols - 1)], default=0.0)
        hgap = max([bottom[r] + top_m[r + 1] + pad for r in range(nrows - 1)], default=0.0)
        cell_w = (width_in - lm - rm - (ncols - 1) * wgap) / ncols
        cell_h = (height_in - bm - tm - (nrows - 1) * hgap) / nrows
        if cell_w <= 0 or cell_h <= 0:  # too small a figure for its text: leave it as it is
            return False
        fig.subplots_adjust(
            left=lm / width_in,
            right=1 - rm / width_in,
            bottom=bm / height_in,
            top=1 - tm / height_in,
            wspace=wgap / cell_w,
            hspace=hgap / cell_h,
        )
        if sup:
            suptitle.set_y(1 - pad / height_in)
            suptitle.set_verticalalignment("top")
        return True


TICK_BINS = 5
"""At most this many intervals between major ticks on a linear axis (matplotlib's default is up to 9):
a tick and its label cost more to draw than a curve."""


class InViewLocator(MaxNLocator):
    """A :class:`~matplotlib.ticker.MaxNLocator` that gives only the ticks in view.

    ``MaxNLocator`` also returns a tick on either side beyond the view, for which matplotlib builds
    a tick (lines and labels) at every draw only to leave it undrawn.
    """

    def __call__(self):
        """The tick locations inside the axis' view interval."""
        if self.axis is None:
            return []
        low, high = sorted(self.axis.get_view_interval())
        locs = self.tick_values(low, high)
        slack = 1e-10 * (high - low)
        return locs[(locs >= low - slack) & (locs <= high + slack)]


def fewer_ticks(ax) -> None:
    """Give ``ax``'s linear axes at most :data:`TICK_BINS` + 1 major ticks, all in view."""
    for axis in (ax.xaxis, ax.yaxis):
        if type(axis.get_major_locator()) is AutoLocator:
            axis.set_major_locator(InViewLocator(TICK_BINS, steps=[1, 2, 2.5, 5, 10]))


def subplots(nrows: int = 1, ncols: int = 1, **kwargs):
    """``plt.subplots`` laid out by :class:`MarginLayout`, with :func:`fewer_ticks` on every axes.

    The axes' titles sit at a fixed height (``axes.titley`` = 1, the title pad above the top edge),
    where matplotlib would put them anyway when no tick label or axis label is on top: otherwise
    every draw measures all the y tick labels of every titled axes to check. Where a y offset text
    (such as ``1e-14``) sits above the axes, :class:`MarginLayout` hands the title back to matplotlib.

    Args:
        nrows: rows of panels.
        ncols: columns of panels.
        **kwargs: passed to ``plt.subplots`` (``figsize`` [in], ``sharex``, ``height_ratios``...).

    Returns:
        (figure, axes) as ``plt.subplots`` returns them.

    """
    import matplotlib as mpl  # deferred: heavy (matplotlib), keeps the CLI's start fast
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    with mpl.rc_context({"axes.titley": 1.0}):  # titles at the top edge + pad, not moved at draw time (see below)
        fig, axes = plt.subplots(nrows, ncols, layout=MarginLayout(), **kwargs)
    for ax in fig.axes:
        fewer_ticks(ax)
    return fig, axes
