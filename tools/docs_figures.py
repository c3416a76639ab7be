"""``make docs-figures``: the README's pictures, each drawn by its writer in ``pasibot_pin.report.docs_figures``.

docs/variants.png, gait.gif, walking.gif, kinematics.png, torques.png, simulation.png and walking_map.png.

``tests/test_docs_figures.py`` draws each again and compares it with the committed file.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.report.docs_figures import DOCS_PICTURES

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def main(argv: list[str] | None = None) -> int:
    """Draw every picture of :data:`~pasibot_pin.report.docs_figures.DOCS_PICTURES` into ``docs/``."""
    argparse.ArgumentParser(description=__doc__).parse_args(argv)
    for write, name in DOCS_PICTURES:
        print(write(DOCS / name).relative_to(ROOT))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
