"""Writing a matplotlib figure to a file: drawn once, the PNG's pixels written by Pillow.

The report, the commands and the design-exploration figures all save through
:func:`save_figure_file` (re-exported by :mod:`pasibot_pin.report.files`).
"""

from __future__ import annotations

from pathlib import Path

from pasibot_pin.files import PART_MARKER, atomic_path

PNG_COMPRESS_LEVEL = 1
"""zlib level of the report's PNGs: faster to write than Pillow's default 6 (the plots' flat colours
compress well at any level)."""

TEXT_HINTING = "no_hinting"
"""FreeType hinting of the text drawn into a written figure (matplotlib's default ``force_autohint``
grid-fits every glyph, which costs about a sixth of a figure's drawing)."""


FIGURE_DPI = 100
"""Resolution of every figure the report and the commands write [dots per inch]."""


def save_figure_file(fig, path: Path, dpi: float = FIGURE_DPI) -> None:
    """``fig.savefig(path, dpi=dpi)``, drawn once; a PNG at :data:`PNG_COMPRESS_LEVEL`.

    ``savefig`` draws a figure that has a layout engine twice (once, not rendered, to lay it out;
    even with the engine switched off, since a figure that had one keeps a placeholder). A PNG of
    an Agg figure is therefore drawn here once (the layout engine runs in that draw) at ``dpi`` and
    its pixels written by Pillow, with ``dpi`` recorded in the file: the pixels ``savefig`` gives
    with ``text.hinting`` = :data:`TEXT_HINTING` (as RGB when the figure is opaque, as it is unless
    its face colour is transparent).
    Other formats and canvases go through ``savefig``. The figure's dpi is restored afterwards.

    Args:
        fig: a matplotlib figure.
        path: output file (its extension names the format); written under a temporary name in its
            folder and renamed when complete (unless ``path`` is such a temporary name already).
        dpi: resolution [dots per inch].

    """
    if PART_MARKER not in Path(path).name:  # a figure appears whole under its name, or not at all
        with atomic_path(Path(path)) as tmp:
            _save_figure(fig, tmp, dpi)
        return
    _save_figure(fig, path, dpi)


def _save_figure(fig, path: Path, dpi: float) -> None:
    """:func:`save_figure_file` straight to ``path``."""
    import matplotlib as mpl  # deferred: heavy (matplotlib), keeps the CLI's start fast
    from matplotlib.backends.backend_agg import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
        FigureCanvasAgg,
    )

    if Path(path).suffix.lower() != ".png" or not isinstance(fig.canvas, FigureCanvasAgg):
        fig.savefig(path, dpi=dpi)
        return
    from PIL import Image  # deferred: heavy (PIL), keeps the CLI's start fast

    original_dpi = fig.dpi
    try:
        fig.dpi = dpi
        canvas = fig.canvas
        with mpl.rc_context({"text.hinting": TEXT_HINTING}):
            canvas.draw()
        renderer = canvas.get_renderer()
        size = (int(renderer.width), int(renderer.height))
        image = Image.frombuffer("RGBA", size, canvas.buffer_rgba(), "raw", "RGBA", 0, 1)
        if image.getchannel("A").getextrema()[0] == 255:  # opaque: the same pixels as RGB, a fifth faster to write
            image = image.convert("RGB")
        image.save(path, format="png", dpi=(dpi, dpi), compress_level=PNG_COMPRESS_LEVEL)
    finally:
        fig.dpi = original_dpi
