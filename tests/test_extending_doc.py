"""``docs/extending.md`` names only what exists, and ``docs/floor.md``'s step-edge numbers are the code's.

Every backticked module path (``dynamics/floor/ground.py``, ``model/spatial.SOLE_POINTS``) resolves: the file
exists, and each name after it is an attribute of the imported module (issue 35: the recipes are checked
against the code as it stands, so a rename that leaves the recipe behind fails here).
"""

from __future__ import annotations

import importlib
import math
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TICKED = re.compile(r"`([^`\s]+)`")


def _names(page: str) -> list[str]:
    out = []
    for token in TICKED.findall((ROOT / "docs" / page).read_text(encoding="utf-8")):
        token = re.split(r"[(\[]|::", token, maxsplit=1)[0].removeprefix("pasibot_pin/")
        if "/" in token and not any(mark in token for mark in ("*", "NAME", "<")):  # NAME, <side>: placeholders
            out.append(token)
    return out


@pytest.mark.parametrize("token", _names("extending.md"))
def test_every_named_module_and_attribute_exists(token):
    if token.startswith(("tests/", "urdf/", "docs/", "benchmarks/", "tools/")):
        assert (ROOT / token).exists(), token
        return
    path, _, attrs = token.partition(".") if not token.endswith(".py") else (token[:-3], "", "")
    assert (ROOT / "pasibot_pin" / f"{path}.py").exists(), token
    obj = importlib.import_module("pasibot_pin." + path.replace("/", "."))
    for name in filter(None, attrs.split(".")):
        obj = getattr(obj, name)  # an AttributeError names what the recipe lost


def test_the_step_edge_numbers_in_the_floor_page_are_the_code_s():
    from pasibot_pin.dynamics.floor.ground import MAX_SLOPE, MAX_STEP_HEIGHT
    from tests.test_step_edge import CLIMB

    text = " ".join((ROOT / "docs" / "floor.md").read_text(encoding="utf-8").split())
    assert f"at most {MAX_STEP_HEIGHT:g} m" in text
    assert f"at most {math.degrees(MAX_SLOPE):.0f} deg" in text
    height, at = CLIMB
    assert f"climbs a {1e3 * height:g} mm step at x = {at:g} m" in text
    assert f"ends {1e3 * height:g} mm higher" in text
