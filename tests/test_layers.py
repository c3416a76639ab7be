"""The package's layers as docs/DESIGN.md draws them: every import points down (or sideways within a unit).

Read from the source (every ``import`` statement, function-level ones included), not from a list
kept by hand: a module that imports upwards across the layers fails here.
"""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "pasibot_pin"

LAYERS: dict[str, int] = {
    # the foundation: no physics, imported by anyone
    "errors": 0,
    "caches": 0,
    "files": 0,
    "units": 0,
    "reprs": 0,
    "net": 0,
    "extras": 0,
    "jobs": 0,
    "progress": 0,
    "constraints": 1,
    "model": 2,
    "kinematics": 3,
    "dynamics": 3,
    "studies": 4,
    "viz": 5,
    "explore": 6,
    "report": 7,
    "cli": 8,
    "__init__": 9,
    "__main__": 9,
}
"""Each unit's layer (a unit: a subpackage, or a top-level module), bottom up, as in docs/DESIGN.md."""

SIDEWAYS: set[tuple[str, str]] = set()
"""Imports allowed between two different units of one layer above the foundation (none: kinematics and
dynamics stay apart; the foundation's small modules may use each other)."""


def unit_of(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def imports(path: Path) -> list[tuple[str, int]]:
    """(imported pasibot_pin unit, line) of every import in ``path``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "pasibot_pin":
            if node.module == "pasibot_pin":  # from pasibot_pin import constraints / __version__
                for alias in node.names:
                    name = alias.name if alias.name in LAYERS else "__init__"
                    found.append((name, node.lineno))
            else:
                found.append((unit_of(node.module), node.lineno))
        elif isinstance(node, ast.Import):
            found += [(unit_of(a.name), node.lineno) for a in node.names if a.name.split(".")[0] == "pasibot_pin"]
    return found


def modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def test_every_unit_has_a_layer():
    units = {unit_of(".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts)) for p in modules()}
    assert units <= set(LAYERS), sorted(units - set(LAYERS))


@pytest.mark.parametrize("path", modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_import_points_up(path):
    source = unit_of(".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts))
    for target, line in imports(path):
        if target == source or target == "__init__" and source == "__main__":
            continue
        if target == "__init__":  # `from pasibot_pin import __version__`
            continue
        upward = LAYERS[target] > LAYERS[source]
        sideways = LAYERS[target] == LAYERS[source] > 0 and (source, target) not in SIDEWAYS
        assert not (upward or sideways), (
            f"{path.relative_to(PACKAGE.parent)}:{line} imports {target} (layer {LAYERS[target]}) "
            f"from {source} (layer {LAYERS[source]})"
        )


def test_the_check_sees_an_upward_import(tmp_path):
    """The check itself can fail: a constraints module importing the report is caught."""
    fake = tmp_path / "bad.py"
    fake.write_text("def f():\n    from pasibot_pin.report.markdown import section\n")
    assert imports(fake) == [("report", 2)]
    assert LAYERS["report"] > LAYERS["constraints"]
