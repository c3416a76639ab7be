"""Every ``--help`` speaks to users: no names of the package's functions, classes, constants or modules."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from pasibot_pin.__main__ import build_parser


def _internal_names(trees: dict[str, ast.Module]) -> set[str]:
    """Top-level functions, classes and constants of every module (``trees``: conftest's package_trees), and every
    module's name."""
    names: set[str] = set()
    for rel, tree in trees.items():
        names.add(Path(rel).stem)
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                names.update(t.id for t in targets if isinstance(t, ast.Name))
    # what users type or read elsewhere: design parameters, metrics, commands and words
    from pasibot_pin.model.design import SPECS
    from pasibot_pin.studies.design_metrics import METRICS

    user = set(SPECS) | set(METRICS) | {"main", "info", "gait", "torques", "contact", "energy", "sweep"}
    user |= {"optimize", "simulate", "analyze", "view", "files", "plan", "paths", "units", "errors", "net", "jobs"}
    return {n for n in names - user if "_" in n.strip("_") or re.search(r"[a-z][A-Z]", n) or n.isupper()}


def _helps() -> tuple[dict[str, str], set[str]]:
    """Each command's help text, and every argument's placeholder (metavar: ``VARIANT``, ``STEPS``)."""
    parser = build_parser()
    out = {"pasibot": parser.format_help()}
    sub = next(a for a in parser._actions if a.dest == "command")
    placeholders: set[str] = set()
    for name, command in sub.choices.items():
        out[name] = command.format_help()
        for action in command._actions:
            metavar = action.metavar if isinstance(action.metavar, str) else action.dest.upper()
            placeholders.update(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", metavar))
    return out, placeholders


HELPS, PLACEHOLDERS = _helps()


@pytest.fixture(scope="module")
def internal_names(package_trees) -> frozenset[str]:
    """:func:`_internal_names` of the package's modules, parsed once per worker (conftest's package_trees)."""
    return frozenset(_internal_names(package_trees))


@pytest.mark.parametrize("command", sorted(HELPS))
def test_help_has_no_internal_names(command, internal_names):
    text = HELPS[command]
    assert "pasibot_pin" not in text and ":func:" not in text and "``" not in text
    words = set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", text))
    leaked = sorted((words - PLACEHOLDERS) & internal_names)
    assert not leaked, f"pasibot {command} --help names internals: {leaked}"


def test_the_check_sees_a_leak(internal_names):
    assert {"LEG_COLUMNS", "gait_columns", "design_metrics"} <= internal_names
